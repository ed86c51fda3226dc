//! The rotary hexapod (6-RUS) through the runtime, against mechanics: `J⁻¹` the derivative of
//! the crank angles (central differences of the inverse kinematics), `q̈` the derivative of
//! `q̇` along the motion, `J⁻¹ J = I`, the forward kinematics undoing the inverse, the forward
//! dynamics undoing the inverse, the joint-space state the platform's; the crank angles the
//! description's closed form. Pinocchio's closed-loop dynamics on the exported robot checks
//! the same kernels from Python (python/tests/test_rus_hexapod.py).

use crate::support;

use c5_robot::RusHexapod as Description;
use c5_runtime::{Error, Pose, RusHexapod, State};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use support::{rel_err, rng};

/// The example with every joint moved by millimetres, other masses, tilted gravity, encoder
/// offsets: a robot no generated file folds in.
pub(crate) fn jittered(r: &mut ChaCha8Rng) -> Description {
    let mut robot = Description::example();
    robot.gravity = [0.3, -0.2, -9.8];
    robot.platform.centre_of_mass = [0.004, -0.006, 0.03];
    robot.platform.inertia = [0.033, 0.03, 0.06, 0.001, -0.002, 0.0015];
    for leg in &mut robot.legs {
        for x in leg.base.iter_mut().chain(&mut leg.platform) {
            *x += r.gen_range(-0.004..0.004);
        }
        leg.axis[2] += r.gen_range(-0.05..0.05);
        leg.crank.mass *= r.gen_range(0.8..1.2);
        leg.rod.mass *= r.gen_range(0.8..1.2);
        leg.encoder_offset = r.gen_range(-0.1..0.1);
    }
    robot.validate().expect("a valid rotary hexapod");
    robot
}

fn robots() -> Vec<RusHexapod> {
    let mut r = rng(41);
    [Description::example(), jittered(&mut r)]
        .into_iter()
        .map(|d| RusHexapod::new(d).unwrap())
        .collect()
}

/// A state near home: turns up to 0.1 rad, 15 mm, rates and accelerations as
/// `support::random_state`'s.
pub(crate) fn near_home(r: &mut ChaCha8Rng, home: &Pose) -> State {
    let mut s = support::random_state(r);
    s.pose.alpha *= 0.2;
    s.pose.beta *= 0.2;
    s.pose.gamma *= 0.2;
    for k in 0..3 {
        s.pose.center[k] = home.center[k] + 0.15 * s.pose.center[k];
    }
    s
}

/// The state at time `t` of the pose `x + t ẋ + t² ẍ/2`.
fn along(x: &[f64; 6], xd: &[f64; 6], xdd: &[f64; 6], t: f64) -> State {
    let at: [f64; 6] = core::array::from_fn(|k| x[k] + t * xd[k] + 0.5 * t * t * xdd[k]);
    let rate: [f64; 6] = core::array::from_fn(|k| xd[k] + t * xdd[k]);
    c5_runtime::trajectory::state_from_pose_derivatives(
        c5_runtime::platform::Freedom::Free,
        &at,
        &rate,
        xdd,
    )
    .unwrap()
}

#[test]
fn the_crank_angles_are_the_descriptions_and_the_jacobians_invert() {
    for robot in robots() {
        let mut r = rng(3);
        for _ in 0..50 {
            let s = near_home(&mut r, &robot.home());
            let (q, _) = robot.inverse_kinematics(&s.pose).unwrap();
            let want = robot.robot().actuator_angles(&s.pose.to_array()).unwrap();
            assert!(rel_err(&q, &want, 1.0) < 1e-14, "{q:?} vs {want:?}");
            let jinv = robot.inverse_jacobian(&s.pose).unwrap();
            let jac = robot.jacobian(&s.pose).unwrap();
            for (i, row) in jinv.iter().enumerate() {
                for j in 0..6 {
                    let p: f64 = row.iter().zip(&jac).map(|(a, b)| a * b[j]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((p - want).abs() < 1e-11, "(J⁻¹ J)[{i}][{j}] = {p}");
                }
            }
        }
    }
}

/// `q̇ = J⁻¹ V` is the rate of the crank angles, and `q̈` the rate of `q̇`, along a motion
/// (central differences).
#[test]
fn the_rates_and_accelerations_are_the_angles_derivatives() {
    let h = 1e-6;
    for robot in robots() {
        let mut r = rng(4);
        for _ in 0..20 {
            let x = near_home(&mut r, &robot.home()).pose.to_array();
            let xd: [f64; 6] = core::array::from_fn(|_| r.gen_range(-0.3..0.3));
            let xdd: [f64; 6] = core::array::from_fn(|_| r.gen_range(-2.0..2.0));
            let s = along(&x, &xd, &xdd, 0.0);
            let q_at = |t: f64| {
                robot
                    .inverse_kinematics(&along(&x, &xd, &xdd, t).pose)
                    .unwrap()
                    .0
            };
            let (up, down) = (q_at(h), q_at(-h));
            let fd: [f64; 6] = core::array::from_fn(|i| (up[i] - down[i]) / (2.0 * h));
            let qd = robot.joint_velocities(&s.pose, &s.twist).unwrap();
            assert!(rel_err(&qd, &fd, 1.0) < 1e-8, "{qd:?} vs {fd:?}");
            let qd_at = |t: f64| {
                let s = along(&x, &xd, &xdd, t);
                robot.joint_velocities(&s.pose, &s.twist).unwrap()
            };
            let (up, down) = (qd_at(h), qd_at(-h));
            let fd: [f64; 6] = core::array::from_fn(|i| (up[i] - down[i]) / (2.0 * h));
            let qdd = robot.joint_accelerations(&s).unwrap();
            assert!(rel_err(&qdd, &fd, 1.0) < 1e-7, "{qdd:?} vs {fd:?}");
        }
    }
}

/// The forward kinematics returns the pose of the inverse's angles, from home and from a
/// nearby pose; the forward dynamics returns the acceleration the inverse dynamics was given;
/// the joint-space state is the platform's.
#[test]
fn the_forward_models_undo_the_inverse_ones() {
    for robot in robots() {
        let mut r = rng(5);
        for _ in 0..30 {
            let s = near_home(&mut r, &robot.home());
            let (q, _) = robot.inverse_kinematics(&s.pose).unwrap();
            let mut near = s.pose;
            near.alpha += 0.01;
            near.center[2] -= 0.002;
            for start in [None, Some(&near)] {
                let pose = robot.forward_kinematics(&q, start).unwrap();
                let err = rel_err(&pose.to_array(), &s.pose.to_array(), 1.0);
                assert!(err < 1e-11, "{start:?}: {err:e}");
            }
            let gamma = robot.inverse_dynamics(&s).unwrap();
            let accel = robot.forward_dynamics(&s.pose, &s.twist, &gamma).unwrap();
            let err = rel_err(&accel.to_array(), &s.accel.to_array(), 1.0);
            assert!(err < 1e-10, "forward dynamics: {err:e}");
            let qd = robot.joint_velocities(&s.pose, &s.twist).unwrap();
            let qdd = robot.joint_accelerations(&s).unwrap();
            let joint = robot.joint_state(&q, &qd, &qdd, Some(&s.pose)).unwrap();
            assert!(rel_err(&joint.twist.to_array(), &s.twist.to_array(), 1.0) < 1e-10);
            assert!(rel_err(&joint.accel.to_array(), &s.accel.to_array(), 1.0) < 1e-9);
        }
    }
}

/// A ball beyond its crank's reach, non-finite inputs: typed errors naming the term.
#[test]
fn bad_states_are_refused() {
    let robot = RusHexapod::new(Description::example()).unwrap();
    let mut lifted = robot.home();
    lifted.center[2] += 0.3;
    match robot.inverse_kinematics(&lifted) {
        Err(Error::Singularity { term, value, .. }) => {
            assert!(term.contains("beyond its crank's reach"), "{term}");
            assert!(value < 0.0);
        }
        other => panic!("{other:?}"),
    }
    let mut nan = robot.home();
    nan.center[0] = f64::NAN;
    assert!(matches!(
        robot.inverse_dynamics(&State {
            pose: nan,
            ..State::default()
        }),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        robot.forward_kinematics(&[f64::INFINITY; 6], None),
        Err(Error::NonFinite { .. })
    ));
}

/// The smallest pivot of the legs' hold over seeded poses within 0.1 rad and 15 mm of home.
fn weakest_hold(robot: &RusHexapod) -> f64 {
    let mut r = rng(3);
    (0..200)
        .map(|_| {
            let s = near_home(&mut r, &robot.home());
            let terms = robot.singularity_terms(&s.pose).unwrap();
            terms[12..].iter().fold(1.0_f64, |m, &t| m.min(t))
        })
        .fold(1.0, f64::min)
}

/// The example's legs hold the platform well about home (pivots above 0.04; measured 0.054);
/// with the 0.085 m cranks for its 0.12 m they hold it fifty times less (measured
/// 1.0e-3), which is why the example's cranks are longer.
#[test]
fn the_examples_legs_hold_the_platform_near_home() {
    let example = RusHexapod::new(Description::example()).unwrap();
    let weakest = weakest_hold(&example);
    assert!(weakest > 0.04, "{weakest:e}");
    let mut short = Description::example();
    for leg in &mut short.legs {
        leg.crank.length = 0.085;
        leg.crank.com = 0.04;
        leg.crank.inertia = [2e-5, 4.2e-4, 4.3e-4];
    }
    let weaker = weakest_hold(&RusHexapod::new(short).unwrap());
    eprintln!("weakest pivot: {weakest:.3} with 0.12 m cranks, {weaker:.1e} with 0.085 m");
    assert!(weakest > 30.0 * weaker, "{weaker:e}");
}

/// The rotary hexapod's derivative kernels are not generated: the capability is absent from
/// its interface (`derivatives()` is `None`), and asked for by name it is refused, naming the
/// mechanism, while the Gough-Stewart platform and the Delta have it.
#[test]
fn a_capability_not_generated_is_absent() {
    use c5_runtime::derivatives::sliced_derivatives_of;
    use c5_runtime::mechanism::derivatives_of;
    use c5_runtime::ParallelRobot;
    let robot = RusHexapod::new(Description::example()).unwrap();
    assert!(ParallelRobot::derivatives(&robot).is_none());
    assert!(robot.as_mechanism().derivatives().is_none());
    match derivatives_of(&robot) {
        Err(Error::Unsupported {
            what: "derivatives",
            mechanism,
            ..
        }) => assert_eq!(mechanism, "rus-hexapod"),
        Err(other) => panic!("{other:?}"),
        Ok(_) => panic!("the rotary hexapod has no derivatives"),
    }
    let hexapod = c5_runtime::GoughStewart::new(c5_robot::GoughStewart::example()).unwrap();
    assert!(derivatives_of(&hexapod).is_ok());
    assert!(sliced_derivatives_of(hexapod.as_mechanism()).is_ok());
    // The Delta's, in its three coordinates, through both paths.
    let delta = c5_runtime::Delta::new(c5_robot::Delta::example()).unwrap();
    assert!(ParallelRobot::derivatives(&delta).is_some());
    assert!(sliced_derivatives_of(delta.as_mechanism()).is_ok());
}
