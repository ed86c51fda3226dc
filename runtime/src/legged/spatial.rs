//! What a legged mechanism whose platform is free in space adds (the Gough-Stewart platform,
//! the rotary hexapod): the inverse kinematics with the vectors `B_i C`, and the forward
//! kinematics, a generated Newton step iterated from a previous solution or from the
//! mechanism's start. (The task-space terms and the joint-space inertia are every legged
//! mechanism's: `legged::robot`.)
//!
//! Its conventions are the C5's: pose `[α β γ xc yc zc]` with `R = Rx(α) Ry(β) Rz(γ)`, twist
//! `(ω; v_C)` and classical acceleration `(ω̇; a_C)` at the platform origin `C`, base frame.

use super::robot::{hold_of, KernelsOf, TermsOf};
use super::{
    Coordinates, Hold, LeggedDescription, LeggedRobot, Linearised, NEWTON_PIVOT_TOLERANCE,
};
use crate::error::Error;
use crate::mechanism::SpatialRobot;
use crate::{finite, finite_matrix, Pose};
use alloc::boxed::Box;
use c5_generated::legged::{Legs, Spatial};

impl<D: LeggedDescription<6>> LeggedRobot<D, 6>
where
    D::Kernels: Spatial,
{
    /// The actuator positions `q` and the vectors from each leg's platform joint `B_i` to `C`
    /// (m, base frame).
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_kinematics(&self, pose: &Pose) -> Result<([f64; 6], [[f64; 3]; 6]), Error> {
        let x = pose.checked("pose")?;
        let (q, p, guard) = KernelsOf::<D, 6>::inverse_kinematics(&x, &self.params);
        let (q, p) = self.checked(((q, p), guard))?;
        Ok((finite("q", q)?, finite_matrix("p", p)?))
    }

    /// The pose whose actuator positions are `q`, by Newton's method from `near` (a previous
    /// solution: two or three steps at a controller's rate) or, without it, from the
    /// mechanism's start; to [`super::FORWARD_TOLERANCE`] (1e-12, m or rad) on every actuator.
    /// The pose found is refused where it is singular, as every kernel refuses it.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::NotConverged`] when the steps stop reducing the residual
    /// (positions no pose near the start has); [`Error::Singularity`] when a step meets a
    /// singular pose, or the pose found is one.
    pub fn forward_kinematics(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<Pose, Error> {
        let near = near.map(|p| p.checked("near")).transpose()?;
        let (x, _) = self.located_with_terms(q, near.as_ref())?;
        Ok(Pose::from_array(x))
    }

    /// The forward kinematics, with the singularity terms at the pose found (all within their
    /// tolerances), for the callers that hold it to a nearer bound.
    fn located_with_terms(
        &self,
        q: &[f64; 6],
        near: Option<&[f64; 6]>,
    ) -> Result<([f64; 6], TermsOf<D, 6>), Error> {
        crate::check_finite("q", q)?;
        let start = match near {
            Some(x) => *x,
            None => self.robot().start(q, self.home_array()),
        };
        let x = super::newton(
            |x, out| {
                let (r, step, conditioning, guard) =
                    KernelsOf::<D, 6>::forward_kinematics_step(x, q, &self.params);
                let (r, step, [pivots @ .., trace]) =
                    self.checked(((r, step, conditioning), guard))?;
                let solvable = pivots.iter().all(|&d| d > NEWTON_PIVOT_TOLERANCE * trace)
                    && step.iter().all(|v| v.is_finite());
                *out = Linearised {
                    residual: finite("residual", r)?,
                    step: solvable.then_some(step),
                };
                Ok(())
            },
            |x| {
                let at = self.actuators_at(x)?;
                Ok(core::array::from_fn(|i| q[i] - at[i]))
            },
            start,
        )?;
        let terms = KernelsOf::<D, 6>::singularity_terms(&x, &self.params);
        crate::singularity::check(terms.as_ref(), KernelsOf::<D, 6>::SINGULARITY_TERMS)?;
        Ok((x, terms))
    }
}

/// The forward kinematics by Newton's method, the hold its weakest pivot.
impl<D: LeggedDescription<6>> super::Locate<6> for LeggedRobot<D, 6>
where
    D::Kernels: Spatial,
{
    fn located(&self, q: &[f64; 6], near: Option<&[f64; 6]>) -> Result<([f64; 6], Hold), Error> {
        let (x, terms) = self.located_with_terms(q, near)?;
        Ok((x, hold_of::<D, 6>(&terms)))
    }
}

/// What a platform free in space adds to every legged mechanism's [`crate::ParallelRobot`].
impl<D: LeggedDescription<6>> SpatialRobot for LeggedRobot<D, 6>
where
    D::Kernels: Spatial,
{
    fn clone_spatial(&self) -> Box<dyn SpatialRobot> {
        Box::new(self.clone())
    }
}
