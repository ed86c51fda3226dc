//! Any parallel robot the runtime knows, behind one trait: what code that serves every
//! mechanism calls (the command line's `eval`, `forward`, `simulate`, `track`, ...).
//!
//! [`ParallelRobot`] is the kinematics and dynamics of a platform on six actuators, in the
//! conventions every mechanism shares (pose `[α β γ xc yc zc]`, twist `(ω; v_C)`, classical
//! acceleration, actuator values and forces in actuator order). [`robot`] makes one from a
//! [`Description`]: the one place a description is mapped to its mechanism.

#[cfg(feature = "derivatives")]
use crate::derivatives::{ForwardDynamicsDerivatives, InverseDynamicsDerivatives};
#[cfg(feature = "identify")]
use crate::identify::{BaseParameters, Friction};
use crate::platform::Mechanism;
use crate::scene::Scene;
use crate::{Acceleration, Error, Evaluation, Limit, Model, Pose, State, Twist, C5};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_robot::Description;

/// The robot as a [`Mechanism`], for the calls every mechanism serves: a `&dyn ParallelRobot`
/// handed on as a `&dyn Mechanism`.
pub trait AsMechanism {
    fn as_mechanism(&self) -> &dyn Mechanism;
}

impl<M: Mechanism> AsMechanism for M {
    fn as_mechanism(&self) -> &dyn Mechanism {
        self
    }
}

/// A parallel robot whose platform is free in space: the kinematics and dynamics of six
/// freedoms, and as a [`Mechanism`] ([`AsMechanism`]) what every mechanism serves.
pub trait ParallelRobot: AsMechanism + core::fmt::Debug + Send + Sync {
    /// The mechanism's name, as robot files spell it (`c5`, `gough-stewart`).
    fn mechanism(&self) -> &'static str;
    /// The name of the model the results follow (`consistent`, `paper`, `gough-stewart`).
    fn model_name(&self) -> &'static str;
    /// The same robot under each of its other models (the C5's: the paper model beside the
    /// consistent one); none for a mechanism of one model.
    fn other_models(&self) -> Vec<Box<dyn ParallelRobot>> {
        Vec::new()
    }
    /// The pose the robot rests at, where its forward kinematics starts without a previous
    /// solution.
    fn home(&self) -> Pose;
    /// The robot's description, as its file gives it: what [`Description::export`] writes
    /// for other tools.
    fn description(&self) -> Description;
    /// The actuator values at `pose` (m).
    fn actuator_positions(&self, pose: &Pose) -> Result<[f64; 6], Error>;
    /// `J⁻¹`, row `i` for actuator `i`, columns `ωx ωy ωz vx vy vz`.
    fn inverse_jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error>;
    /// `J`, rows `ωx … vz`, column `i` for actuator `i`.
    fn jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error>;
    /// `q̇ = J⁻¹ V`.
    fn joint_velocities(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error>;
    /// `q̈` from the platform's motion.
    fn joint_accelerations(&self, state: &State) -> Result<[f64; 6], Error>;
    /// The actuator forces `Γ` (N).
    fn inverse_dynamics(&self, state: &State) -> Result<[f64; 6], Error>;
    /// `M_x` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`.
    fn task_inertia(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error>;
    /// `h` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`.
    fn task_bias(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error>;
    /// The platform's classical acceleration under the actuator forces `gamma` (N).
    fn forward_dynamics(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<Acceleration, Error>;
    /// The pose of the actuator positions `q` (m), from `near` where the mechanism iterates.
    fn forward_kinematics(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<Pose, Error>;
    /// The platform state from the actuators' positions, rates and accelerations.
    fn joint_state(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
        near: Option<&Pose>,
    ) -> Result<State, Error>;
    /// The actuator forces from the actuators' motion.
    fn inverse_dynamics_joint(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
        near: Option<&Pose>,
    ) -> Result<[f64; 6], Error>;
    /// `q`, `q̇`, `q̈`, `Γ`, `J⁻¹` and `J` at one state.
    fn evaluate(&self, state: &State) -> Result<Evaluation, Error>;
    /// The smallest margin of the pose-bound limits at `pose` (the limit, its actuator 1..6,
    /// the margin and the value), `None` when the description sets none.
    fn smallest_pose_margin(&self, pose: &Pose) -> Result<Option<(Limit, usize, f64, f64)>, Error>;
    /// The actuators' speed and force limits (m/s, N), where the description sets them.
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>);
    /// Whether the description sets any limit.
    fn has_limits(&self) -> bool;
    /// A length of the robot that turns rates into speeds for dexterity measures (m): the
    /// C5's half-spacing, a hexapod's platform radius.
    fn characteristic_length(&self) -> f64;
    /// The robot's parameter vector, as its generated `*_params` kernels take it.
    fn parameters(&self) -> &[f64];
    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia at the actuator positions `q`,
    /// from `near` where the mechanism iterates.
    fn joint_inertia(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<[[f64; 6]; 6], Error>;
    /// `c_q` of `Γ = M_q q̈ + c_q`: Coriolis, centrifugal and gravity forces at the actuator
    /// positions `q` and rates `qd`, from `near` where the mechanism iterates.
    fn joint_bias(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        near: Option<&Pose>,
    ) -> Result<[f64; 6], Error>;
    /// The smallest of the pose's singularity terms, each about 1 far from its singularity
    /// and 0 at it: the C5's `|r11|`, `|r22|`, `|r33|` (eq 16), a hexapod's U-joint sines and
    /// pivot ratios of its legs' hold.
    ///
    /// # Errors
    /// A non-finite pose.
    fn singularity_clearance(&self, pose: &Pose) -> Result<f64, Error>;
    /// The robot itself, for what only its mechanism serves (the C5's encoders, its paper
    /// model's kernels).
    fn as_any(&self) -> &dyn core::any::Any;
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn ParallelRobot>;
    /// The robot's parts at `pose`, for drawing it, with the joints and legs past a limit
    /// flagged.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    fn scene(&self, pose: &Pose) -> Result<Scene, Error>;

    /// The standard parameters `π` of this robot with the actuators' `friction`: the inertial
    /// ones, then viscous and Coulomb friction per actuator.
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction; 6]) -> Vec<f64>;
    /// The base parameters of this robot's base regressor.
    ///
    /// # Errors
    /// [`Error::Unsupported`] where this geometry has base parameters the generated
    /// regressor lacks.
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error>;
    /// `Y` at `state` (`6 × n`, columns the standard parameters): `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, state: &State) -> Result<nalgebra::DMatrix<f64>, Error>;
    /// `Y_b` at `state` into `out`, row-major (`6 × n_b`): `Γ = Y_b β` with friction.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a non-finite result, or `out` not `6 n_b` long.
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, state: &State, out: &mut [f64]) -> Result<(), Error>;

    /// The robot's exact derivatives, where its mechanism has them generated; `None` where not
    /// (the rotary hexapod's).
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn Derivatives> {
        None
    }
    /// Its mechanism's kinematic calibration kernel, where one is generated; `None` where not
    /// (the C5's legs are not a list of joint centres).
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel> {
        None
    }
    /// [`ParallelRobot::evaluate`] of every state, or the first refused with its index.
    fn evaluate_many(&self, states: &[State]) -> Result<Vec<Evaluation>, (usize, Error)> {
        states
            .iter()
            .enumerate()
            .map(|(k, s)| self.evaluate(s).map_err(|e| (k, e)))
            .collect()
    }
    /// [`ParallelRobot::inverse_dynamics`] of every state, or the first refused with its
    /// index.
    fn inverse_dynamics_many(&self, states: &[State]) -> Result<Vec<[f64; 6]>, (usize, Error)> {
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
        state: &(dyn Fn(usize) -> State + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; 6], Error>),
    ) {
        (0..n).for_each(|k| each(k, self.inverse_dynamics(&state(k))));
    }
    /// [`ParallelRobot::forward_dynamics`] of inputs `0..n` (pose, twist, forces), each
    /// result handed to `each` in order.
    fn forward_dynamics_each(
        &self,
        n: usize,
        input: &(dyn Fn(usize) -> (Pose, Twist, [f64; 6]) + Sync),
        each: &mut dyn FnMut(usize, Result<Acceleration, Error>),
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
        sample: &(dyn Fn(usize) -> [[f64; 6]; 3] + Sync),
        each: &mut dyn FnMut(usize, Result<[f64; 6], Error>),
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
    fn check_limits(&self, pose: &Pose) -> Result<(), Error> {
        match self.smallest_pose_margin(pose)? {
            Some((limit, actuator, margin, value)) if margin < 0.0 => Err(Error::Limit {
                limit,
                actuator,
                value,
                margin,
            }),
            _ => Ok(()),
        }
    }
    /// Refuses actuator speeds beyond the description's limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the fastest actuator over the limit.
    fn check_speeds(&self, qd: &[f64; 6]) -> Result<(), Error> {
        crate::limits::over(Limit::Speed, self.speed_and_force_limits().0, qd)
    }
    /// Refuses actuator forces beyond the description's limit.
    ///
    /// # Errors
    /// [`Error::Limit`] for the largest force over the limit.
    fn check_forces(&self, gamma: &[f64; 6]) -> Result<(), Error> {
        crate::limits::over(Limit::Force, self.speed_and_force_limits().1, gamma)
    }
}

impl Clone for Box<dyn ParallelRobot> {
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
pub fn robot(description: Description, model: Model) -> Result<Box<dyn ParallelRobot>, Error> {
    let mechanism = crate::platform::load(description, model)?;
    mechanism
        .spatial()
        .map(ParallelRobot::clone_box)
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
    fn task_inertia(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        C5::task_inertia(self, pose)
    }
    fn task_bias(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        C5::task_bias(self, pose, twist)
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
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn Derivatives> {
        Some(self)
    }
}

/// The dynamics' exact derivatives of a robot whose platform is free in space
/// ([`crate::derivatives`]): a capability of the mechanisms whose derivative kernels are
/// generated, reached through [`ParallelRobot::derivatives`].
#[cfg(feature = "derivatives")]
pub trait Derivatives: Send + Sync {
    /// `Γ` and its exact Jacobians with respect to the pose, twist and acceleration.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    fn inverse_dynamics_derivatives(
        &self,
        state: &State,
    ) -> Result<InverseDynamicsDerivatives, Error>;
    /// The forward dynamics and its exact Jacobians with respect to the pose, twist and
    /// forces.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose or a non-finite result.
    fn forward_dynamics_derivatives(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<ForwardDynamicsDerivatives, Error>;
}

/// The derivatives of the mechanisms that have them, through their inherent methods.
macro_rules! derivatives_impl {
    ($($robot:ty),*) => {$(
        #[cfg(feature = "derivatives")]
        impl Derivatives for $robot {
            fn inverse_dynamics_derivatives(
                &self,
                state: &State,
            ) -> Result<InverseDynamicsDerivatives, Error> {
                <$robot>::inverse_dynamics_derivatives(self, state)
            }
            fn forward_dynamics_derivatives(
                &self,
                pose: &Pose,
                twist: &Twist,
                gamma: &[f64; 6],
            ) -> Result<ForwardDynamicsDerivatives, Error> {
                <$robot>::forward_dynamics_derivatives(self, pose, twist, gamma)
            }
        }
    )*};
}
derivatives_impl!(C5, crate::GoughStewart);

/// `robot`'s derivatives, refused by name where its mechanism has none generated.
///
/// # Errors
/// [`Error::Unsupported`] naming the mechanism.
#[cfg(feature = "derivatives")]
pub fn derivatives_of(robot: &dyn ParallelRobot) -> Result<&dyn Derivatives, Error> {
    robot.derivatives().ok_or(Error::Unsupported {
        what: "derivatives",
        mechanism: robot.mechanism(),
        why: "its derivative kernels are not generated yet; its kinematics, dynamics and \
              regressors are (docs/mechanisms.md)",
    })
}
