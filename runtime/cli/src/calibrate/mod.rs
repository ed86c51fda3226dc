//! `c5 calibrate`: a legged robot's true geometry from measured poses (a Gough-Stewart
//! platform, a rotary hexapod, a Delta); where to measure (`--plan`); and simulated
//! measurements for trials (`--simulate`).

mod measurements;
mod report;
mod robot_file;

use crate::Result;
use c5_robot::Description;
use c5_runtime::calibrate::{self, Noise, Nominal, Options};
use clap::Args;
use measurements::Columns;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Fits each leg's geometry (joint centres, a rotary leg's crank and rod lengths, the encoder
/// offset) to measured poses and encoder readings, and writes the calibrated robot file; with
/// `--plan N`, the N poses to measure; with `--simulate TRUTH.toml --poses FILE`, the
/// measurements a robot of that true geometry would give, for trials. Gough-Stewart
/// platforms, rotary hexapods and Deltas.
#[derive(Args)]
pub struct CalibrateArgs {
    /// The nominal robot file (a Gough-Stewart platform, a rotary hexapod or a Delta).
    #[arg(long, required_unless_present = "simulate")]
    robot: Option<PathBuf>,
    /// Measurements: CSV with columns `alpha,beta,gamma,xc,yc,zc,q1..q6` (rad, m; a Delta's
    /// `xc,yc,zc,q1..q3`), one measured pose and the encoder readings a row.
    #[arg(long, conflicts_with_all = ["plan", "simulate"], required_unless_present_any = ["plan", "simulate"])]
    data: Option<PathBuf>,
    /// Write N poses to measure (inside the robot's limits, chosen to make the geometry best
    /// observable) instead of calibrating.
    #[arg(long, value_name = "N", conflicts_with = "simulate")]
    plan: Option<usize>,
    /// Write the measurements that a robot of this true geometry gives at the poses of
    /// `--poses`, with the noise of the `--noise-*` options, instead of calibrating.
    #[arg(long, value_name = "TRUTH.toml", requires = "poses")]
    simulate: Option<PathBuf>,
    /// The poses to simulate (CSV `alpha,beta,gamma,xc,yc,zc`, a Delta's `xc,yc,zc`, as
    /// `--plan` writes).
    #[arg(long)]
    poses: Option<PathBuf>,
    /// Output: the calibrated robot file (default `calibrated.toml`); with `--plan`, the poses
    /// (default `calibration-poses.csv`); with `--simulate`, the measurements (default
    /// `measurements.csv`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write the report as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Also plot each leg's residuals before and after (PNG).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Standard deviation of each measured position component (m).
    #[arg(long, default_value_t = Noise::default().position)]
    noise_position: f64,
    /// Standard deviation of each measured RPY angle (rad).
    #[arg(long, default_value_t = Noise::default().angle)]
    noise_angle: f64,
    /// Standard deviation of each encoder reading (m, or rad for motors' angles).
    #[arg(long, default_value_t = Noise::default().encoder)]
    noise_encoder: f64,
    /// The unit of the parameters' scaling (m for lengths, rad for angles): about the geometric
    /// errors expected.
    #[arg(long, default_value_t = Options::default().scale)]
    scale: f64,
    /// The largest standard deviation (m, or rad) of a fitted combination; worse-known ones
    /// are fixed at their nominal values.
    #[arg(long, default_value_t = Options::default().observable)]
    observable: f64,
    /// Refuse data that leave a combination unobservable (nothing written) instead of fixing it.
    #[arg(long)]
    strict: bool,
    /// Seed of `--plan`'s candidates and `--simulate`'s noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

impl CalibrateArgs {
    fn options(&self) -> Options {
        Options {
            noise: Noise {
                position: self.noise_position,
                angle: self.noise_angle,
                encoder: self.noise_encoder,
            },
            scale: self.scale,
            observable: self.observable,
            strict: self.strict,
            ..Options::default()
        }
    }
}

/// The robot of `path` to calibrate, the file's text, and its measurements' columns.
fn load(path: &Path) -> Result<(Nominal, String, Columns)> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let description = Description::from_toml(&text, &path.display().to_string())?;
    let nominal = Nominal::new(description).map_err(|e| format!("{}: {e}", path.display()))?;
    let columns = Columns::new(
        nominal.mechanism().freedom().pose_names(),
        nominal.actuators(),
    );
    Ok((nominal, text, columns))
}

pub fn run(o: &CalibrateArgs) -> Result<ExitCode> {
    match (&o.simulate, o.plan, &o.robot) {
        (Some(truth), _, _) => simulate(o, truth),
        (None, Some(n), Some(robot)) => plan(o, robot, n),
        (None, None, Some(robot)) => fit(o, robot),
        (None, _, None) => Err("--robot is required".into()),
    }
}

fn plan(o: &CalibrateArgs, robot: &Path, n: usize) -> Result<ExitCode> {
    let (robot, _, columns) = load(robot)?;
    let poses = calibrate::plan(&robot, n, &o.options(), o.seed)?;
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| "calibration-poses.csv".into());
    measurements::write_poses(&out, &poses, &columns)?;
    writeln!(
        std::io::stdout().lock(),
        "wrote {} ({n} poses inside the robot's limits, chosen to make its geometry best \
         observable)",
        out.display()
    )?;
    Ok(ExitCode::SUCCESS)
}

fn simulate(o: &CalibrateArgs, truth: &Path) -> Result<ExitCode> {
    let (truth, _, columns) = load(truth)?;
    let poses_file = o.poses.as_ref().ok_or("--simulate needs --poses")?;
    let poses = measurements::read_poses(poses_file, &columns)?;
    let data = calibrate::simulate(&truth, &poses, &o.options().noise, o.seed)?;
    let out = o.out.clone().unwrap_or_else(|| "measurements.csv".into());
    measurements::write(&out, &data, &columns)?;
    writeln!(
        std::io::stdout().lock(),
        "wrote {} ({} measurements: poses with {} m and {} rad of noise, readings with {} {})",
        out.display(),
        data.len(),
        o.noise_position,
        o.noise_angle,
        o.noise_encoder,
        if truth.angular() { "rad" } else { "m" }
    )?;
    Ok(ExitCode::SUCCESS)
}

fn fit(o: &CalibrateArgs, robot_path: &Path) -> Result<ExitCode> {
    let (nominal, original, columns) = load(robot_path)?;
    let data_path = o.data.as_ref().ok_or("--data is required")?;
    let data = measurements::read(data_path, &columns)?;
    let options = o.options();
    let found = calibrate::calibrate(&nominal, &data, &options)?;
    let (before, after) = (found.before(), found.after());
    let rms = |x: &[calibrate::Spread]| {
        (x.iter().map(|s| s.rms * s.rms).sum::<f64>() / x.len().max(1) as f64).sqrt() * 1e6
    };
    let unit = if found.angular { "µrad" } else { "µm" };
    let header = format!(
        "# Calibrated by `c5 calibrate` from {} measured poses ({}): residual rms {:.1} {unit} \
         with the nominal\n# geometry, {:.2} {unit} with this one. Each changed value says the \
         nominal one.\n",
        data.len(),
        data_path.display(),
        rms(&before),
        rms(&after)
    );
    let text = robot_file::calibrated_text(&original, &found, &header)?;
    let report = report::text(&found, &options)?;
    let out = o.out.clone().unwrap_or_else(|| "calibrated.toml".into());
    std::fs::write(&out, text).map_err(|e| format!("{}: {e}", out.display()))?;
    if let Some(path) = &o.report {
        std::fs::write(path, serde_json::to_string_pretty(&report::json(&found))?)?;
    }
    if let Some(path) = &o.plot {
        report::plot(path, &found)?;
    }
    let mut stdout = std::io::stdout().lock();
    write!(stdout, "{report}")?;
    writeln!(stdout, "\nwrote {}", out.display())?;
    Ok(ExitCode::SUCCESS)
}
