//! The Gough-Stewart platform (6-UPS): six U-P-S legs ([`legged::ups`]) carry the platform.
//!
//! Everything is derived by [`legged`] from the leg's closed forms: `J⁻¹` row `i` is
//! `[(R p_i × u_i)ᵀ u_iᵀ]`, the rates and accelerations are the exact derivatives of
//! `q_i = |C + R p_i - A_i| + o_i`, the legs' wrench comes from their bodies' Newton-Euler
//! equations by virtual work, and the inverse dynamics solves `J⁻ᵀ Γ = F_{N+1} + Φ` through the
//! normal equations (`LDLᵀ`, no pivoting needed). The parameter vector and the descriptions'
//! conventions are `c5_robot::GoughStewart`'s.

use super::bodies::{Dynamics, Inertial};
use super::calibration;
use super::geometry::{rotation_of_pose, Posed};
use super::kernels::{Build, Cite, Decl, Guard, Input, Kernel, Output, Reads};
use super::legged::{self, ups::Ups, Leg};
use super::terms::{self, SingularityTerm};
use super::{Mechanics, Quantity, Structure};
use crate::dag::{Expr, Graph};
use crate::kernel::Shape;
use crate::linalg::{Mat, Mat3, Vec3, Vector};
use c5_robot::gough_stewart::{GEOMETRY_PARAMETERS, LEG_BODY_STANDARD};
use c5_robot::GoughStewart;

/// The Gough-Stewart platform's [`Structure`].
pub struct GoughStewartStructure;

/// The Gough-Stewart platform's [`Mechanics`].
pub struct GoughStewartMechanics;

/// The entries of one leg in the geometry: `A_i`, `a_i`, `p_i`, the offset.
const LEG_GEOMETRY: usize = 10;
/// The standard parameters of one leg body.
const LEG_BODY: usize = LEG_BODY_STANDARD.len();

/// One leg's geometry: `A_i`, the unit `a_i`, `p_i` and the encoder's offset.
struct LegGeometry<'g> {
    base: Vec3<'g>,
    axis: Vec3<'g>,
    platform: Vec3<'g>,
    offset: Expr<'g>,
}

fn vec3<'g>(v: &[Expr<'g>]) -> Vec3<'g> {
    Vector([v[0], v[1], v[2]])
}

/// Leg `i`'s geometry from the mechanism's geometric parameters.
fn leg_geometry<'g>(geometry: &[Expr<'g>], i: usize) -> LegGeometry<'g> {
    let at = &geometry[3 + LEG_GEOMETRY * i..3 + LEG_GEOMETRY * (i + 1)];
    LegGeometry {
        base: vec3(&at[0..3]),
        axis: vec3(&at[3..6]),
        platform: vec3(&at[6..9]),
        offset: at[9],
    }
}

/// A leg body's standard parameters `[m, m c_z, It, Ia]` as inertial parameters in the leg
/// frame: the first moment along `z'`, the inertia `diag(It, It, Ia)`.
fn leg_body<'g>(p: &[Expr<'g>]) -> Inertial<'g> {
    let z = p[0].graph().zero();
    Inertial {
        mass: p[0],
        first_moment: Vector([z, z, p[1]]),
        inertia: Mat([[p[2], z, z], [z, p[2], z], [z, z, p[3]]]),
    }
}

/// The dynamics from the standard inertial parameters `p` (platform, then each leg's cylinder
/// and rod) and gravity.
fn dynamics_of<'g>(gravity: Vec3<'g>, p: &[Expr<'g>]) -> Dynamics<'g> {
    let g = p[0].graph();
    let body = |k: usize| leg_body(&p[10 + LEG_BODY * k..10 + LEG_BODY * (k + 1)]);
    Dynamics {
        gravity,
        platform: Inertial::from_standard(&p[..10]),
        legs: std::array::from_fn(|i| [body(2 * i), body(2 * i + 1)]),
        rod_inertia_per_length_squared: [Mat::zeros(g); 6],
    }
}

impl legged::Legs for GoughStewartMechanics {
    /// The six U-P-S legs, their bodies' parameters from `dynamics` (or massless).
    fn legs<'g>(
        &self,
        geometry: &[Expr<'g>],
        dynamics: Option<&Dynamics<'g>>,
    ) -> Vec<Box<dyn Leg<'g> + 'g>> {
        let g = geometry[0].graph();
        let massless = Inertial::massless(g);
        (0..6)
            .map(|i| {
                let at = leg_geometry(geometry, i);
                let [cylinder, rod] = dynamics.map_or([massless; 2], |d| d.legs[i]);
                Box::new(Ups {
                    base: at.base,
                    axis: at.axis,
                    platform: at.platform,
                    offset: at.offset,
                    cylinder,
                    rod,
                    closed_form: true,
                }) as Box<dyn Leg<'g> + 'g>
            })
            .collect()
    }
}

/// `B_i = C + R p_i` and `d_i = B_i - A_i`, built as the legs' derivation builds them (units
/// where it has them), so that every kernel computes them once.
fn joint_and_leg<'g>(
    geometry: &[Expr<'g>],
    r: &Mat3<'g>,
    c: &Vec3<'g>,
    i: usize,
) -> (Vec3<'g>, Vec3<'g>) {
    let at = leg_geometry(geometry, i);
    let b = *c + Vector((*r * at.platform).0.map(Expr::keep));
    (b, Vector((b - at.base).0.map(Expr::keep)))
}

/// `|u_i × a_i|`, the sine of each leg's angle with its U joint's first axis: the U joint (and
/// the leg's frame) is singular where it vanishes.
fn u_joint_sines<'g>(posed: &Posed<'g>) -> Vec<Expr<'g>> {
    (0..6)
        .map(|i| {
            let (_, d) = joint_and_leg(&posed.geometry, &posed.r, &posed.c, i);
            let e = Vector(
                d.cross(&leg_geometry(&posed.geometry, i).axis)
                    .0
                    .map(Expr::keep),
            );
            e.dot(&e).sqrt() * d.dot(&d).sqrt().recip()
        })
        .collect()
}

const SINES: Output = Output {
    name: "singular",
    shape: Shape::Vector(6),
    doc: "`|u_i × a_i|`, the sine of each leg's angle with its U joint's first axis: the other \
          results are meaningless where one is near zero",
};
const SINES_AND_PIVOTS: Output = Output {
    name: "singular",
    shape: Shape::Vector(12),
    doc: "`|u_i × a_i|` for each leg (the U joints), then the six pivots of the `LDLᵀ` of \
          `J⁻¹ J⁻ᵀ` over its diagonal, in `(0, 1]` (the legs' hold on the platform: the solve \
          loses about as many digits as the smallest takes from one): the other results are \
          meaningless where one is near zero",
};

impl Structure for GoughStewartStructure {
    fn parameter_names(&self) -> Vec<String> {
        GoughStewart::kernel_parameter_names()
    }

    fn geometry_parameters(&self) -> usize {
        GEOMETRY_PARAMETERS
    }

    fn pose<'g>(&self, geometry: &[Expr<'g>], x: &[Expr<'g>]) -> Posed<'g> {
        let r = rotation_of_pose(x);
        let c = vec3(&x[3..6]);
        let legs: [(Vec3<'g>, Vec3<'g>); 6] =
            std::array::from_fn(|i| joint_and_leg(geometry, &r, &c, i));
        Posed {
            r,
            c,
            q: std::array::from_fn(|i| {
                let d = legs[i].1;
                d.dot(&d).sqrt() + leg_geometry(geometry, i).offset
            }),
            p: std::array::from_fn(|i| c - legs[i].0),
            forward: None,
            geometry: geometry.to_vec(),
            centre_in_platform: None,
        }
    }

    fn dynamics<'g>(&self, parameters: &[Expr<'g>]) -> Dynamics<'g> {
        dynamics_of(vec3(&parameters[..3]), &parameters[GEOMETRY_PARAMETERS..])
    }

    fn standard_inertial_names(&self) -> Vec<String> {
        GoughStewart::standard_inertial_names()
    }

    fn standard_inertial_doc(&self) -> &'static str {
        "the platform's ten (mass, first moment `m c`, inertia about `C`, platform frame), \
         then each leg's cylinder and rod, four each (mass, first moment along the leg, \
         transverse and axial inertia about `A_i` and `B_i`, leg frame)"
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
            Guard::Pose => u_joint_sines(posed),
            Guard::Solve => {
                let rows = legged::rows_at(&GoughStewartMechanics, posed);
                let mut terms = u_joint_sines(posed);
                terms.extend(legged::pivot_ratios(&rows));
                terms
            }
        }
    }

    fn guard_output(&self, guard: Guard) -> (Output, &'static str) {
        match guard {
            Guard::Solve => (
                SINES_AND_PIVOTS,
                "\nThe last result holds the U joints' sines and the solve's pivots for a \
                 singularity check.",
            ),
            _ => (
                SINES,
                "\nThe last result holds the U joints' sines for a singularity check.",
            ),
        }
    }

    fn singularity_terms(&self) -> Vec<SingularityTerm> {
        let mut all = terms::u_joints(6, |i| format!("U joint of leg {i}"));
        all.extend(terms::pivots());
        all
    }

    fn conventions(&self) -> &'static str {
        "Actuators in leg order 1..6; `q_i = |B_i - A_i| + o_i`, the encoder's reading, \
         `B_i = C + R p_i`; a positive force extends the leg."
    }

    fn parameter_doc(&self, reads: Reads) -> &'static str {
        match reads {
            Reads::Geometry => {
                "gravity, then per leg `A_i`, the unit `a_i`, `p_i` and the encoder's offset \
                 (the first entries of `GoughStewart::kernel_parameters`)"
            }
            _ => {
                "robot parameters (`GoughStewart::kernel_parameters`: gravity, the legs' \
                 geometry, each body's standard inertial parameters), in the order of the names \
                 in this signature"
            }
        }
    }

    fn has_kernel(&self, kernel: Kernel) -> bool {
        !legged::LACKS.contains(&kernel)
    }

    fn home(&self, parameters: &[f64]) -> [f64; 6] {
        // Level, centred, the legs rising at 60° on average: what `GoughStewart::home` gives a
        // description without `home` or strokes.
        let leg = |i: usize| &parameters[3 + LEG_GEOMETRY * i..3 + LEG_GEOMETRY * (i + 1)];
        let (mut rise, mut span) = (0.0, 0.0);
        for i in 0..6 {
            let (a, p) = (&leg(i)[0..3], &leg(i)[6..9]);
            rise += (a[2] - p[2]) / 6.0;
            span += (a[0] - p[0]).hypot(a[1] - p[1]) / 6.0;
        }
        [0.0, 0.0, 0.0, 0.0, 0.0, rise + span * 3f64.sqrt()]
    }

    fn reach(&self, parameters: &[f64]) -> f64 {
        let leg = |i: usize| &parameters[3 + LEG_GEOMETRY * i..3 + LEG_GEOMETRY * (i + 1)];
        (0..6).map(|i| leg(i)[0].hypot(leg(i)[1])).sum::<f64>() / 6.0 * 0.2
    }
}

/// The Gough-Stewart platform's own kernels: its singularity terms, and the Newton step of its
/// forward kinematics, which has no closed form.
const EXTRA_KERNELS: &[Decl] = &[
    Decl {
        kernel: Kernel::SingularityTerms,
        title: "The singularity terms at a pose: each U joint's sine, and the legs' hold on the \
            platform.",
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
        "`r_i = q_i(X; θ) - q̂_i` with `q_i = |C + R p_i - A_i| + o_i`, the actuator value the \
         geometry `θ` (the `params`) predicts at the measured pose `X`, less the encoder's \
         reading `q̂_i` (m). Leg `i`'s residual depends on its own seven parameters only \
         (`A_i`, `p_i`, `o_i`): row `i` of `geometry_jacobian` holds those seven derivatives; \
         `pose_jacobian` is `∂q/∂X`, which carries the pose's measurement noise into the \
         residuals.",
        &[Input::Pose, Input::Actuators],
        &CALIBRATION_OUTPUTS,
        |cx| {
            let posed = cx.posed();
            let legs = calibration::Legs {
                balls: (0..6).map(|i| posed.c - posed.p[i]).collect(),
                actuator: &|i, b| {
                    let leg = leg_geometry(cx.geometry, i);
                    let d = *b - leg.base;
                    d.dot(&d).sqrt() + leg.offset
                },
                leg_size: LEG_GEOMETRY,
            };
            let pose = cx.input(Input::Pose);
            calibration::build(cx, &legs, &pose, &c5_robot::calibration::UPS)
        },
    ),
];

const CALIBRATION_OUTPUTS: [Output; 3] = calibration::outputs(
    6,
    c5_robot::calibration::UPS.len(),
    6,
    "`∂q_i/∂(A_i, p_i, o_i)`, row `i` for leg `i+1`, columns `A_x A_y A_z p_x p_y p_z o` \
     (base frame for `A`, platform frame for `p`)",
    "`∂q/∂X`, row `i` for leg `i+1`, columns `α β γ xc yc zc`",
);

impl Mechanics for GoughStewartMechanics {
    fn name(&self) -> &'static str {
        c5_robot::description::GOUGH_STEWART
    }

    fn structure(&self) -> &'static dyn Structure {
        &GoughStewartStructure
    }

    fn summary(&self) -> &'static str {
        "The Gough-Stewart platform (6-UPS): each leg a universal joint on the base, a \
         prismatic actuator (cylinder and rod, turning with the leg) and a spherical joint on \
         the platform; every quantity derived from the leg's closed forms by exact \
         differentiation."
    }

    fn equations(&self, quantity: Quantity) -> &'static [&'static str] {
        match quantity {
            Quantity::InverseKinematics => &["q = |C + R p - A| + o"],
            Quantity::PlatformWrench => &["Newton-Euler of the platform"],
            Quantity::InverseJacobian | Quantity::Jacobian | Quantity::JointVelocities => {
                &["q = |C + R p - A| + o", "∂q/∂(θ, C)"]
            }
            Quantity::JointAccelerations => &["q = |C + R p - A| + o", "d²q/dt²"],
            Quantity::LegWrench => &["legs' Newton-Euler", "virtual work"],
            Quantity::InverseDynamics | Quantity::Identification => &[
                "q = |C + R p - A| + o",
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
