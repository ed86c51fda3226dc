//! One runtime type for every legged mechanism, [`LeggedRobot`]: a validated description, its
//! parameter vector and its home, and the checked calls of its generated kernel set. Each call
//! checks its inputs are finite, calls the kernel, refuses the pose where the kernel's
//! singularity terms say so (naming the term), and its results are finite.

use super::{Coordinates, Hold, Motion};
use crate::error::Error;
use crate::scene::Scene;
use crate::singularity::SingularityTerm;
use crate::{finite, finite_matrix, Acceleration, Evaluation, Pose, State, Twist};
use alloc::vec::Vec;
use c5_generated::legged::{Calibrated, Legs, TaskSpace};

/// A legged mechanism's description as the runtime serves it: which generated kernel set
/// computes it, and what the kernels and the shared code need of it. Each mechanism's entry is
/// in the catalogue (`legged::catalogue`).
pub trait LeggedDescription<const N: usize>:
    Copy + core::fmt::Debug + Send + Sync + 'static
{
    /// The mechanism's generated kernels (with their regressors, for identification).
    #[cfg(not(feature = "identify"))]
    type Kernels: Legs<N> + TaskSpace<N> + Calibrated<N>;
    /// The mechanism's generated kernels (with their regressors, for identification).
    #[cfg(feature = "identify")]
    type Kernels: Legs<N> + TaskSpace<N> + Calibrated<N> + c5_generated::legged::Regressors<N>;
    /// Refuses a description that breaks a rule of its mechanism.
    ///
    /// # Errors
    /// The rule broken, naming the field.
    fn validate(&self) -> Result<(), c5_robot::Error>;
    /// The kernels' parameter vector.
    fn kernel_parameters(&self) -> Vec<f64>;
    /// The home pose; `None` where no pose of the mechanism's kind reaches every leg.
    fn home(&self) -> Option<[f64; N]>;
    /// The description as robot files hold it.
    fn description(&self) -> c5_robot::Description;
    /// Where the forward kinematics' iteration starts without a previous solution: `home`,
    /// unless the mechanism knows a start nearer the actuator positions `q`.
    fn start(&self, _q: &[f64; N], home: &[f64; N]) -> [f64; N] {
        *home
    }
    /// How far from home (rad, m) the seeded states that find the base parameters are drawn.
    #[cfg(feature = "identify")]
    const IDENTIFICATION_REACH: [f64; N];
    /// The standard parameters `π` of this robot with the actuators' `friction`.
    #[cfg(feature = "identify")]
    fn standard_parameters(&self, friction: &[crate::identify::Friction; N]) -> Vec<f64>;
    /// A length of the platform: the mean distance of its joints from `C` (m), what tolerances
    /// on the pose scale with.
    fn characteristic_length(&self) -> f64;
    /// The smallest margin of the description's pose-bound limits at the pose `x` (the limit,
    /// the actuator from 1, the margin and the value); `None` where it sets none.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    fn smallest_pose_margin(
        robot: &LeggedRobot<Self, N>,
        x: &[f64; N],
    ) -> Result<Option<(crate::Limit, usize, f64, f64)>, Error> {
        robot.actuators_at(x).map(|_| None)
    }
    /// The description's bounds on the actuators' speeds and forces, where it sets them.
    fn speed_and_force_limits(&self) -> (Option<f64>, Option<f64>) {
        (None, None)
    }
    /// Whether the description sets any limit.
    fn has_limits(&self) -> bool {
        false
    }
    /// The robot's dynamics' exact derivatives, where the mechanism's derivative kernels are
    /// generated.
    #[cfg(feature = "derivatives")]
    fn derivatives(_robot: &LeggedRobot<Self, N>) -> Option<&dyn crate::mechanism::Derivatives<N>> {
        None
    }
    /// The robot's parts at the pose `x`, for the 3D view.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    fn scene(robot: &LeggedRobot<Self, N>, x: &[f64; N]) -> Result<Scene, Error>;
    /// What a platform free in space adds, where the mechanism's platform is one.
    fn spatial(_robot: &LeggedRobot<Self, N>) -> Option<&dyn crate::mechanism::SpatialRobot> {
        None
    }
}

/// The typed coordinates of a platform with `N` freedoms: its pose, twist, acceleration and
/// state, as the runtime's API takes them. A platform free in space has [`Pose`], [`Twist`],
/// [`Acceleration`] and [`State`]; one that only translates has arrays of three and
/// [`crate::Translation`].
pub trait Freedoms<const N: usize> {
    type Pose: Coordinates<Array = [f64; N]> + Copy + core::fmt::Debug;
    type Twist: Coordinates<Array = [f64; N]>;
    type Acceleration;
    type State: Coordinates<Array = Motion<N>> + Copy + Send + Sync;
    /// Which freedom the platform has: what names its slices' coordinates.
    const FREEDOM: crate::platform::Freedom;
    fn pose(x: [f64; N]) -> Self::Pose;
    fn twist(v: [f64; N]) -> Self::Twist;
    fn acceleration(a: [f64; N]) -> Self::Acceleration;
    fn state(motion: Motion<N>) -> Self::State;
    fn pose_array(pose: &Self::Pose) -> [f64; N];
    fn acceleration_array(a: &Self::Acceleration) -> [f64; N];
    fn state_arrays(state: &Self::State) -> Motion<N>;
}

/// The platform with `N` freedoms, whose [`Freedoms`] name its coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Platform<const N: usize>;

impl Freedoms<6> for Platform<6> {
    type Pose = Pose;
    type Twist = Twist;
    type Acceleration = Acceleration;
    type State = State;
    const FREEDOM: crate::platform::Freedom = crate::platform::Freedom::Free;
    fn pose(x: [f64; 6]) -> Pose {
        Pose::from_array(x)
    }
    fn twist(v: [f64; 6]) -> Twist {
        Twist::from_array(v)
    }
    fn acceleration(a: [f64; 6]) -> Acceleration {
        Acceleration::from_array(a)
    }
    fn state([x, v, a]: Motion<6>) -> State {
        State {
            pose: Pose::from_array(x),
            twist: Twist::from_array(v),
            accel: Acceleration::from_array(a),
        }
    }
    fn pose_array(pose: &Pose) -> [f64; 6] {
        pose.to_array()
    }
    fn acceleration_array(a: &Acceleration) -> [f64; 6] {
        a.to_array()
    }
    fn state_arrays(state: &State) -> Motion<6> {
        [
            state.pose.to_array(),
            state.twist.to_array(),
            state.accel.to_array(),
        ]
    }
}

impl Freedoms<3> for Platform<3> {
    type Pose = [f64; 3];
    type Twist = [f64; 3];
    type Acceleration = [f64; 3];
    type State = crate::Translation;
    const FREEDOM: crate::platform::Freedom = crate::platform::Freedom::Translations;
    fn pose(x: [f64; 3]) -> [f64; 3] {
        x
    }
    fn twist(v: [f64; 3]) -> [f64; 3] {
        v
    }
    fn acceleration(a: [f64; 3]) -> [f64; 3] {
        a
    }
    fn state([position, velocity, acceleration]: Motion<3>) -> crate::Translation {
        crate::Translation {
            position,
            velocity,
            acceleration,
        }
    }
    fn pose_array(pose: &[f64; 3]) -> [f64; 3] {
        *pose
    }
    fn acceleration_array(a: &[f64; 3]) -> [f64; 3] {
        *a
    }
    fn state_arrays(state: &crate::Translation) -> Motion<3> {
        [state.position, state.velocity, state.acceleration]
    }
}

/// The pose type of a platform with `N` freedoms.
pub type PoseOf<const N: usize> = <Platform<N> as Freedoms<N>>::Pose;
/// The twist type of a platform with `N` freedoms.
pub type TwistOf<const N: usize> = <Platform<N> as Freedoms<N>>::Twist;
/// The acceleration type of a platform with `N` freedoms.
pub type AccelerationOf<const N: usize> = <Platform<N> as Freedoms<N>>::Acceleration;
/// The state type of a platform with `N` freedoms.
pub type StateOf<const N: usize> = <Platform<N> as Freedoms<N>>::State;
/// The kernel set of the description `D`.
pub(crate) type KernelsOf<D, const N: usize> = <D as LeggedDescription<N>>::Kernels;
/// The parameter vector of the description `D`'s kernels.
pub type ParametersOf<D, const N: usize> = <KernelsOf<D, N> as Legs<N>>::Parameters;
/// Every singularity term of the description `D`'s kernels.
pub type TermsOf<D, const N: usize> = <KernelsOf<D, N> as Legs<N>>::Terms;

/// A validated legged mechanism: its description `D`, its kernels' parameter vector and its
/// home, served in its platform's `N` coordinates through `D`'s generated kernels. Quantities
/// are in the mechanism's units: the actuators' positions in m or rad, their forces in N or
/// N·m.
#[derive(Clone, Debug)]
pub struct LeggedRobot<D: LeggedDescription<N>, const N: usize> {
    robot: D,
    pub(crate) params: ParametersOf<D, N>,
    home: [f64; N],
}

impl<D: LeggedDescription<N>, const N: usize> LeggedRobot<D, N> {
    /// The mechanism of `robot`.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of its mechanism, or no pose reaches
    /// every leg (without a `home`).
    pub fn new(robot: D) -> Result<Self, Error> {
        robot.validate().map_err(Error::from_robot)?;
        let home = robot.home().ok_or_else(|| Error::Robot {
            field: "home".into(),
            rule: "is missing, and no level pose reaches every leg".into(),
        })?;
        let params =
            KernelsOf::<D, N>::parameters(&robot.kernel_parameters()).ok_or_else(|| {
                Error::Robot {
                    field: "parameters".into(),
                    rule: "do not fit the generated kernels (regenerate them)".into(),
                }
            })?;
        Ok(LeggedRobot {
            robot,
            params,
            home,
        })
    }

    /// The description.
    pub fn robot(&self) -> &D {
        &self.robot
    }

    /// The parameter vector, as the `*_params` kernels take it.
    pub fn parameters(&self) -> &ParametersOf<D, N> {
        &self.params
    }

    /// The home pose's coordinates.
    pub(crate) fn home_array(&self) -> &[f64; N] {
        &self.home
    }

    // The kernel calls on coordinates already checked finite, each checking its singularity
    // terms and its results: what the typed calls below and the shared functions go through.

    /// Refuses the kernel's result where its singularity terms `guard` say so.
    pub(crate) fn checked<T>(&self, (value, guard): (T, impl AsRef<[f64]>)) -> Result<T, Error> {
        crate::singularity::check(guard.as_ref(), KernelsOf::<D, N>::SINGULARITY_TERMS)?;
        Ok(value)
    }

    pub(crate) fn inverse_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        let jinv = self.checked(KernelsOf::<D, N>::inverse_jacobian(x, &self.params))?;
        finite_matrix("jinv", jinv)
    }

    pub(crate) fn jacobian_of(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        let jac = self.checked(KernelsOf::<D, N>::jacobian(x, &self.params))?;
        finite_matrix("jacobian", jac)
    }

    pub(crate) fn rates_at(&self, x: &[f64; N], v: &[f64; N]) -> Result<[f64; N], Error> {
        let qd = self.checked(KernelsOf::<D, N>::joint_velocities(x, v, &self.params))?;
        finite("qd", qd)
    }

    pub(crate) fn accelerations_at(&self, [x, v, a]: &Motion<N>) -> Result<[f64; N], Error> {
        let qdd = self.checked(KernelsOf::<D, N>::joint_accelerations(
            x,
            v,
            a,
            &self.params,
        ))?;
        finite("qdd", qdd)
    }

    pub(crate) fn forces_at(&self, [x, v, a]: &Motion<N>) -> Result<[f64; N], Error> {
        let gamma = self.checked(KernelsOf::<D, N>::inverse_dynamics(x, v, a, &self.params))?;
        finite("gamma", gamma)
    }

    pub(crate) fn accelerated_at(
        &self,
        x: &[f64; N],
        v: &[f64; N],
        gamma: &[f64; N],
    ) -> Result<[f64; N], Error> {
        let (a, guard) = KernelsOf::<D, N>::forward_dynamics(x, v, gamma, &self.params);
        let terms = KernelsOf::<D, N>::SINGULARITY_TERMS;
        crate::singularity::check(guard.as_ref(), terms)?;
        crate::singularity::check_conditioned(
            "forward dynamics",
            guard.as_ref(),
            terms,
            crate::singularity::TermKind::UJoint,
            crate::singularity::FORWARD_U_JOINT_TOLERANCE,
        )?;
        finite("acceleration", a)
    }

    pub(crate) fn inertia_of(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        let m = self.checked(KernelsOf::<D, N>::task_inertia(x, &self.params))?;
        finite_matrix("task inertia", m)
    }

    /// The actuator positions at the pose `x`.
    pub(crate) fn actuators_at(&self, x: &[f64; N]) -> Result<[f64; N], Error> {
        let q = self.checked(KernelsOf::<D, N>::actuators(x, &self.params))?;
        finite("q", q)
    }
}

impl<D: LeggedDescription<N>, const N: usize> LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
{
    /// The home pose: the file's, or the level pose nearest the actuators' zero; where the
    /// forward kinematics starts without a previous solution.
    pub fn home(&self) -> PoseOf<N> {
        Platform::<N>::pose(self.home)
    }

    /// The singularity terms at `pose` (what each is, the kernels' `SINGULARITY_TERMS` says):
    /// the joints' and cranks' terms, then the legs' hold (zero at a parallel singularity).
    ///
    /// # Errors
    /// A non-finite pose.
    pub fn singularity_terms(&self, pose: &PoseOf<N>) -> Result<TermsOf<D, N>, Error> {
        let x = pose.checked("pose")?;
        Ok(KernelsOf::<D, N>::singularity_terms(&x, &self.params))
    }

    /// `J⁻¹` (`q̇ = J⁻¹ V`), row `i` for actuator `i+1`, columns the twist's.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn inverse_jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        self.inverse_at(&pose.checked("pose")?)
    }

    /// `J = (J⁻¹)⁻¹`, rows the twist's, column `i` for actuator `i+1`.
    ///
    /// # Errors
    /// A non-finite or singular pose, or the legs' hold.
    pub fn jacobian(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        self.jacobian_of(&pose.checked("pose")?)
    }

    /// `q̇ = J⁻¹ V`.
    ///
    /// # Errors
    /// Non-finite inputs, or a singular pose.
    pub fn joint_velocities(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
    ) -> Result<[f64; N], Error> {
        self.rates_at(&pose.checked("pose")?, &twist.checked("twist")?)
    }

    /// `q̈`, the actuator positions' second derivatives along the platform's motion.
    ///
    /// # Errors
    /// Non-finite inputs, or a singular pose.
    pub fn joint_accelerations(&self, state: &StateOf<N>) -> Result<[f64; N], Error> {
        self.accelerations_at(&state.checked("state")?)
    }

    /// The actuator forces `Γ` for the platform to follow `state`: the platform's and the
    /// legs' bodies' Newton-Euler equations, by virtual work.
    ///
    /// # Errors
    /// Non-finite inputs, or a singular pose or hold.
    pub fn inverse_dynamics(&self, state: &StateOf<N>) -> Result<[f64; N], Error> {
        self.forces_at(&state.checked("state")?)
    }

    /// The forward dynamics: the platform's acceleration under the actuator forces `gamma`.
    ///
    /// # Errors
    /// Non-finite inputs, a singular pose, a U joint too near its singularity for the
    /// acceleration's bound ([`Error::IllConditioned`],
    /// [`crate::singularity::FORWARD_U_JOINT_TOLERANCE`]), or a non-finite result.
    pub fn forward_dynamics(
        &self,
        pose: &PoseOf<N>,
        twist: &TwistOf<N>,
        gamma: &[f64; N],
    ) -> Result<AccelerationOf<N>, Error> {
        let (x, v) = (pose.checked("pose")?, twist.checked("twist")?);
        crate::check_finite("gamma", gamma)?;
        Ok(Platform::<N>::acceleration(
            self.accelerated_at(&x, &v, gamma)?,
        ))
    }

    /// `M_x` of `Γ = Jᵀ (M_x V̇ + h)`, symmetric positive definite.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn task_inertia(&self, pose: &PoseOf<N>) -> Result<[[f64; N]; N], Error> {
        self.inertia_of(&pose.checked("pose")?)
    }

    /// `h` of `Γ = Jᵀ (M_x V̇ + h)`: the Coriolis, centrifugal and gravity terms at `C`.
    ///
    /// # Errors
    /// Non-finite inputs, or a singular pose.
    pub fn task_bias(&self, pose: &PoseOf<N>, twist: &TwistOf<N>) -> Result<[f64; N], Error> {
        let (x, v) = (pose.checked("pose")?, twist.checked("twist")?);
        let h = self.checked(KernelsOf::<D, N>::task_bias(&x, &v, &self.params))?;
        finite("task bias", h)
    }

    /// The robot's parts at `pose`, for the 3D view.
    ///
    /// # Errors
    /// A non-finite or singular pose.
    pub fn scene(&self, pose: &PoseOf<N>) -> Result<Scene, Error> {
        D::scene(self, &pose.checked("pose")?)
    }
}

impl<D: LeggedDescription<N>, const N: usize> LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
    Self: super::Locate<N>,
{
    /// The platform's state from the actuators' positions, rates and accelerations: the
    /// forward kinematics (from `near`, where the mechanism iterates), `V = J q̇`, and the
    /// acceleration `J (q̈ - b)` with `b` the actuators' accelerations at zero platform
    /// acceleration.
    ///
    /// # Errors
    /// As the forward kinematics, a singular pose, or [`Error::IllConditioned`] for nonzero
    /// rates or accelerations where the legs' hold is below
    /// [`super::JOINT_STATE_HOLD_TOLERANCE`].
    pub fn joint_state(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<StateOf<N>, Error> {
        let near = near.map(|x| x.checked("near")).transpose()?;
        super::joint_state(self, &[*q, *qd, *qdd], near.as_ref()).map(Platform::<N>::state)
    }

    /// The actuator forces from the actuators' motion: the inverse dynamics at the platform
    /// state of [`LeggedRobot::joint_state`], served down to the legs' hold tolerance (the
    /// forces stay accurate where the platform's acceleration does not).
    ///
    /// # Errors
    /// As the forward kinematics, or a singular pose.
    pub fn inverse_dynamics_joint(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        qdd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error> {
        let near = near.map(|x| x.checked("near")).transpose()?;
        super::inverse_dynamics_joint(self, &[*q, *qd, *qdd], near.as_ref())
    }

    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia `Jᵀ M_x J`, at the pose of the
    /// actuator positions `q` (found from `near`, where the mechanism iterates).
    ///
    /// # Errors
    /// As the forward kinematics, or a singular pose.
    pub fn joint_inertia(
        &self,
        q: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[[f64; N]; N], Error> {
        let near = near.map(|x| x.checked("near")).transpose()?;
        super::joint_inertia(self, q, near.as_ref())
    }

    /// `c_q` of `Γ = M_q q̈ + c_q`: the forces at zero actuator acceleration.
    ///
    /// # Errors
    /// As [`LeggedRobot::joint_state`].
    pub fn joint_bias(
        &self,
        q: &[f64; N],
        qd: &[f64; N],
        near: Option<&PoseOf<N>>,
    ) -> Result<[f64; N], Error> {
        self.inverse_dynamics_joint(q, qd, &[0.0; N], near)
    }

    /// Everything `eval` reports for one state.
    ///
    /// # Errors
    /// Non-finite inputs or a singular pose.
    pub fn evaluate(&self, state: &StateOf<N>) -> Result<Evaluation<N>, Error> {
        super::evaluate(self, &state.checked("state")?)
    }
}

/// What the shared functions of the legged mechanisms read of one: its kernels, through the
/// checked calls above.
impl<D: LeggedDescription<N>, const N: usize> super::Legged<N> for LeggedRobot<D, N>
where
    Platform<N>: Freedoms<N>,
    Self: super::Locate<N>,
{
    fn actuators(&self, x: &[f64; N]) -> Result<[f64; N], Error> {
        self.actuators_at(x)
    }
    fn rates(&self, x: &[f64; N], v: &[f64; N]) -> Result<[f64; N], Error> {
        self.rates_at(x, v)
    }
    fn accelerations(&self, motion: &Motion<N>) -> Result<[f64; N], Error> {
        self.accelerations_at(motion)
    }
    fn forces(&self, motion: &Motion<N>) -> Result<[f64; N], Error> {
        self.forces_at(motion)
    }
    fn inverse(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        self.inverse_at(x)
    }
    fn jacobian_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        self.jacobian_of(x)
    }
    fn inertia_at(&self, x: &[f64; N]) -> Result<[[f64; N]; N], Error> {
        self.inertia_of(x)
    }
}

/// The weakest of the legs' hold terms among `terms` (the pivot ratios of the legs' solve, or
/// the arms' determinant ratio), each against its bound on the platform's motion.
pub(crate) fn hold_of<D: LeggedDescription<N>, const N: usize>(terms: &TermsOf<D, N>) -> Hold {
    use crate::singularity::TermKind;
    let against_bound =
        |(value, term): &(f64, &SingularityTerm)| value / super::joint_state_bound(term.kind);
    terms
        .as_ref()
        .iter()
        .zip(KernelsOf::<D, N>::SINGULARITY_TERMS)
        .filter(|(_, term)| matches!(term.kind, TermKind::Pivot | TermKind::Hold))
        .map(|(&value, term)| (value, term))
        .min_by(|a, b| against_bound(a).total_cmp(&against_bound(b)))
}
