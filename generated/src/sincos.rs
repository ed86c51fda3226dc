//! The sine and cosine of several arguments at once, for the batch kernels: when every lane
//! lies within an eighth of a turn, [`crate::eighth_turn`]'s polynomials run on all lanes together
//! (vector instructions, no call), and a lane gets the single-state kernel's bits.
//!
//! The batch kernels ask [`within_eighth_turn`] first and, where a lane lies beyond, hand the
//! whole batch to the single-state kernel lane by lane: a kernel that chose between the
//! vectorised pair and a call per lane at each sine-cosine merged the two through memory, which
//! cost the paper model's batch inverse dynamics a fifth of its time. [`sin_cos_lanes`] keeps
//! the per-pair choice for other callers.
//!
//! A branch-free vectorised reduction by `π/2` (fdlibm's, within one ulp of the library beyond
//! `π/4`) was tried and dropped: one ulp of a sine, amplified by the conditioning of a pose near
//! a singularity, moved forward-dynamics results by up to 1.5e-9 of their size.

use crate::eighth_turn::{self, Arith};
use crate::lanes::F64x4;

impl Arith for F64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F64x4::splat(x)
    }
    #[inline(always)]
    fn where_zero(z: Self, a: Self, b: Self) -> Self {
        F64x4(core::array::from_fn(|l| {
            f64::where_zero(z.0[l], a.0[l], b.0[l])
        }))
    }
}

/// Whether every lane lies within an eighth of a turn (`|x| ≤ π/4`, not NaN), where
/// [`sin_cos_eighth_turn`] computes the library's sine and cosine.
#[inline(always)]
pub fn within_eighth_turn(x: F64x4) -> bool {
    // `&` rather than `&&`: one vector comparison, no branch per lane.
    x.0.iter()
        .fold(true, |all, v| all & (v.abs() <= eighth_turn::RANGE))
}

/// `(sin x, cos x)` of four values [`within_eighth_turn`], in vector instructions, each lane
/// equal to [`crate::trig::sin_cos`] of it. Beyond an eighth of a turn the lanes are fdlibm's
/// polynomials without its argument reduction: close, but not the library's bits.
#[inline(always)]
pub fn sin_cos_eighth_turn(x: F64x4) -> (F64x4, F64x4) {
    eighth_turn::kernel(x)
}

/// `(sin x, cos x)` of four values at once, each lane equal to [`crate::trig::sin_cos`] of it.
#[inline(always)]
pub fn sin_cos_lanes(x: F64x4) -> (F64x4, F64x4) {
    if within_eighth_turn(x) {
        sin_cos_eighth_turn(x)
    } else {
        lane_by_lane(x)
    }
}

#[inline(never)]
fn lane_by_lane(x: F64x4) -> (F64x4, F64x4) {
    let mut s = [0.0; 4];
    let mut c = [0.0; 4];
    for l in 0..4 {
        (s[l], c[l]) = crate::trig::sin_cos(x.0[l]);
    }
    (F64x4(s), F64x4(c))
}
