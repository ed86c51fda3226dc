//! What a legged mechanism whose platform only translates adds (the Delta): the forward
//! kinematics in closed form, of the two points where the arms' spheres meet the one on the
//! home position's side. Its [`crate::ParallelRobot<3>`] is every legged mechanism's.
//!
//! Its state is the position `C`, velocity `v_C` and acceleration `a_C` of the platform (base
//! frame, m, m/s, m/s²; [`crate::Translation`]).

use super::robot::{hold_of, KernelsOf, TermsOf};
use super::{Hold, LeggedDescription, LeggedRobot};
use crate::error::Error;
use crate::{check_finite, finite};
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

/// The closed-form forward kinematics (no start needed: `near` is not read), the hold the
/// arms' determinant ratio, which bounds the platform's motion from the actuators'
/// ([`super::JOINT_STATE_HOLD_RATIO_TOLERANCE`]).
impl<D: LeggedDescription<3>> super::Locate<3> for LeggedRobot<D, 3>
where
    D::Kernels: ClosedForm<3>,
{
    fn located(&self, q: &[f64; 3], _near: Option<&[f64; 3]>) -> Result<([f64; 3], Hold), Error> {
        let (position, terms) = self.located_with_terms(q)?;
        Ok((position, hold_of::<D, 3>(&terms)))
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
