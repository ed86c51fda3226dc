//! The checked-in `generated/` crate agrees with itself: the compiled-in manifest with
//! `ops.json`, every generated function with its manifest entry, the chapter's kernels with the
//! chapter's counts.
//!
//! That the checked-in files are exactly what the generator writes today is the codegen CLI's
//! test (`codegen/cli/tests/cli.rs`, one generation through `c5-codegen generate`); on a
//! mismatch it fails, and `UPDATE_GENERATED=1` rewrites them (or run
//! `cargo run -p c5-codegen-cli -- generate`), then commit them.

use c5_generated::manifest::{entry, Kernel, KERNELS};
use serde_json::Value;
use std::path::Path;

/// The kernels of the checked-in `ops.json`, which the codegen CLI's test holds equal to a
/// fresh generation.
fn fresh_manifest() -> Vec<Value> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/ops.json");
    let manifest: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    manifest["kernels"].as_array().unwrap().clone()
}

#[test]
fn the_compiled_in_manifest_holds_the_counts_of_a_fresh_generation() {
    let fresh = fresh_manifest();
    assert_eq!(KERNELS.len(), fresh.len());
    for (got, want) in KERNELS.iter().zip(&fresh) {
        let calls: u64 = want["calls"]
            .as_object()
            .unwrap()
            .values()
            .map(|v| v.as_u64().unwrap())
            .sum();
        let c = &got.count;
        assert_eq!(
            (got.name, got.model, got.setting),
            (
                want["name"].as_str().unwrap(),
                want["model"].as_str().unwrap(),
                want["setting"].as_str().unwrap()
            )
        );
        assert_eq!(
            [c.mul, c.div, c.add, c.neg].map(u64::from),
            ["mul", "div", "add", "neg"].map(|k| want[k].as_u64().unwrap()),
            "{} ({})",
            got.name,
            got.model
        );
        assert_eq!(
            c.calls.iter().map(|(_, k)| u64::from(*k)).sum::<u64>(),
            calls
        );
        assert_eq!(got.chapter.is_some(), !want["chapter"].is_null());
    }
    // The chapter's kernels are there, with their published counts beside ours.
    for kernel in [
        Kernel::InverseJacobian,
        Kernel::Pi1,
        Kernel::Jacobian,
        Kernel::JointAccelerationsSegment,
        Kernel::Step6Factored,
    ] {
        let e = entry("paper", kernel, false).unwrap_or_else(|| panic!("{kernel:?} missing"));
        assert!(e.chapter.is_some(), "{kernel:?} has the chapter's count");
    }
}

#[test]
fn the_parameter_count_is_the_robot_descriptions() {
    let names = c5_robot::Robot::<f64>::kernel_parameter_names();
    assert_eq!(c5_generated::PARAMETERS, names.len());
    assert_eq!(c5_generated::PARAMETERS, c5_robot::PARAMETERS);
    assert!(c5_generated::PARAMETER_NAMES.iter().eq(names.iter()));
}

#[test]
fn every_generated_function_has_its_manifest_entry_and_model() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/src/f64");
    for model in c5_codegen::Model::ALL {
        // The robot-free and `_params` kernels, and the folded ones in files of their own.
        let code = [
            "",
            "_folded",
            "_derivatives",
            "_folded_derivatives",
            "_regressor",
        ]
        .map(|part| std::fs::read_to_string(dir.join(format!("{model}{part}.rs"))).unwrap())
        .concat();
        let all: Vec<&str> = code
            .lines()
            .filter_map(|l| l.strip_prefix("pub fn "))
            .map(|l| l.split('(').next().unwrap())
            .collect();
        // The FMA twins of a kernel sit beside it: `{kernel}_separate` (safe), written once
        // with `#[fma_twin]`, which makes `{kernel}_fused` (`unsafe`, FMA only) of it; the
        // regressors have none.
        let mut functions: Vec<&str> = all
            .iter()
            .copied()
            .filter(|f| !f.ends_with("_separate"))
            .collect();
        for f in functions.iter().filter(|f| !f.ends_with("regressor")) {
            assert!(
                all.contains(&format!("{f}_separate").as_str()),
                "{model}: {f}_separate"
            );
            assert!(
                code.contains(&format!("fma_twin({f}_fused, f64::mul_add)")),
                "{model}: {f}_fused"
            );
        }
        let mut listed: Vec<&str> = KERNELS
            .iter()
            .filter(|k| k.model == model.name())
            .map(|k| k.name)
            .collect();
        functions.sort_unstable();
        listed.sort_unstable();
        assert_eq!(functions, listed, "{model}");
        for kernel in [
            Kernel::InverseDynamics,
            Kernel::Regressor,
            Kernel::BaseRegressor,
        ] {
            assert!(functions.contains(&kernel.name()), "{model}: {kernel:?}");
            assert!(
                entry(model.name(), kernel, false).is_some(),
                "{model}: {kernel:?}"
            );
        }
    }
}

#[test]
fn chapter_kernels_beat_the_chapter() {
    for k in KERNELS.iter().filter(|k| k.chapter.is_some()) {
        let ch = k.chapter.unwrap();
        let c = &k.count;
        assert!(
            c.mul + c.div <= ch.m && c.add <= ch.a,
            "{}: {}m + {}a against the chapter's {}m + {}a",
            k.name,
            c.chapter_m(),
            c.chapter_a(),
            ch.m,
            ch.a
        );
    }
}
