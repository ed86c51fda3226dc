//! Small symbolic matrices and vectors over [`Expr`], so model code reads like its equations.
//!
//! Products of sparse matrices cost nothing to write: zeros and ones fold in the node
//! constructors, so only the arithmetic that survives reaches the kernel.

use crate::dag::{Expr, Graph};
use std::ops::{Add, Index, IndexMut, Mul, Neg, Sub};

/// An `R × C` matrix of expressions.
#[derive(Clone, Copy, Debug)]
pub struct Mat<'g, const R: usize, const C: usize>(pub [[Expr<'g>; C]; R]);

/// An `N`-vector of expressions.
#[derive(Clone, Copy, Debug)]
pub struct Vector<'g, const N: usize>(pub [Expr<'g>; N]);

pub type Vec3<'g> = Vector<'g, 3>;
pub type Vec6<'g> = Vector<'g, 6>;
pub type Mat3<'g> = Mat<'g, 3, 3>;
pub type Mat6<'g> = Mat<'g, 6, 6>;

impl<'g, const R: usize, const C: usize> Mat<'g, R, C> {
    pub fn from_fn(f: impl FnMut(usize, usize) -> Expr<'g>) -> Self {
        let mut f = f;
        Mat(std::array::from_fn(|i| std::array::from_fn(|j| f(i, j))))
    }

    /// A matrix of numbers, folded as constants.
    pub fn from_values(g: &'g Graph, values: [[f64; C]; R]) -> Self {
        Self::from_fn(|i, j| g.constant(values[i][j]))
    }

    pub fn zeros(g: &'g Graph) -> Self {
        Self::from_fn(|_, _| g.zero())
    }

    pub fn transpose(&self) -> Mat<'g, C, R> {
        Mat::from_fn(|i, j| self.0[j][i])
    }

    pub fn column(&self, j: usize) -> Vector<'g, R> {
        Vector(std::array::from_fn(|i| self.0[i][j]))
    }

    pub fn row(&self, i: usize) -> Vector<'g, C> {
        Vector(self.0[i])
    }

    pub fn scale(&self, k: Expr<'g>) -> Self {
        Self::from_fn(|i, j| self.0[i][j] * k)
    }

    /// The rows as plain arrays, for kernel outputs.
    pub fn rows(&self) -> Vec<Expr<'g>> {
        self.0.iter().flatten().copied().collect()
    }
}

impl<'g, const N: usize> Mat<'g, N, N> {
    pub fn identity(g: &'g Graph) -> Self {
        Self::from_fn(|i, j| if i == j { g.one() } else { g.zero() })
    }
}

impl<'g, const N: usize> Vector<'g, N> {
    pub fn from_fn(f: impl FnMut(usize) -> Expr<'g>) -> Self {
        Vector(std::array::from_fn(f))
    }

    pub fn zeros(g: &'g Graph) -> Self {
        Self::from_fn(|_| g.zero())
    }

    pub fn from_values(g: &'g Graph, values: [f64; N]) -> Self {
        Self::from_fn(|i| g.constant(values[i]))
    }

    pub fn dot(&self, other: &Self) -> Expr<'g> {
        (0..N).map(|i| self.0[i] * other.0[i]).sum()
    }

    pub fn scale(&self, k: Expr<'g>) -> Self {
        Self::from_fn(|i| self.0[i] * k)
    }

    pub fn to_vec(&self) -> Vec<Expr<'g>> {
        self.0.to_vec()
    }

    /// Each element offered as a unit under `offer` ([`Expr::keep_where_cheaper`]).
    pub fn keep_where_cheaper(self, offer: &'static str) -> Self {
        Vector(self.0.map(|e| e.keep_where_cheaper(offer)))
    }
}

impl<'g, const N: usize> Index<usize> for Vector<'g, N> {
    type Output = Expr<'g>;
    fn index(&self, i: usize) -> &Expr<'g> {
        &self.0[i]
    }
}

impl<'g, const N: usize> IndexMut<usize> for Vector<'g, N> {
    fn index_mut(&mut self, i: usize) -> &mut Expr<'g> {
        &mut self.0[i]
    }
}

impl<'g, const R: usize, const K: usize, const C: usize> Mul<Mat<'g, K, C>> for Mat<'g, R, K> {
    type Output = Mat<'g, R, C>;
    fn mul(self, rhs: Mat<'g, K, C>) -> Mat<'g, R, C> {
        Mat::from_fn(|i, j| (0..K).map(|k| self.0[i][k] * rhs.0[k][j]).sum())
    }
}

impl<'g, const R: usize, const C: usize> Mul<Vector<'g, C>> for Mat<'g, R, C> {
    type Output = Vector<'g, R>;
    fn mul(self, rhs: Vector<'g, C>) -> Vector<'g, R> {
        Vector::from_fn(|i| (0..C).map(|k| self.0[i][k] * rhs.0[k]).sum())
    }
}

impl<'g, const R: usize, const C: usize> Add for Mat<'g, R, C> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self::from_fn(|i, j| self.0[i][j] + rhs.0[i][j])
    }
}

impl<'g, const R: usize, const C: usize> Sub for Mat<'g, R, C> {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        Self::from_fn(|i, j| self.0[i][j] - rhs.0[i][j])
    }
}

impl<'g, const N: usize> Add for Vector<'g, N> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        Self::from_fn(|i| self.0[i] + rhs.0[i])
    }
}

impl<'g, const N: usize> Sub for Vector<'g, N> {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        Self::from_fn(|i| self.0[i] - rhs.0[i])
    }
}

impl<'g, const N: usize> Neg for Vector<'g, N> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::from_fn(|i| -self.0[i])
    }
}

impl<'g> Vec3<'g> {
    /// `a × b`.
    pub fn cross(&self, b: &Self) -> Self {
        let a = self;
        Vector([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }

    /// The skew-symmetric matrix `ṽ` of section 2.2, with `ṽ w = v × w`.
    pub fn tilde(&self) -> Mat3<'g> {
        let z = self[0].graph().zero();
        let v = self;
        Mat([[z, -v[2], v[1]], [v[2], z, -v[0]], [-v[1], v[0], z]])
    }
}

impl<'g> Vec6<'g> {
    /// A spatial vector from its angular (or moment) and linear (or force) halves.
    pub fn spatial(top: Vec3<'g>, bottom: Vec3<'g>) -> Self {
        Vector([top[0], top[1], top[2], bottom[0], bottom[1], bottom[2]])
    }
    pub fn top(&self) -> Vec3<'g> {
        Vector([self[0], self[1], self[2]])
    }
    pub fn bottom(&self) -> Vec3<'g> {
        Vector([self[3], self[4], self[5]])
    }
}

impl<'g> Mat3<'g> {
    pub fn determinant(&self) -> Expr<'g> {
        let m = &self.0;
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    /// The adjugate, `adj(M) M = det(M) U`.
    pub fn adjugate(&self) -> Self {
        let m = &self.0;
        let cof = |r: usize, c: usize| {
            let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
            let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
            m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
        };
        Mat::from_fn(|i, j| cof(j, i))
    }

    /// `M⁻¹ b` by Cramer's rule, `adj(M) b / det(M)`, one reciprocal shared by the three
    /// entries. The caller guarantees `det(M) ≠ 0`.
    pub fn solve(&self, b: &Vec3<'g>) -> Vec3<'g> {
        let inv = self.determinant().recip();
        (self.adjugate() * *b).scale(inv)
    }
}

impl<'g, const N: usize> Mat<'g, N, N> {
    /// `M⁻¹ b` for a symmetric positive definite `M` by `LDLᵀ`, unrolled (no pivoting, which
    /// an SPD matrix does not need); reads the lower triangle only, and shares `1 / D_jj`.
    pub fn ldlt_solve(&self, b: &Vector<'g, N>) -> Vector<'g, N> {
        self.ldlt_solve_with_pivots(b).0
    }

    /// [`Mat::ldlt_solve`], with the pivots `D_jj`: where one is not above zero (or is small
    /// against the diagonal) `M` is not positive definite (or nearly singular), and the
    /// solution is not to be trusted.
    pub fn ldlt_solve_with_pivots(&self, b: &Vector<'g, N>) -> (Vector<'g, N>, Vector<'g, N>) {
        let m = &self.0;
        let g = m[0][0].graph();
        let mut l = [[g.zero(); N]; N];
        let mut d = [g.zero(); N];
        let mut d_inv = [g.zero(); N];
        for j in 0..N {
            let mut djj = m[j][j];
            for k in 0..j {
                djj = djj - l[j][k] * l[j][k] * d[k];
            }
            d[j] = djj;
            d_inv[j] = djj.recip();
            for i in j + 1..N {
                let mut lij = m[i][j];
                for k in 0..j {
                    lij = lij - l[i][k] * l[j][k] * d[k];
                }
                l[i][j] = lij * d_inv[j];
            }
        }
        let mut z = *b;
        for i in 0..N {
            for k in 0..i {
                z[i] = z[i] - l[i][k] * z[k];
            }
        }
        let mut x = Vector::from_fn(|i| z[i] * d_inv[i]);
        for i in (0..N).rev() {
            for k in i + 1..N {
                x[i] = x[i] - l[k][i] * x[k];
            }
        }
        (x, Vector(d))
    }
}

/// Builds a 6×6 matrix from its four 3×3 blocks.
pub fn blocks<'g>(a: Mat3<'g>, b: Mat3<'g>, c: Mat3<'g>, d: Mat3<'g>) -> Mat6<'g> {
    Mat::from_fn(|i, j| match (i < 3, j < 3) {
        (true, true) => a.0[i][j],
        (true, false) => b.0[i][j - 3],
        (false, true) => c.0[i - 3][j],
        (false, false) => d.0[i - 3][j - 3],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dag::Policy;

    #[test]
    fn sparse_product_costs_nothing_symbolic() {
        let g = Graph::new(Policy::default());
        let x = g.input(0);
        let e = Mat::<3, 3>::identity(&g);
        let m = e * Vector([x, x, x]).tilde() * e;
        assert_eq!(m.0[0][1].id, (-x).id);
        assert_eq!(m.0[0][0].as_const(), Some(0.0));
    }

    #[test]
    fn solve3_inverts_a_numeric_matrix() {
        let g = Graph::new(Policy::default());
        let m = Mat::from_values(&g, [[0.0, 2.0, -1.0], [3.0, 0.0, 4.0], [-2.0, 5.0, 0.0]]);
        let b = Vector::from_values(&g, [1.0, -2.0, 0.5]);
        let x = m.solve(&b);
        let back = m * x;
        for k in 0..3 {
            let got = back[k].as_const().unwrap();
            assert!((got - b[k].as_const().unwrap()).abs() < 1e-14, "{k}: {got}");
        }
    }

    #[test]
    fn ldlt_solves_a_numeric_spd_matrix() {
        let g = Graph::new(Policy::default());
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, -0.2], [0.5, -0.2, 2.0]];
        let m = Mat::from_values(&g, a);
        let b = Vector::from_values(&g, [1.0, -2.0, 0.5]);
        let x = m.ldlt_solve(&b);
        let back = m * x;
        for k in 0..3 {
            let got = back[k].as_const().unwrap();
            assert!((got - b[k].as_const().unwrap()).abs() < 1e-14, "{k}: {got}");
        }
    }

    #[test]
    fn cross_is_anticommutative() {
        let g = Graph::new(Policy::default());
        let a = Vector([g.input(0), g.input(1), g.input(2)]);
        let b = Vector([g.input(3), g.input(4), g.input(5)]);
        let s = a.cross(&b) + b.cross(&a);
        assert!(s.0.iter().all(|e| e.as_const() == Some(0.0)));
    }
}
