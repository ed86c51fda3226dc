//! Emission of compiled kernels as formatted Rust through `quote` and `prettyplease`.

use crate::dag::Func;
use crate::error::Error;
use crate::kernel::{Compiled, KernelSpec, Shape};
use crate::lower::{Instr, Operand};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

/// How emitted Rust calls the elementary functions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrigCalls {
    /// Methods, `x.sin()`, `x.sin_cos()`: the standard library's (or a trait's in scope).
    #[default]
    Methods,
    /// Free functions `sin(x)`, `cos(x)`, `sqrt(x)`, `sin_cos(x)` the including module
    /// provides (the `c5-generated` crate picks `std` or `libm` there).
    Functions,
}

/// Floating-point type of the emitted kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    F64,
    F32,
}

impl Scalar {
    pub fn name(self) -> &'static str {
        match self {
            Scalar::F64 => "f64",
            Scalar::F32 => "f32",
        }
    }

    fn ty(self) -> TokenStream {
        match self {
            Scalar::F64 => quote!(f64),
            Scalar::F32 => quote!(f32),
        }
    }

    fn literal(self, v: f64) -> TokenStream {
        let lit = match self {
            Scalar::F64 => Literal::f64_unsuffixed(v.abs()),
            Scalar::F32 => Literal::f32_unsuffixed(v.abs() as f32),
        };
        if v < 0.0 {
            quote!(-#lit)
        } else {
            quote!(#lit)
        }
    }
}

fn ident(name: &str) -> Ident {
    Ident::new(name, Span::call_site())
}

fn array_type(shape: Shape, ty: &TokenStream) -> TokenStream {
    let len = Literal::usize_unsuffixed;
    match shape {
        Shape::Vector(n) => {
            let n = len(n);
            quote!([#ty; #n])
        }
        Shape::Matrix(r, c) => {
            let (r, c) = (len(r), len(c));
            quote!([[#ty; #c]; #r])
        }
    }
}

fn array_value(shape: Shape, items: &[TokenStream]) -> TokenStream {
    match shape {
        Shape::Vector(_) => quote!([#(#items),*]),
        Shape::Matrix(_, c) => {
            let rows = items.chunks(c).map(|row| quote!([#(#row),*]));
            quote!([#(#rows),*])
        }
    }
}

/// The doc comment of a kernel: what it computes, its equations and its counted operations.
pub fn kernel_doc(spec: &KernelSpec, compiled: &Compiled) -> String {
    let mut doc = format!(" {}\n\n", spec.title);
    doc.push_str(&format!(
        " Equations: {}. Setting: {}.\n",
        spec.equations.join(", "),
        spec.setting
    ));
    if !spec.doc.is_empty() {
        doc.push('\n');
        for line in spec.doc.lines() {
            doc.push_str(&format!(" {line}\n"));
        }
    }
    doc.push_str("\n # Arguments\n\n");
    for a in &spec.inputs {
        doc.push_str(&format!(" - `{}`: {}\n", a.name, a.doc));
    }
    doc.push_str("\n # Returns\n\n");
    for a in &spec.outputs {
        doc.push_str(&format!(" - `{}`: {}\n", a.name, a.doc));
    }
    doc.push_str(&format!("\n Operations: {}.", compiled.count));
    if let Some(ch) = spec.chapter {
        doc.push_str(&format!(" The chapter: {}m + {}a.", ch.m, ch.a));
    }
    doc
}

/// Emits one kernel as a function item.
pub fn emit_kernel(
    spec: &KernelSpec,
    compiled: &Compiled,
    scalar: Scalar,
    trig: TrigCalls,
) -> TokenStream {
    let ty = scalar.ty();
    let used = compiled.program.used_inputs();
    let mut input_names: Vec<String> = Vec::new();
    let mut params = Vec::new();
    let mut destructure = Vec::new();
    for arg in &spec.inputs {
        let base = input_names.len();
        input_names.extend(arg.elements.iter().cloned());
        let name = ident(&arg.name);
        let t = array_type(arg.shape, &ty);
        params.push(quote!(#name: &#t));
        let pats: Vec<TokenStream> = arg
            .elements
            .iter()
            .enumerate()
            .map(|(k, e)| {
                if used.contains(&((base + k) as u32)) {
                    let e = ident(e);
                    quote!(#e)
                } else {
                    quote!(_)
                }
            })
            .collect();
        if pats.iter().any(|p| p.to_string() != "_") {
            let pat = array_value(arg.shape, &pats);
            destructure.push(quote!(let #pat = *#name;));
        } else {
            let unused = ident(&format!("_{}", arg.name));
            params.pop();
            params.push(quote!(#unused: &#t));
        }
    }
    let operand = |o: Operand| -> TokenStream {
        match o {
            Operand::Temp(i) => {
                let t = ident(&format!("t{i}"));
                quote!(#t)
            }
            Operand::Input(i) => {
                let n = ident(&input_names[i as usize]);
                quote!(#n)
            }
            Operand::Const(c) => scalar.literal(c.get()),
        }
    };
    let call = |name: &str, a: TokenStream| {
        let f = ident(name);
        match trig {
            TrigCalls::Methods => quote!(#a.#f()),
            TrigCalls::Functions => quote!(#f(#a)),
        }
    };
    let body = compiled
        .program
        .instrs
        .iter()
        .enumerate()
        .filter(|(_, instr)| !matches!(instr, Instr::PairedCos(_)))
        .map(|(i, instr)| {
            let t = ident(&format!("t{i}"));
            if let Instr::SinCos(a) = *instr {
                let c = ident(&format!("t{}", i + 1));
                let rhs = call("sin_cos", operand(a));
                return quote!(let (#t, #c): (#ty, #ty) = #rhs;);
            }
            let rhs = match *instr {
                Instr::Add(a, b) => {
                    let (a, b) = (operand(a), operand(b));
                    quote!(#a + #b)
                }
                Instr::Sub(a, b) => {
                    let (a, b) = (operand(a), operand(b));
                    quote!(#a - #b)
                }
                Instr::Mul(a, b) => {
                    let (a, b) = (operand(a), operand(b));
                    quote!(#a * #b)
                }
                Instr::Div(a, b) => {
                    let (a, b) = (operand(a), operand(b));
                    quote!(#a / #b)
                }
                Instr::Neg(a) => {
                    let a = operand(a);
                    quote!(-#a)
                }
                Instr::Call(Func::Sign, a) => {
                    let a = operand(a);
                    quote!(((#a > 0.0) as i8 - (#a < 0.0) as i8) as #ty)
                }
                Instr::Call(f, a) => call(f.name(), operand(a)),
                Instr::SinCos(_) | Instr::PairedCos(_) => unreachable!("handled above"),
            };
            quote!(let #t: #ty = #rhs;)
        });
    let mut outs = Vec::new();
    let mut out_types = Vec::new();
    let mut k = 0;
    for arg in &spec.outputs {
        let n = arg.shape.len();
        let items: Vec<TokenStream> = compiled.program.outputs[k..k + n]
            .iter()
            .map(|&o| operand(o))
            .collect();
        k += n;
        outs.push(array_value(arg.shape, &items));
        out_types.push(array_type(arg.shape, &ty));
    }
    let (ret_ty, ret) = if outs.len() == 1 {
        (out_types[0].clone(), outs[0].clone())
    } else {
        (quote!((#(#out_types),*)), quote!((#(#outs),*)))
    };
    // One attribute per line, so the doc prints as `///` lines.
    let doc = kernel_doc(spec, compiled);
    let doc_lines = doc.lines().map(|l| quote!(#[doc = #l]));
    let name = ident(&spec.name);
    quote! {
        #(#doc_lines)*
        #[inline]
        pub fn #name(#(#params),*) -> #ret_ty {
            #(#destructure)*
            #(#body)*
            #ret
        }
    }
}

/// Emits a whole file: the header, then one function per kernel, formatted.
pub fn emit_file(
    header: &str,
    kernels: &[(&KernelSpec, &Compiled)],
    scalar: Scalar,
    trig: TrigCalls,
) -> Result<String, Error> {
    let items = kernels.iter().map(|(s, c)| emit_kernel(s, c, scalar, trig));
    let tokens = quote!(#(#items)*);
    let file: syn::File = syn::parse2(tokens).map_err(|e| Error::Emit {
        kernel: kernels
            .iter()
            .map(|k| k.0.name.clone())
            .collect::<Vec<_>>()
            .join(", "),
        message: e.to_string(),
    })?;
    Ok(format!("{header}\n{}", prettyplease::unparse(&file)))
}

/// The lane type of a batch kernel (defined in `c5-generated`'s `lanes` module).
pub fn lane_type(scalar: Scalar) -> (&'static str, usize) {
    match scalar {
        Scalar::F64 => ("F64x4", 4),
        Scalar::F32 => ("F32x8", 8),
    }
}

/// Emits a kernel's batch version, `{name}_x{lanes}`: the same program run on several states at
/// once, one lane each, in structure-of-arrays form (`pose[k][lane]`). Robot parameters stay
/// scalars. Every lane computes exactly what the single-state kernel computes.
///
/// # Errors
/// A kernel with a matrix input or output (batch kernels take and give vectors).
pub fn emit_batch_kernel(
    spec: &KernelSpec,
    compiled: &Compiled,
    scalar: Scalar,
) -> Result<TokenStream, Error> {
    let (lane_name, lanes) = lane_type(scalar);
    let lane = ident(lane_name);
    let ty = scalar.ty();
    let n = Literal::usize_unsuffixed(lanes);
    if spec
        .inputs
        .iter()
        .chain(&spec.outputs)
        .any(|a| matches!(a.shape, Shape::Matrix(..)))
    {
        return Err(Error::Emit {
            kernel: spec.name.clone(),
            message: "a batch kernel takes and gives vectors only".to_string(),
        });
    }
    let used = compiled.program.used_inputs();
    let mut input_names: Vec<String> = Vec::new();
    let mut params = Vec::new();
    let mut destructure = Vec::new();
    for arg in &spec.inputs {
        let base = input_names.len();
        input_names.extend(arg.elements.iter().cloned());
        let name = ident(&arg.name);
        let len = Literal::usize_unsuffixed(arg.shape.len());
        let scalar_arg = arg.name == "params";
        params.push(if scalar_arg {
            quote!(#name: &[#ty; #len])
        } else {
            quote!(#name: &[[#ty; #n]; #len])
        });
        for (k, e) in arg.elements.iter().enumerate() {
            if used.contains(&((base + k) as u32)) {
                let e = ident(e);
                let k = Literal::usize_unsuffixed(k);
                destructure.push(if scalar_arg {
                    quote!(let #e = #lane::splat(#name[#k]);)
                } else {
                    quote!(let #e = #lane(#name[#k]);)
                });
            }
        }
    }
    let operand = |o: Operand| -> TokenStream {
        match o {
            Operand::Temp(i) => {
                let t = ident(&format!("t{i}"));
                quote!(#t)
            }
            Operand::Input(i) => {
                let e = ident(&input_names[i as usize]);
                quote!(#e)
            }
            Operand::Const(c) => {
                let lit = scalar.literal(c.get());
                quote!(#lane::splat(#lit))
            }
        }
    };
    let mut body = Vec::new();
    for (i, instr) in compiled.program.instrs.iter().enumerate() {
        let t = ident(&format!("t{i}"));
        let rhs = match *instr {
            Instr::Add(a, b) => {
                let (a, b) = (operand(a), operand(b));
                quote!(#a + #b)
            }
            Instr::Sub(a, b) => {
                let (a, b) = (operand(a), operand(b));
                quote!(#a - #b)
            }
            Instr::Mul(a, b) => {
                let (a, b) = (operand(a), operand(b));
                quote!(#a * #b)
            }
            Instr::Div(a, b) => {
                let (a, b) = (operand(a), operand(b));
                quote!(#a / #b)
            }
            Instr::Neg(a) => {
                let a = operand(a);
                quote!(-#a)
            }
            Instr::Call(f, a) => {
                let (a, f) = (operand(a), ident(f.name()));
                quote!(#a.#f())
            }
            Instr::SinCos(a) => {
                let c = ident(&format!("t{}", i + 1));
                let a = operand(a);
                body.push(quote!(let (#t, #c) = #a.sin_cos();));
                continue;
            }
            Instr::PairedCos(_) => continue,
        };
        body.push(quote!(let #t: #lane = #rhs;));
    }
    let mut outs = Vec::new();
    let mut out_types = Vec::new();
    let mut k = 0;
    for arg in &spec.outputs {
        let len = arg.shape.len();
        let items: Vec<TokenStream> = compiled.program.outputs[k..k + len]
            .iter()
            .map(|&o| {
                let v = operand(o);
                quote!((#v).0)
            })
            .collect();
        k += len;
        let len = Literal::usize_unsuffixed(len);
        outs.push(quote!([#(#items),*]));
        out_types.push(quote!([[#ty; #n]; #len]));
    }
    let (ret_ty, ret) = if outs.len() == 1 {
        (out_types[0].clone(), outs[0].clone())
    } else {
        (quote!((#(#out_types),*)), quote!((#(#outs),*)))
    };
    let doc = format!(
        " The batch version of [`{}`]: {lanes} states at once, one lane each (`pose[k][lane]`), \
         each lane computing exactly what `{}` computes. {}",
        spec.name, spec.name, spec.title
    );
    let name = ident(&format!("{}_x{lanes}", spec.name));
    let portable = ident(&format!("{}_x{lanes}_lanes", spec.name));
    let args: Vec<Ident> = spec.inputs.iter().map(|a| ident(&a.name)).collect();
    // The lanes are written for any vector width; on x86 with `std`, a CPU with AVX2 runs them
    // four `f64` (eight `f32`) to an instruction instead of two (four). Separate roundings, no
    // fused multiply-add: every lane computes the same bits either way.
    Ok(quote! {
        #[doc = #doc]
        #[inline]
        pub fn #name(#(#params),*) -> #ret_ty {
            #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
            if std::is_x86_feature_detected!("avx2") {
                #[target_feature(enable = "avx2")]
                fn avx2(#(#params),*) -> #ret_ty {
                    // A lane vector in memory makes LLVM align the frame to the vector width
                    // before it allocates registers, so its spills are aligned too (else they
                    // straddle cache lines or not as the caller's stack falls: up to 30 %).
                    core::hint::black_box(&#lane::splat(0.0));
                    #portable(#(#args),*)
                }
                // SAFETY: the CPU has AVX2 (checked above), the one feature `avx2` assumes.
                return unsafe { avx2(#(#args),*) };
            }
            #portable(#(#args),*)
        }

        #[inline(always)]
        fn #portable(#(#params),*) -> #ret_ty {
            #(#destructure)*
            #(#body)*
            #ret
        }
    })
}

/// Emits a file of batch kernels.
///
/// # Errors
/// As [`emit_batch_kernel`], or emitted code that does not parse (a bug).
pub fn emit_batch_file(
    header: &str,
    kernels: &[(&KernelSpec, &Compiled)],
    scalar: Scalar,
) -> Result<String, Error> {
    let items = kernels
        .iter()
        .map(|(s, c)| emit_batch_kernel(s, c, scalar))
        .collect::<Result<Vec<_>, _>>()?;
    let tokens = quote!(#(#items)*);
    let file: syn::File = syn::parse2(tokens).map_err(|e| Error::Emit {
        kernel: "batch kernels".to_string(),
        message: e.to_string(),
    })?;
    Ok(format!("{header}\n{}", prettyplease::unparse(&file)))
}
