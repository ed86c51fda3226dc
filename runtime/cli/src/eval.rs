//! `c5 eval`: JSON Lines of platform states in, everything the model gives out, one line each.

use crate::jsonl::{self, Key};
use crate::options::RobotArgs;
use c5_runtime::platform::Freedom;
use c5_runtime::{platform::Margin, Error, Limit, Mechanism};
use clap::Args;
use serde_json::{json, Value};
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
    /// Also write the inverse dynamics' exact Jacobians, n×n each, row `i` actuator `i`:
    /// `d_gamma_d_pose`, `d_gamma_d_twist`, `d_gamma_d_acceleration` (columns the platform's
    /// coordinates: α β γ xc yc zc; ωx ωy ωz vx vy vz; ω̇x ω̇y ω̇z ax ay az for six freedoms),
    /// or for lines of actuator values `d_gamma_d_q`, `d_gamma_d_qd`, `d_gamma_d_qdd`
    /// (columns the actuators; the C5's only). Mechanisms whose derivative kernels are
    /// generated: the C5, the Gough-Stewart platform and the Delta.
    #[arg(long, conflicts_with = "base_parameters")]
    derivatives: bool,
    /// Make a line whose pose, actuator speeds or forces break a limit of the robot file's
    /// `[limits]` an error naming the limit and the actuator (else `limits` reports the
    /// smallest margin).
    #[arg(long)]
    strict_limits: bool,
}

/// The keys of an `eval` line for a platform of `freedom`: its state (`pose`, the twist's and
/// the acceleration's parts), or the actuators' (`q`, `qd`, `qdd`), never both; and how many
/// of them describe the platform.
fn keys(freedom: Freedom) -> (Vec<Key>, usize) {
    let n = freedom.dimension();
    let mut keys = vec![Key::required("pose", n)];
    let parts = freedom
        .twist_parts()
        .iter()
        .chain(freedom.acceleration_parts());
    keys.extend(parts.map(|&part| Key::optional(part, 3)));
    let platform = keys.len();
    keys.extend([
        Key::required("q", n),
        Key::optional("qd", n),
        Key::optional("qdd", n),
    ]);
    (keys, platform)
}

/// What an `eval` line gives: the platform's pose, twist and acceleration, or the actuators'
/// positions, rates and accelerations, each in the freedom's coordinates.
enum Line {
    Platform([Vec<f64>; 3]),
    Actuators([Vec<f64>; 3]),
}

fn parse_line(line: &str, freedom: Freedom) -> Result<Line, String> {
    let (keys, platform_keys) = keys(freedom);
    let values = jsonl::parse_present(line, &keys)?;
    let given = |range: std::ops::Range<usize>| -> Vec<&str> {
        range
            .filter(|&k| values[k].is_some())
            .map(|k| keys[k].name)
            .collect()
    };
    let (platform, actuators) = (given(0..platform_keys), given(platform_keys..keys.len()));
    if !platform.is_empty() && !actuators.is_empty() {
        return Err(format!(
            "a line gives the platform's state or the actuators', not both: {} with {}",
            platform.join(", "),
            actuators.join(", ")
        ));
    }
    // The keys of the kind given: absent optional ones are zero, an absent required one is an
    // error (`pose` when the line gives neither kind).
    let kind = if actuators.is_empty() {
        0..platform_keys
    } else {
        platform_keys..keys.len()
    };
    let v = kind
        .map(|k| match &values[k] {
            Some(v) => Ok(v.clone()),
            None if keys[k].required => Err(format!("missing `{}`", keys[k].name)),
            None => Ok(vec![0.0; keys[k].len]),
        })
        .collect::<Result<Vec<_>, String>>()?;
    if !actuators.is_empty() {
        let [q, qd, qdd]: [Vec<f64>; 3] = v.try_into().map_err(|_| "three actuator keys")?;
        return Ok(Line::Actuators([q, qd, qdd]));
    }
    let twist = freedom.twist_parts().len();
    Ok(Line::Platform([
        v[0].clone(),
        v[1..1 + twist].concat(),
        v[1 + twist..].concat(),
    ]))
}

pub fn run(args: &EvalArgs) -> crate::Result<ExitCode> {
    let robot = args.robot.load_mechanism()?;
    if args.derivatives {
        crate::unbuilt::derivatives_of(robot.as_ref())?;
    }
    let estimate = args
        .base_parameters
        .as_ref()
        .map(|p| identified::load(robot.as_ref(), p))
        .transpose()?;
    eval(
        robot.as_ref(),
        estimate.as_ref(),
        args.derivatives,
        args.strict_limits,
    )
}

/// `q`, `qd`, `qdd`, `gamma`, `jinv` and `jacobian` of the platform's `motion`.
fn evaluate(robot: &dyn Mechanism, [x, v, a]: &[Vec<f64>; 3]) -> Result<Value, Error> {
    let n = robot.freedom().dimension();
    let e = robot.evaluate(x, v, a)?;
    Ok(json!({
        "q": e.q, "qd": e.qd, "qdd": e.qdd, "gamma": e.gamma,
        "jinv": jsonl::rows(&e.jinv, n), "jacobian": jsonl::rows(&e.jacobian, n),
    }))
}

/// `values` under the names of its three-number `parts`.
fn put_parts(out: &mut Value, parts: &[&str], values: &[f64]) {
    for (part, chunk) in parts.iter().zip(values.chunks(3)) {
        out[*part] = json!(chunk);
    }
}

/// The forces of identified parameters, where this build has identification.
#[cfg(feature = "identify")]
mod identified {
    pub use c5_runtime::identify::Estimate;

    pub fn load(
        robot: &dyn c5_runtime::Mechanism,
        path: &std::path::Path,
    ) -> crate::Result<Estimate> {
        crate::identify::load_estimate(robot, path)
    }

    pub fn forces(
        estimate: &Estimate,
        robot: &dyn c5_runtime::Mechanism,
        state: &c5_runtime::State,
    ) -> Result<Vec<f64>, String> {
        estimate.forces(robot, state).map_err(|e| e.to_string())
    }
}

/// Without identification: `--base-parameters` says which feature it needs.
#[cfg(not(feature = "identify"))]
mod identified {
    pub enum Estimate {}

    pub fn load(
        _robot: &dyn c5_runtime::Mechanism,
        _path: &std::path::Path,
    ) -> crate::Result<Estimate> {
        Err(crate::unbuilt::needs("`--base-parameters`", "identify"))
    }

    pub fn forces(
        estimate: &Estimate,
        _robot: &dyn c5_runtime::Mechanism,
        _state: &c5_runtime::State,
    ) -> Result<Vec<f64>, String> {
        match *estimate {}
    }
}

/// The inverse dynamics' three Jacobians (`n × n`, row-major), each under its key.
type KeyedJacobians = [(&'static str, Vec<f64>); 3];

/// The inverse dynamics' Jacobians of a line, under their keys: with respect to the
/// platform's state, or to the actuators' motion where the line gives it.
#[cfg(feature = "derivatives")]
fn derivative_keys(
    robot: &dyn Mechanism,
    [x, v, a]: &[Vec<f64>; 3],
    joints: Option<&[Vec<f64>; 3]>,
) -> Result<KeyedJacobians, String> {
    if let Some(joints) = joints {
        return joint_derivative_keys(robot, joints);
    }
    let n = x.len();
    let mut gamma = vec![0.0; n];
    let mut jacobians = [0; 3].map(|_| vec![0.0; n * n]);
    let [d_pose, d_twist, d_accel] = &mut jacobians;
    c5_runtime::derivatives::sliced_derivatives_of(robot)
        .and_then(|d| {
            d.inverse_dynamics_derivatives([x, v, a], &mut gamma, [d_pose, d_twist, d_accel])
        })
        .map_err(|e| e.to_string())?;
    let [d_pose, d_twist, d_accel] = jacobians;
    Ok([
        ("d_gamma_d_pose", d_pose),
        ("d_gamma_d_twist", d_twist),
        ("d_gamma_d_acceleration", d_accel),
    ])
}

/// The joint-space Jacobians, the C5's alone: only its forward kinematics has the closed form
/// these kernels derive.
#[cfg(feature = "derivatives")]
fn joint_derivative_keys(
    robot: &dyn Mechanism,
    [q, qd, qdd]: &[Vec<f64>; 3],
) -> Result<KeyedJacobians, String> {
    let c5 = robot
        .spatial()
        .and_then(|s| s.as_any().downcast_ref::<c5_runtime::C5>())
        .ok_or_else(|| {
            c5_runtime::Error::Unsupported {
                what: "joint-space derivatives",
                mechanism: robot.mechanism(),
                why: "its forward kinematics iterates; use the task-space derivatives with J⁻¹",
            }
            .to_string()
        })?;
    let actuators = |v: &[f64]| {
        v.try_into()
            .map_err(|_| "one value per actuator".to_string())
    };
    let d = c5
        .inverse_dynamics_joint_derivatives(&actuators(q)?, &actuators(qd)?, &actuators(qdd)?)
        .map_err(|e| e.to_string())?;
    Ok([
        ("d_gamma_d_q", d.d_q.as_flattened().to_vec()),
        ("d_gamma_d_qd", d.d_qd.as_flattened().to_vec()),
        ("d_gamma_d_qdd", d.d_qdd.as_flattened().to_vec()),
    ])
}

#[cfg(not(feature = "derivatives"))]
fn derivative_keys(
    _robot: &dyn Mechanism,
    _motion: &[Vec<f64>; 3],
    _joints: Option<&[Vec<f64>; 3]>,
) -> Result<KeyedJacobians, String> {
    Err(crate::unbuilt::needs("`--derivatives`", "derivatives").to_string())
}

/// The smallest margin of every limit the robot sets, at the pose and with the actuators'
/// speeds and forces: the limit, the actuator from 1, the margin and the value.
fn smallest_margin(
    robot: &dyn Mechanism,
    pose: &[f64],
    qd: &[f64],
    gamma: &[f64],
) -> Result<Option<Margin>, c5_runtime::Error> {
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

/// What `eval` adds to a line, as its options ask.
struct Extras<'a> {
    identified: Option<&'a identified::Estimate>,
    derivatives: bool,
    strict_limits: bool,
}

fn eval(
    robot: &dyn Mechanism,
    identified: Option<&identified::Estimate>,
    derivatives: bool,
    strict_limits: bool,
) -> crate::Result<ExitCode> {
    let freedom = robot.freedom();
    let extras = Extras {
        identified,
        derivatives,
        strict_limits,
    };
    jsonl::answer_lines(|line| {
        let (motion, joints) = match parse_line(line, freedom)? {
            Line::Platform(motion) => (motion, None),
            Line::Actuators(joints) => {
                let n = freedom.dimension();
                let mut motion = [0; 3].map(|_| vec![0.0; n]);
                let [x, v, a] = &mut motion;
                let given = [&joints[0][..], &joints[1], &joints[2]];
                robot
                    .joint_state(given, None, [x, v, a])
                    .map_err(|e| e.to_string())?;
                (motion, Some(joints))
            }
        };
        let mut out = evaluate(robot, &motion).map_err(|e| e.to_string())?;
        if let Some([q, qd, qdd]) = &joints {
            // The actuators' values as given, and the platform state they give, in the input
            // keys' conventions.
            out["q"] = json!(q);
            out["qd"] = json!(qd);
            out["qdd"] = json!(qdd);
            out["pose"] = json!(motion[0]);
            put_parts(&mut out, freedom.twist_parts(), &motion[1]);
            put_parts(&mut out, freedom.acceleration_parts(), &motion[2]);
        }
        if let Some([q, qd, qdd]) = &joints {
            // The forces of the joint-space call, what a controller calls, from the pose found.
            let mut gamma = vec![0.0; q.len()];
            robot
                .inverse_dynamics_joint([q, qd, qdd], Some(&motion[0]), &mut gamma)
                .map_err(|e| e.to_string())?;
            out["gamma"] = json!(gamma);
        }
        if extras.derivatives {
            let n = freedom.dimension();
            for (key, jacobian) in derivative_keys(robot, &motion, joints.as_ref())? {
                out[key] = json!(jsonl::rows(&jacobian, n));
            }
        }
        if let Some(estimate) = extras.identified {
            let state = robot
                .state_of([&motion[0], &motion[1], &motion[2]])
                .map_err(|e| e.to_string())?;
            out["gamma"] = json!(identified::forces(estimate, robot, &state)?);
        }
        if robot.has_limits() {
            add_limits(robot, &motion[0], extras.strict_limits, &mut out)?;
        }
        Ok(out)
    })
}

/// The smallest margin of the robot's limits at the line's pose, speeds and forces, as the
/// line's `limits` key; refused where negative with `--strict-limits`.
fn add_limits(
    robot: &dyn Mechanism,
    pose: &[f64],
    strict_limits: bool,
    out: &mut Value,
) -> Result<(), String> {
    let read = |key: &str| -> Result<Vec<f64>, String> {
        serde_json::from_value(out[key].clone()).map_err(|e| e.to_string())
    };
    let (qd, gamma) = (read("qd")?, read("gamma")?);
    let smallest = smallest_margin(robot, pose, &qd, &gamma).map_err(|e| e.to_string())?;
    if let Some((limit, actuator, margin, value)) = smallest {
        if strict_limits && margin < 0.0 {
            let e = Error::Limit {
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
    Ok(())
}
