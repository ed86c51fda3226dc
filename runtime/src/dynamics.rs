//! The platform as a simulated body: its state, integrated through the forward dynamics.
//!
//! The orientation is kept as a unit quaternion and turned into the RPY angles of eq 15 only to
//! call the kernels, so integrating it neither drifts nor meets the angles' singularities.

use crate::math::{asin, atan2, sqrt};
use crate::types::{Acceleration, Pose, State, Twist};
use crate::{Error, Mechanism};
use alloc::vec;
use alloc::vec::Vec;

/// A 3×3 matrix, rows first.
pub type Matrix3 = [[f64; 3]; 3];

/// `R = Rx(α) Ry(β) Rz(γ)` (eq 15).
pub fn rotation(pose: &Pose) -> Matrix3 {
    use crate::math::sin_cos;
    let (sa, ca) = sin_cos(pose.alpha);
    let (sb, cb) = sin_cos(pose.beta);
    let (sg, cg) = sin_cos(pose.gamma);
    [
        [cb * cg, -cb * sg, sb],
        [sg * ca + cg * sb * sa, ca * cg - sa * sb * sg, -cb * sa],
        [sg * sa - cg * sb * ca, sa * cg + ca * sb * sg, cb * ca],
    ]
}

/// The RPY angles `[α β γ]` of a rotation (eq 15 inverted, `|β| ≤ π/2`).
pub fn rpy(r: &Matrix3) -> [f64; 3] {
    [
        atan2(-r[1][2], r[2][2]),
        asin(r[0][2].clamp(-1.0, 1.0)),
        atan2(-r[0][1], r[0][0]),
    ]
}

/// `exp(ṽ)`: the rotation by `|v|` about `v` (Rodrigues).
pub fn exp_rotation(v: [f64; 3]) -> Matrix3 {
    let angle = sqrt(v.iter().map(|x| x * x).sum());
    if angle == 0.0 {
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    }
    let k = v.map(|x| x / angle);
    let (s, c) = crate::math::sin_cos(angle);
    core::array::from_fn(|i| {
        core::array::from_fn(|j| {
            let cross = match (i, j) {
                (0, 1) => -k[2],
                (0, 2) => k[1],
                (1, 0) => k[2],
                (1, 2) => -k[0],
                (2, 0) => -k[1],
                (2, 1) => k[0],
                _ => 0.0,
            };
            let identity = if i == j { 1.0 } else { 0.0 };
            c * identity + s * cross + (1.0 - c) * k[i] * k[j]
        })
    })
}

/// `a b` for 3×3 matrices.
pub fn compose(a: &Matrix3, b: &Matrix3) -> Matrix3 {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// A unit quaternion `[w, x, y, z]` as a rotation matrix.
fn quaternion_to_matrix(q: &[f64; 4]) -> Matrix3 {
    let [w, x, y, z] = *q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// A rotation matrix as a unit quaternion (Shepperd's method, stable for every rotation).
fn matrix_to_quaternion(r: &Matrix3) -> [f64; 4] {
    let trace = r[0][0] + r[1][1] + r[2][2];
    let q = if trace > 0.0 {
        let s = 2.0 * sqrt(1.0 + trace);
        [
            0.25 * s,
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = 2.0 * sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]);
        [
            (r[2][1] - r[1][2]) / s,
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = 2.0 * sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]);
        [
            (r[0][2] - r[2][0]) / s,
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
        ]
    } else {
        let s = 2.0 * sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]);
        [
            (r[1][0] - r[0][1]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
        ]
    };
    normalized(q)
}

fn normalized(q: [f64; 4]) -> [f64; 4] {
    let n = sqrt(q.iter().map(|x| x * x).sum());
    q.map(|x| x / n)
}

/// The platform's state as an integrator holds it: centre, orientation, twist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantState {
    /// `C` (m), base frame.
    pub center: [f64; 3],
    /// The orientation as a unit quaternion `[w, x, y, z]`.
    pub orientation: [f64; 4],
    /// `(ω; v_C)`, base frame.
    pub twist: Twist,
}

impl PlantState {
    /// The state at `pose` with `twist`.
    pub fn new(pose: &Pose, twist: &Twist) -> Self {
        PlantState {
            center: pose.center,
            orientation: matrix_to_quaternion(&rotation(pose)),
            twist: *twist,
        }
    }

    /// `R`.
    pub fn rotation(&self) -> Matrix3 {
        quaternion_to_matrix(&self.orientation)
    }

    /// The pose, with the RPY angles of the orientation.
    pub fn pose(&self) -> Pose {
        let [alpha, beta, gamma] = rpy(&self.rotation());
        Pose {
            alpha,
            beta,
            gamma,
            center: self.center,
        }
    }

    /// The time derivative of the state under `accel`, as a state-shaped increment:
    /// `(v_C, ½ (0, ω) ⊗ q, (ω̇; a_C))`.
    fn rate(&self, accel: &Acceleration) -> [f64; 13] {
        let [w, x, y, z] = self.orientation;
        let [p, q, r] = self.twist.omega;
        let v = self.twist.velocity;
        [
            v[0],
            v[1],
            v[2],
            0.5 * (-p * x - q * y - r * z),
            0.5 * (p * w + q * z - r * y),
            0.5 * (q * w + r * x - p * z),
            0.5 * (r * w + p * y - q * x),
            accel.omega_dot[0],
            accel.omega_dot[1],
            accel.omega_dot[2],
            accel.linear[0],
            accel.linear[1],
            accel.linear[2],
        ]
    }

    fn to_array(self) -> [f64; 13] {
        let c = self.center;
        let q = self.orientation;
        let t = self.twist.to_array();
        [
            c[0], c[1], c[2], q[0], q[1], q[2], q[3], t[0], t[1], t[2], t[3], t[4], t[5],
        ]
    }

    fn from_array(a: &[f64; 13]) -> Self {
        PlantState {
            center: [a[0], a[1], a[2]],
            orientation: normalized([a[3], a[4], a[5], a[6]]),
            twist: Twist {
                omega: [a[7], a[8], a[9]],
                velocity: [a[10], a[11], a[12]],
            },
        }
    }

    /// As a [`State`] with `accel`.
    pub fn with_acceleration(&self, accel: Acceleration) -> State {
        State {
            pose: self.pose(),
            twist: self.twist,
            accel,
        }
    }
}

/// One classical Runge-Kutta step from time `t` to `t + dt`, the plant's motion given by
/// `plant`'s forward dynamics under the actuator forces `forces(t, state)` (one per actuator),
/// evaluated at every stage: a controller running in continuous time. For a sampled controller
/// (a zero-order hold), return the same forces whatever the stage. The forward dynamics is in
/// the platform's coordinates ([`Mechanism::coordinates_of`]), so any freedom steps alike; a
/// platform that only translates keeps its orientation: its state's quaternion stays the
/// identity.
///
/// # Errors
/// The first error of `forces`, or of [`Mechanism::forward_dynamics`] (a singular pose or a
/// non-finite result on the way).
pub fn rk4_step<M: Mechanism + ?Sized>(
    plant: &M,
    state: &PlantState,
    t: f64,
    dt: f64,
    mut forces: impl FnMut(f64, &PlantState) -> Result<Vec<f64>, Error>,
) -> Result<PlantState, Error> {
    rk4_step_by(state, t, dt, |time, s| {
        let gamma = forces(time, s)?;
        acceleration_of(plant, s, &gamma)
    })
}

/// `plant`'s forward dynamics at `state` under the actuator forces `gamma`.
///
/// # Errors
/// As [`Mechanism::forward_dynamics`]; a state that turns a platform that only translates.
pub fn acceleration_of<M: Mechanism + ?Sized>(
    plant: &M,
    state: &PlantState,
    gamma: &[f64],
) -> Result<Acceleration, Error> {
    let [x, v, _] = plant.coordinates_of(&state.with_acceleration(Acceleration::default()))?;
    let mut a = vec![0.0; x.len()];
    plant.forward_dynamics(&x, &v, gamma, &mut a)?;
    Ok(plant.state_of([&x, &v, &a])?.accel)
}

/// One classical Runge-Kutta step under the platform's acceleration `accel(t, state)`.
fn rk4_step_by(
    state: &PlantState,
    t: f64,
    dt: f64,
    mut accel: impl FnMut(f64, &PlantState) -> Result<Acceleration, Error>,
) -> Result<PlantState, Error> {
    let mut rate =
        |time: f64, s: &PlantState| -> Result<[f64; 13], Error> { Ok(s.rate(&accel(time, s)?)) };
    let y0 = state.to_array();
    let along = |k: &[f64; 13], h: f64| {
        let y: [f64; 13] = core::array::from_fn(|i| y0[i] + h * k[i]);
        PlantState::from_array(&y)
    };
    let k1 = rate(t, state)?;
    let k2 = rate(t + 0.5 * dt, &along(&k1, 0.5 * dt))?;
    let k3 = rate(t + 0.5 * dt, &along(&k2, 0.5 * dt))?;
    let k4 = rate(t + dt, &along(&k3, dt))?;
    let y: [f64; 13] =
        core::array::from_fn(|i| y0[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    Ok(PlantState::from_array(&y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_round_trips_through_quaternions_and_rpy() {
        for angles in [
            [0.1, -0.2, 0.3],
            [1.2, 0.4, -2.5],
            [-3.0, 1.4, 3.1],
            [0.0; 3],
        ] {
            let pose = Pose {
                alpha: angles[0],
                beta: angles[1],
                gamma: angles[2],
                center: [0.0; 3],
            };
            let state = PlantState::new(&pose, &Twist::default());
            let back = state.pose();
            assert!(
                (back.alpha - pose.alpha).abs() < 1e-12
                    && (back.beta - pose.beta).abs() < 1e-12
                    && (back.gamma - pose.gamma).abs() < 1e-12,
                "{angles:?} → {back:?}"
            );
        }
    }
}
