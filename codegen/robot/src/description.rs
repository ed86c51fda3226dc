//! A robot file names its mechanism: a C5 joint parallel robot (the default, for files without
//! the line) or a Gough-Stewart platform.

#[cfg(feature = "toml")]
use crate::Error;
use crate::{GoughStewart, Robot};
#[cfg(feature = "toml")]
use alloc::format;
#[cfg(feature = "toml")]
use alloc::string::ToString;

/// The `mechanism` of a Gough-Stewart file.
pub const GOUGH_STEWART: &str = "gough-stewart";
/// The `mechanism` of a C5 file (the default).
pub const C5: &str = "c5";

/// A robot of one of the mechanisms the project knows.
// The variants stay inline: a description is built once and read, never moved in a loop.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Description {
    /// A C5 joint parallel robot.
    C5(Robot),
    /// A Gough-Stewart platform (6-UPS).
    GoughStewart(GoughStewart),
}

impl Default for Description {
    /// The chapter's C5 robot.
    fn default() -> Self {
        Description::C5(Robot::default())
    }
}

impl Description {
    /// The mechanism's name as a file spells it.
    pub fn mechanism(&self) -> &'static str {
        match self {
            Description::C5(_) => C5,
            Description::GoughStewart(_) => GOUGH_STEWART,
        }
    }

    /// A line on the robot, for generated files' headers.
    pub fn summary(&self) -> alloc::string::String {
        match self {
            Description::C5(r) => alloc::format!(
                "a C5 robot, half_spacing {} m, platform mass {} kg",
                r.half_spacing,
                r.platform.mass
            ),
            Description::GoughStewart(r) => alloc::format!(
                "a Gough-Stewart platform, platform mass {} kg",
                r.platform.mass
            ),
        }
    }

    /// Checks every rule of the mechanism's description.
    ///
    /// # Errors
    /// `Error::Invalid` naming the field.
    pub fn validate(&self) -> Result<(), crate::Error> {
        match self {
            Description::C5(r) => r.validate(),
            Description::GoughStewart(r) => r.validate(),
        }
    }

    /// Reads a robot file: its `mechanism` line chooses the description
    /// (`"gough-stewart"`, or `"c5"`, the default when the line is absent).
    ///
    /// # Errors
    /// [`Error::File`] naming the source and what is wrong, an unknown mechanism among them.
    #[cfg(feature = "toml")]
    pub fn from_toml(text: &str, source: &str) -> Result<Self, Error> {
        let table: toml::Table = toml::from_str(text).map_err(|e| Error::File {
            source: source.to_string(),
            message: e.to_string(),
        })?;
        match table.get("mechanism") {
            None => Robot::from_toml(text, source).map(Description::C5),
            Some(toml::Value::String(m)) if m == GOUGH_STEWART => {
                GoughStewart::from_toml(text, source).map(Description::GoughStewart)
            }
            Some(toml::Value::String(m)) if m == C5 => {
                let mut table = table;
                table.remove("mechanism");
                let text = toml::to_string(&table).map_err(|e| Error::File {
                    source: source.to_string(),
                    message: e.to_string(),
                })?;
                Robot::from_toml(&text, source).map(Description::C5)
            }
            Some(other) => Err(Error::File {
                source: source.to_string(),
                message: format!(
                    "unknown `mechanism` {other} (choose \"{C5}\", the default, or \
                     \"{GOUGH_STEWART}\")"
                ),
            }),
        }
    }

    /// Reads [`Description::from_toml`] from a file.
    ///
    /// # Errors
    /// [`Error::Io`], or as [`Description::from_toml`].
    #[cfg(feature = "toml")]
    pub fn from_toml_file(path: &std::path::Path) -> Result<Self, Error> {
        let text = std::fs::read_to_string(path).map_err(|error| Error::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Self::from_toml(&text, &path.display().to_string())
    }

    /// The description as a robot file.
    #[cfg(feature = "toml")]
    pub fn to_toml(&self) -> alloc::string::String {
        match self {
            Description::C5(r) => r.to_toml(),
            Description::GoughStewart(r) => r.to_toml(),
        }
    }

    /// The parameter vector of the mechanism's `*_params` kernels.
    pub fn kernel_parameters(&self) -> alloc::vec::Vec<f64> {
        match self {
            Description::C5(r) => r.kernel_parameters(),
            Description::GoughStewart(r) => r.kernel_parameters(),
        }
    }
}

#[cfg(all(test, feature = "toml"))]
mod tests {
    use super::*;

    #[test]
    fn the_mechanism_line_chooses_the_description() {
        let c5 = Description::from_toml("half_spacing = 0.25", "a.toml").unwrap();
        assert!(matches!(c5, Description::C5(r) if r.half_spacing == 0.25));
        let named = Description::from_toml("mechanism = \"c5\"\nhalf_spacing = 0.3", "b.toml");
        assert!(matches!(named.unwrap(), Description::C5(r) if r.half_spacing == 0.3));
        let e = Description::from_toml("mechanism = \"delta\"", "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("c.toml: unknown `mechanism` \"delta\""),
            "{e}"
        );
    }
}
