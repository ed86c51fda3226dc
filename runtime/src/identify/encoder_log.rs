//! Identification from what an experiment records: the actuator positions (encoder counts) and
//! forces, sampled at a fixed rate, nothing else.
//!
//! Gautier and Khalil's practice: a zero-phase Butterworth low-pass filter on the positions,
//! central differences for the rates and accelerations, the same filter on the forces
//! ("parallel filtering", so that both sides of `Γ = Y β` see the same filter), decimation, and
//! the samples within the filter's settling time of either end dropped. [`LogProcessor`] does
//! it streaming: it filters overlapping blocks forwards and backwards and keeps each block's
//! middle, where the neighbouring blocks' ends have decayed below `1e-12` (the filter's
//! settling time), so memory is bounded whatever the length of the log, and the result is the
//! whole-log `filtfilt` to that precision.

use super::filter::Butterworth;
use std::fmt;

/// How an encoder log is filtered and thinned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogFilter {
    /// The Butterworth filter's order (even).
    pub order: usize,
    /// Its cutoff (Hz); `None` differences the raw positions and forces (no filter).
    pub cutoff: Option<f64>,
    /// One sample kept in so many.
    pub decimate: usize,
}

impl LogFilter {
    /// The default for a log sampled at `rate` (Hz): a fourth-order filter at a twenty-fifth
    /// of the rate (40 Hz at 1 kHz: well above an exciting trajectory's few hertz, below where
    /// the differences of quantized counts put their noise; a lower cutoff also widens the
    /// window where the filtered Coulomb force, smoothed, and the regressor's `sign(q̇)`, a
    /// step, disagree), and one sample kept in `rate / (5 f_c)` (the kept rate five times the
    /// cutoff, so nothing the filter passes folds over).
    pub fn default_for(rate: f64) -> Self {
        let cutoff = rate / 25.0;
        LogFilter {
            order: 4,
            cutoff: Some(cutoff),
            decimate: Self::decimation_for(rate, cutoff),
        }
    }

    /// One sample in `rate / (5 f_c)`, at least one.
    pub fn decimation_for(rate: f64, cutoff: f64) -> usize {
        ((rate / (5.0 * cutoff)).floor() as usize).max(1)
    }
}

/// One kept sample: its index in the log, time, the actuators' filtered positions, rates and
/// accelerations (central differences of the filtered positions), and the filtered forces,
/// one per actuator each.
#[derive(Clone, Debug, PartialEq)]
pub struct Filtered {
    pub index: usize,
    pub t: f64,
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    pub gamma: Vec<f64>,
}

/// Why a log was refused, with the index of the sample at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum LogError {
    /// A setting out of range.
    Settings(String),
    /// A value that is not a finite number.
    NonFinite { index: usize },
    /// The time does not increase.
    NotIncreasing { index: usize, t: f64, previous: f64 },
    /// A sampling interval more than 1 % off the log's (its first).
    Irregular {
        index: usize,
        interval: f64,
        period: f64,
    },
    /// Too few samples for the filter's two settling times and one kept sample.
    TooShort { samples: usize, needed: usize },
    /// Positions or forces not one per actuator.
    WrongWidth {
        index: usize,
        expected: usize,
        got: usize,
    },
}

impl LogError {
    /// The index of the sample at fault, if one is.
    pub fn index(&self) -> Option<usize> {
        match self {
            LogError::NonFinite { index }
            | LogError::NotIncreasing { index, .. }
            | LogError::Irregular { index, .. }
            | LogError::WrongWidth { index, .. } => Some(*index),
            _ => None,
        }
    }
}

impl fmt::Display for LogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LogError::Settings(s) => f.write_str(s),
            LogError::NonFinite { .. } => write!(f, "a value is not a finite number"),
            LogError::NotIncreasing { t, previous, .. } => {
                write!(f, "time must increase: {t} s after {previous} s")
            }
            LogError::Irregular {
                interval, period, ..
            } => {
                let kind = if *interval > 1.5 * period {
                    "a gap"
                } else {
                    "an irregular sample period"
                };
                write!(
                    f,
                    "{kind}: {interval} s since the previous sample, the log's period is \
                     {period} s (at most 1 % off)"
                )
            }
            LogError::TooShort { samples, needed } => write!(
                f,
                "{samples} samples: too short for the filter, which needs at least {needed} \
                 (its settling time at each end, dropped, and one sample between)"
            ),
            LogError::WrongWidth { expected, got, .. } => write!(
                f,
                "{got} positions or forces where the robot has {expected} actuators"
            ),
        }
    }
}

impl std::error::Error for LogError {}

/// The streaming pipeline of an encoder log: push the samples in order, collect the kept ones.
pub struct LogProcessor {
    settings: LogFilter,
    /// How many actuators: each sample holds as many positions and forces.
    actuators: usize,
    filter: Option<Butterworth>,
    /// Samples dropped at each end: the filter's settling time (one without a filter, for the
    /// central differences).
    margin: usize,
    /// Samples a block keeps.
    block: usize,
    /// Raw samples not yet passed, the first at index `start`: each its time, positions and
    /// forces, `1 + 2 actuators` numbers.
    buffer: Vec<f64>,
    start: usize,
    count: usize,
    period: Option<f64>,
    last_t: Option<f64>,
}

impl LogProcessor {
    /// A pipeline for a log of `actuators` positions and forces sampled at `rate` (Hz).
    ///
    /// # Errors
    /// [`LogError::Settings`] for an odd order, a cutoff not below half the rate, or no
    /// decimation.
    pub fn new(settings: LogFilter, rate: f64, actuators: usize) -> Result<Self, LogError> {
        if !(rate.is_finite() && rate > 0.0) || settings.decimate == 0 {
            return Err(LogError::Settings(format!(
                "the sampling rate ({rate} Hz) and the decimation ({}) must be positive",
                settings.decimate
            )));
        }
        let filter = match settings.cutoff {
            None => None,
            Some(fc) => {
                if settings.order < 2 || !settings.order.is_multiple_of(2) {
                    return Err(LogError::Settings(format!(
                        "the filter's order must be even, got {}",
                        settings.order
                    )));
                }
                if !(fc.is_finite() && fc > 0.0 && fc < rate / 2.0) {
                    return Err(LogError::Settings(format!(
                        "the cutoff must be between 0 and half the sampling rate ({} Hz), got \
                         {fc} Hz",
                        rate / 2.0
                    )));
                }
                Some(Butterworth::low_pass(settings.order, fc, rate))
            }
        };
        let margin = filter.as_ref().map_or(1, |f| f.settling(rate).max(1));
        Ok(LogProcessor {
            settings,
            actuators,
            margin,
            block: (8 * margin).max(4096),
            filter,
            buffer: Vec::new(),
            start: 0,
            count: 0,
            period: None,
            last_t: None,
        })
    }

    /// The samples dropped at each end of the log.
    pub fn edge(&self) -> usize {
        self.margin
    }

    /// The samples pushed so far.
    pub fn samples(&self) -> usize {
        self.count
    }

    /// Takes the next sample; appends to `out` the kept samples it completes.
    ///
    /// # Errors
    /// Positions or forces not one per actuator, a non-finite value, a time that does not
    /// increase, or an interval more than 1 % off the first; the pipeline is then unusable.
    pub fn push(
        &mut self,
        t: f64,
        q: &[f64],
        gamma: &[f64],
        out: &mut Vec<Filtered>,
    ) -> Result<(), LogError> {
        let index = self.count;
        if let Some(got) = [q.len(), gamma.len()]
            .into_iter()
            .find(|&n| n != self.actuators)
        {
            return Err(LogError::WrongWidth {
                index,
                expected: self.actuators,
                got,
            });
        }
        if !t.is_finite() || q.iter().chain(gamma).any(|x| !x.is_finite()) {
            return Err(LogError::NonFinite { index });
        }
        if let Some(previous) = self.last_t {
            if t <= previous {
                return Err(LogError::NotIncreasing { index, t, previous });
            }
            let interval = t - previous;
            match self.period {
                None => self.period = Some(interval),
                Some(period) if (interval - period).abs() > 0.01 * period => {
                    return Err(LogError::Irregular {
                        index,
                        interval,
                        period,
                    })
                }
                Some(_) => {}
            }
        }
        self.last_t = Some(t);
        self.buffer.push(t);
        self.buffer.extend_from_slice(q);
        self.buffer.extend_from_slice(gamma);
        self.count += 1;
        if self.buffered() >= self.block + 2 * self.margin {
            self.emit(self.margin..self.margin + self.block, out);
            self.buffer.drain(..self.block * self.stride());
            self.start += self.block;
        }
        Ok(())
    }

    /// The numbers of one raw sample: its time, positions and forces.
    fn stride(&self) -> usize {
        1 + 2 * self.actuators
    }

    /// The raw samples not yet passed.
    fn buffered(&self) -> usize {
        self.buffer.len() / self.stride()
    }

    /// Passes the rest of the log.
    ///
    /// # Errors
    /// [`LogError::TooShort`] if the log had fewer samples than the two settling times and
    /// one.
    pub fn finish(mut self, out: &mut Vec<Filtered>) -> Result<(), LogError> {
        let needed = 2 * self.margin + 1;
        if self.count < needed {
            return Err(LogError::TooShort {
                samples: self.count,
                needed,
            });
        }
        let len = self.buffered();
        self.emit(self.margin..len - self.margin, out);
        Ok(())
    }

    /// Filters the buffer and appends the kept samples among its indices `keep`.
    fn emit(&mut self, keep: std::ops::Range<usize>, out: &mut Vec<Filtered>) {
        let (period, n, stride) = (self.period.unwrap_or(1.0), self.actuators, self.stride());
        let mut channels: Vec<Vec<f64>> = (0..2 * n)
            .map(|c| self.buffer.chunks(stride).map(|s| s[1 + c]).collect())
            .collect();
        if let Some(filter) = &self.filter {
            for channel in &mut channels {
                filter.zero_phase(channel);
            }
        }
        for i in keep {
            let index = self.start + i;
            if !index.is_multiple_of(self.settings.decimate) {
                continue;
            }
            let at = |c: usize, k: usize| channels[c][k];
            out.push(Filtered {
                index,
                t: self.buffer[i * stride],
                q: (0..n).map(|c| at(c, i)).collect(),
                qd: (0..n)
                    .map(|c| (at(c, i + 1) - at(c, i - 1)) / (2.0 * period))
                    .collect(),
                qdd: (0..n)
                    .map(|c| (at(c, i + 1) - 2.0 * at(c, i) + at(c, i - 1)) / (period * period))
                    .collect(),
                gamma: (n..2 * n).map(|c| at(c, i)).collect(),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(k: usize) -> ([f64; 6], [f64; 6]) {
        let t = k as f64 * 1e-3;
        (
            std::array::from_fn(|i| 0.01 * (t * (1.0 + i as f64)).sin()),
            std::array::from_fn(|i| 30.0 * (0.7 * t + i as f64).cos()),
        )
    }

    #[test]
    fn streaming_blocks_equal_the_whole_log_filtered_at_once() {
        let settings = LogFilter::default_for(1000.0);
        let mut p = LogProcessor::new(settings, 1000.0, 6).unwrap();
        let n = 30_000;
        let mut out = Vec::new();
        for k in 0..n {
            let (q, g) = signal(k);
            p.push(k as f64 * 1e-3, &q, &g, &mut out).unwrap();
        }
        let edge = p.edge();
        p.finish(&mut out).unwrap();
        // The whole log at once, as filtfilt does it.
        let filter = Butterworth::low_pass(4, 40.0, 1000.0);
        let mut q0: Vec<f64> = (0..n).map(|k| signal(k).0[0]).collect();
        filter.zero_phase(&mut q0);
        let kept: Vec<usize> = (edge..n - edge)
            .filter(|k| k % settings.decimate == 0)
            .collect();
        assert_eq!(out.iter().map(|s| s.index).collect::<Vec<_>>(), kept);
        for s in &out {
            assert!((s.q[0] - q0[s.index]).abs() < 1e-14, "{}", s.index);
            // The filter barely touches a 1 rad/s sine; its derivatives are the sine's.
            let t = s.t;
            assert!((s.qd[0] - 0.01 * t.cos()).abs() < 1e-7);
            assert!((s.qdd[0] + 0.01 * t.sin()).abs() < 1e-5);
        }
    }

    #[test]
    fn bad_timing_and_short_logs_are_refused_with_the_sample() {
        let settings = LogFilter::default_for(1000.0);
        let mut p = LogProcessor::new(settings, 1000.0, 6).unwrap();
        let (q, g) = signal(0);
        let mut out = Vec::new();
        let e = p.push(0.0, &q[..3], &g, &mut out).unwrap_err();
        assert!(
            matches!(
                e,
                LogError::WrongWidth {
                    expected: 6,
                    got: 3,
                    index: 0
                }
            ),
            "{e}"
        );
        assert_eq!(p.samples(), 0);
        for (k, t) in [0.0, 0.001, 0.002, 0.003].iter().enumerate() {
            p.push(*t, &q, &g, &mut out).unwrap();
            assert_eq!(p.samples(), k + 1);
        }
        let e = p.push(0.00402, &q, &g, &mut out).unwrap_err();
        assert_eq!(e.index(), Some(4));
        assert!(
            e.to_string().starts_with("an irregular sample period"),
            "{e}"
        );
        let e = p.push(0.010, &q, &g, &mut out).unwrap_err();
        assert!(e.to_string().starts_with("a gap"), "{e}");
        let e = p.push(0.003, &q, &g, &mut out).unwrap_err();
        assert!(e.to_string().starts_with("time must increase"), "{e}");
        let e = p.finish(&mut out).unwrap_err();
        assert!(matches!(e, LogError::TooShort { samples: 4, .. }), "{e}");
        assert!(LogProcessor::new(
            LogFilter {
                cutoff: Some(600.0),
                ..settings
            },
            1000.0,
            6
        )
        .is_err());
    }
}
