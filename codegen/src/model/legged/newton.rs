//! The Newton step of a platform free in space's forward kinematics, which has no closed form:
//! the actuators' residual at a pose and the step that cancels it to first order, solved in the
//! kernel (straight-line `LDLᵀ` of the normal equations), so the runtime's iteration only adds
//! the step and compares residuals.

use super::super::kernels::{jacobian_wrt, Build, Cite, Decl, Guard, Input, Kernel, Output, Reads};
use super::super::Quantity;
use crate::kernel::Shape;
use crate::linalg::{Mat6, Vec6, Vector};

/// `r = q − q(X)` and the step `δ` of `(∂q/∂X) δ = r`, by `LDLᵀ` of `(∂q/∂X)ᵀ (∂q/∂X)`, with
/// that factorization's pivots and the trace of `(∂q/∂X)ᵀ (∂q/∂X)`: the runtime refuses the
/// step where a pivot is not above a tolerance of the trace (the pose's Jacobian singular to
/// that precision).
pub const STEP: Decl = Decl {
    kernel: Kernel::ForwardKinematicsStep,
    title: "A Newton step of the forward kinematics: the actuators' residual at a pose and \
            the step of the pose that cancels it to first order.",
    doc: "`r = q - q(X)` and `δ` of `(∂q/∂X) δ = r` (`∂q/∂X`: `J⁻¹` times the map from the \
          pose's rates to the twist, columns `α β γ xc yc zc`), solved through the normal \
          equations by an unrolled `LDLᵀ`. The runtime steps to `X + δ`, from the previous \
          solution or the home pose, until the residual is below its tolerance.",
    equations: Cite::Model(Quantity::InverseJacobian),
    inputs: &[Input::Pose, Input::Actuators],
    outputs: &[
        Output {
            name: "residual",
            shape: Shape::Vector(6),
            doc: "`q - q(X)`: the given actuator positions less those of the pose (the \
                  actuators' unit: m, rad)",
        },
        Output {
            name: "step",
            shape: Shape::Vector(6),
            doc: "`δ`, the step of the pose `[α β γ xc yc zc]` (rad, m)",
        },
        Output {
            name: "conditioning",
            shape: Shape::Vector(7),
            doc: "the pivots of the `LDLᵀ` of `(∂q/∂X)ᵀ (∂q/∂X)`, then its trace: the step \
                  is meaningless where a pivot is not above a small fraction of the trace",
        },
    ],
    guard: Guard::Pose,
    reads: Reads::Robot,
    batch: false,
    chapter: None,
    build: Build::Robot(|cx| {
        let posed = cx.posed();
        let (q, x) = (cx.input(Input::Actuators), cx.input(Input::Pose));
        let residual: Vec6 = Vector::from_fn(|i| q[i] - posed.q[i]);
        let jacobian: Mat6 = jacobian_wrt(cx.graph(), &posed.q, &x);
        let normal = jacobian.transpose() * jacobian;
        let (step, pivots) = normal.ldlt_solve_with_pivots(&(jacobian.transpose() * residual));
        let trace = (1..6).fold(normal.0[0][0], |sum, i| sum + normal.0[i][i]);
        let conditioning = pivots.0.iter().copied().chain([trace]).collect();
        vec![residual.to_vec(), step.to_vec(), conditioning]
    }),
};

/// Holds a mechanism's compiled [`STEP`] to its own inverse kinematics `ik` near `pose`: zero
/// residual and step at the pose of the positions given; near it, `(∂q/∂X) δ = r` with
/// `∂q/∂X` by central differences of the residual, a step that shrinks the residual
/// quadratically, positive pivots whose product is `det(∂q/∂X)²`, and the trace.
#[cfg(test)]
pub(crate) fn check_step(ik: &crate::Program, step: &crate::Program, pose: &[f64]) {
    let q = ik.eval(pose)[..6].to_vec();
    let at = |x: &[f64]| step.eval(&[x, &q[..]].concat());
    assert!(
        at(pose)[..12].iter().all(|v| v.abs() < 1e-14),
        "{:?}",
        at(pose)
    );
    let start: Vec<f64> = pose
        .iter()
        .zip([2e-3, -1e-3, 3e-3, 1e-3, -2e-3, 1e-3])
        .map(|(x, d)| x + d)
        .collect();
    let out = at(&start);
    let (r, delta, conditioning) = (&out[..6], &out[6..12], &out[12..19]);
    let h = 1e-6;
    let jacobian = nalgebra::Matrix6::from_fn(|i, j| {
        let (mut up, mut down) = (start.clone(), start.clone());
        up[j] += h;
        down[j] -= h;
        -(at(&up)[i] - at(&down)[i]) / (2.0 * h)
    });
    let size = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let cancelled = jacobian * nalgebra::Vector6::from_column_slice(delta);
    let gap: Vec<f64> = (0..6).map(|i| cancelled[i] - r[i]).collect();
    assert!(
        size(&gap) < 1e-7 * size(r),
        "(∂q/∂X) δ - r = {gap:?}, r = {r:?}"
    );
    let next: Vec<f64> = start.iter().zip(delta).map(|(x, d)| x + d).collect();
    let after = size(&at(&next)[..6]);
    assert!(
        after < 10.0 * size(r) * size(r),
        "Newton's step shrinks r quadratically: {after:e} from {:e}",
        size(r)
    );
    let pivots = &conditioning[..6];
    assert!(pivots.iter().all(|&d| d > 0.0), "{pivots:?}");
    let det = jacobian.determinant();
    let product: f64 = pivots.iter().product();
    assert!(
        (product - det * det).abs() < 1e-5 * det * det,
        "{product} vs {}",
        det * det
    );
    let trace = (jacobian.transpose() * jacobian).trace();
    assert!((conditioning[6] - trace).abs() < 1e-6 * trace);
}
