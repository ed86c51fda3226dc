//! The measurement and pose files of `c5 calibrate`: CSV with named columns, in any order.

use crate::Result;
use c5_runtime::calibrate::Measurement;
use c5_runtime::Pose;
use std::path::Path;

/// The pose's columns: RPY angles (rad), then the platform origin (m).
pub const POSE: [&str; 6] = ["alpha", "beta", "gamma", "xc", "yc", "zc"];
/// The encoders' columns (m).
pub const READINGS: [&str; 6] = ["q1", "q2", "q3", "q4", "q5", "q6"];

/// The rows of `path` as the values of `columns`, found by name in its header.
fn read_columns<const N: usize>(path: &Path, columns: [&str; N]) -> Result<Vec<[f64; N]>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let header = reader.headers()?.clone();
    let at: Vec<usize> = columns
        .iter()
        .map(|name| {
            header.iter().position(|h| h == *name).ok_or_else(|| {
                format!(
                    "{}: no column `{name}` (the file needs {})",
                    path.display(),
                    columns.join(",")
                )
            })
        })
        .collect::<std::result::Result<_, _>>()?;
    let mut rows = Vec::new();
    for (k, record) in reader.records().enumerate() {
        let row = k + 1;
        let record = record.map_err(|e| format!("{}: row {row}: {e}", path.display()))?;
        let mut values = [0.0; N];
        for (value, (&column, name)) in values.iter_mut().zip(at.iter().zip(columns)) {
            let text = record.get(column).unwrap_or("");
            *value = text
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{}: row {row}, column `{name}`: `{text}` is not a finite number",
                        path.display()
                    )
                })?;
        }
        rows.push(values);
    }
    Ok(rows)
}

/// The measured poses and readings of `path` (`alpha,beta,gamma,xc,yc,zc,q1..q6`).
pub fn read(path: &Path) -> Result<Vec<Measurement>> {
    let columns: [&str; 12] =
        std::array::from_fn(|k| if k < 6 { POSE[k] } else { READINGS[k - 6] });
    Ok(read_columns(path, columns)?
        .into_iter()
        .map(|row| Measurement {
            pose: Pose::from_array(std::array::from_fn(|k| row[k])),
            q: std::array::from_fn(|k| row[6 + k]),
        })
        .collect())
}

/// The poses of `path` (`alpha,beta,gamma,xc,yc,zc`).
pub fn read_poses(path: &Path) -> Result<Vec<Pose>> {
    Ok(read_columns(path, POSE)?
        .into_iter()
        .map(Pose::from_array)
        .collect())
}

fn write_rows(path: &Path, header: &[&str], rows: impl Iterator<Item = Vec<f64>>) -> Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    w.write_record(header)?;
    for row in rows {
        w.write_record(row.iter().map(|v| format!("{v:.17e}")))?;
    }
    w.flush()?;
    Ok(())
}

/// Writes `poses` as a pose CSV.
pub fn write_poses(path: &Path, poses: &[Pose]) -> Result<()> {
    write_rows(path, &POSE, poses.iter().map(|p| p.to_array().to_vec()))
}

/// Writes `data` as a measurement CSV.
pub fn write(path: &Path, data: &[Measurement]) -> Result<()> {
    let header: Vec<&str> = POSE.iter().chain(&READINGS).copied().collect();
    write_rows(
        path,
        &header,
        data.iter().map(|m| [m.pose.to_array(), m.q].concat()),
    )
}
