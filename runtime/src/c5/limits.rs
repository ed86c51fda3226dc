//! The C5's limits: every margin of its stroke, plate-travel and tilt limits from a pose
//! ([`C5::limit_margins`], from the generated `limit_geometry` kernel), and the checks that
//! name the limit, the actuator and the value ([`C5::check_limits`], [`C5::check_speeds`],
//! [`C5::check_forces`]).

use crate::limits::{over, refuse_beyond, Limit};
use crate::{check_divisors, check_finite, finite, Error, Kernels, Pose, C5};

/// Every margin of the pose-bound limits: positive inside, negative outside, in the unit of
/// its limit; `+∞` where the robot sets no such limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitMargins {
    /// `min(Q_i1 - min, max - Q_i1)` (m), per actuator.
    pub stroke: [f64; 6],
    /// `travel - |offset|` (m), per actuator and plate axis.
    pub plate: [[f64; 2]; 6],
    /// `tilt_max - arccos(n_i · m_i)` (rad), per actuator.
    pub tilt: [f64; 6],
    /// What the margins are of: `Q_i1`, the plate offsets, the tilts (rad).
    pub values: LimitValues,
}

/// The quantities the limits bound, at a pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitValues {
    /// `Q_i1` (m).
    pub stroke: [f64; 6],
    /// Each ball's offset on its plate (m), two axes per actuator.
    pub plate: [[f64; 2]; 6],
    /// Each ball's tilt (rad), `arccos(n_i · m_i)`.
    pub tilt: [f64; 6],
}

impl LimitMargins {
    /// The smallest margin: which limit, which actuator (1..6), its margin and the value it is
    /// the margin of. `None` when the robot sets none of these limits.
    pub fn smallest(&self) -> Option<(Limit, usize, f64, f64)> {
        let mut best: Option<(Limit, usize, f64, f64)> = None;
        let mut consider = |limit, i: usize, margin: f64, value: f64| {
            if margin.is_finite() && best.is_none_or(|(_, _, m, _)| margin < m) {
                best = Some((limit, i + 1, margin, value));
            }
        };
        for i in 0..6 {
            consider(Limit::Stroke, i, self.stroke[i], self.values.stroke[i]);
            for a in 0..2 {
                consider(
                    Limit::PlateTravel,
                    i,
                    self.plate[i][a],
                    self.values.plate[i][a],
                );
            }
            consider(Limit::Tilt, i, self.tilt[i], self.values.tilt[i]);
        }
        best
    }
}

impl C5 {
    /// Every margin of the robot's stroke, plate-travel and tilt limits at `pose`, with the
    /// values they bound (one generated kernel, 73 mul, 4 div, 52 add and 3 sine-cosine pairs,
    /// then a subtraction per margin and six arc cosines).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn limit_margins(&self, pose: &Pose) -> Result<LimitMargins, Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (q, plate, cos, r) = self.kernels.limit_geometry_params(&x, &self.params);
        check_divisors(r)?;
        let (q, plate, cos) = (
            finite("q", q)?,
            finite("plate", plate)?,
            finite("tilt", cos)?,
        );
        let limits = &self.robot().limits;
        let values = LimitValues {
            stroke: q,
            plate: core::array::from_fn(|i| [plate[2 * i], plate[2 * i + 1]]),
            tilt: cos.map(|c| crate::math::acos(c.clamp(-1.0, 1.0))),
        };
        let stroke = core::array::from_fn(|i| match limits.stroke {
            Some(s) => (q[i] - s[i][0]).min(s[i][1] - q[i]),
            None => f64::INFINITY,
        });
        let plate = core::array::from_fn(|i| {
            core::array::from_fn(|a| match limits.plate_travel {
                Some(t) => t[a] - values.plate[i][a].abs(),
                None => f64::INFINITY,
            })
        });
        let tilt = core::array::from_fn(|i| match limits.tilt {
            Some(t) => t - values.tilt[i],
            None => f64::INFINITY,
        });
        Ok(LimitMargins {
            stroke,
            plate,
            tilt,
            values,
        })
    }

    /// Refuses a pose outside the robot's stroke, plate-travel or tilt limits.
    ///
    /// # Errors
    /// [`Error::Limit`] naming the limit with the smallest (negative) margin, its actuator and
    /// value; or a non-finite or singular pose.
    pub fn check_limits(&self, pose: &Pose) -> Result<(), Error> {
        refuse_beyond(self.limit_margins(pose)?.smallest())
    }

    /// Refuses actuator speeds `qd` (m/s, segment order) beyond the robot's speed limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the fastest actuator over the limit.
    pub fn check_speeds(&self, qd: &[f64; 6]) -> Result<(), Error> {
        over(Limit::Speed, self.robot().limits.speed, qd)
    }

    /// Refuses actuator forces `gamma` (N, segment order) beyond the robot's force limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the largest force over the limit.
    pub fn check_forces(&self, gamma: &[f64; 6]) -> Result<(), Error> {
        over(Limit::Force, self.robot().limits.force, gamma)
    }
}
