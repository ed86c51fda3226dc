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
use crate::legged;
use crate::{check_finite, finite, finite_matrix, Acceleration, Evaluation, Pose, State, Twist};
use c5_generated::f64::rus_hexapod as kernels;
pub use c5_robot::RusHexapod as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::RUS_HEXAPOD;

/// The length of the parameter vector of the rotary hexapod's `*_params` kernels.
pub const PARAMETERS: usize = kernels::PARAMETERS;

pub use crate::singularity::REACH_TOLERANCE;

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

    legged::spatial_kernel_calls!(18);

    /// Where the forward kinematics starts without a previous solution: home.
    fn start(&self, _q: &[f64; 6]) -> [f64; 6] {
        self.home
    }

    legged::joint_space_methods!();
}

legged::legged_impl!(RusHexapod);
