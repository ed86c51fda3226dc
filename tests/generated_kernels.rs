//! Every generated kernel against the nalgebra reference of its model, on 10 000 seeded random
//! states each: the paper model in both settings (chapter and pose), the consistent model with
//! the default robot folded and with random robots through the parameter vector. Errors are
//! relative to the largest entry of the reference quantity; the bound is 1e-12 except where the
//! reference itself goes through LU factorisations (the paper's `Φ` and `Γ`, the consistent
//! `J` and `Γ`: 6×6 solves with condition numbers up to ~1e2 here), where it is 1e-11.

mod support;

use c5_generated::f64::{consistent as kc, paper as k};
use c5_runtime::reference::{self as r, consistent as rc, Step6, CHAPTER_ORDER};
use c5_runtime::{Robot, State};
use nalgebra::{Matrix6, Vector6};
use support::*;

const STATES: usize = 10_000;

fn chapter_rows(m: &Matrix6<f64>) -> [[f64; 6]; 6] {
    // Chapter row k holds segment CHAPTER_ORDER[k].
    let mut out = [[0.0; 6]; 6];
    for (kk, &i) in CHAPTER_ORDER.iter().enumerate() {
        out[i] = std::array::from_fn(|j| m[(kk, j)]);
    }
    out
}

fn chapter_columns(m: &Matrix6<f64>) -> [[f64; 6]; 6] {
    let mut out = [[0.0; 6]; 6];
    for row in 0..6 {
        for (kk, &i) in CHAPTER_ORDER.iter().enumerate() {
            out[row][i] = m[(row, kk)];
        }
    }
    out
}

fn p_array(p: &[nalgebra::Vector3<f64>; 6]) -> [[f64; 3]; 6] {
    std::array::from_fn(|i| p[i].into())
}

/// Calls the folded kernel `$m::$folded(args)`, or `$m::$with_params(args, params)` when
/// `params` is given.
macro_rules! kernel {
    ($params:expr, $m:ident :: $folded:ident / $with_params:ident ($($arg:expr),*)) => {
        match $params {
            Some(pp) => $m::$with_params($($arg,)* pp),
            None => $m::$folded($($arg),*),
        }
    };
    ($params:expr, $folded:ident / $with_params:ident ($($arg:expr),*)) => {
        kernel!($params, k::$folded / $with_params ($($arg),*))
    };
}

/// Checks the pose-setting kernels for `robot`, through `params` (None: the folded kernels).
fn check_pose_kernels(robot: &Robot, params: Option<&[f64; 152]>, s: &State) {
    let x = s.pose.to_array();
    let v = s.twist.to_array();
    let a = s.accel.to_array();
    let l = robot.half_spacing;
    let (q, p, divisors) = kernel!(params, inverse_kinematics / inverse_kinematics_params(&x));
    let rot = r::rotation(&s.pose);
    let divisors_ref = [rot[(0, 0)], rot[(1, 1)], rot[(2, 2)]];
    assert!(rel_err(&divisors, &divisors_ref, 1.0) < 1e-15);
    let p_ref = r::p_i2(l, &s.pose);
    assert!(
        rel_err(
            &q,
            &r::to_segment_order(&r::inverse_kinematics(l, &s.pose)),
            1e-3
        ) < 1e-12
    );
    assert!(rel_err(&flat(&p), &flat(&p_array(&p_ref)), 1e-3) < 1e-12);

    let jinv = kernel!(
        params,
        inverse_jacobian_pose / inverse_jacobian_pose_params(&x)
    );
    assert!(
        rel_err(
            &flat(&jinv),
            &flat(&chapter_rows(&r::inverse_jacobian(&p_ref))),
            1.0
        ) < 1e-12
    );
    let j = kernel!(params, jacobian_pose / jacobian_pose_params(&x));
    assert!(
        rel_err(
            &flat(&j),
            &flat(&chapter_columns(&r::jacobian(&p_ref))),
            1.0
        ) < 1e-12
    );

    let qd = kernel!(params, joint_velocities / joint_velocities_params(&x, &v));
    let qd_ref = r::to_segment_order(&(r::inverse_jacobian(&p_ref) * s.twist.to_vector()));
    assert!(rel_err(&qd, &qd_ref, 1e-3) < 1e-12);

    let (qdd, divisors) = kernel!(
        params,
        joint_accelerations / joint_accelerations_params(&x, &v, &a)
    );
    assert!(rel_err(&divisors, &divisors_ref, 1.0) < 1e-15);
    let (legs, divisors) = kernel!(
        params,
        leg_joint_accelerations / leg_joint_accelerations_params(&x, &v, &a)
    );
    assert!(rel_err(&divisors, &divisors_ref, 1.0) < 1e-15);
    let vdot = r::spatial_acceleration(&s.twist, &s.accel);
    let q_seg = r::to_segment_order(&r::inverse_kinematics(l, &s.pose));
    for i in 0..6 {
        let want = r::joint_accelerations_projection(&(q_seg[i] * r::axis(i)), &p_ref[i], &vdot, i);
        assert!(
            rel_err(&legs[i], want.as_slice(), 1e-3) < 1e-12,
            "segment {}",
            i + 1
        );
        assert!((legs[i][5] - qdd[i]).abs() <= 1e-15 * qdd[i].abs().max(1.0));
    }

    let (t, acc) = (&s.twist, &s.accel);
    let (phi, _) = kernel!(params, leg_wrench / leg_wrench_params(&x, &v, &a));
    let phi_ref = r::leg_wrench(robot, &s.pose, t, acc).unwrap();
    assert!(rel_err(&phi, phi_ref.as_slice(), 1.0) < 1e-11);
    let f = kernel!(params, platform_wrench / platform_wrench_params(&x, &v, &a));
    let f_ref = r::platform_wrench(robot, &s.pose, t, acc);
    assert!(rel_err(&f, f_ref.as_slice(), 1.0) < 1e-12);
    let (gamma, divisors) = kernel!(
        params,
        inverse_dynamics / inverse_dynamics_params(&x, &v, &a)
    );
    assert!(rel_err(&divisors, &divisors_ref, 1.0) < 1e-15);
    let gamma_ref =
        r::to_segment_order(&r::inverse_dynamics(robot, &s.pose, t, acc, Step6::Khalil).unwrap());
    assert!(
        rel_err(&gamma, &gamma_ref, 1.0) < 1e-11,
        "{gamma:?} vs {gamma_ref:?}"
    );
}

#[test]
fn pose_kernels_with_the_default_robot_folded_equal_the_reference() {
    let mut rng = rng(10);
    let robot = Robot::default();
    for _ in 0..STATES {
        check_pose_kernels(&robot, None, &random_state(&mut rng));
    }
}

#[test]
fn pose_kernels_with_runtime_parameters_equal_the_reference_for_other_robots() {
    let mut rng = rng(11);
    for n in 0..STATES {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let params: [f64; 152] = robot.kernel_parameters().try_into().unwrap();
        check_pose_kernels(&robot, Some(&params), &random_state(&mut rng));
    }
}

#[test]
fn chapter_setting_kernels_equal_the_reference() {
    let mut rng = rng(12);
    let robot = Robot::default();
    for _ in 0..STATES {
        let s = random_state(&mut rng);
        let p_ref = r::p_i2(robot.half_spacing, &s.pose);
        let p = p_array(&p_ref);
        let jinv = k::inverse_jacobian(&p);
        assert!(
            rel_err(
                &flat(&jinv),
                &flat(&chapter_rows(&r::inverse_jacobian(&p_ref))),
                1.0
            ) < 1e-12
        );
        let pi1 = k::pi1(&p);
        assert!(rel_err(&flat(&pi1), &flat(&chapter_columns(&r::pi1(&p_ref))), 1.0) < 1e-12);
        let j = k::jacobian(&p);
        assert!(
            rel_err(
                &flat(&j),
                &flat(&chapter_columns(&r::jacobian(&p_ref))),
                1.0
            ) < 1e-12
        );
        let vdot = r::spatial_acceleration(&s.twist, &s.accel);
        let q1 = r::to_segment_order(&r::inverse_kinematics(robot.half_spacing, &s.pose))[0];
        let qdd = k::joint_accelerations_segment(&p[0], &vdot.into());
        let want = r::joint_accelerations_projection(&(q1 * r::axis(0)), &p_ref[0], &vdot, 0);
        assert!(rel_err(&qdd, want.as_slice(), 1e-3) < 1e-12);
        let kk: [f64; 6] = random_state(&mut rng).accel.to_array().map(|x| 50.0 * x);
        let gamma = k::step6_factored(&p, &kk);
        let want = r::pi1(&p_ref).transpose() * r::j1(&p_ref[0]).transpose() * Vector6::from(kk);
        assert!(rel_err(&gamma, &r::to_segment_order(&want), 1.0) < 1e-12);
    }
}

/// Checks the consistent model's pose kernels for `robot`, through `params` (None: folded).
fn check_consistent_kernels(robot: &Robot, params: Option<&[f64; 152]>, s: &State) {
    let x = s.pose.to_array();
    let v = s.twist.to_array();
    let a = s.accel.to_array();
    let l = robot.half_spacing;
    let rot = r::rotation(&s.pose);
    let divisors_ref = [rot[(0, 0)], rot[(1, 1)], rot[(2, 2)]];
    let check_divisors = |d: [f64; 3]| assert!(rel_err(&d, &divisors_ref, 1.0) < 1e-15);

    let (q, p, d) = kernel!(
        params,
        kc::inverse_kinematics / inverse_kinematics_params(&x)
    );
    check_divisors(d);
    assert!(rel_err(&q, &rc::lengths(l, &s.pose), 1e-3) < 1e-12);
    assert!(rel_err(&flat(&p), &flat(&p_array(&rc::p_i2(l, &s.pose))), 1e-3) < 1e-12);

    let (jinv, d) = kernel!(
        params,
        kc::inverse_jacobian_pose / inverse_jacobian_pose_params(&x)
    );
    check_divisors(d);
    let jinv_ref = rc::inverse_jacobian(l, &s.pose);
    assert!(rel_err(&flat(&jinv), &flat(&from_na(&jinv_ref)), 1.0) < 1e-12);
    let (jac, d) = kernel!(params, kc::jacobian_pose / jacobian_pose_params(&x));
    check_divisors(d);
    let jac_ref = rc::jacobian(l, &s.pose).unwrap();
    assert!(rel_err(&flat(&jac), &flat(&from_na(&jac_ref)), 1.0) < 1e-11);

    let (qd, d) = kernel!(
        params,
        kc::joint_velocities / joint_velocities_params(&x, &v)
    );
    check_divisors(d);
    let qd_ref = rc::joint_velocities(l, &s.pose, &s.twist);
    assert!(rel_err(&qd, qd_ref.as_slice(), 1e-3) < 1e-12);
    let (qdd, d) = kernel!(
        params,
        kc::joint_accelerations / joint_accelerations_params(&x, &v, &a)
    );
    check_divisors(d);
    let qdd_ref = rc::joint_accelerations(l, &s.pose, &s.twist, &s.accel);
    assert!(rel_err(&qdd, qdd_ref.as_slice(), 1e-3) < 1e-12);

    let (t, acc) = (&s.twist, &s.accel);
    let (phi, d) = kernel!(params, kc::leg_wrench / leg_wrench_params(&x, &v, &a));
    check_divisors(d);
    let phi_ref = rc::leg_wrench(robot, &s.pose, t, acc).unwrap();
    assert!(rel_err(&phi, phi_ref.as_slice(), 1.0) < 1e-12);
    let f = kernel!(
        params,
        kc::platform_wrench / platform_wrench_params(&x, &v, &a)
    );
    assert!(
        rel_err(
            &f,
            r::platform_wrench(robot, &s.pose, t, acc).as_slice(),
            1.0
        ) < 1e-12
    );
    let (gamma, d) = kernel!(
        params,
        kc::inverse_dynamics / inverse_dynamics_params(&x, &v, &a)
    );
    check_divisors(d);
    let gamma_ref = rc::inverse_dynamics(robot, &s.pose, t, acc).unwrap();
    assert!(
        rel_err(&gamma, gamma_ref.as_slice(), 1.0) < 1e-11,
        "{gamma:?} vs {gamma_ref:?}"
    );
}

#[test]
fn consistent_kernels_with_the_default_robot_folded_equal_the_reference() {
    let mut rng = rng(14);
    let robot = Robot::default();
    for _ in 0..STATES {
        check_consistent_kernels(&robot, None, &random_state(&mut rng));
    }
}

#[test]
fn consistent_kernels_with_runtime_parameters_equal_the_reference_for_other_robots() {
    let mut rng = rng(15);
    for n in 0..STATES {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let params: [f64; 152] = robot.kernel_parameters().try_into().unwrap();
        check_consistent_kernels(&robot, Some(&params), &random_state(&mut rng));
    }
}

#[test]
fn f32_kernels_track_f64_within_single_precision() {
    use c5_generated::f32::{consistent as kc32, paper as k32};
    let mut rng = rng(13);
    let (mut worst_paper, mut worst_consistent): (f64, f64) = (0.0, 0.0);
    for _ in 0..STATES {
        let s = random_state(&mut rng);
        let (x, v, a) = (s.pose.to_array(), s.twist.to_array(), s.accel.to_array());
        let (x32, v32, a32) = (
            x.map(|e| e as f32),
            v.map(|e| e as f32),
            a.map(|e| e as f32),
        );
        let (g64, _) = k::inverse_dynamics(&x, &v, &a);
        let (g32, _) = k32::inverse_dynamics(&x32, &v32, &a32);
        worst_paper = worst_paper.max(rel_err(&g32.map(f64::from), &g64, 1.0));
        let (g64, _) = kc::inverse_dynamics(&x, &v, &a);
        let (g32, _) = kc32::inverse_dynamics(&x32, &v32, &a32);
        worst_consistent = worst_consistent.max(rel_err(&g32.map(f64::from), &g64, 1.0));
    }
    println!(
        "worst relative error of f32 inverse_dynamics: paper {worst_paper:.2e}, consistent \
         {worst_consistent:.2e}"
    );
    assert!(worst_paper < 1e-5, "{worst_paper}");
    assert!(worst_consistent < 1e-5, "{worst_consistent}");
}
