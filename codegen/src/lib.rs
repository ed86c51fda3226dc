//! Symbolic expansion of the C5 joint parallel robot's equations into straight-line,
//! operation-counted Rust kernels.
//!
//! Data flows one way: the [`model`] writes the chapter's equations over [`Expr`] (a
//! hash-consed, self-simplifying [`dag`]); [`lower`] factors and orders the DAG into a counted
//! [`lower::Program`]; [`emit`] prints it as Rust with `quote` and `prettyplease`, [`emit_c`] as
//! C after [`schedule`] has reordered it for compilers that do not reorder.
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
pub mod emit_c;
pub mod error;
pub mod kernel;
pub mod linalg;
pub mod lower;
pub mod manifest;
pub mod model;
pub mod numeric;
pub mod schedule;
pub mod subsum;
mod write;

pub use c5_robot::{Model, Robot};
pub use count::OpCount;
pub use dag::{Expr, Graph};
pub use emit::{Scalar, TrigCalls};
pub use error::Error;
pub use kernel::{Compiled, KernelSpec, Setting};
pub use model::ParameterSet;

use std::path::{Path, PathBuf};

/// The command that regenerates the checked-in kernels.
pub const REGENERATE: &str = "cargo run -p c5-codegen-cli -- generate";

/// The language of the generated kernels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Language {
    /// One Rust file, for `include!`.
    #[default]
    Rust,
    /// A C99 header and source file (`{stem}.h`, `{stem}.c`), only `<math.h>`.
    C,
}

/// Configuration of a generation, in the manner of `prost_build::Config`.
#[derive(Clone, Debug)]
pub struct Config {
    robot: Robot,
    model: Model,
    parameters: ParameterSet,
    scalar: Scalar,
    language: Language,
    c_naming: Option<emit_c::Naming>,
    chapter_kernels: bool,
    regressors: bool,
    out_dir: Option<PathBuf>,
    file_name: String,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            robot: Robot::default(),
            model: Model::default(),
            parameters: ParameterSet::None,
            scalar: Scalar::F64,
            language: Language::Rust,
            c_naming: None,
            chapter_kernels: false,
            regressors: false,
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

    /// The model of the legs' mechanism. Default: [`Model::Consistent`], the mechanism of
    /// eq 16; [`Model::Paper`] reproduces the chapter as published.
    pub fn model(&mut self, model: Model) -> &mut Self {
        self.model = model;
        self
    }

    /// Which parameters stay kernel inputs, in the order of the kernels' `params` argument.
    /// Default: [`ParameterSet::None`] (all folded).
    pub fn runtime_parameters(&mut self, parameters: ParameterSet) -> &mut Self {
        self.parameters = parameters;
        self
    }

    /// Floating-point type of the kernels. Default: `f64`.
    pub fn scalar(&mut self, scalar: Scalar) -> &mut Self {
        self.scalar = scalar;
        self
    }

    /// The output language. Default: [`Language::Rust`]. For [`Language::C`], the file name's
    /// stem names the header and the source (`c5_kernels.h`, `c5_kernels.c` by default).
    pub fn language(&mut self, language: Language) -> &mut Self {
        self.language = language;
        self
    }

    /// The C functions' names, `{prefix}{kernel}{suffix}`. Default:
    /// [`emit_c::Naming::standard`], `c5_{model}_{kernel}` (and `_f` for `float`).
    pub fn c_naming(&mut self, prefix: &str, suffix: &str) -> &mut Self {
        self.c_naming = Some(emit_c::Naming {
            prefix: prefix.to_string(),
            suffix: suffix.to_string(),
        });
        self
    }

    /// Also emit the chapter-setting kernels (the paper model's equations with `P_i2` as
    /// inputs, the setting of the chapter's operation counts), whatever [`Config::model`].
    /// Default: `false`.
    pub fn chapter_kernels(&mut self, yes: bool) -> &mut Self {
        self.chapter_kernels = yes;
        self
    }

    /// Also emit the identification kernels of [`Config::model`] (Rust only): `regressor`
    /// (`Γ = Y π` over the standard parameters), `base_regressor` (`Γ = Y_b β`), and the
    /// constants `STANDARD_PARAMETERS`, `BASE_PARAMETERS`, `BASE_RELATIONS`,
    /// `BASE_OF_STANDARD`. Both take the geometry and gravity as `params`; the base parameters
    /// are found with this robot's. Default: `false`.
    pub fn regressors(&mut self, yes: bool) -> &mut Self {
        self.regressors = yes;
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

    /// The kernels, compiled and self-checked.
    fn compile(&self) -> Result<(Vec<KernelSpec>, Vec<Compiled>), Error> {
        self.robot.validate()?;
        let mut specs = Vec::new();
        if self.chapter_kernels {
            specs.extend(model::kernels::chapter_specs());
        }
        let pose = model::kernels::specs(self.model, &self.robot, &self.parameters, "")?;
        let pose_count = pose.len();
        specs.extend(pose);
        let compiled = compile_all(&specs.iter().collect::<Vec<_>>())?;
        if self.parameters == ParameterSet::None {
            let pairs: Vec<_> = specs.iter().zip(&compiled).collect();
            model::self_check(&self.robot, &pairs[pairs.len() - pose_count..], "")?;
        }
        Ok((specs, compiled))
    }

    fn banner(&self, pairs: &[(&KernelSpec, &Compiled)]) -> String {
        let robot = if self.robot == Robot::default() {
            "the chapter's (Robot::default())".to_string()
        } else {
            format!(
                "given to Config::robot (half_spacing {} m, platform mass {} kg)",
                self.robot.half_spacing, self.robot.platform.mass
            )
        };
        manifest::header(
            pairs,
            "by the c5-codegen build API",
            &format!(
                "model: {}; robot: {robot}; scalar: {}",
                self.model,
                self.scalar.name()
            ),
        )
    }

    /// Generates the kernels and returns the Rust file's contents.
    ///
    /// # Errors
    /// An invalid robot, a bad parameter name, or a model the engine cannot emit or whose
    /// output fails the generator's self-check.
    pub fn generate_to_string(&self) -> Result<String, Error> {
        let (specs, compiled) = self.compile()?;
        let identification = self
            .regressors
            .then(|| model::regressor::Identification::compile(self.model, &self.robot))
            .transpose()?;
        let mut pairs: Vec<_> = specs.iter().zip(&compiled).collect();
        if let Some(id) = &identification {
            pairs.extend(id.pairs());
        }
        let mut file = emit::emit_file(
            &self.banner(&pairs),
            &pairs,
            self.scalar,
            TrigCalls::Methods,
        )?;
        if let Some(id) = &identification {
            file.push_str(&model::regressor::constants(&id.base)?);
        }
        Ok(file)
    }

    /// Generates the kernels in [`Config::language`] and returns the files' names and contents:
    /// one Rust file, or a C header and source.
    ///
    /// # Errors
    /// As [`Config::generate_to_string`].
    pub fn generate_files(&self) -> Result<Vec<(String, String)>, Error> {
        match self.language {
            Language::Rust => Ok(vec![(self.file_name.clone(), self.generate_to_string()?)]),
            Language::C => {
                let (specs, compiled) = self.compile()?;
                let pairs: Vec<_> = specs.iter().zip(&compiled).collect();
                let banner = emit_c::c_banner(&self.banner(&pairs));
                let stem = Path::new(&self.file_name)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("c5_kernels")
                    .to_string();
                let naming = self
                    .c_naming
                    .clone()
                    .unwrap_or_else(|| emit_c::Naming::standard(self.model, self.scalar));
                let guard: String = stem
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() {
                            c.to_ascii_uppercase()
                        } else {
                            '_'
                        }
                    })
                    .collect();
                let header = format!("{stem}.h");
                Ok(vec![
                    (
                        header.clone(),
                        emit_c::emit_header(
                            &banner,
                            &format!("{guard}_H"),
                            &pairs,
                            self.scalar,
                            &naming,
                        ),
                    ),
                    (
                        format!("{stem}.c"),
                        emit_c::emit_source(&banner, &header, &pairs, self.scalar, &naming),
                    ),
                ])
            }
        }
    }

    /// Generates the kernels into `out_dir` (`file_name`, or the C header and source),
    /// rewriting a file only when it changed.
    ///
    /// # Errors
    /// As [`Config::generate_to_string`], plus [`Error::NoOutDir`] and [`Error::Io`].
    pub fn generate(&self) -> Result<(), Error> {
        let dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => PathBuf::from(std::env::var_os("OUT_DIR").ok_or(Error::NoOutDir)?),
        };
        for (name, contents) in self.generate_files()? {
            write::write_if_changed(&dir.join(name), &contents)?;
        }
        Ok(())
    }
}

/// Compiles every kernel, on every core: each is independent.
fn compile_all(specs: &[&KernelSpec]) -> Result<Vec<Compiled>, Error> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = specs.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        let handles: Vec<_> = specs
            .chunks(chunk)
            .map(|part| scope.spawn(move || part.iter().map(|s| s.compile()).collect::<Vec<_>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a kernel compilation does not panic"))
            .collect()
    })
}

/// Generates the kernels of the default robot with default settings into `OUT_DIR`.
///
/// # Errors
/// As [`Config::generate`].
pub fn generate() -> Result<(), Error> {
    Config::new().generate()
}

/// The kernels the checked-in crate also has in batch form (`_x4` in `f64`, `_x8` in `f32`).
const BATCH_KERNELS: [&str; 4] = [
    "inverse_dynamics",
    "inverse_dynamics_params",
    "forward_dynamics",
    "forward_dynamics_params",
];

/// The kernels of the checked-in crate for one model: the chapter-setting ones (paper model),
/// the pose-setting ones with the default robot folded, and with every parameter an input.
fn crate_kernels(model: Model) -> Result<Vec<KernelSpec>, Error> {
    let robot = Robot::default();
    let mut specs = match model {
        Model::Paper => model::kernels::chapter_specs(),
        Model::Consistent => Vec::new(),
    };
    specs.extend(model::kernels::specs(
        model,
        &robot,
        &ParameterSet::None,
        "",
    )?);
    specs.extend(model::kernels::specs(
        model,
        &robot,
        &ParameterSet::All,
        "_params",
    )?);
    Ok(specs)
}

/// The files of the checked-in `generated/` crate, relative to it, with their contents: one
/// kernel file per model and scalar (`src/f64/consistent.rs`, ...), their batch forms, the
/// identification kernels per model (`src/f64/consistent_regressor.rs`, ...), and the manifest.
///
/// # Errors
/// A model the engine cannot emit, or that fails the self-check (a bug).
pub fn generated_crate_files() -> Result<Vec<(PathBuf, String)>, Error> {
    let robot = Robot::default();
    let per_model = Model::ALL
        .into_iter()
        .map(|m| Ok((m, crate_kernels(m)?)))
        .collect::<Result<Vec<_>, Error>>()?;
    let all_specs: Vec<&KernelSpec> = per_model.iter().flat_map(|(_, s)| s).collect();
    let (compiled, identification) = std::thread::scope(|scope| {
        let identification: Vec<_> = Model::ALL
            .map(|m| scope.spawn(move || model::regressor::Identification::compile(m, &robot)))
            .into_iter()
            .collect();
        let compiled = compile_all(&all_specs);
        let identification: Result<Vec<_>, Error> = identification
            .into_iter()
            .map(|h| h.join().expect("a kernel compilation does not panic"))
            .collect();
        (compiled, identification)
    });
    let (compiled, identification) = (compiled?, identification?);
    let mut pairs: Vec<(&KernelSpec, &Compiled)> =
        all_specs.iter().copied().zip(&compiled).collect();
    pairs.extend(identification.iter().flat_map(|id| id.pairs()));
    let mut files = Vec::new();
    for model in Model::ALL {
        let mine: Vec<_> = pairs
            .iter()
            .copied()
            .filter(|(s, _)| s.model == model && !s.name.ends_with("regressor"))
            .collect();
        for suffix in ["", "_params"] {
            let group: Vec<_> = mine
                .iter()
                .copied()
                .filter(|(s, _)| s.setting == Setting::Pose && s.name.ends_with(suffix))
                .filter(|(s, _)| suffix == "_params" || !s.name.ends_with("_params"))
                .collect();
            model::self_check(&robot, &group, suffix)?;
        }
        let header = manifest::header(
            &mine,
            &format!("by c5-codegen; regenerate with `{REGENERATE}`"),
            &format!("model: {model}; robot: the chapter's (Robot::default())"),
        );
        let batched: Vec<_> = mine
            .iter()
            .copied()
            .filter(|(s, _)| BATCH_KERNELS.contains(&s.name.as_str()))
            .collect();
        for scalar in [Scalar::F64, Scalar::F32] {
            files.push((
                PathBuf::from(format!("src/{}/{model}.rs", scalar.name())),
                emit::emit_file(&header, &mine, scalar, TrigCalls::Functions)?,
            ));
            files.push((
                PathBuf::from(format!("src/{}/{model}_batch.rs", scalar.name())),
                emit::emit_batch_file(&header, &batched, scalar)?,
            ));
        }
    }
    for (model, id) in Model::ALL.into_iter().zip(&identification) {
        let kernels = id.pairs();
        let header = manifest::header(
            &kernels,
            &format!("by c5-codegen; regenerate with `{REGENERATE}`"),
            &format!(
                "model: {model}; any robot of the family (geometry and gravity are `params`; \
                 base parameters found with the chapter's)"
            ),
        );
        files.push((
            PathBuf::from(format!("src/f64/{model}_regressor.rs")),
            emit::emit_file(&header, &kernels, Scalar::F64, TrigCalls::Functions)?
                + &model::regressor::constants(&id.base)?,
        ));
    }
    files.push((PathBuf::from("ops.json"), manifest::json(&pairs)));
    files.push((PathBuf::from("OPS.md"), manifest::markdown(&pairs)));
    Ok(files)
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
