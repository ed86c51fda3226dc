//! `c5 export`: the robot as MJCF (MuJoCo; Pinocchio with its loop closures) or URDF (ROS),
//! for every mechanism (docs/export.md).

use crate::options::RobotArgs;
use c5_robot::{Description, Format};
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

/// Reads the robot as every command does (so a file `eval` refuses for its robot is refused
/// here with the same message), and writes it; nothing is written on an error. The Delta,
/// which the commands of six freedoms do not serve, is exported all the same: its description
/// is checked.
pub fn run(args: &ExportArgs) -> crate::Result<ExitCode> {
    let description = match &args.robot.robot {
        Some(path) => Description::from_toml_file(path)?,
        None => Description::default(),
    };
    let text = c5_runtime::mechanism::export(&description, args.robot.model, args.format)?;
    match &args.out {
        Some(path) => std::fs::write(path, text)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?,
        None => std::io::stdout().lock().write_all(text.as_bytes())?,
    }
    Ok(ExitCode::SUCCESS)
}
