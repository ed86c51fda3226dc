//! Long kernel bodies cut into blocks, so that debug builds of them compile.
//!
//! Every `let` opens a lexical scope nested in the one before it, and LLVM's debug-info writer
//! recurses once per level: a debug build (`-C debuginfo=2`, cargo's `dev` profile) of a body of
//! about 2 700 `let`s overflows rustc's stack (rustc 1.95, 8 MiB). The derivative kernels have up
//! to 16 000. A body longer than [`MAX_LETS_PER_SCOPE`] is therefore cut into blocks of at most
//! that many `let`s, each handing the temporaries read after it on as a tuple:
//! `let (t7, t9) = { let t7 = ..; let t8 = ..; let t9 = ..; (t7, t9) };`. The nesting is then at
//! most one block's length plus the number of blocks; optimised code is the same straight line.

use proc_macro2::{TokenStream, TokenTree};
use quote::{format_ident, quote};
use rustc_hash::FxHashSet as HashSet;

/// The most `let`s one scope of an emitted body holds (the kernels up to the primal dynamics fit
/// in one; rustc overflows at about 2 700).
pub const MAX_LETS_PER_SCOPE: usize = 1000;

/// One statement of a body: `let` binding the temporaries `binds` (`t{i}`).
pub struct Let {
    pub binds: Vec<u32>,
    pub tokens: TokenStream,
}

/// The body's statements, nested in blocks of at most [`MAX_LETS_PER_SCOPE`] where it is longer;
/// `read_after` are the temporaries the code after the body (its return value) reads.
pub fn nest(body: Vec<Let>, read_after: &HashSet<u32>) -> Vec<TokenStream> {
    if body.len() <= MAX_LETS_PER_SCOPE {
        return body.into_iter().map(|s| s.tokens).collect();
    }
    let chunks: Vec<&[Let]> = body.chunks(MAX_LETS_PER_SCOPE).collect();
    // Walking back from the end: what each block must hand on is what is read after it.
    let mut live = read_after.clone();
    let mut blocks = Vec::with_capacity(chunks.len());
    for chunk in chunks.iter().rev() {
        let bound: HashSet<u32> = chunk.iter().flat_map(|s| s.binds.iter().copied()).collect();
        let mut handed: Vec<u32> = bound.iter().copied().filter(|t| live.contains(t)).collect();
        handed.sort_unstable();
        live.retain(|t| !bound.contains(t));
        for s in chunk.iter() {
            temps_read(&s.tokens, &mut live);
        }
        live.retain(|t| !bound.contains(t));
        let names: Vec<_> = handed.iter().map(|t| format_ident!("t{t}")).collect();
        let stmts = chunk.iter().map(|s| &s.tokens);
        blocks.push(quote! {
            let (#(#names,)*) = {
                #(#stmts)*
                (#(#names,)*)
            };
        });
    }
    blocks.reverse();
    blocks
}

/// Adds to `out` every temporary (`t{i}`) the tokens name.
fn temps_read(tokens: &TokenStream, out: &mut HashSet<u32>) {
    for tree in tokens.clone() {
        match tree {
            TokenTree::Ident(id) => {
                if let Some(i) = id
                    .to_string()
                    .strip_prefix('t')
                    .and_then(|n| n.parse::<u32>().ok())
                {
                    out.insert(i);
                }
            }
            TokenTree::Group(g) => temps_read(&g.stream(), out),
            TokenTree::Punct(_) | TokenTree::Literal(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(n: u32) -> Vec<Let> {
        (0..n)
            .map(|i| {
                let t = format_ident!("t{i}");
                let tokens = if i == 0 {
                    quote!(let #t: f64 = x;)
                } else {
                    let (a, b) = (format_ident!("t{}", i - 1), format_ident!("t{}", i / 2));
                    quote!(let #t: f64 = #a * #b;)
                };
                Let {
                    binds: vec![i],
                    tokens,
                }
            })
            .collect()
    }

    #[test]
    fn a_short_body_is_left_as_it_is() {
        let body = chain(10);
        let expected: Vec<String> = body.iter().map(|s| s.tokens.to_string()).collect();
        let out = nest(body, &HashSet::from_iter([9]));
        let got: Vec<String> = out.iter().map(|s| s.to_string()).collect();
        assert_eq!(got, expected);
    }

    #[test]
    fn a_long_body_hands_on_exactly_what_is_read_later() {
        let n = 2 * MAX_LETS_PER_SCOPE as u32 + 5;
        let out = nest(chain(n), &HashSet::from_iter([n - 1]));
        assert_eq!(out.len(), 3);
        // Block 0 hands on its last temporary (read by the next `let`) and the halves that
        // block 1 and 2 read: t{i/2} for i in the later blocks lies in [500, 1002].
        let first = syn::parse2::<syn::Stmt>(out[0].clone()).expect("a statement");
        let syn::Stmt::Local(local) = first else {
            panic!("a let")
        };
        let syn::Pat::Tuple(tuple) = local.pat else {
            panic!("a tuple pattern")
        };
        let m = MAX_LETS_PER_SCOPE as u32;
        let expected: Vec<String> = (m / 2..m).map(|i| format!("t{i}")).collect();
        let got: Vec<String> = tuple.elems.iter().map(|p| quote!(#p).to_string()).collect();
        assert_eq!(got, expected);
        // The last block hands on only what the return reads.
        assert!(out[2]
            .to_string()
            .starts_with(&format!("let (t{} ,)", n - 1)));
    }
}
