//! Symbolic expansion of the C5 joint parallel robot's equations into straight-line,
//! operation-counted Rust kernels.
//!
//! Data flows one way. The [`model`] writes the chapter's equations over [`Expr`] (a
//! hash-consed, self-simplifying [`dag`]), one [`model::Mechanics`] per model; its kernel
//! table ([`model::kernels::TABLE`]) declares each kernel as data: its typed identity
//! ([`Kernel`]), the kinds of input it reads, its outputs and its singularity terms. The
//! engine turns a kernel into a factored, counted [`Program`] (`lower`), checks the generated
//! set against identities between its kernels (`model::selfcheck`), and prints it as Rust
//! (`emit`, with `quote` and `prettyplease`) or as C (`emit_c`, in the order of `schedule`, for
//! compilers that do not reorder), with a kernel-set trait per scalar type so that callers
//! pick a model once. The engine knows nothing about robots; the models know nothing about code
//! emission.
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

mod blocks;
mod count;
pub mod dag;
mod emit;
mod emit_c;
mod error;
mod fuse;
pub mod kernel;
pub mod linalg;
mod lower;
mod manifest;
pub mod model;
mod numeric;
mod schedule;
mod subsum;
mod write;

pub use c5_robot::{Description, GoughStewart, Model, Robot};
pub use count::OpCount;
pub use dag::{Expr, Graph};
pub use emit::Scalar;
pub use emit_c::Naming as CNaming;
pub use error::Error;
pub use kernel::{Compiled, KernelSpec, Setting, Shape};
pub use lower::Program;
pub use model::{Kernel, KernelId, Mechanism, ParameterSet};

use emit::TrigCalls;
use model::Entry;

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
    robot: Description,
    model: Model,
    parameters: ParameterSet,
    scalar: Scalar,
    language: Language,
    c_naming: Option<emit_c::Naming>,
    chapter_kernels: bool,
    regressors: bool,
    fused_multiply_add: bool,
    out_dir: Option<PathBuf>,
    file_name: String,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            robot: Description::default(),
            model: Model::default(),
            parameters: ParameterSet::None,
            scalar: Scalar::F64,
            language: Language::Rust,
            c_naming: None,
            chapter_kernels: false,
            regressors: false,
            fused_multiply_add: true,
            out_dir: None,
            file_name: "c5_kernels.rs".to_string(),
        }
    }
}

impl Config {
    pub fn new() -> Self {
        Self::default()
    }

    /// The C5 robot whose parameters are folded in. Default: the chapter's robot.
    pub fn robot(&mut self, robot: Robot) -> &mut Self {
        self.robot = Description::C5(robot);
        self
    }

    /// The robot, of any mechanism (read a robot file with
    /// [`Description::from_toml_file`]), whose parameters are folded in. Default: the
    /// chapter's C5 robot.
    pub fn description(&mut self, robot: Description) -> &mut Self {
        self.robot = robot;
        self
    }

    /// The C5's model of its legs' mechanism. Default: [`Model::Consistent`], the mechanism of
    /// eq 16; [`Model::Paper`] reproduces the chapter as published. Other mechanisms have one
    /// model and ignore this.
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

    /// The C functions' names, `{prefix}{kernel}{suffix}`. Default: `c5_{module}_{kernel}`
    /// (`c5_consistent_`, `c5_gough_stewart_`), and `_f` appended for `float`.
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

    /// Give each `f64` kernel an FMA twin: in Rust, `{kernel}_fused` (its products fused into
    /// the sums that read them, `mul_add`, compiled for FMA), `{kernel}_separate` (every
    /// operation rounded on its own), and `{kernel}` running the fused twin where the CPU has
    /// FMA (x86, detected at run time), the separate one elsewhere; in C, `C5_FMA(a, b, c)`,
    /// `fma` when `C5_FUSED_MULTIPLY_ADD` is defined, `a * b + c` otherwise. The twins differ
    /// by a few units in the last place; call `{kernel}_separate` (or turn this off) for the
    /// same bits on every machine. Default: `true`.
    pub fn fused_multiply_add(&mut self, yes: bool) -> &mut Self {
        self.fused_multiply_add = yes;
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

    /// The mechanism the configuration describes.
    fn mechanism(&self) -> Result<Mechanism, Error> {
        self.robot.validate()?;
        Ok(Mechanism::of(&self.robot, self.model))
    }

    /// The kernels, compiled and self-checked.
    fn compile(&self) -> Result<(Vec<Entry>, Vec<Compiled>), Error> {
        let mechanism = self.mechanism()?;
        let mut entries = Vec::new();
        if self.chapter_kernels {
            entries.extend(model::kernels::chapter_specs(&Mechanism::c5(
                &Robot::default(),
                Model::Paper,
            )));
        }
        entries.extend(model::kernels::specs(&mechanism, &self.parameters, "")?);
        let compiled = compile_all(&entries)?;
        let robot_kernels: Vec<_> = entries
            .iter()
            .zip(&compiled)
            .filter(|(e, _)| e.spec.family == mechanism.name() && e.spec.setting != Setting::Free)
            .collect();
        model::self_check(&mechanism, &robot_kernels)?;
        Ok((entries, compiled))
    }

    /// The name, inputs and outputs of every kernel the configuration generates, in the order
    /// of the generated file (for writing bindings to them).
    ///
    /// # Errors
    /// As [`Config::generate_to_string`].
    pub fn signatures(&self) -> Result<Vec<Signature>, Error> {
        let (entries, _) = self.compile()?;
        Ok(entries.iter().map(|e| Signature::of(&e.spec)).collect())
    }

    fn banner(&self, pairs: &[(&KernelSpec, &Compiled)]) -> Result<String, Error> {
        let robot = if self.robot == Description::default() {
            "the chapter's (Robot::default())".to_string()
        } else {
            format!("given to Config ({})", self.robot.summary())
        };
        Ok(manifest::header(
            pairs,
            "by the c5-codegen build API",
            &format!(
                "model: {}; robot: {robot}; scalar: {}",
                self.mechanism()?.name(),
                self.scalar.name()
            ),
        ))
    }

    /// Generates the kernels and returns the Rust file's contents.
    ///
    /// # Errors
    /// An invalid robot, a bad parameter name, or a model the engine cannot emit or whose
    /// output fails the generator's self-check.
    pub fn generate_to_string(&self) -> Result<String, Error> {
        let (entries, compiled) = self.compile()?;
        let mechanism = self.mechanism()?;
        let identification = self
            .regressors
            .then(|| model::regressor::Identification::compile(&mechanism))
            .transpose()?;
        let mut pairs: Vec<_> = entries.iter().map(|e| &e.spec).zip(&compiled).collect();
        if let Some(id) = &identification {
            pairs.extend(id.pairs().into_iter().map(|(e, c)| (&e.spec, c)));
        }
        let fma = emit::FmaDispatch::detected();
        let mut file = emit::emit_file(
            &self.banner(&pairs)?,
            &pairs,
            self.scalar,
            TrigCalls::Methods,
            self.fused_multiply_add.then_some(&fma),
        )?;
        if let Some(id) = &identification {
            file.push_str(&model::regressor::constants(
                &id.base,
                mechanism.structure().standard_inertial_doc(),
            )?);
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
                let (entries, compiled) = self.compile()?;
                let pairs: Vec<_> = entries.iter().map(|e| &e.spec).zip(&compiled).collect();
                let banner = emit_c::c_banner(&self.banner(&pairs)?);
                let stem = Path::new(&self.file_name)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("c5_kernels")
                    .to_string();
                let naming = match &self.c_naming {
                    Some(naming) => naming.clone(),
                    None => c_naming(&self.mechanism()?, self.scalar),
                };
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
                        emit_c::emit_source(
                            &banner,
                            &header,
                            &pairs,
                            self.scalar,
                            &naming,
                            self.fused_multiply_add,
                        ),
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

/// The C functions' names of a mechanism's kernels: `c5_{module}_{kernel}` (`c5_consistent_`,
/// `c5_gough_stewart_`), `_f` appended for `float`.
fn c_naming(mechanism: &Mechanism, scalar: Scalar) -> emit_c::Naming {
    emit_c::Naming::with_scalar_suffix(&format!("c5_{}_", module_name(mechanism)), scalar)
}

/// Compiles every kernel, on every core: each is independent.
fn compile_all<E: std::borrow::Borrow<Entry> + Sync>(
    entries: &[E],
) -> Result<Vec<Compiled>, Error> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    // A shared queue, not fixed chunks: the kernels' costs differ by a thousand times.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::Mutex::new(Vec::with_capacity(entries.len()));
    std::thread::scope(|scope| {
        for _ in 0..threads.min(entries.len()) {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(entry) = entries.get(i) else { break };
                let compiled = entry.borrow().spec.compile();
                done.lock()
                    .expect("no compilation panics")
                    .push((i, compiled));
            });
        }
    });
    let mut done = done.into_inner().expect("no compilation panics");
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, c)| c).collect()
}

/// Generates the kernels of the default robot with default settings into `OUT_DIR`.
///
/// # Errors
/// As [`Config::generate`].
pub fn generate() -> Result<(), Error> {
    Config::new().generate()
}

/// A mechanism of the checked-in crate, and which of its kernels the crate holds.
struct CheckedIn {
    mechanism: Mechanism,
    /// One of the C5's models: they share the kernel-set trait.
    c5: bool,
    /// With batch forms (`f64` and `f32`) and folded derivative kernels. The Gough-Stewart
    /// platform's are left out: all its batch forms, kernels of 4 000 to 5 000 operations
    /// instantiated for three instruction sets, took LLVM six minutes to build, twelve times
    /// the rest of the crate; its `inverse_dynamics_params_x4` alone
    /// ([`CheckedIn::batched`], `f64`) adds seconds.
    complete: bool,
    /// The kernels whose `*_params` form comes in batch form too, where the mechanism is not
    /// [`CheckedIn::complete`]: the ones a many-state caller needs, built in seconds.
    batched: &'static [Kernel],
    /// With the folded kernels and the `f32` forms: a mechanism new to the crate has its
    /// `*_params` kernels alone until the runtime serves the others.
    extended: bool,
    /// With the derivative kernels (feature `derivatives`): folded and `*_params` for a
    /// [`CheckedIn::complete`] mechanism, `*_params` for the others.
    derivatives: bool,
    /// With the identification kernels (the regressors and the base parameters).
    identification: bool,
}

/// The mechanisms of the checked-in crate: the C5's two models with the chapter's robot, the
/// Gough-Stewart platform of `docs/hexapod.toml`, the rotary hexapod of
/// `docs/rus-hexapod.toml` and the Delta of `docs/delta.toml` (their `*_params` kernels alone,
/// `f64`).
fn checked_in_mechanisms() -> Vec<CheckedIn> {
    let c5 = Model::ALL.into_iter().map(|m| CheckedIn {
        mechanism: Mechanism::c5(&Robot::default(), m),
        c5: true,
        complete: true,
        batched: &[],
        extended: true,
        derivatives: true,
        identification: true,
    });
    c5.chain([
        CheckedIn {
            mechanism: Mechanism::gough_stewart(&c5_robot::GoughStewart::example()),
            c5: false,
            complete: false,
            batched: &[Kernel::InverseDynamics],
            extended: true,
            derivatives: true,
            identification: true,
        },
        CheckedIn {
            mechanism: Mechanism::rus_hexapod(&c5_robot::RusHexapod::example()),
            c5: false,
            complete: false,
            batched: &[],
            extended: false,
            // 95 500 lines even in reverse mode, and about two minutes more of the crate's
            // build with `derivatives`, which the tests' build cannot afford (docs/derivatives.md).
            derivatives: false,
            identification: true,
        },
        CheckedIn {
            mechanism: Mechanism::delta(&c5_robot::Delta::example()),
            c5: false,
            complete: false,
            batched: &[Kernel::InverseDynamics],
            extended: false,
            derivatives: true,
            identification: true,
        },
    ])
    .collect()
}

/// What the robot of a checked-in mechanism is, for the files' headers.
fn checked_in_robot(mechanism: &Mechanism) -> &'static str {
    if mechanism.name() == c5_robot::description::GOUGH_STEWART {
        "the example of docs/hexapod.toml (GoughStewart::example())"
    } else if mechanism.name() == c5_robot::description::RUS_HEXAPOD {
        "the example of docs/rus-hexapod.toml (RusHexapod::example())"
    } else if mechanism.name() == c5_robot::description::DELTA {
        "the example of docs/delta.toml (Delta::example())"
    } else {
        "the chapter's (Robot::default())"
    }
}

/// The kernels of the checked-in crate for one mechanism: the free-input ones (the paper
/// model's chapter setting), the robot kernels with its description folded (an extended
/// mechanism's), and with every parameter an input (`*_params`).
fn crate_kernels(checked_in: &CheckedIn) -> Result<Vec<Entry>, Error> {
    let mechanism = &checked_in.mechanism;
    let mut entries = model::kernels::chapter_specs(mechanism);
    if checked_in.extended {
        entries.extend(folded_and_with_parameters(
            mechanism,
            model::kernels::specs,
        )?);
    } else {
        entries.extend(model::kernels::specs(
            mechanism,
            &ParameterSet::All,
            "_params",
        )?);
        entries.extend(model::kernels::geometry_specs(mechanism));
    }
    Ok(entries)
}

/// The derivative kernels of the checked-in crate for one mechanism, folded and `*_params`
/// for the C5; `*_params` alone for a mechanism whose kernels any robot of its kind uses (the
/// folded ones would double the largest file for a benchmark).
fn crate_derivatives(checked_in: &CheckedIn) -> Result<Vec<Entry>, Error> {
    let mechanism = &checked_in.mechanism;
    if !checked_in.derivatives {
        Ok(Vec::new())
    } else if checked_in.complete {
        folded_and_with_parameters(mechanism, model::kernels::derivative_specs)
    } else {
        model::kernels::derivative_specs(mechanism, &ParameterSet::All, "_params")
    }
}

/// A table's kernels for one mechanism, given its parameter set and a name suffix.
type Specs = fn(&Mechanism, &ParameterSet, &str) -> Result<Vec<Entry>, Error>;

/// The kernels `specs` declares for one mechanism, its description folded in, then with every
/// parameter an input (`*_params`).
fn folded_and_with_parameters(mechanism: &Mechanism, specs: Specs) -> Result<Vec<Entry>, Error> {
    let mut entries = specs(mechanism, &ParameterSet::None, "")?;
    entries.extend(specs(mechanism, &ParameterSet::All, "_params")?);
    Ok(entries)
}

/// One mechanism's compiled kernels, by kind.
struct MechanismKernels<'a> {
    mechanism: &'a Mechanism,
    kernels: Vec<(&'a Entry, &'a Compiled)>,
    derivatives: Vec<(&'a Entry, &'a Compiled)>,
    identification: Option<&'a model::regressor::Identification>,
    /// [`CheckedIn::extended`].
    extended: bool,
    /// [`CheckedIn::complete`]: the `f32` batch forms are a complete mechanism's alone.
    complete: bool,
}

/// The files of the checked-in `generated/` crate, relative to it, with their contents: one
/// kernel file per mechanism (or C5 model) and scalar (`src/f64/consistent.rs`, ...), their
/// batch forms, the identification and derivative kernels (`f64`), the module file of each
/// scalar with the C5's kernel-set trait (`src/f64/mod.rs`), the parameter and
/// operation-count constants, and the manifest.
///
/// # Errors
/// A mechanism the engine cannot emit, that fails the self-check, or a C5 model whose kernels'
/// signatures differ from another's (a bug).
pub fn generated_crate_files() -> Result<Vec<(PathBuf, String)>, Error> {
    let checked_in = checked_in_mechanisms();
    let per_mechanism = checked_in
        .iter()
        .map(|c| {
            let mut entries = crate_kernels(c)?;
            let batched = |e: &Entry| e.id.parameters && c.batched.contains(&e.id.kernel);
            entries
                .iter_mut()
                .for_each(|e| e.batch &= c.complete || batched(e));
            Ok(entries)
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let derivative_entries = checked_in
        .iter()
        .map(crate_derivatives)
        .collect::<Result<Vec<_>, Error>>()?;
    let all: Vec<&Entry> = per_mechanism
        .iter()
        .flatten()
        .chain(derivative_entries.iter().flatten())
        .collect();
    let (compiled, identification) = std::thread::scope(|scope| {
        let identification: Vec<_> = checked_in
            .iter()
            .map(|c| {
                let m = &c.mechanism;
                c.identification
                    .then(|| scope.spawn(move || model::regressor::Identification::compile(m)))
            })
            .collect();
        let compiled = compile_all(&all);
        let identification: Result<Vec<_>, Error> = identification
            .into_iter()
            .map(|h| {
                h.map(|h| h.join().expect("a kernel compilation does not panic"))
                    .transpose()
            })
            .collect();
        (compiled, identification)
    });
    let (compiled, identification) = (compiled?, identification?);
    let kernels: Vec<(&Entry, &Compiled)> = all.iter().copied().zip(&compiled).collect();
    let regressors: Vec<(&Entry, &Compiled)> = identification
        .iter()
        .flatten()
        .flat_map(|id| id.pairs())
        .collect();
    let is_derivative = |e: &Entry| model::derivatives::is_derivative(e.id.kernel);
    let how = format!("by c5-codegen; regenerate with `{REGENERATE}`");
    let mut files = Vec::new();
    let groups: Vec<MechanismKernels> = checked_in
        .iter()
        .zip(&identification)
        .map(|(checked_in, identification)| {
            let mechanism = &checked_in.mechanism;
            let identification = identification.as_ref();
            let (derivatives, kernels) = kernels
                .iter()
                .copied()
                .filter(|(e, _)| e.spec.family == mechanism.name())
                .partition(|(e, _)| is_derivative(e));
            MechanismKernels {
                mechanism,
                kernels,
                derivatives,
                identification,
                extended: checked_in.extended,
                complete: checked_in.complete,
            }
        })
        .collect();
    for group in &groups {
        files.extend(mechanism_files(group)?);
    }
    fn set<'a>(group: &MechanismKernels<'a>) -> emit::KernelSet<'a> {
        emit::KernelSet {
            module: module_name(group.mechanism),
            summary: group.mechanism.mechanics.summary().to_string(),
            kernels: group
                .kernels
                .iter()
                .filter(|(e, _)| model::kernels::is_shared(e.id.kernel))
                .map(|(e, _)| emit::SetKernel {
                    spec: &e.spec,
                    batch: e.batch,
                    folded: e.folded,
                })
                .collect(),
            regressors: group
                .identification
                .iter()
                .flat_map(|id| id.pairs())
                .map(|(e, _)| &e.spec)
                .collect(),
            derivatives: group
                .derivatives
                .iter()
                .map(|(e, _)| emit::SetKernel {
                    spec: &e.spec,
                    batch: false,
                    folded: e.folded,
                })
                .collect(),
        }
    }
    let (sets, standalone): (Vec<_>, Vec<_>) = groups.iter().partition(|g| {
        checked_in
            .iter()
            .any(|c| c.c5 && std::ptr::eq(&c.mechanism, g.mechanism))
    });
    let sets: Vec<_> = sets.into_iter().map(set).collect();
    let standalone_f32: Vec<_> = standalone
        .iter()
        .filter(|g| g.extended)
        .map(|g| {
            let mut kernels = set(g);
            if !g.complete {
                kernels.kernels.iter_mut().for_each(|k| k.batch = false);
            }
            kernels
        })
        .collect();
    let standalone: Vec<_> = standalone.into_iter().map(set).collect();
    for (scalar, standalone) in [(Scalar::F64, &standalone), (Scalar::F32, &standalone_f32)] {
        files.push((
            PathBuf::from(format!("src/{}/mod.rs", scalar.name())),
            emit::emit_kernel_sets(&how, &sets, standalone, scalar)?,
        ));
    }
    let everything: Vec<(&KernelSpec, &Compiled)> = kernels
        .iter()
        .chain(&regressors)
        .map(|(e, c)| (&e.spec, *c))
        .collect();
    files.push((
        PathBuf::from("src/parameters.rs"),
        manifest::parameter_constants(&how)?,
    ));
    let with_ids: Vec<_> = kernels
        .iter()
        .chain(&regressors)
        .map(|(e, c)| (e.id, &e.spec, *c))
        .collect();
    files.push((
        PathBuf::from("src/manifest.rs"),
        manifest::rust_constants(&how, &with_ids)?,
    ));
    files.push((PathBuf::from("ops.json"), manifest::json(&everything)));
    files.push((PathBuf::from("OPS.md"), manifest::markdown(&everything)));
    Ok(files)
}

/// The generated module of a mechanism: its name with `_` for `-`.
fn module_name(mechanism: &Mechanism) -> String {
    mechanism.name().replace('-', "_")
}

/// One mechanism's files: its kernels in `f64` and `f32` and their batch forms, its
/// derivative and identification kernels in `f64`, each self-checked first.
fn mechanism_files(group: &MechanismKernels<'_>) -> Result<Vec<(PathBuf, String)>, Error> {
    let (mechanism, mine) = (group.mechanism, &group.kernels);
    let module = module_name(mechanism);
    let robot = checked_in_robot(mechanism);
    for parameters in [false, true] {
        let checked: Vec<_> = mine
            .iter()
            .copied()
            .filter(|(e, _)| {
                e.spec.setting != Setting::Free
                    && (e.id.parameters == parameters
                        || e.spec.inputs.iter().all(|a| a.name != "params"))
            })
            .collect();
        if checked.is_empty() || (!parameters && !group.extended) {
            continue; // no folded kernels (calibration's read the geometry alone)
        }
        model::self_check(mechanism, &checked)?;
    }
    let header = |pairs: &[(&KernelSpec, &Compiled)], what: &str| {
        manifest::header(
            pairs,
            &format!("by c5-codegen; regenerate with `{REGENERATE}`"),
            what,
        )
    };
    let what = format!("model: {}; robot: {robot}", mechanism.name());
    let mut files = Vec::new();
    // The kernels with the robot folded in as constants go to files of their own, which the
    // crate compiles with its `folded` feature: the runtime calls the `*_params` forms, which
    // serve any robot of the kind, and a build that does not ask for the folded ones does not
    // pay for them (docs/build-time.md).
    for (part, folded) in [("", false), ("_folded", true)] {
        let specs: Vec<_> = mine
            .iter()
            .filter(|(e, _)| e.folded == folded)
            .map(|(e, c)| (&e.spec, *c))
            .collect();
        if specs.is_empty() {
            continue;
        }
        let batched: Vec<_> = mine
            .iter()
            .filter(|(e, _)| e.batch && e.folded == folded)
            .map(|(e, c)| (&e.spec, *c))
            .collect();
        // A mechanism new to the crate comes in `f64` alone.
        let scalars: &[Scalar] = if group.extended {
            &[Scalar::F64, Scalar::F32]
        } else {
            &[Scalar::F64]
        };
        for &scalar in scalars {
            let mut kernels = emit::emit_file(
                &header(&specs, &what),
                &specs,
                scalar,
                TrigCalls::Functions,
                Some(&emit::FmaDispatch::crate_switch()),
            )?;
            if !folded {
                // The kernel set is the `f64` kernels'.
                let batch_names: Vec<String> = batched
                    .iter()
                    .map(|(s, _)| format!("{}_x4", s.name))
                    .collect();
                // With the derivative kernels of the same part, which a feature gates.
                let names: Vec<&str> = match scalar {
                    Scalar::F64 => specs
                        .iter()
                        .map(|(s, _)| s.name.as_str())
                        .chain(batch_names.iter().map(String::as_str))
                        .chain(
                            group
                                .derivatives
                                .iter()
                                .filter(|(e, _)| e.folded == folded)
                                .map(|(e, _)| e.spec.name.as_str()),
                        )
                        .collect(),
                    _ => Vec::new(),
                };
                let fitted = specs.iter().find_map(|(s, _)| {
                    match (s.name.as_str(), s.outputs.get(1).map(|o| o.shape)) {
                        ("calibration_residuals", Some(Shape::Matrix(_, f))) => Some(f),
                        _ => None,
                    }
                });
                kernels.push_str(&manifest::mechanism_parameter_constants(
                    mechanism, &names, fitted,
                )?);
            }
            files.push((
                PathBuf::from(format!("src/{}/{module}{part}.rs", scalar.name())),
                kernels,
            ));
            if !batched.is_empty() && (scalar == Scalar::F64 || group.complete) {
                files.push((
                    PathBuf::from(format!("src/{}/{module}{part}_batch.rs", scalar.name())),
                    emit::emit_batch_file(&header(&batched, &what), &batched, scalar)?,
                ));
            }
        }
        let derivatives: Vec<_> = group
            .derivatives
            .iter()
            .filter(|(e, _)| e.folded == folded)
            .map(|(e, c)| (&e.spec, *c))
            .collect();
        if !derivatives.is_empty() {
            files.push((
                PathBuf::from(format!("src/f64/{module}{part}_derivatives.rs")),
                emit::emit_file(
                    &header(&derivatives, &what),
                    &derivatives,
                    Scalar::F64,
                    TrigCalls::Functions,
                    Some(&emit::FmaDispatch::crate_switch()),
                )?,
            ));
        }
    }
    let Some(id) = group.identification else {
        return Ok(files);
    };
    let pairs: Vec<_> = id.pairs().into_iter().map(|(e, c)| (&e.spec, c)).collect();
    files.push((
        PathBuf::from(format!("src/f64/{module}_regressor.rs")),
        emit::emit_file(
            &header(
                &pairs,
                &format!(
                    "model: {}; any robot of its kind (geometry and gravity are `params`; \
                     base parameters found with {robot})",
                    mechanism.name()
                ),
            ),
            &pairs,
            Scalar::F64,
            TrigCalls::Functions,
            None,
        )? + &model::regressor::constants(&id.base, mechanism.structure().standard_inertial_doc())?
            + &manifest::regressor_set(mechanism)?,
    ));
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

/// A generated kernel's name, inputs and outputs, for writing bindings to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Signature {
    /// The function's name.
    pub name: String,
    /// The arguments in order, by name and shape.
    pub inputs: Vec<(String, Shape)>,
    /// The results in order, by name and shape (the Rust function returns them as a tuple,
    /// the C function writes them through pointers after the inputs).
    pub outputs: Vec<(String, Shape)>,
}

impl Signature {
    fn of(spec: &KernelSpec) -> Self {
        let ports = |args: &[kernel::Arg]| args.iter().map(|a| (a.name.clone(), a.shape)).collect();
        Signature {
            name: spec.name.clone(),
            inputs: ports(&spec.inputs),
            outputs: ports(&spec.outputs),
        }
    }
}
