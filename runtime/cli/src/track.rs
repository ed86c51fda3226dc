//! `c5 track`: a computed-torque controller tracking a trajectory on a simulated robot.

use crate::columns;
use crate::options::{self, model_parser, RobotArgs};
use crate::simulate::plot;
use crate::trajectory_csv;
use c5_runtime::control::{orientation_error, ComputedTorque};
use c5_runtime::dynamics::{compose, exp_rotation, rk4_step, rotation, rpy, PlantState};
use c5_runtime::trajectory::LinearMove;
use c5_runtime::{Acceleration, Error, Model, Pose, State, Twist, C5};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A computed-torque controller tracking the Section 9 trajectory (or a file) on a simulated
/// robot, integrated through the forward dynamics; writes a CSV and plots.
#[derive(Args)]
pub struct TrackArgs {
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
    /// The controller's robot and model.
    #[command(flatten)]
    controller: RobotArgs,
    /// The simulated plant's robot (TOML) [default: the controller's].
    #[arg(long)]
    plant_robot: Option<PathBuf>,
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
}

pub fn run_cmd(o: &TrackArgs) -> crate::Result<ExitCode> {
    let controller = o.controller.load()?;
    let plant = match o.plant_robot.as_ref() {
        Some(p) => options::load(Some(p), o.plant_model)?,
        None => controller.to_model(o.plant_model),
    };
    let offset: [f64; 6] = match &o.initial_offset {
        None => [0.0; 6],
        Some(v) => <[f64; 6]>::try_from(v.as_slice()).map_err(|_| {
            format!(
                "--initial-offset takes six numbers dx,dy,dz,rx,ry,rz, got {}",
                v.len()
            )
        })?,
    };
    if !(o.bandwidth.is_finite() && o.bandwidth > 0.0) {
        return Err(format!("--bandwidth must be a positive number, got {}", o.bandwidth).into());
    }
    if let Some(limit) = o.force_limit {
        if !(limit.is_finite() && limit > 0.0) {
            return Err(format!("--force-limit must be a positive number, got {limit}").into());
        }
    }
    if offset.iter().any(|x| !x.is_finite()) {
        return Err("--initial-offset must hold six finite numbers".into());
    }
    let (desired, times) = match &o.trajectory {
        Some(path) => {
            let samples = trajectory_csv::read(path)?;
            let times = samples.iter().map(|(t, _)| *t).collect();
            (Desired::Samples(samples), times)
        }
        None => {
            let motion = LinearMove::section9();
            let times = options::sample_times(motion.duration, o.rate, "steps")?;
            (Desired::Motion(Box::new(move |t| motion.state(t))), times)
        }
    };
    let first = desired.at(times[0]);
    let turned = compose(
        &exp_rotation([offset[3], offset[4], offset[5]]),
        &rotation(&first.pose),
    );
    let [alpha, beta, gamma] = rpy(&turned);
    let c = first.pose.center;
    let start = Pose {
        alpha,
        beta,
        gamma,
        center: [c[0] + offset[0], c[1] + offset[1], c[2] + offset[2]],
    };
    let mut law = ComputedTorque::critically_damped(o.bandwidth);
    law.force_limit = o.force_limit;
    let setup = Setup {
        controller: &controller,
        plant: &plant,
        law,
        hold: o.hold,
    };
    let clock = std::time::Instant::now();
    let samples = run(
        &setup,
        &desired,
        &times,
        PlantState::new(&start, &first.twist),
    )
    .map_err(|(t, e)| format!("step at t = {t} s: {e}"))?;
    let elapsed = clock.elapsed();
    std::fs::create_dir_all(&o.out)?;
    let csv = o.out.join("track.csv");
    write_csv(&csv, &samples)?;
    let plots = write_plots(&o.out, &samples)?;
    let [max_pos, max_ori, end_pos, end_ori] = summary(&samples);
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
        writeln!(report, "wrote {}", o.out.join(p).display())?;
    }
    writeln!(
        report,
        "largest error: {max_pos:.6} mm, {max_ori:.6} mrad; at the end: {end_pos:.6} mm, \
         {end_ori:.6} mrad"
    )?;
    Ok(ExitCode::SUCCESS)
}

/// The trajectory to track: a function of time, or samples interpolated linearly between.
pub enum Desired {
    Motion(Box<dyn Fn(f64) -> State>),
    Samples(Vec<(f64, State)>),
}

fn lerp(a: &[f64; 6], b: &[f64; 6], s: f64) -> [f64; 6] {
    std::array::from_fn(|i| a[i] + s * (b[i] - a[i]))
}

impl Desired {
    /// The desired state at `t`.
    pub fn at(&self, t: f64) -> State {
        match self {
            Desired::Motion(f) => f(t),
            Desired::Samples(s) => {
                let k = s.partition_point(|(ts, _)| *ts <= t).clamp(1, s.len() - 1);
                let ((t0, a), (t1, b)) = (&s[k - 1], &s[k]);
                let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                State {
                    pose: Pose::from_array(lerp(&a.pose.to_array(), &b.pose.to_array(), u)),
                    twist: Twist::from_array(lerp(&a.twist.to_array(), &b.twist.to_array(), u)),
                    accel: Acceleration::from_array(lerp(
                        &a.accel.to_array(),
                        &b.accel.to_array(),
                        u,
                    )),
                }
            }
        }
    }
}

/// One sample of a tracking run.
#[derive(Clone, Debug)]
pub struct Sample {
    pub t: f64,
    pub desired: Pose,
    pub actual: Pose,
    /// `C_d - C` (m).
    pub position_error: [f64; 3],
    /// `log(R_d Rᵀ)` (rad).
    pub orientation_error: [f64; 3],
    /// The forces applied from `t` on (N).
    pub gamma: [f64; 6],
}

/// What `track` needs: the controller's and the plant's robots, the law, how to hold the forces.
pub struct Setup<'a> {
    pub controller: &'a C5,
    pub plant: &'a C5,
    pub law: ComputedTorque,
    /// A sampled controller: the forces held over each step (else the law runs at every stage).
    pub hold: bool,
}

fn sample(t: f64, desired: &State, actual: &PlantState, gamma: [f64; 6]) -> Sample {
    Sample {
        t,
        desired: desired.pose,
        actual: actual.pose(),
        position_error: std::array::from_fn(|i| desired.pose.center[i] - actual.center[i]),
        orientation_error: orientation_error(&rotation(&desired.pose), &actual.rotation()),
        gamma,
    }
}

/// Runs the loop over `times` from `start`.
///
/// # Errors
/// The time and the error of the first step that fails (a singular pose on the way, or a
/// non-finite result).
pub fn run(
    setup: &Setup,
    desired: &Desired,
    times: &[f64],
    start: PlantState,
) -> Result<Vec<Sample>, (f64, Error)> {
    let mut state = start;
    let mut samples = Vec::with_capacity(times.len());
    for w in times.windows(2) {
        let (t, dt) = (w[0], w[1] - w[0]);
        let now = desired.at(t);
        let gamma = setup
            .law
            .forces(setup.controller, &now, &state)
            .map_err(|e| (t, e))?;
        samples.push(sample(t, &now, &state, gamma));
        state = rk4_step(setup.plant, &state, t, dt, |time, s| {
            if setup.hold {
                Ok(gamma)
            } else {
                setup.law.forces(setup.controller, &desired.at(time), s)
            }
        })
        .map_err(|e| (t, e))?;
    }
    if let Some(&t) = times.last() {
        let now = desired.at(t);
        let gamma = setup
            .law
            .forces(setup.controller, &now, &state)
            .map_err(|e| (t, e))?;
        samples.push(sample(t, &now, &state, gamma));
    }
    Ok(samples)
}

/// Writes the run as CSV: time, desired and actual pose, errors (mm, mrad), forces (N).
///
/// # Errors
/// I/O errors.
pub fn write_csv(path: &Path, samples: &[Sample]) -> Result<(), Box<dyn std::error::Error>> {
    let mut w = csv::Writer::from_path(path)?;
    let mut header = vec![columns::TIME.to_string()];
    for prefix in ["desired_", "actual_"] {
        header.extend(columns::POSE.map(|c| format!("{prefix}{c}")));
    }
    header.extend(
        [
            "ex_mm", "ey_mm", "ez_mm", "erx_mrad", "ery_mrad", "erz_mrad",
        ]
        .map(String::from),
    );
    header.extend(columns::GAMMA.map(String::from));
    w.write_record(&header)?;
    for s in samples {
        let mut row = vec![s.t];
        row.extend(s.desired.to_array());
        row.extend(s.actual.to_array());
        row.extend(s.position_error.map(|e| e * 1e3));
        row.extend(s.orientation_error.map(|e| e * 1e3));
        row.extend(s.gamma);
        w.write_record(row.iter().map(|v| format!("{v:.12e}")))?;
    }
    w.flush()?;
    Ok(())
}

fn norm(v: &[f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The largest position (mm) and orientation (mrad) errors of the run, and the final ones.
pub fn summary(samples: &[Sample]) -> [f64; 4] {
    let max = |f: &dyn Fn(&Sample) -> f64| samples.iter().map(f).fold(0.0, f64::max);
    let last = samples.last().map_or([0.0; 4], |s| {
        [
            1e3 * norm(&s.position_error),
            1e3 * norm(&s.orientation_error),
            0.0,
            0.0,
        ]
    });
    [
        max(&|s| 1e3 * norm(&s.position_error)),
        max(&|s| 1e3 * norm(&s.orientation_error)),
        last[0],
        last[1],
    ]
}

/// The plots: tracking error (position mm, orientation mrad) and forces against time.
///
/// # Errors
/// I/O or drawing errors.
pub fn write_plots(
    dir: &Path,
    samples: &[Sample],
) -> Result<Vec<String>, Box<dyn std::error::Error>> {
    let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let series = |names: [&str; 3], f: &dyn Fn(&Sample) -> [f64; 3], scale: f64| {
        names
            .iter()
            .enumerate()
            .map(|(k, n)| {
                (
                    n.to_string(),
                    samples.iter().map(|s| scale * f(s)[k]).collect(),
                )
            })
            .collect::<Vec<(String, Vec<f64>)>>()
    };
    let files = [
        (
            "track_position_error.png",
            "Tracking error: position",
            "C_d - C (mm)",
            series(["x", "y", "z"], &|s| s.position_error, 1e3),
        ),
        (
            "track_orientation_error.png",
            "Tracking error: orientation, log(R_d Rᵀ)",
            "rotation (mrad)",
            series(
                ["about x", "about y", "about z"],
                &|s| s.orientation_error,
                1e3,
            ),
        ),
        (
            "track_forces.png",
            "Actuator forces",
            "force (N)",
            (0..6)
                .map(|i| {
                    (
                        format!("Γ{}", i + 1),
                        samples.iter().map(|s| s.gamma[i]).collect(),
                    )
                })
                .collect(),
        ),
    ];
    let mut written = Vec::new();
    for (name, title, y, series) in files {
        plot(&dir.join(name), title, y, &t, &series)?;
        written.push(name.to_string());
    }
    Ok(written)
}
