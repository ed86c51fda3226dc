//! The C5 joint parallel robot for controllers: a safe, typed API over the generated kernels.
//!
//! [`C5`] holds a validated [`Robot`] and a [`Model`], checks every input, calls the generated
//! straight-line kernels (`c5-generated`, the variants that take the robot's parameters, so
//! any valid robot works) and refuses a singular pose or a non-finite result with a typed
//! [`Error`]. It allocates nothing and never panics on its inputs.
//!
//! Two models of the legs' mechanism, one call apart: [`Model::Consistent`] (the default: the
//! mechanism of eq 16, whose forces close the power balance) and [`Model::Paper`] (the
//! chapter as published, right only at zero orientation).
//!
//! The legged mechanisms of the catalogue are one type, [`LeggedRobot`], over each one's
//! generated kernel set ([`legged`]): [`GoughStewart`] (6-UPS), [`RusHexapod`] (6-RUS) and
//! [`Delta`] (three translations) name it for their descriptions. [`platform::load`] makes any
//! mechanism from a robot file behind one [`Mechanism`], its dimension from the platform's
//! freedom.
//!
//! The crate is `no_std` (with `alloc`, for the robot description's error messages) without
//! its default `std` feature; `libm` then provides the trigonometry. With the `identify`
//! feature, `identify` fits the robot's inertial parameters and friction to measured motion and
//! forces. With the `reference` feature, `reference` is the chapter and the consistent model in
//! matrix form with `nalgebra`, kept independent of the generator so the two check each other.
//! With the `calibrate` feature, [`calibrate`] fits a legged mechanism's geometry to measured
//! poses. With the `derivatives` feature, [`derivatives`] gives the dynamics with their exact Jacobians.
//!
//! # Example
//!
//! ```
//! use c5_runtime::{Model, Pose, Robot, State, C5};
//!
//! let robot = C5::new(Robot::default())?; // the consistent model
//! let mut state = State::default();
//! state.pose = Pose::from_array([0.17, 0.26, 0.35, 0.0, 0.0, 0.0]);
//! let gamma = robot.inverse_dynamics(&state)?; // N, segment order
//! let paper = C5::with_model(Robot::default(), Model::Paper)?.inverse_dynamics(&state)?;
//! // At rest in a turned pose the chapter's model misses the load on the horizontal legs.
//! assert!(gamma[0].abs() > 5.0 && paper[0].abs() < 1e-9);
//! # Ok::<(), c5_runtime::Error>(())
//! ```

#![cfg_attr(not(feature = "std"), no_std)]

extern crate alloc;

mod c5;
#[cfg(feature = "calibrate")]
pub mod calibrate;
pub mod control;
mod dense;
#[cfg(feature = "derivatives")]
pub mod derivatives;
pub mod dynamics;
pub mod error;
pub mod gough_stewart;
#[cfg(feature = "identify")]
pub mod identify;
pub mod legged;
pub mod limits;
mod many;
mod math;
pub mod mechanism;
#[cfg(feature = "plan")]
pub mod plan;
pub mod platform;
#[cfg(feature = "reference")]
pub mod reference;
pub mod scene;
pub mod sensors;
pub mod singularity;
pub mod trajectory;
pub mod types;
#[cfg(feature = "workspace")]
pub mod workspace;

pub use c5_robot::{Description, Limits, Model, Robot};
pub use error::Error;
pub use gough_stewart::GoughStewart;
pub use legged::catalogue::{Delta, RusHexapod};
pub use legged::LeggedRobot;
pub use limits::{Limit, LimitMargins};
pub use mechanism::{ParallelRobot, SpatialRobot};
pub use platform::Mechanism;
pub use types::{Acceleration, Pose, State, Translation, Twist};

pub(crate) use c5::check_divisors;
pub use c5::{
    kernels, C5, FORWARD_DYNAMICS_TOLERANCE, JOINT_DYNAMICS_TOLERANCE, JOINT_STATE_TOLERANCE,
    PAPER_FORWARD_DYNAMICS_TOLERANCE, SINGULARITY_TOLERANCE,
};
pub use c5_generated::f64::Kernels;
/// Whether the kernels run their FMA twins (fused multiply-add, where the CPU has it, with the
/// `fma` feature), and the switch to turn them off for the same bits on every machine.
pub use c5_generated::fma;

/// Refuses an input holding NaN or an infinity.
///
/// # Errors
/// [`Error::NonFinite`] naming the input and the index.
#[inline]
pub(crate) fn check_finite(input: &'static str, v: &[f64]) -> Result<(), Error> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(Error::NonFinite { input, index }),
        None => Ok(()),
    }
}

/// Passes `value` on if every number in it is finite.
pub(crate) fn finite<const N: usize>(
    output: &'static str,
    value: [f64; N],
) -> Result<[f64; N], Error> {
    if value.iter().all(|x| x.is_finite()) {
        Ok(value)
    } else {
        Err(Error::NonFiniteResult { output })
    }
}

pub(crate) fn finite_matrix<const R: usize, const C: usize>(
    output: &'static str,
    m: [[f64; C]; R],
) -> Result<[[f64; C]; R], Error> {
    if m.iter().flatten().all(|x| x.is_finite()) {
        Ok(m)
    } else {
        Err(Error::NonFiniteResult { output })
    }
}

/// The kinematic and dynamic quantities of one platform state, actuator order, in the
/// platform's `N` coordinates (six for a platform free in space, three for the Delta's) and the
/// actuators' units (m and N for the C5's and the Gough-Stewart platform's, rad and N·m for
/// motors that turn).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(serialize = "[f64; N]: serde::Serialize, [[f64; N]; N]: serde::Serialize"))
)]
pub struct Evaluation<const N: usize = 6> {
    /// The actuator values `q` (the C5's `Q_i1`, eq 16).
    pub q: [f64; N],
    /// Their rates, `J⁻¹ V`.
    pub qd: [f64; N],
    /// Their accelerations.
    pub qdd: [f64; N],
    /// The actuator forces `Γ_i`.
    pub gamma: [f64; N],
    /// `J⁻¹`, row `i` for actuator `i+1`, columns the twist's.
    pub jinv: [[f64; N]; N],
    /// `J`, column `i` for actuator `i+1`.
    pub jacobian: [[f64; N]; N],
}
