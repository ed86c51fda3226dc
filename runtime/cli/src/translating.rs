//! `c5 eval` and `c5 forward` for a platform that only translates (the Delta): its lines
//! carry three-element states, `pose` `[xc yc zc]`, `velocity` `v_C`, `acceleration` `a_C`, and
//! three actuators (docs/mechanisms.md).

use crate::jsonl::{self, Key};
use c5_runtime::delta::Translation;
use c5_runtime::Delta;
use serde_json::json;
use std::process::ExitCode;

/// The keys of an `eval` line: the platform's state, or the motors' (`q`, `qd`, `qdd`), never
/// both.
const EVAL_KEYS: [Key; 6] = [
    Key::required("pose", 3),
    Key::optional("velocity", 3),
    Key::optional("acceleration", 3),
    Key::required("q", 3),
    Key::optional("qd", 3),
    Key::optional("qdd", 3),
];

/// The keys of a `forward` line.
const FORWARD_KEYS: [Key; 3] = [
    Key::required("pose", 3),
    Key::optional("velocity", 3),
    Key::required("gamma", 3),
];

fn three(v: &[f64]) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

/// The motors' angles, rates and accelerations.
type Motors = [[f64; 3]; 3];

/// The state of an `eval` line, and the motors' values when the line gives them.
fn state_of(robot: &Delta, line: &str) -> Result<(Translation, Option<Motors>), String> {
    let values = jsonl::parse_present(line, &EVAL_KEYS)?;
    let present = |range: std::ops::Range<usize>| range.filter(|&k| values[k].is_some());
    let (platform, motors): (Vec<_>, Vec<_>) = (present(0..3).collect(), present(3..6).collect());
    if !platform.is_empty() && !motors.is_empty() {
        return Err(format!(
            "a line gives the platform's state or the motors', not both: {} with {}",
            EVAL_KEYS[platform[0]].name, EVAL_KEYS[motors[0]].name
        ));
    }
    let first = if motors.is_empty() { 0 } else { 3 };
    let v = (first..first + 3)
        .map(|k| match &values[k] {
            Some(v) => Ok(three(v)),
            None if EVAL_KEYS[k].required => Err(format!("missing `{}`", EVAL_KEYS[k].name)),
            None => Ok([0.0; 3]),
        })
        .collect::<Result<Vec<_>, String>>()?;
    if motors.is_empty() {
        let state = Translation {
            position: v[0],
            velocity: v[1],
            acceleration: v[2],
        };
        return Ok((state, None));
    }
    let state = robot
        .joint_state(&v[0], &v[1], &v[2])
        .map_err(|e| e.to_string())?;
    Ok((state, Some([v[0], v[1], v[2]])))
}

/// `c5 eval`: one line of `q`, `qd`, `qdd`, `gamma`, `jinv` and `jacobian` per state; a line
/// of the motors' values also gets the platform's state they give.
pub fn eval(robot: &Delta) -> crate::Result<ExitCode> {
    jsonl::answer_lines(|line| {
        let (state, motors) = state_of(robot, line)?;
        let e = robot.evaluate(&state).map_err(|e| e.to_string())?;
        let mut out = serde_json::to_value(e).map_err(|e| e.to_string())?;
        if let Some([q, qd, qdd]) = motors {
            out["q"] = json!(q);
            out["qd"] = json!(qd);
            out["qdd"] = json!(qdd);
            out["pose"] = json!(state.position);
            out["velocity"] = json!(state.velocity);
            out["acceleration"] = json!(state.acceleration);
        }
        Ok(out)
    })
}

/// `c5 forward`: the platform's `acceleration` under the motors' torques.
pub fn forward(robot: &Delta) -> crate::Result<ExitCode> {
    jsonl::answer_lines(|line| {
        let v = jsonl::parse(line, &FORWARD_KEYS)?;
        let a = robot
            .forward_dynamics(&three(&v[0]), &three(&v[1]), &three(&v[2]))
            .map_err(|e| e.to_string())?;
        Ok(json!({ "acceleration": a }))
    })
}
