//! One source for every speed figure: docs/speed.md's generated table.
//!
//! `python3 benches/speed_table.py` runs every bench the docs cite in one run and writes the
//! table between docs/speed.md's `speed-table` markers. A time in plain text anywhere in the
//! README or `docs/` (nanoseconds, microseconds, milliseconds: what a kernel, a call or a batch
//! takes) must be one of that table's figures, written as the table writes it, and a page other
//! than speed.md that states one links to it. A time in a code span is a value one sets (a
//! step, a timeout), not a measurement; seconds measure builds and whole programs
//! (docs/build-time.md).

use std::collections::BTreeSet;
use std::fs;
use std::path::PathBuf;

use super::docs_figures::{files, root};

const BEGIN: &str = "<!-- speed-table: begin";
const END: &str = "<!-- speed-table: end -->";

/// The unit at `chars[k..]`, normalised, when a time's unit starts there and ends a word.
fn unit_at(chars: &[char], k: usize) -> Option<(&'static str, usize)> {
    let units: [(&[char], &str); 4] = [
        (&['n', 's'], "ns"),
        (&['µ', 's'], "µs"),
        (&['μ', 's'], "µs"),
        (&['m', 's'], "ms"),
    ];
    units.iter().find_map(|&(spelling, unit)| {
        let end = k + spelling.len();
        let ends_word = !chars.get(end).is_some_and(|c| c.is_alphanumeric());
        (chars.get(k..end) == Some(spelling) && ends_word).then_some((unit, end))
    })
}

/// The number that ends just before `end` (digits and points), with where it starts.
fn number_before(chars: &[char], end: usize) -> Option<(String, usize)> {
    let start = (0..end)
        .rev()
        .take_while(|&i| chars[i].is_ascii_digit() || chars[i] == '.')
        .last()?;
    let starts_word = start == 0 || !chars[start - 1].is_alphanumeric();
    let text: String = chars[start..end].iter().collect();
    let text = text.trim_start_matches('.').to_string();
    (starts_word && text.starts_with(|c: char| c.is_ascii_digit())).then_some((text, start))
}

/// The times stated in `line` outside code spans, as `44.6 ns`; a range `43-45 ns` gives both
/// ends.
fn times(line: &str) -> Vec<String> {
    let chars: Vec<char> = line.chars().collect();
    let mut found = Vec::new();
    let mut in_code = false;
    for k in 0..chars.len() {
        if chars[k] == '`' {
            in_code = !in_code;
        }
        let Some((unit, _)) = unit_at(&chars, k).filter(|_| !in_code) else {
            continue;
        };
        let number_end = if k > 0 && chars[k - 1] == ' ' {
            k - 1
        } else {
            k
        };
        let Some((number, start)) = number_before(&chars, number_end) else {
            continue;
        };
        found.push(format!("{number} {unit}"));
        let dash = start
            .checked_sub(1)
            .filter(|&d| matches!(chars[d], '-' | '–'));
        if let Some((low, _)) = dash.and_then(|d| number_before(&chars, d)) {
            found.push(format!("{low} {unit}"));
        }
    }
    found
}

/// Every Markdown page: the README, python/README.md and everything under `docs/`.
fn pages() -> Vec<PathBuf> {
    let mut out = vec![root().join("README.md"), root().join("python/README.md")];
    files(&root().join("docs"), "md", &mut out);
    out
}

/// The page's times outside code blocks, each with its line number.
fn stated_times(text: &str) -> Vec<(usize, String)> {
    let mut in_code_block = false;
    let mut out = Vec::new();
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code_block = !in_code_block;
        } else if !in_code_block {
            out.extend(times(line).into_iter().map(|t| (number + 1, t)));
        }
    }
    out
}

/// docs/speed.md's generated table.
fn table() -> String {
    let page = fs::read_to_string(root().join("docs/speed.md")).unwrap();
    let start = page
        .find(BEGIN)
        .expect("docs/speed.md has no speed-table begin marker");
    let end = page
        .find(END)
        .expect("docs/speed.md has no speed-table end marker");
    assert!(start < end, "docs/speed.md's markers are out of order");
    page[start..end].to_string()
}

#[test]
fn the_speed_table_is_one_generated_run_with_its_date_and_host() {
    let table = table();
    assert!(
        table.contains("**One run**, 20") && table.contains("Host: "),
        "the table says when and where it was measured:\n{table}"
    );
    let rows = table.lines().filter(|l| l.starts_with("| `")).count();
    assert!(
        rows >= 90,
        "the table holds {rows} benches; it should hold every one (≥ 90)"
    );
    for peer in [
        "pinocchio/c5",
        "pinocchio/delta",
        "sympy_gnu_paper_by_legs",
        "python/",
    ] {
        assert!(table.contains(peer), "the table has no row of `{peer}`");
    }
}

#[test]
fn every_stated_time_is_in_the_speed_table() {
    let measured: BTreeSet<String> = stated_times(&table()).into_iter().map(|(_, t)| t).collect();
    let mut strays = Vec::new();
    for page in pages() {
        let text = fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        let stated = stated_times(&text);
        let is_speed_page = name == "docs/speed.md";
        if !stated.is_empty() && !is_speed_page && !text.contains("speed.md") {
            strays.push(format!(
                "{name}: states times and does not link to docs/speed.md"
            ));
        }
        strays.extend(
            stated
                .into_iter()
                .filter(|(_, time)| !measured.contains(time))
                .map(|(line, time)| format!("{name}:{line}: {time}")),
        );
    }
    assert!(
        strays.is_empty(),
        "times not in docs/speed.md's table (cite the table's figure as it prints it, rerun \
         `python3 benches/speed_table.py`, or write a value one sets as code):\n{}",
        strays.join("\n")
    );
}

#[test]
fn a_time_in_text_is_a_figure_and_one_in_code_a_value() {
    assert_eq!(
        times("inverse dynamics 44.6 ns, batch 11.2 ns"),
        ["44.6 ns", "11.2 ns"]
    );
    assert_eq!(
        times("Pinocchio 30.4 µs (29.9–31.5 µs)"),
        ["30.4 µs", "31.5 µs", "29.9 µs"]
    );
    assert_eq!(times("took 43-45ns"), ["45 ns", "43 ns"]);
    assert_eq!(times("a step of `1 ms`, 52.1 ms a call"), ["52.1 ms"]);
    assert_eq!(
        times("3 nsec, x2 ns, 5 msgs, v1.2 µs"),
        Vec::<String>::new()
    );
    assert_eq!(times("5 μs (Greek mu)"), ["5 µs"]);
}
