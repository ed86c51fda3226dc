//! What a real C5 robot measures and how a controller reads it: encoders that quantize the
//! actuator positions, and an estimator of the actuators' rates from those counts.

use crate::{check_finite, Error};
use alloc::vec::Vec;

/// Incremental encoders on the ball screws: each actuator position is read as a whole number
/// of counts of `resolution` metres (rounded to the nearest), or exactly when `None`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Encoders {
    /// Metres per count.
    pub resolution: Option<f64>,
}

impl Encoders {
    /// Encoders of `resolution` metres per count.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or a non-positive resolution ([`Error::Invalid`]).
    pub fn new(resolution: f64) -> Result<Self, Error> {
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(Error::Invalid {
                what: "encoder resolution",
                rule: "must be a positive number of metres per count",
            });
        }
        Ok(Encoders {
            resolution: Some(resolution),
        })
    }

    /// The positions the encoders report for the actuator positions `q`.
    pub fn read<const N: usize>(&self, q: &[f64; N]) -> [f64; N] {
        q.map(|x| self.reading(x))
    }

    /// The position one encoder reports for the actuator position `x`.
    pub fn reading(&self, x: f64) -> f64 {
        match self.resolution {
            Some(m) => crate::math::round(x / m) * m,
            None => x,
        }
    }
}

/// The actuators' rates from sampled, quantized positions: per actuator, the steady-state
/// Kalman filter of a double integrator driven by a known acceleration (the controller's own
/// command), an α-β filter whose prediction is `x + T v + ½ T² a`, `v + T a`, with both poles
/// of its error dynamics at `p = exp(-ω T)` (critically damped, `ω` the bandwidth):
/// `α = 1 - p²`, `β = (1 - p)²`.
///
/// Why this one: a raw difference of counts turns each count of quantization into a rate
/// spike of `resolution / T` (0.1 mm/s for 1e-7 m at 1 kHz); the filter averages them over
/// about `1/ω`, its rate noise about `resolution · ω / √12`. A plain α-β filter (no
/// acceleration input) tracks a constant rate but lags an accelerating one by
/// `a T (α - β/2) / β` (1.8 mm/s at 0.3 m/s², 50 Hz, 1 kHz), which a controller's damping
/// turns into a tracking error of `Kd · lag / Kp` (0.2 mm here); fed the acceleration the
/// controller commands, it lags only by what the plant does differently from the command.
#[derive(Clone, Debug, PartialEq)]
pub struct RateEstimator {
    alpha: f64,
    beta: f64,
    period: f64,
    /// One per actuator, as many as the first measurement or [`RateEstimator::reset`] gives.
    position: Vec<f64>,
    rate: Vec<f64>,
    started: bool,
}

impl RateEstimator {
    /// An estimator of bandwidth `bandwidth_hz` sampled every `period` seconds.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a non-positive or non-finite bandwidth or period.
    pub fn new(bandwidth_hz: f64, period: f64) -> Result<Self, Error> {
        if !(bandwidth_hz.is_finite() && bandwidth_hz > 0.0 && period.is_finite() && period > 0.0) {
            return Err(Error::Invalid {
                what: "rate estimator",
                rule: "its bandwidth and sampling period must be positive numbers",
            });
        }
        let p = crate::math::exp(-2.0 * core::f64::consts::PI * bandwidth_hz * period);
        Ok(RateEstimator {
            alpha: 1.0 - p * p,
            beta: (1.0 - p) * (1.0 - p),
            period,
            position: Vec::new(),
            rate: Vec::new(),
            started: false,
        })
    }

    /// Starts from a known state (else the first measurement, at rest): the positions and
    /// rates of as many actuators as every later measurement has.
    pub fn reset(&mut self, position: &[f64], rate: &[f64]) {
        self.position = position.to_vec();
        self.rate = rate.to_vec();
        self.started = true;
    }

    /// Takes one measurement, with the actuators' acceleration over the last period as far as
    /// it is known (the command; zeros when nothing is), and returns the estimated positions
    /// and rates.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite measurement or acceleration,
    /// [`Error::WrongLength`] for another number of actuators than the estimator's; the
    /// estimator keeps its state.
    pub fn update(
        &mut self,
        measured: &[f64],
        acceleration: &[f64],
    ) -> Result<(&[f64], &[f64]), Error> {
        check_finite("measured positions", measured)?;
        check_finite("acceleration", acceleration)?;
        if !self.started {
            self.reset(measured, &alloc::vec![0.0; measured.len()]);
            return Ok((&self.position, &self.rate));
        }
        let n = self.position.len();
        for (input, got) in [
            ("measured positions", measured),
            ("acceleration", acceleration),
        ] {
            if got.len() != n {
                return Err(Error::WrongLength {
                    input,
                    expected: n,
                    got: got.len(),
                });
            }
        }
        let t = self.period;
        for i in 0..n {
            let a = acceleration[i];
            let predicted = self.position[i] + t * self.rate[i] + 0.5 * t * t * a;
            let residual = measured[i] - predicted;
            self.position[i] = predicted + self.alpha * residual;
            self.rate[i] += t * a + self.beta / t * residual;
        }
        Ok((&self.position, &self.rate))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoders_round_to_the_nearest_count() {
        let e = Encoders::new(1e-3).unwrap();
        let q = e.read(&[0.00149, -0.0015001, 0.0, 1.0, 2.4996e-3, -7e-4]);
        let counts = q.map(|x| x / 1e-3);
        for (c, want) in counts.iter().zip([1.0, -2.0, 0.0, 1000.0, 2.0, -1.0]) {
            assert!((c - want).abs() < 1e-9, "{counts:?}");
        }
        assert_eq!(Encoders::default().read(&[0.123; 6]), [0.123; 6]);
        assert!(Encoders::new(0.0).is_err() && Encoders::new(f64::NAN).is_err());
    }

    /// The worst rate error after the start-up, tracking `q(t) = 0.001 + v t + ½ a t²`.
    fn worst_rate_error(rate: [f64; 6], accel: [f64; 6], told: bool) -> f64 {
        let dt = 1e-3;
        let mut est = RateEstimator::new(50.0, dt).unwrap();
        let enc = Encoders::new(1e-7).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..2000 {
            let t = k as f64 * dt;
            let q: [f64; 6] =
                core::array::from_fn(|i| 0.001 + rate[i] * t + 0.5 * accel[i] * t * t);
            let known = if told { accel } else { [0.0; 6] };
            let (_, qd) = est.update(&enc.read(&q), &known).unwrap();
            if k > 500 {
                for i in 0..6 {
                    worst = worst.max((qd[i] - (rate[i] + accel[i] * t)).abs());
                }
            }
        }
        worst
    }

    #[test]
    fn the_estimator_smooths_counts_and_follows_an_acceleration_it_is_told() {
        let rate = [0.01, -0.02, 0.0, 0.05, 0.001, -0.003];
        // A raw difference of counts is off by up to resolution / T = 1e-4 m/s.
        assert!(worst_rate_error(rate, [0.0; 6], false) < 1e-5);
        let accel = [0.3, -0.2, 0.1, 0.0, 0.25, -0.3];
        let lagging = worst_rate_error(rate, accel, false);
        let told = worst_rate_error(rate, accel, true);
        // The plain filter's lag: a T (α - β/2) / β ≈ 1.8e-3 m/s at 0.3 m/s².
        assert!((lagging - 1.78e-3).abs() < 1e-4, "{lagging}");
        assert!(told < 1e-5, "{told}");
        let mut est = RateEstimator::new(50.0, 1e-3).unwrap();
        est.reset(&[0.0; 6], &[0.0; 6]);
        let before = est.clone();
        assert!(est.update(&[f64::NAN; 6], &[0.0; 6]).is_err());
        assert!(est.update(&[0.0; 3], &[0.0; 3]).is_err());
        assert_eq!(est, before, "a refused measurement changes nothing");
    }
}
