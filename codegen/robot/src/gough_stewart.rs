//! The description of a Gough-Stewart platform (6-UPS): six legs of variable length, each
//! between a universal joint on the base and a spherical joint on the platform.
//!
//! Conventions, the same as the C5's: pose `[α β γ xc yc zc]` with `R = Rx(α) Ry(β) Rz(γ)`,
//! twist `(ω; v_C)` at the platform origin `C`, base frame, SI units. Leg `i`: the U joint's
//! centre `A_i` and first axis `a_i` in the base frame, the S joint's centre `p_i` in the
//! platform frame, `B_i = C + R p_i`; the actuator value is the encoder's reading,
//! `q_i = |B_i - A_i| + o_i`; a positive force extends the leg. The leg frame is the U joint's:
//! `z' = u_i = (B_i - A_i)/|B_i - A_i|`, `y' = (u_i × a_i)/|u_i × a_i|`, `x' = y' × z'`. The
//! cylinder (centre of mass at `A_i + c u_i`) and the rod (at `B_i - c u_i`) turn with it, each
//! with the inertia `diag(It, It, Ia)` about its centre of mass in the leg frame.

use crate::inertia::check_inertia;
use crate::math::sqrt;
use crate::Error;
use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

/// The platform: its mass, centre of mass and inertia.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Platform {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass from the platform origin `C`, platform frame (m).
    pub centre_of_mass: [f64; 3],
    /// `[Ixx Iyy Izz Ixy Ixz Iyz]` about the centre of mass, platform frame (kg·m²).
    pub inertia: [f64; 6],
}

impl Platform {
    /// Its numbers finite, its mass positive, its inertia a rigid body's.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the field.
    pub fn validate(&self) -> Result<(), Error> {
        let finite = |field: &str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(invalid(field, "must be finite"))
            }
        };
        finite("platform.mass", &[self.mass])?;
        finite("platform.centre_of_mass", &self.centre_of_mass)?;
        finite("platform.inertia", &self.inertia)?;
        if self.mass <= 0.0 {
            return Err(invalid("platform.mass", "must be positive"));
        }
        check_inertia("platform.inertia", &self.inertia_matrix(), false)
    }

    /// Its ten standard parameters about `C`, platform frame, in the order of
    /// [`PLATFORM_STANDARD`]: mass, first moment `m c`, and the inertia moved from the centre
    /// of mass to `C`.
    pub fn standard_parameters(&self) -> [f64; 10] {
        let (m, c) = (self.mass, self.centre_of_mass);
        let c2 = dot(c, c);
        let i = self.inertia_matrix();
        let at = |a: usize, b: usize| i[a][b] + m * (if a == b { c2 } else { 0.0 } - c[a] * c[b]);
        [
            m,
            m * c[0],
            m * c[1],
            m * c[2],
            at(0, 0),
            at(0, 1),
            at(0, 2),
            at(1, 1),
            at(1, 2),
            at(2, 2),
        ]
    }

    /// The inertia as a symmetric matrix.
    pub fn inertia_matrix(&self) -> [[f64; 3]; 3] {
        let [xx, yy, zz, xy, xz, yz] = self.inertia;
        [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]
    }
}

/// A body of a leg, symmetric about the leg's axis: its mass, where its centre of mass sits
/// on the axis, and its inertia.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct LegBody {
    /// Mass (kg).
    pub mass: f64,
    /// The centre of mass's distance along the leg (m): from `A_i` towards `B_i` for the
    /// cylinder, from `B_i` back towards `A_i` for the rod.
    pub com: f64,
    /// `[transverse, transverse, axial]` about the centre of mass, leg frame (kg·m²).
    pub inertia: [f64; 3],
}

/// One U-P-S leg.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct UpsLeg {
    /// `A_i`, the U joint's centre, base frame (m).
    pub base: [f64; 3],
    /// `a_i`, the U joint's first axis, fixed in the base (any nonzero vector; normalised).
    pub u_axis: [f64; 3],
    /// `p_i`, the S joint's centre, platform frame (m).
    pub platform: [f64; 3],
    /// The cylinder, which turns with the leg about `A_i`.
    pub cylinder: LegBody,
    /// The rod, which slides in the cylinder and holds the S joint.
    pub rod: LegBody,
    /// What the encoder reads at zero length: `q_i = |B_i - A_i| + encoder_offset` (m).
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "is_zero"))]
    pub encoder_offset: f64,
}

#[cfg(feature = "serde")]
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The entries of one leg in the kernels' geometry ([`UpsLeg::kernel_geometry`]).
pub const LEG_GEOMETRY: usize = 10;

impl UpsLeg {
    /// The leg's entries in the kernels' parameter vector: `A_i`, `a_i` normalised, `p_i` and
    /// the encoder's offset.
    pub fn kernel_geometry(&self) -> [f64; LEG_GEOMETRY] {
        let n = norm(self.u_axis);
        let mut out = [0.0; LEG_GEOMETRY];
        out[0..3].copy_from_slice(&self.base);
        out[3..6].copy_from_slice(&self.u_axis.map(|x| x / n));
        out[6..9].copy_from_slice(&self.platform);
        out[9] = self.encoder_offset;
        out
    }
}

/// The physical limits of a Gough-Stewart platform; `None` is unlimited (the default).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct LegLimits {
    /// Each actuator's range `[min, max]` of `q_i` (m). A file gives one pair for all six or
    /// six pairs.
    #[cfg_attr(
        feature = "serde",
        serde(
            default,
            skip_serializing_if = "Option::is_none",
            with = "crate::limits::one_or_six"
        )
    )]
    pub stroke: Option<[[f64; 2]; 6]>,
    /// The U joint's cone angle (rad): the largest angle between a leg and its direction at
    /// the home pose, base frame.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub u_joint: Option<f64>,
    /// The S joint's cone angle (rad): the largest angle between a leg and its direction at
    /// the home pose, seen from the platform.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub s_joint: Option<f64>,
    /// The largest actuator speed `|q̇_i|` (m/s).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub speed: Option<f64>,
    /// The largest actuator force `|Γ_i|` (N).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub force: Option<f64>,
}

impl LegLimits {
    /// Whether any limit is set.
    pub fn any(&self) -> bool {
        *self != LegLimits::default()
    }

    /// The rules every limit obeys: a stroke's `min < max`, both finite; the cone angles in
    /// `(0, π/2)`; speed and force positive and finite.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field that breaks a rule.
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(stroke) = &self.stroke {
            for (i, [lo, hi]) in stroke.iter().enumerate() {
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(invalid(
                        format!("limits.stroke[{}]", i + 1),
                        "must be [min, max] with min < max, both finite",
                    ));
                }
            }
        }
        for (name, angle) in [("u_joint", self.u_joint), ("s_joint", self.s_joint)] {
            if let Some(t) = angle {
                if !(t > 0.0 && t < core::f64::consts::FRAC_PI_2) {
                    return Err(invalid(format!("limits.{name}"), "must be in (0, π/2) rad"));
                }
            }
        }
        for (name, bound) in [("speed", self.speed), ("force", self.force)] {
            if let Some(x) = bound {
                if !(x > 0.0 && x.is_finite()) {
                    return Err(invalid(
                        format!("limits.{name}"),
                        "must be positive and finite",
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A Gough-Stewart platform (6-UPS).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct GoughStewart {
    /// Gravity in the base frame (m/s²).
    #[cfg_attr(feature = "serde", serde(default = "default_gravity"))]
    pub gravity: [f64; 3],
    /// The moving platform; its origin is `C`.
    pub platform: Platform,
    /// The six legs, in actuator order.
    #[cfg_attr(feature = "serde", serde(with = "six_legs"))]
    pub legs: [UpsLeg; 6],
    /// The home pose `[α β γ xc yc zc]`: where the forward kinematics starts without a previous
    /// solution and the cone angles are measured from. Default: level, centred over the base,
    /// at the middle of the strokes if `[limits]` gives them, else where the legs rise at 60°
    /// on average ([`GoughStewart::home`]).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub home: Option<[f64; 6]>,
    /// The physical limits; none by default.
    #[cfg_attr(feature = "serde", serde(default, skip_serializing_if = "is_unset"))]
    pub limits: LegLimits,
}

#[cfg(feature = "serde")]
fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

#[cfg(feature = "serde")]
fn is_unset(l: &LegLimits) -> bool {
    !l.any()
}

/// Exactly six `[[legs]]`, with a message that says so.
#[cfg(feature = "serde")]
mod six_legs {
    use super::UpsLeg;
    use alloc::format;
    use alloc::vec::Vec;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(legs: &[UpsLeg; 6], s: S) -> Result<S::Ok, S::Error> {
        legs.as_slice().serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[UpsLeg; 6], D::Error> {
        let legs = Vec::<UpsLeg>::deserialize(d)?;
        let n = legs.len();
        legs.try_into().map_err(|_| {
            serde::de::Error::custom(format!(
                "`legs` must hold exactly six [[legs]], in actuator order; the file gives {n}"
            ))
        })
    }
}

fn invalid(field: impl Into<String>, rule: impl ToString) -> Error {
    Error::Invalid {
        field: field.into(),
        rule: rule.to_string(),
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    sqrt(dot(a, a))
}

/// `R = Rx(α) Ry(β) Rz(γ)` (the C5's eq 15), for the poses the description names.
pub fn rotation(pose: &[f64; 6]) -> [[f64; 3]; 3] {
    let (sa, ca) = crate::math::sin_cos(pose[0]);
    let (sb, cb) = crate::math::sin_cos(pose[1]);
    let (sg, cg) = crate::math::sin_cos(pose[2]);
    [
        [cb * cg, -cb * sg, sb],
        [sg * ca + cg * sb * sa, ca * cg - sa * sb * sg, -cb * sa],
        [sg * sa - cg * sb * ca, sa * cg + ca * sb * sg, cb * ca],
    ]
}

/// The names of the standard parameters of a leg body, in the kernels' parameter vector and
/// the regressor's columns: mass, first moment along the leg, transverse and axial inertia
/// about the reference point (`A_i` for the cylinder, `B_i` for the rod), leg frame.
pub const LEG_BODY_STANDARD: [&str; 4] = ["mass", "mz", "ixx", "izz"];

/// The names of the platform's ten standard parameters.
pub const PLATFORM_STANDARD: [&str; 10] = [
    "mass", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz",
];

/// How many entries open the parameter vector before the inertial ones: gravity, then per leg
/// `A_i`, the unit `a_i`, `p_i` and the encoder's offset.
pub const GEOMETRY_PARAMETERS: usize = 3 + 6 * LEG_GEOMETRY;

/// Length of the parameter vector of the `*_params` kernels.
pub const PARAMETERS: usize = GEOMETRY_PARAMETERS + 10 + 6 * 2 * 4;

impl LegBody {
    /// `[m, m c_z, It_ref, Ia]` about the reference point `c` away along `±z'`: the first
    /// moment `m c_z`, and the transverse inertia moved by the parallel-axis theorem.
    fn standard(&self, c_z: f64) -> [f64; 4] {
        let [t, _, a] = self.inertia;
        [self.mass, self.mass * c_z, t + self.mass * c_z * c_z, a]
    }
}

impl GoughStewart {
    /// The names of [`GoughStewart::kernel_parameters`], in order (valid Rust identifiers).
    pub fn kernel_parameter_names() -> Vec<String> {
        let mut out: Vec<String> = ["x", "y", "z"]
            .iter()
            .map(|a| format!("gravity_{a}"))
            .collect();
        for n in 1..=6 {
            for what in ["base", "axis", "platform"] {
                out.extend(["x", "y", "z"].map(|a| format!("leg{n}_{what}_{a}")));
            }
            out.push(format!("leg{n}_offset"));
        }
        out.extend(Self::standard_inertial_names());
        out
    }

    /// The names of the standard inertial parameters (the identification's unknowns): the
    /// platform's ten (about `C`, platform frame), then each leg's cylinder and rod, four each
    /// ([`LEG_BODY_STANDARD`]).
    pub fn standard_inertial_names() -> Vec<String> {
        let mut out: Vec<String> = PLATFORM_STANDARD
            .iter()
            .map(|s| format!("platform_{s}"))
            .collect();
        for n in 1..=6 {
            for body in ["cylinder", "rod"] {
                out.extend(LEG_BODY_STANDARD.map(|s| format!("leg{n}_{body}_{s}")));
            }
        }
        out
    }

    /// The standard inertial parameters, in the order of
    /// [`GoughStewart::standard_inertial_names`].
    pub fn standard_inertial_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS - GEOMETRY_PARAMETERS);
        out.extend(self.platform.standard_parameters());
        for leg in &self.legs {
            out.extend(leg.cylinder.standard(leg.cylinder.com));
            out.extend(leg.rod.standard(-leg.rod.com));
        }
        out
    }

    /// The standard parameters `π` of `Γ = Y π` with the actuators' `friction`: the inertial
    /// ones ([`GoughStewart::standard_inertial_parameters`]), then the viscous and the Coulomb
    /// coefficients, six each.
    pub fn standard_parameters(&self, friction: &[crate::Friction; 6]) -> Vec<f64> {
        crate::standard::with_friction(self.standard_inertial_parameters(), friction)
    }

    /// The parameter vector of the `*_params` kernels: gravity; per leg `A_i`, `a_i`
    /// normalised, `p_i` and the encoder's offset; then the standard inertial parameters.
    pub fn kernel_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS);
        out.extend(self.gravity);
        for leg in &self.legs {
            out.extend(leg.kernel_geometry());
        }
        out.extend(self.standard_inertial_parameters());
        out
    }

    /// The home pose: the file's `home`, else level and centred over the base at the middle of
    /// the strokes (if `[limits]` gives them), else at the height where the legs rise at 60° on
    /// average.
    pub fn home(&self) -> [f64; 6] {
        if let Some(home) = self.home {
            return home;
        }
        let mean = |f: &dyn Fn(&UpsLeg) -> f64| self.legs.iter().map(f).sum::<f64>() / 6.0;
        let rise = mean(&|l| l.base[2] - l.platform[2]);
        let span = mean(&|l| {
            let d = sub(l.base, l.platform);
            sqrt(d[0] * d[0] + d[1] * d[1])
        });
        let mut height = rise + span * sqrt(3.0);
        if let Some(stroke) = self.limits.stroke {
            // The height whose leg lengths are nearest the strokes' middles: a few Newton steps
            // on the sum of squares, from the 60° height.
            for _ in 0..50 {
                let (mut gradient, mut curvature) = (0.0, 0.0);
                for (leg, [lo, hi]) in self.legs.iter().zip(stroke) {
                    let d = sub(
                        [leg.platform[0], leg.platform[1], leg.platform[2] + height],
                        leg.base,
                    );
                    let length = norm(d);
                    let slope = d[2] / length;
                    let error = length + leg.encoder_offset - 0.5 * (lo + hi);
                    gradient += error * slope;
                    curvature += slope * slope;
                }
                let step = gradient / curvature;
                height -= step;
                // A NaN step (a degenerate description) ends the search too.
                if step.is_nan() || step.abs() <= 1e-15 * height.abs().max(1.0) {
                    break;
                }
            }
        }
        [0.0, 0.0, 0.0, 0.0, 0.0, height]
    }

    /// Leg `i`'s unit vector `u_i` from `A_i` to `B_i` and its length `|B_i - A_i|` at `pose`.
    pub fn leg(&self, i: usize, pose: &[f64; 6]) -> ([f64; 3], f64) {
        let r = rotation(pose);
        let leg = &self.legs[i];
        let p = leg.platform;
        let b: [f64; 3] = core::array::from_fn(|k| {
            pose[3 + k] + r[k][0] * p[0] + r[k][1] * p[1] + r[k][2] * p[2]
        });
        let d = sub(b, leg.base);
        let length = norm(d);
        (d.map(|x| x / length), length)
    }

    /// Checks every rule a physical Gough-Stewart platform obeys.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field that breaks a rule: a non-finite number, a
    /// non-positive mass, an inertia no rigid body has, a zero U-joint axis, two joints at one
    /// point, a leg of zero length or along its U joint's axis at home, a home pose where the
    /// legs cannot hold the platform (`J⁻¹` singular), or a limit out of its range.
    pub fn validate(&self) -> Result<(), Error> {
        let finite = |field: String, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(invalid(field, "must be finite"))
            }
        };
        finite("gravity".into(), &self.gravity)?;
        self.platform.validate()?;
        for (i, leg) in self.legs.iter().enumerate() {
            let at = |field: &str| format!("legs[{}].{field}", i + 1);
            finite(at("base"), &leg.base)?;
            finite(at("u_axis"), &leg.u_axis)?;
            finite(at("platform"), &leg.platform)?;
            finite(at("encoder_offset"), &[leg.encoder_offset])?;
            for (name, body) in [("cylinder", &leg.cylinder), ("rod", &leg.rod)] {
                finite(at(&format!("{name}.mass")), &[body.mass, body.com])?;
                finite(at(&format!("{name}.inertia")), &body.inertia)?;
                if body.mass <= 0.0 {
                    return Err(invalid(at(&format!("{name}.mass")), "must be positive"));
                }
                let [t, t2, a] = body.inertia;
                if t != t2 {
                    return Err(invalid(
                        at(&format!("{name}.inertia")),
                        "must be [transverse, transverse, axial], the first two equal",
                    ));
                }
                if !(t > 0.0 && a >= 0.0) {
                    return Err(invalid(
                        at(&format!("{name}.inertia")),
                        "must have a positive transverse and a non-negative axial moment",
                    ));
                }
                if a > 2.0 * t * (1.0 + 1e-12) {
                    return Err(invalid(
                        at(&format!("{name}.inertia")),
                        "breaks the triangle inequality Ia ≤ 2 It",
                    ));
                }
            }
            if norm(leg.u_axis) < 1e-12 {
                return Err(invalid(at("u_axis"), "must not be zero"));
            }
            for (j, other) in self.legs.iter().enumerate().take(i) {
                if norm(sub(leg.base, other.base)) < 1e-9 {
                    return Err(invalid(
                        at("base"),
                        format_args!("is the same point as legs[{}].base", j + 1),
                    ));
                }
                if norm(sub(leg.platform, other.platform)) < 1e-9 {
                    return Err(invalid(
                        at("platform"),
                        format_args!("is the same point as legs[{}].platform", j + 1),
                    ));
                }
            }
        }
        if let Some(home) = self.home {
            finite("home".into(), &home)?;
        }
        self.limits.validate()?;
        self.validate_home()
    }

    /// At the home pose every leg has a length, stays off its U joint's axis, and the legs
    /// together hold the platform (`J⁻¹` regular).
    fn validate_home(&self) -> Result<(), Error> {
        let home = self.home();
        let r = rotation(&home);
        let mut jinv = [[0.0; 6]; 6];
        for (i, row) in jinv.iter_mut().enumerate() {
            let at = |field: &str| format!("legs[{}].{field}", i + 1);
            let (u, length) = self.leg(i, &home);
            if length.is_nan() || length <= 1e-9 {
                return Err(invalid(
                    at("platform"),
                    "meets the leg's base point at the home pose",
                ));
            }
            let axis = self.legs[i].u_axis;
            let sine = norm(cross(u, axis)) / norm(axis);
            if sine < 1e-3 {
                return Err(invalid(
                    at("u_axis"),
                    format_args!(
                        "is along the leg at the home pose (sine {sine:.1e}): the U joint is \
                         singular there"
                    ),
                ));
            }
            let p = self.legs[i].platform;
            let rp: [f64; 3] = core::array::from_fn(|k| dot(r[k], p));
            let w = cross(rp, u);
            *row = [w[0], w[1], w[2], u[0], u[1], u[2]];
        }
        if regularity(&jinv) < 1e-9 {
            return Err(invalid(
                "legs",
                "cannot hold the platform at the home pose: J⁻¹ is singular there",
            ));
        }
        Ok(())
    }

    /// Reads a Gough-Stewart description in TOML (the form of [`GoughStewart`], with
    /// `mechanism = "gough-stewart"`, which [`crate::Description::from_toml`] reads to choose).
    /// `source` names the file in errors.
    ///
    /// # Errors
    /// [`Error::File`] naming the source and what is wrong: a syntax error, an unknown or
    /// missing field, a wrong type, not six legs, or a broken rule of
    /// [`GoughStewart::validate`].
    #[cfg(feature = "toml")]
    pub fn from_toml(text: &str, source: &str) -> Result<Self, Error> {
        let file_error = |message: String| Error::File {
            source: source.to_string(),
            message,
        };
        let mut table: toml::Table = toml::from_str(text).map_err(|e| file_error(e.to_string()))?;
        match table.remove("mechanism") {
            Some(toml::Value::String(s)) if s == crate::description::GOUGH_STEWART => {}
            other => {
                return Err(file_error(format!(
                    "`mechanism` must be \"{}\" for a Gough-Stewart file, got {other:?}",
                    crate::description::GOUGH_STEWART
                )))
            }
        }
        let robot: GoughStewart = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| file_error(e.to_string()))?;
        robot.validate().map_err(|e| file_error(e.to_string()))?;
        Ok(robot)
    }

    /// The description as TOML, as [`GoughStewart::from_toml`] reads it.
    #[cfg(feature = "toml")]
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a description of finite numbers serialises");
        format!(
            "mechanism = \"{}\"\n{body}",
            crate::description::GOUGH_STEWART
        )
    }
}

impl GoughStewart {
    /// The example of `docs/hexapod.toml`: a positioner of about one metre across (base joints
    /// on a circle of 0.457 m, platform joints on one of 0.292 m, classically crossed legs),
    /// legs of 0.30 to 0.65 m, at mid-stroke 0.425 m above the base at home.
    pub fn example() -> Self {
        let leg = |base: [f64; 3], u_axis: [f64; 3], platform: [f64; 3]| UpsLeg {
            base,
            u_axis,
            platform,
            cylinder: LegBody {
                mass: 2.0,
                com: 0.25,
                inertia: [0.05, 0.05, 0.002],
            },
            rod: LegBody {
                mass: 1.0,
                com: 0.30,
                inertia: [0.03, 0.03, 0.001],
            },
            encoder_offset: 0.0,
        };
        GoughStewart {
            gravity: [0.0, 0.0, -9.81],
            platform: Platform {
                mass: 12.0,
                centre_of_mass: [0.0, 0.0, 0.03],
                inertia: [0.4, 0.4, 0.7, 0.0, 0.0, 0.0],
            },
            legs: [
                leg(
                    [0.45, 0.08, 0.0],
                    [-0.175033, 0.984563, 0.0],
                    [0.25, 0.15, 0.0],
                ),
                leg(
                    [0.45, -0.08, 0.0],
                    [0.175033, 0.984563, 0.0],
                    [0.25, -0.15, 0.0],
                ),
                leg(
                    [-0.294282, 0.349711, 0.0],
                    [-0.765139, -0.643865, 0.0],
                    [-0.254904, 0.141506, 0.0],
                ),
                leg(
                    [-0.155718, 0.429711, 0.0],
                    [-0.940173, -0.340698, 0.0],
                    [0.004904, 0.291506, 0.0],
                ),
                leg(
                    [-0.155718, -0.429711, 0.0],
                    [0.940173, -0.340698, 0.0],
                    [0.004904, -0.291506, 0.0],
                ),
                leg(
                    [-0.294282, -0.349711, 0.0],
                    [0.765139, -0.643865, 0.0],
                    [-0.254904, -0.141506, 0.0],
                ),
            ],
            home: None,
            limits: LegLimits {
                stroke: Some([[0.30, 0.65]; 6]),
                u_joint: Some(0.6),
                s_joint: Some(0.7),
                speed: Some(0.5),
                force: Some(2000.0),
            },
        }
    }
}

/// `|det M| / Π |m_i|` for the 6×6 `M` (its rows `m_i`), by Gaussian elimination with partial
/// pivoting: 1 for orthogonal rows, 0 for dependent ones (Hadamard's inequality).
fn regularity(m: &[[f64; 6]; 6]) -> f64 {
    let mut a = *m;
    let mut scale = 1.0;
    for row in &a {
        scale *= sqrt(row.iter().map(|x| x * x).sum::<f64>());
    }
    if scale.is_nan() || scale <= 0.0 {
        return 0.0;
    }
    let mut det = 1.0;
    for k in 0..6 {
        let pivot = (k..6)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap_or(k);
        a.swap(k, pivot);
        let d = a[k][k];
        if d == 0.0 {
            return 0.0;
        }
        det *= d;
        let pivot_row = a[k];
        for row in a.iter_mut().skip(k + 1) {
            let f = row[k] / d;
            for (x, p) in row.iter_mut().zip(pivot_row).skip(k) {
                *x -= f * p;
            }
        }
    }
    det.abs() / scale
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The example without limits (so that its home is the 60° one).
    fn example() -> GoughStewart {
        GoughStewart {
            limits: LegLimits::default(),
            ..GoughStewart::example()
        }
    }

    /// `docs/hexapod.toml` describes [`GoughStewart::example`].
    #[cfg(feature = "toml")]
    #[test]
    fn the_documented_example_is_the_example() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");
        if let Ok(text) = std::fs::read_to_string(path) {
            let robot = GoughStewart::from_toml(&text, path).unwrap();
            assert_eq!(robot, GoughStewart::example());
            let home = robot.home()[5];
            assert!((home - 0.425).abs() < 5e-4, "{home}");
        }
    }

    #[test]
    fn the_example_is_valid_and_its_vector_has_its_names() {
        let robot = example();
        robot.validate().unwrap();
        let (names, values) = (
            GoughStewart::kernel_parameter_names(),
            robot.kernel_parameters(),
        );
        assert_eq!((names.len(), values.len()), (PARAMETERS, PARAMETERS));
        assert_eq!(names[GEOMETRY_PARAMETERS], "platform_mass");
        let at = |n: &str| values[names.iter().position(|x| x == n).unwrap()];
        // The rod's first moment about B_i points back along the leg; its transverse inertia
        // moves there by the parallel-axis theorem.
        assert_eq!(at("leg3_rod_mz"), -0.3);
        assert!((at("leg3_rod_ixx") - (0.03 + 0.09)).abs() < 1e-15);
        assert!((at("platform_ixx") - (0.4 + 12.0 * 0.0009)).abs() < 1e-15);
        let axis = [at("leg2_axis_x"), at("leg2_axis_y"), at("leg2_axis_z")];
        assert!((norm(axis) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn the_home_pose_stands_the_legs_at_sixty_degrees_or_mid_stroke() {
        let mut robot = example();
        let home = robot.home();
        let rise: f64 = (0..6)
            .map(|i| robot.leg(i, &home).0[2].asin().to_degrees())
            .sum::<f64>()
            / 6.0;
        assert!((rise - 60.0).abs() < 1.0, "{rise}");
        robot.limits.stroke = Some([[0.6, 0.8]; 6]);
        let home = robot.home();
        for i in 0..6 {
            assert!((robot.leg(i, &home).1 - 0.7).abs() < 1e-6);
        }
    }

    #[test]
    fn bad_legs_are_named() {
        let mut robot = example();
        robot.legs[3].u_axis = [0.0; 3];
        assert_eq!(
            robot.validate().unwrap_err().to_string(),
            "invalid robot: `legs[4].u_axis` must not be zero"
        );
        let mut robot = example();
        let (u, _) = robot.leg(1, &robot.home());
        robot.legs[1].u_axis = u;
        let e = robot.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("invalid robot: `legs[2].u_axis` is along the leg"),
            "{e}"
        );
        let mut robot = example();
        robot.legs[5].platform = robot.legs[4].platform;
        assert_eq!(
            robot.validate().unwrap_err().to_string(),
            "invalid robot: `legs[6].platform` is the same point as legs[5].platform"
        );
        let mut robot = example();
        robot.legs[0].rod.inertia = [0.01, 0.01, 0.05];
        let e = robot.validate().unwrap_err().to_string();
        assert!(
            e.contains("`legs[1].rod.inertia` breaks the triangle inequality"),
            "{e}"
        );
        let mut robot = example();
        robot.legs[2].cylinder.mass = -1.0;
        assert_eq!(
            robot.validate().unwrap_err().to_string(),
            "invalid robot: `legs[3].cylinder.mass` must be positive"
        );
    }

    /// All six platform joints on one line of the platform: every leg's moment about that line
    /// vanishes, so no force holds the platform turning about it.
    #[test]
    fn a_platform_the_legs_cannot_hold_is_refused() {
        let mut robot = example();
        for (i, leg) in robot.legs.iter_mut().enumerate() {
            leg.platform = [0.05 * i as f64 - 0.12, 0.0, 0.0];
        }
        let e = robot.validate().unwrap_err().to_string();
        assert!(e.contains("`legs` cannot hold the platform"), "{e}");
    }

    #[cfg(feature = "toml")]
    #[test]
    fn toml_round_trips_and_errors_name_the_field() {
        let robot = example();
        let text = robot.to_toml();
        assert!(text.starts_with("mechanism = \"gough-stewart\""));
        assert_eq!(
            GoughStewart::from_toml(&text, "hexapod.toml").unwrap(),
            robot
        );
        let five = text.rsplit_once("[[legs]]").unwrap().0;
        let e = GoughStewart::from_toml(five, "hexapod.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("hexapod.toml: ") && e.contains("exactly six"),
            "{e}"
        );
        let typo = text.replacen("u_axis", "axis", 1);
        let e = GoughStewart::from_toml(&typo, "hexapod.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown field `axis`"), "{e}");
    }
}
