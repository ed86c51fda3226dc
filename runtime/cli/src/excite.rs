//! `c5 excite`: an exciting trajectory for identification.

use crate::columns;
use crate::options::{scaled_note, section9_for, RobotArgs};
use crate::Result;
use c5_runtime::identify::excite::{self, Envelope, Search};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// Writes an exciting trajectory for identification (a Fourier series about the robot's home
/// pose, inside its limits, away from singular poses, of low condition number) as a
/// trajectory CSV, in the platform's coordinates.
#[derive(Args)]
pub struct ExciteArgs {
    /// Output CSV.
    #[arg(long, default_value = "excite.csv")]
    out: PathBuf,
    /// The robot's geometry, and the model whose base regressor is conditioned.
    #[command(flatten)]
    robot: RobotArgs,
    /// Period of the series (s): the file holds one.
    #[arg(long, default_value_t = 10.0)]
    period: f64,
    /// Harmonics per coordinate.
    #[arg(long, default_value_t = 10)]
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
}

/// Writes an exciting trajectory (one period at `rate`) and reports its condition number
/// against Section 9's.
pub fn run(o: &ExciteArgs) -> Result<ExitCode> {
    let robot = &*o.robot.load_mechanism()?;
    let out = &o.out;
    if !(o.rate.is_finite() && o.rate > 0.0) {
        return Err(format!("--rate must be a positive number, got {}", o.rate).into());
    }
    let search = Search {
        period: o.period,
        harmonics: o.harmonics,
        candidates: o.candidates,
        seed: o.seed,
        ..Search::default()
    };
    let found = excite::design(robot, &Envelope::default(), &search)?;
    let n = (o.period * o.rate).round() as usize;
    let mut w = csv::Writer::from_path(out)?;
    w.write_record(columns::state(robot.freedom()))?;
    let mut states = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 / o.rate;
        let s = found.trajectory.state(t);
        let mut row = vec![t];
        row.extend(robot.coordinates_of(&s)?.concat());
        w.write_record(row.iter().map(|v| format!("{v:.17e}")))?;
        states.push(s);
    }
    w.flush()?;
    let written = excite::condition_number(robot, states)?;
    let (motion, scaled) = section9_for(robot)?;
    let section9 =
        excite::condition_number(robot, (0..=1000).map(|k| motion.state(k as f64 / 1000.0)))?;
    let mut stdout = std::io::stdout().lock();
    writeln!(
        stdout,
        "wrote {} ({n} samples, {} s, {} harmonics)",
        out.display(),
        o.period,
        o.harmonics
    )?;
    writeln!(
        stdout,
        "condition number of the base regressor ({} model, {} base parameters): {written:.1}",
        robot.model_name(),
        robot.base_parameters()?.len()
    )?;
    writeln!(
        stdout,
        "Section 9's straight move{}: {}",
        scaled_note(scaled),
        if section9.is_finite() {
            format!("{section9:.3e}")
        } else {
            "infinite (its fixed orientation excites no inertia)".to_string()
        }
    )?;
    Ok(ExitCode::SUCCESS)
}
