//! The public API returns `Ok` with finite numbers or a typed error for any `f64` input:
//! NaN, ±∞, huge, tiny and subnormal values included. It never panics.

use c5_runtime::{Acceleration, Error, Pose, Robot, State, Twist, C5};
use proptest::prelude::*;

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        proptest::num::f64::ANY,
        -1.0..1.0f64,
        Just(f64::MIN_POSITIVE / 4.0),
        Just(1e300),
        Just(-1e300),
        Just(std::f64::consts::FRAC_PI_2),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn any_state_gets_a_result_or_a_typed_error(
        x in proptest::array::uniform6(any_f64()),
        v in proptest::array::uniform6(any_f64()),
        a in proptest::array::uniform6(any_f64()),
    ) {
        let robot = C5::new(Robot::default()).unwrap();
        let state = State {
            pose: Pose::from_array(x),
            twist: Twist { omega: [v[0], v[1], v[2]], velocity: [v[3], v[4], v[5]] },
            accel: Acceleration { omega_dot: [a[0], a[1], a[2]], linear: [a[3], a[4], a[5]] },
        };
        match robot.evaluate(&state) {
            Ok(e) => {
                let all = e.q.iter().chain(&e.qd).chain(&e.qdd).chain(&e.gamma)
                    .chain(e.jinv.iter().flatten()).chain(e.jacobian.iter().flatten());
                prop_assert!(all.into_iter().all(|x| x.is_finite()));
            }
            Err(Error::NonFinite { .. } | Error::Singular { .. } | Error::NonFiniteResult { .. }) => {}
            Err(other) => prop_assert!(false, "unexpected error {other}"),
        }
        // The narrower calls hold to the same rule.
        let _ = robot.inverse_kinematics(&state.pose);
        let _ = robot.inverse_jacobian(&state.pose);
        let _ = robot.jacobian(&state.pose);
        let _ = robot.joint_velocities(&state.pose, &state.twist);
        let _ = robot.joint_accelerations(&state);
        if let Ok(g) = robot.inverse_dynamics(&state) {
            prop_assert!(g.iter().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn any_robot_parameters_are_accepted_or_rejected_without_panic(
        values in proptest::collection::vec(any_f64(), 152),
    ) {
        let robot = Robot::unflatten(&values);
        match C5::new(robot) {
            Ok(c5) => {
                let _ = c5.inverse_dynamics(&State::default());
            }
            Err(Error::Robot(message)) => prop_assert!(message.starts_with("invalid robot: `")),
            Err(other) => prop_assert!(false, "unexpected error {other}"),
        }
    }
}

#[test]
fn singular_pose_names_the_term() {
    let robot = C5::new(Robot::default()).unwrap();
    let pose = Pose::from_array([0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0]);
    match robot.inverse_kinematics(&pose) {
        Err(Error::Singular { term, value }) => {
            assert_eq!(term, "r11");
            assert!(value.abs() < 1e-9);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn coincident_pi1_denominator_names_the_term() {
    let robot = C5::new(Robot::default()).unwrap();
    let mut p = [[0.1, 0.0, 0.0]; 6];
    p[0][2] = 0.2;
    p[1][2] = 0.2;
    p[4][1] = -0.1;
    p[5][1] = 0.1;
    p[2][0] = -0.1;
    p[3][0] = 0.1;
    assert!(matches!(
        robot.pi1(&p),
        Err(Error::Singular {
            term: "z1 - z2",
            ..
        })
    ));
    p[1][2] = -0.2;
    assert!(robot.pi1(&p).is_ok());
}

#[test]
fn nan_input_names_the_input_and_index() {
    let robot = C5::new(Robot::default()).unwrap();
    let mut s = State::default();
    s.twist.velocity[1] = f64::NAN;
    assert_eq!(
        robot.inverse_dynamics(&s),
        Err(Error::NonFinite {
            input: "twist",
            index: 4
        })
    );
}
