//! `c5 track`: a computed-torque controller tracking a trajectory on a simulated robot.

use crate::simulate::plot;
use c5_runtime::control::{orientation_error, ComputedTorque};
use c5_runtime::dynamics::{rk4_step, rotation, PlantState};
use c5_runtime::{Acceleration, Error, Pose, State, Twist, C5};
use std::path::Path;

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
    let mut header = vec!["t".to_string()];
    for prefix in ["desired_", "actual_"] {
        header.extend(["alpha", "beta", "gamma", "xc", "yc", "zc"].map(|c| format!("{prefix}{c}")));
    }
    header.extend(
        [
            "ex_mm", "ey_mm", "ez_mm", "erx_mrad", "ery_mrad", "erz_mrad",
        ]
        .map(String::from),
    );
    header.extend((1..=6).map(|i| format!("gamma{i}")));
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
