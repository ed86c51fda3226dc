//! What the data can tell: the singular values of a leg's whitened, scaled Jacobian, the
//! combinations too poorly known to fit (each fixed through one of its members), and the
//! estimates' standard deviations.

use super::{Options, Unobservable};
use alloc::vec::Vec;
use c5_robot::calibration::Fitted;
use nalgebra::DMatrix;

/// A leg's design: its singular values, the parameters fitted, the combinations fixed.
pub(super) struct LegDesign {
    /// All of them, largest first.
    pub singular_values: Vec<f64>,
    /// The columns fitted.
    pub free: Vec<usize>,
    pub unobservable: Vec<Unobservable>,
}

/// The smallest singular value of `j`'s columns `free` and its right singular vector.
fn weakest(j: &DMatrix<f64>, free: &[usize]) -> (f64, Vec<f64>) {
    let svd = j.select_columns(free).svd(false, true);
    let v_t = svd.v_t.expect("asked for V");
    let (k, s) =
        svd.singular_values
            .iter()
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |best, (k, &s)| if s < best.1 { (k, s) } else { best },
            );
    (s, v_t.row(k).iter().copied().collect())
}

/// Leg `leg`'s design from its whitened Jacobian `j` scaled by `options.scale`: while the
/// weakest combination of the free parameters has a standard deviation (`scale/σ_min`) above
/// `options.observable`, its largest member is fixed.
pub(super) fn analyse(
    leg: usize,
    j: &DMatrix<f64>,
    fitted: &[Fitted],
    options: &Options,
) -> LegDesign {
    let mut all: Vec<f64> = j.singular_values().iter().copied().collect();
    all.sort_by(|a, b| b.total_cmp(a));
    let bound = options.observable / options.scale;
    let mut free: Vec<usize> = (0..fitted.len()).collect();
    let mut unobservable = Vec::new();
    while !free.is_empty() {
        let (s, v) = weakest(j, &free);
        if s > 0.0 && 1.0 / s <= bound {
            break;
        }
        let largest = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let lead = v.iter().position(|x| x.abs() == largest).unwrap_or(0);
        let sign = v[lead].signum();
        let combination = free
            .iter()
            .zip(&v)
            .filter(|(_, x)| x.abs() >= 1e-2 * largest)
            .map(|(&c, x)| (fitted[c].name(leg + 1), sign * x / largest))
            .collect();
        unobservable.push(Unobservable {
            leg: leg + 1,
            combination,
            std_dev: options.scale / s,
            fixed: fitted[free[lead]].name(leg + 1),
        });
        free.remove(lead);
    }
    LegDesign {
        singular_values: all,
        free,
        unobservable,
    }
}

/// The standard deviations (in scales) of the free parameters' estimates,
/// `√(s² (JᵀJ)⁻¹)ₖₖ`; `None` for the fixed.
pub(super) fn std_devs(j: &DMatrix<f64>, free: &[usize], variance_factor: f64) -> Vec<Option<f64>> {
    let jf = j.select_columns(free);
    let inverse = (jf.transpose() * &jf).try_inverse();
    let mut out = alloc::vec![None; j.ncols()];
    if let Some(c) = inverse {
        for (k, &column) in free.iter().enumerate() {
            out[column] = Some((variance_factor * c[(k, k)]).sqrt());
        }
    }
    out
}
