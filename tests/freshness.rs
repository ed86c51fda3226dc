//! The checked-in `generated/` crate is exactly what the generator writes today.
//!
//! On a mismatch the test fails; run it with `UPDATE_GENERATED=1` to rewrite the files (or run
//! `cargo run -p c5-codegen -- generate`), then commit them.

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

#[test]
fn manifest_lists_every_kernel_with_counts() {
    let m: serde_json::Value = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    let kernels = m["kernels"].as_array().unwrap();
    for name in [
        "inverse_jacobian",
        "pi1",
        "jacobian",
        "joint_accelerations_segment",
        "step6_factored",
        "inverse_dynamics",
    ] {
        let k = kernels
            .iter()
            .find(|k| k["name"] == name)
            .unwrap_or_else(|| panic!("{name} missing"));
        for key in ["mul", "div", "add", "neg"] {
            assert!(k[key].is_u64(), "{name}.{key}");
        }
    }
}

#[test]
fn chapter_kernels_beat_the_chapter() {
    let m: serde_json::Value = serde_json::from_str(c5_generated::OPS_JSON).unwrap();
    for k in m["kernels"].as_array().unwrap() {
        if !k["chapter"].is_null() {
            let n = |key: &str| k[key].as_u64().unwrap();
            let (cm, ca) = (
                k["chapter"]["m"].as_u64().unwrap(),
                k["chapter"]["a"].as_u64().unwrap(),
            );
            assert!(n("mul") + n("div") <= cm && n("add") <= ca, "{}", k["name"]);
        }
    }
}
