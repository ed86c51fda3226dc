//! Emission of compiled kernels as C99: a header and a source file, from the same programs as
//! the Rust output, so the operation counts are the same and the results agree bit for bit
//! (with floating-point contraction off: `-ffp-contract=off`).
//!
//! Each kernel is a `void` function with `const` fixed-size array inputs and its outputs
//! through arrays the caller provides; only `<math.h>`, no allocation, no global state. The
//! instructions come in [`schedule`]'s order (GCC runs them in the order it reads them), the
//! same instructions as the Rust kernel's.

use crate::dag::Func;
use crate::emit::{kernel_doc, Scalar};
use crate::fuse::{self, Fused};
use crate::kernel::{Arg, Compiled, KernelSpec, Shape};
use crate::lower::{Instr, Operand};
use crate::schedule::{schedule, schedule_order};
use std::fmt::Write;

/// How the C functions are named: `{prefix}{kernel}{suffix}`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Naming {
    pub prefix: String,
    pub suffix: String,
}

impl Naming {
    /// `{prefix}{kernel}`, with `_f` appended for `float` kernels (as C's `sinf`), so both
    /// precisions link into one program.
    pub fn with_scalar_suffix(prefix: &str, scalar: Scalar) -> Self {
        Naming {
            prefix: prefix.to_string(),
            suffix: match scalar {
                Scalar::F64 => String::new(),
                Scalar::F32 => "_f".to_string(),
            },
        }
    }

    pub fn function(&self, kernel: &str) -> String {
        format!("{}{kernel}{}", self.prefix, self.suffix)
    }
}

fn c_type(scalar: Scalar) -> &'static str {
    match scalar {
        Scalar::F64 => "double",
        Scalar::F32 => "float",
    }
}

/// A literal that reads back as exactly `v` in the scalar type.
fn literal(scalar: Scalar, v: f64) -> String {
    let body = match scalar {
        Scalar::F64 => format!("{:?}", v.abs()),
        Scalar::F32 => format!("{:?}f", v.abs() as f32),
    };
    if v < 0.0 {
        format!("(-{body})")
    } else {
        body
    }
}

fn dims(shape: Shape) -> String {
    match shape {
        Shape::Vector(n) => format!("[{n}]"),
        Shape::Matrix(r, c) => format!("[{r}][{c}]"),
    }
}

/// `a[i]` or `a[r][c]` for the `k`-th element in row-major order.
fn element(arg: &Arg, k: usize) -> String {
    match arg.shape {
        Shape::Vector(_) => format!("{}[{k}]", arg.name),
        Shape::Matrix(_, c) => format!("{}[{}][{}]", arg.name, k / c, k % c),
    }
}

fn signature(spec: &KernelSpec, scalar: Scalar, naming: &Naming) -> String {
    let ty = c_type(scalar);
    let mut params: Vec<String> = spec
        .inputs
        .iter()
        .map(|a| format!("const {ty} {}{}", a.name, dims(a.shape)))
        .collect();
    params.extend(
        spec.outputs
            .iter()
            .map(|a| format!("{ty} {}{}", a.name, dims(a.shape))),
    );
    format!(
        "void {}({})",
        naming.function(&spec.name),
        params.join(", ")
    )
}

/// The doc comment of a kernel as a C block comment: the Rust kernel's text, the outputs said
/// to be written through the arrays given.
fn doc_comment(spec: &KernelSpec, compiled: &Compiled) -> String {
    let doc = kernel_doc(spec, compiled).replace(" # Returns", " # Outputs (written)");
    let mut out = String::from("/**\n");
    for line in doc.lines() {
        let line = line.strip_prefix(' ').unwrap_or(line);
        if line.is_empty() {
            out.push_str(" *\n");
        } else {
            // `*/` cannot appear inside a block comment.
            let _ = writeln!(out, " * {}", line.replace("*/", "* /"));
        }
    }
    out.push_str(" */\n");
    out
}

/// The header: include guard, `extern "C"` for C++, one documented prototype per kernel.
pub fn emit_header(
    banner: &str,
    guard: &str,
    kernels: &[(&KernelSpec, &Compiled)],
    scalar: Scalar,
    naming: &Naming,
) -> String {
    let mut out = String::new();
    out.push_str(banner);
    let _ = write!(
        out,
        "\n#ifndef {guard}\n#define {guard}\n\n#ifdef __cplusplus\nextern \"C\" {{\n#endif\n\n"
    );
    for (spec, compiled) in kernels {
        out.push_str(&doc_comment(spec, compiled));
        let _ = writeln!(out, "{};\n", signature(spec, scalar, naming));
    }
    let _ = write!(
        out,
        "#ifdef __cplusplus\n}}\n#endif\n\n#endif /* {guard} */\n"
    );
    out
}

fn emit_function(
    spec: &KernelSpec,
    compiled: &Compiled,
    scalar: Scalar,
    naming: &Naming,
    fused: bool,
) -> String {
    let ty = c_type(scalar);
    let order = schedule_order(&compiled.program);
    let program = schedule(&compiled.program);
    // The Rust twin's plan, carried through the scheduled order: the same products fused.
    let fusion = fused.then(|| fuse::plan(&compiled.program).permuted(&order));
    let used = program.used_inputs();
    let mut out = signature(spec, scalar, naming);
    out.push_str("\n{\n");
    // An element's local takes its name, unless an argument has it (the pose's `gamma` and
    // the forces `gamma`).
    let arguments: Vec<&str> = spec
        .inputs
        .iter()
        .chain(&spec.outputs)
        .map(|a| a.name.as_str())
        .collect();
    let mut inputs: Vec<String> = Vec::new();
    for arg in &spec.inputs {
        let mut any = false;
        for (k, name) in arg.elements.iter().enumerate() {
            let local = if arguments.contains(&name.as_str()) {
                format!("{name}_")
            } else {
                name.clone()
            };
            if used.contains(&(inputs.len() as u32)) {
                let _ = writeln!(out, "    const {ty} {local} = {};", element(arg, k));
                any = true;
            }
            inputs.push(local);
        }
        if !any {
            let _ = writeln!(out, "    (void){};", arg.name);
        }
    }
    let operand = |o: Operand| match o {
        Operand::Temp(i) => format!("t{i}"),
        Operand::Input(i) => inputs[i as usize].clone(),
        Operand::Const(c) => literal(scalar, c.get()),
    };
    let call = |name: &str| match scalar {
        Scalar::F64 => name.to_string(),
        Scalar::F32 => format!("{name}f"),
    };
    for (i, instr) in program.instrs.iter().enumerate() {
        if let Some(fusion) = &fusion {
            if fusion.absorbed[i] {
                continue;
            }
            let fused = match fusion.fused[i] {
                Some(Fused::MulAdd(a, b, c)) => Some((operand(a), operand(b), operand(c))),
                Some(Fused::MulSub(a, b, c)) => {
                    Some((operand(a), operand(b), format!("-{}", operand(c))))
                }
                Some(Fused::NegMulAdd(a, b, c)) => {
                    Some((format!("-{}", operand(a)), operand(b), operand(c)))
                }
                None => None,
            };
            if let Some((a, b, c)) = fused {
                let _ = writeln!(out, "    const {ty} t{i} = C5_FMA({a}, {b}, {c});");
                continue;
            }
        }
        let rhs = match *instr {
            Instr::Add(a, b) => format!("{} + {}", operand(a), operand(b)),
            Instr::Sub(a, b) => format!("{} - {}", operand(a), operand(b)),
            Instr::Mul(a, b) => format!("{} * {}", operand(a), operand(b)),
            Instr::Div(a, b) => format!("{} / {}", operand(a), operand(b)),
            Instr::Neg(a) => format!("-{}", operand(a)),
            Instr::Call(Func::Sign, a) => {
                let (a, zero) = (operand(a), literal(scalar, 0.0));
                format!("({ty})(({a} > {zero}) - ({a} < {zero}))")
            }
            Instr::Call(f, a) => format!("{}({})", call(f.name()), operand(a)),
            Instr::SinCos(a) if scalar == Scalar::F64 => {
                let _ = writeln!(out, "    double t{i}, t{};", i + 1);
                let _ = writeln!(out, "    c5_sin_cos({}, &t{i}, &t{});", operand(a), i + 1);
                continue;
            }
            Instr::PairedCos(_) if scalar == Scalar::F64 => continue,
            // C99 has no `sincosf`; compilers fuse the pair themselves.
            Instr::SinCos(a) => format!("{}({})", call("sin"), operand(a)),
            Instr::PairedCos(a) => format!("{}({})", call("cos"), operand(a)),
        };
        let _ = writeln!(out, "    const {ty} t{i} = {rhs};");
    }
    let mut k = 0;
    for arg in &spec.outputs {
        for e in 0..arg.shape.len() {
            let _ = writeln!(
                out,
                "    {} = {};",
                element(arg, e),
                operand(program.outputs[k])
            );
            k += 1;
        }
    }
    out.push_str("}\n");
    out
}

/// The sine and cosine of one argument for the `double` kernels. Within `π/4` (where the
/// robot's angles mostly are) fdlibm's kernel polynomials inline, exactly what musl's `sincos`
/// and the Rust kernels (`c5_generated::eighth_turn`) compute there; outside, the C library's `sin`
/// and `cos`. The C library's own `sincos`, which compilers call for a `sin`-`cos` pair, cost
/// glibc twice the time of the `libm` crate's on this project's machine (30 against 14 ns for
/// the kernels' three pairs), about the whole gap there was between the C and the Rust kernels.
const SIN_COS: &str = r#"
/* sin x and cos x: fdlibm's kernels within pi/4, as musl's sincos computes them there (and the
 * Rust kernels); the C library's sin and cos outside. */
static inline void c5_sin_cos(double x, double *s, double *c)
{
    if (fabs(x) <= 0.78539816339744830962) {
        const double z = x * x, w = z * z;
        const double rs = 8.33333333332248946124e-03 + z * (-1.98412698298579493134e-04
            + z * 2.75573137070700676789e-06) + z * w * (-2.50507602534068634195e-08
            + z * 1.58969099521155010221e-10);
        const double rc = z * (4.16666666666666019037e-02 + z * (-1.38888888888741095749e-03
            + z * 2.48015872894767294178e-05)) + w * w * (-2.75573143513906633035e-07
            + z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11));
        const double hz = 0.5 * z, one_minus_hz = 1.0 - hz;
        *s = z == 0.0 ? x : x + z * x * (-1.66666666666666324348e-01 + z * rs);
        *c = one_minus_hz + (((1.0 - one_minus_hz) - hz) + z * rc);
    } else {
        *s = sin(x);
        *c = cos(x);
    }
}
"#;

/// The product-plus-sums the Rust kernels' FMA twins fuse.
const FMA: &str = r#"
/* C5_FMA(a, b, c) = a * b + c. Defining C5_FUSED_MULTIPLY_ADD makes it C's fma, one rounding:
 * the Rust kernels' FMA twins (`{kernel}_fused`), bit for bit (build with -mfma or
 * -march=native so fma is an instruction, not a call). Otherwise a product then a sum: their
 * separate path (`{kernel}_separate`), bit for bit with -ffp-contract=off. */
#ifndef C5_FMA
#ifdef C5_FUSED_MULTIPLY_ADD
#define C5_FMA(a, b, c) fma((a), (b), (c))
#else
#define C5_FMA(a, b, c) ((a) * (b) + (c))
#endif
#endif
"#;

/// The source file: the header's include, `<math.h>`, one function per kernel. With `fused`
/// (`double` kernels only), the products the Rust FMA twins fuse are written `C5_FMA(a, b, c)`.
pub fn emit_source(
    banner: &str,
    header_name: &str,
    kernels: &[(&KernelSpec, &Compiled)],
    scalar: Scalar,
    naming: &Naming,
    fused: bool,
) -> String {
    let fused = fused && scalar == Scalar::F64;
    let mut out = String::new();
    out.push_str(banner);
    let _ = write!(out, "\n#include <math.h>\n\n#include \"{header_name}\"\n");
    if scalar == Scalar::F64 {
        out.push_str(SIN_COS);
    }
    if fused {
        out.push_str(FMA);
    }
    for (spec, compiled) in kernels {
        out.push('\n');
        out.push_str(&emit_function(spec, compiled, scalar, naming, fused));
    }
    out
}

/// A `//` banner as a `/* */` one for C.
pub fn c_banner(rust_banner: &str) -> String {
    let mut out = String::from("/*\n");
    for line in rust_banner.lines() {
        let line = line.strip_prefix("//").unwrap_or(line);
        let _ = writeln!(out, " *{}", line.replace("*/", "* /"));
    }
    out.push_str(" */\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_read_back_exactly() {
        for v in [0.1, -2.0, 1e-5, 0.1667, 9.81, -1.0 / 3.0, 1e300] {
            let text = literal(Scalar::F64, v);
            let parsed: f64 = text
                .trim_start_matches("(-")
                .trim_end_matches(')')
                .parse()
                .unwrap();
            assert_eq!(if v < 0.0 { -parsed } else { parsed }, v, "{text}");
            assert!(
                text.contains('.') || text.contains('e'),
                "{text} is a double"
            );
        }
        assert_eq!(literal(Scalar::F32, 0.5), "0.5f");
        assert_eq!(literal(Scalar::F32, -2.0), "(-2.0f)");
    }
}
