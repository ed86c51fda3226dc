//! The R-U-S leg of the rotary hexapod and of the Delta: a motor on the base turns a crank
//! about its axis; a rod (the Delta: two parallel rods) runs from a U joint at the crank's tip
//! to a ball on the platform.
//!
//! Conventions (docs/mechanisms.md): `r_i` the motor's axis and `h_i` the crank's direction at
//! `θ_i = 0` (its part orthogonal to `r_i`), both normalised; `k_i = r_i × h_i`; the crank's tip
//! `E_i = A_i + c_i (cos θ_i h_i + sin θ_i k_i)`; the rod from `E_i` to the platform's joint
//! `B_i`, `|B_i − E_i| = L_i`. The actuator is `θ_i`, right-handed about `r_i`, read by the
//! encoder as `θ_i + encoder_offset`; `Γ_i` is the motor's torque about `r_i`.

use crate::math::{atan2, sqrt};
use crate::tree::{cross, dot, norm, scale, sub, unit};
use crate::{check_inertia, Error};
use alloc::format;
use alloc::string::String;
use core::f64::consts::PI;

/// The crank: its length, mass, centre of mass along it, and inertia.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Crank {
    /// `c_i`, from the motor's axis to the U joint (m).
    pub length: f64,
    /// Mass (kg).
    pub mass: f64,
    /// The centre of mass's distance from `A_i` along the crank (m).
    pub com: f64,
    /// `[Ixx, Iyy, Izz]` about the centre of mass in the crank frame `x'' = ` the crank's
    /// direction, `z'' = r_i` (kg·m²); a motor's rotor inertia goes into `Izz`.
    pub inertia: [f64; 3],
}

/// A rod (for the Delta, each of its parallelogram's two).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct RusRod {
    /// `L_i`, from the U joint's centre to the ball's (m).
    pub length: f64,
    /// The Delta's parallelogram: the distance between its two rods (m); absent for the
    /// rotary hexapod's single rod.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub separation: Option<f64>,
    /// Mass (kg), of each rod.
    pub mass: f64,
    /// The centre of mass's distance from the U joint along the rod (m).
    pub com: f64,
    /// `[transverse, transverse, axial]` about the centre of mass, rod frame (kg·m²).
    pub inertia: [f64; 3],
}

/// One R-U-S leg (a Delta's arm).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct RusLeg {
    /// `A_i`, the motor's joint centre, base frame (m).
    pub base: [f64; 3],
    /// `r_i`, the motor's axis (normalised on use).
    pub axis: [f64; 3],
    /// The crank's direction at `θ_i = 0` (its part orthogonal to `r_i`, normalised: `h_i`).
    pub zero: [f64; 3],
    pub crank: Crank,
    pub rod: RusRod,
    /// `p_i`, the ball's centre, platform frame (m); for the Delta the midpoint of its two.
    pub platform: [f64; 3],
    /// `+1` or `−1`: which of the two crank angles that reach `B_i`.
    pub branch: f64,
    /// The encoder reads `θ_i + encoder_offset` (rad).
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "is_zero"))]
    pub encoder_offset: f64,
}

#[cfg(feature = "serde")]
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// Why a crank cannot reach a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unreachable {
    /// `K/ρ`, beyond `±1` where no crank angle reaches.
    pub ratio: f64,
}

impl RusLeg {
    /// `(r_i, h_i, k_i)`, unit and right-handed.
    pub fn axes(&self) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let r = unit(self.axis);
        let h = unit(sub(self.zero, scale(r, dot(self.zero, r))));
        (r, h, cross(r, h))
    }

    /// The crank angle `θ_i` whose rod reaches `b` (base frame), wrapped into `(−π, π]`:
    /// `θ = atan2(e2, e1) + branch·acos(K/ρ)` with `d = b − A_i`, `e1 = d·h`, `e2 = d·k`,
    /// `ρ = √(e1² + e2²)`, `K = (|d|² + c² − L²)/(2c)`.
    ///
    /// # Errors
    /// [`Unreachable`] where `|K| > ρ`.
    pub fn crank_angle(&self, b: [f64; 3]) -> Result<f64, Unreachable> {
        let (_, h, k) = self.axes();
        let d = sub(b, self.base);
        let (e1, e2) = (dot(d, h), dot(d, k));
        let rho = sqrt(e1 * e1 + e2 * e2);
        let c = self.crank.length;
        let l = self.rod.length;
        let ratio = (dot(d, d) + c * c - l * l) / (2.0 * c * rho);
        // NaN (a ball on the axis: ρ = 0) is out of reach too.
        if ratio.is_nan() || ratio.abs() > 1.0 {
            return Err(Unreachable { ratio });
        }
        let angle = atan2(e2, e1) + self.branch * acos(ratio);
        Ok(wrap(angle))
    }

    /// The crank's tip `E_i` at `θ`.
    pub fn elbow(&self, theta: f64) -> [f64; 3] {
        let (_, h, k) = self.axes();
        let (s, c) = crate::math::sin_cos(theta);
        let x = [
            c * h[0] + s * k[0],
            c * h[1] + s * k[1],
            c * h[2] + s * k[2],
        ];
        crate::tree::add(self.base, scale(x, self.crank.length))
    }

    /// Every rule of a physical leg; `at` names its fields (`legs[2].crank.mass`).
    pub(crate) fn validate(&self, at: &dyn Fn(&str) -> String, delta: bool) -> Result<(), Error> {
        let finite = |field: &str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(invalid(at(field), "must be finite"))
            }
        };
        finite("base", &self.base)?;
        finite("axis", &self.axis)?;
        finite("zero", &self.zero)?;
        finite("platform", &self.platform)?;
        finite("encoder_offset", &[self.encoder_offset])?;
        let crank = &self.crank;
        finite("crank", &[crank.length, crank.mass, crank.com])?;
        finite("crank.inertia", &crank.inertia)?;
        let rod = &self.rod;
        finite("rod", &[rod.length, rod.mass, rod.com])?;
        finite("rod.inertia", &rod.inertia)?;
        if norm(self.axis) < 1e-12 {
            return Err(invalid(at("axis"), "must not be zero"));
        }
        let along = norm(cross(unit(self.axis), self.zero));
        if along.is_nan() || along <= 1e-9 * norm(self.zero).max(1e-300) {
            return Err(invalid(
                at("zero"),
                "must not be along `axis` (nor zero): the crank's direction at θ = 0 is its \
                 part orthogonal to the axis",
            ));
        }
        if self.branch != 1.0 && self.branch != -1.0 {
            return Err(invalid(at("branch"), "must be 1 or -1"));
        }
        for (field, length) in [("crank.length", crank.length), ("rod.length", rod.length)] {
            if length <= 0.0 {
                return Err(invalid(at(field), "must be positive"));
            }
        }
        for (field, mass) in [("crank.mass", crank.mass), ("rod.mass", rod.mass)] {
            if mass <= 0.0 {
                return Err(invalid(at(field), "must be positive"));
            }
        }
        let [xx, yy, zz] = crank.inertia;
        check_inertia(&at("crank.inertia"), &diagonal(xx, yy, zz), false)?;
        let [t, t2, a] = rod.inertia;
        if t != t2 {
            return Err(invalid(
                at("rod.inertia"),
                "must be [transverse, transverse, axial], the first two equal",
            ));
        }
        check_inertia(&at("rod.inertia"), &diagonal(t, t, a), true)?;
        match (delta, rod.separation) {
            (true, Some(w)) if w.is_finite() && w > 0.0 => Ok(()),
            (true, Some(_)) => Err(invalid(at("rod.separation"), "must be positive")),
            (true, None) => Err(invalid(
                at("rod.separation"),
                "is missing: the distance between the parallelogram's two rods",
            )),
            (false, Some(_)) => Err(invalid(
                at("rod.separation"),
                "is the Delta's parallelogram; a rotary hexapod's leg has one rod",
            )),
            (false, None) => Ok(()),
        }
    }
}

/// The entries of one leg in the kernels' geometry ([`RusLeg::kernel_geometry`]).
pub const LEG_GEOMETRY: usize = 16;

/// The names of [`RusLeg::kernel_geometry`]'s entries, after `leg{n}_`.
pub const LEG_GEOMETRY_NAMES: [&str; LEG_GEOMETRY] = [
    "base_x",
    "base_y",
    "base_z",
    "axis_x",
    "axis_y",
    "axis_z",
    "zero_x",
    "zero_y",
    "zero_z",
    "platform_x",
    "platform_y",
    "platform_z",
    "crank_length",
    "rod_length",
    "branch",
    "offset",
];

/// The names of the crank's standard parameters ([`RusLeg::crank_standard`]).
pub const CRANK_STANDARD: [&str; 5] = ["mass", "mx", "ixx", "iyy", "izz"];

/// The names of a rod's standard parameters ([`RusLeg::rod_standard`]).
pub const ROD_STANDARD: [&str; 4] = ["mass", "mz", "ixx", "izz"];

impl RusLeg {
    /// The leg's entries in the kernels' parameter vector: `A_i`, the unit `r_i` and `h_i`,
    /// `p_i`, the crank's and the rod's lengths, the branch and the encoder's offset.
    pub fn kernel_geometry(&self) -> [f64; LEG_GEOMETRY] {
        let (r, h, _) = self.axes();
        let mut out = [0.0; LEG_GEOMETRY];
        out[0..3].copy_from_slice(&self.base);
        out[3..6].copy_from_slice(&r);
        out[6..9].copy_from_slice(&h);
        out[9..12].copy_from_slice(&self.platform);
        out[12] = self.crank.length;
        out[13] = self.rod.length;
        out[14] = self.branch;
        out[15] = self.encoder_offset;
        out
    }

    /// The crank's standard parameters about `A_i` in the crank frame (`x''` along the crank,
    /// `z'' = r_i`): mass, first moment `m com` along `x''`, and the diagonal inertia moved
    /// from the centre of mass by the parallel-axis theorem.
    pub fn crank_standard(&self) -> [f64; 5] {
        let Crank {
            mass: m,
            com,
            inertia: [xx, yy, zz],
            ..
        } = self.crank;
        [m, m * com, xx, yy + m * com * com, zz + m * com * com]
    }

    /// A rod's standard parameters about its U joint's centre in the rod frame (`z'` along
    /// the rod): mass, first moment `m com` along `z'`, transverse and axial inertia (the
    /// transverse moved from the centre of mass).
    pub fn rod_standard(&self) -> [f64; 4] {
        let RusRod {
            mass: m,
            com,
            inertia: [t, _, a],
            ..
        } = self.rod;
        [m, m * com, t + m * com * com, a]
    }
}

fn diagonal(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
}

/// `acos x` for `|x| ≤ 1`, as `atan2(√(1 − x²), x)`: no libm function beyond the two
/// the description already needs.
fn acos(x: f64) -> f64 {
    atan2(sqrt((1.0 - x) * (1.0 + x)), x)
}

/// `x` wrapped into `(−π, π]`.
fn wrap(x: f64) -> f64 {
    let mut y = x;
    while y > PI {
        y -= 2.0 * PI;
    }
    while y <= -PI {
        y += 2.0 * PI;
    }
    y
}

pub(crate) fn invalid(field: impl Into<String>, rule: impl core::fmt::Display) -> Error {
    Error::Invalid {
        field: field.into(),
        rule: format!("{rule}"),
    }
}

/// The balls of a level platform centred over the base at height `z`: `p_i + (0, 0, z)`.
fn level(legs: &[RusLeg], z: f64) -> alloc::vec::Vec<[f64; 3]> {
    legs.iter()
        .map(|l| [l.platform[0], l.platform[1], l.platform[2] + z])
        .collect()
}

/// The default home height of a platform on `legs` ([`home_height`] of a level platform).
pub(crate) fn level_home(legs: &[RusLeg]) -> Option<f64> {
    home_height(legs, &|z| level(legs, z))
}

/// The actuators' values `θ_i + encoder_offset` of `legs` reaching `balls`.
///
/// # Errors
/// [`Error::Invalid`] naming the first leg (`{what}[i]`) that cannot reach its ball.
pub(crate) fn actuator_angles(
    legs: &[RusLeg],
    balls: &[[f64; 3]],
    what: &str,
) -> Result<alloc::vec::Vec<f64>, Error> {
    legs.iter()
        .zip(balls)
        .enumerate()
        .map(|(i, (leg, &ball))| {
            let theta = leg.crank_angle(ball).map_err(|u| {
                invalid(
                    format!("{what}[{}]", i + 1),
                    format_args!("cannot reach its ball: |K/ρ| = {:.6} > 1", u.ratio.abs()),
                )
            })?;
            Ok(theta + leg.encoder_offset)
        })
        .collect()
}

/// The checks both mechanisms share: finite gravity, every leg's rules, a finite `home` if
/// given, and every leg reaching its ball at home (`balls_at(home)`, or the default level
/// home, named as [`no_home`] says where there is none).
pub(crate) fn validate_legs(
    gravity: &[f64; 3],
    legs: &[RusLeg],
    what: &str,
    delta: bool,
    home: Option<&[f64]>,
    balls_at_home: Option<alloc::vec::Vec<[f64; 3]>>,
) -> Result<(), Error> {
    if !gravity.iter().all(|g| g.is_finite()) {
        return Err(invalid("gravity", "must be finite"));
    }
    for (i, leg) in legs.iter().enumerate() {
        leg.validate(&|field| format!("{what}[{}].{field}", i + 1), delta)?;
    }
    if home.is_some_and(|h| !h.iter().all(|x| x.is_finite())) {
        return Err(invalid("home", "must be finite"));
    }
    let balls = balls_at_home.ok_or_else(|| no_home(legs, &|z| level(legs, z), what))?;
    actuator_angles(legs, &balls, what).map_err(|e| match e {
        Error::Invalid { field, rule } => invalid(field, format_args!("{rule} at home")),
        other => other,
    })?;
    Ok(())
}

/// Why no default home exists: the first leg (`what[i]`, "legs" or "arms") that reaches its
/// ball at no height at all, else the legs together.
fn no_home(
    legs: &[RusLeg],
    points: &dyn Fn(f64) -> alloc::vec::Vec<[f64; 3]>,
    what: &str,
) -> Error {
    for i in 0..legs.len() {
        let alone = |z: f64| alloc::vec![points(z)[i]];
        if home_height(&legs[i..=i], &alone).is_none() {
            return invalid(
                format!("{what}[{}]", i + 1),
                "cannot reach the platform at any height over the base (crank and rod too \
                 short, or too long, for its ball)",
            );
        }
    }
    // The one leg without which the others share a height.
    for i in 0..legs.len() {
        let others: alloc::vec::Vec<RusLeg> = (0..legs.len())
            .filter(|&j| j != i)
            .map(|j| legs[j])
            .collect();
        let their = |z: f64| {
            let all = points(z);
            (0..legs.len())
                .filter(|&j| j != i)
                .map(|j| all[j])
                .collect()
        };
        if home_height(&others, &their).is_some() {
            return invalid(
                format!("{what}[{}]", i + 1),
                "cannot reach the platform at any height where the others reach it",
            );
        }
    }
    invalid(
        what,
        "cannot all reach the platform at any one level height over the base",
    )
}

/// The height of a level platform centred over the base at which the cranks are nearest their
/// zero, `Σ θ_i²` least among the heights every leg reaches: the default home of the
/// rotary hexapod and of the Delta. `points(z)` gives each leg's `B_i` at height `z`.
pub(crate) fn home_height(
    legs: &[RusLeg],
    points: &dyn Fn(f64) -> alloc::vec::Vec<[f64; 3]>,
) -> Option<f64> {
    let reach = legs
        .iter()
        .map(|l| l.crank.length + l.rod.length + norm(l.base) + norm(l.platform))
        .fold(0.0, f64::max);
    let cost = |z: f64| -> Option<f64> {
        let mut sum = 0.0;
        for (leg, b) in legs.iter().zip(points(z)) {
            let theta = leg.crank_angle(b).ok()?;
            sum += theta * theta;
        }
        Some(sum)
    };
    const SAMPLES: usize = 2000;
    let at = |k: usize| -reach + 2.0 * reach * k as f64 / SAMPLES as f64;
    let best = (0..=SAMPLES)
        .filter_map(|k| cost(at(k)).map(|c| (k, c)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?
        .0;
    // Golden-section search in the best sample's neighbourhood.
    let (mut lo, mut hi) = (at(best.saturating_sub(1)), at((best + 1).min(SAMPLES)));
    let g = 0.5 * (sqrt(5.0) - 1.0);
    for _ in 0..100 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (ca, cb) = (
            cost(a).unwrap_or(f64::INFINITY),
            cost(b).unwrap_or(f64::INFINITY),
        );
        if ca <= cb {
            hi = b;
        } else {
            lo = a;
        }
    }
    let z = 0.5 * (lo + hi);
    cost(z).map(|_| z).or(Some(at(best)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::add;

    fn leg(branch: f64) -> RusLeg {
        RusLeg {
            base: [0.30, 0.08, 0.0],
            axis: [0.97, 0.25, 0.0],
            zero: [-0.25, 0.97, 0.0],
            crank: Crank {
                length: 0.085,
                mass: 0.35,
                com: 0.04,
                inertia: [2e-5, 4.2e-4, 4.3e-4],
            },
            rod: RusRod {
                length: 0.34,
                separation: None,
                mass: 0.22,
                com: 0.16,
                inertia: [2.2e-3, 2.2e-3, 1.5e-5],
            },
            platform: [0.17, 0.09, -0.015],
            branch,
            encoder_offset: 0.0,
        }
    }

    #[test]
    fn the_crank_angle_puts_the_rod_on_the_ball_on_its_branch() {
        for branch in [1.0, -1.0] {
            let leg = leg(branch);
            let (_, h, k) = leg.axes();
            for z in [-0.33, -0.3, 0.3, 0.33] {
                let ball = [0.17, 0.09, z];
                let theta = leg.crank_angle(ball).unwrap();
                let rod = norm(sub(ball, leg.elbow(theta)));
                assert!((rod - 0.34).abs() < 1e-15, "{branch} {z}: {rod}");
                // The branch is the side of the crank from the ball's direction in its plane.
                let d = sub(ball, leg.base);
                let side = wrap(theta - atan2(dot(d, k), dot(d, h)));
                assert_eq!(side.signum(), branch);
            }
        }
    }

    #[test]
    fn a_ball_out_of_reach_is_refused_with_its_ratio() {
        let leg = leg(1.0);
        let far = add(leg.base, [0.0, 0.0, 0.5]);
        let u = leg.crank_angle(far).unwrap_err();
        assert!(u.ratio.abs() > 1.0);
    }

    #[test]
    fn the_zero_direction_is_made_orthogonal_to_the_axis_and_the_axes_right_handed() {
        let mut tilted = leg(1.0);
        tilted.zero[2] = 0.3;
        let (r, h, k) = tilted.axes();
        assert!(dot(r, h).abs() < 1e-16 && (norm(h) - 1.0).abs() < 1e-15);
        assert!((dot(cross(r, h), k) - 1.0).abs() < 1e-15);
    }
}
