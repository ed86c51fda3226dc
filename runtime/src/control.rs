//! Computed-torque control of the platform: the inverse dynamics at work in a controller.

use crate::dynamics::{rotation, Matrix3, PlantState};
use crate::math::sqrt;
use crate::types::{Acceleration, State};
use crate::{Error, Mechanism};
use alloc::vec;
use alloc::vec::Vec;

/// `log(R_d Rᵀ)`: the rotation (axis × angle, base frame) that takes `r` to `r_d`.
pub fn orientation_error(r_d: &Matrix3, r: &Matrix3) -> [f64; 3] {
    let e: Matrix3 = core::array::from_fn(|i| {
        core::array::from_fn(|j| (0..3).map(|k| r_d[i][k] * r[j][k]).sum())
    });
    // vee(E - Eᵀ) / 2 = sin θ · axis.
    let s = [
        0.5 * (e[2][1] - e[1][2]),
        0.5 * (e[0][2] - e[2][0]),
        0.5 * (e[1][0] - e[0][1]),
    ];
    let sin = sqrt(s.iter().map(|x| x * x).sum());
    let cos = 0.5 * (e[0][0] + e[1][1] + e[2][2] - 1.0);
    let angle = crate::math::atan2(sin, cos);
    // θ / sin θ → 1 as θ → 0.
    let scale = if sin < 1e-12 { 1.0 } else { angle / sin };
    s.map(|x| x * scale)
}

/// Computed-torque control: `Γ = ID(x, v, a_d + Kp e + Kd ė)`, the inverse dynamics of the
/// controller's robot at the measured state, with the desired acceleration corrected by a PD
/// law on the pose error (orientation error `log(R_d Rᵀ)`). With an exact model the error obeys
/// `ë + Kd ė + Kp e = 0`; `Kd = 2 √Kp` makes it critically damped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComputedTorque {
    /// `Kp` (1/s²).
    pub kp: f64,
    /// `Kd` (1/s).
    pub kd: f64,
    /// `|Γ_i|` at most this (N); `None` for no limit.
    pub force_limit: Option<f64>,
}

impl ComputedTorque {
    /// Critically damped gains with the error's time constant `1/λ`: `Kp = λ²`, `Kd = 2λ`.
    pub fn critically_damped(lambda: f64) -> Self {
        ComputedTorque {
            kp: lambda * lambda,
            kd: 2.0 * lambda,
            force_limit: None,
        }
    }

    /// The acceleration the law asks for at the measured `actual` state, tracking `desired`.
    pub fn commanded_acceleration(&self, desired: &State, actual: &PlantState) -> Acceleration {
        let e_r = orientation_error(&rotation(&desired.pose), &actual.rotation());
        let (wd, w) = (desired.twist.omega, actual.twist.omega);
        let (vd, v) = (desired.twist.velocity, actual.twist.velocity);
        let (cd, c) = (desired.pose.center, actual.center);
        Acceleration {
            omega_dot: core::array::from_fn(|k| {
                desired.accel.omega_dot[k] + self.kp * e_r[k] + self.kd * (wd[k] - w[k])
            }),
            linear: core::array::from_fn(|k| {
                desired.accel.linear[k] + self.kp * (cd[k] - c[k]) + self.kd * (vd[k] - v[k])
            }),
        }
    }

    /// Computed torque in joint space: `Γ = M_q (q̈_d + Kp e_q + Kd ė_q) + c_q`, the joint-space
    /// inverse dynamics of the controller's robot at the measured actuator positions `q` and
    /// rates `qd`, tracking the desired actuator motion `[q_d, q̇_d, q̈_d]`; within the force
    /// limit. With an exact model each actuator's error obeys `ë + Kd ė + Kp e = 0`.
    ///
    /// # Errors
    /// As [`Mechanism::inverse_dynamics_joint`] of the controller's robot.
    pub fn joint_forces(
        &self,
        controller: &dyn Mechanism,
        desired: [&[f64]; 3],
        q: &[f64],
        qd: &[f64],
    ) -> Result<Vec<f64>, Error> {
        let qdd = self.joint_acceleration(desired, q, qd);
        let mut gamma = vec![0.0; q.len()];
        controller.inverse_dynamics_joint([q, qd, &qdd], None, &mut gamma)?;
        Ok(self.limited(gamma))
    }

    /// The actuator accelerations the joint-space law asks for: `q̈_d + Kp e_q + Kd ė_q`.
    pub fn joint_acceleration(&self, desired: [&[f64]; 3], q: &[f64], qd: &[f64]) -> Vec<f64> {
        let [q_d, qd_d, qdd_d] = desired;
        (0..q.len())
            .map(|i| qdd_d[i] + self.kp * (q_d[i] - q[i]) + self.kd * (qd_d[i] - qd[i]))
            .collect()
    }

    fn limited(&self, gamma: Vec<f64>) -> Vec<f64> {
        match self.force_limit {
            Some(limit) => gamma.into_iter().map(|g| g.clamp(-limit, limit)).collect(),
            None => gamma,
        }
    }

    /// The actuator forces (N or N·m, one per actuator), within the force limit: the inverse
    /// dynamics in the controller's platform coordinates (a platform that only translates
    /// asks for no turn: its orientation error and angular rates are zero).
    ///
    /// # Errors
    /// As [`Mechanism::inverse_dynamics`] of the controller's robot.
    pub fn forces(
        &self,
        controller: &dyn Mechanism,
        desired: &State,
        actual: &PlantState,
    ) -> Result<Vec<f64>, Error> {
        let accel = self.commanded_acceleration(desired, actual);
        let [x, v, a] = controller.coordinates_of(&actual.with_acceleration(accel))?;
        let mut gamma = vec![0.0; x.len()];
        controller.inverse_dynamics(&x, &v, &a, &mut gamma)?;
        Ok(self.limited(gamma))
    }
}
