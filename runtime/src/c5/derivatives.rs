//! The C5's exact derivatives (feature `derivatives`): its generated derivative kernels of both
//! models behind checked calls, with the bounds of eq 16's singularities.

use super::{check_forward, check_forward_dynamics, check_joint_derivatives};
use crate::derivatives::{
    ForwardDynamicsDerivatives, InverseDynamicsDerivatives, JointDynamicsDerivatives,
};
use crate::{check_divisors, finite, finite_matrix};
use crate::{Error, Kernels, Pose, State, Twist, C5};

impl C5 {
    /// The inverse dynamics and its exact Jacobians with respect to the pose, the twist and the
    /// acceleration, in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn inverse_dynamics_derivatives(
        &self,
        state: &State,
    ) -> Result<InverseDynamicsDerivatives<6>, Error> {
        let [x, v, a] = Self::checked_motion(state)?;
        let (gamma, d_pose, d_twist, d_accel, r) = self
            .kernels
            .inverse_dynamics_derivatives_params(&x, &v, &a, &self.params);
        check_divisors(r)?;
        InverseDynamicsDerivatives::checked((gamma, d_pose, d_twist, d_accel))
    }

    /// The forward dynamics and its exact Jacobians with respect to the pose, the twist and the
    /// actuator forces `gamma` (N, segment order), in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    pub fn forward_dynamics_derivatives(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<ForwardDynamicsDerivatives<6>, Error> {
        let [x, v] = C5::checked_forward(pose, twist, gamma)?;
        let (a, d_pose, d_twist, d_gamma, r) =
            self.kernels
                .forward_dynamics_derivatives_params(&x, &v, gamma, &self.params);
        check_forward_dynamics(self.forward_dynamics_tolerance(), r)?;
        ForwardDynamicsDerivatives::checked((a, d_pose, d_twist, d_gamma))
    }

    /// The inverse dynamics from the actuators' positions, rates and accelerations and its
    /// exact Jacobians with respect to each, in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, [`Error::ForwardSingular`], a singular pose, a non-finite result, or
    /// [`Error::IllConditioned`] at a pose nearer eq 16's singularities than
    /// [`crate::JOINT_STATE_TOLERANCE`], where `∂Γ/∂q` cannot be served to `1e-8`.
    pub fn inverse_dynamics_joint_derivatives(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
    ) -> Result<JointDynamicsDerivatives<6>, Error> {
        Self::check_joints(q, qd, qdd)?;
        let (gamma, d_q, d_qd, d_qdd, guard) = self
            .kernels
            .inverse_dynamics_joint_derivatives_params(q, qd, qdd, &self.params);
        check_forward(guard)?;
        check_joint_derivatives([guard[1], guard[2], guard[3]])?;
        Ok(JointDynamicsDerivatives {
            gamma: finite("gamma", gamma)?,
            d_q: finite_matrix("d_gamma_d_q", d_q)?,
            d_qd: finite_matrix("d_gamma_d_qd", d_qd)?,
            d_qdd: finite_matrix("d_gamma_d_qdd", d_qdd)?,
        })
    }
}
