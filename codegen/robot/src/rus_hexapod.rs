//! The rotary hexapod (6-RUS): six motors on the base turn cranks; a rod from each crank's tip
//! (U joint) to the platform (ball) carries it. Motion simulators and servo-driven platforms.
//! The leg is [`crate::rus`]'s; the platform is the Gough-Stewart platform's
//! ([`crate::Platform`]), with the same pose, twist and acceleration conventions.

use crate::gough_stewart::{rotation, PLATFORM_STANDARD};
use crate::rus::{
    actuator_angles, level_home, validate_legs, Crank, RusLeg, RusRod, CRANK_STANDARD,
    LEG_GEOMETRY, LEG_GEOMETRY_NAMES, ROD_STANDARD,
};
use crate::tree::{add, times};
use crate::{Error, Platform};
use alloc::format;
use alloc::string::String;
#[cfg(feature = "toml")]
use alloc::string::ToString;
use alloc::vec::Vec;

/// A rotary hexapod.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct RusHexapod {
    /// Gravity in the base frame (m/s²).
    pub gravity: [f64; 3],
    /// The moving platform; its origin is `C`.
    pub platform: Platform,
    /// The six legs, in actuator order.
    #[cfg_attr(feature = "serde", serde(with = "exactly_six"))]
    pub legs: [RusLeg; 6],
    /// The home pose `[α β γ xc yc zc]`. Default: level, centred over the base, at the height
    /// where the cranks are nearest their zero (`Σ θ_i²` least).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub home: Option<[f64; 6]>,
}

/// How many entries open the parameter vector before the inertial ones: gravity, then each
/// leg's [`RusLeg::kernel_geometry`].
pub const GEOMETRY_PARAMETERS: usize = 3 + 6 * LEG_GEOMETRY;

/// Length of the parameter vector of the `*_params` kernels: the geometry, the platform's ten
/// standard parameters, each leg's crank's five and rod's four.
pub const PARAMETERS: usize =
    GEOMETRY_PARAMETERS + 10 + 6 * (CRANK_STANDARD.len() + ROD_STANDARD.len());

#[cfg(feature = "serde")]
mod exactly_six {
    crate::counted_list!(RusLeg, 6, "six [[legs]]");
}

impl RusHexapod {
    /// The home pose: the file's `home`, else level and centred at the height where the cranks
    /// are nearest their zero; `None` where no height reaches every leg.
    pub fn home(&self) -> Option<[f64; 6]> {
        self.home
            .or_else(|| level_home(&self.legs).map(|z| [0.0, 0.0, 0.0, 0.0, 0.0, z]))
    }

    /// `B_i = C + R p_i` at `pose`.
    pub fn ball(&self, i: usize, pose: &[f64; 6]) -> [f64; 3] {
        let r = rotation(pose);
        add(
            [pose[3], pose[4], pose[5]],
            times(&r, self.legs[i].platform),
        )
    }

    /// The actuators' values `θ_i + encoder_offset` at `pose`.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first leg whose crank cannot reach its ball.
    pub fn actuator_angles(&self, pose: &[f64; 6]) -> Result<[f64; 6], Error> {
        let balls: Vec<[f64; 3]> = (0..6).map(|i| self.ball(i, pose)).collect();
        let q = actuator_angles(&self.legs, &balls, "legs")?;
        Ok(core::array::from_fn(|i| q[i]))
    }

    /// The names of [`RusHexapod::kernel_parameters`], in order (valid Rust identifiers).
    pub fn kernel_parameter_names() -> Vec<String> {
        let mut out: Vec<String> = ["x", "y", "z"]
            .iter()
            .map(|a| format!("gravity_{a}"))
            .collect();
        for n in 1..=6 {
            out.extend(LEG_GEOMETRY_NAMES.map(|s| format!("leg{n}_{s}")));
        }
        out.extend(Self::standard_inertial_names());
        out
    }

    /// The names of the standard inertial parameters: the platform's ten (about `C`, platform
    /// frame), then each leg's crank ([`CRANK_STANDARD`], about `A_i`, crank frame) and rod
    /// ([`ROD_STANDARD`], about the crank's tip `E_i`, rod frame).
    pub fn standard_inertial_names() -> Vec<String> {
        let mut out: Vec<String> = PLATFORM_STANDARD
            .iter()
            .map(|s| format!("platform_{s}"))
            .collect();
        for n in 1..=6 {
            out.extend(CRANK_STANDARD.map(|s| format!("leg{n}_crank_{s}")));
            out.extend(ROD_STANDARD.map(|s| format!("leg{n}_rod_{s}")));
        }
        out
    }

    /// The standard inertial parameters, in the order of
    /// [`RusHexapod::standard_inertial_names`].
    pub fn standard_inertial_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS - GEOMETRY_PARAMETERS);
        out.extend(self.platform.standard_parameters());
        for leg in &self.legs {
            out.extend(leg.crank_standard());
            out.extend(leg.rod_standard());
        }
        out
    }

    /// The standard parameters `π` of `Γ = Y π` with the motors' `friction`: the inertial
    /// ones ([`RusHexapod::standard_inertial_parameters`]), then the viscous (N·m·s/rad) and
    /// the Coulomb (N·m) coefficients, six each.
    pub fn standard_parameters(&self, friction: &[crate::Friction; 6]) -> Vec<f64> {
        crate::standard::with_friction(self.standard_inertial_parameters(), friction)
    }

    /// The parameter vector of the `*_params` kernels: gravity, each leg's geometry
    /// ([`RusLeg::kernel_geometry`]), then the standard inertial parameters.
    pub fn kernel_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS);
        out.extend(self.gravity);
        for leg in &self.legs {
            out.extend(leg.kernel_geometry());
        }
        out.extend(self.standard_inertial_parameters());
        out
    }

    /// The example of `docs/rus-hexapod.toml`: a motion-simulator platform of about 0.7 m
    /// across, its motors on a circle of 0.31 m, its balls on one of 0.19 m, standing about
    /// 0.33 m above its motors at home.
    pub fn example() -> Self {
        let leg = |base: [f64; 3], axis: [f64; 3], zero: [f64; 3], platform: [f64; 3]| RusLeg {
            base,
            axis,
            zero,
            crank: Crank {
                length: 0.12,
                mass: 0.35,
                com: 0.055,
                inertia: [2e-5, 6.5e-4, 6.6e-4],
            },
            rod: RusRod {
                length: 0.34,
                separation: None,
                mass: 0.22,
                com: 0.16,
                inertia: [2.2e-3, 2.2e-3, 1.5e-5],
            },
            platform,
            branch: -1.0,
            encoder_offset: 0.0,
        };
        RusHexapod {
            gravity: [0.0, 0.0, -9.81],
            platform: Platform {
                mass: 3.8,
                centre_of_mass: [0.0, 0.0, 0.025],
                inertia: [0.031, 0.034, 0.058, 0.0, 0.0, 0.0],
            },
            legs: [
                leg(
                    [0.3, 0.08, 0.0],
                    [0.97, 0.25, 0.0],
                    [-0.25, 0.97, 0.0],
                    [0.17, 0.09, -0.015],
                ),
                leg(
                    [0.3, -0.08, 0.0],
                    [-0.97, 0.25, 0.0],
                    [-0.25, -0.97, 0.0],
                    [0.17, -0.09, -0.015],
                ),
                leg(
                    [-0.219282, 0.219808, 0.0],
                    [-0.701506, 0.715045, 0.0],
                    [-0.715045, -0.701506, 0.0],
                    [-0.162942, 0.102224, -0.015],
                ),
                leg(
                    [-0.080718, 0.299808, 0.0],
                    [0.268494, -0.965045, 0.0],
                    [0.965045, 0.268494, 0.0],
                    [-0.007058, 0.192224, -0.015],
                ),
                leg(
                    [-0.080718, -0.299808, 0.0],
                    [-0.268494, -0.965045, 0.0],
                    [0.965045, -0.268494, 0.0],
                    [-0.007058, -0.192224, -0.015],
                ),
                leg(
                    [-0.219282, -0.219808, 0.0],
                    [0.701506, 0.715045, 0.0],
                    [-0.715045, 0.701506, 0.0],
                    [-0.162942, -0.102224, -0.015],
                ),
            ],
            home: None,
        }
    }

    /// Checks every rule a physical rotary hexapod obeys.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field that breaks a rule: a non-finite number, a
    /// non-positive mass or length, an inertia no rigid body has, a zero axis, a `zero` along
    /// its axis, a branch other than ±1, or a rod that cannot reach at home.
    pub fn validate(&self) -> Result<(), Error> {
        self.platform.validate()?;
        let balls = self
            .home()
            .map(|home| (0..6).map(|i| self.ball(i, &home)).collect());
        let home = self.home.as_ref().map(|h| h.as_slice());
        validate_legs(&self.gravity, &self.legs, "legs", false, home, balls)
    }

    /// Reads a rotary hexapod in TOML (`mechanism = "rus-hexapod"`); `source` names the file.
    ///
    /// # Errors
    /// [`Error::File`] naming the source and what is wrong.
    #[cfg(feature = "toml")]
    pub fn from_toml(text: &str, source: &str) -> Result<Self, Error> {
        crate::description::read_toml(text, source, crate::description::RUS_HEXAPOD)
            .and_then(|r: Self| r.validate().map(|()| r).map_err(|e| file_error(source, e)))
    }

    /// The description as TOML, as [`RusHexapod::from_toml`] reads it.
    #[cfg(feature = "toml")]
    pub fn to_toml(&self) -> String {
        crate::description::write_toml(self, crate::description::RUS_HEXAPOD)
    }
}

#[cfg(feature = "toml")]
pub(crate) fn file_error(source: &str, e: Error) -> Error {
    Error::File {
        source: source.to_string(),
        message: e.to_string(),
    }
}

#[cfg(all(test, feature = "toml"))]
mod tests {
    use super::*;

    #[test]
    fn the_example_is_the_docs_file() {
        let file = include_str!("../../../docs/rus-hexapod.toml");
        let read = RusHexapod::from_toml(file, "docs/rus-hexapod.toml").unwrap();
        assert_eq!(read, RusHexapod::example());
    }

    #[test]
    fn the_parameter_vector_has_its_names() {
        let names = RusHexapod::kernel_parameter_names();
        assert_eq!(names.len(), PARAMETERS);
        assert_eq!(RusHexapod::example().kernel_parameters().len(), PARAMETERS);
        assert_eq!(names[GEOMETRY_PARAMETERS], "platform_mass");
        assert_eq!(names[3 + LEG_GEOMETRY], "leg2_base_x");
    }
}
