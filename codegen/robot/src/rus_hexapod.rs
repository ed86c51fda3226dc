//! The rotary hexapod (6-RUS): six motors on the base turn cranks; a rod from each crank's tip
//! (U joint) to the platform (ball) carries it. Motion simulators and servo-driven platforms.
//! The leg is [`crate::rus`]'s; the platform is the Gough-Stewart platform's
//! ([`crate::Platform`]), with the same pose, twist and acceleration conventions.

use crate::gough_stewart::rotation;
use crate::rus::{actuator_angles, level_home, validate_legs, RusLeg};
use crate::tree::{add, times};
use crate::{Error, Platform};
#[cfg(feature = "toml")]
use alloc::string::{String, ToString};
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
