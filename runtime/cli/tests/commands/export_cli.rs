//! `c5 export`: both formats for both mechanisms, the same refusals as `eval` with nothing
//! written, and `simulate --torques`, the held-force run an export is compared with. The
//! exported files are checked against Pinocchio and MuJoCo in python/tests/test_export.py.

use crate::support::{c5, c5_ok};
use std::path::{Path, PathBuf};

const HEXAPOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");
const C5_ROBOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/default-robot.toml");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-export-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn export_writes_each_format_for_each_mechanism_to_stdout_or_a_file() {
    let dir = scratch("formats");
    for (robot, motor) in [(C5_ROBOT, "segment6_stroke"), (HEXAPOD, "leg6_stroke")] {
        for (format, root) in [("mjcf", "<mujoco model="), ("urdf", "<robot name=")] {
            let out = c5_ok(&["export", "--robot", robot, "--format", format], "");
            let text = String::from_utf8(out.stdout).unwrap();
            assert!(
                text.contains(root) && text.contains(motor),
                "{robot} {format}"
            );
            let file = dir.join(format!("robot.{format}"));
            let path = file.to_str().unwrap();
            c5_ok(
                &[
                    "export", "--robot", robot, "--format", format, "--out", path,
                ],
                "",
            );
            assert_eq!(
                std::fs::read_to_string(&file).unwrap(),
                text,
                "{robot} {format}"
            );
        }
    }
    // The default robot without `--robot`, as a file.
    let file = dir.join("c5.xml");
    c5_ok(&["export", "--out", file.to_str().unwrap()], "");
    let written = std::fs::read_to_string(&file).unwrap();
    let printed = String::from_utf8(c5_ok(&["export", "--robot", C5_ROBOT], "").stdout).unwrap();
    assert_eq!(
        written, printed,
        "docs/default-robot.toml is the default robot"
    );
}

#[test]
fn a_file_eval_refuses_is_refused_by_export_with_the_same_message_and_nothing_written() {
    let dir = scratch("refused");
    let good = std::fs::read_to_string(HEXAPOD).unwrap();
    let c5_good = std::fs::read_to_string(C5_ROBOT).unwrap();
    let cases = [
        ("mass.toml", good.replacen("mass = 12.0", "mass = -12.0", 1)),
        (
            "axis.toml",
            good.replacen(
                "u_axis = [-0.175033, 0.984563, 0.0]",
                "u_axis = [0, 0, 0]",
                1,
            ),
        ),
        (
            "spacing.toml",
            c5_good.replacen("half_spacing = 0.2\n", "half_spacing = -0.2\n", 1),
        ),
        (
            "unknown.toml",
            c5_good.replacen("half_spacing", "half_width", 1),
        ),
    ];
    for (name, text) in cases {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        let file = file.to_str().unwrap();
        let eval = c5(&["eval", "--robot", file], "{\"pose\": [0,0,0,0,0,0.4]}\n");
        let target = dir.join(format!("{name}.xml"));
        let export = c5(
            &["export", "--robot", file, "--out", target.to_str().unwrap()],
            "",
        );
        assert!(!eval.status.success() && !export.status.success(), "{name}");
        assert_eq!(export.stderr, eval.stderr, "{name}: the same message");
        assert!(
            String::from_utf8_lossy(&export.stderr).contains(file),
            "{name}"
        );
        assert!(!target.exists(), "{name}: nothing written");
    }
}

#[test]
fn the_paper_model_is_not_exported() {
    let out = c5(&["export", "--model", "paper"], "");
    assert!(!out.status.success() && out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a mechanism"));
}

#[test]
fn simulate_with_held_torques_writes_the_motion_from_rest_at_home() {
    let dir = scratch("held");
    // The C5's home statics (docs: 85.05 N on each vertical actuator): held, it stays.
    let hold = "0,0,0,0,85.0527,85.0527";
    c5_ok(
        &[
            "simulate",
            "--torques",
            hold,
            "--duration",
            "0.05",
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    let rows = read_csv(&dir.join("held.csv"));
    assert_eq!(rows.len(), 51, "t = 0 and 50 steps at 1 kHz");
    assert_eq!(
        rows[0][1..].iter().map(|x| x.abs()).sum::<f64>(),
        0.0,
        "home, at rest"
    );
    let last = rows.last().unwrap();
    assert!((last[0] - 0.05).abs() < 1e-12);
    assert!(
        last[1..].iter().all(|x| x.abs() < 1e-9),
        "held, it stays: {last:?}"
    );
    // One more newton on actuator 5 lifts the platform: z moves up by a t²/2 nearly.
    let push = "0,0,0,0,86.0527,85.0527";
    c5_ok(
        &[
            "simulate",
            "--torques",
            push,
            "--duration",
            "0.05",
            "--out",
            dir.to_str().unwrap(),
        ],
        "",
    );
    let rows = read_csv(&dir.join("held.csv"));
    assert!(rows.last().unwrap()[6] > 1e-6, "{:?}", rows.last());
}

#[test]
fn simulate_refuses_held_torques_of_the_wrong_count_or_not_finite() {
    for torques in ["1,2,3", "1,2,3,4,5,NaN"] {
        let out = c5(
            &["simulate", "--torques", torques, "--out", "/nonexistent/x"],
            "",
        );
        assert!(!out.status.success());
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("--torques"),
            "{torques}"
        );
    }
}

fn read_csv(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

const RUS_HEXAPOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/rus-hexapod.toml");
const DELTA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/delta.toml");

#[test]
fn the_rotary_hexapod_and_the_delta_export_and_the_deltas_derivatives_invert_each_other() {
    for (file, actuators) in [(RUS_HEXAPOD, 6), (DELTA, 3)] {
        let text = String::from_utf8(c5_ok(&["export", "--robot", file], "").stdout).unwrap();
        assert_eq!(text.matches("<motor ").count(), actuators, "{file}");
        let urdf = c5_ok(&["export", "--robot", file, "--format", "urdf"], "");
        assert!(String::from_utf8_lossy(&urdf.stdout).contains("<constraint "));
    }
    // The Delta's derivatives, 3×3 in its coordinates: the forward dynamics' `∂a_C/∂Γ` inverts
    // the inverse dynamics' `∂Γ/∂a_C` at the state they share.
    let line =
        r#"{"pose": [0.01, -0.02, -0.5], "velocity": [0.1, 0, 0.2], "acceleration": [0.5, -1, 2]}"#;
    let inverse = c5_ok(&["eval", "--robot", DELTA, "--derivatives"], line);
    let inverse: serde_json::Value = serde_json::from_slice(&inverse.stdout).unwrap();
    let matrix =
        |v: &serde_json::Value| -> Vec<Vec<f64>> { serde_json::from_value(v.clone()).unwrap() };
    for key in [
        "d_gamma_d_pose",
        "d_gamma_d_twist",
        "d_gamma_d_acceleration",
    ] {
        let m = matrix(&inverse[key]);
        assert!(
            m.len() == 3 && m.iter().all(|row| row.len() == 3),
            "{key}: {m:?}"
        );
    }
    let forward_line = format!(
        r#"{{"pose": [0.01, -0.02, -0.5], "velocity": [0.1, 0, 0.2], "gamma": {}}}"#,
        inverse["gamma"]
    );
    let forward = c5_ok(
        &["forward", "--robot", DELTA, "--derivatives"],
        &forward_line,
    );
    let forward: serde_json::Value = serde_json::from_slice(&forward.stdout).unwrap();
    let accel: Vec<f64> = serde_json::from_value(forward["acceleration"].clone()).unwrap();
    for (a, want) in accel.iter().zip([0.5, -1.0, 2.0]) {
        assert!((a - want).abs() < 1e-9, "{accel:?}");
    }
    let (by_accel, by_gamma) = (
        matrix(&inverse["d_gamma_d_acceleration"]),
        matrix(&forward["d_acceleration_d_gamma"]),
    );
    for (i, row) in by_accel.iter().enumerate() {
        for j in 0..3 {
            let product: f64 = row.iter().zip(&by_gamma).map(|(a, g)| a * g[j]).sum();
            let identity = if i == j { 1.0 } else { 0.0 };
            assert!((product - identity).abs() < 1e-9, "({i}, {j}): {product}");
        }
    }
    // Limits are every mechanism's: a Delta's file sets none, so every line is within them.
    let line = r#"{"pose": [0.0, 0.0, -0.75], "velocity": [0.1, 0, 0], "acceleration": [0, 0, 1]}"#;
    let strict = c5_ok(&["eval", "--robot", DELTA, "--strict-limits"], line);
    let answer: serde_json::Value = serde_json::from_slice(&strict.stdout).unwrap();
    assert_eq!(
        answer["gamma"].as_array().map(Vec::len),
        Some(3),
        "{answer}"
    );
    assert!(answer.get("limits").is_none(), "{answer}");
}

/// `track` on a Delta, the controller's model the plant's: from an offset `e₀` the error
/// decays as critically damped computed torque says, `e(t) = e₀ (1 + λt) e^(-λt)` (λ = 20/s),
/// the centre's in task space and each motor's in joint space; its CSV in the Delta's coordinates (the motors' errors in mrad); a turning
/// offset refused.
#[test]
fn track_brings_a_delta_back_onto_its_path_as_the_gains_say() {
    for space in ["task", "joint"] {
        let dir = scratch(&format!("track-delta-{space}"));
        let args = ["track", "--robot", DELTA, "--space", space, "--no-view"];
        // The Delta's shift alone: three numbers, its platform's freedoms.
        let offset = ["--initial-offset", "0.003,-0.002,0.004"];
        c5_ok(
            &[&args[..], &offset[..], &["--out", dir.to_str().unwrap()]].concat(),
            "",
        );
        let text = std::fs::read_to_string(dir.join("track.csv")).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        assert_eq!(
            header[1..7],
            [
                "desired_xc",
                "desired_yc",
                "desired_zc",
                "actual_xc",
                "actual_yc",
                "actual_zc"
            ]
        );
        assert_eq!(
            header[7..13],
            ["ex_mm", "ey_mm", "ez_mm", "eq1_mrad", "eq2_mrad", "eq3_mrad"]
        );
        let e0 = (3.0f64.powi(2) + 2.0f64.powi(2) + 4.0f64.powi(2)).sqrt();
        let rows = read_csv(&dir.join("track.csv"));
        assert_eq!(rows.len(), 1001);
        let norm = |e: &[f64]| e.iter().map(|x| x * x).sum::<f64>().sqrt();
        for row in &rows {
            let t = row[0];
            let decay = (1.0 + 20.0 * t) * (-20.0 * t).exp();
            // The law closes the loop in its space, where each error decays on its own: the
            // centre's in task space, each motor's in joint space.
            let (got, want): (Vec<f64>, Vec<f64>) = match space {
                "task" => (vec![norm(&row[7..10])], vec![e0 * decay]),
                _ => (
                    row[10..13].to_vec(),
                    rows[0][10..13].iter().map(|e| e * decay).collect(),
                ),
            };
            for (got, want) in got.iter().zip(want) {
                assert!(
                    (got - want).abs() < 1e-5 + 1e-6 * want.abs(),
                    "{space}, t = {t}: {got} against {want}"
                );
            }
        }
    }
    let turned = c5(
        &[
            "track",
            "--robot",
            DELTA,
            "--initial-offset",
            "0,0,0,0.1,0,0",
        ],
        "",
    );
    assert!(!turned.status.success() && turned.stdout.is_empty());
    assert!(String::from_utf8_lossy(&turned.stderr).contains("only translates"));
    let four = c5(
        &["track", "--robot", DELTA, "--initial-offset", "0.003,0,0,0"],
        "",
    );
    assert!(!four.status.success() && four.stdout.is_empty());
    assert!(String::from_utf8_lossy(&four.stderr).contains("three or six numbers, got 4"));
}

/// The Delta held by `simulate --torques`, in its three coordinates: from rest at home under
/// the torques `eval` gives for rest there, it stays; a fourth torque is refused.
#[test]
fn simulate_holds_the_delta_with_three_torques_in_its_three_coordinates() {
    let dir = scratch("held-delta");
    let out = dir.to_str().unwrap();
    let run = |torques: &str| {
        c5_ok(
            &[
                "simulate",
                "--robot",
                DELTA,
                "--torques",
                torques,
                "--duration",
                "0.05",
            ]
            .into_iter()
            .chain(["--out", out])
            .collect::<Vec<_>>(),
            "",
        );
        let text = std::fs::read_to_string(dir.join("held.csv")).unwrap();
        assert_eq!(text.lines().next(), Some("t,xc,yc,zc,vx,vy,vz"));
        read_csv(&dir.join("held.csv"))
    };
    let home = run("0,0,0")[0][1..4].to_vec();
    let line = format!("{{\"pose\": {home:?}}}\n");
    let eval: serde_json::Value =
        serde_json::from_slice(&c5_ok(&["eval", "--robot", DELTA], &line).stdout).unwrap();
    let gamma: Vec<f64> = serde_json::from_value(eval["gamma"].clone()).unwrap();
    let held = gamma.iter().map(|g| format!("{g:e}")).collect::<Vec<_>>();
    let rows = run(&held.join(","));
    assert_eq!(rows.len(), 51);
    let last = rows.last().unwrap();
    for k in 0..3 {
        assert!((last[1 + k] - home[k]).abs() < 1e-12, "{last:?}");
        assert!(last[4 + k].abs() < 1e-9, "{last:?}");
    }
    let four = c5(
        &[
            "simulate",
            "--robot",
            DELTA,
            "--torques",
            "1,2,3,4",
            "--out",
            out,
        ],
        "",
    );
    let err = String::from_utf8_lossy(&four.stderr);
    assert!(
        !four.status.success() && err.contains("3 for this delta"),
        "{err}"
    );
}

/// `simulate` on the Delta: Section 9's move of the centre in its three coordinates, and a
/// trajectory file of a level platform (`t,xc,yc,zc,...`) whose forces are `eval`'s at each
/// row; angular rates without the angles refused.
#[test]
fn simulate_moves_the_delta_along_section_9_and_along_a_file_in_its_coordinates() {
    let dir = scratch("simulate-delta");
    let out = dir.to_str().unwrap();
    c5_ok(
        &["simulate", "--robot", DELTA, "--rate", "20", "--out", out],
        "",
    );
    let text = std::fs::read_to_string(dir.join("section9.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert_eq!(header.len(), 22, "{header:?}");
    assert_eq!(header[1..4], ["xc", "yc", "zc"]);
    assert_eq!(header[19..], ["gamma1", "gamma2", "gamma3"]);
    let rows = read_csv(&dir.join("section9.csv"));
    assert_eq!(rows.len(), 21);
    // Its first ten columns as a file of its own: the same move, so the same forces.
    let file = dir.join("level.csv");
    let level: String = text
        .lines()
        .map(|l| l.split(',').take(10).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    std::fs::write(&file, level).unwrap();
    let sub = dir.join("again");
    let args = ["simulate", "--robot", DELTA, "--trajectory"];
    c5_ok(
        &[
            &args[..],
            &[file.to_str().unwrap(), "--out", sub.to_str().unwrap()],
        ]
        .concat(),
        "",
    );
    let again = read_csv(&sub.join("level.csv"));
    for (a, b) in rows.iter().zip(&again) {
        for k in 0..22 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-11 * (1.0 + a[k].abs()),
                "{a:?} {b:?}"
            );
        }
    }
    let lines: String = rows
        .iter()
        .map(|r| {
            let v = |k: usize| format!("[{}, {}, {}]", r[k], r[k + 1], r[k + 2]);
            format!(
                "{{\"pose\": {}, \"velocity\": {}, \"acceleration\": {}}}\n",
                v(1),
                v(4),
                v(7)
            )
        })
        .collect();
    let eval = c5_ok(&["eval", "--robot", DELTA], &lines);
    for (row, line) in rows
        .iter()
        .zip(String::from_utf8(eval.stdout).unwrap().lines())
    {
        let out: serde_json::Value = serde_json::from_str(line).unwrap();
        let gamma: Vec<f64> = serde_json::from_value(out["gamma"].clone()).unwrap();
        for k in 0..3 {
            assert!((gamma[k] - row[19 + k]).abs() < 1e-10, "{gamma:?} {row:?}");
        }
    }
    let turning = dir.join("turning.csv");
    std::fs::write(
        &turning,
        "t,xc,yc,zc,wx,wy,wz,vx,vy,vz\n0,0,0,-0.45,0,0,0,0,0,0\n",
    )
    .unwrap();
    let refused = c5(
        &[&args[..], &[turning.to_str().unwrap(), "--out", out]].concat(),
        "",
    );
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && err.contains("without alpha, beta, gamma"),
        "{err}"
    );
}

#[test]
fn the_rotary_hexapod_is_served_by_eval_and_forward() {
    let rest = "\"omega\": [0, 0, 0], \"velocity\": [0, 0, 0]";
    let home = "[0, 0, 0, 0, 0, 0.32]";
    let line = format!(
        "{{\"pose\": {home}, {rest}, \"omega_dot\": [0, 0, 0], \"acceleration\": [0, 0, 0]}}\n"
    );
    let eval = c5_ok(&["eval", "--robot", RUS_HEXAPOD], &line);
    let out: serde_json::Value = serde_json::from_slice(&eval.stdout).unwrap();
    let gamma: Vec<f64> = serde_json::from_value(out["gamma"].clone()).unwrap();
    // At rest the motors hold the platform's and the legs' weight.
    assert_eq!(gamma.len(), 6);
    assert!(
        gamma.iter().all(|g| g.is_finite() && g.abs() > 0.01),
        "{gamma:?}"
    );
    let held = format!("{{\"pose\": {home}, {rest}, \"gamma\": {gamma:?}}}\n");
    let forward = c5_ok(&["forward", "--robot", RUS_HEXAPOD], &held);
    let out: serde_json::Value = serde_json::from_slice(&forward.stdout).unwrap();
    for key in ["omega_dot", "acceleration"] {
        let a: Vec<f64> = serde_json::from_value(out[key].clone()).unwrap();
        assert!(a.iter().all(|x| x.abs() < 1e-9), "{key}: {a:?}");
    }
    let audit = c5_ok(&["audit", "--robot", RUS_HEXAPOD], "");
    let text = String::from_utf8_lossy(&audit.stdout);
    assert!(
        text.contains("rus-hexapod inverse_dynamics_params"),
        "{text}"
    );
    assert!(text.contains("robsynth's 43548m + 26665a"), "{text}");
}

#[test]
fn bad_rotary_hexapod_and_delta_files_are_refused_by_field_and_nothing_is_written() {
    let dir = scratch("bad-rus");
    let rus = std::fs::read_to_string(RUS_HEXAPOD).unwrap();
    let delta = std::fs::read_to_string(DELTA).unwrap();
    let first_arm = "axis = [0.0, 1.0, 0.0]\nzero = [1.0, 0.0, 0.0]";
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "unknown.toml",
            rus.replacen("\nbranch = -1\n", "\nbranch = -1\nelbow = 2\n", 1),
            "unknown field `elbow`",
        ),
        (
            "five-legs.toml",
            rus.rsplit_once("[[legs]]").unwrap().0.to_string(),
            "exactly six [[legs]]",
        ),
        (
            "two-arms.toml",
            delta.rsplit_once("[[arms]]").unwrap().0.to_string(),
            "exactly three [[arms]]",
        ),
        (
            "zero-axis.toml",
            delta.replacen("axis = [0.0, 1.0, 0.0]", "axis = [0.0, 0.0, 0.0]", 1),
            "`arms[1].axis` must not be zero",
        ),
        (
            "zero-along-axis.toml",
            delta.replacen(
                first_arm,
                "axis = [0.0, 1.0, 0.0]\nzero = [0.0, 2.0, 0.0]",
                1,
            ),
            "`arms[1].zero` must not be along `axis`",
        ),
        (
            "short-rod.toml",
            delta.replacen("length = 0.62", "length = 0.1", 1),
            "`arms[1]` cannot reach the platform at any height",
        ),
        (
            "massless.toml",
            rus.replacen("mass = 0.35", "mass = 0.0", 1),
            "`legs[1].crank.mass` must be positive",
        ),
        (
            "inertia.toml",
            rus.replacen(
                "inertia = [2e-5, 6.5e-4, 6.6e-4]",
                "inertia = [2e-5, 6.5e-4, 9e-4]",
                1,
            ),
            "`legs[1].crank.inertia` breaks the triangle inequality",
        ),
        (
            "branch.toml",
            rus.replacen("\nbranch = -1\n", "\nbranch = 0\n", 1),
            "`legs[1].branch` must be 1 or -1",
        ),
        (
            "separation.toml",
            delta.replacen("separation = 0.07, ", "", 1),
            "`arms[1].rod.separation` is missing",
        ),
    ];
    for (name, text, needle) in cases {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        let path = file.to_str().unwrap();
        let target = dir.join(format!("{name}.xml"));
        for args in [
            vec!["export", "--robot", path, "--out", target.to_str().unwrap()],
            vec!["eval", "--robot", path],
        ] {
            let out = c5(&args, "{\"pose\": [0, 0, 0.3]}\n");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{name}: {args:?}");
            assert!(err.contains(path) && err.contains(needle), "{name}: {err}");
        }
        assert!(!target.exists(), "{name}: nothing written");
    }
}

#[test]
fn the_delta_is_served_by_eval_and_forward_on_three_element_lines() {
    let home = c5_runtime::Delta::new(c5_robot::Delta::example())
        .unwrap()
        .home();
    let line = format!("{{\"pose\": {home:?}, \"velocity\": [0, 0, 0]}}\n");
    let eval = c5_ok(&["eval", "--robot", DELTA], &line);
    let out: serde_json::Value = serde_json::from_slice(&eval.stdout).unwrap();
    let gamma: Vec<f64> = serde_json::from_value(out["gamma"].clone()).unwrap();
    // At rest the motors hold the platform's and the arms' weight, the three alike.
    assert_eq!(gamma.len(), 3);
    assert!(gamma.iter().all(|g| g.abs() > 0.1), "{gamma:?}");
    assert!(
        (gamma[0] - gamma[1]).abs() < 1e-4 * gamma[0].abs(),
        "{gamma:?}"
    );
    let jinv: Vec<Vec<f64>> = serde_json::from_value(out["jinv"].clone()).unwrap();
    assert_eq!((jinv.len(), jinv[0].len()), (3, 3));
    let held = format!("{{\"pose\": {home:?}, \"gamma\": {gamma:?}}}\n");
    let forward = c5_ok(&["forward", "--robot", DELTA], &held);
    let out: serde_json::Value = serde_json::from_slice(&forward.stdout).unwrap();
    let a: Vec<f64> = serde_json::from_value(out["acceleration"].clone()).unwrap();
    assert!(a.len() == 3 && a.iter().all(|x| x.abs() < 1e-9), "{a:?}");
    let q: Vec<f64> = serde_json::from_value(
        serde_json::from_slice::<serde_json::Value>(&eval.stdout).unwrap()["q"].clone(),
    )
    .unwrap();
    let back = c5_ok(&["eval", "--robot", DELTA], &format!("{{\"q\": {q:?}}}\n"));
    let out: serde_json::Value = serde_json::from_slice(&back.stdout).unwrap();
    let pose: Vec<f64> = serde_json::from_value(out["pose"].clone()).unwrap();
    assert!(
        pose.iter().zip(home).all(|(p, h)| (p - h).abs() < 1e-12),
        "{pose:?}"
    );
    let audit = c5_ok(&["audit", "--robot", DELTA], "");
    let text = String::from_utf8_lossy(&audit.stdout);
    assert!(text.contains("robsynth's 3010m + 1835a"), "{text}");
}

/// `workspace` maps a Delta's centres, level: its CSV in the Delta's coordinates, every
/// reached centre one `eval` serves, the largest torque per newton of load the longest column of
/// its `jacobian` (`Γ = Jᵀ f`), and the orientation flags refused.
#[test]
fn workspace_maps_the_deltas_centres_and_refuses_to_turn_its_platform() {
    let dir = scratch("workspace-delta");
    let out = dir.to_str().unwrap();
    let args = [
        "workspace",
        "--robot",
        DELTA,
        "--points",
        "9",
        "--range",
        "0.35",
    ];
    let mapped = c5_ok(&[&args[..], &["--out", out, "--no-view"]].concat(), "");
    let report = String::from_utf8_lossy(&mapped.stdout);
    let line = report
        .lines()
        .find(|l| l.contains("poses reachable"))
        .unwrap();
    let reached: usize = line.split(" of 729 ").next().unwrap().parse().unwrap();
    assert!(reached > 100 && reached < 729, "{report}");
    let text = std::fs::read_to_string(dir.join("workspace.csv")).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        "xc,yc,zc,inverse_condition,force_ratio"
    );
    let rows = read_csv(&dir.join("workspace.csv"));
    assert_eq!(rows.len(), reached);
    let lines: String = rows
        .iter()
        .step_by(17)
        .map(|r| format!("{{\"pose\": [{}, {}, {}]}}\n", r[0], r[1], r[2]))
        .collect();
    let served = c5_ok(&["eval", "--robot", DELTA], &lines);
    let served = String::from_utf8(served.stdout).unwrap();
    assert_eq!(served.lines().count(), rows.len().div_ceil(17));
    for (row, line) in rows.iter().step_by(17).zip(served.lines()) {
        let out: serde_json::Value = serde_json::from_str(line).unwrap();
        let jac: Vec<Vec<f64>> = serde_json::from_value(out["jacobian"].clone()).unwrap();
        let longest = (0..3)
            .map(|i| (0..3).map(|r| jac[r][i] * jac[r][i]).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        assert!((longest - row[4]).abs() < 1e-12 * longest, "{row:?} {line}");
    }
    for flag in [["--at", "0,0,-0.5"], ["--orientation", "0,0,0.1"]] {
        let refused = c5(&[&args[..], &flag[..], &["--out", out]].concat(), "");
        let err = String::from_utf8_lossy(&refused.stderr);
        assert!(!refused.status.success() && refused.stdout.is_empty());
        assert!(err.contains("platform only translates"), "{err}");
    }
}
