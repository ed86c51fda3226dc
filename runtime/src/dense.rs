//! Small dense linear algebra on arrays, for the few solves the runtime does itself (the
//! Gough-Stewart platform's Newton steps and joint-space maps): Gaussian elimination with
//! partial pivoting, and products.

/// `A x = b` by Gaussian elimination with partial pivoting; `None` when a pivot is below
/// `tolerance` times the largest entry of its column (the matrix is singular to that
/// precision).
pub fn solve<const N: usize>(a: &[[f64; N]; N], b: &[f64; N], tolerance: f64) -> Option<[f64; N]> {
    let mut a = *a;
    let mut b = *b;
    for k in 0..N {
        let scale = (k..N).fold(0.0_f64, |m, i| m.max(a[i][k].abs()));
        let pivot = (k..N).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        // NaN fails both comparisons: refused too.
        let regular = scale > 0.0 && a[pivot][k].abs() > tolerance * scale;
        if !regular {
            return None;
        }
        a.swap(k, pivot);
        b.swap(k, pivot);
        let (pivot_row, pivot_b) = (a[k], b[k]);
        for (row, bi) in a.iter_mut().zip(b.iter_mut()).skip(k + 1) {
            let f = row[k] / pivot_row[k];
            for (x, p) in row.iter_mut().zip(pivot_row).skip(k) {
                *x -= f * p;
            }
            *bi -= f * pivot_b;
        }
    }
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        let s = (i + 1..N).fold(b[i], |s, j| s - a[i][j] * x[j]);
        x[i] = s / a[i][i];
    }
    Some(x)
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
}
