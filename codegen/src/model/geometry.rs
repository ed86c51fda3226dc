//! What both models share of the geometry: the layout, eq 15 (`R`), eq 16 (`Q_i1`), eq 27
//! (`P_i2`) and the transport matrix `P̂` of section 2.2.
//!
//! Conventions (README, "Conventions"): pose `X = [α β γ xc yc zc]`, twist `V = (ω; v_C)`, wrench
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
/// in (docs/models.md, the consistent model; `k` is the axis of `n_i`).
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
    /// `1 + abc` when the pose was found from the actuator positions ([`forward_kinematics`]):
    /// the forward singularity term, positive in the workspace.
    pub forward: Option<Expr<'g>>,
    /// The mechanism's geometric parameters as the kernel sees them (constants, or entries of
    /// its `params`): the leading entries of its parameter vector (the C5's `[L gx gy gz]`).
    pub geometry: Vec<Expr<'g>>,
    /// `Rᵀ C`, the centre in the platform frame, when it is known without rotating `C`
    /// (the forward kinematics gives it as `[r11 h1, r22 h2, r33 h3]`).
    pub centre_in_platform: Option<Vec3<'g>>,
}

/// `L`, the half-spacing of a C5 robot, from its geometric parameters.
pub fn half_spacing<'g>(geometry: &[Expr<'g>]) -> Expr<'g> {
    geometry[0]
}

/// Eqs 15, 16 and 27 from the pose `[α β γ xc yc zc]` of a C5 robot of geometry `[L ...]`.
pub fn pose<'g>(geometry: &[Expr<'g>], x: &[Expr<'g>]) -> Posed<'g> {
    let half_spacing = self::half_spacing(geometry);
    let r = rotation_of_pose(x);
    let r = Mat(r.0.map(|row| row.map(|e| e.keep_where_cheaper("R"))));
    let c = Vector([x[3], x[4], x[5]]);
    let g = x[0].graph();
    let q: [Expr<'g>; 6] = std::array::from_fn(|i| {
        actuator_length(&r, &c, &anchor(half_spacing, i), i).keep_where_cheaper("Q_i1")
    });
    let p = std::array::from_fn(|i| {
        p_i2(&c, &anchor(half_spacing, i), q[i], &axis(g, i)).keep_where_cheaper("P_i2")
    });
    Posed {
        r,
        c,
        q,
        p,
        forward: None,
        geometry: geometry.to_vec(),
        centre_in_platform: None,
    }
}

/// The pairs of segments on each axis `k` of the base frame, `(a, b)` 0-based, and the axis
/// `j` of their anchors `A_a = +L e_j`, `A_b = -L e_j`: the layout eq 16 encodes.
const PAIRS: [(usize, usize, usize); 3] = [(0, 1, 2), (2, 3, 0), (4, 5, 1)];

/// The forward kinematics in closed form (docs/joint-space.md): `R` and `C` from the
/// actuator positions `Q_i1`, with no trigonometry and no linear solve.
///
/// For the pair `(a, b)` on axis `k` with anchors `±L e_j`, eq 16 is `m·(A + Q e_k - C) = 0`
/// with `m = R e_k`. The difference of the pair gives `m_j / m_k = (Q_b - Q_a) / 2L`: with
/// `a = (Q2 - Q1)/2L = r31/r11`, `b = (Q4 - Q3)/2L = r12/r22`, `c = (Q6 - Q5)/2L = r23/r33`,
/// the columns of `R` are, up to their lengths, `(1, s, a)`, `(b, 1, t)`, `(u, c, 1)`.
/// Orthogonality is linear in `s`, `t`, `u` (`s + a t = -b`, `t + b u = -c`, `u + c s = -a`):
/// `s = (ac - b - a²b) / (1 + abc)` and its cyclic images, then three normalisations. The
/// columns keep a positive diagonal (the labelling in the workspace; `R·diag(σ)` with
/// `det diag(σ) = 1` gives the same `Q`), and they make a rotation exactly where `1 + abc > 0`
/// (a reflection beyond it). The columns are built scaled by `1 + abc` (positive in the
/// workspace), which spares the division by it: on the chain to every result, it cost more than
/// the six products it adds (the forward kinematics took 16 ns with it, 13 without). The
/// half-sums `h_k` of the pairs give `m̂_k·C = (1 + abc) h_k` for
/// these columns `m̂_k`, so `C = Σ_k m̂_k (1 + abc) h_k / |m̂_k|²`, and `Rᵀ C` is simply
/// `[r11 h1, r22 h2, r33 h3]`.
pub fn forward_kinematics<'g>(geometry: &[Expr<'g>], q: &[Expr<'g>; 6]) -> Posed<'g> {
    let half_spacing = self::half_spacing(geometry);
    let g = half_spacing.graph();
    let scale = (half_spacing * 2.0).recip();
    // Per axis k: the pair's ratio m_j/m_k and half-sum.
    let ratio: [Expr<'g>; 3] = std::array::from_fn(|k| (q[PAIRS[k].1] - q[PAIRS[k].0]) * scale);
    let half_sum: [Expr<'g>; 3] = std::array::from_fn(|k| (q[PAIRS[k].0] + q[PAIRS[k].1]) * 0.5);
    let [a, b, c] = ratio;
    let forward = g.one() + a * b * c;
    // The columns scaled by `1 + abc` (positive in the workspace), which takes the division
    // off the chain to every result: the third component of each is the numerator of `s`,
    // `t` or `u`.
    let third = [
        a * c - b * (g.one() + a * a),
        a * b - c * (g.one() + b * b),
        b * c - a * (g.one() + c * c),
    ];
    // Column k: `1 + abc` on axis k, the ratio times it on axis j, the third on the last.
    let columns: [Vec3<'g>; 3] = std::array::from_fn(|k| {
        let j = PAIRS[k].2;
        Vector::from_fn(|e| {
            if e == k {
                forward
            } else if e == j {
                ratio[k] * forward
            } else {
                third[k]
            }
        })
    });
    let inverse_square: [Expr<'g>; 3] =
        std::array::from_fn(|k| columns[k].dot(&columns[k]).recip());
    let unit: [Vec3<'g>; 3] = std::array::from_fn(|k| columns[k].scale(inverse_square[k].sqrt()));
    let r = Mat::from_fn(|row, k| unit[k][row].keep_where_cheaper("R from the actuators"));
    // `m̂_k·C = (1 + abc) h_k` for these columns.
    let centre = (0..3)
        .map(|k| columns[k].scale(forward * half_sum[k] * inverse_square[k]))
        .fold(Vec3::zeros(g), |acc, v| acc + v)
        .keep_where_cheaper("C from the actuators");
    let p = std::array::from_fn(|i| p_i2(&centre, &anchor(half_spacing, i), q[i], &axis(g, i)));
    // `R e_k · C = r_kk (m̂_k · C) = r_kk h_k`.
    let centre_in_platform = Vector::from_fn(|k| r.0[k][k] * half_sum[k]);
    Posed {
        r,
        c: centre,
        q: *q,
        p,
        forward: Some(forward),
        geometry: geometry.to_vec(),
        centre_in_platform: Some(centre_in_platform),
    }
}

/// The platform's motion: twist and classical acceleration, base frame.
pub struct Motion<'g> {
    /// `V = (ω; v_C)`.
    pub twist: Vec6<'g>,
    /// `(ω̇; a_C)`, `a_C = d v_C/dt`.
    pub accel: Vec6<'g>,
    /// The actuators' motion when the kernel is given it (the joint setting): the twist and
    /// acceleration above are then derived from it, and a model may read it directly instead.
    pub joint: Option<JointMotion<'g>>,
}

impl<'g> Motion<'g> {
    /// A platform motion with no actuator motion given.
    pub fn new(twist: Vec6<'g>, accel: Vec6<'g>) -> Self {
        Motion {
            twist,
            accel,
            joint: None,
        }
    }
}

/// The actuators' rates and accelerations, `Q̇_a` and `Q̈_a`, segment order.
#[derive(Clone, Copy)]
pub struct JointMotion<'g> {
    pub qd: Vec6<'g>,
    pub qdd: Vec6<'g>,
}
