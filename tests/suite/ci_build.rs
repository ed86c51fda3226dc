//! CI's `pip install` builds the Python module on the kernels the tests' build compiled: the
//! module's feature `tests-build` gives `c5-generated` and `c5-runtime` the features that
//! `cargo test --workspace --release` gives them, so cargo reuses the tests' units instead of
//! compiling the kernels a second time (python/Cargo.toml, `.ci/run`).

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

/// The features cargo resolves for `package` when building `selection` (`cargo tree`'s
/// inverted feature graph, from the lock file).
fn features_of(package: &str, selection: &[&str]) -> BTreeSet<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")))
        .args(["tree", "--locked", "--prefix", "none", "-e", "features"])
        .args(selection)
        .args(["-i", package])
        .output()
        .expect("cargo runs");
    assert!(
        output.status.success(),
        "cargo tree: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let prefix = format!("{package} feature \"");
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .filter_map(|line| line.strip_prefix(&prefix)?.split('"').next())
        .map(str::to_owned)
        .collect()
}

#[test]
fn the_python_modules_ci_build_has_the_tests_kernel_features() {
    let module = ["-p", "c5-python", "--features", "tests-build"];
    for package in ["c5-generated", "c5-runtime"] {
        let tests = features_of(package, &["--workspace"]);
        assert!(tests.contains("derivatives"), "{package}: {tests:?}");
        assert_eq!(
            features_of(package, &module),
            tests,
            "{package}: python/Cargo.toml's `tests-build` differs from the tests' features"
        );
    }
}
