//! The numerical linear algebra the generator needs at generation time: QR with column pivoting,
//! and the dependencies it reveals between columns.

/// `A P = Q R` by Householder reflections, each step taking the remaining column of largest norm.
/// Ties, up to rounding, go to the column first in `A`, so that of equal columns the earliest
/// leads.
#[derive(Clone, Debug)]
pub struct PivotedQr {
    /// `R`, `min(m, n)` rows of `n` entries, upper triangular.
    pub r: Vec<Vec<f64>>,
    /// Column `k` of `R` is column `permutation[k]` of `A`.
    pub permutation: Vec<usize>,
}

/// The pivoted QR of the row-major matrix `a` (`m` rows of `n` entries).
pub fn pivoted_qr(a: &[Vec<f64>]) -> PivotedQr {
    let m = a.len();
    let n = a.first().map_or(0, Vec::len);
    let mut a = a.to_vec();
    let mut permutation: Vec<usize> = (0..n).collect();
    for k in 0..m.min(n) {
        let norm = |j: usize, a: &[Vec<f64>]| a[k..].iter().map(|row| row[j] * row[j]).sum::<f64>();
        let norms: Vec<f64> = (k..n).map(|j| norm(j, &a)).collect();
        let largest = norms.iter().copied().fold(0.0, f64::max);
        let pivot = (k..n)
            .filter(|&j| norms[j - k] >= largest * (1.0 - 1e-9))
            .min_by_key(|&j| permutation[j])
            .unwrap_or(k);
        for row in a.iter_mut() {
            row.swap(k, pivot);
        }
        permutation.swap(k, pivot);
        let x: Vec<f64> = a[k..].iter().map(|row| row[k]).collect();
        let length = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if length == 0.0 {
            continue;
        }
        let alpha = if x[0] > 0.0 { -length } else { length };
        let mut v = x;
        v[0] -= alpha;
        let v2: f64 = v.iter().map(|t| t * t).sum();
        for j in k..n {
            let s: f64 = v.iter().zip(&a[k..]).map(|(vi, row)| vi * row[j]).sum();
            let f = 2.0 * s / v2;
            for (vi, row) in v.iter().zip(a[k..].iter_mut()) {
                row[j] -= f * vi;
            }
        }
    }
    let r = a
        .into_iter()
        .take(m.min(n))
        .enumerate()
        .map(|(i, row)| {
            row.into_iter()
                .enumerate()
                .map(|(j, x)| if j < i { 0.0 } else { x })
                .collect()
        })
        .collect();
    PivotedQr { r, permutation }
}

impl PivotedQr {
    /// The numerical rank: the diagonal entries above `tolerance · |R_00|`.
    pub fn rank(&self, tolerance: f64) -> usize {
        let first = self.r.first().map_or(0.0, |row| row[0].abs());
        self.r
            .iter()
            .enumerate()
            .take_while(|(i, row)| row[*i].abs() > tolerance * first)
            .count()
    }

    /// `K = R11⁻¹ R12` for rank `r`: column `permutation[r + d]` of `A` is
    /// `Σ_i K[i][d] · column permutation[i]`.
    pub fn dependencies(&self, r: usize) -> Vec<Vec<f64>> {
        let n = self.permutation.len();
        // Column `d` of `K` solves `R11 x = R12[:, d]` by back substitution.
        let columns: Vec<Vec<f64>> = (r..n)
            .map(|c| {
                let mut x = vec![0.0; r];
                for i in (0..r).rev() {
                    let tail: f64 = (i + 1..r).map(|j| self.r[i][j] * x[j]).sum();
                    x[i] = (self.r[i][c] - tail) / self.r[i][i];
                }
                x
            })
            .collect();
        (0..r)
            .map(|i| columns.iter().map(|x| x[i]).collect())
            .collect()
    }
}

/// A seeded linear congruential generator: the generator's sample states must be the same on
/// every machine and every run, so that the generated files are.
#[derive(Clone, Debug)]
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Self {
        Lcg(seed)
    }

    /// Uniform in `[-bound, bound)`.
    pub fn uniform(&mut self, bound: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let unit = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        bound * (2.0 * unit - 1.0)
    }

    /// One uniform draw per bound.
    pub fn vector(&mut self, bounds: &[f64]) -> Vec<f64> {
        bounds.iter().map(|&b| self.uniform(b)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_repeated_and_a_combined_column_are_found_dependent() {
        // Columns: a, b, a (again), 2a - b, c.
        let rows: Vec<Vec<f64>> = (0..8)
            .map(|i| {
                let t = i as f64;
                let (a, b, c) = (t.sin() + 2.0, (0.7 * t).cos(), t * t - 3.0);
                vec![a, b, a, 2.0 * a - b, c]
            })
            .collect();
        let qr = pivoted_qr(&rows);
        let r = qr.rank(1e-10);
        assert_eq!(r, 3);
        let k = qr.dependencies(r);
        // Every dependent column is rebuilt from the independent ones.
        for d in 0..2 {
            for row in &rows {
                let rebuilt: f64 = (0..r).map(|i| k[i][d] * row[qr.permutation[i]]).sum();
                assert!((rebuilt - row[qr.permutation[r + d]]).abs() < 1e-10);
            }
        }
    }
}
