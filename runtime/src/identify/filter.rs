//! A Butterworth low-pass filter as a cascade of second-order sections, run forwards and
//! backwards for zero phase (what `scipy.signal.sosfiltfilt` does with `butter`).

use std::f64::consts::PI;

/// One second-order section, `H(z) = (b0 + b1 z⁻¹ + b2 z⁻²) / (1 + a1 z⁻¹ + a2 z⁻²)`, run in
/// transposed direct form II.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    pub b: [f64; 3],
    pub a: [f64; 2],
}

impl Section {
    /// The section's state for a constant input `x` (its DC gain is 1): no start-up transient.
    fn steady(&self, x: f64) -> [f64; 2] {
        let s2 = (self.b[2] - self.a[1]) * x;
        [(self.b[1] - self.a[0]) * x + s2, s2]
    }

    #[inline]
    fn step(&self, state: &mut [f64; 2], x: f64) -> f64 {
        let y = self.b[0] * x + state[0];
        state[0] = self.b[1] * x - self.a[0] * y + state[1];
        state[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// A Butterworth low-pass filter of even order: `|H(f)|² = 1 / (1 + (f/f_c)^(2n))`.
#[derive(Clone, Debug, PartialEq)]
pub struct Butterworth {
    pub order: usize,
    /// The cutoff `f_c` (Hz): the single pass is 3 dB down there, the zero-phase pair 6 dB.
    pub cutoff: f64,
    pub sections: Vec<Section>,
}

impl Butterworth {
    /// The low-pass filter of `order` (even, at least 2) and `cutoff` for samples at `rate`
    /// (both Hz, `cutoff < rate / 2`): the analogue prototype's pole pairs, damping
    /// `ζ_k = sin((2k + 1) π / 2n)`, through the bilinear transform prewarped at the cutoff,
    /// `K = tan(π f_c / f_s)`; each section normalised to a DC gain of 1.
    ///
    /// # Panics
    /// On an odd order or a cutoff outside `(0, rate / 2)`: settings are checked by the caller.
    pub fn low_pass(order: usize, cutoff: f64, rate: f64) -> Self {
        assert!(order >= 2 && order.is_multiple_of(2), "an even order");
        assert!(
            cutoff > 0.0 && cutoff < rate / 2.0,
            "a cutoff below Nyquist"
        );
        let k = (PI * cutoff / rate).tan();
        let sections = (0..order / 2)
            .map(|i| {
                let zeta = ((2 * i + 1) as f64 * PI / (2 * order) as f64).sin();
                let norm = 1.0 + 2.0 * zeta * k + k * k;
                let b0 = k * k / norm;
                Section {
                    b: [b0, 2.0 * b0, b0],
                    a: [
                        2.0 * (k * k - 1.0) / norm,
                        (1.0 - 2.0 * zeta * k + k * k) / norm,
                    ],
                }
            })
            .collect();
        Butterworth {
            order,
            cutoff,
            sections,
        }
    }

    /// How many samples at `rate` the impulse response takes to decay below `1e-12` of its
    /// size: the slowest pole pair's time constant, `1 / (2π f_c sin(π / 2n))`, times 27.6.
    pub fn settling(&self, rate: f64) -> usize {
        let decay = 2.0 * PI * self.cutoff * (PI / (2 * self.order) as f64).sin();
        (27.7 * rate / decay).ceil() as usize
    }

    /// Filters `signal` in place, forwards then backwards (zero phase, gain `|H|²`), each pass
    /// started in the steady state of its first value.
    pub fn zero_phase(&self, signal: &mut [f64]) {
        // Every section's input starts at the same value, the sections having a DC gain of 1.
        let (Some(&first), Some(&last)) = (signal.first(), signal.last()) else {
            return;
        };
        for section in &self.sections {
            let mut state = section.steady(first);
            for v in signal.iter_mut() {
                *v = section.step(&mut state, *v);
            }
        }
        let last = signal.last().copied().unwrap_or(last);
        for section in &self.sections {
            let mut state = section.steady(last);
            for v in signal.iter_mut().rev() {
                *v = section.step(&mut state, *v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sections_are_scipys() {
        // scipy.signal.butter(4, 20, fs=1000, output="sos") puts the whole gain in the first
        // section; the poles and the product of the gains are the same.
        let f = Butterworth::low_pass(4, 20.0, 1000.0);
        let mut a: Vec<[f64; 2]> = f.sections.iter().map(|s| s.a).collect();
        a.sort_by(|x, y| x[0].total_cmp(&y[0]));
        let want = [
            [-1.893_415_601_022_5, 0.908_464_412_949_295],
            [-1.778_313_488_139_435, 0.792_447_471_832_947],
        ];
        for (got, want) in a.iter().zip(want) {
            assert!((got[0] - want[0]).abs() < 1e-14 && (got[1] - want[1]).abs() < 1e-14);
        }
        let gain: f64 = f.sections.iter().map(|s| s.b[0]).product();
        assert!((gain - 1.329_372_889_875_29e-5).abs() < 1e-18);
    }

    /// The steady amplitude of a unit sine at `freq` after the zero-phase pair.
    fn amplitude(f: &Butterworth, freq: f64, rate: f64) -> f64 {
        let n = 20 * f.settling(rate);
        let mut x: Vec<f64> = (0..n)
            .map(|k| (2.0 * PI * freq * k as f64 / rate).sin())
            .collect();
        f.zero_phase(&mut x);
        let middle = &x[n / 3..2 * n / 3];
        middle.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
    }

    #[test]
    fn the_zero_phase_pair_has_the_butterworth_magnitude_squared() {
        let (rate, fc) = (1000.0, 20.0);
        let f = Butterworth::low_pass(4, fc, rate);
        for ratio in [0.25, 1.0, 2.0] {
            let want = 1.0 / (1.0 + f64::powi(ratio, 8));
            let got = amplitude(&f, ratio * fc, rate);
            assert!((got - want).abs() < 2e-3, "{ratio}: {got} vs {want}");
        }
        // A constant passes unchanged, to the last bit's worth: the passes start steady.
        let mut c = vec![3.25; 500];
        f.zero_phase(&mut c);
        assert!(c.iter().all(|v| (v - 3.25).abs() < 1e-12));
    }
}
