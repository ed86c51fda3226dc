//! The robot's description: geometry, gravity and the dynamic parameters of every body.
//!
//! [`Robot`] is generic over its scalar so the same description holds numbers (`Robot<f64>`,
//! the default robot of the chapter's appendix, validated) and symbols (`Robot<Expr>`, for the
//! model); [`Robot::flatten`] and [`Robot::unflatten`] fix the order of the runtime parameter
//! vector once.

use crate::inertia::check_inertia;
use crate::{Error, Limits};
use alloc::format;
use alloc::string::{String, ToString};
use alloc::vec;
use alloc::vec::Vec;

/// Axis of segment `i` (0-based): `n_i = e_AXIS[i]`; segments 1,2 along x, 3,4 along y, 5,6
/// along z. The platform normal of the segment's plates is the same column of `R`.
pub const AXIS: [usize; 6] = [0, 0, 1, 1, 2, 2];

/// Number of entries of the runtime parameter vector ([`Robot::flatten`]).
pub const PARAMETERS: usize = 152;

/// How many entries open the parameter vector before the first body's: the half-spacing and
/// gravity, all the identification kernels read of a robot.
pub const GEOMETRY_PARAMETERS: usize = 4;

/// A rigid body: mass, centre of mass and inertia about the centre of mass.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct RigidBody<T = f64> {
    /// Mass (kg).
    pub mass: T,
    /// Centre of mass from the body's reference point, in the platform frame (m).
    pub com: [T; 3],
    /// Inertia about the centre of mass, in the platform frame (kg·m²).
    pub inertia: [[T; 3]; 3],
}

/// The actuator rod (body 1): it translates along its segment and never rotates.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Rod<T = f64> {
    pub mass: T,
    /// Constant part of `J_Gi1` in the base frame (kg·m²).
    pub inertia: [[T; 3]; 3],
    /// Part of `J_Gi1` proportional to `Q_i1²` (kg), as in the appendix tables.
    pub inertia_per_length_squared: [[T; 3]; 3],
}

/// One segment: the rod (body 1) and the C5 joint (body 2, centre of mass at `B_i`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Segment<T = f64> {
    pub rod: Rod<T>,
    pub joint: RigidBody<T>,
}

/// A C5 joint parallel robot of the chapter's family.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Robot<T = f64> {
    /// `L`, half the distance between the two parallel segments of a pair (m).
    pub half_spacing: T,
    /// Gravity in the base frame (m/s²).
    pub gravity: [T; 3],
    /// The mobile platform; its reference point is `C`.
    pub platform: RigidBody<T>,
    /// Segments 1..6.
    pub segments: [Segment<T>; 6],
    /// The physical limits (strokes, plates, tilt, speed, force); none by default. Not
    /// parameters of the kernels: the runtime checks them.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Limits::is_unset")
    )]
    pub limits: Limits,
}

fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
}

impl Default for Robot<f64> {
    /// The chapter's robot: `L = 0.2 m`, the appendix's masses and inertias, `g = (0, 0, -9.81)`.
    fn default() -> Self {
        let segment = |axis: usize| {
            let mut fixed = [0.00125; 3];
            fixed[axis] = 0.0025;
            let mut per_q2 = [0.1667; 3];
            per_q2[axis] = 0.0;
            let mut joint = [0.0084; 3];
            joint[axis] = 0.00167;
            Segment {
                rod: Rod {
                    mass: 2.0,
                    inertia: diag(fixed[0], fixed[1], fixed[2]),
                    inertia_per_length_squared: diag(per_q2[0], per_q2[1], per_q2[2]),
                },
                joint: RigidBody {
                    mass: 1.67,
                    com: [0.0; 3],
                    inertia: diag(joint[0], joint[1], joint[2]),
                },
            }
        };
        Robot {
            half_spacing: 0.2,
            gravity: [0.0, 0.0, -9.81],
            platform: RigidBody {
                mass: 10.0,
                com: [0.0; 3],
                inertia: diag(0.375, 0.1875, 0.1875),
            },
            segments: [
                segment(0),
                segment(0),
                segment(1),
                segment(1),
                segment(2),
                segment(2),
            ],
            limits: Limits::default(),
        }
    }
}

const SYM: [(usize, usize, &str); 6] = [
    (0, 0, "xx"),
    (0, 1, "xy"),
    (0, 2, "xz"),
    (1, 1, "yy"),
    (1, 2, "yz"),
    (2, 2, "zz"),
];

/// Visits every parameter in the fixed order of the runtime parameter vector.
fn visit<T: Copy>(r: &Robot<T>, mut f: impl FnMut(String, T)) {
    let sym = |prefix: &str, m: &[[T; 3]; 3], f: &mut dyn FnMut(String, T)| {
        for (i, j, n) in SYM {
            f(format!("{prefix}_{n}"), m[i][j]);
        }
    };
    f("half_spacing".into(), r.half_spacing);
    for (k, a) in ["x", "y", "z"].iter().enumerate() {
        f(format!("gravity_{a}"), r.gravity[k]);
    }
    let body = |prefix: &str, b: &RigidBody<T>, f: &mut dyn FnMut(String, T)| {
        f(format!("{prefix}_mass"), b.mass);
        for (k, a) in ["x", "y", "z"].iter().enumerate() {
            f(format!("{prefix}_com_{a}"), b.com[k]);
        }
        sym(&format!("{prefix}_inertia"), &b.inertia, f);
    };
    body("platform", &r.platform, &mut f);
    for (i, s) in r.segments.iter().enumerate() {
        let n = i + 1;
        f(format!("rod{n}_mass"), s.rod.mass);
        sym(&format!("rod{n}_inertia"), &s.rod.inertia, &mut f);
        sym(
            &format!("rod{n}_inertia_q2"),
            &s.rod.inertia_per_length_squared,
            &mut f,
        );
        body(&format!("joint{n}"), &s.joint, &mut f);
    }
}

impl<T: Copy> Robot<T> {
    /// Number of entries of the runtime parameter vector.
    pub const PARAMETERS: usize = PARAMETERS;

    /// The parameters in the order of the runtime parameter vector.
    pub fn flatten(&self) -> Vec<T> {
        let mut out = Vec::with_capacity(Self::PARAMETERS);
        visit(self, |_, v| out.push(v));
        out
    }

    /// Names of the runtime parameters, in order (valid Rust identifiers).
    pub fn parameter_names() -> Vec<String>
    where
        T: Default,
    {
        let mut out = Vec::new();
        visit(&Robot::<T>::filled(T::default()), |n, _| out.push(n));
        out
    }

    fn filled(v: T) -> Self {
        let body = RigidBody {
            mass: v,
            com: [v; 3],
            inertia: [[v; 3]; 3],
        };
        let seg = Segment {
            rod: Rod {
                mass: v,
                inertia: [[v; 3]; 3],
                inertia_per_length_squared: [[v; 3]; 3],
            },
            joint: body,
        };
        Robot {
            half_spacing: v,
            gravity: [v; 3],
            platform: body,
            segments: [seg; 6],
            limits: Limits::default(),
        }
    }

    /// Rebuilds a robot from its parameter vector (the inverse of [`Robot::flatten`]), without
    /// limits.
    ///
    /// # Panics
    /// If `values` does not hold [`Robot::PARAMETERS`] entries.
    pub fn unflatten(values: &[T]) -> Self {
        assert_eq!(values.len(), Self::PARAMETERS, "parameter vector length");
        let mut it = values.iter().copied();
        let mut next = || it.next().expect("length checked");
        let sym = |next: &mut dyn FnMut() -> T| {
            let mut m = [[values[0]; 3]; 3];
            for (i, j, _) in SYM {
                let v = next();
                m[i][j] = v;
                m[j][i] = v;
            }
            m
        };
        let body = |next: &mut dyn FnMut() -> T| {
            let mass = next();
            let com = [next(), next(), next()];
            let inertia = sym(next);
            RigidBody { mass, com, inertia }
        };
        let half_spacing = next();
        let gravity = [next(), next(), next()];
        let platform = body(&mut next);
        let segments = core::array::from_fn(|_| {
            let mass = next();
            let inertia = sym(&mut next);
            let inertia_per_length_squared = sym(&mut next);
            let joint = body(&mut next);
            Segment {
                rod: Rod {
                    mass,
                    inertia,
                    inertia_per_length_squared,
                },
                joint,
            }
        });
        Robot {
            half_spacing,
            gravity,
            platform,
            segments,
            limits: Limits::default(),
        }
    }

    /// Maps every parameter through `f` (the limits, not parameters, are kept).
    pub fn map<U: Copy>(&self, f: impl FnMut(T) -> U) -> Robot<U> {
        Robot {
            limits: self.limits,
            ..Robot::unflatten(&self.flatten().into_iter().map(f).collect::<Vec<_>>())
        }
    }
}

/// The suffixes of a body's ten standard parameters, in their order in the kernel parameter
/// vector: mass, first moment `m c`, inertia about the reference point.
const STANDARD: [&str; 10] = [
    "mass", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz",
];

/// A body's ten standard parameters from its mass, centre of mass `c` and inertia about the
/// centre of mass: `[m, m c, I_G + m (|c|² 1 - c cᵀ)]` (`I` as xx, xy, xz, yy, yz, zz).
pub fn standard_of(body: &RigidBody) -> [f64; 10] {
    let (m, c) = (body.mass, body.com);
    let c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    let i =
        |a: usize, b: usize| body.inertia[a][b] + m * (if a == b { c2 } else { 0.0 } - c[a] * c[b]);
    [
        m,
        m * c[0],
        m * c[1],
        m * c[2],
        i(0, 0),
        i(0, 1),
        i(0, 2),
        i(1, 1),
        i(1, 2),
        i(2, 2),
    ]
}

impl Robot<f64> {
    /// The parameter vector of the `*_params` kernels: [`Robot::flatten`]'s order and length,
    /// with the platform's and each body 2's centre of mass and inertia in standard form (first
    /// moment `m c`, inertia about the reference point `C` or `B_i`), in which the dynamics is
    /// linear. Names: [`Robot::kernel_parameter_names`].
    pub fn kernel_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS);
        out.push(self.half_spacing);
        out.extend(self.gravity);
        out.extend(standard_of(&self.platform));
        for s in &self.segments {
            out.push(s.rod.mass);
            for m in [&s.rod.inertia, &s.rod.inertia_per_length_squared] {
                out.extend(SYM.iter().map(|&(i, j, _)| m[i][j]));
            }
            out.extend(standard_of(&s.joint));
        }
        out
    }
}

impl<T> Robot<T> {
    /// The names of [`Robot::kernel_parameters`], in order (valid Rust identifiers):
    /// `half_spacing`, `gravity_x`..., `platform_mass`, `platform_mx`..., `platform_ixx`...,
    /// `rod1_mass`, `rod1_inertia_xx`..., `rod1_inertia_q2_xx`..., `joint1_mass`, `joint1_mx`...
    pub fn kernel_parameter_names() -> Vec<String> {
        let mut out = vec!["half_spacing".to_string()];
        out.extend(["x", "y", "z"].map(|a| format!("gravity_{a}")));
        out.extend(STANDARD.map(|s| format!("platform_{s}")));
        for n in 1..=6 {
            out.push(format!("rod{n}_mass"));
            for prefix in ["inertia", "inertia_q2"] {
                out.extend(SYM.iter().map(|(_, _, a)| format!("rod{n}_{prefix}_{a}")));
            }
            out.extend(STANDARD.map(|s| format!("joint{n}_{s}")));
        }
        out
    }
}

fn invalid(field: impl Into<String>, rule: &str) -> Error {
    Error::Invalid {
        field: field.into(),
        rule: rule.to_string(),
    }
}

#[cfg(feature = "toml")]
impl Robot<f64> {
    /// Reads and validates a robot description in TOML (the serde form of [`Robot`]). Every
    /// field left out takes the chapter's value ([`Robot::default`]): a file may give only
    /// `half_spacing`, or only a `[limits]` table; a `[[segments]]` entry overrides the segment
    /// of its position. Unknown fields are refused. `source` names the file in errors.
    ///
    /// # Errors
    /// [`Error::File`] naming the source and what is wrong: a syntax error, an unknown field,
    /// a wrong type, or a broken rule of [`Robot::validate`].
    pub fn from_toml(text: &str, source: &str) -> Result<Self, Error> {
        let file_error = |message: String| Error::File {
            source: source.to_string(),
            message,
        };
        let given: toml::Table = toml::from_str(text).map_err(|e| file_error(e.to_string()))?;
        let mut merged =
            toml::Table::try_from(Robot::default()).expect("the default robot serialises");
        merge(&mut merged, given);
        let robot: Robot = toml::Value::Table(merged)
            .try_into()
            .map_err(|e: toml::de::Error| file_error(e.to_string()))?;
        robot.validate().map_err(|e| file_error(e.to_string()))?;
        Ok(robot)
    }

    /// Reads [`Robot::from_toml`] from a file.
    ///
    /// # Errors
    /// [`Error::Io`], or as [`Robot::from_toml`].
    pub fn from_toml_file(path: &std::path::Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|error| Error::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Self::from_toml(&text, &path.display().to_string())
    }

    /// The description as TOML, as [`Robot::from_toml`] reads it.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a robot of finite numbers serialises")
    }
}

/// `given` laid over `base`: tables merge key by key, arrays of tables element by element,
/// anything else is replaced.
#[cfg(feature = "toml")]
fn merge(base: &mut toml::Table, given: toml::Table) {
    use toml::Value;
    for (key, value) in given {
        match (base.get_mut(&key), value) {
            (Some(Value::Table(b)), Value::Table(g)) => merge(b, g),
            (Some(Value::Array(b)), Value::Array(g))
                if g.iter().all(Value::is_table) && b.iter().all(Value::is_table) =>
            {
                for (k, item) in g.into_iter().enumerate() {
                    match (b.get_mut(k), item) {
                        (Some(Value::Table(bt)), Value::Table(gt)) => merge(bt, gt),
                        (_, item) => b.push(item),
                    }
                }
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
}

impl Robot<f64> {
    /// Checks every rule a physical robot obeys.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field that breaks a rule: a non-finite value, a
    /// non-positive `half_spacing` or mass, or an inertia no rigid body has (not symmetric, not
    /// positive definite, or principal moments breaking the triangle inequality; see
    /// [`check_inertia`]).
    pub fn validate(&self) -> Result<(), Error> {
        let mut bad = None;
        visit(self, |name, v| {
            if !v.is_finite() && bad.is_none() {
                bad = Some(name);
            }
        });
        if let Some(name) = bad {
            return Err(invalid(name, "must be finite"));
        }
        if self.half_spacing <= 0.0 {
            return Err(invalid("half_spacing", "must be positive"));
        }
        let body = |prefix: &str, b: &RigidBody| -> Result<(), Error> {
            if b.mass <= 0.0 {
                return Err(invalid(format!("{prefix}.mass"), "must be positive"));
            }
            check_inertia(&format!("{prefix}.inertia"), &b.inertia, false)
        };
        body("platform", &self.platform)?;
        for (i, s) in self.segments.iter().enumerate() {
            let n = i + 1;
            if s.rod.mass <= 0.0 {
                return Err(invalid(
                    format!("segments[{n}].rod.mass"),
                    "must be positive",
                ));
            }
            check_inertia(&format!("segments[{n}].rod.inertia"), &s.rod.inertia, false)?;
            check_inertia(
                &format!("segments[{n}].rod.inertia_per_length_squared"),
                &s.rod.inertia_per_length_squared,
                true,
            )?;
            body(&format!("segments[{n}].joint"), &s.joint)?;
        }
        self.limits.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flatten_round_trips() {
        let r = Robot::default();
        let v = r.flatten();
        assert_eq!(v.len(), Robot::<f64>::PARAMETERS);
        assert_eq!(Robot::unflatten(&v), r);
        assert_eq!(Robot::<f64>::parameter_names().len(), v.len());
    }

    #[test]
    fn kernel_parameters_are_the_standard_form_in_flatten_order() {
        let mut r = Robot::default();
        r.platform.com = [0.01, -0.02, 0.03];
        let k = r.kernel_parameters();
        let names = Robot::<f64>::kernel_parameter_names();
        assert_eq!((k.len(), names.len()), (PARAMETERS, PARAMETERS));
        let at = |n: &str| k[names.iter().position(|x| x == n).unwrap()];
        assert_eq!(at("platform_mass"), 10.0);
        assert!((at("platform_my") - 10.0 * -0.02).abs() < 1e-15);
        // Parallel axes: I_xx about C = I_xx about G + m (cy² + cz²).
        assert!((at("platform_ixx") - (0.375 + 10.0 * (0.0004 + 0.0009))).abs() < 1e-15);
        assert!((at("platform_ixy") - (0.0 - 10.0 * 0.01 * -0.02)).abs() < 1e-15);
        assert_eq!(at("rod3_inertia_q2_yy"), 0.0);
        assert_eq!(at("joint6_mass"), 1.67);
        // The geometry opens the vector: the half-spacing and gravity, then the first body.
        assert_eq!(
            names[..GEOMETRY_PARAMETERS],
            ["half_spacing", "gravity_x", "gravity_y", "gravity_z"]
        );
        assert_eq!(names[GEOMETRY_PARAMETERS], "platform_mass");
        // Where nothing is off its reference point, the two vectors agree.
        assert_eq!(
            Robot::default().kernel_parameters(),
            Robot::default().flatten()
        );
    }

    #[test]
    fn default_robot_is_valid() {
        Robot::default().validate().unwrap();
    }

    #[test]
    fn non_positive_mass_is_named() {
        let mut r = Robot::default();
        r.segments[2].joint.mass = 0.0;
        let e = r.validate().unwrap_err().to_string();
        assert_eq!(
            e,
            "invalid robot: `segments[3].joint.mass` must be positive"
        );
    }

    #[cfg(feature = "toml")]
    #[test]
    fn toml_round_trips() {
        let r = Robot::default();
        assert_eq!(Robot::from_toml(&r.to_toml(), "default.toml").unwrap(), r);
    }

    #[cfg(feature = "toml")]
    #[test]
    fn toml_errors_name_file_field_and_rule() {
        let text = Robot::default().to_toml();
        let unknown = text.replacen("half_spacing = 0.2", "half_spacing = 0.2\nspacing = 1", 1);
        let e = Robot::from_toml(&unknown, "robot.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("robot.toml: ") && e.contains("unknown field `spacing`"),
            "{e}"
        );
        let wrong = text.replacen("half_spacing = 0.2", "half_spacing = \"wide\"", 1);
        let e = Robot::from_toml(&wrong, "robot.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("half_spacing") && e.contains("invalid type"),
            "{e}"
        );
        let negative = text.replacen("mass = 10.0", "mass = -10.0", 1);
        let e = Robot::from_toml(&negative, "robot.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`platform.mass` must be positive"), "{e}");
    }

    /// A file gives what differs from the chapter's robot; everything else is the chapter's.
    #[cfg(feature = "toml")]
    #[test]
    fn a_partial_file_is_the_default_robot_but_for_what_it_gives() {
        let r = Robot::from_toml("half_spacing = 0.25", "robot.toml").unwrap();
        assert_eq!(
            r,
            Robot {
                half_spacing: 0.25,
                ..Robot::default()
            }
        );
        let r = Robot::from_toml(
            "[platform]\nmass = 12.0\n[[segments]]\n[segments.joint]\nmass = 1.0",
            "robot.toml",
        )
        .unwrap();
        let mut want = Robot::default();
        want.platform.mass = 12.0;
        want.segments[0].joint.mass = 1.0;
        assert_eq!(r, want);
        let r = Robot::from_toml(
            "[limits]\nstroke = [-0.1, 0.1]\nplate_travel = 0.05\ntilt = 0.5",
            "robot.toml",
        )
        .unwrap();
        let limits = Limits {
            stroke: Some([[-0.1, 0.1]; 6]),
            plate_travel: Some([0.05, 0.05]),
            tilt: Some(0.5),
            ..Limits::default()
        };
        assert_eq!(
            r,
            Robot {
                limits,
                ..Robot::default()
            }
        );
        // Round trip with limits, and six strokes or two travels given one by one.
        assert_eq!(Robot::from_toml(&r.to_toml(), "again.toml").unwrap(), r);
        let text = "[limits]\nstroke = [[-0.1, 0.1], [-0.1, 0.1], [-0.2, 0.1], [-0.1, 0.1], \
                    [-0.1, 0.1], [-0.1, 0.3]]\nplate_travel = [0.04, 0.06]";
        let r = Robot::from_toml(text, "robot.toml").unwrap();
        assert_eq!(r.limits.stroke.unwrap()[2], [-0.2, 0.1]);
        assert_eq!(r.limits.plate_travel, Some([0.04, 0.06]));
        assert_eq!(Robot::from_toml(&r.to_toml(), "again.toml").unwrap(), r);
    }

    #[cfg(feature = "toml")]
    #[test]
    fn bad_limits_are_refused_by_name() {
        for (text, needle) in [
            (
                "stroke = [0.1, -0.1]",
                "`limits.stroke[1]` must be [min, max] with min < max",
            ),
            (
                "stroke = [0.1]",
                "`stroke` takes [min, max] or six [min, max] pairs",
            ),
            (
                "plate_travel = -0.01",
                "`limits.plate_travel` must be positive",
            ),
            ("tilt = 2.0", "`limits.tilt` must be in (0, π/2)"),
            ("speed = 0", "`limits.speed` must be positive"),
            ("force = -5", "`limits.force` must be positive"),
            ("torque = 5", "unknown field `torque`"),
        ] {
            let e = Robot::from_toml(&format!("[limits]\n{text}"), "robot.toml")
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
    }

    #[test]
    fn indefinite_inertia_is_rejected() {
        let mut r = Robot::default();
        r.platform.inertia[0][0] = -1.0;
        assert!(r.validate().is_err());
        let mut r = Robot::default();
        r.platform.inertia[0][1] = 0.3;
        assert!(r.validate().is_err(), "asymmetric");
    }

    #[test]
    fn inertias_no_rigid_body_has_are_refused_with_the_rule() {
        let mut r = Robot::default();
        r.segments[1].joint.inertia = [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(
            r.validate().unwrap_err().to_string(),
            "invalid robot: `segments[2].joint.inertia` must be positive definite"
        );
        let mut r = Robot::default();
        r.platform.inertia = diag(1.0, 0.1, 0.1);
        let e = r.validate().unwrap_err().to_string();
        assert!(
            e.starts_with(
                "invalid robot: `platform.inertia` breaks the triangle inequality Ixx ≤ Iyy + Izz"
            ),
            "{e}"
        );
    }
}
