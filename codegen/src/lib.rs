//! Symbolic expansion of the C5 joint parallel robot's equations into straight-line,
//! operation-counted Rust kernels.
//!
//! Data flows one way: the [`model`] writes the chapter's equations over [`Expr`] (a
//! hash-consed, self-simplifying [`dag`]); [`lower`] factors and schedules the DAG into a counted
//! [`lower::Program`]; [`emit`] prints it as Rust with `quote` and `prettyplease`.
//!
//! # Example
//!
//! A crate with its own robot calls the generator from `build.rs`:
//!
//! ```no_run
//! // build.rs
//! fn main() -> Result<(), Box<dyn std::error::Error>> {
//!     let mut robot = c5_codegen::Robot::default();
//!     robot.half_spacing = 0.25;
//!     robot.platform.mass = 12.0;
//!     c5_codegen::Config::new().robot(robot).generate()?;
//!     Ok(())
//! }
//! ```
//!
//! and pulls the kernels in:
//!
//! ```ignore
//! // src/lib.rs
//! #[rustfmt::skip]
//! #[allow(clippy::all, unused_parens)]
//! pub mod kernels {
//!     include!(concat!(env!("OUT_DIR"), "/c5_kernels.rs"));
//! }
//! ```

pub mod count;
pub mod dag;
pub mod emit;
pub mod error;
pub mod kernel;
pub mod linalg;
pub mod lower;
pub mod manifest;
pub mod model;
pub mod robot;
mod write;

pub use count::OpCount;
pub use dag::{Expr, Graph};
pub use emit::Scalar;
pub use error::Error;
pub use kernel::{Compiled, KernelSpec};
pub use model::ParameterSet;
pub use robot::Robot;

use std::path::{Path, PathBuf};

/// The command that regenerates the checked-in kernels.
pub const REGENERATE: &str = "cargo run -p c5-codegen -- generate";

/// Configuration of a generation, in the manner of `prost_build::Config`.
#[derive(Clone, Debug)]
pub struct Config {
    robot: Robot,
    parameters: ParameterSet,
    scalar: Scalar,
    chapter_kernels: bool,
    out_dir: Option<PathBuf>,
    file_name: String,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            robot: Robot::default(),
            parameters: ParameterSet::None,
            scalar: Scalar::F64,
            chapter_kernels: false,
            out_dir: None,
            file_name: "c5_kernels.rs".to_string(),
        }
    }
}

impl Config {
    pub fn new() -> Self {
        Self::default()
    }

    /// The robot whose parameters are folded in. Default: the chapter's robot.
    pub fn robot(&mut self, robot: Robot) -> &mut Self {
        self.robot = robot;
        self
    }

    /// Which parameters stay kernel inputs. Default: [`ParameterSet::None`] (all folded).
    pub fn runtime_parameters(&mut self, parameters: ParameterSet) -> &mut Self {
        self.parameters = parameters;
        self
    }

    /// Floating-point type of the kernels. Default: `f64`.
    pub fn scalar(&mut self, scalar: Scalar) -> &mut Self {
        self.scalar = scalar;
        self
    }

    /// Also emit the chapter-setting kernels (`P_i2` as inputs). Default: `false`.
    pub fn chapter_kernels(&mut self, yes: bool) -> &mut Self {
        self.chapter_kernels = yes;
        self
    }

    /// Output directory. Default: the `OUT_DIR` of the build script.
    pub fn out_dir(&mut self, dir: impl Into<PathBuf>) -> &mut Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// Name of the generated file. Default: `c5_kernels.rs`.
    pub fn file_name(&mut self, name: &str) -> &mut Self {
        self.file_name = name.to_string();
        self
    }

    fn specs(&self) -> Result<Vec<KernelSpec>, Error> {
        self.robot.validate()?;
        let names = Robot::<f64>::parameter_names();
        if let ParameterSet::Named(chosen) = &self.parameters {
            if let Some(unknown) = chosen.iter().find(|c| !names.contains(c)) {
                return Err(Error::InvalidRobot {
                    field: unknown.clone(),
                    rule: "is not a parameter name".to_string(),
                });
            }
        }
        let mut specs = Vec::new();
        if self.chapter_kernels {
            specs.extend(model::chapter_kernels());
        }
        specs.extend(model::pose_kernels(&self.robot, &self.parameters, ""));
        specs.extend(model::divisor_kernels());
        Ok(specs)
    }

    /// Generates the kernels and returns the file's contents.
    ///
    /// # Errors
    /// An invalid robot, an unknown parameter name, or a model the engine cannot emit.
    pub fn generate_to_string(&self) -> Result<String, Error> {
        let specs = self.specs()?;
        let compiled = specs
            .iter()
            .map(|s| s.compile())
            .collect::<Result<Vec<_>, _>>()?;
        let pairs: Vec<_> = specs.iter().zip(&compiled).collect();
        let header = manifest::header(&pairs, "by the c5-codegen build API");
        emit::emit_file(&header, &pairs, self.scalar)
    }

    /// Generates the kernels into `out_dir/file_name`, rewriting the file only when it changed.
    ///
    /// # Errors
    /// As [`Config::generate_to_string`], plus [`Error::NoOutDir`] and [`Error::Io`].
    pub fn generate(&self) -> Result<(), Error> {
        let dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => PathBuf::from(std::env::var_os("OUT_DIR").ok_or(Error::NoOutDir)?),
        };
        let code = self.generate_to_string()?;
        write::write_if_changed(&dir.join(&self.file_name), &code)
    }
}

/// Generates the kernels of the default robot with default settings into `OUT_DIR`.
///
/// # Errors
/// As [`Config::generate`].
pub fn generate() -> Result<(), Error> {
    Config::new().generate()
}

/// The files of the checked-in `generated/` crate, relative to it, with their contents.
///
/// # Errors
/// A model the engine cannot emit (a bug).
pub fn generated_crate_files() -> Result<Vec<(PathBuf, String)>, Error> {
    let robot = Robot::default();
    let mut specs = model::chapter_kernels();
    specs.extend(model::pose_kernels(&robot, &ParameterSet::None, ""));
    specs.extend(model::pose_kernels(&robot, &ParameterSet::All, "_params"));
    specs.extend(model::divisor_kernels());
    let compiled = specs
        .iter()
        .map(|s| s.compile())
        .collect::<Result<Vec<_>, _>>()?;
    let pairs: Vec<_> = specs.iter().zip(&compiled).collect();
    let header = manifest::header(
        &pairs,
        &format!("by c5-codegen; regenerate with `{REGENERATE}`"),
    );
    Ok(vec![
        (
            PathBuf::from("src/f64.rs"),
            emit::emit_file(&header, &pairs, Scalar::F64)?,
        ),
        (
            PathBuf::from("src/f32.rs"),
            emit::emit_file(&header, &pairs, Scalar::F32)?,
        ),
        (PathBuf::from("ops.json"), manifest::json(&pairs)),
        (PathBuf::from("OPS.md"), manifest::markdown(&pairs)),
    ])
}

/// Writes [`generated_crate_files`] under `dir`, only the files that changed; returns the
/// paths that were stale.
///
/// # Errors
/// As [`generated_crate_files`], plus [`Error::Io`].
pub fn write_generated_crate(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut stale = Vec::new();
    for (rel, contents) in generated_crate_files()? {
        let path = dir.join(&rel);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(contents.as_str()) {
            write::write_if_changed(&path, &contents)?;
            stale.push(rel);
        }
    }
    Ok(stale)
}
