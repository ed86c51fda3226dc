//! Trajectory CSV files (`simulate --trajectory`, `track --trajectory`, `identify --data`):
//! read row by row, the missing derivatives by finite differences on the fly, so a file of any
//! length streams through in constant memory.

use c5_runtime::trajectory::omega_from_rpy_rates;
use c5_runtime::{Acceleration, Pose, State, Twist};
use std::cell::Cell;
use std::fmt;
use std::fs::File;
use std::path::Path;
use std::rc::Rc;

/// Why a trajectory file was refused.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryError {
    pub file: String,
    /// 1-based line of the file, when the problem has one.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for TrajectoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for TrajectoryError {}

use crate::columns::{ACCEL, POSE, TIME, TWIST};

/// One sample of a trajectory file: its line, time, state and the extra columns asked for.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub line: usize,
    pub t: f64,
    pub state: State,
    pub extra: Vec<f64>,
}

type Item = Result<Sample, TrajectoryError>;

/// The rows as read: the state's given parts filled, the others zero.
struct Rows {
    file: String,
    reader: csv::Reader<File>,
    header: Vec<String>,
    record: csv::StringRecord,
    /// `t`, then the pose's six columns (`None` where the file leaves the angles out).
    pose: Vec<Option<usize>>,
    twist: Option<Vec<Option<usize>>>,
    accel: Option<Vec<Option<usize>>>,
    extra: Vec<usize>,
    line: usize,
    last_t: Option<f64>,
    bytes: Rc<Cell<u64>>,
}

impl Rows {
    fn err(&self, line: Option<usize>, message: String) -> TrajectoryError {
        TrajectoryError {
            file: self.file.clone(),
            line,
            message,
        }
    }

    fn parse(&self) -> Result<Sample, TrajectoryError> {
        let line = self.line;
        let value = |k: usize| -> Result<f64, TrajectoryError> {
            let field = self.record.get(k).ok_or_else(|| {
                self.err(Some(line), format!("no value for `{}`", self.header[k]))
            })?;
            let v: f64 = field.parse().map_err(|_| {
                self.err(
                    Some(line),
                    format!("`{}` = {field:?} is not a number", self.header[k]),
                )
            })?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(self.err(Some(line), format!("`{}` is not finite", self.header[k])))
            }
        };
        let six = |cols: &[Option<usize>]| -> Result<[f64; 6], TrajectoryError> {
            let mut out = [0.0; 6];
            for (o, c) in out.iter_mut().zip(cols) {
                if let Some(c) = *c {
                    *o = value(c)?;
                }
            }
            Ok(out)
        };
        let t = value(self.pose[0].unwrap_or_default())?;
        let pose = Pose::from_array(six(&self.pose[1..])?);
        let twist = match &self.twist {
            Some(c) => Twist::from_array(six(c)?),
            None => Twist::default(),
        };
        let accel = match &self.accel {
            Some(c) => Acceleration::from_array(six(c)?),
            None => Acceleration::default(),
        };
        let extra = self
            .extra
            .iter()
            .map(|&c| value(c))
            .collect::<Result<_, _>>()?;
        Ok(Sample {
            line,
            t,
            state: State { pose, twist, accel },
            extra,
        })
    }
}

impl Iterator for Rows {
    type Item = Item;

    fn next(&mut self) -> Option<Item> {
        self.line += 1;
        match self.reader.read_record(&mut self.record) {
            Ok(false) => return None,
            Err(e) => return Some(Err(self.err(Some(self.line), e.to_string()))),
            Ok(true) => {}
        }
        self.bytes.set(self.reader.position().byte());
        let sample = match self.parse() {
            Ok(s) => s,
            Err(e) => return Some(Err(e)),
        };
        if self.last_t.is_some_and(|last| sample.t <= last) {
            return Some(Err(
                self.err(Some(self.line), "time must increase".to_string())
            ));
        }
        self.last_t = Some(sample.t);
        Some(Ok(sample))
    }
}

/// A derivative by finite differences of the samples, central inside and one-sided at the
/// ends (non-uniform times), with one sample of look-ahead.
struct Differentiate<I> {
    source: I,
    /// What is differentiated, and where the derivative goes.
    value: fn(&State) -> [f64; 6],
    store: fn(&mut State, [f64; 6]),
    previous: Option<(f64, [f64; 6])>,
    current: Option<Sample>,
    file: String,
}

impl<I: Iterator<Item = Item>> Iterator for Differentiate<I> {
    type Item = Item;

    fn next(&mut self) -> Option<Item> {
        let mut current = match self.current.take() {
            Some(c) => c,
            None => match self.source.next()? {
                Ok(first) => first,
                Err(e) => return Some(Err(e)),
            },
        };
        let next = match self.source.next() {
            Some(Ok(n)) => Some(n),
            Some(Err(e)) => return Some(Err(e)),
            None => None,
        };
        let here = (current.t, (self.value)(&current.state));
        let (a, b) = match (&self.previous, &next) {
            (Some(p), Some(n)) => (*p, (n.t, (self.value)(&n.state))),
            (None, Some(n)) => (here, (n.t, (self.value)(&n.state))),
            (Some(p), None) => (*p, here),
            (None, None) => {
                return Some(Err(TrajectoryError {
                    file: self.file.clone(),
                    line: None,
                    message: "derivatives by finite differences need at least two samples"
                        .to_string(),
                }))
            }
        };
        let derivative = std::array::from_fn(|j| (b.1[j] - a.1[j]) / (b.0 - a.0));
        (self.store)(&mut current.state, derivative);
        self.previous = Some(here);
        self.current = next;
        Some(Ok(current))
    }
}

/// `[α β γ xc yc zc]` → (`ω` through the RPY rates, `v_C`): the twist from the pose's rate.
fn twist_from_pose_rate(state: &mut State, rate: [f64; 6]) {
    let p = &state.pose;
    state.twist = Twist {
        omega: omega_from_rpy_rates([p.alpha, p.beta, p.gamma], [rate[0], rate[1], rate[2]]),
        velocity: [rate[3], rate[4], rate[5]],
    };
}

/// A trajectory file opened for streaming (its progress and derived columns are read by
/// `identify`).
#[cfg_attr(not(feature = "identify"), allow(dead_code))]
pub struct Trajectory {
    samples: Box<dyn Iterator<Item = Item>>,
    bytes: Rc<Cell<u64>>,
    /// The file's length in bytes (for progress).
    pub len: u64,
    /// Whether the twist and the acceleration come from finite differences.
    pub derived: (bool, bool),
}

impl Iterator for Trajectory {
    type Item = Item;

    fn next(&mut self) -> Option<Item> {
        self.samples.next()
    }
}

#[cfg_attr(not(feature = "identify"), allow(dead_code))]
impl Trajectory {
    /// Bytes of the file read so far.
    pub fn position(&self) -> u64 {
        self.bytes.get()
    }
}

/// Opens a trajectory CSV: `t, alpha, beta, gamma, xc, yc, zc`, optionally the twist
/// (`wx wy wz vx vy vz`) and classical acceleration (`wdx wdy wdz ax ay az`), and the
/// `extra` columns, required. A file of a level platform (a Delta's) may leave the angles
/// out, and then the angular rates and accelerations too: `t, xc, yc, zc`, optionally
/// `vx vy vz` and `ax ay az`. Missing derivatives come from finite differences of the
/// samples (the twist's angular part through the RPY rates).
///
/// # Errors
/// A missing file or column; the samples then report a malformed or non-finite number, fewer
/// than two samples where derivatives are needed, or times that do not increase, each with
/// the file and line.
pub fn open(path: &Path, extra: &[&str]) -> Result<Trajectory, TrajectoryError> {
    let file = path.display().to_string();
    let err = |line: Option<usize>, message: String| TrajectoryError {
        file: file.clone(),
        line,
        message,
    };
    let len = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
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
    let column = |name: &str| header.iter().position(|h| h == name);
    let find = |names: &[&str], required: bool| -> Result<Option<Vec<usize>>, TrajectoryError> {
        let found: Vec<Option<usize>> = names.iter().map(|n| column(n)).collect();
        if found.iter().all(Option::is_some) {
            return Ok(Some(found.into_iter().flatten().collect()));
        }
        if !required && found.iter().all(Option::is_none) {
            return Ok(None);
        }
        let missing: Vec<&str> = names
            .iter()
            .zip(&found)
            .filter(|(_, f)| f.is_none())
            .map(|(n, _)| *n)
            .collect();
        Err(err(
            Some(1),
            format!(
                "missing column(s) {} (these come together: {})",
                missing.join(", "),
                names.join(", ")
            ),
        ))
    };
    let angles = find(&POSE[..3], false)?;
    let time_and_centre: Vec<&str> = std::iter::once(TIME)
        .chain(POSE[3..].iter().copied())
        .collect();
    let centre = find(&time_and_centre, true)?.unwrap_or_default();
    let every = |columns: Vec<usize>| columns.into_iter().map(Some).collect::<Vec<_>>();
    let pose: Vec<Option<usize>> = std::iter::once(Some(centre[0]))
        .chain(match &angles {
            Some(a) => every(a.clone()),
            None => vec![None; 3],
        })
        .chain(every(centre[1..].to_vec()))
        .collect();
    let (twist, accel) = if angles.is_some() {
        (
            find(&TWIST, false)?.map(every),
            find(&ACCEL, false)?.map(every),
        )
    } else {
        for part in [&TWIST[..3], &ACCEL[..3]] {
            if part.iter().any(|name| column(name).is_some()) {
                return Err(err(
                    Some(1),
                    format!(
                        "{} given without alpha, beta, gamma: a file without the angles is of \
                         a level platform",
                        part.join(", ")
                    ),
                ));
            }
        }
        let linear = |names: &[&str]| -> Result<_, TrajectoryError> {
            Ok(find(names, false)?.map(|c| [vec![None; 3], every(c)].concat()))
        };
        (linear(&TWIST[3..])?, linear(&ACCEL[3..])?)
    };
    let extra = if extra.is_empty() {
        Vec::new()
    } else {
        find(extra, true)?.unwrap_or_default()
    };
    let derived = (twist.is_none(), accel.is_none());
    let bytes = Rc::new(Cell::new(0));
    let mut samples: Box<dyn Iterator<Item = Item>> = Box::new(Rows {
        file: file.clone(),
        reader,
        header,
        record: csv::StringRecord::new(),
        pose,
        twist,
        accel,
        extra,
        line: 1,
        last_t: None,
        bytes: bytes.clone(),
    });
    if derived.0 {
        samples = Box::new(Differentiate {
            source: samples,
            value: |s| s.pose.to_array(),
            store: twist_from_pose_rate,
            previous: None,
            current: None,
            file: file.clone(),
        });
    }
    if derived.1 {
        samples = Box::new(Differentiate {
            source: samples,
            value: |s| s.twist.to_array(),
            store: |s, a| s.accel = Acceleration::from_array(a),
            previous: None,
            current: None,
            file,
        });
    }
    Ok(Trajectory {
        samples,
        bytes,
        len,
        derived,
    })
}

/// Reads a whole trajectory file (see [`open`]): its times and states.
///
/// # Errors
/// As [`open`], and fewer than two samples.
pub fn read(path: &Path) -> Result<Vec<(f64, State)>, TrajectoryError> {
    let samples: Vec<(f64, State)> = open(path, &[])?
        .map(|s| s.map(|s| (s.t, s.state)))
        .collect::<Result<_, _>>()?;
    if samples.len() < 2 {
        return Err(TrajectoryError {
            file: path.display().to_string(),
            line: None,
            message: "a trajectory needs at least two samples".to_string(),
        });
    }
    Ok(samples)
}
