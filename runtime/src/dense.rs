//! Small dense linear algebra on arrays, for the few solves the runtime does itself (the
//! joint-space maps, a level start's least squares): Gaussian elimination with partial
//! pivoting, and products.

/// `A x = b` by Gaussian elimination with partial pivoting; `None` when an entry is not
/// finite or a pivot is below `tolerance` times the largest entry of `A` (the matrix is
/// singular to that precision).
///
/// Plain index loops and one reciprocal per pivot (a division's latency is several
/// multiplications'). The row swaps depend on the data, so at 6×6 it still takes about 180 ns
/// on this project's machine: the forward kinematics' Newton steps are solved in their
/// generated kernel instead.
#[inline]
#[allow(clippy::needless_range_loop)] // the index loops are what LLVM unrolls
pub fn solve<const N: usize>(a: &[[f64; N]; N], b: &[f64; N], tolerance: f64) -> Option<[f64; N]> {
    // An infinite entry makes the bound infinite, so no pivot passes it; a NaN, which `max`
    // passes over and no comparison refuses, reaches the solution (NaN never vanishes), which
    // is checked last.
    let bound = tolerance * a.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (mut a, mut b) = (*a, *b);
    let mut reciprocal = [0.0; N];
    for k in 0..N {
        let mut pivot = k;
        for i in k + 1..N {
            if a[i][k].abs() > a[pivot][k].abs() {
                pivot = i;
            }
        }
        if a[pivot][k].abs() <= bound {
            return None;
        }
        a.swap(k, pivot);
        b.swap(k, pivot);
        reciprocal[k] = 1.0 / a[k][k];
        for i in k + 1..N {
            let f = a[i][k] * reciprocal[k];
            for j in k + 1..N {
                a[i][j] -= f * a[k][j];
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        let mut s = b[i];
        for j in i + 1..N {
            s -= a[i][j] * x[j];
        }
        x[i] = s * reciprocal[i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// `A x`.
pub fn mul_vec<const N: usize>(a: &[[f64; N]; N], x: &[f64; N]) -> [f64; N] {
    core::array::from_fn(|i| (0..N).map(|j| a[i][j] * x[j]).sum())
}

/// `A B`.
pub fn mul<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> [[f64; N]; N] {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..N).map(|k| a[i][k] * b[k][j]).sum()))
}

/// `Aᵀ`.
pub fn transpose<const N: usize>(a: &[[f64; N]; N]) -> [[f64; N]; N] {
    core::array::from_fn(|i| core::array::from_fn(|j| a[j][i]))
}

/// The largest magnitude of `v`.
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pivoting_solves_a_matrix_with_a_zero_leading_entry() {
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let b = [3.0, 2.0, 4.0];
        let x = solve(&a, &b, 1e-12).unwrap();
        let back = mul_vec(&a, &x);
        for k in 0..3 {
            assert!((back[k] - b[k]).abs() < 1e-14, "{back:?}");
        }
        assert!(solve(&[[1.0, 2.0], [2.0, 4.0]], &[1.0, 1.0], 1e-12).is_none());
    }

    /// A pivot of `1e-14` against entries of 4 is singular at `1e-12` and regular at `1e-16`;
    /// a NaN is refused.
    #[test]
    fn the_tolerance_is_relative_to_the_largest_entry() {
        let nearly = [[1.0, 2.0], [2.0, 4.0 + 1e-14]];
        assert!(solve(&nearly, &[1.0, 1.0], 1e-12).is_none());
        let x = solve(&nearly, &[1.0, 2.0], 1e-16).unwrap();
        assert!((x[0] + 2.0 * x[1] - 1.0).abs() < 1e-12, "{x:?}");
        assert!(solve(&[[1.0, f64::NAN], [0.0, 1.0]], &[1.0, 1.0], 1e-12).is_none());
        assert!(solve(&[[1.0, 0.0], [f64::NAN, 1.0]], &[1.0, 1.0], 1e-12).is_none());
        assert!(solve(&[[1.0, 0.0], [0.0, 1.0]], &[f64::NAN, 1.0], 1e-12).is_none());
        assert!(solve(&[[f64::INFINITY, 0.0], [0.0, 1.0]], &[1.0, 1.0], 1e-12).is_none());
    }
}
