//! The C5 joint parallel robot: a safe, typed API over the generated kernels, the matrix-form
//! reference, and the chapter's Section 9 study.
//!
//! [`C5`] checks its inputs and calls the generated straight-line kernels (`c5-generated`,
//! runtime-parameter variants, so any valid [`Robot`] works); [`reference`] is the chapter in
//! matrix form with `nalgebra`, kept independent so the two check each other.

pub mod error;
pub mod reference;
pub mod simulate;
pub mod trajectory;
pub mod types;

pub use c5_codegen::Robot;
pub use error::Error;
pub use types::{Acceleration, Pose, State, Twist};

use c5_generated::f64 as k;

/// Smallest accepted `|r11|`, `|r22|`, `|r33|` (the divisors of eq 16). Below it a pose is
/// [`Error::Singular`]: an actuator length would be off by more than `|Δ|/1e-9` per unit error.
pub const SINGULARITY_TOLERANCE: f64 = 1e-9;

/// A validated robot with its parameter vector, ready to evaluate kernels.
#[derive(Clone, Debug)]
pub struct C5 {
    robot: Robot,
    params: [f64; c5_generated::PARAMETERS],
}

/// Refuses a pose where a divisor of eq 16 (`[r11 r22 r33]`) is below the tolerance.
fn check_divisors(r: [f64; 3]) -> Result<(), Error> {
    for (term, value) in ["r11", "r22", "r33"].into_iter().zip(r) {
        if value.abs() < SINGULARITY_TOLERANCE {
            return Err(Error::Singular { term, value });
        }
    }
    Ok(())
}

fn check_finite(input: &'static str, v: &[f64]) -> Result<(), Error> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(Error::NonFinite { input, index }),
        None => Ok(()),
    }
}

/// Passes `value` on if every number in it is finite.
fn finite<T: AsRef<[f64]>>(output: &'static str, value: T) -> Result<T, Error> {
    if value.as_ref().iter().all(|x| x.is_finite()) {
        Ok(value)
    } else {
        Err(Error::NonFiniteResult { output })
    }
}

fn finite_matrix<const R: usize, const C: usize>(
    output: &'static str,
    m: [[f64; C]; R],
) -> Result<[[f64; C]; R], Error> {
    if m.iter().flatten().all(|x| x.is_finite()) {
        Ok(m)
    } else {
        Err(Error::NonFiniteResult { output })
    }
}

impl C5 {
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of [`Robot::validate`].
    pub fn new(robot: Robot) -> Result<Self, Error> {
        robot.validate().map_err(|e| Error::Robot(e.to_string()))?;
        let mut params = [0.0; c5_generated::PARAMETERS];
        params.copy_from_slice(&robot.flatten());
        Ok(C5 { robot, params })
    }

    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// A finite, non-singular pose; for the kernels that do not return the divisors of eq 16
    /// themselves.
    fn check_pose(&self, pose: &Pose) -> Result<[f64; 6], Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        check_divisors(k::singularity_terms(&x))?;
        Ok(x)
    }

    /// Finite inputs; the singularity check is left to the divisors the kernel returns.
    fn check_motion(&self, state: &State) -> Result<[[f64; 6]; 3], Error> {
        let x = state.pose.to_array();
        let v = state.twist.to_array();
        let a = state.accel.to_array();
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        check_finite("acceleration", &a)?;
        Ok([x, v, a])
    }

    /// Eqs 15, 16, 27: actuator lengths `Q_i1` and the vectors `P_i2`, segment order.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_kinematics(&self, pose: &Pose) -> Result<([f64; 6], [[f64; 3]; 6]), Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (q, p, r) = k::inverse_kinematics_params(&x, &self.params);
        check_divisors(r)?;
        Ok((finite("q", q)?, finite_matrix("p", p)?))
    }

    /// Eq 22: `J⁻¹` (row `i` = segment `i+1`, columns `ωx ωy ωz vx vy vz`).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        let x = self.check_pose(pose)?;
        finite_matrix("jinv", k::inverse_jacobian_pose_params(&x, &self.params))
    }

    /// Eq 40: `J = J1 Π1` (rows `ωx … vz`, column `i` = segment `i+1`).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        let x = self.check_pose(pose)?;
        finite_matrix("jacobian", k::jacobian_pose_params(&x, &self.params))
    }

    /// `Q̇_a = J⁻¹ V`, segment order.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn joint_velocities(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        let x = self.check_pose(pose)?;
        let v = twist.to_array();
        check_finite("twist", &v)?;
        finite("qd", k::joint_velocities_params(&x, &v, &self.params))
    }

    /// Eqs 43-48: actuator accelerations `Q̈_a` by projection, segment order.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn joint_accelerations(&self, state: &State) -> Result<[f64; 6], Error> {
        let [x, v, a] = self.check_motion(state)?;
        let (qdd, _, r) = k::joint_accelerations_params(&x, &v, &a, &self.params);
        check_divisors(r)?;
        finite("qdd", qdd)
    }

    /// Eq 60 with eq 62: actuator forces `Γ` (N), segment order.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn inverse_dynamics(&self, state: &State) -> Result<[f64; 6], Error> {
        let [x, v, a] = self.check_motion(state)?;
        let (gamma, r) = k::inverse_dynamics_params(&x, &v, &a, &self.params);
        check_divisors(r)?;
        finite("gamma", gamma)
    }

    /// Eq 39 in the chapter's setting: `Π1` from given vectors `P_i2` (segment order), rows
    /// `[ẇ_p1 u̇_p1 γ̇_p β̇_p α̇_p Q̇_11]`, column `i` for segment `i+1`.
    ///
    /// # Errors
    /// A non-finite input, or [`Error::Singular`] naming `y5 - y6`, `z1 - z2` or `x3 - x4` when
    /// its magnitude is below [`SINGULARITY_TOLERANCE`] (m).
    pub fn pi1(&self, p: &[[f64; 3]; 6]) -> Result<[[f64; 6]; 6], Error> {
        check_finite("p", p.as_flattened())?;
        let d = k::pi1_denominators(p);
        for (term, value) in ["y5 - y6", "z1 - z2", "x3 - x4"].into_iter().zip(d) {
            if value.abs() < SINGULARITY_TOLERANCE {
                return Err(Error::Singular { term, value });
            }
        }
        finite_matrix("pi1", k::pi1(p))
    }

    /// Everything `eval` and `simulate` report for one state, in one call.
    ///
    /// Every public method checks its inputs (finite) and the pose (not singular, from the
    /// divisors of eq 16 that the kernels return, or from `singularity_terms` for the kernels
    /// that never divide by them) and its outputs (finite), so no NaN or infinity leaves the API
    /// silently.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn evaluate(&self, state: &State) -> Result<Evaluation, Error> {
        let [x, v, a] = self.check_motion(state)?;
        let p = &self.params;
        let (q, _, r) = k::inverse_kinematics_params(&x, p);
        check_divisors(r)?;
        Ok(Evaluation {
            q: finite("q", q)?,
            qd: finite("qd", k::joint_velocities_params(&x, &v, p))?,
            qdd: finite("qdd", k::joint_accelerations_params(&x, &v, &a, p).0)?,
            gamma: finite("gamma", k::inverse_dynamics_params(&x, &v, &a, p).0)?,
            jinv: finite_matrix("jinv", k::inverse_jacobian_pose_params(&x, p))?,
            jacobian: finite_matrix("jacobian", k::jacobian_pose_params(&x, p))?,
        })
    }
}

/// The kinematic and dynamic quantities of one platform state, segment order.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Evaluation {
    /// `Q_i1` (m), eq 16.
    pub q: [f64; 6],
    /// `Q̇_i1` (m/s), `J⁻¹ V`.
    pub qd: [f64; 6],
    /// `Q̈_i1` (m/s²), eqs 43-48.
    pub qdd: [f64; 6],
    /// `Γ_i` (N), eq 60/62.
    pub gamma: [f64; 6],
    /// `J⁻¹`, row `i` = segment `i+1`.
    pub jinv: [[f64; 6]; 6],
    /// `J`, column `i` = segment `i+1`.
    pub jacobian: [[f64; 6]; 6],
}
