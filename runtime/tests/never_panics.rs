//! The public API returns `Ok` with finite numbers or a typed error for any `f64` input:
//! NaN, ±∞, huge, tiny and subnormal values included, for valid and invalid robots, in both
//! models. It never panics.

use c5_runtime::{Acceleration, Error, Model, Pose, Robot, State, Twist, C5};
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

fn any_model() -> impl Strategy<Value = Model> {
    prop_oneof![Just(Model::Consistent), Just(Model::Paper)]
}

/// A state in the robot's workspace: moderate angles and positions, any motion.
fn workspace_state() -> impl Strategy<Value = State> {
    (
        proptest::array::uniform3(-0.6..0.6f64),
        proptest::array::uniform3(-0.1..0.1f64),
        proptest::array::uniform6(-3.0..3.0f64),
        proptest::array::uniform6(-20.0..20.0f64),
    )
        .prop_map(|(angles, center, v, a)| State {
            pose: Pose {
                alpha: angles[0],
                beta: angles[1],
                gamma: angles[2],
                center,
            },
            twist: Twist {
                omega: [v[0], v[1], v[2]],
                velocity: [v[3], v[4], v[5]],
            },
            accel: Acceleration {
                omega_dot: [a[0], a[1], a[2]],
                linear: [a[3], a[4], a[5]],
            },
        })
}

/// A valid robot: the default one with its masses, spacing, gravity and centres of mass
/// changed, and its inertias scaled (a scaled physical tensor is physical).
fn valid_robot() -> impl Strategy<Value = Robot> {
    (
        0.05..1.0f64,
        proptest::array::uniform3(-20.0..20.0f64),
        proptest::collection::vec(0.1..20.0f64, 13),
        proptest::collection::vec(-0.05..0.05f64, 21),
    )
        .prop_map(|(l, g, masses, coms)| {
            let mut r = Robot {
                half_spacing: l,
                gravity: g,
                ..Robot::default()
            };
            r.platform.mass = masses[0];
            r.platform.com = [coms[0], coms[1], coms[2]];
            r.platform.inertia = r
                .platform
                .inertia
                .map(|row| row.map(|x| x * masses[0] / 10.0));
            for (i, s) in r.segments.iter_mut().enumerate() {
                s.rod.mass = masses[1 + 2 * i];
                s.joint.mass = masses[2 + 2 * i];
                s.joint.com = [coms[3 + 3 * i], coms[4 + 3 * i], coms[5 + 3 * i]];
            }
            r
        })
}

fn check_evaluation(robot: &C5, state: &State) -> Result<(), TestCaseError> {
    match robot.evaluate(state) {
        Ok(e) => {
            let all =
                e.q.iter()
                    .chain(&e.qd)
                    .chain(&e.qdd)
                    .chain(&e.gamma)
                    .chain(e.jinv.iter().flatten())
                    .chain(e.jacobian.iter().flatten());
            prop_assert!(all.into_iter().all(|x| x.is_finite()));
        }
        Err(Error::NonFinite { .. } | Error::Singular { .. } | Error::NonFiniteResult { .. }) => {}
        Err(other) => prop_assert!(false, "unexpected error {other}"),
    }
    Ok(())
}

proptest! {
    // Seeded, so every run tries the same cases; a failing case found is written to
    // `never_panics.proptest-regressions` beside this file (checked in) and replayed first.
    #![proptest_config(ProptestConfig {
        cases: 2000,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x00c5_5eed),
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..ProptestConfig::default()
    })]

    #[test]
    fn any_state_gets_a_result_or_a_typed_error(
        x in proptest::array::uniform6(any_f64()),
        v in proptest::array::uniform6(any_f64()),
        a in proptest::array::uniform6(any_f64()),
        model in any_model(),
    ) {
        let robot = C5::with_model(Robot::default(), model).unwrap();
        let state = State {
            pose: Pose::from_array(x),
            twist: Twist { omega: [v[0], v[1], v[2]], velocity: [v[3], v[4], v[5]] },
            accel: Acceleration { omega_dot: [a[0], a[1], a[2]], linear: [a[3], a[4], a[5]] },
        };
        check_evaluation(&robot, &state)?;
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
    fn valid_robots_in_their_workspace_give_finite_results(
        robot in valid_robot(),
        state in workspace_state(),
        model in any_model(),
    ) {
        let c5 = C5::with_model(robot, model).unwrap();
        let e = c5.evaluate(&state);
        // Inside the workspace (|angles| ≤ 0.6 rad, so |r_kk| ≥ 0.5) every state is served.
        prop_assert!(e.is_ok(), "{e:?}");
        let e = e.unwrap();
        // And what it serves is consistent: J⁻¹ J = I.
        for i in 0..6 {
            for j in 0..6 {
                let p: f64 = (0..6).map(|k| e.jinv[i][k] * e.jacobian[k][j]).sum();
                let want = f64::from(u8::from(i == j));
                prop_assert!((p - want).abs() < 1e-9, "(J⁻¹ J)[{}][{}] = {}", i, j, p);
            }
        }
        prop_assert_eq!(c5.inverse_dynamics(&state).unwrap(), e.gamma);
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
            Err(Error::Robot { field, rule }) => prop_assert!(!field.is_empty() && !rule.is_empty()),
            Err(other) => prop_assert!(false, "unexpected error {other}"),
        }
    }
}

#[test]
fn singular_pose_names_the_term_in_both_models() {
    for model in Model::ALL {
        let robot = C5::with_model(Robot::default(), model).unwrap();
        let pose = Pose::from_array([0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0]);
        for result in [
            robot.inverse_kinematics(&pose).map(|_| ()),
            robot.inverse_jacobian(&pose).map(|_| ()),
            robot.jacobian(&pose).map(|_| ()),
        ] {
            match result {
                Err(Error::Singular { term, value }) => {
                    assert_eq!(term, "r11", "{model}");
                    assert!(value.abs() < 1e-9);
                }
                other => panic!("{model}: {other:?}"),
            }
        }
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
    for model in Model::ALL {
        let robot = C5::with_model(Robot::default(), model).unwrap();
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
}

#[test]
fn an_invalid_robot_names_the_field_and_the_rule() {
    let mut robot = Robot::default();
    robot.platform.inertia = [[1.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]];
    let e = C5::new(robot).unwrap_err();
    assert!(
        matches!(&e, Error::Robot { field, rule } if field == "platform.inertia" && rule.contains("triangle inequality")),
        "{e:?}"
    );
}

#[test]
fn many_states_at_once_equal_one_at_a_time_and_name_the_refused_one() {
    for model in Model::ALL {
        let robot = C5::with_model(Robot::default(), model).unwrap();
        let states: Vec<State> = (0..11)
            .map(|k| {
                let f = |j: usize| ((k * 7 + j) as f64 * 0.37).sin();
                State {
                    pose: Pose::from_array([
                        0.3 * f(1),
                        0.3 * f(2),
                        0.3 * f(3),
                        0.05 * f(4),
                        0.05 * f(5),
                        0.05 * f(6),
                    ]),
                    twist: Twist::from_array(std::array::from_fn(|j| f(7 + j))),
                    accel: Acceleration::from_array(std::array::from_fn(|j| 3.0 * f(13 + j))),
                }
            })
            .collect();
        let many = robot.inverse_dynamics_many(&states).unwrap();
        let evaluations = robot.evaluate_many(&states).unwrap();
        for (k, s) in states.iter().enumerate() {
            assert_eq!(many[k], robot.inverse_dynamics(s).unwrap(), "{model} {k}");
            assert_eq!(evaluations[k], robot.evaluate(s).unwrap());
        }
        let mut bad = states.clone();
        bad[9].pose.beta = std::f64::consts::FRAC_PI_2;
        assert!(matches!(
            robot.inverse_dynamics_many(&bad),
            Err((9, Error::Singular { term: "r11", .. }))
        ));
        bad[6].accel.linear[2] = f64::NAN;
        assert!(matches!(
            robot.inverse_dynamics_many(&bad),
            Err((6, Error::NonFinite { .. }))
        ));
    }
}
