//! The calibrated robot file: the nominal file's text with each leg's values the calibration
//! changed replaced (`base`, `platform`, `crank.length`, a motor's `axis` and `zero`, ...),
//! every other field, comment and layout kept (`toml_edit`), and a comment on each value
//! changed giving the nominal one.

use crate::Result;
use c5_robot::calibration::Fitted;
use c5_robot::Description;
use c5_runtime::calibrate::Report;
use toml_edit::{DocumentMut, Item, TableLike, Value};

/// Rounds to the nanometre (nanoradian): far below any measurement, and short in the file.
fn nm(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

/// Rounds every number of `value` with [`nm`].
fn rounded(value: &Value) -> Value {
    match value {
        Value::Float(f) => Value::from(nm(*f.value())),
        Value::Array(a) => Value::Array(a.iter().map(rounded).collect()),
        other => other.clone(),
    }
}

/// The text of `value` without its decoration.
fn bare(value: &Value) -> String {
    let mut v = value.clone();
    v.decor_mut().clear();
    v.to_string().trim().to_string()
}

/// The numbers of `value` (a number or an array of them).
fn numbers(value: &Value) -> Option<Vec<f64>> {
    match value {
        Value::Float(f) => Some(vec![*f.value()]),
        Value::Integer(i) => Some(vec![*i.value() as f64]),
        Value::Array(a) => a.iter().map(|v| numbers(v).map(|n| n[0])).collect(),
        _ => None,
    }
}

/// The paths of the numbers of the calibrated leg `new` (its keys, and one level of its
/// sub-tables' keys) that differ from the nominal leg `was`.
fn changed(was: &dyn TableLike, new: &dyn TableLike) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for (key, item) in new.iter() {
        if let Some(inner) = item.as_table_like() {
            for (sub, _) in inner.iter() {
                out.push(vec![key.to_string(), sub.to_string()]);
            }
        } else {
            out.push(vec![key.to_string()]);
        }
    }
    out.retain(|path| {
        let path: Vec<&str> = path.iter().map(String::as_str).collect();
        let now = value_at(new, &path).and_then(numbers);
        let before = value_at(was, &path).and_then(numbers);
        match (now, before) {
            (Some(now), Some(before)) => {
                now.len() != before.len()
                    || now.iter().zip(&before).any(|(a, b)| (a - b).abs() > 1e-12)
            }
            // An absent `encoder_offset` is zero.
            (Some(now), None) => now.iter().any(|x| *x != 0.0),
            _ => false,
        }
    });
    out
}

/// The legs' tables of `doc` under `key`, if it holds `n` of them.
fn leg_tables<'d>(
    doc: &'d mut DocumentMut,
    key: &str,
    n: usize,
) -> Option<&'d mut toml_edit::ArrayOfTables> {
    doc.get_mut(key)
        .and_then(Item::as_array_of_tables_mut)
        .filter(|legs| legs.len() == n)
}

/// The value at `path` in `table`.
fn value_at<'t>(table: &'t dyn TableLike, path: &[&str]) -> Option<&'t Value> {
    match path {
        [last] => table.get(last)?.as_value(),
        [first, rest @ ..] => value_at(table.get(first)?.as_table_like()?, rest),
        [] => None,
    }
}

/// The names of leg `leg`'s parameters under `key` that the data could not separate.
fn kept(report: &Report, fitted: &[Fitted], leg: usize, key: &[&str]) -> String {
    let names: Vec<String> = fitted
        .iter()
        .filter(|f| f.key == key)
        .map(|f| f.name(leg))
        .filter(|name| report.unobservable.iter().any(|u| &u.fixed == name))
        .collect();
    if names.is_empty() {
        String::new()
    } else {
        format!(" ({} not observable: kept)", names.join(", "))
    }
}

/// Sets `path` in the leg's `table` to `value`. A top-level key's comment says the nominal
/// value (an existing comment kept); a key inside an inline table (`crank.length`) cannot carry
/// one, so the inline table's line does.
fn set(table: &mut dyn TableLike, path: &[&str], value: Value, note: String) {
    let comment_on = |v: &mut Value, note: &str| {
        let old = v
            .decor()
            .suffix()
            .and_then(|s| s.as_str())
            .map(|s| s.trim().trim_start_matches('#').trim().to_string())
            .filter(|s| !s.is_empty() && !s.starts_with("calibrated"));
        let comment = match old {
            Some(old) => format!("{old}; {note}"),
            None => note.to_string(),
        };
        v.decor_mut().set_suffix(format!("   # {comment}"));
    };
    match path {
        [key] => {
            let mut value = value;
            value.decor_mut().set_prefix(" ");
            comment_on(&mut value, &note);
            table.insert(key, Item::Value(value));
        }
        [parent, key] => {
            let Some(item) = table.get_mut(parent) else {
                return;
            };
            if let Some(inline) = item.as_inline_table_mut() {
                let mut value = value;
                value.decor_mut().set_prefix(" ");
                value.decor_mut().set_suffix("");
                inline.insert(*key, value);
            } else if let Some(inner) = item.as_table_like_mut() {
                set(inner, &[key], value, note);
                return;
            }
            if let Some(v) = item.as_value_mut() {
                comment_on(v, &format!("{key} {note}"));
            }
        }
        _ => {}
    }
}

/// The text of the calibrated file from the nominal file's `original` text.
///
/// # Errors
/// A result that does not read back as the calibrated robot. A nominal file whose legs are not
/// tables under the mechanism's key is written from the description, without its comments.
pub fn calibrated_text(original: &str, report: &Report, header: &str) -> Result<String> {
    let robot = &report.robot;
    let fitted = robot.fitted().ok_or("this mechanism has no calibration")?;
    let (key, n) = (robot.legs_key(), report.legs());
    let mut calibrated: DocumentMut = robot.to_toml().parse()?;
    let mut doc: DocumentMut = original.parse()?;
    let body = match (
        leg_tables(&mut doc, key, n),
        leg_tables(&mut calibrated, key, n),
    ) {
        (Some(legs), Some(found)) => {
            for (i, (table, new)) in legs.iter_mut().zip(found.iter()).enumerate() {
                for path in changed(table, new) {
                    let path: Vec<&str> = path.iter().map(String::as_str).collect();
                    let Some(value) = value_at(new, &path) else {
                        continue;
                    };
                    let was = value_at(table, &path).map_or_else(|| "0 (absent)".into(), bare);
                    let note = format!(
                        "calibrated; nominal {was}{}",
                        kept(report, fitted, i + 1, &path)
                    );
                    set(table, &path, rounded(value), note);
                }
            }
            doc.to_string()
        }
        _ => robot.to_toml(),
    };
    let text = format!("{header}{body}");
    check_reads_back(&text, report)?;
    Ok(text)
}

/// The written text must describe the calibrated robot (to the nanometre of its rounding).
fn check_reads_back(text: &str, report: &Report) -> Result<()> {
    let back = Description::from_toml(text, "calibrated file")?;
    for leg in 0..report.legs() {
        let (a, b) = (back.fitted_values(leg), report.robot.fitted_values(leg));
        let off = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        if a.len() != b.len() || off > 1e-9 {
            return Err(format!("the calibrated file reads back {off:e} off").into());
        }
    }
    Ok(())
}
