//! `--robot FILE.toml` and `--trajectory FILE.csv`: good files are used, bad ones are refused
//! with the file, the field or line, and the rule, and nothing is written.

use crate::support;
use c5_runtime::reference::{self as r, consistent as rc, Step6};
use c5_runtime::trajectory::LinearMove;
use c5_runtime::Robot;

use std::path::{Path, PathBuf};
use support::{c5, c5_ok};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn default_toml() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/default-robot.toml"),
    )
    .unwrap()
}

#[test]
fn docs_default_robot_is_the_default_robot() {
    assert_eq!(
        Robot::from_toml(&default_toml(), "docs/default-robot.toml").unwrap(),
        Robot::default()
    );
}

#[test]
fn bad_robot_files_are_refused_and_nothing_is_written() {
    let dir = scratch("bad-robot");
    let cases = [
        (
            "unknown.toml",
            default_toml().replacen("half_spacing = 0.2\n", "half_width = 0.2\n", 1),
            "unknown field `half_width`",
        ),
        (
            "type.toml",
            default_toml().replacen("mass = 10.0", "mass = \"heavy\"", 1),
            "invalid type",
        ),
        (
            "mass.toml",
            default_toml().replacen("mass = 1.67", "mass = 0.0", 1),
            "`segments[1].joint.mass` must be positive",
        ),
        (
            "inertia.toml",
            default_toml().replacen("[[0.375, 0.0, 0.0]", "[[-0.375, 0.0, 0.0]", 1),
            "`platform.inertia` must be positive definite",
        ),
        (
            "triangle.toml",
            default_toml().replacen("[[0.375, 0.0, 0.0]", "[[0.5, 0.0, 0.0]", 1),
            "`platform.inertia` breaks the triangle inequality Ixx ≤ Iyy + Izz",
        ),
    ];
    for (name, text, needle) in cases {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        let out_dir = dir.join(format!("{name}-out"));
        let out = c5(
            &[
                "simulate",
                "--robot",
                file.to_str().unwrap(),
                "--out",
                out_dir.to_str().unwrap(),
            ],
            "",
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}");
        assert!(
            err.contains(file.to_str().unwrap()) && err.contains(needle),
            "{name}: {err}"
        );
        assert!(!out_dir.exists(), "{name}: nothing is written");
        let out = c5(
            &["eval", "--robot", file.to_str().unwrap()],
            "{\"pose\": [0,0,0,0,0,0]}\n",
        );
        assert!(
            !out.status.success() && out.stdout.is_empty(),
            "{name}: eval refuses too"
        );
    }
}

#[test]
fn eval_uses_the_robot_file() {
    let dir = scratch("robot");
    let text = default_toml()
        .replacen("mass = 10.0", "mass = 14.0", 1)
        .replacen("half_spacing = 0.2", "half_spacing = 0.25", 1);
    let file = dir.join("robot.toml");
    std::fs::write(&file, &text).unwrap();
    let robot = Robot::from_toml(&text, "robot.toml").unwrap();
    let line = "{\"pose\": [0.1, 0.2, 0.3, 0.01, 0.0, 0.02], \"omega\": [0.3, 0, 0]}\n";
    let pose = c5_runtime::Pose::from_array([0.1, 0.2, 0.3, 0.01, 0.0, 0.02]);
    let twist = c5_runtime::Twist {
        omega: [0.3, 0.0, 0.0],
        velocity: [0.0; 3],
    };
    let consistent: [f64; 6] = rc::inverse_dynamics(&robot, &pose, &twist, &Default::default())
        .unwrap()
        .into();
    let paper = r::to_segment_order(
        &r::inverse_dynamics(&robot, &pose, &twist, &Default::default(), Step6::Khalil).unwrap(),
    );
    for (model, want) in [("consistent", consistent), ("paper", paper)] {
        let out = c5(
            &["eval", "--robot", file.to_str().unwrap(), "--model", model],
            line,
        );
        assert!(out.status.success());
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        for i in 0..6 {
            assert!(
                (v["gamma"][i].as_f64().unwrap() - want[i]).abs() < 1e-9 * 200.0,
                "{model}"
            );
        }
    }
    // The default is the consistent model.
    let out = c5(&["eval", "--robot", file.to_str().unwrap()], line);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((v["gamma"][0].as_f64().unwrap() - consistent[0]).abs() < 1e-9 * 200.0);
}

#[test]
fn trajectory_csv_with_poses_only_gets_its_derivatives_by_finite_differences() {
    let dir = scratch("trajectory");
    let motion = LinearMove::section9();
    let mut csv = String::from("t,alpha,beta,gamma,xc,yc,zc\n");
    for t in motion.times(1000.0) {
        let p = motion.state(t).pose.to_array();
        csv.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            p[0], p[1], p[2], p[3], p[4], p[5]
        ));
    }
    let file = dir.join("traj.csv");
    std::fs::write(&file, csv).unwrap();
    let out_dir = dir.join("out");
    c5_ok(
        &[
            "simulate",
            "--trajectory",
            file.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ],
        "",
    );
    // Named after the trajectory file.
    let mut rows = csv::Reader::from_path(out_dir.join("traj.csv")).unwrap();
    let header = rows.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let robot = Robot::default();
    for rec in rows.records().map(Result::unwrap).filter(|r| {
        let t: f64 = r[0].parse().unwrap();
        (0.05..0.95).contains(&t)
    }) {
        let t: f64 = rec[0].parse().unwrap();
        let s = motion.state(t);
        let consistent = rc::inverse_dynamics(&robot, &s.pose, &s.twist, &s.accel).unwrap();
        let paper = r::to_segment_order(
            &r::inverse_dynamics(&robot, &s.pose, &s.twist, &s.accel, Step6::Khalil).unwrap(),
        );
        for i in 0..6 {
            for (column, want) in [("gamma", consistent[i]), ("gamma_paper", paper[i])] {
                let got: f64 = rec[col(&format!("{column}{}", i + 1))].parse().unwrap();
                assert!(
                    (got - want).abs() < 1e-3,
                    "t={t} {column}{}: {got} vs {want}",
                    i + 1
                );
            }
        }
    }
}

#[test]
fn bad_trajectory_files_name_the_line() {
    let dir = scratch("bad-trajectory");
    let cases = [
        (
            "t,alpha,beta,gamma,xc,yc\n0,0,0,0,0,0\n",
            ":1: missing column(s) zc",
        ),
        (
            "t,alpha,beta,gamma,xc,yc,zc\n0,0,0,0,0,0,0\n0.1,0,0,x,0,0,0\n",
            ":3: `gamma` = \"x\" is not a number",
        ),
        (
            "t,alpha,beta,gamma,xc,yc,zc\n0,0,0,0,0,0,0\n0,0,0,0,0,0,0\n",
            ":3: time must increase",
        ),
        (
            "t,alpha,beta,gamma,xc,yc,zc,wx\n0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0\n",
            "missing column(s) wy, wz, vx, vy, vz",
        ),
    ];
    for (k, (text, needle)) in cases.iter().enumerate() {
        let file = dir.join(format!("bad{k}.csv"));
        std::fs::write(&file, text).unwrap();
        let out_dir = dir.join(format!("out{k}"));
        let out = c5(
            &[
                "simulate",
                "--trajectory",
                file.to_str().unwrap(),
                "--out",
                out_dir.to_str().unwrap(),
            ],
            "",
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(needle),
            "case {k}: {err}"
        );
        assert!(!out_dir.exists());
    }
}

/// The default move on a robot that cannot take all of Section 9's turn (the rotary hexapod's
/// example loses its hold at 0.65 s): its angles scaled down by tenths until every state is
/// served, said so; the C5 takes the whole turn.
#[test]
fn the_default_move_fits_the_robots_reach_and_says_so() {
    let dir = scratch("default-move");
    let rus = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/rus-hexapod.toml");
    let deg = std::f64::consts::PI / 180.0;
    for (robot, scale) in [(Some(rus), 0.8), (None, 1.0)] {
        let out = dir.join(format!("{scale}"));
        let mut args = vec!["simulate", "--out", out.to_str().unwrap(), "--rate", "200"];
        args.extend(robot.map(|r| ["--robot", r]).into_iter().flatten());
        let report = String::from_utf8_lossy(&c5_ok(&args, "").stdout).to_string();
        assert_eq!(
            report.contains("its orientation scaled to 80 % (this robot cannot take all of it)"),
            scale < 1.0,
            "{report}"
        );
        let mut rows = csv::Reader::from_path(out.join("section9.csv")).unwrap();
        let first = rows.records().next().unwrap().unwrap();
        let angles: Vec<f64> = (1..4).map(|k| first[k].parse().unwrap()).collect();
        for (got, full) in angles.iter().zip([10.0, 15.0, 20.0]) {
            assert!(
                (got - scale * full * deg).abs() < 1e-12,
                "{got} vs {scale} × {full}°"
            );
        }
    }
}
