//! The chapter's equations, written once over symbolic expressions, one item per equation.
//!
//! Conventions (DESIGN.md): pose `X = [α β γ xc yc zc]`, twist `V = (ω; v_C)`, wrench
//! `F = (n; f)`, `P̂ = [[U, P̃], [0, U]]`, segments in the order 1..6 everywhere (the chapter lists
//! actuators 6..1; only the nalgebra reference keeps that order). The corrections of the chapter's
//! slips are marked `Slip n` where they apply.

use crate::dag::Expr;
use crate::linalg::{blocks, Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use crate::robot::{RigidBody, Robot};

/// Axis `n_i` of segment `i` (0-based): segments 1,2 along x, 3,4 along y, 5,6 along z.
pub const AXIS: [usize; 6] = [0, 0, 1, 1, 2, 2];

/// `n_i` as a constant vector.
pub fn axis<'g>(g: &'g crate::Graph, i: usize) -> Vec3<'g> {
    Vector::from_fn(|k| g.constant(if k == AXIS[i] { 1.0 } else { 0.0 }))
}

/// `A_i`: `A_1=(0,0,L)`, `A_2=(0,0,-L)`, `A_3=(L,0,0)`, `A_4=(-L,0,0)`, `A_5=(0,L,0)`,
/// `A_6=(0,-L,0)` (the layout eq 16 encodes).
pub fn anchor<'g>(l: Expr<'g>, i: usize) -> Vec3<'g> {
    let g = l.graph();
    let (k, sign) = [
        (2, 1.0),
        (2, -1.0),
        (0, 1.0),
        (0, -1.0),
        (1, 1.0),
        (1, -1.0),
    ][i];
    Vector::from_fn(|j| if j == k { l * sign } else { g.zero() })
}

/// Eq 15: `R = Rx(α) Ry(β) Rz(γ)` from the sines and cosines of the RPY angles.
pub fn rotation<'g>(sin: Vec3<'g>, cos: Vec3<'g>) -> Mat3<'g> {
    let (sa, sb, sg) = (sin[0], sin[1], sin[2]);
    let (ca, cb, cg) = (cos[0], cos[1], cos[2]);
    Mat([
        [cb * cg, -(cb * sg), sb],
        [sg * ca + cg * sb * sa, ca * cg - sa * sb * sg, -(cb * sa)],
        [sg * sa - cg * sb * ca, sa * cg + ca * sb * sg, cb * ca],
    ])
}

/// Eq 16: the actuator length `Q_i1`, from `m_i·(B_i - C) = 0` where `m_i` is the column of
/// `R` along `n_i`; for segment 1 this reads `Q_11 = xc + (r31 (zc - L) + r21 yc) / r11`.
pub fn actuator_length<'g>(r: &Mat3<'g>, c: &Vec3<'g>, a: &Vec3<'g>, i: usize) -> Expr<'g> {
    let k = AXIS[i];
    let m = r.column(k);
    let others: Expr<'g> = (0..3)
        .filter(|&j| j != k)
        .map(|j| m[j] * (c[j] - a[j]))
        .sum();
    c[k] - a[k] + others / m[k]
}

/// Eq 27: `P_i2 = -Q_i1 n_i + A_iO + OC`, the vector from `B_i` to `C`.
pub fn p_i2<'g>(c: &Vec3<'g>, a: &Vec3<'g>, q: Expr<'g>, n: &Vec3<'g>) -> Vec3<'g> {
    *c - *a - n.scale(q)
}

/// Section 2.2: `P̂ = [[U, P̃], [0, U]]`.
pub fn p_hat<'g>(p: &Vec3<'g>) -> Mat6<'g> {
    let g = p[0].graph();
    blocks(Mat::identity(g), p.tilde(), Mat::zeros(g), Mat::identity(g))
}

/// `P̂⁻¹ = [[U, -P̃], [0, U]]`, the wrench transport from `B_i` to `C` (Slip 2: the dual of eq 5).
pub fn p_hat_inv<'g>(p: &Vec3<'g>) -> Mat6<'g> {
    p_hat(&-*p)
}

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
/// `(ω̇; a_C - ω × v_C)` (DESIGN.md, Conventions).
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

/// Newton-Euler of a rigid body: its wrench `(n; f)` about a point `O` of the body whose
/// classical acceleration is `a_o`, for a body turning at `ω`, `ω̇` with its centre of mass at
/// `s` from `O` (base frame), net of gravity `g`; `n_g` is the moment about the centre of mass
/// (Euler's equations, [`Frame::euler_moment`]).
#[allow(clippy::too_many_arguments)]
pub fn rigid_body_wrench<'g>(
    mass: Expr<'g>,
    s: &Vec3<'g>,
    n_g: &Vec3<'g>,
    omega: &Vec3<'g>,
    omega_dot: &Vec3<'g>,
    a_o: &Vec3<'g>,
    gravity: &Vec3<'g>,
) -> Vec6<'g> {
    let a_g = *a_o + omega_dot.cross(s) + omega.cross(&omega.cross(s));
    let f = (a_g - *gravity).scale(mass);
    Vec6::spatial(*n_g + s.cross(&f), f)
}

/// `ω̇̃ + ω̃ ω̃`: the map from a platform point's offset `r` (from `C`) to its acceleration
/// relative to `C`, `ω̇ × r + ω × (ω × r)`. One matrix for every point of the platform.
pub fn point_acceleration_map<'g>(omega: &Vec3<'g>, omega_dot: &Vec3<'g>) -> Mat3<'g> {
    omega_dot.tilde() + omega.tilde() * omega.tilde()
}

/// The symbolic robot seen from the base frame at one pose.
pub struct Frame<'g> {
    pub r: Mat3<'g>,
}

impl<'g> Frame<'g> {
    /// `R x` for a platform-frame vector.
    pub fn vector(&self, v: &[Expr<'g>; 3]) -> Vec3<'g> {
        self.r * Vector(*v)
    }

    /// Eqs 55-56 for a body turning with the platform: `I_C ω̇ + ω × I_C ω` with `I_C = R I Rᵀ`,
    /// evaluated as Euler's equations in the platform frame, `R (I ω̇_p + ω_p × I ω_p)` with
    /// `ω_p = Rᵀ ω`. The same value; but `ω_p` is shared by every body that turns with the
    /// platform, and the moments of those bodies add up before the one rotation back.
    pub fn euler_moment(
        &self,
        inertia: &[[Expr<'g>; 3]; 3],
        omega: &Vec3<'g>,
        omega_dot: &Vec3<'g>,
    ) -> Vec3<'g> {
        self.r * self.euler_moment_in_platform(inertia, omega, omega_dot)
    }

    /// `I ω̇_p + ω_p × I ω_p` in the platform frame (see [`Frame::euler_moment`]).
    pub fn euler_moment_in_platform(
        &self,
        inertia: &[[Expr<'g>; 3]; 3],
        omega: &Vec3<'g>,
        omega_dot: &Vec3<'g>,
    ) -> Vec3<'g> {
        let rt = self.r.transpose();
        let (w, wd) = (rt * *omega, rt * *omega_dot);
        let i = Mat(*inertia);
        i * wd + w.cross(&(i * w))
    }
}

/// Eq 49's `T_i = M_i Q̈_i + C_i + G_i` by recursive Newton-Euler over the leg's two bodies:
/// forward, body 1 moves as `Q̈_i1 n_i` and body 2 with the platform (eqs 43-45); backward,
/// `F_i2` is body 2's wrench at `B_i` and `F_i1 = F(body 1) + P̂_i1 F_i2` (eq 10); then
/// `T_i = [H_i2ᵀ F_i2; H_i1ᵀ F_i1]`.
#[allow(clippy::too_many_arguments)]
pub fn leg_dynamics<'g>(
    robot: &Robot<Expr<'g>>,
    frame: &Frame<'g>,
    i: usize,
    q: Expr<'g>,
    p: &Vec3<'g>,
    twist: &Vec6<'g>,
    vdot: &Vec6<'g>,
) -> Vec6<'g> {
    let g = q.graph();
    let seg = &robot.segments[i];
    let n = axis(g, i);
    let gravity = Vector(robot.gravity);
    let (omega, omega_dot) = (twist.top(), vdot.top());
    let qdd = joint_accelerations_segment(p, vdot, i);
    // Body 2 moves with the platform: the classical acceleration of its point B_i is the
    // spatial one of eq 43 plus ω × v_B, that is a_C + (ω̇̃ + ω̃ω̃)(B_i - C) with B_i - C = -P_i2.
    let a_c = vdot.bottom() + omega.cross(&twist.bottom());
    let a_b = a_c - point_acceleration_map(&omega, &omega_dot) * *p;
    let joint: &RigidBody<Expr<'g>> = &seg.joint;
    let f2 = rigid_body_wrench(
        joint.mass,
        &frame.vector(&joint.com),
        &frame.euler_moment(&joint.inertia, &omega, &omega_dot),
        &omega,
        &omega_dot,
        &a_b,
        &gravity,
    );
    // Body 1: never rotates; centre of mass at Q_i1/2 along n_i from A_i; J_Gi1 in the base
    // frame multiplies its zero angular velocity and acceleration (Slip 5).
    let zero = Vec3::zeros(g);
    let j_g1 = Mat(seg.rod.inertia) + Mat(seg.rod.inertia_per_length_squared).scale(q * q);
    let n_g1 = j_g1 * zero + zero.cross(&(j_g1 * zero));
    let f1 = rigid_body_wrench(
        seg.rod.mass,
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

/// Eqs 52-57: `F_{N+1} = Λ_C V̇_{N+1} + C_C + G_C` with the classical acceleration
/// `(ω̇; a_C)`; `I_C = R I Rᵀ` (eq 55) about the centre of mass, moved to `C` with the parallel
/// axis term when the centre of mass is off `C`.
pub fn platform_wrench<'g>(
    robot: &Robot<Expr<'g>>,
    frame: &Frame<'g>,
    twist: &Vec6<'g>,
    accel: &Vec6<'g>,
) -> Vec6<'g> {
    let body = &robot.platform;
    let gc = frame.vector(&body.com);
    let m = body.mass;
    let (omega, wd, a) = (twist.top(), accel.top(), accel.bottom());
    let g = Vector(robot.gravity);
    // The parallel-axis part of I_C, for a centre of mass off C: -m G̃C G̃C.
    let shift = (gc.tilde() * gc.tilde()).scale(-m);
    // Eq 54: Λ_C = [[I_C, m G̃C], [-m G̃C, m U]], and eq 56: C_C = [ω̃ I_C ω; -m ω̃ G̃C ω]; the
    // `R I Rᵀ` part of both is Euler's equations (eq 55).
    let euler = frame.euler_moment(&body.inertia, &omega, &wd);
    let lambda_vdot = Vec6::spatial(
        euler + shift * wd + (gc.tilde() * a).scale(m),
        a.scale(m) - (gc.tilde() * wd).scale(m),
    );
    let c_c = Vec6::spatial(
        omega.cross(&(shift * omega)),
        -(omega.tilde() * gc.tilde() * omega).scale(m),
    );
    // Eq 57: G_C = [-m G̃C; -m U] g.
    let g_c = Vec6::spatial(-(gc.tilde() * g).scale(m), -g.scale(m));
    lambda_vdot + c_c + g_c
}

/// Eq 62: `Γ = Π1ᵀ J1ᵀ K`, actuator forces in segment order.
pub fn step6_factored<'g>(p: &[Vec3<'g>; 6], k: &Vec6<'g>) -> Vec6<'g> {
    pi1(p).transpose() * (j1(&p[0]).transpose() * *k)
}

/// The platform state, expanded into the quantities every equation needs.
pub struct Posed<'g> {
    pub frame: Frame<'g>,
    /// `Q_i1`, eq 16.
    pub q: [Expr<'g>; 6],
    /// `P_i2`, eq 27.
    pub p: [Vec3<'g>; 6],
}

/// Eqs 15, 16 and 27 from the pose `[α β γ xc yc zc]`.
pub fn pose<'g>(robot: &Robot<Expr<'g>>, x: &[Expr<'g>]) -> Posed<'g> {
    let sin = Vector([x[0].sin(), x[1].sin(), x[2].sin()]);
    let cos = Vector([x[0].cos(), x[1].cos(), x[2].cos()]);
    let r = rotation(sin, cos);
    let c = Vector([x[3], x[4], x[5]]);
    let g = x[0].graph();
    let q: [Expr<'g>; 6] =
        std::array::from_fn(|i| actuator_length(&r, &c, &anchor(robot.half_spacing, i), i));
    let p = std::array::from_fn(|i| p_i2(&c, &anchor(robot.half_spacing, i), q[i], &axis(g, i)));
    Posed {
        frame: Frame { r },
        q,
        p,
    }
}

/// `(ω̇; a_C - ω × v_C)`: the spatial acceleration at `C` from the classical one.
pub fn spatial_acceleration<'g>(twist: &Vec6<'g>, accel: &Vec6<'g>) -> Vec6<'g> {
    Vec6::spatial(
        accel.top(),
        accel.bottom() - twist.top().cross(&twist.bottom()),
    )
}

/// Step 3 of section 8.2, corrected: `Φ = Σ P̂_i2⁻¹ J_Bi⁻ᵀ T_i` (Slips 2 and 3).
pub fn leg_wrench<'g>(
    robot: &Robot<Expr<'g>>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    vdot: &Vec6<'g>,
) -> Vec6<'g> {
    let g = twist[0].graph();
    let mut phi = Vec6::zeros(g);
    for i in 0..6 {
        let t = leg_dynamics(robot, &posed.frame, i, posed.q[i], &posed.p[i], twist, vdot);
        phi = phi + p_hat_inv(&posed.p[i]) * (leg_jacobian_at_b(g, i) * t);
    }
    phi
}

/// Eq 60 with step 6 by eq 62: `Γ = Π1ᵀ J1ᵀ (F_{N+1} + Φ)` (Slip 1: `J⁻ᵀ`, not `J⁻¹`).
pub fn inverse_dynamics<'g>(
    robot: &Robot<Expr<'g>>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    accel: &Vec6<'g>,
) -> Vec6<'g> {
    let vdot = spatial_acceleration(twist, accel);
    let k =
        platform_wrench(robot, &posed.frame, twist, accel) + leg_wrench(robot, posed, twist, &vdot);
    step6_factored(&posed.p, &k)
}

/// `Q̇_a = J⁻¹ V` (eq 20), segment order.
pub fn joint_velocities<'g>(posed: &Posed<'g>, twist: &Vec6<'g>) -> Vec6<'g> {
    inverse_jacobian(&posed.p) * *twist
}
