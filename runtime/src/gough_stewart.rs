//! The Gough-Stewart platform (6-UPS) for controllers: [`GoughStewart`], the legged runtime
//! type over its generated kernels (`c5_generated::f64::gough_stewart`, the variants that take
//! the robot's parameters, so any valid description works), and what only it has: the stroke
//! and joint-cone limits of its description.
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
use crate::limits::Limit;
use crate::Pose;
pub use c5_robot::GoughStewart as Description;

/// The mechanism's name, as robot files and the manifest spell it.
pub const MECHANISM: &str = c5_robot::description::GOUGH_STEWART;

/// The length of the parameter vector of the hexapod's `*_params` kernels.
pub const PARAMETERS: usize = c5_generated::f64::gough_stewart::PARAMETERS;

pub use crate::singularity::{FORWARD_U_JOINT_TOLERANCE, HOLD_TOLERANCE, U_JOINT_TOLERANCE};

pub use crate::legged::{FORWARD_ITERATIONS, FORWARD_TOLERANCE, JOINT_STATE_HOLD_TOLERANCE};

pub use crate::legged::catalogue::GoughStewart;

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
    /// Every margin of the description's stroke and joint-cone limits at `pose`.
    ///
    /// # Errors
    /// A non-finite pose, or a U joint at its singularity.
    pub fn limit_margins(&self, pose: &Pose) -> Result<LegMargins, Error> {
        let (q, p) = self.inverse_kinematics(pose)?;
        let x = pose.to_array();
        let robot = self.robot();
        let u = directions(robot, pose.center, &p);
        // The legs' directions at home from the description's closed form (`B_i = C + R b_i`),
        // not a second inverse kinematics on every call.
        let home = self.home().to_array();
        let r = c5_robot::gough_stewart::rotation(&home);
        let to_centre: [[f64; 3]; 6] = core::array::from_fn(|i| {
            let b = robot.legs[i].platform;
            core::array::from_fn(|k| -(r[k][0] * b[0] + r[k][1] * b[1] + r[k][2] * b[2]))
        });
        let base = directions(robot, [home[3], home[4], home[5]], &to_centre);
        let home_directions: [_; 6] =
            core::array::from_fn(|i| (base[i], to_platform(&home, base[i])));
        let limits = &robot.limits;
        let angle = |a: [f64; 3], b: [f64; 3]| crate::math::acos(dot(a, b).clamp(-1.0, 1.0));
        let margin =
            |bound: Option<f64>, value: f64| (bound.map_or(f64::INFINITY, |b| b - value), value);
        Ok(LegMargins {
            stroke: core::array::from_fn(|i| match limits.stroke {
                Some(s) => ((q[i] - s[i][0]).min(s[i][1] - q[i]), q[i]),
                None => (f64::INFINITY, q[i]),
            }),
            u_joint: core::array::from_fn(|i| {
                margin(limits.u_joint, angle(u[i], home_directions[i].0))
            }),
            s_joint: core::array::from_fn(|i| {
                margin(
                    limits.s_joint,
                    angle(to_platform(&x, u[i]), home_directions[i].1),
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
        crate::limits::refuse_beyond(self.limit_margins(pose)?.smallest())
    }
}

/// Where the forward kinematics starts without a previous solution: the level pose
/// (`R = I`) whose leg lengths fit `q` best, by Gauss-Newton on the centre from above the
/// home pose's. A hexapod has up to 40 poses for one `q`; Newton reaches the workspace's
/// from a start within it. Against a 50-digit reference the pose found errs by about
/// `6.5e-19/ρ` relative (2.3e-8 at `ρ = 1.8e-11`), and within [`HOLD_TOLERANCE`] by at most
/// `3e-13`.
pub(crate) fn level_start(robot: &Description, q: &[f64; 6]) -> [f64; 6] {
    let home = robot.home();
    let mut c = [0.0, 0.0, home[5]];
    for _ in 0..20 {
        let mut normal = [[0.0; 3]; 3];
        let mut rhs = [0.0; 3];
        for (leg, qi) in robot.legs.iter().zip(q) {
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
