//! A legged mechanism's `*_params` kernels as one set: the generator writes, beside each legged
//! mechanism's kernels, a unit type `Kernels` implementing these traits, so a caller serves
//! every such mechanism with one generic type, reaching its kernels through the set rather
//! than its module's path. Each kernel's last result is its singularity terms, the first of
//! the module's `SINGULARITY_TERMS`.

use crate::guard::SingularityTerm;

/// The kernels every legged mechanism has, its platform in `N` coordinates (a pose, a twist,
/// an acceleration) and `N` actuators.
pub trait Legs<const N: usize>: 'static {
    /// The mechanism's name, as robot files spell it.
    const MECHANISM: &'static str;
    /// What each singularity term measures, in order (the module's `SINGULARITY_TERMS`).
    const SINGULARITY_TERMS: &'static [SingularityTerm];
    /// The parameter vector the kernels take (`[f64; PARAMETERS]`).
    type Parameters: Copy + core::fmt::Debug + Send + Sync + AsRef<[f64]> + 'static;
    /// Every singularity term (`[f64; SINGULARITY_TERMS.len()]`).
    type Terms: Copy + core::fmt::Debug + Send + Sync + AsRef<[f64]> + 'static;

    /// The parameter vector of `values`; `None` where it has another length.
    fn parameters(values: &[f64]) -> Option<Self::Parameters>;
    /// `singularity_terms_params`.
    fn singularity_terms(x: &[f64; N], p: &Self::Parameters) -> Self::Terms;
    /// The actuator positions of `inverse_kinematics_params`.
    fn actuators(x: &[f64; N], p: &Self::Parameters) -> ([f64; N], impl AsRef<[f64]>);
    /// `inverse_jacobian_pose_params`.
    fn inverse_jacobian(x: &[f64; N], p: &Self::Parameters) -> ([[f64; N]; N], impl AsRef<[f64]>);
    /// `jacobian_pose_params`.
    fn jacobian(x: &[f64; N], p: &Self::Parameters) -> ([[f64; N]; N], impl AsRef<[f64]>);
    /// `joint_velocities_params`.
    fn joint_velocities(
        x: &[f64; N],
        v: &[f64; N],
        p: &Self::Parameters,
    ) -> ([f64; N], impl AsRef<[f64]>);
    /// `joint_accelerations_params`.
    fn joint_accelerations(
        x: &[f64; N],
        v: &[f64; N],
        a: &[f64; N],
        p: &Self::Parameters,
    ) -> ([f64; N], impl AsRef<[f64]>);
    /// `inverse_dynamics_params`.
    fn inverse_dynamics(
        x: &[f64; N],
        v: &[f64; N],
        a: &[f64; N],
        p: &Self::Parameters,
    ) -> ([f64; N], impl AsRef<[f64]>);
    /// `forward_dynamics_params`.
    fn forward_dynamics(
        x: &[f64; N],
        v: &[f64; N],
        gamma: &[f64; N],
        p: &Self::Parameters,
    ) -> ([f64; N], impl AsRef<[f64]>);
    /// `inverse_dynamics_params_x4`, where the mechanism's inverse dynamics comes in batch
    /// form (feature `batch`): four states a call, lane `l` of every input the `l`-th state's,
    /// each lane computing exactly what [`Legs::inverse_dynamics`] computes, the singularity
    /// terms lane by lane. `None` where it does not.
    #[cfg(feature = "batch")]
    #[inline]
    fn inverse_dynamics_x4(
        _x: &[[f64; 4]; N],
        _v: &[[f64; 4]; N],
        _a: &[[f64; 4]; N],
        _p: &Self::Parameters,
    ) -> Option<([[f64; 4]; N], impl AsRef<[[f64; 4]]>)> {
        None::<([[f64; 4]; N], [[f64; 4]; 0])>
    }
}

/// The task-space terms of `Γ = Jᵀ (M_x V̇ + h)`, in the platform's `N` coordinates: what the
/// joint-space inertia `M_q = Jᵀ M_x J` and a task-space controller read.
pub trait TaskSpace<const N: usize>: Legs<N> {
    /// `task_inertia_params`: `M_x`, symmetric positive definite.
    fn task_inertia(x: &[f64; N], p: &Self::Parameters) -> ([[f64; N]; N], impl AsRef<[f64]>);
    /// `task_bias_params`: `h`, the velocity and gravity terms.
    fn task_bias(x: &[f64; N], v: &[f64; N], p: &Self::Parameters)
        -> ([f64; N], impl AsRef<[f64]>);
}

/// The kernels of a legged mechanism whose platform is free in space: the inverse kinematics
/// with the vectors `B_i C`, and a step of the forward kinematics' Newton iteration.
pub trait Spatial: Legs<6> {
    /// `inverse_kinematics_params`: the actuator positions and the vectors `B_i C`.
    fn inverse_kinematics(
        x: &[f64; 6],
        p: &Self::Parameters,
    ) -> ([f64; 6], [[f64; 3]; 6], impl AsRef<[f64]>);
    /// `forward_kinematics_step_params`: the residual of `q` at `x`, the Newton step that
    /// cancels it to first order, and its solve's pivots and scale.
    fn forward_kinematics_step(
        x: &[f64; 6],
        q: &[f64; 6],
        p: &Self::Parameters,
    ) -> ([f64; 6], [f64; 6], [f64; 7], impl AsRef<[f64]>);
}

/// The dynamics' exact derivatives of a legged mechanism (feature `derivatives`), in the
/// platform's `N` coordinates: each kernel's value and its three Jacobians, row-major (row `i`
/// output `i`), from one generated kernel.
#[cfg(feature = "derivatives")]
pub trait Derivatives<const N: usize>: Legs<N> {
    /// `inverse_dynamics_derivatives_params`: `Γ`, `∂Γ/∂X`, `∂Γ/∂V`, `∂Γ/∂a`.
    #[allow(clippy::type_complexity)]
    fn inverse_dynamics_derivatives(
        x: &[f64; N],
        v: &[f64; N],
        a: &[f64; N],
        p: &Self::Parameters,
    ) -> (
        [f64; N],
        [[f64; N]; N],
        [[f64; N]; N],
        [[f64; N]; N],
        impl AsRef<[f64]>,
    );
    /// `forward_dynamics_derivatives_params`: `a`, `∂a/∂X`, `∂a/∂V`, `∂a/∂Γ`; its terms are
    /// those of the solve with `M_x` (the legs' hold is not among them).
    #[allow(clippy::type_complexity)]
    fn forward_dynamics_derivatives(
        x: &[f64; N],
        v: &[f64; N],
        gamma: &[f64; N],
        p: &Self::Parameters,
    ) -> (
        [f64; N],
        [[f64; N]; N],
        [[f64; N]; N],
        [[f64; N]; N],
        impl AsRef<[f64]>,
    );
}

/// The kernels of a legged mechanism whose forward kinematics is in closed form: the two
/// candidate poses of the actuator positions.
pub trait ClosedForm<const N: usize>: Legs<N> {
    /// What each term of `forward_kinematics_params`' guard measures.
    const FORWARD_KINEMATICS_TERMS: &'static [SingularityTerm];
    /// `forward_kinematics_params`: the two poses, and where they merge.
    fn forward_kinematics(q: &[f64; N], p: &Self::Parameters)
        -> ([[f64; N]; 2], impl AsRef<[f64]>);
}

/// The kinematic calibration's kernel of a legged mechanism: each leg's residual, and its
/// exact Jacobians in the leg's fitted geometry and in the pose.
pub trait Calibrated<const N: usize>: Legs<N> {
    /// A row of the Jacobian in the fitted geometry (`[f64; fitted per leg]`).
    type FittedRow: Copy + Default + core::fmt::Debug + AsRef<[f64]> + 'static;
    /// `calibration_residuals`: `ρ_i(X; θ) - q_i` of the readings `q` at the pose `x`, with
    /// the geometry and gravity of `p`; `∂/∂θ_i`, row `i` for leg `i`; `∂/∂X`.
    fn calibration_residuals(
        x: &[f64; N],
        q: &[f64; N],
        p: &Self::Parameters,
    ) -> ([f64; N], [Self::FittedRow; N], [[f64; N]; N]);
}

/// The identification kernels of a legged mechanism (feature `regressor`): its regressors over
/// the standard and the base parameters, which read the geometry and gravity of the parameter
/// vector, and what each base parameter groups.
pub trait Regressors<const N: usize>: Legs<N> {
    /// A row of the standard regressor (`[f64; STANDARD_PARAMETERS.len()]`).
    type StandardRow: Copy + core::fmt::Debug + AsRef<[f64]> + 'static;
    /// A row of the base regressor (`[f64; BASE_PARAMETERS.len()]`).
    type BaseRow: Copy + core::fmt::Debug + AsRef<[f64]> + 'static;
    /// The standard parameters, the columns of `regressor`.
    const STANDARD_PARAMETERS: &'static [&'static str];
    /// The base parameters, the columns of `base_regressor`.
    const BASE_PARAMETERS: &'static [&'static str];
    /// `β = B π`: each base parameter's terms `(standard index, coefficient)`.
    const BASE_OF_STANDARD: &'static [&'static [(usize, f64)]];
    /// `regressor`: `Γ = Y π`, row `i` for actuator `i+1`.
    fn regressor(
        x: &[f64; N],
        v: &[f64; N],
        a: &[f64; N],
        p: &Self::Parameters,
    ) -> ([Self::StandardRow; N], impl AsRef<[f64]>);
    /// `base_regressor`: `Γ = Y_b β`, row `i` for actuator `i+1`.
    fn base_regressor(
        x: &[f64; N],
        v: &[f64; N],
        a: &[f64; N],
        p: &Self::Parameters,
    ) -> ([Self::BaseRow; N], impl AsRef<[f64]>);
}

/// The first `G` numbers of the parameter vector `p`: the geometry and gravity, what the
/// regressors and the calibration read of it.
#[inline]
pub(crate) fn geometry<const G: usize, const P: usize>(p: &[f64; P]) -> [f64; G] {
    const { assert!(G <= P, "the geometry opens the parameter vector") };
    core::array::from_fn(|k| p[k])
}
