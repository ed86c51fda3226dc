//! Kinematic calibration's kernel, for every legged mechanism: the legs' residuals
//! `r_i = q_i(X; θ) - q̂_i` at a measured pose `X` and readings `q̂`, and their exact Jacobians
//! with respect to each leg's fitted geometry ([`c5_robot::calibration`]) and to the pose.
//!
//! The mechanism gives its actuators' closed forms `q_i(X; θ)` on the kernel's inputs; this
//! module differentiates them. Leg `i`'s actuator reads its own geometry alone, so row `i` of
//! the geometry Jacobian holds the derivatives with respect to leg `i`'s fitted entries.

use super::kernels::{Build, Cite, Context, Decl, Guard, Input, Kernel, Output, Reads, RobotBuild};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Vec3, Vector};
use c5_robot::calibration::{Coordinate, Fitted};

/// The first index of the balls' symbols the derivation builds on; none survives in a kernel.
const BALL_SYMBOLS: u32 = 1 << 28;

/// What the residuals are built from: per leg, the point `B_i` through which the pose
/// reaches its actuator (its platform joint's centre) as an expression of the kernel's inputs,
/// the actuator's closed form at any such point, and where the geometry holds the leg's
/// entries (`3 + leg_size·i`, after gravity).
pub struct Legs<'a, 'g> {
    pub balls: Vec<Vec3<'g>>,
    pub actuator: &'a dyn Fn(usize, &Vec3<'g>) -> Expr<'g>,
    pub leg_size: usize,
}

/// [`residuals`] on the kernel's inputs: the readings its actuators, `pose` its pose's
/// coordinates.
pub fn build<'g>(
    cx: &Context<'_, 'g>,
    legs: &Legs<'_, 'g>,
    pose: &[Expr<'g>],
    fitted: &[Fitted],
) -> Vec<Vec<Expr<'g>>> {
    let readings = cx.input(Input::Actuators);
    residuals(cx.graph(), cx.geometry, legs, &readings, pose, fitted)
}

/// The kernel's three results: the residuals, the geometry Jacobian (row `i`: `∂q_i/∂θ_i`,
/// one column per fitted parameter) and the pose Jacobian `∂q/∂X`.
///
/// Each actuator is differentiated on a symbol `B̂_i` for its ball, then by the chain rule:
/// `∂q_i/∂θ = ∂q̂_i/∂θ + ∇_B q̂_i · ∂B_i/∂θ` and `∂q_i/∂X = ∇_B q̂_i · ∂B_i/∂X`, so that
/// the pose's derivatives do not run through the legs' closed forms again.
pub fn residuals<'g>(
    g: &'g Graph,
    geometry_of: &[Expr<'g>],
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
        let at = &geometry_of[3 + legs.leg_size * i..3 + legs.leg_size * (i + 1)];
        residual.push(q - readings[i]);
        let along = |x: Expr<'g>| g.derivatives(&[q], x)[0] + through_ball(x);
        geometry.extend(fitted.iter().map(|f| match f.coordinate {
            Coordinate::Entry(entry) => along(at[entry]),
            turn => {
                // The platform's ball does not move with the motor's axis: one tangent of the
                // leg's closed form along the turn. The zero turns with the axis,
                // `dh = -(h·dr) r`, which keeps it orthogonal.
                let (r, h) = (&at[3..6], &at[6..9]);
                let dr = axis_rate(turn, r);
                let h_dr = (0..3).fold(g.zero(), |sum, k| sum + h[k] * dr[k]).keep();
                let rates: Vec<(Expr<'g>, Expr<'g>)> = (0..3)
                    .map(|k| (r[k], dr[k]))
                    .chain((0..3).map(|k| (h[k], -(h_dr * r[k]))))
                    .collect();
                g.tangents(&[q], &rates)[0]
            }
        }));
        by_pose.extend(pose.iter().map(|&x| through_ball(x)));
    }
    [residual, geometry, by_pose]
        .into_iter()
        .map(|exprs| g.substitute(&exprs, &values))
        .collect()
}

/// The motor axis's rate `dr` per radian of its azimuth (`(-r_y, r_x, 0)`) or elevation
/// (`(-r_z r_x/ρ, -r_z r_y/ρ, ρ)`, `ρ = √(r_x² + r_y²)`), `r` a unit vector.
fn axis_rate<'g>(turn: Coordinate, r: &[Expr<'g>]) -> [Expr<'g>; 3] {
    let g = r[0].graph();
    match turn {
        Coordinate::Azimuth => [-r[1], r[0], g.zero()],
        _ => {
            let rho = (r[0] * r[0] + r[1] * r[1]).sqrt().keep();
            let over = (r[2] * rho.recip()).keep();
            [-(over * r[0]), -(over * r[1]), rho]
        }
    }
}

/// The residual kernel of a mechanism: `inputs` its pose's kind then the actuators,
/// `outputs` made by [`outputs`], and `build` calling [`build`] with the mechanism's closed
/// forms.
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
    use crate::model::kernels::compiled;
    use crate::model::kernels::Kernel;
    use crate::model::Mechanism;
    use c5_robot::Description;

    /// Each legged mechanism's residual vanishes at the readings of its own geometry, and its
    /// Jacobians are the residual's derivatives with respect to each leg's fitted parameters
    /// (central differences of the description's values, the motor axis's turns included) and
    /// to the pose.
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
                    // Through the description: a turn of the axis moves its zero too.
                    let moved = |by: f64| {
                        let mut built = robot.clone();
                        let mut values = built.fitted_values(leg);
                        values[column] += by;
                        assert!(built.set_fitted_values(leg, &values));
                        built.kernel_parameters()[..geometry.len()].to_vec()
                    };
                    let fd = (at(&pose, &moved(h))[leg] - at(&pose, &moved(-h))[leg]) / (2.0 * h);
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
