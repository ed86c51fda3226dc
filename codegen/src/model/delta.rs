//! The Delta: three R-U-S arms ([`legged::rus`], each with a parallelogram of two rods) carry a
//! platform that only translates.
//!
//! The platform's freedom is three: its position `C`, velocity `v_C` and acceleration `a_C`
//! (its frame stays parallel to the base's). Every arm is the rotary hexapod's leg with
//! `B_i = C + p_i` and two rods offset by `±w_i/2` along the motor's axis, so the legs'
//! derivation ([`legged::leg_state`]) gives each arm's crank angle, its row of `J⁻¹`, its
//! acceleration and the force its bodies need, with the platform's rotation held at the
//! identity and its angular motion at zero. Of each row and wrench only the translation part
//! is the Delta's: the moments are the parallelograms' to carry, and no actuator works on a
//! rotation the platform cannot make.
//!
//! - `J⁻¹` (3×3): the translation parts of the arms' rows, `q̇ = J⁻¹ v_C`;
//! - the force at `C` the actuators put on the platform, `W = m (a_C − g) + Σ Φ_i`, with
//!   `J⁻ᵀ Γ = W` solved by Cramer's rule (one reciprocal of `det J⁻¹`);
//! - the forward dynamics `a_C = M_x⁻¹ (J⁻ᵀ Γ − h)`, `M_x = ∂W/∂a_C`, `h = W(a_C = 0)`;
//! - the forward kinematics in closed form: the platform's `C` is where three spheres meet,
//!   centred at `E_i − p_i` with radii `L_i`; both meeting points are returned, and the
//!   runtime keeps the one on its home's side.
//!
//! The kernels are the Delta's own ([`DeltaMechanics::extra_kernels`]): the shared table's are
//! those of a platform with six freedoms, which the Delta's [`Structure::has_kernel`] declines.

use super::bodies::{Dynamics, Inertial};
use super::calibration;
use super::derivatives;
use super::geometry::{Motion, Posed};
use super::kernels::{Build, Cite, Context, Decl, Guard, Input, Kernel, Output, Reads};
use super::legged::{self, rus::Rus, Leg, LegState};
use super::rus_hexapod::{crank_body, rod_body};
use super::terms::{self, SingularityTerm, TermKind};
use super::{Freedom, Mechanics, Quantity, Structure, INTERNAL_INPUTS};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use c5_robot::delta::{ARM_GEOMETRY, GEOMETRY_PARAMETERS};
use c5_robot::rus::{CRANK_STANDARD, ROD_STANDARD};
use c5_robot::Delta;

/// The Delta's [`Structure`] and [`Mechanics`].
pub struct DeltaMechanics;

/// The standard parameters of one arm: the crank's, then each rod's.
const ARM_BODIES: usize = CRANK_STANDARD.len() + ROD_STANDARD.len();

fn vec3<'g>(v: &[Expr<'g>]) -> Vec3<'g> {
    Vector([v[0], v[1], v[2]])
}

/// Arm `i` of the geometry, massless: the rotary hexapod's leg with its two rods at
/// `±w_i/2` along the motor's axis.
fn arm<'g>(geometry: &[Expr<'g>], i: usize) -> Rus<'g> {
    let at = &geometry[3 + ARM_GEOMETRY * i..3 + ARM_GEOMETRY * (i + 1)];
    let g = at[0].graph();
    let massless = Inertial::massless(g);
    let half = (at[16] * 0.5).keep();
    Rus {
        base: vec3(&at[0..3]),
        axis: vec3(&at[3..6]),
        zero: vec3(&at[6..9]),
        platform: vec3(&at[9..12]),
        crank_length: at[12],
        rod_length: at[13],
        branch: at[14],
        offset: at[15],
        crank: massless,
        rod: massless,
        rods: vec![half, -half],
        closed_form: true,
    }
}

/// The dynamics from the standard inertial parameters `p` (the platform's mass, then each
/// arm's crank and rod) and gravity. [`Dynamics`] holds six legs: a Delta's last three are
/// massless and no kernel of the Delta reads them.
fn dynamics_of<'g>(gravity: Vec3<'g>, p: &[Expr<'g>]) -> Dynamics<'g> {
    let g = p[0].graph();
    let arm = |i: usize| &p[1 + ARM_BODIES * i..1 + ARM_BODIES * (i + 1)];
    let massless = Inertial::massless(g);
    Dynamics {
        gravity,
        platform: Inertial {
            mass: p[0],
            ..massless
        },
        legs: std::array::from_fn(|i| {
            if i < 3 {
                let (crank, rod) = arm(i).split_at(CRANK_STANDARD.len());
                [crank_body(crank), rod_body(rod)]
            } else {
                [massless, massless]
            }
        }),
        rod_inertia_per_length_squared: [Mat::zeros(g); 6],
    }
}

/// The platform's translation: position, velocity and acceleration (base frame).
#[derive(Clone, Copy)]
struct Translation<'g> {
    position: Vec3<'g>,
    velocity: Vec3<'g>,
    accel: Vec3<'g>,
}

impl<'g> Translation<'g> {
    /// The kernel's position, with its velocity and acceleration where it takes them (zero
    /// where not).
    fn of(cx: &Context<'_, 'g>) -> Self {
        let g = cx.graph();
        let read = |kind: Input| {
            if cx.has(kind) {
                vec3(&cx.input(kind))
            } else {
                Vec3::zeros(g)
            }
        };
        Translation {
            position: vec3(&cx.input(Input::Position)),
            velocity: read(Input::Velocity),
            accel: read(Input::LinearAccel),
        }
    }
}

/// The arms at the platform's translation, their bodies under the dynamics' gravity (or
/// massless, for kinematics): the legs' derivation with `R = I` and no angular motion.
fn arm_states<'g>(
    geometry: &[Expr<'g>],
    dynamics: Option<&Dynamics<'g>>,
    at: &Translation<'g>,
) -> Vec<LegState<'g>> {
    let g = at.position[0].graph();
    let zero = Vec3::zeros(g);
    let legs: Vec<Box<dyn Leg<'g> + 'g>> = (0..3)
        .map(|i| {
            let mut arm = arm(geometry, i);
            if let Some(d) = dynamics {
                [arm.crank, arm.rod] = d.legs[i];
            }
            Box::new(arm) as Box<dyn Leg<'g> + 'g>
        })
        .collect();
    let motion = Motion::new(
        Vec6::spatial(zero, at.velocity),
        Vec6::spatial(zero, at.accel),
    );
    let gravity = dynamics.map_or(zero, |d| d.gravity);
    legged::leg_states(&legs, &(Mat3::identity(g), at.position), &motion, &gravity)
}

/// `J⁻¹`: row `i` the translation part of arm `i`'s row, `∂θ_i/∂C`.
fn inverse_jacobian<'g>(states: &[LegState<'g>]) -> Mat3<'g> {
    Mat(std::array::from_fn(|i| states[i].jinv_row.bottom().0))
}

/// `W = m (a_C − g) + Σ Φ_i`: the force at `C` the actuators put on the platform.
fn task_force<'g>(
    dynamics: &Dynamics<'g>,
    at: &Translation<'g>,
    states: &[LegState<'g>],
) -> Vec3<'g> {
    let platform = (at.accel - dynamics.gravity).scale(dynamics.platform.mass);
    states
        .iter()
        .fold(platform, |sum, arm| sum + arm.wrench.bottom())
}

/// `Γ` from `J⁻ᵀ Γ = W` for the bodies' `dynamics`, with `J⁻¹`.
fn inverse_dynamics<'g>(
    geometry: &[Expr<'g>],
    dynamics: &Dynamics<'g>,
    at: &Translation<'g>,
) -> (Vec3<'g>, Mat3<'g>) {
    let states = arm_states(geometry, Some(dynamics), at);
    let w = task_force(dynamics, at, &states);
    let jinv = inverse_jacobian(&states);
    (jinv.transpose().solve(&w), jinv)
}

/// `M_x = ∂W/∂a_C` at `position`: `W` is affine in `a_C`, so `M_x` is its exact derivative,
/// symmetric positive definite (its lower triangle mirrored).
fn task_inertia<'g>(cx: &Context<'_, 'g>, position: &Vec3<'g>) -> Mat3<'g> {
    let g = cx.graph();
    let unknown: Vec3<'g> = Vector::from_fn(|k| g.input(INTERNAL_INPUTS + k as u32));
    let probe = Translation {
        position: *position,
        velocity: Vec3::zeros(g),
        accel: unknown,
    };
    let states = arm_states(cx.geometry, Some(cx.dynamics), &probe);
    let w = task_force(cx.dynamics, &probe, &states).to_vec();
    let columns: Vec<Vec<Expr<'g>>> = unknown.0.iter().map(|&u| g.derivatives(&w, u)).collect();
    Mat::from_fn(|r, c| columns[r.min(c)][r.max(c)])
}

/// `h = W(a_C = 0)`: the force the arms' and the platform's velocity and gravity need, with
/// the arms' states at rest acceleration (whose rows are `J⁻¹`'s).
fn task_bias<'g>(cx: &Context<'_, 'g>, at: &Translation<'g>) -> (Vec3<'g>, Vec<LegState<'g>>) {
    let rest = Translation {
        accel: Vec3::zeros(cx.graph()),
        ..*at
    };
    let states = arm_states(cx.geometry, Some(cx.dynamics), &rest);
    (task_force(cx.dynamics, &rest, &states), states)
}

/// `a_C = M_x⁻¹ (J⁻ᵀ Γ − h)`, by `LDLᵀ` ([`task_inertia`], [`task_bias`]).
fn forward_dynamics<'g>(cx: &Context<'_, 'g>, at: &Translation<'g>, gamma: &Vec3<'g>) -> Vec3<'g> {
    let m_x = task_inertia(cx, &at.position);
    let (h, states) = task_bias(cx, at);
    let driving = inverse_jacobian(&states).transpose() * *gamma;
    m_x.ldlt_solve(&(driving - h))
}

/// Per arm `|u_i × r_i|` (the U joints' sine), then per arm `1 − (K/ρ)²` (crank and rod
/// aligned where it vanishes, the ball out of reach where it is negative).
fn pose_terms<'g>(geometry: &[Expr<'g>], position: &Vec3<'g>) -> Vec<Expr<'g>> {
    let arms: Vec<(Expr<'g>, Expr<'g>)> = (0..3)
        .map(|i| {
            let arm = arm(geometry, i);
            let b = *position + arm.platform;
            let crank = arm.crank_state(&b);
            (arm.rod_frame(&crank.elbow, &b).1, crank.aligned)
        })
        .collect();
    arms.iter()
        .map(|t| t.0)
        .chain(arms.iter().map(|t| t.1))
        .collect()
}

/// The arms' hold on the platform, `det(J⁻¹)² / Π |row_i|²`: in `[0, 1]`, one where the rows
/// are orthogonal, zero where the arms cannot hold the platform.
fn hold<'g>(jinv: &Mat3<'g>) -> Expr<'g> {
    let det = jinv.determinant();
    let norms = (0..3).fold(det.graph().one(), |p, i| {
        let r = jinv.row(i);
        p * r.dot(&r)
    });
    det * det * norms.recip()
}

/// [`pose_terms`] and the arms' [`hold`].
fn solve_terms<'g>(geometry: &[Expr<'g>], position: &Vec3<'g>) -> Vec<Expr<'g>> {
    let rest = Translation {
        position: *position,
        velocity: Vec3::zeros(position[0].graph()),
        accel: Vec3::zeros(position[0].graph()),
    };
    let jinv = inverse_jacobian(&arm_states(geometry, None, &rest));
    let mut terms = pose_terms(geometry, position);
    terms.push(hold(&jinv));
    terms
}

/// The two points where the spheres about `P_i = E_i − p_i` of radii `L_i` meet, and the
/// terms that say whether they do: `(L_1² − |y_0|²)/L_1²` (negative where the spheres miss,
/// zero where the two points merge) and `|n|²/(|a|² |b|²)` (zero where the centres line up).
/// With `a = P_2 − P_1`, `b = P_3 − P_1`, `n = a × b`: the points are `P_1 + y_0 ± t n`,
/// `y_0 = (k_a b × n + k_b n × a)/(2|n|²)` in the centres' plane (`2 a·y = k_a`,
/// `2 b·y = k_b` from differences of the spheres), `t² = (L_1² − |y_0|²)/|n|²`.
fn meeting_points<'g>(geometry: &[Expr<'g>], q: &[Expr<'g>]) -> Vec<Vec<Expr<'g>>> {
    let centre = |i: usize| {
        let arm = arm(geometry, i);
        let theta = q[i] - arm.offset;
        let k = arm.axis.cross(&arm.zero);
        let along = arm.zero.scale(theta.cos()) + k.scale(theta.sin());
        let p = Vector(
            (arm.base + along.scale(arm.crank_length) - arm.platform)
                .0
                .map(Expr::keep),
        );
        (p, arm.rod_length * arm.rod_length)
    };
    let [(p1, r1), (p2, r2), (p3, r3)] = [centre(0), centre(1), centre(2)];
    let keep = |v: Vec3<'g>| Vector(v.0.map(Expr::keep));
    let (a, b) = (keep(p2 - p1), keep(p3 - p1));
    let n = keep(a.cross(&b));
    let n2 = n.dot(&n).keep();
    let ka = a.dot(&a) + r1 - r2;
    let kb = b.dot(&b) + r1 - r3;
    let half = (n2 * 2.0).recip();
    let y0 = keep((b.cross(&n).scale(ka) + n.cross(&a).scale(kb)).scale(half));
    let reach = (r1 - y0.dot(&y0)).keep();
    let t = (reach * n2.recip()).sqrt().keep();
    let mid = p1 + y0;
    let plus = mid + n.scale(t);
    let minus = mid - n.scale(t);
    vec![
        plus.to_vec().into_iter().chain(minus.to_vec()).collect(),
        vec![reach * r1.recip(), n2 * (a.dot(&a) * b.dot(&b)).recip()],
    ]
}

const POSE_TERMS: Output = Output {
    name: "singular",
    shape: Shape::Vector(6),
    doc: "`|u_i × r_i|` for each arm (its U joints' sine), then `1 - (K/ρ)²` for each arm \
          (zero where crank and rods align, negative where the platform is out of the crank's \
          reach): the other results are meaningless where one is near zero or negative",
};
const SOLVE_TERMS: Output = Output {
    name: "singular",
    shape: Shape::Vector(7),
    doc: "`|u_i × r_i|` for each arm, `1 - (K/ρ)²` for each arm, then the arms' hold \
          `det(J⁻¹)² / Π |row_i|²` in `[0, 1]` (zero where they cannot hold the platform): the \
          other results are meaningless where one is near zero or negative",
};
const FORWARD_TERMS: Output = Output {
    name: "singular",
    shape: Shape::Vector(2),
    doc: "`(L_1² - |y_0|²)/L_1²` (negative where the three spheres miss, zero where the two \
          points merge) and `|n|²/(|a|² |b|²)` (zero where the spheres' centres line up): the \
          points are meaningless where one is near zero or negative",
};
const GAMMA: Output = Output {
    name: "gamma",
    shape: Shape::Vector(3),
    doc: "`Γ`, the motors' torques about their axes `r_i` (N·m), arm order",
};
const ACCEL: Output = Output {
    name: "accel",
    shape: Shape::Vector(3),
    doc: "the platform's acceleration `a_C` (m/s²), base frame",
};
const Q: Output = Output {
    name: "q",
    shape: Shape::Vector(3),
    doc: "the motors' angles `θ_i + o_i` (rad), arm order",
};
const JINV: Output = Output {
    name: "jinv",
    shape: Shape::Matrix(3, 3),
    doc: "`J⁻¹`, row `i` for arm `i+1`, columns `[vx vy vz]`: `q̇ = J⁻¹ v_C`",
};

/// A kernel of the Delta: its robot's parameters as `params`, its terms its last result.
const fn decl(
    kernel: Kernel,
    title: &'static str,
    quantity: Quantity,
    inputs: &'static [Input],
    outputs: &'static [Output],
    build: super::kernels::RobotBuild,
) -> Decl {
    Decl {
        kernel,
        title,
        doc: "",
        equations: Cite::Model(quantity),
        inputs,
        outputs,
        guard: Guard::Never,
        reads: Reads::Robot,
        // The many-state callers' kernel; whether it is emitted is the crate's choice
        // (`CheckedIn::batched`).
        batch: matches!(kernel, Kernel::InverseDynamics),
        chapter: None,
        build: Build::Robot(build),
    }
}

const POSITION: &[Input] = &[Input::Position];
const MOTION: &[Input] = &[Input::Position, Input::Velocity, Input::LinearAccel];

/// Every kernel of the Delta.
const KERNELS: &[Decl] = &[
    decl(
        Kernel::SingularityTerms,
        "The singularity terms at a position: each U joint's sine, each crank's reach, and the \
         arms' hold on the platform.",
        Quantity::InverseJacobian,
        POSITION,
        &[SOLVE_TERMS],
        |cx| vec![solve_terms(cx.geometry, &Translation::of(cx).position)],
    ),
    decl(
        Kernel::InverseKinematics,
        "Inverse kinematics: the motors' angles at a position.",
        Quantity::InverseKinematics,
        POSITION,
        &[Q, POSE_TERMS],
        |cx| {
            let c = Translation::of(cx).position;
            let q = (0..3)
                .map(|i| {
                    let arm = arm(cx.geometry, i);
                    arm.actuator_at(&(c + arm.platform))
                })
                .collect();
            vec![q, pose_terms(cx.geometry, &c)]
        },
    ),
    decl(
        Kernel::InverseJacobianPose,
        "Inverse Jacobian `J⁻¹` at a position.",
        Quantity::InverseJacobian,
        POSITION,
        &[JINV, POSE_TERMS],
        |cx| {
            let at = Translation::of(cx);
            let jinv = inverse_jacobian(&arm_states(cx.geometry, None, &at));
            vec![jinv.rows(), pose_terms(cx.geometry, &at.position)]
        },
    ),
    decl(
        Kernel::JacobianPose,
        "Jacobian `J = (J⁻¹)⁻¹` at a position: `v_C = J q̇`.",
        Quantity::Jacobian,
        POSITION,
        &[
            Output {
                name: "jacobian",
                shape: Shape::Matrix(3, 3),
                doc: "`J`, rows `[vx vy vz]`, column `i` for arm `i+1`",
            },
            SOLVE_TERMS,
        ],
        |cx| {
            let at = Translation::of(cx);
            let jinv = inverse_jacobian(&arm_states(cx.geometry, None, &at));
            let inverse_det = jinv.determinant().recip().keep();
            let jac = jinv.adjugate().scale(inverse_det);
            vec![jac.rows(), solve_terms(cx.geometry, &at.position)]
        },
    ),
    decl(
        Kernel::JointVelocities,
        "The motors' rates `q̇ = J⁻¹ v_C`.",
        Quantity::JointVelocities,
        &[Input::Position, Input::Velocity],
        &[
            Output {
                name: "qd",
                shape: Shape::Vector(3),
                doc: "the motors' rates (rad/s), arm order",
            },
            POSE_TERMS,
        ],
        |cx| {
            let at = Translation::of(cx);
            let states = arm_states(cx.geometry, None, &at);
            let qd = (inverse_jacobian(&states) * at.velocity).to_vec();
            vec![qd, pose_terms(cx.geometry, &at.position)]
        },
    ),
    decl(
        Kernel::JointAccelerations,
        "The motors' accelerations `q̈` from the platform's motion.",
        Quantity::JointAccelerations,
        MOTION,
        &[
            Output {
                name: "qdd",
                shape: Shape::Vector(3),
                doc: "the motors' accelerations (rad/s²), arm order",
            },
            POSE_TERMS,
        ],
        |cx| {
            let at = Translation::of(cx);
            let states = arm_states(cx.geometry, None, &at);
            let qdd = states.iter().map(|s| s.qdd).collect();
            vec![qdd, pose_terms(cx.geometry, &at.position)]
        },
    ),
    decl(
        Kernel::InverseDynamics,
        "Inverse dynamics: the motors' torques `Γ` from the platform's motion.",
        Quantity::InverseDynamics,
        MOTION,
        &[GAMMA, SOLVE_TERMS],
        |cx| {
            let at = Translation::of(cx);
            vec![
                inverse_dynamics(cx.geometry, cx.dynamics, &at).0.to_vec(),
                solve_terms(cx.geometry, &at.position),
            ]
        },
    ),
    decl(
        Kernel::TaskInertia,
        "Task-space inertia `M_x` of `Γ = Jᵀ (M_x a_C + h)`: symmetric positive definite.",
        Quantity::TaskSpace,
        POSITION,
        &[
            Output {
                name: "m",
                shape: Shape::Matrix(3, 3),
                doc: "`M_x = ∂(J⁻ᵀ Γ)/∂a_C` (kg), rows and columns `[vx vy vz]`, base frame",
            },
            POSE_TERMS,
        ],
        |cx| {
            let position = Translation::of(cx).position;
            vec![
                task_inertia(cx, &position).rows(),
                pose_terms(cx.geometry, &position),
            ]
        },
    ),
    decl(
        Kernel::TaskBias,
        "Task-space bias `h` of `Γ = Jᵀ (M_x a_C + h)`: the arms' velocity terms and gravity.",
        Quantity::TaskSpace,
        &[Input::Position, Input::Velocity],
        &[
            Output {
                name: "h",
                shape: Shape::Vector(3),
                doc: "`h`, the force at `C` at rest acceleration (N), base frame",
            },
            POSE_TERMS,
        ],
        |cx| {
            let at = Translation::of(cx);
            vec![
                task_bias(cx, &at).0.to_vec(),
                pose_terms(cx.geometry, &at.position),
            ]
        },
    ),
    decl(
        Kernel::ForwardDynamics,
        "Forward dynamics: the platform's acceleration `a_C` under the motors' torques.",
        Quantity::ForwardDynamics,
        &[Input::Position, Input::Velocity, Input::Gamma],
        &[ACCEL, SOLVE_TERMS],
        |cx| {
            let at = Translation::of(cx);
            let gamma = vec3(&cx.input(Input::Gamma));
            vec![
                forward_dynamics(cx, &at, &gamma).to_vec(),
                solve_terms(cx.geometry, &at.position),
            ]
        },
    ),
    decl(
        Kernel::ForwardKinematics,
        "Forward kinematics in closed form: the two positions whose arms have the motors' \
         angles.",
        Quantity::InverseKinematics,
        &[Input::Actuators],
        &[
            Output {
                name: "positions",
                shape: Shape::Matrix(2, 3),
                doc: "the two points `C` where the arms' spheres meet (m), base frame: a \
                      robot's is the one on its home's side of the centres' plane",
            },
            FORWARD_TERMS,
        ],
        |cx| meeting_points(cx.geometry, &cx.input(Input::Actuators)),
    ),
    calibration::decl(
        "`r_i = q_i(C; θ) - q̂_i` with `q_i = θ_i(C) + o_i`, the motor angle the geometry `θ` \
         (the `params`) gives at the measured position `C` (the inverse kinematics, with its \
         branch), less the encoder's reading `q̂_i` (rad). Arm `i`'s residual depends on its \
         own eight parameters only (`A_i`, the motor axis's azimuth and elevation, `c_i`, `L_i`, \
         `o_i`; its `p_i` moves it as `-A_i` does): row `i` of `geometry_jacobian` holds those \
         eight derivatives; `pose_jacobian` is \
         `∂q/∂C`, which carries the position's measurement noise into the residuals.",
        POSITION_AND_ANGLES,
        &CALIBRATION_OUTPUTS,
        |cx| {
            let c = Translation::of(cx).position;
            let legs = calibration::Legs {
                balls: (0..3).map(|i| c + arm(cx.geometry, i).platform).collect(),
                actuator: &|i, b| arm(cx.geometry, i).actuator_at(b),
                leg_size: ARM_GEOMETRY,
            };
            calibration::build(cx, &legs, &c.to_vec(), &c5_robot::calibration::DELTA_ARM)
        },
    ),
];

const POSITION_AND_ANGLES: &[Input] = &[Input::Position, Input::Actuators];

const CALIBRATION_OUTPUTS: [Output; 3] = super::calibration::outputs(
    3,
    c5_robot::calibration::DELTA_ARM.len(),
    3,
    "`∂q_i/∂(A_i, r_i, c_i, L_i, o_i)`, row `i` for arm `i+1`, columns \
     `A_x A_y A_z r_az r_el c L o` (base frame; the crank's zero turns with the axis)",
    "`∂q/∂C`, row `i` for arm `i+1`, columns `xc yc zc`",
);

impl Structure for DeltaMechanics {
    fn parameter_names(&self) -> Vec<String> {
        Delta::kernel_parameter_names()
    }

    fn geometry_parameters(&self) -> usize {
        GEOMETRY_PARAMETERS
    }

    fn freedom(&self) -> Freedom {
        Freedom::Translations
    }

    /// The Delta has no six-freedom pose: its kernels read [`Input::Position`].
    fn pose<'g>(&self, geometry: &[Expr<'g>], _x: &[Expr<'g>]) -> Posed<'g> {
        no_six_freedoms(geometry[0].graph(), "a pose");
        let g = geometry[0].graph();
        Posed {
            r: Mat::zeros(g),
            c: Vec3::zeros(g),
            q: [g.zero(); 6],
            p: [Vec3::zeros(g); 6],
            forward: None,
            geometry: geometry.to_vec(),
            centre_in_platform: None,
        }
    }

    fn dynamics<'g>(&self, parameters: &[Expr<'g>]) -> Dynamics<'g> {
        dynamics_of(vec3(&parameters[..3]), &parameters[GEOMETRY_PARAMETERS..])
    }

    fn standard_inertial_names(&self) -> Vec<String> {
        Delta::standard_inertial_names()
    }

    fn standard_inertial_doc(&self) -> &'static str {
        "the platform's mass, then each arm's crank (mass, first moment along the crank, its \
         three inertias about `A_i`, crank frame) and each of its two rods (mass, first moment \
         along the rod, transverse and axial inertia about its U joint, rod frame)"
    }

    fn dynamics_from_standard<'g>(
        &self,
        _g: &'g Graph,
        gravity: Vec3<'g>,
        p: &[Expr<'g>],
    ) -> Dynamics<'g> {
        dynamics_of(gravity, p)
    }

    /// The Delta's kernels return their terms as declared outputs.
    fn guard<'g>(&self, _guard: Guard, posed: &Posed<'g>) -> Vec<Expr<'g>> {
        no_six_freedoms(posed.c[0].graph(), "a guard of the shared table");
        Vec::new()
    }

    /// The singularity terms at the kernel's position, and the arms' hold.
    fn guard_at<'g>(&self, _guard: Guard, cx: &Context<'_, 'g>) -> Vec<Expr<'g>> {
        solve_terms(cx.geometry, &Translation::of(cx).position)
    }

    fn guard_output(&self, _guard: Guard) -> (Output, &'static str) {
        (SOLVE_TERMS, "")
    }

    fn singularity_terms(&self) -> Vec<SingularityTerm> {
        let mut all = terms::u_joints(3, |i| format!("U joints of arm {i}"));
        all.extend(terms::reaches(
            3,
            |i| format!("crank and rods of arm {i} aligned (1 - (K/ρ)²)"),
            |i| format!("platform beyond the reach of arm {i} (1 - (K/ρ)²)"),
        ));
        all.push(terms::single(
            TermKind::Hold,
            "arms' hold (det(J⁻¹)² / Π |row|²)",
        ));
        all
    }

    fn forward_kinematics_terms(&self) -> Vec<SingularityTerm> {
        vec![
            terms::single(
                TermKind::ForwardKinematics,
                "the arms' spheres do not meet, or touch at one point ((L² - |y0|²)/L²)",
            ),
            terms::single(
                TermKind::ForwardKinematics,
                "the arms' sphere centres in a line (|n|²/(|a|² |b|²))",
            ),
        ]
    }

    fn conventions(&self) -> &'static str {
        "Actuators in arm order 1..3; `q_i = θ_i + o_i`, the encoder's reading of the upper \
         arm's angle `θ_i` (rad, right-handed about the motor's axis `r_i`, zero along `h_i`), \
         `θ_i = atan2(e2, e1) + b_i acos(K/ρ)` reaching `B_i = C + p_i`; `Γ_i` is the motor's \
         torque about `r_i` (N·m). The platform translates only: its state is `C`, `v_C`, \
         `a_C` (base frame)."
    }

    fn parameter_doc(&self, _reads: Reads) -> &'static str {
        "robot parameters (`Delta::kernel_parameters`: gravity, each arm's geometry and its \
         parallelogram's separation, the platform's mass, each body's standard inertial \
         parameters), in the order of the names in this signature"
    }

    /// None of the shared table's kernels, which take a six-freedom pose: the Delta's are
    /// its own ([`Mechanics::extra_kernels`]).
    fn has_kernel(&self, _kernel: Kernel) -> bool {
        false
    }

    fn home(&self, parameters: &[f64]) -> [f64; 6] {
        let c = description(parameters).home().unwrap_or([0.0; 3]);
        [0.0, 0.0, 0.0, c[0], c[1], c[2]]
    }

    fn reach(&self, parameters: &[f64]) -> f64 {
        let d = description(parameters);
        d.arms.iter().map(|a| a.crank.length).sum::<f64>() / 3.0 * 0.5
    }
}

/// Marks the graph invalid, so that generation fails naming what was asked: a six-freedom
/// quantity of the Delta, whose platform only translates.
fn no_six_freedoms(g: &Graph, what: &str) {
    g.invalidate(format!(
        "the Delta's platform only translates: it has no {what} of six freedoms"
    ));
}

/// A description with `parameters`' geometry (its bodies the example's): what the seeded
/// states' home needs.
fn description(parameters: &[f64]) -> Delta {
    let mut robot = Delta::example();
    for (i, arm) in robot.arms.iter_mut().enumerate() {
        let at = &parameters[3 + ARM_GEOMETRY * i..3 + ARM_GEOMETRY * (i + 1)];
        arm.base.copy_from_slice(&at[0..3]);
        arm.axis.copy_from_slice(&at[3..6]);
        arm.zero.copy_from_slice(&at[6..9]);
        arm.platform.copy_from_slice(&at[9..12]);
        arm.crank.length = at[12];
        arm.rod.length = at[13];
        arm.branch = at[14];
        arm.encoder_offset = at[15];
        arm.rod.separation = Some(at[16]);
    }
    robot
}

/// The six-freedom methods of [`Mechanics`], which no kernel of the Delta calls: each marks
/// the graph invalid ([`no_six_freedoms`]) and returns zeros.
macro_rules! six_freedoms_absent {
    ($($name:ident($($arg:ident: $ty:ty),*) -> $out:ident from $posed:ident;)*) => {
        $(fn $name<'g>(&self, $($arg: $ty),*) -> $out<'g> {
            let g = $posed.c[0].graph();
            no_six_freedoms(g, stringify!($name));
            $out::zeros(g)
        })*
    };
}

impl Mechanics for DeltaMechanics {
    fn name(&self) -> &'static str {
        c5_robot::description::DELTA
    }

    fn structure(&self) -> &'static dyn Structure {
        &DeltaMechanics
    }

    fn summary(&self) -> &'static str {
        "The Delta: three motors on the base turn upper arms; a parallelogram of two rods from \
         each arm's tip keeps the platform parallel to the base, so it only translates; every \
         quantity derived from the arm's closed forms by exact differentiation."
    }

    fn equations(&self, quantity: Quantity) -> &'static [&'static str] {
        const IK: &str = "θ = atan2(e2, e1) + b acos(K/ρ)";
        match quantity {
            Quantity::InverseKinematics => &[IK, "|C + p_i − E_i(θ_i)| = L_i"],
            Quantity::InverseJacobian | Quantity::Jacobian | Quantity::JointVelocities => {
                &[IK, "∂θ/∂C"]
            }
            Quantity::JointAccelerations => &[IK, "d²θ/dt²"],
            Quantity::ForwardDynamics => {
                &["Newton-Euler", "virtual work", "M_x a_C = J⁻ᵀ Γ − h (LDLᵀ)"]
            }
            Quantity::TaskSpace => &["Newton-Euler", "virtual work", "∂W/∂a_C"],
            _ => &[
                IK,
                "Newton-Euler",
                "virtual work",
                "J⁻ᵀ Γ = m (a_C − g) + Φ",
            ],
        }
    }

    six_freedoms_absent! {
        inverse_jacobian(posed: &Posed<'g>) -> Mat6 from posed;
        jacobian(posed: &Posed<'g>) -> Mat6 from posed;
        joint_velocities(posed: &Posed<'g>, _twist: &Vec6<'g>) -> Vec6 from posed;
        joint_accelerations(posed: &Posed<'g>, _motion: &Motion<'g>) -> Vec6 from posed;
        leg_wrench(_dynamics: &Dynamics<'g>, posed: &Posed<'g>, _motion: &Motion<'g>) -> Vec6 from posed;
        inverse_dynamics(_dynamics: &Dynamics<'g>, posed: &Posed<'g>, _motion: &Motion<'g>) -> Vec6 from posed;
    }

    /// `Γ` from `J⁻ᵀ Γ = W` and the motors' rates `J⁻¹ v_C`, at the kernel's translation.
    fn regressor_terms<'g>(
        &self,
        cx: &Context<'_, 'g>,
        dynamics: &Dynamics<'g>,
    ) -> (Vec<Expr<'g>>, Vec<Expr<'g>>) {
        let at = Translation::of(cx);
        let (gamma, jinv) = inverse_dynamics(cx.geometry, dynamics, &at);
        (gamma.to_vec(), (jinv * at.velocity).to_vec())
    }

    fn extra_kernels(&self) -> &'static [Decl] {
        KERNELS
    }

    fn extra_derivative_kernels(&self) -> &'static [Decl] {
        DERIVATIVE_KERNELS
    }
}

/// A 3×3 Jacobian output.
const fn jacobian(name: &'static str, doc: &'static str) -> Output {
    Output {
        name,
        shape: Shape::Matrix(3, 3),
        doc,
    }
}

/// The Delta's derivative kernels (feature `derivatives` of `c5-generated`): the inverse
/// dynamics by the implicit function theorem on `J⁻ᵀ Γ = W` ([`derivatives::by_wrench_residual`],
/// through its own solve, `M_x` for `∂W/∂a_C`); the forward dynamics by the implicit function
/// theorem on `ID(C, v_C, a_C) = Γ` ([`super::derivatives::Implicit`]), `∂a_C/∂Γ` the exact
/// derivative of its own solve. The optimizer takes each in the cheaper mode
/// ([`crate::dag::Policy::reverse_mode`]): reverse for the first (4 090 multiplications, 5 335
/// in forward mode), forward for the second (5 546, 5 868 in reverse mode).
const DERIVATIVE_KERNELS: &[Decl] = &[
    decl(
        Kernel::InverseDynamicsDerivatives,
        "Inverse dynamics and its exact Jacobians: `Γ`, `∂Γ/∂C`, `∂Γ/∂v_C`, `∂Γ/∂a_C`; row `i` \
         arm `i+1`, columns `x y z`. `∂Γ/∂a_C = Jᵀ M_x`.",
        Quantity::InverseDynamics,
        MOTION,
        &[
            GAMMA,
            jacobian("d_pose", "`∂Γ/∂C` (N·m/m)"),
            jacobian("d_twist", "`∂Γ/∂v_C` (N·m·s/m)"),
            jacobian("d_accel", "`∂Γ/∂a_C` (N·m·s²/m)"),
            SOLVE_TERMS,
        ],
        |cx| {
            let at = Translation::of(cx);
            let states = arm_states(cx.geometry, Some(cx.dynamics), &at);
            let wrench = task_force(cx.dynamics, &at, &states).to_vec();
            let jinv_t = inverse_jacobian(&states).transpose();
            let gamma = jinv_t.solve(&vec3(&wrench)).to_vec();
            let inertia = task_inertia(cx, &at.position);
            let wrt: Vec<Vec<Expr>> = MOTION.iter().map(|&kind| cx.input(kind)).collect();
            let jacobians = derivatives::by_wrench_residual(
                &wrench,
                |x| (jinv_t * vec3(x)).to_vec(),
                &gamma,
                |w| jinv_t.solve(&vec3(w)).to_vec(),
                |x| {
                    let k = at.accel.0.iter().position(|a| a.id == x.id)?;
                    Some(inertia.column(k).to_vec())
                },
                &wrt,
            );
            let mut out = vec![gamma];
            out.extend(jacobians);
            out.push(solve_terms(cx.geometry, &at.position));
            out
        },
    ),
    decl(
        Kernel::ForwardDynamicsDerivatives,
        "Forward dynamics and its exact Jacobians: `a_C`, `∂a_C/∂C`, `∂a_C/∂v_C`, `∂a_C/∂Γ`; \
         rows `ax ay az`. `∂a_C/∂Γ = M_x⁻¹ J⁻ᵀ`; `∂a_C/∂x = -(∂a_C/∂Γ) ∂ID/∂x`.",
        Quantity::ForwardDynamics,
        &[Input::Position, Input::Velocity, Input::Gamma],
        &[
            ACCEL,
            jacobian("d_pose", "`∂a_C/∂C` (1/s²)"),
            jacobian("d_twist", "`∂a_C/∂v_C` (1/s)"),
            jacobian("d_gamma", "`∂a_C/∂Γ` (m/s²/(N·m))"),
            SOLVE_TERMS,
        ],
        |cx| {
            let g = cx.graph();
            let at = Translation::of(cx);
            let forces = cx.input(Input::Gamma);
            let accel = forward_dynamics(cx, &at, &vec3(&forces)).to_vec();
            let d_gamma = g.jacobian(&accel, &forces);
            let unknown: Vec3 = Vector::from_fn(|k| g.input(INTERNAL_INPUTS + k as u32));
            let probe = Translation {
                accel: unknown,
                ..at
            };
            let gamma = inverse_dynamics(cx.geometry, cx.dynamics, &probe)
                .0
                .to_vec();
            let implicit = derivatives::Implicit {
                d_gamma: &d_gamma,
                gamma: &gamma,
                unknown: &unknown.to_vec(),
                accel: &accel,
            };
            let d_pose = implicit.jacobian(&cx.input(Input::Position));
            let d_twist = implicit.jacobian(&cx.input(Input::Velocity));
            let terms = solve_terms(cx.geometry, &at.position);
            vec![accel, d_pose, d_twist, d_gamma, terms]
        },
    ),
];

#[cfg(test)]
mod tests;
