//! `c5 plan`: a minimum-effort rest-to-rest move between two poses by iLQR on the forward
//! dynamics and its exact Jacobians, written as a trajectory CSV that `simulate --trajectory`
//! and `track --trajectory` read, and plotted beside the quintic move of the same duration;
//! for every robot whose platform is free in space and whose derivatives are generated.

use crate::columns;
use crate::options::{self, RobotArgs};
use crate::simulate::plot;
use crate::view;
use c5_runtime::plan::{plan, quintic_forces, Problem, Settings};
use c5_runtime::{Mechanism, Pose, SpatialRobot};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Plans a minimum-effort rest-to-rest move (iLQR on the forward dynamics and its
/// derivatives): writes `plan.csv` (t, the pose, twist, acceleration and the forces
/// gamma1..gamma6) and `plan_forces.png` beside the quintic move's forces. The C5 and the
/// Gough-Stewart platform (the mechanisms with derivative kernels).
#[derive(Args)]
pub struct PlanArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// The start pose `α,β,γ,xc,yc,zc` (rad, m) [default: Section 9's start, from the robot's
    /// home].
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    from: Option<Vec<f64>>,
    /// The goal pose `α,β,γ,xc,yc,zc` (rad, m) [default: Section 9's end, from the robot's
    /// home].
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    to: Option<Vec<f64>>,
    /// The move's duration (s).
    #[arg(long, default_value_t = 1.0)]
    duration: f64,
    /// Steps per second of the plan (its forces are held over each step).
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
    /// The largest force any actuator may apply (N) [default: unlimited].
    #[arg(long)]
    force_limit: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    view: view::PageArgs,
}

fn pose(given: &Option<Vec<f64>>, default: Pose, flag: &str) -> crate::Result<Pose> {
    match given {
        None => Ok(default),
        Some(v) if v.len() == 6 => Ok(Pose::from_array(std::array::from_fn(|i| v[i]))),
        Some(v) => Err(format!("{flag} takes 6 numbers (α,β,γ,xc,yc,zc), got {}", v.len()).into()),
    }
}

/// Peak and RMS of the forces.
fn peak_rms(forces: &[[f64; 6]]) -> (f64, f64) {
    let all: Vec<f64> = forces.iter().flatten().copied().collect();
    let peak = all.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    (
        peak,
        (all.iter().map(|f| f * f).sum::<f64>() / all.len() as f64).sqrt(),
    )
}

/// The robot of `--robot` as a platform free in space, or why it cannot be planned for.
fn spatial(mechanism: &dyn Mechanism) -> crate::Result<&dyn SpatialRobot> {
    mechanism.spatial().ok_or_else(|| {
        format!(
            "plan: the {} robot's platform only translates, and the planner takes a platform \
             free in space (the C5, the Gough-Stewart platform)",
            mechanism.mechanism()
        )
        .into()
    })
}

pub fn run(args: &PlanArgs) -> crate::Result<ExitCode> {
    let mechanism = args.robot.load_mechanism()?;
    let robot = spatial(mechanism.as_ref())?;
    // Section 9's move is checked state by state: only where a pose is left to it.
    let defaulted = args.from.is_none() || args.to.is_none();
    let (section9, scaled) = if defaulted {
        options::section9_for(mechanism.as_ref())?
    } else {
        (c5_runtime::trajectory::LinearMove::section9(), None)
    };
    let mut end = section9.start;
    end.center = section9.end;
    let problem = Problem {
        start: pose(&args.from, section9.start, "--from")?,
        goal: pose(&args.to, end, "--to")?,
        duration: args.duration,
        steps: options::sample_times(args.duration, args.rate, "steps")?.len() - 1,
        force_limit: args.force_limit,
    };
    let started = Instant::now();
    let planned = plan(robot, &problem, &Settings::default())?;
    let elapsed = started.elapsed();
    std::fs::create_dir_all(&args.out)?;
    let csv = args.out.join("plan.csv");
    write_csv(&csv, &planned)?;
    let quintic = quintic_forces(robot, &problem)?;
    let png = args.out.join("plan_forces.png");
    plot_forces(&png, &planned.times, &planned.forces, &quintic)?;
    let (peak, rms) = peak_rms(&planned.forces);
    let (q_peak, q_rms) = peak_rms(&quintic);
    println!(
        "plan: {} steps of {:.4} s, {} iLQR iterations in {} rounds, {:.2?}; goal error {:.1e}",
        problem.steps,
        problem.duration / problem.steps as f64,
        planned.iterations,
        planned.costs.len(),
        elapsed,
        planned.goal_error
    );
    println!("forces: peak {peak:.2} N, RMS {rms:.2} N (the quintic move: peak {q_peak:.2} N, RMS {q_rms:.2} N)");
    if defaulted {
        println!(
            "the default poses are Section 9's, from this robot's home{}",
            options::scaled_note(scaled)
        );
    }
    println!("wrote {} and {}", csv.display(), png.display());
    let drawn: Vec<view::Sample> = planned
        .times
        .iter()
        .zip(&planned.states)
        .enumerate()
        .map(|(k, (&t, s))| {
            view::Sample::of_state(t, s, &planned.forces[k.min(planned.forces.len() - 1)])
        })
        .collect();
    let title = "Minimum-effort plan (iLQR)";
    if let Some(p) = args
        .view
        .write(mechanism.as_ref(), &drawn, title, &args.out)?
    {
        println!("wrote {} (the 3D view)", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn write_csv(path: &Path, p: &c5_runtime::plan::Plan) -> crate::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut header = columns::state(columns::Freedom::Free);
    header.extend(columns::per_actuator("gamma", 6));
    writeln!(w, "{}", header.join(","))?;
    for (k, (t, s)) in p.times.iter().zip(&p.states).enumerate() {
        // The last sample has no step after it: the forces that hold the goal are the last
        // step's.
        let gamma = p.forces[k.min(p.forces.len() - 1)];
        let row: Vec<String> = std::iter::once(*t)
            .chain(s.pose.to_array())
            .chain(s.twist.to_array())
            .chain(s.accel.to_array())
            .chain(gamma)
            .map(|x| format!("{x}"))
            .collect();
        writeln!(w, "{}", row.join(","))?;
    }
    w.flush()?;
    Ok(())
}

fn plot_forces(
    path: &Path,
    times: &[f64],
    planned: &[[f64; 6]],
    quintic: &[[f64; 6]],
) -> crate::Result<()> {
    let t: Vec<f64> = times.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let mut series = Vec::new();
    for (name, forces) in [("plan", planned), ("quintic", quintic)] {
        for i in 0..6 {
            series.push((
                format!("Γ{} {name}", i + 1),
                forces.iter().map(|f| f[i]).collect(),
            ));
        }
    }
    plot(
        path,
        "Minimum-effort plan (iLQR) and the quintic move: actuator forces",
        "force (N)",
        &t,
        &series,
    )
}
