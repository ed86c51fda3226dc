//! Minimum-effort motion planning (feature `plan`): a rest-to-rest move between two poses in a
//! given time, actuator forces within a limit, by iLQR on the forward dynamics and its exact
//! Jacobians ([`Derivatives::forward_dynamics_derivatives`]), with an augmented Lagrangian for
//! the goal and the force limits. It plans for every robot whose platform is free in space and
//! whose mechanism has its derivatives generated (the C5 and the Gough-Stewart platform).
//!
//! The state is `s = (X, V)`: the pose `[α β γ xc yc zc]` and the twist `(ω; v_C)`; the control
//! the forces `Γ`. The dynamics `ṡ = (Ė(X)⁻¹ ω, v_C, a(X, V, Γ))`, with `E` the map from RPY
//! rates to `ω` (`ω = α̇ x + β̇ Rx(α) y + γ̇ Rx(α) Ry(β) z`), is integrated by explicit Euler at the
//! plan's step. The cost is the effort `½ Σ_k dt |Γ_k|² / σ²` (`σ` = [`EFFORT_SCALE`]); the goal
//! `s_N = (X_goal, 0)` and the limits `|Γ_i| ≤ Γ_max` are constraints, held by an augmented
//! Lagrangian (multipliers updated between iLQR solves, penalties raised while a constraint is
//! not met), so the plan ends at the goal to the tolerance asked for, not merely near it.

use crate::derivatives::ForwardDynamicsDerivatives;
use crate::mechanism::{derivatives_of, Derivatives, SpatialRobot};
use crate::platform::Freedom;
use crate::trajectory::state_from_pose_derivatives;
use crate::{Acceleration, Error, Pose, State, Twist};
use nalgebra::{SMatrix, SVector};

type S = SVector<f64, 12>;
type U = SVector<f64, 6>;
type Sxx = SMatrix<f64, 12, 12>;
type Sxu = SMatrix<f64, 12, 6>;
type Uxx = SMatrix<f64, 6, 6>;

/// Forces are weighed in units of this (N) in the effort: it keeps the cost of order one.
pub const EFFORT_SCALE: f64 = 100.0;

/// An iLQR solve of the first augmented-Lagrangian round stops when a full step gains, or the
/// model promises, less than this fraction of the cost; each later round asks ten times more,
/// down to [`FINEST_TOLERANCE`], as the constraints' terms shrink.
const FIRST_TOLERANCE: f64 = 1e-4;
const FINEST_TOLERANCE: f64 = 1e-13;

/// A rest-to-rest move to plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub start: Pose,
    pub goal: Pose,
    /// The move's duration (s).
    pub duration: f64,
    /// Steps of the plan (its forces are held over each, `dt = duration / steps`).
    pub steps: usize,
    /// `|Γ_i| ≤ force_limit` (N) for every actuator at every step, if given.
    pub force_limit: Option<f64>,
}

/// When the planner stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The largest `|s_N - s_goal|` accepted (rad, m, rad/s, m/s).
    pub goal_tolerance: f64,
    /// The largest excess over the force limit accepted (N).
    pub force_tolerance: f64,
    /// iLQR iterations at most, all augmented-Lagrangian rounds together.
    pub max_iterations: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            goal_tolerance: 1e-8,
            force_tolerance: 1e-6,
            max_iterations: 500,
        }
    }
}

/// A planned move.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// `t_k = k dt`, `steps + 1` of them.
    pub times: Vec<f64>,
    /// The state at each time, its acceleration the one the forces give (zero at the end).
    pub states: Vec<State>,
    /// The forces held over each step (N, segment order), `steps` of them.
    pub forces: Vec<[f64; 6]>,
    /// iLQR iterations taken (backward and forward passes).
    pub iterations: usize,
    /// Per round of the augmented Lagrangian, the objective after each accepted iLQR
    /// iteration (the effort plus the round's constraint terms): strictly decreasing in a round.
    pub costs: Vec<Vec<f64>>,
    /// `|s_N - s_goal|∞` reached.
    pub goal_error: f64,
    /// The largest `|Γ_i| - Γ_max` over the plan (≤ 0 inside the limit).
    pub force_excess: f64,
}

/// Why a plan failed.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanError {
    /// The problem is not well posed (named field and rule).
    Invalid(&'static str),
    /// The dynamics refused a state on the way (a singular pose).
    Dynamics(Error),
    /// The iterations ran out before the goal and the limits were met.
    NotConverged { goal_error: f64, force_excess: f64 },
}

impl core::fmt::Display for PlanError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PlanError::Invalid(why) => write!(f, "invalid plan: {why}"),
            PlanError::Dynamics(e) => {
                write!(f, "the plan reached a state the dynamics refuses: {e}")
            }
            PlanError::NotConverged {
                goal_error,
                force_excess,
            } => write!(
                f,
                "no plan met the goal and the limits in the iterations allowed (goal error \
                 {goal_error:e}, force excess {force_excess:e} N)"
            ),
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

/// The Euler step `s + dt f(s, u)`, with its Jacobians `A = ∂s'/∂s`, `B = ∂s'/∂u`.
fn step(
    robot: &dyn Derivatives<6>,
    s: &S,
    u: &U,
    dt: f64,
) -> Result<(S, Sxx, Sxu, Acceleration), Error> {
    let pose = Pose::from_array(std::array::from_fn(|i| s[i]));
    let twist = Twist::from_array(std::array::from_fn(|i| s[6 + i]));
    let gamma: [f64; 6] = std::array::from_fn(|i| u[i]);
    let ForwardDynamicsDerivatives {
        accel,
        d_pose,
        d_twist,
        d_gamma,
    } = robot.forward_dynamics_derivatives(&pose, &twist, &gamma)?;
    let (rates, d_angles, d_omega) = rpy_rates([s[0], s[1], s[2]], twist.omega);
    let a = accel;
    let mut f = S::zeros();
    let mut fs = Sxx::zeros();
    let mut fu = Sxu::zeros();
    for i in 0..3 {
        f[i] = rates[i];
        f[3 + i] = s[9 + i];
        fs[(3 + i, 9 + i)] = 1.0;
        for j in 0..3 {
            fs[(i, j)] = d_angles[i][j];
            fs[(i, 6 + j)] = d_omega[i][j];
        }
    }
    for i in 0..6 {
        f[6 + i] = a[i];
        for j in 0..6 {
            fs[(6 + i, j)] = d_pose[i][j];
            fs[(6 + i, 6 + j)] = d_twist[i][j];
            fu[(6 + i, j)] = d_gamma[i][j];
        }
    }
    Ok((
        s + f * dt,
        Sxx::identity() + fs * dt,
        fu * dt,
        Acceleration::from_array(accel),
    ))
}

/// The augmented Lagrangian's state: multipliers and penalties of the goal and the limits.
struct Lagrangian {
    /// The plan's step (s): the effort is a sum over steps of this length.
    dt: f64,
    goal: S,
    goal_multiplier: S,
    goal_penalty: f64,
    limit: Option<f64>,
    /// Per step, the multipliers of `u - Γmax ≤ 0` (first six) and `-u - Γmax ≤ 0`.
    limit_multipliers: Vec<SVector<f64, 12>>,
    limit_penalty: f64,
}

impl Lagrangian {
    /// The constraint values `c ≤ 0` of the limits at `u`, and their multipliers' active set.
    fn limit_terms(&self, k: usize, u: &U) -> Option<(SVector<f64, 12>, SVector<f64, 12>)> {
        let limit = self.limit?;
        let c = SVector::<f64, 12>::from_fn(|i, _| {
            if i < 6 {
                u[i] - limit
            } else {
                -u[i - 6] - limit
            }
        });
        // max(0, λ + ρ c): the multipliers the penalty acts with.
        let active = (self.limit_multipliers[k] + c * self.limit_penalty).map(|x| x.max(0.0));
        Some((c, active))
    }

    /// The stage cost at step `k`: effort plus the limits' augmented terms.
    fn stage(&self, k: usize, u: &U) -> f64 {
        let mut cost = 0.5 * self.dt * u.norm_squared() / (EFFORT_SCALE * EFFORT_SCALE);
        if let Some((_, active)) = self.limit_terms(k, u) {
            let lambda = &self.limit_multipliers[k];
            cost += (active.norm_squared() - lambda.norm_squared()) / (2.0 * self.limit_penalty);
        }
        cost
    }

    /// `∂ℓ/∂u`, `∂²ℓ/∂u²` of [`Lagrangian::stage`].
    fn stage_derivatives(&self, k: usize, u: &U) -> (U, Uxx) {
        let w = self.dt / (EFFORT_SCALE * EFFORT_SCALE);
        let mut lu = u * w;
        let mut luu = Uxx::identity() * w;
        if let Some((_, active)) = self.limit_terms(k, u) {
            for i in 0..6 {
                lu[i] += active[i] - active[6 + i];
                for on in [active[i] > 0.0, active[6 + i] > 0.0] {
                    if on {
                        luu[(i, i)] += self.limit_penalty;
                    }
                }
            }
        }
        (lu, luu)
    }

    fn terminal(&self, s: &S) -> f64 {
        let e = s - self.goal;
        self.goal_multiplier.dot(&e) + 0.5 * self.goal_penalty * e.norm_squared()
    }

    fn total(&self, states: &[S], controls: &[U]) -> f64 {
        let effort: f64 = controls
            .iter()
            .enumerate()
            .map(|(k, u)| self.stage(k, u))
            .sum();
        effort + self.terminal(&states[states.len() - 1])
    }

    fn force_excess(&self, controls: &[U]) -> f64 {
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
fn rollout(robot: &dyn Derivatives<6>, s0: &S, controls: &[U], dt: f64) -> Result<Vec<S>, Error> {
    let mut states = Vec::with_capacity(controls.len() + 1);
    states.push(*s0);
    for u in controls {
        let s = states[states.len() - 1];
        states.push(step(robot, &s, u, dt)?.0);
    }
    Ok(states)
}

/// One iLQR solve of the current augmented Lagrangian: backward passes with a
/// Levenberg-Marquardt shift of `Q_uu`, forward passes with a line search, until a full step
/// gains or promises less than `tolerance` of the cost. Returns the iterations spent.
fn ilqr(
    robot: &dyn Derivatives<6>,
    al: &Lagrangian,
    states: &mut Vec<S>,
    controls: &mut Vec<U>,
    budget: usize,
    tolerance: f64,
    costs: &mut Vec<f64>,
) -> Result<usize, Error> {
    let (n, dt) = (controls.len(), al.dt);
    let mut cost = al.total(states, controls);
    let mut shift = 1e-9;
    let mut iterations = 0;
    while iterations < budget {
        iterations += 1;
        // Linearise along the current trajectory.
        let mut a = Vec::with_capacity(n);
        let mut b = Vec::with_capacity(n);
        for k in 0..n {
            let (_, ak, bk, _) = step(robot, &states[k], &controls[k], dt)?;
            a.push(ak);
            b.push(bk);
        }
        // Backward pass.
        let (gains, feedforward, expected) = loop {
            let e = states[n] - al.goal;
            let mut vx = al.goal_multiplier + e * al.goal_penalty;
            let mut vxx = Sxx::identity() * al.goal_penalty;
            let mut gains = vec![SMatrix::<f64, 6, 12>::zeros(); n];
            let mut feedforward = vec![U::zeros(); n];
            let mut expected = 0.0;
            let mut failed = false;
            for k in (0..n).rev() {
                let (lu, luu) = al.stage_derivatives(k, &controls[k]);
                let qx = a[k].transpose() * vx;
                let qu = lu + b[k].transpose() * vx;
                let vxx_b = vxx * b[k];
                let qxx = a[k].transpose() * vxx * a[k];
                let quu = luu + b[k].transpose() * vxx_b + Uxx::identity() * shift;
                let qux = vxx_b.transpose() * a[k];
                let Some(chol) = quu.cholesky() else {
                    failed = true;
                    break;
                };
                let kk = -chol.solve(&qux);
                let ff = -chol.solve(&qu);
                expected += ff.dot(&qu);
                vx = qx + kk.transpose() * (quu * ff) + kk.transpose() * qu + qux.transpose() * ff;
                vxx = qxx + kk.transpose() * quu * kk + kk.transpose() * qux + qux.transpose() * kk;
                vxx = (vxx + vxx.transpose()) * 0.5;
                gains[k] = kk;
                feedforward[k] = ff;
            }
            if !failed {
                break (gains, feedforward, expected);
            }
            shift = (shift * 10.0).max(1e-6);
            if shift > 1e10 {
                return Ok(iterations);
            }
        };
        // Forward pass with a line search on the step.
        let mut accepted = false;
        let mut step_size = 1.0;
        while step_size > 1e-4 {
            let mut new_states = Vec::with_capacity(n + 1);
            let mut new_controls = Vec::with_capacity(n);
            new_states.push(states[0]);
            let mut refused = false;
            for k in 0..n {
                let u = controls[k]
                    + feedforward[k] * step_size
                    + gains[k] * (new_states[k] - states[k]);
                match step(robot, &new_states[k], &u, dt) {
                    Ok((s, ..)) => new_states.push(s),
                    Err(_) => {
                        refused = true;
                        break;
                    }
                }
                new_controls.push(u);
            }
            if !refused {
                let new_cost = al.total(&new_states, &new_controls);
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
                    if (step_size == 1.0 && gain <= small) || -expected <= small {
                        return Ok(iterations);
                    }
                    break;
                }
            }
            step_size *= 0.5;
        }
        if !accepted {
            shift = (shift * 10.0).max(1e-6);
            if shift > 1e10 || -expected <= tolerance * cost.abs() {
                return Ok(iterations);
            }
        }
    }
    Ok(iterations)
}

/// Plans the move: starting from the forces that hold the start pose, iLQR solves of the
/// augmented Lagrangian until the plan ends at the goal and keeps the limits.
///
/// # Errors
/// [`PlanError::Invalid`] for a problem that cannot be planned (non-positive duration or
/// steps, a limit below zero, a non-finite pose), [`PlanError::Dynamics`] for a singular start
/// or goal, or a robot whose mechanism has no derivatives generated ([`Error::Unsupported`]),
/// [`PlanError::NotConverged`] when the iterations run out.
pub fn plan(
    robot: &dyn SpatialRobot,
    problem: &Problem,
    settings: &Settings,
) -> Result<Plan, PlanError> {
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
    let (start, goal) = (problem.start.to_array(), problem.goal.to_array());
    if !start.iter().chain(&goal).all(|x| x.is_finite()) {
        return Err(PlanError::Invalid(
            "the start and goal poses must be finite",
        ));
    }
    let derivatives = derivatives_of(robot).map_err(PlanError::Dynamics)?;
    let dt = problem.duration / problem.steps as f64;
    let n = problem.steps;
    // The first guess: the quintic move's forces, which reach the goal but for the Euler
    // step's drift (a ramp between the forces that hold the start and the goal, open loop,
    // drifts a hexapod into a singular pose within a second).
    let mut controls: Vec<U> = quintic_forces(robot, problem)
        .map_err(PlanError::Dynamics)?
        .iter()
        .map(|gamma| U::from_column_slice(gamma))
        .collect();
    let s0 = S::from_fn(|i, _| if i < 6 { start[i] } else { 0.0 });
    let mut states = rollout(derivatives, &s0, &controls, dt).map_err(PlanError::Dynamics)?;
    let mut al = Lagrangian {
        dt,
        goal: S::from_fn(|i, _| if i < 6 { goal[i] } else { 0.0 }),
        goal_multiplier: S::zeros(),
        goal_penalty: 10.0,
        limit: problem.force_limit,
        limit_multipliers: vec![SVector::zeros(); n],
        limit_penalty: 1e-3,
    };
    let mut costs = Vec::new();
    let mut iterations = 0;
    let mut previous_error = f64::INFINITY;
    loop {
        let mut round = Vec::new();
        iterations += ilqr(
            derivatives,
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
        if goal_error <= settings.goal_tolerance && force_excess <= settings.force_tolerance {
            return assemble(
                derivatives,
                &states,
                &controls,
                dt,
                iterations,
                costs,
                goal_error,
                force_excess,
            );
        }
        if iterations >= settings.max_iterations {
            return Err(PlanError::NotConverged {
                goal_error,
                force_excess,
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
            if let Some((_, active)) = al.limit_terms(k, u) {
                al.limit_multipliers[k] = active;
            }
        }
        if force_excess > settings.force_tolerance {
            al.limit_penalty = (al.limit_penalty * 10.0).min(1e8);
        }
    }
}

/// The forces of the quintic rest-to-rest move between the problem's poses (Section 9's
/// profile, straight in the centre and in the RPY angles) at the middle of each of its steps:
/// the plan's first guess, and the move it is compared with.
///
/// # Errors
/// A state of the move the robot refuses (a singular pose on the way, a non-finite problem).
pub fn quintic_forces(robot: &dyn SpatialRobot, problem: &Problem) -> Result<Vec<[f64; 6]>, Error> {
    let (a, b) = (problem.start.to_array(), problem.goal.to_array());
    let (d, dt) = (problem.duration, problem.duration / problem.steps as f64);
    (0..problem.steps)
        .map(|k| {
            let (s, sd, sdd) = crate::trajectory::quintic((k as f64 + 0.5) * dt / d);
            let along =
                |rate: f64| -> Vec<f64> { a.iter().zip(&b).map(|(a, b)| rate * (b - a)).collect() };
            let x: Vec<f64> = along(s).iter().zip(&a).map(|(step, a)| a + step).collect();
            let state = state_from_pose_derivatives(
                Freedom::Free,
                &x,
                &along(sd / d),
                &along(sdd / (d * d)),
            )?;
            robot.inverse_dynamics(&state)
        })
        .collect()
}

/// The plan's samples: states with the accelerations the forces give, the goal at rest.
#[allow(clippy::too_many_arguments)]
fn assemble(
    robot: &dyn Derivatives<6>,
    states: &[S],
    controls: &[U],
    dt: f64,
    iterations: usize,
    costs: Vec<Vec<f64>>,
    goal_error: f64,
    force_excess: f64,
) -> Result<Plan, PlanError> {
    let mut samples = Vec::with_capacity(states.len());
    for (k, s) in states.iter().enumerate() {
        let accel = match controls.get(k) {
            Some(u) => step(robot, s, u, dt).map_err(PlanError::Dynamics)?.3,
            None => Acceleration::default(),
        };
        samples.push(State {
            pose: Pose::from_array(std::array::from_fn(|i| s[i])),
            twist: Twist::from_array(std::array::from_fn(|i| s[6 + i])),
            accel,
        });
    }
    Ok(Plan {
        times: (0..states.len()).map(|k| k as f64 * dt).collect(),
        states: samples,
        forces: controls
            .iter()
            .map(|u| std::array::from_fn(|i| u[i]))
            .collect(),
        iterations,
        costs,
        goal_error,
        force_excess,
    })
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
