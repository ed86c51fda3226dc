//! The paper model: the chapter as published, eqs 20-22 (`J⁻¹`), 36-41 (`J = J1 Π1`), 43-48
//! (joint accelerations by projection) and Khalil's inverse dynamics (eqs 49-62), one item per
//! equation.
//!
//! Its inverse Jacobian is the derivative of eq 16 only at zero orientation (Slip 4): kept to
//! reproduce the chapter. The corrections of the chapter's other slips are marked `Slip n`
//! where they apply.

use super::bodies::{
    platform_wrench, point_acceleration_map, rigid_body_wrench, wrench_turning_with_platform,
    Dynamics, Frame, Lumped,
};
use super::c5::C5;
use super::geometry::{axis, p_hat, p_hat_inv, spatial_acceleration, Motion, Posed};
use super::kernels::{Build, Cite, Decl, Guard, Input, Kernel, Output, Reads};
use super::{Mechanics, Model, Quantity, Structure};
use crate::dag::Expr;
use crate::kernel::{ChapterCount, Shape};
use crate::linalg::{Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use c5_robot::AXIS;

/// The paper model's [`Mechanics`].
pub struct Paper;

impl Mechanics for Paper {
    fn name(&self) -> &'static str {
        Model::Paper.name()
    }

    fn structure(&self) -> &'static dyn Structure {
        &C5
    }

    fn summary(&self) -> &'static str {
        "The chapter as published: `J⁻¹` of eq 22 (rows `[(n_i × P_i2)ᵀ n_iᵀ]`), the \
         derivative of eq 16 only at zero orientation (slip 4)."
    }

    fn equations(&self, quantity: Quantity) -> &'static [&'static str] {
        match quantity {
            Quantity::InverseKinematics => &["15", "16", "27"],
            Quantity::PlatformWrench => &["52", "54", "55", "56", "57"],
            Quantity::InverseJacobian => &["15", "16", "22", "27"],
            Quantity::Jacobian => &["15", "16", "27", "39", "40", "41"],
            Quantity::JointVelocities => &["20", "22"],
            Quantity::JointAccelerations => &["43", "44", "45", "46", "47", "48"],
            Quantity::LegWrench => &["43", "48", "49", "50", "60"],
            Quantity::InverseDynamics => &["15", "16", "27", "43-48", "49-57", "60", "62"],
            Quantity::TaskSpace => &["15", "16", "27", "43-48", "49-57", "60", "∂W/∂V̇"],
            Quantity::ForwardDynamics => &[
                "15",
                "16",
                "22",
                "43-48",
                "49-57",
                "60",
                "M_x V̇ = J⁻ᵀ Γ - h (LDLᵀ)",
            ],
            Quantity::Identification => &["15", "16", "27", "43-48", "49-57", "60", "62", "∂Γ/∂π"],
        }
    }

    fn inverse_jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g> {
        inverse_jacobian(&posed.p)
    }

    fn jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g> {
        jacobian(&posed.p)
    }

    fn joint_velocities<'g>(&self, posed: &Posed<'g>, twist: &Vec6<'g>) -> Vec6<'g> {
        joint_velocities(posed, twist)
    }

    fn joint_accelerations<'g>(&self, posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g> {
        joint_accelerations(posed, motion)
    }

    fn leg_wrench<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        leg_wrench(dynamics, posed, motion)
    }

    fn inverse_dynamics<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        inverse_dynamics(dynamics, posed, motion)
    }

    fn inverse_dynamics_by_body<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        inverse_dynamics_by_legs(dynamics, posed, motion)
    }

    fn task_wrench<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        motion: &Motion<'g>,
    ) -> Vec6<'g> {
        task_wrench(dynamics, posed, motion)
    }

    fn extra_kernels(&self) -> &'static [Decl] {
        EXTRA_KERNELS
    }
}

fn p_rows<'g>(p: &[Expr<'g>]) -> [Vec3<'g>; 6] {
    std::array::from_fn(|i| Vector([p[3 * i], p[3 * i + 1], p[3 * i + 2]]))
}

fn vec6<'g>(v: &[Expr<'g>]) -> Vec6<'g> {
    Vector(std::array::from_fn(|i| v[i]))
}

const fn chapter(m: u32, a: u32) -> Option<ChapterCount> {
    Some(ChapterCount { m, a })
}

/// The chapter's own setting (the components of `P_i2` free inputs, as its counts assume),
/// and the passive-joint accelerations of the projection scheme.
const EXTRA_KERNELS: &[Decl] = &[
    Decl {
        kernel: Kernel::InverseJacobian,
        title: "Inverse Jacobian `J⁻¹` of the paper model, rows `[(n_i × P_i2)ᵀ n_iᵀ]`.",
        doc: "",
        equations: Cite::Fixed(&["22"]),
        inputs: &[Input::P],
        outputs: &[Output {
            name: "jinv",
            shape: Shape::Matrix(6, 6),
            doc: "`J⁻¹`, row `i` for segment `i+1`, columns `[ωx ωy ωz vx vy vz]`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: chapter(18, 30),
        build: Build::Free(|_, i| vec![inverse_jacobian(&p_rows(&i[0])).rows()]),
    },
    Decl {
        kernel: Kernel::Pi1,
        title: "`Π1`, the map from actuator rates to the joint rates of segment 1, `Q̇_1 = Π1 Q̇_a`.",
        doc: "",
        equations: Cite::Fixed(&["36", "37", "38", "39"]),
        inputs: &[Input::P],
        outputs: &[Output {
            name: "pi1",
            shape: Shape::Matrix(6, 6),
            doc: "rows `[ẇ_p1 u̇_p1 γ̇_p β̇_p α̇_p Q̇_11]`, column `i` for segment `i+1`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: chapter(17, 28),
        build: Build::Free(|_, i| vec![pi1(&p_rows(&i[0])).rows()]),
    },
    Decl {
        kernel: Kernel::Jacobian,
        title: "Jacobian in factored form, `J = J1 Π1`, including `Π1`.",
        doc: "The chapter's count for eq 40 alone is 29m + 37a; with `Π1` it is 46m + 65a.",
        equations: Cite::Fixed(&["39", "40", "41"]),
        inputs: &[Input::P],
        outputs: &[Output {
            name: "jacobian",
            shape: Shape::Matrix(6, 6),
            doc: "`J`, rows `[ωx ωy ωz vx vy vz]`, column `i` for segment `i+1`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: chapter(29 + 17, 37 + 28),
        build: Build::Free(|_, i| vec![jacobian(&p_rows(&i[0])).rows()]),
    },
    Decl {
        kernel: Kernel::JointAccelerationsSegment,
        title: "Joint accelerations of segment 1 by projection, `Q̈_1 = [Q̈_12; Q̈_11]`.",
        doc: "Every segment costs the same; segment 1 is generated here.",
        equations: Cite::Fixed(&["43", "44", "45", "46", "47", "48"]),
        inputs: &[Input::P1, Input::SpatialAccel],
        outputs: &[Output {
            name: "qdd",
            shape: Shape::Vector(6),
            doc: "`[ẅ_p1 ü_p1 γ̈_p β̈_p α̈_p Q̈_11]`",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: chapter(10, 10),
        build: Build::Free(|_, i| {
            let p = Vector([i[0][0], i[0][1], i[0][2]]);
            vec![joint_accelerations_segment(&p, &vec6(&i[1]), 0).to_vec()]
        }),
    },
    Decl {
        kernel: Kernel::Step6Factored,
        title: "Step 6 of the inverse dynamics, `Γ = Π1ᵀ J1ᵀ K`, with no linear solve.",
        doc: "",
        equations: Cite::Fixed(&["62"]),
        inputs: &[Input::P, Input::Wrench],
        outputs: &[Output {
            name: "gamma",
            shape: Shape::Vector(6),
            doc: "`Γ` (N), segment order",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: chapter(65, 67),
        build: Build::Free(|_, i| vec![step6_factored(&p_rows(&i[0]), &vec6(&i[1])).to_vec()]),
    },
    Decl {
        kernel: Kernel::Pi1Denominators,
        title: "The denominators of `Π1`, `[y5 - y6, z1 - z2, x3 - x4]`.",
        doc: "In the pose setting they are the constant `-2L`.",
        equations: Cite::Fixed(&["39"]),
        inputs: &[Input::P],
        outputs: &[Output {
            name: "d",
            shape: Shape::Vector(3),
            doc: "`[y5 - y6, z1 - z2, x3 - x4]` (m)",
        }],
        guard: Guard::Never,
        reads: Reads::Nothing,
        batch: false,
        chapter: None,
        build: Build::Free(|_, i| {
            let p = p_rows(&i[0]);
            vec![vec![
                p[4][1] - p[5][1],
                p[0][2] - p[1][2],
                p[2][0] - p[3][0],
            ]]
        }),
    },
    Decl {
        kernel: Kernel::LegJointAccelerations,
        title: "Joint accelerations of every segment by projection, the passive joints included.",
        doc: "The passive-joint accelerations of eq 48 are components of the spatial \
              acceleration: they differ from `d/dt Q̇_i2` (eq 42) by `-Q̇_i1 H_i2ᵀ (0; n_i × ω)`.",
        equations: Cite::Fixed(&["43", "44", "45", "46", "47", "48"]),
        inputs: &[Input::Pose, Input::Twist, Input::Accel],
        outputs: &[Output {
            name: "legs",
            shape: Shape::Matrix(6, 6),
            doc: "row `i`: `Q̈_i = [ẅ_p ü_p γ̈_p β̈_p α̈_p Q̈_i1]` of segment `i+1`",
        }],
        guard: Guard::Pose,
        reads: Reads::Robot,
        batch: false,
        chapter: None,
        build: Build::Robot(|cx| vec![leg_joint_accelerations(&cx.posed(), &cx.motion()).rows()]),
    },
];

/// Eq 21: row `[(n_i × P_i2)ᵀ n_iᵀ]` of `J⁻¹` (the paper model).
pub fn inverse_jacobian_row<'g>(n: &Vec3<'g>, p: &Vec3<'g>) -> Vec6<'g> {
    Vec6::spatial(n.cross(p), *n)
}

/// Eq 22: `J⁻¹`, row `i` for segment `i` (the chapter stacks them 6..1).
pub fn inverse_jacobian<'g>(p: &[Vec3<'g>; 6]) -> Mat6<'g> {
    let g = p[0][0].graph();
    Mat(std::array::from_fn(|i| {
        inverse_jacobian_row(&axis(g, i), &p[i]).0
    }))
}

/// Rows of `Π1` as linear forms in `Q̇_a` (segment order), derived as the chapter does:
/// eq 38 gives `α̇_p, β̇_p, γ̇_p` from pairs of actuators, eqs 36-37 give `u̇_p1, ẇ_p1`.
/// Returns the rows `[ẇ_p1, u̇_p1, γ̇_p, β̇_p, α̇_p, Q̇_11]` (eq 39's row order).
pub fn pi1<'g>(p: &[Vec3<'g>; 6]) -> Mat6<'g> {
    let g = p[0][0].graph();
    let (x, y, z) = (
        |i: usize| p[i - 1][0],
        |i: usize| p[i - 1][1],
        |i: usize| p[i - 1][2],
    );
    let e = |i: usize| Vector::<6>::from_fn(|k| if k == i - 1 { g.one() } else { g.zero() });
    // Eq 38: Q̇51 = (y6 - y5) α̇ + Q̇61, Q̇11 = (z2 - z1) β̇ + Q̇21, Q̇31 = (x4 - x3) γ̇ + Q̇41.
    let alpha = (e(5) - e(6)).scale((y(6) - y(5)).recip());
    let beta = (e(1) - e(2)).scale((z(2) - z(1)).recip());
    let gamma = (e(3) - e(4)).scale((x(4) - x(3)).recip());
    // Eq 36: u̇_p1 = (z1 - z3) α̇ + (x3 - x1) γ̇ + Q̇31.
    let u = alpha.scale(z(1) - z(3)) + gamma.scale(x(3) - x(1)) + e(3);
    // Eq 37: ẇ_p1 = (y5 - y1) α̇ + (x1 - x5) β̇ + Q̇51.
    let w = alpha.scale(y(5) - y(1)) + beta.scale(x(1) - x(5)) + e(5);
    Mat([w.0, u.0, gamma.0, beta.0, alpha.0, e(1).0])
}

/// Eq 41: `J1 = [P̂_12ᵀ H_12, P̂_12ᵀ P̂_11ᵀ H_11]`, the Jacobian of segment 1 as a serial chain.
pub fn j1<'g>(p12: &Vec3<'g>) -> Mat6<'g> {
    leg_jacobian(p12, 0)
}

/// Eq 40: `J = J1 Π1`.
pub fn jacobian<'g>(p: &[Vec3<'g>; 6]) -> Mat6<'g> {
    j1(&p[0]) * pi1(p)
}

/// Section 3: `H_i1`, the prismatic axis of the actuator (`(0; n_i)`).
pub fn h_i1<'g>(g: &'g crate::Graph, i: usize) -> Mat<'g, 6, 1> {
    let n = axis(g, i);
    Mat::from_fn(|r, _| if r < 3 { g.zero() } else { n[r - 3] })
}

/// Section 3: `H_i2`, the five axes of the C5 joint `[w_p u_p γ_p β_p α_p]`: two translations
/// across `n_i`, then rotations about z, y, x.
pub fn h_i2<'g>(g: &'g crate::Graph, i: usize) -> Mat<'g, 6, 5> {
    // Rows hit by each column (the chapter's matrices H_12, H_32, H_52).
    let rows: [usize; 5] = match AXIS[i] {
        0 => [5, 4, 2, 1, 0],
        1 => [5, 3, 2, 1, 0],
        _ => [4, 3, 2, 1, 0],
    };
    Mat::from_fn(|r, c| if rows[c] == r { g.one() } else { g.zero() })
}

/// Section 3: `W_i2 = H_i1`, the direction the C5 joint constrains.
pub fn w_i2<'g>(g: &'g crate::Graph, i: usize) -> Mat<'g, 6, 1> {
    h_i1(g, i)
}

/// `[H_i2 H_i1]`, the leg's joint axes as one 6×6 matrix.
fn leg_axes<'g>(g: &'g crate::Graph, i: usize) -> Mat6<'g> {
    let (h2, h1) = (h_i2(g, i), h_i1(g, i));
    Mat::from_fn(|r, c| if c < 5 { h2.0[r][c] } else { h1.0[r][0] })
}

/// Eq 25: `J_i = β_i (P_iᵗ)⁻¹ H_i = [P̂_i2ᵀ H_i2, P̂_i2ᵀ P̂_i1ᵀ H_i1]`; `P̂_i1ᵀ H_i1 = H_i1`
/// whatever `P_i1`, because a prismatic axis has no angular part.
pub fn leg_jacobian<'g>(p: &Vec3<'g>, i: usize) -> Mat6<'g> {
    p_hat(p).transpose() * leg_axes(p[0].graph(), i)
}

/// Eq 50: `J_Bi = P̂_i2⁻ᵀ J_i = [H_i2 H_i1]`, a permutation matrix, so `J_Bi⁻ᵀ = J_Bi`.
pub fn leg_jacobian_at_b<'g>(g: &'g crate::Graph, i: usize) -> Mat6<'g> {
    leg_axes(g, i)
}

/// Eq 43: `V̇_i2 = P̂_i2⁻ᵀ V̇_{N+1}`, with `V̇_{N+1}` the spatial acceleration
/// `(ω̇; a_C - ω × v_C)` (README, "Conventions").
pub fn body2_acceleration<'g>(p: &Vec3<'g>, vdot: &Vec6<'g>) -> Vec6<'g> {
    // P̂⁻ᵀ = [[U, 0], [P̃, U]]: the linear part gains P × ω̇.
    Vec6::spatial(vdot.top(), vdot.bottom() + p.cross(&vdot.top()))
}

/// Eqs 45-48: `Q̈_i = [Q̈_i2; Q̈_i1]` of segment `i` by projection. `Q̈_i1 = (W_i2ᵀ P̂_i1ᵀ H_i1)⁻¹
/// W_i2ᵀ V̇_i2` (eq 47), `V̇_i1 = H_i1 Q̈_i1` (eq 45), `Q̈_i2 = H_i2ᵀ (V̇_i2 - P̂_i1ᵀ V̇_i1)` (eq 48).
pub fn joint_accelerations_segment<'g>(p: &Vec3<'g>, vdot: &Vec6<'g>, i: usize) -> Vec6<'g> {
    let g = p[0].graph();
    let v2 = body2_acceleration(p, vdot);
    let (h1, h2, w2) = (h_i1(g, i), h_i2(g, i), w_i2(g, i));
    let w2t_h1 = (w2.transpose() * h1).0[0][0];
    let qdd1 = (w2.transpose() * v2)[0] / w2t_h1;
    let v1 = h1.column(0).scale(qdd1);
    let qdd2 = h2.transpose() * (v2 - v1);
    Vector([qdd2[0], qdd2[1], qdd2[2], qdd2[3], qdd2[4], qdd1])
}

/// Eq 49's `T_i = M_i Q̈_i + C_i + G_i` by recursive Newton-Euler over the leg's two bodies:
/// forward, body 1 moves as `Q̈_i1 n_i` and body 2 with the platform (eqs 43-45); backward,
/// `F_i2` is body 2's wrench at `B_i` and `F_i1 = F(body 1) + P̂_i1 F_i2` (eq 10); then
/// `T_i = [H_i2ᵀ F_i2; H_i1ᵀ F_i1]`.
#[allow(clippy::too_many_arguments)]
pub fn leg_dynamics<'g>(
    dynamics: &Dynamics<'g>,
    r: Mat3<'g>,
    i: usize,
    q: Expr<'g>,
    p: &Vec3<'g>,
    twist: &Vec6<'g>,
    vdot: &Vec6<'g>,
) -> Vec6<'g> {
    let g = q.graph();
    let n = axis(g, i);
    let gravity = dynamics.gravity;
    let (omega, omega_dot) = (twist.top(), vdot.top());
    let qdd = joint_accelerations_segment(p, vdot, i);
    // Body 2 moves with the platform: the classical acceleration of its point B_i is the
    // spatial one of eq 43 plus ω × v_B, that is a_C + (ω̇̃ + ω̃ω̃)(B_i - C) with B_i - C = -P_i2.
    let a_c = vdot.bottom() + omega.cross(&twist.bottom());
    let a_b = a_c - point_acceleration_map(&omega, &omega_dot) * *p;
    let frame = Frame::new(r, &omega, &omega_dot);
    let f2 = wrench_turning_with_platform(
        &dynamics.legs[i][1],
        &frame,
        &omega,
        &omega_dot,
        &a_b,
        &gravity,
    );
    // Body 1: never rotates; centre of mass at Q_i1/2 along n_i from A_i; J_Gi1 in the base
    // frame multiplies its zero angular velocity and acceleration (Slip 5).
    let zero = Vec3::zeros(g);
    let rod = &dynamics.legs[i][0];
    let j_g1 = rod.inertia + dynamics.rod_inertia_per_length_squared[i].scale(q * q);
    let n_g1 = j_g1 * zero + zero.cross(&(j_g1 * zero));
    let f1 = rigid_body_wrench(
        rod.mass,
        &n.scale(q * 0.5),
        &n_g1,
        &zero,
        &zero,
        &n.scale(qdd[5]),
        &gravity,
    );
    let p_i1 = n.scale(q);
    let f1 = f1 + p_hat(&p_i1) * f2;
    let t2 = h_i2(g, i).transpose() * f2;
    let t1 = (h_i1(g, i).transpose() * f1)[0];
    Vector([t2[0], t2[1], t2[2], t2[3], t2[4], t1])
}

/// Eq 62: `Γ = Π1ᵀ J1ᵀ K`, actuator forces in segment order.
pub fn step6_factored<'g>(p: &[Vec3<'g>; 6], k: &Vec6<'g>) -> Vec6<'g> {
    pi1(p).transpose() * (j1(&p[0]).transpose() * *k)
}

/// Step 3 of section 8.2, corrected: `Φ = Σ P̂_i2⁻¹ J_Bi⁻ᵀ T_i` (Slips 2 and 3), from the
/// classical motion (eq 43 is fed its spatial acceleration).
pub fn leg_wrench<'g>(dynamics: &Dynamics<'g>, posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g> {
    let vdot = spatial_acceleration(&motion.twist, &motion.accel);
    leg_wrench_from_spatial(dynamics, posed, &motion.twist, &vdot)
}

/// [`leg_wrench`] from the twist and the spatial acceleration `V̇_{N+1}`.
fn leg_wrench_from_spatial<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    vdot: &Vec6<'g>,
) -> Vec6<'g> {
    let g = twist[0].graph();
    let mut phi = Vec6::zeros(g);
    for i in 0..6 {
        let t = leg_dynamics(dynamics, posed.r, i, posed.q[i], &posed.p[i], twist, vdot);
        phi = phi + p_hat_inv(&posed.p[i]) * (leg_jacobian_at_b(g, i) * t);
    }
    phi
}

/// Eq 60 regrouped, the kernels' inverse dynamics: `Γ = Π1ᵀ J1ᵀ (F_{N+1} + Φ₂) + τ` (Slip 1:
/// `J⁻ᵀ`, not `J⁻¹`; step 6 by eq 62). It equals the chapter's steps 1-6 ([`leg_wrench`]) at
/// 400 counted operations against their 582: `J_Bi` is a permutation (eq 50), so `J_Bi T_i = F_i2 + H_i1 H_i1ᵀ (F_i1 -
/// F_i2)`, and `H_i1ᵀ P̂_i1 F_i2` is `n_i·f_i2`: each body 2's wrench reaches `C` whole, and of
/// the rod only its axial load `τ_i`, along column `i` of `J⁻ᵀ` (eq 22), so that `Jᵀ` gives it
/// back unchanged. The bodies 2 move as points of the platform (eq 43): their wrenches at `C`
/// are one lumped body's, `F_{N+1} + Φ₂` ([`platform_and_bodies2`]).
pub fn inverse_dynamics<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> Vec6<'g> {
    let (wrench, tau) = regrouped(dynamics, posed, motion);
    step6_factored(&posed.p, &wrench) + tau
}

/// `W = J⁻ᵀ Γ = F_{N+1} + Φ₂ + J⁻ᵀ τ` ([`inverse_dynamics`] before step 6).
pub fn task_wrench<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> Vec6<'g> {
    let (wrench, tau) = regrouped(dynamics, posed, motion);
    wrench + inverse_jacobian(&posed.p).transpose() * tau
}

/// `F_{N+1} + Φ₂`, the wrench at `C` of the platform and the bodies 2, and `τ`, the rods' axial
/// loads.
fn regrouped<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> (Vec6<'g>, Vec6<'g>) {
    let (twist, accel) = (&motion.twist, &motion.accel);
    let frame = Frame::new(posed.r, &twist.top(), &accel.top());
    let wrench = platform_and_bodies2(dynamics, posed, &frame).wrench(
        &frame,
        &twist.top(),
        &accel.top(),
        &accel.bottom(),
        &dynamics.gravity,
    );
    let vdot = spatial_acceleration(twist, accel);
    let tau = Vector::from_fn(|i| rod_load(dynamics, i, &posed.p[i], &vdot));
    (wrench, tau)
}

/// The platform and the six bodies 2 as one body about `C`: a body 2 has its reference point at
/// `B_i = C - P_i2` and turns with the platform (eq 43).
pub fn platform_and_bodies2<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    frame: &Frame<'g>,
) -> Lumped<'g> {
    (0..6).fold(Lumped::platform(&dynamics.platform), |lumped, i| {
        lumped.with(&dynamics.legs[i][1], frame, &-posed.p[i])
    })
}

/// `τ_i = H_i1ᵀ F(body 1) = m_i1 (Q̈_i1 - n_i·g)`: the rod translates along `n_i` at `Q̈_i1`
/// (eq 47, by projection), so of its wrench only its mass times that, net of gravity, reaches
/// the actuator.
pub fn rod_load<'g>(dynamics: &Dynamics<'g>, i: usize, p: &Vec3<'g>, vdot: &Vec6<'g>) -> Expr<'g> {
    let qdd = joint_accelerations_segment(p, vdot, i)[5];
    let n = axis(p[0].graph(), i);
    dynamics.legs[i][0].mass * (qdd - n.dot(&dynamics.gravity))
}

/// Eq 60 with step 6 by eq 62, as the chapter computes it: `Γ = Π1ᵀ J1ᵀ (F_{N+1} + Φ)`, `Φ`
/// from every leg's `T_i` (steps 1-3). The kernels use [`inverse_dynamics`], equal to it; the
/// regressor this (each body's parameters meet only its own motion here: cheaper columns).
pub fn inverse_dynamics_by_legs<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> Vec6<'g> {
    let (twist, accel) = (&motion.twist, &motion.accel);
    let vdot = spatial_acceleration(twist, accel);
    let frame = Frame::new(posed.r, &twist.top(), &accel.top());
    let k = platform_wrench(dynamics, &frame, twist, accel)
        + leg_wrench_from_spatial(dynamics, posed, twist, &vdot);
    step6_factored(&posed.p, &k)
}

/// Eqs 43-48 for every segment: the actuator accelerations `Q̈_i1` by projection, from the
/// classical motion.
pub fn joint_accelerations<'g>(posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g> {
    let vdot = spatial_acceleration(&motion.twist, &motion.accel);
    Vector::from_fn(|i| joint_accelerations_segment(&posed.p[i], &vdot, i)[5])
}

/// Eqs 43-48 for every segment: row `i` is `Q̈_i = [ẅ_p ü_p γ̈_p β̈_p α̈_p Q̈_i1]` of segment
/// `i+1`, the passive joints included.
pub fn leg_joint_accelerations<'g>(posed: &Posed<'g>, motion: &Motion<'g>) -> Mat6<'g> {
    let vdot = spatial_acceleration(&motion.twist, &motion.accel);
    Mat(std::array::from_fn(|i| {
        joint_accelerations_segment(&posed.p[i], &vdot, i).0
    }))
}

/// `Q̇_a = J⁻¹ V` (eq 20), segment order.
pub fn joint_velocities<'g>(posed: &Posed<'g>, twist: &Vec6<'g>) -> Vec6<'g> {
    inverse_jacobian(&posed.p) * *twist
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dag::Graph;
    use crate::model::geometry::pose;
    use crate::model::lopsided;
    use crate::numeric::Lcg;

    fn values<const N: usize>(v: &Vector<'_, N>) -> [f64; N] {
        v.0.map(|e| e.as_const().expect("every input is a constant"))
    }

    /// The regrouped inverse dynamics and task wrench against the chapter's steps 1-6, on a
    /// robot whose bodies 2 are off their balls (every term of the lumped body in play), at
    /// seeded states: the graph folds constant inputs, so each side is a number.
    #[test]
    fn the_regrouped_inverse_dynamics_is_the_chapters() {
        let g = Graph::new(crate::dag::Policy::FLAT);
        let params: Vec<_> = lopsided()
            .kernel_parameters()
            .into_iter()
            .map(|v| g.constant(v))
            .collect();
        let dynamics = Dynamics::from_kernel_parameters(&params);
        let mut rng = Lcg::new(3);
        for _ in 0..20 {
            let mut constants = |bounds: &[f64]| -> Vec6<'_> {
                let v = rng.vector(bounds);
                Vector::from_fn(|i| g.constant(v[i]))
            };
            let x = constants(&[0.3, 0.3, 0.3, 0.05, 0.05, 0.05]);
            let motion = Motion::new(
                constants(&[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]),
                constants(&[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]),
            );
            let posed = pose(&params[..4], &x.0);
            let want = values(&inverse_dynamics_by_legs(&dynamics, &posed, &motion));
            let got = values(&inverse_dynamics(&dynamics, &posed, &motion));
            let frame = Frame::new(posed.r, &motion.twist.top(), &motion.accel.top());
            let chapter_wrench = platform_wrench(&dynamics, &frame, &motion.twist, &motion.accel)
                + leg_wrench(&dynamics, &posed, &motion);
            let want_w = values(&chapter_wrench);
            let got_w = values(&task_wrench(&dynamics, &posed, &motion));
            for (got, want) in [(got, want), (got_w, want_w)] {
                let scale = want.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                for k in 0..6 {
                    assert!(
                        (got[k] - want[k]).abs() <= 1e-12 * scale,
                        "component {k}: {got:?} against {want:?}"
                    );
                }
            }
        }
    }
}
