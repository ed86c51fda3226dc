//! `c5-codegen`: regenerates the checked-in `generated/` crate, or writes kernels for a robot
//! described in a TOML file.

use c5_codegen::{Config, Description, Language, Model, ParameterSet, Scalar};
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "c5-codegen",
    version,
    about = "Generates the C5 robot's straight-line, operation-counted kernels"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Rewrites the generated/ crate (kernels of both models, their kernel-set trait, the
    /// constants, ops.json, OPS.md) for the default robot.
    Generate {
        /// The generated/ directory [default: the workspace's, found from the current
        /// directory upwards].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Writes the pose-setting kernels of a robot (parameters folded unless
    /// --runtime-parameters), in Rust or C.
    Kernels {
        /// The robot description (the TOML form of `c5_codegen::Robot`) [default: the
        /// chapter's robot].
        #[arg(long)]
        robot: Option<PathBuf>,
        /// The Rust file to write, or for `--lang c` the directory of `c5_kernels.h` and
        /// `c5_kernels.c`.
        #[arg(long)]
        out: PathBuf,
        /// The output language.
        #[arg(long, default_value = "rust", value_parser = PossibleValuesParser::new(["rust", "c"]))]
        lang: String,
        /// The model of the legs' mechanism.
        #[arg(long, default_value = "consistent", value_parser = model_parser())]
        model: Model,
        /// Every robot parameter an input (`params`, in the order of `Robot::flatten`).
        #[arg(long)]
        runtime_parameters: bool,
        /// `f32` kernels instead of `f64`.
        #[arg(long)]
        f32: bool,
        /// Also the chapter-setting kernels (the paper model with `P_i2` as inputs).
        #[arg(long)]
        chapter: bool,
    },
}

fn model_parser() -> impl TypedValueParser<Value = Model> {
    PossibleValuesParser::new(Model::ALL.map(Model::name))
        .map(|name| name.parse::<Model>().expect("one of the possible values"))
}

/// The `generated/` directory of the workspace that holds `start`.
fn find_generated(start: &Path) -> Option<PathBuf> {
    start.ancestors().map(|d| d.join("generated")).find(|g| {
        std::fs::read_to_string(g.join("Cargo.toml"))
            .is_ok_and(|text| text.contains("name = \"c5-generated\""))
    })
}

fn generate(out: Option<PathBuf>) -> Result<(), String> {
    let dir = match out {
        Some(dir) => dir,
        None => {
            let cwd = std::env::current_dir().map_err(|e| e.to_string())?;
            find_generated(&cwd).ok_or_else(|| {
                format!(
                    "no generated/ directory of the c5-generated crate above {}; pass --out DIR",
                    cwd.display()
                )
            })?
        }
    };
    let stale = c5_codegen::write_generated_crate(&dir).map_err(|e| e.to_string())?;
    for p in &stale {
        println!("wrote {}", dir.join(p).display());
    }
    if stale.is_empty() {
        println!("{} is up to date", dir.display());
    }
    println!(
        "operation counts: {}; beside the chapter's: cargo run --release -- audit",
        dir.join("OPS.md").display()
    );
    Ok(())
}

fn kernels(
    robot: Option<&Path>,
    out: &Path,
    model: Model,
    runtime_parameters: bool,
    f32: bool,
    chapter: bool,
    c: bool,
) -> Result<(), String> {
    let robot = match robot {
        Some(path) => Description::from_toml_file(path).map_err(|e| e.to_string())?,
        None => Description::default(),
    };
    let mut config = Config::new();
    config
        .description(robot)
        .model(model)
        .chapter_kernels(chapter);
    // For C, `out` is a directory; for Rust, the file.
    let dir = if c {
        config.language(Language::C);
        out.to_path_buf()
    } else {
        let name = out
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or("--out must name a file")?;
        config.file_name(name);
        match out.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    if runtime_parameters {
        config.runtime_parameters(ParameterSet::All);
    }
    if f32 {
        config.scalar(Scalar::F32);
    }
    let files = config.generate_files().map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for (name, contents) in files {
        let path = dir.join(name);
        std::fs::write(&path, contents).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Generate { out } => generate(out),
        Command::Kernels {
            robot,
            out,
            model,
            runtime_parameters,
            f32,
            chapter,
            lang,
        } => kernels(
            robot.as_deref(),
            &out,
            model,
            runtime_parameters,
            f32,
            chapter,
            lang == "c",
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
