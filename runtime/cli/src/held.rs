//! `c5 simulate --torques`: the robot let go from home at rest with its actuators held at
//! constant forces, integrated through the forward dynamics; what an exported MJCF file
//! simulated in MuJoCo under the same `ctrl` is compared with (docs/export.md). Every
//! mechanism, whatever its platform's freedom, through [`Mechanism`].

use crate::columns;
use c5_runtime::{Error, Mechanism};
use std::path::Path;

/// One sample: the time, the pose and the twist, in the platform's coordinates.
pub struct Sample {
    pub t: f64,
    pub pose: Vec<f64>,
    pub twist: Vec<f64>,
}

/// The states from home at rest, every `1/rate` s for `duration` s, under the constant forces
/// `gamma` (RK4 over each step).
///
/// # Errors
/// The time and the error of the first step that fails (a singular pose on the way).
pub fn run(
    robot: &dyn Mechanism,
    gamma: &[f64],
    duration: f64,
    rate: f64,
) -> Result<Vec<Sample>, (f64, Error)> {
    let mut pose = robot.home();
    let mut twist = vec![0.0; pose.len()];
    let steps = (duration * rate).round() as usize;
    let dt = 1.0 / rate;
    let mut samples = Vec::with_capacity(steps + 1);
    samples.push(Sample {
        t: 0.0,
        pose: pose.clone(),
        twist: twist.clone(),
    });
    for k in 0..steps {
        let t = k as f64 * dt;
        robot
            .step_held(&mut pose, &mut twist, gamma, dt)
            .map_err(|e| (t, e))?;
        samples.push(Sample {
            t: (k + 1) as f64 * dt,
            pose: pose.clone(),
            twist: twist.clone(),
        });
    }
    Ok(samples)
}

/// `t`, the pose and the twist of each state, as a trajectory CSV without accelerations, its
/// columns named by the platform's `freedom`.
pub fn write_csv(path: &Path, freedom: columns::Freedom, samples: &[Sample]) -> crate::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    let header = std::iter::once(columns::TIME)
        .chain(freedom.pose_names().iter().copied())
        .chain(freedom.twist_names().iter().copied());
    w.write_record(header)?;
    for s in samples {
        let row = std::iter::once(&s.t).chain(&s.pose).chain(&s.twist);
        w.write_record(row.map(|v| format!("{v:.17e}")))?;
    }
    w.flush()?;
    Ok(())
}
