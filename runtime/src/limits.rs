//! The robot's limits at run time: the kinds of limit, and the checks that name the limit,
//! the actuator and the value, written once for every mechanism
//! ([`crate::ParallelRobot::check_limits`], [`crate::Mechanism::check_limits`]). Each
//! mechanism gives its margins: the C5's from its generated `limit_geometry` kernel
//! ([`LimitMargins`]), a hexapod's from its legs' strokes and joint cones.

use crate::Error;
use core::fmt;

pub use crate::c5::limits::{LimitMargins, LimitValues};

/// A kind of limit of [`c5_robot::Limits`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize),
    serde(rename_all = "snake_case")
)]
pub enum Limit {
    /// The ball-screw stroke: `Q_i1` within `[min, max]` (m).
    Stroke,
    /// The ball's offset on its plate, along one of its two axes (m).
    PlateTravel,
    /// The angle between the rod's axis and the plate's normal (rad).
    Tilt,
    /// A Gough-Stewart leg's angle from its direction at home, base frame: the U joint's
    /// cone (rad).
    UJoint,
    /// A Gough-Stewart leg's angle from its direction at home, seen from the platform: the
    /// S joint's cone (rad).
    SJoint,
    /// The actuator's speed `|Q̇_i1|` (m/s).
    Speed,
    /// The actuator's force `|Γ_i|` (N).
    Force,
}

impl Limit {
    /// The limit's name, as errors and the command line spell it.
    pub const fn name(self) -> &'static str {
        match self {
            Limit::Stroke => "stroke",
            Limit::PlateTravel => "plate travel",
            Limit::Tilt => "tilt",
            Limit::UJoint => "U joint",
            Limit::SJoint => "S joint",
            Limit::Speed => "speed",
            Limit::Force => "force",
        }
    }

    /// The unit of its values and margins.
    pub const fn unit(self) -> &'static str {
        match self {
            Limit::Stroke | Limit::PlateTravel => "m",
            Limit::Tilt | Limit::UJoint | Limit::SJoint => "rad",
            Limit::Speed => "m/s",
            Limit::Force => "N",
        }
    }
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The smallest margin of a pose's limits, as an error where it is negative.
pub(crate) fn refuse_beyond(smallest: Option<(Limit, usize, f64, f64)>) -> Result<(), Error> {
    match smallest {
        Some((limit, actuator, margin, value)) if margin < 0.0 => Err(Error::Limit {
            limit,
            actuator,
            value,
            margin,
        }),
        _ => Ok(()),
    }
}

/// The value of `values` furthest over `bound` in magnitude, as an error.
pub(crate) fn over(limit: Limit, bound: Option<f64>, values: &[f64]) -> Result<(), Error> {
    let Some(bound) = bound else { return Ok(()) };
    let (i, margin) = values.iter().map(|v| bound - v.abs()).enumerate().fold(
        (0, f64::INFINITY),
        |best, (i, m)| if m < best.1 { (i, m) } else { best },
    );
    if margin < 0.0 {
        return Err(Error::Limit {
            limit,
            actuator: i + 1,
            value: values[i],
            margin,
        });
    }
    Ok(())
}
