//! The dynamics' exact derivatives, for optimal control and estimation: each kernel returns the
//! value and its Jacobians with respect to the state and the input, built by the engine's
//! exact differentiation on the same graph as the value, so they share every subexpression.
//!
//! The inverse dynamics is differentiated directly. The forward dynamics is not (its solve
//! would be differentiated term by term): its result `a` is the root of `ID(X, V, a) = Γ`, so
//! the implicit function theorem gives its Jacobians from partial derivatives taken at the `a`
//! found, the acceleration a free unknown while differentiating and replaced by `a` after.
//! Two routes, the model picks ([`Mechanics::forward_dynamics_jacobians`]): through the
//! task-space residual and `M_x` ([`by_task_residual`], the paper model, which solves with
//! `M_x`), or through the inverse dynamics and the model's own solve ([`by_inverse_dynamics`],
//! the consistent model, whose forward dynamics is solved by blocks in the platform frame).
//! Each is the cheaper for its model: 5 600 against 7 200 operations (paper), 4 800 against
//! 6 500 (consistent).

use super::bodies::Dynamics;
use super::geometry::{Motion, Posed};
use super::kernels::{Build, Cite, Context, Decl, Guard, Input, Kernel, Output, Reads};
use super::{Mechanics, Quantity, INTERNAL_INPUTS};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Vec6, Vector};

/// Whether `kernel` is one of the derivative kernels (a model's, or a mechanism's own), which
/// the crate puts in its feature-gated file.
pub fn is_derivative(kernel: Kernel) -> bool {
    matches!(
        kernel,
        Kernel::InverseDynamicsDerivatives
            | Kernel::ForwardDynamicsDerivatives
            | Kernel::InverseDynamicsJointDerivatives
    )
}

/// `Γ` and its Jacobians with respect to each of the kernel's inputs, in their order, by the
/// model's own method ([`Mechanics::inverse_dynamics_jacobians`]).
fn inverse_dynamics_and_jacobians<'g>(
    cx: &Context<'_, 'g>,
    inputs: &[Input],
) -> Vec<Vec<Expr<'g>>> {
    let (posed, motion) = (cx.posed(), cx.motion());
    let gamma = cx.mech.inverse_dynamics(cx.dynamics, &posed, &motion);
    let wrt: Vec<Vec<Expr<'g>>> = inputs.iter().map(|&kind| cx.input(kind)).collect();
    let jacobians = cx
        .mech
        .inverse_dynamics_jacobians(cx.dynamics, &posed, &motion, &gamma, &wrt);
    std::iter::once(gamma.to_vec()).chain(jacobians).collect()
}

/// `∂Γ/∂x` (row-major, `n × xs.len()` for each of `wrt`) of an inverse dynamics that solves
/// `J⁻ᵀ(X) Γ = W(X, V, a)`, by the implicit function theorem on the task-space residual
/// `r = W - J⁻ᵀ Γ̃`: `∂Γ/∂x = J⁻ᵀ⁻¹ ∂r/∂x` at `Γ̃ = Γ`, every column through `solve`, the
/// kernel's own solve of `J⁻ᵀ` (its factorisation shared). Differentiating `Γ` directly
/// differentiates the factorisation too. `known` gives `∂r/∂x` for an input `x` where the
/// model builds it more cheaply than the engine differentiates it (`M_x`, for the
/// acceleration).
pub fn by_wrench_residual<'g>(
    wrench: &[Expr<'g>],
    inverse_jacobian_transposed: impl Fn(&[Expr<'g>]) -> Vec<Expr<'g>>,
    gamma: &[Expr<'g>],
    solve: impl Fn(&[Expr<'g>]) -> Vec<Expr<'g>>,
    known: impl Fn(Expr<'g>) -> Option<Vec<Expr<'g>>>,
    wrt: &[Vec<Expr<'g>>],
) -> Vec<Vec<Expr<'g>>> {
    let g = gamma[0].graph();
    let n = gamma.len();
    // Past the accelerations' unknowns, which `known`'s `M_x` may be built with.
    let unknown: Vec<Expr<'g>> = (0..n)
        .map(|k| g.input(INTERNAL_INPUTS + 64 + k as u32))
        .collect();
    let held = inverse_jacobian_transposed(&unknown);
    let residual: Vec<Expr<'g>> = wrench.iter().zip(&held).map(|(&w, &h)| w - h).collect();
    let at_solution: Vec<(Expr<'g>, Expr<'g>)> =
        unknown.iter().copied().zip(gamma.iter().copied()).collect();
    let given: Vec<Vec<Option<Vec<Expr<'g>>>>> = wrt
        .iter()
        .map(|xs| xs.iter().map(|&x| known(x)).collect())
        .collect();
    let differentiated: Vec<Expr<'g>> = wrt
        .iter()
        .flatten()
        .zip(given.iter().flatten())
        .filter_map(|(&x, column)| column.is_none().then_some(x))
        .collect();
    let mut partials = columns_at(&residual, &differentiated, &at_solution).into_iter();
    given
        .into_iter()
        .map(|columns| {
            let columns: Vec<Vec<Expr<'g>>> = columns
                .into_iter()
                .map(|column| solve(&column.unwrap_or_else(|| partials.next().expect("a column"))))
                .collect();
            (0..n)
                .flat_map(|i| columns.iter().map(move |c| c[i]))
                .collect()
        })
        .collect()
}

/// The columns `∂f/∂x` for each of `xs`, with the free unknowns then replaced by their values
/// `at_solution`.
fn columns_at<'g>(
    f: &[Expr<'g>],
    xs: &[Expr<'g>],
    at_solution: &[(Expr<'g>, Expr<'g>)],
) -> Vec<Vec<Expr<'g>>> {
    let Some(&first) = f.first() else {
        return vec![];
    };
    let g = first.graph();
    let rows = g.substitute(&g.jacobian(f, xs), at_solution);
    let m = xs.len();
    (0..m)
        .map(|j| (0..f.len()).map(|i| rows[i * m + j]).collect())
        .collect()
}

/// The inputs the forward dynamics' Jacobians are taken with respect to: the elements of the
/// kernel's pose, twist and force inputs.
pub struct ForwardInputs<'a, 'g> {
    pub pose: &'a [Expr<'g>],
    pub twist: &'a [Expr<'g>],
    pub forces: &'a [Expr<'g>],
}

/// `∂a/∂X`, `∂a/∂V`, `∂a/∂Γ` (row-major 6×6 each) of `accel`, the forward dynamics of `mech`,
/// by the implicit function theorem on the task-space residual
/// `r = W(X, V, a) - J⁻ᵀ(X) Γ` (`W` the wrench the platform needs): `∂a/∂x = -M_x⁻¹ ∂r/∂x`,
/// `∂a/∂Γ = M_x⁻¹ J⁻ᵀ`, every solve through one `LDLᵀ` of `M_x`. The partial derivatives of `r`
/// are taken with the acceleration as six free unknowns, then replaced by `accel`. The default
/// of [`Mechanics::forward_dynamics_jacobians`],
/// for models that solve with `M_x` themselves.
pub fn by_task_residual<'g, M: Mechanics + ?Sized>(
    mech: &M,
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    gamma: &Vec6<'g>,
    accel: &Vec6<'g>,
    wrt: &ForwardInputs<'_, 'g>,
) -> [Vec<Expr<'g>>; 3] {
    let g = accel[0].graph();
    let unknown = free_acceleration(g);
    let jinv_t = mech.inverse_jacobian(posed).transpose();
    let residual = (mech.task_wrench(dynamics, posed, &Motion::new(*twist, unknown))
        - jinv_t * *gamma)
        .to_vec();
    let at_solution: Vec<(Expr<'g>, Expr<'g>)> =
        unknown.0.into_iter().zip(accel.0.map(Expr::keep)).collect();
    let inertia = mech.task_inertia(dynamics, posed);
    let sensitivity =
        |dr: &[Expr<'g>]| -> Vec6<'g> { -inertia.ldlt_solve(&Vector::from_fn(|i| dr[i])) };
    let columns = |xs: &[Expr<'g>]| {
        from_columns(
            &columns_at(&residual, xs, &at_solution)
                .iter()
                .map(|dr| sensitivity(dr))
                .collect::<Vec<_>>(),
        )
    };
    let d_gamma: Vec<Vec6<'g>> = (0..6)
        .map(|j| inertia.ldlt_solve(&jinv_t.column(j)))
        .collect();
    [
        columns(wrt.pose),
        columns(wrt.twist),
        from_columns(&d_gamma),
    ]
}

/// The same Jacobians for a model whose forward dynamics is its own structured solve:
/// `∂a/∂Γ = M_x⁻¹ J⁻ᵀ` is the exact derivative of `accel` (affine in the forces), built from
/// that solve; and since `ID(X, V, a) = Γ` at the solution, `∂a/∂x = -(∂a/∂Γ) ∂ID/∂x`, the
/// inverse dynamics differentiated with the acceleration as free unknowns, then replaced by
/// `accel`. Two 6×6 products and no other solve.
pub fn by_inverse_dynamics<'g, M: Mechanics + ?Sized>(
    mech: &M,
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    accel: &Vec6<'g>,
    wrt: &ForwardInputs<'_, 'g>,
) -> [Vec<Expr<'g>>; 3] {
    let g = accel[0].graph();
    let d_gamma = g.jacobian(&accel.to_vec(), wrt.forces);
    let unknown = free_acceleration(g);
    let gamma = mech
        .inverse_dynamics(dynamics, posed, &Motion::new(*twist, unknown))
        .to_vec();
    let implicit = Implicit {
        d_gamma: &d_gamma,
        gamma: &gamma,
        unknown: &unknown.to_vec(),
        accel: &accel.to_vec(),
    };
    [
        implicit.jacobian(wrt.pose),
        implicit.jacobian(wrt.twist),
        d_gamma,
    ]
}

/// The forward dynamics' `a` as the root of `ID(x, a) = Γ`, for its Jacobians by the implicit
/// function theorem: `∂a/∂x = -(∂a/∂Γ) ∂ID/∂x`, in any dimension `n`.
pub(crate) struct Implicit<'a, 'g> {
    /// `∂a/∂Γ`, row-major `n × n`: the exact derivative of the forward dynamics' own solve.
    pub d_gamma: &'a [Expr<'g>],
    /// The inverse dynamics with the acceleration as the free `unknown`s.
    pub gamma: &'a [Expr<'g>],
    pub unknown: &'a [Expr<'g>],
    /// The forward dynamics' acceleration, put in for the unknowns after differentiating.
    pub accel: &'a [Expr<'g>],
}

impl<'g> Implicit<'_, 'g> {
    /// `∂a/∂x` for each of `xs`, row-major (`n × xs.len()`).
    pub fn jacobian(&self, xs: &[Expr<'g>]) -> Vec<Expr<'g>> {
        let n = self.gamma.len();
        let g = self.gamma[0].graph();
        let at_solution: Vec<(Expr<'g>, Expr<'g>)> = self
            .unknown
            .iter()
            .copied()
            .zip(self.accel.iter().copied())
            .collect();
        let partial = g.substitute(&g.jacobian(self.gamma, xs), &at_solution);
        let m = xs.len();
        (0..n * m)
            .map(|ij| {
                let (i, j) = (ij / m, ij % m);
                -(0..n)
                    .map(|k| self.d_gamma[n * i + k] * partial[m * k + j])
                    .fold(g.zero(), |sum, term| sum + term)
            })
            .collect()
    }
}

/// Six fresh unknowns for the platform's acceleration.
fn free_acceleration(g: &Graph) -> Vec6<'_> {
    Vector(std::array::from_fn(|k| g.input(INTERNAL_INPUTS + k as u32)))
}

/// Row-major 6×6 from six columns.
fn from_columns<'g>(columns: &[Vec6<'g>]) -> Vec<Expr<'g>> {
    (0..6)
        .flat_map(|i| columns.iter().map(move |c| c[i]))
        .collect()
}

/// `a`, `∂a/∂X`, `∂a/∂V`, `∂a/∂Γ`, by the model's own method.
fn forward_dynamics_and_jacobians<'g>(cx: &Context<'_, 'g>) -> Vec<Vec<Expr<'g>>> {
    let (mech, dynamics) = (cx.mech, cx.dynamics);
    let posed = cx.posed();
    let twist = cx.motion().twist;
    let gamma = cx.forces();
    let accel = mech.forward_dynamics(dynamics, &posed, &twist, &gamma);
    let (pose, velocity, forces) = (
        cx.input(Input::Pose),
        cx.input(Input::Twist),
        cx.input(Input::Gamma),
    );
    let wrt = ForwardInputs {
        pose: &pose,
        twist: &velocity,
        forces: &forces,
    };
    let [d_pose, d_twist, d_gamma] =
        mech.forward_dynamics_jacobians(dynamics, &posed, &twist, &gamma, &accel, &wrt);
    vec![accel.to_vec(), d_pose, d_twist, d_gamma]
}

const fn jacobian(name: &'static str, doc: &'static str) -> Output {
    Output {
        name,
        shape: Shape::Matrix(6, 6),
        doc,
    }
}

/// The derivative kernels every model is generated into (feature `derivatives` of
/// `c5-generated`, `f64` only).
pub const KERNELS: [Decl; 3] = [
    Decl {
        kernel: Kernel::InverseDynamicsDerivatives,
        title: "Inverse dynamics and its exact Jacobians: `Γ`, `∂Γ/∂X`, `∂Γ/∂V`, `∂Γ/∂(ω̇; a_C)`.",
        doc: "Row `i` of each Jacobian is actuator `i+1`; its columns are the components of the \
              input in its own order (`α β γ xc yc zc`; `ωx ωy ωz vx vy vz`; `ω̇x ω̇y ω̇z ax ay az`). \
              `∂Γ/∂(ω̇; a_C) = Jᵀ M_x`.",
        equations: Cite::Model(Quantity::InverseDynamics),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[
            Output {
                name: "gamma",
                shape: Shape::Vector(6),
                doc: "`Γ` (N), segment order",
            },
            jacobian("d_pose", "`∂Γ/∂X` (N/rad, N/m)"),
            jacobian("d_twist", "`∂Γ/∂V` (N·s/rad, N·s/m)"),
            jacobian("d_accel", "`∂Γ/∂(ω̇; a_C)` (N·s²/rad, kg)"),
        ],
        guard: Guard::Solve,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            inverse_dynamics_and_jacobians(cx, &[Input::Pose, Input::Twist, Input::Accel])
        }),
    },
    Decl {
        kernel: Kernel::ForwardDynamicsDerivatives,
        title: "Forward dynamics and its exact Jacobians: `a = (ω̇; a_C)`, `∂a/∂X`, `∂a/∂V`, \
                `∂a/∂Γ`.",
        doc: "Rows `ω̇x ω̇y ω̇z ax ay az`; columns the components of the input in its own order \
              (`α β γ xc yc zc`; `ωx ωy ωz vx vy vz`; `Γ1 … Γ6`). `∂a/∂Γ = M_x⁻¹ J⁻ᵀ`; by the \
              implicit function theorem on `ID(X, V, a) = Γ`, `∂a/∂X = -(∂a/∂Γ) ∂ID/∂X`.",
        equations: Cite::Model(Quantity::ForwardDynamics),
        inputs: &[Input::Pose, Input::Twist, Input::Gamma],
        outputs: &[
            Output {
                name: "accel",
                shape: Shape::Vector(6),
                doc: "classical platform acceleration `(ω̇; a_C)` (rad/s², m/s²), base frame",
            },
            jacobian("d_pose", "`∂a/∂X`"),
            jacobian("d_twist", "`∂a/∂V`"),
            jacobian("d_gamma", "`∂a/∂Γ` (rad/s²/N, m/s²/N)"),
        ],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(forward_dynamics_and_jacobians),
    },
    Decl {
        kernel: Kernel::InverseDynamicsJointDerivatives,
        title: "Inverse dynamics from the actuators' motion and its exact Jacobians: `Γ`, \
                `∂Γ/∂q`, `∂Γ/∂q̇`, `∂Γ/∂q̈`.",
        doc: "Row `i` of each Jacobian is actuator `i+1`, column `j` actuator `j+1`. \
              `∂Γ/∂q̈ = M_q`.",
        equations: Cite::Model(Quantity::InverseDynamics),
        inputs: &[
            Input::Actuators,
            Input::ActuatorRates,
            Input::ActuatorAccelerations,
        ],
        outputs: &[
            Output {
                name: "gamma",
                shape: Shape::Vector(6),
                doc: "`Γ` (N), segment order",
            },
            jacobian("d_q", "`∂Γ/∂q` (N/m)"),
            jacobian("d_qd", "`∂Γ/∂q̇` (N·s/m)"),
            jacobian("d_qdd", "`∂Γ/∂q̈ = M_q` (kg)"),
        ],
        guard: Guard::Forward,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| {
            inverse_dynamics_and_jacobians(
                cx,
                &[
                    Input::Actuators,
                    Input::ActuatorRates,
                    Input::ActuatorAccelerations,
                ],
            )
        }),
    },
];

#[cfg(test)]
mod tests {
    use super::super::kernels::derivative_specs;
    use crate::{Mechanism, Model, ParameterSet, Robot};

    /// Each Jacobian against central differences of the kernel's own value, both models.
    #[test]
    fn the_jacobians_are_the_derivatives_of_the_value() {
        let point: [f64; 18] = [
            0.17, -0.26, 0.35, 0.01, -0.02, 0.03, 0.3, -0.2, 0.1, 0.05, 0.02, -0.01, 40.0, -20.0,
            15.0, 30.0, 80.0, 95.0,
        ];
        let paper = Mechanism::c5(&Robot::default(), Model::Paper);
        let ik = super::super::kernels::specs(&paper, &ParameterSet::None, "")
            .unwrap()
            .into_iter()
            .find(|e| e.id.kernel == super::super::kernels::Kernel::InverseKinematics)
            .unwrap()
            .spec
            .compile()
            .unwrap()
            .program;
        for model in Model::ALL {
            let mechanism = Mechanism::c5(&Robot::default(), model);
            for entry in derivative_specs(&mechanism, &ParameterSet::None, "").unwrap() {
                let started = std::time::Instant::now();
                let compiled = entry.spec.compile().unwrap();
                eprintln!(
                    "{model} {}: {} ({:.1?})",
                    entry.spec.name,
                    compiled.count,
                    started.elapsed()
                );
                // Joint inputs: the actuator positions of the pose above, plausible rates.
                let inputs: Vec<f64> = if entry.spec.name.contains("joint") {
                    let q = &ik.eval(&point[..6])[..6];
                    q.iter()
                        .chain(&[0.1, -0.05, 0.2, 0.0, 0.03, -0.1])
                        .chain(&[1.0, -0.5, 0.2, 0.3, -0.7, 0.4])
                        .copied()
                        .collect()
                } else {
                    point.to_vec()
                };
                let program = &compiled.program;
                let at = |x: &[f64]| program.eval(x);
                let base = at(&inputs);
                for block in 0..3 {
                    for j in 0..6 {
                        let k = 6 * block + j;
                        let h = 1e-6 * inputs[k].abs().max(1.0);
                        let (mut up, mut down) = (inputs.clone(), inputs.clone());
                        up[k] += h;
                        down[k] -= h;
                        let (fu, fd) = (at(&up), at(&down));
                        for i in 0..6 {
                            let numeric = (fu[i] - fd[i]) / (2.0 * h);
                            let exact = base[6 + 36 * block + 6 * i + j];
                            assert!(
                                (exact - numeric).abs() <= 1e-6 * exact.abs().max(1.0),
                                "{model} {}: block {block}, ∂{i}/∂{j}: {exact} vs {numeric}",
                                entry.spec.name
                            );
                        }
                    }
                }
            }
        }
    }
}
