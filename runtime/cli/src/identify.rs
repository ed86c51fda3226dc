//! `c5 identify`, `c5 excite` and the identified parameters `c5 eval --base-parameters` reads.

use crate::columns::per_actuator;
use crate::encoder_log;
use crate::options::RobotArgs;
use crate::trajectory_csv;
use crate::Result;
use c5_runtime::identify::encoder_log::{Filtered, LogFilter, LogProcessor};
use c5_runtime::identify::{Estimate, Identifier};
use c5_runtime::Mechanism;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Identifies the base parameters (inertial and friction) from measured motion and forces:
/// weighted least squares, streaming, for every mechanism. The robot file gives the geometry
/// and gravity; its masses play no part.
#[derive(Args)]
pub struct IdentifyArgs {
    /// Samples: a trajectory CSV (t, alpha, beta, gamma, xc, yc, zc, optionally the twist
    /// wx..vz and acceleration wdx..az; a Delta's t, xc, yc, zc, optionally vx..vz and
    /// ax..az) with the measured forces gamma1..gamma6 (a Delta's gamma1..gamma3); or an
    /// encoder log (t, q1..q6, gamma1..gamma6; a Delta's q1..q3, gamma1..gamma3), filtered,
    /// differenced and decimated first.
    #[arg(long)]
    data: PathBuf,
    #[command(flatten)]
    robot: RobotArgs,
    /// Writes the parameters here (JSON) and a summary on stdout; else the JSON on stdout.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Encoder logs: the zero-phase Butterworth low-pass filter's cutoff (Hz) [default: the
    /// sampling rate / 25].
    #[arg(long)]
    cutoff: Option<f64>,
    /// Encoder logs: one sample kept in so many after the filter [default: the sampling rate /
    /// (5 × cutoff)].
    #[arg(long)]
    decimate: Option<usize>,
}

pub fn run(args: &IdentifyArgs) -> Result<ExitCode> {
    let robot = args.robot.load_mechanism()?;
    let robot = &*robot;
    if encoder_log::is_encoder_log(&args.data) {
        let (estimate, report) = from_encoders(robot, args)?;
        write(
            robot.base_parameters()?.relations().to_vec(),
            &args.data,
            args.out.as_deref(),
            estimate,
            Some(report),
            (false, false),
        )?;
    } else {
        if args.cutoff.is_some() || args.decimate.is_some() {
            return Err(format!(
                "{}: --cutoff and --decimate filter encoder logs (t, q1.., gamma1..); \
                 this file has the platform's state",
                args.data.display()
            )
            .into());
        }
        identify_cmd(robot, &args.data, args.out.as_deref())?;
    }
    Ok(ExitCode::SUCCESS)
}

/// What `identify` writes: the estimate and, for the reader, what each base parameter groups;
/// for an encoder log, how it was filtered.
#[derive(Serialize, Deserialize)]
pub struct Identified {
    #[serde(flatten)]
    pub estimate: Estimate,
    #[serde(default)]
    pub relations: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterReport>,
}

/// How an encoder log was filtered and thinned.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FilterReport {
    /// `"butterworth, zero phase (forwards and backwards)"`.
    pub kind: String,
    pub order: usize,
    pub cutoff_hz: f64,
    pub decimate: usize,
    pub sample_rate_hz: f64,
    pub samples_read: usize,
    pub samples_kept: usize,
    /// Dropped at each end: the filter's settling time.
    pub edge_samples: usize,
}

/// Identifies from an encoder log: the samples through [`LogProcessor`] (filter, central
/// differences, decimation, edges dropped), then the forward kinematics and the actuators'
/// motion to the platform's state, into the streaming estimator.
fn from_encoders(robot: &dyn Mechanism, args: &IdentifyArgs) -> Result<(Estimate, FilterReport)> {
    let data = &args.data;
    let n = robot.freedom().dimension();
    let mut rows = encoder_log::open(data, n)?;
    let progress = progress_bar(rows.len);
    // The sampling rate, from the first two samples, designs the filter.
    let first: Vec<encoder_log::Row> = rows
        .by_ref()
        .take(2)
        .collect::<std::result::Result<_, _>>()?;
    let rate = match first.as_slice() {
        [a, b] if b.t > a.t => 1.0 / (b.t - a.t),
        [_, b] => return Err(rows.error(b.line, "time must increase".into()).into()),
        _ => return Err(format!("{}: a log needs samples", data.display()).into()),
    };
    let mut settings = LogFilter::default_for(rate);
    if let Some(cutoff) = args.cutoff {
        settings.cutoff = Some(cutoff);
        settings.decimate = LogFilter::decimation_for(rate, cutoff);
    }
    if let Some(decimate) = args.decimate {
        settings.decimate = decimate;
    }
    let mut pipeline =
        LogProcessor::new(settings, rate, n).map_err(|e| format!("{}: {e}", data.display()))?;
    let mut identifier = Identifier::new(robot)?;
    let mut kept: Vec<Filtered> = Vec::new();
    // Where the forward kinematics iterates, it starts from the previous sample's pose.
    let (mut near, mut started) = (vec![0.0; n], false);
    let mut motion = [0; 3].map(|_| vec![0.0; n]);
    // The lines of the samples not yet kept or passed over: sample `index` is
    // `lines[index - passed]`.
    let mut lines: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut passed = 0;
    let mut consumed = 0;
    let mut take = |kept: &mut Vec<Filtered>,
                    lines: &mut std::collections::VecDeque<usize>,
                    passed: &mut usize|
     -> Result<()> {
        for s in kept.drain(..) {
            let line = lines[s.index - *passed];
            let [x, v, a] = &mut motion;
            robot
                .joint_state(
                    [&s.q, &s.qd, &s.qdd],
                    started.then_some(&near[..]),
                    [x, v, a],
                )
                .map_err(|e| format!("{}:{line}: {e}", data.display()))?;
            near.copy_from_slice(x);
            started = true;
            identifier
                .add_motion([x, v, a], &s.gamma)
                .map_err(|e| format!("{}:{line}: {e}", data.display()))?;
            consumed += 1;
            // Kept samples come in order: the lines before this one are done with.
            while *passed < s.index {
                lines.pop_front();
                *passed += 1;
            }
        }
        Ok(())
    };
    let mut push = |row: encoder_log::Row,
                    kept: &mut Vec<Filtered>,
                    lines: &mut std::collections::VecDeque<usize>|
     -> Result<()> {
        lines.push_back(row.line);
        pipeline
            .push(row.t, row.q(), row.gamma(), kept)
            .map_err(|e| format!("{}:{}: {e}", data.display(), row.line).into())
    };
    for row in first {
        push(row, &mut kept, &mut lines)?;
    }
    while let Some(row) = rows.next() {
        push(row?, &mut kept, &mut lines)?;
        if !kept.is_empty() {
            take(&mut kept, &mut lines, &mut passed)?;
            progress.set_position(rows.position());
        }
    }
    let (samples_read, edge) = (pipeline.samples(), pipeline.edge());
    pipeline
        .finish(&mut kept)
        .map_err(|e| format!("{}: {e}", data.display()))?;
    take(&mut kept, &mut lines, &mut passed)?;
    progress.finish_and_clear();
    let estimate = identifier
        .estimate()
        .map_err(|e| format!("{}: {e}", data.display()))?;
    let report = FilterReport {
        kind: "butterworth, zero phase (forwards and backwards)".to_string(),
        order: settings.order,
        cutoff_hz: settings.cutoff.unwrap_or(f64::NAN),
        decimate: settings.decimate,
        sample_rate_hz: rate,
        samples_read,
        samples_kept: consumed,
        edge_samples: edge,
    };
    Ok((estimate, report))
}

fn progress_bar(len: u64) -> ProgressBar {
    let progress = if len >= PROGRESS_FROM_BYTES {
        ProgressBar::new(len)
    } else {
        ProgressBar::hidden()
    };
    progress.set_style(
        ProgressStyle::with_template("{bar:40} {bytes}/{total_bytes} {per_sec} eta {eta}")
            .expect("a valid template"),
    );
    progress
}

/// Files smaller than this identify without a progress bar.
const PROGRESS_FROM_BYTES: u64 = 10 << 20;

/// Fits the base parameters of `robot`'s model and geometry to the samples of `data`.
fn identify_cmd(robot: &dyn Mechanism, data: &Path, out: Option<&Path>) -> Result<()> {
    let n = robot.freedom().dimension();
    let gamma_columns = per_actuator("gamma", n);
    let gamma_columns: Vec<&str> = gamma_columns.iter().map(String::as_str).collect();
    let samples = trajectory_csv::open(data, &gamma_columns)?;
    let progress = progress_bar(samples.len);
    let derived = samples.derived;
    let mut identifier = Identifier::new(robot)?;
    let mut samples = samples;
    while let Some(sample) = samples.next() {
        let sample = sample?;
        identifier
            .add(&sample.state, &sample.extra[..n])
            .map_err(|e| format!("{}:{}: {e}", data.display(), sample.line))?;
        if identifier.samples().is_multiple_of(4096) {
            progress.set_position(samples.position());
        }
    }
    progress.finish_and_clear();
    let estimate = identifier
        .estimate()
        .map_err(|e| format!("{}: {e}", data.display()))?;
    let relations = identifier.base_parameters().relations().to_vec();
    write(relations, data, out, estimate, None, derived)
}

/// Writes the parameters (JSON on stdout, or to `out` with a summary on stdout).
fn write(
    relations: Vec<String>,
    data: &Path,
    out: Option<&Path>,
    estimate: Estimate,
    filter: Option<FilterReport>,
    derived: (bool, bool),
) -> Result<()> {
    let identified = Identified {
        relations,
        estimate,
        filter,
    };
    let json = serde_json::to_string_pretty(&identified)? + "\n";
    let mut stdout = std::io::stdout().lock();
    match out {
        None => stdout.write_all(json.as_bytes())?,
        Some(path) => {
            std::fs::write(path, json)?;
            let e = &identified.estimate;
            if derived.0 || derived.1 {
                writeln!(
                    stdout,
                    "{}: no twist or acceleration columns, derived by finite differences",
                    data.display()
                )?;
            }
            if let Some(f) = &identified.filter {
                writeln!(
                    stdout,
                    "{}: an encoder log at {} Hz: order-{} Butterworth at {} Hz, zero phase; \
                     {} of {} samples kept (one in {}, {} dropped at each end)",
                    data.display(),
                    f.sample_rate_hz,
                    f.order,
                    f.cutoff_hz,
                    f.samples_kept,
                    f.samples_read,
                    f.decimate,
                    f.edge_samples
                )?;
            }
            writeln!(
                stdout,
                "{} samples, {} model: {} base parameters, condition number {:.1}",
                e.samples,
                e.model,
                e.names.len(),
                e.condition_number
            )?;
            writeln!(
                stdout,
                "residual RMS per actuator (N, or N·m for a motor): {}",
                e.residual_rms
                    .iter()
                    .map(|r| format!("{r:.3e}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            )?;
            writeln!(
                stdout,
                "{:<18} {:>14} {:>12} {:>9}",
                "parameter", "estimate", "std dev", "rel %"
            )?;
            for j in 0..e.names.len() {
                writeln!(
                    stdout,
                    "{:<18} {:>14.6e} {:>12.3e} {:>9.3}",
                    e.names[j], e.values[j], e.std_dev[j], e.relative_std_dev_percent[j]
                )?;
            }
            writeln!(stdout, "wrote {}", path.display())?;
        }
    }
    Ok(())
}

/// Reads identified parameters for `robot`'s model.
pub fn load_estimate(robot: &dyn Mechanism, path: &Path) -> Result<Estimate> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let identified: Identified =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let e = identified.estimate;
    let base = robot.base_parameters()?;
    if e.model != robot.model_name() {
        return Err(format!(
            "{}: parameters of the {} model; pass --model {}",
            path.display(),
            e.model,
            e.model
        )
        .into());
    }
    if e.names != base.names() || e.values.len() != base.len() {
        return Err(format!(
            "{}: the base parameters are not those of this version's {} model",
            path.display(),
            robot.model_name()
        )
        .into());
    }
    if let Some(j) = e.values.iter().position(|v| !v.is_finite()) {
        return Err(format!("{}: `{}` is not finite", path.display(), e.names[j]).into());
    }
    Ok(e)
}
