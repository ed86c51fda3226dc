//! The C5 through the interface of every robot whose platform is free in space, its
//! [`ParallelRobot`] and [`SpatialRobot`]: its inherent calls, and the batch kernels for the
//! calls over many states (feature `batch`).

#[cfg(feature = "derivatives")]
use crate::derivatives::{ForwardDynamicsDerivatives, InverseDynamicsDerivatives};
#[cfg(feature = "identify")]
use crate::identify::{BaseParameters, Friction};
#[cfg(feature = "derivatives")]
use crate::mechanism::Derivatives;
use crate::mechanism::{ParallelRobot, SpatialRobot};
use crate::scene::Scene;
use crate::{Acceleration, Error, Evaluation, Limit, Model, Pose, State, Twist, C5};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_robot::Description;

impl ParallelRobot for C5 {
    fn mechanism(&self) -> &'static str {
        c5_robot::description::C5
    }
    fn model_name(&self) -> &'static str {
        self.model().name()
    }
    fn other_models(&self) -> Vec<Box<dyn ParallelRobot>> {
        Model::ALL
            .into_iter()
            .filter(|&m| m != self.model())
            .map(|m| Box::new(self.to_model(m)) as Box<dyn ParallelRobot>)
            .collect()
    }
    /// Four states at a time through the batch kernels (feature `batch`).
    fn evaluate_many(&self, states: &[State]) -> Result<Vec<Evaluation>, (usize, Error)> {
        C5::evaluate_many(self, states)
    }
    fn inverse_dynamics_each(
        &self,
        n: usize,
        state: &(dyn Fn(usize) -> State + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; 6], Error>),
    ) {
        C5::inverse_dynamics_each(self, n, state, each)
    }
    fn forward_dynamics_each(
        &self,
        n: usize,
        input: &(dyn Fn(usize) -> (Pose, Twist, [f64; 6]) + Sync),
        each: &mut dyn FnMut(usize, Result<Acceleration, Error>),
    ) {
        C5::forward_dynamics_each(self, n, input, each)
    }
    fn inverse_dynamics_joint_each(
        &self,
        n: usize,
        sample: &(dyn Fn(usize) -> [[f64; 6]; 3] + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; 6], Error>),
    ) {
        C5::inverse_dynamics_joint_each(self, n, sample, each)
    }
    /// Four states at a time through the batch kernels (feature `batch`).
    fn inverse_dynamics_many(&self, states: &[State]) -> Result<Vec<[f64; 6]>, (usize, Error)> {
        C5::inverse_dynamics_many(self, states)
    }
    fn home(&self) -> Pose {
        Pose::default()
    }
    fn description(&self) -> Description {
        Description::C5(*self.robot())
    }
    fn actuator_positions(&self, pose: &Pose) -> Result<[f64; 6], Error> {
        Ok(self.inverse_kinematics(pose)?.0)
    }
    fn scene(&self, pose: &Pose) -> Result<Scene, Error> {
        Self::scene(self, pose)
    }
    fn inverse_jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        C5::inverse_jacobian(self, pose)
    }
    fn jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        C5::jacobian(self, pose)
    }
    fn joint_velocities(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        C5::joint_velocities(self, pose, twist)
    }
    fn joint_accelerations(&self, state: &State) -> Result<[f64; 6], Error> {
        C5::joint_accelerations(self, state)
    }
    fn inverse_dynamics(&self, state: &State) -> Result<[f64; 6], Error> {
        C5::inverse_dynamics(self, state)
    }
    fn forward_dynamics(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<Acceleration, Error> {
        C5::forward_dynamics(self, pose, twist, gamma)
    }
    /// In closed form: `near` is not needed.
    fn forward_kinematics(&self, q: &[f64; 6], _near: Option<&Pose>) -> Result<Pose, Error> {
        C5::forward_kinematics(self, q)
    }
    fn joint_state(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
        _near: Option<&Pose>,
    ) -> Result<State, Error> {
        C5::joint_state(self, q, qd, qdd)
    }
    fn inverse_dynamics_joint(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
        _near: Option<&Pose>,
    ) -> Result<[f64; 6], Error> {
        C5::inverse_dynamics_joint(self, q, qd, qdd)
    }
    fn evaluate(&self, state: &State) -> Result<Evaluation, Error> {
        C5::evaluate(self, state)
    }
    fn smallest_pose_margin(&self, pose: &Pose) -> Result<Option<(Limit, usize, f64, f64)>, Error> {
        Ok(self.limit_margins(pose)?.smallest())
    }
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>) {
        (self.robot().limits.speed, self.robot().limits.force)
    }
    fn has_limits(&self) -> bool {
        self.robot().limits.any()
    }
    fn characteristic_length(&self) -> f64 {
        self.robot().half_spacing
    }
    fn singularity_clearance(&self, pose: &Pose) -> Result<f64, Error> {
        Ok(C5::singularity_terms(pose)?
            .iter()
            .fold(f64::INFINITY, |m, r| m.min(r.abs())))
    }
    fn parameters(&self) -> &[f64] {
        C5::parameters(self)
    }
    fn task_inertia(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        C5::task_inertia(self, pose)
    }
    fn task_bias(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        C5::task_bias(self, pose, twist)
    }
    /// In closed form: `near` is not needed.
    fn joint_inertia(&self, q: &[f64; 6], _near: Option<&Pose>) -> Result<[[f64; 6]; 6], Error> {
        C5::joint_inertia(self, q)
    }
    /// In closed form: `near` is not needed.
    fn joint_bias(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        _near: Option<&Pose>,
    ) -> Result<[f64; 6], Error> {
        C5::joint_bias(self, q, qd)
    }
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, state: &State) -> Result<nalgebra::DMatrix<f64>, Error> {
        let y = C5::regressor(self, state)?;
        Ok(nalgebra::DMatrix::from_iterator(
            6,
            y.ncols(),
            y.iter().copied(),
        ))
    }
    fn as_any(&self) -> &dyn core::any::Any {
        self
    }
    fn clone_box(&self) -> Box<dyn ParallelRobot> {
        Box::new(self.clone())
    }
    fn spatial(&self) -> Option<&dyn SpatialRobot> {
        Some(self)
    }
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn Derivatives<6>> {
        Some(self)
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction; 6]) -> Vec<f64> {
        self.robot().standard_parameters(friction)
    }
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error> {
        Ok(C5::base_parameters(self))
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, state: &State, out: &mut [f64]) -> Result<(), Error> {
        C5::base_regressor_into(self, state, out)
    }
}

impl SpatialRobot for C5 {
    fn clone_spatial(&self) -> Box<dyn SpatialRobot> {
        Box::new(self.clone())
    }
}

/// The C5's exact derivatives, through its inherent methods.
#[cfg(feature = "derivatives")]
impl Derivatives<6> for C5 {
    fn inverse_dynamics_derivatives(
        &self,
        state: &State,
    ) -> Result<InverseDynamicsDerivatives<6>, Error> {
        C5::inverse_dynamics_derivatives(self, state)
    }
    fn forward_dynamics_derivatives(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<ForwardDynamicsDerivatives<6>, Error> {
        C5::forward_dynamics_derivatives(self, pose, twist, gamma)
    }
}
