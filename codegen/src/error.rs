//! Errors of the generator.

use std::fmt;
use std::path::PathBuf;

/// What can go wrong while generating kernels.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The robot description breaks a rule (a non-positive mass, a non-finite value, ...).
    InvalidRobot { field: String, rule: String },
    /// A robot description file is malformed or describes an invalid robot.
    RobotFile { source: String, message: String },
    /// A model produced something the engine cannot emit.
    InvalidModel { kernel: String, reason: String },
    /// `OUT_DIR` is not set and no output directory was given.
    NoOutDir,
    /// Reading or writing a file failed.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The emitted tokens did not parse as Rust (a bug in the emitter).
    Emit { kernel: String, message: String },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidRobot { field, rule } => write!(f, "invalid robot: `{field}` {rule}"),
            Error::RobotFile { source, message } => write!(f, "{source}: {message}"),
            Error::InvalidModel { kernel, reason } => {
                write!(f, "kernel `{kernel}` cannot be generated: {reason}")
            }
            Error::NoOutDir => write!(f, "OUT_DIR is not set; call Config::out_dir"),
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Emit { kernel, message } => {
                write!(f, "emitted code for `{kernel}` does not parse: {message}")
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}
