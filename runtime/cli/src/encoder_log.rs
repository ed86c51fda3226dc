//! Encoder logs, `t,q1..q6,gamma1..gamma6`: what a real experiment records (`simulate
//! --encoder-log` writes them, `identify --data` reads them), read row by row.

use crate::columns::{per_actuator, GAMMA, POSE, TIME};
use crate::trajectory_csv::TrajectoryError;
use std::fs::File;
use std::path::Path;

/// One row: its line, time, encoder positions and forces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub line: usize,
    pub t: f64,
    pub q: [f64; 6],
    pub gamma: [f64; 6],
}

/// The rows of an encoder log, in order.
pub struct Rows {
    file: String,
    reader: csv::Reader<File>,
    record: csv::StringRecord,
    header: Vec<String>,
    columns: [usize; 13],
    line: usize,
    /// The file's length and how far the reader is (for a progress bar).
    pub len: u64,
}

/// Whether the CSV at `path` is an encoder log: it has the columns `q1..q6` and no pose (every
/// pose has the centre's `xc`; a level platform's has no angles).
pub fn is_encoder_log(path: &Path) -> bool {
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .and_then(|mut r| r.headers().cloned())
        .is_ok_and(|h| h.iter().any(|c| c == "q1") && !h.iter().any(|c| c == POSE[3]))
}

/// Opens an encoder log.
///
/// # Errors
/// A missing file or column, with the file and line.
pub fn open(path: &Path) -> Result<Rows, TrajectoryError> {
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
        .chain(per_actuator("q", 6))
        .chain(GAMMA.map(String::from))
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
                "missing column(s) {} (an encoder log has t, q1..q6, gamma1..gamma6)",
                missing.join(", ")
            ),
        ));
    }
    let columns = std::array::from_fn(|k| {
        header
            .iter()
            .position(|h| *h == names[k])
            .expect("checked above")
    });
    Ok(Rows {
        len: std::fs::metadata(path).map(|m| m.len()).unwrap_or(0),
        file,
        reader,
        record: csv::StringRecord::new(),
        header,
        columns,
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
        let mut v = [0.0; 13];
        for (k, slot) in v.iter_mut().enumerate() {
            *slot = value(k)?;
        }
        Ok(Row {
            line: self.line,
            t: v[0],
            q: std::array::from_fn(|i| v[1 + i]),
            gamma: std::array::from_fn(|i| v[7 + i]),
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
