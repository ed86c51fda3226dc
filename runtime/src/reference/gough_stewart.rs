//! The Gough-Stewart platform in matrix form, written another way than the generator's: leg
//! by leg with Newton-Euler and the joints' reaction forces, through the U joints' angles.
//!
//! The generator differentiates each leg's closed forms and assembles the dynamics by virtual
//! work, then solves the normal equations. Here each leg's motion comes from its U joint's two
//! rates (`u̇ = ω_L × u` solved for `θ̇₁`, `θ̇₂`; `ω_L = θ̇₁ a + θ̇₂ y'`, and the accelerations
//! likewise), each body's wrench about its centre of mass in the base frame, the S joint's
//! force on the platform from the leg's moments about `A_i` along the U joint's two axes (the
//! joint transmits no moment about them) and the rod's axial balance, and the actuator forces
//! from the platform's Newton-Euler equations by an LU solve. Conventions: the runtime's
//! (`crate::gough_stewart`).

use super::rotation;
use crate::types::{Acceleration, Pose, State, Twist};
use c5_robot::GoughStewart;
use nalgebra::{Matrix3, Matrix3x2, Matrix6, Vector2, Vector3, Vector6};

/// One leg's kinematics at a platform state.
#[derive(Clone, Copy, Debug)]
pub struct Leg {
    /// `A_i`, `B_i` and `u_i` (base frame), the length `|B_i - A_i|`.
    pub base: Vector3<f64>,
    pub joint: Vector3<f64>,
    pub u: Vector3<f64>,
    pub length: f64,
    /// `R p_i`.
    pub r: Vector3<f64>,
    /// `Ḃ`, `B̈`, `L̇`, `L̈`.
    pub b_dot: Vector3<f64>,
    pub b_ddot: Vector3<f64>,
    pub length_dot: f64,
    pub length_ddot: f64,
    /// `u̇`, `ü`.
    pub u_dot: Vector3<f64>,
    pub u_ddot: Vector3<f64>,
    /// The leg's frame `[x' y' u]` and its angular velocity and acceleration (base frame).
    pub frame: Matrix3<f64>,
    pub omega: Vector3<f64>,
    pub omega_dot: Vector3<f64>,
}

fn v3(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

/// Leg `i` at `state`.
pub fn leg(robot: &GoughStewart, i: usize, state: &State) -> Leg {
    let description = &robot.legs[i];
    let rot = rotation(&state.pose);
    let (w, wd) = (v3(state.twist.omega), v3(state.accel.omega_dot));
    let r = rot * v3(description.platform);
    let base = v3(description.base);
    let joint = v3(state.pose.center) + r;
    let d = joint - base;
    let length = d.norm();
    let u = d / length;
    let b_dot = v3(state.twist.velocity) + w.cross(&r);
    let b_ddot = v3(state.accel.linear) + wd.cross(&r) + w.cross(&w.cross(&r));
    let length_dot = u.dot(&b_dot);
    let u_dot = (b_dot - u * length_dot) / length;
    let length_ddot = u.dot(&b_ddot) + length * u_dot.norm_squared();
    let u_ddot = (b_ddot - u * length_ddot - u_dot * (2.0 * length_dot)) / length;
    // The U joint: the first axis `a` fixed in the base, the second `y'` fixed in the leg.
    let a = v3(description.u_axis).normalize();
    let y = u.cross(&a).normalize();
    let x = y.cross(&u);
    let frame = Matrix3::from_columns(&[x, y, u]);
    // `u̇ = ω_L × u` with `ω_L = θ̇₁ a + θ̇₂ y'`: two unknowns, three equations (consistent).
    let rates = Matrix3x2::from_columns(&[a.cross(&u), y.cross(&u)]);
    let solve = |m: &Matrix3x2<f64>, rhs: &Vector3<f64>| -> Vector2<f64> {
        (m.transpose() * m)
            .try_inverse()
            .expect("the U joint is regular")
            * (m.transpose() * rhs)
    };
    let theta_dot = solve(&rates, &u_dot);
    let omega = a * theta_dot[0] + y * theta_dot[1];
    // `ü = ω̇_L × u + ω_L × u̇` with `ω̇_L = θ̈₁ a + θ̈₂ y' + θ̇₁ θ̇₂ (a × y')` (`y'` turns with
    // the first joint only).
    let carried = a.cross(&y) * (theta_dot[0] * theta_dot[1]);
    let theta_ddot = solve(&rates, &(u_ddot - carried.cross(&u) - omega.cross(&u_dot)));
    let omega_dot = a * theta_ddot[0] + y * theta_ddot[1] + carried;
    Leg {
        base,
        joint,
        u,
        length,
        r,
        b_dot,
        b_ddot,
        length_dot,
        length_ddot,
        u_dot,
        u_ddot,
        frame,
        omega,
        omega_dot,
    }
}

/// `q_i = |B_i - A_i| + o_i` (m).
pub fn actuator_positions(robot: &GoughStewart, pose: &Pose) -> [f64; 6] {
    let state = State {
        pose: *pose,
        ..State::default()
    };
    std::array::from_fn(|i| leg(robot, i, &state).length + robot.legs[i].encoder_offset)
}

/// `J⁻¹`, rows `[(R p_i × u_i)ᵀ u_iᵀ]`.
pub fn inverse_jacobian(robot: &GoughStewart, pose: &Pose) -> Matrix6<f64> {
    let state = State {
        pose: *pose,
        ..State::default()
    };
    Matrix6::from_fn(|i, j| {
        let l = leg(robot, i, &state);
        if j < 3 {
            l.r.cross(&l.u)[j]
        } else {
            l.u[j - 3]
        }
    })
}

/// `q̇ = u_i · Ḃ_i` and `q̈ = L̈_i`.
pub fn joint_rates(robot: &GoughStewart, state: &State) -> ([f64; 6], [f64; 6]) {
    let legs: [Leg; 6] = std::array::from_fn(|i| leg(robot, i, state));
    (legs.map(|l| l.length_dot), legs.map(|l| l.length_ddot))
}

/// A body's Newton-Euler wrench about its centre of mass, base frame: `(I ω̇ + ω × I ω;
/// m (a - g))`, `I` given in `frame`.
fn body_wrench(
    mass: f64,
    inertia: &Matrix3<f64>,
    frame: &Matrix3<f64>,
    omega: &Vector3<f64>,
    omega_dot: &Vector3<f64>,
    accel: &Vector3<f64>,
    gravity: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let i = frame * inertia * frame.transpose();
    (
        i * omega_dot + omega.cross(&(i * omega)),
        (accel - gravity) * mass,
    )
}

/// The actuator forces `Γ` (N) at `state`.
pub fn inverse_dynamics(robot: &GoughStewart, state: &State) -> [f64; 6] {
    let g = v3(robot.gravity);
    let rot = rotation(&state.pose);
    let (w, wd) = (v3(state.twist.omega), v3(state.accel.omega_dot));
    // The platform's needed wrench about `C`, from its centre of mass.
    let p = &robot.platform;
    let s = rot * v3(p.centre_of_mass);
    let a_g = v3(state.accel.linear) + wd.cross(&s) + w.cross(&w.cross(&s));
    let (n_g, f) = body_wrench(
        p.mass,
        &Matrix3::from(p.inertia_matrix()),
        &rot,
        &w,
        &wd,
        &a_g,
        &g,
    );
    let mut needed = Vector6::zeros();
    needed
        .fixed_rows_mut::<3>(0)
        .copy_from(&(n_g + s.cross(&f)));
    needed.fixed_rows_mut::<3>(3).copy_from(&f);
    let mut lines = Matrix6::zeros();
    let mut rod_axial = [0.0; 6];
    for i in 0..6 {
        let l = leg(robot, i, state);
        let description = &robot.legs[i];
        let body = |b: &c5_robot::LegBody| Matrix3::from_diagonal(&Vector3::from(b.inertia));
        let (cylinder, rod) = (&description.cylinder, &description.rod);
        let g_cylinder = l.base + l.u * cylinder.com;
        let g_rod = l.joint - l.u * rod.com;
        let a_cylinder = l.u_ddot * cylinder.com;
        let a_rod = l.b_ddot - l.u_ddot * rod.com;
        let (n_c, f_c) = body_wrench(
            cylinder.mass,
            &body(cylinder),
            &l.frame,
            &l.omega,
            &l.omega_dot,
            &a_cylinder,
            &g,
        );
        let (n_r, f_r) = body_wrench(
            rod.mass,
            &body(rod),
            &l.frame,
            &l.omega,
            &l.omega_dot,
            &a_rod,
            &g,
        );
        // The leg's needed moment about `A_i`; the S joint's force `F` on the platform puts
        // `-F` on the leg at `B_i`: `D × (-F) + τ_U = M_A`, `τ_U` free of moments along `a`
        // and `y'`. Along `y'` that gives `F·x'`, along `a` `F·y'`.
        let moment = n_c + n_r + (g_cylinder - l.base).cross(&f_c) + (g_rod - l.base).cross(&f_r);
        let (x, y) = (
            l.frame.column(0).into_owned(),
            l.frame.column(1).into_owned(),
        );
        let a = v3(description.u_axis).normalize();
        let f_x = -moment.dot(&y) / l.length;
        let f_y = moment.dot(&a) / (l.length * a.dot(&x));
        let transverse = x * f_x + y * f_y;
        // The platform gets `F_i = F_⊥ + λ_i u_i` at `B_i`; the rod's axial balance gives
        // `Γ_i = f_rod · u_i + λ_i`.
        let moment_of_transverse = l.r.cross(&transverse);
        for k in 0..3 {
            needed[k] -= moment_of_transverse[k];
            needed[3 + k] -= transverse[k];
        }
        for k in 0..3 {
            lines[(k, i)] = l.r.cross(&l.u)[k];
            lines[(3 + k, i)] = l.u[k];
        }
        rod_axial[i] = f_r.dot(&l.u);
    }
    let lambda = lines.lu().solve(&needed).expect("a regular pose");
    std::array::from_fn(|i| rod_axial[i] + lambda[i])
}

/// The forward dynamics: the acceleration at which [`inverse_dynamics`] gives `gamma`
/// (it is affine in the acceleration: six evaluations make its matrix).
pub fn forward_dynamics(
    robot: &GoughStewart,
    pose: &Pose,
    twist: &Twist,
    gamma: &[f64; 6],
) -> Acceleration {
    let at = |a: [f64; 6]| {
        Vector6::from(inverse_dynamics(
            robot,
            &State {
                pose: *pose,
                twist: *twist,
                accel: Acceleration::from_array(a),
            },
        ))
    };
    let bias = at([0.0; 6]);
    let matrix = Matrix6::from_fn(|i, j| {
        let mut e = [0.0; 6];
        e[j] = 1.0;
        at(e)[i] - bias[i]
    });
    let a = matrix
        .lu()
        .solve(&(Vector6::from(*gamma) - bias))
        .expect("a regular pose");
    Acceleration::from_array(a.into())
}

/// The kinetic and potential energy of every body: the platform, and each leg's cylinder
/// (centre of mass `A_i + c u_i`) and rod (`B_i - c u_i`), turning at the leg's `ω_L`.
pub fn energy(robot: &GoughStewart, state: &State) -> (f64, f64) {
    let g = v3(robot.gravity);
    let rot = rotation(&state.pose);
    let w = v3(state.twist.omega);
    let p = &robot.platform;
    let s = rot * v3(p.centre_of_mass);
    let spin = |frame: &Matrix3<f64>, inertia: &Matrix3<f64>, w: &Vector3<f64>| {
        0.5 * w.dot(&(frame * inertia * frame.transpose() * w))
    };
    let v_g = v3(state.twist.velocity) + w.cross(&s);
    let mut kinetic =
        0.5 * p.mass * v_g.norm_squared() + spin(&rot, &Matrix3::from(p.inertia_matrix()), &w);
    let mut potential = -p.mass * g.dot(&(v3(state.pose.center) + s));
    for i in 0..6 {
        let l = leg(robot, i, state);
        let description = &robot.legs[i];
        for (body, centre, velocity) in [
            (
                &description.cylinder,
                l.base + l.u * description.cylinder.com,
                l.u_dot * description.cylinder.com,
            ),
            (
                &description.rod,
                l.joint - l.u * description.rod.com,
                l.b_dot - l.u_dot * description.rod.com,
            ),
        ] {
            let inertia = Matrix3::from_diagonal(&Vector3::from(body.inertia));
            kinetic +=
                0.5 * body.mass * velocity.norm_squared() + spin(&l.frame, &inertia, &l.omega);
            potential -= body.mass * g.dot(&centre);
        }
    }
    (kinetic, potential)
}
