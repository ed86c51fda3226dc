//! Any parallel robot the runtime knows, in its platform's typed coordinates: what code that
//! serves every mechanism of a freedom calls (the command line's `eval`, `forward`, `simulate`,
//! `track`, ...).
//!
//! [`ParallelRobot<N>`] is the kinematics and dynamics of a platform with `N` freedoms on as many
//! actuators, in the conventions every mechanism shares (for six: pose `[α β γ xc yc zc]`, twist
//! `(ω; v_C)`, classical acceleration; for three translations: `C`, `v_C`, `a_C`; actuator
//! values and forces in actuator order, the task-space and joint-space inertia); [`SpatialRobot`]
//! the same robot behind the six-coordinate [`crate::State`] of the C5's API. [`robot`] makes
//! one of six freedoms from a [`Description`]; [`crate::platform::load`] makes any as a
//! [`Mechanism`].

#[cfg(feature = "derivatives")]
use crate::derivatives::{ForwardDynamicsDerivatives, InverseDynamicsDerivatives};
#[cfg(feature = "identify")]
use crate::identify::{BaseParameters, Friction};
use crate::legged::{AccelerationOf, Freedoms, Platform, PoseOf, StateOf, TwistOf};
use crate::platform::Mechanism;
use crate::scene::Scene;
use crate::{Error, Evaluation, Limit, Model};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_robot::Description;

/// A parallel robot whose platform has `N` freedoms (six, free in space, by default; three
/// for a platform that only translates), in its platform's typed coordinates ([`PoseOf`],
/// [`TwistOf`], [`StateOf`], [`AccelerationOf`]) and `N` actuators. As a [`Mechanism`]
/// ([`ParallelRobot::into_mechanism`]) it serves every caller that takes any freedom.
pub trait ParallelRobot<const N: usize = 6>: core::fmt::Debug + Send + Sync
where
    Platform<N>: Freedoms<N>,
{
    /// The mechanism's name, as robot files spell it (`c5`, `gough-stewart`, `delta`).
    fn mechanism(&self) -> &'static str;
    /// The name of the model the results follow (`consistent`, `paper`, `gough-stewart`).
    fn model_name(&self) -> &'static str;
    /// The same robot under each of its other models (the C5's: the paper model beside the
    /// consistent one); none for a mechanism of one model.
    fn other_models(&self) -> Vec<Box<dyn ParallelRobot<N>>> {
        Vec::new()
    }
    /// The pose the robot rests at, where its forward kinematics starts without a previous
    /// solution.
    fn home(&self) -> PoseOf<N>;
    /// The robot's description, as its file gives it: what [`Description::export`] writes
    /// for other tools.
    fn description(&self) -> Description;
    /// The actuator values at `pose` (m or rad).
    fn actuator_positions(&self, pose: &PoseOf<N>) -> Result<[f64; N], Error>;
    /// `J⁻¹`, row `i` for actuator `i`, columns the twist's.
    fn inverse_jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error>;
    /// `J`, rows the twist's, column `i` for actuator `i`.
    fn jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error>;
    /// `q̇ = J⁻¹ V`.
    fn joint_velocities(&self, pose: &PoseOf<N>, twist: &TwistOf<N>) -> Result<[f64; N], Error>;
    /// `q̈` from the platform's motion.
    fn joint_accelerations(&self, state: &StateOf<N>) -> Result<[f64; N], Error>;
    /// The actuator forces `Γ` (N or N·m).
    fn inverse_dynamics(&self, state: &StateOf<N>) -> Result<[f64; N], Error>;
    /// The platform's acceleration under the actuator forces `gamma`.
    fn forward_dynamics(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<AccelerationOf<N>, Error>;
    /// The pose of the actuator positions `q`, from `near` where the mechanism iterates.
    fn forward_kinematics(
        &self,
        q: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<PoseOf<N>, Error>;
    /// The platform state from the actuators' positions, rates and accelerations.
    fn joint_state(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<StateOf<N>, Error>;
    /// The actuator forces from the actuators' motion.
    fn inverse_dynamics_joint(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error>;
    /// `M_x` of `Γ = Jᵀ (M_x V̇ + h)` (`V̇` the classical acceleration, `(ω̇; a_C)` or `a_C`),
    /// symmetric positive definite.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    fn task_inertia(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error>;
    /// `h` of `Γ = Jᵀ (M_x V̇ + h)`: the Coriolis, centrifugal and gravity terms at `C`.
    ///
    /// # Errors
    /// Non-finite inputs, or a singular pose.
    fn task_bias(&self, pose: &PoseOf<N>, twist: &TwistOf<N>) -> Result<[f64; N], Error>;
    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia `Jᵀ M_x J` at the actuator
    /// positions `q`, from `near` where the mechanism iterates.
    ///
    /// # Errors
    /// As the forward kinematics, or a singular pose.
    fn joint_inertia(&self, q: &[f64; N], near: Option<&PoseOf<N>>)
        -> Result<[[f64; N]; N], Error>;
    /// `c_q` of `Γ = M_q q̈ + c_q`: Coriolis, centrifugal and gravity forces at the actuator
    /// positions `q` and rates `qd`, from `near` where the mechanism iterates.
    fn joint_bias(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error>;
    /// `q`, `q̇`, `q̈`, `Γ`, `J⁻¹` and `J` at one state.
    fn evaluate(&self, state: &StateOf<N>) -> Result<Evaluation<N>, Error>;
    /// The smallest margin of the pose-bound limits at `pose` (the limit, its actuator from 1,
    /// the margin and the value), `None` when the description sets none.
    fn smallest_pose_margin(
        &self,
        pose: &PoseOf<N>,
    ) -> Result<Option<(Limit, usize, f64, f64)>, Error>;
    /// The actuators' speed and force limits, where the description sets them.
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>);
    /// Whether the description sets any limit.
    fn has_limits(&self) -> bool;
    /// A length of the robot that turns rates into speeds for dexterity measures (m): the
    /// C5's half-spacing, a legged platform's mean joint radius.
    fn characteristic_length(&self) -> f64;
    /// The robot's parameter vector, as its generated `*_params` kernels take it.
    fn parameters(&self) -> &[f64];
    /// The smallest of the pose's singularity terms, each about 1 far from its singularity
    /// and 0 at it: the C5's `|r11|`, `|r22|`, `|r33|` (eq 16), a legged mechanism's U-joint
    /// sines, cranks' reach and pivot ratios of its legs' hold.
    ///
    /// # Errors
    /// A non-finite pose.
    fn singularity_clearance(&self, pose: &PoseOf<N>) -> Result<f64, Error>;
    /// The robot itself, for what only its mechanism serves (the C5's encoders, its paper
    /// model's kernels).
    fn as_any(&self) -> &dyn core::any::Any;
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn ParallelRobot<N>>;
    /// The robot as a [`Mechanism`], whose calls take slices of any freedom, borrowed.
    fn as_mechanism(&self) -> &dyn Mechanism
    where
        Self: Sized + Clone + 'static,
    {
        crate::platform::Sliced::<Self, N>::of(self)
    }
    /// The robot as a boxed [`Mechanism`].
    fn into_mechanism(self) -> Box<dyn Mechanism>
    where
        Self: Sized + Clone + 'static,
    {
        Box::new(crate::platform::Sliced(self))
    }
    /// The robot as a [`SpatialRobot`], where its platform is free in space.
    fn spatial(&self) -> Option<&dyn SpatialRobot> {
        None
    }
    /// The robot's exact derivatives, where its mechanism has them generated; `None` where not
    /// (the rotary hexapod's).
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn Derivatives<N>> {
        None
    }
    /// The robot's parts at `pose`, for drawing it, with the joints and legs past a limit
    /// flagged.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    fn scene(&self, pose: &PoseOf<N>) -> Result<Scene, Error>;

    /// The standard parameters `π` of this robot with the actuators' `friction`: the inertial
    /// ones, then viscous and Coulomb friction per actuator.
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction; N]) -> Vec<f64>;
    /// The base parameters of this robot's base regressor.
    ///
    /// # Errors
    /// [`Error::Unsupported`] where this geometry has base parameters the generated
    /// regressor lacks.
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error>;
    /// `Y` at `state` (`N × n`, columns the standard parameters): `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, state: &StateOf<N>) -> Result<nalgebra::DMatrix<f64>, Error>;
    /// `Y_b` at `state` into `out`, row-major (`N × n_b`): `Γ = Y_b β` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `N n_b` long.
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, state: &StateOf<N>, out: &mut [f64]) -> Result<(), Error>;

    /// Its mechanism's kinematic calibration kernel, where one is generated; `None` where not
    /// (the C5's legs are not a list of joint centres).
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel> {
        None
    }
    /// [`ParallelRobot::evaluate`] of every state, or the first refused with its index.
    fn evaluate_many(&self, states: &[StateOf<N>]) -> Result<Vec<Evaluation<N>>, (usize, Error)> {
        states
            .iter()
            .enumerate()
            .map(|(k, s)| self.evaluate(s).map_err(|e| (k, e)))
            .collect()
    }
    /// [`ParallelRobot::inverse_dynamics`] of every state, or the first refused with its
    /// index.
    fn inverse_dynamics_many(
        &self,
        states: &[StateOf<N>],
    ) -> Result<Vec<[f64; N]>, (usize, Error)> {
        states
            .iter()
            .enumerate()
            .map(|(k, s)| self.inverse_dynamics(s).map_err(|e| (k, e)))
            .collect()
    }
    /// [`ParallelRobot::inverse_dynamics`] of states `0..n` (`state(k)` the `k`-th), each
    /// result handed to `each` in order: for callers that read states from their own storage
    /// (numpy arrays, a log). The C5 goes four states at a time through its batch kernels
    /// (feature `batch`).
    fn inverse_dynamics_each(
        &self,
        n: usize,
        state: &(dyn Fn(usize) -> StateOf<N> + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; N], Error>),
    ) {
        (0..n).for_each(|k| each(k, self.inverse_dynamics(&state(k))));
    }
    /// [`ParallelRobot::forward_dynamics`] of inputs `0..n` (pose, twist, forces), each
    /// result handed to `each` in order.
    #[allow(clippy::type_complexity)]
    fn forward_dynamics_each(
        &self,
        n: usize,
        input: &(dyn Fn(usize) -> (PoseOf<N>, TwistOf<N>, [f64; N]) + Sync),
        each: &mut dyn FnMut(usize, Result<AccelerationOf<N>, Error>),
    ) {
        (0..n).for_each(|k| {
            let (pose, twist, gamma) = input(k);
            each(k, self.forward_dynamics(&pose, &twist, &gamma))
        });
    }
    /// [`ParallelRobot::inverse_dynamics_joint`] of samples `0..n` (`[q, q̇, q̈]`, each
    /// solved from home where the mechanism iterates), each result handed to `each` in
    /// order.
    fn inverse_dynamics_joint_each(
        &self,
        n: usize,
        sample: &(dyn Fn(usize) -> [[f64; N]; 3] + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; N], Error>),
    ) {
        (0..n).for_each(|k| {
            let [q, qd, qdd] = sample(k);
            each(k, self.inverse_dynamics_joint(&q, &qd, &qdd, None))
        });
    }
    /// Refuses a pose beyond the description's pose-bound limits.
    ///
    /// # Errors
    /// [`Error::Limit`] naming the limit with the smallest (negative) margin.
    fn check_limits(&self, pose: &PoseOf<N>) -> Result<(), Error> {
        crate::limits::refuse_beyond(self.smallest_pose_margin(pose)?)
    }
    /// Refuses actuator speeds beyond the description's limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the fastest actuator over the limit.
    fn check_speeds(&self, qd: &[f64; N]) -> Result<(), Error> {
        crate::limits::over(Limit::Speed, self.speed_and_force_limits().0, qd)
    }
    /// Refuses actuator forces beyond the description's limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the largest force over the limit.
    fn check_forces(&self, gamma: &[f64; N]) -> Result<(), Error> {
        crate::limits::over(Limit::Force, self.speed_and_force_limits().1, gamma)
    }
}

/// A platform free in space as a boxed [`ParallelRobot<6>`], for the calls that take the C5's
/// six-coordinate [`crate::State`] (the program's C5 reports, Python's `State` calls).
pub trait SpatialRobot: ParallelRobot<6> {
    /// A boxed copy.
    fn clone_spatial(&self) -> Box<dyn SpatialRobot>;
}

impl<const N: usize> Clone for Box<dyn ParallelRobot<N>>
where
    Platform<N>: Freedoms<N>,
{
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// The robot of `description` as a platform free in space, the C5 with `model` (the other
/// mechanisms have one model): [`crate::platform::load`]'s robot, for what only six freedoms
/// serve.
///
/// # Errors
/// [`Error::Robot`] if the description breaks a rule of its mechanism; [`Error::Unsupported`]
/// for the Delta, whose platform has three freedoms: [`crate::Delta`] serves it.
pub fn robot(description: Description, model: Model) -> Result<Box<dyn SpatialRobot>, Error> {
    let mechanism = crate::platform::load(description, model)?;
    mechanism
        .spatial()
        .map(SpatialRobot::clone_spatial)
        .ok_or(Error::Unsupported {
            what: "six-freedom platform",
            mechanism: mechanism.mechanism(),
            why: "its platform only translates: `c5_runtime::Mechanism` serves it, and this \
                  takes six freedoms",
        })
}

/// The robot of `description` in `format` for other tools (docs/export.md), after the checks
/// [`crate::platform::load`] makes, so that a file the commands refuse is refused here with
/// the same message.
///
/// # Errors
/// As [`crate::platform::load`]; the C5's paper model, which is not a mechanism, is refused.
pub fn export(
    description: &Description,
    model: Model,
    format: c5_robot::Format,
) -> Result<alloc::string::String, Error> {
    crate::platform::load(description.clone(), model)?;
    if matches!(description, Description::C5(_)) && model == Model::Paper {
        return Err(Error::Unsupported {
            what: "export",
            mechanism: description.mechanism(),
            why: "the paper model is the chapter's equations, not a mechanism: it has no bodies \
                  and joints to export (export the consistent model, the default)",
        });
    }
    description.export(format).map_err(Error::from_robot)
}

/// The dynamics' exact derivatives of a robot whose platform has `N` freedoms
/// ([`crate::derivatives`]), in its typed coordinates: a capability of the mechanisms whose
/// derivative kernels are generated, reached through [`ParallelRobot::derivatives`].
#[cfg(feature = "derivatives")]
pub trait Derivatives<const N: usize>: Send + Sync
where
    Platform<N>: Freedoms<N>,
{
    /// `Γ` and its exact Jacobians with respect to the pose, twist and acceleration.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    fn inverse_dynamics_derivatives(
        &self,
        state: &StateOf<N>,
    ) -> Result<InverseDynamicsDerivatives<N>, Error>;
    /// The forward dynamics and its exact Jacobians with respect to the pose, twist and
    /// forces.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    fn forward_dynamics_derivatives(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<ForwardDynamicsDerivatives<N>, Error>;
}

/// `robot`'s derivatives, refused by name where its mechanism has none generated.
///
/// # Errors
/// [`Error::Unsupported`] naming the mechanism.
#[cfg(feature = "derivatives")]
pub fn derivatives_of<const N: usize, R: ParallelRobot<N> + ?Sized>(
    robot: &R,
) -> Result<&dyn Derivatives<N>, Error>
where
    Platform<N>: Freedoms<N>,
{
    robot
        .derivatives()
        .ok_or(unsupported_derivatives(robot.mechanism()))
}

/// The refusal of derivatives to a mechanism without them generated.
#[cfg(feature = "derivatives")]
pub(crate) fn unsupported_derivatives(mechanism: &'static str) -> Error {
    Error::Unsupported {
        what: "derivatives",
        mechanism,
        why: "its derivative kernels are not generated yet; its kinematics, dynamics and \
              regressors are (docs/mechanisms.md)",
    }
}
