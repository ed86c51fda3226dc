//! The options several commands share, declared once: the robot and its model.

use c5_runtime::{Model, Robot, C5};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use std::path::PathBuf;

/// The robot description and the model of the legs' mechanism.
#[derive(Args, Clone, Debug)]
pub struct RobotArgs {
    /// A robot description (TOML) instead of the chapter's robot.
    #[arg(long)]
    pub robot: Option<PathBuf>,
    /// The model of the legs' mechanism the results follow.
    #[arg(long, default_value = "consistent", value_parser = model_parser())]
    pub model: Model,
}

impl RobotArgs {
    /// The robot of `--robot` (or the chapter's) with the model of `--model`.
    pub fn load(&self) -> crate::Result<C5> {
        load(self.robot.as_ref(), self.model)
    }
}

/// Parses a model's name, listing the names in `--help`.
pub fn model_parser() -> impl TypedValueParser<Value = Model> {
    PossibleValuesParser::new(Model::ALL.map(Model::name))
        .map(|name| name.parse::<Model>().expect("one of the possible values"))
}

/// The robot of `path` (or the chapter's) with `model`.
pub fn load(path: Option<&PathBuf>, model: Model) -> crate::Result<C5> {
    let robot = match path {
        Some(p) => Robot::from_toml_file(p)?,
        None => Robot::default(),
    };
    Ok(C5::with_model(robot, model)?)
}

/// The sample times of a default trajectory of `duration` at `rate`, or why not.
pub fn sample_times(duration: f64, rate: f64, what: &str) -> crate::Result<Vec<f64>> {
    c5_runtime::trajectory::sample_times(duration, rate, crate::MAX_SAMPLES).map_err(|n| {
        if n == usize::MAX {
            format!("--rate must be a positive number, got {rate}").into()
        } else {
            format!(
                "--rate {rate} would take {n} {what} of the {duration} s move (at most {})",
                crate::MAX_SAMPLES
            )
            .into()
        }
    })
}
