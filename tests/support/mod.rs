//! Shared helpers of the integration tests: seeded random states and tolerant comparisons.
#![allow(dead_code)]

use c5_runtime::{Acceleration, Pose, Robot, State, Twist};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn uniform<const N: usize>(r: &mut ChaCha8Rng, bound: f64) -> [f64; N] {
    std::array::from_fn(|_| r.gen_range(-bound..=bound))
}

/// A random state: |α|,|β|,|γ| ≤ 0.5 rad, |c| ≤ 0.08 m, |ω| ≤ 1 rad/s, |v| ≤ 0.5 m/s,
/// |ω̇| ≤ 5 rad/s², |a| ≤ 2 m/s² per component.
pub fn random_state(r: &mut ChaCha8Rng) -> State {
    let angles: [f64; 3] = uniform(r, 0.5);
    State {
        pose: Pose {
            alpha: angles[0],
            beta: angles[1],
            gamma: angles[2],
            center: uniform(r, 0.08),
        },
        twist: Twist {
            omega: uniform(r, 1.0),
            velocity: uniform(r, 0.5),
        },
        accel: Acceleration {
            omega_dot: uniform(r, 5.0),
            linear: uniform(r, 2.0),
        },
    }
}

/// A valid robot far from the default: other spacing, masses, inertias (full, rotated),
/// centres of mass off their reference points, tilted gravity.
pub fn random_robot(r: &mut ChaCha8Rng) -> Robot {
    let mut robot = Robot {
        half_spacing: r.gen_range(0.15..0.3),
        gravity: [r.gen_range(-1.0..1.0), r.gen_range(-1.0..1.0), -9.81],
        ..Robot::default()
    };
    let spd = |r: &mut ChaCha8Rng, scale: f64| {
        let a: [[f64; 3]; 3] = std::array::from_fn(|_| uniform(r, 1.0));
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = scale
                    * ((0..3).map(|k| a[i][k] * a[j][k]).sum::<f64>()
                        + if i == j { 0.5 } else { 0.0 });
            }
        }
        m
    };
    robot.platform.mass = r.gen_range(5.0..15.0);
    robot.platform.com = uniform(r, 0.05);
    robot.platform.inertia = spd(r, 0.1);
    for s in &mut robot.segments {
        s.rod.mass = r.gen_range(1.0..3.0);
        s.joint.mass = r.gen_range(1.0..2.5);
        s.joint.com = uniform(r, 0.02);
        s.joint.inertia = spd(r, 0.005);
    }
    robot.validate().expect("random robot is valid");
    robot
}

/// Largest absolute difference, relative to the largest magnitude of `want` (at least `floor`).
pub fn rel_err(got: &[f64], want: &[f64], floor: f64) -> f64 {
    assert_eq!(got.len(), want.len());
    let scale = want.iter().fold(floor, |m, w| m.max(w.abs()));
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0, f64::max)
        / scale
}

pub fn flat<const R: usize, const C: usize>(m: &[[f64; C]; R]) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

pub fn from_na(m: &nalgebra::Matrix6<f64>) -> [[f64; 6]; 6] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}
