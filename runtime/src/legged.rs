//! What the runtime's legged mechanisms (the Gough-Stewart platform, the rotary hexapod) share
//! beyond their kernels: the forward kinematics' Newton iteration, the platform's motion from
//! the actuators' (`V = J q̇`, `(ω̇; a_C) = J (q̈ - b)`), the joint-space forces and inertia,
//! and `eval`'s evaluation; written once over [`Legged`], which each mechanism implements with
//! its own kernels.

use crate::error::Error;
use crate::singularity::SingularityTerm;
use crate::{dense, finite, finite_matrix, Acceleration, Evaluation, Pose, State, Twist};

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

/// A platform's motion in its `N` coordinates: pose, twist and acceleration.
pub(crate) type Motion<const N: usize> = [[f64; N]; 3];

/// A platform's coordinates (a pose, a twist, a state), as the kernels take them, checked
/// finite: what lets one set of checked kernel calls serve every platform.
pub(crate) trait Coordinates {
    type Array;
    /// The coordinates, refused by `name` where one is not finite.
    fn checked(&self, name: &'static str) -> Result<Self::Array, Error>;
}

impl<const N: usize> Coordinates for [f64; N] {
    type Array = [f64; N];
    fn checked(&self, name: &'static str) -> Result<[f64; N], Error> {
        crate::check_finite(name, self)?;
        Ok(*self)
    }
}

impl Coordinates for Pose {
    type Array = [f64; 6];
    fn checked(&self, name: &'static str) -> Result<[f64; 6], Error> {
        self.to_array().checked(name)
    }
}

impl Coordinates for Twist {
    type Array = [f64; 6];
    fn checked(&self, name: &'static str) -> Result<[f64; 6], Error> {
        self.to_array().checked(name)
    }
}

/// A state's pose, twist and acceleration, each checked finite by its own name.
impl Coordinates for State {
    type Array = Motion<6>;
    fn checked(&self, _name: &'static str) -> Result<Motion<6>, Error> {
        crate::C5::checked_motion(self)
    }
}

/// The weakest of the legs' hold's pivot ratios at a pose, and what it is; `None` where the
/// mechanism's hold is not measured by pivots.
pub(crate) type Hold = Option<(f64, &'static SingularityTerm)>;

/// A mechanism whose platform rides on legs, in its platform's `N` coordinates, through its
/// kernels: what the shared functions below are written over.
pub(crate) trait Legged<const N: usize> {
    /// The pose of the actuator positions `q` (found from `near`, or the mechanism's start)
    /// and the legs' hold there, the pose refused where singular.
    fn located(&self, q: &[f64; N], near: Option<&[f64; N]>) -> Result<([f64; N], Hold), Error>;
    fn actuators(&self, x: &[f64; N]) -> Result<[f64; N], Error>;
    fn rates(&self, x: &[f64; N], v: &[f64; N]) -> Result<[f64; N], Error>;
    fn accelerations(&self, motion: &Motion<N>) -> Result<[f64; N], Error>;
    fn forces(&self, motion: &Motion<N>) -> Result<[f64; N], Error>;
    fn inverse(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
    fn jacobian_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
    /// The forward dynamics: the platform's acceleration under the actuator forces `gamma`.
    fn accelerated(&self, x: &[f64; N], v: &[f64; N], gamma: &[f64; N]) -> Result<[f64; N], Error>;
}

/// A legged mechanism with its task-space inertia `M_x` generated.
pub(crate) trait TaskInertia<const N: usize>: Legged<N> {
    fn inertia_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error>;
}

/// What a step of the forward kinematics gives at a pose: the actuators' residual and its
/// Jacobian.
#[derive(Clone, Copy, Default)]
pub(crate) struct Linearised {
    pub residual: [f64; 6],
    pub jacobian: [[f64; 6]; 6],
}

/// Newton's method from `x` on the residual and Jacobian `step` writes at a pose (a generated
/// forward-kinematics step), each step halved until it reduces the largest residual, to
/// [`FORWARD_TOLERANCE`] within [`FORWARD_ITERATIONS`] steps. The step writes into one of two
/// buffers, the current pose's or the trial's, so the loop moves none of its 42 numbers.
///
/// # Errors
/// The step's errors; [`Error::NotConverged`] when the steps stop reducing the residual;
/// [`Error::Singularity`] when the Jacobian is singular.
pub(crate) fn newton(
    step: impl Fn(&[f64; 6], &mut Linearised) -> Result<(), Error>,
    mut x: [f64; 6],
) -> Result<[f64; 6], Error> {
    let mut buffers = [Linearised::default(); 2];
    let mut current = 0;
    step(&x, &mut buffers[current])?;
    for _ in 0..FORWARD_ITERATIONS {
        let at = &buffers[current];
        let size = dense::max_abs(&at.residual);
        if size <= FORWARD_TOLERANCE {
            return Ok(x);
        }
        let delta =
            dense::solve_normal(&at.jacobian, &at.residual, 1e-13).ok_or(Error::Singularity {
                term: "forward kinematics' Jacobian",
                value: 0.0,
                bound: 1e-13,
            })?;
        let mut scale = 1.0;
        loop {
            let trial: [f64; 6] = core::array::from_fn(|k| x[k] + scale * delta[k]);
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
/// nonzero rates or accelerations where the legs' hold is below [`JOINT_STATE_HOLD_TOLERANCE`].
pub(crate) fn joint_state<const N: usize, R: Legged<N>>(
    robot: &R,
    joints: &Motion<N>,
    near: Option<&[f64; N]>,
) -> Result<Motion<N>, Error> {
    let (motion, hold) = platform_motion(robot, joints, near)?;
    let [_, qd, qdd] = joints;
    // At rest the twist and acceleration are zero, exactly, wherever the pose is served.
    if let Some((value, term)) = hold {
        if value < JOINT_STATE_HOLD_TOLERANCE && qd.iter().chain(qdd).any(|&x| x != 0.0) {
            return Err(Error::IllConditioned {
                what: "platform motion from the actuators",
                term: term.name,
                value,
                bound: JOINT_STATE_HOLD_TOLERANCE,
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
pub(crate) fn joint_inertia<const N: usize, R: TaskInertia<N>>(
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

/// The checked calls of a legged mechanism's kernels (`kernels::*_params`, the type's `params`),
/// in its impl block: each checks its inputs are finite, calls the kernel, refuses the pose
/// where the kernel's singularity terms say so (the module's `check_terms`), and its results
/// are finite. Quantities are in the mechanism's units (its module's documentation): the
/// actuators' positions in m or rad, their forces in N or N·m. `$terms` is the length of the
/// singularity terms.
macro_rules! kernel_calls {
    (terms: $terms:literal, coordinates: $n:literal, pose: $pose:ty, twist: $twist:ty, state: $state:ty) => {
        /// The singularity terms at `pose` (the kernel `singularity_terms`; what each is,
        /// `kernels::SINGULARITY_TERMS` says): the joints' terms, then the legs' hold (zero at
        /// a parallel singularity).
        ///
        /// # Errors
        /// A non-finite pose.
        pub fn singularity_terms(&self, pose: &$pose) -> Result<[f64; $terms], Error> {
            let x = $crate::legged::Coordinates::checked(pose, "pose")?;
            Ok(kernels::singularity_terms_params(&x, &self.params))
        }

        /// `J⁻¹` (`q̇ = J⁻¹ V`), row `i` for actuator `i+1`, columns the twist's.
        ///
        /// # Errors
        /// A non-finite or singular pose.
        pub fn inverse_jacobian(&self, pose: &$pose) -> Result<[[f64; $n]; $n], Error> {
            let x = $crate::legged::Coordinates::checked(pose, "pose")?;
            let (jinv, guard) = kernels::inverse_jacobian_pose_params(&x, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite_matrix("jinv", jinv)
        }

        /// `J = (J⁻¹)⁻¹`, rows the twist's, column `i` for actuator `i+1`.
        ///
        /// # Errors
        /// A non-finite or singular pose, or the legs' hold.
        pub fn jacobian(&self, pose: &$pose) -> Result<[[f64; $n]; $n], Error> {
            let x = $crate::legged::Coordinates::checked(pose, "pose")?;
            let (jac, guard) = kernels::jacobian_pose_params(&x, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite_matrix("jacobian", jac)
        }

        /// `q̇ = J⁻¹ V`.
        ///
        /// # Errors
        /// Non-finite inputs, or a singular pose.
        pub fn joint_velocities(&self, pose: &$pose, twist: &$twist) -> Result<[f64; $n], Error> {
            let x = $crate::legged::Coordinates::checked(pose, "pose")?;
            let v = $crate::legged::Coordinates::checked(twist, "twist")?;
            let (qd, guard) = kernels::joint_velocities_params(&x, &v, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite("qd", qd)
        }

        /// `q̈`, the actuator positions' second derivatives along the platform's motion.
        ///
        /// # Errors
        /// Non-finite inputs, or a singular pose.
        pub fn joint_accelerations(&self, state: &$state) -> Result<[f64; $n], Error> {
            let [x, v, a] = $crate::legged::Coordinates::checked(state, "state")?;
            let (qdd, guard) = kernels::joint_accelerations_params(&x, &v, &a, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite("qdd", qdd)
        }

        /// The actuator forces `Γ` for the platform to follow `state`: the platform's and the
        /// legs' bodies' Newton-Euler equations, by virtual work.
        ///
        /// # Errors
        /// Non-finite inputs, or a singular pose or hold.
        pub fn inverse_dynamics(&self, state: &$state) -> Result<[f64; $n], Error> {
            let [x, v, a] = $crate::legged::Coordinates::checked(state, "state")?;
            let (gamma, guard) = kernels::inverse_dynamics_params(&x, &v, &a, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite("gamma", gamma)
        }
    };
}
pub(crate) use kernel_calls;

/// The checked calls of a legged mechanism's kernels whose platform is free in space: those of
/// [`kernel_calls`], the inverse kinematics with the vectors `B_i C`, the task-space terms, the
/// forward kinematics (Newton's method from the type's `start`) and the forward dynamics.
macro_rules! spatial_kernel_calls {
    ($terms:literal) => {
        $crate::legged::kernel_calls!(
            terms: $terms,
            coordinates: 6,
            pose: Pose,
            twist: Twist,
            state: State
        );

        /// The actuator positions `q` and the vectors from each leg's platform joint `B_i` to
        /// `C` (m, base frame).
        ///
        /// # Errors
        /// A non-finite or singular pose.
        pub fn inverse_kinematics(&self, pose: &Pose) -> Result<([f64; 6], [[f64; 3]; 6]), Error> {
            let x = pose.to_array();
            check_finite("pose", &x)?;
            let (q, p, guard) = kernels::inverse_kinematics_params(&x, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            Ok((finite("q", q)?, finite_matrix("p", p)?))
        }

        /// `M_x` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`, symmetric positive definite.
        ///
        /// # Errors
        /// A non-finite or singular pose.
        pub fn task_inertia(&self, pose: &Pose) -> Result<[[f64; 6]; 6], Error> {
            let x = pose.to_array();
            check_finite("pose", &x)?;
            let (m, guard) = kernels::task_inertia_params(&x, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite_matrix("task inertia", m)
        }

        /// `h` of `Γ = Jᵀ (M_x (ω̇; a_C) + h)`: Coriolis, centrifugal and gravity terms at
        /// `C`.
        ///
        /// # Errors
        /// Non-finite inputs, or a singular pose.
        pub fn task_bias(&self, pose: &Pose, twist: &Twist) -> Result<[f64; 6], Error> {
            let (x, v) = (pose.to_array(), twist.to_array());
            check_finite("pose", &x)?;
            check_finite("twist", &v)?;
            let (h, guard) = kernels::task_bias_params(&x, &v, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            finite("task bias", h)
        }

        /// The pose whose actuator positions are `q`, by Newton's method from `near` (a
        /// previous solution: two or three steps at a controller's rate) or, without it, from
        /// the mechanism's start; to `FORWARD_TOLERANCE` (1e-12, m or rad) on every actuator. The pose found is refused where it is singular, as every kernel refuses
        /// it.
        ///
        /// # Errors
        /// [`Error::NonFinite`]; [`Error::NotConverged`] when the steps stop reducing the
        /// residual (positions no pose near the start has); [`Error::Singularity`] when a step
        /// meets a singular pose, or the pose found is one.
        pub fn forward_kinematics(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<Pose, Error> {
            self.located(q, near).map(|(pose, _)| pose)
        }

        /// The forward kinematics, with the singularity terms at the pose found (all within
        /// their tolerances), for the callers that hold it to a nearer bound.
        fn located(
            &self,
            q: &[f64; 6],
            near: Option<&Pose>,
        ) -> Result<(Pose, [f64; $terms]), Error> {
            check_finite("q", q)?;
            let start = match near {
                Some(p) => {
                    check_finite("near", &p.to_array())?;
                    p.to_array()
                }
                None => self.start(q),
            };
            let x = legged::newton(
                |x, out| {
                    let (r, jac, guard) =
                        kernels::forward_kinematics_step_params(x, q, &self.params);
                    crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
                    *out = legged::Linearised {
                        residual: finite("residual", r)?,
                        jacobian: jac,
                    };
                    Ok(())
                },
                start,
            )?;
            let terms = kernels::singularity_terms_params(&x, &self.params);
            crate::singularity::check(&terms, &kernels::SINGULARITY_TERMS)?;
            Ok((Pose::from_array(x), terms))
        }

        /// The forward dynamics: the platform's classical acceleration `(ω̇; a_C)` under the
        /// actuator forces `gamma`.
        ///
        /// # Errors
        /// Non-finite inputs, a singular pose, a U joint too near its singularity for the
        /// acceleration's bound ([`Error::IllConditioned`],
        /// [`crate::singularity::FORWARD_U_JOINT_TOLERANCE`]), or a non-finite result.
        pub fn forward_dynamics(
            &self,
            pose: &Pose,
            twist: &Twist,
            gamma: &[f64; 6],
        ) -> Result<Acceleration, Error> {
            let [x, v] = crate::C5::checked_forward(pose, twist, gamma)?;
            let (a, guard) = kernels::forward_dynamics_params(&x, &v, gamma, &self.params);
            crate::singularity::check(&guard, &kernels::SINGULARITY_TERMS)?;
            crate::singularity::check_conditioned(
                "forward dynamics",
                &guard,
                &kernels::SINGULARITY_TERMS,
                crate::singularity::TermKind::UJoint,
                crate::singularity::FORWARD_U_JOINT_TOLERANCE,
            )?;
            Ok(Acceleration::from_array(finite("acceleration", a)?))
        }
    };
}
pub(crate) use spatial_kernel_calls;

/// A platform state free in space from its coordinates.
pub(crate) fn spatial_state([x, v, a]: Motion<6>) -> State {
    State {
        pose: Pose::from_array(x),
        twist: Twist::from_array(v),
        accel: Acceleration::from_array(a),
    }
}

/// The [`Legged`] and [`TaskInertia`] implementations of a legged mechanism's runtime type whose
/// platform is free in space, through its inherent methods.
macro_rules! legged_impl {
    ($robot:ty) => {
        impl $crate::legged::Legged<6> for $robot {
            fn located(
                &self,
                q: &[f64; 6],
                near: Option<&[f64; 6]>,
            ) -> Result<([f64; 6], $crate::legged::Hold), Error> {
                let near = near.map(|x| Pose::from_array(*x));
                let (pose, terms) = <$robot>::located(self, q, near.as_ref())?;
                let hold = $crate::singularity::weakest(
                    &terms,
                    &kernels::SINGULARITY_TERMS,
                    $crate::singularity::TermKind::Pivot,
                );
                Ok((pose.to_array(), hold))
            }
            fn actuators(&self, x: &[f64; 6]) -> Result<[f64; 6], Error> {
                Ok(self.inverse_kinematics(&Pose::from_array(*x))?.0)
            }
            fn rates(&self, x: &[f64; 6], v: &[f64; 6]) -> Result<[f64; 6], Error> {
                self.joint_velocities(&Pose::from_array(*x), &Twist::from_array(*v))
            }
            fn accelerations(&self, motion: &$crate::legged::Motion<6>) -> Result<[f64; 6], Error> {
                self.joint_accelerations(&$crate::legged::spatial_state(*motion))
            }
            fn forces(&self, motion: &$crate::legged::Motion<6>) -> Result<[f64; 6], Error> {
                self.inverse_dynamics(&$crate::legged::spatial_state(*motion))
            }
            fn inverse(&self, x: &[f64; 6]) -> Result<[[f64; 6]; 6], Error> {
                self.inverse_jacobian(&Pose::from_array(*x))
            }
            fn jacobian_at(&self, x: &[f64; 6]) -> Result<[[f64; 6]; 6], Error> {
                self.jacobian(&Pose::from_array(*x))
            }
            fn accelerated(
                &self,
                x: &[f64; 6],
                v: &[f64; 6],
                gamma: &[f64; 6],
            ) -> Result<[f64; 6], Error> {
                let (pose, twist) = (Pose::from_array(*x), Twist::from_array(*v));
                Ok(self.forward_dynamics(&pose, &twist, gamma)?.to_array())
            }
        }

        impl $crate::legged::TaskInertia<6> for $robot {
            fn inertia_at(&self, x: &[f64; 6]) -> Result<[[f64; 6]; 6], Error> {
                self.task_inertia(&Pose::from_array(*x))
            }
        }
    };
}
pub(crate) use legged_impl;

/// The joint-space methods and `evaluate` of a legged mechanism's runtime type whose platform
/// is free in space (through the functions above), in its impl block.
macro_rules! joint_space_methods {
    () => {
        /// The platform state from the actuators' positions, rates and accelerations: the
        /// forward kinematics (from `near`), `V = J q̇`, and `(ω̇; a_C) = J (q̈ - b)` with `b`
        /// the actuators' accelerations at zero platform acceleration.
        ///
        /// # Errors
        /// As the forward kinematics, a singular pose, or [`Error::IllConditioned`] for
        /// nonzero rates or accelerations where the legs' hold is below
        /// [`crate::gough_stewart::JOINT_STATE_HOLD_TOLERANCE`].
        pub fn joint_state(
            &self,
            q: &[f64; 6],
            qd: &[f64; 6],
            qdd: &[f64; 6],
            near: Option<&Pose>,
        ) -> Result<State, Error> {
            let near = near.map(Pose::to_array);
            legged::joint_state(self, &[*q, *qd, *qdd], near.as_ref()).map(legged::spatial_state)
        }

        /// The actuator forces from the actuators' motion: the inverse dynamics at the
        /// platform state of `joint_state`, served down to the legs' hold tolerance (the
        /// forces stay accurate where the platform's acceleration does not).
        ///
        /// # Errors
        /// As the forward kinematics, or a singular pose.
        pub fn inverse_dynamics_joint(
            &self,
            q: &[f64; 6],
            qd: &[f64; 6],
            qdd: &[f64; 6],
            near: Option<&Pose>,
        ) -> Result<[f64; 6], Error> {
            let near = near.map(Pose::to_array);
            legged::inverse_dynamics_joint(self, &[*q, *qd, *qdd], near.as_ref())
        }

        /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia `Jᵀ M_x J`, at the pose of the
        /// actuator positions `q` (found from `near`).
        ///
        /// # Errors
        /// As the forward kinematics, or a singular pose.
        pub fn joint_inertia(
            &self,
            q: &[f64; 6],
            near: Option<&Pose>,
        ) -> Result<[[f64; 6]; 6], Error> {
            legged::joint_inertia(self, q, near.map(Pose::to_array).as_ref())
        }

        /// `c_q` of `Γ = M_q q̈ + c_q`: the forces at zero actuator acceleration.
        ///
        /// # Errors
        /// As `joint_state`.
        pub fn joint_bias(
            &self,
            q: &[f64; 6],
            qd: &[f64; 6],
            near: Option<&Pose>,
        ) -> Result<[f64; 6], Error> {
            self.inverse_dynamics_joint(q, qd, &[0.0; 6], near)
        }

        /// Everything `eval` reports for one state.
        ///
        /// # Errors
        /// Non-finite inputs or a singular pose.
        pub fn evaluate(&self, state: &State) -> Result<Evaluation, Error> {
            let motion = [
                state.pose.to_array(),
                state.twist.to_array(),
                state.accel.to_array(),
            ];
            legged::evaluate(self, &motion)
        }
    };
}
pub(crate) use joint_space_methods;

/// The per-state calls of [`crate::platform::Mechanism`] over slices, in the impl block of a
/// legged mechanism whose `Legged<$n>` serves them: each checks every slice's length before it
/// computes (nothing written on an error), then writes its result.
macro_rules! slice_calls {
    ($n:literal) => {
        fn actuator_positions(&self, pose: &[f64], q: &mut [f64]) -> Result<(), Error> {
            $crate::platform::room::<$n>("q", q)?;
            let x = $crate::platform::array("pose", pose)?;
            $crate::platform::put(q, &$crate::legged::Legged::<$n>::actuators(self, &x)?);
            Ok(())
        }
        fn inverse_jacobian(&self, pose: &[f64], jinv: &mut [f64]) -> Result<(), Error> {
            $crate::platform::room::<{ $n * $n }>("jinv", jinv)?;
            let x = $crate::platform::array("pose", pose)?;
            let m = $crate::legged::Legged::<$n>::inverse(self, &x)?;
            $crate::platform::put(jinv, m.as_flattened());
            Ok(())
        }
        fn jacobian(&self, pose: &[f64], jac: &mut [f64]) -> Result<(), Error> {
            $crate::platform::room::<{ $n * $n }>("jacobian", jac)?;
            let x = $crate::platform::array("pose", pose)?;
            let m = $crate::legged::Legged::<$n>::jacobian_at(self, &x)?;
            $crate::platform::put(jac, m.as_flattened());
            Ok(())
        }
        fn joint_velocities(
            &self,
            pose: &[f64],
            twist: &[f64],
            qd: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("qd", qd)?;
            let x = $crate::platform::array("pose", pose)?;
            let v = $crate::platform::array("twist", twist)?;
            $crate::platform::put(qd, &$crate::legged::Legged::<$n>::rates(self, &x, &v)?);
            Ok(())
        }
        fn joint_accelerations(
            &self,
            pose: &[f64],
            twist: &[f64],
            acceleration: &[f64],
            qdd: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("qdd", qdd)?;
            let motion = $crate::legged::motion_of::<$n>(
                [pose, twist, acceleration],
                $crate::legged::MOTION,
            )?;
            let values = $crate::legged::Legged::<$n>::accelerations(self, &motion)?;
            $crate::platform::put(qdd, &values);
            Ok(())
        }
        fn inverse_dynamics(
            &self,
            pose: &[f64],
            twist: &[f64],
            acceleration: &[f64],
            gamma: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("gamma", gamma)?;
            let motion = $crate::legged::motion_of::<$n>(
                [pose, twist, acceleration],
                $crate::legged::MOTION,
            )?;
            let values = $crate::legged::Legged::<$n>::forces(self, &motion)?;
            $crate::platform::put(gamma, &values);
            Ok(())
        }
        fn forward_dynamics(
            &self,
            pose: &[f64],
            twist: &[f64],
            gamma: &[f64],
            acceleration: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("acceleration", acceleration)?;
            let [x, v, g] =
                $crate::legged::motion_of::<$n>([pose, twist, gamma], ["pose", "twist", "gamma"])?;
            let a = $crate::legged::Legged::<$n>::accelerated(self, &x, &v, &g)?;
            $crate::platform::put(acceleration, &a);
            Ok(())
        }
        fn forward_kinematics(
            &self,
            q: &[f64],
            near: Option<&[f64]>,
            pose: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("pose", pose)?;
            let near = near
                .map(|x| $crate::platform::array::<$n>("near", x))
                .transpose()?;
            let q = $crate::platform::array("q", q)?;
            let (x, _) = $crate::legged::Legged::<$n>::located(self, &q, near.as_ref())?;
            $crate::platform::put(pose, &x);
            Ok(())
        }
        fn inverse_dynamics_joint(
            &self,
            joints: [&[f64]; 3],
            near: Option<&[f64]>,
            gamma: &mut [f64],
        ) -> Result<(), Error> {
            $crate::platform::room::<$n>("gamma", gamma)?;
            let near = near
                .map(|x| $crate::platform::array::<$n>("near", x))
                .transpose()?;
            let joints = $crate::legged::motion_of::<$n>(joints, ["q", "qd", "qdd"])?;
            let values = $crate::legged::inverse_dynamics_joint(self, &joints, near.as_ref())?;
            $crate::platform::put(gamma, &values);
            Ok(())
        }
        fn joint_state(
            &self,
            joints: [&[f64]; 3],
            near: Option<&[f64]>,
            out: [&mut [f64]; 3],
        ) -> Result<(), Error> {
            for (name, slice) in $crate::legged::MOTION.into_iter().zip(&out) {
                $crate::platform::room::<$n>(name, slice)?;
            }
            let near = near
                .map(|x| $crate::platform::array::<$n>("near", x))
                .transpose()?;
            let joints = $crate::legged::motion_of::<$n>(joints, ["q", "qd", "qdd"])?;
            let motion = $crate::legged::joint_state(self, &joints, near.as_ref())?;
            for (slice, values) in out.into_iter().zip(&motion) {
                $crate::platform::put(slice, values);
            }
            Ok(())
        }
    };
}
pub(crate) use slice_calls;

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
