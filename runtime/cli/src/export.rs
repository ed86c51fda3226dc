//! `c5 export`: the robot as MJCF (MuJoCo; Pinocchio with its loop closures) or URDF (ROS),
//! for every mechanism (docs/export.md).

use crate::options::RobotArgs;
use c5_robot::Format;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// Writes the robot as MJCF or URDF: the platform as the root body, each leg hanging from it,
/// its loop closed on the base by a weld (MJCF) or a `<constraint>` (URDF), every body at the
/// home pose with its mass and inertia, one motor per actuator
#[derive(Args, Debug)]
pub struct ExportArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// The format.
    #[arg(long, default_value = "mjcf", value_parser = format_parser())]
    format: Format,
    /// The file to write [default: standard output].
    #[arg(long)]
    out: Option<PathBuf>,
}

fn format_parser() -> impl TypedValueParser<Value = Format> {
    PossibleValuesParser::new(Format::ALL.map(Format::name))
        .map(|name| name.parse::<Format>().expect("one of the possible values"))
}

/// Loads the robot as every command does (so a file `eval` refuses is refused here with the
/// same message) and writes it; nothing is written on an error.
pub fn run(args: &ExportArgs) -> crate::Result<ExitCode> {
    // The runtime's checks too (a home pose the legs cannot hold, say), as `eval`'s.
    let robot = args.robot.load_any()?;
    if robot.model_name() == c5_runtime::Model::Paper.name() {
        return Err(
            "the paper model is the chapter's equations, not a mechanism: it has no \
                    bodies and joints to export (export the consistent model, the default)"
                .into(),
        );
    }
    let text = robot.description().export(args.format)?;
    match &args.out {
        Some(path) => std::fs::write(path, text)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?,
        None => std::io::stdout().lock().write_all(text.as_bytes())?,
    }
    Ok(ExitCode::SUCCESS)
}
