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

/// A sampled trajectory read from a CSV file.
pub mod csv_input {
    use crate::types::{Acceleration, Pose, State, Twist};
    use nalgebra::{Matrix3, Vector3};
    use std::fmt;
    use std::path::Path;

    /// Why a trajectory file was refused.
    #[derive(Debug, Clone, PartialEq)]
    pub struct TrajectoryError {
        pub file: String,
        /// 1-based line of the file, when the problem has one.
        pub line: Option<usize>,
        pub message: String,
    }

    impl fmt::Display for TrajectoryError {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            match self.line {
                Some(l) => write!(f, "{}:{l}: {}", self.file, self.message),
                None => write!(f, "{}: {}", self.file, self.message),
            }
        }
    }

    impl std::error::Error for TrajectoryError {}

    const POSE: [&str; 7] = ["t", "alpha", "beta", "gamma", "xc", "yc", "zc"];
    const TWIST: [&str; 6] = ["wx", "wy", "wz", "vx", "vy", "vz"];
    const ACCEL: [&str; 6] = ["wdx", "wdy", "wdz", "ax", "ay", "az"];

    /// `ω` from RPY rates for `R = Rx(α) Ry(β) Rz(γ)`:
    /// `ω = α̇ x + β̇ Rx(α) y + γ̇ Rx(α) Ry(β) z`.
    fn omega_from_rates(pose: &Pose, rates: &Vector3<f64>) -> Vector3<f64> {
        let (sa, ca) = pose.alpha.sin_cos();
        let (sb, cb) = pose.beta.sin_cos();
        let e = Matrix3::new(1.0, 0.0, sb, 0.0, ca, -sa * cb, 0.0, sa, ca * cb);
        e * rates
    }

    /// Central differences inside, one-sided at the ends, for non-uniform times.
    fn derivative(t: &[f64], y: &[Vector3<f64>], k: usize) -> Vector3<f64> {
        let n = t.len();
        let (a, b) = match k {
            0 => (0, 1),
            _ if k == n - 1 => (n - 2, n - 1),
            _ => (k - 1, k + 1),
        };
        (y[b] - y[a]) / (t[b] - t[a])
    }

    /// Reads `t, alpha, beta, gamma, xc, yc, zc` and, optionally, the twist
    /// (`wx wy wz vx vy vz`) and classical acceleration (`wdx wdy wdz ax ay az`) columns.
    /// Missing derivatives come from finite differences of the samples (the twist's angular
    /// part through the RPY rates).
    ///
    /// # Errors
    /// A missing file or column, a malformed or non-finite number, fewer than two samples, or
    /// times that do not increase; the error names the file and line.
    pub fn read(path: &Path) -> Result<Vec<(f64, State)>, TrajectoryError> {
        let file = path.display().to_string();
        let err = |line: Option<usize>, message: String| TrajectoryError {
            file: file.clone(),
            line,
            message,
        };
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_path(path)
            .map_err(|e| err(None, e.to_string()))?;
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| err(Some(1), e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let column = |name: &str| header.iter().position(|h| h == name);
        let find = |names: &[&str]| -> Result<Option<Vec<usize>>, TrajectoryError> {
            let found: Vec<Option<usize>> = names.iter().map(|n| column(n)).collect();
            match (
                found.iter().all(Option::is_some),
                found.iter().any(Option::is_some),
            ) {
                (true, _) => Ok(Some(found.into_iter().flatten().collect())),
                (false, false) => Ok(None),
                (false, true) => {
                    let missing: Vec<&str> = names
                        .iter()
                        .zip(&found)
                        .filter(|(_, f)| f.is_none())
                        .map(|(n, _)| *n)
                        .collect();
                    Err(err(
                        Some(1),
                        format!(
                            "missing column(s) {} (these come together: {})",
                            missing.join(", "),
                            names.join(", ")
                        ),
                    ))
                }
            }
        };
        let pose_cols = find(&POSE)?
            .ok_or_else(|| err(Some(1), format!("missing column(s) {}", POSE.join(", "))))?;
        let twist_cols = find(&TWIST)?;
        let accel_cols = find(&ACCEL)?;
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for (n, record) in reader.records().enumerate() {
            let line = n + 2;
            let record = record.map_err(|e| err(Some(line), e.to_string()))?;
            let mut row = vec![0.0; header.len()];
            for (k, field) in record.iter().enumerate().take(header.len()) {
                let v: f64 = field.parse().map_err(|_| {
                    err(
                        Some(line),
                        format!("`{}` = {field:?} is not a number", header[k]),
                    )
                })?;
                if !v.is_finite() {
                    return Err(err(Some(line), format!("`{}` is not finite", header[k])));
                }
                row[k] = v;
            }
            if let Some(prev) = rows.last() {
                if row[pose_cols[0]] <= prev[pose_cols[0]] {
                    return Err(err(Some(line), "time must increase".to_string()));
                }
            }
            rows.push(row);
        }
        if rows.len() < 2 {
            return Err(err(
                None,
                "a trajectory needs at least two samples".to_string(),
            ));
        }
        let t: Vec<f64> = rows.iter().map(|r| r[pose_cols[0]]).collect();
        let poses: Vec<Pose> = rows
            .iter()
            .map(|r| Pose::from_array(std::array::from_fn(|k| r[pose_cols[k + 1]])))
            .collect();
        let pick = |r: &[f64], cols: &[usize], from: usize| {
            Vector3::new(r[cols[from]], r[cols[from + 1]], r[cols[from + 2]])
        };
        let (omega, velocity): (Vec<Vector3<f64>>, Vec<Vector3<f64>>) = match &twist_cols {
            Some(c) => rows.iter().map(|r| (pick(r, c, 0), pick(r, c, 3))).unzip(),
            None => {
                let angles: Vec<Vector3<f64>> = poses
                    .iter()
                    .map(|p| Vector3::new(p.alpha, p.beta, p.gamma))
                    .collect();
                let centers: Vec<Vector3<f64>> =
                    poses.iter().map(|p| Vector3::from(p.center)).collect();
                (0..rows.len())
                    .map(|k| {
                        let rates = derivative(&t, &angles, k);
                        (
                            omega_from_rates(&poses[k], &rates),
                            derivative(&t, &centers, k),
                        )
                    })
                    .unzip()
            }
        };
        let (omega_dot, linear): (Vec<Vector3<f64>>, Vec<Vector3<f64>>) = match &accel_cols {
            Some(c) => rows.iter().map(|r| (pick(r, c, 0), pick(r, c, 3))).unzip(),
            None => (0..rows.len())
                .map(|k| (derivative(&t, &omega, k), derivative(&t, &velocity, k)))
                .unzip(),
        };
        Ok((0..rows.len())
            .map(|k| {
                let state = State {
                    pose: poses[k],
                    twist: Twist {
                        omega: omega[k].into(),
                        velocity: velocity[k].into(),
                    },
                    accel: Acceleration {
                        omega_dot: omega_dot[k].into(),
                        linear: linear[k].into(),
                    },
                };
                (t[k], state)
            })
            .collect())
    }
}
