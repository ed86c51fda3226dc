//! `c5 track`: a computed-torque controller tracking a trajectory on a simulated robot.

use crate::columns;
use crate::options::{self, model_parser, ForceNoise, RobotArgs, SensorArgs};
use crate::simulate::plot;
use crate::trajectory_csv;
use crate::view;
use c5_runtime::control::{orientation_error, ComputedTorque};
use c5_runtime::dynamics::{compose, exp_rotation, rk4_step, rotation, rpy, PlantState};
use c5_runtime::platform::Freedom;
use c5_runtime::sensors::{Encoders, RateEstimator};
use c5_runtime::{Acceleration, Error, Mechanism, Model, Pose, State, Twist};
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A computed-torque controller tracking the Section 9 trajectory (or a file) on a simulated
/// robot of any mechanism, in its platform's coordinates, integrated through the forward
/// dynamics; writes a CSV and plots.
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
    /// The plant's start off the trajectory: `dx,dy,dz` (m), then, for a platform that turns,
    /// optionally a rotation vector `rx,ry,rz` (rad, base frame).
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
    /// Where the law closes the loop: on the platform's pose (task) or on the actuators
    /// (joint: `Γ = M_q (q̈_d + Kp e_q + Kd ė_q) + c_q`).
    #[arg(long, value_enum, default_value_t = Space::Task)]
    space: Space,
    /// The controller's rate (Hz): it reads the encoders and holds its forces between
    /// samples; at most the integration rate (`--rate`, or the trajectory file's), of which it
    /// runs every n-th step. Implies the measured loop.
    #[arg(long)]
    control_rate: Option<f64>,
    /// The encoders and the forces' noise: with any of them (or `--control-rate`) the
    /// controller sees only the encoders' counts, and estimates the rates.
    #[command(flatten)]
    sensors: SensorArgs,
    /// The rate estimator's bandwidth (Hz): an α-β filter per actuator on the counts.
    #[arg(long, default_value_t = 50.0)]
    estimator_bandwidth: f64,
    /// Go on past the plant robot's `[limits]` (stroke, plate travel, tilt, speed, force)
    /// instead of stopping at the first one broken.
    #[arg(long)]
    ignore_limits: bool,
    /// The 3D view of the plant along its tracked motion.
    #[command(flatten)]
    view: view::PageArgs,
}

/// Where a computed-torque law closes the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Space {
    /// On the platform's pose and twist.
    Task,
    /// On the actuators' positions and rates.
    Joint,
}

pub fn run_cmd(o: &TrackArgs) -> crate::Result<ExitCode> {
    let controller = o.controller.load_mechanism()?;
    // The plant is the controller's robot (or its own file) under the plant's model.
    let plant = options::load_mechanism(
        o.plant_robot.as_ref().or(o.controller.robot.as_ref()),
        o.plant_model,
    )?;
    if controller.freedom() != plant.freedom() || controller.mechanism() != plant.mechanism() {
        return Err(format!(
            "the plant ({}) and the controller ({}) must be the same mechanism",
            plant.mechanism(),
            controller.mechanism()
        )
        .into());
    }
    let freedom = plant.freedom();
    // A shift alone, or a shift and a turn (a rotation vector); a platform that only translates
    // takes the shift.
    let (shift, turn): ([f64; 3], [f64; 3]) = match o.initial_offset.as_deref() {
        None => ([0.0; 3], [0.0; 3]),
        Some(&[dx, dy, dz]) => ([dx, dy, dz], [0.0; 3]),
        Some(&[dx, dy, dz, rx, ry, rz]) => ([dx, dy, dz], [rx, ry, rz]),
        Some(v) => {
            return Err(format!(
                "--initial-offset takes dx,dy,dz (m) and, for a platform that turns, optionally \
                 rx,ry,rz (rad): three or six numbers, got {}",
                v.len()
            )
            .into())
        }
    };
    if !(o.bandwidth.is_finite() && o.bandwidth > 0.0) {
        return Err(format!("--bandwidth must be a positive number, got {}", o.bandwidth).into());
    }
    if let Some(limit) = o.force_limit {
        if !(limit.is_finite() && limit > 0.0) {
            return Err(format!("--force-limit must be a positive number, got {limit}").into());
        }
    }
    if shift.iter().chain(&turn).any(|x| !x.is_finite()) {
        return Err("--initial-offset must hold finite numbers".into());
    }
    if !freedom.turns() && turn != [0.0; 3] {
        return Err(format!(
            "--initial-offset turns the platform, and the {}'s only translates: give rx,ry,rz = 0",
            plant.mechanism()
        )
        .into());
    }
    let mut scaled = None;
    let (desired, times) = match &o.trajectory {
        Some(path) => {
            let samples = trajectory_csv::read(path)?;
            let times = samples.iter().map(|(t, _)| *t).collect();
            (Desired::Samples(samples), times)
        }
        None => {
            let motion;
            (motion, scaled) = options::section9_for(controller.as_ref())?;
            let times = options::sample_times(motion.duration, o.rate, "steps")?;
            (Desired::Motion(Box::new(move |t| motion.state(t))), times)
        }
    };
    let first = desired.at(times[0]);
    let turned = compose(&exp_rotation(turn), &rotation(&first.pose));
    let [alpha, beta, gamma] = rpy(&turned);
    let c = first.pose.center;
    let start = Pose {
        alpha,
        beta,
        gamma,
        center: core::array::from_fn(|i| c[i] + shift[i]),
    };
    let mut law = ComputedTorque::critically_damped(o.bandwidth);
    // The actuators saturate at the robot's force limit unless told otherwise.
    law.force_limit = o.force_limit.or(plant.speed_and_force_limits().1);
    let setup = Setup {
        controller: controller.as_ref(),
        plant: plant.as_ref(),
        law,
        hold: o.hold,
        space: o.space,
        limits: !o.ignore_limits,
    };
    let measured = o.sensors.any() || o.control_rate.is_some();
    let clock = std::time::Instant::now();
    let initial = PlantState::new(&start, &first.twist);
    let samples = if measured {
        if o.hold {
            return Err("--hold is the ideal loop's; the measured loop holds its forces".into());
        }
        let step = times.get(1).map_or(1e-3, |t| t - times[0]);
        let every = match o.control_rate {
            None => 1,
            Some(rate) if rate.is_finite() && rate > 0.0 && rate <= 1.0001 / step => {
                ((1.0 / (rate * step)).round() as usize).max(1)
            }
            Some(rate) => {
                return Err(format!(
                    "--control-rate must be positive and at most the integration rate ({} Hz), \
                     got {rate}",
                    1.0 / step
                )
                .into())
            }
        };
        let loop_ = Measured {
            encoders: o.sensors.encoders()?,
            noise: o.sensors.noise()?,
            estimator: RateEstimator::new(o.estimator_bandwidth, every as f64 * step).map_err(
                |_| {
                    format!(
                        "--estimator-bandwidth must be positive, got {}",
                        o.estimator_bandwidth
                    )
                },
            )?,
            every,
        };
        run_measured(&setup, &desired, &times, initial, loop_)
    } else {
        run(&setup, &desired, &times, initial)
    }
    .map_err(|(t, e)| format!("step at t = {t} s: {e}"))?;
    let elapsed = clock.elapsed();
    std::fs::create_dir_all(&o.out)?;
    let csv = o.out.join("track.csv");
    let tree = plant.description().body_tree();
    write_csv(&csv, &samples, freedom, tree.actuators_turn())?;
    let unit = tree.actuator_unit();
    let plots = write_plots(&o.out, &samples, freedom, unit)?;
    let drawn: Vec<view::Sample> = samples
        .iter()
        .map(|s| view::Sample {
            t: s.t,
            pose: s.actual.clone(),
            twist: None,
            gamma: s.gamma.clone(),
        })
        .collect();
    let title = format!("Tracking ({} robot, the plant)", plant.mechanism());
    let page = o.view.write(plant.as_ref(), &drawn, &title, &o.out)?;
    let [max_pos, max_ori, end_pos, end_ori] = summary(&samples);
    let [rms_pos, rms_ori] = rms(&samples);
    let mut report = std::io::stdout().lock();
    writeln!(
        report,
        "tracked {} steps in {:.1} ms: controller {} model in {} space, plant {} model{}",
        samples.len(),
        elapsed.as_secs_f64() * 1e3,
        controller.model_name(),
        match o.space {
            Space::Task => "task",
            Space::Joint => "joint",
        },
        plant.model_name(),
        if measured {
            ", measured (encoders and estimated rates)"
        } else {
            ", ideal (the exact state)"
        }
    )?;
    if scaled.is_some() {
        writeln!(
            report,
            "the desired motion: Section 9's{}",
            options::scaled_note(scaled)
        )?;
    }
    writeln!(report, "wrote {}", csv.display())?;
    for p in plots {
        writeln!(report, "wrote {}", o.out.join(p).display())?;
    }
    if let Some(p) = page {
        writeln!(report, "wrote {} (the 3D view)", p.display())?;
    }
    if freedom.turns() {
        writeln!(
            report,
            "largest error: {max_pos:.6} mm, {max_ori:.6} mrad; at the end: {end_pos:.6} mm, \
             {end_ori:.6} mrad"
        )?;
        writeln!(report, "RMS error: {rms_pos:.6} mm, {rms_ori:.6} mrad")?;
    } else {
        writeln!(
            report,
            "largest error: {max_pos:.6} mm; at the end: {end_pos:.6} mm"
        )?;
        writeln!(report, "RMS error: {rms_pos:.6} mm")?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The trajectory to track: a function of time, or samples interpolated linearly between.
pub enum Desired {
    Motion(Box<dyn Fn(f64) -> State>),
    Samples(Vec<(f64, State)>),
}

fn lerp<const N: usize>(a: &[f64; N], b: &[f64; N], s: f64) -> [f64; N] {
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

/// One sample of a tracking run, poses in the platform's coordinates.
#[derive(Clone, Debug)]
pub struct Sample {
    pub t: f64,
    pub desired: Vec<f64>,
    pub actual: Vec<f64>,
    /// `C_d - C` (m).
    pub position_error: [f64; 3],
    /// `log(R_d Rᵀ)` (rad); zero for a platform that only translates.
    pub orientation_error: [f64; 3],
    /// `q_d - q`, the actuators' error (m, or rad where they turn).
    pub actuator_error: Vec<f64>,
    /// The forces applied from `t` on (N or N·m).
    pub gamma: Vec<f64>,
}

/// What `track` needs: the controller's and the plant's robots, the law, how to hold the forces.
pub struct Setup<'a> {
    pub controller: &'a dyn Mechanism,
    pub plant: &'a dyn Mechanism,
    pub law: ComputedTorque,
    /// A sampled controller: the forces held over each step (else the law runs at every stage).
    pub hold: bool,
    /// Where the law closes the loop.
    pub space: Space,
    /// Stop at the first sample where the plant breaks one of its robot's limits.
    pub limits: bool,
}

/// The platform's pose and twist of `state` in `robot`'s coordinates.
fn coordinates(robot: &dyn Mechanism, state: &PlantState) -> Result<[Vec<f64>; 2], Error> {
    let [x, v, _] = robot.coordinates_of(&state.with_acceleration(Acceleration::default()))?;
    Ok([x, v])
}

/// `robot`'s actuator positions at `pose` (its coordinates).
fn actuators(robot: &dyn Mechanism, pose: &[f64]) -> Result<Vec<f64>, Error> {
    let mut q = vec![0.0; pose.len()];
    robot.actuator_positions(pose, &mut q)?;
    Ok(q)
}

impl Setup<'_> {
    /// The law's forces at the plant's exact state.
    fn forces(&self, desired: &State, actual: &PlantState) -> Result<Vec<f64>, Error> {
        match self.space {
            Space::Task => self.law.forces(self.controller, desired, actual),
            Space::Joint => {
                let c = self.controller;
                let [x, v] = coordinates(c, actual)?;
                let q = actuators(c, &x)?;
                let mut qd = vec![0.0; x.len()];
                c.joint_velocities(&x, &v, &mut qd)?;
                let [q_d, qd_d, qdd_d] = self.joints(desired)?;
                self.law.joint_forces(c, [&q_d, &qd_d, &qdd_d], &q, &qd)
            }
        }
    }

    /// The desired actuator motion `[q_d, q̇_d, q̈_d]` of the controller's model.
    fn joints(&self, desired: &State) -> Result<[Vec<f64>; 3], Error> {
        let c = self.controller;
        let [x, v, a] = c.coordinates_of(desired)?;
        let (mut qd, mut qdd) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        c.joint_velocities(&x, &v, &mut qd)?;
        c.joint_accelerations(&x, &v, &a, &mut qdd)?;
        Ok([actuators(c, &x)?, qd, qdd])
    }
}

/// The measured loop: encoders, the controller's rate estimator, its sampling and the forces'
/// noise.
pub struct Measured {
    pub encoders: Encoders,
    pub noise: ForceNoise,
    pub estimator: RateEstimator,
    /// The controller runs every this many integration steps.
    pub every: usize,
}

fn sample(
    setup: &Setup,
    t: f64,
    desired: &State,
    actual: &PlantState,
    gamma: Vec<f64>,
) -> Result<Sample, Error> {
    let [wanted, _, _] = setup.controller.coordinates_of(desired)?;
    let [pose, twist] = coordinates(setup.plant, actual)?;
    let q_d = actuators(setup.controller, &wanted)?;
    let q = actuators(setup.plant, &pose)?;
    if setup.limits && setup.plant.has_limits() {
        let mut qd = vec![0.0; q.len()];
        setup.plant.joint_velocities(&pose, &twist, &mut qd)?;
        setup.plant.check_limits(&pose)?;
        setup.plant.check_speeds(&qd)?;
        setup.plant.check_forces(&gamma)?;
    }
    Ok(Sample {
        t,
        desired: wanted,
        actual: pose,
        position_error: std::array::from_fn(|i| desired.pose.center[i] - actual.center[i]),
        orientation_error: orientation_error(&rotation(&desired.pose), &actual.rotation()),
        actuator_error: q_d.iter().zip(&q).map(|(d, a)| d - a).collect(),
        gamma,
    })
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
        let gamma = setup.forces(&now, &state).map_err(|e| (t, e))?;
        let held = gamma.clone();
        samples.push(sample(setup, t, &now, &state, gamma).map_err(|e| (t, e))?);
        state = rk4_step(setup.plant, &state, t, dt, |time, s| {
            if setup.hold {
                Ok(held.clone())
            } else {
                setup.forces(&desired.at(time), s)
            }
        })
        .map_err(|e| (t, e))?;
    }
    if let Some(&t) = times.last() {
        let now = desired.at(t);
        let gamma = setup.forces(&now, &state).map_err(|e| (t, e))?;
        samples.push(sample(setup, t, &now, &state, gamma).map_err(|e| (t, e))?);
    }
    Ok(samples)
}

/// Runs the measured loop over `times` from `start`: every `every` steps the controller reads
/// the encoders (the plant's actuator positions, quantized), estimates the positions and rates,
/// and commands forces, held (with their noise) until its next sample; the plant integrates
/// each step by RK4.
///
/// In task space the controller's state is the forward kinematics of the estimated positions
/// and `V = J q̇` of the estimated rates; in joint space, the estimates themselves.
///
/// # Errors
/// The time and the error of the first step that fails.
pub fn run_measured(
    setup: &Setup,
    desired: &Desired,
    times: &[f64],
    start: PlantState,
    mut sensors: Measured,
) -> Result<Vec<Sample>, (f64, Error)> {
    let c = setup.controller;
    let n = c.freedom().dimension();
    let mut state = start;
    let mut samples = Vec::with_capacity(times.len());
    let mut gamma = vec![0.0; n];
    // The actuators' acceleration the last command asked for: the estimator's input.
    let mut commanded = vec![0.0; n];
    let mut seen: Option<Vec<f64>> = None;
    for (k, &t) in times.iter().enumerate() {
        let now = desired.at(t);
        if k % sensors.every == 0 {
            let mut measure = || -> Result<Vec<f64>, Error> {
                let [pose, _] = coordinates(setup.plant, &state)?;
                let truth = actuators(setup.plant, &pose)?;
                let counts: Vec<f64> = truth.iter().map(|&q| sensors.encoders.reading(q)).collect();
                let joints = setup.joints(&now)?;
                // The estimator starts at the first counts with the planned rates.
                let (q, qd) = if k == 0 {
                    sensors.estimator.reset(&counts, &joints[1]);
                    (counts, joints[1].clone())
                } else {
                    let (q, qd) = sensors.estimator.update(&counts, &commanded)?;
                    (q.to_vec(), qd.to_vec())
                };
                let [q_d, qd_d, qdd_d] = &joints;
                let desired_joints = [q_d.as_slice(), qd_d, qdd_d];
                match setup.space {
                    Space::Joint => {
                        commanded = setup.law.joint_acceleration(desired_joints, &q, &qd);
                        setup.law.joint_forces(c, desired_joints, &q, &qd)
                    }
                    // From the last pose seen: a warm start where the forward kinematics
                    // iterates.
                    Space::Task => {
                        let (mut x, mut v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                        c.joint_state(
                            [&q, &qd, &vec![0.0; n]],
                            seen.as_deref(),
                            [&mut x, &mut v, &mut a],
                        )?;
                        let now_seen = c.state_of([&x, &v, &a])?;
                        seen = Some(x);
                        let actual = PlantState::new(&now_seen.pose, &now_seen.twist);
                        let accel = setup.law.commanded_acceleration(&now, &actual);
                        let [x, v, a] = c.coordinates_of(&actual.with_acceleration(accel))?;
                        c.joint_accelerations(&x, &v, &a, &mut commanded)?;
                        setup.law.forces(c, &now, &actual)
                    }
                }
            };
            let command = measure().map_err(|e| (t, e))?;
            gamma = command.iter().map(|&g| sensors.noise.noisy(g)).collect();
        }
        samples.push(sample(setup, t, &now, &state, gamma.clone()).map_err(|e| (t, e))?);
        if let Some(&next) = times.get(k + 1) {
            state = rk4_step(setup.plant, &state, t, next - t, |_, _| Ok(gamma.clone()))
                .map_err(|e| (t, e))?;
        }
    }
    Ok(samples)
}

/// Writes the run as CSV: time, desired and actual pose in the platform's coordinates, errors
/// (mm, and mrad where the platform turns; the actuators' in mm, or mrad where they turn),
/// forces.
///
/// # Errors
/// I/O errors.
pub fn write_csv(
    path: &Path,
    samples: &[Sample],
    freedom: Freedom,
    actuators_turn: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let n = freedom.dimension();
    let actuator_unit = if actuators_turn { "mrad" } else { "mm" };
    let mut w = csv::Writer::from_path(path)?;
    let mut header = vec![columns::TIME.to_string()];
    for prefix in ["desired_", "actual_"] {
        header.extend(freedom.pose_names().iter().map(|c| format!("{prefix}{c}")));
    }
    header.extend(["ex_mm", "ey_mm", "ez_mm"].map(String::from));
    if freedom.turns() {
        header.extend(["erx_mrad", "ery_mrad", "erz_mrad"].map(String::from));
    }
    header.extend(
        columns::per_actuator("eq", n)
            .iter()
            .map(|c| format!("{c}_{actuator_unit}")),
    );
    header.extend(columns::per_actuator("gamma", n));
    w.write_record(&header)?;
    for s in samples {
        let mut row = vec![s.t];
        row.extend(&s.desired);
        row.extend(&s.actual);
        row.extend(s.position_error.map(|e| e * 1e3));
        if freedom.turns() {
            row.extend(s.orientation_error.map(|e| e * 1e3));
        }
        row.extend(s.actuator_error.iter().map(|e| e * 1e3));
        row.extend(&s.gamma);
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

/// The RMS position (mm) and orientation (mrad) errors of the run.
pub fn rms(samples: &[Sample]) -> [f64; 2] {
    let n = samples.len().max(1) as f64;
    let mean_square =
        |f: &dyn Fn(&Sample) -> f64| samples.iter().map(|s| f(s).powi(2)).sum::<f64>() / n;
    [
        1e3 * mean_square(&|s| norm(&s.position_error)).sqrt(),
        1e3 * mean_square(&|s| norm(&s.orientation_error)).sqrt(),
    ]
}

/// The plots: tracking error (position mm, orientation mrad where the platform turns) and
/// forces against time.
///
/// # Errors
/// I/O or drawing errors.
pub fn write_plots(
    dir: &Path,
    samples: &[Sample],
    freedom: Freedom,
    unit: &str,
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
    let n = freedom.dimension();
    let force_axis = format!("force ({unit})");
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
            force_axis.as_str(),
            (0..n)
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
    // A platform that only translates has no orientation error to plot.
    let turns = freedom.turns();
    for (name, title, y, series) in files
        .into_iter()
        .filter(|f| turns || f.0 != "track_orientation_error.png")
    {
        plot(&dir.join(name), title, y, &t, &series)?;
        written.push(name.to_string());
    }
    Ok(written)
}
