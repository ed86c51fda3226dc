//! Emission of compiled kernels as formatted Rust through `quote` and `prettyplease`.

use crate::blocks::{self, Let};
use crate::count::OpCount;
use crate::dag::Func;
use crate::error::Error;
use crate::fuse::Fusion;
use crate::kernel::{Arg, Compiled, KernelSpec, Shape};
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

/// The highest cost ([`OpCount::weight`]: its operations, a division 1.9, a sign change 0.25,
/// a call 20) of a kernel whose body is `#[inline]`.
///
/// An `#[inline]` body is compiled to machine code in every crate that calls it, and only
/// there: a small kernel then costs its caller no call and a crate nothing it does not call.
/// A larger one gains nothing from inlining (it is thousands of straight-line operations), and
/// each caller's copy was compiled again, with LLVM's time growing faster than its length: the
/// runtime, its unit tests and every test binary each compiled the hexapods' and the
/// derivatives' kernels. Above this size the body is compiled once, in the crate that holds it.
pub const INLINE_LIMIT: f64 = 1500.0;

/// `#[inline]` for a kernel that costs at most [`INLINE_LIMIT`], nothing for a dearer one.
fn inline_attribute(count: &OpCount) -> TokenStream {
    if count.weight() <= INLINE_LIMIT {
        quote!(#[inline])
    } else {
        TokenStream::new()
    }
}

/// Emits one kernel as a function item. With `fma`, three: `{name}_separate` (every operation
/// rounded on its own), `{name}_fused` (the products the [`crate::fuse`] plan folds, fused:
/// `mul_add` in a function compiled for FMA), and `{name}`, which runs the fused twin where
/// `fma` says the CPU has FMA, else the separate one. The two paths are one body, written
/// once in [`c5_fma_twin`]'s notation ([`FmaDispatch::twins`]).
pub fn emit_kernel(
    spec: &KernelSpec,
    compiled: &Compiled,
    scalar: Scalar,
    trig: TrigCalls,
    fma: Option<&FmaDispatch>,
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
    let read_after = compiled.program.output_temps();
    let body = |fusion: Option<&Fusion>| -> Vec<TokenStream> {
        let mut body = Vec::new();
        for (i, instr) in compiled.program.instrs.iter().enumerate() {
            let t = ident(&format!("t{i}"));
            let rhs = match fused_rhs(fusion, &compiled.program.instrs, i, &operand) {
                Fold::Product(product) => {
                    body.push(product);
                    continue;
                }
                Fold::Fused(rhs) => rhs,
                Fold::Separate => match *instr {
                    Instr::SinCos(a) => {
                        let c = ident(&format!("t{}", i + 1));
                        let rhs = call("sin_cos", operand(a));
                        body.push(Let {
                            binds: vec![i as u32, i as u32 + 1],
                            tokens: quote!(let (#t, #c): (#ty, #ty) = #rhs;),
                        });
                        continue;
                    }
                    Instr::PairedCos(_) => continue,
                    Instr::Call(Func::Sign, a) => {
                        let a = operand(a);
                        quote!(((#a > 0.0) as i8 - (#a < 0.0) as i8) as #ty)
                    }
                    Instr::Call(f, a) => call(f.name(), operand(a)),
                    other => arithmetic(other, &operand),
                },
            };
            body.push(Let {
                binds: vec![i as u32],
                tokens: quote!(let #t: #ty = #rhs;),
            });
        }
        blocks::nest(body, &read_after)
    };
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
    let inline = inline_attribute(&compiled.count);
    let mut doc = kernel_doc(spec, compiled);
    if inline.is_empty() {
        doc.push_str(&format!(
            "\n\n Its body is not `#[inline]`: a kernel that costs more than {INLINE_LIMIT} (its \
             operations, a division 1.9, a call 20) is compiled once, in the crate that holds it, \
             not again in each crate that calls it."
        ));
    }
    let doc_lines = doc.lines().map(|l| quote!(#[doc = #l]));
    let name = ident(&spec.name);
    let Some(fma) = fma else {
        let body = body(None);
        return quote! {
            #(#doc_lines)*
            #inline
            pub fn #name(#(#params),*) -> #ret_ty {
                #(#destructure)*
                #(#body)*
                #ret
            }
        };
    };
    let fusion = crate::fuse::plan(&compiled.program);
    let body = body(Some(&fusion));
    let separate_name = ident(&format!("{}_separate", spec.name));
    let fused_name = ident(&format!("{}_fused", spec.name));
    let args = param_names(&params);
    let (cfg, enabled) = (&fma.cfg, &fma.enabled);
    let separate_doc = format!(
        " [`{}`] with every operation rounded on its own: the same bits on every machine.",
        spec.name
    );
    let written_once = quote! {
        #[doc = #separate_doc]
        #inline
        pub fn #separate_name(#(#params),*) -> #ret_ty {
            #(#destructure)*
            #(#body)*
            #ret
        }
    };
    let paths = fma.twins(&fused_name, quote!(#ty::mul_add), written_once);
    quote! {
        #(#doc_lines)*
        #[inline]
        pub fn #name(#(#params),*) -> #ret_ty {
            #[cfg(#cfg)]
            if #enabled {
                // SAFETY: the CPU has FMA (checked just above), the one feature it assumes.
                return unsafe { #fused_name(#(#args),*) };
            }
            #separate_name(#(#args),*)
        }

        #paths
    }
}

/// Where a kernel's FMA twin exists and how the kernel decides to call it.
#[derive(Clone, Debug)]
pub struct FmaDispatch {
    /// The `cfg` predicate under which the twin is compiled.
    pub cfg: TokenStream,
    /// A `bool` expression: run the twin (true only where the CPU has FMA).
    pub enabled: TokenStream,
    /// The `#[fma_twin]` attribute that expands each kernel's body into its two paths where
    /// the file is compiled, and the `cfg` under which it does (`c5-generated`'s: its `fma`
    /// feature, from `c5-fma-twin-macro`; without it the body's marks are plain functions,
    /// `fma::marks`). `None`: the generator expands them itself (a crate of its own, which
    /// need not depend on the macro).
    pub twin_attribute: Option<(TokenStream, TokenStream)>,
}

impl FmaDispatch {
    /// For a crate of its own (a `build.rs` output): the standard library's detection, on x86.
    pub fn detected() -> Self {
        FmaDispatch {
            cfg: quote!(any(target_arch = "x86", target_arch = "x86_64")),
            enabled: quote!(std::is_x86_feature_detected!("fma")),
            twin_attribute: None,
        }
    }

    /// For `c5-generated`: its `fma` feature and switch (`crate::fma`).
    pub fn crate_switch() -> Self {
        FmaDispatch {
            cfg: quote!(all(
                feature = "fma",
                any(target_arch = "x86", target_arch = "x86_64")
            )),
            enabled: quote!(crate::fma::enabled()),
            twin_attribute: Some((quote!(feature = "fma"), quote!(fma_twin))),
        }
    }

    /// A function whose body is written once (its folded products marked, [`c5_fma_twin`]'s
    /// notation) and its FMA twin `twin`, whose fused multiply-add is `mul_add`, as the file
    /// writes them.
    fn twins(&self, twin: &Ident, mul_add: TokenStream, written_once: TokenStream) -> TokenStream {
        match &self.twin_attribute {
            Some((cfg, attribute)) => quote! {
                #[cfg_attr(#cfg, #attribute(#twin, #mul_add))]
                #written_once
            },
            None => c5_fma_twin::expand(quote!(#twin, #mul_add), written_once, &self.cfg)
                .expect("the generator writes a function with a body"),
        }
    }
}

/// The names of a function's parameters (`name: &T` items), to call it with them.
fn param_names(params: &[TokenStream]) -> Vec<TokenStream> {
    params
        .iter()
        .map(|p| {
            let name = p
                .clone()
                .into_iter()
                .next()
                .expect("a parameter has a name");
            quote!(#name)
        })
        .collect()
}

/// What an instruction becomes on a path.
enum Fold {
    /// A product that one sum reads and fuses: `let t = product(a, b);` ([`c5_fma_twin`]'s
    /// notation: its rounded value on the separate path, its factors on the FMA twin).
    Product(Let),
    /// A sum or difference with a product folded in: this right-hand side (`p.plus(c)`, ...).
    Fused(TokenStream),
    /// As it is.
    Separate,
}

/// Instruction `i` of `instrs` under `fusion` (`None`: every operation rounded on its own).
///
/// A body written once serves both paths ([`c5_fma_twin`]): a folded product stays where the
/// program computes it, as `product(a, b)`, and the sum that reads it is `p.plus(c)` (or
/// `added_to`, `minus`, `subtracted_from`). So each path keeps the program's order, and
/// compiles to what a body written for it alone would.
fn fused_rhs(
    fusion: Option<&Fusion>,
    instrs: &[Instr],
    i: usize,
    operand: &dyn Fn(Operand) -> TokenStream,
) -> Fold {
    let Some(fusion) = fusion else {
        return Fold::Separate;
    };
    if fusion.absorbed[i] {
        let Instr::Mul(a, b) = instrs[i] else {
            unreachable!("only products are folded into sums")
        };
        let (t, a, b) = (ident(&format!("t{i}")), operand(a), operand(b));
        return Fold::Product(Let {
            binds: vec![i as u32],
            tokens: quote!(let #t = product(#a, #b);),
        });
    }
    if fusion.fused[i].is_none() {
        return Fold::Separate;
    }
    // The product the sum folds in: the one operand that is a folded product (a product is
    // folded only where its one reader is this sum, so the other operand is not).
    let folded = |o: Operand| matches!(o, Operand::Temp(t) if fusion.absorbed[t as usize]);
    let rhs = match instrs[i] {
        Instr::Add(x, y) if folded(x) => {
            let (p, c) = (operand(x), operand(y));
            quote!(#p.plus(#c))
        }
        Instr::Add(x, y) => {
            let (c, p) = (operand(x), operand(y));
            quote!(#p.added_to(#c))
        }
        Instr::Sub(x, y) if folded(x) => {
            let (p, c) = (operand(x), operand(y));
            quote!(#p.minus(#c))
        }
        Instr::Sub(x, y) => {
            let (c, p) = (operand(x), operand(y));
            quote!(#p.subtracted_from(#c))
        }
        _ => unreachable!("only sums and differences fold a product"),
    };
    Fold::Fused(rhs)
}

/// The right-hand side of an arithmetic instruction.
fn arithmetic(instr: Instr, operand: &dyn Fn(Operand) -> TokenStream) -> TokenStream {
    match instr {
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
        Instr::Call(..) | Instr::SinCos(_) | Instr::PairedCos(_) => {
            unreachable!("calls are emitted by the caller")
        }
    }
}

/// Emits a whole file: the header, then one function per kernel, formatted.
///
/// With `fma`, each `f64` kernel gets an FMA twin and dispatches to it (see [`emit_kernel`]);
/// `f32` kernels have none.
pub fn emit_file(
    header: &str,
    kernels: &[(&KernelSpec, &Compiled)],
    scalar: Scalar,
    trig: TrigCalls,
    fma: Option<&FmaDispatch>,
) -> Result<String, Error> {
    let fma = fma.filter(|_| scalar == Scalar::F64);
    let items = kernels
        .iter()
        .map(|(s, c)| emit_kernel(s, c, scalar, trig, fma));
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
    // Batch kernels live in `c5-generated`, whose `fma` feature and switch they use.
    let fma = scalar == Scalar::F64;
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
    let read_after = compiled.program.output_temps();
    let name = ident(&format!("{}_x{lanes}", spec.name));
    let args: Vec<Ident> = spec.inputs.iter().map(|a| ident(&a.name)).collect();
    // `f64` lanes compute the sine-cosine pairs of the inputs in vector instructions when every
    // lane lies within an eighth of a turn, checked on entry, all at once: one branch ahead of any
    // arithmetic. A batch with a lane beyond goes state by state through the single kernel.
    // Choosing at each pair instead merged the two ways through memory (the paper model's batch
    // inverse dynamics 20 % slower), and checking at each pair split the blocks LLVM schedules
    // (6 %). Running the lanes a second time with the library's pairs would keep such a batch at
    // vector speed, at a third more build time for `c5-generated`.
    let mut on_entry: Vec<u32> = Vec::new();
    for instr in &compiled.program.instrs {
        if let Instr::SinCos(Operand::Input(k)) = *instr {
            if !on_entry.contains(&k) {
                on_entry.push(k);
            }
        }
    }
    let eighth_turn = scalar == Scalar::F64 && !on_entry.is_empty();
    let by_states = ident(&format!("{}_x{lanes}_by_states", spec.name));
    let by_states_fused = ident(&format!("{}_x{lanes}_by_states_fused", spec.name));
    let fma_cfg = FmaDispatch::crate_switch().cfg;
    // With a fusion plan (`f64`), one body for both paths (`c5_fma_twin`'s notation).
    let body = |fusion: Option<&Fusion>| -> Vec<TokenStream> {
        let mut body = Vec::new();
        if eighth_turn {
            let checks = on_entry.iter().map(|&k| {
                let x = operand(Operand::Input(k));
                quote!(#x.within_eighth_turn())
            });
            // The lanes' FMA path goes state by state through the single kernels' FMA twins.
            let fused_return = fusion.is_some().then(|| {
                quote! {
                    #[cfg(#fma_cfg)]
                    if FUSED {
                        // SAFETY: only the FMA twin, which the CPU's FMA gates, takes this.
                        return unsafe { #by_states_fused(#(#args),*) };
                    }
                }
            });
            body.push(Let {
                binds: Vec::new(),
                // `&`, not `&&`: the comparisons combine without a branch each.
                tokens: quote! {
                    if !(#(#checks)&*) {
                        #fused_return
                        return #by_states(#(#args),*);
                    }
                },
            });
        }
        for (i, instr) in compiled.program.instrs.iter().enumerate() {
            let t = ident(&format!("t{i}"));
            let rhs = match fused_rhs(fusion, &compiled.program.instrs, i, &operand) {
                Fold::Product(product) => {
                    body.push(product);
                    continue;
                }
                Fold::Fused(rhs) => rhs,
                Fold::Separate => match *instr {
                    Instr::Call(f, a) => {
                        let (a, f) = (operand(a), ident(f.name()));
                        quote!(#a.#f())
                    }
                    Instr::SinCos(a) => {
                        let c = ident(&format!("t{}", i + 1));
                        let checked = eighth_turn && matches!(a, Operand::Input(_));
                        let a = operand(a);
                        let tokens = if checked {
                            quote!(let (#t, #c) = #a.sin_cos_eighth_turn();)
                        } else {
                            quote!(let (#t, #c) = #a.sin_cos();)
                        };
                        body.push(Let {
                            binds: vec![i as u32, i as u32 + 1],
                            tokens,
                        });
                        continue;
                    }
                    Instr::PairedCos(_) => continue,
                    other => arithmetic(other, &operand),
                },
            };
            body.push(Let {
                binds: vec![i as u32],
                tokens: quote!(let #t: #lane = #rhs;),
            });
        }
        blocks::nest(body, &read_after)
    };
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
    let portable = ident(&format!("{}_x{lanes}_lanes", spec.name));
    // The FMA twin of the lanes: the single kernel's fusion plan, so each lane computes what
    // the single kernel's fused twin computes. One body, written once, is both.
    let fusion = fma.then(|| crate::fuse::plan(&compiled.program));
    let body = body(fusion.as_ref());
    let lanes_fn = quote! {
        #[inline(always)]
        fn #portable(#(#params),*) -> #ret_ty {
            #(#destructure)*
            #(#body)*
            #ret
        }
    };
    let (lanes_fns, dispatch) = if fma {
        let fused = ident(&format!("{}_x{lanes}_lanes_fused", spec.name));
        let switch = FmaDispatch::crate_switch();
        let FmaDispatch { cfg, enabled, .. } = &switch;
        let dispatch = quote! {
            #[cfg(#cfg)]
            if #enabled {
                if std::is_x86_feature_detected!("avx512vl") {
                    #[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
                    fn avx512_fma(#(#params),*) -> #ret_ty {
                        core::hint::black_box(&#lane::splat(0.0));
                        // SAFETY: compiled for FMA, called only where the CPU has it.
                        unsafe { #fused(#(#args),*) }
                    }
                    // SAFETY: the CPU has AVX-512VL (checked just above) and FMA (`enabled`).
                    return unsafe { avx512_fma(#(#args),*) };
                }
                #[target_feature(enable = "avx2,fma")]
                fn avx2_fma(#(#params),*) -> #ret_ty {
                    core::hint::black_box(&#lane::splat(0.0));
                    // SAFETY: compiled for FMA, called only where the CPU has it.
                    unsafe { #fused(#(#args),*) }
                }
                // SAFETY: `enabled` is true only where the CPU has FMA and AVX2.
                return unsafe { avx2_fma(#(#args),*) };
            }
        };
        // The twin is `unsafe`: its lanes' `mul_add` needs FMA, which only the dispatch above
        // checks.
        let lanes_fns = switch.twins(&fused, quote!(#lane::mul_add), lanes_fn);
        (lanes_fns, Some(dispatch))
    } else {
        (lanes_fn, None)
    };
    let separate = quote!(#portable(#(#args),*));
    let by_states_fns = eighth_turn.then(|| {
        let single = ident(&format!("{}_separate", spec.name));
        let single_fused = ident(&format!("{}_fused", spec.name));
        let (body, body_fused) = (
            by_states_body(spec, lanes, &single),
            by_states_body(spec, lanes, &single_fused),
        );
        let cfg = FmaDispatch::crate_switch().cfg;
        let doc = format!(
            " [`{name}`] state by state through [`{single}`], for a batch with an angle beyond an \
             eighth of a turn (π/4)."
        );
        let doc_fused = format!(" [`{by_states}`] through [`{single_fused}`].");
        quote! {
            #[doc = #doc]
            #[cold]
            #[inline(never)]
            fn #by_states(#(#params),*) -> #ret_ty {
                #body
            }

            #[doc = #doc_fused]
            ///
            /// # Safety
            /// The CPU must have FMA.
            #[cfg(#cfg)]
            #[cold]
            #[inline(never)]
            unsafe fn #by_states_fused(#(#params),*) -> #ret_ty {
                #body_fused
            }
        }
    });
    // The lanes are written for any vector width; on x86 with `std`, a CPU with AVX2 runs them
    // four `f64` (eight `f32`) to an instruction instead of two (four). On the FMA path (as the
    // single kernels take it) the lanes fuse what the single kernels fuse; on the other, every
    // operation is rounded on its own. Either way each lane computes the single kernel's bits.
    Ok(quote! {
        #[doc = #doc]
        #[inline]
        pub fn #name(#(#params),*) -> #ret_ty {
            #dispatch
            #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
            if std::is_x86_feature_detected!("avx2") {
                #[target_feature(enable = "avx2")]
                fn avx2(#(#params),*) -> #ret_ty {
                    // A lane vector in memory makes LLVM align the frame to the vector width
                    // before it allocates registers, so its spills are aligned too (else they
                    // straddle cache lines or not as the caller's stack falls: up to 30 %).
                    core::hint::black_box(&#lane::splat(0.0));
                    #separate
                }
                // SAFETY: the CPU has AVX2 (checked above), the one feature `avx2` assumes.
                return unsafe { avx2(#(#args),*) };
            }
            #separate
        }

        #lanes_fns

        #by_states_fns
    })
}

/// The body of a batch kernel run state by state: each lane's inputs gathered, the single kernel
/// `single` called on them, its results scattered back into the lanes.
fn by_states_body(spec: &KernelSpec, lanes: usize, single: &Ident) -> TokenStream {
    let n = Literal::usize_unsuffixed(lanes);
    let inputs = spec.inputs.iter().map(|a| {
        let name = ident(&a.name);
        // As in the batch signature: the robot's parameters are one for all lanes.
        if a.name == "params" {
            quote!(#name)
        } else {
            quote!(&core::array::from_fn(|k| #name[k][lane]))
        }
    });
    let outs: Vec<Ident> = (0..spec.outputs.len())
        .map(|k| ident(&format!("out{k}")))
        .collect();
    let states: Vec<Ident> = (0..spec.outputs.len())
        .map(|k| ident(&format!("state{k}")))
        .collect();
    let lens = spec
        .outputs
        .iter()
        .map(|a| Literal::usize_unsuffixed(a.shape.len()));
    let (pattern, ret) = match (&outs[..], &states[..]) {
        ([out], [state]) => (quote!(#state), quote!(#out)),
        _ => (quote!((#(#states),*)), quote!((#(#outs),*))),
    };
    quote! {
        #(let mut #outs = [[0.0; #n]; #lens];)*
        for lane in 0..#n {
            let #pattern = #single(#(#inputs),*);
            #(
                for (k, v) in #states.into_iter().enumerate() {
                    #outs[k][lane] = v;
                }
            )*
        }
        #ret
    }
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

/// The argument and return types of a kernel's function: `(name, type)` per input, and the
/// return type.
fn single_signature(spec: &KernelSpec, scalar: Scalar) -> (Vec<(Ident, TokenStream)>, TokenStream) {
    let ty = scalar.ty();
    let args = spec
        .inputs
        .iter()
        .map(|a| {
            let t = array_type(a.shape, &ty);
            (ident(&a.name), quote!(&#t))
        })
        .collect();
    let outs: Vec<TokenStream> = spec
        .outputs
        .iter()
        .map(|a| array_type(a.shape, &ty))
        .collect();
    (args, tuple_type(&outs))
}

fn tuple_type(items: &[TokenStream]) -> TokenStream {
    if items.len() == 1 {
        items[0].clone()
    } else {
        quote!((#(#items),*))
    }
}

/// The same for the batch form (`{name}_x{lanes}`).
fn batch_signature(spec: &KernelSpec, scalar: Scalar) -> (Vec<(Ident, TokenStream)>, TokenStream) {
    let ty = scalar.ty();
    let n = Literal::usize_unsuffixed(lane_type(scalar).1);
    let lanes = |a: &Arg| {
        let len = Literal::usize_unsuffixed(a.shape.len());
        quote!([[#ty; #n]; #len])
    };
    let args = spec
        .inputs
        .iter()
        .map(|a| {
            let t = if a.name == "params" {
                array_type(a.shape, &ty)
            } else {
                lanes(a)
            };
            (ident(&a.name), quote!(&#t))
        })
        .collect();
    let outs: Vec<TokenStream> = spec.outputs.iter().map(lanes).collect();
    (args, tuple_type(&outs))
}

/// One model's kernels in the kernel-set trait.
pub struct KernelSet<'a> {
    /// The module of the model's kernels (`consistent`); the type implementing the trait is
    /// the same name capitalised (`Consistent`).
    pub module: String,
    /// A line on the model, for the type's documentation.
    pub summary: String,
    /// The kernels every model shares.
    pub kernels: Vec<SetKernel<'a>>,
    /// The identification kernels (`f64` only, feature `regressor`): the regressor, then the
    /// base regressor whose width is the model's.
    pub regressors: Vec<&'a KernelSpec>,
    /// The derivative kernels (`f64` only, feature `derivatives`).
    pub derivatives: Vec<SetKernel<'a>>,
}

/// A kernel of a [`KernelSet`].
#[derive(Clone, Copy)]
pub struct SetKernel<'a> {
    pub spec: &'a KernelSpec,
    /// It also has a batch form (feature `batch`).
    pub batch: bool,
    /// The robot's parameters are folded in (feature `folded`): its file is
    /// `{module}_folded*.rs`, and its trait method exists with the feature.
    pub folded: bool,
}

impl SetKernel<'_> {
    /// The `cfg` of its trait method, `extra` (another feature) added.
    fn cfg(&self, extra: Option<&str>) -> TokenStream {
        let features: Vec<&str> = self
            .folded
            .then_some("folded")
            .into_iter()
            .chain(extra)
            .collect();
        match features.as_slice() {
            [] => quote!(),
            [one] => quote!(#[cfg(feature = #one)]),
            many => quote!(#[cfg(all(#(feature = #many),*))]),
        }
    }
}

fn type_name(module: &str) -> Ident {
    let mut chars = module.chars();
    let first = chars.next().map(|c| c.to_ascii_uppercase());
    ident(&first.into_iter().chain(chars).collect::<String>())
}

/// One trait method: its declaration, its implementation calling the model's kernel, and its
/// signature alone (to hold every model to the same).
struct Method {
    decl: TokenStream,
    body: TokenStream,
    signature: String,
    /// The method's attributes and signature, for another implementation.
    header: TokenStream,
    name: Ident,
    args: Vec<Ident>,
}

fn method(
    doc: &str,
    cfg: &TokenStream,
    name: &Ident,
    (args, ret): &(Vec<(Ident, TokenStream)>, TokenStream),
    call: TokenStream,
) -> Method {
    let params: Vec<TokenStream> = args.iter().map(|(n, t)| quote!(#n: #t)).collect();
    let signature = quote!(#cfg fn #name(&self, #(#params),*) -> #ret).to_string();
    let decl = quote!(#cfg #[doc = #doc] fn #name(&self, #(#params),*) -> #ret;);
    let header = quote!(#cfg #[inline] fn #name(&self, #(#params),*) -> #ret);
    let body = quote!(#header { #call });
    Method {
        decl,
        body,
        signature,
        header,
        name: name.clone(),
        args: args.iter().map(|(n, _)| n.clone()).collect(),
    }
}

/// The methods of one model's set, in the order of the trait.
fn methods(set: &KernelSet, scalar: Scalar) -> Vec<Method> {
    let module = ident(&set.module);
    let mut out = Vec::new();
    for kernel in &set.kernels {
        let spec = kernel.spec;
        let name = ident(&spec.name);
        let sig = single_signature(spec, scalar);
        let args = sig.0.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        let doc = format!(" {}", spec.title);
        out.push(method(
            &doc,
            &kernel.cfg(None),
            &name,
            &sig,
            quote!(#module::#name(#(#args),*)),
        ));
        if kernel.batch {
            let lanes = lane_type(scalar).1;
            let batched = ident(&format!("{}_x{lanes}", spec.name));
            let sig = batch_signature(spec, scalar);
            let doc = format!(
                " [`Kernels::{}`] of {lanes} states at once, one lane each (`pose[k][lane]`), \
                 each lane computing exactly what the single-state kernel computes.",
                spec.name
            );
            out.push(method(
                &doc,
                &kernel.cfg(Some("batch")),
                &batched,
                &sig,
                quote!(#module::#batched(#(#args),*)),
            ));
        }
    }
    if scalar == Scalar::F64 {
        for kernel in &set.derivatives {
            let spec = kernel.spec;
            let name = ident(&spec.name);
            let sig = single_signature(spec, scalar);
            let args = sig.0.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
            out.push(method(
                &format!(" {}", spec.title),
                &kernel.cfg(Some("derivatives")),
                &name,
                &sig,
                quote!(#module::#name(#(#args),*)),
            ));
        }
    }
    if scalar == Scalar::F64 {
        let cfg = quote!(#[cfg(feature = "regressor")]);
        for (k, spec) in set.regressors.iter().enumerate() {
            let name = ident(&spec.name);
            let (args, ret) = single_signature(spec, scalar);
            let names = args.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
            if k == 0 {
                let doc = format!(" {}", spec.title);
                out.push(method(
                    &doc,
                    &cfg,
                    &name,
                    &(args, ret),
                    quote!(#module::#name(#(#names),*)),
                ));
                continue;
            }
            // The base regressor's width is the model's number of base parameters: the trait
            // writes its rows into a slice, `None` if the slice has another length.
            let into = ident(&format!("{}_into", spec.name));
            let rest: Vec<TokenStream> = spec.outputs[1..]
                .iter()
                .map(|a| array_type(a.shape, &scalar.ty()))
                .collect();
            let rest_ty = tuple_type(&rest);
            let mut sig_args = args.clone();
            sig_args.push((ident("y"), quote!(&mut [f64])));
            let doc = format!(
                " {} Writes `Y_b` row-major into `y` (`6 × base_parameters().len()`) and returns \
                 the other results, or `None` if `y` has another length.",
                spec.title
            );
            out.push(method(
                &doc,
                &cfg,
                &into,
                &(sig_args, quote!(Option<#rest_ty>)),
                quote! {
                    let (rows, rest) = #module::#name(#(#names),*);
                    let width = rows[0].len();
                    if y.len() != 6 * width {
                        return None;
                    }
                    for (row, out) in rows.iter().zip(y.chunks_exact_mut(width)) {
                        out.copy_from_slice(row);
                    }
                    Some(rest)
                },
            ));
            for (constant, ty, doc) in [
                (
                    "BASE_PARAMETERS",
                    quote!(&'static [&'static str]),
                    " The base parameters' names, the columns of the base regressor.",
                ),
                (
                    "BASE_RELATIONS",
                    quote!(&'static [&'static str]),
                    " What each base parameter groups, as a relation between standard parameters.",
                ),
                (
                    "BASE_OF_STANDARD",
                    quote!(&'static [&'static [(usize, f64)]]),
                    " `β = B π`: each base parameter's terms `(standard index, coefficient)`.",
                ),
            ] {
                let c = ident(constant);
                let name = ident(&constant.to_ascii_lowercase());
                out.push(method(
                    doc,
                    &cfg,
                    &name,
                    &(Vec::new(), ty),
                    quote!(&#module::#c),
                ));
            }
        }
    }
    out
}

/// The kernel-set trait of a scalar type and its implementation by each model, so that a
/// caller picks a model once and calls every kernel through it. Every model's kernels must
/// have the same signatures.
///
/// # Errors
/// A kernel whose signature differs between models, or that one model lacks.
pub fn emit_kernel_sets(
    how: &str,
    sets: &[KernelSet],
    standalone: &[KernelSet],
    scalar: Scalar,
) -> Result<String, Error> {
    let per_set: Vec<Vec<Method>> = sets.iter().map(|s| methods(s, scalar)).collect();
    let first = &per_set[0];
    for (set, methods) in sets.iter().zip(&per_set).skip(1) {
        let same = methods.len() == first.len()
            && methods
                .iter()
                .zip(first)
                .all(|(a, b)| a.signature == b.signature);
        if !same {
            return Err(Error::InvalidModel {
                kernel: set.module.clone(),
                reason: format!(
                    "its kernels' signatures differ from the {} model's: every model has \
                     the same kernels, with the same arguments and results",
                    sets[0].module
                ),
            });
        }
    }
    let decls = first.iter().map(|m| &m.decl);
    let trait_doc = format!(
        " The kernels every model has, with one signature for all (`{}`): pick a model once \
         ([`Consistent`], [`Paper`]) and call every kernel through it, statically \
         (`K: Kernels`) or dynamically (`&dyn Kernels`).",
        scalar.name()
    );
    let impls = sets.iter().zip(&per_set).map(|(set, methods)| {
        let name = type_name(&set.module);
        let module = &set.module;
        let bodies = methods.iter().map(|m| &m.body);
        let doc = format!(" The {module} model's kernels: {}", set.summary);
        quote! {
            #[doc = #doc]
            #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
            pub struct #name;

            impl Kernels for #name {
                #[inline]
                fn model(&self) -> &'static str {
                    #module
                }
                #(#bodies)*
            }
        }
    });
    let all: Vec<Ident> = sets.iter().map(|s| type_name(&s.module)).collect();
    let count = Literal::usize_unsuffixed(sets.len());
    let variant_docs = sets
        .iter()
        .zip(&all)
        .map(|(set, ty)| format!(" The {} model's kernels, [`{ty}`].", set.module));
    let dispatch = first.iter().map(|m| {
        let (header, name, args) = (&m.header, &m.name, &m.args);
        let arms = all
            .iter()
            .map(|model| quote!(AnyModel::#model => #model.#name(#(#args),*)));
        quote!(#header { match self { #(#arms,)* } })
    });
    let (lane, _) = lane_type(scalar);
    let lane = ident(lane);
    let modules = sets.iter().chain(standalone).map(|set| {
        let module = ident(&set.module);
        let file = |part: &str| format!("{}{part}.rs", set.module);
        let kernels = file("");
        let batch = set.kernels.iter().any(|k| k.batch).then(|| {
            quote! {
                #[cfg(feature = "batch")]
                use crate::lanes::#lane;
            }
        });
        // One `include!` per further file the set has, under the features its kernels need:
        // each part's robot-free and `*_params` kernels, then its folded ones.
        let batched: Vec<SetKernel> = set.kernels.iter().filter(|k| k.batch).copied().collect();
        let derivatives: &[SetKernel] = match scalar {
            Scalar::F64 => &set.derivatives,
            Scalar::F32 => &[],
        };
        let parts: [(&str, Option<&str>, &[SetKernel]); 3] = [
            ("", None, &set.kernels),
            ("_batch", Some("batch"), &batched),
            ("_derivatives", Some("derivatives"), derivatives),
        ];
        let mut files = Vec::new();
        for folded in [false, true] {
            for (part, feature, kernels) in parts {
                let Some(first) = kernels.iter().find(|k| k.folded == folded) else {
                    continue;
                };
                let cfg = first.cfg(feature);
                if cfg.is_empty() {
                    continue; // the main file, included above without a condition
                }
                let name = file(&format!("{}{part}", if folded { "_folded" } else { "" }));
                files.push(quote!(#cfg include!(#name);));
            }
        }
        // The `f64` kernels' bodies are written once for both paths ([`FmaDispatch::twins`]).
        let twins = (scalar == Scalar::F64).then(|| {
            quote! {
                #[cfg(feature = "fma")]
                use c5_fma_twin_macro::fma_twin;
                use crate::fma::marks::{product, Folded};
            }
        });
        let regressors = (scalar == Scalar::F64 && !set.regressors.is_empty()).then(|| {
            let regressors = file("_regressor");
            quote! {
                #[cfg(feature = "regressor")]
                include!(#regressors);
            }
        });
        let doc = format!(
            " The {} kernels, `{}`: {}",
            set.module,
            scalar.name(),
            set.summary
        );
        quote! {
            #[doc = #doc]
            #[allow(clippy::all, clippy::pedantic, clippy::nursery, unused_parens, unused_imports)]
            pub mod #module {
                use crate::trig::{atan, cos, sin, sin_cos, sqrt};
                #twins
                include!(#kernels);
                #batch
                #(#files)*
                #regressors
            }
        }
    });
    let tokens = quote! {
        #(#modules)*

        #[doc = #trait_doc]
        pub trait Kernels: core::fmt::Debug + Sync {
            /// The model's name, as the command line and the manifest spell it.
            fn model(&self) -> &'static str;
            #(#decls)*
        }

        #(#impls)*

        /// Every model's kernels, the default model first.
        pub const MODELS: [&dyn Kernels; #count] = [#(&#all),*];

        /// One of the models, chosen at run time: its kernels are called through one `match`,
        /// statically, so a program builds only the kernels it calls (a `&dyn Kernels`
        /// builds every kernel of every model for its vtables).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum AnyModel {
            #(#[doc = #variant_docs] #all,)*
        }

        impl AnyModel {
            /// Every model, the default first.
            pub const ALL: [AnyModel; #count] = [#(AnyModel::#all),*];
        }

        impl Kernels for AnyModel {
            #[inline]
            fn model(&self) -> &'static str {
                match self {
                    #(AnyModel::#all => #all.model(),)*
                }
            }
            #(#dispatch)*
        }
    };
    let file: syn::File = syn::parse2(tokens).map_err(|e| Error::Emit {
        kernel: "kernel sets".to_string(),
        message: e.to_string(),
    })?;
    Ok(format!(
        "// @generated {how}. Do not edit.\n\n//! Kernels in `{}`: one module per model or mechanism; the C5's models \
         have the same kernel names and arguments, and the kernel-set trait [`Kernels`] that \
         each of them implements.\n\n\
         // The derivative kernels return a value, three Jacobians and the singularity terms.\n\
         #![allow(clippy::type_complexity)]\n\n{}",
        scalar.name(),
        prettyplease::unparse(&file)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kernel_is_inline_up_to_the_limit_and_compiled_once_above_it() {
        let at_limit = OpCount {
            mul: 800,
            add: 700,
            ..OpCount::default()
        };
        let above = OpCount {
            div: 1,
            ..at_limit.clone()
        };
        assert_eq!(at_limit.weight(), INLINE_LIMIT);
        assert_eq!(
            inline_attribute(&at_limit).to_string(),
            quote!(#[inline]).to_string()
        );
        assert!(inline_attribute(&above).is_empty());
    }
}
