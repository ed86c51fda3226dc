//! Kinematic calibration's kernel, for every legged mechanism: the legs' residuals
//! `r_i = q_i(X; θ) - q̂_i` at a measured pose `X` and readings `q̂`, and their exact Jacobians
//! with respect to each leg's fitted geometry ([`c5_robot::calibration`]) and to the pose.
//!
//! The mechanism gives its actuators' closed forms `q_i(X; θ)` on the kernel's inputs; this
//! module differentiates them. Leg `i`'s actuator reads its own geometry alone, so row `i` of
//! the geometry Jacobian holds the derivatives with respect to leg `i`'s fitted entries.

use super::kernels::Kernel;
use super::kernels::{Build, Cite, Decl, Guard, Input, Output, Reads, RobotBuild};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Vec3, Vector};
use c5_robot::calibration::Fitted;

/// The first index of the balls' symbols the derivation builds on; none survives in a kernel.
const BALL_SYMBOLS: u32 = 1 << 28;

/// What the residuals are built from: per leg, the point `B_i` through which the pose
/// reaches its actuator (its platform joint's centre) as an expression of the kernel's inputs,
/// and the actuator's closed form at any such point.
pub struct Legs<'a, 'g> {
    pub balls: Vec<Vec3<'g>>,
    pub actuator: &'a dyn Fn(usize, &Vec3<'g>) -> Expr<'g>,
    /// Leg `i`'s entries of the geometry.
    pub geometry: &'a dyn Fn(usize) -> Vec<Expr<'g>>,
}

/// The kernel's three results: the residuals, the geometry Jacobian (row `i`: `∂q_i/∂θ_i`,
/// one column per fitted parameter) and the pose Jacobian `∂q/∂X`.
///
/// Each actuator is differentiated on a symbol `B̂_i` for its ball, then by the chain rule:
/// `∂q_i/∂θ = ∂q̂_i/∂θ + ∇_B q̂_i · ∂B_i/∂θ` and `∂q_i/∂X = ∇_B q̂_i · ∂B_i/∂X`, so that
/// the pose's derivatives do not run through the legs' closed forms again.
pub fn residuals<'g>(
    g: &'g Graph,
    legs: &Legs<'_, 'g>,
    readings: &[Expr<'g>],
    pose: &[Expr<'g>],
    fitted: &[Fitted],
) -> Vec<Vec<Expr<'g>>> {
    let n = legs.balls.len();
    let mut values = Vec::with_capacity(3 * n);
    let mut residual = Vec::with_capacity(n);
    let mut geometry = Vec::with_capacity(n * fitted.len());
    let mut by_pose = Vec::with_capacity(n * pose.len());
    for (i, ball) in legs.balls.iter().enumerate() {
        let symbol: Vec3<'g> = Vector::from_fn(|k| g.input(BALL_SYMBOLS + (3 * i + k) as u32));
        values.extend((0..3).map(|k| (symbol[k], ball[k])));
        let q = (legs.actuator)(i, &symbol);
        let gradient: Vec<Expr<'g>> = (0..3)
            .map(|k| g.derivatives(&[q], symbol[k])[0].keep())
            .collect();
        let through_ball = |x: Expr<'g>| {
            (0..3).fold(g.zero(), |sum, k| {
                sum + gradient[k] * g.derivatives(&[ball[k]], x)[0]
            })
        };
        let at = (legs.geometry)(i);
        residual.push(q - readings[i]);
        geometry.extend(fitted.iter().map(|f| {
            let x = at[f.entry];
            g.derivatives(&[q], x)[0] + through_ball(x)
        }));
        by_pose.extend(pose.iter().map(|&x| through_ball(x)));
    }
    [residual, geometry, by_pose]
        .into_iter()
        .map(|exprs| g.substitute(&exprs, &values))
        .collect()
}

/// The residual kernel of a mechanism: `inputs` its pose's kind then the actuators,
/// `outputs` made by [`outputs`], and `build` calling [`residuals`] with the mechanism's
/// closed forms.
pub const fn decl(
    doc: &'static str,
    inputs: &'static [Input],
    outputs: &'static [Output],
    build: RobotBuild,
) -> Decl {
    Decl {
        kernel: Kernel::CalibrationResiduals,
        title: "Kinematic calibration: the legs' residuals at a measured pose, and their exact \
                Jacobians with respect to each leg's geometry and to the pose.",
        doc,
        equations: Cite::Fixed(&["r = q(X; θ) - q̂", "∂q/∂θ", "∂q/∂X"]),
        inputs,
        outputs,
        guard: Guard::Never,
        reads: Reads::Geometry,
        batch: false,
        chapter: None,
        build: Build::Robot(build),
    }
}

/// The kernel's outputs for `legs` actuators, `fitted` parameters per leg and `freedom` pose
/// coordinates, their documentation naming the columns.
pub const fn outputs(
    legs: usize,
    fitted: usize,
    freedom: usize,
    geometry_doc: &'static str,
    pose_doc: &'static str,
) -> [Output; 3] {
    [
        Output {
            name: "residual",
            shape: Shape::Vector(legs),
            doc: "`q(X; θ) - q̂`: the actuator values the geometry predicts at the pose less \
                  the readings",
        },
        Output {
            name: "geometry_jacobian",
            shape: Shape::Matrix(legs, fitted),
            doc: geometry_doc,
        },
        Output {
            name: "pose_jacobian",
            shape: Shape::Matrix(legs, freedom),
            doc: pose_doc,
        },
    ]
}

#[cfg(test)]
mod tests {
    use crate::model::kernels::specs;
    use crate::model::kernels::Kernel;
    use crate::model::Mechanism;
    use crate::ParameterSet;
    use c5_robot::Description;

    fn compiled(mechanism: &Mechanism, kernel: Kernel) -> crate::Program {
        specs(mechanism, &ParameterSet::None, "")
            .unwrap()
            .into_iter()
            .find(|e| e.id.kernel == kernel)
            .unwrap()
            .spec
            .compile()
            .unwrap()
            .program
    }

    /// Each legged mechanism's residual vanishes at the readings of its own geometry, and its
    /// Jacobians are the residual's derivatives with respect to each leg's fitted parameters
    /// and to the pose (central differences).
    #[test]
    fn the_calibration_jacobians_are_the_residuals_derivatives() {
        let cases = [
            (
                Description::GoughStewart(c5_robot::GoughStewart::example()),
                Mechanism::gough_stewart(&c5_robot::GoughStewart::example()),
                c5_robot::GoughStewart::example().home().to_vec(),
                c5_robot::gough_stewart::LEG_GEOMETRY,
            ),
            (
                Description::RusHexapod(c5_robot::RusHexapod::example()),
                Mechanism::rus_hexapod(&c5_robot::RusHexapod::example()),
                c5_robot::RusHexapod::example().home().unwrap().to_vec(),
                c5_robot::rus::LEG_GEOMETRY,
            ),
            (
                Description::Delta(c5_robot::Delta::example()),
                Mechanism::delta(&c5_robot::Delta::example()),
                c5_robot::Delta::example().home().unwrap().to_vec(),
                c5_robot::delta::ARM_GEOMETRY,
            ),
        ];
        for (robot, mechanism, home, leg_size) in cases {
            let fitted = robot.fitted().unwrap();
            let n = fitted.len();
            let (ik, calibration) = (
                compiled(&mechanism, Kernel::InverseKinematics),
                compiled(&mechanism, Kernel::CalibrationResiduals),
            );
            let freedom = home.len();
            let legs = freedom;
            let steps = [0.08, -0.06, 0.15, 0.02, -0.01, 0.03];
            let pose: Vec<f64> = home
                .iter()
                .zip(&steps[6 - freedom..])
                .map(|(h, d)| h + 0.5 * d)
                .collect();
            let q = ik.eval(&pose)[..legs].to_vec();
            let geometry = robot.kernel_parameters()[..3 + legs * leg_size].to_vec();
            let at = |x: &[f64], theta: &[f64]| calibration.eval(&[x, &q[..], theta].concat());
            let out = at(&pose, &geometry);
            let name = robot.mechanism();
            assert!(
                out[..legs].iter().all(|r| r.abs() < 1e-14),
                "{name}: {:?}",
                &out[..legs]
            );
            let h = 1e-6;
            for leg in 0..legs {
                for (column, f) in fitted.iter().enumerate() {
                    let entry = 3 + leg_size * leg + f.entry;
                    let (mut up, mut down) = (geometry.clone(), geometry.clone());
                    up[entry] += h;
                    down[entry] -= h;
                    let fd = (at(&pose, &up)[leg] - at(&pose, &down)[leg]) / (2.0 * h);
                    let exact = out[legs + n * leg + column];
                    assert!(
                        (fd - exact).abs() < 1e-7 * (1.0 + fd.abs()),
                        "{name} leg {leg} {}: {exact} vs {fd}",
                        f.name(leg + 1)
                    );
                }
            }
            for j in 0..freedom {
                let (mut up, mut down) = (pose.clone(), pose.clone());
                up[j] += h;
                down[j] -= h;
                let (a, b) = (at(&up, &geometry), at(&down, &geometry));
                for i in 0..legs {
                    let fd = (a[i] - b[i]) / (2.0 * h);
                    let exact = out[legs + legs * n + freedom * i + j];
                    assert!(
                        (fd - exact).abs() < 1e-7 * (1.0 + fd.abs()),
                        "{name} ∂q{i}/∂x{j}: {exact} vs {fd}"
                    );
                }
            }
        }
    }
}
