//! Every robot-file example in the docs is one a user can copy: each ```toml block of README.md
//! and docs/*.md, completed from its mechanism's example file where it elides legs (`# ... five
//! more [[legs]]`), is read by `Description::from_toml`; every docs/*.toml file is read as it
//! is. A field in the wrong table (a `home` after `[[legs]]`, which TOML gives to the last leg)
//! fails here.

use c5_robot::Description;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The ```toml blocks of a Markdown file, with the line each starts on.
fn toml_blocks(path: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut blocks = Vec::new();
    let mut open: Option<(usize, String)> = None;
    for (n, line) in text.lines().enumerate() {
        match &mut open {
            None if line.trim_start() == "```toml" => open = Some((n + 1, String::new())),
            Some(_) if line.trim_start() == "```" => blocks.push(open.take().unwrap()),
            Some((_, block)) => {
                block.push_str(line);
                block.push('\n');
            }
            None => {}
        }
    }
    blocks
}

/// The documented example file of a mechanism, and the name of its list of legs.
fn example_of(mechanism: &str) -> (PathBuf, &'static str) {
    let docs = root().join("docs");
    match mechanism {
        "gough-stewart" => (docs.join("hexapod.toml"), "legs"),
        "rus-hexapod" => (docs.join("rus-hexapod.toml"), "legs"),
        "delta" => (docs.join("delta.toml"), "arms"),
        _ => (docs.join("default-robot.toml"), "segments"),
    }
}

/// `snippet` laid over its mechanism's example file: its tables merged key by key, its k-th
/// leg over the example's k-th.
fn completed(snippet: &toml::Table) -> String {
    let mechanism = snippet
        .get("mechanism")
        .and_then(|m| m.as_str())
        .unwrap_or("c5");
    let (path, legs) = example_of(mechanism);
    let mut whole: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for (key, value) in snippet {
        match (whole.get_mut(key), value) {
            (Some(toml::Value::Array(items)), toml::Value::Array(given)) if key == legs => {
                for (item, given) in items.iter_mut().zip(given) {
                    if let (Some(item), Some(given)) = (item.as_table_mut(), given.as_table()) {
                        item.extend(given.clone());
                    }
                }
            }
            (Some(toml::Value::Table(table)), toml::Value::Table(given)) => {
                table.extend(given.clone());
            }
            _ => {
                whole.insert(key.clone(), value.clone());
            }
        }
    }
    toml::to_string(&whole).unwrap()
}

#[test]
fn every_robot_file_example_in_the_docs_is_read() {
    let mut docs = vec![root().join("README.md")];
    for entry in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        if entry.path().extension().is_some_and(|e| e == "md") {
            docs.push(entry.path());
        }
    }
    let mut read = 0;
    for doc in &docs {
        for (line, block) in toml_blocks(doc) {
            let at = format!("{}:{line}", doc.display());
            let snippet: toml::Table =
                toml::from_str(&block).unwrap_or_else(|e| panic!("{at}: not TOML: {e}"));
            Description::from_toml(&completed(&snippet), &at)
                .unwrap_or_else(|e| panic!("{at}: the example is refused: {e}"));
            read += 1;
        }
    }
    assert!(read >= 4, "found only {read} examples");
}

#[test]
fn every_robot_file_in_docs_is_read() {
    let mut read = 0;
    for entry in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        let path = entry.path();
        if path.extension().is_some_and(|e| e == "toml") {
            Description::from_toml_file(&path).unwrap_or_else(|e| panic!("{e}"));
            read += 1;
        }
    }
    assert!(read >= 5, "found only {read} robot files");
}

#[test]
fn a_home_after_the_legs_is_caught() {
    // The mistake docs/mechanisms.md made: TOML gives a key after `[[legs]]` to the last leg.
    let snippet: toml::Table = toml::from_str(
        "mechanism = \"gough-stewart\"\n[[legs]]\nencoder_offset = 0.0\nhome = [0, 0, 0, 0, 0, 0.45]\n",
    )
    .unwrap();
    let err = Description::from_toml(&completed(&snippet), "snippet")
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown field `home`"), "{err}");
}
