//! A robot file names its mechanism: a C5 joint parallel robot (the default, for files without
//! the line), a Gough-Stewart platform, a rotary hexapod or a Delta.

#[cfg(feature = "toml")]
use crate::Error;
use crate::{Delta, GoughStewart, Robot, RusHexapod};
#[cfg(feature = "toml")]
use alloc::format;
#[cfg(feature = "toml")]
use alloc::string::ToString;

/// The `mechanism` of a Gough-Stewart file.
pub const GOUGH_STEWART: &str = "gough-stewart";
/// The `mechanism` of a C5 file (the default).
pub const C5: &str = "c5";
/// The `mechanism` of a rotary hexapod's file.
pub const RUS_HEXAPOD: &str = "rus-hexapod";
/// The `mechanism` of a Delta's file.
pub const DELTA: &str = "delta";

/// A robot of one of the mechanisms the project knows.
// The variants stay inline: a description is built once and read, never moved in a loop.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Description {
    /// A C5 joint parallel robot.
    C5(Robot),
    /// A Gough-Stewart platform (6-UPS).
    GoughStewart(GoughStewart),
    /// A rotary hexapod (6-RUS).
    RusHexapod(RusHexapod),
    /// A Delta (3 translations).
    Delta(Delta),
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
            Description::RusHexapod(_) => RUS_HEXAPOD,
            Description::Delta(_) => DELTA,
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
            Description::RusHexapod(r) => {
                alloc::format!("a rotary hexapod, platform mass {} kg", r.platform.mass)
            }
            Description::Delta(r) => {
                alloc::format!("a Delta, platform mass {} kg", r.platform.mass)
            }
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
            Description::RusHexapod(r) => r.validate(),
            Description::Delta(r) => r.validate(),
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
            Some(toml::Value::String(m)) if m == RUS_HEXAPOD => {
                RusHexapod::from_toml(text, source).map(Description::RusHexapod)
            }
            Some(toml::Value::String(m)) if m == DELTA => {
                Delta::from_toml(text, source).map(Description::Delta)
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
                    "unknown `mechanism` {other} (choose \"{C5}\", the default, \
                     \"{GOUGH_STEWART}\", \"{RUS_HEXAPOD}\" or \"{DELTA}\")"
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
            Description::RusHexapod(r) => r.to_toml(),
            Description::Delta(r) => r.to_toml(),
        }
    }

    /// The parameter vector of the mechanism's `*_params` kernels.
    pub fn kernel_parameters(&self) -> alloc::vec::Vec<f64> {
        match self {
            Description::C5(r) => r.kernel_parameters(),
            Description::GoughStewart(r) => r.kernel_parameters(),
            Description::RusHexapod(r) => r.kernel_parameters(),
            Description::Delta(r) => r.kernel_parameters(),
        }
    }
}

/// Reads a description of `mechanism` from TOML: the `mechanism` line checked and dropped, the
/// rest deserialised (unknown fields refused).
#[cfg(feature = "toml")]
pub(crate) fn read_toml<T: serde::de::DeserializeOwned>(
    text: &str,
    source: &str,
    mechanism: &str,
) -> Result<T, Error> {
    let file_error = |message: alloc::string::String| Error::File {
        source: source.to_string(),
        message,
    };
    let mut table: toml::Table = toml::from_str(text).map_err(|e| file_error(e.to_string()))?;
    match table.remove("mechanism") {
        Some(toml::Value::String(s)) if s == mechanism => {}
        other => {
            return Err(file_error(format!(
                "`mechanism` must be \"{mechanism}\", got {other:?}"
            )))
        }
    }
    toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| file_error(e.to_string()))
}

/// A description as TOML with its `mechanism` line first.
#[cfg(feature = "toml")]
pub(crate) fn write_toml<T: serde::Serialize>(robot: &T, mechanism: &str) -> alloc::string::String {
    let body = toml::to_string(robot).expect("a description of finite numbers serialises");
    format!("mechanism = \"{mechanism}\"\n{body}")
}

/// A serde module for `[T; N]` read from a list of exactly `N` tables, refusing another count
/// with a message that names it (`what`: "six [[legs]]").
#[cfg(feature = "serde")]
#[macro_export]
#[doc(hidden)]
macro_rules! counted_list {
    ($item:ty, $n:expr, $what:expr) => {
        use super::*;
        use alloc::vec::Vec;
        use serde::{Deserialize, Deserializer, Serialize, Serializer};

        pub fn serialize<S: Serializer>(items: &[$item; $n], s: S) -> Result<S::Ok, S::Error> {
            items.as_slice().serialize(s)
        }

        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[$item; $n], D::Error> {
            let items = Vec::<$item>::deserialize(d)?;
            let n = items.len();
            items.try_into().map_err(|_| {
                serde::de::Error::custom(alloc::format!(
                    "must hold exactly {}, in actuator order; the file gives {n}",
                    $what
                ))
            })
        }
    };
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
        let e = Description::from_toml("mechanism = \"scara\"", "c.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("c.toml: unknown `mechanism` \"scara\"") && e.contains("\"delta\""),
            "{e}"
        );
        let e = Description::from_toml("mechanism = \"delta\"", "d.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("d.toml: missing field"), "{e}");
    }
}

#[cfg(all(test, feature = "toml"))]
mod new_mechanisms {
    use super::*;

    fn docs(name: &str) -> String {
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../docs/{name}")),
        )
        .unwrap()
    }

    #[test]
    fn the_rotary_hexapod_and_the_delta_read_and_write_their_files() {
        for name in ["rus-hexapod.toml", "delta.toml"] {
            let robot = Description::from_toml(&docs(name), name).unwrap();
            let again = Description::from_toml(&robot.to_toml(), "written").unwrap();
            assert_eq!(robot, again, "{name}");
            assert_eq!(robot.mechanism(), name.trim_end_matches(".toml"));
        }
    }

    #[test]
    fn a_given_home_is_the_home_and_one_out_of_reach_is_refused_by_leg() {
        let text =
            docs("delta.toml").replacen("[platform]", "home = [0.0, 0.0, -0.4]\n[platform]", 1);
        let Description::Delta(delta) = Description::from_toml(&text, "home.toml").unwrap() else {
            panic!("a Delta");
        };
        assert_eq!(delta.home(), Some([0.0, 0.0, -0.4]));
        assert!(delta.actuator_angles(&[0.0, 0.0, -0.4]).is_ok());
        let far =
            docs("delta.toml").replacen("[platform]", "home = [0.0, 0.0, -2.0]\n[platform]", 1);
        let err = Description::from_toml(&far, "far.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`arms[1]` cannot reach its ball") && err.contains("at home"),
            "{err}"
        );
    }
}
