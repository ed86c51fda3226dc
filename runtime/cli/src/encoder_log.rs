//! Encoder logs, `t,q1..qn,gamma1..gamman` for `n` actuators: what a real experiment records
//! (`simulate --encoder-log` writes them, `identify --data` reads them), read row by row.

use crate::columns::{per_actuator, POSE, TIME};
use crate::trajectory_csv::TrajectoryError;
use std::fs::File;
use std::path::Path;

/// The most actuators a robot has: a row's room, so that reading one allocates nothing.
const MOST: usize = crate::columns::Freedom::Free.dimension();

/// One row: its line, time, encoder positions and forces (one per actuator each).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub line: usize,
    pub t: f64,
    /// The positions, then the forces.
    values: [f64; 2 * MOST],
    actuators: usize,
}

impl Row {
    /// The encoders' positions.
    pub fn q(&self) -> &[f64] {
        &self.values[..self.actuators]
    }

    /// The forces.
    pub fn gamma(&self) -> &[f64] {
        &self.values[self.actuators..2 * self.actuators]
    }
}

/// The rows of an encoder log, in order.
pub struct Rows {
    file: String,
    reader: csv::Reader<File>,
    record: csv::StringRecord,
    header: Vec<String>,
    /// The columns of `t`, the positions and the forces.
    columns: Vec<usize>,
    actuators: usize,
    line: usize,
    /// The file's length and how far the reader is (for a progress bar).
    pub len: u64,
}

/// Whether the CSV at `path` is an encoder log: it has the column `q1` and no pose (every pose
/// has the centre's `xc`; a level platform's has no angles).
pub fn is_encoder_log(path: &Path) -> bool {
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .and_then(|mut r| r.headers().cloned())
        .is_ok_and(|h| h.iter().any(|c| c == "q1") && !h.iter().any(|c| c == POSE[3]))
}

/// Opens an encoder log of a robot of `actuators` actuators.
///
/// # Errors
/// A missing file or column, with the file and line.
pub fn open(path: &Path, actuators: usize) -> Result<Rows, TrajectoryError> {
    let file = path.display().to_string();
    let err = |line: Option<usize>, message: String| TrajectoryError {
        file: file.clone(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| err(None, e.to_string()))?;
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| err(Some(1), e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    let names: Vec<String> = std::iter::once(TIME.to_string())
        .chain(per_actuator("q", actuators))
        .chain(per_actuator("gamma", actuators))
        .collect();
    let missing: Vec<&str> = names
        .iter()
        .filter(|n| !header.contains(n))
        .map(String::as_str)
        .collect();
    if !missing.is_empty() {
        return Err(err(
            Some(1),
            format!(
                "missing column(s) {} (this robot's encoder log has t, q1..q{actuators}, \
                 gamma1..gamma{actuators})",
                missing.join(", ")
            ),
        ));
    }
    let columns = names
        .iter()
        .map(|name| {
            header
                .iter()
                .position(|h| h == name)
                .expect("checked above")
        })
        .collect();
    Ok(Rows {
        len: std::fs::metadata(path).map(|m| m.len()).unwrap_or(0),
        file,
        reader,
        record: csv::StringRecord::new(),
        header,
        columns,
        actuators,
        line: 1,
    })
}

impl Rows {
    /// The bytes read so far.
    pub fn position(&self) -> u64 {
        self.reader.position().byte()
    }

    /// An error at `line` of this file.
    pub fn error(&self, line: usize, message: String) -> TrajectoryError {
        TrajectoryError {
            file: self.file.clone(),
            line: Some(line),
            message,
        }
    }

    fn parse(&self) -> Result<Row, TrajectoryError> {
        let value = |k: usize| -> Result<f64, TrajectoryError> {
            let c = self.columns[k];
            let name = &self.header[c];
            let field = self
                .record
                .get(c)
                .ok_or_else(|| self.error(self.line, format!("no value for `{name}`")))?;
            let v: f64 = field.parse().map_err(|_| {
                self.error(self.line, format!("`{name}` = {field:?} is not a number"))
            })?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(self.error(self.line, format!("`{name}` is not finite")))
            }
        };
        let mut values = [0.0; 2 * MOST];
        for (k, slot) in values[..2 * self.actuators].iter_mut().enumerate() {
            *slot = value(1 + k)?;
        }
        Ok(Row {
            line: self.line,
            t: value(0)?,
            values,
            actuators: self.actuators,
        })
    }
}

impl Iterator for Rows {
    type Item = Result<Row, TrajectoryError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.line += 1;
        match self.reader.read_record(&mut self.record) {
            Ok(false) => None,
            Err(e) => Some(Err(self.error(self.line, e.to_string()))),
            Ok(true) => Some(self.parse()),
        }
    }
}
