//! `c5`: the Section 9 study, JSON Lines evaluation and the operation-count audit.

mod identify;
mod jsonl;
mod simulate;
mod track;
mod trajectory_csv;

use c5_runtime::control::ComputedTorque;
use c5_runtime::dynamics::{compose, exp_rotation, rotation, rpy, PlantState};
use c5_runtime::identify::Estimate;
use c5_runtime::trajectory::{sample_times, LinearMove};
use c5_runtime::{Acceleration, Model, Pose, Robot, State, Twist, C5};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};
use jsonl::Key;
use serde_json::{json, Value};
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;

/// The most samples `simulate` evaluates (about 2.5 GB of results).
const MAX_SAMPLES: usize = 10_000_000;

#[derive(Parser)]
#[command(
    name = "c5",
    version,
    about = "Kinematics and inverse dynamics of the C5 joint parallel robot"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

fn model_parser() -> impl TypedValueParser<Value = Model> {
    PossibleValuesParser::new(Model::ALL.map(Model::name))
        .map(|name| name.parse::<Model>().expect("one of the possible values"))
}

#[derive(Subcommand)]
enum Command {
    /// Section 9: inverse dynamics along the default trajectory (or a file); writes a CSV and
    /// four plots, figure 10 with both models' forces.
    Simulate {
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Sampling rate of the default trajectory (Hz); the last sample is its end.
        #[arg(long, default_value_t = 1000.0, conflicts_with = "trajectory")]
        rate: f64,
        /// A trajectory CSV (t, alpha, beta, gamma, xc, yc, zc, and optionally the twist
        /// wx..vz and acceleration wdx..az) instead of the default one; its rows are the samples.
        #[arg(long)]
        trajectory: Option<PathBuf>,
        /// A robot description (TOML) instead of the chapter's robot.
        #[arg(long)]
        robot: Option<PathBuf>,
        /// The model of the CSV's q, qd, qdd and gamma columns (the other model's forces are
        /// added as `gamma_paper1..6` or `gamma_consistent1..6`).
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
    },
    /// Reads JSON Lines of platform states on stdin, writes one JSON line of results per line.
    Eval {
        /// A robot description (TOML) instead of the chapter's robot.
        #[arg(long)]
        robot: Option<PathBuf>,
        /// The model the results follow.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
        /// Identified parameters (`c5 identify --out`): `gamma` is then `Y_b β`, the forces
        /// of the identified robot with its friction (the robot file gives only the geometry).
        #[arg(long)]
        base_parameters: Option<PathBuf>,
    },
    /// Identifies the base parameters (inertial and friction) from measured motion and forces:
    /// weighted least squares, streaming.
    Identify {
        /// Samples: a trajectory CSV (t, alpha, beta, gamma, xc, yc, zc, optionally the twist
        /// wx..vz and acceleration wdx..az) with the measured forces gamma1..gamma6.
        #[arg(long)]
        data: PathBuf,
        /// The model to fit.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
        /// The robot's geometry and gravity (TOML); its masses play no part.
        #[arg(long)]
        robot: Option<PathBuf>,
        /// Writes the parameters here (JSON) and a summary on stdout; else the JSON on stdout.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Writes an exciting trajectory for identification (a Fourier series inside the
    /// workspace, away from singular poses, of low condition number) as a trajectory CSV.
    Excite {
        /// Output CSV.
        #[arg(long, default_value = "excite.csv")]
        out: PathBuf,
        /// The model whose base regressor is conditioned.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
        /// The robot's geometry (TOML).
        #[arg(long)]
        robot: Option<PathBuf>,
        /// Period of the series (s): the file holds one.
        #[arg(long, default_value_t = 10.0)]
        period: f64,
        /// Harmonics per coordinate.
        #[arg(long, default_value_t = 5)]
        harmonics: usize,
        /// Samples per second written.
        #[arg(long, default_value_t = 100.0)]
        rate: f64,
        /// Candidate trajectories tried.
        #[arg(long, default_value_t = 400)]
        candidates: usize,
        /// Seed of the search.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Reads JSON Lines of platform states and actuator forces on stdin (`pose`, `omega`,
    /// `velocity`, `gamma`), writes the platform's acceleration (`omega_dot`, `acceleration`).
    Forward {
        /// A robot description (TOML) instead of the chapter's robot.
        #[arg(long)]
        robot: Option<PathBuf>,
        /// The model the results follow.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
    },
    /// A computed-torque controller tracking the Section 9 trajectory (or a file) on a simulated
    /// robot, integrated through the forward dynamics; writes a CSV and plots.
    Track {
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// A trajectory CSV (as for `simulate`) instead of the Section 9 move; integrated from
        /// sample to sample, the desired state interpolated between.
        #[arg(long)]
        trajectory: Option<PathBuf>,
        /// Integration and control rate for the default trajectory (Hz).
        #[arg(long, default_value_t = 1000.0, conflicts_with = "trajectory")]
        rate: f64,
        /// The controller's robot (TOML) instead of the chapter's.
        #[arg(long)]
        robot: Option<PathBuf>,
        /// The simulated plant's robot (TOML) [default: the controller's].
        #[arg(long)]
        plant_robot: Option<PathBuf>,
        /// The controller's model.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
        /// The plant's model.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        plant_model: Model,
        /// The plant's start off the trajectory: `dx,dy,dz` (m) and a rotation vector
        /// `rx,ry,rz` (rad, base frame).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        initial_offset: Option<Vec<f64>>,
        /// `λ` (1/s): critically damped gains `Kp = λ²`, `Kd = 2λ`.
        #[arg(long, default_value_t = 20.0)]
        bandwidth: f64,
        /// Largest actuator force (N), applied to each actuator.
        #[arg(long)]
        force_limit: Option<f64>,
        /// A sampled controller: forces held over each step (else the law runs at every
        /// integration stage, a continuous-time controller).
        #[arg(long)]
        hold: bool,
    },
    /// Prints the generated kernels' operation counts beside the chapter's.
    Audit {
        /// Only the kernels of this model (default: both).
        #[arg(long, value_parser = model_parser())]
        model: Option<Model>,
    },
}

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn load_robot(path: Option<&PathBuf>, model: Model) -> Result<C5> {
    let robot = match path {
        Some(p) => Robot::from_toml_file(p)?,
        None => Robot::default(),
    };
    Ok(C5::with_model(robot, model)?)
}

/// Whether `e` is a write to a closed pipe (`c5 eval | head -1`): the reader has all it
/// wants, so the run ends quietly and successfully.
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    let pipe = Some(std::io::ErrorKind::BrokenPipe);
    let mut source = Some(e);
    while let Some(err) = source {
        // serde_json's error hides its I/O error from `source()`, but tells its kind.
        let kind = err
            .downcast_ref::<std::io::Error>()
            .map(std::io::Error::kind)
            .or_else(|| {
                err.downcast_ref::<serde_json::Error>()
                    .and_then(serde_json::Error::io_error_kind)
            });
        if kind == pipe {
            return true;
        }
        source = err.source();
    }
    false
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate {
            out,
            rate,
            trajectory,
            robot,
            model,
        } => load_robot(robot.as_ref(), model)
            .and_then(|r| simulate_cmd(&r, &out, rate, trajectory.as_ref())),
        Command::Eval {
            robot,
            model,
            base_parameters,
        } => load_robot(robot.as_ref(), model).and_then(|r| {
            let estimate = base_parameters
                .map(|p| identify::load_estimate(&r, &p))
                .transpose()?;
            eval_cmd(&r, estimate.as_ref())
        }),
        Command::Identify {
            data,
            model,
            robot,
            out,
        } => load_robot(robot.as_ref(), model)
            .and_then(|r| identify::identify_cmd(&r, &data, out.as_deref()))
            .map(|()| ExitCode::SUCCESS),
        Command::Excite {
            out,
            model,
            robot,
            period,
            harmonics,
            rate,
            candidates,
            seed,
        } => load_robot(robot.as_ref(), model)
            .and_then(|r| {
                let options = identify::ExciteOptions {
                    period,
                    harmonics,
                    rate,
                    candidates,
                    seed,
                };
                identify::excite_cmd(&r, &out, &options)
            })
            .map(|()| ExitCode::SUCCESS),
        Command::Forward { robot, model } => {
            load_robot(robot.as_ref(), model).and_then(|r| forward_cmd(&r))
        }
        Command::Track {
            out,
            trajectory,
            rate,
            robot,
            plant_robot,
            model,
            plant_model,
            initial_offset,
            bandwidth,
            force_limit,
            hold,
        } => (|| {
            let controller = load_robot(robot.as_ref(), model)?;
            let plant = match plant_robot.as_ref() {
                Some(p) => load_robot(Some(p), plant_model)?,
                None => controller.to_model(plant_model),
            };
            let offset = match initial_offset {
                None => [0.0; 6],
                Some(v) => <[f64; 6]>::try_from(v.as_slice()).map_err(|_| {
                    format!(
                        "--initial-offset takes six numbers dx,dy,dz,rx,ry,rz, got {}",
                        v.len()
                    )
                })?,
            };
            let options = TrackOptions {
                trajectory: trajectory.as_ref(),
                rate,
                offset,
                bandwidth,
                force_limit,
                hold,
            };
            track_cmd(&controller, &plant, &out, &options)
        })(),
        Command::Audit { model } => audit_cmd(model),
    };
    match result {
        Ok(code) => code,
        Err(e) if is_broken_pipe(e.as_ref()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn simulate_cmd(
    robot: &C5,
    out: &PathBuf,
    rate: f64,
    trajectory: Option<&PathBuf>,
) -> Result<ExitCode> {
    let states = match trajectory {
        Some(path) => trajectory_csv::read(path)?,
        None => {
            let motion = LinearMove::section9();
            let times = sample_times(motion.duration, rate, MAX_SAMPLES).map_err(|n| {
                if n == usize::MAX {
                    format!("--rate must be a positive number, got {rate}")
                } else {
                    format!(
                        "--rate {rate} would take {n} samples of the {} s move (at most \
                         {MAX_SAMPLES})",
                        motion.duration
                    )
                }
            })?;
            times.into_iter().map(|t| (t, motion.state(t))).collect()
        }
    };
    // Everything is computed before anything is written: a refused sample writes nothing.
    let study =
        simulate::run(robot, &states).map_err(|(t, e)| format!("sample at t = {t} s: {e}"))?;
    std::fs::create_dir_all(out)?;
    let csv = out.join("section9.csv");
    simulate::write_csv(&csv, &study)?;
    let plots = simulate::write_plots(out, &study)?;
    let mut report = std::io::stdout().lock();
    match trajectory {
        Some(p) => writeln!(report, "{}: {} samples", p.display(), study.samples.len())?,
        None => writeln!(
            report,
            "Section 9: {} samples at {rate} Hz",
            study.samples.len()
        )?,
    }
    writeln!(report, "wrote {}", csv.display())?;
    for p in plots {
        writeln!(report, "wrote {}", out.join(p).display())?;
    }
    writeln!(
        report,
        "peak |Γ| per actuator (N), {} model, and the largest difference from the {} model:",
        study.model, study.other
    )?;
    for i in 0..6 {
        let peak = study
            .samples
            .iter()
            .map(|s| s.eval.gamma[i].abs())
            .fold(0.0, f64::max);
        let gap = study
            .samples
            .iter()
            .map(|s| (s.eval.gamma[i] - s.other_gamma[i]).abs())
            .fold(0.0, f64::max);
        writeln!(report, "  Γ{}: {peak:8.3}   (difference {gap:7.3})", i + 1)?;
    }
    writeln!(
        report,
        "time per sample (q, q̇, q̈, Γ, J⁻¹, J): {:.0} ns",
        study.time_per_sample * 1e9
    )?;
    Ok(ExitCode::SUCCESS)
}

/// The keys of an `eval` line.
const STATE_KEYS: [Key; 5] = [
    Key {
        name: "pose",
        len: 6,
        required: true,
    },
    Key {
        name: "omega",
        len: 3,
        required: false,
    },
    Key {
        name: "velocity",
        len: 3,
        required: false,
    },
    Key {
        name: "omega_dot",
        len: 3,
        required: false,
    },
    Key {
        name: "acceleration",
        len: 3,
        required: false,
    },
];

fn parse_state(line: &str) -> std::result::Result<State, String> {
    let v = jsonl::parse(line, &STATE_KEYS)?;
    let three = |k: usize| [v[k][0], v[k][1], v[k][2]];
    Ok(State {
        pose: Pose::from_array(std::array::from_fn(|i| v[0][i])),
        twist: Twist {
            omega: three(1),
            velocity: three(2),
        },
        accel: Acceleration {
            omega_dot: three(3),
            linear: three(4),
        },
    })
}

/// Streams JSON Lines: one result line per non-blank input line, a bad line answered with
/// `{"line": n, "error": ...}` and the exit status 1 at the end.
fn json_lines(
    mut answer: impl FnMut(&str) -> std::result::Result<Value, String>,
) -> Result<ExitCode> {
    let stdin = std::io::stdin().lock();
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    let mut failed = false;
    for (n, line) in stdin.lines().enumerate() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let out = answer(&line).unwrap_or_else(|error| {
            failed = true;
            json!({"line": n + 1, "error": error})
        });
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

fn eval_cmd(robot: &C5, identified: Option<&Estimate>) -> Result<ExitCode> {
    json_lines(|line| {
        let state = parse_state(line)?;
        let e = robot.evaluate(&state).map_err(|e| e.to_string())?;
        let mut out = serde_json::to_value(e).map_err(|e| e.to_string())?;
        if let Some(estimate) = identified {
            let gamma = estimate.forces(robot, &state).map_err(|e| e.to_string())?;
            out["gamma"] = json!(gamma);
        }
        Ok(out)
    })
}

/// The keys of a `forward` line.
const FORWARD_KEYS: [Key; 4] = [
    Key {
        name: "pose",
        len: 6,
        required: true,
    },
    Key {
        name: "omega",
        len: 3,
        required: false,
    },
    Key {
        name: "velocity",
        len: 3,
        required: false,
    },
    Key {
        name: "gamma",
        len: 6,
        required: true,
    },
];

fn forward_cmd(robot: &C5) -> Result<ExitCode> {
    json_lines(|line| {
        let v = jsonl::parse(line, &FORWARD_KEYS)?;
        let pose = Pose::from_array(std::array::from_fn(|i| v[0][i]));
        let twist = Twist {
            omega: [v[1][0], v[1][1], v[1][2]],
            velocity: [v[2][0], v[2][1], v[2][2]],
        };
        let gamma: [f64; 6] = std::array::from_fn(|i| v[3][i]);
        let a = robot
            .forward_dynamics(&pose, &twist, &gamma)
            .map_err(|e| e.to_string())?;
        Ok(json!({"omega_dot": a.omega_dot, "acceleration": a.linear}))
    })
}

struct TrackOptions<'a> {
    trajectory: Option<&'a PathBuf>,
    rate: f64,
    offset: [f64; 6],
    bandwidth: f64,
    force_limit: Option<f64>,
    hold: bool,
}

fn track_cmd(controller: &C5, plant: &C5, out: &PathBuf, o: &TrackOptions) -> Result<ExitCode> {
    if !(o.bandwidth.is_finite() && o.bandwidth > 0.0) {
        return Err(format!("--bandwidth must be a positive number, got {}", o.bandwidth).into());
    }
    if let Some(limit) = o.force_limit {
        if !(limit.is_finite() && limit > 0.0) {
            return Err(format!("--force-limit must be a positive number, got {limit}").into());
        }
    }
    if o.offset.iter().any(|x| !x.is_finite()) {
        return Err("--initial-offset must hold six finite numbers".into());
    }
    let (desired, times) = match o.trajectory {
        Some(path) => {
            let samples = trajectory_csv::read(path)?;
            let times = samples.iter().map(|(t, _)| *t).collect();
            (track::Desired::Samples(samples), times)
        }
        None => {
            let motion = LinearMove::section9();
            let times = sample_times(motion.duration, o.rate, MAX_SAMPLES).map_err(|n| {
                if n == usize::MAX {
                    format!("--rate must be a positive number, got {}", o.rate)
                } else {
                    format!(
                        "--rate {} would take {n} steps (at most {MAX_SAMPLES})",
                        o.rate
                    )
                }
            })?;
            (
                track::Desired::Motion(Box::new(move |t| motion.state(t))),
                times,
            )
        }
    };
    let first = desired.at(times[0]);
    let turned = compose(
        &exp_rotation([o.offset[3], o.offset[4], o.offset[5]]),
        &rotation(&first.pose),
    );
    let [alpha, beta, gamma] = rpy(&turned);
    let c = first.pose.center;
    let start = Pose {
        alpha,
        beta,
        gamma,
        center: [c[0] + o.offset[0], c[1] + o.offset[1], c[2] + o.offset[2]],
    };
    let mut law = ComputedTorque::critically_damped(o.bandwidth);
    law.force_limit = o.force_limit;
    let setup = track::Setup {
        controller,
        plant,
        law,
        hold: o.hold,
    };
    let clock = std::time::Instant::now();
    let samples = track::run(
        &setup,
        &desired,
        &times,
        PlantState::new(&start, &first.twist),
    )
    .map_err(|(t, e)| format!("step at t = {t} s: {e}"))?;
    let elapsed = clock.elapsed();
    std::fs::create_dir_all(out)?;
    let csv = out.join("track.csv");
    track::write_csv(&csv, &samples)?;
    let plots = track::write_plots(out, &samples)?;
    let [max_pos, max_ori, end_pos, end_ori] = track::summary(&samples);
    let mut report = std::io::stdout().lock();
    writeln!(
        report,
        "tracked {} steps in {:.1} ms: controller {} model, plant {} model",
        samples.len(),
        elapsed.as_secs_f64() * 1e3,
        controller.model(),
        plant.model()
    )?;
    writeln!(report, "wrote {}", csv.display())?;
    for p in plots {
        writeln!(report, "wrote {}", out.join(p).display())?;
    }
    writeln!(
        report,
        "largest error: {max_pos:.6} mm, {max_ori:.6} mrad; at the end: {end_pos:.6} mm, \
         {end_ori:.6} mrad"
    )?;
    Ok(ExitCode::SUCCESS)
}

fn audit_cmd(model: Option<Model>) -> Result<ExitCode> {
    let table = c5_codegen::manifest::audit(c5_generated::OPS_JSON, model)?;
    std::io::stdout().lock().write_all(table.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}
