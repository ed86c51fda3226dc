//! Many states at once, for every mechanism whose kernels come in batch form: four states a
//! kernel call, each state's result or why it was refused, so one bad state costs only itself.
//!
//! The batch kernels' lanes compute exactly what the single-state kernels compute (the tests
//! hold them equal to the bit), so a group of four with a refused state is redone one state at
//! a time, as is a remainder of fewer than four: every state gets the result, or the error,
//! that the single-state method gives it.

use crate::Error;
use alloc::vec::Vec;

/// `[element][lane]` from four states' arrays.
#[cfg(feature = "batch")]
fn lanes<const N: usize>(rows: &[[f64; N]; 4]) -> [[f64; 4]; N] {
    core::array::from_fn(|k| core::array::from_fn(|l| rows[l][k]))
}

/// Whether every value is finite, without a branch per value.
#[cfg(feature = "batch")]
#[inline]
fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// Whether every lane's guard terms (`guard[term][lane]`) pass `check`, without branching per
/// lane: which lane is refused, and why, is for the single-state method to say.
#[cfg(feature = "batch")]
#[inline]
pub(crate) fn lanes_hold<const G: usize>(
    guard: &[[f64; 4]; G],
    check: impl Fn([f64; G]) -> Result<(), Error>,
) -> bool {
    (0..4).fold(true, |ok, l| {
        ok & check(core::array::from_fn(|e| guard[e][l])).is_ok()
    })
}

/// [`lanes_hold`] for a guard of any length (a legged mechanism's terms, `terms` saying what
/// each measures); `false` for one longer than the buffer, which the single-state method then
/// checks.
#[cfg(feature = "batch")]
#[inline]
pub(crate) fn terms_hold(
    guard: &[[f64; 4]],
    terms: &[crate::singularity::SingularityTerm],
) -> bool {
    const MOST: usize = 64;
    if guard.len() > MOST {
        return false;
    }
    let mut lane = [0.0; MOST];
    (0..4).fold(true, |ok, l| {
        for (value, term) in lane.iter_mut().zip(guard) {
            *value = term[l];
        }
        ok & crate::singularity::check(&lane[..guard.len()], terms).is_ok()
    })
}

/// One row of a batch call: its three input arrays of `N` numbers, the kernel on four rows,
/// and the single-state method that must agree with a lane.
#[cfg(feature = "batch")]
pub(crate) struct Batched<Input, Kernel, Single> {
    /// Row `k`'s three input arrays.
    pub input: Input,
    /// The batch kernel on four rows, lane-major: its result, or `None` where a lane's guard
    /// terms refuse it (or the mechanism has no batch form).
    pub kernel: Kernel,
    /// The single-state method, for a group with a refused row and for the remainder.
    pub single: Single,
}

#[cfg(feature = "batch")]
impl<Input, Kernel, Single, const N: usize> Batched<Input, Kernel, Single>
where
    Input: Fn(usize) -> [[f64; N]; 3],
    Kernel: Fn(&[[f64; 4]; N], &[[f64; 4]; N], &[[f64; 4]; N]) -> Option<[[f64; 4]; N]>,
    Single: Fn(usize) -> Result<[f64; N], Error>,
{
    /// Four rows through the batch kernel, or `None` if one of them is refused.
    #[inline]
    fn four(&self, k: usize) -> Option<[[f64; N]; 4]> {
        let rows: [[[f64; N]; 3]; 4] = core::array::from_fn(|l| (self.input)(k + l));
        if !all_finite(rows.as_flattened().as_flattened()) {
            return None;
        }
        let column = |j: usize| lanes(&core::array::from_fn(|l| rows[l][j]));
        let result = (self.kernel)(&column(0), &column(1), &column(2))?;
        if !all_finite(result.as_flattened()) {
            return None;
        }
        Some(core::array::from_fn(|l| {
            core::array::from_fn(|e| result[e][l])
        }))
    }

    /// Every row `0..n` in order, to `each`.
    pub fn run(&self, n: usize, mut each: impl FnMut(usize, Result<[f64; N], Error>)) {
        let full = n / 4 * 4;
        for k in (0..full).step_by(4) {
            match self.four(k) {
                Some(rows) => {
                    for (l, row) in rows.into_iter().enumerate() {
                        each(k + l, Ok(row));
                    }
                }
                None => (k..k + 4).for_each(|r| each(r, (self.single)(r))),
            }
        }
        (full..n).for_each(|r| each(r, (self.single)(r)));
    }
}

/// Every row `0..n` in order through the single-state method: the batch methods without the
/// batch kernels.
#[cfg(not(feature = "batch"))]
pub(crate) fn one_at_a_time<T>(
    n: usize,
    single: impl Fn(usize) -> Result<T, Error>,
    mut each: impl FnMut(usize, Result<T, Error>),
) {
    (0..n).for_each(|k| each(k, single(k)));
}

/// Collects `run`'s results, or the first refused index and why.
pub(crate) fn collect<T>(
    n: usize,
    run: impl FnOnce(&mut dyn FnMut(usize, Result<T, Error>)),
) -> Result<Vec<T>, (usize, Error)> {
    let mut out = Vec::with_capacity(n);
    let mut first = None;
    run(&mut |k, result| match result {
        Ok(value) if first.is_none() => out.push(value),
        Ok(_) => {}
        Err(e) => {
            first.get_or_insert((k, e));
        }
    });
    match first {
        Some(refused) => Err(refused),
        None => Ok(out),
    }
}
