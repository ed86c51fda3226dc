//! `c5 eval`: one JSON line out per line in, bad lines reported alone (strictly: unknown and
//! repeated keys are refused), results equal to the matrix-form reference of the model asked
//! for.

use crate::support;

use c5_runtime::reference::{self as r, consistent as rc, Step6, CHAPTER_ORDER};
use c5_runtime::{Acceleration, Pose, Robot, Twist};
use rand::{Rng, SeedableRng};
use serde_json::Value;

fn run_eval(input: &str) -> (Vec<Value>, i32) {
    run_eval_with(&["eval"], input)
}

fn run_eval_with(args: &[&str], input: &str) -> (Vec<Value>, i32) {
    let out = support::c5(args, input);
    let lines = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).expect("every output line is JSON"))
        .collect();
    (lines, out.status.code().unwrap())
}

#[test]
fn bad_lines_get_their_own_error_and_the_others_their_results() {
    let input = [
        r#"{"pose": [0, 0, 0, 0, 0, 0]}"#,
        r#"{"pose": [0, 0, 0"#,
        r#"{"velocity": [0, 0, 0]}"#,
        r#"{"pose": [0, 0, 0, 0, 0]}"#,
        r#"{"pose": [0, 0, 0, 0, 0, "x"]}"#,
        r#"{"pose": [0, 1.5707963267948966, 0, 0, 0, 0]}"#,
        r#"{"pose": [0.1, 0.2, 0.3, 0.01, 0.02, 0.03], "omega": [0.1, 0.2, 0.3]}"#,
    ]
    .join("\n");
    let (out, code) = run_eval_with(&["eval", "--model", "paper"], &input);
    assert_eq!(out.len(), 7);
    assert_eq!(code, 1, "a failed line makes the exit status 1");
    let gamma = out[0]["gamma"].as_array().unwrap();
    assert!((gamma[4].as_f64().unwrap() - 117.8181).abs() < 1e-9);
    for (n, needle) in [
        (2, "malformed JSON"),
        (3, "missing `pose`"),
        (4, "6 numbers"),
        (5, "not a finite number"),
        (6, "singular pose: r11"),
    ] {
        assert_eq!(out[n - 1]["line"], n, "line number of {needle}");
        let e = out[n - 1]["error"].as_str().unwrap();
        assert!(e.contains(needle), "line {n}: {e}");
    }
    assert!(out[6]["q"].is_array());
}

#[test]
fn unknown_repeated_and_misshapen_keys_are_refused_by_name() {
    let input = [
        r#"{"pose": [0, 0, 0, 0, 0, 0], "accel": [0, 0, 1]}"#,
        r#"{"pose": [0, 0, 0, 0, 0, 0], "pose": [0.1, 0, 0, 0, 0, 0]}"#,
        r#"{"pose": [0, 0, 0, 0, 0, 0], "omega": [0, 0]}"#,
        r#"{"pose": [0, 0, 0, 0, 0, 0], "velocity": 3}"#,
        r#"[0, 0, 0, 0, 0, 0]"#,
    ]
    .join("\n");
    let (out, code) = run_eval(&input);
    assert_eq!((out.len(), code), (5, 1));
    for (n, needle) in [
        (
            1,
            "unknown key `accel` (accepted keys: pose, omega, velocity, omega_dot, acceleration, \
             q, qd, qdd)",
        ),
        (2, "`pose` is given twice"),
        (3, "`omega` must hold 3 numbers, got 2"),
        (4, "`velocity` must be an array of 3 numbers"),
        (5, "a line must be a JSON object"),
    ] {
        assert_eq!(out[n - 1]["line"], n);
        assert_eq!(out[n - 1]["error"].as_str().unwrap(), needle, "line {n}");
    }
}

#[test]
fn blank_lines_are_skipped_and_numbering_follows_the_file() {
    let (out, code) = run_eval("\n{\"pose\": [0, 0, 0, 0, 0, 0]}\n   \n{\"pose\": 1}\n");
    assert_eq!((out.len(), code), (2, 1));
    assert!(out[0]["gamma"].is_array());
    assert_eq!(out[1]["line"], 4);
}

#[test]
fn all_good_lines_exit_zero() {
    let (out, code) = run_eval("{\"pose\": [0, 0, 0, 0, 0, 0]}\n");
    assert_eq!((out.len(), code), (1, 0));
}

#[test]
fn a_bad_model_is_refused_with_the_choices() {
    let out = support::c5(&["eval", "--model", "exact"], "");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("exact") && err.contains("consistent") && err.contains("paper"),
        "{err}"
    );
}

/// Random states as `eval` lines, and the states.
fn random_lines() -> (String, Vec<(Pose, Twist, Acceleration)>) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    let mut states = Vec::new();
    let mut input = String::new();
    for _ in 0..300 {
        let pose = Pose::from_array([u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)]);
        let twist = Twist {
            omega: [u(1.0), u(1.0), u(1.0)],
            velocity: [u(0.5), u(0.5), u(0.5)],
        };
        let accel = Acceleration {
            omega_dot: [u(5.0), u(5.0), u(5.0)],
            linear: [u(2.0), u(2.0), u(2.0)],
        };
        input.push_str(
            &serde_json::json!({
                "pose": pose.to_array(), "omega": twist.omega, "velocity": twist.velocity,
                "omega_dot": accel.omega_dot, "acceleration": accel.linear,
            })
            .to_string(),
        );
        input.push('\n');
        states.push((pose, twist, accel));
    }
    (input, states)
}

fn vec(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn close(got: &[f64], want: &[f64]) -> bool {
    let scale = want.iter().fold(1e-3_f64, |m, x| m.max(x.abs()));
    got.iter()
        .zip(want)
        .all(|(g, w)| (g - w).abs() <= 1e-9 * scale)
}

#[test]
fn eval_agrees_with_the_consistent_reference_by_default() {
    let (input, states) = random_lines();
    let (out, code) = run_eval(&input);
    assert_eq!(code, 0);
    let robot = Robot::default();
    let l = robot.half_spacing;
    for ((pose, twist, accel), o) in states.iter().zip(&out) {
        let gamma = rc::inverse_dynamics(&robot, pose, twist, accel).unwrap();
        assert!(close(&vec(&o["gamma"]), gamma.as_slice()));
        assert!(close(&vec(&o["q"]), &rc::lengths(l, pose)));
        assert!(close(
            &vec(&o["qd"]),
            rc::joint_velocities(l, pose, twist).as_slice()
        ));
        assert!(close(
            &vec(&o["qdd"]),
            rc::joint_accelerations(l, pose, twist, accel).as_slice()
        ));
        let jinv = rc::inverse_jacobian(l, pose);
        let jac = rc::jacobian(l, pose).unwrap();
        for i in 0..6 {
            let row: Vec<f64> = (0..6).map(|j| jinv[(i, j)]).collect();
            assert!(close(&vec(&o["jinv"][i]), &row), "jinv row {i}");
            let row: Vec<f64> = (0..6).map(|j| jac[(i, j)]).collect();
            assert!(close(&vec(&o["jacobian"][i]), &row), "jacobian row {i}");
        }
    }
}

#[test]
fn eval_agrees_with_the_paper_reference_when_asked() {
    let (input, states) = random_lines();
    let (out, code) = run_eval_with(&["eval", "--model", "paper"], &input);
    assert_eq!(code, 0);
    let robot = Robot::default();
    for ((pose, twist, accel), o) in states.iter().zip(&out) {
        let p = r::p_i2(robot.half_spacing, pose);
        let gamma = r::to_segment_order(
            &r::inverse_dynamics(&robot, pose, twist, accel, Step6::Khalil).unwrap(),
        );
        assert!(close(&vec(&o["gamma"]), &gamma));
        assert!(close(
            &vec(&o["q"]),
            &r::to_segment_order(&r::inverse_kinematics(robot.half_spacing, pose))
        ));
        assert!(close(
            &vec(&o["qd"]),
            &r::to_segment_order(&(r::inverse_jacobian(&p) * twist.to_vector()))
        ));
        let jinv = r::inverse_jacobian(&p);
        let jac = r::jacobian(&p);
        for (k, &i) in CHAPTER_ORDER.iter().enumerate() {
            let row: Vec<f64> = (0..6).map(|j| jinv[(k, j)]).collect();
            assert!(
                close(&vec(&o["jinv"][i]), &row),
                "jinv row of segment {}",
                i + 1
            );
            for j in 0..6 {
                let got = o["jacobian"][j][i].as_f64().unwrap();
                assert!((got - jac[(j, k)]).abs() < 1e-9 * jac.amax().max(1.0));
            }
            let qdd =
                r::joint_accelerations_conventional(robot.half_spacing, pose, twist, accel, i)
                    .unwrap()[5];
            assert!((o["qdd"][i].as_f64().unwrap() - qdd).abs() < 1e-9 * qdd.abs().max(1.0));
        }
    }
}

/// The actuators' values of a state, written with the consistent model's reference.
fn actuator_line(s: &c5_runtime::State) -> String {
    let l = Robot::default().half_spacing;
    let q = rc::lengths(l, &s.pose);
    let qd = rc::joint_velocities(l, &s.pose, &s.twist);
    let qdd = rc::joint_accelerations(l, &s.pose, &s.twist, &s.accel);
    serde_json::json!({"q": q, "qd": qd.as_slice(), "qdd": qdd.as_slice()}).to_string()
}

#[test]
fn actuator_lines_give_the_platform_state_and_the_forces_of_the_state_they_came_from() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(90);
    let robot = Robot::default();
    let mut u = |b: f64| rng.gen_range(-b..=b);
    let states: Vec<c5_runtime::State> = (0..300)
        .map(|_| c5_runtime::State {
            pose: Pose::from_array([u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)]),
            twist: Twist {
                omega: [u(1.0), u(1.0), u(1.0)],
                velocity: [u(0.5), u(0.5), u(0.5)],
            },
            accel: Acceleration {
                omega_dot: [u(5.0), u(5.0), u(5.0)],
                linear: [u(2.0), u(2.0), u(2.0)],
            },
        })
        .collect();
    let input: Vec<String> = states.iter().map(actuator_line).collect();
    let (out, code) = run_eval_with(&["eval", "--model", "consistent"], &input.join("\n"));
    assert_eq!((out.len(), code), (states.len(), 0));
    let rel = |got: &Value, want: &[f64]| {
        let got: Vec<f64> = got
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let scale = want.iter().fold(1.0_f64, |m, w| m.max(w.abs()));
        got.iter()
            .zip(want)
            .map(|(g, w)| (g - w).abs())
            .fold(0.0, f64::max)
            / scale
    };
    for (o, s) in out.iter().zip(&states) {
        assert!(rel(&o["pose"], &s.pose.to_array()) < 1e-12, "{o}");
        assert!(rel(&o["omega"], &s.twist.omega) < 1e-12);
        assert!(rel(&o["velocity"], &s.twist.velocity) < 1e-12);
        assert!(rel(&o["omega_dot"], &s.accel.omega_dot) < 1e-11);
        assert!(rel(&o["acceleration"], &s.accel.linear) < 1e-11);
        let gamma = rc::inverse_dynamics(&robot, &s.pose, &s.twist, &s.accel).unwrap();
        assert!(rel(&o["gamma"], gamma.as_slice()) < 1e-10, "{o}");
        assert!(rel(&o["q"], &rc::lengths(robot.half_spacing, &s.pose)) < 1e-12);
    }
}

#[test]
fn a_line_mixing_platform_and_actuator_keys_is_refused_naming_them() {
    let input = [
        r#"{"pose": [0, 0, 0, 0, 0, 0], "qd": [0, 0, 0, 0, 0, 0]}"#,
        r#"{"qdd": [0, 0, 0, 0, 0, 0]}"#,
        r#"{"q": [0.4, -0.4, 0.4, -0.4, 0.4, -0.4]}"#,
        r#"{"q": [0, 0, 0, 0, 0, 0]}"#,
    ]
    .join("\n");
    let (out, code) = run_eval(&input);
    assert_eq!((out.len(), code), (4, 1));
    assert_eq!(
        out[0]["error"],
        "a line gives the platform's state or the actuators', not both: pose with qd"
    );
    assert_eq!(out[1]["error"], "missing `q`");
    // a = b = c = -2: 1 + abc = -7, no pose of the workspace.
    let e = out[2]["error"].as_str().unwrap();
    assert!(e.starts_with("forward singular: 1 + abc = -7"), "{e}");
    // Home: the platform at rest at the origin, and its forces.
    assert_eq!(
        out[3]["pose"],
        serde_json::json!([0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    );
    assert!((out[3]["gamma"][4].as_f64().unwrap() - 85.0527).abs() < 1e-3);
}

#[test]
fn numbers_are_read_exactly_and_actuator_forces_are_the_joint_space_kernels() {
    // Decimal strings a fast parser rounds to the neighbouring f64 (serde_json without
    // `float_roundtrip` reads each of these one unit in the last place off).
    let q = [
        "0.09620358486050973",
        "-0.013588488165355739",
        "0.24518022692615737",
        "-0.11556497931600751",
        "0.0",
        "0.0",
    ];
    let input = format!(r#"{{"q": [{}]}}"#, q.join(", "));
    let (out, code) = run_eval(&input);
    assert_eq!((out.len(), code), (1, 0), "{out:?}");
    let q: [f64; 6] = std::array::from_fn(|i| q[i].parse().unwrap());
    assert_eq!(vec(&out[0]["q"]), q, "the input, as given, to the bit");
    let c5 = c5_runtime::C5::new(Robot::default()).unwrap();
    let gamma = c5.inverse_dynamics_joint(&q, &[0.0; 6], &[0.0; 6]).unwrap();
    assert_eq!(
        vec(&out[0]["gamma"]),
        gamma,
        "what a controller calling the kernel gets"
    );
}
