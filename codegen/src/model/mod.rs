//! The mechanisms: the equations, and the kernel table a mechanism is built into.
//!
//! A mechanism is a value ([`Mechanism`]): the kind of robot with its description's numbers.
//! Its kind answers two questions. [`Structure`]: what its description holds (the parameter
//! vector, the pose and the leg closed forms, the bodies' dynamics, the singularities); and
//! [`Mechanics`]: how the legs tie the actuators to the platform (the Jacobians, rates,
//! accelerations and forces). The kernel table ([`kernels`]) is the same for every mechanism,
//! less the kernels a structure does not have, so a new mechanism is one new file implementing
//! both traits. The C5 has two models of its legs, [`paper`] and [`consistent`], over one
//! structure ([`c5`]): what they share lives in [`geometry`] (eqs 15, 16, 27) and [`bodies`]
//! (Newton-Euler, eqs 52-57). Mechanisms whose platform rides on legs of known types derive
//! everything from the legs' closed forms ([`legged`]): the Gough-Stewart platform
//! ([`gough_stewart`]), the rotary hexapod ([`rus_hexapod`]) and the Delta ([`delta`]), whose
//! platform only translates and whose kernels are its own, on three actuators.
//!
//! This is the only place that knows both the robots and the kernel list; the engine sees
//! [`KernelSpec`](crate::KernelSpec)s and nothing else.

pub mod bodies;
pub mod c5;
pub mod calibration;
pub mod consistent;
pub mod delta;
pub mod derivatives;
pub mod geometry;
pub mod gough_stewart;
pub mod kernels;
pub mod legged;
pub mod paper;
pub mod regressor;
pub mod rus_hexapod;
mod selfcheck;
pub mod terms;

pub use c5_robot::tree::Freedom;
pub use c5_robot::Model;
pub use kernels::{Decl, Entry, Guard, Kernel, KernelId, Output, ParameterSet};
pub use selfcheck::self_check;

use crate::dag::{Expr, Graph};
use crate::linalg::{Mat6, Vec3, Vec6, Vector};
use bodies::Dynamics;
use geometry::{JointMotion, Motion, Posed};

/// A quantity whose equations differ between models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    InverseKinematics,
    InverseJacobian,
    Jacobian,
    JointVelocities,
    JointAccelerations,
    LegWrench,
    InverseDynamics,
    /// The platform's own wrench.
    PlatformWrench,
    /// `M_x` and `h` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`.
    TaskSpace,
    ForwardDynamics,
    /// The regressors of identification, `∂Γ/∂π`.
    Identification,
}

/// The first index of the inputs a model creates for itself (the unknown accelerations whose
/// coefficients make `M_x`); no kernel's outputs may depend on them.
pub const INTERNAL_INPUTS: u32 = 1 << 30;

/// How the legs tie the actuators to the platform: everything that differs between models.
///
/// Every method builds symbolic expressions from the expanded pose ([`Posed`]) and, where it
/// needs them, the platform's motion and the bodies' standard parameters ([`Dynamics`]), in
/// which the dynamics is linear; segment order 1..6 throughout.
pub trait Mechanics: Sync {
    /// The family's name: the generated module's (with `_` for `-`), the manifest's and the
    /// command line's.
    fn name(&self) -> &'static str;
    /// What the mechanism's description holds.
    fn structure(&self) -> &'static dyn Structure;
    /// One line on what the model is, for the documentation of its kernels.
    fn summary(&self) -> &'static str;
    /// The equations (the chapter's numbers, or the design's) behind `quantity`.
    fn equations(&self, quantity: Quantity) -> &'static [&'static str];
    /// `J⁻¹`, row `i` for segment `i+1`, columns `[ωx ωy ωz vx vy vz]`.
    fn inverse_jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g>;
    /// `J`, rows `[ωx ωy ωz vx vy vz]`, column `i` for segment `i+1`.
    fn jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g>;
    /// `Q̇_a = J⁻¹ V`.
    fn joint_velocities<'g>(&self, posed: &Posed<'g>, twist: &Vec6<'g>) -> Vec6<'g>;
    /// `Q̈_a` from the classical motion.
    fn joint_accelerations<'g>(&self, posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g>;
    /// `Φ` at `C` (base frame): the legs' loads as one wrench, `Γ = Jᵀ (F_{N+1} + Φ)`.
    fn leg_wrench<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g>;
    /// `Γ`, the actuator forces.
    fn inverse_dynamics<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g>;
    /// `Γ` for the regressor, which differentiates it by every body's parameters: a form where
    /// each body's parameters meet only its own motion makes the cheapest columns. Default:
    /// [`Mechanics::inverse_dynamics`].
    fn inverse_dynamics_by_body<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        self.inverse_dynamics(dynamics, posed, motion)
    }
    /// What the regressor differentiates at the kernel's state, for the bodies' `dynamics`:
    /// the actuator forces `Γ` ([`Mechanics::inverse_dynamics_by_body`]) and the actuators'
    /// rates, the friction's columns. A mechanism whose platform does not take the six-freedom
    /// pose reads its own inputs.
    fn regressor_terms<'g>(
        &self,
        cx: &kernels::Context<'_, 'g>,
        dynamics: &Dynamics<'g>,
    ) -> (Vec<Expr<'g>>, Vec<Expr<'g>>) {
        let (posed, motion) = (cx.posed(), cx.motion());
        (
            self.inverse_dynamics_by_body(dynamics, &posed, &motion)
                .to_vec(),
            self.joint_velocities(&posed, &motion.twist).to_vec(),
        )
    }
    /// `W = J⁻ᵀ Γ = F_{N+1} + Φ`, the wrench at `C` (base frame) the actuators put on the
    /// platform.
    fn task_wrench<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        let (twist, accel) = (&motion.twist, &motion.accel);
        let frame = bodies::Frame::new(posed.r, &twist.top(), &accel.top());
        bodies::platform_wrench(dynamics, &frame, twist, accel)
            + self.leg_wrench(dynamics, posed, motion)
    }

    /// `M_x = ∂W/∂(ω̇; a_C)`, the task-space inertia (base frame): `W` is affine in the
    /// acceleration, so its exact derivative is the matrix, free of the twist.
    fn task_inertia<'g>(&self, dynamics: &Dynamics<'g>, posed: &Posed<'g>) -> Mat6<'g> {
        let g = posed.c[0].graph();
        let unknown = Vector::from_fn(|k| g.input(INTERNAL_INPUTS + k as u32));
        let motion = Motion::new(Vec6::zeros(g), unknown);
        let w = self.task_wrench(dynamics, posed, &motion).to_vec();
        kernels::jacobian_wrt(g, &w, &unknown.0)
    }

    /// `h = W` at zero acceleration: Coriolis, centrifugal and gravity terms (base frame).
    fn task_bias<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        twist: &Vec6<'g>,
    ) -> Vec6<'g> {
        let motion = Motion::new(*twist, Vec6::zeros(twist[0].graph()));
        self.task_wrench(dynamics, posed, &motion)
    }

    /// The direct dynamic model: `(ω̇; a_C) = M_x⁻¹ (J⁻ᵀ Γ - h)`, the solve unrolled (`LDLᵀ`).
    fn forward_dynamics<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        twist: &Vec6<'g>,
        gamma: &Vec6<'g>,
    ) -> Vec6<'g> {
        let w = self.inverse_jacobian(posed).transpose() * *gamma;
        let rhs = w - self.task_bias(dynamics, posed, twist);
        self.task_inertia(dynamics, posed).ldlt_solve(&rhs)
    }

    /// `∂a/∂X`, `∂a/∂V`, `∂a/∂Γ` (row-major 6×6 each) of `accel`, this model's forward dynamics
    /// at the state, with respect to the kernel inputs `wrt`. Default:
    /// [`derivatives::by_task_residual`], through `M_x` as the default forward dynamics solves.
    #[allow(clippy::too_many_arguments)]
    fn forward_dynamics_jacobians<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        twist: &Vec6<'g>,
        gamma: &Vec6<'g>,
        accel: &Vec6<'g>,
        wrt: &derivatives::ForwardInputs<'_, 'g>,
    ) -> [Vec<crate::Expr<'g>>; 3] {
        derivatives::by_task_residual(self, dynamics, posed, twist, gamma, accel, wrt)
    }

    /// `∂Γ/∂x` (row-major, `6 × xs.len()`) of `gamma`, this model's inverse dynamics at the
    /// state, for each of the kernel inputs `wrt`. Default: `Γ` differentiated directly.
    fn inverse_dynamics_jacobians<'g>(
        &self,
        _dynamics: &Dynamics<'g>,
        _posed: &Posed<'g>,
        _motion: &Motion<'g>,
        gamma: &Vec6<'g>,
        wrt: &[Vec<crate::Expr<'g>>],
    ) -> Vec<Vec<crate::Expr<'g>>> {
        let g = gamma[0].graph();
        wrt.iter()
            .map(|xs| g.jacobian(&gamma.to_vec(), xs))
            .collect()
    }

    /// The platform's motion from the actuators' (the joint setting): `V = J Q̇_a` and
    /// `(ω̇; a_C) = J (Q̈_a - h)`, where `h` is `Q̈_a` at zero platform acceleration (`Q̈_a` is
    /// affine in it, with `J⁻¹` its linear part); the actuators' motion is kept beside.
    fn motion_from_actuators<'g>(&self, posed: &Posed<'g>, joint: &JointMotion<'g>) -> Motion<'g> {
        let jac = self.jacobian(posed);
        let twist = (jac * joint.qd).keep_where_cheaper("V from the actuators' rates");
        let zero = Vec6::zeros(twist[0].graph());
        let bias = self.joint_accelerations(posed, &Motion::new(twist, zero));
        Motion {
            twist,
            accel: (jac * (joint.qdd - bias))
                .keep_where_cheaper("(ω̇; a_C) from the actuators' accelerations"),
            joint: Some(*joint),
        }
    }

    /// Kernels only this model has (the paper's chapter-setting kernels).
    fn extra_kernels(&self) -> &'static [Decl] {
        &[]
    }
    /// Derivative kernels only this mechanism has, beside those of
    /// [`derivatives::KERNELS`] its structure has (the Delta's, in its three coordinates).
    fn extra_derivative_kernels(&self) -> &'static [Decl] {
        &[]
    }
}

/// What a mechanism's description holds, for the kernels: its parameter vector, its pose in
/// closed form, its bodies' dynamic parameters and its singularities.
pub trait Structure: Sync {
    /// The names of the parameter vector of the `*_params` kernels, in order (valid Rust
    /// identifiers).
    fn parameter_names(&self) -> Vec<String>;
    /// How many of the first parameters are the geometry and gravity: [`Posed::geometry`], and
    /// the `params` of the identification kernels.
    fn geometry_parameters(&self) -> usize;
    /// The platform at the pose `[α β γ xc yc zc]` (eq 15), with the actuator values and the
    /// vectors from each leg's platform joint to `C`.
    fn pose<'g>(&self, geometry: &[Expr<'g>], x: &[Expr<'g>]) -> Posed<'g>;
    /// The platform from the actuator positions in closed form, where the mechanism has one
    /// (the kernels that read actuator positions exist only then).
    fn forward_kinematics<'g>(
        &self,
        _geometry: &[Expr<'g>],
        _q: &[Expr<'g>; 6],
    ) -> Option<Posed<'g>> {
        None
    }
    /// The bodies' dynamic parameters from the whole parameter vector.
    fn dynamics<'g>(&self, parameters: &[Expr<'g>]) -> Dynamics<'g>;
    /// The names of the standard inertial parameters, the unknowns of identification (friction
    /// not included), in the order of [`Structure::dynamics_from_standard`].
    fn standard_inertial_names(&self) -> Vec<String>;
    /// What the standard inertial parameters are, for their documentation: the bodies, their
    /// reference points and frames.
    fn standard_inertial_doc(&self) -> &'static str;
    /// The dynamics with the standard inertial parameters `p` and gravity given.
    fn dynamics_from_standard<'g>(
        &self,
        g: &'g Graph,
        gravity: Vec3<'g>,
        p: &[Expr<'g>],
    ) -> Dynamics<'g>;
    /// The singularity terms a kernel of `guard` returns as its last result.
    fn guard<'g>(&self, guard: Guard, posed: &Posed<'g>) -> Vec<Expr<'g>>;
    /// [`Structure::guard`] at the kernel's state: at its pose, unless the mechanism's
    /// platform takes another.
    fn guard_at<'g>(&self, guard: Guard, cx: &kernels::Context<'_, 'g>) -> Vec<Expr<'g>> {
        self.guard(guard, &cx.posed())
    }
    /// That result's declaration, and the sentence the kernel's documentation adds about it.
    fn guard_output(&self, guard: Guard) -> (Output, &'static str);
    /// What each term of the longest guard measures, in order (a shorter guard is its
    /// beginning), for the runtime's one check; none where the mechanism's kernels are checked
    /// by hand (the C5's divisors).
    fn singularity_terms(&self) -> Vec<terms::SingularityTerm> {
        Vec::new()
    }
    /// What each term of the closed-form forward kinematics' guard measures, where it has one.
    fn forward_kinematics_terms(&self) -> Vec<terms::SingularityTerm> {
        Vec::new()
    }
    /// What the documentation of every kernel says of the conventions (the actuators' order).
    fn conventions(&self) -> &'static str;
    /// The documentation of the `params` argument of the kernels that read `reads`.
    fn parameter_doc(&self, reads: kernels::Reads) -> &'static str;
    /// Whether the mechanism has `kernel` of the shared table ([`kernels::TABLE`]).
    fn has_kernel(&self, _kernel: kernels::Kernel) -> bool {
        true
    }
    /// The pose around which seeded states are drawn (checks, base parameters).
    fn home(&self, parameters: &[f64]) -> [f64; 6];
    /// A length of the workspace: seeded states stay within a fraction of it of [`Structure::home`].
    fn reach(&self, parameters: &[f64]) -> f64;
    /// How the platform moves: free in space, or translating only.
    fn freedom(&self) -> Freedom {
        Freedom::Free
    }
    /// How many actuators (and platform freedoms) the mechanism has: the length of its
    /// actuator inputs.
    fn actuators(&self) -> usize {
        self.freedom().dimension()
    }
    /// The largest turn (rad) about each axis from [`Structure::home`] of seeded states.
    fn turn_reach(&self) -> f64 {
        0.4
    }
}

/// A mechanism with its description's numbers: what a kernel set is generated from.
#[derive(Clone)]
pub struct Mechanism {
    pub mechanics: &'static dyn Mechanics,
    /// The description's kernel parameters, in the order of
    /// [`Structure::parameter_names`]: folded into the kernels, or the values of their `params`.
    pub parameters: Vec<f64>,
}

impl std::fmt::Debug for Mechanism {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mechanism")
            .field("name", &self.mechanics.name())
            .field("parameters", &self.parameters)
            .finish()
    }
}

impl Mechanism {
    /// A C5 robot with one of its models.
    pub fn c5(robot: &c5_robot::Robot, model: Model) -> Self {
        Mechanism {
            mechanics: mechanics(model),
            parameters: robot.kernel_parameters(),
        }
    }

    /// The robot of `description`; a C5 with `model` (the other mechanisms have one model).
    pub fn of(description: &c5_robot::Description, model: Model) -> Self {
        match description {
            c5_robot::Description::C5(robot) => Mechanism::c5(robot, model),
            c5_robot::Description::GoughStewart(robot) => Mechanism::gough_stewart(robot),
            c5_robot::Description::RusHexapod(robot) => Mechanism::rus_hexapod(robot),
            c5_robot::Description::Delta(robot) => Mechanism::delta(robot),
        }
    }

    /// A Gough-Stewart platform.
    pub fn gough_stewart(robot: &c5_robot::GoughStewart) -> Self {
        Mechanism {
            mechanics: &gough_stewart::GoughStewartMechanics,
            parameters: robot.kernel_parameters(),
        }
    }

    /// A rotary hexapod.
    pub fn rus_hexapod(robot: &c5_robot::RusHexapod) -> Self {
        Mechanism {
            mechanics: &rus_hexapod::RusHexapodMechanics,
            parameters: robot.kernel_parameters(),
        }
    }

    /// A Delta.
    pub fn delta(robot: &c5_robot::Delta) -> Self {
        Mechanism {
            mechanics: &delta::DeltaMechanics,
            parameters: robot.kernel_parameters(),
        }
    }

    pub fn name(&self) -> &'static str {
        self.mechanics.name()
    }

    pub fn structure(&self) -> &'static dyn Structure {
        self.mechanics.structure()
    }

    /// The geometry and gravity: the first [`Structure::geometry_parameters`] parameters.
    pub fn geometry(&self) -> &[f64] {
        &self.parameters[..self.structure().geometry_parameters()]
    }
}

/// The mechanics of a C5 `model`.
pub fn mechanics(model: Model) -> &'static dyn Mechanics {
    match model {
        Model::Consistent => &consistent::Consistent,
        Model::Paper => &paper::Paper,
    }
}

/// A robot unlike the chapter's: off-centre masses, full inertias.
#[cfg(test)]
pub(crate) fn lopsided() -> c5_robot::Robot {
    let mut robot = c5_robot::Robot::default();
    robot.platform.mass = 7.3;
    robot.platform.com = [0.01, -0.02, 0.015];
    robot.platform.inertia = [
        [0.09, 0.004, -0.003],
        [0.004, 0.08, 0.002],
        [-0.003, 0.002, 0.12],
    ];
    for (i, segment) in robot.segments.iter_mut().enumerate() {
        let t = i as f64;
        segment.rod.mass = 1.5 + 0.1 * t;
        segment.joint.mass = 0.7 + 0.05 * t;
        segment.joint.com = [0.01, 0.005 * t, -0.02];
        segment.joint.inertia[0][1] = 0.001 * t;
        segment.joint.inertia[1][0] = 0.001 * t;
    }
    robot
}
