//! Rest-to-rest trajectories: the quintic (minimum-jerk) profile of Section 9.

use crate::types::{Acceleration, Pose, State, Twist};

/// `s(τ) = 10τ³ - 15τ⁴ + 6τ⁵` and its first two derivatives with respect to `τ`.
pub fn quintic(tau: f64) -> (f64, f64, f64) {
    let t = tau.clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    (
        t3 * (10.0 - 15.0 * t + 6.0 * t2),
        30.0 * t2 * (1.0 - 2.0 * t + t2),
        60.0 * t * (1.0 - 3.0 * t + 2.0 * t2),
    )
}

/// A straight-line, constant-orientation, rest-to-rest motion of the platform centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearMove {
    pub start: Pose,
    /// End point of the centre (m); the orientation stays that of `start`.
    pub end: [f64; 3],
    /// Duration (s).
    pub duration: f64,
}

impl LinearMove {
    /// Section 9's default: α=10°, β=15°, γ=20°, centre from the origin to (0.04, 0.03, 0.05) m
    /// in 1 s.
    pub fn section9() -> Self {
        LinearMove {
            start: Pose {
                alpha: 10f64.to_radians(),
                beta: 15f64.to_radians(),
                gamma: 20f64.to_radians(),
                center: [0.0; 3],
            },
            end: [0.04, 0.03, 0.05],
            duration: 1.0,
        }
    }

    /// The platform state at time `t` (clamped to the motion).
    pub fn state(&self, t: f64) -> State {
        let (s, ds, dds) = quintic(t / self.duration);
        let d = self.duration;
        let mut pose = self.start;
        let mut twist = Twist::default();
        let mut accel = Acceleration::default();
        for k in 0..3 {
            let delta = self.end[k] - self.start.center[k];
            pose.center[k] = self.start.center[k] + delta * s;
            twist.velocity[k] = delta * ds / d;
            accel.linear[k] = delta * dds / (d * d);
        }
        State { pose, twist, accel }
    }

    /// Sample times at `rate` Hz, both ends included.
    pub fn times(&self, rate: f64) -> Vec<f64> {
        let n = (self.duration * rate).round() as usize;
        (0..=n).map(|i| i as f64 / rate).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quintic_is_rest_to_rest() {
        assert_eq!(quintic(0.0), (0.0, 0.0, 0.0));
        let (s, v, a) = quintic(1.0);
        assert!((s - 1.0).abs() < 1e-15 && v.abs() < 1e-15 && a.abs() < 1e-12);
    }

    #[test]
    fn quintic_derivatives_match_finite_differences() {
        let h = 1e-6;
        for &t in &[0.1, 0.37, 0.5, 0.81] {
            let (s0, v0, a0) = quintic(t);
            let (sp, vp, _) = quintic(t + h);
            let (sm, vm, _) = quintic(t - h);
            assert!(
                ((sp - sm) / (2.0 * h) - v0).abs() < 1e-8,
                "velocity at {t} ({s0})"
            );
            assert!(
                ((vp - vm) / (2.0 * h) - a0).abs() < 1e-6,
                "acceleration at {t}"
            );
        }
    }
}
