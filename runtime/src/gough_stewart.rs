//! The Gough-Stewart platform (6-UPS) for controllers: a safe, typed API over its generated
//! kernels (`c5_generated::f64::gough_stewart`, the variants that take the robot's parameters,
//! so any valid description works).
//!
//! Its conventions are the C5's: pose `[α β γ xc yc zc]` with `R = Rx(α) Ry(β) Rz(γ)`, twist
//! `(ω; v_C)` and classical acceleration `(ω̇; a_C)` at the platform origin `C`, base frame.
//! The actuator values are the encoders' readings, `q_i = |B_i - A_i| + o_i` (m), and a
//! positive force `Γ_i` extends leg `i`. Every call checks its inputs, refuses a pose where a
//! U joint or the legs' hold on the platform is singular ([`Error::Singularity`]), and its
//! results are finite. The forward kinematics has no closed form: a generated Newton step,
//! iterated here from a previous solution or from a level start.

use crate::dense;
use crate::error::Error;
use crate::legged::{self, check_conditioned, newton, Linearised};
use crate::limits::Limit;
use crate::{check_finite, finite, finite_matrix, Acceleration, Evaluation, Pose, State, Twist};
use c5_generated::f64::gough_stewart as kernels;
pub use c5_robot::GoughStewart as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::GOUGH_STEWART;

/// The length of the parameter vector of the hexapod's `*_params` kernels.
pub const PARAMETERS: usize = kernels::PARAMETERS;

/// Smallest accepted sine of a leg's angle with its U joint's first axis: below it the leg's
/// frame (its spin about its own axis) is lost.
pub const U_JOINT_TOLERANCE: f64 = 1e-6;

/// Smallest accepted pivot ratio `ρ` of the solve with `J⁻ᵀ` (the `LDLᵀ` of `J⁻¹ J⁻ᵀ`, each
/// pivot over its diagonal entry): near zero the legs lose their hold on the platform (a
/// parallel singularity) and the forces grow without bound. Against a 50-digit reference
/// (`python/tests/exact_hexapod.py`), the inverse dynamics and `J` err by about `1.5e-15/ρ`
/// relative and the forward dynamics by up to `3e-18/ρ^1.5`, so at `1e-7` they were already
/// past `1e-8`; at this bound the worst measured is `2.2e-11` (docs/embedding.md). The forward
/// dynamics, which solves `M_x`, checks it too.
pub const HOLD_TOLERANCE: f64 = 1e-5;

/// Smallest sine of a leg's angle with its U joint's first axis at which the forward dynamics
/// (and its derivatives) are served. Near that singularity the leg's spin about its own axis
/// grows as `1/sine` for a given platform twist, and with it `M_x` and `h`: each stays within
/// `1e-10` of a 50-digit reference, but the acceleration solved from them errs by 1.1e-8 at a
/// sine of `1e-3`, 6e-5 at `1e-4` and by a factor of 20 at `1e-5` (legs that hold the platform
/// well, `ρ = 0.14`). At this bound the worst measured is 1e-11; below it the call is refused
/// ([`Error::IllConditioned`]). The inverse dynamics, `J`, `M_x` and `h` are served down to
/// [`U_JOINT_TOLERANCE`].
pub const FORWARD_U_JOINT_TOLERANCE: f64 = 1e-2;

pub use crate::legged::{FORWARD_ITERATIONS, FORWARD_TOLERANCE, JOINT_STATE_HOLD_TOLERANCE};

/// The names of the singularity terms, as errors report them: the U joints, then the pivots.
const TERMS: [&str; 12] = [
    "U joint of leg 1",
    "U joint of leg 2",
    "U joint of leg 3",
    "U joint of leg 4",
    "U joint of leg 5",
    "U joint of leg 6",
    "legs' hold (pivot 1)",
    "legs' hold (pivot 2)",
    "legs' hold (pivot 3)",
    "legs' hold (pivot 4)",
    "legs' hold (pivot 5)",
    "legs' hold (pivot 6)",
];

/// Refuses the singularity terms below their tolerance (or NaN): the U joints' sines, then
/// (when given) the pivots of the solve.
pub(crate) fn check_terms(terms: &[f64]) -> Result<(), Error> {
    for (k, &value) in terms.iter().enumerate() {
        let bound = if k < 6 {
            U_JOINT_TOLERANCE
        } else {
            HOLD_TOLERANCE
        };
        if value.is_nan() || value < bound {
            return Err(Error::Singularity {
                term: TERMS[k],
                value,
                bound,
            });
        }
    }
    Ok(())
}

/// A validated Gough-Stewart platform and its parameter vector.
#[derive(Clone, Debug)]
pub struct GoughStewart {
    robot: Description,
    params: [f64; PARAMETERS],
    /// Each leg's direction at home, base frame and platform frame: what the joints' cone
    /// angles are measured from.
    home_directions: [([f64; 3], [f64; 3]); 6],
}

/// The margins of the pose-bound limits of a Gough-Stewart platform, per leg: positive
/// inside, negative outside, `+∞` where the description sets no such limit; with the values
/// they are margins of (m, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegMargins {
    /// `min(q_i - min, max - q_i)` (m), and `q_i`.
    pub stroke: [(f64, f64); 6],
    /// `u_joint - θ_U` (rad), and the U joint's cone angle `θ_U`.
    pub u_joint: [(f64, f64); 6],
    /// `s_joint - θ_S` (rad), and the S joint's cone angle `θ_S`.
    pub s_joint: [(f64, f64); 6],
}

impl LegMargins {
    /// The smallest margin: the limit, the leg (1..6), the margin and the value; `None` when
    /// the description sets none of these limits.
    pub fn smallest(&self) -> Option<(Limit, usize, f64, f64)> {
        let mut best: Option<(Limit, usize, f64, f64)> = None;
        for (limit, margins) in [
            (Limit::Stroke, &self.stroke),
            (Limit::UJoint, &self.u_joint),
            (Limit::SJoint, &self.s_joint),
        ] {
            for (i, &(margin, value)) in margins.iter().enumerate() {
                if margin.is_finite() && best.is_none_or(|(_, _, m, _)| margin < m) {
                    best = Some((limit, i + 1, margin, value));
                }
            }
        }
        best
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = crate::math::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v.map(|x| x / n)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `Rᵀ v` for the rotation of `pose`.
fn to_platform(pose: &[f64; 6], v: [f64; 3]) -> [f64; 3] {
    let r = c5_robot::gough_stewart::rotation(pose);
    core::array::from_fn(|k| r[0][k] * v[0] + r[1][k] * v[1] + r[2][k] * v[2])
}

/// Each leg's direction from `A_i` to `B_i`, base frame, from `C` and the vectors from each
/// `B_i` to `C`.
fn directions(robot: &Description, centre: [f64; 3], p: &[[f64; 3]; 6]) -> [[f64; 3]; 6] {
    core::array::from_fn(|i| {
        let a = robot.legs[i].base;
        unit(core::array::from_fn(|k| centre[k] - p[i][k] - a[k]))
    })
}

impl GoughStewart {
    /// The platform of `robot`.
    ///
    /// # Errors
    /// [`Error::Robot`] if the description breaks a rule of `GoughStewart::validate`.
    pub fn new(robot: Description) -> Result<Self, Error> {
        robot.validate().map_err(Error::from_robot)?;
        let mut params = [0.0; PARAMETERS];
        params.copy_from_slice(&robot.kernel_parameters());
        let home = robot.home();
        let (_, p, _) = kernels::inverse_kinematics_params(&home, &params);
        let base = directions(&robot, [home[3], home[4], home[5]], &p);
        let home_directions = core::array::from_fn(|i| (base[i], to_platform(&home, base[i])));
        Ok(GoughStewart {
            robot,
            params,
            home_directions,
        })
    }

    /// Every margin of the description's stroke and joint-cone limits at `pose`.
    ///
    /// # Errors
    /// A non-finite pose, or a U joint at its singularity.
    pub fn limit_margins(&self, pose: &Pose) -> Result<LegMargins, Error> {
        let (q, p) = self.inverse_kinematics(pose)?;
        let x = pose.to_array();
        let u = directions(&self.robot, pose.center, &p);
        let limits = &self.robot.limits;
        let angle = |a: [f64; 3], b: [f64; 3]| crate::math::acos(dot(a, b).clamp(-1.0, 1.0));
        let margin =
            |bound: Option<f64>, value: f64| (bound.map_or(f64::INFINITY, |b| b - value), value);
        Ok(LegMargins {
            stroke: core::array::from_fn(|i| match limits.stroke {
                Some(s) => ((q[i] - s[i][0]).min(s[i][1] - q[i]), q[i]),
                None => (f64::INFINITY, q[i]),
            }),
            u_joint: core::array::from_fn(|i| {
                margin(limits.u_joint, angle(u[i], self.home_directions[i].0))
            }),
            s_joint: core::array::from_fn(|i| {
                margin(
                    limits.s_joint,
                    angle(to_platform(&x, u[i]), self.home_directions[i].1),
                )
            }),
        })
    }

    /// Refuses a pose outside the stroke or joint-cone limits.
    ///
    /// # Errors
    /// [`Error::Limit`] naming the limit with the smallest (negative) margin, its leg and value;
    /// or a non-finite or singular pose.
    pub fn check_limits(&self, pose: &Pose) -> Result<(), Error> {
        match self.limit_margins(pose)?.smallest() {
            Some((limit, actuator, margin, value)) if margin < 0.0 => Err(Error::Limit {
                limit,
                actuator,
                value,
                margin,
            }),
            _ => Ok(()),
        }
    }

    pub fn robot(&self) -> &Description {
        &self.robot
    }

    /// The parameter vector, as the `*_params` kernels take it.
    pub fn parameters(&self) -> &[f64; PARAMETERS] {
        &self.params
    }

    /// The home pose: where the forward kinematics starts without a previous solution when
    /// the level start fails, and the joints' cone angles are measured from.
    pub fn home(&self) -> Pose {
        Pose::from_array(self.robot.home())
    }

    legged::kernel_calls!(12);

    /// The forward dynamics: the platform's classical acceleration `(ω̇; a_C)` under the
    /// actuator forces `gamma` (N).
    ///
    /// # Errors
    /// Non-finite inputs, a U joint at its singularity, a pose too near a singularity for the
    /// acceleration's bound ([`Error::IllConditioned`], [`FORWARD_U_JOINT_TOLERANCE`]), or a
    /// non-finite result.
    pub fn forward_dynamics(
        &self,
        pose: &Pose,
        twist: &Twist,
        gamma: &[f64; 6],
    ) -> Result<Acceleration, Error> {
        let (x, v) = (pose.to_array(), twist.to_array());
        check_finite("pose", &x)?;
        check_finite("twist", &v)?;
        check_finite("gamma", gamma)?;
        let (a, guard) = kernels::forward_dynamics_params(&x, &v, gamma, &self.params);
        // The U joints' sines and the legs' hold.
        check_terms(&guard)?;
        check_conditioned(
            "forward dynamics",
            &guard[..6],
            &TERMS[..6],
            FORWARD_U_JOINT_TOLERANCE,
        )?;
        Ok(Acceleration::from_array(finite("acceleration", a)?))
    }

    /// The pose whose actuator positions are `q` (m), found by Newton's method from `near` (a
    /// previous solution: two or three steps at a controller's rate) or, without it, from the
    /// level pose that fits `q` best; to [`FORWARD_TOLERANCE`] on every actuator. A hexapod
    /// has up to 40 poses for one `q`: this is the one Newton reaches from the start, the
    /// workspace's from a start within it.
    ///
    /// The pose is refused where the legs' hold is below [`HOLD_TOLERANCE`], as every kernel
    /// of the hexapod refuses it: against a 50-digit reference its error grows as about
    /// `6.5e-19/ρ` relative (2.3e-8 at `ρ = 1.8e-11`), and within the bound it is at most
    /// `3e-13`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::NotConverged`] when the steps stop reducing the residual
    /// (positions no pose near the start has); [`Error::Singularity`] when a step meets a
    /// singular pose, or the pose found is one.
    pub fn forward_kinematics(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<Pose, Error> {
        self.located(q, near).map(|(pose, _)| pose)
    }

    /// [`GoughStewart::forward_kinematics`], with the singularity terms at the pose found (all
    /// within their tolerances), for the callers that hold it to a nearer bound.
    fn located(&self, q: &[f64; 6], near: Option<&Pose>) -> Result<(Pose, [f64; 12]), Error> {
        check_finite("q", q)?;
        let start = match near {
            Some(p) => {
                check_finite("near", &p.to_array())?;
                p.to_array()
            }
            None => self.level_start(q),
        };
        let x = self.newton(q, start)?;
        let terms = kernels::singularity_terms_params(&x, &self.params);
        check_terms(&terms)?;
        Ok((Pose::from_array(x), terms))
    }

    /// Refuses a pose where the legs' hold is below [`HOLD_TOLERANCE`]: for the kernels that
    /// solve with `M_x` rather than `J⁻ᵀ`, whose own singularity terms are the U joints' alone.
    #[cfg(feature = "derivatives")]
    pub(crate) fn check_hold(&self, x: &[f64; 6]) -> Result<(), Error> {
        check_terms(&kernels::singularity_terms_params(x, &self.params))
    }

    /// Refuses, for the kernels that solve `M_x` for the acceleration, a pose where the legs'
    /// hold is below [`HOLD_TOLERANCE`] or a U joint's sine (of `sines`, the kernel's guard)
    /// below [`FORWARD_U_JOINT_TOLERANCE`].
    #[cfg(feature = "derivatives")]
    pub(crate) fn check_acceleration_solve(
        &self,
        x: &[f64; 6],
        sines: &[f64],
    ) -> Result<(), Error> {
        self.check_hold(x)?;
        check_conditioned(
            "forward dynamics",
            sines,
            &TERMS[..6],
            FORWARD_U_JOINT_TOLERANCE,
        )
    }

    /// Newton's method on `q(X) = q` from `x` ([`newton`]).
    fn newton(&self, q: &[f64; 6], x: [f64; 6]) -> Result<[f64; 6], Error> {
        newton(
            |x, out| {
                let (r, jac, guard) = kernels::forward_kinematics_step_params(x, q, &self.params);
                check_terms(&guard)?;
                *out = Linearised {
                    residual: finite("residual", r)?,
                    jacobian: jac,
                };
                Ok(())
            },
            x,
        )
    }

    /// The level pose (`R = I`) whose leg lengths fit `q` best: Gauss-Newton on the centre, from
    /// above the home pose's.
    fn level_start(&self, q: &[f64; 6]) -> [f64; 6] {
        let home = self.robot.home();
        let mut c = [0.0, 0.0, home[5]];
        for _ in 0..20 {
            let mut normal = [[0.0; 3]; 3];
            let mut rhs = [0.0; 3];
            for (leg, qi) in self.robot.legs.iter().zip(q) {
                let d: [f64; 3] = core::array::from_fn(|k| c[k] + leg.platform[k] - leg.base[k]);
                let length = crate::math::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                let u = d.map(|x| x / length);
                let error = qi - leg.encoder_offset - length;
                for i in 0..3 {
                    rhs[i] += u[i] * error;
                    for j in 0..3 {
                        normal[i][j] += u[i] * u[j];
                    }
                }
            }
            let Some(step) = dense::solve(&normal, &rhs, 1e-12) else {
                break;
            };
            for k in 0..3 {
                c[k] += step[k];
            }
            if dense::max_abs(&step) < 1e-13 {
                break;
            }
        }
        if c.iter().all(|x| x.is_finite()) {
            [0.0, 0.0, 0.0, c[0], c[1], c[2]]
        } else {
            home
        }
    }

    legged::joint_space_methods!();
}

legged::legged_impl!(GoughStewart, 6);
