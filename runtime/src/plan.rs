//! Minimum-effort motion planning (feature `plan`): a rest-to-rest move between two poses in a
//! given time, actuator forces within a limit, by iLQR on the forward dynamics and its exact
//! Jacobians ([`SlicedDerivatives::forward_dynamics_derivatives`]), with an augmented
//! Lagrangian for the goal, the force limits and the clearance from singular poses. It plans
//! for every robot whose mechanism has its derivatives generated (the C5, the Gough-Stewart
//! platform and the Delta), in its platform's own coordinates ([`Mechanism::freedom`]).
//!
//! The state is `s = (X, V)`: the pose (`[α β γ xc yc zc]`, or `[xc yc zc]` for a platform
//! that only translates) and the twist (`(ω; v_C)`, or `v_C`); the control the forces `Γ`.
//! The dynamics `ṡ = (Ẋ(X, V), a(X, V, Γ))`, with `Ẋ = (Ė(X)⁻¹ ω, v_C)` where the platform
//! turns (`E` the map from RPY rates to `ω`, `ω = α̇ x + β̇ Rx(α) y + γ̇ Rx(α) Ry(β) z`) and
//! `Ẋ = v_C` where it translates, is integrated by explicit Euler at the plan's step. The cost
//! is the effort `½ Σ_k dt |Γ_k|² / σ²` (`σ` = [`EFFORT_SCALE`]); the goal `s_N = (X_goal, 0)`
//! the limits `|Γ_i| ≤ Γ_max` and the workspace `c(X_k) ≥ c_min` at every step (`c` the
//! [`Mechanism::singularity_clearance`]) are constraints, held by an augmented Lagrangian
//! (multipliers updated between iLQR solves, penalties raised while a constraint is not met),
//! so the plan ends at the goal to the tolerance asked for, not merely near it.
//!
//! The workspace constraint is there because a minimum-effort path seeks singular poses: where
//! a Delta's crank and rods align, the arm holds the platform's weight with no torque, so an
//! unconstrained plan sags towards that edge of the reach, where the dynamics' Jacobians grow
//! without bound and no step makes progress.

use crate::derivatives::{sliced_derivatives_of, SlicedDerivatives};
use crate::platform::{Freedom, Mechanism};
use crate::trajectory::state_from_pose_derivatives;
use crate::{Error, State};
use nalgebra::{SMatrix, SVector};

/// Forces are weighed in units of this (N or N·m) in the effort. (Scaled by the robot's own
/// forces instead, the RMS of the quintic move's, the goal's first penalty is too weak: the
/// C5's plan took 102 iterations instead of 39, and the example Delta's sagged out of reach.)
pub const EFFORT_SCALE: f64 = 100.0;

/// An iLQR solve of the first augmented-Lagrangian round stops when a full step gains, or the
/// model promises, less than this fraction of the cost; each later round asks ten times more,
/// down to [`FINEST_TOLERANCE`], as the constraints' terms shrink.
const FIRST_TOLERANCE: f64 = 1e-4;
const FINEST_TOLERANCE: f64 = 1e-13;

/// The default of [`Problem::least_clearance`]: a crank at least 0.1 rad (5.7°) from aligned
/// with its rods (the reach term is the squared sine of their angle), a hundredth of the C5's
/// `|r_ii|` at home. The C5's and the hexapod's plans of Section 9's move keep above it
/// unconstrained (their least clearance is 0.025 and 0.097); the example Delta's does not.
pub const LEAST_CLEARANCE: f64 = 0.01;

/// A rest-to-rest move to plan, its poses in the platform's coordinates
/// ([`Freedom::pose_names`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub start: Vec<f64>,
    pub goal: Vec<f64>,
    /// The move's duration (s).
    pub duration: f64,
    /// Steps of the plan (its forces are held over each, `dt = duration / steps`).
    pub steps: usize,
    /// `|Γ_i| ≤ force_limit` (N) for every actuator at every step, if given.
    pub force_limit: Option<f64>,
    /// The [`Mechanism::singularity_clearance`] every pose of the plan keeps, at least (its
    /// terms are about 1 far from a singular pose and 0 at it): the workspace the plan stays
    /// in. [`LEAST_CLEARANCE`] by default; 0 keeps the plan within reach only.
    pub least_clearance: f64,
}

/// When the planner stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The largest `|s_N - s_goal|` accepted (rad, m, rad/s, m/s).
    pub goal_tolerance: f64,
    /// The largest excess over the force limit accepted (N).
    pub force_tolerance: f64,
    /// The largest shortfall of a pose's clearance below [`Problem::least_clearance`].
    pub clearance_tolerance: f64,
    /// iLQR iterations at most, all augmented-Lagrangian rounds together.
    pub max_iterations: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            goal_tolerance: 1e-8,
            force_tolerance: 1e-6,
            clearance_tolerance: 1e-6,
            max_iterations: 500,
        }
    }
}

/// A planned move.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// `t_k = k dt`, `steps + 1` of them.
    pub times: Vec<f64>,
    /// The state at each time, its acceleration the one the forces give (zero at the end),
    /// as [`Mechanism::state_of`] gives it.
    pub states: Vec<State>,
    /// The forces held over each step (N, actuator order), `steps` of them.
    pub forces: Vec<Vec<f64>>,
    /// iLQR iterations taken (backward and forward passes).
    pub iterations: usize,
    /// Per round of the augmented Lagrangian, the objective after each accepted iLQR
    /// iteration (the effort plus the round's constraint terms): strictly decreasing in a round.
    pub costs: Vec<Vec<f64>>,
    /// `|s_N - s_goal|∞` reached.
    pub goal_error: f64,
    /// The largest `|Γ_i| - Γ_max` over the plan (≤ 0 inside the limit).
    pub force_excess: f64,
    /// The least [`Mechanism::singularity_clearance`] over the plan's poses.
    pub least_clearance: f64,
}

/// Why a plan failed.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanError {
    /// The problem is not well posed (named field and rule).
    Invalid(&'static str),
    /// The dynamics refused a state on the way (a singular pose).
    Dynamics(Error),
    /// The iterations ran out before the goal and the limits were met.
    NotConverged {
        goal_error: f64,
        force_excess: f64,
        /// The least clearance the last plan reached.
        least_clearance: f64,
    },
}

impl core::fmt::Display for PlanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PlanError::Invalid(why) => write!(f, "invalid plan: {why}"),
            PlanError::Dynamics(e @ Error::Unsupported { .. }) => write!(f, "cannot plan: {e}"),
            PlanError::Dynamics(e) => {
                write!(f, "the plan reached a state the dynamics refuses: {e}")
            }
            PlanError::NotConverged {
                goal_error,
                force_excess,
                least_clearance,
            } => {
                write!(
                    f,
                    "no plan met the goal and the limits in the iterations allowed (goal \
                     error {goal_error:e}, "
                )?;
                if force_excess.is_finite() {
                    write!(f, "force excess {force_excess:e} N, ")?;
                }
                write!(f, "least clearance {least_clearance:e})")
            }
        }
    }
}

impl std::error::Error for PlanError {}

/// `(α̇ β̇ γ̇) = E⁻¹ ω` and its Jacobians with respect to the angles and to `ω`.
fn rpy_rates(angles: [f64; 3], w: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3], [[f64; 3]; 3]) {
    let (sa, ca) = angles[0].sin_cos();
    let (sb, cb) = angles[1].sin_cos();
    let beta_dot = ca * w[1] + sa * w[2];
    let gamma_dot = (-sa * w[1] + ca * w[2]) / cb;
    let alpha_dot = w[0] - sb * gamma_dot;
    // ∂γ̇ with respect to α, β; ∂β̇ with respect to α.
    let dg_da = (-ca * w[1] - sa * w[2]) / cb;
    let dg_db = gamma_dot * sb / cb;
    let db_da = -sa * w[1] + ca * w[2];
    let d_angles = [
        [-sb * dg_da, -cb * gamma_dot - sb * dg_db, 0.0],
        [db_da, 0.0, 0.0],
        [dg_da, dg_db, 0.0],
    ];
    let d_omega = [
        [1.0, sb * sa / cb, -sb * ca / cb],
        [0.0, ca, sa],
        [0.0, -sa / cb, ca / cb],
    ];
    ([alpha_dot, beta_dot, gamma_dot], d_angles, d_omega)
}

/// `Ẋ` of the platform's pose `X` and twist `V`, with `∂Ẋ/∂X` and `∂Ẋ/∂V`: the centre's
/// rate is `v_C`; where the platform turns, the angles' rates are `E⁻¹ ω` ([`rpy_rates`]).
fn pose_rates<const N: usize>(
    freedom: Freedom,
    pose: &[f64],
    twist: &[f64],
) -> (SVector<f64, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let mut rates = SVector::<f64, N>::from_column_slice(twist);
    let mut d_pose = SMatrix::<f64, N, N>::zeros();
    let mut d_twist = SMatrix::<f64, N, N>::identity();
    if freedom.turns() {
        // The angles and `ω` come first in a turning platform's coordinates.
        let (r, d_angles, d_omega) =
            rpy_rates([pose[0], pose[1], pose[2]], [twist[0], twist[1], twist[2]]);
        for i in 0..3 {
            rates[i] = r[i];
            for j in 0..3 {
                d_pose[(i, j)] = d_angles[i][j];
                d_twist[(i, j)] = d_omega[i][j];
            }
        }
    }
    (rates, d_pose, d_twist)
}

/// The plan's model of the robot: its forward dynamics with their Jacobians, in the
/// platform's `N` coordinates, and its clearance from singular poses; the state has `M = 2N`.
struct Model<'a> {
    robot: &'a dyn Mechanism,
    freedom: Freedom,
    derivatives: &'a dyn SlicedDerivatives,
}

/// The step of the clearance's central differences (rad, m): its terms are smooth at the
/// scale of the robot's links, so their error is about `h²/L²`.
const CLEARANCE_STEP: f64 = 1e-6;

/// One linearised Euler step: `s' = s + dt f(s, u)`, `A = ∂s'/∂s`, `B = ∂s'/∂u`, and the
/// acceleration the forces give.
struct Step<const N: usize, const M: usize> {
    next: SVector<f64, M>,
    a: SMatrix<f64, M, M>,
    b: SMatrix<f64, M, N>,
    accel: [f64; N],
}

impl Model<'_> {
    /// The clearance of the pose of `s` (`+∞` for a pose it cannot judge, a non-finite one,
    /// which the dynamics refuse before).
    fn clearance<const M: usize>(&self, s: &SVector<f64, M>) -> f64 {
        self.robot
            .singularity_clearance(&s.as_slice()[..M / 2])
            .unwrap_or(f64::INFINITY)
    }

    /// The least clearance over `states`.
    fn least_clearance<const M: usize>(&self, states: &[SVector<f64, M>]) -> f64 {
        states
            .iter()
            .map(|s| self.clearance(s))
            .fold(f64::INFINITY, f64::min)
    }

    /// `∂c/∂s` of [`Model::clearance`] by central differences (zero in the twist's part).
    fn clearance_gradient<const M: usize>(&self, s: &SVector<f64, M>) -> SVector<f64, M> {
        SVector::from_fn(|j, _| {
            if j >= M / 2 {
                return 0.0;
            }
            let (mut up, mut down) = (*s, *s);
            up[j] += CLEARANCE_STEP;
            down[j] -= CLEARANCE_STEP;
            (self.clearance(&up) - self.clearance(&down)) / (2.0 * CLEARANCE_STEP)
        })
    }

    /// The Euler step `s + dt f(s, u)` with its Jacobians.
    fn step<const N: usize, const M: usize>(
        &self,
        s: &SVector<f64, M>,
        u: &SVector<f64, N>,
        dt: f64,
    ) -> Result<Step<N, M>, Error> {
        let (pose, twist) = s.as_slice().split_at(N);
        let mut accel = [0.0; N];
        let [mut d_pose, mut d_twist, mut d_gamma] = [[[0.0; N]; N]; 3];
        self.derivatives.forward_dynamics_derivatives(
            pose,
            twist,
            u.as_slice(),
            &mut accel,
            [
                d_pose.as_flattened_mut(),
                d_twist.as_flattened_mut(),
                d_gamma.as_flattened_mut(),
            ],
        )?;
        let (rates, rates_pose, rates_twist) = pose_rates::<N>(self.freedom, pose, twist);
        let matrix = |m: &[[f64; N]; N]| SMatrix::<f64, N, N>::from_fn(|i, j| m[i][j]);
        let mut f = SVector::<f64, M>::zeros();
        f.fixed_rows_mut::<N>(0).copy_from(&rates);
        f.fixed_rows_mut::<N>(N).copy_from_slice(&accel);
        let mut fs = SMatrix::<f64, M, M>::zeros();
        fs.fixed_view_mut::<N, N>(0, 0).copy_from(&rates_pose);
        fs.fixed_view_mut::<N, N>(0, N).copy_from(&rates_twist);
        fs.fixed_view_mut::<N, N>(N, 0).copy_from(&matrix(&d_pose));
        fs.fixed_view_mut::<N, N>(N, N).copy_from(&matrix(&d_twist));
        let mut fu = SMatrix::<f64, M, N>::zeros();
        fu.fixed_view_mut::<N, N>(N, 0).copy_from(&matrix(&d_gamma));
        Ok(Step {
            next: s + f * dt,
            a: SMatrix::<f64, M, M>::identity() + fs * dt,
            b: fu * dt,
            accel,
        })
    }
}

/// The augmented Lagrangian's state: multipliers and penalties of the goal and the limits,
/// for `N` actuators and a state of `M = 2N`.
struct Lagrangian<const N: usize, const M: usize> {
    /// The plan's step (s).
    dt: f64,
    /// `dt / σ²`: the effort's weight of `½ |Γ_k|²` at each step.
    effort_weight: f64,
    goal: SVector<f64, M>,
    goal_multiplier: SVector<f64, M>,
    goal_penalty: f64,
    limit: Option<f64>,
    /// Per step, the multipliers of `u - Γmax ≤ 0` (first `N`) and `-u - Γmax ≤ 0`: `2N = M`
    /// of them.
    limit_multipliers: Vec<SVector<f64, M>>,
    limit_penalty: f64,
    /// `c_min - c(X_k) ≤ 0` at every state: the bound, a multiplier a state, the penalty.
    least_clearance: f64,
    clearance_multipliers: Vec<f64>,
    clearance_penalty: f64,
}

/// A state's term in the objective, `∂ℓ/∂s` and (Gauss-Newton) `∂²ℓ/∂s²`.
type StateTerm<const M: usize> = (SVector<f64, M>, SMatrix<f64, M, M>);

impl<const N: usize, const M: usize> Lagrangian<N, M> {
    /// The multipliers the limits' penalty acts with at `u`, `max(0, λ + ρ c)` of the
    /// constraint values `c ≤ 0`.
    fn active_limits(&self, k: usize, u: &SVector<f64, N>) -> Option<SVector<f64, M>> {
        let limit = self.limit?;
        let c = SVector::<f64, M>::from_fn(|i, _| {
            if i < N {
                u[i] - limit
            } else {
                -u[i - N] - limit
            }
        });
        Some((self.limit_multipliers[k] + c * self.limit_penalty).map(|x| x.max(0.0)))
    }

    /// The stage cost at step `k`: effort plus the limits' augmented terms.
    fn stage(&self, k: usize, u: &SVector<f64, N>) -> f64 {
        let mut cost = 0.5 * self.effort_weight * u.norm_squared();
        if let Some(active) = self.active_limits(k, u) {
            let lambda = &self.limit_multipliers[k];
            cost += (active.norm_squared() - lambda.norm_squared()) / (2.0 * self.limit_penalty);
        }
        cost
    }

    /// `∂ℓ/∂u`, `∂²ℓ/∂u²` of [`Lagrangian::stage`].
    fn stage_derivatives(
        &self,
        k: usize,
        u: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let w = self.effort_weight;
        let mut lu = u * w;
        let mut luu = SMatrix::<f64, N, N>::identity() * w;
        if let Some(active) = self.active_limits(k, u) {
            for i in 0..N {
                lu[i] += active[i] - active[N + i];
                for on in [active[i] > 0.0, active[N + i] > 0.0] {
                    if on {
                        luu[(i, i)] += self.limit_penalty;
                    }
                }
            }
        }
        (lu, luu)
    }

    /// The multiplier the clearance's penalty acts with at state `k` of clearance `c`,
    /// `max(0, λ + ρ (c_min - c))`.
    fn active_clearance(&self, k: usize, clearance: f64) -> f64 {
        let violation = self.least_clearance - clearance;
        (self.clearance_multipliers[k] + self.clearance_penalty * violation).max(0.0)
    }

    /// The clearance's augmented term at state `k`.
    fn clearance_term(&self, k: usize, clearance: f64) -> f64 {
        let (active, lambda) = (
            self.active_clearance(k, clearance),
            self.clearance_multipliers[k],
        );
        (active * active - lambda * lambda) / (2.0 * self.clearance_penalty)
    }

    /// Each state's clearance term's derivatives, `None` where the term is flat (the state
    /// clear of the bound and its multiplier zero): the gradient only where it acts.
    fn state_terms(&self, model: &Model, states: &[SVector<f64, M>]) -> Vec<Option<StateTerm<M>>> {
        states
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let active = self.active_clearance(k, model.clearance(s));
                (active > 0.0).then(|| {
                    let g = -model.clearance_gradient(s);
                    (g * active, g * g.transpose() * self.clearance_penalty)
                })
            })
            .collect()
    }

    fn terminal(&self, s: &SVector<f64, M>) -> f64 {
        let e = s - self.goal;
        self.goal_multiplier.dot(&e) + 0.5 * self.goal_penalty * e.norm_squared()
    }

    fn total(
        &self,
        model: &Model,
        states: &[SVector<f64, M>],
        controls: &[SVector<f64, N>],
    ) -> f64 {
        let effort: f64 = controls
            .iter()
            .enumerate()
            .map(|(k, u)| self.stage(k, u))
            .sum();
        let clearance: f64 = states
            .iter()
            .enumerate()
            .map(|(k, s)| self.clearance_term(k, model.clearance(s)))
            .sum();
        effort + clearance + self.terminal(&states[states.len() - 1])
    }

    fn force_excess(&self, controls: &[SVector<f64, N>]) -> f64 {
        match self.limit {
            Some(limit) => controls
                .iter()
                .flat_map(|u| u.iter().map(|x| x.abs() - limit))
                .fold(f64::NEG_INFINITY, f64::max),
            None => f64::NEG_INFINITY,
        }
    }
}

/// The states of the controls from `s0`.
fn rollout<const N: usize, const M: usize>(
    model: &Model,
    s0: &SVector<f64, M>,
    controls: &[SVector<f64, N>],
    dt: f64,
) -> Result<Vec<SVector<f64, M>>, Error> {
    let mut states = Vec::with_capacity(controls.len() + 1);
    states.push(*s0);
    for u in controls {
        let next = model.step(&states[states.len() - 1], u, dt)?.next;
        states.push(next);
    }
    Ok(states)
}

/// A backward pass's policy: per step the feedback gains and the feedforward, and the cost
/// change its model promises.
struct Policy<const N: usize, const M: usize> {
    gains: Vec<SMatrix<f64, N, M>>,
    feedforward: Vec<SVector<f64, N>>,
    expected: f64,
}

/// The backward pass along the linearisation `(A_k, B_k)` with a Levenberg-Marquardt shift of
/// `Q_uu`; `None` where a `Q_uu` is not positive definite.
fn backward<const N: usize, const M: usize>(
    al: &Lagrangian<N, M>,
    states: &[SVector<f64, M>],
    controls: &[SVector<f64, N>],
    linear: &[(SMatrix<f64, M, M>, SMatrix<f64, M, N>)],
    state_terms: &[Option<StateTerm<M>>],
    shift: f64,
) -> Option<Policy<N, M>> {
    let n = controls.len();
    let e = states[n] - al.goal;
    let mut vx = al.goal_multiplier + e * al.goal_penalty;
    let mut vxx = SMatrix::<f64, M, M>::identity() * al.goal_penalty;
    let with_state_term =
        |k: usize, (lx, lxx): (SVector<f64, M>, SMatrix<f64, M, M>)| match &state_terms[k] {
            Some((sx, sxx)) => (lx + sx, lxx + sxx),
            None => (lx, lxx),
        };
    (vx, vxx) = with_state_term(n, (vx, vxx));
    let mut gains = vec![SMatrix::<f64, N, M>::zeros(); n];
    let mut feedforward = vec![SVector::<f64, N>::zeros(); n];
    let mut expected = 0.0;
    for k in (0..n).rev() {
        let (a, b) = &linear[k];
        let (lu, luu) = al.stage_derivatives(k, &controls[k]);
        let (qx, qxx) = with_state_term(k, (a.transpose() * vx, a.transpose() * vxx * a));
        let qu = lu + b.transpose() * vx;
        let vxx_b = vxx * b;
        let quu = luu + b.transpose() * vxx_b + SMatrix::<f64, N, N>::identity() * shift;
        let qux = vxx_b.transpose() * a;
        let chol = quu.cholesky()?;
        let kk = -chol.solve(&qux);
        let ff = -chol.solve(&qu);
        expected += ff.dot(&qu);
        vx = qx + kk.transpose() * (quu * ff) + kk.transpose() * qu + qux.transpose() * ff;
        vxx = qxx + kk.transpose() * quu * kk + kk.transpose() * qux + qux.transpose() * kk;
        vxx = (vxx + vxx.transpose()) * 0.5;
        gains[k] = kk;
        feedforward[k] = ff;
    }
    Some(Policy {
        gains,
        feedforward,
        expected,
    })
}

/// The forward pass of `policy` at `step_size` from the current trajectory: the new states and
/// controls, `None` where the dynamics refuse a state on the way.
type Trajectory<const N: usize, const M: usize> = (Vec<SVector<f64, M>>, Vec<SVector<f64, N>>);

fn forward<const N: usize, const M: usize>(
    model: &Model,
    policy: &Policy<N, M>,
    states: &[SVector<f64, M>],
    controls: &[SVector<f64, N>],
    step_size: f64,
    dt: f64,
) -> Option<Trajectory<N, M>> {
    let n = controls.len();
    let mut new_states = Vec::with_capacity(n + 1);
    let mut new_controls = Vec::with_capacity(n);
    new_states.push(states[0]);
    for k in 0..n {
        let u = controls[k]
            + policy.feedforward[k] * step_size
            + policy.gains[k] * (new_states[k] - states[k]);
        new_states.push(model.step(&new_states[k], &u, dt).ok()?.next);
        new_controls.push(u);
    }
    Some((new_states, new_controls))
}

/// One iLQR solve of the current augmented Lagrangian: backward passes with a
/// Levenberg-Marquardt shift of `Q_uu`, forward passes with a line search, until a full step
/// gains or promises less than `tolerance` of the cost. Returns the iterations spent.
fn ilqr<const N: usize, const M: usize>(
    model: &Model,
    al: &Lagrangian<N, M>,
    states: &mut Vec<SVector<f64, M>>,
    controls: &mut Vec<SVector<f64, N>>,
    budget: usize,
    tolerance: f64,
    costs: &mut Vec<f64>,
) -> Result<usize, Error> {
    let dt = al.dt;
    let mut cost = al.total(model, states, controls);
    let mut shift = 1e-9;
    let mut iterations = 0;
    while iterations < budget {
        iterations += 1;
        let linear = states
            .iter()
            .zip(controls.iter())
            .map(|(s, u)| model.step(s, u, dt).map(|step| (step.a, step.b)))
            .collect::<Result<Vec<_>, _>>()?;
        let state_terms = al.state_terms(model, states);
        let policy = loop {
            if let Some(policy) = backward(al, states, controls, &linear, &state_terms, shift) {
                break policy;
            }
            shift = (shift * 10.0).max(1e-6);
            if shift > 1e10 {
                return Ok(iterations);
            }
        };
        // Forward passes with a line search on the step.
        let mut accepted = false;
        let mut step_size = 1.0;
        while step_size > 1e-4 {
            if let Some((new_states, new_controls)) =
                forward(model, &policy, states, controls, step_size, dt)
            {
                let new_cost = al.total(model, &new_states, &new_controls);
                if new_cost < cost {
                    let gain = cost - new_cost;
                    *states = new_states;
                    *controls = new_controls;
                    cost = new_cost;
                    costs.push(cost);
                    accepted = true;
                    shift = (shift / 10.0).max(1e-9);
                    // This round is solved well enough when a full step gains, or the model
                    // promises, less than `tolerance` of the cost: the multipliers' update then
                    // does more than further iterations would.
                    let small = tolerance * cost.abs();
                    if (step_size == 1.0 && gain <= small) || -policy.expected <= small {
                        return Ok(iterations);
                    }
                    break;
                }
            }
            step_size *= 0.5;
        }
        if !accepted {
            shift = (shift * 10.0).max(1e-6);
            if shift > 1e10 || -policy.expected <= tolerance * cost.abs() {
                return Ok(iterations);
            }
        }
    }
    Ok(iterations)
}

/// The problem's refusals: a duration, steps, limit or poses that cannot be planned.
fn check(problem: &Problem, freedom: Freedom) -> Result<(), PlanError> {
    if !(problem.duration > 0.0 && problem.duration.is_finite()) {
        return Err(PlanError::Invalid("`duration` must be positive and finite"));
    }
    if problem.steps < 2 {
        return Err(PlanError::Invalid("`steps` must be at least 2"));
    }
    if problem
        .force_limit
        .is_some_and(|l| !(l > 0.0 && l.is_finite()))
    {
        return Err(PlanError::Invalid(
            "`force_limit` must be positive and finite",
        ));
    }
    if !(problem.least_clearance >= 0.0 && problem.least_clearance.is_finite()) {
        return Err(PlanError::Invalid(
            "`least_clearance` must be finite and not negative",
        ));
    }
    let n = freedom.dimension();
    if problem.start.len() != n || problem.goal.len() != n {
        return Err(PlanError::Invalid(
            "the start and goal poses must have the platform's coordinates",
        ));
    }
    if !problem
        .start
        .iter()
        .chain(&problem.goal)
        .all(|x| x.is_finite())
    {
        return Err(PlanError::Invalid(
            "the start and goal poses must be finite",
        ));
    }
    Ok(())
}

/// Plans the move: starting from the forces of the quintic move, iLQR solves of the
/// augmented Lagrangian until the plan ends at the goal and keeps the limits.
///
/// # Errors
/// [`PlanError::Invalid`] for a problem that cannot be planned (non-positive duration or
/// steps, a limit below zero, poses not of the platform's coordinates or not finite, a start
/// or goal closer to a singular pose than [`Problem::least_clearance`]),
/// [`PlanError::Dynamics`] for a singular start or goal, or a robot whose mechanism has no
/// derivatives generated ([`Error::Unsupported`]), [`PlanError::NotConverged`] when the
/// iterations run out.
pub fn plan(
    robot: &dyn Mechanism,
    problem: &Problem,
    settings: &Settings,
) -> Result<Plan, PlanError> {
    check(problem, robot.freedom())?;
    let derivatives = sliced_derivatives_of(robot).map_err(PlanError::Dynamics)?;
    for pose in [&problem.start, &problem.goal] {
        if robot
            .singularity_clearance(pose)
            .map_err(PlanError::Dynamics)?
            < problem.least_clearance
        {
            return Err(PlanError::Invalid(
                "the start and goal poses must keep the least clearance asked of the plan",
            ));
        }
    }
    let model = Model {
        robot,
        freedom: robot.freedom(),
        derivatives,
    };
    // The iterations' matrices are sized at compile time, by the platform's dimension: a
    // tenth of the C5's planning time went to allocating them.
    match robot.freedom() {
        Freedom::Free => solve::<6, 12>(robot, &model, problem, settings),
        Freedom::Translations => solve::<3, 6>(robot, &model, problem, settings),
    }
}

/// [`plan`] for a platform of `N` coordinates, the state's `M = 2N`.
fn solve<const N: usize, const M: usize>(
    robot: &dyn Mechanism,
    model: &Model,
    problem: &Problem,
    settings: &Settings,
) -> Result<Plan, PlanError> {
    const { assert!(M == 2 * N, "the state is the pose and the twist") };
    let dt = problem.duration / problem.steps as f64;
    let n = problem.steps;
    // The first guess: the quintic move's forces, which reach the goal but for the Euler
    // step's drift (a ramp between the forces that hold the start and the goal, open loop,
    // drifts a hexapod into a singular pose within a second).
    let mut controls: Vec<SVector<f64, N>> = quintic_forces(robot, problem)
        .map_err(PlanError::Dynamics)?
        .iter()
        .map(|gamma| SVector::from_column_slice(gamma))
        .collect();
    let at_rest =
        |pose: &[f64]| SVector::<f64, M>::from_fn(|i, _| pose.get(i).copied().unwrap_or(0.0));
    let s0 = at_rest(&problem.start);
    let mut states = rollout(model, &s0, &controls, dt).map_err(PlanError::Dynamics)?;
    let mut al = Lagrangian::<N, M> {
        dt,
        effort_weight: dt / (EFFORT_SCALE * EFFORT_SCALE),
        goal: at_rest(&problem.goal),
        goal_multiplier: SVector::zeros(),
        goal_penalty: 10.0,
        limit: problem.force_limit,
        limit_multipliers: vec![SVector::zeros(); n],
        limit_penalty: 1e-3,
        least_clearance: problem.least_clearance,
        clearance_multipliers: vec![0.0; n + 1],
        clearance_penalty: 1.0,
    };
    let mut costs = Vec::new();
    let mut iterations = 0;
    let mut previous_error = f64::INFINITY;
    loop {
        let mut round = Vec::new();
        iterations += ilqr(
            model,
            &al,
            &mut states,
            &mut controls,
            settings.max_iterations.saturating_sub(iterations),
            (FIRST_TOLERANCE * 0.1_f64.powi(costs.len() as i32)).max(FINEST_TOLERANCE),
            &mut round,
        )
        .map_err(PlanError::Dynamics)?;
        costs.push(round);
        let goal_error = (states[n] - al.goal).amax();
        let force_excess = al.force_excess(&controls);
        let least_clearance = model.least_clearance(&states);
        let shortfall = problem.least_clearance - least_clearance;
        if goal_error <= settings.goal_tolerance
            && force_excess <= settings.force_tolerance
            && shortfall <= settings.clearance_tolerance
        {
            let done = Plan {
                times: (0..states.len()).map(|k| k as f64 * dt).collect(),
                states: Vec::new(),
                forces: controls.iter().map(|u| u.as_slice().to_vec()).collect(),
                iterations,
                costs,
                goal_error,
                force_excess,
                least_clearance,
            };
            return samples::<N, M>(robot, model, &states, dt, done);
        }
        if iterations >= settings.max_iterations {
            return Err(PlanError::NotConverged {
                goal_error,
                force_excess,
                least_clearance,
            });
        }
        // The multipliers' update, and a stiffer penalty where the last round did not shrink
        // the violation enough.
        let e = states[n] - al.goal;
        al.goal_multiplier += e * al.goal_penalty;
        if goal_error > 0.25 * previous_error {
            al.goal_penalty = (al.goal_penalty * 10.0).min(1e12);
        }
        previous_error = goal_error;
        for (k, u) in controls.iter().enumerate() {
            if let Some(active) = al.active_limits(k, u) {
                al.limit_multipliers[k] = active;
            }
        }
        if force_excess > settings.force_tolerance {
            al.limit_penalty = (al.limit_penalty * 10.0).min(1e8);
        }
        for (k, s) in states.iter().enumerate() {
            al.clearance_multipliers[k] = al.active_clearance(k, model.clearance(s));
        }
        if shortfall > settings.clearance_tolerance {
            al.clearance_penalty = (al.clearance_penalty * 10.0).min(1e8);
        }
    }
}

/// The forces of the quintic rest-to-rest move between the problem's poses (Section 9's
/// profile, straight in the platform's coordinates) at the middle of each of its steps: the
/// plan's first guess, and the move it is compared with.
///
/// # Errors
/// A state of the move the robot refuses (a singular pose on the way, a non-finite problem,
/// poses not of the platform's coordinates).
pub fn quintic_forces(robot: &dyn Mechanism, problem: &Problem) -> Result<Vec<Vec<f64>>, Error> {
    let (a, b) = (&problem.start, &problem.goal);
    let (d, dt) = (problem.duration, problem.duration / problem.steps as f64);
    (0..problem.steps)
        .map(|k| {
            let (s, sd, sdd) = crate::trajectory::quintic((k as f64 + 0.5) * dt / d);
            let along =
                |rate: f64| -> Vec<f64> { a.iter().zip(b).map(|(a, b)| rate * (b - a)).collect() };
            let x: Vec<f64> = along(s).iter().zip(a).map(|(step, a)| a + step).collect();
            let state = state_from_pose_derivatives(
                robot.freedom(),
                &x,
                &along(sd / d),
                &along(sdd / (d * d)),
            )?;
            let [pose, twist, accel] = robot.coordinates_of(&state)?;
            let mut gamma = vec![0.0; pose.len()];
            robot.inverse_dynamics(&pose, &twist, &accel, &mut gamma)?;
            Ok(gamma)
        })
        .collect()
}

/// The plan's samples: states with the accelerations the forces give, the goal at rest.
fn samples<const N: usize, const M: usize>(
    robot: &dyn Mechanism,
    model: &Model,
    states: &[SVector<f64, M>],
    dt: f64,
    mut plan: Plan,
) -> Result<Plan, PlanError> {
    for (k, s) in states.iter().enumerate() {
        let accel = match plan.forces.get(k) {
            Some(u) => {
                let u = SVector::<f64, N>::from_column_slice(u);
                model.step(s, &u, dt).map_err(PlanError::Dynamics)?.accel
            }
            None => [0.0; N],
        };
        let (pose, twist) = s.as_slice().split_at(N);
        let state = robot
            .state_of([pose, twist, &accel])
            .map_err(PlanError::Dynamics)?;
        plan.states.push(state);
    }
    Ok(plan)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `E⁻¹ ω` inverts `ω = α̇ x + β̇ Rx(α) y + γ̇ Rx(α) Ry(β) z`, and its Jacobians are its
    /// central differences.
    #[test]
    fn rpy_rates_invert_the_omega_map_and_have_their_derivatives() {
        let (angles, w) = ([0.3, -0.4, 0.7], [0.2, -0.5, 0.9]);
        let (rates, d_angles, d_omega) = rpy_rates(angles, w);
        let back = crate::trajectory::omega_from_rpy_rates(angles, rates);
        for k in 0..3 {
            assert!((back[k] - w[k]).abs() < 1e-15);
        }
        let h = 1e-6;
        for j in 0..3 {
            let (mut up, mut down) = (angles, angles);
            up[j] += h;
            down[j] -= h;
            let (ru, rd) = (rpy_rates(up, w).0, rpy_rates(down, w).0);
            let (mut wu, mut wd) = (w, w);
            wu[j] += h;
            wd[j] -= h;
            let (su, sd) = (rpy_rates(angles, wu).0, rpy_rates(angles, wd).0);
            for i in 0..3 {
                assert!((d_angles[i][j] - (ru[i] - rd[i]) / (2.0 * h)).abs() < 1e-9);
                assert!((d_omega[i][j] - (su[i] - sd[i]) / (2.0 * h)).abs() < 1e-9);
            }
        }
    }
}
