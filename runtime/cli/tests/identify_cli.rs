//! `c5 excite`, `c5 identify` and `c5 eval --base-parameters`: the round trip identifies a
//! robot that predicts its own forces, and bad data is refused with the file and line.

mod support;

use c5_runtime::identify::Friction;
use c5_runtime::{Robot, State, C5};
use serde_json::Value;
use std::path::{Path, PathBuf};
use support::c5;

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
    let out = c5(
        &[
            "excite",
            "--out",
            traj.to_str().unwrap(),
            "--candidates",
            "60",
        ],
        "",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report = String::from_utf8(out.stdout).unwrap();
    assert!(
        report.contains("Section 9's straight move: infinite"),
        "{report}"
    );
    let data = dir.join("data.csv");
    add_forces(&traj, &data, true);
    let params = dir.join("params.json");
    let out = c5(
        &[
            "identify",
            "--data",
            data.to_str().unwrap(),
            "--out",
            params.to_str().unwrap(),
        ],
        "",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
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
    let out = c5(
        &["eval", "--base-parameters", params.to_str().unwrap()],
        &format!("{line}\n"),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
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
    let out = c5(
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let data = dir.join("data.csv");
    add_forces(&traj, &data, false);
    let out = c5(&["identify", "--data", data.to_str().unwrap()], "");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
        model: c5_runtime::Model::Consistent,
        names: vec!["a".into(), "b".into()],
        values: vec![0.0, 2.0],
        std_dev: vec![0.1, 0.2],
        relative_std_dev_percent: vec![f64::INFINITY, 10.0],
        condition_number: 3.0,
        residual_rms: [0.5; 6],
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
