//! Every error bound the README or `docs/` states names the test that asserts it.
//!
//! A figure in `1e-7` notation in plain text is a claim: the paragraph, list item or table
//! (with the paragraph that introduces it) that states it must name, in backticks, a test
//! function of this repository (Rust `#[test]`, proptest, or Python `test_*`). That test asserts
//! the figure with at most ten times margin (docs/verification.md, "Figures and their tests").
//! A figure in a code span (`` `1e-9` ``) is a value one sets or reads (a tolerance, a step, an
//! input, a message), not a claim, and code blocks are code.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

pub(super) fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` with extension `ext`, outside build output and generated code.
pub(super) fn files(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let skip = ["target", ".git", "generated", "node_modules", ".venv"];
        if path.is_dir() && !skip.iter().any(|s| name == *s) {
            files(&path, ext, out);
        } else if path.extension().is_some_and(|e| e == ext) {
            out.push(path);
        }
    }
}

/// The identifier after `keyword` at the start of `text` (after spaces), if any.
fn identifier_after<'t>(text: &'t str, keyword: &str) -> Option<&'t str> {
    let rest = text.trim_start().strip_prefix(keyword)?;
    let end = rest
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
}

/// The names of the repository's tests: Rust functions marked `#[test]` or inside a
/// `proptest!`, Python `def test_*`.
fn test_names() -> HashSet<String> {
    let mut names = HashSet::new();
    let mut rust = Vec::new();
    files(root(), "rs", &mut rust);
    for path in rust {
        let text = fs::read_to_string(&path).unwrap();
        let mut pending = false;
        let mut in_proptest = false;
        for line in text.lines() {
            let line = line.trim();
            if line.starts_with("proptest!") {
                in_proptest = true;
            }
            if line == "#[test]" {
                pending = true;
            }
            if let Some(name) = identifier_after(line, "fn ") {
                if pending || in_proptest {
                    names.insert(name.to_string());
                }
                pending = false;
            }
        }
    }
    let mut python = Vec::new();
    files(&root().join("python"), "py", &mut python);
    for path in python {
        for line in fs::read_to_string(&path).unwrap().lines() {
            if let Some(name) = identifier_after(line, "def ") {
                if name.starts_with("test_") {
                    names.insert(name.to_string());
                }
            }
        }
    }
    names
}

/// Whether `text` has a figure like `3.8e-10` outside code spans.
fn plain_figure(text: &str) -> Option<String> {
    let mut in_code = false;
    let chars: Vec<char> = text.chars().collect();
    for (k, &c) in chars.iter().enumerate() {
        if c == '`' {
            in_code = !in_code;
            continue;
        }
        let starts = c.is_ascii_digit()
            && (k == 0 || !(chars[k - 1].is_alphanumeric() || chars[k - 1] == '.'));
        if in_code || !starts {
            continue;
        }
        let mut j = k;
        while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.') {
            j += 1;
        }
        if chars.get(j) == Some(&'e')
            && chars.get(j + 1) == Some(&'-')
            && chars.get(j + 2).is_some_and(char::is_ascii_digit)
        {
            let end = (j + 2..=chars.len())
                .find(|&e| !chars.get(e).is_some_and(char::is_ascii_digit))
                .unwrap_or(chars.len());
            return Some(chars[k..end].iter().collect());
        }
    }
    None
}

/// The words in backticks in `text`, each with any `path::` prefix removed.
fn code_spans(text: &str) -> impl Iterator<Item = &str> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .map(|span| span.rsplit("::").next().unwrap_or(span))
}

/// A claim and the text that may name its test.
struct Claim {
    /// Where: file and line.
    at: String,
    /// The figure found.
    figure: String,
    /// The claim's own text and its context (a list item's parents, a table's introduction).
    text: String,
}

/// The paragraphs, list items and tables of `doc` that state a figure. A list item may lean on
/// the items it is nested in; a table on the paragraph before it.
fn claims(doc: &Path) -> Vec<Claim> {
    let text = fs::read_to_string(doc).unwrap();
    let name = doc.strip_prefix(root()).unwrap().display().to_string();
    let mut out = Vec::new();
    // (indent, text) of the list items enclosing the current line.
    let mut parents: Vec<(usize, String)> = Vec::new();
    let mut block = String::new();
    let mut block_start = 0;
    let mut previous_block = String::new();
    let mut in_code_block = false;
    let flush = |block: &mut String, start: usize, context: &str, out: &mut Vec<Claim>| {
        if let Some(figure) = plain_figure(block) {
            out.push(Claim {
                at: format!("{name}:{}", start + 1),
                figure,
                text: format!("{context}\n{block}"),
            });
        }
        block.clear();
    };
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code_block = !in_code_block;
            continue;
        }
        if in_code_block {
            continue;
        }
        let indent = line.len() - line.trim_start().len();
        let item = [
            "- ", "* ", "1. ", "2. ", "3. ", "4. ", "5. ", "6. ", "7. ", "8. ", "9. ",
        ]
        .iter()
        .any(|m| line.trim_start().starts_with(m));
        let blank = line.trim().is_empty();
        let table = line.trim_start().starts_with('|');
        let block_is_table = block.trim_start().starts_with('|');
        if blank || item || (table != block_is_table && !block.is_empty()) {
            let context = if block_is_table {
                previous_block.clone()
            } else {
                parents.iter().map(|(_, t)| t.as_str()).collect()
            };
            if !block.trim().is_empty() {
                previous_block = block.clone();
            }
            flush(&mut block, block_start, &context, &mut out);
            if blank {
                parents.clear();
            }
        }
        if item {
            parents.retain(|&(i, _)| i < indent);
            parents.push((indent, line.to_string()));
        } else if let Some(last) = parents.last_mut() {
            last.1.push_str(line);
        }
        if block.is_empty() {
            block_start = number;
        }
        block.push_str(line);
        block.push('\n');
    }
    let context: String = parents.iter().map(|(_, t)| t.as_str()).collect();
    flush(&mut block, block_start, &context, &mut out);
    out
}

#[test]
fn every_stated_bound_names_its_test() {
    let names = test_names();
    assert!(names.len() > 200, "found only {} tests", names.len());
    let mut docs = vec![root().join("README.md")];
    files(&root().join("docs"), "md", &mut docs);
    let unnamed: Vec<String> = docs
        .iter()
        .flat_map(|doc| claims(doc))
        .filter(|claim| !code_spans(&claim.text).any(|span| names.contains(span)))
        .map(|claim| format!("{} ({})", claim.at, claim.figure))
        .collect();
    assert!(
        unnamed.is_empty(),
        "figures that name no test (name the test that asserts each, in backticks; or write a \
         value that is not a claim as code):\n{}",
        unnamed.join("\n")
    );
}

#[test]
fn a_figure_in_code_is_not_a_claim_and_one_in_text_is() {
    assert_eq!(
        plain_figure("to 3.8e-10 relative").as_deref(),
        Some("3.8e-10")
    );
    assert_eq!(plain_figure("below `1e-9` (a tolerance)"), None);
    assert_eq!(plain_figure("version 1.2e-3x"), Some("1.2e-3".into()));
    assert_eq!(plain_figure("x1e-9"), None);
    assert_eq!(plain_figure("speed 1e6, 12 e-3"), None);
}
