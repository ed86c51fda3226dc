//! The checked-in `generated/` crate is exactly what the generator writes today.
//!
//! On a mismatch the test fails; run it with `UPDATE_GENERATED=1` to rewrite the files (or run
//! `cargo run -p c5-codegen-cli -- generate`), then commit them.

use c5_codegen::manifest::Manifest;
use std::path::Path;

#[test]
fn generated_files_are_fresh() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated");
    let mut stale = Vec::new();
    for (rel, contents) in c5_codegen::generated_crate_files().expect("generation succeeds") {
        let path = dir.join(&rel);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(contents.as_str()) {
            if std::env::var_os("UPDATE_GENERATED").is_some() {
                std::fs::write(&path, &contents).expect("rewrite");
            }
            stale.push(rel.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "stale generated files: {stale:?}; regenerate with `UPDATE_GENERATED=1 cargo test --test freshness` or `{}`",
        c5_codegen::REGENERATE
    );
}

fn fresh_manifest() -> Manifest {
    let files = c5_codegen::generated_crate_files().expect("generation succeeds");
    let (_, json) = files
        .iter()
        .find(|(rel, _)| rel == Path::new("ops.json"))
        .expect("ops.json is generated");
    serde_json::from_str(json).unwrap()
}

#[test]
fn the_compiled_in_manifest_holds_the_counts_of_a_fresh_generation() {
    let shipped: Manifest = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    let fresh = fresh_manifest();
    assert_eq!(shipped.kernels.len(), fresh.kernels.len());
    for (got, want) in shipped.kernels.iter().zip(&fresh.kernels) {
        assert_eq!(got, want, "{} ({})", want.name, want.model);
    }
    // The chapter's kernels are there, with their published counts beside ours.
    for name in [
        "inverse_jacobian",
        "pi1",
        "jacobian",
        "joint_accelerations_segment",
        "step6_factored",
    ] {
        let e = shipped
            .kernels
            .iter()
            .find(|k| k.name == name)
            .unwrap_or_else(|| panic!("{name} missing"));
        assert!(e.chapter.is_some(), "{name} has the chapter's count");
    }
}

#[test]
fn every_generated_function_has_its_manifest_entry_and_model() {
    let manifest: Manifest = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/src/f64");
    for model in c5_codegen::Model::ALL {
        let code = ["", "_regressor"]
            .map(|part| std::fs::read_to_string(dir.join(format!("{model}{part}.rs"))).unwrap())
            .concat();
        let functions: Vec<&str> = code
            .lines()
            .filter_map(|l| l.strip_prefix("pub fn "))
            .map(|l| l.split('(').next().unwrap())
            .collect();
        let listed: Vec<&str> = manifest
            .kernels
            .iter()
            .filter(|k| k.model == model)
            .map(|k| k.name.as_str())
            .collect();
        assert_eq!(functions, listed, "{model}");
        for kernel in ["inverse_dynamics", "regressor", "base_regressor"] {
            assert!(functions.contains(&kernel), "{model}: {kernel}");
        }
    }
}

#[test]
fn chapter_kernels_beat_the_chapter() {
    let m: Manifest = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    for k in m.kernels.iter().filter(|k| k.chapter.is_some()) {
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
