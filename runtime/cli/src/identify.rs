//! `c5 identify`, `c5 excite` and the identified parameters `c5 eval --base-parameters` reads.

use crate::columns::GAMMA;
use crate::options::RobotArgs;
use crate::trajectory_csv;
use crate::Result;
use c5_runtime::identify::{Estimate, Identifier};
use c5_runtime::C5;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Identifies the base parameters (inertial and friction) from measured motion and forces:
/// weighted least squares, streaming. The robot file gives the geometry and gravity; its
/// masses play no part.
#[derive(Args)]
pub struct IdentifyArgs {
    /// Samples: a trajectory CSV (t, alpha, beta, gamma, xc, yc, zc, optionally the twist
    /// wx..vz and acceleration wdx..az) with the measured forces gamma1..gamma6.
    #[arg(long)]
    data: PathBuf,
    #[command(flatten)]
    robot: RobotArgs,
    /// Writes the parameters here (JSON) and a summary on stdout; else the JSON on stdout.
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(args: &IdentifyArgs) -> Result<ExitCode> {
    let robot = args.robot.load()?;
    identify_cmd(&robot, &args.data, args.out.as_deref())?;
    Ok(ExitCode::SUCCESS)
}

/// What `identify` writes: the estimate and, for the reader, what each base parameter groups.
#[derive(Serialize, Deserialize)]
pub struct Identified {
    #[serde(flatten)]
    pub estimate: Estimate,
    #[serde(default)]
    pub relations: Vec<String>,
}

/// Files smaller than this identify without a progress bar.
const PROGRESS_FROM_BYTES: u64 = 10 << 20;

/// Fits the base parameters of `robot`'s model and geometry to the samples of `data`.
fn identify_cmd(robot: &C5, data: &Path, out: Option<&Path>) -> Result<()> {
    let samples = trajectory_csv::open(data, &GAMMA)?;
    let progress = if samples.len >= PROGRESS_FROM_BYTES {
        ProgressBar::new(samples.len)
    } else {
        ProgressBar::hidden()
    };
    progress.set_style(
        ProgressStyle::with_template("{bar:40} {bytes}/{total_bytes} {per_sec} eta {eta}")
            .expect("a valid template"),
    );
    let derived = samples.derived;
    let mut identifier = Identifier::new(robot);
    let mut samples = samples;
    while let Some(sample) = samples.next() {
        let sample = sample?;
        let gamma: [f64; 6] = std::array::from_fn(|i| sample.extra[i]);
        identifier
            .add(&sample.state, &gamma)
            .map_err(|e| format!("{}:{}: {e}", data.display(), sample.line))?;
        if identifier.samples().is_multiple_of(4096) {
            progress.set_position(samples.position());
        }
    }
    progress.finish_and_clear();
    let estimate = identifier
        .estimate()
        .map_err(|e| format!("{}: {e}", data.display()))?;
    let identified = Identified {
        relations: robot
            .base_parameters()
            .relations()
            .iter()
            .map(|s| s.to_string())
            .collect(),
        estimate,
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
                "residual RMS per actuator (N): {}",
                e.residual_rms.map(|r| format!("{r:.3e}")).join(" ")
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
pub fn load_estimate(robot: &C5, path: &Path) -> Result<Estimate> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let identified: Identified =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let e = identified.estimate;
    let base = robot.base_parameters();
    if e.model != robot.model() {
        return Err(format!(
            "{}: parameters of the {} model; pass --model {}",
            path.display(),
            e.model,
            e.model
        )
        .into());
    }
    if e.names
        .iter()
        .map(String::as_str)
        .ne(base.names().iter().copied())
        || e.values.len() != base.len()
    {
        return Err(format!(
            "{}: the base parameters are not those of this version's {} model",
            path.display(),
            robot.model()
        )
        .into());
    }
    if let Some(j) = e.values.iter().position(|v| !v.is_finite()) {
        return Err(format!("{}: `{}` is not finite", path.display(), e.names[j]).into());
    }
    Ok(e)
}
