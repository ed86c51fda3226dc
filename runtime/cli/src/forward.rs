//! `c5 forward`: JSON Lines of platform states and actuator forces in, the platform's
//! acceleration out.

use crate::jsonl::{self, Key};
use crate::options::{Loaded, RobotArgs};
use c5_runtime::{Pose, Twist};
use clap::Args;
use serde_json::json;
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

/// The keys of a `forward` line.
const FORWARD_KEYS: [Key; 4] = [
    Key::required("pose", 6),
    Key::optional("omega", 3),
    Key::optional("velocity", 3),
    Key::required("gamma", 6),
];

pub fn run(args: &ForwardArgs) -> crate::Result<ExitCode> {
    if args.derivatives && !cfg!(feature = "derivatives") {
        return Err(crate::unbuilt::needs("`--derivatives`", "derivatives"));
    }
    let robot = match args.robot.load_freedoms()? {
        Loaded::Six(robot) => robot,
        Loaded::Translating(_) if args.derivatives => {
            return Err("`--derivatives` is not served for the Delta yet".into())
        }
        Loaded::Translating(delta) => return crate::translating::forward(&delta),
    };
    jsonl::answer_lines(|line| {
        let v = jsonl::parse(line, &FORWARD_KEYS)?;
        let pose = Pose::from_array(std::array::from_fn(|i| v[0][i]));
        let twist = Twist {
            omega: [v[1][0], v[1][1], v[1][2]],
            velocity: [v[2][0], v[2][1], v[2][2]],
        };
        let gamma: [f64; 6] = std::array::from_fn(|i| v[3][i]);
        #[cfg(feature = "derivatives")]
        if args.derivatives {
            let d = robot
                .forward_dynamics_derivatives(&pose, &twist, &gamma)
                .map_err(|e| e.to_string())?;
            return Ok(json!({
                "omega_dot": d.accel.omega_dot,
                "acceleration": d.accel.linear,
                "d_acceleration_d_pose": d.d_pose,
                "d_acceleration_d_twist": d.d_twist,
                "d_acceleration_d_gamma": d.d_gamma,
            }));
        }
        let a = robot
            .forward_dynamics(&pose, &twist, &gamma)
            .map_err(|e| e.to_string())?;
        Ok(json!({"omega_dot": a.omega_dot, "acceleration": a.linear}))
    })
}
