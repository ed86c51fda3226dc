//! `c5 forward`: JSON Lines of platform states and actuator forces in, the platform's
//! acceleration out.

use crate::jsonl::{self, Key};
use crate::options::RobotArgs;
use c5_runtime::platform::Freedom;
use c5_runtime::Mechanism;
use clap::Args;
use serde_json::{json, Value};
use std::process::ExitCode;

/// Reads JSON Lines of platform states and actuator forces on stdin (`pose`, `omega`,
/// `velocity`, `gamma`), writes the platform's acceleration (`omega_dot`, `acceleration`).
#[derive(Args)]
pub struct ForwardArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Also write the forward dynamics' exact Jacobians, n×n each, rows the acceleration's
    /// coordinates: `d_acceleration_d_pose`, `d_acceleration_d_twist`, `d_acceleration_d_gamma`
    /// (columns the pose's, the twist's and the actuators; for six freedoms rows
    /// ω̇x ω̇y ω̇z ax ay az, columns α β γ xc yc zc and ωx ωy ωz vx vy vz). Mechanisms whose
    /// derivative kernels are generated: the C5, the Gough-Stewart platform and the Delta.
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
    let robot = &*args.robot.load_mechanism()?;
    if args.derivatives {
        crate::unbuilt::derivatives_of(robot)?;
    }
    let freedom = robot.freedom();
    let keys = keys(freedom);
    jsonl::answer_lines(|line| {
        let v = jsonl::parse(line, &keys)?;
        let (pose, gamma) = (&v[0], &v[v.len() - 1]);
        let twist = v[1..v.len() - 1].concat();
        if args.derivatives {
            return derivatives(robot, pose, &twist, gamma);
        }
        let mut accel = vec![0.0; freedom.dimension()];
        robot
            .forward_dynamics(pose, &twist, gamma, &mut accel)
            .map_err(|e| e.to_string())?;
        Ok(acceleration_parts(freedom, &accel))
    })
}

/// The acceleration under the names of its three-number parts.
fn acceleration_parts(freedom: Freedom, accel: &[f64]) -> Value {
    let parts = freedom.acceleration_parts().iter().zip(accel.chunks(3));
    Value::Object(
        parts
            .map(|(part, a)| (part.to_string(), json!(a)))
            .collect(),
    )
}

/// The forward dynamics and its exact Jacobians, `n × n` each, in the platform's coordinates.
#[cfg(feature = "derivatives")]
fn derivatives(
    robot: &dyn Mechanism,
    pose: &[f64],
    twist: &[f64],
    gamma: &[f64],
) -> Result<Value, String> {
    let n = robot.freedom().dimension();
    let mut accel = vec![0.0; n];
    let mut jacobians = [0; 3].map(|_| vec![0.0; n * n]);
    let [d_pose, d_twist, d_gamma] = &mut jacobians;
    c5_runtime::derivatives::sliced_derivatives_of(robot)
        .and_then(|d| {
            d.forward_dynamics_derivatives(
                pose,
                twist,
                gamma,
                &mut accel,
                [d_pose, d_twist, d_gamma],
            )
        })
        .map_err(|e| e.to_string())?;
    let mut out = acceleration_parts(robot.freedom(), &accel);
    let keys = [
        "d_acceleration_d_pose",
        "d_acceleration_d_twist",
        "d_acceleration_d_gamma",
    ];
    for (key, jacobian) in keys.into_iter().zip(&jacobians) {
        out[key] = json!(jsonl::rows(jacobian, n));
    }
    Ok(out)
}

/// Without the derivative kernels `run` refuses `--derivatives` before any line.
#[cfg(not(feature = "derivatives"))]
fn derivatives(
    _robot: &dyn Mechanism,
    _pose: &[f64],
    _twist: &[f64],
    _gamma: &[f64],
) -> Result<Value, String> {
    Err(crate::unbuilt::needs("`--derivatives`", "derivatives").to_string())
}
