//! Any parallel robot, whatever its platform's freedom, behind one trait whose dimension comes
//! from the model: what the program's and Python's calls that serve every mechanism go through.
//!
//! A [`Mechanism`] reads and writes the platform's coordinates as slices of
//! [`Freedom::dimension`] numbers, in the order [`Freedom::pose_names`],
//! [`Freedom::twist_names`] and [`Freedom::acceleration_names`] give (`[α β γ xc yc zc]`,
//! `(ω; v_C)`, `(ω̇; a_C)` for a platform free in space; `[xc yc zc]`, `v_C`, `a_C` for one that
//! only translates), and as many actuators. Its matrices are row-major. The per-state calls
//! write into the caller's slices, so a controller's loop allocates nothing (the conveniences
//! `home`, `evaluate`, `coordinates_of` and `state_of` return owned values); a slice of the
//! wrong length is refused ([`Error::WrongLength`]) with nothing written.
//!
//! [`load`] makes one from a [`Description`]. Every robot serves it through its typed
//! [`ParallelRobot<N>`] and one adapter, [`Sliced`] (`robot.as_mechanism()`,
//! `robot.into_mechanism()`), and [`Mechanism::spatial`] gives a [`SpatialRobot`] back for
//! what only six freedoms have (the derivatives).

use crate::dynamics::{rk4_step, PlantState};
#[cfg(feature = "identify")]
use crate::identify::{BaseParameters, Friction};
use crate::legged::{Freedoms, Platform, PoseOf, StateOf};
use crate::mechanism::{ParallelRobot, SpatialRobot};
use crate::{Acceleration, Error, GoughStewart, Limit, Model, Pose, RusHexapod, Twist, C5};
use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;
pub use c5_robot::tree::Freedom;
use c5_robot::Description;

/// A parallel robot of any freedom: its kinematics and dynamics in its platform's coordinates.
pub trait Mechanism: core::fmt::Debug + Send + Sync {
    /// The mechanism's name, as robot files spell it (`c5`, `gough-stewart`, `delta`).
    fn mechanism(&self) -> &'static str;
    /// The name of the model the results follow (`consistent`, `paper`, the mechanism's).
    fn model_name(&self) -> &'static str;
    /// How the platform moves, and so the length of every slice.
    fn freedom(&self) -> Freedom;
    /// The robot's description, as its file gives it.
    fn description(&self) -> Description;
    /// The robot's parameter vector, as its generated `*_params` kernels take it.
    fn parameters(&self) -> &[f64];
    /// The pose the robot rests at, where its forward kinematics starts.
    fn home(&self) -> Vec<f64>;
    /// The robot as a platform free in space, for what only six freedoms serve; `None` for a
    /// platform that only translates.
    fn spatial(&self) -> Option<&dyn SpatialRobot>;
    /// The robot's exact derivatives in its platform's coordinates, where its mechanism has
    /// them generated; `None` where not.
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn crate::derivatives::SlicedDerivatives>;
    /// Its mechanism's kinematic calibration kernel, where one is generated.
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel>;

    /// The actuator values at `pose` into `q`.
    ///
    /// # Errors
    /// Wrong lengths, non-finite inputs, a pose at a singularity or beyond reach.
    fn actuator_positions(&self, pose: &[f64], q: &mut [f64]) -> Result<(), Error>;
    /// `J⁻¹` at `pose`, row `i` for actuator `i`, columns the twist's, row-major into `jinv`.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn inverse_jacobian(&self, pose: &[f64], jinv: &mut [f64]) -> Result<(), Error>;
    /// `J` at `pose`, rows the twist's, column `i` for actuator `i`, row-major into `jac`.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`], and the legs' hold on the platform.
    fn jacobian(&self, pose: &[f64], jac: &mut [f64]) -> Result<(), Error>;
    /// `q̇ = J⁻¹ V` into `qd`.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn joint_velocities(&self, pose: &[f64], twist: &[f64], qd: &mut [f64]) -> Result<(), Error>;
    /// `q̈` of the platform's motion into `qdd`.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn joint_accelerations(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        qdd: &mut [f64],
    ) -> Result<(), Error>;
    /// The actuator forces `Γ` of the platform's motion into `gamma`: the inverse dynamics.
    ///
    /// # Errors
    /// As [`Mechanism::jacobian`].
    fn inverse_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        gamma: &mut [f64],
    ) -> Result<(), Error>;
    /// The platform's classical acceleration under the actuator forces `gamma` into
    /// `acceleration`: the forward dynamics.
    ///
    /// # Errors
    /// As [`Mechanism::jacobian`], and where the forward dynamics cannot be served to its
    /// accuracy bound.
    fn forward_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        gamma: &[f64],
        acceleration: &mut [f64],
    ) -> Result<(), Error>;
    /// `M_x` of `Γ = Jᵀ (M_x V̇ + h)` at `pose`, row-major into `m` (`n × n`, rows and
    /// columns the acceleration's): symmetric positive definite.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn task_inertia(&self, pose: &[f64], m: &mut [f64]) -> Result<(), Error>;
    /// `h` of `Γ = Jᵀ (M_x V̇ + h)` at `pose` and `twist` into `h`: the Coriolis, centrifugal
    /// and gravity terms at `C`.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn task_bias(&self, pose: &[f64], twist: &[f64], h: &mut [f64]) -> Result<(), Error>;
    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia `Jᵀ M_x J` at the actuator values
    /// `q`, row-major into `m`, the pose found from `near` (else the robot's start).
    ///
    /// # Errors
    /// As [`Mechanism::forward_kinematics`], and a singular pose.
    fn joint_inertia(&self, q: &[f64], near: Option<&[f64]>, m: &mut [f64]) -> Result<(), Error>;
    /// The pose of the actuator values `q` into `pose`, from `near` where the mechanism
    /// iterates (else from home).
    ///
    /// # Errors
    /// Wrong lengths, non-finite inputs, no pose or a singular one.
    fn forward_kinematics(
        &self,
        q: &[f64],
        near: Option<&[f64]>,
        pose: &mut [f64],
    ) -> Result<(), Error>;
    /// The platform's pose, twist and acceleration from the actuators' values, rates and
    /// accelerations (`out`: pose, twist, acceleration).
    ///
    /// # Errors
    /// As [`Mechanism::forward_kinematics`], and where `J` cannot be applied to its accuracy
    /// bound.
    fn joint_state(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        out: [&mut [f64]; 3],
    ) -> Result<(), Error>;
    /// One classical Runge-Kutta step of `dt` under the constant actuator forces `gamma`,
    /// `pose` and `twist` advanced in place (unchanged on an error).
    ///
    /// # Errors
    /// As [`Mechanism::forward_dynamics`] at any stage.
    fn step_held(
        &self,
        pose: &mut [f64],
        twist: &mut [f64],
        gamma: &[f64],
        dt: f64,
    ) -> Result<(), Error> {
        let n = self.freedom().dimension();
        let zero = vec![0.0; n];
        let start = self.state_of([pose, twist, &zero])?;
        let plant = PlantState::new(&start.pose, &start.twist);
        let next = rk4_step(self, &plant, 0.0, dt, |_, _| Ok(gamma.to_vec()))?;
        let [x, v, _] = self.coordinates_of(&next.with_acceleration(Acceleration::default()))?;
        put(pose, &x);
        put(twist, &v);
        Ok(())
    }
    /// The actuator forces `Γ` of the actuators' motion `[q, q̇, q̈]` into `gamma`: the
    /// joint-space inverse dynamics `Γ = M_q q̈ + c_q`, the pose found from `near` (else the
    /// robot's start).
    ///
    /// # Errors
    /// As [`Mechanism::joint_state`] and [`Mechanism::inverse_dynamics`].
    fn inverse_dynamics_joint(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        gamma: &mut [f64],
    ) -> Result<(), Error> {
        let n = self.freedom().dimension();
        let (mut x, mut v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.joint_state(joints, near, [&mut x, &mut v, &mut a])?;
        self.inverse_dynamics(&x, &v, &a, gamma)
    }

    /// Whether the robot file sets any limit.
    fn has_limits(&self) -> bool;
    /// The actuators' speed and force bounds (m/s or rad/s, N or N·m), where the robot file
    /// sets them.
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>);
    /// The smallest margin of the robot file's pose-bound limits at `pose` (the limit, the
    /// actuator from 1, the margin and the value), `None` where it sets none.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn smallest_pose_margin(&self, pose: &[f64]) -> Result<Option<Margin>, Error>;
    /// Refuses a pose beyond the robot file's pose-bound limits.
    ///
    /// # Errors
    /// [`Error::Limit`] naming the limit with the smallest (negative) margin; as
    /// [`Mechanism::actuator_positions`].
    fn check_limits(&self, pose: &[f64]) -> Result<(), Error> {
        crate::limits::refuse_beyond(self.smallest_pose_margin(pose)?)
    }
    /// Refuses actuator speeds `qd` beyond the robot file's bound.
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `qd` is not one per actuator; [`Error::Limit`] for the
    /// fastest actuator over the bound.
    fn check_speeds(&self, qd: &[f64]) -> Result<(), Error> {
        one_per_actuator(self, "qd", qd)?;
        crate::limits::over(Limit::Speed, self.speed_and_force_limits().0, qd)
    }
    /// Refuses actuator forces `gamma` beyond the robot file's bound.
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `gamma` is not one per actuator; [`Error::Limit`] for the
    /// largest force over the bound.
    fn check_forces(&self, gamma: &[f64]) -> Result<(), Error> {
        one_per_actuator(self, "gamma", gamma)?;
        crate::limits::over(Limit::Force, self.speed_and_force_limits().1, gamma)
    }

    /// The robot's parts at `pose`, for drawing it ([`crate::scene`]): a leg per actuator,
    /// those past a limit of the robot file flagged.
    ///
    /// # Errors
    /// As [`Mechanism::actuator_positions`].
    fn scene(&self, pose: &[f64]) -> Result<crate::scene::Scene, Error>;
    /// A boxed copy.
    fn clone_mechanism(&self) -> Box<dyn Mechanism>;
    /// The smallest of the singularity terms at `pose`, each about 1 far from its singularity
    /// and 0 at it (negative beyond reach).
    ///
    /// # Errors
    /// A pose of the wrong length or not finite.
    fn singularity_clearance(&self, pose: &[f64]) -> Result<f64, Error>;

    /// The standard parameters `π` of this robot with `friction`, one per actuator: the
    /// inertial ones, then viscous and Coulomb friction per actuator.
    ///
    /// # Errors
    /// [`Error::WrongLength`] if `friction` is not one per actuator.
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction]) -> Result<Vec<f64>, Error>;
    /// The base parameters of this robot's base regressor.
    ///
    /// # Errors
    /// [`Error::Unsupported`] where this geometry has base parameters the generated
    /// regressor lacks.
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error>;
    /// `Y` at the state `[pose, twist, acceleration]` (`n × p`, a row per actuator, a column
    /// per standard parameter): `Γ = Y π` with friction.
    ///
    /// # Errors
    /// Wrong lengths, non-finite inputs, a singular pose or a non-finite result.
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, motion: [&[f64]; 3]) -> Result<nalgebra::DMatrix<f64>, Error>;
    /// `Y_b` at the state `[pose, twist, acceleration]` into `out`, row-major (`n × n_b`):
    /// `Γ = Y_b β` with friction. For streaming without allocation.
    ///
    /// # Errors
    /// Wrong lengths, non-finite inputs, a singular pose, a non-finite result.
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, motion: [&[f64]; 3], out: &mut [f64]) -> Result<(), Error>;

    /// `q`, `q̇`, `q̈`, `Γ`, `J⁻¹` and `J` of one state.
    ///
    /// # Errors
    /// As [`Mechanism::jacobian`].
    fn evaluate(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
    ) -> Result<Evaluated, Error> {
        let n = self.freedom().dimension();
        let mut e = Evaluated {
            q: vec![0.0; n],
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            gamma: vec![0.0; n],
            jinv: vec![0.0; n * n],
            jacobian: vec![0.0; n * n],
        };
        self.actuator_positions(pose, &mut e.q)?;
        self.joint_velocities(pose, twist, &mut e.qd)?;
        self.joint_accelerations(pose, twist, acceleration, &mut e.qdd)?;
        self.inverse_dynamics(pose, twist, acceleration, &mut e.gamma)?;
        self.inverse_jacobian(pose, &mut e.jinv)?;
        self.jacobian(pose, &mut e.jacobian)?;
        Ok(e)
    }
    /// A platform state of six coordinates in this platform's: all of it for a platform free
    /// in space, the centre's motion for one that only translates.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a state that turns a platform that only translates.
    fn coordinates_of(&self, state: &crate::State) -> Result<[Vec<f64>; 3], Error> {
        let (pose, twist, accel) = (state.pose, state.twist, state.accel);
        match self.freedom() {
            Freedom::Free => Ok([
                pose.to_array().to_vec(),
                twist.to_array().to_vec(),
                accel.to_array().to_vec(),
            ]),
            Freedom::Translations => {
                let angular = [pose.alpha, pose.beta, pose.gamma]
                    .into_iter()
                    .chain(twist.omega)
                    .chain(accel.omega_dot);
                if angular.into_iter().any(|x| x != 0.0) {
                    return Err(Error::Unsupported {
                        what: "a motion that turns the platform",
                        mechanism: self.mechanism(),
                        why: "its platform only translates",
                    });
                }
                Ok([
                    pose.center.to_vec(),
                    twist.velocity.to_vec(),
                    accel.linear.to_vec(),
                ])
            }
        }
    }
    /// The platform state of six coordinates of this platform's (the angles and angular
    /// motion zero for one that only translates).
    ///
    /// # Errors
    /// Slices of the wrong length.
    fn state_of(&self, motion: [&[f64]; 3]) -> Result<crate::State, Error> {
        let [pose, twist, acceleration] = motion;
        match self.freedom() {
            Freedom::Free => spatial_state(pose, twist, acceleration),
            Freedom::Translations => {
                let (x, v, a) = (
                    array("pose", pose)?,
                    array("twist", twist)?,
                    array("acceleration", acceleration)?,
                );
                Ok(crate::State {
                    pose: Pose {
                        center: x,
                        ..Pose::default()
                    },
                    twist: Twist {
                        omega: [0.0; 3],
                        velocity: v,
                    },
                    accel: Acceleration {
                        omega_dot: [0.0; 3],
                        linear: a,
                    },
                })
            }
        }
    }

    /// [`Mechanism::inverse_dynamics`] of states `0..n`, `motion(k, [pose, twist,
    /// acceleration])` filling the `k`-th state's slices, each result handed to `each` in
    /// order: for callers that read states from their own storage (numpy arrays, a log). The
    /// C5 goes four states at a time through its batch kernels (feature `batch`).
    fn inverse_dynamics_each(&self, n: usize, motion: &Inputs<'_>, each: &mut Each<'_>) {
        let d = self.freedom().dimension();
        for k in 0..n {
            let ([mut x, mut v, mut a], mut gamma) = ([[0.0; MOST]; 3], [0.0; MOST]);
            motion(k, [&mut x[..d], &mut v[..d], &mut a[..d]]);
            let result = self.inverse_dynamics(&x[..d], &v[..d], &a[..d], &mut gamma[..d]);
            each(k, result.map(|()| &gamma[..d]));
        }
    }
    /// [`Mechanism::forward_dynamics`] of inputs `0..n`, `input(k, [pose, twist, gamma])`
    /// filling the `k`-th, each result handed to `each` in order, as
    /// [`Mechanism::inverse_dynamics_each`].
    fn forward_dynamics_each(&self, n: usize, input: &Inputs<'_>, each: &mut Each<'_>) {
        let d = self.freedom().dimension();
        for k in 0..n {
            let ([mut x, mut v, mut g], mut accel) = ([[0.0; MOST]; 3], [0.0; MOST]);
            input(k, [&mut x[..d], &mut v[..d], &mut g[..d]]);
            let result = self.forward_dynamics(&x[..d], &v[..d], &g[..d], &mut accel[..d]);
            each(k, result.map(|()| &accel[..d]));
        }
    }
}

impl Clone for Box<dyn Mechanism> {
    fn clone(&self) -> Self {
        self.clone_mechanism()
    }
}

/// What [`Mechanism::evaluate`] gives of one state, in the platform's dimension `n`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Evaluated {
    /// The actuator values.
    pub q: Vec<f64>,
    /// Their rates, `J⁻¹ V`.
    pub qd: Vec<f64>,
    /// Their accelerations.
    pub qdd: Vec<f64>,
    /// The actuator forces `Γ`.
    pub gamma: Vec<f64>,
    /// `J⁻¹`, row-major `n × n`.
    pub jinv: Vec<f64>,
    /// `J`, row-major `n × n`.
    pub jacobian: Vec<f64>,
}

/// Fills the `k`-th input's three slices, each of the platform's dimension: what the `*_each`
/// methods read states through.
pub type Inputs<'a> = dyn Fn(usize, [&mut [f64]; 3]) + Sync + 'a;

/// Takes the `k`-th result of a `*_each` method: its values, or why the state was refused.
pub type Each<'a> = dyn FnMut(usize, Result<&[f64], Error>) + 'a;

/// A limit's margin: the limit, the actuator from 1, the margin (negative beyond it) and the
/// value.
pub type Margin = (Limit, usize, f64, f64);

/// Refuses `values` unless it has one number per actuator of `robot`.
fn one_per_actuator<M: Mechanism + ?Sized>(
    robot: &M,
    input: &'static str,
    values: &[f64],
) -> Result<(), Error> {
    let expected = robot.freedom().dimension();
    if values.len() == expected {
        Ok(())
    } else {
        Err(Error::WrongLength {
            input,
            expected,
            got: values.len(),
        })
    }
}

/// The most coordinates a platform has: the buffers' size.
const MOST: usize = Freedom::Free.dimension();

/// The robot of `description`, the C5 with `model` (the other mechanisms have one model): the
/// one place a description is mapped to its runtime type for [`Mechanism`].
///
/// # Errors
/// [`Error::Robot`] if the description breaks a rule of its mechanism.
pub fn load(description: Description, model: Model) -> Result<Box<dyn Mechanism>, Error> {
    Ok(match description {
        Description::C5(r) => C5::with_model(r, model)?.into_mechanism(),
        Description::GoughStewart(r) => GoughStewart::new(r)?.into_mechanism(),
        Description::RusHexapod(r) => RusHexapod::new(r)?.into_mechanism(),
        Description::Delta(r) => crate::Delta::new(r)?.into_mechanism(),
    })
}

/// `values` as an array of `N`, refused by name when its length is not `N`.
pub(crate) fn array<const N: usize>(
    input: &'static str,
    values: &[f64],
) -> Result<[f64; N], Error> {
    exactly(input, values)
}

/// `values` as an array of `N` of any kind, refused by name when its length is not `N`.
pub(crate) fn exactly<T: Copy, const N: usize>(
    input: &'static str,
    values: &[T],
) -> Result<[T; N], Error> {
    values.try_into().map_err(|_| Error::WrongLength {
        input,
        expected: N,
        got: values.len(),
    })
}

/// Checks that `out` takes `N` numbers, before anything is computed.
pub(crate) fn room<const N: usize>(output: &'static str, out: &[f64]) -> Result<(), Error> {
    array::<N>(output, out).map(drop)
}

/// Copies `values` into `out`, whose length [`room`] checked.
pub(crate) fn put(out: &mut [f64], values: &[f64]) {
    out.copy_from_slice(values);
}

/// A typed robot of `N` freedoms served through slices: the one implementation of
/// [`Mechanism`], for every [`ParallelRobot`] whatever its freedom. Each per-state call checks
/// every slice's length before it computes (nothing written on an error), then writes its
/// result.
#[derive(Clone, Debug)]
#[repr(transparent)]
pub struct Sliced<R, const N: usize>(pub R);

impl<R, const N: usize> Sliced<R, N> {
    /// `robot` served through slices, borrowed: what [`ParallelRobot::as_mechanism`] gives.
    pub fn of(robot: &R) -> &Self {
        // SAFETY: `Sliced` is `repr(transparent)` over `R`, so a `&R` is a valid `&Sliced<R,
        // N>` for the same lifetime (what the `ref-cast` crate derives).
        unsafe { &*(robot as *const R).cast::<Self>() }
    }
}

/// The pose in `pose`, as the platform of `N` freedoms types it.
pub(crate) fn pose_of<const N: usize>(name: &'static str, pose: &[f64]) -> Result<PoseOf<N>, Error>
where
    Platform<N>: Freedoms<N>,
{
    array(name, pose).map(Platform::<N>::pose)
}

/// The platform's state from its three slices.
pub(crate) fn state_from<const N: usize>(motion: [&[f64]; 3]) -> Result<StateOf<N>, Error>
where
    Platform<N>: Freedoms<N>,
{
    crate::legged::motion_of(motion, crate::legged::MOTION).map(Platform::<N>::state)
}

/// The actuators' motion `[q, q̇, q̈]` and the pose to start from.
type Joints<const N: usize> = ([[f64; N]; 3], Option<PoseOf<N>>);

fn joints_from<const N: usize>(
    joints: [&[f64]; 3],
    near: Option<&[f64]>,
) -> Result<Joints<N>, Error>
where
    Platform<N>: Freedoms<N>,
{
    let near = near.map(|x| pose_of::<N>("near", x)).transpose()?;
    Ok((crate::legged::motion_of(joints, ["q", "qd", "qdd"])?, near))
}

/// Checks that `out` takes an `N × N` matrix, before anything is computed.
pub(crate) fn room_for_matrix<const N: usize>(
    output: &'static str,
    out: &[f64],
) -> Result<(), Error> {
    if out.len() == N * N {
        Ok(())
    } else {
        Err(Error::WrongLength {
            input: output,
            expected: N * N,
            got: out.len(),
        })
    }
}

impl<R: ParallelRobot<N> + Clone + 'static, const N: usize> Mechanism for Sliced<R, N>
where
    Platform<N>: Freedoms<N>,
{
    fn mechanism(&self) -> &'static str {
        self.0.mechanism()
    }
    fn model_name(&self) -> &'static str {
        self.0.model_name()
    }
    fn freedom(&self) -> Freedom {
        Platform::<N>::FREEDOM
    }
    fn description(&self) -> Description {
        self.0.description()
    }
    fn parameters(&self) -> &[f64] {
        self.0.parameters()
    }
    fn home(&self) -> Vec<f64> {
        Platform::<N>::pose_array(&self.0.home()).to_vec()
    }
    fn spatial(&self) -> Option<&dyn SpatialRobot> {
        self.0.spatial()
    }
    #[cfg(feature = "derivatives")]
    fn derivatives(&self) -> Option<&dyn crate::derivatives::SlicedDerivatives> {
        self.0
            .derivatives()
            .map(|_| self as &dyn crate::derivatives::SlicedDerivatives)
    }
    #[cfg(feature = "calibrate")]
    fn calibration(&self) -> Option<crate::calibrate::ResidualKernel> {
        self.0.calibration()
    }
    fn clone_mechanism(&self) -> Box<dyn Mechanism> {
        Box::new(self.clone())
    }
    fn singularity_clearance(&self, pose: &[f64]) -> Result<f64, Error> {
        self.0.singularity_clearance(&pose_of::<N>("pose", pose)?)
    }
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[Friction]) -> Result<Vec<f64>, Error> {
        Ok(self.0.standard_parameters(&exactly("friction", friction)?))
    }
    #[cfg(feature = "identify")]
    fn base_parameters(&self) -> Result<BaseParameters, Error> {
        self.0.base_parameters()
    }
    #[cfg(feature = "identify")]
    fn standard_regressor(&self, motion: [&[f64]; 3]) -> Result<nalgebra::DMatrix<f64>, Error> {
        self.0.standard_regressor(&state_from::<N>(motion)?)
    }
    #[cfg(feature = "identify")]
    fn base_regressor_into(&self, motion: [&[f64]; 3], out: &mut [f64]) -> Result<(), Error> {
        self.0.base_regressor_into(&state_from::<N>(motion)?, out)
    }
    fn actuator_positions(&self, pose: &[f64], q: &mut [f64]) -> Result<(), Error> {
        room::<N>("q", q)?;
        put(q, &self.0.actuator_positions(&pose_of::<N>("pose", pose)?)?);
        Ok(())
    }
    fn inverse_jacobian(&self, pose: &[f64], jinv: &mut [f64]) -> Result<(), Error> {
        room_for_matrix::<N>("jinv", jinv)?;
        let pose = pose_of::<N>("pose", pose)?;
        put(jinv, self.0.inverse_jacobian(&pose)?.as_flattened());
        Ok(())
    }
    fn jacobian(&self, pose: &[f64], jac: &mut [f64]) -> Result<(), Error> {
        room_for_matrix::<N>("jacobian", jac)?;
        let pose = pose_of::<N>("pose", pose)?;
        put(jac, self.0.jacobian(&pose)?.as_flattened());
        Ok(())
    }
    fn joint_velocities(&self, pose: &[f64], twist: &[f64], qd: &mut [f64]) -> Result<(), Error> {
        room::<N>("qd", qd)?;
        let pose = pose_of::<N>("pose", pose)?;
        let twist = Platform::<N>::twist(array("twist", twist)?);
        put(qd, &self.0.joint_velocities(&pose, &twist)?);
        Ok(())
    }
    fn joint_accelerations(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        qdd: &mut [f64],
    ) -> Result<(), Error> {
        room::<N>("qdd", qdd)?;
        let state = state_from::<N>([pose, twist, acceleration])?;
        put(qdd, &self.0.joint_accelerations(&state)?);
        Ok(())
    }
    fn inverse_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        acceleration: &[f64],
        gamma: &mut [f64],
    ) -> Result<(), Error> {
        room::<N>("gamma", gamma)?;
        let state = state_from::<N>([pose, twist, acceleration])?;
        put(gamma, &self.0.inverse_dynamics(&state)?);
        Ok(())
    }
    fn forward_dynamics(
        &self,
        pose: &[f64],
        twist: &[f64],
        gamma: &[f64],
        acceleration: &mut [f64],
    ) -> Result<(), Error> {
        room::<N>("acceleration", acceleration)?;
        let pose = pose_of::<N>("pose", pose)?;
        let twist = Platform::<N>::twist(array("twist", twist)?);
        let a = self
            .0
            .forward_dynamics(&pose, &twist, &array("gamma", gamma)?)?;
        put(acceleration, &Platform::<N>::acceleration_array(&a));
        Ok(())
    }
    fn task_inertia(&self, pose: &[f64], m: &mut [f64]) -> Result<(), Error> {
        room_for_matrix::<N>("task inertia", m)?;
        let pose = pose_of::<N>("pose", pose)?;
        put(m, self.0.task_inertia(&pose)?.as_flattened());
        Ok(())
    }
    fn task_bias(&self, pose: &[f64], twist: &[f64], h: &mut [f64]) -> Result<(), Error> {
        room::<N>("task bias", h)?;
        let pose = pose_of::<N>("pose", pose)?;
        let twist = Platform::<N>::twist(array("twist", twist)?);
        put(h, &self.0.task_bias(&pose, &twist)?);
        Ok(())
    }
    fn joint_inertia(&self, q: &[f64], near: Option<&[f64]>, m: &mut [f64]) -> Result<(), Error> {
        room_for_matrix::<N>("joint inertia", m)?;
        let near = near.map(|x| pose_of::<N>("near", x)).transpose()?;
        put(
            m,
            self.0
                .joint_inertia(&array("q", q)?, near.as_ref())?
                .as_flattened(),
        );
        Ok(())
    }
    fn forward_kinematics(
        &self,
        q: &[f64],
        near: Option<&[f64]>,
        pose: &mut [f64],
    ) -> Result<(), Error> {
        room::<N>("pose", pose)?;
        let near = near.map(|x| pose_of::<N>("near", x)).transpose()?;
        let found = self.0.forward_kinematics(&array("q", q)?, near.as_ref())?;
        put(pose, &Platform::<N>::pose_array(&found));
        Ok(())
    }
    fn joint_state(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        out: [&mut [f64]; 3],
    ) -> Result<(), Error> {
        let [pose, twist, acceleration] = out;
        room::<N>("pose", pose)?;
        room::<N>("twist", twist)?;
        room::<N>("acceleration", acceleration)?;
        let ([q, qd, qdd], near) = joints_from::<N>(joints, near)?;
        let state = self.0.joint_state(&q, &qd, &qdd, near.as_ref())?;
        let [x, v, a] = Platform::<N>::state_arrays(&state);
        put(pose, &x);
        put(twist, &v);
        put(acceleration, &a);
        Ok(())
    }
    fn inverse_dynamics_joint(
        &self,
        joints: [&[f64]; 3],
        near: Option<&[f64]>,
        gamma: &mut [f64],
    ) -> Result<(), Error> {
        room::<N>("gamma", gamma)?;
        let ([q, qd, qdd], near) = joints_from::<N>(joints, near)?;
        put(
            gamma,
            &self
                .0
                .inverse_dynamics_joint(&q, &qd, &qdd, near.as_ref())?,
        );
        Ok(())
    }
    fn scene(&self, pose: &[f64]) -> Result<crate::scene::Scene, Error> {
        self.0.scene(&pose_of::<N>("pose", pose)?)
    }
    fn has_limits(&self) -> bool {
        self.0.has_limits()
    }
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>) {
        self.0.speed_and_force_limits()
    }
    fn smallest_pose_margin(&self, pose: &[f64]) -> Result<Option<Margin>, Error> {
        self.0.smallest_pose_margin(&pose_of::<N>("pose", pose)?)
    }
    /// Through the robot's own calls over many states (the C5's batch kernels, feature
    /// `batch`).
    fn inverse_dynamics_each(&self, n: usize, motion: &Inputs<'_>, each: &mut Each<'_>) {
        let state = |k: usize| {
            let [mut x, mut v, mut a] = [[0.0; N]; 3];
            motion(k, [&mut x, &mut v, &mut a]);
            Platform::<N>::state([x, v, a])
        };
        self.0
            .inverse_dynamics_each(n, &state, &mut |k, result| match result {
                Ok(gamma) => each(k, Ok(&gamma)),
                Err(e) => each(k, Err(e)),
            });
    }
    /// Through the robot's own calls over many states (the C5's batch kernels, feature
    /// `batch`).
    fn forward_dynamics_each(&self, n: usize, input: &Inputs<'_>, each: &mut Each<'_>) {
        let at = |k: usize| {
            let [mut x, mut v, mut g] = [[0.0; N]; 3];
            input(k, [&mut x, &mut v, &mut g]);
            (Platform::<N>::pose(x), Platform::<N>::twist(v), g)
        };
        self.0
            .forward_dynamics_each(n, &at, &mut |k, result| match result {
                Ok(accel) => each(k, Ok(&Platform::<N>::acceleration_array(&accel))),
                Err(e) => each(k, Err(e)),
            });
    }
}

/// A platform state free in space from its three slices.
fn spatial_state(pose: &[f64], twist: &[f64], acceleration: &[f64]) -> Result<crate::State, Error> {
    Ok(crate::State {
        pose: Pose::from_array(array("pose", pose)?),
        twist: Twist::from_array(array("twist", twist)?),
        accel: Acceleration::from_array(array("acceleration", acceleration)?),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every mechanism the catalogue has, from its example description.
    fn every_mechanism() -> Vec<Box<dyn Mechanism>> {
        [
            Description::default(),
            Description::GoughStewart(c5_robot::GoughStewart::example()),
            Description::RusHexapod(c5_robot::RusHexapod::example()),
            Description::Delta(c5_robot::Delta::example()),
        ]
        .into_iter()
        .map(|d| load(d, Model::Consistent).unwrap())
        .collect()
    }

    /// A pose near home, moved by `k` small steps of each coordinate, and a twist and an
    /// acceleration of that dimension.
    fn motion(robot: &dyn Mechanism, k: f64) -> [Vec<f64>; 3] {
        let n = robot.freedom().dimension();
        let mut pose = robot.home();
        for (i, x) in pose.iter_mut().enumerate() {
            *x += 0.004 * k * ((i as f64) * 1.7 + 0.3).sin();
        }
        let twist = (0..n).map(|i| 0.2 * (k + i as f64).cos()).collect();
        let accel = (0..n).map(|i| 0.9 * (2.0 * k - i as f64).sin()).collect();
        [pose, twist, accel]
    }

    fn product(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
        (0..n * n)
            .map(|ij| (0..n).map(|k| a[ij / n * n + k] * b[k * n + ij % n]).sum())
            .collect()
    }

    #[test]
    fn the_slices_have_the_freedoms_dimension_and_j_times_its_inverse_is_the_identity() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            assert_eq!(robot.home().len(), n, "{}", robot.mechanism());
            let [pose, ..] = motion(&*robot, 1.0);
            let (mut jinv, mut jac) = (vec![0.0; n * n], vec![0.0; n * n]);
            robot.inverse_jacobian(&pose, &mut jinv).unwrap();
            robot.jacobian(&pose, &mut jac).unwrap();
            let identity = product(&jac, &jinv, n);
            for (ij, x) in identity.iter().enumerate() {
                let expected = if ij / n == ij % n { 1.0 } else { 0.0 };
                assert!(
                    (x - expected).abs() < 1e-12,
                    "{}: {identity:?}",
                    robot.mechanism()
                );
            }
        }
    }

    #[test]
    fn the_forward_dynamics_undoes_the_inverse_and_the_forward_kinematics_the_inverse() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            for k in 0..4 {
                let [pose, twist, accel] = motion(&*robot, k as f64);
                let (mut gamma, mut back) = (vec![0.0; n], vec![0.0; n]);
                robot
                    .inverse_dynamics(&pose, &twist, &accel, &mut gamma)
                    .unwrap();
                robot
                    .forward_dynamics(&pose, &twist, &gamma, &mut back)
                    .unwrap();
                for i in 0..n {
                    assert!((back[i] - accel[i]).abs() < 1e-9, "{}", robot.mechanism());
                }
                let (mut q, mut found) = (vec![0.0; n], vec![0.0; n]);
                robot.actuator_positions(&pose, &mut q).unwrap();
                robot.forward_kinematics(&q, None, &mut found).unwrap();
                for i in 0..n {
                    assert!((found[i] - pose[i]).abs() < 1e-11, "{}", robot.mechanism());
                }
            }
        }
    }

    /// `q̇ = J⁻¹ V` against the actuators' values differenced along a translation of the
    /// platform (the pose's rate is then the twist's, for every freedom).
    #[test]
    fn the_actuators_rates_are_their_positions_differenced() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let [pose, ..] = motion(&*robot, 2.0);
            let mut twist = vec![0.0; n];
            twist[n - 3..].copy_from_slice(&[0.05, -0.08, 0.11]);
            let mut qd = vec![0.0; n];
            robot.joint_velocities(&pose, &twist, &mut qd).unwrap();
            let h = 1e-6;
            let at = |s: f64| {
                let moved: Vec<f64> = pose.iter().zip(&twist).map(|(x, v)| x + s * v).collect();
                let mut q = vec![0.0; n];
                robot.actuator_positions(&moved, &mut q).unwrap();
                q
            };
            let (plus, minus) = (at(h), at(-h));
            for i in 0..n {
                let differenced = (plus[i] - minus[i]) / (2.0 * h);
                assert!((differenced - qd[i]).abs() < 1e-8, "{}", robot.mechanism());
            }
        }
    }

    #[test]
    fn the_platform_from_the_actuators_motion_is_the_one_that_gave_it() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let [pose, twist, accel] = motion(&*robot, 3.0);
            let [mut q, mut qd, mut qdd] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            robot.actuator_positions(&pose, &mut q).unwrap();
            robot.joint_velocities(&pose, &twist, &mut qd).unwrap();
            robot
                .joint_accelerations(&pose, &twist, &accel, &mut qdd)
                .unwrap();
            let [mut x, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            robot
                .joint_state([&q, &qd, &qdd], None, [&mut x, &mut v, &mut a])
                .unwrap();
            for i in 0..n {
                assert!((x[i] - pose[i]).abs() < 1e-11, "{}", robot.mechanism());
                assert!((v[i] - twist[i]).abs() < 1e-10, "{}", robot.mechanism());
                assert!((a[i] - accel[i]).abs() < 1e-9, "{}", robot.mechanism());
            }
        }
    }

    #[test]
    fn each_state_gets_its_own_result_and_a_refused_one_is_named() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let mut states: Vec<[Vec<f64>; 3]> =
                (0..6).map(|k| motion(&*robot, k as f64)).collect();
            states[3][0][n - 1] = f64::NAN;
            let fill = |k: usize, out: [&mut [f64]; 3]| {
                for (slot, values) in out.into_iter().zip(&states[k]) {
                    slot.copy_from_slice(values);
                }
            };
            let (mut gamma, mut refused) = (vec![vec![0.0; n]; 6], Vec::new());
            robot.inverse_dynamics_each(6, &fill, &mut |k, result| match result {
                Ok(g) => gamma[k] = g.to_vec(),
                Err(e) => refused.push((k, e)),
            });
            assert_eq!(refused.len(), 1, "{}", robot.mechanism());
            assert_eq!(refused[0].0, 3);
            assert!(matches!(refused[0].1, Error::NonFinite { .. }));
            let mut accel = vec![vec![]; 6];
            let given = |k: usize, out: [&mut [f64]; 3]| {
                let [x, v, g] = out;
                x.copy_from_slice(&states[k][0]);
                v.copy_from_slice(&states[k][1]);
                g.copy_from_slice(&gamma[k]);
            };
            robot.forward_dynamics_each(6, &given, &mut |k, result| {
                if let Ok(a) = result {
                    accel[k] = a.to_vec();
                }
            });
            for (k, [x, v, a]) in states.iter().enumerate().filter(|&(k, _)| k != 3) {
                let mut one = vec![0.0; n];
                robot.inverse_dynamics(x, v, a, &mut one).unwrap();
                assert_eq!(one, gamma[k], "{}", robot.mechanism());
                for i in 0..n {
                    assert!((accel[k][i] - a[i]).abs() < 1e-9, "{}", robot.mechanism());
                }
            }
        }
    }

    #[test]
    fn limits_are_checked_in_any_freedoms_slices_and_a_file_without_them_bounds_nothing() {
        let limited = c5_robot::Robot {
            limits: c5_robot::Limits {
                stroke: Some([[-0.01, 0.01]; 6]),
                speed: Some(0.5),
                force: Some(300.0),
                ..c5_robot::Limits::default()
            },
            ..c5_robot::Robot::default()
        };
        let c5 = load(Description::C5(limited), Model::Consistent).unwrap();
        assert!(c5.has_limits());
        assert_eq!(c5.speed_and_force_limits(), (Some(0.5), Some(300.0)));
        c5.check_limits(&c5.home()).unwrap();
        let mut far = c5.home();
        far[3] += 0.05;
        assert!(matches!(c5.check_limits(&far), Err(Error::Limit { .. })));
        assert!(matches!(
            c5.check_speeds(&[0.1, 0.2, -0.6, 0.0, 0.0, 0.0]),
            Err(Error::Limit { actuator: 3, .. })
        ));
        assert!(matches!(
            c5.check_forces(&[0.0; 3]),
            Err(Error::WrongLength {
                input: "gamma",
                expected: 6,
                got: 3
            })
        ));
        let delta = load(
            Description::Delta(c5_robot::Delta::example()),
            Model::Consistent,
        )
        .unwrap();
        assert!(!delta.has_limits());
        delta.check_limits(&delta.home()).unwrap();
        delta.check_forces(&[1e9; 3]).unwrap();
        assert!(matches!(
            delta.check_speeds(&[0.0; 6]),
            Err(Error::WrongLength {
                input: "qd",
                expected: 3,
                got: 6
            })
        ));
    }

    #[test]
    fn a_slice_of_the_wrong_length_is_refused_and_nothing_is_written() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let [pose, twist, accel] = motion(&*robot, 1.0);
            let mut gamma = vec![7.0; n];
            let short = &pose[..n - 1];
            assert!(matches!(
                robot.inverse_dynamics(short, &twist, &accel, &mut gamma),
                Err(Error::WrongLength { input: "pose", .. })
            ));
            let mut long = vec![7.0; n + 1];
            assert!(matches!(
                robot.inverse_dynamics(&pose, &twist, &accel, &mut long),
                Err(Error::WrongLength { input: "gamma", .. })
            ));
            assert!(gamma.iter().chain(&long).all(|&g| g == 7.0));
        }
    }

    #[test]
    fn a_state_goes_to_the_platforms_coordinates_and_back_and_a_turn_is_refused_by_a_delta() {
        for robot in every_mechanism() {
            let [x, v, a] = motion(&*robot, 2.0);
            let state = robot.state_of([&x, &v, &a]).unwrap();
            assert_eq!(robot.coordinates_of(&state).unwrap(), [x, v, a]);
            let e = robot.evaluate(&state.pose.to_array()[..0], &[], &[]);
            assert!(matches!(e, Err(Error::WrongLength { .. })));
            let mut turned = state;
            turned.twist.omega[1] = 0.1;
            let translating = robot.freedom() == Freedom::Translations;
            assert_eq!(
                robot.coordinates_of(&turned).is_err(),
                translating,
                "{}",
                robot.mechanism()
            );
        }
    }

    /// The joint-space inverse dynamics of the actuators' motion is the inverse dynamics of
    /// the platform's motion that gave it, for every mechanism (the Delta through the provided
    /// method, the others through their own).
    #[test]
    fn the_forces_of_the_actuators_motion_are_those_of_the_platforms() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            for k in 0..4 {
                let [x, v, a] = motion(robot.as_ref(), f64::from(k));
                let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                robot.actuator_positions(&x, &mut q).unwrap();
                robot.joint_velocities(&x, &v, &mut qd).unwrap();
                robot.joint_accelerations(&x, &v, &a, &mut qdd).unwrap();
                let (mut want, mut got) = (vec![0.0; n], vec![0.0; n]);
                robot.inverse_dynamics(&x, &v, &a, &mut want).unwrap();
                robot
                    .inverse_dynamics_joint([&q, &qd, &qdd], Some(&x), &mut got)
                    .unwrap();
                let scale = want.iter().fold(1.0_f64, |m, g| m.max(g.abs()));
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() < 1e-9 * scale,
                        "{}: {got:?} {want:?}",
                        robot.mechanism()
                    );
                }
            }
        }
    }

    /// Every mechanism's task-space terms through slices: `Γ = Jᵀ (M_x V̇ + h)`, and in joint
    /// space `Γ = M_q q̈ + c_q` with `M_q` symmetric; a matrix slot of the wrong size is
    /// refused before anything is written.
    #[test]
    fn the_task_and_joint_space_terms_give_every_mechanisms_forces() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let name = robot.mechanism();
            for k in 0..4 {
                let [x, v, a] = motion(robot.as_ref(), f64::from(k));
                let (mut m_x, mut jac, mut m_q) =
                    (vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]);
                let (mut h, mut gamma, mut q, mut qd, mut qdd) = (
                    vec![0.0; n],
                    vec![0.0; n],
                    vec![0.0; n],
                    vec![0.0; n],
                    vec![0.0; n],
                );
                robot.task_inertia(&x, &mut m_x).unwrap();
                robot.task_bias(&x, &v, &mut h).unwrap();
                robot.jacobian(&x, &mut jac).unwrap();
                robot.inverse_dynamics(&x, &v, &a, &mut gamma).unwrap();
                robot.actuator_positions(&x, &mut q).unwrap();
                robot.joint_velocities(&x, &v, &mut qd).unwrap();
                robot.joint_accelerations(&x, &v, &a, &mut qdd).unwrap();
                robot.joint_inertia(&q, Some(&x), &mut m_q).unwrap();
                let wrench: Vec<f64> = (0..n)
                    .map(|i| (0..n).map(|j| m_x[i * n + j] * a[j]).sum::<f64>() + h[i])
                    .collect();
                let mut bias = vec![0.0; n];
                let rest = vec![0.0; n];
                robot
                    .inverse_dynamics_joint([&q, &qd, &rest], Some(&x), &mut bias)
                    .unwrap();
                let scale = gamma.iter().fold(1.0_f64, |m, g| m.max(g.abs()));
                let inertia = m_q.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
                for i in 0..n {
                    let task: f64 = (0..n).map(|j| jac[j * n + i] * wrench[j]).sum();
                    let joint: f64 = (0..n).map(|j| m_q[i * n + j] * qdd[j]).sum::<f64>() + bias[i];
                    assert!(
                        (task - gamma[i]).abs() < 1e-10 * scale,
                        "{name}: {task} {gamma:?}"
                    );
                    assert!(
                        (joint - gamma[i]).abs() < 1e-9 * scale,
                        "{name}: {joint} {gamma:?}"
                    );
                    for j in 0..n {
                        assert!(
                            (m_q[i * n + j] - m_q[j * n + i]).abs() < 1e-12 * inertia,
                            "{name}"
                        );
                    }
                }
            }
            let mut small = vec![7.0; n * n - 1];
            assert!(matches!(
                robot.task_inertia(&robot.home(), &mut small),
                Err(Error::WrongLength { .. })
            ));
            assert!(small.iter().all(|&m| m == 7.0));
        }
    }

    /// Under the forces that hold the platform at rest, a held step leaves it there; under
    /// more, it moves the way the forward dynamics points.
    #[test]
    fn a_held_step_rests_under_the_holding_forces() {
        for robot in every_mechanism() {
            let n = robot.freedom().dimension();
            let mut pose = robot.home();
            let (rest, mut twist) = (vec![0.0; n], vec![0.0; n]);
            let mut hold = vec![0.0; n];
            robot
                .inverse_dynamics(&pose, &rest, &rest, &mut hold)
                .unwrap();
            let start = pose.clone();
            robot.step_held(&mut pose, &mut twist, &hold, 1e-3).unwrap();
            for i in 0..n {
                assert!((pose[i] - start[i]).abs() < 1e-12, "{}", robot.mechanism());
                assert!(twist[i].abs() < 1e-9, "{}", robot.mechanism());
            }
        }
    }

    /// Through slices, a mechanism's derivatives give the inverse dynamics' forces, and the
    /// forward dynamics' `∂a/∂Γ = M_x⁻¹ J⁻ᵀ` inverts the inverse dynamics' `∂Γ/∂a = Jᵀ M_x`;
    /// a mechanism without them refuses by name; a slot of the wrong size is refused with
    /// nothing written.
    #[cfg(feature = "derivatives")]
    #[test]
    fn the_sliced_derivatives_invert_each_other_or_are_refused_by_name() {
        use crate::derivatives::sliced_derivatives_of;
        for robot in every_mechanism() {
            let (name, n) = (robot.mechanism(), robot.freedom().dimension());
            let Ok(derivatives) = sliced_derivatives_of(&*robot) else {
                let refused = sliced_derivatives_of(&*robot).map(|_| ());
                assert!(robot.derivatives().is_none(), "{name}");
                assert!(
                    matches!(refused, Err(Error::Unsupported { mechanism, .. }) if mechanism == name),
                    "{refused:?}"
                );
                continue;
            };
            let [pose, twist, accel] = motion(&*robot, 1.0);
            let (mut gamma, mut direct) = (vec![0.0; n], vec![0.0; n]);
            let mut by_id = [0; 3].map(|_| vec![0.0; n * n]);
            let [d_pose, d_twist, d_accel] = &mut by_id;
            let motion = [&pose[..], &twist, &accel];
            derivatives
                .inverse_dynamics_derivatives(motion, &mut gamma, [d_pose, d_twist, d_accel])
                .unwrap();
            robot
                .inverse_dynamics(&pose, &twist, &accel, &mut direct)
                .unwrap();
            for (g, d) in gamma.iter().zip(&direct) {
                assert!((g - d).abs() < 1e-12 * (1.0 + d.abs()), "{name}: {gamma:?}");
            }
            let mut found = vec![0.0; n];
            let mut by_fd = [0; 3].map(|_| vec![0.0; n * n]);
            let [f_pose, f_twist, f_gamma] = &mut by_fd;
            derivatives
                .forward_dynamics_derivatives(
                    &pose,
                    &twist,
                    &gamma,
                    &mut found,
                    [f_pose, f_twist, f_gamma],
                )
                .unwrap();
            for (a, want) in found.iter().zip(&accel) {
                assert!((a - want).abs() < 1e-9, "{name}: {found:?}");
            }
            let identity = product(&by_fd[2], &by_id[2], n);
            for (ij, x) in identity.iter().enumerate() {
                let expected = if ij / n == ij % n { 1.0 } else { 0.0 };
                assert!((x - expected).abs() < 1e-9, "{name}: {identity:?}");
            }
            let mut untouched = vec![7.0; n];
            let mut short = vec![0.0; n * n - 1];
            let mut rest = [0; 2].map(|_| vec![0.0; n * n]);
            let [r1, r2] = &mut rest;
            let wrong = derivatives.inverse_dynamics_derivatives(
                motion,
                &mut untouched,
                [r1, &mut short, r2],
            );
            assert!(
                matches!(
                    wrong,
                    Err(Error::WrongLength {
                        input: "d_gamma_d_twist",
                        ..
                    })
                ),
                "{wrong:?}"
            );
            assert!(untouched.iter().all(|&x| x == 7.0), "{name}");
        }
    }
}
