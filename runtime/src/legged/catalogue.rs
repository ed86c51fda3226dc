//! The catalogue of legged mechanisms: for each description of `c5_robot`, its generated
//! kernel set and what the shared code asks of it. Adding a legged mechanism to the runtime
//! is one entry here and one alias; everything else is [`LeggedRobot`]'s.

use super::{LeggedDescription, LeggedRobot};
use crate::error::Error;
use crate::mechanism::SpatialRobot;
use crate::scene::Scene;
use crate::Pose;
use alloc::vec::Vec;
use c5_generated::f64 as generated;
use c5_robot::Description;

/// The Gough-Stewart platform (6-UPS).
pub type GoughStewart = LeggedRobot<c5_robot::GoughStewart, 6>;
/// The rotary hexapod (6-RUS). Its actuator values are the encoders' readings of the crank
/// angles, `q_i = θ_i + o_i` (rad), and `Γ_i` is the motor's torque about its axis `r_i`
/// (N·m), a positive torque driving `θ_i` positive.
pub type RusHexapod = LeggedRobot<c5_robot::RusHexapod, 6>;
/// The Delta: its platform only translates, its state is `C`, `v_C` and `a_C` (base frame;
/// [`crate::Translation`]). Its actuator values are the encoders' readings of the upper arms'
/// angles, `q_i = θ_i + o_i` (rad), and `Γ_i` the motors' torques (N·m).
pub type Delta = LeggedRobot<c5_robot::Delta, 3>;

impl LeggedDescription<6> for c5_robot::GoughStewart {
    type Kernels = generated::gough_stewart::Kernels;
    #[cfg(feature = "identify")]
    const IDENTIFICATION_REACH: [f64; 6] = [0.2, 0.2, 0.2, 0.03, 0.03, 0.03];
    fn validate(&self) -> Result<(), c5_robot::Error> {
        c5_robot::GoughStewart::validate(self)
    }
    fn kernel_parameters(&self) -> Vec<f64> {
        c5_robot::GoughStewart::kernel_parameters(self)
    }
    fn home(&self) -> Option<[f64; 6]> {
        Some(c5_robot::GoughStewart::home(self))
    }
    fn description(&self) -> Description {
        Description::GoughStewart(*self)
    }
    fn start(&self, q: &[f64; 6], _home: &[f64; 6]) -> [f64; 6] {
        crate::gough_stewart::level_start(self, q)
    }
    fn characteristic_length(&self) -> f64 {
        mean_length(self.legs.iter().map(|leg| leg.platform))
    }
    fn smallest_pose_margin(
        robot: &GoughStewart,
        x: &[f64; 6],
    ) -> Result<Option<(crate::Limit, usize, f64, f64)>, Error> {
        Ok(robot.limit_margins(&Pose::from_array(*x))?.smallest())
    }
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>) {
        (self.limits.speed, self.limits.force)
    }
    fn has_limits(&self) -> bool {
        self.limits.any()
    }
    #[cfg(feature = "derivatives")]
    fn derivatives(robot: &GoughStewart) -> Option<&dyn crate::mechanism::Derivatives<6>> {
        Some(robot)
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[crate::identify::Friction; 6]) -> Vec<f64> {
        c5_robot::GoughStewart::standard_parameters(self, friction)
    }
    fn spatial(robot: &GoughStewart) -> Option<&dyn SpatialRobot> {
        Some(robot)
    }
    fn scene(robot: &GoughStewart, x: &[f64; 6]) -> Result<Scene, Error> {
        crate::scene::gough_stewart::scene(robot, &Pose::from_array(*x))
    }
}

impl LeggedDescription<6> for c5_robot::RusHexapod {
    type Kernels = generated::rus_hexapod::Kernels;
    #[cfg(feature = "identify")]
    const IDENTIFICATION_REACH: [f64; 6] = [0.1, 0.1, 0.1, 0.02, 0.02, 0.02];
    fn validate(&self) -> Result<(), c5_robot::Error> {
        c5_robot::RusHexapod::validate(self)
    }
    fn kernel_parameters(&self) -> Vec<f64> {
        c5_robot::RusHexapod::kernel_parameters(self)
    }
    fn home(&self) -> Option<[f64; 6]> {
        c5_robot::RusHexapod::home(self)
    }
    fn description(&self) -> Description {
        Description::RusHexapod(*self)
    }
    fn characteristic_length(&self) -> f64 {
        mean_length(self.legs.iter().map(|leg| leg.platform))
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[crate::identify::Friction; 6]) -> Vec<f64> {
        c5_robot::RusHexapod::standard_parameters(self, friction)
    }
    fn spatial(robot: &RusHexapod) -> Option<&dyn SpatialRobot> {
        Some(robot)
    }
    fn scene(robot: &RusHexapod, x: &[f64; 6]) -> Result<Scene, Error> {
        crate::scene::cranked::rus_hexapod(robot, &Pose::from_array(*x))
    }
}

impl LeggedDescription<3> for c5_robot::Delta {
    type Kernels = generated::delta::Kernels;
    #[cfg(feature = "identify")]
    const IDENTIFICATION_REACH: [f64; 3] = [0.05, 0.05, 0.05];
    fn validate(&self) -> Result<(), c5_robot::Error> {
        c5_robot::Delta::validate(self)
    }
    fn kernel_parameters(&self) -> Vec<f64> {
        c5_robot::Delta::kernel_parameters(self)
    }
    fn home(&self) -> Option<[f64; 3]> {
        c5_robot::Delta::home(self)
    }
    fn description(&self) -> Description {
        Description::Delta(*self)
    }
    fn characteristic_length(&self) -> f64 {
        mean_length(self.arms.iter().map(|arm| arm.platform))
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[crate::identify::Friction; 3]) -> Vec<f64> {
        c5_robot::Delta::standard_parameters(self, friction)
    }
    fn scene(robot: &Delta, x: &[f64; 3]) -> Result<Scene, Error> {
        crate::scene::cranked::delta(robot, x)
    }
    #[cfg(feature = "derivatives")]
    fn derivatives(robot: &Delta) -> Option<&dyn crate::mechanism::Derivatives<3>> {
        Some(robot)
    }
}

/// The mean length of `points`' vectors from `C` (m).
fn mean_length(points: impl ExactSizeIterator<Item = [f64; 3]>) -> f64 {
    let n = points.len() as f64;
    points
        .map(|p| crate::math::sqrt(p.iter().map(|x| x * x).sum()))
        .sum::<f64>()
        / n
}
