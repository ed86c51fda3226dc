//! What a legged mechanism whose platform only translates adds (the Delta): the forward
//! kinematics in closed form, of the two points where the arms' spheres meet the one on the
//! home position's side; and [`Mechanism`], whose every slice holds three numbers.
//!
//! Its state is the position `C`, velocity `v_C` and acceleration `a_C` of the platform (base
//! frame, m, m/s, m/s²; [`crate::Translation`]).

use super::robot::{hold_of, KernelsOf, TermsOf};
use super::{motion_of, Freedoms, Hold, LeggedDescription, LeggedRobot, Platform, MOTION};
use crate::error::Error;
use crate::mechanism::ParallelRobot;
use crate::platform::{array, put, room, Freedom, Mechanism};
use crate::{check_finite, finite};
use alloc::boxed::Box;
use alloc::vec::Vec;
use c5_generated::legged::{ClosedForm, Legs};

impl<D: LeggedDescription<3>> LeggedRobot<D, 3>
where
    D::Kernels: ClosedForm<3>,
{
    /// The actuators' positions at `position`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::Singularity`] naming the term.
    pub fn inverse_kinematics(&self, position: &[f64; 3]) -> Result<[f64; 3], Error> {
        check_finite("position", position)?;
        self.actuators_at(position)
    }

    /// The position whose actuator positions are `q`: of the two points where the arms'
    /// spheres meet, the one on the home position's side of the spheres' centres (the plane
    /// halfway between the two points). Refused where the spheres miss or touch, or at the
    /// point's singularities, as every kernel refuses it.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::Singularity`] naming the term.
    pub fn forward_kinematics(&self, q: &[f64; 3]) -> Result<[f64; 3], Error> {
        self.located_with_terms(q).map(|(position, _)| position)
    }

    /// [`LeggedRobot::forward_kinematics`] and the singularity terms at the position found.
    fn located_with_terms(&self, q: &[f64; 3]) -> Result<([f64; 3], TermsOf<D, 3>), Error> {
        check_finite("q", q)?;
        let (points, guard) = KernelsOf::<D, 3>::forward_kinematics(q, &self.params);
        crate::singularity::check(guard.as_ref(), KernelsOf::<D, 3>::FORWARD_KINEMATICS_TERMS)?;
        let [plus, minus] = points;
        let home = self.home_array();
        let side: f64 = (0..3)
            .map(|k| (plus[k] - minus[k]) * (home[k] - 0.5 * (plus[k] + minus[k])))
            .sum();
        let position = finite("position", if side >= 0.0 { plus } else { minus })?;
        let terms = KernelsOf::<D, 3>::singularity_terms(&position, &self.params);
        crate::singularity::check(terms.as_ref(), KernelsOf::<D, 3>::SINGULARITY_TERMS)?;
        Ok((position, terms))
    }
}

/// The closed-form forward kinematics (no start needed: `near` is not read), the hold its
/// weakest pivot where the mechanism's terms have pivots. The Delta's hold is one ratio, not
/// calibrated against a high-precision reference: it bounds the position, not the motion
/// applied through `J`.
impl<D: LeggedDescription<3>> super::Locate<3> for LeggedRobot<D, 3>
where
    D::Kernels: ClosedForm<3>,
{
    fn located(&self, q: &[f64; 3], _near: Option<&[f64; 3]>) -> Result<([f64; 3], Hold), Error> {
        let (position, terms) = self.located_with_terms(q)?;
        Ok((position, hold_of::<D, 3>(&terms)))
    }
}

/// A translating legged mechanism through the interface of every mechanism: each per-state
/// call checks every slice's length before it computes (nothing written on an error), then
/// writes its result.
impl<D: LeggedDescription<3>> Mechanism for LeggedRobot<D, 3>
where
    D::Kernels: ClosedForm<3>,
{
    fn mechanism(&self) -> &'static str {
        D::Kernels::MECHANISM
    }
    fn model_name(&self) -> &'static str {
        D::Kernels::MECHANISM
    }
    fn freedom(&self) -> Freedom {
        Freedom::Translations
    }
    fn description(&self) -> c5_robot::Description {
        self.robot().description()
    }
    fn parameters(&self) -> &[f64] {
        self.params.as_ref()
    }
    fn home(&self) -> Vec<f64> {
        self.home_array().to_vec()
    }
    fn spatial(&self) -> Option<&dyn ParallelRobot> {
        None
    }
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel> {
        Some(crate::calibrate::residuals_of::<D::Kernels, 3>)
    }
    fn clone_mechanism(&self) -> Box<dyn Mechanism> {
        Box::new(self.clone())
    }
    fn singularity_clearance(&self, pose: &[f64]) -> Result<f64, Error> {
        let terms = self.singularity_terms(&array("pose", pose)?)?;
        Ok(terms.as_ref().iter().copied().fold(f64::INFINITY, f64::min))
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(
        &self,
        friction: &[crate::identify::Friction],
    ) -> Result<Vec<f64>, Error> {
        let friction = crate::platform::exactly("friction", friction)?;
        Ok(LeggedRobot::standard_parameters(self, &friction))
    }
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<crate::identify::BaseParameters, Error> {
        LeggedRobot::base_parameters(self)
    }
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, motion: [&[f64]; 3]) -> Result<nalgebra::DMatrix<f64>, Error> {
        let y = self.regressor(&Platform::<3>::state(motion_of(motion, MOTION)?))?;
        let width = y[0].as_ref().len();
        Ok(nalgebra::DMatrix::from_fn(3, width, |i, j| {
            y[i].as_ref()[j]
        }))
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, motion: [&[f64]; 3], out: &mut [f64]) -> Result<(), Error> {
        self.base_regressor_into(&Platform::<3>::state(motion_of(motion, MOTION)?), out)
    }
    fn scene(&self, pose: &[f64]) -> Result<crate::scene::Scene, Error> {
        D::scene(self, &array("pose", pose)?)
    }
    fn actuator_positions(&self, pose: &[f64], q: &mut [f64]) -> Result<(), Error> {
        room::<3>("q", q)?;
        put(q, &self.inverse_kinematics(&array("pose", pose)?)?);
        Ok(())
    }
    fn inverse_jacobian(&self, pose: &[f64], jinv: &mut [f64]) -> Result<(), Error> {
        room::<9>("jinv", jinv)?;
        put(
            jinv,
            self.inverse_jacobian(&array("pose", pose)?)?.as_flattened(),
        );
        Ok(())
    }
    fn jacobian(&self, pose: &[f64], jac: &mut [f64]) -> Result<(), Error> {
        room::<9>("jacobian", jac)?;
        put(
            jac,
            LeggedRobot::jacobian(self, &array("pose", pose)?)?.as_flattened(),
        );
        Ok(())
    }
    fn joint_velocities(&self, pose: &[f64], twist: &[f64], qd: &mut [f64]) -> Result<(), Error> {
        room::<3>("qd", qd)?;
        let (x, v) = (array("pose", pose)?, array("twist", twist)?);
        put(qd, &LeggedRobot::joint_velocities(self, &x, &v)?);
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
        let motion = motion_of([pose, twist, acceleration], MOTION)?;
        put(
            qdd,
            &LeggedRobot::joint_accelerations(self, &Platform::<3>::state(motion))?,
        );
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
        let motion = motion_of([pose, twist, acceleration], MOTION)?;
        put(
            gamma,
            &LeggedRobot::inverse_dynamics(self, &Platform::<3>::state(motion))?,
        );
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
        let [x, v, g] = motion_of([pose, twist, gamma], ["pose", "twist", "gamma"])?;
        put(
            acceleration,
            &LeggedRobot::forward_dynamics(self, &x, &v, &g)?,
        );
        Ok(())
    }
    fn forward_kinematics(
        &self,
        q: &[f64],
        near: Option<&[f64]>,
        pose: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("pose", pose)?;
        let near = near.map(|x| array::<3>("near", x)).transpose()?;
        let q = array("q", q)?;
        let (x, _) = super::Locate::located(self, &q, near.as_ref())?;
        put(pose, &x);
        Ok(())
    }
    fn inverse_dynamics_joint(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        gamma: &mut [f64],
    ) -> Result<(), Error> {
        room::<3>("gamma", gamma)?;
        let near = near.map(|x| array::<3>("near", x)).transpose()?;
        let joints = motion_of(joints, ["q", "qd", "qdd"])?;
        put(
            gamma,
            &super::inverse_dynamics_joint(self, &joints, near.as_ref())?,
        );
        Ok(())
    }
    fn joint_state(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        out: [&mut [f64]; 3],
    ) -> Result<(), Error> {
        for (name, slice) in MOTION.into_iter().zip(&out) {
            room::<3>(name, slice)?;
        }
        let near = near.map(|x| array::<3>("near", x)).transpose()?;
        let joints = motion_of(joints, ["q", "qd", "qdd"])?;
        let motion = super::joint_state(self, &joints, near.as_ref())?;
        for (slice, values) in out.into_iter().zip(&motion) {
            put(slice, values);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::{Delta, Error};
    use c5_robot::Delta as Description;

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
