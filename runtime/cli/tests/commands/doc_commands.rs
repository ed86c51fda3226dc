//! Every command line of the README and of docs/ that runs the program, run as written: the
//! lines of `sh` blocks and the inline `cargo run --release …` spans, `cargo run … --` and `c5`
//! both meaning the program these tests build with every command. Each page runs in its own
//! scratch directory, in the page's order (a later line reads what an earlier one wrote), with a
//! copy of docs/ beside it; a line's standard input is its `echo '…' |` or its `< file`.
//!
//! The files a reader brings (`states.jsonl`, `forces.jsonl`, `hexapod.toml`,
//! `measurements.csv`) are stood in for by [`FIXTURES`]. Lines that run something other than
//! the program (the generator, `cc`, Python, git) are left to their own tests, and named in
//! [`OTHER_PROGRAMS`] so that a new kind of line is noticed.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// What a line that starts with one of these runs is not the program.
const OTHER_PROGRAMS: &[&str] = &[
    "cargo test",
    "cargo run -p c5-codegen-cli",
    "cargo run -p c5-codegen ",
    "cc ",
    "pip ",
    "python",
    "git ",
    "time cargo test",
    "time bash",
    "#",
];

/// The files the docs' lines read that a user brings, and what the test puts there: the
/// default robot's state and forces, the example hexapod, and the example's measurements.
const FIXTURES: &[(&str, Fixture)] = &[
    ("states.jsonl", Fixture::Text(STATE)),
    ("forces.jsonl", Fixture::Text(FORCES)),
    ("hexapod.toml", Fixture::Copy("docs/hexapod.toml")),
    (
        "measurements.csv",
        Fixture::Copy("docs/calibration/measurements.csv"),
    ),
];

const STATE: &str = "{\"pose\": [0.1, 0.05, -0.08, 0.01, 0.02, -0.03], \"omega\": [0.2, 0, 0]}\n";
const FORCES: &str =
    "{\"pose\": [0.1, 0.05, -0.08, 0.01, 0.02, -0.03], \"gamma\": [10, -5, 3, 0, 40, 41]}\n";

enum Fixture {
    Text(&'static str),
    Copy(&'static str),
}

/// One command line of a page.
#[derive(Debug)]
struct Line {
    /// Where it is: the page and the line the command starts on.
    at: String,
    /// The program's arguments.
    args: Vec<String>,
    /// Its standard input: an `echo`'s text, or a file of the scratch directory.
    stdin: Option<Input>,
}

#[derive(Debug)]
enum Input {
    Text(String),
    File(String),
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The page's shell lines (continuations joined, comments cut) with their line numbers, and its
/// prose without its code blocks.
fn shell_lines_and_prose(text: &str) -> (Vec<(usize, String)>, String) {
    let (mut lines, mut prose) = (Vec::new(), String::new());
    let mut block: Option<bool> = None;
    let mut pending: Option<(usize, String)> = None;
    for (k, raw) in text.lines().enumerate() {
        if raw.trim_start().starts_with("```") {
            block = match block {
                None => Some(raw.trim_start() == "```sh"),
                Some(_) => None,
            };
            continue;
        }
        match block {
            None => {
                prose.push_str(raw);
                prose.push('\n');
            }
            Some(false) => {}
            Some(true) => {
                let line = without_comment(raw);
                let (start, mut joined) = pending.take().unwrap_or((k + 1, String::new()));
                joined.push(' ');
                joined.push_str(line.trim().trim_end_matches('\\').trim());
                if line.trim_end().ends_with('\\') {
                    pending = Some((start, joined));
                } else if !joined.trim().is_empty() {
                    lines.push((start, joined.trim().to_string()));
                }
            }
        }
    }
    (lines, prose)
}

/// `line` without a `# comment` outside quotes.
fn without_comment(line: &str) -> &str {
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '#') if i == 0 || line[..i].ends_with(' ') => return &line[..i],
            _ => {}
        }
    }
    line
}

/// The inline `cargo run --release …` spans of the prose, a span's line breaks as spaces.
fn inline_commands(prose: &str) -> Vec<String> {
    prose
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|span| span.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|span| span.starts_with("cargo run --release"))
        .collect()
}

/// Splits a command at spaces, keeping quoted text whole (without its quotes).
fn words(command: &str) -> Vec<String> {
    let (mut words, mut word, mut quote) = (Vec::new(), String::new(), None);
    for c in command.chars() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, ' ') if !word.is_empty() => words.push(std::mem::take(&mut word)),
            (None, ' ') => {}
            _ => word.push(c),
        }
    }
    if !word.is_empty() {
        words.push(word);
    }
    words
}

/// The program's line of `command`, `None` for another program's (which must be one of
/// [`OTHER_PROGRAMS`]) or for a placeholder (`…`).
fn program_line(at: String, command: &str) -> Option<Line> {
    let (echo, command) = match command.split_once(" | ") {
        Some((echo, rest)) if echo.starts_with("echo ") => (Some(words(echo)[1].clone()), rest),
        _ => (None, command),
    };
    let command = command.trim();
    let mut all = words(command);
    if all.iter().any(|w| w == "..." || w == "…") {
        return None;
    }
    let args = if let Some(rest) = command.strip_prefix("c5 ") {
        words(rest)
    } else if command.starts_with("cargo run")
        && !command.contains(" -p c5-codegen")
        && all.iter().any(|w| w == "--")
    {
        let dashes = all.iter().position(|w| w == "--").unwrap();
        all.split_off(dashes + 1)
    } else if command.starts_with("time cargo run") {
        let dashes = all.iter().position(|w| w == "--")?;
        all.split_off(dashes + 1)
    } else {
        assert!(
            OTHER_PROGRAMS.iter().any(|p| command.starts_with(p)),
            "{at}: `{command}` runs neither the program nor one of the others named here"
        );
        return None;
    };
    let (mut args, mut stdin) = (args, echo.map(|text| Input::Text(text + "\n")));
    if let Some(k) = args.iter().position(|w| w == "<") {
        stdin = Some(Input::File(args[k + 1].clone()));
        args.truncate(k);
    }
    Some(Line { at, args, stdin })
}

/// Every line of `page` that runs the program, in the page's order (its `sh` blocks first,
/// then its prose's spans, which mostly name what the blocks show).
fn lines_of(page: &Path) -> Vec<Line> {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page.file_name().unwrap().to_string_lossy().into_owned();
    let (shell, prose) = shell_lines_and_prose(&text);
    let blocks = shell
        .into_iter()
        .filter_map(|(k, command)| program_line(format!("{name}:{k}"), &command));
    let spans = inline_commands(&prose)
        .into_iter()
        .filter_map(|command| program_line(format!("{name} (prose): `{command}`"), &command));
    blocks.chain(spans).collect()
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

fn scratch_root() -> PathBuf {
    std::env::temp_dir().join(format!("c5-doc-commands-{}", std::process::id()))
}

/// A scratch directory for `page`: a copy of docs/ and the fixtures.
fn scratch(page: &str) -> PathBuf {
    let dir = scratch_root().join(page);
    let _ = std::fs::remove_dir_all(&dir);
    copy_tree(&root().join("docs"), &dir.join("docs"));
    for (name, fixture) in FIXTURES {
        match fixture {
            Fixture::Text(text) => std::fs::write(dir.join(name), text).unwrap(),
            Fixture::Copy(from) => {
                std::fs::copy(dir.join(from), dir.join(name)).unwrap();
            }
        }
    }
    dir
}

/// Runs `line` in `dir`; its standard error if it fails.
fn run(line: &Line, dir: &Path) -> Result<(), String> {
    let stdin = match &line.stdin {
        None => Stdio::null(),
        Some(Input::Text(_)) => Stdio::piped(),
        Some(Input::File(name)) => std::fs::File::open(dir.join(name))
            .map_err(|e| format!("{name}: {e}"))?
            .into(),
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_c5"))
        .args(&line.args)
        .current_dir(dir)
        .stdin(stdin)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("c5 runs");
    if let Some(Input::Text(text)) = &line.stdin {
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    let out = child.wait_with_output().unwrap();
    match out.status.success() {
        true => Ok(()),
        false => Err(String::from_utf8_lossy(&out.stderr).into_owned()),
    }
}

#[test]
fn every_command_line_of_the_readme_and_the_docs_runs_as_written() {
    let mut pages = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    let (mut ran, mut failed) = (0, Vec::new());
    for page in &pages {
        let lines = lines_of(page);
        if lines.is_empty() {
            continue;
        }
        let dir = scratch(&page.file_stem().unwrap().to_string_lossy());
        for line in &lines {
            ran += 1;
            if let Err(why) = run(line, &dir) {
                failed.push(format!("{}: c5 {}\n{why}", line.at, line.args.join(" ")));
            }
        }
    }
    assert!(ran > 40, "only {ran} command lines found");
    assert!(
        failed.is_empty(),
        "{} of {ran} failed:\n{}",
        failed.len(),
        failed.join("\n")
    );
    // The pages' copies of docs/ and what they wrote; kept where a line failed, to look at.
    let _ = std::fs::remove_dir_all(scratch_root());
}

/// The parsing the test above relies on.
#[test]
fn lines_are_read_as_a_shell_reads_them() {
    let (lines, prose) = shell_lines_and_prose(
        "a `cargo run --release -- audit\n--robot docs/delta.toml` b\n```sh\necho '{\"q\": [1, 2]}' \\\n  | cargo run --release -- eval   # q\nc5 calibrate --plan 6 \\\n   --out p.csv\n```\n",
    );
    assert_eq!(lines.len(), 2);
    let eval = program_line("x".into(), &lines[0].1).unwrap();
    assert_eq!(eval.args, ["eval"]);
    assert!(matches!(eval.stdin, Some(Input::Text(ref t)) if t == "{\"q\": [1, 2]}\n"));
    let plan = program_line("y".into(), &lines[1].1).unwrap();
    assert_eq!(plan.args, ["calibrate", "--plan", "6", "--out", "p.csv"]);
    let spans = inline_commands(&prose);
    assert_eq!(
        spans,
        ["cargo run --release -- audit --robot docs/delta.toml"]
    );
    let piped = program_line("z".into(), "cargo run --release -- eval < states.jsonl").unwrap();
    assert!(matches!(piped.stdin, Some(Input::File(ref f)) if f == "states.jsonl"));
    assert!(program_line("w".into(), "cargo run -p c5-codegen-cli -- generate").is_none());
    assert!(program_line("v".into(), "cargo run --release …").is_none());
}
