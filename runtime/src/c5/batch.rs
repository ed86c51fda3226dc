//! The C5's many states at once: its batch kernels four states at a time through
//! [`crate::many`], each state's result or why it was refused, so one bad state costs only
//! itself.
//!
//! Without the `batch` feature the same methods go one state at a time, with the same results
//! to the bit: a program that calls them for convenience (the `c5` program's `simulate`) then
//! does not compile the batch kernels, about 15 s of LLVM on two cores (docs/build-time.md).

#[cfg(feature = "batch")]
use crate::c5::{check_forward_dynamics, check_joint_dynamics};
use crate::many::collect;
#[cfg(not(feature = "batch"))]
use crate::many::one_at_a_time;
#[cfg(feature = "batch")]
use crate::many::{lanes_hold, Batched};
#[cfg(feature = "batch")]
use crate::{check_divisors, Kernels};
use crate::{Acceleration, Error, Pose, State, Twist, C5};
use alloc::vec::Vec;

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
                let (gamma, guard) = self
                    .kernels
                    .inverse_dynamics_params_x4(x, v, a, &self.params);
                lanes_hold(&guard, check_divisors).then_some(gamma)
            },
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
                let (accel, guard) = self
                    .kernels
                    .forward_dynamics_params_x4(x, v, g, &self.params);
                let tolerance = self.forward_dynamics_tolerance();
                lanes_hold(&guard, |r| check_forward_dynamics(tolerance, r)).then_some(accel)
            },
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
                let (gamma, guard) =
                    self.kernels
                        .inverse_dynamics_joint_params_x4(q, qd, qdd, &self.params);
                lanes_hold(&guard, check_joint_dynamics).then_some(gamma)
            },
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
