//! `c5-codegen kernels --robot FILE.toml`: kernels for a described robot, or a clear refusal.

use std::process::Command;

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-codegen-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn kernels_for_a_robot_file() {
    let dir = scratch("good");
    let robot = c5_codegen::Robot {
        half_spacing: 0.3,
        ..Default::default()
    };
    let file = dir.join("robot.toml");
    std::fs::write(&file, robot.to_toml()).unwrap();
    let out = dir.join("kernels.rs");
    let status = Command::new(env!("CARGO_BIN_EXE_c5-codegen"))
        .args([
            "kernels",
            "--robot",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let code = std::fs::read_to_string(&out).unwrap();
    assert!(code.starts_with("// @generated"));
    assert!(code.contains("pub fn inverse_dynamics("));
    let expected = c5_codegen::Config::new()
        .robot(robot)
        .generate_to_string()
        .unwrap();
    assert_eq!(code, expected);
}

#[test]
fn a_bad_robot_file_writes_nothing() {
    let dir = scratch("bad");
    let file = dir.join("robot.toml");
    std::fs::write(
        &file,
        c5_codegen::Robot::default()
            .to_toml()
            .replacen("mass = 10.0", "mass = -1.0", 1),
    )
    .unwrap();
    let out = dir.join("kernels.rs");
    let output = Command::new(env!("CARGO_BIN_EXE_c5-codegen"))
        .args([
            "kernels",
            "--robot",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        err.contains("robot.toml") && err.contains("`platform.mass` must be positive"),
        "{err}"
    );
    assert!(!out.exists());
}

/// Every file under `dir`.
fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path);
        }
    }
    files
}

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_c5-codegen"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn help_and_version_succeed_and_unknown_arguments_are_refused() {
    for args in [
        &["--help"][..],
        &["--version"],
        &["generate", "--help"],
        &["kernels", "--help"],
    ] {
        let out = run(args);
        assert!(out.status.success(), "{args:?}");
        assert!(!out.stdout.is_empty(), "{args:?}");
    }
    let out = run(&["generate", "--frobnicate"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--frobnicate"));
    let out = run(&[
        "kernels", "--robot", "x.toml", "--out", "y.rs", "--model", "exact",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("consistent") && err.contains("paper"));
}

/// The freshness test of the checked-in crate, run as a developer regenerates it: `generate`
/// writes every file of `generated/` where it is told, and each is the checked-in one. On a
/// mismatch it fails; with `UPDATE_GENERATED=1` it also copies the fresh files over the
/// checked-in ones (then commit them). `tests/suite/freshness.rs` reads the checked-in manifest this
/// test holds fresh, rather than generating a second time.
#[test]
fn generate_writes_the_checked_in_crate_where_it_is_told_and_finds_no_workspace_from_elsewhere() {
    let dir = scratch("generate");
    let out = run(&["generate", "--out", dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let checked_in = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../generated");
    let mut stale = Vec::new();
    let written = walk(&dir);
    for entry in &written {
        let rel = entry.strip_prefix(&dir).unwrap();
        let fresh = std::fs::read_to_string(entry).unwrap();
        if std::fs::read_to_string(checked_in.join(rel))
            .ok()
            .as_deref()
            != Some(fresh.as_str())
        {
            if std::env::var_os("UPDATE_GENERATED").is_some() {
                std::fs::write(checked_in.join(rel), &fresh).unwrap();
            }
            stale.push(rel.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "stale generated files: {stale:?}; regenerate with `{}` (or rerun this test with UPDATE_GENERATED=1)",
        c5_codegen::REGENERATE
    );
    // The kernels of every mechanism, their trait, parameters and manifest.
    for rel in [
        "src/f64/mod.rs",
        "src/f64/consistent.rs",
        "src/f64/gough_stewart.rs",
        "ops.json",
    ] {
        assert!(dir.join(rel).exists(), "{rel} not written");
    }
    assert!(written.len() > 20, "only {} files written", written.len());
    // From a directory outside any workspace, without --out, it says what to do.
    let out = Command::new(env!("CARGO_BIN_EXE_c5-codegen"))
        .arg("generate")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("pass --out DIR"));
}
