//! The chapter's paper model in matrix form, written with `nalgebra` straight from the
//! chapter, one function per equation, in the chapter's own order: `J⁻¹` rows, `Π1` columns,
//! `Q_a` and `Γ` are `[6 5 4 3 2 1]` here (eq 30). [`CHAPTER_ORDER`] converts to the segment
//! order of the public API. The chapter's slips (docs/models.md) are corrected where marked.
//! [`model`] is the one place the reference tells the C5's two models apart.

use super::consistent;
use crate::types::{Acceleration, Pose, Twist};
use c5_robot::Robot;
use nalgebra::{Matrix3, Matrix6, SMatrix, Vector3, Vector6};

/// `CHAPTER_ORDER[k]` is the (0-based) segment at the chapter's position `k`: `[Q61 … Q11]`.
pub const CHAPTER_ORDER: [usize; 6] = [5, 4, 3, 2, 1, 0];

/// Reorders a chapter-ordered vector into segment order 1..6.
pub fn to_segment_order(v: &Vector6<f64>) -> [f64; 6] {
    let mut out = [0.0; 6];
    for (k, &seg) in CHAPTER_ORDER.iter().enumerate() {
        out[seg] = v[k];
    }
    out
}

/// Reorders a segment-ordered vector into the chapter's order.
pub fn to_chapter_order(v: &[f64; 6]) -> Vector6<f64> {
    Vector6::from_fn(|k, _| v[CHAPTER_ORDER[k]])
}

/// `ṽ` (section 2.2).
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `P̂ = [[U, P̃], [0, U]]` (section 2.2).
pub fn p_hat(p: &Vector3<f64>) -> Matrix6<f64> {
    let mut m = Matrix6::identity();
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&skew(p));
    m
}

/// Eq 15: the RPY rotation matrix, entry by entry.
pub fn rotation(pose: &Pose) -> Matrix3<f64> {
    let (sa, ca) = pose.alpha.sin_cos();
    let (sb, cb) = pose.beta.sin_cos();
    let (sg, cg) = pose.gamma.sin_cos();
    Matrix3::new(
        cb * cg,
        -cb * sg,
        sb,
        sg * ca + cg * sb * sa,
        ca * cg - sa * sb * sg,
        -cb * sa,
        sg * sa - cg * sb * ca,
        sa * cg + ca * sb * sg,
        cb * ca,
    )
}

/// `n_i` of segment `i` (0-based).
pub fn axis(i: usize) -> Vector3<f64> {
    let mut n = Vector3::zeros();
    n[[0, 0, 1, 1, 2, 2][i]] = 1.0;
    n
}

/// `A_i` of segment `i` (0-based) for half-spacing `l`.
pub fn anchor(l: f64, i: usize) -> Vector3<f64> {
    [
        Vector3::new(0.0, 0.0, l),
        Vector3::new(0.0, 0.0, -l),
        Vector3::new(l, 0.0, 0.0),
        Vector3::new(-l, 0.0, 0.0),
        Vector3::new(0.0, l, 0.0),
        Vector3::new(0.0, -l, 0.0),
    ][i]
}

/// Eq 16: `Q_a = [Q61 Q51 Q41 Q31 Q21 Q11]`, transcribed.
pub fn inverse_kinematics(l: f64, pose: &Pose) -> Vector6<f64> {
    let r = rotation(pose);
    let [xc, yc, zc] = pose.center;
    let q11 = xc + (r[(2, 0)] * (zc - l) + r[(1, 0)] * yc) / r[(0, 0)];
    let q21 = xc + (r[(2, 0)] * (zc + l) + r[(1, 0)] * yc) / r[(0, 0)];
    let q31 = yc + (r[(0, 1)] * (xc - l) + r[(2, 1)] * zc) / r[(1, 1)];
    let q41 = yc + (r[(0, 1)] * (xc + l) + r[(2, 1)] * zc) / r[(1, 1)];
    let q51 = zc + (r[(1, 2)] * (yc - l) + r[(0, 2)] * xc) / r[(2, 2)];
    let q61 = zc + (r[(1, 2)] * (yc + l) + r[(0, 2)] * xc) / r[(2, 2)];
    Vector6::new(q61, q51, q41, q31, q21, q11)
}

/// Eq 27: `P_i2 = -Q_i1 n_i + A_iO + OC` for every segment (segment order).
pub fn p_i2(l: f64, pose: &Pose) -> [Vector3<f64>; 6] {
    let q = to_segment_order(&inverse_kinematics(l, pose));
    let c = Vector3::from(pose.center);
    std::array::from_fn(|i| -q[i] * axis(i) - anchor(l, i) + c)
}

/// Eq 22: `J⁻¹`, rows `[(n_i × P_i2)ᵀ n_iᵀ]` for segments 6..1.
pub fn inverse_jacobian(p: &[Vector3<f64>; 6]) -> Matrix6<f64> {
    let mut m = Matrix6::zeros();
    for (k, &i) in CHAPTER_ORDER.iter().enumerate() {
        let n = axis(i);
        let top = n.cross(&p[i]);
        m.fixed_view_mut::<1, 3>(k, 0).copy_from(&top.transpose());
        m.fixed_view_mut::<1, 3>(k, 3).copy_from(&n.transpose());
    }
    m
}

/// Eq 39: `Π1`, transcribed (columns `Q̇61 … Q̇11`).
pub fn pi1(p: &[Vector3<f64>; 6]) -> Matrix6<f64> {
    let x = |i: usize| p[i - 1].x;
    let y = |i: usize| p[i - 1].y;
    let z = |i: usize| p[i - 1].z;
    #[rustfmt::skip]
    let m = Matrix6::new(
        (y(5) - y(1)) / (y(5) - y(6)), (y(6) - y(1)) / (y(6) - y(5)), 0.0, 0.0, (x(1) - x(5)) / (z(1) - z(2)), (x(1) - x(5)) / (z(2) - z(1)),
        (z(1) - z(3)) / (y(5) - y(6)), (z(1) - z(3)) / (y(6) - y(5)), (x(3) - x(1)) / (x(3) - x(4)), (x(4) - x(1)) / (x(4) - x(3)), 0.0, 0.0,
        0.0, 0.0, 1.0 / (x(3) - x(4)), 1.0 / (x(4) - x(3)), 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 1.0 / (z(1) - z(2)), 1.0 / (z(2) - z(1)),
        1.0 / (y(5) - y(6)), 1.0 / (y(6) - y(5)), 0.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    );
    m
}

/// Eq 41: `J1`, transcribed.
pub fn j1(p12: &Vector3<f64>) -> Matrix6<f64> {
    let (x1, y1, z1) = (p12.x, p12.y, p12.z);
    #[rustfmt::skip]
    let m = Matrix6::new(
        0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
        0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, -y1, z1, 0.0, 1.0,
        0.0, 1.0, x1, 0.0, -z1, 0.0,
        1.0, 0.0, 0.0, -x1, y1, 0.0,
    );
    m
}

/// Eq 40: `J = J1 Π1` (columns `Q̇61 … Q̇11`).
pub fn jacobian(p: &[Vector3<f64>; 6]) -> Matrix6<f64> {
    j1(&p[0]) * pi1(p)
}

/// Section 3: `H_i1`.
pub fn h_i1(i: usize) -> SMatrix<f64, 6, 1> {
    let mut h = SMatrix::<f64, 6, 1>::zeros();
    h[3 + [0, 0, 1, 1, 2, 2][i]] = 1.0;
    h
}

/// Section 3: `H_i2`, columns `[w_p u_p γ_p β_p α_p]`.
pub fn h_i2(i: usize) -> SMatrix<f64, 6, 5> {
    let rows = match i / 2 {
        0 => [5, 4, 2, 1, 0],
        1 => [5, 3, 2, 1, 0],
        _ => [4, 3, 2, 1, 0],
    };
    let mut h = SMatrix::<f64, 6, 5>::zeros();
    for (c, &r) in rows.iter().enumerate() {
        h[(r, c)] = 1.0;
    }
    h
}

/// Section 3: `W_i2`.
pub fn w_i2(i: usize) -> SMatrix<f64, 6, 1> {
    h_i1(i)
}

/// Eq 25: `J_i = [P̂_i2ᵀ H_i2, P̂_i2ᵀ P̂_i1ᵀ H_i1]`, columns `Q_i = [Q_i2; Q_i1]`.
pub fn leg_jacobian(i: usize, p_i1: &Vector3<f64>, p_i2: &Vector3<f64>) -> Matrix6<f64> {
    let mut j = Matrix6::zeros();
    let a = p_hat(p_i2).transpose();
    j.fixed_view_mut::<6, 5>(0, 0).copy_from(&(a * h_i2(i)));
    j.fixed_view_mut::<6, 1>(0, 5)
        .copy_from(&(a * p_hat(p_i1).transpose() * h_i1(i)));
    j
}

/// Eq 50: `J_Bi = P̂_i2⁻ᵀ J_i`.
pub fn leg_jacobian_at_b(
    i: usize,
    p_i1: &Vector3<f64>,
    p_i2: &Vector3<f64>,
) -> Option<Matrix6<f64>> {
    Some(p_hat(p_i2).transpose().try_inverse()? * leg_jacobian(i, p_i1, p_i2))
}

/// The leg geometry of segment `i`: `P_i1 = Q_i1 n_i` and `P_i2`.
fn leg(l: f64, pose: &Pose, i: usize) -> (Vector3<f64>, Vector3<f64>) {
    let q = to_segment_order(&inverse_kinematics(l, pose));
    (q[i] * axis(i), p_i2(l, pose)[i])
}

/// Eq 42, the conventional way: `Q̈_i = J_i⁻¹ V̇ + (d/dt J_i⁻¹) V` with the classical `V̇`,
/// `d/dt J_i⁻¹ = -J_i⁻¹ J̇_i J_i⁻¹`, `Ṗ_i1 = Q̇_i1 n_i`, `Ṗ_i2 = v_C - Q̇_i1 n_i`.
pub fn joint_accelerations_conventional(
    l: f64,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
    i: usize,
) -> Option<Vector6<f64>> {
    let (p1, p2) = leg(l, pose, i);
    let v = twist.to_vector();
    let j = leg_jacobian(i, &p1, &p2);
    let j_inv = j.try_inverse()?;
    let qd = j_inv * v;
    let n = axis(i);
    let p1_dot = qd[5] * n;
    let p2_dot = Vector3::from(twist.velocity) - qd[5] * n;
    let dt = |p: &Vector3<f64>| {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-skew(p)));
        m
    };
    let a2 = p_hat(&p2).transpose();
    let mut j_dot = Matrix6::zeros();
    j_dot
        .fixed_view_mut::<6, 5>(0, 0)
        .copy_from(&(dt(&p2_dot) * h_i2(i)));
    j_dot
        .fixed_view_mut::<6, 1>(0, 5)
        .copy_from(&((dt(&p2_dot) * p_hat(&p1).transpose() + a2 * dt(&p1_dot)) * h_i1(i)));
    let j_inv_dot = -j_inv * j_dot * j_inv;
    Some(j_inv * accel.to_vector() + j_inv_dot * v)
}

/// `(ω̇; a_C - ω × v_C)`, the spatial acceleration at `C`.
pub fn spatial_acceleration(twist: &Twist, accel: &Acceleration) -> Vector6<f64> {
    let w = Vector3::from(twist.omega);
    let v = Vector3::from(twist.velocity);
    let a = Vector3::from(accel.linear) - w.cross(&v);
    let wd = accel.omega_dot;
    Vector6::new(wd[0], wd[1], wd[2], a.x, a.y, a.z)
}

/// Eqs 43-48: `Q̈_i = [Q̈_i2; Q̈_i1]` by projection, from the spatial acceleration `vdot`.
pub fn joint_accelerations_projection(
    p1: &Vector3<f64>,
    p2: &Vector3<f64>,
    vdot: &Vector6<f64>,
    i: usize,
) -> Vector6<f64> {
    // Eq 43.
    let v2 = p_hat(p2)
        .transpose()
        .try_inverse()
        .expect("P̂ is unimodular")
        * vdot;
    let (h1, h2, w2) = (h_i1(i), h_i2(i), w_i2(i));
    let p1t = p_hat(p1).transpose();
    // Eq 47.
    let qdd1 = (w2.transpose() * v2)[0] / (w2.transpose() * p1t * h1)[0];
    // Eq 45.
    let v1 = h1 * qdd1;
    // Eq 48.
    let qdd2 = h2.transpose() * v2 - h2.transpose() * p1t * v1;
    Vector6::new(qdd2[0], qdd2[1], qdd2[2], qdd2[3], qdd2[4], qdd1)
}

/// The motion of the two bodies of a leg, as the recursion computes it.
#[derive(Clone, Copy, Debug)]
pub struct LegMotion {
    /// Classical acceleration of body 1's centre of mass.
    pub rod_acceleration: Vector3<f64>,
    /// Classical acceleration of body 2's centre of mass.
    pub joint_acceleration: Vector3<f64>,
    /// Angular acceleration of body 2.
    pub joint_angular_acceleration: Vector3<f64>,
}

/// Eq 49's `T_i = M_i Q̈_i + C_i + G_i` by recursive Newton-Euler, with the motion it used.
pub fn leg_dynamics(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
    i: usize,
) -> (Vector6<f64>, LegMotion) {
    let l = robot.half_spacing;
    let r = rotation(pose);
    let (p1, p2) = leg(l, pose, i);
    let q = p1.dot(&axis(i));
    let g = Vector3::from(robot.gravity);
    let w = Vector3::from(twist.omega);
    let vdot = spatial_acceleration(twist, accel);
    let qdd = joint_accelerations_projection(&p1, &p2, &vdot, i);
    // Forward recursion (eq 9 with the projection's Q̈): spatial accelerations at O_i1 = A_i
    // and O_i2 = B_i.
    let v1_dot = h_i1(i) * qdd[5];
    let v2_dot = p_hat(&p1).transpose() * v1_dot + h_i2(i) * qdd.fixed_rows::<5>(0);
    // Body 2: moves with the platform; B_i's platform-point velocity is v_C - ω × P_i2.
    let seg = &robot.segments[i];
    let s = r * Vector3::from(seg.joint.com);
    let i2 = r * Matrix3::from(seg.joint.inertia).transpose() * r.transpose();
    let wd = v2_dot.fixed_rows::<3>(0).into_owned();
    let v_b = Vector3::from(twist.velocity) - w.cross(&p2);
    let a_b = v2_dot.fixed_rows::<3>(3) + w.cross(&v_b);
    let a_g2 = a_b + wd.cross(&s) + w.cross(&w.cross(&s));
    let f2 = seg.joint.mass * (a_g2 - g);
    let n2 = i2 * wd + w.cross(&(i2 * w)) + s.cross(&f2);
    let f_i2 = Vector6::new(n2.x, n2.y, n2.z, f2.x, f2.y, f2.z);
    // Body 1: translates along n_i; J_Gi1 multiplies a zero angular motion.
    let n = axis(i);
    let a_g1 = v1_dot.fixed_rows::<3>(3).into_owned();
    let f1 = seg.rod.mass * (a_g1 - g);
    let j_g1 =
        Matrix3::from(seg.rod.inertia) + q * q * Matrix3::from(seg.rod.inertia_per_length_squared);
    let w1 = Vector3::zeros();
    let n1 = j_g1 * w1 + w1.cross(&(j_g1 * w1)) + (0.5 * q * n).cross(&f1);
    // Backward recursion, eq 10.
    let f_i1 = Vector6::new(n1.x, n1.y, n1.z, f1.x, f1.y, f1.z) + p_hat(&p1) * f_i2;
    let t2 = h_i2(i).transpose() * f_i2;
    let t1 = (h_i1(i).transpose() * f_i1)[0];
    let t = Vector6::new(t2[0], t2[1], t2[2], t2[3], t2[4], t1);
    let motion = LegMotion {
        rod_acceleration: a_g1,
        joint_acceleration: a_g2,
        joint_angular_acceleration: wd,
    };
    (t, motion)
}

/// Eqs 52-57: `F_{N+1} = Λ_C V̇ + C_C + G_C` with the classical `V̇ = (ω̇; a_C)`.
pub fn platform_wrench(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Vector6<f64> {
    let r = rotation(pose);
    let b = &robot.platform;
    let m = b.mass;
    let gc = r * Vector3::from(b.com);
    // Eq 55, moved from the centre of mass to C (parallel axes).
    let i_c = r * Matrix3::from(b.inertia).transpose() * r.transpose() - m * skew(&gc) * skew(&gc);
    let mut lambda = Matrix6::zeros();
    lambda.fixed_view_mut::<3, 3>(0, 0).copy_from(&i_c);
    lambda
        .fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(m * skew(&gc)));
    lambda
        .fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(-m * skew(&gc)));
    lambda
        .fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(m * Matrix3::identity()));
    let w = Vector3::from(twist.omega);
    let c_top = skew(&w) * i_c * w;
    let c_bot = -m * skew(&w) * skew(&gc) * w;
    let g = Vector3::from(robot.gravity);
    let g_top = -m * skew(&gc) * g;
    let g_bot = -m * g;
    lambda * accel.to_vector()
        + Vector6::new(c_top.x, c_top.y, c_top.z, c_bot.x, c_bot.y, c_bot.z)
        + Vector6::new(g_top.x, g_top.y, g_top.z, g_bot.x, g_bot.y, g_bot.z)
}

/// Step 3, corrected (Slips 2, 3): `Φ = Σ P̂_i2⁻¹ J_Bi⁻ᵀ T_i`, with `J_Bi` inverted by LU.
pub fn leg_wrench(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Option<Vector6<f64>> {
    let mut phi = Vector6::zeros();
    for i in 0..6 {
        let (p1, p2) = leg(robot.half_spacing, pose, i);
        let (t, _) = leg_dynamics(robot, pose, twist, accel, i);
        let jb = leg_jacobian_at_b(i, &p1, &p2)?;
        let f_b = jb.transpose().lu().solve(&t)?;
        phi += p_hat(&p2).try_inverse()? * f_b;
    }
    Some(phi)
}

/// How step 6 (`Γ = Jᵀ K`) is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step6 {
    /// Khalil's: build `J⁻¹` (eq 22) and solve `J⁻ᵀ Γ = K` (eq 61) by LU.
    Khalil,
    /// The chapter's: `Γ = Π1ᵀ J1ᵀ K` (eq 62).
    Factored,
}

/// Eq 60 (Slip 1 corrected, `J⁻ᵀ`): `Γ = Jᵀ (F_{N+1} + Φ)`, chapter order `[Γ61 … Γ11]`.
pub fn inverse_dynamics(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
    step6: Step6,
) -> Option<Vector6<f64>> {
    let k = platform_wrench(robot, pose, twist, accel) + leg_wrench(robot, pose, twist, accel)?;
    let p = p_i2(robot.half_spacing, pose);
    match step6 {
        Step6::Khalil => inverse_jacobian(&p).transpose().lu().solve(&k),
        Step6::Factored => Some(pi1(&p).transpose() * j1(&p[0]).transpose() * k),
    }
}

/// One model's reference, every quantity in segment order (rows of `J⁻¹`, columns of `J`,
/// entries of `Q̇`, `Q̈`, `Γ` for segments 1..6), so that a check written once holds every
/// model to its own reference. `None` where a solve of the reference fails.
#[derive(Clone, Copy)]
pub struct ModelReference {
    /// `J⁻¹` (row `i` for segment `i+1`).
    pub inverse_jacobian: fn(f64, &Pose) -> Matrix6<f64>,
    /// `J` (column `i` for segment `i+1`), as the model builds it.
    pub jacobian: fn(f64, &Pose) -> Option<Matrix6<f64>>,
    /// `Q̇_a = J⁻¹ V`.
    pub joint_velocities: fn(f64, &Pose, &Twist) -> Vector6<f64>,
    /// `Q̈_a` from the platform's classical motion.
    pub joint_accelerations: fn(f64, &Pose, &Twist, &Acceleration) -> Vector6<f64>,
    /// `Φ`, the legs' loads at `C`.
    pub leg_wrench: fn(&Robot, &Pose, &Twist, &Acceleration) -> Option<Vector6<f64>>,
    /// `Γ`.
    pub inverse_dynamics: fn(&Robot, &Pose, &Twist, &Acceleration) -> Option<Vector6<f64>>,
}

/// The paper model's rows of `J⁻¹` in segment order. The permutation is its own inverse:
/// segment `i` is at chapter row `CHAPTER_ORDER[i]`.
fn paper_inverse_jacobian(l: f64, pose: &Pose) -> Matrix6<f64> {
    let chapter = inverse_jacobian(&p_i2(l, pose));
    Matrix6::from_fn(|i, j| chapter[(CHAPTER_ORDER[i], j)])
}

/// The reference of `model`: the one place the reference tells the models apart.
pub fn model(model: c5_robot::Model) -> ModelReference {
    match model {
        c5_robot::Model::Paper => ModelReference {
            inverse_jacobian: paper_inverse_jacobian,
            jacobian: |l, pose| {
                let chapter = jacobian(&p_i2(l, pose));
                Some(Matrix6::from_fn(|r, i| chapter[(r, CHAPTER_ORDER[i])]))
            },
            joint_velocities: |l, pose, twist| paper_inverse_jacobian(l, pose) * twist.to_vector(),
            joint_accelerations: |l, pose, twist, accel| {
                let vdot = spatial_acceleration(twist, accel);
                Vector6::from_fn(|i, _| {
                    let (p1, p2) = leg(l, pose, i);
                    joint_accelerations_projection(&p1, &p2, &vdot, i)[5]
                })
            },
            leg_wrench,
            inverse_dynamics: |robot, pose, twist, accel| {
                let gamma = inverse_dynamics(robot, pose, twist, accel, Step6::Khalil)?;
                Some(Vector6::from(to_segment_order(&gamma)))
            },
        },
        c5_robot::Model::Consistent => ModelReference {
            inverse_jacobian: consistent::inverse_jacobian,
            jacobian: consistent::jacobian,
            joint_velocities: consistent::joint_velocities,
            joint_accelerations: consistent::joint_accelerations,
            leg_wrench: consistent::leg_wrench,
            inverse_dynamics: consistent::inverse_dynamics,
        },
    }
}

/// `W = J⁻ᵀ Γ = F_{N+1} + Φ` of `model`: the wrench at `C` (base frame) the actuators put on
/// the platform for the motion.
pub fn task_wrench(
    robot: &Robot,
    model: c5_robot::Model,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Option<Vector6<f64>> {
    let phi = (self::model(model).leg_wrench)(robot, pose, twist, accel)?;
    Some(platform_wrench(robot, pose, twist, accel) + phi)
}

/// `(M_x, h)` of `Γ = Jᵀ (M_x V̇ + h)`, numerically: `h = W(0)`, column `k` of `M_x` is
/// `W(e_k) - h` (`W` is affine in the acceleration).
pub fn task_space(
    robot: &Robot,
    model: c5_robot::Model,
    pose: &Pose,
    twist: &Twist,
) -> Option<(Matrix6<f64>, Vector6<f64>)> {
    let h = task_wrench(robot, model, pose, twist, &Acceleration::default())?;
    let mut m = Matrix6::zeros();
    for k in 0..6 {
        let mut unit = [0.0; 6];
        unit[k] = 1.0;
        let accel = Acceleration {
            omega_dot: [unit[0], unit[1], unit[2]],
            linear: [unit[3], unit[4], unit[5]],
        };
        m.set_column(k, &(task_wrench(robot, model, pose, twist, &accel)? - h));
    }
    Some((m, h))
}

/// The forward dynamics, numerically: `M_x V̇ = J⁻ᵀ Γ - h` by Cholesky; `gamma` in segment
/// order. `None` where `M_x` is not positive definite or a solve fails.
pub fn forward_dynamics(
    robot: &Robot,
    model: c5_robot::Model,
    pose: &Pose,
    twist: &Twist,
    gamma: &[f64; 6],
) -> Option<Acceleration> {
    let (m, h) = task_space(robot, model, pose, twist)?;
    let jinv = (self::model(model).inverse_jacobian)(robot.half_spacing, pose);
    let w = jinv.transpose() * Vector6::from(*gamma);
    let a = m.cholesky()?.solve(&(w - h));
    Some(Acceleration {
        omega_dot: [a[0], a[1], a[2]],
        linear: [a[3], a[4], a[5]],
    })
}
