//! The dynamics' exact derivatives of every legged mechanism whose derivative kernels are
//! generated (feature `derivatives`): the kernel set's `Derivatives<N>` behind checked calls,
//! written once for every such mechanism.

use super::robot::{KernelsOf, LeggedDescription, LeggedRobot};
use super::{Coordinates, Freedoms, Platform};
use crate::derivatives::{ForwardDynamicsDerivatives, InverseDynamicsDerivatives};
use crate::error::Error;
use crate::legged::{PoseOf, StateOf, TwistOf};
use crate::singularity::{self, TermKind, FORWARD_U_JOINT_TOLERANCE};
use c5_generated::legged::{Derivatives, Legs};

impl<D: LeggedDescription<N>, const N: usize> LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
    KernelsOf<D, N>: Derivatives<N>,
{
    /// The inverse dynamics and its exact Jacobians with respect to the pose, the twist and the
    /// acceleration, in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or hold, or a non-finite result.
    pub fn inverse_dynamics_derivatives(
        &self,
        state: &StateOf<N>,
    ) -> Result<InverseDynamicsDerivatives<N>, Error> {
        let [x, v, a] = state.checked("state")?;
        let (gamma, d_pose, d_twist, d_accel, guard) =
            KernelsOf::<D, N>::inverse_dynamics_derivatives(&x, &v, &a, &self.params);
        singularity::check(guard.as_ref(), KernelsOf::<D, N>::SINGULARITY_TERMS)?;
        InverseDynamicsDerivatives::checked((gamma, d_pose, d_twist, d_accel))
    }

    /// The forward dynamics and its exact Jacobians with respect to the pose, the twist and the
    /// actuator forces `gamma`, in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, the legs' hold below its tolerance, a U joint too
    /// near its singularity for the acceleration's bound ([`Error::IllConditioned`]), or a
    /// non-finite result.
    pub fn forward_dynamics_derivatives(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<ForwardDynamicsDerivatives<N>, Error> {
        let (x, v) = (pose.checked("pose")?, twist.checked("twist")?);
        crate::check_finite("gamma", gamma)?;
        let terms = KernelsOf::<D, N>::SINGULARITY_TERMS;
        // The kernel solves with `M_x`, so its own terms do not hold the legs' hold: the pose's
        // terms do.
        singularity::check(
            KernelsOf::<D, N>::singularity_terms(&x, &self.params).as_ref(),
            terms,
        )?;
        let (a, d_pose, d_twist, d_gamma, guard) =
            KernelsOf::<D, N>::forward_dynamics_derivatives(&x, &v, gamma, &self.params);
        singularity::check(guard.as_ref(), terms)?;
        singularity::check_conditioned(
            "forward dynamics",
            guard.as_ref(),
            terms,
            TermKind::UJoint,
            FORWARD_U_JOINT_TOLERANCE,
        )?;
        ForwardDynamicsDerivatives::checked((a, d_pose, d_twist, d_gamma))
    }
}

impl<D: LeggedDescription<N>, const N: usize> crate::mechanism::Derivatives<N> for LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
    KernelsOf<D, N>: Derivatives<N>,
{
    fn inverse_dynamics_derivatives(
        &self,
        state: &StateOf<N>,
    ) -> Result<InverseDynamicsDerivatives<N>, Error> {
        LeggedRobot::inverse_dynamics_derivatives(self, state)
    }
    fn forward_dynamics_derivatives(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<ForwardDynamicsDerivatives<N>, Error> {
        LeggedRobot::forward_dynamics_derivatives(self, pose, twist, gamma)
    }
}
