//! `c5`: the Section 9 study, JSON Lines evaluation, forward dynamics and tracking,
//! identification, calibration, the workspace, the 3D view, the operation-count audit and the
//! export to MJCF and URDF; one
//! module per command. The program (`src/main.rs`) calls [`main`].
//!
//! The commands live in this library rather than in the binary so that the package's tests
//! can depend on the package with every command built in
//! (`[dev-dependencies] c5-cli = { path = ".", features = ["full"] }`): a plain build leaves
//! the identification and derivative kernels out (docs/build-time.md).

mod audit;
mod calibrate;
mod columns;
#[cfg(feature = "identify")]
mod encoder_log;
mod eval;
#[cfg(feature = "identify")]
mod excite;
mod export;
mod forward;
mod held;
#[cfg(feature = "identify")]
mod identify;
mod jsonl;
mod options;
#[cfg(feature = "derivatives")]
mod plan;
mod png_figure;
mod simulate;
mod track;
mod trajectory_csv;
mod unbuilt;
mod view;
mod workspace;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// The most samples `simulate` evaluates (about 2.5 GB of results).
const MAX_SAMPLES: usize = 10_000_000;

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

#[derive(Parser)]
#[command(
    name = "c5",
    version,
    about = "Kinematics and dynamics of parallel robots: the C5 joint parallel robot (the \
             chapter's, the default), and from a robot file (`--robot`) the Gough-Stewart \
             platform, the rotary hexapod (6-RUS) and the Delta (`eval`, `forward`, \
             `simulate`, `track`, `workspace`, `view`, `audit`, `export`)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Simulate(simulate::SimulateArgs),
    Eval(eval::EvalArgs),
    #[cfg(feature = "identify")]
    Identify(identify::IdentifyArgs),
    /// Identification [not in this build: the `identify` feature].
    #[cfg(not(feature = "identify"))]
    Identify(unbuilt::UnbuiltArgs),
    #[cfg(feature = "identify")]
    Excite(excite::ExciteArgs),
    /// An exciting trajectory for identification [not in this build: the `identify` feature].
    #[cfg(not(feature = "identify"))]
    Excite(unbuilt::UnbuiltArgs),
    Forward(forward::ForwardArgs),
    Track(track::TrackArgs),
    #[cfg(feature = "derivatives")]
    Plan(plan::PlanArgs),
    /// A minimum-effort move by iLQR [not in this build: the `derivatives` feature].
    #[cfg(not(feature = "derivatives"))]
    Plan(unbuilt::UnbuiltArgs),
    Workspace(workspace::WorkspaceArgs),
    Audit(audit::AuditArgs),
    Calibrate(calibrate::CalibrateArgs),
    View(view::ViewArgs),
    Export(export::ExportArgs),
}

/// Whether `e` is a write to a closed pipe (`c5 eval | head -1`): the reader has all it
/// wants, so the run ends quietly and successfully.
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    let pipe = Some(std::io::ErrorKind::BrokenPipe);
    let mut source = Some(e);
    while let Some(err) = source {
        // serde_json's error hides its I/O error from `source()`, but tells its kind.
        let kind = err
            .downcast_ref::<std::io::Error>()
            .map(std::io::Error::kind)
            .or_else(|| {
                err.downcast_ref::<serde_json::Error>()
                    .and_then(serde_json::Error::io_error_kind)
            });
        if kind == pipe {
            return true;
        }
        source = err.source();
    }
    false
}

/// Runs the command of the process's arguments; prints its error, if any, and says how it went.
pub fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Simulate(args) => simulate::run_cmd(&args),
        Command::Eval(args) => eval::run(&args),
        #[cfg(feature = "identify")]
        Command::Identify(args) => identify::run(&args),
        #[cfg(feature = "identify")]
        Command::Excite(args) => excite::run(&args),
        #[cfg(not(feature = "identify"))]
        Command::Identify(_) => Err(unbuilt::needs("`c5 identify`", "identify")),
        #[cfg(not(feature = "identify"))]
        Command::Excite(_) => Err(unbuilt::needs("`c5 excite`", "identify")),
        Command::Forward(args) => forward::run(&args),
        Command::Track(args) => track::run_cmd(&args),
        #[cfg(feature = "derivatives")]
        Command::Plan(args) => plan::run(&args),
        #[cfg(not(feature = "derivatives"))]
        Command::Plan(_) => Err(unbuilt::needs("`c5 plan`", "derivatives")),
        Command::Workspace(args) => workspace::run(&args),
        Command::Audit(args) => audit::run(&args),
        Command::Calibrate(args) => calibrate::run(&args),
        Command::View(args) => view::run(&args),
        Command::Export(args) => export::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) if is_broken_pipe(e.as_ref()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
