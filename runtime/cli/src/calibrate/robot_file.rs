//! The calibrated robot file: the nominal file's text with each leg's `base`, `platform` and
//! `encoder_offset` replaced, every other field, comment and layout kept (`toml_edit`), and a
//! comment on each value changed giving the nominal one.

use crate::Result;
use c5_robot::Description;
use c5_runtime::calibrate::Report;
use toml_edit::{Array, DocumentMut, Item, Table, Value};

/// Rounds to the nanometre: far below any measurement, and short in the file.
fn nm(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

fn format_vector(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{}", nm(*x))).collect();
    format!("[{}]", items.join(", "))
}

/// Sets `table[key]` to `value`, its comment saying what it was; an existing comment is kept.
fn set(table: &mut Table, key: &str, mut value: Value, was: String, note: &str) {
    let old = table
        .get(key)
        .and_then(Item::as_value)
        .and_then(|v| v.decor().suffix())
        .and_then(|s| s.as_str())
        .map(|s| s.trim().trim_start_matches('#').trim().to_string())
        .filter(|s| !s.is_empty() && !s.starts_with("calibrated"));
    let mut comment = format!("calibrated; nominal {was}{note}");
    if let Some(old) = old {
        comment = format!("{old}; {comment}");
    }
    value.decor_mut().set_prefix(" ");
    value.decor_mut().set_suffix(format!("   # {comment}"));
    table.insert(key, Item::Value(value));
}

/// The names of the parameters of leg `leg` (1..6) kept at nominal, as a note.
fn kept(report: &Report, leg: usize, prefix: char) -> String {
    let names: Vec<&str> = report
        .unobservable
        .iter()
        .filter(|u| u.leg == leg && u.fixed.starts_with(prefix))
        .map(|u| u.fixed.as_str())
        .collect();
    if names.is_empty() {
        String::new()
    } else {
        format!(" ({} not observable: kept)", names.join(", "))
    }
}

/// The text of the calibrated file from the nominal file's `original` text.
///
/// # Errors
/// A nominal file whose legs are not six `[[legs]]` tables (the text is then written from the
/// description, without the original's comments), or a result that does not read back as the
/// calibrated robot.
pub fn calibrated_text(original: &str, report: &Report, header: &str) -> Result<String> {
    let mut doc: DocumentMut = original.parse()?;
    let legs = doc
        .get_mut("legs")
        .and_then(Item::as_array_of_tables_mut)
        .filter(|legs| legs.len() == 6);
    let body = match legs {
        Some(legs) => {
            for (i, table) in legs.iter_mut().enumerate() {
                let (leg, was) = (&report.robot.legs[i], &nominal_leg(report, i));
                let vector =
                    |v: [f64; 3]| Value::Array(v.iter().map(|x| nm(*x)).collect::<Array>());
                set(
                    table,
                    "base",
                    vector(leg.base),
                    format_vector(&was.0),
                    &kept(report, i + 1, 'A'),
                );
                set(
                    table,
                    "platform",
                    vector(leg.platform),
                    format_vector(&was.1),
                    &kept(report, i + 1, 'p'),
                );
                set(
                    table,
                    "encoder_offset",
                    Value::from(nm(leg.encoder_offset)),
                    format!("{}", was.2),
                    &kept(report, i + 1, 'o'),
                );
            }
            doc.to_string()
        }
        None => Description::GoughStewart(report.robot).to_toml(),
    };
    let text = format!("{header}{body}");
    check_reads_back(&text, report)?;
    Ok(text)
}

/// Leg `i`'s nominal `A`, `p` and `o`, from the report's parameters.
fn nominal_leg(report: &Report, i: usize) -> ([f64; 3], [f64; 3], f64) {
    let p = &report.parameters[7 * i..7 * (i + 1)];
    (
        [p[0].nominal, p[1].nominal, p[2].nominal],
        [p[3].nominal, p[4].nominal, p[5].nominal],
        p[6].nominal,
    )
}

/// The written text must describe the calibrated robot (to the nanometre of its rounding).
fn check_reads_back(text: &str, report: &Report) -> Result<()> {
    let Description::GoughStewart(back) = Description::from_toml(text, "calibrated file")? else {
        return Err("the calibrated file does not describe a Gough-Stewart platform".into());
    };
    for (a, b) in back.legs.iter().zip(&report.robot.legs) {
        let values = |l: &c5_robot::gough_stewart::UpsLeg| {
            [
                l.base.as_slice(),
                l.platform.as_slice(),
                &[l.encoder_offset],
            ]
            .concat()
        };
        let off = values(a)
            .iter()
            .zip(values(b))
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        if off > 1e-9 {
            return Err(format!("the calibrated file reads back {off:e} m off").into());
        }
    }
    Ok(())
}
