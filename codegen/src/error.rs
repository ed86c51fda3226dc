//! Errors of the generator.

use std::fmt;
use std::path::PathBuf;

/// What can go wrong while generating kernels.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The robot description breaks a rule, or a description file is malformed.
    Robot(c5_robot::Error),
    /// A name given to [`crate::ParameterSet::Named`] is not a parameter of
    /// [`crate::Robot::kernel_parameter_names`].
    UnknownParameter { name: String },
    /// A name given twice to [`crate::ParameterSet::Named`].
    DuplicateParameter { name: String },
    /// A model produced something the engine cannot emit.
    InvalidModel { kernel: String, reason: String },
    /// A kernel's self-check failed: its program does not compute what its model says (a bug).
    SelfCheck { kernel: String, check: String },
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
            Error::Robot(e) => write!(f, "{e}"),
            Error::UnknownParameter { name } => write!(
                f,
                "unknown parameter `{name}` (the names are those of Robot::kernel_parameter_names, \
                 e.g. `platform_mass`, `gravity_z`)"
            ),
            Error::DuplicateParameter { name } => {
                write!(f, "parameter `{name}` is named twice")
            }
            Error::InvalidModel { kernel, reason } => {
                write!(f, "kernel `{kernel}` cannot be generated: {reason}")
            }
            Error::SelfCheck { kernel, check } => {
                write!(f, "kernel `{kernel}` fails its self-check: {check}")
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
            Error::Robot(e) => Some(e),
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<c5_robot::Error> for Error {
    fn from(e: c5_robot::Error) -> Self {
        Error::Robot(e)
    }
}
