//! The consistent model: the mechanism eq 16 describes (docs/models.md), whose kinematics are the
//! exact time derivatives of eq 16 and whose forces close the power balance.
//!
//! A design decision, drawn from eq 16, eq 27 and Section 3 ("a spherical joint tied to two
//! crossed sliding plates"): the ball centre `B_i = A_i + Q_i1 n_i` is on the actuator axis;
//! the plates slide in the platform plane through `C` whose normal is the platform axis
//! `m_i = R e_k` (`k` = x, y, z for segments 1-2, 3-4, 5-6), so `m_i·(B_i - C) = 0` is eq 16.
//! The rod (body 1) translates along `n_i`; the plates and ball housing (body 2) keep the
//! platform's orientation and translate with the ball. The ball transmits a force and no
//! moment; the plates a force along `m_i` and moments.
//!
//! Most of the work happens in the platform frame, where the inverse Jacobian has eq 22's
//! sparsity: with `p_i = Rᵀ P_i2` (which lies in its plane, `e_k·p_i = 0`) and
//! `D = diag(n_i·m_i)`, `J⁻¹ = D⁻¹ S(p) diag(Rᵀ, Rᵀ)`, `S` with rows `[(e_k × p_i)ᵀ e_kᵀ]`. So
//! `J = diag(R, R) S⁻¹ D` and step 6 is `Γ = D S⁻ᵀ diag(Rᵀ, Rᵀ) K`: the chapter's factored
//! Jacobian and solve-free step 6 carry over, with a 3×3 system in place of eq 38's three
//! divisions (the pairs of segments no longer share a coordinate: `y1 ≠ y2` in the platform
//! frame once the platform turns).

use super::bodies::{wrench_in_platform_frame, Dynamics, Frame};
use super::c5::C5;
use super::geometry::{anchor, divisor, half_spacing, platform_axis, JointMotion, Motion, Posed};
use super::{Mechanics, Model, Quantity, Structure};
use crate::dag::Expr;
use crate::linalg::{Mat, Mat3, Mat6, Vec3, Vec6, Vector};
use c5_robot::AXIS;

/// The consistent model's [`Mechanics`].
pub struct Consistent;

impl Mechanics for Consistent {
    fn name(&self) -> &'static str {
        Model::Consistent.name()
    }

    fn structure(&self) -> &'static dyn Structure {
        &C5
    }

    fn summary(&self) -> &'static str {
        "The mechanism eq 16 describes (docs/models.md): the plates of segment `i` slide in the \
         platform plane of normal `m_i = R e_k`; rates and accelerations are the exact time \
         derivatives of eq 16 and the forces close the power balance."
    }

    fn equations(&self, quantity: Quantity) -> &'static [&'static str] {
        match quantity {
            Quantity::InverseKinematics => &["15", "16", "27"],
            Quantity::PlatformWrench => &["52", "54", "55", "56", "57"],
            Quantity::InverseJacobian => &["15", "16", "16 d/dt", "27"],
            Quantity::Jacobian => &["15", "16", "16 d/dt", "27", "40 (J = diag(R,R) S⁻¹ D)"],
            Quantity::JointVelocities => &["15", "16", "16 d/dt"],
            Quantity::JointAccelerations => &["15", "16", "16 d²/dt²"],
            Quantity::LegWrench => &["16 d²/dt²", "virtual work"],
            Quantity::InverseDynamics => &[
                "15",
                "16",
                "16 d²/dt²",
                "27",
                "52-57",
                "virtual work",
                "62 (Γ = D S⁻ᵀ Rᵀ K + τ)",
            ],
            Quantity::TaskSpace => &["15", "16", "16 d²/dt²", "52-57", "virtual work", "∂W/∂V̇"],
            Quantity::ForwardDynamics => &[
                "15",
                "16",
                "16 d²/dt²",
                "52-57",
                "virtual work",
                "M_x V̇ = J⁻ᵀ Γ - h (LDLᵀ)",
            ],
            Quantity::Identification => &[
                "15",
                "16",
                "16 d²/dt²",
                "27",
                "52-57",
                "virtual work",
                "62 (Γ = D S⁻ᵀ Rᵀ K + τ)",
                "∂Γ/∂π",
            ],
        }
    }

    fn inverse_jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g> {
        inverse_jacobian(posed)
    }

    fn jacobian<'g>(&self, posed: &Posed<'g>) -> Mat6<'g> {
        jacobian(posed)
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

    fn motion_from_actuators<'g>(&self, posed: &Posed<'g>, joint: &JointMotion<'g>) -> Motion<'g> {
        motion_from_actuators(posed, joint)
    }

    /// Through the inverse dynamics and the structured solve, which `M_x` would not share.
    fn forward_dynamics_jacobians<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        twist: &Vec6<'g>,
        _gamma: &Vec6<'g>,
        accel: &Vec6<'g>,
        wrt: &super::derivatives::ForwardInputs<'_, 'g>,
    ) -> [Vec<Expr<'g>>; 3] {
        super::derivatives::by_inverse_dynamics(self, dynamics, posed, twist, accel, wrt)
    }

    fn forward_dynamics<'g>(
        &self,
        dynamics: &Dynamics<'g>,
        posed: &Posed<'g>,
        twist: &Vec6<'g>,
        gamma: &Vec6<'g>,
    ) -> Vec6<'g> {
        forward_dynamics(dynamics, posed, twist, gamma)
    }
}

/// `e_k`, the platform axis of segment `i` in the platform frame.
fn unit<'g>(g: &'g crate::Graph, i: usize) -> Vec3<'g> {
    Vector::from_fn(|j| g.constant(if j == AXIS[i] { 1.0 } else { 0.0 }))
}

/// The segments paired along each axis: `(a, b)` = (1, 2), (3, 4), (5, 6), 0-based.
const PAIRS: [(usize, usize); 3] = [(0, 1), (2, 3), (4, 5)];

/// Eq 16 differentiated, row `i` of `J⁻¹` (Slip 4): from `m_i·(B_i - C) = 0`,
/// `Q̇_i1 (n_i·m_i) = (m_i × P_i2)·ω + m_i·v_C`, so the row is `[(m_i × P_i2)ᵀ m_iᵀ] / (n_i·m_i)`.
pub fn inverse_jacobian_row<'g>(m: &Vec3<'g>, p: &Vec3<'g>, d: Expr<'g>) -> Vec6<'g> {
    let inv = d.recip();
    Vec6::spatial(m.cross(p).scale(inv), m.scale(inv))
}

/// `J⁻¹` in the base frame, row `i` for segment `i+1`.
pub fn inverse_jacobian<'g>(posed: &Posed<'g>) -> Mat6<'g> {
    Mat(std::array::from_fn(|i| {
        inverse_jacobian_row(
            &platform_axis(&posed.r, i),
            &posed.p[i],
            divisor(&posed.r, i),
        )
        .0
    }))
}

/// A pose seen from the platform: `p_i = Rᵀ P_i2`, `ν_i = Rᵀ n_i` and `d_i = n_i·m_i`.
pub struct PlatformView<'g> {
    pub p: [Vec3<'g>; 6],
    pub nu: [Vec3<'g>; 6],
    pub d: [Expr<'g>; 6],
}

/// The platform view of `posed`. `p_i = Rᵀ P_i2`, or `Rᵀ C - Rᵀ A_i - Q_i1 ν_i` where the
/// forward kinematics gives `Rᵀ C` without a rotation; its component along `e_k` is zero
/// (eq 16) and is set so, since no equation below reads it.
pub fn platform_view<'g>(posed: &Posed<'g>) -> PlatformView<'g> {
    let rt = posed.r.transpose();
    let g = posed.c[0].graph();
    let nu: [Vec3<'g>; 6] = std::array::from_fn(|i| posed.r.row(AXIS[i]));
    let p = std::array::from_fn(|i| {
        let full = match posed.centre_in_platform {
            Some(centre) => {
                centre - rt * anchor(half_spacing(&posed.geometry), i) - nu[i].scale(posed.q[i])
            }
            None => rt * posed.p[i],
        };
        Vector::from_fn(|j| if j == AXIS[i] { g.zero() } else { full[j] })
            .keep_where_cheaper("p_i, the legs' platform points in the platform frame")
    });
    PlatformView {
        p,
        nu,
        d: std::array::from_fn(|i| divisor(&posed.r, i)),
    }
}

/// Row `i` of `S(p)`: `[(e_k × p_i)ᵀ e_kᵀ]`, eq 22's row with `n_i → e_k`, `P_i2 → p_i`.
pub fn s_row<'g>(p: &[Vec3<'g>; 6], i: usize) -> Vec6<'g> {
    let e = unit(p[0][0].graph(), i);
    Vec6::spatial(e.cross(&p[i]), e)
}

/// `G`: the pair differences of `S`. The rows of a pair share their linear part `e_kᵀ`, so their
/// difference is angular only: row `k` of `G` is `(e_k × (p_a - p_b))ᵀ`. In the chapter's
/// setting `G` is diagonal (eq 38); here it is a full 3×3 matrix once the platform turns.
pub fn pair_matrix<'g>(p: &[Vec3<'g>; 6]) -> Mat3<'g> {
    Mat(std::array::from_fn(|k| {
        let (a, b) = PAIRS[k];
        (s_row(p, a) - s_row(p, b)).top().0
    }))
}

/// `S⁻¹ q`, the platform-frame twist `(w; u)` with `S (w; u) = q`: the pair differences give
/// `G w = [q_1 - q_2, q_3 - q_4, q_5 - q_6]`, then the first segment of each pair gives
/// `u_k = q_a - (e_k × p_a)·w`.
pub fn s_inverse<'g>(p: &[Vec3<'g>; 6], q: &Vec6<'g>) -> Vec6<'g> {
    let rhs = Vector::from_fn(|k| q[PAIRS[k].0] - q[PAIRS[k].1]);
    let w = pair_matrix(p).solve(&rhs);
    let u = Vector::from_fn(|k| {
        let a = PAIRS[k].0;
        q[a] - s_row(p, a).top().dot(&w)
    });
    Vec6::spatial(w, u)
}

/// `S⁻ᵀ k`: the `y` with `Sᵀ y = (n; f)`. The linear rows give `y_a + y_b = f_k` per pair;
/// putting `y_b = f_k - y_a` in the angular rows leaves `Gᵀ [y_1 y_3 y_5] = n - Σ f_k e_k × p_b`.
/// `y_i` is the force the plates of segment `i` put on the platform along `m_i`.
pub fn s_inverse_transpose<'g>(p: &[Vec3<'g>; 6], k: &Vec6<'g>) -> Vec6<'g> {
    let (n, f) = (k.top(), k.bottom());
    let mut rhs = n;
    for (axis, &(_, b)) in PAIRS.iter().enumerate() {
        rhs = rhs - s_row(p, b).top().scale(f[axis]);
    }
    let ya = pair_matrix(p).transpose().solve(&rhs);
    let g = n[0].graph();
    let mut y = Vec6::zeros(g);
    for (axis, &(a, b)) in PAIRS.iter().enumerate() {
        y[a] = ya[axis];
        y[b] = f[axis] - ya[axis];
    }
    y
}

/// `J = diag(R, R) S⁻¹ D`, rows `[ωx ωy ωz vx vy vz]`, column `i` for segment `i+1`.
pub fn jacobian<'g>(posed: &Posed<'g>) -> Mat6<'g> {
    let view = platform_view(posed);
    let g = posed.c[0].graph();
    let columns: [Vec6<'g>; 6] = std::array::from_fn(|j| {
        let q = Vector::from_fn(|i| if i == j { view.d[j] } else { g.zero() });
        let wu = s_inverse(&view.p, &q);
        Vec6::spatial(posed.r * wu.top(), posed.r * wu.bottom())
    });
    Mat::from_fn(|r, c| columns[c][r])
}

/// The platform's motion in the platform frame: `w = Rᵀ ω`, `ẇ = Rᵀ ω̇`, `u = Rᵀ v_C` and the
/// classical `a = Rᵀ a_C`, with the actuators' motion when it is given.
struct PlatformMotion<'g> {
    frame: Frame<'g>,
    u: Vec3<'g>,
    a: Vec3<'g>,
    joint: Option<JointMotion<'g>>,
}

/// The platform's motion seen from the platform: rotated from the base frame, or, given the
/// actuators' motion, straight from it without a rotation (`S⁻¹`, eq 16 differentiated).
fn platform_motion<'g>(posed: &Posed<'g>, motion: &Motion<'g>) -> PlatformMotion<'g> {
    match motion.joint {
        None => {
            let frame = Frame::new(posed.r, &motion.twist.top(), &motion.accel.top());
            PlatformMotion {
                u: frame
                    .to_platform(&motion.twist.bottom())
                    .keep_where_cheaper("u, v_C in the platform frame"),
                a: frame
                    .to_platform(&motion.accel.bottom())
                    .keep_where_cheaper("a, a_C in the platform frame"),
                frame,
                joint: None,
            }
        }
        Some(joint) => {
            let view = platform_view(posed);
            let scaled = |v: &Vec6<'g>| Vector::from_fn(|i| view.d[i] * v[i]);
            // `D Q̇ = S (w; u)`.
            let wu = s_inverse(&view.p, &scaled(&joint.qd))
                .keep_where_cheaper("(w; u) from the actuators' rates");
            let (w, u) = (wu.top(), wu.bottom());
            // `D Q̈ = S (ẇ; a) + b(w, u, Q̇)`.
            let bias = acceleration_bias(&view, &w, &u, &joint.qd);
            let wda = s_inverse(&view.p, &(scaled(&joint.qdd) - bias))
                .keep_where_cheaper("(ẇ; a) from the actuators' accelerations");
            PlatformMotion {
                frame: Frame {
                    r: posed.r,
                    omega: w,
                    omega_dot: wda.top(),
                },
                u,
                a: wda.bottom(),
                joint: Some(joint),
            }
        }
    }
}

/// The part of `(n_i·m_i) Q̈_i1` that is not `S (ẇ; a)`: `(w × e_k)·(p_i × w + 2 (u - ν_i Q̇_i1))`
/// (see [`joint_accelerations`]).
fn acceleration_bias<'g>(
    view: &PlatformView<'g>,
    w: &Vec3<'g>,
    u: &Vec3<'g>,
    qd: &Vec6<'g>,
) -> Vec6<'g> {
    Vector::from_fn(|i| {
        let g = w[0].graph();
        let e = unit(g, i);
        let p = view.p[i];
        let slip = (*u - view.nu[i].scale(qd[i])).scale(g.constant(2.0));
        w.cross(&e).dot(&(p.cross(w) + slip))
    })
}

/// The platform's motion from the actuators', base frame: `(w; u) = S⁻¹ D Q̇`,
/// `(ẇ; a) = S⁻¹ (D Q̈ - b)`, rotated by `R`.
pub fn motion_from_actuators<'g>(posed: &Posed<'g>, joint: &JointMotion<'g>) -> Motion<'g> {
    let g = posed.c[0].graph();
    let pm = platform_motion(
        posed,
        &Motion {
            twist: Vec6::zeros(g),
            accel: Vec6::zeros(g),
            joint: Some(*joint),
        },
    );
    let base = |v: &Vec3<'g>| pm.frame.to_base(v);
    Motion {
        twist: Vec6::spatial(base(&pm.frame.omega), base(&pm.u)),
        accel: Vec6::spatial(base(&pm.frame.omega_dot), base(&pm.a)),
        joint: Some(*joint),
    }
}

/// `Q̇_a = J⁻¹ V`, segment order, computed as `D⁻¹ S(p) (w; u)` in the platform frame.
pub fn joint_velocities<'g>(posed: &Posed<'g>, twist: &Vec6<'g>) -> Vec6<'g> {
    let view = platform_view(posed);
    let g = posed.c[0].graph();
    let motion = Motion::new(*twist, Vec6::zeros(g));
    let pm = platform_motion(posed, &motion);
    rates(&view, &pm)
}

fn rates<'g>(view: &PlatformView<'g>, pm: &PlatformMotion<'g>) -> Vec6<'g> {
    if let Some(joint) = pm.joint {
        return joint.qd;
    }
    let wu = Vec6::spatial(pm.frame.omega, pm.u);
    Vector::from_fn(|i| s_row(&view.p, i).dot(&wu) / view.d[i])
}

/// Eq 16 differentiated twice: with `u_i = ω × m_i`,
/// `Q̈_i1 (n_i·m_i) = (m_i × P_i2)·ω̇ + m_i·a_C + u_i·(P_i2 × ω + 2 (v_C - Q̇_i1 n_i))`,
/// written in the platform frame (`m_i → e_k`, `P_i2 → p_i`, `n_i → ν_i`, vectors `→ Rᵀ x`).
/// The terms in `ω` and `Q̇_i1` are what eq 47 lacks.
pub fn joint_accelerations<'g>(posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g> {
    let view = platform_view(posed);
    let pm = platform_motion(posed, motion);
    accelerations(&view, &pm, &rates(&view, &pm))
}

fn accelerations<'g>(view: &PlatformView<'g>, pm: &PlatformMotion<'g>, qd: &Vec6<'g>) -> Vec6<'g> {
    if let Some(joint) = pm.joint {
        return joint.qdd;
    }
    let (w, wd) = (pm.frame.omega, pm.frame.omega_dot);
    Vector::from_fn(|i| {
        let g = w[0].graph();
        let e = unit(g, i);
        let p = view.p[i];
        let u = w.cross(&e);
        let slip = (pm.u - view.nu[i].scale(qd[i])).scale(g.constant(2.0));
        (e.cross(&p).dot(&wd) + pm.a[AXIS[i]] + u.dot(&(p.cross(&w) + slip))) / view.d[i]
    })
}

/// The loads of the legs, split as the mechanism carries them.
pub struct LegLoads<'g> {
    /// `Q̈_a`.
    pub qdd: Vec6<'g>,
    /// The moment each body 2 puts on the platform (platform frame): Euler's equations plus the
    /// moment of its force about `B_i`. The ball carries no moment and body 2 turns with the
    /// platform, so this goes to the platform whole.
    pub moments: [Vec3<'g>; 6],
    /// `τ_i`: the force along `n_i` that drives the rod and body 2 along the actuator axis
    /// (their translation is `Q̇_i1 n_i`), straight to actuator `i`.
    pub direct: Vec6<'g>,
}

/// The legs' loads by virtual power: body 1 moves as `Q̇_i1 n_i`, body 2's centre of mass as
/// `Q̇_i1 n_i + ω × R c_i` turning at `ω`; so its force along `n_i` and the rod's go to the
/// actuator, and its moment about `B_i` to the platform.
fn leg_loads<'g>(
    dynamics: &Dynamics<'g>,
    view: &PlatformView<'g>,
    pm: &PlatformMotion<'g>,
    gravity: &Vec3<'g>,
) -> LegLoads<'g> {
    let qd = rates(view, pm);
    let qdd = accelerations(view, pm, &qd);
    let frame = &pm.frame;
    let g = qd[0].graph();
    let mut moments = [Vec3::zeros(g); 6];
    let mut direct = Vec6::zeros(g);
    for i in 0..6 {
        let (rod, body) = (&dynamics.legs[i][0], &dynamics.legs[i][1]);
        let k = AXIS[i];
        // Body 2 about B_i, whose classical acceleration is Q̈_i1 n_i (ν_i in this frame).
        let wrench = wrench_in_platform_frame(body, frame, &view.nu[i].scale(qdd[i]), gravity);
        moments[i] = wrench.top();
        // n_i·f for the rod and body 2: n_i·(Q̈ n_i) = Q̈ and n_i·g = g_k exactly; the first
        // moment adds ν_i·(ω̇ × h + ω × (ω × h)).
        let h = body.first_moment;
        let offset = frame.omega_dot.cross(&h) + frame.omega.cross(&frame.omega.cross(&h));
        let g_k = dynamics.gravity[k];
        direct[i] = (rod.mass + body.mass) * (qdd[i] - g_k) + view.nu[i].dot(&offset);
    }
    LegLoads {
        qdd,
        moments,
        direct,
    }
}

/// Everything step 6 needs: the platform view, the wrench `K_p` at `C` in the platform frame
/// (the platform's own plus the moments of the bodies 2) and the direct terms `τ`.
fn loads<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> (PlatformView<'g>, Vec6<'g>, LegLoads<'g>) {
    let view = platform_view(posed);
    let pm = platform_motion(posed, motion);
    let gravity = pm.frame.to_platform(&dynamics.gravity);
    let legs = leg_loads(dynamics, &view, &pm, &gravity);
    let platform = wrench_in_platform_frame(&dynamics.platform, &pm.frame, &pm.a, &gravity);
    let g = gravity[0].graph();
    let moments = legs.moments.iter().fold(Vec3::zeros(g), |acc, m| acc + *m);
    let k = platform + Vec6::spatial(moments, Vec3::zeros(g));
    (view, k, legs)
}

/// `Φ` at `C`, base frame, such that `Γ = Jᵀ (F_{N+1} + Φ)` as in eq 60: the moments of the
/// bodies 2, plus each direct term `τ_i` seen at the platform, a force `τ_i / d_i` along `m_i`
/// at `B_i` (`Sᵀ D⁻¹ τ` in the platform frame).
pub fn leg_wrench<'g>(dynamics: &Dynamics<'g>, posed: &Posed<'g>, motion: &Motion<'g>) -> Vec6<'g> {
    let view = platform_view(posed);
    let pm = platform_motion(posed, motion);
    let gravity = pm.frame.to_platform(&dynamics.gravity);
    let legs = leg_loads(dynamics, &view, &pm, &gravity);
    let g = gravity[0].graph();
    let mut phi = Vec6::zeros(g);
    for i in 0..6 {
        phi = phi
            + Vec6::spatial(legs.moments[i], Vec3::zeros(g))
            + s_row(&view.p, i).scale(legs.direct[i] / view.d[i]);
    }
    Vec6::spatial(
        pm.frame.to_base(&phi.top()),
        pm.frame.to_base(&phi.bottom()),
    )
}

/// The wrench the plates put on the platform for the motion `pm` (`K_p`, platform frame) and
/// the direct terms `τ`: the generalized force on the platform is `K_p + Sᵀ D⁻¹ τ` (`Sᵀ D⁻¹ Γ`
/// for the forces `Γ` of the inverse dynamics, since `Γ = D S⁻ᵀ K_p + τ`): no solve.
fn plate_wrench_and_direct_terms<'g>(
    dynamics: &Dynamics<'g>,
    view: &PlatformView<'g>,
    pm: &PlatformMotion<'g>,
    gravity: &Vec3<'g>,
) -> (Vec6<'g>, Vec6<'g>) {
    let legs = leg_loads(dynamics, view, pm, gravity);
    let g = gravity[0].graph();
    let platform = wrench_in_platform_frame(&dynamics.platform, &pm.frame, &pm.a, gravity);
    let moments = legs.moments.iter().fold(Vec3::zeros(g), |acc, m| acc + *m);
    (
        platform + Vec6::spatial(moments, Vec3::zeros(g)),
        legs.direct,
    )
}

/// `Sᵀ D⁻¹ x`: forces along the actuators seen at the platform (platform frame).
fn at_platform<'g>(view: &PlatformView<'g>, x: &Vec6<'g>) -> Vec6<'g> {
    let g = x[0].graph();
    (0..6).fold(Vec6::zeros(g), |acc, i| {
        acc + s_row(&view.p, i).scale(x[i] / view.d[i])
    })
}

/// The forward dynamics from the mechanism's structure, in the platform frame. The generalized
/// force `W' = K_p + Sᵀ D⁻¹ τ` is affine in the platform-frame acceleration
/// `a' = (Rᵀ ω̇; Rᵀ a_C)`, and its derivative `M' = ∂W'/∂a'` is the platform's spatial inertia
/// plus the bodies 2's rotational inertias (constant in this frame) plus
/// `Sᵀ D⁻¹ diag(m_rod + m_2) D⁻¹ S` (the rods and bodies 2 translating with their balls, `S`
/// with three non-zeros a row) and, with a body 2's centre of mass off its ball, their
/// coupling. So `M' a' = Sᵀ D⁻¹ (Γ - τ(0)) - K_p(0)`, solved by an unrolled `LDLᵀ`, and
/// `(ω̇; a_C) = (R ẇ'; R a')`: no derivative through `J⁻¹` and no rotation of the inertia.
pub fn forward_dynamics<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    twist: &Vec6<'g>,
    gamma: &Vec6<'g>,
) -> Vec6<'g> {
    let g = posed.c[0].graph();
    let view = platform_view(posed);
    let rt = posed.r.transpose();
    let (w, u) = (rt * twist.top(), rt * twist.bottom());
    let gravity = rt * dynamics.gravity;
    let moving = |accel: Vec6<'g>| PlatformMotion {
        frame: Frame {
            r: posed.r,
            omega: w,
            omega_dot: accel.top(),
        },
        u,
        a: accel.bottom(),
        joint: None,
    };
    let unknown: Vec6<'g> = Vector::from_fn(|k| g.input(super::INTERNAL_INPUTS + k as u32));
    let (plates, direct) =
        plate_wrench_and_direct_terms(dynamics, &view, &moving(unknown), &gravity);
    let inertia = super::kernels::jacobian_wrt(
        g,
        &(plates + at_platform(&view, &direct)).to_vec(),
        &unknown.0,
    );
    let (plates, direct) =
        plate_wrench_and_direct_terms(dynamics, &view, &moving(Vec6::zeros(g)), &gravity);
    let rhs = at_platform(&view, &(*gamma - direct)) - plates;
    let a = solve_linear_first(&inertia, &rhs);
    Vec6::spatial(posed.r * a.top(), posed.r * a.bottom())
}

/// `M' a' = r` for the platform-frame inertia, by blocks: its linear block is diagonal (the
/// rows of `S` have `e_kᵀ` as their linear part, and the platform's and the bodies 2's linear
/// inertia is a mass times the identity), so the linear accelerations are eliminated without
/// fill-in and the angular ones solve the 3×3 Schur complement `A - B D⁻¹ Bᵀ` in closed form (one
/// division on the chain, where an `LDLᵀ` has a pivot after a pivot). Falls back on a 6×6
/// `LDLᵀ` if a parameter set makes the block not diagonal.
fn solve_linear_first<'g>(inertia: &Mat6<'g>, r: &Vec6<'g>) -> Vec6<'g> {
    // The lower triangle only: the upper one is the same numbers by other expressions.
    let m: Mat6<'g> = Mat::from_fn(|i, j| inertia.0[i.max(j)][i.min(j)]);
    let diagonal =
        (0..3).all(|i| (0..3).all(|j| i == j || m.0[3 + i][3 + j].as_const() == Some(0.0)));
    if !diagonal {
        return m.ldlt_solve(r);
    }
    let m = &m.0;
    let inv: [Expr<'g>; 3] = std::array::from_fn(|k| m[3 + k][3 + k].recip());
    let b = |i: usize, k: usize| m[3 + k][i];
    let schur: Mat3<'g> = Mat::from_fn(|i, j| {
        (0..3).fold(m[i.max(j)][i.min(j)], |acc, k| {
            acc - b(i, k) * b(j, k) * inv[k]
        })
    });
    let rhs: Vec3<'g> =
        Vector::from_fn(|i| (0..3).fold(r[i], |acc, k| acc - b(i, k) * inv[k] * r[3 + k]));
    let angular = schur.solve(&rhs);
    let linear: Vec3<'g> =
        Vector::from_fn(|k| (0..3).fold(r[3 + k], |acc, i| acc - b(i, k) * angular[i]) * inv[k]);
    Vec6::spatial(angular, linear)
}

/// The inverse dynamics by virtual work, with step 6 factored: `Γ = D S⁻ᵀ K_p + τ`, where
/// `K_p = diag(Rᵀ, Rᵀ) K` is the wrench the plates must put on the platform (no linear solve
/// but the 3×3 of [`s_inverse_transpose`]).
pub fn inverse_dynamics<'g>(
    dynamics: &Dynamics<'g>,
    posed: &Posed<'g>,
    motion: &Motion<'g>,
) -> Vec6<'g> {
    let (view, k, legs) = loads(dynamics, posed, motion);
    let y = s_inverse_transpose(&view.p, &k);
    Vector::from_fn(|i| view.d[i] * y[i] + legs.direct[i])
}
