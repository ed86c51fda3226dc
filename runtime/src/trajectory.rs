//! Platform trajectories: the quintic rest-to-rest move of Section 9, finite Fourier series
//! (rotating, exciting motions), and the RPY kinematics that turn pose derivatives into the
//! twist and classical acceleration.

use crate::math::sin_cos;
use crate::types::{Acceleration, Pose, State, Twist};
use alloc::vec::Vec;

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

/// Sample times of `[0, duration]` at `rate` Hz: `k / rate` while inside, and the end itself
/// (so the last sample is the end of the motion whatever the rate).
///
/// # Errors
/// The number of samples it would take when it exceeds `max_samples`, or when `rate` or
/// `duration` is not a positive finite number (then `usize::MAX`).
pub fn sample_times(duration: f64, rate: f64, max_samples: usize) -> Result<Vec<f64>, usize> {
    if !(rate.is_finite() && rate > 0.0 && duration.is_finite() && duration > 0.0) {
        return Err(usize::MAX);
    }
    let span = duration * rate;
    // Truncation is `floor` for a positive number; the slack keeps 1000 × 1.0 at 1000.
    let whole = (span * (1.0 + 1e-12)) as usize;
    let total = whole.saturating_add(2);
    if total > max_samples || !span.is_finite() || span >= usize::MAX as f64 {
        return Err(total);
    }
    let mut t: Vec<f64> = (0..=whole).map(|k| k as f64 / rate).collect();
    match t.last_mut() {
        Some(last) if (duration - *last).abs() <= 1e-9 * duration => *last = duration,
        _ => t.push(duration),
    }
    Ok(t)
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
        let deg = core::f64::consts::PI / 180.0;
        LinearMove {
            start: Pose {
                alpha: 10.0 * deg,
                beta: 15.0 * deg,
                gamma: 20.0 * deg,
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

    /// Sample times at `rate` Hz, both ends included (see [`sample_times`]); empty for a rate
    /// that is not a positive number.
    pub fn times(&self, rate: f64) -> Vec<f64> {
        sample_times(self.duration, rate, usize::MAX).unwrap_or_default()
    }
}

/// `E(α, β)` with `ω = E [α̇ β̇ γ̇]` for `R = Rx(α) Ry(β) Rz(γ)`: the columns are `x`,
/// `Rx(α) y` and `Rx(α) Ry(β) z`.
fn rate_map(alpha: f64, beta: f64) -> [[f64; 3]; 3] {
    let (sa, ca) = sin_cos(alpha);
    let (sb, cb) = sin_cos(beta);
    [[1.0, 0.0, sb], [0.0, ca, -sa * cb], [0.0, sa, ca * cb]]
}

fn apply(m: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    core::array::from_fn(|i| (0..3).map(|j| m[i][j] * v[j]).sum())
}

/// `ω` (base frame) from the RPY angles `[α β γ]` and their rates:
/// `ω = α̇ x + β̇ Rx(α) y + γ̇ Rx(α) Ry(β) z`.
pub fn omega_from_rpy_rates(angles: [f64; 3], rates: [f64; 3]) -> [f64; 3] {
    apply(&rate_map(angles[0], angles[1]), &rates)
}

/// `ω̇` from the RPY angles and their first and second derivatives: `E θ̈ + Ė θ̇`, with
/// `Ė = ∂E/∂α α̇ + ∂E/∂β β̇`.
pub fn omega_dot_from_rpy(angles: [f64; 3], rates: [f64; 3], accels: [f64; 3]) -> [f64; 3] {
    let (sa, ca) = sin_cos(angles[0]);
    let (sb, cb) = sin_cos(angles[1]);
    let (ad, bd) = (rates[0], rates[1]);
    let e_dot = [
        [0.0, 0.0, cb * bd],
        [0.0, -sa * ad, -ca * cb * ad + sa * sb * bd],
        [0.0, ca * ad, -sa * cb * ad - ca * sb * bd],
    ];
    let a = apply(&rate_map(angles[0], angles[1]), &accels);
    let b = apply(&e_dot, &rates);
    core::array::from_fn(|i| a[i] + b[i])
}

/// The platform state from the pose `X = [α β γ xc yc zc]` and its first two time
/// derivatives.
pub fn state_from_pose_derivatives(x: [f64; 6], xd: [f64; 6], xdd: [f64; 6]) -> State {
    let angles = [x[0], x[1], x[2]];
    let rates = [xd[0], xd[1], xd[2]];
    State {
        pose: Pose::from_array(x),
        twist: Twist {
            omega: omega_from_rpy_rates(angles, rates),
            velocity: [xd[3], xd[4], xd[5]],
        },
        accel: Acceleration {
            omega_dot: omega_dot_from_rpy(angles, rates, [xdd[0], xdd[1], xdd[2]]),
            linear: [xdd[3], xdd[4], xdd[5]],
        },
    }
}

/// A finite Fourier series in every pose coordinate, periodic in `period`:
/// `X(t) = X₀ + Σ_l a_l sin(l ω_f t) + b_l (cos(l ω_f t) - 1)`, `ω_f = 2π / period`, so
/// `X(0) = X₀`. Smooth, rotating, and with exact derivatives: the excitation trajectories of
/// identification, and rotating test motions.
#[derive(Clone, Debug, PartialEq)]
pub struct Fourier {
    /// `X₀`, the pose at `t = 0`.
    pub offset: [f64; 6],
    /// `T` (s).
    pub period: f64,
    /// `a_l`, harmonic `l = 1, 2, ...` per coordinate.
    pub sine: Vec<[f64; 6]>,
    /// `b_l`.
    pub cosine: Vec<[f64; 6]>,
}

impl Fourier {
    /// The pose and its first two time derivatives at `t`.
    pub fn pose_derivatives(&self, t: f64) -> ([f64; 6], [f64; 6], [f64; 6]) {
        let wf = 2.0 * core::f64::consts::PI / self.period;
        let (mut x, mut xd, mut xdd) = (self.offset, [0.0; 6], [0.0; 6]);
        let harmonics = self.sine.len().max(self.cosine.len());
        for l in 0..harmonics {
            let w = wf * (l + 1) as f64;
            let (s, c) = sin_cos(w * t);
            let a = self.sine.get(l).copied().unwrap_or([0.0; 6]);
            let b = self.cosine.get(l).copied().unwrap_or([0.0; 6]);
            for k in 0..6 {
                x[k] += a[k] * s + b[k] * (c - 1.0);
                xd[k] += w * (a[k] * c - b[k] * s);
                xdd[k] -= w * w * (a[k] * s + b[k] * c);
            }
        }
        (x, xd, xdd)
    }

    /// The platform state at `t`.
    pub fn state(&self, t: f64) -> State {
        let (x, xd, xdd) = self.pose_derivatives(t);
        state_from_pose_derivatives(x, xd, xdd)
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

    #[test]
    fn sampling_ends_on_the_end_whatever_the_rate() {
        let t = sample_times(1.0, 1000.0, usize::MAX).unwrap();
        assert_eq!((t.len(), t[1000]), (1001, 1.0));
        let t = sample_times(1.0, 1.5, usize::MAX).unwrap();
        assert_eq!(t, [0.0, 1.0 / 1.5, 1.0]);
        assert!(t.iter().all(|&x| x <= 1.0));
        assert_eq!(sample_times(1.0, 1e9, 10_000_000), Err(1_000_000_002));
        assert!(sample_times(1.0, f64::NAN, 10).is_err());
        assert!(sample_times(1.0, -3.0, 10).is_err());
    }

    #[test]
    fn fourier_derivatives_match_finite_differences() {
        let f = Fourier {
            offset: [0.1, -0.2, 0.3, 0.01, 0.02, -0.03],
            period: 2.0,
            sine: alloc::vec![[0.1, 0.05, -0.2, 0.02, -0.01, 0.03], [0.03; 6]],
            cosine: alloc::vec![[-0.05, 0.1, 0.02, 0.01, 0.02, -0.02]],
        };
        assert_eq!(f.pose_derivatives(0.0).0, f.offset);
        let h = 1e-5;
        for &t in &[0.0, 0.3, 1.1] {
            let (_, xd, xdd) = f.pose_derivatives(t);
            let (xp, xdp, _) = f.pose_derivatives(t + h);
            let (xm, xdm, _) = f.pose_derivatives(t - h);
            for k in 0..6 {
                assert!(((xp[k] - xm[k]) / (2.0 * h) - xd[k]).abs() < 1e-8);
                assert!(((xdp[k] - xdm[k]) / (2.0 * h) - xdd[k]).abs() < 1e-7);
            }
        }
    }
}
