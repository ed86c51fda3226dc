//! The rotary hexapod (6-RUS) for controllers: a safe, typed API over its generated kernels
//! (`c5_generated::f64::rus_hexapod`, the variants that take the robot's parameters, so any
//! valid description works).
//!
//! Its conventions are the Gough-Stewart platform's for the platform (pose
//! `[α β γ xc yc zc]`, twist `(ω; v_C)`, classical acceleration `(ω̇; a_C)` at `C`, base
//! frame). The actuator values are the encoders' readings of the crank angles,
//! `q_i = θ_i + o_i` (rad), and `Γ_i` is the motor's torque about its axis `r_i` (N·m), a
//! positive torque driving `θ_i` positive. Every call checks its inputs and refuses a pose
//! where a ball is beyond its crank's reach, a crank and its rod align, a U joint or the legs'
//! hold on the platform is singular ([`Error::Singularity`], naming the term). The forward
//! kinematics is a generated Newton step iterated here, from a previous solution or from home.

use crate::error::Error;
use crate::gough_stewart::{FORWARD_U_JOINT_TOLERANCE, HOLD_TOLERANCE, U_JOINT_TOLERANCE};
use crate::legged::{self, check_conditioned, newton, Linearised};
use crate::{check_finite, finite, finite_matrix, Acceleration, Evaluation, Pose, State, Twist};
use c5_generated::f64::rus_hexapod as kernels;
pub use c5_robot::RusHexapod as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::RUS_HEXAPOD;

/// The length of the parameter vector of the rotary hexapod's `*_params` kernels.
pub const PARAMETERS: usize = kernels::PARAMETERS;

/// Smallest accepted `1 - (K/ρ)²`, the squared sine of the angle between a crank and its rod
/// in the crank's plane: at zero they align (the ball at the edge of the crank's reach, where
/// `∂θ/∂B` is unbounded); negative, the ball is beyond reach.
pub const REACH_TOLERANCE: f64 = 1e-10;

/// The names of the singularity terms, as errors report them.
const TERMS: [&str; 18] = [
    "U joint of leg 1",
    "U joint of leg 2",
    "U joint of leg 3",
    "U joint of leg 4",
    "U joint of leg 5",
    "U joint of leg 6",
    "crank and rod of leg 1 aligned (1 - (K/ρ)²)",
    "crank and rod of leg 2 aligned (1 - (K/ρ)²)",
    "crank and rod of leg 3 aligned (1 - (K/ρ)²)",
    "crank and rod of leg 4 aligned (1 - (K/ρ)²)",
    "crank and rod of leg 5 aligned (1 - (K/ρ)²)",
    "crank and rod of leg 6 aligned (1 - (K/ρ)²)",
    "legs' hold (pivot 1)",
    "legs' hold (pivot 2)",
    "legs' hold (pivot 3)",
    "legs' hold (pivot 4)",
    "legs' hold (pivot 5)",
    "legs' hold (pivot 6)",
];

/// The cranks' reach terms' names where they are negative.
const BEYOND_REACH: [&str; 6] = [
    "ball of leg 1 beyond its crank's reach (1 - (K/ρ)²)",
    "ball of leg 2 beyond its crank's reach (1 - (K/ρ)²)",
    "ball of leg 3 beyond its crank's reach (1 - (K/ρ)²)",
    "ball of leg 4 beyond its crank's reach (1 - (K/ρ)²)",
    "ball of leg 5 beyond its crank's reach (1 - (K/ρ)²)",
    "ball of leg 6 beyond its crank's reach (1 - (K/ρ)²)",
];

/// Refuses the singularity terms below their tolerance (or NaN): the U joints' sines, the
/// cranks' reach, then (when given) the pivots of the solve.
pub(crate) fn check_terms(terms: &[f64]) -> Result<(), Error> {
    // The reach first: beyond it every other term is NaN.
    for k in (6..12).chain(0..6).chain(12..terms.len()) {
        let value = terms[k];
        let bound = match k {
            0..6 => U_JOINT_TOLERANCE,
            6..12 => REACH_TOLERANCE,
            _ => HOLD_TOLERANCE,
        };
        if value.is_nan() || value < bound {
            let beyond = (6..12).contains(&k) && value < 0.0;
            return Err(Error::Singularity {
                term: if beyond {
                    BEYOND_REACH[k - 6]
                } else {
                    TERMS[k]
                },
                value,
                bound,
            });
        }
    }
    Ok(())
}

/// A validated rotary hexapod and its parameter vector.
#[derive(Clone, Debug)]
pub struct RusHexapod {
    robot: Description,
    params: [f64; PARAMETERS],
    home: [f64; 6],
}

impl RusHexapod {
    /// The rotary hexapod of `robot`.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of `RusHexapod::validate`.
    pub fn new(robot: Description) -> Result<Self, Error> {
        robot.validate().map_err(Error::from_robot)?;
        let home = robot.home().ok_or_else(|| Error::Robot {
            field: "home".into(),
            rule: "is missing, and no level height reaches every leg".into(),
        })?;
        let mut params = [0.0; PARAMETERS];
        params.copy_from_slice(&robot.kernel_parameters());
        Ok(RusHexapod {
            robot,
            params,
            home,
        })
    }

    pub fn robot(&self) -> &Description {
        &self.robot
    }

    /// The parameter vector, as the `*_params` kernels take it.
    pub fn parameters(&self) -> &[f64; PARAMETERS] {
        &self.params
    }

    /// The home pose: where the forward kinematics starts without a previous solution.
    pub fn home(&self) -> Pose {
        Pose::from_array(self.home)
    }

    legged::kernel_calls!(18);

    /// The forward dynamics: the platform's classical acceleration under the motor torques
    /// `gamma` (N·m).
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a U joint too near its singularity for the
    /// acceleration's bound ([`Error::IllConditioned`]), or a non-finite result.
    pub fn forward_dynamics(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<Acceleration, Error> {
        let (x, v) = (pose.to_array(), twist.to_array());
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        check_finite("gamma", gamma)?;
        let (a, guard) = kernels::forward_dynamics_params(&x, &v, gamma, &self.params);
        // The U joints' sines, the cranks' reach and the legs' hold.
        check_terms(&guard)?;
        check_conditioned(
            "forward dynamics",
            &guard[..6],
            &TERMS[..6],
            FORWARD_U_JOINT_TOLERANCE,
        )?;
        Ok(Acceleration::from_array(finite("acceleration", a)?))
    }

    /// The pose whose actuator positions are `q` (rad), by Newton's method from `near` (a
    /// previous solution) or from home; the pose found is refused where it is singular.
    ///
    /// # Errors
    /// [`Error::NonFinite`], [`Error::NotConverged`], [`Error::Singularity`].
    pub fn forward_kinematics(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<Pose, Error> {
        self.located(q, near).map(|(pose, _)| pose)
    }

    /// [`RusHexapod::forward_kinematics`] and the singularity terms at the pose found.
    fn located(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<(Pose, [f64; 18]), Error> {
        check_finite("q", q)?;
        let start = match near {
            Some(p) => {
                check_finite("near", &p.to_array())?;
                p.to_array()
            }
            None => self.home,
        };
        let x = newton(
            |x, out| {
                let (r, jac, guard) = kernels::forward_kinematics_step_params(x, q, &self.params);
                check_terms(&guard)?;
                *out = Linearised {
                    residual: finite("residual", r)?,
                    jacobian: jac,
                };
                Ok(())
            },
            start,
        )?;
        let terms = kernels::singularity_terms_params(&x, &self.params);
        check_terms(&terms)?;
        Ok((Pose::from_array(x), terms))
    }

    legged::joint_space_methods!();
}

legged::legged_impl!(RusHexapod, 12);
