//! The legged mechanisms (the Gough-Stewart platform, the rotary hexapod, the Delta), served
//! by one type, [`LeggedRobot`], over each mechanism's generated kernel set: its checked
//! kernel calls ([`robot`], the task-space terms among them), what a platform free in space
//! adds (the forward kinematics' Newton iteration: [`spatial`]), what a translating one does (the
//! closed-form forward kinematics: [`translating`]), and each mechanism's catalogue entry
//! ([`catalogue`]). Written once here: the platform's motion from the actuators'
//! (`V = J q̇`, `(ω̇; a_C) = J (q̈ - b)`), the joint-space forces and inertia, and `eval`'s
//! evaluation.

pub mod catalogue;
#[cfg(feature = "derivatives")]
mod derivatives;
pub mod robot;
mod served;
pub mod spatial;
pub mod translating;

pub use robot::{
    AccelerationOf, Freedoms, LeggedDescription, LeggedRobot, ParametersOf, Platform, PoseOf,
    StateOf, TermsOf, TwistOf,
};

use crate::error::Error;
use crate::singularity::SingularityTerm;
use crate::{dense, finite, finite_matrix, Evaluation, Pose, State, Twist};

/// The forward kinematics' tolerance: the largest residual of an actuator position (m or rad).
pub const FORWARD_TOLERANCE: f64 = 1e-12;

/// The most Newton steps the forward kinematics takes.
pub const FORWARD_ITERATIONS: usize = 50;

/// Smallest pivot ratio `ρ` of the legs' hold (the `LDLᵀ` of the solve with `J⁻ᵀ`, each pivot
/// over its diagonal entry) at which the platform's twist and acceleration are served from the
/// actuators' rates and accelerations: `V = J q̇` and `(ω̇; a_C) = J (q̈ - b)` apply `J`, ill
/// conditioned near the parallel singularity. Against a 50-digit reference of the
/// Gough-Stewart platform the acceleration errs by up to about `1.7e-15/ρ^1.5` relative (6.4e-9
/// at `ρ = 1.8e-5`, 7e-11 at `4e-4`); below this bound, with nonzero rates or accelerations,
/// the call is refused ([`Error::IllConditioned`]). The pose alone, the joint-space forces and
/// the inertia stay accurate and are served down to the mechanism's hold tolerance.
pub const JOINT_STATE_HOLD_TOLERANCE: f64 = 1e-3;

/// Smallest hold of three arms on a platform that translates, `det(J⁻¹)² / Π |row_i|²` (the
/// Delta's), at which the platform's velocity and acceleration are served from the actuators'
/// rates and accelerations: [`JOINT_STATE_HOLD_TOLERANCE`] for that measure. Against a
/// 50-digit reference of the Delta (`python/tests/exact_delta.py`), the acceleration errs by up
/// to 1.7e-12 relative at holds of 1e-3 to 1e-2, 1.7e-11 at 1e-4, 6.3e-10 at 1e-5, 6.4e-8 at
/// 1e-6 and 5.9e-5 at 1e-8, the velocity by 3.5e-13 at 1e-4; below this bound, with nonzero
/// rates or accelerations, the call is refused ([`Error::IllConditioned`]). The position, `J`
/// and the joint-space forces are served down to the arms' hold tolerance
/// ([`crate::singularity::HOLD_RATIO_TOLERANCE`]).
pub const JOINT_STATE_HOLD_RATIO_TOLERANCE: f64 = 1e-4;

/// The bound of [`joint_state`] on a hold term of `kind`: a pivot ratio of the legs' solve, or
/// the arms' determinant ratio.
pub(crate) const fn joint_state_bound(kind: crate::singularity::TermKind) -> f64 {
    match kind {
        crate::singularity::TermKind::Hold => JOINT_STATE_HOLD_RATIO_TOLERANCE,
        _ => JOINT_STATE_HOLD_TOLERANCE,
    }
}

/// A platform's motion in its `N` coordinates: pose, twist and acceleration.
pub type Motion<const N: usize> = [[f64; N]; 3];

/// A platform's coordinates (a pose, a twist, a state), as the kernels take them, checked
/// finite: what lets one set of checked kernel calls serve every platform.
pub trait Coordinates {
    type Array;
    /// The coordinates, refused by `name` where one is not finite.
    fn checked(&self, name: &'static str) -> Result<Self::Array, Error>;
}

impl<const N: usize> Coordinates for [f64; N] {
    type Array = [f64; N];
    #[inline]
    fn checked(&self, name: &'static str) -> Result<[f64; N], Error> {
        crate::check_finite(name, self)?;
        Ok(*self)
    }
}

impl Coordinates for Pose {
    type Array = [f64; 6];
    #[inline]
    fn checked(&self, name: &'static str) -> Result<[f64; 6], Error> {
        self.to_array().checked(name)
    }
}

impl Coordinates for Twist {
    type Array = [f64; 6];
    #[inline]
    fn checked(&self, name: &'static str) -> Result<[f64; 6], Error> {
        self.to_array().checked(name)
    }
}

/// A state's pose, twist and acceleration, each checked finite by its own name.
impl Coordinates for State {
    type Array = Motion<6>;
    #[inline]
    fn checked(&self, _name: &'static str) -> Result<Motion<6>, Error> {
        crate::C5::checked_motion(self)
    }
}

/// A translation's position, velocity and acceleration, each checked finite by its own name.
impl Coordinates for crate::Translation {
    type Array = Motion<3>;
    #[inline]
    fn checked(&self, _name: &'static str) -> Result<Motion<3>, Error> {
        crate::check_finite("position", &self.position)?;
        crate::check_finite("velocity", &self.velocity)?;
        crate::check_finite("acceleration", &self.acceleration)?;
        Ok([self.position, self.velocity, self.acceleration])
    }
}

/// The weakest of the legs' hold terms at a pose (their pivot ratios, or the arms' determinant
/// ratio), and what it is; `None` where the mechanism has no hold term.
pub type Hold = Option<(f64, &'static SingularityTerm)>;

/// Where a legged mechanism's platform is, from its actuators' positions: its forward
/// kinematics, iterated (a platform free in space) or in closed form (one that translates).
pub trait Locate<const N: usize> {
    /// The pose of the actuator positions `q` (found from `near` where the mechanism iterates,
    /// else from its start) and the legs' hold there, the pose refused where singular.
    fn located(&self, q: &[f64; N], near: Option<&[f64; N]>) -> Result<([f64; N], Hold), Error>;
}

/// A mechanism whose platform rides on legs, in its platform's `N` coordinates, through its
/// kernels: what the shared functions below are written over.
pub(crate) trait Legged<const N: usize>: Locate<N> {
    fn actuators(&self, x: &[f64; N]) -> Result<[f64; N], Error>;
    fn rates(&self, x: &[f64; N], v: &[f64; N]) -> Result<[f64; N], Error>;
    fn accelerations(&self, motion: &Motion<N>) -> Result<[f64; N], Error>;
    fn forces(&self, motion: &Motion<N>) -> Result<[f64; N], Error>;
    fn inverse(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
    fn jacobian_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
    fn inertia_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
}

/// What a step of the forward kinematics gives at a pose of `N` coordinates: the actuators'
/// residual, and the step of the pose that cancels it to first order (`None` where the pose's
/// Jacobian is singular to the solve's precision, [`NEWTON_PIVOT_TOLERANCE`]).
#[derive(Clone, Copy)]
pub(crate) struct Linearised<const N: usize> {
    pub residual: [f64; N],
    pub step: Option<[f64; N]>,
}

impl<const N: usize> Default for Linearised<N> {
    fn default() -> Self {
        Linearised {
            residual: [0.0; N],
            step: None,
        }
    }
}

/// The smallest pivot of a Newton step's solve (the `LDLᵀ` of `(∂q/∂X)ᵀ (∂q/∂X)`), relative
/// to that matrix's trace, at which the step is taken.
pub(crate) const NEWTON_PIVOT_TOLERANCE: f64 = 1e-13;

/// Newton's method from `x` on the residual and step `step` writes at a pose (a generated
/// forward-kinematics step, which solves its own linear system), each step halved until it
/// reduces the largest residual, to [`FORWARD_TOLERANCE`] within [`FORWARD_ITERATIONS`]
/// steps. Where the residual's fall so far (Newton's: the next about `c r²`, `c` measured from
/// the last two) predicts that the next step lands within a tenth of the tolerance, its
/// landing point is checked by `residual` alone (the inverse kinematics, a third of a step's
/// cost), and a whole step follows only if it misses. The step writes into one of two
/// buffers, the current pose's or the trial's, so the loop moves none of their numbers.
///
/// # Errors
/// The step's errors; [`Error::NotConverged`] when the steps stop reducing the residual;
/// [`Error::Singularity`] when the Jacobian is singular.
pub(crate) fn newton<const N: usize>(
    step: impl Fn(&[f64; N], &mut Linearised<N>) -> Result<(), Error>,
    residual: impl Fn(&[f64; N]) -> Result<[f64; N], Error>,
    mut x: [f64; N],
) -> Result<[f64; N], Error> {
    let mut buffers = [Linearised::default(); 2];
    let (mut current, mut previous) = (0, f64::INFINITY);
    step(&x, &mut buffers[current])?;
    for _ in 0..FORWARD_ITERATIONS {
        let at = &buffers[current];
        let size = dense::max_abs(&at.residual);
        if size <= FORWARD_TOLERANCE {
            return Ok(x);
        }
        let delta = at.step.ok_or(Error::Singularity {
            term: "forward kinematics' Jacobian",
            value: 0.0,
            bound: NEWTON_PIVOT_TOLERANCE,
        })?;
        let predicted = size / (previous * previous) * size * size;
        if previous.is_finite() && predicted < 0.1 * FORWARD_TOLERANCE {
            let landing: [f64; N] = core::array::from_fn(|k| x[k] + delta[k]);
            if residual(&landing).is_ok_and(|r| dense::max_abs(&r) <= FORWARD_TOLERANCE) {
                return Ok(landing);
            }
        }
        previous = size;
        let mut scale = 1.0;
        loop {
            let trial: [f64; N] = core::array::from_fn(|k| x[k] + scale * delta[k]);
            let next = &mut buffers[1 - current];
            match step(&trial, next) {
                Ok(()) if dense::max_abs(&next.residual) < size => {
                    (x, current) = (trial, 1 - current);
                    break;
                }
                _ if scale > 1e-3 => scale *= 0.5,
                _ => {
                    return Err(Error::NotConverged {
                        what: "forward kinematics",
                        residual: size,
                    })
                }
            }
        }
    }
    Err(Error::NotConverged {
        what: "forward kinematics",
        residual: dense::max_abs(&buffers[current].residual),
    })
}

/// The platform's motion from the actuators' positions, rates and accelerations, refused with
/// nonzero rates or accelerations where the legs' hold is below its bound
/// ([`JOINT_STATE_HOLD_TOLERANCE`], [`JOINT_STATE_HOLD_RATIO_TOLERANCE`]).
pub(crate) fn joint_state<const N: usize, R: Legged<N>>(
    robot: &R,
    joints: &Motion<N>,
    near: Option<&[f64; N]>,
) -> Result<Motion<N>, Error> {
    let (motion, hold) = platform_motion(robot, joints, near)?;
    let [_, qd, qdd] = joints;
    // At rest the twist and acceleration are zero, exactly, wherever the pose is served.
    if let Some((value, term)) = hold {
        let bound = joint_state_bound(term.kind);
        if value < bound && qd.iter().chain(qdd).any(|&x| x != 0.0) {
            return Err(Error::IllConditioned {
                what: "platform motion from the actuators",
                term: term.name,
                value,
                bound,
            });
        }
    }
    Ok(motion)
}

/// [`joint_state`] without its bound on the motion (for the joint-space forces, which stay
/// accurate down to the hold tolerance), and the hold at its pose: the forward kinematics,
/// `V = J q̇`, and `(ω̇; a_C) = J (q̈ - b)` with `b` the actuators' accelerations at zero
/// platform acceleration.
fn platform_motion<const N: usize, R: Legged<N>>(
    robot: &R,
    [q, qd, qdd]: &Motion<N>,
    near: Option<&[f64; N]>,
) -> Result<(Motion<N>, Hold), Error> {
    crate::check_finite("qd", qd)?;
    crate::check_finite("qdd", qdd)?;
    let (x, hold) = robot.located(q, near)?;
    let jac = robot.jacobian_at(&x)?;
    let v = finite("twist", dense::mul_vec(&jac, qd))?;
    let bias = robot.accelerations(&[x, v, [0.0; N]])?;
    let relative: [f64; N] = core::array::from_fn(|i| qdd[i] - bias[i]);
    let a = finite("acceleration", dense::mul_vec(&jac, &relative))?;
    Ok(([x, v, a], hold))
}

/// The actuator forces from the actuators' motion: the inverse dynamics at the platform state
/// of [`joint_state`], served down to the hold tolerance.
pub(crate) fn inverse_dynamics_joint<const N: usize, R: Legged<N>>(
    robot: &R,
    joints: &Motion<N>,
    near: Option<&[f64; N]>,
) -> Result<[f64; N], Error> {
    robot.forces(&platform_motion(robot, joints, near)?.0)
}

/// `M_q = Jᵀ M_x J` at the pose of the actuator positions `q`.
pub(crate) fn joint_inertia<const N: usize, R: Legged<N>>(
    robot: &R,
    q: &[f64; N],
    near: Option<&[f64; N]>,
) -> Result<[[f64; N]; N], Error> {
    let (x, _) = robot.located(q, near)?;
    let (jac, m) = (robot.jacobian_at(&x)?, robot.inertia_at(&x)?);
    finite_matrix(
        "joint inertia",
        dense::mul(&dense::transpose(&jac), &dense::mul(&m, &jac)),
    )
}

/// Everything `eval` reports for one state.
pub(crate) fn evaluate<const N: usize, R: Legged<N>>(
    robot: &R,
    motion: &Motion<N>,
) -> Result<Evaluation<N>, Error> {
    let [x, v, _] = motion;
    Ok(Evaluation {
        q: robot.actuators(x)?,
        qd: robot.rates(x, v)?,
        qdd: robot.accelerations(motion)?,
        gamma: robot.forces(motion)?,
        jinv: robot.inverse(x)?,
        jacobian: robot.jacobian_at(x)?,
    })
}

/// The platform's motion: its pose, twist and acceleration.
pub(crate) const MOTION: [&str; 3] = ["pose", "twist", "acceleration"];

/// Three slices of `N` numbers as arrays, refused by their `names` where one has another
/// length.
pub(crate) fn motion_of<const N: usize>(
    slices: [&[f64]; 3],
    names: [&'static str; 3],
) -> Result<Motion<N>, Error> {
    let [x, v, a] = slices;
    Ok([
        crate::platform::array(names[0], x)?,
        crate::platform::array(names[1], v)?,
        crate::platform::array(names[2], a)?,
    ])
}
