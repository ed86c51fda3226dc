//! The Gough-Stewart platform on the command line: `eval` and `forward` with `--robot
//! hexapod.toml` give the runtime's numbers to the bit, `eval` fed leg lengths returns the pose
//! they came from, bad hexapod files are refused naming the file and the field, and
//! `simulate`, `track`, `workspace`, `audit` and `plan` serve it.

use crate::support;

use c5_runtime::{GoughStewart, ParallelRobot, Pose, State};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

const EXAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-hexapod-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn lines(out: &std::process::Output) -> Vec<Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn hexapod() -> GoughStewart {
    let text = std::fs::read_to_string(EXAMPLE).unwrap();
    GoughStewart::new(c5_robot::GoughStewart::from_toml(&text, EXAMPLE).unwrap()).unwrap()
}

fn state(k: usize) -> State {
    let s = |a: f64| (a * (k as f64 + 1.0)).sin();
    State {
        pose: Pose::from_array([
            0.2 * s(1.1),
            -0.15 * s(0.7),
            0.2 * s(1.9),
            0.05 * s(2.3),
            -0.04 * s(0.3),
            0.425 + 0.06 * s(1.3),
        ]),
        twist: c5_runtime::Twist::from_array([s(0.4), s(0.8), s(1.2), 0.3 * s(0.5), 0.2, -0.1]),
        accel: c5_runtime::Acceleration::from_array([3.0 * s(0.9), -2.0, 1.0, s(0.2), 0.5, 1.5]),
    }
}

fn array(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .flat_map(|x| match x.as_array() {
            Some(row) => row.iter().map(|y| y.as_f64().unwrap()).collect(),
            None => vec![x.as_f64().unwrap()],
        })
        .collect()
}

#[test]
fn eval_and_forward_serve_the_runtimes_numbers() {
    let robot = hexapod();
    let states: Vec<State> = (0..8).map(state).collect();
    let input: String = states
        .iter()
        .map(|s| {
            json!({
                "pose": s.pose.to_array(),
                "omega": s.twist.omega,
                "velocity": s.twist.velocity,
                "omega_dot": s.accel.omega_dot,
                "acceleration": s.accel.linear,
            })
            .to_string()
                + "\n"
        })
        .collect();
    let out = lines(&support::c5_ok(&["eval", "--robot", EXAMPLE], &input));
    for (s, line) in states.iter().zip(&out) {
        let e = robot.evaluate(s).unwrap();
        assert_eq!(array(&line["q"]), e.q);
        assert_eq!(array(&line["qd"]), e.qd);
        assert_eq!(array(&line["qdd"]), e.qdd);
        assert_eq!(array(&line["gamma"]), e.gamma);
        assert_eq!(array(&line["jinv"]), e.jinv.concat());
        assert_eq!(array(&line["jacobian"]), e.jacobian.concat());
    }
    // The forward dynamics of those forces gives the accelerations back.
    let input: String = states
        .iter()
        .zip(&out)
        .map(|(s, line)| {
            json!({
                "pose": s.pose.to_array(),
                "omega": s.twist.omega,
                "velocity": s.twist.velocity,
                "gamma": line["gamma"],
            })
            .to_string()
                + "\n"
        })
        .collect();
    let back = lines(&support::c5_ok(&["forward", "--robot", EXAMPLE], &input));
    for (s, line) in states.iter().zip(&back) {
        let got = [array(&line["omega_dot"]), array(&line["acceleration"])].concat();
        let want = s.accel.to_array();
        for k in 0..6 {
            assert!(
                (got[k] - want[k]).abs() < 1e-9 * want[k].abs().max(1.0),
                "{got:?}"
            );
        }
    }
}

#[test]
fn eval_of_leg_lengths_returns_their_pose() {
    let robot = hexapod();
    let input: String = (0..8)
        .map(|k| {
            let (q, _) = robot.inverse_kinematics(&state(k).pose).unwrap();
            json!({ "q": q }).to_string() + "\n"
        })
        .collect();
    let out = lines(&support::c5_ok(&["eval", "--robot", EXAMPLE], &input));
    for (k, line) in out.iter().enumerate() {
        let got = array(&line["pose"]);
        let want = state(k).pose.to_array();
        for i in 0..6 {
            assert!((got[i] - want[i]).abs() < 1e-11, "{k}: {got:?} vs {want:?}");
        }
    }
}

/// Each broken file is refused with its name and the field, and the command writes nothing.
#[test]
fn bad_hexapod_files_are_refused_by_field() {
    let good = std::fs::read_to_string(EXAMPLE).unwrap();
    let cases: [(&str, String, &str); 6] = [
        (
            "five-legs.toml",
            good.rsplit_once("[[legs]]").unwrap().0.to_string(),
            "exactly six [[legs]]",
        ),
        (
            "no-rod.toml",
            good.replacen(
                "rod = { mass = 1.0, com = 0.30, inertia = [0.03, 0.03, 0.001] }",
                "",
                1,
            ),
            "missing field `rod`",
        ),
        (
            "zero-axis.toml",
            good.replacen(
                "u_axis = [-0.175033, 0.984563, 0.0]",
                "u_axis = [0.0, 0.0, 0.0]",
                1,
            ),
            "`legs[1].u_axis` must not be zero",
        ),
        (
            "negative-mass.toml",
            good.replacen("mass = 12.0", "mass = -12.0", 1),
            "`platform.mass` must be positive",
        ),
        (
            "flat-inertia.toml",
            good.replacen(
                "inertia = [0.4, 0.4, 0.7, 0.0, 0.0, 0.0]",
                "inertia = [0.1, 0.1, 0.7, 0.0, 0.0, 0.0]",
                1,
            ),
            "`platform.inertia` breaks the triangle inequality",
        ),
        (
            "scara.toml",
            good.replacen("mechanism = \"gough-stewart\"", "mechanism = \"scara\"", 1),
            "unknown `mechanism`",
        ),
    ];
    for (name, text, needle) in cases {
        let path = scratch(name);
        std::fs::write(&path, text).unwrap();
        let out_dir = scratch(&format!("{name}.out"));
        let path = path.to_str().unwrap();
        for args in [
            vec!["eval", "--robot", path],
            vec![
                "simulate",
                "--robot",
                path,
                "--out",
                out_dir.to_str().unwrap(),
            ],
        ] {
            let out = support::c5(&args, r#"{"pose": [0, 0, 0, 0, 0, 0.4]}"#);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{name}: {args:?} succeeded");
            assert!(err.contains(path) && err.contains(needle), "{name}: {err}");
            assert!(!Path::new(&out_dir).exists(), "{name}: wrote {out_dir:?}");
        }
    }
}

#[test]
fn simulate_track_workspace_and_audit_serve_the_hexapod() {
    let out_dir = scratch("runs");
    let out = out_dir.to_str().unwrap();
    let simulated = support::c5_ok(&["simulate", "--robot", EXAMPLE, "--out", out], "");
    assert!(String::from_utf8_lossy(&simulated.stdout).contains("1001 samples"));
    // The CSV's forces are the runtime's at its states.
    let robot = hexapod();
    let mut reader = csv::Reader::from_path(out_dir.join("section9.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let at = |name: &str| header.iter().position(|h| h == name).unwrap();
    for row in reader.records().take(50) {
        let row = row.unwrap();
        let v = |name: &str| row[at(name)].parse::<f64>().unwrap();
        let pose = ["alpha", "beta", "gamma", "xc", "yc", "zc"].map(v);
        let twist = ["wx", "wy", "wz", "vx", "vy", "vz"].map(v);
        let accel = ["wdx", "wdy", "wdz", "ax", "ay", "az"].map(v);
        let gamma = robot
            .inverse_dynamics(&State {
                pose: Pose::from_array(pose),
                twist: c5_runtime::Twist::from_array(twist),
                accel: c5_runtime::Acceleration::from_array(accel),
            })
            .unwrap();
        for (i, expected) in gamma.iter().enumerate() {
            let got = v(&format!("gamma{}", i + 1));
            assert!((got - expected).abs() < 1e-9 * expected.abs().max(1.0));
        }
    }
    // Computed torque from an offset start converges onto the trajectory.
    let tracked = support::c5_ok(
        &[
            "track",
            "--robot",
            EXAMPLE,
            "--out",
            out,
            "--initial-offset",
            "0.002,0,0,0,0,0.01",
        ],
        "",
    );
    let report = String::from_utf8_lossy(&tracked.stdout);
    let end = report
        .split("at the end: ")
        .nth(1)
        .and_then(|s| s.split(" mm").next())
        .and_then(|s| s.trim().parse::<f64>().ok())
        .unwrap();
    assert!(end < 0.01, "{report}");
    // The home pose is in the workspace.
    let mapped = support::c5_ok(
        &[
            "workspace",
            "--robot",
            EXAMPLE,
            "--points",
            "11",
            "--range",
            "0.3",
            "--out",
            out,
        ],
        "",
    );
    let report = String::from_utf8_lossy(&mapped.stdout);
    let reachable: usize = report.split(" of ").next().unwrap().trim().parse().unwrap();
    assert!(reachable > 100 && reachable < 1331, "{report}");
    let audit = support::c5_ok(&["audit", "--robot", EXAMPLE], "");
    let table = String::from_utf8_lossy(&audit.stdout);
    assert!(table.contains("gough-stewart inverse_dynamics_params") && table.contains("robsynth"));
    assert!(!table.contains("consistent"), "{table}");
}

/// `excite`, `identify` and `eval --base-parameters` on a hexapod file: the identified
/// parameters predict the forces (with friction) of the example hexapod the data came from;
/// `eval --derivatives` and `forward --derivatives` serve its exact Jacobians.
#[test]
fn excite_identify_and_derivatives_serve_the_hexapod() {
    let robot = hexapod();
    let states: Vec<State> = (0..5).map(state).collect();
    super::identify_cli::identification_round_trip(
        EXAMPLE,
        &*robot.clone().into_mechanism(),
        &states,
        46,
    );
    let input: String = states
        .iter()
        .map(|s| {
            json!({"pose": s.pose.to_array(), "omega": s.twist.omega, "velocity": s.twist.velocity,
                   "omega_dot": s.accel.omega_dot, "acceleration": s.accel.linear})
            .to_string()
                + "\n"
        })
        .collect();
    let with_jacobians = lines(&support::c5_ok(
        &["eval", "--robot", EXAMPLE, "--derivatives"],
        &input,
    ));
    for (k, line) in with_jacobians.iter().enumerate() {
        let d = robot.inverse_dynamics_derivatives(&state(k)).unwrap();
        assert_eq!(array(&line["d_gamma_d_pose"]), d.d_pose.as_flattened());
        assert_eq!(
            array(&line["d_gamma_d_acceleration"]),
            d.d_accel.as_flattened()
        );
    }
    let s = state(0);
    let forward_line = json!({"pose": s.pose.to_array(), "omega": s.twist.omega,
                             "velocity": s.twist.velocity, "gamma": [10.0, -20.0, 30.0, 0.0, 5.0, 1.0]})
    .to_string();
    let forward = lines(&support::c5_ok(
        &["forward", "--robot", EXAMPLE, "--derivatives"],
        &forward_line,
    ));
    let d = robot
        .forward_dynamics_derivatives(&s.pose, &s.twist, &[10.0, -20.0, 30.0, 0.0, 5.0, 1.0])
        .unwrap();
    assert_eq!(
        array(&forward[0]["d_acceleration_d_gamma"]),
        d.d_gamma.as_flattened()
    );
    // Leg lengths with --derivatives: the joint-space derivatives are the C5's alone, said so.
    let q = robot.inverse_kinematics(&s.pose).unwrap().0;
    let refused = support::c5(
        &["eval", "--robot", EXAMPLE, "--derivatives"],
        &(json!({"q": q}).to_string() + "\n"),
    );
    assert!(!refused.status.success());
    let error = &lines(&refused)[0]["error"];
    assert!(
        error
            .as_str()
            .unwrap()
            .starts_with("no joint-space derivatives for the gough-stewart mechanism"),
        "{error}"
    );
}

/// `plan` serves every mechanism whose derivative kernels are generated, in its platform's
/// coordinates (the hexapod: six; the Delta: three): the plan starts and ends at rest, its end
/// is Section 9's move from the robot's home, and every row's forces are the ones the robot's
/// inverse dynamics (another kernel than the planner's forward dynamics) needs for the row's
/// motion. The rotary hexapod (no derivative kernels) is refused by name.
#[test]
fn plan_serves_the_mechanisms_with_derivatives_and_refuses_by_name_the_others() {
    let docs = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/");
    for file in ["hexapod.toml", "delta.toml"] {
        plans_the_inverse_dynamics_forces(&format!("{docs}{file}"));
    }
    let out = scratch("plan-refused");
    let path = format!("{docs}rus-hexapod.toml");
    let refused = support::c5(
        &[
            "plan",
            "--robot",
            &path,
            "--out",
            out.to_str().unwrap(),
            "--no-view",
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("derivative kernels are not generated"),
        "{stderr}"
    );
}

fn plans_the_inverse_dynamics_forces(file: &str) {
    let dir = scratch(&format!(
        "plan-{}",
        Path::new(file).file_stem().unwrap().display()
    ));
    let out = dir.to_str().unwrap();
    let args = [
        "plan",
        "--robot",
        file,
        "--duration",
        "0.3",
        "--rate",
        "200",
        "--out",
        out,
        "--no-view",
    ];
    support::c5_ok(&args, "");
    let robot = c5_runtime::platform::load(
        c5_robot::Description::from_toml_file(Path::new(file)).unwrap(),
        c5_runtime::Model::default(),
    )
    .unwrap();
    let n = robot.freedom().dimension();
    let csv = std::fs::read_to_string(dir.join("plan.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 61);
    assert_eq!(
        rows[0].len(),
        1 + 4 * n,
        "{file}: t, pose, twist, acceleration, Γ"
    );
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    let (pose, twist, accel, gamma) = (
        1..1 + n,
        1 + n..1 + 2 * n,
        1 + 2 * n..1 + 3 * n,
        1 + 3 * n..,
    );
    for k in twist.clone() {
        assert_eq!(first[k], 0.0, "{file}: starts at rest");
        assert!(last[k].abs() < 1e-7, "{file}: ends at rest: {last:?}");
    }
    // Section 9's move: the centre, the last three of the pose's coordinates.
    let moved = [0.04, 0.03, 0.05];
    for j in 0..n {
        let expected = if j + 3 >= n { moved[j + 3 - n] } else { 0.0 };
        let k = pose.start + j;
        assert!(
            (last[k] - first[k] - expected).abs() < 1e-7,
            "{file}: {last:?}"
        );
    }
    for row in &rows[..rows.len() - 1] {
        let mut needed = vec![0.0; n];
        robot
            .inverse_dynamics(
                &row[pose.clone()],
                &row[twist.clone()],
                &row[accel.clone()],
                &mut needed,
            )
            .unwrap();
        for (i, (g, planned)) in needed.iter().zip(&row[gamma.clone()]).enumerate() {
            assert!(
                (g - planned).abs() < 1e-9 * (1.0 + g.abs()),
                "{file}: t = {}: Γ{} {g} from the motion, {planned} planned",
                row[0],
                i + 1,
            );
        }
    }
}
