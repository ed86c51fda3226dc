//! What kinematic calibration fits of a legged mechanism: per leg, the entries of its kernel
//! geometry that move its actuator's reading and that a built robot gets wrong by millimetres
//! (joint centres, lengths, the encoder's zero). The generator differentiates the residual
//! kernel with respect to them; the runtime reads and writes them through
//! [`Description::fitted_values`] and [`Description::set_fitted_values`].
//!
//! What is left out, and why:
//! - the U-P-S leg's U-joint axis and the R-U-S leg's branch do not move the actuator;
//! - the R-U-S leg's motor axis and crank zero: a turn of the zero about the axis is the
//!   encoder's offset, already fitted; a tilt of the axis is not fitted yet;
//! - the Delta's platform points `p_i`: a platform that only translates sees `p_i - A_i`
//!   alone, so `A_i` carries the pair.

use crate::{Description, RusLeg, UpsLeg};
use alloc::vec::Vec;

/// One geometric parameter fitted per leg.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fitted {
    /// Its symbol: `A` (the base joint's or the motor's centre), `p` (the platform joint's
    /// centre), `c` (the crank's length), `L` (the rod's), `o` (the encoder's offset).
    pub symbol: &'static str,
    /// The component, `x`, `y`, `z`, or empty for a scalar.
    pub component: &'static str,
    /// Where the leg's kernel geometry holds it.
    pub entry: usize,
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
        entry,
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
        entry,
        key,
        angle,
    }
}

const BASE: &[&str] = &["base"];
const PLATFORM: &[&str] = &["platform"];
const OFFSET: &[&str] = &["encoder_offset"];
const CRANK: &[&str] = &["crank", "length"];
const ROD: &[&str] = &["rod", "length"];

/// A U-P-S leg's (the Gough-Stewart platform's): `A_i`, `p_i`, `o_i`, entries of
/// [`UpsLeg::kernel_geometry`].
pub const UPS: [Fitted; 7] = {
    let [ax, ay, az] = point("A", 0, BASE);
    let [px, py, pz] = point("p", 6, PLATFORM);
    [ax, ay, az, px, py, pz, scalar("o", 9, OFFSET, false)]
};

/// A rotary hexapod's R-U-S leg: `A_i`, `p_i`, the crank's length `c_i`, the rod's `L_i` and the
/// encoder's offset `o_i` (rad), entries of [`RusLeg::kernel_geometry`].
pub const RUS: [Fitted; 9] = {
    let [ax, ay, az] = point("A", 0, BASE);
    let [px, py, pz] = point("p", 9, PLATFORM);
    [
        ax,
        ay,
        az,
        px,
        py,
        pz,
        scalar("c", 12, CRANK, false),
        scalar("L", 13, ROD, false),
        scalar("o", 15, OFFSET, true),
    ]
};

/// A Delta's arm: [`RUS`] without `p_i`, which only `p_i - A_i` reaches.
pub const DELTA_ARM: [Fitted; 6] = {
    let [ax, ay, az] = point("A", 0, BASE);
    [
        ax,
        ay,
        az,
        scalar("c", 12, CRANK, false),
        scalar("L", 13, ROD, false),
        scalar("o", 15, OFFSET, true),
    ]
};

impl UpsLeg {
    /// Sets entry `entry` of [`UpsLeg::kernel_geometry`] where it is a field of its own
    /// (`A_i`, `p_i`, `o_i`); returns whether it was.
    pub fn set_geometry(&mut self, entry: usize, value: f64) -> bool {
        match entry {
            0..=2 => self.base[entry] = value,
            6..=8 => self.platform[entry - 6] = value,
            9 => self.encoder_offset = value,
            _ => return false,
        }
        true
    }
}

impl RusLeg {
    /// Sets entry `entry` of [`RusLeg::kernel_geometry`] where it is a field of its own (`A_i`,
    /// `p_i`, the lengths, the offset; not the normalised axes nor the branch); returns whether
    /// it was.
    pub fn set_geometry(&mut self, entry: usize, value: f64) -> bool {
        match entry {
            0..=2 => self.base[entry] = value,
            9..=11 => self.platform[entry - 9] = value,
            12 => self.crank.length = value,
            13 => self.rod.length = value,
            15 => self.encoder_offset = value,
            _ => return false,
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
        let geometry: Option<Vec<f64>> = match self {
            Description::C5(_) => None,
            Description::GoughStewart(r) => r.legs.get(leg).map(|l| l.kernel_geometry().to_vec()),
            Description::RusHexapod(r) => r.legs.get(leg).map(|l| l.kernel_geometry().to_vec()),
            Description::Delta(r) => r.arms.get(leg).map(|l| l.kernel_geometry().to_vec()),
        };
        geometry.map_or_else(Vec::new, |g| fitted.iter().map(|f| g[f.entry]).collect())
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
        let set = |apply: &mut dyn FnMut(usize, f64) -> bool| {
            fitted
                .iter()
                .zip(values)
                .all(|(f, &value)| apply(f.entry, value))
        };
        match self {
            Description::C5(_) => false,
            Description::GoughStewart(r) => r
                .legs
                .get_mut(leg)
                .is_some_and(|l| set(&mut |e, v| l.set_geometry(e, v))),
            Description::RusHexapod(r) => r
                .legs
                .get_mut(leg)
                .is_some_and(|l| set(&mut |e, v| l.set_geometry(e, v))),
            Description::Delta(r) => r
                .arms
                .get_mut(leg)
                .is_some_and(|l| set(&mut |e, v| l.set_geometry(e, v))),
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
                assert_eq!(robot.fitted_values(leg), values);
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
        assert_eq!(RUS[7].name(2), "L2");
        assert!(RUS[8].angle && !UPS[6].angle);
    }
}
