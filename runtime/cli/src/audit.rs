//! `c5 audit`: every generated kernel's counted operations beside the chapter's count, from
//! the manifest the generator compiled into `c5-generated`.

use c5_generated::manifest::{Count, KERNELS};
use c5_runtime::{Description, Model};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::options::model_parser;

/// Prints the generated kernels' operation counts beside the chapter's (the C5's) or a peer's
/// (the Gough-Stewart platform's).
#[derive(Args)]
pub struct AuditArgs {
    /// Only the kernels of this C5 model (default: every model and mechanism).
    #[arg(long, value_parser = model_parser())]
    model: Option<Model>,
    /// Only the kernels of this robot file's mechanism (a C5 file: both C5 models, or
    /// `--model`'s). The `*_params` kernels' counts hold for every robot of the mechanism; the
    /// folded ones are those of the checked-in robot (the chapter's, `docs/hexapod.toml`).
    #[arg(long)]
    robot: Option<PathBuf>,
}

/// A peer's count of a mechanism's inverse dynamics with every parameter an input.
struct Peer {
    mechanism: &'static str,
    /// What the mechanism is and what the peer's count covers.
    what: &'static str,
    mul: u32,
    add: u32,
}

/// robsynth's generated inverse dynamics in task space, parameters as inputs: the 6-UPS's
/// (`P6RRPRRR14V3G1A0_invdyn_para_pf_slag_vp1`, the legs' joint angles given; 12 divisions,
/// 42 calls) and the 6-RUS's, their published counts (the mechanisms issue).
const ROBSYNTH: [Peer; 3] = [
    Peer {
        mechanism: c5_robot::description::GOUGH_STEWART,
        what: "The 6-UPS inverse dynamics with every parameter an input (inverse kinematics \
               included; robsynth's with the joint angles given)",
        mul: 2660,
        add: 1664,
    },
    Peer {
        mechanism: c5_robot::description::RUS_HEXAPOD,
        what: "The 6-RUS inverse dynamics with every parameter an input (inverse kinematics \
               included)",
        mul: 43548,
        add: 26665,
    },
    Peer {
        mechanism: c5_robot::description::DELTA,
        what: "The Delta's inverse dynamics with every parameter an input (inverse kinematics \
               included)",
        mul: 3010,
        add: 1835,
    },
];

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
    table_of(&|m| model.is_none_or(|model| model.name() == m))
}

/// The audit table of the kernels whose model `keep` keeps.
fn table_of(keep: &dyn Fn(&str) -> bool) -> String {
    let mut out = format!(
        "{:<10} {:<30} {:>8} {:>12} {:>12} {:>6}  mul/div/add/neg, calls\n",
        "model", "kernel", "setting", "chapter", "generated", "ratio"
    );
    for e in KERNELS.iter().filter(|e| keep(e.model)) {
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
        "\nratio = generated (m + a) / chapter (m + a); a division counts as a multiplication.\n",
    );
    if keep("consistent") || keep("paper") {
        out.push_str(
            "The chapter's Khalil step 6 (J⁻¹ by eq 22, then an LU solve of eq 61) costs 134m + 125a;\n\
             the generated factored step 6 is `step6_factored`.\n",
        );
    }
    for peer in &ROBSYNTH {
        let Some(e) = KERNELS
            .iter()
            .find(|e| e.model == peer.mechanism && e.name == "inverse_dynamics_params")
            .filter(|_| keep(peer.mechanism))
        else {
            continue;
        };
        let c = &e.count;
        out.push_str(&format!(
            "{}: generated `inverse_dynamics_params` {}/{}/{}/{} ({} calls), robsynth's {}m + \
             {}a: {:.2} of its multiplications, {:.2} of its additions.\n",
            peer.what,
            c.mul,
            c.div,
            c.add,
            c.neg,
            c.calls.iter().map(|(_, n)| n).sum::<u32>(),
            peer.mul,
            peer.add,
            f64::from(c.mul) / f64::from(peer.mul),
            f64::from(c.add) / f64::from(peer.add),
        ));
    }
    out
}

pub fn run(args: &AuditArgs) -> crate::Result<ExitCode> {
    let table = match &args.robot {
        None => table(args.model),
        Some(path) => {
            let mechanism = match Description::from_toml_file(path)? {
                Description::C5(_) => None,
                other => Some(other.mechanism()),
            };
            let model = args.model;
            table_of(&move |m| match mechanism {
                Some(name) => m == name,
                None => {
                    m != c5_runtime::gough_stewart::MECHANISM
                        && model.is_none_or(|model| model.name() == m)
                }
            })
        }
    };
    std::io::stdout().lock().write_all(table.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}
