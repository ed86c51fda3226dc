//! The C5's many states at once: its batch kernels four states at a time, each state's result
//! or why it was refused, so one bad state costs only itself.
//!
//! Without the `batch` feature the same methods go one state at a time, with the same results
//! to the bit: a program that calls them for convenience (the `c5` program's `simulate`) then
//! does not compile the batch kernels, about 15 s of LLVM on two cores (docs/build-time.md).
//!
//! The batch kernels' lanes compute exactly what the single-state kernels compute (the tests
//! hold them equal to the bit), so a group of four with a refused state is redone one state at
//! a time, as is a remainder of fewer than four: every state gets the result, or the error,
//! that the single-state method gives it.

#[cfg(feature = "batch")]
use crate::c5::{check_forward_dynamics, check_joint_dynamics};
#[cfg(feature = "batch")]
use crate::{check_divisors, Kernels};
use crate::{Acceleration, Error, Pose, State, Twist, C5};
use alloc::vec::Vec;

/// `[element][lane]` from four states' arrays.
#[cfg(feature = "batch")]
fn lanes(rows: &[[f64; 6]; 4]) -> [[f64; 4]; 6] {
    core::array::from_fn(|k| core::array::from_fn(|l| rows[l][k]))
}

/// Whether every value is finite, without a branch per value.
#[cfg(feature = "batch")]
#[inline]
fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// One row of a batch call: its three input arrays, the kernel, and the single-state method
/// that must agree with a lane.
#[cfg(feature = "batch")]
struct Batched<Input, Kernel, Guard, Single> {
    /// Row `k`'s three input arrays.
    input: Input,
    /// The batch kernel on four rows: the result and the guard terms, lane-major.
    kernel: Kernel,
    /// The guard terms' check (the divisors of eq 16, or the forward singularity).
    guard: Guard,
    /// The single-state method, for a group with a refused row and for the remainder.
    single: Single,
}

#[cfg(feature = "batch")]
impl<Input, Kernel, Guard, Single, const G: usize> Batched<Input, Kernel, Guard, Single>
where
    Input: Fn(usize) -> [[f64; 6]; 3],
    Kernel: Fn(&[[f64; 4]; 6], &[[f64; 4]; 6], &[[f64; 4]; 6]) -> ([[f64; 4]; 6], [[f64; 4]; G]),
    Guard: Fn([f64; G]) -> Result<(), Error>,
    Single: Fn(usize) -> Result<[f64; 6], Error>,
{
    /// Four rows through the batch kernel, or `None` if one of them is refused. The checks
    /// run over all four rows at once, without branching per value: which row is refused, and
    /// why, is for the single-state method to say.
    #[inline]
    fn four(&self, k: usize) -> Option<[[f64; 6]; 4]> {
        let rows: [[[f64; 6]; 3]; 4] = core::array::from_fn(|l| (self.input)(k + l));
        if !all_finite(rows.as_flattened().as_flattened()) {
            return None;
        }
        let column = |j: usize| lanes(&core::array::from_fn(|l| rows[l][j]));
        let (result, guard) = (self.kernel)(&column(0), &column(1), &column(2));
        let guards_hold = (0..4).fold(true, |ok, l| {
            ok & (self.guard)(core::array::from_fn(|e| guard[e][l])).is_ok()
        });
        if !(guards_hold && all_finite(result.as_flattened())) {
            return None;
        }
        Some(core::array::from_fn(|l| {
            core::array::from_fn(|e| result[e][l])
        }))
    }

    /// Every row `0..n` in order, to `each`.
    fn run(&self, n: usize, mut each: impl FnMut(usize, Result<[f64; 6], Error>)) {
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
fn one_at_a_time<T>(
    n: usize,
    single: impl Fn(usize) -> Result<T, Error>,
    mut each: impl FnMut(usize, Result<T, Error>),
) {
    (0..n).for_each(|k| each(k, single(k)));
}

/// Collects `run`'s results, or the first refused index and why.
fn collect<T>(
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

impl C5 {
    /// [`C5::inverse_dynamics`] of states `0..n` (`state(k)` the `k`-th), four at a time
    /// through the batch kernel (one at a time without the `batch` feature): each state's
    /// forces, or why it was refused, handed to `each` in order. For callers that read states
    /// from their own storage (numpy arrays, a log).
    pub fn inverse_dynamics_each(
        &self,
        n: usize,
        state: impl Fn(usize) -> State,
        each: impl FnMut(usize, Result<[f64; 6], Error>),
    ) {
        let single = |k| self.inverse_dynamics(&state(k));
        #[cfg(feature = "batch")]
        Batched {
            input: |k| {
                let s = state(k);
                [s.pose.to_array(), s.twist.to_array(), s.accel.to_array()]
            },
            kernel: |x: &_, v: &_, a: &_| {
                self.kernels
                    .inverse_dynamics_params_x4(x, v, a, &self.params)
            },
            guard: check_divisors,
            single,
        }
        .run(n, each);
        #[cfg(not(feature = "batch"))]
        one_at_a_time(n, single, each);
    }

    /// Actuator forces `Γ` of many states, four at a time through the batch kernels (each lane
    /// computes exactly what [`C5::inverse_dynamics`] computes), with the same checks.
    ///
    /// # Errors
    /// The index of the first refused state, and why (non-finite inputs, a singular pose, or a
    /// non-finite result).
    pub fn inverse_dynamics_many(&self, states: &[State]) -> Result<Vec<[f64; 6]>, (usize, Error)> {
        collect(states.len(), |each| {
            self.inverse_dynamics_each(states.len(), |k| states[k], each)
        })
    }

    /// [`C5::forward_dynamics`] of inputs `0..n` (`input(k)` the `k`-th pose, twist and
    /// actuator forces), four at a time through the batch kernel (one at a time without the
    /// `batch` feature): each platform acceleration, or why it was refused, handed to `each` in
    /// order.
    pub fn forward_dynamics_each(
        &self,
        n: usize,
        input: impl Fn(usize) -> (Pose, Twist, [f64; 6]),
        mut each: impl FnMut(usize, Result<Acceleration, Error>),
    ) {
        let single = |k| {
            let (pose, twist, gamma) = input(k);
            self.forward_dynamics(&pose, &twist, &gamma)
                .map(|a| a.to_array())
        };
        let each = |k, a: Result<[f64; 6], Error>| each(k, a.map(Acceleration::from_array));
        #[cfg(feature = "batch")]
        Batched {
            input: |k| {
                let (pose, twist, gamma) = input(k);
                [pose.to_array(), twist.to_array(), gamma]
            },
            kernel: |x: &_, v: &_, g: &_| {
                self.kernels
                    .forward_dynamics_params_x4(x, v, g, &self.params)
            },
            guard: |r| check_forward_dynamics(self.forward_dynamics_tolerance(), r),
            single,
        }
        .run(n, each);
        #[cfg(not(feature = "batch"))]
        one_at_a_time(n, single, each);
    }

    /// [`C5::inverse_dynamics_joint`] of samples `0..n` (`sample(k)` the `k`-th `[q, q̇, q̈]`),
    /// four at a time through the batch kernel (one at a time without the `batch` feature):
    /// each sample's forces, or why it was refused, handed to `each` in order.
    pub fn inverse_dynamics_joint_each(
        &self,
        n: usize,
        sample: impl Fn(usize) -> [[f64; 6]; 3],
        each: impl FnMut(usize, Result<[f64; 6], Error>),
    ) {
        let single = |k| {
            let [q, qd, qdd] = sample(k);
            self.inverse_dynamics_joint(&q, &qd, &qdd)
        };
        #[cfg(feature = "batch")]
        Batched {
            input: &sample,
            kernel: |q: &_, qd: &_, qdd: &_| {
                self.kernels
                    .inverse_dynamics_joint_params_x4(q, qd, qdd, &self.params)
            },
            guard: check_joint_dynamics,
            single,
        }
        .run(n, each);
        #[cfg(not(feature = "batch"))]
        one_at_a_time(n, single, each);
    }

    /// [`C5::inverse_dynamics_joint`] for many samples `(q, q̇, q̈)`, four at a time through the
    /// batch kernels (each lane computes exactly what the single-sample kernel does).
    ///
    /// # Errors
    /// The index of the first refused sample, and why.
    pub fn inverse_dynamics_joint_many(
        &self,
        samples: &[[[f64; 6]; 3]],
    ) -> Result<Vec<[f64; 6]>, (usize, Error)> {
        collect(samples.len(), |each| {
            self.inverse_dynamics_joint_each(samples.len(), |k| samples[k], each)
        })
    }

    /// [`C5::evaluate`] for many states, the inverse dynamics through the batch kernels.
    ///
    /// # Errors
    /// The index of the first refused state, and why.
    pub fn evaluate_many(
        &self,
        states: &[State],
    ) -> Result<Vec<crate::Evaluation>, (usize, Error)> {
        let gammas = self.inverse_dynamics_many(states)?;
        states
            .iter()
            .zip(gammas)
            .enumerate()
            .map(|(k, (state, gamma))| {
                let at = |e| (k, e);
                let (q, _) = self.inverse_kinematics(&state.pose).map_err(at)?;
                Ok(crate::Evaluation {
                    q,
                    qd: self
                        .joint_velocities(&state.pose, &state.twist)
                        .map_err(at)?,
                    qdd: self.joint_accelerations(state).map_err(at)?,
                    gamma,
                    jinv: self.inverse_jacobian(&state.pose).map_err(at)?,
                    jacobian: self.jacobian(&state.pose).map_err(at)?,
                })
            })
            .collect()
    }
}
