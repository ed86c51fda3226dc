//! `c5 excite`, `c5 identify` and `c5 eval --base-parameters`: the round trip identifies a
//! robot that predicts its own forces, and bad data is refused with the file and line.

use crate::support;

use c5_runtime::identify::Friction;
use c5_runtime::{
    Acceleration, Delta, Mechanism, ParallelRobot, Pose, Robot, RusHexapod, State, Twist, C5,
};
use serde_json::Value;
use std::path::{Path, PathBuf};
use support::{c5, c5_ok};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-identify-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A robot unlike the default, with friction: what the "measurements" come from.
fn measured_robot() -> (Robot, [Friction; 6]) {
    let mut robot = Robot::default();
    robot.platform.mass = 12.5;
    robot.platform.com = [0.01, -0.015, 0.02];
    for (i, s) in robot.segments.iter_mut().enumerate() {
        s.joint.mass += 0.1 * i as f64;
        s.joint.com = [0.005, -0.004 * i as f64, 0.01];
    }
    let friction = std::array::from_fn(|i| Friction {
        viscous: 5.0 + i as f64,
        coulomb: 2.0 - 0.1 * i as f64,
    });
    (robot, friction)
}

fn forces(c5: &C5, friction: &[Friction; 6], state: &State) -> [f64; 6] {
    let gamma = c5.inverse_dynamics(state).unwrap();
    let qd = c5.joint_velocities(&state.pose, &state.twist).unwrap();
    std::array::from_fn(|i| {
        gamma[i] + friction[i].viscous * qd[i] + friction[i].coulomb * qd[i].signum()
    })
}

/// Appends `gamma1..6` of the measured robot to an `excite` file; `derivatives: false` drops
/// the twist and acceleration columns (as a position-only logger would).
fn add_forces(traj: &Path, data: &Path, derivatives: bool) {
    let (robot, friction) = measured_robot();
    let truth = C5::new(robot).unwrap();
    let mut reader = csv::Reader::from_path(traj).unwrap();
    let mut writer = csv::Writer::from_path(data).unwrap();
    let keep = if derivatives { 19 } else { 7 };
    let mut header: Vec<String> = reader
        .headers()
        .unwrap()
        .iter()
        .take(keep)
        .map(String::from)
        .collect();
    header.extend((1..=6).map(|i| format!("gamma{i}")));
    writer.write_record(&header).unwrap();
    for record in reader.records() {
        let v: Vec<f64> = record.unwrap().iter().map(|f| f.parse().unwrap()).collect();
        let state = State {
            pose: c5_runtime::Pose::from_array(std::array::from_fn(|k| v[1 + k])),
            twist: c5_runtime::Twist::from_array(std::array::from_fn(|k| v[7 + k])),
            accel: c5_runtime::Acceleration::from_array(std::array::from_fn(|k| v[13 + k])),
        };
        let mut row: Vec<String> = v[..keep].iter().map(|x| format!("{x:e}")).collect();
        row.extend(
            forces(&truth, &friction, &state)
                .iter()
                .map(|x| format!("{x:e}")),
        );
        writer.write_record(&row).unwrap();
    }
    writer.flush().unwrap();
}

#[test]
fn excite_identify_and_eval_round_trip() {
    let dir = scratch("round-trip");
    let traj = dir.join("traj.csv");
    let out = c5_ok(
        &[
            "excite",
            "--out",
            traj.to_str().unwrap(),
            "--candidates",
            "60",
        ],
        "",
    );
    let report = String::from_utf8(out.stdout).unwrap();
    assert!(
        report.contains("Section 9's straight move: infinite"),
        "{report}"
    );
    let data = dir.join("data.csv");
    add_forces(&traj, &data, true);
    let params = dir.join("params.json");
    c5_ok(
        &[
            "identify",
            "--data",
            data.to_str().unwrap(),
            "--out",
            params.to_str().unwrap(),
        ],
        "",
    );
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&params).unwrap()).unwrap();
    assert_eq!(json["model"], "consistent");
    assert_eq!(json["names"].as_array().unwrap().len(), 46);
    assert!(json["condition_number"].as_f64().unwrap() < 1e4);
    let names = json["names"].as_array().unwrap();
    let at = |name: &str| {
        let j = names.iter().position(|n| n == name).unwrap();
        json["values"][j].as_f64().unwrap()
    };
    assert!(
        (at("platform_mass") - 12.5).abs() < 1e-8,
        "{}",
        at("platform_mass")
    );
    assert!((at("fv3") - 7.0).abs() < 1e-8 && (at("fc6") - 1.5).abs() < 1e-8);
    // The identified robot predicts the measured robot's forces at a state off the data.
    let (robot, friction) = measured_robot();
    let truth = C5::new(robot).unwrap();
    let state = State {
        pose: c5_runtime::Pose::from_array([0.1, -0.05, 0.2, 0.01, 0.02, -0.01]),
        twist: c5_runtime::Twist::from_array([0.3, -0.2, 0.1, 0.05, -0.02, 0.04]),
        accel: c5_runtime::Acceleration::from_array([1.0, 0.5, -0.7, 0.3, 0.2, -0.4]),
    };
    let line = r#"{"pose":[0.1,-0.05,0.2,0.01,0.02,-0.01],"omega":[0.3,-0.2,0.1],"velocity":[0.05,-0.02,0.04],"omega_dot":[1.0,0.5,-0.7],"acceleration":[0.3,0.2,-0.4]}"#;
    let out = c5_ok(
        &["eval", "--base-parameters", params.to_str().unwrap()],
        &format!("{line}\n"),
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let want = forces(&truth, &friction, &state);
    for i in 0..6 {
        let got = v["gamma"][i].as_f64().unwrap();
        assert!((got - want[i]).abs() < 1e-8 * 100.0, "{got} vs {}", want[i]);
    }
    // Parameters of one model are refused for the other.
    let out = c5(
        &[
            "eval",
            "--model",
            "paper",
            "--base-parameters",
            params.to_str().unwrap(),
        ],
        &format!("{line}\n"),
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--model consistent"));
}

#[test]
fn positions_only_identify_through_finite_differences() {
    let dir = scratch("positions");
    let traj = dir.join("traj.csv");
    c5_ok(
        &[
            "excite",
            "--out",
            traj.to_str().unwrap(),
            "--candidates",
            "40",
            "--rate",
            "1000",
        ],
        "",
    );
    let data = dir.join("data.csv");
    add_forces(&traj, &data, false);
    let out = c5_ok(&["identify", "--data", data.to_str().unwrap()], "");
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mass = json["values"][0].as_f64().unwrap();
    // Second differences at 1 kHz of a smooth motion: close, not exact.
    assert!((mass - 12.5).abs() < 0.05, "platform mass {mass}");
}

#[test]
fn bad_data_is_refused_with_the_file_and_line() {
    let dir = scratch("bad");
    let good_header = "t,alpha,beta,gamma,xc,yc,zc,gamma1,gamma2,gamma3,gamma4,gamma5,gamma6";
    let row = |t: f64| format!("{t},0.1,0.1,0.1,0,0,0,1,2,3,4,5,6");
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "no-forces.csv",
            format!("t,alpha,beta,gamma,xc,yc,zc\n{}\n", "0,0,0,0,0,0,0"),
            "missing column(s) gamma1",
        ),
        (
            "not-a-number.csv",
            format!("{good_header}\n{}\n{}\n0.2,0.1,x,0.1,0,0,0,1,2,3,4,5,6\n", row(0.0), row(0.1)),
            "not-a-number.csv:4: `beta` = \"x\" is not a number",
        ),
        (
            "backwards.csv",
            format!("{good_header}\n{}\n{}\n", row(0.1), row(0.0)),
            "backwards.csv:3: time must increase",
        ),
        (
            "few.csv",
            format!("{good_header}\n{}\n{}\n{}\n", row(0.0), row(0.1), row(0.2)),
            "too few samples: 3",
        ),
        (
            "still.csv",
            format!(
                "{good_header}\n{}\n",
                (0..100).map(|k| row(k as f64 * 0.01)).collect::<Vec<_>>().join("\n")
            ),
            "cannot identify",
        ),
        (
            "singular.csv",
            format!(
                "{good_header}\n{}\n{}\n0.2,0,1.5707963267948966,1.5707963267948966,0,0,0,1,2,3,4,5,6\n",
                row(0.0),
                row(0.1)
            ),
            "singular.csv:4: singular pose",
        ),
    ];
    for (name, contents, expected) in cases {
        let path = dir.join(name);
        std::fs::write(&path, contents).unwrap();
        let out_json = dir.join(format!("{name}.json"));
        let out = c5(
            &[
                "identify",
                "--data",
                path.to_str().unwrap(),
                "--out",
                out_json.to_str().unwrap(),
            ],
            "",
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name} accepted");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert!(!out_json.exists(), "{name}: wrote a result");
    }
}

#[test]
fn an_infinite_relative_deviation_survives_json() {
    let e = c5_runtime::identify::Estimate {
        model: c5_runtime::Model::Consistent.name().to_string(),
        names: vec!["a".into(), "b".into()],
        values: vec![0.0, 2.0],
        std_dev: vec![0.1, 0.2],
        relative_std_dev_percent: vec![f64::INFINITY, 10.0],
        condition_number: 3.0,
        residual_rms: vec![0.5; 6],
        samples: 100,
    };
    let text = serde_json::to_string(&e).unwrap();
    assert!(
        text.contains("\"relative_std_dev_percent\":[null,10.0]"),
        "{text}"
    );
    let back: c5_runtime::identify::Estimate = serde_json::from_str(&text).unwrap();
    assert_eq!(back, e);
}

/// An unseen robot: off-centre masses, full inertias, another spacing.
fn unseen_robot() -> Robot {
    let mut robot = Robot {
        half_spacing: 0.23,
        ..Robot::default()
    };
    robot.platform.mass = 13.1;
    robot.platform.com = [-0.012, 0.018, 0.009];
    robot.platform.inertia = [
        [0.41, 0.012, -0.008],
        [0.012, 0.22, 0.006],
        [-0.008, 0.006, 0.25],
    ];
    for (i, s) in robot.segments.iter_mut().enumerate() {
        let k = i as f64;
        s.rod.mass = 1.8 + 0.07 * k;
        s.joint.mass = 1.4 + 0.05 * k;
        s.joint.com = [0.006 - 0.002 * k, 0.003 * k, -0.008];
    }
    robot.validate().unwrap();
    robot
}

#[test]
fn an_encoder_log_of_an_unseen_robot_identifies_it_through_the_command_line() {
    let dir = scratch("encoder-log");
    let robot = unseen_robot();
    let file = dir.join("unseen.toml");
    std::fs::write(&file, robot.to_toml()).unwrap();
    let path = |name: &str| dir.join(name).display().to_string();
    let run = |args: &[&str]| c5_ok(args, "");
    // What an experiment records: an exciting trajectory at 1 kHz, the encoders at 1e-7 m a
    // count, the forces with 0.5 N of noise.
    run(&[
        "excite",
        "--rate",
        "1000",
        "--robot",
        &path("unseen.toml"),
        "--out",
        &path("excite.csv"),
    ]);
    run(&[
        "simulate",
        "--robot",
        &path("unseen.toml"),
        "--trajectory",
        &path("excite.csv"),
        "--out",
        &path("sim"),
        "--encoder-log",
        &path("log.csv"),
        "--encoder-resolution",
        "1e-7",
        "--force-noise",
        "0.5",
        "--seed",
        "7",
    ]);
    let header = std::fs::read_to_string(dir.join("log.csv")).unwrap();
    assert!(header.starts_with("t,q1,q2,q3,q4,q5,q6,gamma1,gamma2,gamma3,gamma4,gamma5,gamma6\n"));
    let summary = run(&[
        "identify",
        "--data",
        &path("log.csv"),
        "--robot",
        &path("unseen.toml"),
        "--out",
        &path("params.json"),
    ]);
    let summary = String::from_utf8(summary.stdout).unwrap();
    assert!(summary.contains("an encoder log at 1000 Hz"), "{summary}");
    let params: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("params.json")).unwrap()).unwrap();
    assert_eq!(params["filter"]["cutoff_hz"], 40.0);
    assert_eq!(params["filter"]["decimate"], 5);
    // Unseen states of the identification envelope (the box `excite` searches), any rates.
    let truth = C5::new(robot).unwrap();
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(17);
    let mut u = |b: f64| rand::Rng::gen_range(&mut rng, -b..=b);
    let states: Vec<State> = (0..1000)
        .map(|_| State {
            pose: c5_runtime::Pose::from_array([
                u(0.35),
                u(0.35),
                u(0.35),
                u(0.05),
                u(0.05),
                u(0.05),
            ]),
            twist: c5_runtime::Twist {
                omega: [u(1.0), u(1.0), u(1.0)],
                velocity: [u(0.2), u(0.2), u(0.2)],
            },
            accel: c5_runtime::Acceleration {
                omega_dot: [u(4.0), u(4.0), u(4.0)],
                linear: [u(2.0), u(2.0), u(2.0)],
            },
        })
        .collect();
    let input: Vec<String> = states
        .iter()
        .map(|s| {
            serde_json::json!({
                "pose": s.pose.to_array(), "omega": s.twist.omega, "velocity": s.twist.velocity,
                "omega_dot": s.accel.omega_dot, "acceleration": s.accel.linear
            })
            .to_string()
        })
        .collect();
    let out = c5(
        &[
            "eval",
            "--robot",
            &path("unseen.toml"),
            "--base-parameters",
            &path("params.json"),
        ],
        &input.join("\n"),
    );
    assert!(out.status.success());
    let (rms, worst, force_rms) = force_errors(
        &out.stdout,
        states
            .iter()
            .map(|s| truth.inverse_dynamics(s).unwrap().to_vec()),
    );
    println!("forces RMS {force_rms:.1} N: error RMS {rms:.3} N, largest {worst:.3} N");
    assert!(rms < 0.15 && worst < 0.5, "RMS {rms}, largest {worst}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `excite` on the robot file `file`, the forces of `robot` (its description) with friction
/// "measured" along that trajectory, `identify` from them, then `eval --base-parameters` on
/// `states`: the identified parameters (`base` of them) predict the measured forces. The
/// files and lines are in the platform's coordinates.
pub(crate) fn identification_round_trip(
    file: &str,
    robot: &dyn Mechanism,
    states: &[State],
    base: usize,
) {
    let dir = scratch(&format!("round-trip-{}", robot.mechanism()));
    let trajectory = dir.join("excite.csv");
    let excited = c5_ok(
        &[
            "excite",
            "--robot",
            file,
            "--out",
            trajectory.to_str().unwrap(),
            "--candidates",
            "40",
            "--rate",
            "100",
        ],
        "",
    );
    let report = String::from_utf8_lossy(&excited.stdout);
    assert!(
        report.contains(&format!("{} model", robot.mechanism())),
        "{report}"
    );
    let freedom = robot.freedom();
    let n = freedom.dimension();
    let friction: Vec<(f64, f64)> = (0..n)
        .map(|i| (4.0 + i as f64, 1.0 + 0.2 * i as f64))
        .collect();
    let measured = |[x, v, a]: &[Vec<f64>; 3]| -> Vec<f64> {
        let (mut gamma, mut qd) = (vec![0.0; n], vec![0.0; n]);
        robot.inverse_dynamics(x, v, a, &mut gamma).unwrap();
        robot.joint_velocities(x, v, &mut qd).unwrap();
        (0..n)
            .map(|i| gamma[i] + friction[i].0 * qd[i] + friction[i].1 * qd[i].signum())
            .collect()
    };
    let data = dir.join("measured.csv");
    let mut reader = csv::Reader::from_path(&trajectory).unwrap();
    let mut writer = csv::Writer::from_path(&data).unwrap();
    let mut header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header.len(), 1 + 3 * n, "{header:?}");
    header.extend((1..=n).map(|i| format!("gamma{i}")));
    writer.write_record(&header).unwrap();
    for record in reader.records() {
        let v: Vec<f64> = record.unwrap().iter().map(|f| f.parse().unwrap()).collect();
        let motion = [0, 1, 2].map(|p| v[1 + p * n..1 + (p + 1) * n].to_vec());
        let mut row: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
        row.extend(measured(&motion).iter().map(|x| format!("{x:e}")));
        writer.write_record(&row).unwrap();
    }
    writer.flush().unwrap();
    let params = dir.join("identified.json");
    let identified = c5_ok(
        &[
            "identify",
            "--robot",
            file,
            "--data",
            data.to_str().unwrap(),
            "--out",
            params.to_str().unwrap(),
        ],
        "",
    );
    let report = String::from_utf8_lossy(&identified.stdout);
    assert!(
        report.contains(&format!("{base} base parameters")),
        "{report}"
    );
    let motions: Vec<[Vec<f64>; 3]> = states
        .iter()
        .map(|s| robot.coordinates_of(s).unwrap())
        .collect();
    let input: String = motions
        .iter()
        .map(|[x, v, a]| {
            let mut line = serde_json::json!({ "pose": x });
            for (part, values) in freedom.twist_parts().iter().zip(v.chunks(3)) {
                line[*part] = serde_json::json!(values);
            }
            for (part, values) in freedom.acceleration_parts().iter().zip(a.chunks(3)) {
                line[*part] = serde_json::json!(values);
            }
            line.to_string() + "\n"
        })
        .collect();
    let predicted = c5_ok(
        &[
            "eval",
            "--robot",
            file,
            "--base-parameters",
            params.to_str().unwrap(),
        ],
        &input,
    );
    let lines = String::from_utf8_lossy(&predicted.stdout);
    assert_eq!(lines.lines().count(), states.len(), "{lines}");
    for (line, motion) in lines.lines().zip(&motions) {
        let line: Value = serde_json::from_str(line).unwrap();
        let gamma: Vec<f64> = line["gamma"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g.as_f64().unwrap())
            .collect();
        let want = measured(motion);
        assert_eq!(gamma.len(), n, "{line}");
        for (got, want) in gamma.iter().zip(want) {
            assert!(
                (got - want).abs() < 1e-6 * want.abs().max(1.0),
                "{}: {got} vs {want}",
                robot.mechanism()
            );
        }
    }
}

/// The rotary hexapod's file through `excite`, `identify` and `eval --base-parameters`.
#[test]
fn excite_and_identify_serve_the_rotary_hexapod() {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/rus-hexapod.toml");
    let text = std::fs::read_to_string(file).unwrap();
    let robot = RusHexapod::new(c5_robot::RusHexapod::from_toml(&text, file).unwrap()).unwrap();
    let home = robot.home().to_array();
    let states: Vec<State> = (0..5)
        .map(|k| {
            let s = |a: f64| (a * (k as f64 + 1.0)).sin();
            let offset = [
                0.08 * s(1.1),
                -0.06 * s(0.7),
                0.08 * s(1.9),
                0.02 * s(2.3),
                -0.02 * s(0.3),
                0.02 * s(1.3),
            ];
            State {
                pose: Pose::from_array(std::array::from_fn(|j| home[j] + offset[j])),
                twist: Twist::from_array([
                    0.3 * s(0.5),
                    -0.2,
                    0.1 * s(1.7),
                    0.05,
                    0.02 * s(0.9),
                    -0.04,
                ]),
                accel: Acceleration::from_array([1.0 * s(0.4), 0.5, -0.8, 0.3 * s(1.2), -0.2, 0.4]),
            }
        })
        .collect();
    identification_round_trip(file, &*robot.into_mechanism(), &states, 46);
}

/// The Delta's file through `excite`, `identify` and `eval --base-parameters`, in its three
/// coordinates: the CSV columns `t, xc, yc, zc, vx.., ax..` and the forces `gamma1..gamma3`.
#[test]
fn excite_and_identify_serve_the_delta() {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/delta.toml");
    let text = std::fs::read_to_string(file).unwrap();
    let robot = Delta::new(c5_robot::Delta::from_toml(&text, file).unwrap()).unwrap();
    let home = robot.home();
    let states: Vec<State> = (0..5)
        .map(|k| {
            let s = |a: f64| (a * (k as f64 + 1.0)).sin();
            let mut state = State::default();
            state.pose.center = [
                home[0] + 0.03 * s(1.1),
                home[1] - 0.02 * s(0.7),
                home[2] + 0.03 * s(1.9),
            ];
            state.twist.velocity = [0.3 * s(0.5), -0.2, 0.1 * s(1.7)];
            state.accel.linear = [1.0 * s(0.4), 0.5, -0.8];
            state
        })
        .collect();
    let robot = robot.into_mechanism();
    let base = robot.base_parameters().unwrap().len();
    assert!((10..34).contains(&base), "{base} base parameters");
    identification_round_trip(file, &*robot, &states, base);
}

/// What an experiment on a Delta records (`simulate --encoder-log`: `t, q1..q3,
/// gamma1..gamma3`, the encoders at 1e-6 rad a count, the torques with 0.01 N·m of noise)
/// identifies it through the filter, the differences and the closed-form forward kinematics:
/// the identified parameters predict the torques of unseen states.
#[test]
fn an_encoder_log_of_a_delta_identifies_it() {
    let dir = scratch("delta-encoder-log");
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/delta.toml");
    let path = |name: &str| dir.join(name).display().to_string();
    let run = |args: &[&str]| c5_ok(args, "");
    let excite = path("excite.csv");
    run(&[
        "excite", "--rate", "1000", "--robot", file, "--out", &excite,
    ]);
    let log = path("log.csv");
    run(&[
        "simulate",
        "--robot",
        file,
        "--trajectory",
        &excite,
        "--out",
        &path("sim"),
        "--encoder-log",
        &log,
        "--encoder-resolution",
        "1e-6",
        "--force-noise",
        "0.01",
        "--seed",
        "3",
    ]);
    let header = std::fs::read_to_string(&log).unwrap();
    assert!(header.starts_with("t,q1,q2,q3,gamma1,gamma2,gamma3\n"));
    let params = path("params.json");
    let summary = run(&[
        "identify", "--data", &log, "--robot", file, "--out", &params,
    ]);
    let summary = String::from_utf8(summary.stdout).unwrap();
    assert!(summary.contains("an encoder log at 1000 Hz"), "{summary}");
    assert!(
        summary.contains("delta model: 19 base parameters"),
        "{summary}"
    );
    let text = std::fs::read_to_string(file).unwrap();
    let truth = Delta::new(c5_robot::Delta::from_toml(&text, file).unwrap()).unwrap();
    let home = truth.home();
    let truth = truth.into_mechanism();
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(19);
    let mut u = |b: f64| rand::Rng::gen_range(&mut rng, -b..=b);
    let states: Vec<[[f64; 3]; 3]> = (0..500)
        .map(|_| {
            [
                std::array::from_fn(|k| home[k] + u(0.04)),
                std::array::from_fn(|_| u(0.2)),
                std::array::from_fn(|_| u(2.0)),
            ]
        })
        .collect();
    let input: Vec<String> = states
        .iter()
        .map(|[x, v, a]| {
            serde_json::json!({"pose": x, "velocity": v, "acceleration": a}).to_string()
        })
        .collect();
    let out = c5_ok(
        &["eval", "--robot", file, "--base-parameters", &params],
        &input.join("\n"),
    );
    let (rms, worst, torque_rms) = force_errors(
        &out.stdout,
        states.iter().map(|[x, v, a]| {
            let mut want = vec![0.0; 3];
            truth.inverse_dynamics(x, v, a, &mut want).unwrap();
            want
        }),
    );
    println!("torques RMS {torque_rms:.3} N·m: error RMS {rms:.2e} N·m, largest {worst:.2e} N·m");
    assert!(
        rms < 0.003 * torque_rms && worst < 0.01 * torque_rms,
        "RMS {rms}, largest {worst}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The RMS and the largest difference of the `gamma` of `eval`'s lines `stdout` from `want`
/// (each line's forces), and the RMS of `want`.
fn force_errors(stdout: &[u8], want: impl Iterator<Item = Vec<f64>>) -> (f64, f64, f64) {
    let (mut sq, mut worst, mut force_sq, mut n) = (0.0, 0.0_f64, 0.0, 0.0);
    for (line, want) in String::from_utf8_lossy(stdout).lines().zip(want) {
        let line: Value = serde_json::from_str(line).unwrap();
        for (i, w) in want.iter().enumerate() {
            let e = line["gamma"][i].as_f64().unwrap() - w;
            sq += e * e;
            worst = worst.max(e.abs());
            force_sq += w * w;
            n += 1.0;
        }
    }
    ((sq / n).sqrt(), worst, (force_sq / n).sqrt())
}
