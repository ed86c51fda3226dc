//! `c5 eval`: JSON Lines of platform states in, everything the model gives out, one line each.

use crate::identify::load_estimate;
use crate::jsonl::{self, Key};
use crate::options::RobotArgs;
use c5_runtime::identify::Estimate;
use c5_runtime::{Acceleration, Pose, State, Twist, C5};
use clap::Args;
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

/// Reads JSON Lines of platform states on stdin, writes one JSON line of results per line.
#[derive(Args)]
pub struct EvalArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Identified parameters (`c5 identify --out`): `gamma` is then `Y_b β`, the forces
    /// of the identified robot with its friction (the robot file gives only the geometry).
    #[arg(long)]
    base_parameters: Option<PathBuf>,
}

/// The keys of an `eval` line.
const STATE_KEYS: [Key; 5] = [
    Key {
        name: "pose",
        len: 6,
        required: true,
    },
    Key {
        name: "omega",
        len: 3,
        required: false,
    },
    Key {
        name: "velocity",
        len: 3,
        required: false,
    },
    Key {
        name: "omega_dot",
        len: 3,
        required: false,
    },
    Key {
        name: "acceleration",
        len: 3,
        required: false,
    },
];

fn parse_state(line: &str) -> Result<State, String> {
    let v = jsonl::parse(line, &STATE_KEYS)?;
    let three = |k: usize| [v[k][0], v[k][1], v[k][2]];
    Ok(State {
        pose: Pose::from_array(std::array::from_fn(|i| v[0][i])),
        twist: Twist {
            omega: three(1),
            velocity: three(2),
        },
        accel: Acceleration {
            omega_dot: three(3),
            linear: three(4),
        },
    })
}

pub fn run(args: &EvalArgs) -> crate::Result<ExitCode> {
    let robot = args.robot.load()?;
    let estimate = args
        .base_parameters
        .as_ref()
        .map(|p| load_estimate(&robot, p))
        .transpose()?;
    eval(&robot, estimate.as_ref())
}

fn eval(robot: &C5, identified: Option<&Estimate>) -> crate::Result<ExitCode> {
    jsonl::answer_lines(|line| {
        let state = parse_state(line)?;
        let e = robot.evaluate(&state).map_err(|e| e.to_string())?;
        let mut out = serde_json::to_value(e).map_err(|e| e.to_string())?;
        if let Some(estimate) = identified {
            let gamma = estimate.forces(robot, &state).map_err(|e| e.to_string())?;
            out["gamma"] = json!(gamma);
        }
        Ok(out)
    })
}
