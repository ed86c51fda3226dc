//! `c5 forward` (JSON Lines of states and forces → accelerations) and `c5 track` (a
//! computed-torque controller on a simulated robot).

use crate::support;

use c5_runtime::reference as r;
use c5_runtime::{Model, Pose, Robot, Twist};
use serde_json::Value;
use support::{c5, c5_ok};

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
    c5_ok(&["track", "--out", dir.to_str().unwrap()], "");
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
    c5_ok(
        &[
            "track",
            "--plant-robot",
            file.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    // A heavier platform than the controller believes sags under gravity.
    let ez = csv_column(&dir.join("track.csv"), "ez_mm");
    assert!(ez.last().unwrap() > &0.1, "{:?}", ez.last());
}

#[test]
fn the_joint_space_law_with_the_exact_state_gives_each_actuator_the_ideal_error() {
    let dir = scratch("joint-ideal");
    c5_ok(
        &[
            "track",
            "--space",
            "joint",
            "--initial-offset",
            "0.004,-0.003,0.002,0.01,0,-0.02",
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    // Exact models, the continuous law: ë + 2λė + λ²e = 0 per actuator, from rest, so
    // e(t) = e₀ (1 + λt) e^(-λt) (λ = 20 /s).
    let t = csv_column(&dir.join("track.csv"), "t");
    let lambda = 20.0;
    for i in 1..=6 {
        let e = csv_column(&dir.join("track.csv"), &format!("eq{i}_mm"));
        assert!(e[0].abs() > 0.1, "actuator {i} starts off: {}", e[0]);
        for (k, (&t, &got)) in t.iter().zip(&e).enumerate() {
            let want = e[0] * (1.0 + lambda * t) * (-lambda * t).exp();
            assert!(
                (got - want).abs() < 1e-5,
                "actuator {i} at {t} s (#{k}): {got} vs {want} mm"
            );
        }
    }
}

#[test]
fn the_joint_space_law_on_quantized_encoders_tracks_an_exciting_trajectory() {
    let dir = scratch("joint-measured");
    let path = |n: &str| dir.join(n).display().to_string();
    let out = c5(
        &["excite", "--rate", "1000", "--out", &path("excite.csv")],
        "",
    );
    assert!(out.status.success());
    for space in ["joint", "task"] {
        let out = c5_ok(
            &[
                "track",
                "--space",
                space,
                "--trajectory",
                &path("excite.csv"),
                "--encoder-resolution",
                "1e-7",
                "--control-rate",
                "1000",
                "--out",
                &path(space),
            ],
            "",
        );
        let report = String::from_utf8(out.stdout).unwrap();
        assert!(
            report.contains("measured (encoders and estimated rates)"),
            "{report}"
        );
        let csv = dir.join(space).join("track.csv");
        let norm = |cols: [&str; 3]| -> Vec<f64> {
            let c: Vec<Vec<f64>> = cols.iter().map(|n| csv_column(&csv, n)).collect();
            (0..c[0].len())
                .map(|k| (c[0][k].powi(2) + c[1][k].powi(2) + c[2][k].powi(2)).sqrt())
                .collect()
        };
        let position = norm(["ex_mm", "ey_mm", "ez_mm"]);
        let orientation = norm(["erx_mrad", "ery_mrad", "erz_mrad"]);
        let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        let peak = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(*x));
        // 1e-7 m counts, rates by the estimator at 50 Hz, forces held for 1 ms: the error is
        // the counts' and the hold's, tens of micrometres at worst (measured 0.036 mm and
        // 0.24 mrad peak, 0.005 mm and 0.025 mrad RMS).
        assert!(peak(&position) < 0.1 && rms(&position) < 0.01, "{space}");
        assert!(
            peak(&orientation) < 0.5 && rms(&orientation) < 0.05,
            "{space}"
        );
    }
    // Out-of-range settings are refused.
    let bad = c5(
        &["track", "--control-rate", "2000", "--out", &path("bad")],
        "",
    );
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--control-rate must be"));
    let bad = c5(
        &["track", "--encoder-resolution", "0", "--out", &path("bad")],
        "",
    );
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--encoder-resolution"));
}
