//! The R-U-S leg of the rotary hexapod (and the Delta's arm): a motor at `A_i` on the base turns
//! a crank of length `c` about its axis `r_i`; a rod of length `L` runs from a U joint at the
//! crank's tip `E_i` (first axis `r_i`, fixed in the crank) to a ball at `B_i = C + R p_i` on
//! the platform.
//!
//! Its coordinates are `B_i` (base frame). The crank's angle has a closed form in them (the
//! issue's inverse kinematics, docs/mechanisms.md): with `d = B - A`, `e1 = d·h`, `e2 = d·k`,
//! `ρ² = e1² + e2²`, `K = (|d|² + c² - L²)/(2c)` and `W = √(ρ² - K²)`,
//!
//! `cos θ = (e1 K - b e2 W)/ρ²`, `sin θ = (e2 K + b e1 W)/ρ²`
//!
//! (`θ = atan2(e2, e1) + b acos(K/ρ)`, `b` the branch), so the crank's and the rod's frames are
//! algebraic in the coordinates and only the actuator's value calls a function:
//! `θ = 2 atan(sin θ/(1 + cos θ))`, in `(-π, π)` as the description wraps it. The crank frame
//! is `x'' = cos θ h + sin θ k`, `z'' = r`; the rod frame `z' = u = (B - E)/L`,
//! `y' = (u × r)/|u × r|`, `x' = y' × z'` (the U joint's second axis is fixed in the rod).
//! `|B - E| = L` holds identically in the coordinates, so `u` divides by the constant.

use super::{AngularMotion, Hidden, Leg, LegBody, MassMatrix, Placement};
use crate::dag::Expr;
use crate::linalg::{Mat, Vec3, Vector};
use crate::model::bodies::Inertial;

/// One R-U-S leg's parameters: `A_i`, the unit `r_i` and `h_i` (base frame), `p_i` (platform
/// frame), the crank's and the rod's lengths, the branch (`±1`), the encoder's offset, and the
/// crank's (about `A_i`, crank frame) and each rod's (about its U joint, rod frame) inertial
/// parameters.
pub struct Rus<'g> {
    pub base: Vec3<'g>,
    pub axis: Vec3<'g>,
    pub zero: Vec3<'g>,
    pub platform: Vec3<'g>,
    pub crank_length: Expr<'g>,
    pub rod_length: Expr<'g>,
    pub branch: Expr<'g>,
    pub offset: Expr<'g>,
    pub crank: Inertial<'g>,
    pub rod: Inertial<'g>,
    /// Each rod's offset along `r_i` from the crank's tip and from the ball: `[0]` for the
    /// rotary hexapod's one rod, `[w/2, -w/2]` for a Delta's parallelogram.
    pub rods: Vec<Expr<'g>>,
    /// Give the rods' angular motion in closed form (else the derivation finds it).
    pub closed_form: bool,
}

/// The leg's closed forms at its coordinates.
pub struct CrankState<'g> {
    /// `cos θ`, `sin θ`.
    pub cos: Expr<'g>,
    pub sin: Expr<'g>,
    /// `1 - (K/ρ)²`: the squared sine of the angle between crank and rod in the crank's
    /// plane; zero where they align (the reach's edge), negative beyond reach.
    pub aligned: Expr<'g>,
    /// The crank's direction `x''` and its tip `E`.
    pub along: Vec3<'g>,
    pub elbow: Vec3<'g>,
}

/// `θ` in `(-π, π)` from its cosine and sine: `2 atan(sin θ/(1 + cos θ))`.
fn half_angle<'g>(cos: Expr<'g>, sin: Expr<'g>) -> Expr<'g> {
    (sin * (cos + 1.0).recip()).atan() * 2.0
}

fn keep<'g>(v: Vec3<'g>) -> Vec3<'g> {
    Vector(v.0.map(Expr::keep))
}

impl<'g> Rus<'g> {
    /// `θ`'s cosine and sine, the crank's direction and tip, at the ball `b`.
    pub fn crank_state(&self, b: &Vec3<'g>) -> CrankState<'g> {
        let d = keep(*b - self.base);
        let k = keep(self.axis.cross(&self.zero));
        let (e1, e2) = (d.dot(&self.zero).keep(), d.dot(&k).keep());
        let rho2 = (e1 * e1 + e2 * e2).keep();
        let c = self.crank_length;
        let l = self.rod_length;
        let big_k = ((d.dot(&d) + c * c - l * l) * (c * 2.0).recip()).keep();
        let w2 = (rho2 - big_k * big_k).keep();
        let w = (w2.sqrt() * self.branch).keep();
        let inverse = rho2.recip().keep();
        let cos = ((e1 * big_k - e2 * w) * inverse).keep();
        let sin = ((e2 * big_k + e1 * w) * inverse).keep();
        let along = keep(self.zero.scale(cos) + k.scale(sin));
        CrankState {
            cos,
            sin,
            aligned: w2 * inverse,
            along,
            elbow: keep(self.base + along.scale(c)),
        }
    }

    /// The actuator's value at the ball `b`: `θ + o`, `θ = 2 atan(sin θ/(1 + cos θ))`.
    pub fn actuator_at(&self, b: &Vec3<'g>) -> Expr<'g> {
        let crank = self.crank_state(b);
        half_angle(crank.cos, crank.sin) + self.offset
    }

    /// The rod's axes `x', y', z'` and `|u × r|` (the U joint's sine), for the elbow `e` and
    /// ball `b`.
    pub fn rod_frame(&self, e: &Vec3<'g>, b: &Vec3<'g>) -> ([Vec3<'g>; 3], Expr<'g>) {
        let z = keep((*b - *e).scale(self.rod_length.recip()));
        let n = keep(z.cross(&self.axis));
        let sine = n.dot(&n).sqrt().keep();
        let y = keep(n.scale(sine.recip()));
        ([keep(y.cross(&z)), y, z], sine)
    }
}

impl<'g> Rus<'g> {
    /// The crank's direction `x'' = cos θ h + sin θ k`, its normal `y'' = r × x'' =
    /// cos θ k - sin θ h` and its tip `E`, from the hidden `cos θ`, `sin θ` (`s[3]`, `s[4]`).
    fn crank_axes(&self, s: &[Expr<'g>]) -> (Vec3<'g>, Vec3<'g>, Vec3<'g>) {
        let k = keep(self.axis.cross(&self.zero));
        let (cos, sin) = (s[3], s[4]);
        let along = keep(self.zero.scale(cos) + k.scale(sin));
        let normal = keep(k.scale(cos) - self.zero.scale(sin));
        (
            along,
            normal,
            keep(self.base + along.scale(self.crank_length)),
        )
    }

    /// `∇θ = (B - E)/(c (B - E)·y'')`: the constraint `|B - E(θ)| = L` differentiated.
    fn angle_gradient(&self, s: &[Expr<'g>]) -> Vec3<'g> {
        let (_, normal, elbow) = self.crank_axes(s);
        let rod = keep(Vector([s[0], s[1], s[2]]) - elbow);
        let scale = (rod.dot(&normal) * self.crank_length).recip().keep();
        keep(rod.scale(scale))
    }
}

impl<'g> Leg<'g> for Rus<'g> {
    fn coordinates(&self, placement: &Placement<'g>) -> Vec<Expr<'g>> {
        placement.point(&self.platform).to_vec()
    }

    /// `cos θ` and `sin θ`, whose partials are `-sin θ ∇θ` and `cos θ ∇θ`.
    fn hidden_count(&self) -> usize {
        2
    }

    fn hidden(&self, s: &[Expr<'g>]) -> Vec<Hidden<'g>> {
        let crank = self.crank_state(&Vector([s[0], s[1], s[2]]));
        let gradient = self.angle_gradient(s);
        let (cos, sin) = (s[3], s[4]);
        vec![
            Hidden {
                value: crank.cos,
                gradient: gradient.0.iter().map(|&d| -(sin * d)).collect(),
            },
            Hidden {
                value: crank.sin,
                gradient: gradient.0.iter().map(|&d| cos * d).collect(),
            },
        ]
    }

    fn actuator(&self, s: &[Expr<'g>]) -> Expr<'g> {
        half_angle(s[3], s[4]) + self.offset
    }

    fn actuator_gradient(&self, s: &[Expr<'g>]) -> Option<Vec<Expr<'g>>> {
        Some(self.angle_gradient(s).to_vec())
    }

    /// The rod's origin, the elbow, moves along `y''` alone: its velocity per unit rate is
    /// a rank-one map, which the energy's products keep and the differentiated `φ` does not.
    fn mass_matrix(&self) -> MassMatrix {
        MassMatrix::Energy
    }

    fn bodies(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> Vec<LegBody<'g>> {
        let b = Vector([s[0], s[1], s[2]]);
        let (along, normal, elbow) = self.crank_axes(s);
        let ([x, y, z], _) = self.rod_frame(&elbow, &b);
        let frame = |axes: [Vec3<'g>; 3]| Mat::from_fn(|i, j| axes[j][i]);
        // The crank turns about its own `z'' = r`: `ω = (0, 0, θ̇)`, and at rest accelerations
        // of the ball `ω̇ = (0, 0, θ̈₀)`, the `θ̈₀` of the rod's motion (the derivation finds it
        // without the closed forms).
        let gradient = self.angle_gradient(s);
        let g = s[0].graph();
        let crank_rates: Vec<Vec3<'g>> = (0..3)
            .map(|k| Vector([g.zero(), g.zero(), gradient[k]]))
            .collect();
        let motion = self.closed_form.then(|| self.rod_motion(s, sd));
        let mut bodies = vec![LegBody {
            rotation: frame([along, normal, self.axis]),
            origin: self.base,
            inertial: self.crank,
            angular: motion.as_ref().map(|m| AngularMotion {
                rates: crank_rates.clone(),
                bias: Vector([g.zero(), g.zero(), m.crank_bias]),
            }),
            angular_rates: Some(crank_rates),
            velocity_rates: None,
            acceleration_bias: None,
        }];
        let angular = motion.as_ref().map(|m| m.rod.clone());
        let elbow_bias = motion.as_ref().map(|m| m.elbow_bias);
        // Every point of a rod's end at the elbow moves as the elbow, `Ė = c θ̇ y''`: in the
        // rod's frame, `c (x'·y'', y'·y'', z'·y'') ∇θ`.
        let velocity_rates = self.closed_form.then(|| {
            let along_normal = keep(Vector([x.dot(&normal), y.dot(&normal), z.dot(&normal)]));
            let scaled = keep(gradient.scale(self.crank_length));
            (0..3).map(|k| along_normal.scale(scaled[k])).collect()
        });
        bodies.extend(self.rods.iter().map(|&offset| LegBody {
            rotation: frame([x, y, z]),
            origin: elbow + self.axis.scale(offset),
            inertial: self.rod,
            angular: angular.clone(),
            angular_rates: None,
            velocity_rates: velocity_rates.clone(),
            acceleration_bias: elbow_bias,
        }));
        bodies
    }
}

impl<'g> Rus<'g> {
    /// The rods' angular motion in their frame. A rod turns as a U-P-S leg of constant length
    /// `L` on the U joint's fixed first axis `r` (docs of [`super::ups`]): `ω = G ḋ` with
    /// `G = [-y'; x'; -κ y']/L`, `κ = (r·u)/|u × r|`, `d = B - E`; and
    /// `ω̇ = G d̈ + (ω_y ω_z, -ω_x ω_z, ω_x ω_y/|u × r|² + κ ω_y ω_z)`. The elbow moves as
    /// `Ė = c θ̇ y''` and `Ë = c (θ̈ y'' - θ̇² x'')`, so `ḋ = M Ḃ` with `M = I - c y'' ∇θᵀ`, and
    /// `θ̈ = ∇θ·B̈ + θ̈₀` with `θ̈₀ = (c θ̇² d·x'' + |ḋ|²)/(c d·y'')` (the constraint
    /// `|d|² = L²` differentiated twice).
    fn rod_motion(&self, s: &[Expr<'g>], sd: &[Expr<'g>]) -> RodMotion<'g> {
        let b = Vector([s[0], s[1], s[2]]);
        let (along, normal, elbow) = self.crank_axes(s);
        let ([x, y, z], sine) = self.rod_frame(&elbow, &b);
        let d = keep(b - elbow);
        let c = self.crank_length;
        let inverse_length = self.rod_length.recip().keep();
        let kappa = (self.axis.dot(&z) * sine.recip()).keep();
        let map = |v: &Vec3<'g>| {
            let wx = -(y.dot(v) * inverse_length);
            Vector([wx, x.dot(v) * inverse_length, kappa * wx])
        };
        let gradient = self.angle_gradient(s);
        let through_elbow = Vector(map(&normal).0.map(Expr::keep));
        let unit = |k: usize| {
            let g = s[0].graph();
            Vector::from_fn(|j| if j == k { g.one() } else { g.zero() })
        };
        // `ω_z = κ ω_x` in every column, as in `map`.
        let rates = (0..3)
            .map(|k| {
                let column = map(&unit(k)) - through_elbow.scale(c * gradient[k]);
                let wx = column[0].keep();
                Vector([wx, column[1], kappa * wx])
            })
            .collect();
        let b_dot = Vector([sd[0], sd[1], sd[2]]);
        let theta_dot = gradient.dot(&b_dot).keep();
        let d_dot = keep(b_dot - normal.scale(c * theta_dot));
        let omega = Vector(map(&d_dot).0.map(Expr::keep));
        let scale = (d.dot(&normal) * c).recip();
        let theta_ddot =
            ((d.dot(&along) * c * theta_dot * theta_dot + d_dot.dot(&d_dot)) * scale).keep();
        let elbow_bias =
            keep(normal.scale(c * theta_ddot) - along.scale(c * theta_dot * theta_dot));
        let [wx, wy, wz] = omega.0;
        let coupling = (wy * wz).keep();
        let bias = map(&-elbow_bias)
            + Vector([
                coupling,
                -(wx * wz),
                wx * wy * (sine * sine).recip() + kappa * coupling,
            ]);
        RodMotion {
            rod: AngularMotion { rates, bias },
            crank_bias: theta_ddot,
            elbow_bias,
        }
    }
}

/// A leg's motion at rest accelerations of its ball, `B̈ = 0`, in closed form
/// ([`Rus::rod_motion`]).
struct RodMotion<'g> {
    /// The rods' angular motion in their frame.
    rod: AngularMotion<'g>,
    /// `θ̈₀`, the crank's angular acceleration.
    crank_bias: Expr<'g>,
    /// `Ë₀ = c (θ̈₀ y'' - θ̇² x'')`, the elbow's acceleration (base frame).
    elbow_bias: Vec3<'g>,
}
