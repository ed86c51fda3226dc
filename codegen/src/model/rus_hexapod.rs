//! The rotary hexapod (6-RUS): six R-U-S legs ([`legged::rus`]) carry the platform.
//!
//! As for the Gough-Stewart platform, everything is derived by [`legged`] from the leg's closed
//! forms: the crank angle `θ_i` from the ball `B_i = C + R p_i` (with its branch), and the
//! crank's and the rod's frames. The rates and accelerations are the exact derivatives of
//! `θ_i`, the legs' wrench comes from their bodies' Newton-Euler equations by virtual work, and
//! the inverse dynamics solves `J⁻ᵀ Γ = F_{N+1} + Φ` through the normal equations. The
//! parameter vector and the descriptions' conventions are `c5_robot::RusHexapod`'s.

use super::bodies::{Dynamics, Inertial};
use super::calibration;
use super::geometry::{rotation_of_pose, Posed};
use super::kernels::{Build, Cite, Decl, Guard, Input, Kernel, Output, Reads};
use super::legged::{self, rus::Rus, Leg};
use super::terms::{self, SingularityTerm};
use super::{Mechanics, Quantity, Structure};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Mat, Mat3, Vec3, Vector};
use c5_robot::rus::{CRANK_STANDARD, LEG_GEOMETRY, ROD_STANDARD};
use c5_robot::rus_hexapod::GEOMETRY_PARAMETERS;
use c5_robot::RusHexapod;

/// The rotary hexapod's [`Structure`] and [`Mechanics`].
pub struct RusHexapodMechanics;

/// The standard parameters of one leg: the crank's, then the rod's.
const LEG_BODIES: usize = CRANK_STANDARD.len() + ROD_STANDARD.len();

fn vec3<'g>(v: &[Expr<'g>]) -> Vec3<'g> {
    Vector([v[0], v[1], v[2]])
}

/// Leg `i` of the geometry, massless.
fn leg<'g>(geometry: &[Expr<'g>], i: usize) -> Rus<'g> {
    let at = &geometry[3 + LEG_GEOMETRY * i..3 + LEG_GEOMETRY * (i + 1)];
    let massless = Inertial::massless(at[0].graph());
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
        rods: vec![at[0].graph().zero()],
        closed_form: true,
    }
}

/// The crank's standard parameters `[m, m x, Ixx, Iyy, Izz]` (about `A_i`, crank frame).
pub(super) fn crank_body<'g>(p: &[Expr<'g>]) -> Inertial<'g> {
    let z = p[0].graph().zero();
    Inertial {
        mass: p[0],
        first_moment: Vector([p[1], z, z]),
        inertia: Mat([[p[2], z, z], [z, p[3], z], [z, z, p[4]]]),
    }
}

/// The rod's standard parameters `[m, m z, It, Ia]` (about the crank's tip, rod frame).
pub(super) fn rod_body<'g>(p: &[Expr<'g>]) -> Inertial<'g> {
    let z = p[0].graph().zero();
    Inertial {
        mass: p[0],
        first_moment: Vector([z, z, p[1]]),
        inertia: Mat([[p[2], z, z], [z, p[2], z], [z, z, p[3]]]),
    }
}

/// The dynamics from the standard inertial parameters `p` (platform, then each leg's crank
/// and rod) and gravity.
fn dynamics_of<'g>(gravity: Vec3<'g>, p: &[Expr<'g>]) -> Dynamics<'g> {
    let g = p[0].graph();
    let leg = |i: usize| &p[10 + LEG_BODIES * i..10 + LEG_BODIES * (i + 1)];
    Dynamics {
        gravity,
        platform: Inertial::from_standard(&p[..10]),
        legs: std::array::from_fn(|i| {
            let (crank, rod) = leg(i).split_at(CRANK_STANDARD.len());
            [crank_body(crank), rod_body(rod)]
        }),
        rod_inertia_per_length_squared: [Mat::zeros(g); 6],
    }
}

impl legged::Legs for RusHexapodMechanics {
    fn legs<'g>(
        &self,
        geometry: &[Expr<'g>],
        dynamics: Option<&Dynamics<'g>>,
    ) -> Vec<Box<dyn Leg<'g> + 'g>> {
        (0..6)
            .map(|i| {
                let mut leg = leg(geometry, i);
                if let Some(d) = dynamics {
                    [leg.crank, leg.rod] = d.legs[i];
                }
                Box::new(leg) as Box<dyn Leg<'g> + 'g>
            })
            .collect()
    }

    /// `ℓ² = Σ |p_i|²/6`, the platform's joints' mean squared radius: a crank turns by about
    /// as much per radian of the platform as per `ℓ` metres.
    fn translation_weight<'g>(&self, geometry: &[Expr<'g>]) -> Option<Expr<'g>> {
        let sum = (0..6).fold(geometry[0].graph().zero(), |sum, i| {
            let p = leg(geometry, i).platform;
            sum + p.dot(&p)
        });
        Some((sum * (1.0 / 6.0)).keep())
    }
}

/// `B_i = C + R p_i`, built as the legs' derivation builds it (`R p_i` a unit), so that every
/// kernel computes it once.
fn ball<'g>(geometry: &[Expr<'g>], r: &Mat3<'g>, c: &Vec3<'g>, i: usize) -> Vec3<'g> {
    *c + Vector((*r * leg(geometry, i).platform).0.map(Expr::keep))
}

/// Per leg, `|u_i × r_i|` (the U joint's sine), then per leg `1 - (K/ρ)²` (crank and rod
/// aligned where it vanishes, the ball out of reach where it is negative).
fn pose_terms<'g>(posed: &Posed<'g>) -> Vec<Expr<'g>> {
    let legs: Vec<(Expr<'g>, Expr<'g>)> = (0..6)
        .map(|i| {
            let leg = leg(&posed.geometry, i);
            let b = ball(&posed.geometry, &posed.r, &posed.c, i);
            let crank = leg.crank_state(&b);
            let (_, sine) = leg.rod_frame(&crank.elbow, &b);
            (sine, crank.aligned)
        })
        .collect();
    legs.iter()
        .map(|t| t.0)
        .chain(legs.iter().map(|t| t.1))
        .collect()
}

const POSE_TERMS: Output = Output {
    name: "singular",
    shape: Shape::Vector(12),
    doc: "`|u_i × r_i|` for each leg (its U joint's sine), then `1 - (K/ρ)²` for each leg (zero \
          where crank and rod align, negative where the ball is out of the crank's reach): the \
          other results are meaningless where one is near zero or negative",
};
const SOLVE_TERMS: Output = Output {
    name: "singular",
    shape: Shape::Vector(18),
    doc: "`|u_i × r_i|` for each leg (its U joint's sine), `1 - (K/ρ)²` for each leg (crank and \
          rod aligned at zero, out of reach below), then the six pivots of the `LDLᵀ` of \
          `J⁻¹ J⁻ᵀ` over its diagonal, in `(0, 1]` (the legs' hold on the platform): the other \
          results are meaningless where one is near zero or negative",
};

impl Structure for RusHexapodMechanics {
    fn parameter_names(&self) -> Vec<String> {
        RusHexapod::kernel_parameter_names()
    }

    fn geometry_parameters(&self) -> usize {
        GEOMETRY_PARAMETERS
    }

    fn pose<'g>(&self, geometry: &[Expr<'g>], x: &[Expr<'g>]) -> Posed<'g> {
        let r = rotation_of_pose(x);
        let c = vec3(&x[3..6]);
        let balls: [Vec3<'g>; 6] = std::array::from_fn(|i| ball(geometry, &r, &c, i));
        Posed {
            r,
            c,
            q: std::array::from_fn(|i| leg(geometry, i).actuator_at(&balls[i])),
            p: std::array::from_fn(|i| c - balls[i]),
            forward: None,
            geometry: geometry.to_vec(),
            centre_in_platform: None,
        }
    }

    fn dynamics<'g>(&self, parameters: &[Expr<'g>]) -> Dynamics<'g> {
        dynamics_of(vec3(&parameters[..3]), &parameters[GEOMETRY_PARAMETERS..])
    }

    fn standard_inertial_names(&self) -> Vec<String> {
        RusHexapod::standard_inertial_names()
    }

    fn standard_inertial_doc(&self) -> &'static str {
        "the platform's ten (mass, first moment `m c`, inertia about `C`, platform frame), \
         then each leg's crank (mass, first moment along the crank, its three inertias about \
         `A_i`, crank frame) and rod (mass, first moment along the rod, transverse and axial \
         inertia about the crank's tip, rod frame)"
    }

    fn dynamics_from_standard<'g>(
        &self,
        _g: &'g Graph,
        gravity: Vec3<'g>,
        p: &[Expr<'g>],
    ) -> Dynamics<'g> {
        dynamics_of(gravity, p)
    }

    fn guard<'g>(&self, guard: Guard, posed: &Posed<'g>) -> Vec<Expr<'g>> {
        match guard {
            Guard::Never | Guard::Forward => Vec::new(),
            Guard::Pose => pose_terms(posed),
            Guard::Solve => {
                let mut terms = pose_terms(posed);
                terms.extend(legged::pivot_ratios(&legged::rows_at(self, posed)));
                terms
            }
        }
    }

    fn guard_output(&self, guard: Guard) -> (Output, &'static str) {
        match guard {
            Guard::Solve => (
                SOLVE_TERMS,
                "\nThe last result holds the U joints' sines, the cranks' reach and the solve's \
                 pivots for a singularity check.",
            ),
            _ => (
                POSE_TERMS,
                "\nThe last result holds the U joints' sines and the cranks' reach for a \
                 singularity check.",
            ),
        }
    }

    fn singularity_terms(&self) -> Vec<SingularityTerm> {
        let mut all = terms::u_joints(6, |i| format!("U joint of leg {i}"));
        all.extend(terms::reaches(
            6,
            |i| format!("crank and rod of leg {i} aligned (1 - (K/ρ)²)"),
            |i| format!("ball of leg {i} beyond its crank's reach (1 - (K/ρ)²)"),
        ));
        all.extend(terms::pivots());
        all
    }

    fn conventions(&self) -> &'static str {
        "Actuators in leg order 1..6; `q_i = θ_i + o_i`, the encoder's reading of the crank \
         angle `θ_i` (rad, right-handed about the motor's axis `r_i`, zero along `h_i`), \
         `θ_i = atan2(e2, e1) + b_i acos(K/ρ)` reaching `B_i = C + R p_i`; `Γ_i` is the \
         motor's torque about `r_i` (N·m)."
    }

    fn parameter_doc(&self, reads: Reads) -> &'static str {
        match reads {
            Reads::Geometry => {
                "gravity, then per leg `A_i`, the unit `r_i` and `h_i`, `p_i`, the crank's and \
                 the rod's lengths, the branch and the encoder's offset (the first entries of \
                 `RusHexapod::kernel_parameters`)"
            }
            _ => {
                "robot parameters (`RusHexapod::kernel_parameters`: gravity, the legs' \
                 geometry, each body's standard inertial parameters), in the order of the names \
                 in this signature"
            }
        }
    }

    fn has_kernel(&self, kernel: Kernel) -> bool {
        !legged::LACKS.contains(&kernel)
    }

    fn home(&self, parameters: &[f64]) -> [f64; 6] {
        description(parameters).home().unwrap_or([0.0; 6])
    }

    /// A rotary hexapod turns less than a linear one: with the 0.085 m cranks, the
    /// example's legs lost their hold on the platform (a pivot below 1e-8) at 18° of yaw with
    /// 12° of roll.
    fn turn_reach(&self) -> f64 {
        0.2
    }

    fn reach(&self, parameters: &[f64]) -> f64 {
        let d = description(parameters);
        d.legs.iter().map(|l| l.crank.length).sum::<f64>() / 6.0 * 0.5
    }
}

/// A description with `parameters`' geometry (its bodies the example's): what the seeded
/// states' home needs.
fn description(parameters: &[f64]) -> RusHexapod {
    let mut robot = RusHexapod::example();
    for (i, leg) in robot.legs.iter_mut().enumerate() {
        let at = &parameters[3 + LEG_GEOMETRY * i..3 + LEG_GEOMETRY * (i + 1)];
        leg.base.copy_from_slice(&at[0..3]);
        leg.axis.copy_from_slice(&at[3..6]);
        leg.zero.copy_from_slice(&at[6..9]);
        leg.platform.copy_from_slice(&at[9..12]);
        leg.crank.length = at[12];
        leg.rod.length = at[13];
        leg.branch = at[14];
        leg.encoder_offset = at[15];
    }
    robot
}

/// The rotary hexapod's own kernels: its singularity terms, and the Newton step of its forward
/// kinematics, which has no closed form.
const EXTRA_KERNELS: &[Decl] = &[
    Decl {
        kernel: Kernel::SingularityTerms,
        title: "The singularity terms at a pose: each U joint's sine, each crank's reach, and \
                the legs' hold on the platform.",
        doc: "Cheaper than the dynamics it guards: one check before them.",
        equations: Cite::Model(Quantity::InverseJacobian),
        inputs: &[Input::Pose],
        outputs: &[],
        guard: Guard::Solve,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|_| Vec::new()),
    },
    legged::newton::STEP,
    calibration::decl(
        "`r_i = q_i(X; θ) - q̂_i` with `q_i = θ_i(X) + o_i`, the crank angle the geometry `θ` \
         (the `params`) gives at the measured pose `X` (the inverse kinematics, with its \
         branch), less the encoder's reading `q̂_i` (rad). Leg `i`'s residual depends on its own \
         eleven parameters only (`A_i`, the motor axis's azimuth and elevation, `p_i`, `c_i`, \
         `L_i`, `o_i`): row `i` of `geometry_jacobian` holds those eleven derivatives; `pose_jacobian` is `∂q/∂X`, which \
         carries the pose's measurement noise into the residuals.",
        &[Input::Pose, Input::Actuators],
        &CALIBRATION_OUTPUTS,
        |cx| {
            let posed = cx.posed();
            let legs = calibration::Legs {
                balls: (0..6)
                    .map(|i| ball(cx.geometry, &posed.r, &posed.c, i))
                    .collect(),
                actuator: &|i, b| leg(cx.geometry, i).actuator_at(b),
                leg_size: LEG_GEOMETRY,
            };
            let pose = cx.input(Input::Pose);
            calibration::build(cx, &legs, &pose, &c5_robot::calibration::RUS)
        },
    ),
];

const CALIBRATION_OUTPUTS: [Output; 3] = calibration::outputs(
    6,
    c5_robot::calibration::RUS.len(),
    6,
    "`∂q_i/∂(A_i, r_i, p_i, c_i, L_i, o_i)`, row `i` for leg `i+1`, columns \
     `A_x A_y A_z r_az r_el p_x p_y p_z c L o` (base frame for `A` and the motor axis's azimuth \
     and elevation, platform frame for `p`; the crank's zero turns with the axis)",
    "`∂q/∂X`, row `i` for leg `i+1`, columns `α β γ xc yc zc`",
);

impl Mechanics for RusHexapodMechanics {
    fn name(&self) -> &'static str {
        c5_robot::description::RUS_HEXAPOD
    }

    fn structure(&self) -> &'static dyn Structure {
        &RusHexapodMechanics
    }

    fn summary(&self) -> &'static str {
        "The rotary hexapod (6-RUS): each leg a motor on the base turning a crank, a rod from a \
         universal joint at the crank's tip to a spherical joint on the platform; every \
         quantity derived from the leg's closed forms by exact differentiation."
    }

    fn equations(&self, quantity: Quantity) -> &'static [&'static str] {
        const IK: &str = "θ = atan2(e2, e1) + b acos(K/ρ)";
        match quantity {
            Quantity::InverseKinematics => &[IK],
            Quantity::PlatformWrench => &["Newton-Euler of the platform"],
            Quantity::InverseJacobian | Quantity::Jacobian | Quantity::JointVelocities => {
                &[IK, "∂θ/∂(θ, C)"]
            }
            Quantity::JointAccelerations => &[IK, "d²θ/dt²"],
            Quantity::LegWrench => &["legs' Newton-Euler", "virtual work"],
            Quantity::InverseDynamics | Quantity::Identification => &[
                IK,
                "Newton-Euler",
                "virtual work",
                "J⁻ᵀ Γ = F + Φ (LDLᵀ of J⁻¹ J⁻ᵀ)",
            ],
            Quantity::TaskSpace => &["Newton-Euler", "virtual work", "∂W/∂V̇"],
            Quantity::ForwardDynamics => {
                &["Newton-Euler", "virtual work", "M_x V̇ = J⁻ᵀ Γ - h (LDLᵀ)"]
            }
        }
    }

    legged::legged_mechanics!();

    fn extra_kernels(&self) -> &'static [Decl] {
        EXTRA_KERNELS
    }
}

#[cfg(test)]
mod tests;
