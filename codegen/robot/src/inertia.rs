//! Whether an inertia tensor is one a rigid body can have.
//!
//! A tensor `I` about the centre of mass is physical when it is symmetric, positive definite,
//! and its principal moments obey the triangle inequality `I1 ≤ I2 + I3`. The last two together
//! say that `Σ = ½ tr(I) 1 - I`, the body's second moment of mass `∫ r rᵀ dm`, is positive
//! semi-definite; with a positive mass that makes the pseudo-inertia matrix
//! `[[Σ + m c cᵀ, m c], [m cᵀ, m]]` positive semi-definite, whatever the centre of mass `c`.
//! Flat bodies sit on the boundary (a thin plate has `Ixx = Iyy + Izz`: the chapter's platform
//! and rods are such), so the triangle inequality is checked with a tolerance, not strictly.

use crate::Error;
use alloc::format;
use alloc::string::ToString;

/// Relative tolerance of the checks: rounding in a decimal description, not physics.
const TOLERANCE: f64 = 1e-12;

fn invalid(field: &str, rule: impl ToString) -> Error {
    Error::Invalid {
        field: field.to_string(),
        rule: rule.to_string(),
    }
}

/// `det` of the principal submatrix of `m` on the rows and columns `idx`.
fn principal_minor(m: &[[f64; 3]; 3], idx: &[usize]) -> f64 {
    match *idx {
        [i] => m[i][i],
        [i, j] => m[i][i] * m[j][j] - m[i][j] * m[j][i],
        _ => {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        }
    }
}

const PRINCIPAL: [&[usize]; 7] = [&[0], &[1], &[2], &[0, 1], &[0, 2], &[1, 2], &[0, 1, 2]];

/// Positive semi-definite within `tol · scale^k` on each principal minor of order `k`.
fn semi_definite(m: &[[f64; 3]; 3], scale: f64) -> bool {
    PRINCIPAL.iter().all(|idx| {
        let scale_k: f64 = idx.iter().map(|_| scale).product();
        principal_minor(m, idx) >= -TOLERANCE * scale_k
    })
}

/// Checks that `inertia`, about the centre of mass, is physical: symmetric, positive definite
/// (semi-definite when `allow_singular`, for the part of a rod's inertia that grows with its
/// length), and with principal moments obeying the triangle inequality. `field` names the
/// tensor in the error.
///
/// # Errors
/// [`Error::Invalid`] naming the field and the rule it breaks: `must be symmetric`,
/// `must be positive definite` (or `semi-definite`), or which triangle inequality fails
/// (`breaks the triangle inequality Ixx ≤ Iyy + Izz`).
pub fn check_inertia(field: &str, m: &[[f64; 3]; 3], allow_singular: bool) -> Result<(), Error> {
    if m.iter().flatten().any(|x| !x.is_finite()) {
        return Err(invalid(field, "must be finite"));
    }
    let scale = m.iter().flatten().fold(0.0_f64, |s, x| s.max(x.abs()));
    let asymmetric = (0..3).any(|i| {
        (0..3).any(|j| (m[i][j] - m[j][i]).abs() > TOLERANCE * scale.max(f64::MIN_POSITIVE))
    });
    if asymmetric {
        return Err(invalid(field, "must be symmetric"));
    }
    if allow_singular {
        if !semi_definite(m, scale) {
            return Err(invalid(field, "must be positive semi-definite"));
        }
    } else {
        let leading = [&[0][..], &[0, 1], &[0, 1, 2]];
        if !leading.iter().all(|idx| principal_minor(m, idx) > 0.0) {
            return Err(invalid(field, "must be positive definite"));
        }
    }
    // Σ = ½ tr(I) 1 - I: its diagonal is ½(Iyy + Izz - Ixx), ½(Ixx + Izz - Iyy), ...
    let half_trace = 0.5 * (m[0][0] + m[1][1] + m[2][2]);
    let sigma: [[f64; 3]; 3] = core::array::from_fn(|i| {
        core::array::from_fn(|j| if i == j { half_trace } else { 0.0 } - m[i][j])
    });
    let axes = ["xx", "yy", "zz"];
    for i in 0..3 {
        if sigma[i][i] < -TOLERANCE * scale {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let (j, k) = (j.min(k), j.max(k));
            return Err(invalid(
                field,
                format!(
                    "breaks the triangle inequality I{} ≤ I{} + I{} (no rigid body has these moments)",
                    axes[i], axes[j], axes[k]
                ),
            ));
        }
    }
    if !semi_definite(&sigma, scale) {
        return Err(invalid(
            field,
            "breaks the triangle inequality of its principal moments (½ tr(I) 1 - I must be \
             positive semi-definite: no rigid body has this tensor)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

    fn rule(m: [[f64; 3]; 3]) -> Option<alloc::string::String> {
        check_inertia("i", &m, false).err().map(|e| e.to_string())
    }

    fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
        [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
    }

    #[test]
    fn physical_tensors_pass_flat_ones_included() {
        assert_eq!(rule(diag(1.0, 1.0, 1.0)), None);
        // A thin plate (the chapter's platform) and a rotated full tensor.
        assert_eq!(rule(diag(0.375, 0.1875, 0.1875)), None);
        assert_eq!(rule(diag(0.0025, 0.00125, 0.00125)), None);
        assert_eq!(
            rule([[0.3, 0.05, 0.0], [0.05, 0.2, 0.01], [0.0, 0.01, 0.25]]),
            None
        );
    }

    #[test]
    fn an_indefinite_tensor_is_refused() {
        assert_eq!(
            rule([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]]).as_deref(),
            Some("invalid robot: `i` must be positive definite")
        );
    }

    #[test]
    fn the_broken_triangle_inequality_is_named() {
        let e = rule(diag(1.0, 0.1, 0.1)).unwrap();
        assert!(e.contains("Ixx ≤ Iyy + Izz"), "{e}");
        let e = rule(diag(0.1, 0.1, 0.5)).unwrap();
        assert!(e.contains("Izz ≤ Ixx + Iyy"), "{e}");
    }

    #[test]
    fn a_rotated_tensor_breaking_the_triangle_inequality_is_refused() {
        // diag(1, 0.1, 0.1) turned by 45° about z: no diagonal entry shows the fault alone.
        let (c, s) = (
            core::f64::consts::FRAC_1_SQRT_2,
            core::f64::consts::FRAC_1_SQRT_2,
        );
        let d = [1.0, 0.1, 0.1];
        let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let m: [[f64; 3]; 3] = core::array::from_fn(|i| {
            core::array::from_fn(|j| (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum())
        });
        assert!(rule(m).unwrap().contains("triangle inequality"));
    }

    #[test]
    fn asymmetric_and_non_finite_tensors_are_refused() {
        let mut m = diag(1.0, 1.0, 1.0);
        m[0][1] = 0.3;
        assert!(rule(m).unwrap().ends_with("must be symmetric"));
        m[0][1] = f64::NAN;
        assert!(rule(m).unwrap().ends_with("must be finite"));
    }

    #[test]
    fn the_length_part_of_a_rod_may_be_singular() {
        assert!(check_inertia("i", &diag(0.0, 0.1667, 0.1667), true).is_ok());
        assert!(check_inertia("i", &diag(0.0, 0.1667, 0.1667), false).is_err());
        assert!(check_inertia("i", &diag(0.0, -0.1, 0.1), true).is_err());
    }
}
