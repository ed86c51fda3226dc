//! The U-P-S leg of the Gough-Stewart platform: a universal joint at `A_i` on the base, a
//! prismatic actuator (cylinder and rod), a spherical joint at `B_i = C + R p_i` on the
//! platform.
//!
//! Its coordinates are `B_i` (base frame). The actuator's value is the leg's length plus the
//! encoder's offset, `q = |B_i - A_i| + o_i`. Cylinder and rod turn together in the U joint's
//! frame: `z' = u = (B_i - A_i)/|B_i - A_i|`, `y' = (u × a)/|u × a|` (`a` the U joint's first
//! axis, fixed in the base), `x' = y' × z'`; the cylinder's reference point is `A_i`, the rod's
//! `B_i`. The leg's spin about its own axis is the U joint's, exact: `θ̇₁ (a·u)`.

use super::{AngularMotion, Leg, LegBody, Placement};
use crate::dag::Expr;
use crate::linalg::{Mat, Vec3, Vector};
use crate::model::bodies::Inertial;

/// One U-P-S leg's parameters: `A_i` (base frame), the U joint's first axis `a_i` (unit, base
/// frame), `p_i` (platform frame), the encoder's offset, and the cylinder's and rod's inertial
/// parameters (about `A_i` and `B_i`, leg frame).
pub struct Ups<'g> {
    pub base: Vec3<'g>,
    pub axis: Vec3<'g>,
    pub platform: Vec3<'g>,
    pub offset: Expr<'g>,
    pub cylinder: Inertial<'g>,
    pub rod: Inertial<'g>,
    /// Give the bodies' angular velocities in closed form (else the derivation finds them).
    pub closed_form: bool,
}

impl<'g> Ups<'g> {
    /// `d = B - A`, as units (with `A` constant, their sums would flatten into every
    /// expression that reads them).
    fn leg_vector(&self, s: &[Expr<'g>]) -> Vec3<'g> {
        Vector((Vector([s[0], s[1], s[2]]) - self.base).0.map(Expr::keep))
    }

    /// `d = B - A`, `e = d × a` and the leg frame's axes `x', y', z'` at the coordinates `s`.
    fn frame(&self, s: &[Expr<'g>]) -> (Vec3<'g>, Vec3<'g>, [Vec3<'g>; 3]) {
        let d = self.leg_vector(s);
        let e = Vector(d.cross(&self.axis).0.map(Expr::keep));
        // The axes as units: every projection on them then costs three products.
        let z = d.scale(d.dot(&d).sqrt().recip()).0.map(Expr::keep);
        let y = e.scale(e.dot(&e).sqrt().recip()).0.map(Expr::keep);
        let (y, z) = (Vector(y), Vector(z));
        (d, e, [Vector(y.cross(&z).0.map(Expr::keep)), y, z])
    }
}

impl<'g> Leg<'g> for Ups<'g> {
    /// `q̇ = u·ḋ`: the translation part of the row is `u`.
    fn unit_translation(&self) -> bool {
        true
    }

    fn coordinates(&self, placement: &Placement<'g>) -> Vec<Expr<'g>> {
        placement.point(&self.platform).to_vec()
    }

    fn actuator(&self, s: &[Expr<'g>]) -> Expr<'g> {
        let d = self.leg_vector(s);
        d.dot(&d).sqrt() + self.offset
    }

    fn bodies(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> Vec<LegBody<'g>> {
        let (_, _, [x, y, z]) = self.frame(s);
        let rotation = Mat::from_fn(|i, j| [x, y, z][j][i]);
        let angular = self.closed_form.then(|| self.angular_motion(s, sd));
        vec![
            LegBody {
                rotation,
                origin: self.base,
                inertial: self.cylinder,
                angular: angular.clone(),
                angular_rates: None,
                velocity_rates: None,
                acceleration_bias: None,
            },
            LegBody {
                rotation,
                origin: Vector([s[0], s[1], s[2]]),
                inertial: self.rod,
                angular,
                angular_rates: None,
                velocity_rates: None,
                acceleration_bias: None,
            },
        ]
    }
}

impl<'g> Ups<'g> {
    /// The leg's angular motion in its frame, from the U joint's two rates: with `ω = G ḋ`,
    /// `G = [-y'; x'; -κ y'] / |d|` and `κ = (a·d)/|d × a|`, so `ω_z' = κ ω_x'` is the U joint's
    /// spin `θ̇₁ (a·u)`; and `ω̇ = G d̈ + b` with
    /// `b = (ω_y ω_z - 2 q̇ ω_x/|d|, -ω_x ω_z - 2 q̇ ω_y/|d|, ω_x ω_y/|u × a|² + κ b_x)`, where
    /// `q̇ = u·ḋ` (body-frame identities of the rotating axes: `ẏ'·u̇ = -ω_y ω_z`, ...).
    fn angular_motion(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> AngularMotion<'g> {
        let (d, e, [x, y, z]) = self.frame(s);
        let rate = Vector([sd[0], sd[1], sd[2]]);
        let squared_length = d.dot(&d);
        let inverse_length = squared_length.sqrt().recip().keep();
        let inverse_sine = e.dot(&e).sqrt().recip().keep();
        let kappa = (self.axis.dot(&d) * inverse_sine).keep();
        let rates = (0..3)
            .map(|k| Vector([-y[k], x[k], -(kappa * y[k])]).scale(inverse_length))
            .collect();
        let omega_x = -(y.dot(&rate) * inverse_length);
        let omega_y = x.dot(&rate) * inverse_length;
        let omega_z = kappa * omega_x;
        let qd2 = (z.dot(&rate) * inverse_length * 2.0).keep();
        let bias_x = omega_y * omega_z - qd2 * omega_x;
        let bias_y = -(omega_x * omega_z) - qd2 * omega_y;
        // `1/|u × a|² = |d|²/|d × a|²` for a unit `a`.
        let inverse_sine_squared = squared_length * inverse_sine * inverse_sine;
        let bias_z = omega_x * omega_y * inverse_sine_squared + kappa * bias_x;
        AngularMotion {
            rates,
            bias: Vector([bias_x, bias_y, bias_z]),
        }
    }
}
