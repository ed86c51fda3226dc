//! The Delta: three motors on the base turn upper arms (cranks); a parallelogram of two rods
//! from each arm's tip to the platform keeps the platform parallel to the base, so it only
//! translates. Pick-and-place and packaging lines. The arm is [`crate::rus`]'s leg with
//! `B_i = C + p_i`; its two rods run from `E_i ± (w_i/2) r_i` to `C + p_i ± (w_i/2) r_i`.

use crate::rus::{actuator_angles, invalid, level_home, validate_legs, RusLeg};
use crate::tree::add;
use crate::Error;
#[cfg(feature = "toml")]
use alloc::string::String;
use alloc::vec::Vec;

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
