//! `c5 eval`: JSON Lines of platform states in, everything the model gives out, one line each.

use crate::jsonl::{self, Key};
use crate::options::{Loaded, RobotArgs};
use c5_runtime::{Acceleration, Limit, ParallelRobot, Pose, State, Twist};
use clap::Args;
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

/// Reads JSON Lines of platform states (or of actuator positions, rates and accelerations) on
/// stdin, writes one JSON line of results per line.
#[derive(Args)]
pub struct EvalArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Identified parameters (`c5 identify --out`): `gamma` is then `Y_b β`, the forces
    /// of the identified robot with its friction (the robot file gives only the geometry).
    #[arg(long)]
    base_parameters: Option<PathBuf>,
    /// Also write the inverse dynamics' exact Jacobians, 6×6 each, row `i` actuator `i`:
    /// `d_gamma_d_pose`, `d_gamma_d_twist`, `d_gamma_d_acceleration` (columns α β γ xc yc zc;
    /// ωx ωy ωz vx vy vz; ω̇x ω̇y ω̇z ax ay az), or for lines of actuator values `d_gamma_d_q`,
    /// `d_gamma_d_qd`, `d_gamma_d_qdd` (columns actuators 1..6; the C5's only).
    #[arg(long, conflicts_with = "base_parameters")]
    derivatives: bool,
    /// Make a line whose pose, actuator speeds or forces break a limit of the robot file's
    /// `[limits]` an error naming the limit and the actuator (else `limits` reports the
    /// smallest margin).
    #[arg(long)]
    strict_limits: bool,
}

/// The keys of an `eval` line: the platform's state, or the actuators' (`q`, `qd`, `qdd`),
/// never both.
const KEYS: [Key; 8] = [
    Key::required("pose", 6),
    Key::optional("omega", 3),
    Key::optional("velocity", 3),
    Key::optional("omega_dot", 3),
    Key::optional("acceleration", 3),
    Key::required("q", 6),
    Key::optional("qd", 6),
    Key::optional("qdd", 6),
];

/// How many of [`KEYS`] describe the platform; the rest describe the actuators.
const PLATFORM_KEYS: usize = 5;

/// What an `eval` line gives.
enum Line {
    /// The platform's state.
    Platform(State),
    /// The actuators' positions, rates and accelerations (m, m/s, m/s², segment order).
    Actuators([[f64; 6]; 3]),
}

fn parse_line(line: &str) -> Result<Line, String> {
    let values = jsonl::parse_present(line, &KEYS)?;
    let given = |range: std::ops::Range<usize>| -> Vec<&str> {
        range
            .filter(|&k| values[k].is_some())
            .map(|k| KEYS[k].name)
            .collect()
    };
    let (platform, actuators) = (given(0..PLATFORM_KEYS), given(PLATFORM_KEYS..KEYS.len()));
    if !platform.is_empty() && !actuators.is_empty() {
        return Err(format!(
            "a line gives the platform's state or the actuators', not both: {} with {}",
            platform.join(", "),
            actuators.join(", ")
        ));
    }
    // The keys of the kind given: absent optional ones are zero, an absent required one is an
    // error (`pose` when the line gives neither kind).
    let (first, kind) = if actuators.is_empty() {
        (0, PLATFORM_KEYS)
    } else {
        (PLATFORM_KEYS, KEYS.len() - PLATFORM_KEYS)
    };
    let v = (first..first + kind)
        .map(|k| match &values[k] {
            Some(v) => Ok(v.clone()),
            None if KEYS[k].required => Err(format!("missing `{}`", KEYS[k].name)),
            None => Ok(vec![0.0; KEYS[k].len]),
        })
        .collect::<Result<Vec<_>, String>>()?;
    if actuators.is_empty() {
        let three = |k: usize| [v[k][0], v[k][1], v[k][2]];
        Ok(Line::Platform(State {
            pose: Pose::from_array(std::array::from_fn(|i| v[0][i])),
            twist: Twist {
                omega: three(1),
                velocity: three(2),
            },
            accel: Acceleration {
                omega_dot: three(3),
                linear: three(4),
            },
        }))
    } else {
        Ok(Line::Actuators(std::array::from_fn(|k| {
            std::array::from_fn(|i| v[k][i])
        })))
    }
}

pub fn run(args: &EvalArgs) -> crate::Result<ExitCode> {
    if args.derivatives && !cfg!(feature = "derivatives") {
        return Err(crate::unbuilt::needs("`--derivatives`", "derivatives"));
    }
    let robot = match args.robot.load_freedoms()? {
        Loaded::Six(robot) => robot,
        Loaded::Translating(delta) => {
            if args.derivatives || args.base_parameters.is_some() || args.strict_limits {
                return Err(
                    "`--derivatives`, `--base-parameters` and `--strict-limits` are \
                            not served for the Delta yet: `c5 eval` gives its kinematics and \
                            torques"
                        .into(),
                );
            }
            return crate::translating::eval(&delta);
        }
    };
    let estimate = match &args.base_parameters {
        Some(p) => Some(identified::load(robot.as_ref(), p)?),
        None => None,
    };
    eval(
        robot.as_ref(),
        estimate.as_ref(),
        args.derivatives,
        args.strict_limits,
    )
}

/// The forces of identified parameters, where this build has identification.
#[cfg(feature = "identify")]
mod identified {
    pub use c5_runtime::identify::Estimate;

    pub fn load(
        robot: &dyn c5_runtime::ParallelRobot,
        path: &std::path::Path,
    ) -> crate::Result<Estimate> {
        crate::identify::load_estimate(robot, path)
    }

    pub fn forces(
        estimate: &Estimate,
        robot: &dyn c5_runtime::ParallelRobot,
        state: &c5_runtime::State,
    ) -> Result<[f64; 6], String> {
        estimate.forces(robot, state).map_err(|e| e.to_string())
    }
}

/// Without identification: `--base-parameters` says which feature it needs.
#[cfg(not(feature = "identify"))]
mod identified {
    pub enum Estimate {}

    pub fn load(
        _robot: &dyn c5_runtime::ParallelRobot,
        _path: &std::path::Path,
    ) -> crate::Result<Estimate> {
        Err(crate::unbuilt::needs("`--base-parameters`", "identify"))
    }

    pub fn forces(
        estimate: &Estimate,
        _robot: &dyn c5_runtime::ParallelRobot,
        _state: &c5_runtime::State,
    ) -> Result<[f64; 6], String> {
        match *estimate {}
    }
}

/// The inverse dynamics' three Jacobians, each under its key.
type KeyedJacobians = [(&'static str, [[f64; 6]; 6]); 3];

/// The inverse dynamics' Jacobians of a line, under their keys.
#[cfg(feature = "derivatives")]
fn derivative_keys(
    robot: &dyn ParallelRobot,
    state: &State,
    joints: Option<[[f64; 6]; 3]>,
) -> Result<KeyedJacobians, String> {
    Ok(match joints {
        Some([q, qd, qdd]) => {
            let d = robot
                .inverse_dynamics_joint_derivatives(&q, &qd, &qdd)
                .map_err(|e| e.to_string())?;
            [
                ("d_gamma_d_q", d.d_q),
                ("d_gamma_d_qd", d.d_qd),
                ("d_gamma_d_qdd", d.d_qdd),
            ]
        }
        None => {
            let d = robot
                .inverse_dynamics_derivatives(state)
                .map_err(|e| e.to_string())?;
            [
                ("d_gamma_d_pose", d.d_pose),
                ("d_gamma_d_twist", d.d_twist),
                ("d_gamma_d_acceleration", d.d_accel),
            ]
        }
    })
}

#[cfg(not(feature = "derivatives"))]
fn derivative_keys(
    _robot: &dyn ParallelRobot,
    _state: &State,
    _joints: Option<[[f64; 6]; 3]>,
) -> Result<KeyedJacobians, String> {
    Err(crate::unbuilt::needs("`--derivatives`", "derivatives").to_string())
}

/// The smallest margin of every limit the robot sets, at the pose and with the actuators'
/// speeds and forces: the limit, the actuator (1..6), the margin and the value.
fn smallest_margin(
    robot: &dyn ParallelRobot,
    pose: &c5_runtime::Pose,
    qd: &[f64; 6],
    gamma: &[f64; 6],
) -> Result<Option<(Limit, usize, f64, f64)>, c5_runtime::Error> {
    let mut best = robot.smallest_pose_margin(pose)?;
    let (speed, force) = robot.speed_and_force_limits();
    for (limit, bound, values) in [(Limit::Speed, speed, qd), (Limit::Force, force, gamma)] {
        let Some(bound) = bound else { continue };
        for (i, v) in values.iter().enumerate() {
            let margin = bound - v.abs();
            if best.is_none_or(|(_, _, m, _)| margin < m) {
                best = Some((limit, i + 1, margin, *v));
            }
        }
    }
    Ok(best)
}

fn eval(
    robot: &dyn ParallelRobot,
    identified: Option<&identified::Estimate>,
    derivatives: bool,
    strict_limits: bool,
) -> crate::Result<ExitCode> {
    jsonl::answer_lines(|line| {
        let (state, joints) = match parse_line(line)? {
            Line::Platform(state) => (state, None),
            Line::Actuators(joints) => {
                let [q, qd, qdd] = &joints;
                let state = robot
                    .joint_state(q, qd, qdd, None)
                    .map_err(|e| e.to_string())?;
                (state, Some(joints))
            }
        };
        let e = robot.evaluate(&state).map_err(|e| e.to_string())?;
        let mut out = serde_json::to_value(e).map_err(|e| e.to_string())?;
        if let Some([q, qd, qdd]) = joints {
            // The actuators' values as given, the forces of the joint-space kernel (what a
            // controller calls), and the platform state they give, in the input keys'
            // conventions.
            let gamma = robot
                .inverse_dynamics_joint(&q, &qd, &qdd, Some(&state.pose))
                .map_err(|e| e.to_string())?;
            out["q"] = json!(q);
            out["qd"] = json!(qd);
            out["qdd"] = json!(qdd);
            out["gamma"] = json!(gamma);
            out["pose"] = json!(state.pose.to_array());
            out["omega"] = json!(state.twist.omega);
            out["velocity"] = json!(state.twist.velocity);
            out["omega_dot"] = json!(state.accel.omega_dot);
            out["acceleration"] = json!(state.accel.linear);
        }
        if derivatives {
            for (key, jacobian) in derivative_keys(robot, &state, joints)? {
                out[key] = json!(jacobian);
            }
        }
        if let Some(estimate) = identified {
            out["gamma"] = json!(identified::forces(estimate, robot, &state)?);
        }
        if robot.has_limits() {
            let gamma: [f64; 6] =
                serde_json::from_value(out["gamma"].clone()).map_err(|e| e.to_string())?;
            let smallest =
                smallest_margin(robot, &state.pose, &e.qd, &gamma).map_err(|e| e.to_string())?;
            if let Some((limit, actuator, margin, value)) = smallest {
                if strict_limits && margin < 0.0 {
                    let e = c5_runtime::Error::Limit {
                        limit,
                        actuator,
                        value,
                        margin,
                    };
                    return Err(e.to_string());
                }
                out["limits"] = json!({
                    "limit": limit.name(),
                    "actuator": actuator,
                    "margin": margin,
                    "value": value,
                });
            }
        }
        Ok(out)
    })
}
