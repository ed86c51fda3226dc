//! `c5 audit`: every generated kernel's counted operations beside the chapter's count, from
//! the manifest the generator compiled into `c5-generated`.

use c5_generated::manifest::{Count, KERNELS};
use c5_runtime::Model;
use clap::Args;
use std::io::Write;
use std::process::ExitCode;

use crate::options::model_parser;

/// Prints the generated kernels' operation counts beside the chapter's.
#[derive(Args)]
pub struct AuditArgs {
    /// Only the kernels of this model (default: both).
    #[arg(long, value_parser = model_parser())]
    model: Option<Model>,
}

fn calls(c: &Count) -> String {
    if c.calls.is_empty() {
        "0".to_string()
    } else {
        c.calls
            .iter()
            .map(|(n, k)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The audit table: each kernel's `m + a` (a division counted as a multiplication) beside the
/// chapter's and their ratio, then the separate counts; only `model`'s kernels when given.
pub fn table(model: Option<Model>) -> String {
    let mut out = format!(
        "{:<10} {:<30} {:>8} {:>12} {:>12} {:>6}  mul/div/add/neg, calls\n",
        "model", "kernel", "setting", "chapter", "generated", "ratio"
    );
    for e in KERNELS
        .iter()
        .filter(|e| model.is_none_or(|m| m.name() == e.model))
    {
        let c = &e.count;
        let (m, a) = (c.chapter_m(), c.chapter_a());
        let (chapter, ratio) = match e.chapter {
            Some(ch) => (
                format!("{}m + {}a", ch.m, ch.a),
                format!("{:.2}", f64::from(m + a) / f64::from(ch.m + ch.a)),
            ),
            None => ("—".to_string(), "—".to_string()),
        };
        out.push_str(&format!(
            "{:<10} {:<30} {:>8} {:>12} {:>12} {:>6}  {}/{}/{}/{}, {}\n",
            e.model,
            e.name,
            e.setting,
            chapter,
            format!("{m}m + {a}a"),
            ratio,
            c.mul,
            c.div,
            c.add,
            c.neg,
            calls(c)
        ));
    }
    out.push_str(
        "\nratio = generated (m + a) / chapter (m + a); a division counts as a multiplication.\n\
         The chapter's Khalil step 6 (J⁻¹ by eq 22, then an LU solve of eq 61) costs 134m + 125a;\n\
         the generated factored step 6 is `step6_factored`.\n",
    );
    out
}

pub fn run(args: &AuditArgs) -> crate::Result<ExitCode> {
    std::io::stdout()
        .lock()
        .write_all(table(args.model).as_bytes())?;
    Ok(ExitCode::SUCCESS)
}
