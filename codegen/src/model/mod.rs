//! The C5 robot's models: the equations, and the kernel table a model is built into.
//!
//! A model is a value: [`mechanics`] gives the [`Mechanics`] of a [`Model`], and the kernel
//! table ([`kernels`]) is the same for every model, so a third model is one new file
//! implementing [`Mechanics`] (and a name in [`Model`]). What both models share lives in
//! [`geometry`] (eqs 15, 16, 27) and [`bodies`] (Newton-Euler, eqs 52-57).
//!
//! This is the only place that knows both the robot and the kernel list; the engine sees
//! [`KernelSpec`](crate::KernelSpec)s and nothing else.

pub mod bodies;
pub mod consistent;
pub mod derivatives;
pub mod geometry;
pub mod kernels;
pub mod paper;
pub mod regressor;
mod selfcheck;

pub use c5_robot::Model;
pub use kernels::{Decl, Entry, Kernel, KernelId, ParameterSet};
pub use selfcheck::self_check;

use crate::linalg::{Mat6, Vec6, Vector};
use bodies::Dynamics;
use geometry::{JointMotion, Motion, Posed};

/// A quantity whose equations differ between models.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    InverseJacobian,
    Jacobian,
    JointVelocities,
    JointAccelerations,
    LegWrench,
    InverseDynamics,
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
    fn model(&self) -> Model;
    /// One line on what the model is, for the documentation of its kernels.
    fn summary(&self) -> &'static str;
    /// The equations (the chapter's numbers, or DESIGN.md's) behind `quantity`.
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

    /// The platform's motion from the actuators' (the joint setting): `V = J Q̇_a` and
    /// `(ω̇; a_C) = J (Q̈_a - h)`, where `h` is `Q̈_a` at zero platform acceleration (`Q̈_a` is
    /// affine in it, with `J⁻¹` its linear part); the actuators' motion is kept beside.
    fn motion_from_actuators<'g>(&self, posed: &Posed<'g>, joint: &JointMotion<'g>) -> Motion<'g> {
        let jac = self.jacobian(posed);
        let twist = jac * joint.qd;
        let zero = Vec6::zeros(twist[0].graph());
        let bias = self.joint_accelerations(posed, &Motion::new(twist, zero));
        Motion {
            twist,
            accel: jac * (joint.qdd - bias),
            joint: Some(*joint),
        }
    }

    /// Kernels only this model has (the paper's chapter-setting kernels).
    fn extra_kernels(&self) -> &'static [Decl] {
        &[]
    }
}

/// The mechanics of `model`.
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
