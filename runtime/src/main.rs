//! `c5`: the Section 9 study, JSON-lines evaluation and the operation-count audit.

use c5_runtime::simulate;
use c5_runtime::trajectory::{self, LinearMove};
use c5_runtime::{Acceleration, Pose, Robot, State, Twist, C5};
use clap::{Parser, Subcommand};
use serde_json::{json, Value};
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "c5",
    about = "Kinematics and inverse dynamics of the C5 joint parallel robot"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Section 9: inverse dynamics along the default trajectory; writes a CSV and four plots.
    Simulate {
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Sampling rate of the default trajectory (Hz).
        #[arg(long, default_value_t = 1000.0)]
        rate: f64,
        /// A trajectory CSV (t, alpha, beta, gamma, xc, yc, zc, and optionally the twist
        /// wx..vz and acceleration wdx..az) instead of the default one.
        #[arg(long)]
        trajectory: Option<PathBuf>,
        /// A robot description (TOML) instead of the chapter's robot.
        #[arg(long)]
        robot: Option<PathBuf>,
    },
    /// Reads JSON Lines of platform states on stdin, writes one JSON line of results per line.
    Eval {
        /// A robot description (TOML) instead of the chapter's robot.
        #[arg(long)]
        robot: Option<PathBuf>,
    },
    /// Prints the generated kernels' operation counts beside the chapter's.
    Audit,
}

fn load_robot(path: Option<&PathBuf>) -> Result<C5> {
    let robot = match path {
        Some(p) => Robot::from_toml_file(p)?,
        None => Robot::default(),
    };
    Ok(C5::new(robot)?)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate {
            out,
            rate,
            trajectory,
            robot,
        } => load_robot(robot.as_ref())
            .and_then(|r| simulate_cmd(&r, &out, rate, trajectory.as_ref())),
        Command::Eval { robot } => load_robot(robot.as_ref()).and_then(|r| eval_cmd(&r)),
        Command::Audit => audit_cmd(),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn simulate_cmd(
    robot: &C5,
    out: &PathBuf,
    rate: f64,
    trajectory: Option<&PathBuf>,
) -> Result<ExitCode> {
    if !(rate.is_finite() && rate > 0.0) {
        return Err(format!("--rate must be a positive number, got {rate}").into());
    }
    let states = match trajectory {
        Some(path) => trajectory::csv_input::read(path)?,
        None => simulate::sample(&LinearMove::section9(), rate),
    };
    // Everything is computed before anything is written: a refused sample writes nothing.
    let study =
        simulate::run(robot, &states).map_err(|(t, e)| format!("sample at t = {t} s: {e}"))?;
    std::fs::create_dir_all(out)?;
    let csv = out.join("section9.csv");
    simulate::write_csv(&csv, &study)?;
    let plots = simulate::write_plots(out, &study)?;
    match trajectory {
        Some(p) => println!("{}: {} samples", p.display(), study.samples.len()),
        None => println!("Section 9: {} samples at {rate} Hz", study.samples.len()),
    }
    println!("wrote {}", csv.display());
    for p in plots {
        println!("wrote {}", out.join(p).display());
    }
    println!("peak |Γ| per actuator (N):");
    for i in 0..6 {
        let peak = study
            .samples
            .iter()
            .map(|s| s.eval.gamma[i].abs())
            .fold(0.0, f64::max);
        println!("  Γ{}: {peak:.3}", i + 1);
    }
    println!(
        "time per sample (q, q̇, q̈, Γ, J⁻¹, J): {:.0} ns",
        study.time_per_sample * 1e9
    );
    Ok(ExitCode::SUCCESS)
}

fn vec3(
    obj: &serde_json::Map<String, Value>,
    key: &str,
    len: usize,
) -> std::result::Result<Option<Vec<f64>>, String> {
    let Some(v) = obj.get(key) else {
        return Ok(None);
    };
    let arr = v
        .as_array()
        .ok_or_else(|| format!("`{key}` must be an array of {len} numbers"))?;
    if arr.len() != len {
        return Err(format!(
            "`{key}` must hold {len} numbers, got {}",
            arr.len()
        ));
    }
    arr.iter()
        .enumerate()
        .map(|(i, x)| {
            x.as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("`{key}[{i}]` is not a finite number"))
        })
        .collect::<std::result::Result<Vec<f64>, String>>()
        .map(Some)
}

fn parse_state(line: &str) -> std::result::Result<State, String> {
    let v: Value = serde_json::from_str(line).map_err(|e| format!("malformed JSON: {e}"))?;
    let obj = v.as_object().ok_or("a line must be a JSON object")?;
    let pose = vec3(obj, "pose", 6)?.ok_or("missing `pose`")?;
    let three = |key: &str| -> std::result::Result<[f64; 3], String> {
        Ok(vec3(obj, key, 3)?.map_or([0.0; 3], |v| [v[0], v[1], v[2]]))
    };
    Ok(State {
        pose: Pose::from_array(std::array::from_fn(|i| pose[i])),
        twist: Twist {
            omega: three("omega")?,
            velocity: three("velocity")?,
        },
        accel: Acceleration {
            omega_dot: three("omega_dot")?,
            linear: three("acceleration")?,
        },
    })
}

fn eval_cmd(robot: &C5) -> Result<ExitCode> {
    let stdin = std::io::stdin().lock();
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    let mut failed = false;
    for (n, line) in stdin.lines().enumerate() {
        let line = line?;
        let result = parse_state(&line).and_then(|s| robot.evaluate(&s).map_err(|e| e.to_string()));
        let out = match result {
            Ok(e) => serde_json::to_value(e)?,
            Err(error) => {
                failed = true;
                json!({"line": n + 1, "error": error})
            }
        };
        serde_json::to_writer(&mut stdout, &out)?;
        stdout.write_all(b"\n")?;
    }
    stdout.flush()?;
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn audit_cmd() -> Result<ExitCode> {
    print!("{}", c5_codegen::manifest::audit(c5_generated::OPS_JSON)?);
    Ok(ExitCode::SUCCESS)
}
