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
use crate::platform::{array, put, room, Freedom, Mechanism};
use crate::{check_finite, finite, finite_matrix};
use alloc::vec::Vec;
use c5_generated::f64::delta as kernels;
pub use c5_robot::Delta as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::DELTA;

/// The length of the parameter vector of the Delta's `*_params` kernels.
pub const PARAMETERS: usize = c5_robot::delta::PARAMETERS;

pub use crate::singularity::{FORWARD_KINEMATICS_TOLERANCE, HOLD_RATIO_TOLERANCE};

/// Refuses the singularity terms below their tolerance (or NaN), as the kernels' terms say
/// what each measures.
fn check_terms(terms: &[f64]) -> Result<(), Error> {
    crate::singularity::check(terms, &kernels::SINGULARITY_TERMS)
}

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

    /// The singularity terms at `position`, unchecked: each arm's U joints' sine, each arm's
    /// reach `1 - (K/ρ)²`, and the arms' hold `det(J⁻¹)² / Π |row_i|²`; for monitoring how
    /// near a singularity the platform is.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite input.
    pub fn singularity_terms(&self, position: &[f64; 3]) -> Result<[f64; 7], Error> {
        check_finite("position", position)?;
        Ok(kernels::singularity_terms_params(position, &self.params))
    }

    /// The motors' angles at `position`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::Singularity`] naming the term.
    pub fn inverse_kinematics(&self, position: &[f64; 3]) -> Result<[f64; 3], Error> {
        check_finite("position", position)?;
        let (q, terms) = kernels::inverse_kinematics_params(position, &self.params);
        check_terms(&terms)?;
        finite("q", q)
    }

    /// `J⁻¹` at `position`: `q̇ = J⁻¹ v_C`.
    ///
    /// # Errors
    /// As [`Delta::inverse_kinematics`].
    pub fn inverse_jacobian(&self, position: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        check_finite("position", position)?;
        let (jinv, terms) = kernels::inverse_jacobian_pose_params(position, &self.params);
        check_terms(&terms)?;
        finite_matrix("jinv", jinv)
    }

    /// `J = (J⁻¹)⁻¹` at `position`: `v_C = J q̇`.
    ///
    /// # Errors
    /// As [`Delta::inverse_kinematics`], and the arms' hold.
    pub fn jacobian(&self, position: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        check_finite("position", position)?;
        let (jac, terms) = kernels::jacobian_pose_params(position, &self.params);
        check_terms(&terms)?;
        finite_matrix("jacobian", jac)
    }

    /// The motors' rates `J⁻¹ v_C`.
    ///
    /// # Errors
    /// As [`Delta::inverse_kinematics`].
    pub fn joint_velocities(
        &self,
        position: &[f64; 3],
        velocity: &[f64; 3],
    ) -> Result<[f64; 3], Error> {
        check_finite("position", position)?;
        check_finite("velocity", velocity)?;
        let (qd, terms) = kernels::joint_velocities_params(position, velocity, &self.params);
        check_terms(&terms)?;
        finite("qd", qd)
    }

    /// The motors' accelerations.
    ///
    /// # Errors
    /// As [`Delta::inverse_kinematics`].
    pub fn joint_accelerations(&self, state: &Translation) -> Result<[f64; 3], Error> {
        self.check_state(state)?;
        let (qdd, terms) = kernels::joint_accelerations_params(
            &state.position,
            &state.velocity,
            &state.acceleration,
            &self.params,
        );
        check_terms(&terms)?;
        finite("qdd", qdd)
    }

    /// The motors' torques that give the platform `state`'s motion.
    ///
    /// # Errors
    /// As [`Delta::jacobian`].
    pub fn inverse_dynamics(&self, state: &Translation) -> Result<[f64; 3], Error> {
        self.check_state(state)?;
        let (gamma, terms) = kernels::inverse_dynamics_params(
            &state.position,
            &state.velocity,
            &state.acceleration,
            &self.params,
        );
        check_terms(&terms)?;
        finite("gamma", gamma)
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
        check_terms(&terms)?;
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
        check_terms(&terms)?;
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

    fn check_state(&self, state: &Translation) -> Result<(), Error> {
        checked_motion(state).map(drop)
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
    fn accelerations(&self, [x, v, a]: &crate::legged::Motion<3>) -> Result<[f64; 3], Error> {
        self.joint_accelerations(&translation_of(x, v, a))
    }
    fn forces(&self, [x, v, a]: &crate::legged::Motion<3>) -> Result<[f64; 3], Error> {
        self.inverse_dynamics(&translation_of(x, v, a))
    }
    fn inverse(&self, x: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        self.inverse_jacobian(x)
    }
    fn jacobian_at(&self, x: &[f64; 3]) -> Result<[[f64; 3]; 3], Error> {
        self.jacobian(x)
    }
}

/// The state of a position, velocity and acceleration.
fn translation_of(x: &[f64; 3], v: &[f64; 3], a: &[f64; 3]) -> Translation {
    Translation {
        position: *x,
        velocity: *v,
        acceleration: *a,
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
        let [x, v, a] = motion;
        let y = Delta::regressor(self, &translation(x, v, a)?)?;
        Ok(nalgebra::DMatrix::from_fn(3, y[0].len(), |i, j| y[i][j]))
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, motion: [&[f64]; 3], out: &mut [f64]) -> Result<(), Error> {
        let [x, v, a] = motion;
        Delta::base_regressor_into(self, &translation(x, v, a)?, out)
    }
    fn scene(&self, pose: &[f64]) -> Result<crate::scene::Scene, Error> {
        Delta::scene(self, &array("pose", pose)?)
    }
    fn actuator_positions(&self, pose: &[f64], q: &mut [f64]) -> Result<(), Error> {
        room::<3>("q", q)?;
        put(q, &self.inverse_kinematics(&array("pose", pose)?)?);
        Ok(())
    }
    fn inverse_jacobian(&self, pose: &[f64], jinv: &mut [f64]) -> Result<(), Error> {
        room::<9>("jinv", jinv)?;
        let m = Delta::inverse_jacobian(self, &array("pose", pose)?)?;
        put(jinv, m.as_flattened());
        Ok(())
    }
    fn jacobian(&self, pose: &[f64], jac: &mut [f64]) -> Result<(), Error> {
        room::<9>("jacobian", jac)?;
        put(
            jac,
            Delta::jacobian(self, &array("pose", pose)?)?.as_flattened(),
        );
        Ok(())
    }
    fn joint_velocities(&self, pose: &[f64], twist: &[f64], qd: &mut [f64]) -> Result<(), Error> {
        room::<3>("qd", qd)?;
        let rates = Delta::joint_velocities(self, &array("pose", pose)?, &array("twist", twist)?)?;
        put(qd, &rates);
        Ok(())
    }
    fn joint_accelerations(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        qdd: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("qdd", qdd)?;
        let state = translation(pose, twist, acceleration)?;
        put(qdd, &Delta::joint_accelerations(self, &state)?);
        Ok(())
    }
    fn inverse_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        gamma: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("gamma", gamma)?;
        let state = translation(pose, twist, acceleration)?;
        put(gamma, &Delta::inverse_dynamics(self, &state)?);
        Ok(())
    }
    fn forward_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        gamma: &[f64],
        acceleration: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("acceleration", acceleration)?;
        let (x, v, g) = (
            array("pose", pose)?,
            array("twist", twist)?,
            array("gamma", gamma)?,
        );
        put(acceleration, &Delta::forward_dynamics(self, &x, &v, &g)?);
        Ok(())
    }
    /// In closed form: `near` is not needed, and only its length is checked.
    fn forward_kinematics(
        &self,
        q: &[f64],
        near: Option<&[f64]>,
        pose: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("pose", pose)?;
        near.map(|x| array::<3>("near", x)).transpose()?;
        put(pose, &Delta::forward_kinematics(self, &array("q", q)?)?);
        Ok(())
    }
    fn joint_state(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        out: [&mut [f64]; 3],
    ) -> Result<(), Error> {
        let [pose, twist, acceleration] = out;
        room::<3>("pose", pose)?;
        room::<3>("twist", twist)?;
        room::<3>("acceleration", acceleration)?;
        near.map(|x| array::<3>("near", x)).transpose()?;
        let [q, qd, qdd] = joints;
        let (q, qd, qdd) = (array("q", q)?, array("qd", qd)?, array("qdd", qdd)?);
        let state = Delta::joint_state(self, &q, &qd, &qdd)?;
        put(pose, &state.position);
        put(twist, &state.velocity);
        put(acceleration, &state.acceleration);
        Ok(())
    }
}

/// A Delta's state from its three slices.
fn translation(
    pose: &[f64],
    twist: &[f64],
    acceleration: &[f64],
) -> Result<crate::delta::Translation, Error> {
    Ok(crate::delta::Translation {
        position: array("pose", pose)?,
        velocity: array("twist", twist)?,
        acceleration: array("acceleration", acceleration)?,
    })
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
