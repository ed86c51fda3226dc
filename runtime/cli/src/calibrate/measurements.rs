//! The measurement and pose files of `c5 calibrate`: CSV with named columns, in any order: the
//! pose's (`alpha,beta,gamma,xc,yc,zc`, a Delta's `xc,yc,zc`) and the readings' `q1..qn`.

use crate::Result;
use c5_runtime::calibrate::Measurement;
use std::path::Path;

/// The columns of a robot's measurements: its pose's coordinates, and `q1..qn`.
pub struct Columns {
    pub pose: &'static [&'static str],
    pub readings: Vec<String>,
}

impl Columns {
    /// The columns of a robot whose pose has the coordinates `pose` and `n` actuators.
    pub fn new(pose: &'static [&'static str], n: usize) -> Self {
        Columns {
            pose,
            readings: (1..=n).map(|i| format!("q{i}")).collect(),
        }
    }

    fn all(&self) -> Vec<&str> {
        self.pose
            .iter()
            .copied()
            .chain(self.readings.iter().map(String::as_str))
            .collect()
    }
}

/// The rows of `path` as the values of `columns`, found by name in its header.
fn read_columns(path: &Path, columns: &[&str]) -> Result<Vec<Vec<f64>>> {
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
        let mut values = vec![0.0; columns.len()];
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

/// The measured poses and readings of `path`.
pub fn read(path: &Path, columns: &Columns) -> Result<Vec<Measurement>> {
    let width = columns.pose.len();
    Ok(read_columns(path, &columns.all())?
        .into_iter()
        .map(|mut row| {
            let q = row.split_off(width);
            Measurement { pose: row, q }
        })
        .collect())
}

/// The poses of `path`.
pub fn read_poses(path: &Path, columns: &Columns) -> Result<Vec<Vec<f64>>> {
    read_columns(path, columns.pose)
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
pub fn write_poses(path: &Path, poses: &[Vec<f64>], columns: &Columns) -> Result<()> {
    write_rows(path, columns.pose, poses.iter().cloned())
}

/// Writes `data` as a measurement CSV.
pub fn write(path: &Path, data: &[Measurement], columns: &Columns) -> Result<()> {
    write_rows(
        path,
        &columns.all(),
        data.iter().map(|m| [m.pose.as_slice(), &m.q].concat()),
    )
}
