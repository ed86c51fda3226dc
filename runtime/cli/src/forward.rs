//! `c5 forward`: JSON Lines of platform states and actuator forces in, the platform's
//! acceleration out.

use crate::jsonl::{self, Key};
use crate::options::RobotArgs;
use c5_runtime::platform::Freedom;
use c5_runtime::SpatialRobot;
use clap::Args;
use serde_json::{json, Value};
use std::process::ExitCode;

/// Reads JSON Lines of platform states and actuator forces on stdin (`pose`, `omega`,
/// `velocity`, `gamma`), writes the platform's acceleration (`omega_dot`, `acceleration`).
#[derive(Args)]
pub struct ForwardArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Also write the forward dynamics' exact Jacobians, 6×6 each, rows ω̇x ω̇y ω̇z ax ay az:
    /// `d_acceleration_d_pose`, `d_acceleration_d_twist`, `d_acceleration_d_gamma` (columns
    /// α β γ xc yc zc; ωx ωy ωz vx vy vz; actuators 1..6).
    #[arg(long)]
    derivatives: bool,
}

/// The keys of a `forward` line for a platform of `freedom`: `pose`, the twist's parts,
/// `gamma`.
fn keys(freedom: Freedom) -> Vec<Key> {
    let n = freedom.dimension();
    let mut keys = vec![Key::required("pose", n)];
    keys.extend(
        freedom
            .twist_parts()
            .iter()
            .map(|&part| Key::optional(part, 3)),
    );
    keys.push(Key::required("gamma", n));
    keys
}

pub fn run(args: &ForwardArgs) -> crate::Result<ExitCode> {
    if args.derivatives && !cfg!(feature = "derivatives") {
        return Err(crate::unbuilt::needs("`--derivatives`", "derivatives"));
    }
    let robot = args.robot.load_mechanism()?;
    let freedom = robot.freedom();
    let spatial = match (robot.spatial(), args.derivatives) {
        (None, true) => {
            return Err(format!(
                "`--derivatives` is not served for the {} yet: its platform only translates",
                robot.mechanism()
            )
            .into())
        }
        (spatial, true) => spatial,
        (_, false) => None,
    };
    let keys = keys(freedom);
    jsonl::answer_lines(|line| {
        let v = jsonl::parse(line, &keys)?;
        let (pose, gamma) = (&v[0], &v[v.len() - 1]);
        let twist = v[1..v.len() - 1].concat();
        if let Some(robot) = spatial {
            return derivatives(robot, pose, &twist, gamma);
        }
        let mut accel = vec![0.0; freedom.dimension()];
        robot
            .forward_dynamics(pose, &twist, gamma, &mut accel)
            .map_err(|e| e.to_string())?;
        let parts = freedom.acceleration_parts().iter().zip(accel.chunks(3));
        Ok(Value::Object(
            parts
                .map(|(part, a)| (part.to_string(), json!(a)))
                .collect(),
        ))
    })
}

/// The forward dynamics and its exact Jacobians, for a platform free in space.
#[cfg(feature = "derivatives")]
fn derivatives(
    robot: &dyn SpatialRobot,
    pose: &[f64],
    twist: &[f64],
    gamma: &[f64],
) -> Result<Value, String> {
    let six = |v: &[f64]| <[f64; 6]>::try_from(v).map_err(|_| "six freedoms".to_string());
    let pose = c5_runtime::Pose::from_array(six(pose)?);
    let twist = c5_runtime::Twist::from_array(six(twist)?);
    let gamma = six(gamma)?;
    let d = c5_runtime::mechanism::derivatives_of(robot)
        .and_then(|d| d.forward_dynamics_derivatives(&pose, &twist, &gamma))
        .map_err(|e| e.to_string())?;
    Ok(json!({
        "omega_dot": d.accel.omega_dot,
        "acceleration": d.accel.linear,
        "d_acceleration_d_pose": d.d_pose,
        "d_acceleration_d_twist": d.d_twist,
        "d_acceleration_d_gamma": d.d_gamma,
    }))
}

/// Without the derivative kernels `run` refuses `--derivatives` before any line.
#[cfg(not(feature = "derivatives"))]
fn derivatives(
    _robot: &dyn SpatialRobot,
    _pose: &[f64],
    _twist: &[f64],
    _gamma: &[f64],
) -> Result<Value, String> {
    Err(crate::unbuilt::needs("`--derivatives`", "derivatives").to_string())
}
