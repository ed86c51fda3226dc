//! The C5 joint parallel robot for controllers: a safe, typed API over its generated kernels
//! (both models, the variants that take the robot's parameters), the bounds of its accuracy
//! contract near eq 16's singularities, and the checks of the divisors its kernels return.

mod batch;
#[cfg(feature = "derivatives")]
mod derivatives;
pub(crate) mod limits;
mod parallel_robot;

use crate::{
    check_finite, finite, finite_matrix, Acceleration, Error, Evaluation, Pose, State, Twist,
};
use crate::{Kernels, Model, Robot};
use c5_generated::f64::{paper, AnyModel};

// The parameter vector's length is generated from the robot description's one definition.
const _: () = assert!(c5_generated::PARAMETERS == c5_robot::PARAMETERS);

/// The generated kernels of `model`. Every model has the same kernels with the same signatures
/// ([`Kernels`]), so everything else calls them through this, statically (only the kernels
/// called are built).
pub fn kernels(model: Model) -> AnyModel {
    ModelParts::of(model).kernels
}

/// What differs between the models at run time: the one place a model is mapped to its code
/// and its bounds.
#[derive(Clone, Copy, Debug)]
struct ModelParts {
    kernels: AnyModel,
    /// The smallest divisor of eq 16 at which the model's forward dynamics is served.
    forward_dynamics_tolerance: f64,
}

impl ModelParts {
    fn of(model: Model) -> Self {
        let (kernels, forward_dynamics_tolerance) = match model {
            Model::Consistent => (AnyModel::Consistent, FORWARD_DYNAMICS_TOLERANCE),
            Model::Paper => (AnyModel::Paper, PAPER_FORWARD_DYNAMICS_TOLERANCE),
        };
        ModelParts {
            kernels,
            forward_dynamics_tolerance,
        }
    }
}

/// Smallest accepted `|r11|`, `|r22|`, `|r33|` (the divisors of eq 16). Below it a pose is
/// [`Error::Singular`]: an actuator length would be off by more than `|Δ|/1e-9` per unit error.
pub const SINGULARITY_TOLERANCE: f64 = 1e-9;

/// Smallest `|r11|`, `|r22|`, `|r33|` at which the forward dynamics is served (its accuracy
/// contract, docs/embedding.md). Near eq 16's singularities the forward dynamics is ill
/// conditioned: the forces that hold a modest acceleration grow like `1/s³`, so their rounding
/// moves the acceleration by about `1.2e-15/s³` relative (measured against a 50-digit
/// reference, `python/tests/test_accuracy.py`), and faster still below `s = 1e-3`. At `1e-2`
/// the worst measured error is `3.8e-10`, within the `1e-8` the `f64` API promises; below it
/// the call is refused ([`Error::IllConditioned`]). The task-space kernels that evaluate (the
/// kinematics, the inverse dynamics, `M_x`, `∂Γ/∂(X, V, A)`) stay within `1e-14` up to
/// [`SINGULARITY_TOLERANCE`]; the joint-space ones have bounds of their own
/// ([`JOINT_STATE_TOLERANCE`], [`JOINT_DYNAMICS_TOLERANCE`]).
pub const FORWARD_DYNAMICS_TOLERANCE: f64 = 1e-2;

/// [`FORWARD_DYNAMICS_TOLERANCE`] for the paper model, whose forward dynamics is better
/// conditioned near eq 16's singularities (its `J⁻¹` divides by nothing). Against its own
/// 50-digit reference (`ExactPaper`, `python/tests/exact.py`) its error grows as about `1/s²`:
/// 1e-12 at worst in `[1e-3, 1e-2)`, 8.3e-11 in `[1e-4, 1e-3)`, 1.1e-8 in `[1e-5, 1e-4)`.
pub const PAPER_FORWARD_DYNAMICS_TOLERANCE: f64 = 1e-4;

/// Smallest `|r11|`, `|r22|`, `|r33|` at which the platform's twist and acceleration are
/// served from the actuators' rates and accelerations ([`C5::joint_state`], `c5 eval` on
/// actuator lines): `V = J q̇` and `(ω̇; a_C) = J (q̈ - h)` apply `J`, which is ill conditioned
/// near eq 16's singularities. Against a 50-digit reference the acceleration errs by about
/// `3e-18/s³` relative (`3.1e-10` at worst in `[1e-3, 1e-2)`, `1.3e-8` in `[1e-4, 1e-3)`) and
/// the twist by about `1e-18/s²`; below this bound, with nonzero rates or accelerations, the
/// call is refused ([`Error::IllConditioned`]). The pose alone is served down to
/// [`SINGULARITY_TOLERANCE`], as are the joint-space forces and inertia, which stay accurate.
pub const JOINT_STATE_TOLERANCE: f64 = 1e-3;

/// Smallest `|r11|`, `|r22|`, `|r33|` at which the joint-space inverse dynamics, inertia and
/// bias are served ([`C5::inverse_dynamics_joint`], [`C5::joint_inertia`],
/// [`C5::joint_bias`]). Their error against a 50-digit reference grows as `1/s`: about
/// `2.6e-17/s` for `Γ` and `1.4e-17/s` for `M_q`, so `2.5e-8` at worst in `[1e-9, 1e-8)`,
/// past the `1e-8` bound, and `1.9e-10` in `[1e-7, 1e-6)`.
pub const JOINT_DYNAMICS_TOLERANCE: f64 = 1e-7;

/// Refuses a pose where `what` cannot be served to its bound: a divisor of eq 16 below
/// `bound` (after [`check_divisors`]).
///
/// # Errors
/// [`Error::Singular`] or [`Error::IllConditioned`] naming the divisor.
#[inline]
fn check_conditioned(what: &'static str, bound: f64, r: [f64; 3]) -> Result<(), Error> {
    check_divisors(r)?;
    for (term, value) in ["r11", "r22", "r33"].into_iter().zip(r) {
        if value.abs() < bound {
            return Err(Error::IllConditioned {
                what,
                term,
                value,
                bound,
            });
        }
    }
    Ok(())
}

/// Refuses actuator positions where the joint-space inverse dynamics, inertia or bias cannot be
/// served to their bound: at or beyond the forward singularity ([`check_forward`]), or a
/// divisor of eq 16 below [`JOINT_DYNAMICS_TOLERANCE`].
///
/// # Errors
/// [`Error::ForwardSingular`], [`Error::Singular`] or [`Error::IllConditioned`].
#[inline]
pub(crate) fn check_joint_dynamics(guard: [f64; 4]) -> Result<(), Error> {
    check_forward(guard)?;
    check_conditioned(
        "joint-space dynamics",
        JOINT_DYNAMICS_TOLERANCE,
        [guard[1], guard[2], guard[3]],
    )
}

/// Refuses a pose where the joint-space Jacobians `∂Γ/∂q`, `∂Γ/∂q̇` cannot be served to their
/// bound: a divisor of eq 16 below [`JOINT_STATE_TOLERANCE`]. They differentiate through the
/// pose the actuators give, and err against a 50-digit reference by `1.7e-11` at worst in
/// `[1e-4, 1e-3)` and by `3e-4` near `5e-6`.
///
/// # Errors
/// [`Error::Singular`] or [`Error::IllConditioned`] naming the divisor.
#[cfg(feature = "derivatives")]
#[inline]
pub(crate) fn check_joint_derivatives(r: [f64; 3]) -> Result<(), Error> {
    check_conditioned("joint-space derivatives", JOINT_STATE_TOLERANCE, r)
}

/// Refuses a pose where the forward dynamics cannot be served to its bound: a divisor of eq
/// 16 below the model's [`C5::forward_dynamics_tolerance`] (after [`check_divisors`]).
///
/// # Errors
/// [`Error::Singular`] or [`Error::IllConditioned`] naming the divisor.
#[inline]
pub(crate) fn check_forward_dynamics(bound: f64, r: [f64; 3]) -> Result<(), Error> {
    check_conditioned("forward dynamics", bound, r)
}

/// A validated robot, the model its kernels follow, and its parameter vector.
#[derive(Clone, Debug)]
pub struct C5 {
    robot: Robot,
    model: Model,
    // The batch kernels (c5/batch.rs) and the derivatives (derivatives.rs) call them too.
    pub(crate) kernels: AnyModel,
    forward_dynamics_tolerance: f64,
    pub(crate) params: [f64; c5_generated::PARAMETERS],
}

/// Whether a divisor is too small to divide by (or NaN).
fn is_singular(value: f64) -> bool {
    value.is_nan() || value.abs() < SINGULARITY_TOLERANCE
}

/// Refuses a pose where a divisor of eq 16 (`[r11 r22 r33]`, the last result of the kernels
/// that divide by them) is below [`SINGULARITY_TOLERANCE`], or NaN: for code that calls the
/// generated kernels itself, as `C5` does.
///
/// # Errors
/// [`Error::Singular`] naming the divisor.
#[inline]
pub(crate) fn check_divisors(r: [f64; 3]) -> Result<(), Error> {
    for (term, value) in ["r11", "r22", "r33"].into_iter().zip(r) {
        if is_singular(value) {
            return Err(Error::Singular { term, value });
        }
    }
    Ok(())
}

/// Refuses actuator positions at or beyond the forward singularity (`[1 + abc, r11, r22, r33]`,
/// the last result of the joint-setting kernels), or where a divisor of eq 16 vanishes.
///
/// # Errors
/// [`Error::ForwardSingular`], or [`Error::Singular`] naming the divisor.
#[inline]
pub(crate) fn check_forward(guard: [f64; 4]) -> Result<(), Error> {
    let value = guard[0];
    if value.is_nan() || value < SINGULARITY_TOLERANCE {
        return Err(Error::ForwardSingular { value });
    }
    check_divisors([guard[1], guard[2], guard[3]])
}

impl C5 {
    /// The robot with the consistent model.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of [`Robot::validate`].
    pub fn new(robot: Robot) -> Result<Self, Error> {
        Self::with_model(robot, Model::Consistent)
    }

    /// The robot with the given model.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of [`Robot::validate`].
    pub fn with_model(robot: Robot, model: Model) -> Result<Self, Error> {
        robot.validate().map_err(Error::from_robot)?;
        let mut params = [0.0; c5_generated::PARAMETERS];
        params.copy_from_slice(&robot.kernel_parameters());
        let parts = ModelParts::of(model);
        Ok(C5 {
            robot,
            model,
            kernels: parts.kernels,
            forward_dynamics_tolerance: parts.forward_dynamics_tolerance,
            params,
        })
    }

    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    pub fn model(&self) -> Model {
        self.model
    }

    /// The smallest `|r11|`, `|r22|`, `|r33|` at which this model's forward dynamics (and its
    /// batch and derivative forms) is served: [`FORWARD_DYNAMICS_TOLERANCE`] for the
    /// consistent model, [`PAPER_FORWARD_DYNAMICS_TOLERANCE`] for the paper model.
    pub fn forward_dynamics_tolerance(&self) -> f64 {
        self.forward_dynamics_tolerance
    }

    /// The same robot with another model.
    pub fn to_model(&self, model: Model) -> Self {
        let parts = ModelParts::of(model);
        C5 {
            model,
            kernels: parts.kernels,
            forward_dynamics_tolerance: parts.forward_dynamics_tolerance,
            ..self.clone()
        }
    }

    /// The generated kernels this robot's model calls.
    pub fn kernels(&self) -> AnyModel {
        self.kernels
    }

    /// The robot's parameter vector, as the `*_params` kernels take it.
    pub fn parameters(&self) -> &[f64; c5_generated::PARAMETERS] {
        &self.params
    }

    /// `[r11 r22 r33]`, the divisors of eq 16 at `pose`, the same in both models: a pose is
    /// singular where one vanishes, and their size says how far it is from that.
    ///
    /// # Errors
    /// A non-finite pose.
    pub fn singularity_terms(pose: &Pose) -> Result<[f64; 3], Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        Ok(paper::singularity_terms(&x))
    }

    /// A forward dynamics' pose and twist as arrays, with `gamma`, each checked finite.
    pub(crate) fn checked_forward(
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<[[f64; 6]; 2], Error> {
        let (x, v) = (pose.to_array(), twist.to_array());
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        check_finite("gamma", gamma)?;
        Ok([x, v])
    }

    /// Finite inputs; the singularity check is left to the divisors the kernel returns.
    pub(crate) fn checked_motion(state: &State) -> Result<[[f64; 6]; 3], Error> {
        let x = state.pose.to_array();
        let v = state.twist.to_array();
        let a = state.accel.to_array();
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        check_finite("acceleration", &a)?;
        Ok([x, v, a])
    }

    /// Eqs 15, 16, 27: actuator lengths `Q_i1` and the vectors `P_i2`, segment order (the
    /// same in both models).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_kinematics(&self, pose: &Pose) -> Result<([f64; 6], [[f64; 3]; 6]), Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (q, p, r) = self.kernels.inverse_kinematics_params(&x, &self.params);
        check_divisors(r)?;
        Ok((finite("q", q)?, finite_matrix("p", p)?))
    }

    /// `J⁻¹` (row `i` = segment `i+1`, columns `ωx ωy ωz vx vy vz`).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (jinv, r) = self.kernels.inverse_jacobian_pose_params(&x, &self.params);
        check_divisors(r)?;
        finite_matrix("jinv", jinv)
    }

    /// `J`, factored (rows `ωx … vz`, column `i` = segment `i+1`).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn jacobian(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (jac, r) = self.kernels.jacobian_pose_params(&x, &self.params);
        check_divisors(r)?;
        finite_matrix("jacobian", jac)
    }

    /// `Q̇_a = J⁻¹ V`, segment order.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn joint_velocities(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        let (x, v) = (pose.to_array(), twist.to_array());
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        let (qd, r) = self.kernels.joint_velocities_params(&x, &v, &self.params);
        check_divisors(r)?;
        finite("qd", qd)
    }

    /// Actuator accelerations `Q̈_a`, segment order: eq 16 differentiated twice (consistent),
    /// or the projection scheme of eqs 43-48 (paper).
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn joint_accelerations(&self, state: &State) -> Result<[f64; 6], Error> {
        let [x, v, a] = Self::checked_motion(state)?;
        let (qdd, r) = self
            .kernels
            .joint_accelerations_params(&x, &v, &a, &self.params);
        check_divisors(r)?;
        finite("qdd", qdd)
    }

    /// Actuator forces `Γ` (N), segment order: the force each actuator must apply along `+n_i`
    /// for the platform to follow the state.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn inverse_dynamics(&self, state: &State) -> Result<[f64; 6], Error> {
        let [x, v, a] = Self::checked_motion(state)?;
        let (gamma, r) = self
            .kernels
            .inverse_dynamics_params(&x, &v, &a, &self.params);
        check_divisors(r)?;
        finite("gamma", gamma)
    }

    /// `M_x` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`: the task-space inertia, symmetric positive
    /// definite (rows and columns `ωx ωy ωz vx vy vz`, base frame).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn task_inertia(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
        let x = pose.to_array();
        check_finite("pose", &x)?;
        let (m, r) = self.kernels.task_inertia_params(&x, &self.params);
        check_divisors(r)?;
        finite_matrix("task inertia", m)
    }

    /// `h` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`: Coriolis, centrifugal and gravity terms at `C`.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn task_bias(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
        let (x, v) = (pose.to_array(), twist.to_array());
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        let (h, r) = self.kernels.task_bias_params(&x, &v, &self.params);
        check_divisors(r)?;
        finite("task bias", h)
    }

    /// The forward dynamics: the platform's classical acceleration `(ω̇; a_C)` under actuator
    /// forces `gamma` (N, segment order).
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a pose nearer eq 16's singularities than
    /// [`C5::forward_dynamics_tolerance`] ([`Error::IllConditioned`]), or a non-finite result.
    pub fn forward_dynamics(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<Acceleration, Error> {
        let [x, v] = C5::checked_forward(pose, twist, gamma)?;
        let (a, r) = self
            .kernels
            .forward_dynamics_params(&x, &v, gamma, &self.params);
        check_forward_dynamics(self.forward_dynamics_tolerance(), r)?;
        let a = finite("acceleration", a)?;
        Ok(Acceleration::from_array(a))
    }

    /// The forward kinematics in closed form: the platform's pose from the actuator positions
    /// `q` (m, segment order), with no iteration and no trigonometry but the angles' three arc
    /// tangents. The same for both models (eq 16); the pose returned is the placement in the
    /// workspace, every `r_kk > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`], or [`Error::ForwardSingular`] where no pose of the workspace has
    /// these positions.
    pub fn forward_kinematics(&self, q: &[f64; 6]) -> Result<Pose, Error> {
        check_finite("q", q)?;
        let (r, c, guard) = self.kernels.forward_kinematics_params(q, &self.params);
        check_forward(guard)?;
        let [alpha, beta, gamma] = finite("pose", self.kernels.rpy_angles(&r))?;
        Ok(Pose {
            alpha,
            beta,
            gamma,
            center: finite("pose", c)?,
        })
    }

    /// The platform state from the actuators' positions `q`, rates `qd` and accelerations
    /// `qdd` (m, m/s, m/s², segment order): the forward kinematics, `V = J q̇` and
    /// `(ω̇; a_C) = J (q̈ - h)` of the model, in one kernel.
    ///
    /// # Errors
    /// Non-finite inputs, [`Error::ForwardSingular`], a singular pose, a non-finite result,
    /// or [`Error::IllConditioned`] for nonzero rates or accelerations at a pose nearer eq
    /// 16's singularities than [`JOINT_STATE_TOLERANCE`].
    pub fn joint_state(&self, q: &[f64; 6], qd: &[f64; 6], qdd: &[f64; 6]) -> Result<State, Error> {
        Self::check_joints(q, qd, qdd)?;
        let (x, v, a, guard) = self.kernels.platform_state_params(q, qd, qdd, &self.params);
        check_forward(guard)?;
        // At rest the twist and acceleration are zero, exactly, wherever the pose is served.
        if qd.iter().chain(qdd).any(|&x| x != 0.0) {
            check_conditioned(
                "platform motion from the actuators",
                JOINT_STATE_TOLERANCE,
                [guard[1], guard[2], guard[3]],
            )?;
        }
        Ok(State {
            pose: Pose::from_array(finite("pose", x)?),
            twist: Twist::from_array(finite("twist", v)?),
            accel: Acceleration::from_array(finite("acceleration", a)?),
        })
    }

    pub(crate) fn check_joints(q: &[f64; 6], qd: &[f64; 6], qdd: &[f64; 6]) -> Result<(), Error> {
        check_finite("q", q)?;
        check_finite("qd", qd)?;
        check_finite("qdd", qdd)
    }

    /// Actuator forces `Γ` (N, segment order) from the actuators' positions, rates and
    /// accelerations: the inverse dynamics at the state they give, without trigonometry.
    ///
    /// # Errors
    /// Non-finite inputs, [`Error::ForwardSingular`], a non-finite result, or a pose nearer
    /// eq 16's singularities than [`JOINT_DYNAMICS_TOLERANCE`] ([`Error::IllConditioned`]).
    pub fn inverse_dynamics_joint(
        &self,
        q: &[f64; 6],
        qd: &[f64; 6],
        qdd: &[f64; 6],
    ) -> Result<[f64; 6], Error> {
        Self::check_joints(q, qd, qdd)?;
        let (gamma, guard) = self
            .kernels
            .inverse_dynamics_joint_params(q, qd, qdd, &self.params);
        check_joint_dynamics(guard)?;
        finite("gamma", gamma)
    }

    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia (kg, symmetric positive definite;
    /// `Jᵀ M_x J`), at the actuator positions `q`.
    ///
    /// # Errors
    /// A non-finite input, [`Error::ForwardSingular`], a non-finite result, or a pose nearer
    /// eq 16's singularities than [`JOINT_DYNAMICS_TOLERANCE`] ([`Error::IllConditioned`]).
    pub fn joint_inertia(&self, q: &[f64; 6]) -> Result<[[f64; 6]; 6], Error> {
        check_finite("q", q)?;
        let (m, guard) = self.kernels.joint_inertia_params(q, &self.params);
        check_joint_dynamics(guard)?;
        finite_matrix("joint inertia", m)
    }

    /// `c_q` of `Γ = M_q q̈ + c_q`: Coriolis, centrifugal and gravity forces (N) at the
    /// actuators' positions `q` and rates `qd`.
    ///
    /// # Errors
    /// Non-finite inputs, [`Error::ForwardSingular`], a non-finite result, or a pose nearer
    /// eq 16's singularities than [`JOINT_DYNAMICS_TOLERANCE`] ([`Error::IllConditioned`]).
    pub fn joint_bias(&self, q: &[f64; 6], qd: &[f64; 6]) -> Result<[f64; 6], Error> {
        check_finite("q", q)?;
        check_finite("qd", qd)?;
        let (c, guard) = self.kernels.joint_bias_params(q, qd, &self.params);
        check_joint_dynamics(guard)?;
        finite("joint bias", c)
    }

    /// Eq 39 in the chapter's setting (the paper model): `Π1` from given vectors `P_i2`
    /// (segment order), rows `[ẇ_p1 u̇_p1 γ̇_p β̇_p α̇_p Q̇_11]`, column `i` for segment `i+1`.
    ///
    /// # Errors
    /// A non-finite input, or [`Error::Singular`] naming `y5 - y6`, `z1 - z2` or `x3 - x4` when
    /// its magnitude is below [`SINGULARITY_TOLERANCE`] (m).
    pub fn pi1(&self, p: &[[f64; 3]; 6]) -> Result<[[f64; 6]; 6], Error> {
        check_finite("p", p.as_flattened())?;
        let d = paper::pi1_denominators(p);
        for (term, value) in ["y5 - y6", "z1 - z2", "x3 - x4"].into_iter().zip(d) {
            if is_singular(value) {
                return Err(Error::Singular { term, value });
            }
        }
        finite_matrix("pi1", paper::pi1(p))
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
        let (q, _) = self.inverse_kinematics(&state.pose)?;
        Ok(Evaluation {
            q,
            qd: self.joint_velocities(&state.pose, &state.twist)?,
            qdd: self.joint_accelerations(state)?,
            gamma: self.inverse_dynamics(state)?,
            jinv: self.inverse_jacobian(&state.pose)?,
            jacobian: self.jacobian(&state.pose)?,
        })
    }
}
