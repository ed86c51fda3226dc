//! `c5-codegen`: regenerates the checked-in `generated/` crate, or writes kernels for a robot
//! described in a TOML file.

use c5_codegen::{Config, ParameterSet, Robot, Scalar};
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage:
  c5-codegen generate
      rewrite generated/ (kernels, ops.json, OPS.md) for the default robot
  c5-codegen kernels --robot FILE.toml --out FILE.rs [--runtime-parameters] [--f32] [--chapter]
      write the pose-setting kernels of the robot in FILE.toml (parameters folded unless
      --runtime-parameters), in f64 unless --f32, with the chapter-setting kernels if --chapter";

fn kernels(args: &[String]) -> Result<(), String> {
    let mut robot = None;
    let mut out = None;
    let mut config = Config::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--robot" => robot = Some(PathBuf::from(it.next().ok_or("--robot needs a file")?)),
            "--out" => out = Some(PathBuf::from(it.next().ok_or("--out needs a file")?)),
            "--runtime-parameters" => {
                config.runtime_parameters(ParameterSet::All);
            }
            "--f32" => {
                config.scalar(Scalar::F32);
            }
            "--chapter" => {
                config.chapter_kernels(true);
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    let robot = robot.ok_or(format!("--robot is required\n{USAGE}"))?;
    let out = out.ok_or(format!("--out is required\n{USAGE}"))?;
    let robot = Robot::from_toml_file(&robot).map_err(|e| e.to_string())?;
    let dir = out.parent().map(PathBuf::from).unwrap_or_default();
    let name = out
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or("--out must name a file")?;
    config
        .robot(robot)
        .out_dir(if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir
        })
        .file_name(name)
        .generate()
        .map_err(|e| e.to_string())?;
    println!("wrote {}", out.display());
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../generated");
    let result = match args.first().map(String::as_str) {
        Some("generate") => c5_codegen::write_generated_crate(&dir)
            .map(|stale| {
                for p in &stale {
                    println!("wrote generated/{}", p.display());
                }
                if stale.is_empty() {
                    println!("generated/ is up to date");
                }
                let ops = std::fs::read_to_string(dir.join("ops.json")).unwrap_or_default();
                match c5_codegen::manifest::audit(&ops) {
                    Ok(table) => print!("\n{table}"),
                    Err(e) => eprintln!("cannot read ops.json: {e}"),
                }
            })
            .map_err(|e| e.to_string()),
        Some("kernels") => kernels(&args[1..]),
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
