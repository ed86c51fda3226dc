//! The C5's leg as a leg type (P-S-PP): the actuator's rod slides along the fixed axis `n_i`
//! through `A_i`, the ball at `B_i = A_i + Q_i1 n_i` joins it to two crossed plates that slide
//! in the platform plane of normal `m_i = R e_k` (the consistent model's mechanism).
//!
//! Its coordinates are the platform's whole placement (`R` row-major, then `C`): the plates
//! keep the platform's orientation. The shipped C5 kernels are the consistent model's
//! hand-derived ones; this leg type proves the derivation of [`super`] general, since through
//! it the C5 comes out the same (the tests of [`crate::model::legged`]).

use super::{Leg, LegBody, Placement};
use crate::dag::Expr;
use crate::linalg::{Mat, Mat3, Vec3, Vector};
use crate::model::bodies::Inertial;
use crate::model::geometry::{actuator_length, axis};

/// Segment `i`'s leg: its anchor `A_i`, the rod (reference point `B_i`, base frame) and the
/// plates and ball housing (reference point `B_i`, platform frame).
pub struct Psp<'g> {
    pub segment: usize,
    pub anchor: Vec3<'g>,
    pub rod: Inertial<'g>,
    pub joint: Inertial<'g>,
}

fn placement<'g>(s: &[Expr<'g>]) -> (Mat3<'g>, Vec3<'g>) {
    (
        Mat::from_fn(|i, j| s[3 * i + j]),
        Vector([s[9], s[10], s[11]]),
    )
}

impl<'g> Leg<'g> for Psp<'g> {
    fn coordinates(&self, placement: &Placement<'g>) -> Vec<Expr<'g>> {
        let mut s = placement.r.rows();
        s.extend(placement.c.to_vec());
        s
    }

    /// Eq 16: `m_i·(B_i - C) = 0`.
    fn actuator(&self, s: &[Expr<'g>]) -> Expr<'g> {
        let (r, c) = placement(s);
        actuator_length(&r, &c, &self.anchor, self.segment)
    }

    fn bodies(&self, s: &[Expr<'g>], _sd: &[Expr<'g>]) -> Vec<LegBody<'g>> {
        let (r, _) = placement(s);
        let g = s[0].graph();
        let n = axis(g, self.segment);
        let ball = self.anchor + n.scale(self.actuator(s));
        vec![
            LegBody {
                rotation: Mat::identity(g),
                origin: ball,
                inertial: self.rod,
                angular: None,
                angular_rates: None,
                velocity_rates: None,
                acceleration_bias: None,
            },
            LegBody {
                rotation: r,
                origin: ball,
                inertial: self.joint,
                angular: None,
                angular_rates: None,
                velocity_rates: None,
                acceleration_bias: None,
            },
        ]
    }
}
