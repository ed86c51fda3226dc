//! Strict JSON Lines input: one object per line, known keys only, each once, arrays of finite
//! numbers of the declared length.
//!
//! `serde_json` keeps the last of two equal keys; a line is therefore read as the list of its
//! entries, and every rule is checked here, with messages that name the key.

use serde::de::{Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use serde_json::Value;
use std::fmt;

/// A key a command accepts: its name, the length of its array, and whether it is required
/// (an optional key left out is all zeros).
#[derive(Clone, Copy, Debug)]
pub struct Key {
    pub name: &'static str,
    pub len: usize,
    pub required: bool,
}

impl Key {
    /// A key every line must give.
    pub const fn required(name: &'static str, len: usize) -> Self {
        Key {
            name,
            len,
            required: true,
        }
    }

    /// A key a line may leave out (all zeros then).
    pub const fn optional(name: &'static str, len: usize) -> Self {
        Key {
            name,
            len,
            required: false,
        }
    }
}

/// The entries of one JSON object, in order, duplicates kept.
struct Entries(Vec<(String, Value)>);

impl<'de> Deserialize<'de> for Entries {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Collect;
        impl<'de> Visitor<'de> for Collect {
            type Value = Entries;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Entries, A::Error> {
                let mut out = Vec::new();
                while let Some(entry) = map.next_entry::<String, Value>()? {
                    out.push(entry);
                }
                Ok(Entries(out))
            }
        }
        d.deserialize_map(Collect)
    }
}

/// The values of one line: for each of `keys`, its numbers (zeros for an absent optional key).
///
/// # Errors
/// A message naming what is wrong: malformed JSON, not an object, an unknown key (with the
/// accepted ones), a key given twice, a missing required key, an array of the wrong length, or
/// an element that is not a finite number.
pub fn parse(line: &str, keys: &[Key]) -> Result<Vec<Vec<f64>>, String> {
    let values = parse_present(line, keys)?;
    keys.iter()
        .zip(values)
        .map(|(k, v)| match v {
            Some(v) => Ok(v),
            None if k.required => Err(format!("missing `{}`", k.name)),
            None => Ok(vec![0.0; k.len]),
        })
        .collect()
}

/// The values of one line, `None` for an absent key, whether required or not.
///
/// # Errors
/// As [`parse`], but for a missing key.
pub fn parse_present(line: &str, keys: &[Key]) -> Result<Vec<Option<Vec<f64>>>, String> {
    let entries: Entries = serde_json::from_str(line).map_err(|e| {
        if e.is_data() {
            "a line must be a JSON object".to_string()
        } else {
            format!("malformed JSON: {e}")
        }
    })?;
    let accepted = || keys.iter().map(|k| k.name).collect::<Vec<_>>().join(", ");
    let mut values: Vec<Option<Vec<f64>>> = vec![None; keys.len()];
    for (name, value) in &entries.0 {
        let Some(at) = keys.iter().position(|k| k.name == name) else {
            return Err(format!(
                "unknown key `{name}` (accepted keys: {})",
                accepted()
            ));
        };
        if values[at].is_some() {
            return Err(format!("`{name}` is given twice"));
        }
        let len = keys[at].len;
        let array = value
            .as_array()
            .ok_or_else(|| format!("`{name}` must be an array of {len} numbers"))?;
        if array.len() != len {
            return Err(format!(
                "`{name}` must hold {len} numbers, got {}",
                array.len()
            ));
        }
        let numbers = array
            .iter()
            .enumerate()
            .map(|(i, x)| {
                x.as_f64()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("`{name}[{i}]` is not a finite number"))
            })
            .collect::<Result<Vec<f64>, String>>()?;
        values[at] = Some(numbers);
    }
    Ok(values)
}

/// Streams JSON Lines from stdin to stdout: one result line per non-blank input line, a bad
/// line answered with `{"line": n, "error": ...}` and the exit status 1 at the end.
pub fn answer_lines(
    mut answer: impl FnMut(&str) -> Result<Value, String>,
) -> crate::Result<std::process::ExitCode> {
    use std::io::{BufRead, Write};
    let stdin = std::io::stdin().lock();
    let mut stdout = std::io::BufWriter::new(std::io::stdout().lock());
    let mut failed = false;
    for (n, line) in stdin.lines().enumerate() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let out = answer(&line).unwrap_or_else(|error| {
            failed = true;
            serde_json::json!({"line": n + 1, "error": error})
        });
        serde_json::to_writer(&mut stdout, &out)?;
        stdout.write_all(b"\n")?;
    }
    stdout.flush()?;
    Ok(if failed {
        std::process::ExitCode::FAILURE
    } else {
        std::process::ExitCode::SUCCESS
    })
}

/// A matrix of `n` columns, row-major, as rows.
pub fn rows(values: &[f64], n: usize) -> Vec<&[f64]> {
    values.chunks(n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const KEYS: [Key; 2] = [Key::required("pose", 6), Key::optional("omega", 3)];

    fn err(line: &str) -> String {
        parse(line, &KEYS).unwrap_err()
    }

    #[test]
    fn a_good_line_gives_every_key_absent_ones_as_zeros() {
        let v = parse(r#"{"pose": [1, 2, 3, 4, 5, 6]}"#, &KEYS).unwrap();
        assert_eq!(v, vec![vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0], vec![0.0; 3]]);
    }

    #[test]
    fn each_broken_rule_is_named() {
        assert_eq!(
            err(r#"{"pose": [0,0,0,0,0,0], "accel": [0,0,1]}"#),
            "unknown key `accel` (accepted keys: pose, omega)"
        );
        assert_eq!(
            err(r#"{"pose": [0,0,0,0,0,0], "pose": [1,0,0,0,0,0]}"#),
            "`pose` is given twice"
        );
        assert_eq!(err(r#"{"omega": [0,0,0]}"#), "missing `pose`");
        assert_eq!(
            err(r#"{"pose": [0,0,0,0,0]}"#),
            "`pose` must hold 6 numbers, got 5"
        );
        assert_eq!(
            err(r#"{"pose": [0,0,0,0,0,"x"]}"#),
            "`pose[5]` is not a finite number"
        );
        assert_eq!(err(r#"[1, 2]"#), "a line must be a JSON object");
        assert!(err(r#"{"pose": [0"#).starts_with("malformed JSON"));
    }
}
