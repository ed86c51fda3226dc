//! `c5 view`: the robot along a trajectory as an animated 3D page that opens offline in a
//! browser, legs coloured by their forces, what crosses a limit in the warning colour. The
//! commands that write plots (`simulate`, `track`, `plan`) write one beside them with
//! [`write`].

mod colors;
mod figure;
mod page;
mod plotly;

use crate::columns;
use crate::options::RobotArgs;
use crate::trajectory_csv;
use c5_runtime::Mechanism;
use clap::Args;
use figure::{Readout, Shot};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// How many frames a page holds unless told otherwise: enough for smooth play, small enough
/// for a page of a few hundred kilobytes beside plotly.js.
pub const FRAME_BUDGET: u32 = 300;

/// An animated 3D view of the robot along a trajectory CSV, as one self-contained HTML page.
#[derive(Args)]
pub struct ViewArgs {
    /// The trajectory (t, alpha, beta, gamma, xc, yc, zc, or t, xc, yc, zc for a platform that
    /// only translates; optionally the twist, the acceleration and the forces gamma1..gammaN,
    /// which colour the legs; without them the model's inverse dynamics gives the forces).
    trajectory: PathBuf,
    #[command(flatten)]
    robot: RobotArgs,
    /// The page to write.
    #[arg(long, default_value = "view.html")]
    out: PathBuf,
    /// The most frames the page holds; a longer trajectory is decimated evenly in time,
    /// keeping its first and last samples.
    #[arg(long, default_value_t = FRAME_BUDGET, value_parser = clap::value_parser!(u32).range(2..))]
    frames: u32,
}

/// One sample to draw, in the platform's coordinates ([`Mechanism::freedom`]): its time, pose,
/// twist where known (for the speed limit) and actuator forces (N or N·m).
#[derive(Clone, Debug)]
pub struct Sample {
    pub t: f64,
    pub pose: Vec<f64>,
    pub twist: Option<Vec<f64>>,
    pub gamma: Vec<f64>,
}

impl Sample {
    /// A sample of a whole platform state, in `robot`'s platform's coordinates.
    ///
    /// # Errors
    /// A state that turns a platform that only translates.
    #[cfg(feature = "derivatives")]
    pub fn of_state(
        robot: &dyn Mechanism,
        t: f64,
        state: &c5_runtime::State,
        gamma: &[f64],
    ) -> crate::Result<Self> {
        let [pose, twist, _] = robot.coordinates_of(state)?;
        Ok(Sample {
            t,
            pose,
            twist: Some(twist),
            gamma: gamma.to_vec(),
        })
    }
}

/// The page the commands that write plots write beside them.
#[derive(Args, Clone, Debug)]
pub struct PageArgs {
    /// Do not write the 3D view (`view.html`) beside the plots.
    #[arg(long)]
    no_view: bool,
    /// The most frames of the 3D view.
    #[arg(long, default_value_t = FRAME_BUDGET, value_parser = clap::value_parser!(u32).range(2..))]
    view_frames: u32,
}

impl PageArgs {
    /// Writes `dir/view.html` unless `--no-view`; returns its path when written.
    ///
    /// # Errors
    /// As [`write`].
    pub fn write(
        &self,
        robot: &dyn Mechanism,
        samples: &[Sample],
        title: &str,
        dir: &Path,
    ) -> crate::Result<Option<PathBuf>> {
        if self.no_view {
            return Ok(None);
        }
        let path = dir.join("view.html");
        write(robot, samples, self.view_frames as usize, title, &path)?;
        Ok(Some(path))
    }
}

pub fn run(args: &ViewArgs) -> crate::Result<ExitCode> {
    let robot = args.robot.load_mechanism()?;
    let samples = read(&args.trajectory, robot.as_ref())?;
    let title = format!("{} — {}", args.trajectory.display(), robot.mechanism());
    let frames = write(
        robot.as_ref(),
        &samples,
        args.frames as usize,
        &title,
        &args.out,
    )?;
    writeln!(
        std::io::stdout().lock(),
        "wrote {} ({frames} frames of {} samples)",
        args.out.display(),
        samples.len()
    )?;
    Ok(ExitCode::SUCCESS)
}

/// The samples of a trajectory file in the platform's coordinates, the forces from its
/// `gamma1..N` columns where it has them, from `robot`'s inverse dynamics where it does not.
fn read(path: &Path, robot: &dyn Mechanism) -> crate::Result<Vec<Sample>> {
    let n = robot.freedom().dimension();
    let names = columns::per_actuator("gamma", n);
    let has_forces = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .and_then(|mut r| r.headers().cloned())
        .map(|h| names.iter().any(|g| h.iter().any(|c| c == g)))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let extra: Vec<&str> = match has_forces {
        true => names.iter().map(String::as_str).collect(),
        false => Vec::new(),
    };
    let mut samples = Vec::new();
    for sample in trajectory_csv::open(path, &extra)? {
        let s = sample?;
        let at = |e: c5_runtime::Error| format!("{}:{}: {e}", path.display(), s.line);
        let [pose, twist, accel] = robot.coordinates_of(&s.state).map_err(at)?;
        let gamma = match has_forces {
            true => s.extra.clone(),
            false => {
                let mut gamma = vec![0.0; n];
                robot
                    .inverse_dynamics(&pose, &twist, &accel, &mut gamma)
                    .map_err(at)?;
                gamma
            }
        };
        samples.push(Sample {
            t: s.t,
            pose,
            twist: Some(twist),
            gamma,
        });
    }
    if samples.is_empty() {
        return Err(format!("{}: no samples", path.display()).into());
    }
    Ok(samples)
}

/// The indices of at most `budget` samples of `n`, evenly spread, the first and the last
/// always among them.
pub fn decimate(n: usize, budget: usize) -> Vec<usize> {
    if n <= budget || budget < 2 {
        return (0..n).collect();
    }
    (0..budget)
        .map(|j| ((j as f64) * (n - 1) as f64 / (budget - 1) as f64).round() as usize)
        .collect()
}

/// Writes the page of `samples` to `path`; returns how many frames it holds.
///
/// # Errors
/// A sample the robot refuses (its time and why), or the file not written.
pub fn write(
    robot: &dyn Mechanism,
    samples: &[Sample],
    budget: usize,
    title: &str,
    path: &Path,
) -> crate::Result<usize> {
    let (speed_limit, force_limit) = robot.speed_and_force_limits();
    let largest = samples
        .iter()
        .flat_map(|s| &s.gamma)
        .fold(0.0, |m: f64, g| m.max(g.abs()));
    let scale = force_limit.unwrap_or(largest).max(f64::MIN_POSITIVE);
    let over = |limit: Option<f64>, v: &[f64]| -> Vec<bool> {
        v.iter()
            .map(|x| limit.is_some_and(|l| x.abs() > l))
            .collect()
    };
    let legs = robot.freedom().dimension();
    let unit = robot.description().body_tree().actuator_unit();
    let picked = decimate(samples.len(), budget);
    let shots = picked
        .iter()
        .map(|&k| {
            let s = &samples[k];
            let at = |e: c5_runtime::Error| format!("sample at t = {} s: {e}", s.t);
            let scene = robot.scene(&s.pose).map_err(at)?;
            let over_speed = match &s.twist {
                Some(twist) => {
                    let mut qd = vec![0.0; legs];
                    robot
                        .joint_velocities(&s.pose, twist, &mut qd)
                        .map_err(at)?;
                    over(speed_limit, &qd)
                }
                None => vec![false; legs],
            };
            Ok(Shot {
                t: s.t,
                scene,
                gamma: s.gamma.clone(),
                over_force: over(force_limit, &s.gamma),
                over_speed,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let readout: Vec<Readout> = shots
        .iter()
        .map(|shot| Readout {
            t: shot.t,
            gamma: shot.gamma.clone(),
            colours: (0..legs).map(|i| shot.leg_colour(i, scale)).collect(),
            warnings: (0..legs)
                .filter_map(|i| {
                    let w = shot.warnings(i);
                    (!w.is_empty()).then(|| format!("leg {}: {}", i + 1, w.join(", ")))
                })
                .collect(),
        })
        .collect();
    let scale_origin = match force_limit {
        Some(_) => "the robot file's force limit",
        None => "the largest force of the trajectory",
    };
    let every = if picked.len() < samples.len() {
        format!(
            "{} frames of {} samples (about one in {:.0})",
            picked.len(),
            samples.len(),
            samples.len() as f64 / picked.len() as f64
        )
    } else {
        format!("all {} samples", samples.len())
    };
    let note = format!(
        "{} robot, {} model; {every}. Legs coloured by their force on ±{scale:.1} {unit} ({scale_origin}): \
         blue pulls, red pushes; magenta: past a [limits] bound.",
        robot.mechanism(),
        robot.model_name(),
    );
    let plot = figure::figure(&shots, scale, unit);
    let html = page::page(title, &note, &plot, &readout, unit)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, html).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(shots.len())
}

/// The most points a workspace page draws: more make the page slow to turn.
pub const CLOUD_BUDGET: usize = 60_000;

/// Writes a page of the point cloud `points` (a workspace's reachable poses) coloured by
/// `values`, at most [`CLOUD_BUDGET`] of them (every k-th), with `robot` drawn where given.
///
/// # Errors
/// The file not written.
pub fn write_cloud(
    points: &[[f64; 3]],
    values: &[f64],
    measure: &str,
    names: [&str; 3],
    robot: Option<&c5_runtime::scene::Scene>,
    title: &str,
    path: &Path,
) -> crate::Result<()> {
    let every = points.len().div_ceil(CLOUD_BUDGET).max(1);
    let kept: Vec<[f64; 3]> = points.iter().step_by(every).copied().collect();
    let shades: Vec<f64> = values.iter().step_by(every).copied().collect();
    let note = if every > 1 {
        format!(
            "{} of {} reachable points (one in {every}); {measure}.",
            kept.len(),
            points.len()
        )
    } else {
        format!("{} reachable points; {measure}.", points.len())
    };
    let plot = figure::cloud(&kept, &shades, measure, names, robot);
    std::fs::write(path, page::page(title, &note, &plot, &[], "")?)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_the_ends_and_the_budget() {
        assert_eq!(decimate(5, 300), vec![0, 1, 2, 3, 4]);
        let picked = decimate(4001, 300);
        assert_eq!(picked.len(), 300);
        assert_eq!((picked[0], picked[299]), (0, 4000));
        assert!(picked.windows(2).all(|w| w[1] > w[0]));
        let gaps: Vec<usize> = picked.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g == 13 || g == 14), "{gaps:?}");
    }
}
