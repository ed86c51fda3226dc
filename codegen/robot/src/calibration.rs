//! What kinematic calibration fits of a legged mechanism: per leg, the entries of its kernel
//! geometry that move its actuator's reading and that a built robot gets wrong by millimetres
//! (joint centres, lengths, the encoder's zero). The generator differentiates the residual
//! kernel with respect to them; the runtime reads and writes them through
//! [`Description::fitted_values`] and [`Description::set_fitted_values`].
//!
//! The R-U-S leg's motor axis `r_i` is fitted by its direction's azimuth and elevation in the
//! base frame ([`Coordinate::Azimuth`], [`Coordinate::Elevation`]): a motor mounted askew
//! tilts its crank's plane. The crank's zero `h_i` turns with the axis (it is kept orthogonal
//! to it); its turn about the axis is the encoder's offset, fitted on its own.
//!
//! What is left out, and why:
//! - the U-P-S leg's U-joint axis and the R-U-S leg's branch do not move the actuator;
//! - the Delta's platform points `p_i`: a platform that only translates sees `p_i - A_i`
//!   alone, so `A_i` carries the pair.

use crate::math::{atan2, sin_cos, sqrt};
use crate::tree::{dot, scale, sub, unit};
use crate::{Description, RusLeg, UpsLeg};
use alloc::vec::Vec;

/// Where a fitted parameter sits in a leg's kernel geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coordinate {
    /// An entry of its own.
    Entry(usize),
    /// The azimuth `atan2(r_y, r_x)` of the R-U-S leg's motor axis `r` (entries 3..6), its
    /// crank's zero `h` (entries 6..9) turning with it.
    Azimuth,
    /// The elevation `asin r_z` of the motor axis, `h` turning with it.
    Elevation,
}

/// One geometric parameter fitted per leg.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fitted {
    /// Its symbol: `A` (the base joint's or the motor's centre), `p` (the platform joint's
    /// centre), `c` (the crank's length), `L` (the rod's), `o` (the encoder's offset).
    pub symbol: &'static str,
    /// The component, `x`, `y`, `z`, or empty for a scalar.
    pub component: &'static str,
    /// What it is in the leg's kernel geometry.
    pub coordinate: Coordinate,
    /// Its key in the leg's table of the robot file (`crank.length` a key of a sub-table).
    pub key: &'static [&'static str],
    /// Whether it is an angle (rad); else a length (m).
    pub angle: bool,
}

impl Fitted {
    /// Its name for leg `leg` (from 1): `A3.x`, `L2`, `o6`.
    pub fn name(&self, leg: usize) -> alloc::string::String {
        match self.component {
            "" => alloc::format!("{}{leg}", self.symbol),
            c => alloc::format!("{}{leg}.{c}", self.symbol),
        }
    }
}

const fn point(symbol: &'static str, first: usize, key: &'static [&'static str]) -> [Fitted; 3] {
    [
        component(symbol, "x", first, key),
        component(symbol, "y", first + 1, key),
        component(symbol, "z", first + 2, key),
    ]
}

const fn component(
    symbol: &'static str,
    component: &'static str,
    entry: usize,
    key: &'static [&'static str],
) -> Fitted {
    Fitted {
        symbol,
        component,
        coordinate: Coordinate::Entry(entry),
        key,
        angle: false,
    }
}

const fn scalar(
    symbol: &'static str,
    entry: usize,
    key: &'static [&'static str],
    angle: bool,
) -> Fitted {
    Fitted {
        symbol,
        component: "",
        coordinate: Coordinate::Entry(entry),
        key,
        angle,
    }
}

const BASE: &[&str] = &["base"];
const PLATFORM: &[&str] = &["platform"];
const OFFSET: &[&str] = &["encoder_offset"];
const CRANK: &[&str] = &["crank", "length"];
const ROD: &[&str] = &["rod", "length"];
const AXIS: &[&str] = &["axis"];

const fn turn(component: &'static str, coordinate: Coordinate) -> Fitted {
    Fitted {
        symbol: "r",
        component,
        coordinate,
        key: AXIS,
        angle: true,
    }
}

/// A U-P-S leg's (the Gough-Stewart platform's): `A_i`, `p_i`, `o_i`, entries of
/// [`UpsLeg::kernel_geometry`].
pub const UPS: [Fitted; 7] = {
    let [ax, ay, az] = point("A", 0, BASE);
    let [px, py, pz] = point("p", 6, PLATFORM);
    [ax, ay, az, px, py, pz, scalar("o", 9, OFFSET, false)]
};

/// A rotary hexapod's R-U-S leg: `A_i`, the motor axis's azimuth and elevation (rad), `p_i`,
/// the crank's length `c_i`, the rod's `L_i` and the encoder's offset `o_i` (rad), of
/// [`RusLeg::kernel_geometry`].
pub const RUS: [Fitted; 11] = {
    let [ax, ay, az] = point("A", 0, BASE);
    let [px, py, pz] = point("p", 9, PLATFORM);
    [
        ax,
        ay,
        az,
        turn("az", Coordinate::Azimuth),
        turn("el", Coordinate::Elevation),
        px,
        py,
        pz,
        scalar("c", 12, CRANK, false),
        scalar("L", 13, ROD, false),
        scalar("o", 15, OFFSET, true),
    ]
};

/// A Delta's arm: [`RUS`] without `p_i`, which only `p_i - A_i` reaches.
pub const DELTA_ARM: [Fitted; 8] = {
    let [ax, ay, az] = point("A", 0, BASE);
    [
        ax,
        ay,
        az,
        turn("az", Coordinate::Azimuth),
        turn("el", Coordinate::Elevation),
        scalar("c", 12, CRANK, false),
        scalar("L", 13, ROD, false),
        scalar("o", 15, OFFSET, true),
    ]
};

impl UpsLeg {
    /// The value of `coordinate` of [`UpsLeg::kernel_geometry`]; `None` for a turn, which a
    /// U-P-S leg does not fit.
    pub fn fitted_value(&self, coordinate: Coordinate) -> Option<f64> {
        match coordinate {
            Coordinate::Entry(entry) => self.kernel_geometry().get(entry).copied(),
            Coordinate::Azimuth | Coordinate::Elevation => None,
        }
    }

    /// Sets `coordinate` of [`UpsLeg::kernel_geometry`] where it is a field of its own (`A_i`,
    /// `p_i`, `o_i`); returns whether it was.
    pub fn set_fitted_value(&mut self, coordinate: Coordinate, value: f64) -> bool {
        match coordinate {
            Coordinate::Entry(entry @ 0..=2) => self.base[entry] = value,
            Coordinate::Entry(entry @ 6..=8) => self.platform[entry - 6] = value,
            Coordinate::Entry(9) => self.encoder_offset = value,
            _ => return false,
        }
        true
    }
}

impl RusLeg {
    /// The value of `coordinate` of [`RusLeg::kernel_geometry`].
    pub fn fitted_value(&self, coordinate: Coordinate) -> Option<f64> {
        let (r, _, _) = self.axes();
        match coordinate {
            Coordinate::Entry(entry) => self.kernel_geometry().get(entry).copied(),
            Coordinate::Azimuth => Some(atan2(r[1], r[0])),
            Coordinate::Elevation => Some(atan2(r[2], sqrt(r[0] * r[0] + r[1] * r[1]))),
        }
    }

    /// Sets `coordinate` of [`RusLeg::kernel_geometry`] where it is a field of its own (`A_i`,
    /// `p_i`, the lengths, the offset; not the branch) or the axis's direction (the zero then
    /// set to the crank's direction at `θ = 0`, orthogonal to the new axis); returns whether it
    /// was.
    pub fn set_fitted_value(&mut self, coordinate: Coordinate, value: f64) -> bool {
        let (r, h, _) = self.axes();
        let (azimuth, elevation) = (
            atan2(r[1], r[0]),
            atan2(r[2], sqrt(r[0] * r[0] + r[1] * r[1])),
        );
        let mut turn = |azimuth: f64, elevation: f64| {
            let (sa, ca) = sin_cos(azimuth);
            let (se, ce) = sin_cos(elevation);
            let axis = [ce * ca, ce * sa, se];
            self.axis = axis;
            self.zero = unit(sub(h, scale(axis, dot(h, axis))));
        };
        match coordinate {
            Coordinate::Entry(entry @ 0..=2) => self.base[entry] = value,
            Coordinate::Entry(entry @ 9..=11) => self.platform[entry - 9] = value,
            Coordinate::Entry(12) => self.crank.length = value,
            Coordinate::Entry(13) => self.rod.length = value,
            Coordinate::Entry(15) => self.encoder_offset = value,
            Coordinate::Azimuth => turn(value, elevation),
            Coordinate::Elevation => turn(azimuth, value),
            Coordinate::Entry(_) => return false,
        }
        true
    }
}

impl Description {
    /// The parameters kinematic calibration fits per leg; `None` for the C5, whose legs are
    /// not a list of joint centres.
    pub fn fitted(&self) -> Option<&'static [Fitted]> {
        match self {
            Description::C5(_) => None,
            Description::GoughStewart(_) => Some(&UPS),
            Description::RusHexapod(_) => Some(&RUS),
            Description::Delta(_) => Some(&DELTA_ARM),
        }
    }

    /// The robot file's list of legs: `legs`, the Delta's `arms`.
    pub fn legs_key(&self) -> &'static str {
        match self {
            Description::Delta(_) => "arms",
            _ => "legs",
        }
    }

    /// The values of leg `leg`'s (from 0) [`Description::fitted`] parameters; empty for a
    /// mechanism without them or a leg it does not have.
    pub fn fitted_values(&self, leg: usize) -> Vec<f64> {
        let fitted = self.fitted().unwrap_or(&[]);
        let value: &dyn Fn(Coordinate) -> Option<f64> = match self {
            Description::C5(_) => &|_| None,
            Description::GoughStewart(r) => &|c| r.legs.get(leg)?.fitted_value(c),
            Description::RusHexapod(r) => &|c| r.legs.get(leg)?.fitted_value(c),
            Description::Delta(r) => &|c| r.arms.get(leg)?.fitted_value(c),
        };
        fitted
            .iter()
            .map(|f| value(f.coordinate))
            .collect::<Option<Vec<f64>>>()
            .unwrap_or_default()
    }

    /// Sets leg `leg`'s (from 0) [`Description::fitted`] parameters to `values`, in their
    /// order; returns whether the mechanism has them and the leg (nothing changed if not).
    pub fn set_fitted_values(&mut self, leg: usize, values: &[f64]) -> bool {
        let Some(fitted) = self.fitted() else {
            return false;
        };
        if values.len() != fitted.len() {
            return false;
        }
        let set = |apply: &mut dyn FnMut(Coordinate, f64) -> bool| {
            fitted
                .iter()
                .zip(values)
                .all(|(f, &value)| apply(f.coordinate, value))
        };
        match self {
            Description::C5(_) => false,
            Description::GoughStewart(r) => r
                .legs
                .get_mut(leg)
                .is_some_and(|l| set(&mut |c, v| l.set_fitted_value(c, v))),
            Description::RusHexapod(r) => r
                .legs
                .get_mut(leg)
                .is_some_and(|l| set(&mut |c, v| l.set_fitted_value(c, v))),
            Description::Delta(r) => r
                .arms
                .get_mut(leg)
                .is_some_and(|l| set(&mut |c, v| l.set_fitted_value(c, v))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every fitted parameter reads back what was set, in the kernels' parameter vector too.
    #[test]
    fn the_fitted_values_are_set_and_read_back_through_the_kernel_geometry() {
        for mut robot in [
            Description::GoughStewart(crate::GoughStewart::example()),
            Description::RusHexapod(crate::RusHexapod::example()),
            Description::Delta(crate::Delta::example()),
        ] {
            let fitted = robot.fitted().unwrap();
            let legs = if matches!(robot, Description::Delta(_)) {
                3
            } else {
                6
            };
            for leg in 0..legs {
                let values: Vec<f64> = robot
                    .fitted_values(leg)
                    .iter()
                    .enumerate()
                    .map(|(k, v)| v + 1e-3 * (k + 1) as f64)
                    .collect();
                assert!(robot.set_fitted_values(leg, &values));
                let back = robot.fitted_values(leg);
                let off = back.iter().zip(&values).map(|(a, b)| (a - b).abs());
                assert!(off.fold(0.0, f64::max) < 1e-14, "{back:?} vs {values:?}");
            }
            assert_eq!(fitted.len(), robot.fitted_values(0).len());
            assert!(!robot.set_fitted_values(legs, &robot.fitted_values(0)));
        }
        assert!(Description::default().fitted().is_none());
        assert!(Description::default().fitted_values(0).is_empty());
    }

    #[test]
    fn the_names_carry_the_leg() {
        assert_eq!(UPS[2].name(3), "A3.z");
        assert_eq!(RUS[9].name(2), "L2");
        assert_eq!(RUS[3].name(1), "r1.az");
        assert!(RUS[10].angle && RUS[4].angle && !UPS[6].angle);
    }
}
