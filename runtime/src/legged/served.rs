//! Every legged mechanism, whatever its platform's freedom, through [`ParallelRobot`]: one
//! implementation over [`LeggedRobot`]'s checked calls, and so, through
//! [`crate::platform::Sliced`], one [`crate::Mechanism`].

use super::robot::{AccelerationOf, Freedoms, LeggedDescription, LeggedRobot, Platform};
use super::{Coordinates, Locate, PoseOf, StateOf, TwistOf};
use crate::error::Error;
#[cfg(feature = "identify")]
use crate::identify::{BaseParameters, Friction};
use crate::mechanism::{ParallelRobot, SpatialRobot};
use crate::scene::Scene;
use crate::{Evaluation, Limit};
use alloc::boxed::Box;
#[cfg(feature = "identify")]
use alloc::vec::Vec;
use c5_generated::legged::Legs;

impl<D: LeggedDescription<N>, const N: usize> ParallelRobot<N> for LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
    Self: Locate<N>,
{
    fn mechanism(&self) -> &'static str {
        D::Kernels::MECHANISM
    }
    fn model_name(&self) -> &'static str {
        D::Kernels::MECHANISM
    }
    fn home(&self) -> PoseOf<N> {
        Self::home(self)
    }
    fn description(&self) -> c5_robot::Description {
        self.robot().description()
    }
    fn actuator_positions(&self, pose: &PoseOf<N>) -> Result<[f64; N], Error> {
        self.actuators_at(&pose.checked("pose")?)
    }
    fn inverse_jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        Self::inverse_jacobian(self, pose)
    }
    fn jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        Self::jacobian(self, pose)
    }
    fn joint_velocities(&self, pose: &PoseOf<N>, twist: &TwistOf<N>) -> Result<[f64; N], Error> {
        Self::joint_velocities(self, pose, twist)
    }
    fn joint_accelerations(&self, state: &StateOf<N>) -> Result<[f64; N], Error> {
        Self::joint_accelerations(self, state)
    }
    fn inverse_dynamics(&self, state: &StateOf<N>) -> Result<[f64; N], Error> {
        Self::inverse_dynamics(self, state)
    }
    fn forward_dynamics(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<AccelerationOf<N>, Error> {
        Self::forward_dynamics(self, pose, twist, gamma)
    }
    /// Iterated from `near` (else the mechanism's start) for a platform free in space; in
    /// closed form, `near` not read, for one that translates.
    fn forward_kinematics(
        &self,
        q: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<PoseOf<N>, Error> {
        crate::check_finite("q", q)?;
        let near = near.map(|x| x.checked("near")).transpose()?;
        let (x, _) = self.located(q, near.as_ref())?;
        Ok(Platform::<N>::pose(x))
    }
    fn joint_state(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<StateOf<N>, Error> {
        Self::joint_state(self, q, qd, qdd, near)
    }
    fn inverse_dynamics_joint(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error> {
        Self::inverse_dynamics_joint(self, q, qd, qdd, near)
    }
    fn task_inertia(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        Self::task_inertia(self, pose)
    }
    fn task_bias(&self, pose: &PoseOf<N>, twist: &TwistOf<N>) -> Result<[f64; N], Error> {
        Self::task_bias(self, pose, twist)
    }
    fn joint_inertia(
        &self,
        q: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[[f64; N]; N], Error> {
        Self::joint_inertia(self, q, near)
    }
    fn joint_bias(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error> {
        Self::joint_bias(self, q, qd, near)
    }
    fn evaluate(&self, state: &StateOf<N>) -> Result<Evaluation<N>, Error> {
        Self::evaluate(self, state)
    }
    fn smallest_pose_margin(
        &self,
        pose: &PoseOf<N>,
    ) -> Result<Option<(Limit, usize, f64, f64)>, Error> {
        D::smallest_pose_margin(self, &pose.checked("pose")?)
    }
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>) {
        self.robot().speed_and_force_limits()
    }
    fn has_limits(&self) -> bool {
        self.robot().has_limits()
    }
    fn characteristic_length(&self) -> f64 {
        self.robot().characteristic_length()
    }
    fn parameters(&self) -> &[f64] {
        self.params.as_ref()
    }
    fn singularity_clearance(&self, pose: &PoseOf<N>) -> Result<f64, Error> {
        let terms = self.singularity_terms(pose)?;
        Ok(terms.as_ref().iter().copied().fold(f64::INFINITY, f64::min))
    }
    fn as_any(&self) -> &dyn core::any::Any {
        self
    }
    fn clone_box(&self) -> Box<dyn ParallelRobot<N>> {
        Box::new(self.clone())
    }
    fn spatial(&self) -> Option<&dyn SpatialRobot> {
        D::spatial(self)
    }
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn crate::mechanism::Derivatives<N>> {
        D::derivatives(self)
    }
    fn scene(&self, pose: &PoseOf<N>) -> Result<Scene, Error> {
        Self::scene(self, pose)
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction; N]) -> Vec<f64> {
        Self::standard_parameters(self, friction)
    }
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error> {
        Self::base_parameters(self)
    }
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, state: &StateOf<N>) -> Result<nalgebra::DMatrix<f64>, Error> {
        let y = self.regressor(state)?;
        let width = y[0].as_ref().len();
        Ok(nalgebra::DMatrix::from_fn(N, width, |i, j| {
            y[i].as_ref()[j]
        }))
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, state: &StateOf<N>, out: &mut [f64]) -> Result<(), Error> {
        Self::base_regressor_into(self, state, out)
    }
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel> {
        Some(crate::calibrate::residuals_of::<D::Kernels, N>)
    }
    /// Four states at a time through the batch kernel, where the mechanism's inverse dynamics
    /// comes in batch form (feature `batch`); one at a time where not.
    fn inverse_dynamics_each(
        &self,
        n: usize,
        state: &(dyn Fn(usize) -> StateOf<N> + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; N], Error>),
    ) {
        let single = |k| Self::inverse_dynamics(self, &state(k));
        #[cfg(feature = "batch")]
        crate::many::Batched {
            input: |k| Platform::<N>::state_arrays(&state(k)),
            kernel: |x: &_, v: &_, a: &_| {
                let (gamma, guard) = D::Kernels::inverse_dynamics_x4(x, v, a, &self.params)?;
                let terms = D::Kernels::SINGULARITY_TERMS;
                crate::many::terms_hold(guard.as_ref(), terms).then_some(gamma)
            },
            single,
        }
        .run(n, each);
        #[cfg(not(feature = "batch"))]
        crate::many::one_at_a_time(n, single, each);
    }
    fn inverse_dynamics_many(
        &self,
        states: &[StateOf<N>],
    ) -> Result<alloc::vec::Vec<[f64; N]>, (usize, Error)> {
        crate::many::collect(states.len(), |each| {
            ParallelRobot::inverse_dynamics_each(self, states.len(), &|k| states[k], each)
        })
    }
}
