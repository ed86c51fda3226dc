//! `c5 simulate --torques`: the robot let go from home at rest with its actuators held at
//! constant forces, integrated through the forward dynamics; what an exported MJCF file
//! simulated in MuJoCo under the same `ctrl` is compared with (docs/export.md).

use crate::columns;
use c5_runtime::dynamics::{rk4_step, PlantState};
use c5_runtime::{Error, ParallelRobot, Twist};
use std::path::Path;

/// The states from home at rest, every `1/rate` s for `duration` s, under the constant forces
/// `gamma` (RK4 over each step).
///
/// # Errors
/// The time and the error of the first step that fails (a singular pose on the way).
pub fn run(
    robot: &dyn ParallelRobot,
    gamma: [f64; 6],
    duration: f64,
    rate: f64,
) -> Result<Vec<(f64, PlantState)>, (f64, Error)> {
    let rest = Twist {
        omega: [0.0; 3],
        velocity: [0.0; 3],
    };
    let mut state = PlantState::new(&robot.home(), &rest);
    let steps = (duration * rate).round() as usize;
    let dt = 1.0 / rate;
    let mut samples = vec![(0.0, state)];
    for k in 0..steps {
        let t = k as f64 * dt;
        state = rk4_step(robot, &state, t, dt, |_, _| Ok(gamma)).map_err(|e| (t, e))?;
        samples.push(((k + 1) as f64 * dt, state));
    }
    Ok(samples)
}

/// `t`, the pose and the twist of each state, as a trajectory CSV without accelerations.
pub fn write_csv(path: &Path, samples: &[(f64, PlantState)]) -> crate::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    let header = std::iter::once(columns::TIME)
        .chain(columns::POSE)
        .chain(columns::TWIST);
    w.write_record(header)?;
    for (t, s) in samples {
        let pose = s.pose();
        let mut row = vec![*t];
        row.extend([pose.alpha, pose.beta, pose.gamma]);
        row.extend(pose.center);
        row.extend(s.twist.omega);
        row.extend(s.twist.velocity);
        w.write_record(row.iter().map(|v| format!("{v:.17e}")))?;
    }
    w.flush()?;
    Ok(())
}
