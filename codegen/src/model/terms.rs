//! What each singularity term a mechanism's kernels return measures, and its name: data the
//! generator writes beside the kernels (`SINGULARITY_TERMS`), so that the runtime checks every
//! mechanism's terms with one function, bounding each by its kind.

/// What a singularity term measures, which decides its bound in the runtime.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TermKind {
    /// The sine of a U joint's angle: zero where the joint locks.
    UJoint,
    /// `1 - (K/ρ)²` of a crank: zero where crank and rod align, negative beyond reach.
    Reach,
    /// A pivot ratio of the solve with `J⁻ᵀ`: zero at a parallel singularity.
    Pivot,
    /// The legs' hold as one ratio `det(J⁻¹)² / Π |row_i|²`: zero at a parallel singularity.
    Hold,
    /// A term of a closed-form forward kinematics: zero where its solutions merge.
    ForwardKinematics,
}

impl TermKind {
    /// The variant's path in the generated crate.
    pub fn path(self) -> &'static str {
        match self {
            TermKind::UJoint => "UJoint",
            TermKind::Reach => "Reach",
            TermKind::Pivot => "Pivot",
            TermKind::Hold => "Hold",
            TermKind::ForwardKinematics => "ForwardKinematics",
        }
    }
}

/// One singularity term: its kind, its name in errors, and its name where it is negative (a
/// point beyond reach), if that reads differently.
#[derive(Clone, Debug, PartialEq)]
pub struct SingularityTerm {
    pub kind: TermKind,
    pub name: String,
    pub negative: Option<String>,
}

impl SingularityTerm {
    fn new(kind: TermKind, name: String) -> Self {
        SingularityTerm {
            kind,
            name,
            negative: None,
        }
    }

    /// The term as a value of `c5_generated::guard::SingularityTerm`.
    pub fn to_rust(&self) -> String {
        format!(
            "crate::guard::SingularityTerm {{ kind: crate::guard::TermKind::{}, name: {:?}, \
             negative: {:?} }}",
            self.kind.path(),
            self.name,
            self.negative.as_deref().unwrap_or(&self.name)
        )
    }
}

/// `count` U joints' sines, named by `name(i)` for the joint of the `i`-th leg (from 1).
pub fn u_joints(count: usize, name: impl Fn(usize) -> String) -> Vec<SingularityTerm> {
    (1..=count)
        .map(|i| SingularityTerm::new(TermKind::UJoint, name(i)))
        .collect()
}

/// `count` cranks' reach terms, named `aligned(i)`, and `beyond(i)` where negative.
pub fn reaches(
    count: usize,
    aligned: impl Fn(usize) -> String,
    beyond: impl Fn(usize) -> String,
) -> Vec<SingularityTerm> {
    (1..=count)
        .map(|i| SingularityTerm {
            negative: Some(beyond(i)),
            ..SingularityTerm::new(TermKind::Reach, aligned(i))
        })
        .collect()
}

/// The six pivot ratios of the legs' hold on the platform.
pub fn pivots() -> Vec<SingularityTerm> {
    (1..=6)
        .map(|k| SingularityTerm::new(TermKind::Pivot, format!("legs' hold (pivot {k})")))
        .collect()
}

/// One term of kind `kind` named `name`.
pub fn single(kind: TermKind, name: &str) -> SingularityTerm {
    SingularityTerm::new(kind, name.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{delta, gough_stewart, rus_hexapod, Guard, Mechanics};

    /// Every legged mechanism describes as many terms as its longest guard returns, the
    /// shorter guard's terms first, and every name once.
    #[test]
    fn the_descriptions_match_the_guards() {
        let mechanisms: [&dyn Mechanics; 3] = [
            &gough_stewart::GoughStewartMechanics,
            &rus_hexapod::RusHexapodMechanics,
            &delta::DeltaMechanics,
        ];
        for mechanics in mechanisms {
            let structure = mechanics.structure();
            let terms = structure.singularity_terms();
            let solve = structure.guard_output(Guard::Solve).0.shape.len();
            let pose = structure.guard_output(Guard::Pose).0.shape.len();
            assert_eq!(terms.len(), solve, "{}", mechanics.name());
            assert!(pose <= solve);
            let kinds: Vec<_> = terms.iter().map(|t| t.kind).collect();
            assert!(
                kinds[pose..]
                    .iter()
                    .all(|k| matches!(k, TermKind::Pivot | TermKind::Hold)),
                "{}: the solve adds only the hold",
                mechanics.name()
            );
            let mut names: Vec<_> = terms.iter().map(|t| &t.name).collect();
            names.sort();
            names.dedup();
            assert_eq!(names.len(), terms.len(), "{}", mechanics.name());
        }
    }
}
