//! The robot's limits on the command line: a robot file that gives only `[limits]` (everything
//! else the chapter's), `eval --strict-limits` refusing by name, `eval`'s `limits` key, `track`
//! and `simulate` stopping at the first violation, `workspace` mapping a grid.

use crate::support;

use serde_json::Value;
use std::path::PathBuf;

fn robot_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-limits-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const LIMITS: &str = "[limits]\nstroke = [-0.1, 0.1]\nplate_travel = 0.15\ntilt = 0.5\n";

fn eval(args: &[&str], input: &str) -> Vec<Value> {
    let out = support::c5(args, input);
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn strict_eval_accepts_inside_and_refuses_stroke_and_tilt_by_name() {
    let robot = robot_file("only-limits.toml", LIMITS);
    let robot = robot.to_str().unwrap();
    let input = [
        // Inside: a small turn and offset.
        r#"{"pose": [0.1, 0.2, 0.15, 0.02, -0.01, 0.03]}"#,
        // At zero orientation Q1 = Q2 = xc: 0.12 m leaves the ±0.1 m stroke.
        r#"{"pose": [0, 0, 0, 0.12, 0, 0]}"#,
        // α = 0.6 rad tilts the balls of segments 3-6 past 0.5 rad (r22 = r33 = cos 0.6).
        r#"{"pose": [0.6, 0, 0, 0, 0, 0]}"#,
    ]
    .join("\n");
    let out = eval(&["eval", "--robot", robot, "--strict-limits"], &input);
    assert_eq!(out.len(), 3);
    assert!(out[0]["gamma"].is_array(), "{}", out[0]);
    let limits = &out[0]["limits"];
    assert!(limits["margin"].as_f64().unwrap() > 0.0, "{limits}");
    let e = out[1]["error"].as_str().unwrap();
    assert!(
        e.starts_with("stroke limit exceeded at actuator 1: 0.12"),
        "{e}"
    );
    let e = out[2]["error"].as_str().unwrap();
    assert!(
        e.starts_with("tilt limit exceeded at actuator 3: 0.6"),
        "{e}"
    );
    // The rest of the robot is the chapter's: the forces at the home pose are its statics.
    let home = eval(
        &["eval", "--robot", robot],
        r#"{"pose": [0, 0, 0, 0, 0, 0]}"#,
    );
    let gamma = home[0]["gamma"].as_array().unwrap();
    assert!(
        (gamma[4].as_f64().unwrap() - 85.0527).abs() < 1e-3,
        "{gamma:?}"
    );
    // Without --strict-limits the line is answered, its smallest margin negative.
    let lax = eval(
        &["eval", "--robot", robot],
        r#"{"pose": [0, 0, 0, 0.12, 0, 0]}"#,
    );
    assert_eq!(lax[0]["limits"]["limit"], "stroke");
    assert!((lax[0]["limits"]["margin"].as_f64().unwrap() + 0.02).abs() < 1e-12);
}

#[test]
fn track_and_simulate_stop_at_the_first_violation_unless_told_otherwise() {
    let robot = robot_file("track-limits.toml", LIMITS);
    let robot = robot.to_str().unwrap();
    let dir = std::env::temp_dir().join(format!("c5-limits-track-{}", std::process::id()));
    let dir = dir.to_str().unwrap();
    let out = support::c5(
        &[
            "track",
            "--robot",
            robot,
            "--initial-offset",
            "0.5,0,0,0,0,0",
            "--out",
            dir,
        ],
        "",
    );
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("step at t = 0 s: ") && e.contains("limit exceeded at actuator"),
        "{e}"
    );
    let tight = robot_file("tight.toml", "[limits]\nstroke = [-0.05, 0.05]\n");
    let tight = tight.to_str().unwrap();
    let out = support::c5(&["simulate", "--robot", tight, "--out", dir], "");
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("stroke limit exceeded") && e.contains("--ignore-limits"),
        "{e}"
    );
    support::c5_ok(
        &[
            "simulate",
            "--robot",
            tight,
            "--out",
            dir,
            "--ignore-limits",
        ],
        "",
    );
    // A trajectory file names its output after itself.
    let trajectory = std::path::Path::new(dir).join("section9.csv");
    let renamed = std::path::Path::new(dir).join("my_move.csv");
    std::fs::copy(&trajectory, &renamed).unwrap();
    let out2 = std::path::Path::new(dir).join("again");
    support::c5_ok(
        &[
            "simulate",
            "--trajectory",
            renamed.to_str().unwrap(),
            "--out",
            out2.to_str().unwrap(),
        ],
        "",
    );
    assert!(out2.join("my_move.csv").exists());
    assert!(!out2.join("section9.csv").exists());
}

#[test]
fn workspace_maps_a_grid_and_reports_its_volume() {
    let robot = robot_file("ws.toml", "[limits]\nstroke = [-0.1, 0.1]\n");
    let dir = std::env::temp_dir().join(format!("c5-limits-ws-{}", std::process::id()));
    let out = support::c5_ok(
        &[
            "workspace",
            "--robot",
            robot.to_str().unwrap(),
            "--points",
            "21",
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    let report = String::from_utf8_lossy(&out.stdout);
    // ±0.3 m in 21 points: 0.03 m apart, so the box ±0.1 m holds 7 points a side (−0.09 to
    // 0.09), 343 of 9261 poses, 343 · 0.03³ m³.
    assert!(report.contains("343 of 9261 poses reachable"), "{report}");
    assert!(report.contains("volume 0.009261 m³"), "{report}");
    let csv = std::fs::read_to_string(dir.join("workspace.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 343);
    for png in ["workspace_dexterity.png", "workspace_force_ratio.png"] {
        assert!(std::fs::metadata(dir.join(png)).unwrap().len() > 1000);
    }
}
