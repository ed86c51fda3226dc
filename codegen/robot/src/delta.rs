//! The Delta: three motors on the base turn upper arms (cranks); a parallelogram of two rods
//! from each arm's tip to the platform keeps the platform parallel to the base, so it only
//! translates. Pick-and-place and packaging lines. The arm is [`crate::rus`]'s leg with
//! `B_i = C + p_i`; its two rods run from `E_i ± (w_i/2) r_i` to `C + p_i ± (w_i/2) r_i`.

use crate::rus::{
    actuator_angles, invalid, level_home, validate_legs, RusLeg, CRANK_STANDARD, LEG_GEOMETRY,
    LEG_GEOMETRY_NAMES, ROD_STANDARD,
};
use crate::tree::add;
use crate::Error;
use alloc::string::{String, ToString};
use alloc::vec::Vec;

/// The entries of one arm in the kernels' geometry: the rotary hexapod leg's
/// ([`RusLeg::kernel_geometry`]), then the parallelogram's separation `w_i`.
pub const ARM_GEOMETRY: usize = LEG_GEOMETRY + 1;

/// How many entries open the parameter vector before the inertial ones: gravity, then each
/// arm's [`ARM_GEOMETRY`].
pub const GEOMETRY_PARAMETERS: usize = 3 + 3 * ARM_GEOMETRY;

/// Length of the parameter vector of the `*_params` kernels: the geometry, the platform's
/// mass (a platform that only translates feels neither its inertia nor where its centre of
/// mass is), each arm's crank's five and rod's four standard parameters.
pub const PARAMETERS: usize =
    GEOMETRY_PARAMETERS + 1 + 3 * (CRANK_STANDARD.len() + ROD_STANDARD.len());

/// The Delta's platform: it translates only, so its rotational inertia is never felt.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct DeltaPlatform {
    /// Mass (kg), with whatever it carries.
    pub mass: f64,
    /// Centre of mass from the platform origin `C` (m).
    pub centre_of_mass: [f64; 3],
}

/// A Delta robot.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Delta {
    /// Gravity in the base frame (m/s²).
    pub gravity: [f64; 3],
    /// The platform, whose frame stays parallel to the base's.
    pub platform: DeltaPlatform,
    /// The three arms, in actuator order.
    #[cfg_attr(feature = "serde", serde(with = "exactly_three"))]
    pub arms: [RusLeg; 3],
    /// The home position `[xc yc zc]`. Default: centred over the base at the height where the
    /// arms are nearest their zero (`Σ θ_i²` least).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub home: Option<[f64; 3]>,
}

#[cfg(feature = "serde")]
mod exactly_three {
    crate::counted_list!(RusLeg, 3, "three [[arms]]");
}

impl Delta {
    /// The home position: the file's `home`, else centred at the height where the arms are
    /// nearest their zero; `None` where no height reaches every arm.
    pub fn home(&self) -> Option<[f64; 3]> {
        self.home
            .or_else(|| level_home(&self.arms).map(|z| [0.0, 0.0, z]))
    }

    /// The actuators' values `θ_i + encoder_offset` at the platform position `c`.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first arm that cannot reach.
    pub fn actuator_angles(&self, c: &[f64; 3]) -> Result<[f64; 3], Error> {
        let q = actuator_angles(&self.arms, &self.balls(c), "arms")?;
        Ok(core::array::from_fn(|i| q[i]))
    }

    /// The example of `docs/delta.toml`: a pick-and-place Delta of about 0.5 m across, its
    /// motors on a circle of 0.205 m, upper arms of 0.26 m, parallelograms of 0.62 m rods
    /// 0.07 m apart; the arms by turns of 120 degrees (to the file's six digits).
    pub fn example() -> Self {
        let arm = |base: [f64; 3], axis: [f64; 3], zero: [f64; 3], platform: [f64; 3]| RusLeg {
            base,
            axis,
            zero,
            crank: crate::rus::Crank {
                length: 0.26,
                mass: 0.9,
                com: 0.11,
                inertia: [4e-4, 6.1e-3, 6.2e-3],
            },
            rod: crate::rus::RusRod {
                length: 0.62,
                separation: Some(0.07),
                mass: 0.12,
                com: 0.31,
                inertia: [3.9e-3, 3.9e-3, 4e-6],
            },
            platform,
            branch: -1.0,
            encoder_offset: 0.0,
        };
        Delta {
            gravity: [0.0, 0.0, -9.81],
            platform: DeltaPlatform {
                mass: 0.65,
                centre_of_mass: [0.0, 0.0, -0.012],
            },
            arms: [
                arm(
                    [0.205, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.048, 0.0, 0.0],
                ),
                arm(
                    [-0.1025, 0.177535, 0.0],
                    [-0.866025, -0.5, 0.0],
                    [-0.5, 0.866025, 0.0],
                    [-0.024, 0.041569, 0.0],
                ),
                arm(
                    [-0.1025, -0.177535, 0.0],
                    [0.866025, -0.5, 0.0],
                    [-0.5, -0.866025, 0.0],
                    [-0.024, -0.041569, 0.0],
                ),
            ],
            home: None,
        }
    }

    /// The names of [`Delta::kernel_parameters`], in order (valid Rust identifiers).
    pub fn kernel_parameter_names() -> Vec<String> {
        let mut out: Vec<String> = ["x", "y", "z"]
            .iter()
            .map(|a| alloc::format!("gravity_{a}"))
            .collect();
        for n in 1..=3 {
            out.extend(LEG_GEOMETRY_NAMES.map(|s| alloc::format!("arm{n}_{s}")));
            out.push(alloc::format!("arm{n}_separation"));
        }
        out.extend(Self::standard_inertial_names());
        out
    }

    /// The names of the standard inertial parameters: the platform's mass, then each arm's
    /// crank ([`CRANK_STANDARD`], about `A_i`, crank frame) and each of its two rods
    /// ([`ROD_STANDARD`], about its U joint, rod frame; the two alike).
    pub fn standard_inertial_names() -> Vec<String> {
        let mut out = alloc::vec!["platform_mass".to_string()];
        for n in 1..=3 {
            out.extend(CRANK_STANDARD.map(|s| alloc::format!("arm{n}_crank_{s}")));
            out.extend(ROD_STANDARD.map(|s| alloc::format!("arm{n}_rod_{s}")));
        }
        out
    }

    /// The standard inertial parameters, in the order of [`Delta::standard_inertial_names`].
    pub fn standard_inertial_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS - GEOMETRY_PARAMETERS);
        out.push(self.platform.mass);
        for arm in &self.arms {
            out.extend(arm.crank_standard());
            out.extend(arm.rod_standard());
        }
        out
    }

    /// The standard parameters `π` of `Γ = Y π` with the motors' `friction`: the inertial
    /// ones ([`Delta::standard_inertial_parameters`]), then the viscous (N·m·s/rad) and the
    /// Coulomb (N·m) coefficients, three each.
    pub fn standard_parameters(&self, friction: &[crate::Friction; 3]) -> Vec<f64> {
        crate::standard::with_friction(self.standard_inertial_parameters(), friction)
    }

    /// The parameter vector of the `*_params` kernels: gravity, each arm's geometry
    /// ([`RusLeg::kernel_geometry`] and the separation), then the standard inertial
    /// parameters.
    pub fn kernel_parameters(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(PARAMETERS);
        out.extend(self.gravity);
        for arm in &self.arms {
            out.extend(arm.kernel_geometry());
            out.push(arm.rod.separation.unwrap_or(0.0));
        }
        out.extend(self.standard_inertial_parameters());
        out
    }

    /// `B_i = C + p_i` at the platform position `c`.
    fn balls(&self, c: &[f64; 3]) -> Vec<[f64; 3]> {
        self.arms.iter().map(|a| add(*c, a.platform)).collect()
    }

    /// Checks every rule a physical Delta obeys.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field that breaks a rule (as
    /// [`crate::RusHexapod::validate`], and a missing or non-positive `rod.separation`).
    pub fn validate(&self) -> Result<(), Error> {
        let p = &self.platform;
        if !(p.mass.is_finite() && p.centre_of_mass.iter().all(|x| x.is_finite())) {
            return Err(invalid("platform", "must be finite"));
        }
        if p.mass <= 0.0 {
            return Err(invalid("platform.mass", "must be positive"));
        }
        let balls = self.home().map(|home| self.balls(&home));
        let home = self.home.as_ref().map(|h| h.as_slice());
        validate_legs(&self.gravity, &self.arms, "arms", true, home, balls)
    }

    /// Reads a Delta in TOML (`mechanism = "delta"`); `source` names the file.
    ///
    /// # Errors
    /// [`Error::File`] naming the source and what is wrong.
    #[cfg(feature = "toml")]
    pub fn from_toml(text: &str, source: &str) -> Result<Self, Error> {
        crate::description::read_toml(text, source, crate::description::DELTA).and_then(
            |r: Self| {
                r.validate()
                    .map(|()| r)
                    .map_err(|e| crate::rus_hexapod::file_error(source, e))
            },
        )
    }

    /// The description as TOML, as [`Delta::from_toml`] reads it.
    #[cfg(feature = "toml")]
    pub fn to_toml(&self) -> String {
        crate::description::write_toml(self, crate::description::DELTA)
    }
}

#[cfg(all(test, feature = "toml"))]
mod tests {
    use super::*;

    #[test]
    fn the_example_is_the_docs_file() {
        let file = include_str!("../../../docs/delta.toml");
        let read = Delta::from_toml(file, "docs/delta.toml").unwrap();
        assert_eq!(read, Delta::example());
    }

    #[test]
    fn the_parameter_vector_has_its_names() {
        let names = Delta::kernel_parameter_names();
        assert_eq!(names.len(), PARAMETERS);
        assert_eq!(Delta::example().kernel_parameters().len(), PARAMETERS);
        assert_eq!(names[GEOMETRY_PARAMETERS], "platform_mass");
        assert_eq!(names[3 + ARM_GEOMETRY], "arm2_base_x");
        assert_eq!(names[3 + LEG_GEOMETRY], "arm1_separation");
    }
}
