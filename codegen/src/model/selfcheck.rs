//! The generator checks its own output where it is cheap to: identities between the compiled
//! programs of one model, evaluated on seeded platform states.
//!
//! `J⁻¹ J = I`, `Q̇_a = J⁻¹ V`, `Γ = Jᵀ (F_{N+1} + Φ)` and `forward(Γ(V̇)) = V̇`: kernels
//! built by different routes (the consistent model's `J` goes through a 3×3 solve, its `Γ`
//! through `S⁻ᵀ`, the forward dynamics through derivatives and an `LDLᵀ`) that must agree, or
//! the model or the engine has a bug.

use crate::error::Error;
use crate::kernel::{Compiled, KernelSpec};
use crate::numeric::Lcg;
use c5_robot::Robot;

/// A small deterministic generator, so the check needs no dependency and never varies.
struct Kernels<'a> {
    robot: &'a Robot,
    list: &'a [(&'a KernelSpec, &'a Compiled)],
    suffix: &'a str,
}

impl Kernels<'_> {
    /// Evaluates kernel `base` (with the group's suffix) on `motion` (pose, then twist and
    /// acceleration as it takes them), its `params` taken from the robot. `None` if the group
    /// has no such kernel.
    fn eval(&self, base: &str, motion: &[&[f64]]) -> Option<Vec<f64>> {
        let name = format!("{base}{}", self.suffix);
        let (spec, compiled) = self.list.iter().find(|(s, _)| s.name == name)?;
        let values = self.robot.kernel_parameters();
        let names = Robot::<f64>::kernel_parameter_names();
        let mut inputs = Vec::with_capacity(spec.input_len());
        for (k, arg) in spec.inputs.iter().enumerate() {
            if arg.name == "params" {
                inputs.extend(arg.elements.iter().map(|e| {
                    let i = names.iter().position(|n| n == e).expect("a parameter name");
                    values[i]
                }));
            } else {
                inputs.extend_from_slice(motion[k]);
            }
        }
        Some(compiled.program.eval(&inputs))
    }
}

fn close(got: f64, want: f64, scale: f64) -> bool {
    (got - want).abs() <= 1e-9 * scale.max(1.0)
}

/// Checks the identities between the kernels of one model and parameter set (`suffix` is
/// appended to their names), on seeded states of `robot`'s workspace.
///
/// # Errors
/// [`Error::SelfCheck`] naming the kernel and the identity that fails.
pub fn self_check(
    robot: &Robot,
    list: &[(&KernelSpec, &Compiled)],
    suffix: &str,
) -> Result<(), Error> {
    let kernels = Kernels {
        robot,
        list,
        suffix,
    };
    let fail = |kernel: &str, check: String| Error::SelfCheck {
        kernel: format!("{kernel}{suffix}"),
        check,
    };
    let mut rng = Lcg::new(0x00c5_c5c5);
    let l = robot.half_spacing;
    for _ in 0..8 {
        let pose = rng.vector(&[0.4, 0.4, 0.4, 0.3 * l, 0.3 * l, 0.3 * l]);
        let twist = rng.vector(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]);
        let accel = rng.vector(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]);
        let (Some(jinv), Some(jac)) = (
            kernels.eval("inverse_jacobian_pose", &[&pose]),
            kernels.eval("jacobian_pose", &[&pose]),
        ) else {
            continue;
        };
        for i in 0..6 {
            for j in 0..6 {
                let product: f64 = (0..6).map(|k| jinv[6 * i + k] * jac[6 * k + j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                if !close(product, want, 1.0) {
                    return Err(fail(
                        "jacobian_pose",
                        format!("(J⁻¹ J)[{i}][{j}] = {product} at pose {pose:?}"),
                    ));
                }
            }
        }
        if let Some(qd) = kernels.eval("joint_velocities", &[&pose, &twist]) {
            for i in 0..6 {
                let want: f64 = (0..6).map(|k| jinv[6 * i + k] * twist[k]).sum();
                if !close(qd[i], want, want.abs()) {
                    return Err(fail(
                        "joint_velocities",
                        format!("Q̇_{} = {} but (J⁻¹ V) = {want}", i + 1, qd[i]),
                    ));
                }
            }
        }
        let full = [&pose[..], &twist[..], &accel[..]];
        if let (Some(gamma), Some(f), Some(phi)) = (
            kernels.eval("inverse_dynamics", &full),
            kernels.eval("platform_wrench", &full),
            kernels.eval("leg_wrench", &full),
        ) {
            let scale = gamma.iter().fold(1.0_f64, |m, g| m.max(g.abs()));
            for i in 0..6 {
                let want: f64 = (0..6).map(|k| jac[6 * k + i] * (f[k] + phi[k])).sum();
                if !close(gamma[i], want, scale) {
                    return Err(fail(
                        "inverse_dynamics",
                        format!("Γ_{} = {} but Jᵀ (F + Φ) = {want}", i + 1, gamma[i]),
                    ));
                }
            }
            if let Some(back) = kernels.eval("forward_dynamics", &[&pose, &twist, &gamma[..6]]) {
                let scale = accel.iter().fold(1.0_f64, |m, a| m.max(a.abs()));
                for k in 0..6 {
                    if !close(back[k], accel[k], scale) {
                        return Err(fail(
                            "forward_dynamics",
                            format!("forward(Γ(V̇))[{k}] = {} but V̇[{k}] = {}", back[k], accel[k]),
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}
