//! `c5 plan`: a minimum-effort rest-to-rest move between two poses by iLQR on the forward
//! dynamics and its exact Jacobians, written as a trajectory CSV that `simulate --trajectory`
//! and `track --trajectory` read, and plotted beside the quintic move of the same duration;
//! for every robot whose mechanism has its derivatives generated, in its platform's coordinates.

use crate::columns;
use crate::options::{self, RobotArgs};
use crate::simulate::plot;
use crate::view;
use c5_runtime::plan::{plan, quintic_forces, Problem, Settings};
use c5_runtime::{Mechanism, State};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Plans a minimum-effort rest-to-rest move (iLQR on the forward dynamics and its
/// derivatives): writes `plan.csv` (t, the pose, twist, acceleration and the forces
/// gamma1..gammaN) and `plan_forces.png` beside the quintic move's forces. The C5, the
/// Gough-Stewart platform and the Delta (the mechanisms with derivative kernels).
#[derive(Args)]
pub struct PlanArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// The start pose in the platform's coordinates, `α,β,γ,xc,yc,zc` or (a platform that only
    /// translates) `xc,yc,zc` (rad, m) [default: Section 9's start, from the robot's home].
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    from: Option<Vec<f64>>,
    /// The goal pose, as `--from` [default: Section 9's end, from the robot's home].
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    to: Option<Vec<f64>>,
    /// The move's duration (s).
    #[arg(long, default_value_t = 1.0)]
    duration: f64,
    /// Steps per second of the plan (its forces are held over each step).
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
    /// The largest force any actuator may apply (N, or N·m where the motors turn) [default:
    /// unlimited].
    #[arg(long)]
    force_limit: Option<f64>,
    /// The least singularity clearance every pose of the plan keeps (its terms about 1 far
    /// from a singular pose, 0 at it: a crank and its rods aligned, a U joint at its
    /// singularity, legs unable to hold the platform); 0 keeps the plan within reach only.
    #[arg(long, default_value_t = c5_runtime::plan::LEAST_CLEARANCE)]
    clearance: f64,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    view: view::PageArgs,
}

/// The pose given by `flag`, in the platform's coordinates, else `default`'s.
fn pose(
    robot: &dyn Mechanism,
    given: &Option<Vec<f64>>,
    default: &State,
    flag: &str,
) -> crate::Result<Vec<f64>> {
    let names = robot.freedom().pose_names();
    match given {
        None => Ok(robot.coordinates_of(default)?[0].clone()),
        Some(v) if v.len() == names.len() => Ok(v.clone()),
        Some(v) => Err(format!(
            "{flag} takes {} numbers ({}), got {}",
            names.len(),
            names.join(","),
            v.len()
        )
        .into()),
    }
}

/// Peak and RMS of the forces.
fn peak_rms(forces: &[Vec<f64>]) -> (f64, f64) {
    let all: Vec<f64> = forces.iter().flatten().copied().collect();
    let peak = all.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    (
        peak,
        (all.iter().map(|f| f * f).sum::<f64>() / all.len() as f64).sqrt(),
    )
}

pub fn run(args: &PlanArgs) -> crate::Result<ExitCode> {
    let mechanism = args.robot.load_mechanism()?;
    let robot = mechanism.as_ref();
    // Section 9's move is checked state by state: only where a pose is left to it.
    let defaulted = args.from.is_none() || args.to.is_none();
    let (section9, scaled) = if defaulted {
        options::section9_for(robot)?
    } else {
        (c5_runtime::trajectory::LinearMove::section9(), None)
    };
    let at = |pose| State {
        pose,
        ..State::default()
    };
    let mut end = section9.start;
    end.center = section9.end;
    let problem = Problem {
        start: pose(robot, &args.from, &at(section9.start), "--from")?,
        goal: pose(robot, &args.to, &at(end), "--to")?,
        duration: args.duration,
        steps: options::sample_times(args.duration, args.rate, "steps")?.len() - 1,
        force_limit: args.force_limit,
        least_clearance: args.clearance,
    };
    let started = Instant::now();
    let planned = plan(robot, &problem, &Settings::default())?;
    let elapsed = started.elapsed();
    std::fs::create_dir_all(&args.out)?;
    let csv = args.out.join("plan.csv");
    write_csv(robot, &csv, &planned)?;
    let quintic = quintic_forces(robot, &problem)?;
    let png = args.out.join("plan_forces.png");
    plot_forces(robot, &png, &planned.times, &planned.forces, &quintic)?;
    let (peak, rms) = peak_rms(&planned.forces);
    let (q_peak, q_rms) = peak_rms(&quintic);
    // Written, not printed: a closed stdout (`c5 plan | head -1`) ends the run quietly.
    let mut report = std::io::stdout().lock();
    writeln!(
        report,
        "plan: {} steps of {:.4} s, {} iLQR iterations in {} rounds, {:.2?}; goal error {:.1e}, \
         least clearance {:.3}",
        problem.steps,
        problem.duration / problem.steps as f64,
        planned.iterations,
        planned.costs.len(),
        elapsed,
        planned.goal_error,
        planned.least_clearance
    )?;
    let unit = robot.description().body_tree().actuator_unit();
    writeln!(
        report,
        "forces: peak {peak:.2} {unit}, RMS {rms:.2} {unit} (the quintic move: peak {q_peak:.2} \
         {unit}, RMS {q_rms:.2} {unit})"
    )?;
    if defaulted {
        writeln!(
            report,
            "the default poses are Section 9's, from this robot's home{}",
            options::scaled_note(scaled)
        )?;
    }
    writeln!(report, "wrote {} and {}", csv.display(), png.display())?;
    let drawn: Vec<view::Sample> = planned
        .times
        .iter()
        .zip(&planned.states)
        .enumerate()
        .map(|(k, (&t, s))| {
            view::Sample::of_state(
                robot,
                t,
                s,
                &planned.forces[k.min(planned.forces.len() - 1)],
            )
        })
        .collect::<crate::Result<_>>()?;
    let title = "Minimum-effort plan (iLQR)";
    if let Some(p) = args.view.write(robot, &drawn, title, &args.out)? {
        writeln!(report, "wrote {} (the 3D view)", p.display())?;
    }
    Ok(ExitCode::SUCCESS)
}

fn write_csv(robot: &dyn Mechanism, path: &Path, p: &c5_runtime::plan::Plan) -> crate::Result<()> {
    let freedom = robot.freedom();
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut header = columns::state(freedom);
    header.extend(columns::per_actuator("gamma", freedom.dimension()));
    writeln!(w, "{}", header.join(","))?;
    for (k, (t, s)) in p.times.iter().zip(&p.states).enumerate() {
        // The last sample has no step after it: the forces that hold the goal are the last
        // step's.
        let gamma = &p.forces[k.min(p.forces.len() - 1)];
        let row: Vec<String> = std::iter::once(*t)
            .chain(robot.coordinates_of(s)?.concat())
            .chain(gamma.iter().copied())
            .map(|x| format!("{x}"))
            .collect();
        writeln!(w, "{}", row.join(","))?;
    }
    w.flush()?;
    Ok(())
}

fn plot_forces(
    robot: &dyn Mechanism,
    path: &Path,
    times: &[f64],
    planned: &[Vec<f64>],
    quintic: &[Vec<f64>],
) -> crate::Result<()> {
    let t: Vec<f64> = times.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let mut series = Vec::new();
    for (name, forces) in [("plan", planned), ("quintic", quintic)] {
        for i in 0..planned[0].len() {
            series.push((
                format!("Γ{} {name}", i + 1),
                forces.iter().map(|f| f[i]).collect(),
            ));
        }
    }
    plot(
        path,
        "Minimum-effort plan (iLQR) and the quintic move: actuator forces",
        &format!(
            "force ({})",
            robot.description().body_tree().actuator_unit()
        ),
        &t,
        &series,
    )
}
