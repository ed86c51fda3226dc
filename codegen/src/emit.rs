//! Emission of compiled kernels as formatted Rust through `quote` and `prettyplease`.

use crate::error::Error;
use crate::kernel::{Compiled, KernelSpec, Shape};
use crate::lower::{Instr, Operand};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

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
pub fn emit_kernel(spec: &KernelSpec, compiled: &Compiled, scalar: Scalar) -> TokenStream {
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
    let body = compiled
        .program
        .instrs
        .iter()
        .enumerate()
        .map(|(i, instr)| {
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
                    let a = operand(a);
                    let f = ident(f.name());
                    quote!(#a.#f())
                }
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
) -> Result<String, Error> {
    let items = kernels.iter().map(|(s, c)| emit_kernel(s, c, scalar));
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
