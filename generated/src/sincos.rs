//! The sine and cosine of several arguments at once, for the batch kernels: when every lane
//! lies within a quarter turn, [`crate::quarter`]'s polynomials run on all lanes together
//! (vector instructions, no call); otherwise each lane calls what the single-state kernels
//! call. Either way a lane gets the single-state kernel's bits.
//!
//! A branch-free vectorised reduction by `π/2` (fdlibm's, within one ulp of the library beyond
//! `π/4`) was tried and dropped: one ulp of a sine, amplified by the conditioning of a pose near
//! a singularity, moved forward-dynamics results by up to 1.5e-9 of their size.

use crate::quarter::{self, Arith};

/// `N` lanes of `f64`, every operation lane by lane (LLVM turns them into vector instructions).
#[derive(Clone, Copy)]
pub(crate) struct Wide<const N: usize>(pub [f64; N]);

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> core::ops::$trait for Wide<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Wide(core::array::from_fn(|l| self.0[l] $op rhs.0[l]))
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);

impl<const N: usize> Arith for Wide<N> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Wide([x; N])
    }
    #[inline(always)]
    fn where_zero(z: Self, a: Self, b: Self) -> Self {
        Wide(core::array::from_fn(|l| {
            f64::where_zero(z.0[l], a.0[l], b.0[l])
        }))
    }
}

/// `(sin x, cos x)` of `N` values at once, each lane equal to [`crate::trig::sin_cos`] of it.
#[inline(always)]
pub fn sin_cos_lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    // `&` rather than `&&`: one vector comparison, no branch per lane.
    if x.iter()
        .fold(true, |all, v| all & (v.abs() <= quarter::RANGE))
    {
        let (s, c) = quarter::kernel(Wide(x));
        (s.0, c.0)
    } else {
        lane_by_lane(x)
    }
}

#[inline(never)]
fn lane_by_lane<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    for l in 0..N {
        (s[l], c[l]) = crate::trig::sin_cos(x[l]);
    }
    (s, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_lane_is_the_single_state_sine_and_cosine() {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan();
        for xs in [
            [0.3, -0.0, 0.785, -1e-300],
            [0.3, -2.0, 0.7, 63.9],
            [1e6, f64::NAN, 0.0, f64::INFINITY],
        ] {
            let (s, c) = sin_cos_lanes(xs);
            for l in 0..4 {
                let one = crate::trig::sin_cos(xs[l]);
                assert!(same(s[l], one.0) && same(c[l], one.1), "{xs:?}, lane {l}");
            }
        }
    }
}
