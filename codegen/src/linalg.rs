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
    fn cross_is_anticommutative() {
        let g = Graph::new(Policy::default());
        let a = Vector([g.input(0), g.input(1), g.input(2)]);
        let b = Vector([g.input(3), g.input(4), g.input(5)]);
        let s = a.cross(&b) + b.cross(&a);
        assert!(s.0.iter().all(|e| e.as_const() == Some(0.0)));
    }
}
