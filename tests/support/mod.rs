//! Shared helpers of the integration tests: seeded random states and tolerant comparisons.
#![allow(dead_code)]

use c5_runtime::reference::{self as r, consistent as rc};
use c5_runtime::{Acceleration, Pose, Robot, State, Twist};
use nalgebra::{Matrix3, Vector3};
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
    // A physical inertia: `I = tr(Σ) 1 - Σ` for a random second moment of mass
    // `Σ = A Aᵀ + 0.1·1` (positive definite), so every triangle inequality holds.
    let spd = |r: &mut ChaCha8Rng, scale: f64| {
        let a: [[f64; 3]; 3] = std::array::from_fn(|_| uniform(r, 1.0));
        let sigma: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3).map(|k| a[i][k] * a[j][k]).sum::<f64>() + if i == j { 0.1 } else { 0.0 }
            })
        });
        let trace = sigma[0][0] + sigma[1][1] + sigma[2][2];
        std::array::from_fn(|i| {
            std::array::from_fn(|j| scale * (if i == j { trace } else { 0.0 } - sigma[i][j]))
        })
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

/// Kinetic and potential energy of the consistent mechanism, written from the bodies' masses,
/// velocities and positions: the platform (centre of mass `C + R c`), the rods (rigid,
/// translating with the ball at `Q̇_i n_i`: every point of a rod rises as `B_i` does) and the
/// bodies 2 (turning with the platform, centre of mass `B_i + R c_i`, velocity
/// `Q̇_i n_i + ω × R c_i`). `Q̇` is `J⁻¹ V`, which `tests/suite/consistent_model.rs` holds to the
/// derivative of eq 16.
pub fn consistent_energy(robot: &Robot, s: &State) -> (f64, f64) {
    let l = robot.half_spacing;
    let rot = r::rotation(&s.pose);
    let g = Vector3::from(robot.gravity);
    let w = Vector3::from(s.twist.omega);
    let v = Vector3::from(s.twist.velocity);
    let c = Vector3::from(s.pose.center);
    let q = rc::lengths(l, &s.pose);
    let qd = rc::joint_velocities(l, &s.pose, &s.twist);
    let spin = |inertia: &[[f64; 3]; 3]| {
        let i = rot * Matrix3::from(*inertia).transpose() * rot.transpose();
        0.5 * w.dot(&(i * w))
    };
    let p = &robot.platform;
    let s_p = rot * Vector3::from(p.com);
    let mut kinetic = 0.5 * p.mass * (v + w.cross(&s_p)).norm_squared() + spin(&p.inertia);
    let mut potential = -p.mass * g.dot(&(c + s_p));
    for i in 0..6 {
        let seg = &robot.segments[i];
        let n = r::axis(i);
        let b = r::anchor(l, i) + q[i] * n;
        let s2 = rot * Vector3::from(seg.joint.com);
        kinetic += 0.5 * seg.rod.mass * qd[i] * qd[i]
            + 0.5 * seg.joint.mass * (qd[i] * n + w.cross(&s2)).norm_squared()
            + spin(&seg.joint.inertia);
        potential -= seg.rod.mass * g.dot(&b) + seg.joint.mass * g.dot(&(b + s2));
    }
    (kinetic, potential)
}
