//! The Delta for controllers: a safe, typed API over its generated kernels
//! (`c5_generated::f64::delta`, the variants that take the robot's parameters, so any valid
//! description works).
//!
//! The platform only translates: its state is its position `C`, velocity `v_C` and
//! acceleration `a_C` (base frame, m, m/s, m/s²). The actuator values are the encoders'
//! readings of the upper arms' angles, `q_i = θ_i + o_i` (rad), and `Γ_i` is the motor's torque
//! about its axis `r_i` (N·m), a positive torque driving `θ_i` positive. Every call checks its
//! inputs and refuses a position where the platform is beyond an arm's reach, an arm's crank
//! and rods align, a U joint or the arms' hold on the platform is singular
//! ([`Error::Singularity`], naming the term). The forward kinematics is in closed form: of the
//! two points where the arms' spheres meet, the one on the home position's side.

use crate::error::Error;
use crate::mechanism::ParallelRobot;
use crate::platform::{array, Freedom, Mechanism};
use crate::{check_finite, finite, finite_matrix};
use alloc::vec::Vec;
use c5_generated::f64::delta as kernels;
pub use c5_robot::Delta as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::DELTA;

/// The length of the parameter vector of the Delta's `*_params` kernels.
pub const PARAMETERS: usize = c5_robot::delta::PARAMETERS;

pub use crate::singularity::{FORWARD_KINEMATICS_TOLERANCE, HOLD_RATIO_TOLERANCE};

/// The platform's state: position, velocity and acceleration of `C` (base frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Translation {
    /// `C` (m).
    pub position: [f64; 3],
    /// `v_C` (m/s).
    pub velocity: [f64; 3],
    /// `a_C` (m/s²).
    pub acceleration: [f64; 3],
}

/// `state`'s position, velocity and acceleration, each checked finite.
pub(crate) fn checked_motion(state: &Translation) -> Result<[[f64; 3]; 3], Error> {
    check_finite("position", &state.position)?;
    check_finite("velocity", &state.velocity)?;
    check_finite("acceleration", &state.acceleration)?;
    Ok([state.position, state.velocity, state.acceleration])
}

/// A state's position, velocity and acceleration, each checked finite by its own name.
impl crate::legged::Coordinates for Translation {
    type Array = crate::legged::Motion<3>;
    fn checked(&self, _name: &'static str) -> Result<crate::legged::Motion<3>, Error> {
        checked_motion(self)
    }
}

/// The kinematic and dynamic quantities of one state, arm order: `q` the motors' angles (rad),
/// `Γ` their torques (N·m), `J⁻¹` with columns `[vx vy vz]`.
pub type DeltaEvaluation = crate::Evaluation<3>;

/// A validated Delta and its parameter vector.
#[derive(Clone, Debug)]
pub struct Delta {
    robot: Description,
    params: [f64; PARAMETERS],
    home: [f64; 3],
}

impl Delta {
    /// The Delta of `robot`.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of `Delta::validate`.
    pub fn new(robot: Description) -> Result<Self, Error> {
        robot.validate().map_err(Error::from_robot)?;
        let home = robot.home().ok_or_else(|| Error::Robot {
            field: "home".into(),
            rule: "is missing, and no height reaches every arm".into(),
        })?;
        let mut params = [0.0; PARAMETERS];
        params.copy_from_slice(&robot.kernel_parameters());
        Ok(Delta {
            robot,
            params,
            home,
        })
    }

    pub fn robot(&self) -> &Description {
        &self.robot
    }

    /// The `*_params` kernels' parameter vector (`Delta::kernel_parameters`).
    pub fn parameters(&self) -> &[f64; PARAMETERS] {
        &self.params
    }

    /// The home position: the file's, or centred at the height where the arms are nearest
    /// their zero.
    pub fn home(&self) -> [f64; 3] {
        self.home
    }

    crate::legged::kernel_calls!(
        terms: 7,
        coordinates: 3,
        pose: [f64; 3],
        twist: [f64; 3],
        state: Translation
    );

    /// The motors' angles at `position`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::Singularity`] naming the term.
    pub fn inverse_kinematics(&self, position: &[f64; 3]) -> Result<[f64; 3], Error> {
        check_finite("position", position)?;
        let (q, terms) = kernels::inverse_kinematics_params(position, &self.params);
        crate::singularity::check(&terms, &kernels::SINGULARITY_TERMS)?;
        finite("q", q)
    }

    /// The platform's acceleration under the motors' torques `gamma`.
    ///
    /// # Errors
    /// As [`Delta::jacobian`].
    pub fn forward_dynamics(
        &self,
        position: &[f64; 3],
        velocity: &[f64; 3],
        gamma: &[f64; 3],
    ) -> Result<[f64; 3], Error> {
        check_finite("position", position)?;
        check_finite("velocity", velocity)?;
        check_finite("gamma", gamma)?;
        let (accel, terms) =
            kernels::forward_dynamics_params(position, velocity, gamma, &self.params);
        crate::singularity::check(&terms, &kernels::SINGULARITY_TERMS)?;
        finite("acceleration", accel)
    }

    /// The position whose motors' angles are `q`: of the two points where the arms' spheres
    /// meet, the one on the home position's side of the spheres' centres (the plane halfway
    /// between the two points). Refused where the spheres miss or touch, or at the point's
    /// singularities as [`Delta::jacobian`].
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::Singularity`] naming the term.
    pub fn forward_kinematics(&self, q: &[f64; 3]) -> Result<[f64; 3], Error> {
        self.located(q).map(|(position, _)| position)
    }

    /// [`Delta::forward_kinematics`] and the singularity terms at the position found.
    fn located(&self, q: &[f64; 3]) -> Result<([f64; 3], [f64; 7]), Error> {
        check_finite("q", q)?;
        let (points, terms) = kernels::forward_kinematics_params(q, &self.params);
        crate::singularity::check(&terms, &kernels::FORWARD_KINEMATICS_TERMS)?;
        let [plus, minus] = points;
        let side: f64 = (0..3)
            .map(|k| (plus[k] - minus[k]) * (self.home[k] - 0.5 * (plus[k] + minus[k])))
            .sum();
        let position = finite("position", if side >= 0.0 { plus } else { minus })?;
        let terms = self.singularity_terms(&position)?;
        crate::singularity::check(&terms, &kernels::SINGULARITY_TERMS)?;
        Ok((position, terms))
    }

    /// The platform's state from the motors' angles, rates and accelerations:
    /// `C` by [`Delta::forward_kinematics`], `v_C = J q̇`, `a_C = J (q̈ − b)` with `b` the motors'
    /// accelerations at the velocity and no platform acceleration. Unlike the hexapods', the
    /// arms' hold (one ratio, not calibrated against a high-precision reference) bounds only
    /// the position, not the motion applied through `J`.
    ///
    /// # Errors
    /// As [`Delta::forward_kinematics`].
    pub fn joint_state(
        &self,
        q: &[f64; 3],
        qd: &[f64; 3],
        qdd: &[f64; 3],
    ) -> Result<Translation, Error> {
        let [position, velocity, acceleration] =
            crate::legged::joint_state(self, &[*q, *qd, *qdd], None)?;
        Ok(Translation {
            position,
            velocity,
            acceleration,
        })
    }

    /// The motors' torques from their angles, rates and accelerations: the inverse dynamics
    /// at the platform's state of [`Delta::joint_state`].
    ///
    /// # Errors
    /// As [`Delta::joint_state`].
    pub fn inverse_dynamics_joint(
        &self,
        q: &[f64; 3],
        qd: &[f64; 3],
        qdd: &[f64; 3],
    ) -> Result<[f64; 3], Error> {
        crate::legged::inverse_dynamics_joint(self, &[*q, *qd, *qdd], None)
    }

    /// Everything `c5 eval` writes for one state.
    ///
    /// # Errors
    /// As [`Delta::inverse_dynamics`].
    pub fn evaluate(&self, state: &Translation) -> Result<DeltaEvaluation, Error> {
        crate::legged::evaluate(self, &checked_motion(state)?)
    }
}

/// The Delta's kernels for what every legged mechanism shares: its platform's motion from the
/// motors' and its evaluation. Its hold is one ratio, not pivots, and bounds no motion.
impl crate::legged::Legged<3> for Delta {
    fn located(
        &self,
        q: &[f64; 3],
        _near: Option<&[f64; 3]>,
    ) -> Result<([f64; 3], crate::legged::Hold), Error> {
        let (position, terms) = Delta::located(self, q)?;
        let hold = crate::singularity::weakest(
            &terms,
            &kernels::SINGULARITY_TERMS,
            crate::singularity::TermKind::Pivot,
        );
        Ok((position, hold))
    }
    fn actuators(&self, x: &[f64; 3]) -> Result<[f64; 3], Error> {
        self.inverse_kinematics(x)
    }
    fn rates(&self, x: &[f64; 3], v: &[f64; 3]) -> Result<[f64; 3], Error> {
        self.joint_velocities(x, v)
    }
    fn accelerations(&self, motion: &crate::legged::Motion<3>) -> Result<[f64; 3], Error> {
        self.joint_accelerations(&translation_of(motion))
    }
    fn forces(&self, motion: &crate::legged::Motion<3>) -> Result<[f64; 3], Error> {
        self.inverse_dynamics(&translation_of(motion))
    }
    fn inverse(&self, x: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        self.inverse_jacobian(x)
    }
    fn jacobian_at(&self, x: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        self.jacobian(x)
    }
    fn accelerated(&self, x: &[f64; 3], v: &[f64; 3], gamma: &[f64; 3]) -> Result<[f64; 3], Error> {
        self.forward_dynamics(x, v, gamma)
    }
}

/// The state of a position, velocity and acceleration.
fn translation_of([position, velocity, acceleration]: &crate::legged::Motion<3>) -> Translation {
    Translation {
        position: *position,
        velocity: *velocity,
        acceleration: *acceleration,
    }
}

/// The Delta through the interface of every mechanism: its platform translates, so every slice
/// holds three numbers.
impl Mechanism for Delta {
    fn mechanism(&self) -> &'static str {
        crate::delta::MECHANISM
    }
    fn model_name(&self) -> &'static str {
        crate::delta::MECHANISM
    }
    fn freedom(&self) -> Freedom {
        Freedom::Translations
    }
    fn description(&self) -> c5_robot::Description {
        c5_robot::Description::Delta(*self.robot())
    }
    fn parameters(&self) -> &[f64] {
        Delta::parameters(self)
    }
    fn home(&self) -> Vec<f64> {
        Delta::home(self).to_vec()
    }
    fn spatial(&self) -> Option<&dyn ParallelRobot> {
        None
    }
    fn clone_mechanism(&self) -> alloc::boxed::Box<dyn Mechanism> {
        alloc::boxed::Box::new(self.clone())
    }
    fn singularity_clearance(&self, pose: &[f64]) -> Result<f64, Error> {
        let terms = self.singularity_terms(&array("pose", pose)?)?;
        Ok(terms.into_iter().fold(f64::INFINITY, f64::min))
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(
        &self,
        friction: &[crate::identify::Friction],
    ) -> Result<Vec<f64>, Error> {
        let friction = crate::platform::exactly("friction", friction)?;
        Ok(Delta::standard_parameters(self, &friction))
    }
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<crate::identify::BaseParameters, Error> {
        Delta::base_parameters(self)
    }
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, motion: [&[f64]; 3]) -> Result<nalgebra::DMatrix<f64>, Error> {
        let motion = crate::legged::motion_of(motion, crate::legged::MOTION)?;
        let y = Delta::regressor(self, &translation_of(&motion))?;
        Ok(nalgebra::DMatrix::from_fn(3, y[0].len(), |i, j| y[i][j]))
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, motion: [&[f64]; 3], out: &mut [f64]) -> Result<(), Error> {
        let motion = crate::legged::motion_of(motion, crate::legged::MOTION)?;
        Delta::base_regressor_into(self, &translation_of(&motion), out)
    }
    fn scene(&self, pose: &[f64]) -> Result<crate::scene::Scene, Error> {
        Delta::scene(self, &array("pose", pose)?)
    }
    crate::legged::slice_calls!(3);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> Delta {
        Delta::new(Description::example()).unwrap()
    }

    #[test]
    fn home_is_served_and_its_angles_give_it_back() {
        let robot = example();
        let home = robot.home();
        let q = robot.inverse_kinematics(&home).unwrap();
        let back = robot.forward_kinematics(&q).unwrap();
        for k in 0..3 {
            assert!((back[k] - home[k]).abs() < 1e-12, "{back:?} {home:?}");
        }
    }

    #[test]
    fn a_platform_out_of_reach_is_refused_by_name() {
        let robot = example();
        let mut far = robot.home();
        far[2] -= 2.0;
        match robot.inverse_kinematics(&far) {
            Err(Error::Singularity { term, .. }) => assert!(term.contains("beyond the reach")),
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            robot.inverse_kinematics(&[f64::NAN, 0.0, 0.0]),
            Err(Error::NonFinite { .. })
        ));
    }
}
