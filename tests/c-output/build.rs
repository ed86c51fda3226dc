//! Generates the C kernels of both models in both precisions for the default robot, compiles
//! them with `-ffp-contract=off` (so they compute exactly what the Rust kernels compute) and,
//! for the bench, once more with `-O3 -march=native`; writes the Rust FFI adapters the tests
//! call.

use c5_codegen::{CNaming as Naming, Config, Language, Model, Scalar, Shape, Signature};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The C kernels of `model`: the robot kernels, and the chapter-setting ones for the model
/// that has them (the paper model's).
fn config(out: &Path, model: Model, scalar: Scalar, stem: &str, naming: &Naming) -> Config {
    let mut config = Config::new();
    config
        .model(model)
        .scalar(scalar)
        .language(Language::C)
        .chapter_kernels(model == Model::Paper)
        .c_naming(&naming.prefix, &naming.suffix)
        .file_name(&format!("{stem}.c"))
        .out_dir(out);
    config
}

fn rust_type(shape: Shape, ty: &str) -> String {
    match shape {
        Shape::Vector(n) => format!("[{ty}; {n}]"),
        Shape::Matrix(r, c) => format!("[[{ty}; {c}]; {r}]"),
    }
}

/// The adapters of one kernel: the C function and the Rust kernel, both as
/// `fn(&[f64]) -> Vec<f64>` over the flattened inputs and outputs.
fn adapters(
    out: &mut String,
    spec: &Signature,
    model: Model,
    scalar: Scalar,
    naming: &Naming,
    path: Arithmetic,
) -> String {
    let ty = scalar.name();
    let c_name = naming.function(&spec.name);
    let id = format!("{model}_{ty}_{}{}", path.suffix(), spec.name);
    let mut args = Vec::new();
    let mut unpack = String::new();
    let mut offset = 0;
    for (k, (_, shape)) in spec.inputs.iter().enumerate() {
        let t = rust_type(*shape, ty);
        let _ = writeln!(
            unpack,
            "    let a{k}: {t} = unflat(&input[{offset}..{}]);",
            offset + shape.len()
        );
        offset += shape.len();
        args.push(format!("&a{k}"));
    }
    // The C prototype takes pointers to the first element (rows for matrices).
    let c_params: Vec<String> = spec
        .inputs
        .iter()
        .map(|(name, shape)| match shape {
            Shape::Vector(_) => format!("{name}: *const {ty}"),
            Shape::Matrix(_, c) => format!("{name}: *const [{ty}; {c}]"),
        })
        .chain(spec.outputs.iter().map(|(name, shape)| match shape {
            Shape::Vector(_) => format!("{name}: *mut {ty}"),
            Shape::Matrix(_, c) => format!("{name}: *mut [{ty}; {c}]"),
        }))
        .collect();
    let _ = writeln!(
        out,
        "extern \"C\" {{ fn {c_name}({}); }}",
        c_params.join(", ")
    );
    // C.
    let _ = writeln!(out, "pub fn c_{id}(input: &[f64]) -> Vec<f64> {{\n{unpack}");
    for (k, (_, shape)) in spec.outputs.iter().enumerate() {
        let _ = writeln!(
            out,
            "    let mut o{k}: {} = Default::default();",
            rust_type(*shape, ty)
        );
    }
    let mut call: Vec<String> = (0..spec.inputs.len())
        .map(|k| format!("a{k}.as_ptr()"))
        .collect();
    call.extend((0..spec.outputs.len()).map(|k| format!("o{k}.as_mut_ptr()")));
    let _ = writeln!(out, "    unsafe {{ {c_name}({}) }};", call.join(", "));
    let _ = writeln!(out, "    let mut v = Vec::new();");
    for k in 0..spec.outputs.len() {
        let _ = writeln!(out, "    flat(&o{k}, &mut v);");
    }
    let _ = writeln!(out, "    v\n}}");
    // Rust.
    let _ = writeln!(
        out,
        "pub fn rust_{id}(input: &[f64]) -> Vec<f64> {{\n{unpack}"
    );
    let call = match path {
        Arithmetic::Only => format!("c5_generated::{ty}::{model}::{}", spec.name),
        Arithmetic::Separate => format!("c5_generated::{ty}::{model}::{}_separate", spec.name),
        // The test calls it only where `c5_generated::fma::available()`.
        Arithmetic::Fused => format!("unsafe {{ c5_generated::{ty}::{model}::{}_fused", spec.name),
    };
    let close = if path == Arithmetic::Fused { " }" } else { "" };
    let n = spec.outputs.len();
    if n == 1 {
        let _ = writeln!(out, "    let o0 = {call}({}){close};", args.join(", "));
    } else {
        let names: Vec<String> = (0..n).map(|k| format!("o{k}")).collect();
        let _ = writeln!(
            out,
            "    let ({}) = {call}({}){close};",
            names.join(", "),
            args.join(", ")
        );
    }
    let _ = writeln!(out, "    let mut v = Vec::new();");
    for k in 0..n {
        let _ = writeln!(out, "    flat(&o{k}, &mut v);");
    }
    let _ = writeln!(out, "    v\n}}");
    id
}

/// Which of a kernel's arithmetic paths: `f32` kernels have one; `f64` kernels a separate
/// path (every operation rounded on its own) and an FMA twin.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Arithmetic {
    Only,
    Separate,
    Fused,
}

impl Arithmetic {
    fn suffix(self) -> &'static str {
        match self {
            Arithmetic::Only | Arithmetic::Separate => "",
            Arithmetic::Fused => "fused_",
        }
    }

    fn name(self) -> &'static str {
        match self {
            Arithmetic::Only => "only",
            Arithmetic::Separate => "separate",
            Arithmetic::Fused => "fused",
        }
    }
}

/// Replaces the library calls of a generated C file by the Rust kernels' own sine, cosine and
/// arc tangent (src/lib.rs defines them), so the test compares two programs, not two maths
/// libraries. Every library call is `= sin(…)`, `= cos(…)` or `= atan(…)` (`sinf`, ...) in the
/// emitted code (the `double` kernels' own `c5_sin_cos` inside π/4 stays); the square root and
/// `fma` are correctly rounded everywhere.
fn own_trigonometry(source: &Path) {
    let text = std::fs::read_to_string(source).unwrap();
    let text = ["sin", "cos", "atan", "sinf", "cosf", "atanf"]
        .iter()
        .fold(text, |t, f| {
            t.replace(&format!("= {f}("), &format!("= c5_test_{f}("))
        });
    let text = text.replace(
        "#include <math.h>",
        "double fabs(double);\ndouble sqrt(double);\nfloat sqrtf(float);\n\
         double fma(double, double, double);\n\
         double c5_test_sin(double);\ndouble c5_test_cos(double);\n\
         double c5_test_atan(double);\n\
         float c5_test_sinf(float);\nfloat c5_test_cosf(float);\n\
         float c5_test_atanf(float);",
    );
    std::fs::write(source, text).unwrap();
}

/// A copy of the generated `{stem}.c` and `{stem}.h` with every name that starts with `from`
/// starting with `to` instead (the functions, the file names, the `#include`): the same kernels
/// under another prefix, without generating them again.
fn renamed(out: &Path, stem: &str, from: &str, to: &str) -> PathBuf {
    let new_stem = stem.replacen(from, to, 1);
    for ext in ["c", "h"] {
        let text = std::fs::read_to_string(out.join(format!("{stem}.{ext}"))).unwrap();
        std::fs::write(
            out.join(format!("{new_stem}.{ext}")),
            text.replace(from, to),
        )
        .unwrap();
    }
    out.join(format!("{new_stem}.c"))
}

fn main() {
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    let mut sources = Vec::new();
    let mut table = String::new();
    let mut code = String::from(
        "// Written by build.rs: FFI adapters of the C kernels and the Rust kernels.\n",
    );
    let mut fused_sources = Vec::new();
    let mut native = Vec::new();
    for model in Model::ALL {
        for scalar in [Scalar::F64, Scalar::F32] {
            // One generation per model and scalar: the separate and the fused arithmetic are the
            // same C source (`C5_FMA` is chosen when it is compiled), under two prefixes.
            let naming = Naming::with_scalar_suffix(&format!("c5_{model}_"), scalar);
            let stem = format!("c5_{model}_{}", scalar.name());
            let config = config(&out, model, scalar, &stem, &naming);
            config.generate().unwrap();
            let signatures = config.signatures().unwrap();
            let paths: &[Arithmetic] = match scalar {
                Scalar::F64 => &[Arithmetic::Separate, Arithmetic::Fused],
                Scalar::F32 => &[Arithmetic::Only],
            };
            if scalar == Scalar::F64 {
                // For the bench: the kernels as a user would build them, with the C library.
                native.push(renamed(
                    &out,
                    &stem,
                    &format!("c5_{model}_"),
                    &format!("native_{model}_"),
                ));
            }
            for &path in paths {
                let (source, naming) = match path {
                    Arithmetic::Fused => {
                        let prefix = format!("c5_fused_{model}_");
                        let source = renamed(&out, &stem, &naming.prefix, &prefix);
                        let naming = Naming {
                            prefix,
                            suffix: String::new(),
                        };
                        (source, naming)
                    }
                    _ => (out.join(format!("{stem}.c")), naming.clone()),
                };
                own_trigonometry(&source);
                if path == Arithmetic::Fused {
                    fused_sources.push(source);
                } else {
                    sources.push(source);
                }
                for spec in &signatures {
                    let id = adapters(&mut code, spec, model, scalar, &naming, path);
                    let inputs: Vec<String> = spec
                        .inputs
                        .iter()
                        .map(|(name, _)| format!("{name:?}"))
                        .collect();
                    let _ = writeln!(
                        table,
                        "    Kernel {{ model: {:?}, scalar: {:?}, path: {:?}, name: {:?}, inputs: &[{}], c: c_{id}, rust: rust_{id} }},",
                        model.name(),
                        scalar.name(),
                        path.name(),
                        spec.name,
                        inputs.join(", ")
                    );
                }
            }
        }
    }
    let _ = write!(code, "pub const KERNELS: &[Kernel] = &[\n{table}];\n");
    std::fs::write(out.join("ffi.rs"), code).unwrap();
    // The C kernels call the Rust kernels' own sine and cosine (src/lib.rs defines them), so
    // what the test compares is the two programs, not two maths libraries.
    cc::Build::new()
        .files(&sources)
        .include(&out)
        .std("c99")
        .opt_level(2)
        .flag("-ffp-contract=off")
        .warnings(true)
        .extra_warnings(true)
        .warnings_into_errors(true)
        .compile("c5kernels");
    // The FMA twins: `C5_FMA` is C's `fma`, an instruction with `-mfma`.
    cc::Build::new()
        .files(&fused_sources)
        .include(&out)
        .std("c99")
        .opt_level(2)
        .define("C5_FUSED_MULTIPLY_ADD", None)
        .flag_if_supported("-mfma")
        .flag("-ffp-contract=off")
        .warnings(true)
        .extra_warnings(true)
        .warnings_into_errors(true)
        .compile("c5kernels_fused");
    // The baseline: the same inverse dynamics written with SymPy (sympy/generate.py).
    // `paper_by_legs`: the paper model as the chapter computes it, leg by leg.
    let baselines = ["consistent", "paper", "paper_by_legs"];
    let sympy = baselines.map(|b| PathBuf::from(format!("sympy/sympy_{b}.c")));
    native.extend(sympy.iter().cloned());
    cc::Build::new()
        .files(&native)
        .include(&out)
        .std("c99")
        .opt_level(3)
        .flag("-march=native")
        .compile("c5native");
    // The SymPy baseline again in GCC's default GNU mode, which contracts `a * b + c` into
    // fused multiply-adds (`-ffp-contract=fast`; `-std=c99` turns that off): what a user who
    // types `gcc -O3 -march=native` gets. Its functions are renamed `sympy_gnu_*`.
    let mut gnu = cc::Build::new();
    gnu.files(&sympy).opt_level(3).flag("-march=native");
    for baseline in baselines {
        gnu.define(
            &format!("sympy_{baseline}_inverse_dynamics"),
            Some(format!("sympy_gnu_{baseline}_inverse_dynamics").as_str()),
        );
    }
    gnu.compile("c5sympygnu");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=sympy");
}
