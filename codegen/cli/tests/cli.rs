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

#[test]
fn generate_writes_where_it_is_told_and_finds_no_workspace_from_elsewhere() {
    let dir = scratch("generate");
    let out = run(&["generate", "--out", dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (rel, contents) in c5_codegen::generated_crate_files().unwrap() {
        assert_eq!(std::fs::read_to_string(dir.join(rel)).unwrap(), contents);
    }
    // From a directory outside any workspace, without --out, it says what to do.
    let out = Command::new(env!("CARGO_BIN_EXE_c5-codegen"))
        .arg("generate")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("pass --out DIR"));
}
