//! The C example of `docs/c-output.md`: `main.c` and the `cc` command beside it, built and run
//! against kernels generated as the guide says.

use std::path::Path;
use std::process::Command;

/// The fenced block of the guide whose first line starts with `first`.
fn block(readme: &str, fence: &str, first: &str) -> String {
    readme
        .split(&format!("```{fence}\n"))
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .find(|b| b.starts_with(first))
        .unwrap_or_else(|| panic!("the guide has a ```{fence} block starting with {first:?}"))
        .to_string()
}

#[test]
fn the_readme_c_example_builds_and_runs() {
    let readme = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/c-output.md"),
    )
    .unwrap();
    let main_c = block(&readme, "c", "/* main.c");
    let commands = block(&readme, "sh", "# C:");
    let build = commands
        .lines()
        .find(|l| l.starts_with("cc "))
        .expect("the cc command")
        .split(" && ")
        .next()
        .unwrap()
        .to_string();
    let dir = std::env::temp_dir().join(format!("c5-readme-c-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("main.c"), main_c).unwrap();
    // What `c5-codegen kernels --lang c --out .` writes.
    for (name, contents) in c5_codegen::Config::new()
        .language(c5_codegen::Language::C)
        .generate_files()
        .unwrap()
    {
        std::fs::write(dir.join(name), contents).unwrap();
    }
    let status = Command::new("sh")
        .arg("-c")
        .arg(&build)
        .current_dir(&dir)
        .status()
        .unwrap();
    assert!(status.success(), "{build}");
    let out = Command::new(dir.join("main")).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    // The consistent model at rest, α=10° β=15° γ=20°.
    assert!(
        text.contains("gamma1 = -8.02") && text.contains("gamma5 = 80.39"),
        "{text}"
    );
}
