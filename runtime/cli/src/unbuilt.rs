//! What a build of `c5` without its `identify` or `derivatives` feature leaves out. A plain
//! `cargo run --release -- simulate` compiles neither the regressor nor the derivative kernels
//! (docs/build-time.md); the commands and flags that need them stay in `--help` and say how to
//! get them.

use clap::Args;

/// The arguments of a command this build leaves out, taken as they come.
#[derive(Args)]
pub struct UnbuiltArgs {
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, hide = true)]
    args: Vec<String>,
}

/// The error for `what` (a command or a flag), which needs `feature`.
pub fn needs(what: &str, feature: &str) -> Box<dyn std::error::Error> {
    let kernels = match feature {
        "identify" => "the identification (regressor) kernels",
        _ => "the dynamics' derivative kernels",
    };
    format!(
        "{what} is not in this build of c5: it needs the `{feature}` feature ({kernels}), which \
         `cargo run --release -p c5-cli -F {feature} -- ...` builds (or `-F full`, every \
         command; `cargo install --path runtime/cli --features full` installs it)"
    )
    .into()
}

/// Refuses `--derivatives` before any line is read: in a build without the derivative
/// kernels, or for a mechanism whose derivative kernels are not generated (naming it).
#[cfg_attr(not(feature = "derivatives"), allow(unused_variables))]
pub fn derivatives_of(robot: &dyn c5_runtime::Mechanism) -> crate::Result<()> {
    if !cfg!(feature = "derivatives") {
        return Err(needs("`--derivatives`", "derivatives"));
    }
    #[cfg(feature = "derivatives")]
    c5_runtime::derivatives::sliced_derivatives_of(robot)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_says_what_to_build() {
        let e = needs("`c5 plan`", "derivatives").to_string();
        assert!(e.starts_with("`c5 plan` is not in this build of c5"));
        assert!(e.contains("-p c5-cli -F derivatives") && e.contains("derivative kernels"));
        assert!(e.contains("cargo install --path runtime/cli --features full"));
        let e = needs("`--base-parameters`", "identify").to_string();
        assert!(e.contains("-p c5-cli -F identify") && e.contains("regressor"));
    }
}
