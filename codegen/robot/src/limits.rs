//! The robot's physical limits: ball-screw strokes, plate travel, ball tilt, actuator speed
//! and force. Every limit is optional; an absent one does not bound anything.

use crate::Error;
use alloc::format;
use alloc::string::ToString;

/// The robot's limits; `None` is unlimited (the default for every field).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Limits {
    /// Each actuator's stroke `[min, max]` (m): the range of `Q_i1`, the ball centre's position
    /// along the actuator's axis (zero at the home pose). A file gives one pair for all six or
    /// six pairs.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none", with = "one_or_six")
    )]
    pub stroke: Option<[[f64; 2]; 6]>,
    /// How far the ball may sit from its plate's centre (the anchor `A_i` carried by the
    /// platform) along each axis of the plate (m): the first and second in-plane axes of the
    /// platform frame, in the order x, y, z without the plate's normal (`y, z` for segments 1
    /// and 2, `x, z` for 3 and 4, `x, y` for 5 and 6). A file gives one number for both or two.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none", with = "one_or_two")
    )]
    pub plate_travel: Option<[f64; 2]>,
    /// The largest angle between the rod's axis `n_i` and the plate's normal `m_i` (rad), which
    /// the ball's housing allows: `arccos(n_i · m_i) ≤ tilt`.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub tilt: Option<f64>,
    /// The largest actuator speed `|Q̇_i1|` (m/s).
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

fn invalid(field: &str, rule: &str) -> Error {
    Error::Invalid {
        field: format!("limits.{field}"),
        rule: rule.to_string(),
    }
}

fn positive(field: &str, v: Option<f64>) -> Result<(), Error> {
    match v {
        Some(x) if !(x > 0.0 && x.is_finite()) => {
            Err(invalid(field, "must be positive and finite"))
        }
        _ => Ok(()),
    }
}

impl Limits {
    /// Whether any limit is set.
    pub fn any(&self) -> bool {
        *self != Limits::default()
    }

    /// Whether no limit is set (the default).
    pub fn is_unset(&self) -> bool {
        !self.any()
    }

    /// The rules every limit obeys: a stroke's `min < max`, both finite; plate travel, speed
    /// and force positive and finite; the tilt in `(0, π/2)`, where the ball still transmits
    /// the rod's force to its plate.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first field (`limits.stroke[3]`, ...) that breaks a rule.
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(stroke) = &self.stroke {
            for (i, [lo, hi]) in stroke.iter().enumerate() {
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(invalid(
                        &format!("stroke[{}]", i + 1),
                        "must be [min, max] with min < max, both finite",
                    ));
                }
            }
        }
        if let Some([a, b]) = self.plate_travel {
            positive("plate_travel", Some(a))?;
            positive("plate_travel", Some(b))?;
        }
        if let Some(t) = self.tilt {
            if !(t > 0.0 && t < core::f64::consts::FRAC_PI_2) {
                return Err(invalid("tilt", "must be in (0, π/2) rad"));
            }
        }
        positive("speed", self.speed)?;
        positive("force", self.force)
    }
}

/// `[min, max]` for all six actuators, or six pairs.
#[cfg(feature = "serde")]
pub(crate) mod one_or_six {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Given {
        One([f64; 2]),
        Six([[f64; 2]; 6]),
    }

    pub fn serialize<S: Serializer>(v: &Option<[[f64; 2]; 6]>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(all) if all.iter().all(|p| p == &all[0]) => all[0].serialize(s),
            other => other.serialize(s),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 2]; 6]>, D::Error> {
        Ok(Some(
            match Given::deserialize(d).map_err(|_| {
                serde::de::Error::custom("`stroke` takes [min, max] or six [min, max] pairs")
            })? {
                Given::One(p) => [p; 6],
                Given::Six(all) => all,
            },
        ))
    }
}

/// One number for both axes of the plate, or two.
#[cfg(feature = "serde")]
mod one_or_two {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Given {
        One(f64),
        Two([f64; 2]),
    }

    pub fn serialize<S: Serializer>(v: &Option<[f64; 2]>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some([a, b]) if a == b => a.serialize(s),
            other => other.serialize(s),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        Ok(Some(
            match Given::deserialize(d)
                .map_err(|_| serde::de::Error::custom("`plate_travel` takes one number or two"))?
            {
                Given::One(x) => [x, x],
                Given::Two(p) => p,
            },
        ))
    }
}
