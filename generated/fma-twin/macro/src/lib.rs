//! `#[fma_twin]`: a `c5-generated` kernel's body written once, compiled as its separate path
//! and as its FMA twin. The notation and the expansion are [`c5_fma_twin`]'s.

use proc_macro::TokenStream;

/// Where `c5-generated`'s FMA twins exist: its `fma` feature, on x86.
const CFG: &str = r#"all(feature = "fma", any(target_arch = "x86", target_arch = "x86_64"))"#;

/// Expands the function it annotates (its separate path, its folded products marked) into
/// itself and its FMA twin: `#[fma_twin(NAME, MUL_ADD)]`, as [`c5_fma_twin::expand`] says.
#[proc_macro_attribute]
pub fn fma_twin(attr: TokenStream, item: TokenStream) -> TokenStream {
    let cfg = CFG.parse().expect("the constant parses");
    match c5_fma_twin::expand(attr.into(), item.into(), &cfg) {
        Ok(tokens) => tokens.into(),
        Err(e) => {
            let message = proc_macro2::Literal::string(&e.0);
            format!("compile_error!({message});")
                .parse()
                .expect("a literal parses")
        }
    }
}
