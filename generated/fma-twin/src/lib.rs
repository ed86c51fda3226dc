//! A generated kernel's arithmetic written once, expanded into its two paths.
//!
//! Each `f64` kernel has two paths: the *separate* one, where every operation is rounded on its
//! own (the same bits on every machine), and its *FMA twin*, where each product that one sum
//! alone reads is fused into that sum (`mul_add`: one rounding, one instruction). The
//! generator writes the body once, as the separate path, with the folded products marked:
//!
//! - `let p = product(a, b);` a product that one sum folds in, where the program computes it;
//! - `p.plus(c)` (`a·b + c`), `p.added_to(c)` (`c + a·b`), `p.minus(c)` (`a·b − c`) and
//!   `p.subtracted_from(c)` (`c − a·b`): the sum that reads it, as the whole right-hand side of
//!   a `let`.
//!
//! [`expand`] turns that into two functions, each of which is what a body written for that path
//! alone would be, so the compiler does no more work than for two such bodies:
//!
//! | written | separate path | FMA twin |
//! |---|---|---|
//! | `product(a, b)` | `a * b` | `(a, b)` (the factors, kept) |
//! | `p.plus(c)` | `p + c` | `mul_add(p.0, p.1, c)` |
//! | `p.added_to(c)` | `c + p` | `mul_add(p.0, p.1, c)` |
//! | `p.minus(c)` | `p - c` | `mul_add(p.0, p.1, -(c))` |
//! | `p.subtracted_from(c)` | `c - p` | `mul_add(-p.0, p.1, c)` |
//!
//! A product stays where the program computes it on both paths, so each keeps the program's
//! order. Where the body names `FUSED`, each path gets `const FUSED: bool` (false, true) first.
//!
//! The `#[fma_twin]` attribute of `c5-fma-twin-macro` calls [`expand`] for `c5-generated`'s
//! checked-in kernels; the generator calls it itself for the files a `build.rs` writes.

use proc_macro2::{Delimiter, Group, Ident, Literal, Punct, Spacing, TokenStream, TokenTree};

/// Which path a body is rewritten for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    Separate,
    Fused,
}

/// Why a kernel could not be expanded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error(pub String);

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

/// Expands `item`, a function whose body is written once (the module's notation), into two:
/// `item` itself with its separate arithmetic, and its FMA twin.
///
/// `attr` is `NAME, MUL_ADD`: the twin's name and the path of the fused multiply-add
/// (`f64::mul_add`, `F64x4::mul_add`). The twin exists where `cfg` holds. It is `item` but for
/// its arithmetic, its name and its docs, and `unsafe` (its `mul_add` needs FMA). Unless `item`
/// is `#[inline(always)]` (inlined into a caller compiled for FMA, as the batch kernels' lanes
/// are), the twin is compiled for FMA (`#[target_feature(enable = "fma")]`) and documented
/// from the names: `k_fused`'s kernel is `k`.
pub fn expand(
    attr: TokenStream,
    item: TokenStream,
    cfg: &TokenStream,
) -> Result<TokenStream, Error> {
    let usage = || {
        Error("#[fma_twin(NAME, MUL_ADD)]: the twin's name, the fused multiply-add's path".into())
    };
    let mut args = split_commas(attr).into_iter();
    let (Some(name), Some(mul_add), None) = (args.next(), args.next(), args.next()) else {
        return Err(usage());
    };
    let mut name = name.into_iter();
    let (Some(TokenTree::Ident(name)), None) = (name.next(), name.next()) else {
        return Err(usage());
    };
    if mul_add.is_empty() {
        return Err(usage());
    }
    let Function {
        attrs,
        head,
        signature,
        body,
    } = Function::split(item)?;
    let mut marks = Marks::default();
    let separate = rewrite_body(&body, Path::Separate, &mul_add, &mut marks);
    let fused = rewrite_body(&body, Path::Fused, &mul_add, &mut Marks::default());
    let inlined = attrs
        .iter()
        .any(|a| a.to_string().replace(' ', "") == "#[inline(always)]");
    let mut out = TokenStream::new();
    for attr in &attrs {
        out.extend(attr.clone());
    }
    out.extend(head.clone());
    out.extend(signature.clone());
    out.extend([separate]);
    if !inlined {
        out.extend(twin_doc(&name, &head, marks.products));
    }
    out.extend(attribute("cfg", cfg.clone()));
    if !inlined {
        out.extend(quote_tokens("#[target_feature(enable = \"fma\")]"));
    }
    for attr in attrs.iter().filter(|a| !is_doc(a)) {
        out.extend(attr.clone());
    }
    out.extend(twin_head(head, name));
    out.extend(signature);
    out.extend([fused]);
    Ok(out)
}

/// `#[name(args)]`.
fn attribute(name: &str, args: TokenStream) -> TokenStream {
    let meta: TokenStream = [
        TokenTree::Ident(Ident::new(name, proc_macro2::Span::call_site())),
        TokenTree::Group(Group::new(Delimiter::Parenthesis, args)),
    ]
    .into_iter()
    .collect();
    [
        punct('#'),
        TokenTree::Group(Group::new(Delimiter::Bracket, meta)),
    ]
    .into_iter()
    .collect()
}

/// The twin's head: `item`'s, `unsafe` (once), with the twin's name.
fn twin_head(head: TokenStream, name: Ident) -> TokenStream {
    let mut out = TokenStream::new();
    for token in head {
        match &token {
            TokenTree::Ident(i) if i == "unsafe" => {}
            TokenTree::Ident(i) if i == "fn" => {
                out.extend(quote_tokens("unsafe fn"));
                out.extend([TokenTree::Ident(name.clone())]);
                return out;
            }
            _ => out.extend([token]),
        }
    }
    out
}

/// The twin's docs: what it fuses (`products` of them) and what it assumes.
fn twin_doc(name: &Ident, head: &TokenStream, products: usize) -> TokenStream {
    let twin = name.to_string();
    let kernel = twin.strip_suffix("_fused").unwrap_or(&twin);
    let separate = head
        .clone()
        .into_iter()
        .last()
        .map(|t| t.to_string())
        .unwrap_or_default();
    let what = match products {
        0 => format!(
            " [`{kernel}`] on the FMA path: no product here is read by a sum alone, so this is \
             [`{separate}`]'s arithmetic."
        ),
        n => format!(
            " [`{kernel}`] with {n} of its products fused into the sums that read them \
             (`mul_add`, one rounding each): the path [`{kernel}`] takes where the CPU has FMA."
        ),
    };
    let lines = [
        what.as_str(),
        "",
        " # Safety",
        " The CPU must have FMA (`is_x86_feature_detected!(\"fma\")`).",
    ];
    lines
        .iter()
        .flat_map(|l| quote_tokens(&format!("#[doc = {}]", Literal::string(l))))
        .collect()
}

/// A function item cut where the expansion needs it.
struct Function {
    /// Each outer attribute: `#` and its bracketed group.
    attrs: Vec<TokenStream>,
    /// From the visibility to the name: `pub fn k_separate`.
    head: TokenStream,
    /// The parameters and the return type.
    signature: TokenStream,
    /// The braced body.
    body: Group,
}

impl Function {
    fn split(item: TokenStream) -> Result<Function, Error> {
        let mut tokens: Vec<TokenTree> = item.into_iter().collect();
        let Some(TokenTree::Group(body)) = tokens.pop() else {
            return Err(Error(
                "#[fma_twin] applies to a function with a body".into(),
            ));
        };
        if body.delimiter() != Delimiter::Brace {
            return Err(Error(
                "#[fma_twin] applies to a function with a body".into(),
            ));
        }
        let mut attrs = Vec::new();
        let mut rest = tokens.into_iter().peekable();
        while matches!(rest.peek(), Some(TokenTree::Punct(p)) if p.as_char() == '#') {
            let hash = rest.next();
            let group = rest.next();
            attrs.push(hash.into_iter().chain(group).collect());
        }
        let mut head = TokenStream::new();
        let mut seen_fn = false;
        for token in rest.by_ref() {
            let is_name = seen_fn && matches!(token, TokenTree::Ident(_));
            seen_fn |= matches!(&token, TokenTree::Ident(i) if i == "fn");
            head.extend([token]);
            if is_name {
                break;
            }
        }
        if !seen_fn {
            return Err(Error("#[fma_twin] applies to a function".into()));
        }
        Ok(Function {
            attrs,
            head,
            signature: rest.collect(),
            body,
        })
    }
}

/// Whether an attribute is a doc comment (`#[doc = "..."]`).
fn is_doc(attr: &TokenStream) -> bool {
    let Some(TokenTree::Group(g)) = attr.clone().into_iter().nth(1) else {
        return false;
    };
    matches!(g.stream().into_iter().next(), Some(TokenTree::Ident(i)) if i == "doc")
}

/// What a body marks: its folded products, and whether it reads `FUSED`.
#[derive(Default)]
struct Marks {
    products: usize,
    names_fused: bool,
}

/// The body for `path`, with `const FUSED` first where it reads `FUSED`.
fn rewrite_body(body: &Group, path: Path, mul_add: &TokenStream, marks: &mut Marks) -> TokenTree {
    let rewritten = rewrite(body.stream(), path, mul_add, marks);
    let mut stream = TokenStream::new();
    if marks.names_fused {
        let value = path == Path::Fused;
        stream.extend(quote_tokens(&format!("const FUSED: bool = {value};")));
    }
    stream.extend(rewritten);
    let mut group = Group::new(Delimiter::Brace, stream);
    group.set_span(body.span());
    TokenTree::Group(group)
}

/// Tokens from source text this crate writes (always valid).
fn quote_tokens(source: &str) -> TokenStream {
    source.parse().expect("the crate's own token text parses")
}

/// `stream` with its folded products and the sums that read them written for `path`.
///
/// An identifier's text is read only where the token after it could make it a mark: naming
/// each one costs a call into the compiler, and a kernel has hundreds of thousands.
fn rewrite(
    stream: TokenStream,
    path: Path,
    mul_add: &TokenStream,
    marks: &mut Marks,
) -> TokenStream {
    let tokens: Vec<TokenTree> = stream.into_iter().collect();
    let mut out = Vec::with_capacity(tokens.len());
    let mut i = 0;
    while i < tokens.len() {
        if let (TokenTree::Ident(name), Some(TokenTree::Group(g))) = (&tokens[i], tokens.get(i + 1))
        {
            marks.names_fused |= g.delimiter() == Delimiter::Brace && name == "FUSED";
        }
        if let Some(factors) = product_at(&tokens, i) {
            marks.products += 1;
            match path {
                Path::Separate => {
                    let [a, b] = factors;
                    out.extend(a);
                    out.push(punct('*'));
                    out.extend(b);
                }
                Path::Fused => out.push(tokens[i + 1].clone()),
            }
            i += 2;
            continue;
        }
        if let Some((p, sum, c)) = sum_at(&tokens, i) {
            out.extend(sum.write(p, c, path, mul_add));
            i += 4;
            continue;
        }
        out.push(match &tokens[i] {
            TokenTree::Group(g) => {
                let mut group =
                    Group::new(g.delimiter(), rewrite(g.stream(), path, mul_add, marks));
                group.set_span(g.span());
                TokenTree::Group(group)
            }
            other => other.clone(),
        });
        i += 1;
    }
    out.into_iter().collect()
}

/// `product(a, b)` at `i`: its two factors.
fn product_at(tokens: &[TokenTree], i: usize) -> Option<[TokenStream; 2]> {
    let (TokenTree::Ident(name), Some(TokenTree::Group(args))) = (&tokens[i], tokens.get(i + 1))
    else {
        return None;
    };
    if args.delimiter() != Delimiter::Parenthesis || name != "product" {
        return None;
    }
    let [a, b]: [TokenStream; 2] = split_commas(args.stream()).try_into().ok()?;
    Some([a, b])
}

/// A sum that reads a folded product.
#[derive(Clone, Copy)]
enum Sum {
    /// `p.plus(c)`: `a·b + c`.
    Plus,
    /// `p.added_to(c)`: `c + a·b`.
    AddedTo,
    /// `p.minus(c)`: `a·b − c`.
    Minus,
    /// `p.subtracted_from(c)`: `c − a·b`.
    SubtractedFrom,
}

/// `p.plus(c)` (or another [`Sum`]) at `i`.
fn sum_at(tokens: &[TokenTree], i: usize) -> Option<(&Ident, Sum, TokenStream)> {
    let [TokenTree::Ident(p), TokenTree::Punct(dot), TokenTree::Ident(method), TokenTree::Group(c)] =
        tokens.get(i..i + 4)?
    else {
        return None;
    };
    if dot.as_char() != '.' || c.delimiter() != Delimiter::Parenthesis {
        return None;
    }
    let sum = match method.to_string().as_str() {
        "plus" => Sum::Plus,
        "added_to" => Sum::AddedTo,
        "minus" => Sum::Minus,
        "subtracted_from" => Sum::SubtractedFrom,
        _ => return None,
    };
    Some((p, sum, c.stream()))
}

impl Sum {
    /// This sum of the product `p` and `c`, written for `path`.
    fn write(self, p: &Ident, c: TokenStream, path: Path, mul_add: &TokenStream) -> TokenStream {
        let p = TokenTree::Ident(p.clone());
        let mut out = TokenStream::new();
        if path == Path::Separate {
            let (left, op, right) = match self {
                Sum::Plus => (p.into(), '+', c),
                Sum::AddedTo => (c, '+', p.into()),
                Sum::Minus => (p.into(), '-', c),
                Sum::SubtractedFrom => (c, '-', p.into()),
            };
            out.extend(left);
            out.extend([punct(op)]);
            out.extend(right);
            return out;
        }
        let factor = |k: usize| -> TokenStream {
            [
                p.clone(),
                punct('.'),
                TokenTree::Literal(Literal::usize_unsuffixed(k)),
            ]
            .into_iter()
            .collect()
        };
        let negated = |s: TokenStream| -> TokenStream {
            let group = Group::new(Delimiter::Parenthesis, s);
            [punct('-'), TokenTree::Group(group)].into_iter().collect()
        };
        let (a, c) = match self {
            Sum::Plus | Sum::AddedTo => (factor(0), c),
            Sum::Minus => (factor(0), negated(c)),
            Sum::SubtractedFrom => (negated(factor(0)), c),
        };
        let mut args = a;
        args.extend([punct(',')]);
        args.extend(factor(1));
        args.extend([punct(',')]);
        args.extend(c);
        out.extend(mul_add.clone());
        out.extend([TokenTree::Group(Group::new(Delimiter::Parenthesis, args))]);
        out
    }
}

fn punct(c: char) -> TokenTree {
    TokenTree::Punct(Punct::new(c, Spacing::Alone))
}

/// `stream` cut at its top-level commas (a trailing comma ends the last part).
fn split_commas(stream: TokenStream) -> Vec<TokenStream> {
    let mut parts = vec![TokenStream::new()];
    for token in stream {
        match &token {
            TokenTree::Punct(p) if p.as_char() == ',' => parts.push(TokenStream::new()),
            _ => parts.last_mut().expect("never empty").extend([token]),
        }
    }
    if parts.last().is_some_and(|p| p.is_empty()) && parts.len() > 1 {
        parts.pop();
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    fn expanded(body: TokenStream) -> String {
        let item = quote! {
            /// The separate path.
            #[inline]
            pub fn k_separate(x: &[f64; 2]) -> f64 { #body }
        };
        let cfg = quote!(feature = "fma");
        expand(quote!(k_fused, f64::mul_add), item, &cfg)
            .unwrap()
            .to_string()
    }

    #[test]
    fn each_sum_is_rounded_twice_on_the_separate_path_and_fused_on_the_twin() {
        let out = expanded(quote! {
            let [a, b] = *x;
            let p = product(a, b);
            let q = product(b, -2.0);
            let r = product(a, a);
            let s = product(b, b);
            let t0: f64 = p.plus(b);
            let t1: f64 = q.added_to(t0);
            let t2: f64 = r.minus(-1.5);
            let t3: f64 = s.subtracted_from(t2);
            t1 + t3
        });
        let (separate, fused) = out.split_once("pub unsafe fn").unwrap();
        for expected in [
            "let p = a * b ;",
            "let q = b * - 2.0 ;",
            "let t0 : f64 = p + b ;",
            "let t1 : f64 = t0 + q ;",
            "let t2 : f64 = r - - 1.5 ;",
            "let t3 : f64 = t2 - s ;",
        ] {
            assert!(separate.contains(expected), "{expected} in {separate}");
        }
        for expected in [
            "let p = (a , b) ;",
            "let t0 : f64 = f64 :: mul_add (p . 0 , p . 1 , b) ;",
            "let t1 : f64 = f64 :: mul_add (q . 0 , q . 1 , t0) ;",
            "let t2 : f64 = f64 :: mul_add (r . 0 , r . 1 , - (- 1.5)) ;",
            "let t3 : f64 = f64 :: mul_add (- (s . 0) , s . 1 , t2) ;",
        ] {
            assert!(fused.contains(expected), "{expected} in {fused}");
        }
    }

    #[test]
    fn the_twin_keeps_the_signature_and_attributes_with_its_own_docs() {
        let out = expanded(quote!(x[0]));
        let (separate, fused) = out.split_once("} # [doc").unwrap();
        let head = "# [doc = r\" The separate path.\"] # [inline] pub fn k_separate (x : & [f64 ; 2]) -> f64";
        assert!(separate.starts_with(head), "{separate}");
        assert!(
            fused.contains("no product here is read by a sum alone, so this is [`k_separate`]'s")
        );
        assert!(fused.contains("# Safety"));
        let twin = "# [cfg (feature = \"fma\")] # [target_feature (enable = \"fma\")] # [inline] \
                    pub unsafe fn k_fused (x : & [f64 ; 2]) -> f64 { x [0] }";
        assert!(fused.ends_with(twin), "{fused}");
        assert!(!fused.contains("separate path"));
    }

    #[test]
    fn an_unsafe_item_has_one_unsafe_twin() {
        let item = quote!(
            pub unsafe fn k_separate(x: f64) -> f64 {
                x
            }
        );
        let out = expand(quote!(k_fused, f64::mul_add), item, &quote!(unix)).unwrap();
        assert!(
            out.to_string()
                .contains("# [target_feature (enable = \"fma\")] pub unsafe fn k_fused (x : f64)"),
            "{out}"
        );
        assert!(!out.to_string().contains("unsafe unsafe"));
    }

    #[test]
    fn the_twin_counts_its_fused_products() {
        let out = expanded(
            quote!(let p = product(x[0], x[1]); let q = product(x[0], x[0]); p.plus(q.plus(1.0))),
        );
        assert!(out.contains("[`k`] with 2 of its products fused into the sums that read them"));
    }

    #[test]
    fn an_inlined_body_has_an_inlined_twin_compiled_by_its_caller() {
        let item = quote!(
            #[inline(always)]
            fn lanes(x: &F64x4) -> F64x4 {
                *x
            }
        );
        let out = expand(quote!(lanes_fused, F64x4::mul_add), item, &quote!(unix)).unwrap();
        let twin = "# [cfg (unix)] # [inline (always)] unsafe fn lanes_fused (x : & F64x4) -> F64x4 { * x }";
        assert!(out.to_string().ends_with(twin), "{out}");
        assert!(!out.to_string().contains("doc") && !out.to_string().contains("target_feature"));
    }

    #[test]
    fn fused_is_a_constant_of_each_path_where_the_body_names_it() {
        let out = expanded(quote!({
            if FUSED {
                return 1.0;
            }
            x[0]
        }));
        let (separate, fused) = out.split_once("pub unsafe fn").unwrap();
        assert!(separate.contains("const FUSED : bool = false ;"));
        assert!(fused.contains("const FUSED : bool = true ;"));
        assert!(!expanded(quote!(x[0])).contains("FUSED"));
    }

    #[test]
    fn a_malformed_attribute_or_item_is_an_error() {
        let cfg = quote!(unix);
        let item = quote!(
            fn k(x: f64) -> f64 {
                x
            }
        );
        assert!(expand(quote!(k_fused), item.clone(), &cfg).is_err());
        assert!(expand(quote!(k_fused, f64::mul_add, x), item.clone(), &cfg).is_err());
        assert!(expand(quote!(pub fn k_fused, f64::mul_add), item.clone(), &cfg).is_err());
        assert!(expand(quote!(k_fused,), item, &cfg).is_err());
        let attr = quote!(k_fused, f64::mul_add);
        assert!(expand(
            attr.clone(),
            quote!(
                struct S;
            ),
            &cfg
        )
        .is_err());
        assert!(expand(
            attr,
            quote!(
                const K: f64 = 1.0;
            ),
            &cfg
        )
        .is_err());
    }
}
