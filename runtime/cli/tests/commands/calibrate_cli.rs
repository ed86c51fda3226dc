//! `c5 calibrate` end to end, as the calibration issue asks: a hexapod whose true geometry the
//! project has not seen, 60 planned poses measured with noise, and a calibrated file whose
//! inverse kinematics predicts unseen readings to micrometres, whose forward kinematics finds
//! unseen poses within 50 µm, and whose every parameter lies within four reported standard
//! deviations of the truth; bad input refused with a message and nothing written.

use crate::support;

use c5_runtime::{GoughStewart, Pose};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;
use std::path::{Path, PathBuf};
use support::{c5, c5_ok};

const EXAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-calibrate-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn load(path: &Path) -> GoughStewart {
    let text = std::fs::read_to_string(path).unwrap();
    GoughStewart::new(c5_robot::GoughStewart::from_toml(&text, s(path)).unwrap()).unwrap()
}

/// The example with every joint centre moved by up to 2 mm per component and every encoder
/// offset by up to 3 mm, written as a robot file.
fn write_as_built(path: &Path, seed: u64) -> GoughStewart {
    let mut robot = *load(Path::new(EXAMPLE)).robot();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for leg in &mut robot.legs {
        for k in 0..3 {
            leg.base[k] += rng.gen_range(-2e-3..2e-3);
            leg.platform[k] += rng.gen_range(-2e-3..2e-3);
        }
        leg.encoder_offset = rng.gen_range(-3e-3..3e-3);
    }
    std::fs::write(path, c5_robot::Description::GoughStewart(robot).to_toml()).unwrap();
    GoughStewart::new(robot).unwrap()
}

fn rows(path: &Path) -> Vec<Vec<f64>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    reader
        .records()
        .map(|r| r.unwrap().iter().map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn calibrate_recovers_an_unseen_hexapod() {
    let (truth_file, poses, data, out, report) = (
        scratch("truth.toml"),
        scratch("poses.csv"),
        scratch("measurements.csv"),
        scratch("calibrated.toml"),
        scratch("report.json"),
    );
    let truth = write_as_built(&truth_file, 7);
    c5_ok(
        &[
            "calibrate",
            "--plan",
            "60",
            "--robot",
            EXAMPLE,
            "--out",
            s(&poses),
        ],
        "",
    );
    assert_eq!(rows(&poses).len(), 60);
    c5_ok(
        &[
            "calibrate",
            "--simulate",
            s(&truth_file),
            "--poses",
            s(&poses),
        ]
        .into_iter()
        .chain(["--out", s(&data), "--seed", "3"])
        .collect::<Vec<_>>(),
        "",
    );
    let printed = c5_ok(
        &[
            "calibrate",
            "--robot",
            EXAMPLE,
            "--data",
            s(&data),
            "--out",
            s(&out),
        ]
        .into_iter()
        .chain(["--report", s(&report)])
        .collect::<Vec<_>>(),
        "",
    );
    let text = String::from_utf8_lossy(&printed.stdout);
    assert!(text.contains("every parameter is observable"), "{text}");

    // Every parameter within four reported standard deviations of the truth.
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let true_values: Vec<f64> = truth
        .robot()
        .legs
        .iter()
        .flat_map(|l| {
            [
                l.base.as_slice(),
                l.platform.as_slice(),
                &[l.encoder_offset],
            ]
            .concat()
        })
        .collect();
    for (p, t) in json["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .zip(true_values)
    {
        let (estimate, sigma) = (
            p["estimate"].as_f64().unwrap(),
            p["std_dev"].as_f64().unwrap(),
        );
        assert!((estimate - t).abs() < 4.0 * sigma, "{p} vs {t}");
    }

    // The calibrated file keeps the nominal one's comments and fields, and says what changed.
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(
        written.contains("# leg 1") && written.contains("calibrated; nominal [0.45, 0.08, 0.0]")
    );
    let fitted = load(&out);
    assert_eq!(fitted.robot().limits, truth.robot().limits);

    // Unseen poses: readings predicted to micrometres, poses found within 50 µm.
    let nominal = load(Path::new(EXAMPLE));
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let home = nominal.home().to_array();
    let (mut errors, mut nominal_errors, mut worst) = (Vec::new(), Vec::new(), 0.0f64);
    while errors.len() < 6 * 40 {
        let pose = Pose::from_array(std::array::from_fn(|k| {
            home[k] + rng.gen_range(-1.0..1.0) * if k < 3 { 0.2 } else { 0.08 }
        }));
        if nominal.check_limits(&pose).is_err() {
            continue;
        }
        let (q, _) = truth.inverse_kinematics(&pose).unwrap();
        let (q_fit, _) = fitted.inverse_kinematics(&pose).unwrap();
        let (q_nominal, _) = nominal.inverse_kinematics(&pose).unwrap();
        errors.extend((0..6).map(|i| q_fit[i] - q[i]));
        nominal_errors.extend((0..6).map(|i| q_nominal[i] - q[i]));
        let found = fitted.forward_kinematics(&q, None).unwrap();
        let off = (0..3)
            .map(|k| (found.center[k] - pose.center[k]).powi(2))
            .sum::<f64>();
        worst = worst.max(off.sqrt());
    }
    let rms = |e: &[f64]| (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
    assert!(rms(&errors) < 10e-6, "calibrated: {:e} m rms", rms(&errors));
    assert!(
        rms(&nominal_errors) > 5e-4,
        "nominal: {:e} m rms",
        rms(&nominal_errors)
    );
    assert!(worst < 50e-6, "forward kinematics {worst:e} m off");
}

/// Bad input: a message naming the problem, a failure status, and no file written.
#[test]
fn calibrate_refuses_bad_input() {
    let (truth_file, poses, data) = (
        scratch("bad-truth.toml"),
        scratch("bad-poses.csv"),
        scratch("bad-measurements.csv"),
    );
    write_as_built(&truth_file, 8);
    c5_ok(
        &[
            "calibrate",
            "--plan",
            "20",
            "--robot",
            EXAMPLE,
            "--out",
            s(&poses),
        ],
        "",
    );
    let simulate = [
        "calibrate",
        "--simulate",
        s(&truth_file),
        "--poses",
        s(&poses),
    ];
    c5_ok(&[&simulate[..], &["--out", s(&data)]].concat(), "");
    let text = std::fs::read_to_string(&data).unwrap();
    let lines: Vec<&str> = text.lines().collect();

    let cases: Vec<(&str, String, &str)> = vec![
        ("few", lines[..6].join("\n"), "at least 8"),
        ("column", text.replacen("q3", "q7", 1), "no column `q3`"),
        (
            "nan",
            {
                let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                l[5] = format!("{},inf", lines[5].rsplit_once(',').unwrap().0);
                l.join("\n")
            },
            "row 5, column `q6`",
        ),
        (
            "unreachable",
            {
                let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
                let mut f: Vec<String> = l[3].split(',').map(String::from).collect();
                f[5] = "1.5".into();
                l[3] = f.join(",");
                l.join("\n")
            },
            "measurement 3: the robot cannot reach its pose",
        ),
    ];
    for (name, content, message) in cases {
        let (input, out) = (
            scratch(&format!("{name}.csv")),
            scratch(&format!("{name}.toml")),
        );
        std::fs::write(&input, content).unwrap();
        let run = c5(
            &[
                "calibrate",
                "--robot",
                EXAMPLE,
                "--data",
                s(&input),
                "--out",
                s(&out),
            ],
            "",
        );
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(
            !run.status.success() && err.contains(message),
            "{name}: {err}"
        );
        assert!(!out.exists(), "{name}: wrote {}", out.display());
    }

    // A C5 file is refused by name.
    let c5_file = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/default-robot.toml");
    let run = c5(&["calibrate", "--plan", "20", "--robot", c5_file], "");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("kinematic calibration") && err.contains("c5"),
        "{err}"
    );

    // One orientation cannot separate the joint centres: named, and refused with --strict.
    let level = scratch("level.csv");
    let home = load(Path::new(EXAMPLE)).home().to_array();
    let mut pose_rows = String::from("alpha,beta,gamma,xc,yc,zc\n");
    for k in 0..20 {
        let t = k as f64;
        let (x, y, z) = (
            0.06 * (0.7 * t).sin(),
            0.06 * (1.3 * t).cos(),
            home[5] + 0.05 * (0.4 * t).sin(),
        );
        pose_rows += &format!("0,0,0,{x},{y},{z}\n");
    }
    std::fs::write(&level, pose_rows).unwrap();
    let level_data = scratch("level-measurements.csv");
    let simulate = [
        "calibrate",
        "--simulate",
        s(&truth_file),
        "--poses",
        s(&level),
    ];
    c5_ok(&[&simulate[..], &["--out", s(&level_data)]].concat(), "");
    let out = scratch("level.toml");
    let run = c5(
        &[
            "calibrate",
            "--robot",
            EXAMPLE,
            "--data",
            s(&level_data),
            "--out",
            s(&out),
            "--strict",
        ],
        "",
    );
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && err.contains("cannot separate") && err.contains("A1."),
        "{err}"
    );
    assert!(!out.exists());
    let run = c5_ok(
        &[
            "calibrate",
            "--robot",
            EXAMPLE,
            "--data",
            s(&level_data),
            "--out",
            s(&out),
        ],
        "",
    );
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("fixed at nominal instead of smeared"),
        "{text}"
    );
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("not observable: kept"));
}

/// The rotary hexapod and the Delta through the program: poses planned in their coordinates,
/// measurements simulated from a robot built 1.5 mm off its file, and a calibrated file that
/// keeps the original's comments, says each nominal value (a crank's length on its inline
/// table's line) and carries the fitted geometry.
#[test]
fn calibrate_serves_the_rotary_hexapod_and_the_delta() {
    for (file, pose_header) in [
        ("rus-hexapod.toml", "alpha,beta,gamma,xc,yc,zc"),
        ("delta.toml", "xc,yc,zc"),
    ] {
        let nominal_path = format!("{}/../../docs/{file}", env!("CARGO_MANIFEST_DIR"));
        let nominal_text = std::fs::read_to_string(&nominal_path).unwrap();
        let nominal = c5_robot::Description::from_toml(&nominal_text, file).unwrap();
        let mut truth = nominal.clone();
        let legs = if file == "delta.toml" { 3 } else { 6 };
        for leg in 0..legs {
            let values: Vec<f64> = truth
                .fitted_values(leg)
                .iter()
                .enumerate()
                .map(|(k, v)| v + 1.5e-3 * if (k + leg) % 2 == 0 { 1.0 } else { -1.0 })
                .collect();
            assert!(truth.set_fitted_values(leg, &values));
        }
        let truth_path = scratch(&format!("truth-{file}"));
        std::fs::write(&truth_path, truth.to_toml()).unwrap();
        let (poses, data, out) = (
            scratch(&format!("poses-{file}.csv")),
            scratch(&format!("measurements-{file}.csv")),
            scratch(&format!("calibrated-{file}")),
        );
        c5_ok(
            &[
                "calibrate",
                "--robot",
                &nominal_path,
                "--plan",
                "60",
                "--out",
                s(&poses),
            ],
            "",
        );
        let header = std::fs::read_to_string(&poses).unwrap();
        assert!(header.starts_with(pose_header), "{file}: {header:.60}");
        c5_ok(
            &[
                "calibrate",
                "--simulate",
                s(&truth_path),
                "--poses",
                s(&poses),
                "--out",
                s(&data),
            ],
            "",
        );
        let report = scratch(&format!("report-{file}.json"));
        let printed = c5_ok(
            &[
                "calibrate",
                "--robot",
                &nominal_path,
                "--data",
                s(&data),
                "--out",
                s(&out),
                "--report",
                s(&report),
            ],
            "",
        );
        let text = String::from_utf8_lossy(&printed.stdout);
        assert!(text.contains("µrad"), "{file}: {text}");
        let json: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        let sigma: Vec<f64> = json["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["std_dev"].as_f64().unwrap())
            .collect();
        let written = std::fs::read_to_string(&out).unwrap();
        assert!(
            written.contains("length calibrated; nominal 0.") && written.contains("# "),
            "{file}: {written}"
        );
        let fitted = c5_robot::Description::from_toml(&written, file).unwrap();
        let fitted_values = (0..legs).flat_map(|leg| fitted.fitted_values(leg));
        let true_values = (0..legs).flat_map(|leg| truth.fitted_values(leg));
        for (k, (f, t)) in fitted_values.zip(true_values).enumerate() {
            assert!(
                (f - t).abs() < 4.0 * sigma[k] + 2e-9,
                "{file} parameter {k}: fitted {f}, truth {t}, σ {}",
                sigma[k]
            );
        }
    }
}
