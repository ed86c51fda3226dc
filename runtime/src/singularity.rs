//! The legged mechanisms' singularity terms against their bounds: one check for every
//! mechanism, each term bounded by what it measures. The terms and their names are the
//! model's, generated beside the kernels (`SINGULARITY_TERMS` in each mechanism's module); a
//! leg type that brings a new kind of term brings its bound here, nothing per mechanism.

use crate::error::Error;
pub use c5_generated::guard::{SingularityTerm, TermKind};

/// Smallest accepted sine of a leg's angle with its U joint's first axis: below it the leg's
/// frame (its spin about its own axis) is lost.
pub const U_JOINT_TOLERANCE: f64 = 1e-6;

/// Smallest accepted `1 - (K/ρ)²`, the squared sine of the angle between a crank and its rod
/// in the crank's plane: at zero they align (the ball at the edge of the crank's reach, where
/// `∂θ/∂B` is unbounded); negative, the ball is beyond reach.
pub const REACH_TOLERANCE: f64 = 1e-10;

/// Smallest accepted pivot ratio `ρ` of the solve with `J⁻ᵀ` (the `LDLᵀ` of `J⁻¹ J⁻ᵀ`, each
/// pivot over its diagonal entry): near zero the legs lose their hold on the platform (a
/// parallel singularity) and the forces grow without bound. Against a 50-digit reference
/// (`python/tests/exact_hexapod.py`), the Gough-Stewart platform's inverse dynamics and `J`
/// err by about `1.5e-15/ρ` relative and the forward dynamics by up to `3e-18/ρ^1.5`, so at
/// `1e-7` they were already past `1e-8`; at this bound the worst measured is `2.2e-11`
/// (docs/embedding.md). The forward dynamics, which solves `M_x`, checks it too.
pub const HOLD_TOLERANCE: f64 = 1e-5;

/// Smallest accepted hold of three arms on a platform that translates, `det(J⁻¹)² / Π
/// |row_i|²` (one where the arms' rows are orthogonal, zero where they cannot hold the
/// platform): near zero the solve `J⁻ᵀ Γ = W` divides by a vanishing determinant. Against a
/// 50-digit reference of the Delta (`python/tests/exact_delta.py`: its kinematics, and its
/// torques by virtual power), down to this bound `J` errs by up to 1.2e-12 relative, the
/// torques by 4.6e-12 and the forward dynamics by 2.4e-12 (6.5e-15, 6.5e-15 and 8.9e-15 at
/// holds of 1e-3). The platform's motion from the actuators' has its own, higher bound
/// ([`crate::legged::JOINT_STATE_HOLD_RATIO_TOLERANCE`]).
pub const HOLD_RATIO_TOLERANCE: f64 = 1e-8;

/// Smallest accepted term of a closed-form forward kinematics (the Delta's: how far inside the
/// three spheres' reach the platform is, `(L_1² − |y_0|²)/L_1²`, zero where the two meeting
/// points merge, and how far from a line their centres are, `|n|²/(|a|² |b|²)`).
pub const FORWARD_KINEMATICS_TOLERANCE: f64 = 1e-10;

/// Smallest sine of a leg's angle with its U joint's first axis at which the forward dynamics
/// (and its derivatives) are served. Near that singularity the leg's spin about its own axis
/// grows as `1/sine` for a given platform twist, and with it `M_x` and `h`: each stays within
/// `1e-10` of a 50-digit reference, but the acceleration solved from them errs by 1.1e-8 at a
/// sine of `1e-3`, 6e-5 at `1e-4` and by a factor of 20 at `1e-5` (legs that hold the platform
/// well, `ρ = 0.14`). At this bound the worst measured is 1e-11; below it the call is refused
/// ([`Error::IllConditioned`]). The inverse dynamics, `J`, `M_x` and `h` are served down to
/// [`U_JOINT_TOLERANCE`].
pub const FORWARD_U_JOINT_TOLERANCE: f64 = 1e-2;

/// The smallest accepted value of a term of `kind`.
pub const fn bound(kind: TermKind) -> f64 {
    match kind {
        TermKind::UJoint => U_JOINT_TOLERANCE,
        TermKind::Reach => REACH_TOLERANCE,
        TermKind::Pivot => HOLD_TOLERANCE,
        TermKind::Hold => HOLD_RATIO_TOLERANCE,
        TermKind::ForwardKinematics => FORWARD_KINEMATICS_TOLERANCE,
    }
}

/// Refuses the first of `values` below its bound, or NaN ([`Error::Singularity`] naming it),
/// `terms` saying what each measures (a kernel's terms are the first of its mechanism's). The
/// cranks' reach goes first: beyond it every other term is NaN, and the reach names the cause.
#[inline]
pub fn check(values: &[f64], terms: &[SingularityTerm]) -> Result<(), Error> {
    // One pass where every term holds (NaN fails `>=`); the ordered search only for the error.
    let holds = |(&value, term): (&f64, &SingularityTerm)| value >= bound(term.kind);
    if values.iter().zip(terms).all(holds) {
        return Ok(());
    }
    refusal(values, terms)
}

/// The error of [`check`] where a term fails: the reach first, then the others in order.
#[cold]
#[inline(never)]
fn refusal(values: &[f64], terms: &[SingularityTerm]) -> Result<(), Error> {
    let pairs = || values.iter().zip(terms);
    let reach = pairs().filter(|(_, t)| t.kind == TermKind::Reach);
    let rest = pairs().filter(|(_, t)| t.kind != TermKind::Reach);
    for (&value, term) in reach.chain(rest) {
        let bound = bound(term.kind);
        if value.is_nan() || value < bound {
            return Err(Error::Singularity {
                term: if value < 0.0 {
                    term.negative
                } else {
                    term.name
                },
                value,
                bound,
            });
        }
    }
    Ok(())
}

/// Refuses the first term of `kind` below `bound` where `what` cannot be served to its
/// accuracy bound though the pose is not singular ([`Error::IllConditioned`]).
pub fn check_conditioned(
    what: &'static str,
    values: &[f64],
    terms: &[SingularityTerm],
    kind: TermKind,
    bound: f64,
) -> Result<(), Error> {
    let weak = values
        .iter()
        .zip(terms)
        .find(|(&value, t)| t.kind == kind && value < bound);
    match weak {
        Some((&value, term)) => Err(Error::IllConditioned {
            what,
            term: term.name,
            value,
            bound,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use c5_generated::f64::{delta, gough_stewart, rus_hexapod};

    #[test]
    fn the_reach_is_named_first_and_beyond_it_by_its_negative_name() {
        let terms = &rus_hexapod::SINGULARITY_TERMS;
        let mut values = [0.5; 18];
        values[0] = f64::NAN;
        values[8] = -0.2;
        match check(&values, terms) {
            Err(Error::Singularity { term, bound, .. }) => {
                assert!(term.contains("leg 3 beyond its crank's reach"), "{term}");
                assert_eq!(bound, REACH_TOLERANCE);
            }
            other => panic!("{other:?}"),
        }
        values[8] = 1e-12;
        assert!(matches!(
            check(&values, terms),
            Err(Error::Singularity { term, .. }) if term.contains("leg 3 aligned")
        ));
        values[8] = 0.5;
        assert!(matches!(
            check(&values, terms),
            Err(Error::Singularity {
                term: "U joint of leg 1",
                ..
            })
        ));
        values[0] = 0.5;
        assert!(check(&values, terms).is_ok());
    }

    #[test]
    fn each_kind_has_its_bound_and_a_kernels_terms_are_the_first() {
        let terms = &delta::SINGULARITY_TERMS;
        let mut values = [0.5; 7];
        values[6] = 0.5 * HOLD_RATIO_TOLERANCE;
        assert!(matches!(
            check(&values, terms),
            Err(Error::Singularity { term, bound, .. })
                if term.starts_with("arms' hold") && bound == HOLD_RATIO_TOLERANCE
        ));
        // The pose's terms alone, without the hold.
        assert!(check(&values[..6], terms).is_ok());
        let terms = &gough_stewart::SINGULARITY_TERMS;
        let mut values = [0.5; 12];
        values[9] = 0.5 * HOLD_TOLERANCE;
        assert!(matches!(
            check(&values, terms),
            Err(Error::Singularity {
                term: "legs' hold (pivot 4)",
                ..
            })
        ));
        values[9] = 0.5;
        values[2] = 1e-3;
        assert!(check(&values, terms).is_ok());
        assert!(matches!(
            check_conditioned("forward dynamics", &values, terms, TermKind::UJoint, 1e-2),
            Err(Error::IllConditioned {
                term: "U joint of leg 3",
                ..
            })
        ));
    }
}
