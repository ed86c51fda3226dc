//! The consistent model in matrix form (docs/models.md, "Which model?"), segment order.
//!
//! Written in the base frame, as a reader of the mechanism would: `J⁻¹` row by row, `J` by
//! inverting it (LU), `Q̈` from eq 16 differentiated twice in vector form, and `Γ` by virtual
//! work with the bodies' inertias turned into the base frame (`R I Rᵀ`). The generator works in
//! the platform frame with a factored `J`; the two meet only in the tests.

use super::{anchor, axis, inverse_kinematics, platform_wrench, rotation, to_segment_order};
use crate::types::{Acceleration, Pose, Twist};
use c5_robot::{Robot, AXIS};
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// `m_i = R e_k`, the normal of the plane the plates of segment `i` slide in.
pub fn platform_axis(pose: &Pose, i: usize) -> Vector3<f64> {
    rotation(pose).column(AXIS[i]).into_owned()
}

/// `Q_i1` (eq 16) in segment order.
pub fn lengths(l: f64, pose: &Pose) -> [f64; 6] {
    to_segment_order(&inverse_kinematics(l, pose))
}

/// `P_i2 = C - B_i`, `B_i = A_i + Q_i1 n_i` (eq 27), segment order.
pub fn p_i2(l: f64, pose: &Pose) -> [Vector3<f64>; 6] {
    let q = lengths(l, pose);
    let c = Vector3::from(pose.center);
    std::array::from_fn(|i| c - anchor(l, i) - q[i] * axis(i))
}

/// `J⁻¹`, row `i` = `[(m_i × P_i2)ᵀ m_iᵀ] / (n_i·m_i)`: eq 16 differentiated.
pub fn inverse_jacobian(l: f64, pose: &Pose) -> Matrix6<f64> {
    let mut m = Matrix6::zeros();
    for (i, p) in p_i2(l, pose).iter().enumerate() {
        let mi = platform_axis(pose, i);
        let d = mi.dot(&axis(i));
        m.fixed_view_mut::<1, 3>(i, 0)
            .copy_from(&(mi.cross(p) / d).transpose());
        m.fixed_view_mut::<1, 3>(i, 3)
            .copy_from(&(mi / d).transpose());
    }
    m
}

/// `J`, the inverse of [`inverse_jacobian`] by LU; `None` where it is singular.
pub fn jacobian(l: f64, pose: &Pose) -> Option<Matrix6<f64>> {
    inverse_jacobian(l, pose).try_inverse()
}

/// `Q̇_a = J⁻¹ V`.
pub fn joint_velocities(l: f64, pose: &Pose, twist: &Twist) -> Vector6<f64> {
    inverse_jacobian(l, pose) * twist.to_vector()
}

/// `Q̈_a`: differentiating `Q̇_i1 (n_i·m_i) = (m_i × P_i2)·ω + m_i·v_C` with `ṁ_i = ω × m_i`,
/// `Ṗ_i2 = v_C - Q̇_i1 n_i` gives
/// `Q̈_i1 (n_i·m_i) = (m_i × P_i2)·ω̇ + m_i·a_C + ((ω × m_i) × P_i2 + m_i × Ṗ_i2)·ω
///                  + (ω × m_i)·v_C - Q̇_i1 (ω × m_i)·n_i`.
pub fn joint_accelerations(
    l: f64,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Vector6<f64> {
    let p = p_i2(l, pose);
    let qd = joint_velocities(l, pose, twist);
    let (w, v) = (Vector3::from(twist.omega), Vector3::from(twist.velocity));
    let (wd, a) = (Vector3::from(accel.omega_dot), Vector3::from(accel.linear));
    Vector6::from_fn(|i, _| {
        let (m, n) = (platform_axis(pose, i), axis(i));
        let m_dot = w.cross(&m);
        let p_dot = v - qd[i] * n;
        let rhs = m.cross(&p[i]).dot(&wd)
            + m.dot(&a)
            + (m_dot.cross(&p[i]) + m.cross(&p_dot)).dot(&w)
            + m_dot.dot(&v)
            - qd[i] * m_dot.dot(&n);
        rhs / m.dot(&n)
    })
}

/// How the bodies of leg `i` move, in the consistent mechanism.
#[derive(Clone, Copy, Debug)]
pub struct LegMotion {
    /// Classical acceleration of the rod's centre of mass: `Q̈_i1 n_i`.
    pub rod_acceleration: Vector3<f64>,
    /// Classical acceleration of body 2's centre of mass `B_i + R c`.
    pub joint_acceleration: Vector3<f64>,
    /// Angular acceleration of body 2: the platform's.
    pub joint_angular_acceleration: Vector3<f64>,
}

/// The loads of the legs: the moment each body 2 puts on the platform (base frame) and the
/// direct force `τ_i` along `n_i` of the rod and body 2, with the bodies' motion.
pub fn leg_loads(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> ([Vector3<f64>; 6], Vector6<f64>, [LegMotion; 6]) {
    let l = robot.half_spacing;
    let r = rotation(pose);
    let g = Vector3::from(robot.gravity);
    let qdd = joint_accelerations(l, pose, twist, accel);
    let (w, wd) = (Vector3::from(twist.omega), Vector3::from(accel.omega_dot));
    let mut moments = [Vector3::zeros(); 6];
    let mut tau = Vector6::zeros();
    let mut motion = [LegMotion {
        rod_acceleration: Vector3::zeros(),
        joint_acceleration: Vector3::zeros(),
        joint_angular_acceleration: Vector3::zeros(),
    }; 6];
    for i in 0..6 {
        let n = axis(i);
        let seg = &robot.segments[i];
        let a_rod = qdd[i] * n;
        let s = r * Vector3::from(seg.joint.com);
        let a_g2 = qdd[i] * n + wd.cross(&s) + w.cross(&w.cross(&s));
        let f2 = seg.joint.mass * (a_g2 - g);
        let inertia = r * Matrix3::from(seg.joint.inertia).transpose() * r.transpose();
        moments[i] = inertia * wd + w.cross(&(inertia * w)) + s.cross(&f2);
        tau[i] = n.dot(&(f2 + seg.rod.mass * (a_rod - g)));
        motion[i] = LegMotion {
            rod_acceleration: a_rod,
            joint_acceleration: a_g2,
            joint_angular_acceleration: wd,
        };
    }
    (moments, tau, motion)
}

/// `Φ` at `C` with `Γ = Jᵀ (F_{N+1} + Φ)`: the moments of the bodies 2 and `J⁻ᵀ τ`.
pub fn leg_wrench(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Option<Vector6<f64>> {
    let (moments, tau, _) = leg_loads(robot, pose, twist, accel);
    let m: Vector3<f64> = moments.iter().sum();
    let jinv = inverse_jacobian(robot.half_spacing, pose);
    Some(Vector6::new(m.x, m.y, m.z, 0.0, 0.0, 0.0) + jinv.transpose() * tau)
}

/// `Γ = Jᵀ K + τ`, segment order, by virtual work: `K` is the platform's wrench (eqs 52-57)
/// plus the moments of the bodies 2, `J` the LU inverse of `J⁻¹`.
pub fn inverse_dynamics(
    robot: &Robot,
    pose: &Pose,
    twist: &Twist,
    accel: &Acceleration,
) -> Option<Vector6<f64>> {
    let (moments, tau, _) = leg_loads(robot, pose, twist, accel);
    let m: Vector3<f64> = moments.iter().sum();
    let k = platform_wrench(robot, pose, twist, accel) + Vector6::new(m.x, m.y, m.z, 0.0, 0.0, 0.0);
    Some(jacobian(robot.half_spacing, pose)?.transpose() * k + tau)
}

/// `∂Q/∂X`: how the actuator positions change with the pose coordinates `[α β γ xc yc zc]`,
/// `J⁻¹ diag(E, U)` with `ω = E [α̇ β̇ γ̇]`, `E = [x, Rx(α) y, Rx(α) Ry(β) z]`.
pub fn pose_jacobian(l: f64, pose: &Pose) -> Matrix6<f64> {
    let (sa, ca) = pose.alpha.sin_cos();
    let (sb, cb) = pose.beta.sin_cos();
    let e = Matrix3::new(1.0, 0.0, sb, 0.0, ca, -sa * cb, 0.0, sa, ca * cb);
    let mut map = Matrix6::identity();
    map.fixed_view_mut::<3, 3>(0, 0).copy_from(&e);
    inverse_jacobian(l, pose) * map
}

/// The forward kinematics the usual way, for comparison: Newton-Raphson on eq 16 from `start`
/// (the previous sample, in a controller), `X ← X + (∂Q/∂X)⁻¹ (Q - Q(X))` by LU until the
/// step is below `tolerance`; the pose and the iterations it took, or `None` if it does not
/// converge in 50 or a solve fails.
pub fn forward_kinematics_newton(
    l: f64,
    q: &[f64; 6],
    start: &Pose,
    tolerance: f64,
) -> Option<(Pose, usize)> {
    let mut x = Vector6::from(start.to_array());
    let target = Vector6::from(*q);
    for iteration in 1..=50 {
        let pose = Pose::from_array(x.into());
        let residual = target - Vector6::from(lengths(l, &pose));
        let step = pose_jacobian(l, &pose).lu().solve(&residual)?;
        x += step;
        if step.amax() < tolerance {
            return Some((Pose::from_array(x.into()), iteration));
        }
    }
    None
}
