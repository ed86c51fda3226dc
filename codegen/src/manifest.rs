//! The operation-count manifest (`ops.json`, `OPS.md`) and the generated files' header.

use crate::count::OpCount;
use crate::kernel::{ChapterCount, Compiled, KernelSpec, Setting};
use c5_robot::Model;
use serde::{Deserialize, Serialize};

/// One kernel's entry in `ops.json`. The counts hold for every scalar type and every output
/// language: they are the counts of the one program all of them print.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    pub name: String,
    /// The model whose equations the kernel computes (`"consistent"` or `"paper"`).
    pub model: Model,
    pub setting: Setting,
    pub equations: Vec<String>,
    #[serde(flatten)]
    pub count: OpCount,
    pub chapter: Option<ChapterCount>,
}

/// The whole manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub kernels: Vec<Entry>,
}

fn entries(kernels: &[(&KernelSpec, &Compiled)]) -> Vec<Entry> {
    kernels
        .iter()
        .map(|(s, c)| Entry {
            name: s.name.clone(),
            model: s.model,
            setting: s.setting,
            equations: s.equations.clone(),
            count: c.count.clone(),
            chapter: s.chapter,
        })
        .collect()
}

pub fn json(kernels: &[(&KernelSpec, &Compiled)]) -> String {
    let m = Manifest {
        kernels: entries(kernels),
    };
    serde_json::to_string_pretty(&m).expect("manifest serialises") + "\n"
}

fn calls(c: &OpCount) -> String {
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

/// `ops.json` as a Markdown table.
pub fn markdown(kernels: &[(&KernelSpec, &Compiled)]) -> String {
    let mut out = String::from(
        "# Operation counts of the generated kernels\n\n\
         Generated with the kernels; `m` counts a division as a multiplication, as the chapter does. \
         The counts hold for the Rust and the C output alike, in `f64` and `f32`: all print one program.\n\n\
         | model | kernel | setting | equations | mul | div | add | neg | calls | generated m + a | chapter m + a |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for e in entries(kernels) {
        let c = &e.count;
        out.push_str(&format!(
            "| {} | `{}` | {} | {} | {} | {} | {} | {} | {} | {}m + {}a | {} |\n",
            e.model,
            e.name,
            e.setting,
            e.equations.join(", "),
            c.mul,
            c.div,
            c.add,
            c.neg,
            calls(c),
            c.chapter_m(),
            c.chapter_a(),
            e.chapter
                .map_or("—".to_string(), |ch| format!("{}m + {}a", ch.m, ch.a)),
        ));
    }
    out
}

/// The `@generated` header with a cost summary; `what` says which model and robot.
pub fn header(kernels: &[(&KernelSpec, &Compiled)], how: &str, what: &str) -> String {
    let mut out = format!(
        "// @generated {how}. Do not edit.\n// {what}\n//\n// Kernel operation counts (mul, div, add, neg, calls):\n"
    );
    for (s, c) in kernels {
        let n = &c.count;
        out.push_str(&format!(
            "//   {:<32} {:>5} {:>4} {:>5} {:>4}  {}\n",
            s.name,
            n.mul,
            n.div,
            n.add,
            n.neg,
            calls(n)
        ));
    }
    out
}

/// The audit: every kernel's counted operations beside the chapter's count, with the ratio of
/// `m + a` (a division counted as a multiplication), from the text of `ops.json`; only the
/// kernels of `model` when one is given.
///
/// # Errors
/// If `ops_json` is not a manifest.
pub fn audit(ops_json: &str, model: Option<Model>) -> Result<String, serde_json::Error> {
    let mut m: Manifest = serde_json::from_str(ops_json)?;
    m.kernels
        .retain(|e| model.is_none_or(|wanted| e.model == wanted));
    let mut out = format!(
        "{:<10} {:<30} {:>8} {:>12} {:>12} {:>6}  mul/div/add/neg, calls\n",
        "model", "kernel", "setting", "chapter", "generated", "ratio"
    );
    for e in &m.kernels {
        let c = &e.count;
        let (m_, a) = (c.chapter_m(), c.chapter_a());
        let (chapter, ratio) = match e.chapter {
            Some(ch) => (
                format!("{}m + {}a", ch.m, ch.a),
                format!("{:.2}", f64::from(m_ + a) / f64::from(ch.m + ch.a)),
            ),
            None => ("—".to_string(), "—".to_string()),
        };
        out.push_str(&format!(
            "{:<10} {:<30} {:>8} {:>12} {:>12} {:>6}  {}/{}/{}/{}, {}\n",
            e.model.name(),
            e.name,
            e.setting.to_string(),
            chapter,
            format!("{m_}m + {a}a"),
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
    Ok(out)
}
