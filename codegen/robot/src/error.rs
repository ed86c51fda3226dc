//! Why a robot description or a model name was refused.

use alloc::string::String;
use core::fmt;

/// Why a robot description or a model name was refused.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// A parameter breaks a rule a physical robot obeys; `field` names it as the description
    /// spells it (`segments[3].joint.inertia`).
    Invalid { field: String, rule: String },
    /// A description file is malformed or describes an invalid robot; `source` names the file.
    File { source: String, message: String },
    /// A description file could not be read.
    #[cfg(feature = "std")]
    Io {
        path: std::path::PathBuf,
        error: std::io::Error,
    },
    /// A model name that is not one of [`crate::Model::ALL`].
    UnknownModel { given: String },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Invalid { field, rule } => write!(f, "invalid robot: `{field}` {rule}"),
            Error::File { source, message } => write!(f, "{source}: {message}"),
            #[cfg(feature = "std")]
            Error::Io { path, error } => write!(f, "{}: {error}", path.display()),
            Error::UnknownModel { given } => {
                write!(f, "unknown model `{given}` (choose one of: ")?;
                for (k, m) in crate::Model::ALL.iter().enumerate() {
                    if k > 0 {
                        f.write_str(", ")?;
                    }
                    f.write_str(m.name())?;
                }
                f.write_str(")")
            }
        }
    }
}

impl core::error::Error for Error {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            #[cfg(feature = "std")]
            Error::Io { error, .. } => Some(error),
            _ => None,
        }
    }
}
