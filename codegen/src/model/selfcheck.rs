//! The generator checks its own output where it is cheap to: identities between the compiled
//! programs of one model, evaluated on seeded platform states.
//!
//! `J⁻¹ J = I`, `Q̇_a = J⁻¹ V`, `Γ = Jᵀ (F_{N+1} + Φ)`, `forward(Γ(V̇)) = V̇`, the forward
//! kinematics undoing the inverse, the platform state and the forces from the actuators'
//! motion equal to those of the pose, and `Γ = M_q Q̈_a + c_q`: kernels
//! built by different routes (the consistent model's `J` goes through a 3×3 solve, its `Γ`
//! through `S⁻ᵀ`, the forward dynamics through derivatives and an `LDLᵀ`) that must agree, or
//! the model or the engine has a bug.

use super::kernels::{Entry, Kernel};
use super::Mechanism;
use crate::error::Error;
use crate::kernel::Compiled;
use crate::numeric::Lcg;

/// The kernels of one mechanism and parameter variant, found by what they compute.
struct Kernels<'a> {
    mechanism: &'a Mechanism,
    names: Vec<String>,
    list: &'a [(&'a Entry, &'a Compiled)],
}

impl Kernels<'_> {
    /// Evaluates `kernel` on `motion` (pose, then twist and acceleration as it takes them), its
    /// `params` taken from the mechanism's description.
    ///
    /// # Errors
    /// [`Error::SelfCheck`] when the group has no such kernel: a kernel the check expects is
    /// missing (renamed or dropped from the table).
    fn eval(&self, kernel: Kernel, motion: &[&[f64]]) -> Result<Vec<f64>, Error> {
        let (entry, compiled) = self
            .list
            .iter()
            .find(|(e, _)| e.id.kernel == kernel)
            .ok_or_else(|| Error::SelfCheck {
                kernel: kernel.name().to_string(),
                check: "the kernel is missing from the generated set".to_string(),
            })?;
        let spec = &entry.spec;
        let values = &self.mechanism.parameters;
        let mut inputs = Vec::with_capacity(spec.input_len());
        for (k, arg) in spec.inputs.iter().enumerate() {
            if arg.name == "params" {
                inputs.extend(arg.elements.iter().map(|e| {
                    let i = self
                        .names
                        .iter()
                        .position(|n| n == e)
                        .expect("a parameter name");
                    values[i]
                }));
            } else {
                inputs.extend_from_slice(motion[k]);
            }
        }
        Ok(compiled.program.eval(&inputs))
    }
}

/// `R` (eq 15, row-major) and `C` of a pose `[α β γ xc yc zc]`.
fn rotation_and_centre(pose: &[f64]) -> Vec<f64> {
    let (sa, ca) = pose[0].sin_cos();
    let (sb, cb) = pose[1].sin_cos();
    let (sg, cg) = pose[2].sin_cos();
    vec![
        cb * cg,
        -cb * sg,
        sb,
        sg * ca + cg * sb * sa,
        ca * cg - sa * sb * sg,
        -cb * sa,
        sg * sa - cg * sb * ca,
        sa * cg + ca * sb * sg,
        cb * ca,
        pose[3],
        pose[4],
        pose[5],
    ]
}

fn close(got: f64, want: f64, scale: f64) -> bool {
    (got - want).abs() <= 1e-9 * scale.max(1.0)
}

/// Checks the identities between the kernels of one mechanism and parameter variant, on
/// seeded states of its workspace; those of the joint setting where its structure has them.
///
/// # Errors
/// [`Error::SelfCheck`] naming the kernel and the identity that fails, or a kernel the check
/// expects that is missing.
pub fn self_check(mechanism: &Mechanism, list: &[(&Entry, &Compiled)]) -> Result<(), Error> {
    let structure = mechanism.structure();
    let kernels = Kernels {
        mechanism,
        names: structure.parameter_names(),
        list,
    };
    let fail = |kernel: Kernel, check: String| Error::SelfCheck {
        kernel: kernel.name().to_string(),
        check,
    };
    if structure.actuators() == 3 {
        return translating(&kernels);
    }
    let joint_setting = structure.has_kernel(Kernel::ForwardKinematics);
    let mut rng = Lcg::new(0x00c5_c5c5);
    let l = structure.reach(&mechanism.parameters);
    let home = structure.home(&mechanism.parameters);
    for _ in 0..8 {
        let t = structure.turn_reach();
        let offset = rng.vector(&[t, t, t, 0.3 * l, 0.3 * l, 0.3 * l]);
        let pose: Vec<f64> = offset.iter().zip(&home).map(|(d, h)| h + d).collect();
        let twist = rng.vector(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]);
        let accel = rng.vector(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]);
        let q = kernels.eval(Kernel::InverseKinematics, &[&pose])?;
        if joint_setting {
            // The forward kinematics undoes the inverse: R and C of the pose from its Q.
            let placement = kernels.eval(Kernel::ForwardKinematics, &[&q[..6]])?;
            let want = rotation_and_centre(&pose);
            for (k, (&got, &want)) in placement.iter().zip(&want).enumerate() {
                if !close(got, want, 1.0) {
                    return Err(fail(
                        Kernel::ForwardKinematics,
                        format!("(R, C)[{k}] = {got} but the pose gives {want} at {pose:?}"),
                    ));
                }
            }
        }
        let jinv = kernels.eval(Kernel::InverseJacobianPose, &[&pose])?;
        let jac = kernels.eval(Kernel::JacobianPose, &[&pose])?;
        for i in 0..6 {
            for j in 0..6 {
                let product: f64 = (0..6).map(|k| jinv[6 * i + k] * jac[6 * k + j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                if !close(product, want, 1.0) {
                    return Err(fail(
                        Kernel::JacobianPose,
                        format!("(J⁻¹ J)[{i}][{j}] = {product} at pose {pose:?}"),
                    ));
                }
            }
        }
        let qd = kernels.eval(Kernel::JointVelocities, &[&pose, &twist])?;
        for i in 0..6 {
            let want: f64 = (0..6).map(|k| jinv[6 * i + k] * twist[k]).sum();
            if !close(qd[i], want, want.abs()) {
                return Err(fail(
                    Kernel::JointVelocities,
                    format!("Q̇_{} = {} but (J⁻¹ V) = {want}", i + 1, qd[i]),
                ));
            }
        }
        let full = [&pose[..], &twist[..], &accel[..]];
        let gamma = kernels.eval(Kernel::InverseDynamics, &full)?;
        let f = kernels.eval(Kernel::PlatformWrench, &full)?;
        let phi = kernels.eval(Kernel::LegWrench, &full)?;
        let scale = gamma.iter().fold(1.0_f64, |m, g| m.max(g.abs()));
        for i in 0..6 {
            let want: f64 = (0..6).map(|k| jac[6 * k + i] * (f[k] + phi[k])).sum();
            if !close(gamma[i], want, scale) {
                return Err(fail(
                    Kernel::InverseDynamics,
                    format!("Γ_{} = {} but Jᵀ (F + Φ) = {want}", i + 1, gamma[i]),
                ));
            }
        }
        // From what the encoders would measure, the same state and the same forces.
        let qd = &qd[..6];
        let qdd = kernels.eval(Kernel::JointAccelerations, &full)?;
        if !joint_setting {
            check_forward(&kernels, &pose, &twist, &accel, &gamma)?;
            continue;
        }
        let joint = [&q[..6], qd, &qdd[..6]];
        let state = kernels.eval(Kernel::PlatformState, &joint)?;
        for (k, want) in pose.iter().chain(&twist).chain(&accel).enumerate() {
            if !close(state[k], *want, want.abs()) {
                return Err(fail(
                    Kernel::PlatformState,
                    format!("state[{k}] = {} but the state is {want}", state[k]),
                ));
            }
        }
        let from_joints = kernels.eval(Kernel::InverseDynamicsJoint, &joint)?;
        let m_q = kernels.eval(Kernel::JointInertia, &[&q[..6]])?;
        let c_q = kernels.eval(Kernel::JointBias, &[&q[..6], qd])?;
        for i in 0..6 {
            let split: f64 = c_q[i] + (0..6).map(|k| m_q[6 * i + k] * qdd[k]).sum::<f64>();
            if !close(from_joints[i], gamma[i], scale) || !close(split, gamma[i], scale) {
                return Err(fail(
                    Kernel::InverseDynamicsJoint,
                    format!(
                        "Γ_{} = {} from the joints, {split} as M_q Q̈ + c_q, {} from the pose",
                        i + 1,
                        from_joints[i],
                        gamma[i]
                    ),
                ));
            }
        }
        check_forward(&kernels, &pose, &twist, &accel, &gamma)?;
    }
    Ok(())
}

/// `forward(Γ(V̇)) = V̇`.
fn check_forward(
    kernels: &Kernels<'_>,
    pose: &[f64],
    twist: &[f64],
    accel: &[f64],
    gamma: &[f64],
) -> Result<(), Error> {
    let back = kernels.eval(Kernel::ForwardDynamics, &[pose, twist, &gamma[..6]])?;
    let scale = accel.iter().fold(1.0_f64, |m, a| m.max(a.abs()));
    for k in 0..6 {
        if !close(back[k], accel[k], scale) {
            return Err(Error::SelfCheck {
                kernel: Kernel::ForwardDynamics.name().to_string(),
                check: format!("forward(Γ(V̇))[{k}] = {} but V̇[{k}] = {}", back[k], accel[k]),
            });
        }
    }
    Ok(())
}

/// The identities of a mechanism whose platform translates on three actuators (the Delta):
/// `J⁻¹ J = I`, `q̇ = J⁻¹ v_C`, `forward(Γ(a_C)) = a_C`, and one of the forward kinematics'
/// two points the position whose angles it was given.
fn translating(kernels: &Kernels<'_>) -> Result<(), Error> {
    let fail = |kernel: Kernel, check: String| Error::SelfCheck {
        kernel: kernel.name().to_string(),
        check,
    };
    let (mechanism, structure) = (kernels.mechanism, kernels.mechanism.structure());
    let l = structure.reach(&mechanism.parameters);
    let home = &structure.home(&mechanism.parameters)[3..];
    let mut rng = Lcg::new(0x00c5_c5c5);
    for _ in 0..8 {
        let offset = rng.vector(&[0.3 * l, 0.3 * l, 0.3 * l]);
        let position: Vec<f64> = offset.iter().zip(home).map(|(d, h)| h + d).collect();
        let velocity = rng.vector(&[0.5, 0.5, 0.5]);
        let accel = rng.vector(&[2.0, 2.0, 2.0]);
        let q = kernels.eval(Kernel::InverseKinematics, &[&position])?;
        let points = kernels.eval(Kernel::ForwardKinematics, &[&q[..3]])?;
        let found = points[..6].chunks(3).any(|p| {
            p.iter()
                .zip(&position)
                .all(|(got, want)| close(*got, *want, 1.0))
        });
        if !found {
            return Err(fail(
                Kernel::ForwardKinematics,
                format!("neither of {:?} is {position:?}", &points[..6]),
            ));
        }
        let jinv = kernels.eval(Kernel::InverseJacobianPose, &[&position])?;
        let jac = kernels.eval(Kernel::JacobianPose, &[&position])?;
        for i in 0..3 {
            for j in 0..3 {
                let product: f64 = (0..3).map(|k| jinv[3 * i + k] * jac[3 * k + j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                if !close(product, want, 1.0) {
                    return Err(fail(
                        Kernel::JacobianPose,
                        format!("(J⁻¹ J)[{i}][{j}] = {product} at {position:?}"),
                    ));
                }
            }
        }
        let qd = kernels.eval(Kernel::JointVelocities, &[&position, &velocity])?;
        for i in 0..3 {
            let want: f64 = (0..3).map(|k| jinv[3 * i + k] * velocity[k]).sum();
            if !close(qd[i], want, want.abs()) {
                return Err(fail(
                    Kernel::JointVelocities,
                    format!("q̇_{} = {} but (J⁻¹ v) = {want}", i + 1, qd[i]),
                ));
            }
        }
        let gamma = kernels.eval(Kernel::InverseDynamics, &[&position, &velocity, &accel])?;
        let back = kernels.eval(
            Kernel::ForwardDynamics,
            &[&position, &velocity, &gamma[..3]],
        )?;
        let scale = accel.iter().fold(1.0_f64, |m, a| m.max(a.abs()));
        for k in 0..3 {
            if !close(back[k], accel[k], scale) {
                return Err(fail(
                    Kernel::ForwardDynamics,
                    format!("forward(Γ(a))[{k}] = {} but a[{k}] = {}", back[k], accel[k]),
                ));
            }
        }
    }
    Ok(())
}
