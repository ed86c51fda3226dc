//! The derivative kernels against central differences of independent implementations: the
//! nalgebra references of both models (task space) and the joint-space primal kernel, on 1 000
//! seeded states each, random robots among them; and the identities that tie them: `∂Γ/∂A` is
//! the inverse of `∂A/∂Γ`, `∂Γ/∂q̈` is `M_q`.
//!
//! Step: `h = 1e-5` in each input component (rad, m, rad/s, m/s, N), central: the truncation
//! error, `h²/6 |f'''|`, and the rounding error `ε |f| / h` are each about 1e-10 of the
//! derivatives for most states, and 1.8e-8 at worst over these (measured), so the bound `1e-7`
//! relative to the Jacobian's largest entry holds that figure at about five times and still
//! catches any wrong term (a wrong sign, a missing product rule term, a swapped column are all
//! of order one).

use crate::support;

use c5_runtime::reference as r;
use c5_runtime::{Acceleration, Model, Pose, Robot, State, Twist, C5};
use support::*;

const STATES: usize = 1_000;
const STEP: f64 = 1e-5;
const TOLERANCE: f64 = 1e-7;

/// Central differences of `f` (6 outputs) in each of the 6 components of `x`, as a row-major
/// Jacobian: row output, column component.
fn central(f: impl Fn(&[f64; 6]) -> [f64; 6], x: &[f64; 6]) -> [[f64; 6]; 6] {
    let mut columns = [[0.0; 6]; 6];
    for (j, column) in columns.iter_mut().enumerate() {
        let (mut up, mut down) = (*x, *x);
        up[j] += STEP;
        down[j] -= STEP;
        let (fu, fd) = (f(&up), f(&down));
        *column = std::array::from_fn(|i| (fu[i] - fd[i]) / (2.0 * STEP));
    }
    std::array::from_fn(|i| std::array::from_fn(|j| columns[j][i]))
}

fn assert_close(what: &str, exact: &[[f64; 6]; 6], numeric: &[[f64; 6]; 6]) {
    let e = rel_err(&flat(exact), &flat(numeric), 1.0);
    assert!(
        e <= TOLERANCE,
        "{what}: {e:e}\nexact {exact:?}\nnumeric {numeric:?}"
    );
}

/// The robots of the states: every third a random one, else the chapter's.
fn robots(rng: &mut rand_chacha::ChaCha8Rng) -> Vec<Robot> {
    (0..STATES)
        .map(|n| {
            if n % 3 == 0 {
                random_robot(rng)
            } else {
                Robot::default()
            }
        })
        .collect()
}

/// `Γ` of the model's nalgebra reference.
fn reference_gamma(robot: &Robot, model: Model, s: &State) -> [f64; 6] {
    let gamma = (r::model(model).inverse_dynamics)(robot, &s.pose, &s.twist, &s.accel)
        .expect("a regular state");
    std::array::from_fn(|i| gamma[i])
}

#[test]
fn inverse_dynamics_jacobians_are_the_references_central_differences() {
    let mut rng = rng(91);
    let states: Vec<State> = (0..STATES).map(|_| random_state(&mut rng)).collect();
    for model in Model::ALL {
        for (robot, s) in robots(&mut rng).into_iter().zip(&states) {
            let c5 = C5::with_model(robot, model).unwrap();
            let d = c5.inverse_dynamics_derivatives(s).unwrap();
            // The value: the primal kernel's, to rounding (another program computes it).
            let e = rel_err(&d.gamma, &c5.inverse_dynamics(s).unwrap(), 1.0);
            assert!(e < 1e-13, "{model}: the value, {e:e}");
            let gamma_at = |x: &[f64; 6], v: &[f64; 6], a: &[f64; 6]| {
                let state = State {
                    pose: Pose::from_array(*x),
                    twist: Twist::from_array(*v),
                    accel: Acceleration::from_array(*a),
                };
                reference_gamma(&robot, model, &state)
            };
            let (x, v, a) = (s.pose.to_array(), s.twist.to_array(), s.accel.to_array());
            assert_close(
                &format!("{model} ∂Γ/∂X"),
                &d.d_pose,
                &central(|x| gamma_at(x, &v, &a), &x),
            );
            assert_close(
                &format!("{model} ∂Γ/∂V"),
                &d.d_twist,
                &central(|v| gamma_at(&x, v, &a), &v),
            );
            assert_close(
                &format!("{model} ∂Γ/∂A"),
                &d.d_accel,
                &central(|a| gamma_at(&x, &v, a), &a),
            );
        }
    }
}

#[test]
fn forward_dynamics_jacobians_are_the_references_central_differences() {
    let mut rng = rng(92);
    let states: Vec<State> = (0..STATES).map(|_| random_state(&mut rng)).collect();
    for model in Model::ALL {
        for (robot, s) in robots(&mut rng).into_iter().zip(&states) {
            let c5 = C5::with_model(robot, model).unwrap();
            // Forces of the robot's size: those that give the state's acceleration.
            let gamma = c5.inverse_dynamics(s).unwrap();
            let d = c5
                .forward_dynamics_derivatives(&s.pose, &s.twist, &gamma)
                .unwrap();
            let a = c5.forward_dynamics(&s.pose, &s.twist, &gamma).unwrap();
            let e = rel_err(&d.accel, &a.to_array(), 1.0);
            assert!(e < 1e-12, "{model}: the value, {e:e}");
            let accel_at = |x: &[f64; 6], v: &[f64; 6], g: &[f64; 6]| {
                r::forward_dynamics(
                    &robot,
                    model,
                    &Pose::from_array(*x),
                    &Twist::from_array(*v),
                    g,
                )
                .expect("a regular state")
                .to_array()
            };
            let (x, v) = (s.pose.to_array(), s.twist.to_array());
            assert_close(
                &format!("{model} ∂A/∂X"),
                &d.d_pose,
                &central(|x| accel_at(x, &v, &gamma), &x),
            );
            assert_close(
                &format!("{model} ∂A/∂V"),
                &d.d_twist,
                &central(|v| accel_at(&x, v, &gamma), &v),
            );
            assert_close(
                &format!("{model} ∂A/∂Γ"),
                &d.d_gamma,
                &central(|g| accel_at(&x, &v, g), &gamma),
            );
        }
    }
}

#[test]
fn the_acceleration_jacobians_of_the_two_dynamics_are_inverses() {
    let mut rng = rng(93);
    for model in Model::ALL {
        for robot in robots(&mut rng) {
            let s = random_state(&mut rng);
            let c5 = C5::with_model(robot, model).unwrap();
            let gamma: [f64; 6] =
                std::array::from_fn(|_| rand::Rng::gen_range(&mut rng, -80.0..80.0));
            let forward = c5
                .forward_dynamics_derivatives(&s.pose, &s.twist, &gamma)
                .unwrap();
            let at = State {
                accel: Acceleration::from_array(forward.accel),
                ..s
            };
            let inverse = c5.inverse_dynamics_derivatives(&at).unwrap();
            // ∂Γ/∂A · ∂A/∂Γ = I, and Γ(a(Γ)) = Γ.
            for (i, row) in inverse.d_accel.iter().enumerate() {
                for j in 0..6 {
                    let product: f64 = (0..6).map(|k| row[k] * forward.d_gamma[k][j]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (product - want).abs() < 1e-10,
                        "{model}: ({i}, {j}) = {product}"
                    );
                }
            }
            let e = rel_err(&inverse.gamma, &gamma, 1.0);
            assert!(e < 1e-9, "{model}: Γ(a(Γ)) - Γ = {e:e}");
        }
    }
}

#[test]
fn joint_space_jacobians_are_the_primals_central_differences() {
    let mut rng = rng(94);
    for model in Model::ALL {
        for robot in robots(&mut rng) {
            let s = random_state(&mut rng);
            let c5 = C5::with_model(robot, model).unwrap();
            let (q, _) = c5.inverse_kinematics(&s.pose).unwrap();
            let qd = c5.joint_velocities(&s.pose, &s.twist).unwrap();
            let qdd = c5.joint_accelerations(&s).unwrap();
            let d = c5
                .inverse_dynamics_joint_derivatives(&q, &qd, &qdd)
                .unwrap();
            let e = rel_err(
                &d.gamma,
                &c5.inverse_dynamics_joint(&q, &qd, &qdd).unwrap(),
                1.0,
            );
            assert!(e < 1e-13, "{model}: the value, {e:e}");
            let gamma = |q: &[f64; 6], qd: &[f64; 6], qdd: &[f64; 6]| {
                c5.inverse_dynamics_joint(q, qd, qdd).unwrap()
            };
            assert_close(
                &format!("{model} ∂Γ/∂q"),
                &d.d_q,
                &central(|q| gamma(q, &qd, &qdd), &q),
            );
            assert_close(
                &format!("{model} ∂Γ/∂q̇"),
                &d.d_qd,
                &central(|qd| gamma(&q, qd, &qdd), &qd),
            );
            // ∂Γ/∂q̈ is M_q, the joint-space inertia kernel's (the same engine, another build).
            let m = c5.joint_inertia(&q).unwrap();
            let e = rel_err(&flat(&d.d_qdd), &flat(&m), 1.0);
            assert!(e < 1e-12, "{model}: ∂Γ/∂q̈ and M_q differ by {e:e}");
        }
    }
}
