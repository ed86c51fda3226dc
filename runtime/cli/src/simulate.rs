//! Section 9: the inverse dynamics along a trajectory, in both models, as a CSV and four
//! plots.

use crate::columns;
use crate::options::{self, RobotArgs};
use crate::trajectory_csv;
use crate::view;
use c5_runtime::platform::{Evaluated, Freedom};
use c5_runtime::{Error, Mechanism, State};
use clap::Args;
use plotters::prelude::*;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Section 9: inverse dynamics along the default trajectory (or a file); writes a CSV and
/// four plots, figure 10 with every model's forces.
#[derive(Args)]
pub struct SimulateArgs {
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
    /// The robot, and the model of the CSV's q, qd, qdd and gamma columns (the other models'
    /// forces are added as `gamma_paper1..6` or `gamma_consistent1..6`).
    #[command(flatten)]
    robot: RobotArgs,
    /// Also writes what a real experiment records, `t,q1..q6,gamma1..gamma6`: the encoders'
    /// positions and the forces, with `--encoder-resolution` and `--force-noise`.
    #[arg(long)]
    encoder_log: Option<PathBuf>,
    #[command(flatten)]
    sensors: options::SensorArgs,
    /// Go on past the robot's `[limits]` (stroke, plate travel, tilt, speed, force) instead of
    /// stopping at the first sample that breaks one.
    #[arg(long)]
    ignore_limits: bool,
    #[command(flatten)]
    view: view::PageArgs,
    /// Instead of the inverse dynamics along a trajectory, the forward dynamics: the robot let
    /// go from home at rest with its actuators held at these forces, one per actuator (N, or
    /// N·m for a motor that turns; three for the Delta), integrated by RK4 at `--rate` for
    /// `--duration`; writes `held.csv` (t, the pose, the twist, in the platform's
    /// coordinates). MuJoCo simulating `c5 export`'s file under the same `ctrl` follows it
    /// (docs/export.md).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true,
          conflicts_with_all = ["trajectory", "encoder_log"])]
    torques: Option<Vec<f64>>,
    /// How long `--torques` runs (s).
    #[arg(long, default_value_t = 0.5, requires = "torques")]
    duration: f64,
}

/// `--torques`: the forward dynamics under held forces.
fn run_held(args: &SimulateArgs, torques: &[f64]) -> crate::Result<ExitCode> {
    let robot = args.robot.load_mechanism()?;
    let actuators = robot.freedom().dimension();
    if torques.len() != actuators {
        return Err(format!(
            "--torques takes one force per actuator, {actuators} for this {}, got {}",
            robot.mechanism(),
            torques.len()
        )
        .into());
    }
    if !torques.iter().all(|g| g.is_finite()) {
        return Err("--torques must be finite numbers".into());
    }
    let (duration, rate) = (args.duration, args.rate);
    if !(duration.is_finite() && duration > 0.0 && rate.is_finite() && rate > 0.0)
        || duration * rate > crate::MAX_SAMPLES as f64
    {
        return Err(format!(
            "--duration and --rate must be positive, with at most {} steps; got {duration} s at \
             {rate} Hz",
            crate::MAX_SAMPLES
        )
        .into());
    }
    let samples = crate::held::run(robot.as_ref(), torques, duration, rate)
        .map_err(|(t, e)| format!("step at t = {t} s: {e}"))?;
    std::fs::create_dir_all(&args.out)?;
    let csv = args.out.join("held.csv");
    crate::held::write_csv(&csv, robot.freedom(), &samples)?;
    let mut report = std::io::stdout().lock();
    writeln!(
        report,
        "held forces: {} steps of RK4 at {rate} Hz from home at rest\nwrote {}",
        samples.len() - 1,
        csv.display()
    )?;
    Ok(ExitCode::SUCCESS)
}

pub fn run_cmd(args: &SimulateArgs) -> crate::Result<ExitCode> {
    if let Some(torques) = &args.torques {
        return run_held(args, torques);
    }
    let robot = args.robot.load_mechanism()?;
    let (out, rate) = (&args.out, args.rate);
    let mut scaled = None;
    let states = match &args.trajectory {
        Some(path) => trajectory_csv::read(path)?,
        None => {
            let motion;
            (motion, scaled) = options::section9_for(robot.as_ref())?;
            let times = options::sample_times(motion.duration, rate, "samples")?;
            times.into_iter().map(|t| (t, motion.state(t))).collect()
        }
    };
    if args.sensors.any() && args.encoder_log.is_none() {
        return Err("--encoder-resolution and --force-noise shape the --encoder-log".into());
    }
    let (encoders, mut noise) = (args.sensors.encoders()?, args.sensors.noise()?);
    // Everything is computed before anything is written: a refused sample writes nothing.
    let study =
        run(robot.as_ref(), &states).map_err(|(t, e)| format!("sample at t = {t} s: {e}"))?;
    if !args.ignore_limits && robot.has_limits() {
        for s in &study.samples {
            robot
                .check_limits(&s.motion[0])
                .and_then(|()| robot.check_speeds(&s.eval.qd))
                .and_then(|()| robot.check_forces(&s.eval.gamma))
                .map_err(|e| format!("sample at t = {} s: {e} (--ignore-limits to go on)", s.t))?;
        }
    }
    std::fs::create_dir_all(out)?;
    let n = study.freedom.dimension();
    if let Some(path) = &args.encoder_log {
        let mut w = csv::Writer::from_path(path)?;
        let mut header = vec![columns::TIME.to_string()];
        header.extend(columns::per_actuator("q", n));
        header.extend(columns::per_actuator("gamma", n));
        w.write_record(&header)?;
        for s in &study.samples {
            let mut row = vec![s.t];
            row.extend(s.eval.q.iter().map(|&q| encoders.reading(q)));
            row.extend(s.eval.gamma.iter().map(|&g| noise.noisy(g)));
            w.write_record(row.iter().map(|v| format!("{v:.17e}")))?;
        }
        w.flush()?;
    }
    // Named after the trajectory file (`plan.csv` gives `out/plan.csv`); Section 9's own.
    let stem = args
        .trajectory
        .as_ref()
        .and_then(|p| p.file_stem())
        .map_or_else(|| "section9".into(), |s| s.to_string_lossy().into_owned());
    let csv = out.join(format!("{stem}.csv"));
    write_csv(&csv, &study)?;
    let plots = write_plots(out, &study)?;
    let title = match &args.trajectory {
        Some(p) => format!("{} ({} robot)", p.display(), robot.mechanism()),
        None => format!("Section 9 ({} robot)", robot.mechanism()),
    };
    let drawn: Vec<view::Sample> = study
        .samples
        .iter()
        .map(|s| view::Sample {
            t: s.t,
            pose: s.motion[0].clone(),
            twist: Some(s.motion[1].clone()),
            gamma: s.eval.gamma.clone(),
        })
        .collect();
    let page = args.view.write(robot.as_ref(), &drawn, &title, out)?;
    let mut report = std::io::stdout().lock();
    match &args.trajectory {
        Some(p) => writeln!(report, "{}: {} samples", p.display(), study.samples.len())?,
        None => writeln!(
            report,
            "Section 9: {} samples at {rate} Hz{}",
            study.samples.len(),
            options::scaled_note(scaled)
        )?,
    }
    writeln!(report, "wrote {}", csv.display())?;
    if let Some(path) = &args.encoder_log {
        writeln!(report, "wrote {} (the encoder log)", path.display())?;
    }
    for p in plots {
        writeln!(report, "wrote {}", out.join(p).display())?;
    }
    if let Some(p) = page {
        writeln!(
            report,
            "wrote {} (the 3D view: open it in a browser)",
            p.display()
        )?;
    }
    for (k, other) in study.others.iter().enumerate() {
        writeln!(
            report,
            "peak |Γ| per actuator (N), {} model, and the largest difference from the {other} \
             model:",
            study.model
        )?;
        for i in 0..n {
            let peak = study
                .samples
                .iter()
                .map(|s| s.eval.gamma[i].abs())
                .fold(0.0, f64::max);
            let gap = study
                .samples
                .iter()
                .map(|s| (s.eval.gamma[i] - s.others[k][i]).abs())
                .fold(0.0, f64::max);
            writeln!(report, "  Γ{}: {peak:8.3}   (difference {gap:7.3})", i + 1)?;
        }
    }
    writeln!(
        report,
        "time per sample (q, q̇, q̈, Γ, J⁻¹, J): {:.0} ns",
        study.time_per_sample * 1e9
    )?;
    Ok(ExitCode::SUCCESS)
}

/// One sample of the study, in the platform's coordinates.
#[derive(Clone, Debug)]
pub struct Sample {
    pub t: f64,
    /// The platform's pose, twist and acceleration.
    pub motion: [Vec<f64>; 3],
    /// Everything the chosen model gives.
    pub eval: Evaluated,
    /// The actuator forces of each of [`Study::others`].
    pub others: Vec<Vec<f64>>,
}

/// The study's samples and how long the kernels took.
#[derive(Clone, Debug)]
pub struct Study {
    /// How the platform moves: the samples' coordinates.
    pub freedom: Freedom,
    /// The model of [`Sample::eval`]; the others gave [`Sample::others`].
    pub model: &'static str,
    pub others: Vec<&'static str>,
    pub samples: Vec<Sample>,
    /// Mean wall time of [`Mechanism::evaluate`] per sample (s).
    pub time_per_sample: f64,
}

/// Evaluates every state of a trajectory with `robot`'s model, and the forces of the others.
///
/// # Errors
/// The first sample whose state is refused (non-finite, singular, or turning a platform that
/// only translates), with its time.
pub fn run(robot: &dyn Mechanism, states: &[(f64, State)]) -> Result<Study, (f64, Error)> {
    let motions = states
        .iter()
        .map(|(t, s)| robot.coordinates_of(s).map_err(|e| (*t, e)))
        .collect::<Result<Vec<_>, _>>()?;
    let start = Instant::now();
    let evals = motions
        .iter()
        .zip(states)
        .map(|([x, v, a], (t, _))| robot.evaluate(x, v, a).map_err(|e| (*t, e)))
        .collect::<Result<Vec<_>, _>>()?;
    let time_per_sample = start.elapsed().as_secs_f64() / evals.len().max(1) as f64;
    let other_robots = robot
        .spatial()
        .map(|r| r.other_models())
        .unwrap_or_default();
    let others: Vec<&'static str> = other_robots.iter().map(|r| r.model_name()).collect();
    let only: Vec<State> = states.iter().map(|&(_, s)| s).collect();
    let forces = other_robots
        .iter()
        .map(|r| {
            r.inverse_dynamics_many(&only)
                .map_err(|(k, e)| (states[k].0, e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let samples = states
        .iter()
        .zip(motions)
        .zip(evals)
        .enumerate()
        .map(|(k, ((&(t, _), motion), eval))| Sample {
            t,
            motion,
            eval,
            others: forces.iter().map(|f| f[k].to_vec()).collect(),
        })
        .collect();
    Ok(Study {
        freedom: robot.freedom(),
        model: robot.model_name(),
        others,
        samples,
        time_per_sample,
    })
}

/// Header of the CSV: time, pose, twist, acceleration (in the platform's coordinates), `q`,
/// `q̇`, `q̈`, `Γ` of the chosen model, and `Γ` of each other one (`gamma_paper1..6` or
/// `gamma_consistent1..6`).
pub fn csv_header(freedom: Freedom, others: &[&str]) -> Vec<String> {
    let n = freedom.dimension();
    let mut h = columns::state(freedom);
    for name in ["q", "qd", "qdd", "gamma"] {
        h.extend(columns::per_actuator(name, n));
    }
    for other in others {
        h.extend(columns::per_actuator(&format!("gamma_{other}"), n));
    }
    h
}

/// Writes the samples as CSV.
///
/// # Errors
/// I/O errors.
pub fn write_csv(path: &Path, study: &Study) -> Result<(), Box<dyn std::error::Error>> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record(csv_header(study.freedom, &study.others))?;
    for s in &study.samples {
        let mut row = vec![s.t];
        row.extend(s.motion.iter().flatten());
        for v in [&s.eval.q, &s.eval.qd, &s.eval.qdd, &s.eval.gamma] {
            row.extend(v);
        }
        for v in &s.others {
            row.extend(v);
        }
        w.write_record(row.iter().map(|v| format!("{v:.12e}")))?;
    }
    w.flush()?;
    Ok(())
}

pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The font ships with the crate, so the plots need no system fonts.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../assets/DejaVuSans.ttf"),
        );
    });
}

/// Plots several series against time.
pub fn plot(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(String, Vec<f64>)],
) -> Result<(), Box<dyn std::error::Error>> {
    register_font();
    crate::png_figure::write(path, (900, 560), |root| {
        root.fill(&WHITE)?;
        let (lo, hi) = series
            .iter()
            .flat_map(|(_, v)| v.iter().copied())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let pad = ((hi - lo) * 0.08).max(1e-9);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 24))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(t[0]..t[t.len() - 1], (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("time t (s)")
            .y_desc(y_label)
            .label_style(("sans-serif", 15))
            .draw()?;
        for (k, (name, v)) in series.iter().enumerate() {
            let color = Palette99::pick(k).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    t.iter().copied().zip(v.iter().copied()),
                    color.stroke_width(2),
                ))?
                .label(name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()?;
        Ok(())
    })
}

/// The centre's part of a pose, twist or acceleration: its last three coordinates, whatever the
/// platform's freedom.
fn centre(values: &[f64]) -> [f64; 3] {
    let n = values.len();
    std::array::from_fn(|k| values[n - 3 + k])
}

/// The four figures of Section 9 (figs 7-10) as PNG files in `dir`.
///
/// # Errors
/// I/O or drawing errors.
pub fn write_plots(dir: &Path, study: &Study) -> Result<Vec<String>, Box<dyn std::error::Error>> {
    let t: Vec<f64> = study.samples.iter().map(|s| s.t).collect();
    let xyz = |f: &dyn Fn(&Sample) -> [f64; 3]| -> Vec<(String, Vec<f64>)> {
        ["x", "y", "z"]
            .iter()
            .enumerate()
            .map(|(k, a)| {
                (
                    a.to_string(),
                    study.samples.iter().map(|s| f(s)[k]).collect(),
                )
            })
            .collect()
    };
    let files = [
        (
            "fig7_trajectory.png",
            "Platform trajectory (fig. 7)",
            "centre position (m)",
            xyz(&|s| centre(&s.motion[0])),
        ),
        (
            "fig8_velocity.png",
            "Platform linear velocity (fig. 8)",
            "velocity (m/s)",
            xyz(&|s| centre(&s.motion[1])),
        ),
        (
            "fig9_acceleration.png",
            "Platform linear acceleration (fig. 9)",
            "acceleration (m/s²)",
            xyz(&|s| centre(&s.motion[2])),
        ),
    ];
    let mut written = Vec::new();
    for (name, title, y, series) in files {
        plot(&dir.join(name), title, y, &t, &series)?;
        written.push(name.to_string());
    }
    let name = "fig10_forces.png";
    plot_forces(&dir.join(name), study, &t)?;
    written.push(name.to_string());
    Ok(written)
}

/// Figure 10: one panel per actuator, so no series hides another; in each, the default model
/// (the consistent one) solid and the others dashed, in the actuator's colour.
fn plot_forces(path: &Path, study: &Study, t: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    register_font();
    crate::png_figure::write(path, (1200, 720), |root| {
        root.fill(&WHITE)?;
        let title = match study.others.first() {
            Some(other) => format!(
                "Actuator forces Γ (fig. 10): {} model solid, {other} model dashed",
                study.model
            ),
            None => format!("Actuator forces Γ ({})", study.model),
        };
        let root = root.titled(&title, ("sans-serif", 22))?;
        let n = study.freedom.dimension();
        for (i, panel) in root.split_evenly((n.div_ceil(3), 3)).iter().enumerate() {
            let series: Vec<(&str, Vec<f64>)> = std::iter::once((
                study.model,
                study.samples.iter().map(|s| s.eval.gamma[i]).collect(),
            ))
            .chain(
                study
                    .others
                    .iter()
                    .enumerate()
                    .map(|(k, &m)| (m, study.samples.iter().map(|s| s.others[k][i]).collect())),
            )
            .collect();
            let (lo, hi) = series
                .iter()
                .flat_map(|(_, v)| v.iter().copied())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            let pad = ((hi - lo) * 0.1).max(0.5);
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("Γ{}", i + 1), ("sans-serif", 18))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(t[0]..t[t.len() - 1], (lo - pad)..(hi + pad))?;
            chart
                .configure_mesh()
                .x_desc("t (s)")
                .y_desc("force (N, or N·m)")
                .label_style(("sans-serif", 13))
                .draw()?;
            let color = Palette99::pick(i).to_rgba();
            for (k, (model, values)) in series.iter().enumerate() {
                let points = t.iter().copied().zip(values.iter().copied());
                let style = color.stroke_width(2);
                let label = model.to_string();
                if k == 0 {
                    chart
                        .draw_series(LineSeries::new(points, style))?
                        .label(label)
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
                } else {
                    // Each further model dashed a little finer.
                    let dash = 7 - k.min(4) as u32;
                    chart
                        .draw_series(DashedLineSeries::new(points, dash, 5, style))?
                        .label(label)
                        .legend(move |(x, y)| {
                            EmptyElement::at((x, y))
                                + PathElement::new(vec![(0, 0), (dash as i32, 0)], style)
                                + PathElement::new(
                                    vec![(dash as i32 + 5, 0), (2 * dash as i32 + 5, 0)],
                                    style,
                                )
                        });
                }
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()?;
        }
        Ok(())
    })
}
