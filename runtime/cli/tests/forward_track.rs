//! `c5 forward` (JSON Lines of states and forces → accelerations) and `c5 track` (a
//! computed-torque controller on a simulated robot).

mod support;

use c5_runtime::reference as r;
use c5_runtime::{Model, Pose, Robot, Twist};
use serde_json::Value;
use support::c5;

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-track-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn lines(out: &std::process::Output) -> Vec<Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn forward_agrees_with_the_reference_in_both_models_and_refuses_bad_lines() {
    let pose = Pose::from_array([0.1, -0.2, 0.15, 0.01, 0.02, -0.01]);
    let twist = Twist {
        omega: [0.2, -0.1, 0.3],
        velocity: [0.05, 0.0, -0.02],
    };
    let gamma = [10.0, -5.0, 3.0, 4.0, 90.0, 85.0];
    let line = serde_json::json!({
        "pose": pose.to_array(), "omega": twist.omega, "velocity": twist.velocity, "gamma": gamma,
    })
    .to_string();
    for model in Model::ALL {
        let out = c5(&["forward", "--model", model.name()], &format!("{line}\n"));
        assert!(out.status.success(), "{model}");
        let v = &lines(&out)[0];
        let want = r::forward_dynamics(&Robot::default(), model, &pose, &twist, &gamma).unwrap();
        for k in 0..3 {
            for (key, w) in [
                ("omega_dot", want.omega_dot[k]),
                ("acceleration", want.linear[k]),
            ] {
                let got = v[key][k].as_f64().unwrap();
                assert!(
                    (got - w).abs() < 1e-9 * w.abs().max(1.0),
                    "{model} {key}[{k}]"
                );
            }
        }
    }
    let out = c5(
        &["forward"],
        "{\"pose\": [0, 0, 0, 0, 0, 0]}\n{\"pose\": [0, 0, 0, 0, 0, 0], \"gamma\": [1, 2, 3, 4, 5, 6], \"accel\": [0, 0, 0]}\n",
    );
    let v = lines(&out);
    assert!(!out.status.success());
    assert_eq!(v[0]["error"], "missing `gamma`");
    assert!(v[1]["error"]
        .as_str()
        .unwrap()
        .starts_with("unknown key `accel`"));
}

fn csv_column(path: &std::path::Path, name: &str) -> Vec<f64> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let col = reader
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == name)
        .unwrap();
    reader
        .records()
        .map(|r| r.unwrap()[col].parse().unwrap())
        .collect()
}

#[test]
fn track_follows_the_trajectory_and_recovers_from_an_offset() {
    let dir = scratch("track");
    let out = c5(&["track", "--out", dir.to_str().unwrap()], "");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in [
        "track.csv",
        "track_position_error.png",
        "track_orientation_error.png",
        "track_forces.png",
    ] {
        assert!(dir.join(name).exists(), "{name}");
    }
    let ex = csv_column(&dir.join("track.csv"), "ex_mm");
    assert_eq!(ex.len(), 1001);
    assert!(
        ex.iter().all(|e| e.abs() < 1e-6),
        "an exact model tracks exactly"
    );
    // From 5 mm off in x: back within 1 µm by the end, and never past the trajectory.
    let out = c5(
        &[
            "track",
            "--initial-offset",
            "0.005,0,0,0,0,0",
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    assert!(out.status.success());
    let ex = csv_column(&dir.join("track.csv"), "ex_mm");
    assert!((ex[0] + 5.0).abs() < 1e-9, "{}", ex[0]);
    assert!(ex.last().unwrap().abs() < 1e-3);
    assert!(
        ex.iter().all(|e| *e <= 0.01 * 5.0),
        "no overshoot beyond 1 %"
    );
}

#[test]
fn track_with_the_paper_model_misses_the_mechanism() {
    let dir = scratch("paper");
    let out = c5(
        &["track", "--model", "paper", "--out", dir.to_str().unwrap()],
        "",
    );
    assert!(out.status.success());
    let ez = csv_column(&dir.join("track.csv"), "ez_mm");
    let worst = ez.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    assert!(
        worst > 1.0,
        "the paper model's controller leaves millimetres: {worst}"
    );
}

#[test]
fn track_refuses_bad_options() {
    for (args, needle) in [
        (&["track", "--initial-offset", "1,2"][..], "six numbers"),
        (&["track", "--bandwidth=-3"], "--bandwidth"),
        (&["track", "--force-limit", "0"], "--force-limit"),
        (&["track", "--rate", "1e9"], "steps"),
        (&["track", "--plant-model", "exact"], "consistent"),
    ] {
        let out = c5(args, "");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(needle),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_plant_that_differs_from_the_controllers_robot_is_simulated() {
    let dir = scratch("plant");
    let text = Robot::default()
        .to_toml()
        .replacen("mass = 10.0", "mass = 13.0", 1);
    let file = dir.join("plant.toml");
    std::fs::write(&file, text).unwrap();
    let out = c5(
        &[
            "track",
            "--plant-robot",
            file.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A heavier platform than the controller believes sags under gravity.
    let ez = csv_column(&dir.join("track.csv"), "ez_mm");
    assert!(ez.last().unwrap() > &0.1, "{:?}", ez.last());
}
