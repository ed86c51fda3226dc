//! What both models share of the geometry: the layout, eq 15 (`R`), eq 16 (`Q_i1`), eq 27
//! (`P_i2`) and the transport matrix `P̂` of section 2.2.
//!
//! Conventions (DESIGN.md): pose `X = [α β γ xc yc zc]`, twist `V = (ω; v_C)`, wrench
//! `F = (n; f)`, `P̂ = [[U, P̃], [0, U]]`, segments in the order 1..6 everywhere (the chapter lists
//! actuators 6..1; only the nalgebra reference keeps that order).

use crate::dag::{Expr, Graph};
use crate::linalg::{blocks, Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use c5_robot::AXIS;

/// `n_i`, the axis of segment `i` (0-based), as a constant vector.
pub fn axis(g: &Graph, i: usize) -> Vec3<'_> {
    Vector::from_fn(|k| g.constant(if k == AXIS[i] { 1.0 } else { 0.0 }))
}

/// `A_i`: `A_1=(0,0,L)`, `A_2=(0,0,-L)`, `A_3=(L,0,0)`, `A_4=(-L,0,0)`, `A_5=(0,L,0)`,
/// `A_6=(0,-L,0)` (the layout eq 16 encodes).
pub fn anchor(l: Expr<'_>, i: usize) -> Vec3<'_> {
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

/// Eq 15 from the pose's angles.
pub fn rotation_of_pose<'g>(x: &[Expr<'g>]) -> Mat3<'g> {
    let sin = Vector([x[0].sin(), x[1].sin(), x[2].sin()]);
    let cos = Vector([x[0].cos(), x[1].cos(), x[2].cos()]);
    rotation(sin, cos)
}

/// `m_i = R e_k`: the platform axis of segment `i`, the normal of the plane its plates slide
/// in (DESIGN.md, the consistent model; `k` is the axis of `n_i`).
pub fn platform_axis<'g>(r: &Mat3<'g>, i: usize) -> Vec3<'g> {
    r.column(AXIS[i])
}

/// `n_i · m_i = r_kk`: the divisor of eq 16 for segment `i`; the pose is singular where it
/// vanishes.
pub fn divisor<'g>(r: &Mat3<'g>, i: usize) -> Expr<'g> {
    r.0[AXIS[i]][AXIS[i]]
}

/// `[r11 r22 r33]`, the three distinct divisors of eq 16.
pub fn divisors<'g>(r: &Mat3<'g>) -> Vec<Expr<'g>> {
    vec![r.0[0][0], r.0[1][1], r.0[2][2]]
}

/// Eq 16: the actuator length `Q_i1`, from `m_i·(B_i - C) = 0` with `B_i = A_i + Q_i1 n_i`;
/// for segment 1 this reads `Q_11 = xc + (r31 (zc - L) + r21 yc) / r11`.
pub fn actuator_length<'g>(r: &Mat3<'g>, c: &Vec3<'g>, a: &Vec3<'g>, i: usize) -> Expr<'g> {
    let k = AXIS[i];
    let m = platform_axis(r, i);
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

/// `(ω̇; a_C - ω × v_C)`: the spatial acceleration at `C` from the classical one.
pub fn spatial_acceleration<'g>(twist: &Vec6<'g>, accel: &Vec6<'g>) -> Vec6<'g> {
    Vec6::spatial(
        accel.top(),
        accel.bottom() - twist.top().cross(&twist.bottom()),
    )
}

/// The platform's pose, expanded into the quantities every equation needs.
pub struct Posed<'g> {
    /// `R`, eq 15.
    pub r: Mat3<'g>,
    /// `C`, the platform centre.
    pub c: Vec3<'g>,
    /// `Q_i1`, eq 16.
    pub q: [Expr<'g>; 6],
    /// `P_i2`, eq 27, base frame.
    pub p: [Vec3<'g>; 6],
}

/// Eqs 15, 16 and 27 from the pose `[α β γ xc yc zc]` of a robot of half-spacing `L`.
pub fn pose<'g>(half_spacing: Expr<'g>, x: &[Expr<'g>]) -> Posed<'g> {
    let r = rotation_of_pose(x);
    let c = Vector([x[3], x[4], x[5]]);
    let g = x[0].graph();
    let q: [Expr<'g>; 6] =
        std::array::from_fn(|i| actuator_length(&r, &c, &anchor(half_spacing, i), i));
    let p = std::array::from_fn(|i| p_i2(&c, &anchor(half_spacing, i), q[i], &axis(g, i)));
    Posed { r, c, q, p }
}

/// The platform's motion: twist and classical acceleration, base frame.
pub struct Motion<'g> {
    /// `V = (ω; v_C)`.
    pub twist: Vec6<'g>,
    /// `(ω̇; a_C)`, `a_C = d v_C/dt`.
    pub accel: Vec6<'g>,
}
