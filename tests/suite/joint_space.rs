//! The kernels from the actuator positions, rates and accelerations (what the encoders
//! measure) against the platform state they came from, against a Newton-Raphson forward
//! kinematics written independently with nalgebra, against finite differences of the forward
//! kinematics along a rotating motion, and against the bodies' kinetic energy.

use crate::support;

use c5_runtime::reference::{self as r, consistent as rc};
use c5_runtime::{Error, Kernels, Model, Pose, Robot, State, C5};
use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};
use rand::Rng;
use support::*;

const STATES: usize = 10_000;

/// `(Q, Q̇, Q̈)` of a platform state in `c5`'s model.
fn actuators(c5: &C5, s: &State) -> [[f64; 6]; 3] {
    [
        c5.inverse_kinematics(&s.pose).unwrap().0,
        c5.joint_velocities(&s.pose, &s.twist).unwrap(),
        c5.joint_accelerations(s).unwrap(),
    ]
}

fn close_rel(got: &[f64], want: &[f64], tolerance: f64) -> bool {
    rel_err(got, want, 1.0) <= tolerance
}

/// `check(n, c5, state)` on `STATES` seeded states, each in both models of a robot that is
/// random for even `n` and the chapter's for odd `n` (whose kernels are also folded).
fn for_each_case(seed: u64, mut check: impl FnMut(usize, &C5, &State)) {
    let mut rng = rng(seed);
    for n in 0..STATES {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let s = random_state(&mut rng);
        for model in Model::ALL {
            check(n, &C5::with_model(robot, model).unwrap(), &s);
        }
    }
}

#[test]
fn forward_and_inverse_kinematics_undo_each_other() {
    for_each_case(80, |n, c5, s| {
        let model = c5.model();
        // X → Q → X.
        let (q, _) = c5.inverse_kinematics(&s.pose).unwrap();
        let back = c5.forward_kinematics(&q).unwrap();
        assert!(
            close_rel(&back.to_array(), &s.pose.to_array(), 1e-13),
            "{model}: {back:?} vs {:?}",
            s.pose
        );
        // Q → X → Q.
        let (again, _) = c5.inverse_kinematics(&back).unwrap();
        assert!(close_rel(&again, &q, 1e-13), "{model}");
        // The folded kernels of the default robot, through the trait.
        if n % 2 == 1 {
            let (rot, c, singular) = c5.kernels().forward_kinematics(&q);
            let want = r::rotation(&s.pose);
            assert!(singular[0] > 0.0);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((rot[i][j] - want[(i, j)]).abs() < 1e-13);
                }
                assert!((c[i] - s.pose.center[i]).abs() < 1e-13);
            }
            assert_eq!(singular[1..], [rot[0][0], rot[1][1], rot[2][2]]);
        }
    });
}

/// A uniformly random rotation.
fn random_rotation(rng: &mut rand_chacha::ChaCha8Rng) -> Matrix3<f64> {
    let v: [f64; 4] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
    let q = nalgebra::Quaternion::new(v[0], v[1], v[2], v[3]);
    *UnitQuaternion::from_quaternion(q)
        .to_rotation_matrix()
        .matrix()
}

/// `[α β γ]` of a rotation, `R = Rx(α) Ry(β) Rz(γ)` (any branch).
fn rpy(m: &Matrix3<f64>) -> [f64; 3] {
    [
        (-m[(1, 2)]).atan2(m[(2, 2)]),
        m[(0, 2)].clamp(-1.0, 1.0).asin(),
        (-m[(0, 1)]).atan2(m[(0, 0)]),
    ]
}

#[test]
fn over_all_rotations_the_pose_found_is_a_labelling_of_the_true_one() {
    // `R·diag(σ)`, `det diag(σ) = 1`, puts every plate in the same plane: the same Q.
    let labellings = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let mut rng = rng(81);
    let l = Robot::default().half_spacing;
    let c5 = C5::new(Robot::default()).unwrap();
    let (mut served, mut refused) = (0, 0);
    for _ in 0..STATES {
        let rot = random_rotation(&mut rng);
        let [alpha, beta, gamma] = rpy(&rot);
        let pose = Pose {
            alpha,
            beta,
            gamma,
            center: std::array::from_fn(|_| rng.gen_range(-0.08..0.08)),
        };
        // Away from eq 16's singularities, where Q would be huge.
        if (0..3).any(|k| rot[(k, k)].abs() < 0.05) {
            continue;
        }
        let q = rc::lengths(l, &pose);
        match c5.forward_kinematics(&q) {
            Ok(found) => {
                served += 1;
                let got = r::rotation(&found);
                let matches = labellings.iter().any(|sigma| {
                    let labelled = rot * Matrix3::from_diagonal(&Vector3::from(*sigma));
                    (got - labelled).amax() < 1e-9
                });
                assert!(matches, "{pose:?} gave {found:?}");
                assert!(
                    (0..3).all(|k| got[(k, k)] > 0.0),
                    "the workspace's placement"
                );
                assert!(close_rel(&found.center, &pose.center, 1e-9));
            }
            Err(Error::ForwardSingular { value }) => {
                refused += 1;
                // Refused only where no labelling has every r_kk > 0.
                let best = labellings
                    .iter()
                    .map(|sigma| {
                        (0..3)
                            .map(|k| sigma[k] * rot[(k, k)])
                            .fold(f64::MAX, f64::min)
                    })
                    .fold(f64::MIN, f64::max);
                assert!(
                    best <= 1e-6,
                    "refused ({value}) a pose with a labelling inside"
                );
            }
            Err(e) => panic!("{e}"),
        }
    }
    println!("served {served}, refused {refused} (no labelling in the workspace)");
    assert!(served > 1000 && refused > 100, "{served} {refused}");
}

#[test]
fn the_forward_kinematics_agrees_with_newton_raphson() {
    let mut rng = rng(82);
    let robot = Robot::default();
    let c5 = C5::new(robot).unwrap();
    for _ in 0..1000 {
        let s = random_state(&mut rng);
        let (q, _) = c5.inverse_kinematics(&s.pose).unwrap();
        // From a start a controller would have: the pose a little off.
        let mut start = s.pose;
        start.alpha += 0.01;
        start.center[2] -= 0.002;
        let (newton, iterations) =
            rc::forward_kinematics_newton(robot.half_spacing, &q, &start, 1e-13).unwrap();
        assert!(iterations <= 8, "{iterations}");
        let closed = c5.forward_kinematics(&q).unwrap();
        assert!(close_rel(&closed.to_array(), &newton.to_array(), 1e-12));
    }
}

/// A rotating motion of the actuators: `Q(t) = Q0 + A sin(ωt + φ)`, with its derivatives.
fn actuator_motion(t: f64) -> [[f64; 6]; 3] {
    let q0 = [0.01, -0.02, 0.015, 0.03, -0.01, 0.02];
    let amp = [0.03, -0.02, 0.025, 0.02, -0.03, 0.015];
    let w = [1.1, 1.7, 0.9, 2.3, 1.3, 0.7];
    let phase = [0.0, 0.4, 1.0, 2.0, 0.3, 1.5];
    let f = |k: usize, i: usize| {
        let (s, c) = (w[i] * t + phase[i]).sin_cos();
        [s, w[i] * c, -w[i] * w[i] * s][k] * amp[i] + if k == 0 { q0[i] } else { 0.0 }
    };
    [0, 1, 2].map(|k| std::array::from_fn(|i| f(k, i)))
}

fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

#[test]
fn the_twist_and_acceleration_are_the_derivatives_of_the_forward_kinematics() {
    // The consistent model: its J is the derivative of eq 16, so of the forward kinematics.
    let c5 = C5::new(Robot::default()).unwrap();
    let h = 1e-5;
    let placement = |t: f64| {
        let pose = c5.forward_kinematics(&actuator_motion(t)[0]).unwrap();
        (r::rotation(&pose), Vector3::from(pose.center))
    };
    let (mut worst_v, mut worst_a): (f64, f64) = (0.0, 0.0);
    for k in 0..200 {
        let t = 0.05 * k as f64;
        let [q, qd, qdd] = actuator_motion(t);
        let state = c5.joint_state(&q, &qd, &qdd).unwrap();
        let ((r_minus, c_minus), (r0, c0), (r_plus, c_plus)) =
            (placement(t - h), placement(t), placement(t + h));
        let omega = vee(&((r_plus - r_minus) / (2.0 * h) * r0.transpose()));
        let velocity = (c_plus - c_minus) / (2.0 * h);
        // A wider step for the second difference, whose rounding grows as 1/h².
        let h2 = 20.0 * h;
        let (c_before, c_after) = (placement(t - h2).1, placement(t + h2).1);
        let acceleration = (c_after - 2.0 * c0 + c_before) / (h2 * h2);
        let twist_fd = [omega.as_slice(), velocity.as_slice()].concat();
        worst_v = worst_v.max(rel_err(&state.twist.to_array(), &twist_fd, 1e-3));
        // ω̇ from the kernel's own ω at t ± h.
        let omega_at = |t: f64| {
            let [q, qd, qdd] = actuator_motion(t);
            Vector3::from(c5.joint_state(&q, &qd, &qdd).unwrap().twist.omega)
        };
        let omega_dot = (omega_at(t + h) - omega_at(t - h)) / (2.0 * h);
        let accel_fd = [omega_dot.as_slice(), acceleration.as_slice()].concat();
        worst_a = worst_a.max(rel_err(&state.accel.to_array(), &accel_fd, 1e-2));
    }
    println!("worst relative error: twist {worst_v:.1e}, acceleration {worst_a:.1e}");
    // docs/joint-space.md states 1.9e-10 and 1.7e-8: held at ten times.
    assert!(worst_v < 1.9e-9, "{worst_v}");
    assert!(worst_a < 1.7e-7, "{worst_a}");
}

#[test]
fn each_model_maps_the_actuators_motion_back_to_the_state_it_came_from() {
    for_each_case(83, |_, c5, s| {
        let model = c5.model();
        let [q, qd, qdd] = actuators(c5, s);
        let found = c5.joint_state(&q, &qd, &qdd).unwrap();
        assert!(close_rel(&found.pose.to_array(), &s.pose.to_array(), 1e-12));
        assert!(close_rel(
            &found.twist.to_array(),
            &s.twist.to_array(),
            1e-12
        ));
        assert!(
            close_rel(&found.accel.to_array(), &s.accel.to_array(), 1e-11),
            "{model}: {:?} vs {:?}",
            found.accel,
            s.accel
        );
    });
}

#[test]
fn the_inverse_dynamics_from_the_joints_is_the_task_space_one() {
    for_each_case(84, |n, c5, s| {
        let model = c5.model();
        let [q, qd, qdd] = actuators(c5, s);
        let joint = c5.inverse_dynamics_joint(&q, &qd, &qdd).unwrap();
        let task = c5.inverse_dynamics(s).unwrap();
        assert!(
            close_rel(&joint, &task, 1e-12),
            "{model}: {joint:?} vs {task:?}"
        );
        // Split as Γ = M_q Q̈ + c_q.
        let m = c5.joint_inertia(&q).unwrap();
        let c = c5.joint_bias(&q, &qd).unwrap();
        let split: Vec<f64> = (0..6)
            .map(|i| c[i] + (0..6).map(|k| m[i][k] * qdd[k]).sum::<f64>())
            .collect();
        assert!(close_rel(&split, &task, 1e-12), "{model}");
        // The folded kernels of the default robot.
        if n % 2 == 1 {
            let (folded, _) = c5.kernels().inverse_dynamics_joint(&q, &qd, &qdd);
            assert!(close_rel(&folded, &task, 1e-12));
        }
    });
}

#[test]
fn the_batch_joint_inverse_dynamics_equals_the_single_one_to_the_bit() {
    let mut rng = rng(85);
    let c5 = C5::new(random_robot(&mut rng)).unwrap();
    let samples: Vec<[[f64; 6]; 3]> = (0..1001)
        .map(|_| actuators(&c5, &random_state(&mut rng)))
        .collect();
    let many = c5.inverse_dynamics_joint_many(&samples).unwrap();
    for (sample, got) in samples.iter().zip(&many) {
        let [q, qd, qdd] = sample;
        assert_eq!(*got, c5.inverse_dynamics_joint(q, qd, qdd).unwrap());
    }
}

#[test]
fn the_joint_inertia_is_symmetric_positive_definite_and_gives_the_kinetic_energy() {
    let mut rng = rng(86);
    for n in 0..2000 {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let c5 = C5::new(robot).unwrap();
        let s = random_state(&mut rng);
        let [q, qd, _] = actuators(&c5, &s);
        let m = Matrix6::from_fn(|i, j| c5.joint_inertia(&q).unwrap()[i][j]);
        assert!((m - m.transpose()).amax() < 1e-12 * m.amax());
        assert!(m.cholesky().is_some(), "positive definite");
        // ½ Q̇ᵀ M_q Q̇ is the bodies' kinetic energy, written from their masses and velocities.
        let qd_v = Vector6::from(qd);
        let from_m = 0.5 * qd_v.dot(&(m * qd_v));
        let (kinetic, _) = consistent_energy(&robot, &s);
        assert!(
            (from_m - kinetic).abs() <= 1e-12 * kinetic.max(1e-3),
            "{from_m} vs {kinetic}"
        );
    }
}

#[test]
fn at_and_beyond_the_forward_singularity_the_error_is_typed_never_a_wrong_pose() {
    let c5 = C5::new(Robot::default()).unwrap();
    let l = c5.robot().half_spacing;
    // Q with pair ratios a, b, c (and the half-sums zero): 1 + abc is the forward term.
    let from_ratios = |a: f64, b: f64, c: f64| {
        let half = |x: f64| [-x * l, x * l];
        let [q1, q2] = half(a);
        let [q3, q4] = half(b);
        let [q5, q6] = half(c);
        [q1, q2, q3, q4, q5, q6]
    };
    // At it exactly (a = b = 1, c = -1) and beyond it: refused, with the term's value.
    for (c, want) in [(-1.0, 0.0), (-1.5, -0.5), (-3.0, -2.0)] {
        let q = from_ratios(1.0, 1.0, c);
        match c5.forward_kinematics(&q) {
            Err(Error::ForwardSingular { value }) => assert!((value - want).abs() < 1e-12),
            other => panic!("1 + abc = {want}: {other:?}"),
        }
        let zero = [0.0; 6];
        assert!(matches!(
            c5.inverse_dynamics_joint(&q, &zero, &zero),
            Err(Error::ForwardSingular { .. })
        ));
        assert!(matches!(
            c5.joint_state(&q, &zero, &zero),
            Err(Error::ForwardSingular { .. })
        ));
        assert!(matches!(
            c5.joint_inertia(&q),
            Err(Error::ForwardSingular { .. })
        ));
    }
    // Approaching it: every answer is a pose whose Q is the one given, or the typed error.
    let mut rng = rng(87);
    let (mut served, mut refused) = (0, 0);
    for _ in 0..100_000 {
        let a = rng.gen_range(-3.0..3.0);
        let b = rng.gen_range(-3.0..3.0);
        // 1 + abc within ±1e-6 of zero.
        let c = (-1.0 + rng.gen_range(-1e-6..1e-6)) / (a * b);
        let q = from_ratios(a, b, c);
        if q.iter().any(|x| !x.is_finite()) {
            continue;
        }
        match c5.forward_kinematics(&q) {
            Ok(pose) => {
                served += 1;
                let back = rc::lengths(l, &pose);
                assert!(back.iter().all(|x| x.is_finite()));
                assert!(close_rel(&back, &q, 1e-6), "{q:?} → {pose:?} → {back:?}");
            }
            Err(Error::ForwardSingular { value }) => {
                refused += 1;
                assert!(value < 1e-9);
            }
            // Where 1 + abc passes, a column of R may still be too short to divide by.
            Err(Error::Singular { value, .. }) => {
                refused += 1;
                assert!(value.abs() < 1e-9);
            }
            Err(e) => panic!("{e}"),
        }
    }
    assert!(served > 1000 && refused > 1000, "{served} {refused}");
    // Non-finite input: the input's error, not a pose.
    let mut q = [0.0; 6];
    q[3] = f64::NAN;
    assert_eq!(
        c5.forward_kinematics(&q),
        Err(Error::NonFinite {
            input: "q",
            index: 3
        })
    );
}

/// The workless terms on their own, which a power balance cannot see: with gravity off, the
/// joint-space bias `c(q, q̇) = Γ(q, q̇, q̈ = 0)` is the Coriolis and centrifugal force of the
/// inertia `M(q)`, `c_i = Σ_jk (∂M_ij/∂q_k - ½ ∂M_jk/∂q_i) q̇_j q̇_k` (its Christoffel symbols),
/// with `∂M/∂q` by central differences of `joint_inertia`. Both mechanisms, through the trait;
/// the C5 in the consistent model (the paper model is not a mechanism: no inertia has its bias).
#[test]
fn the_bias_is_the_christoffel_form_of_the_inertia() {
    use c5_runtime::mechanism::{robot, SpatialRobot};
    use c5_runtime::{Description, Model};
    let c5 = c5_runtime::Robot {
        gravity: [0.0; 3],
        ..c5_runtime::Robot::default()
    };
    let mut hexapod = c5_robot::GoughStewart::example();
    hexapod.gravity = [0.0; 3];
    // The paper model, whose bias is not its inertia's, must fail the same check: the check
    // can tell.
    // The robot, a pose, the actuators' rates, and whether it is a mechanism.
    type Case = (Box<dyn SpatialRobot>, [f64; 6], [f64; 6], bool);
    let cases: [Case; 3] = [
        (
            robot(Description::C5(c5), Model::Paper).unwrap(),
            [0.2, -0.15, 0.25, 0.01, -0.02, 0.015],
            [0.05, -0.08, 0.03, 0.07, -0.04, 0.06],
            false,
        ),
        (
            robot(Description::C5(c5), Model::Consistent).unwrap(),
            [0.2, -0.15, 0.25, 0.01, -0.02, 0.015],
            [0.05, -0.08, 0.03, 0.07, -0.04, 0.06],
            true,
        ),
        (
            robot(Description::GoughStewart(hexapod), Model::Consistent).unwrap(),
            [0.1, -0.08, 0.15, 0.02, -0.015, 0.44],
            [0.04, -0.06, 0.05, 0.03, -0.05, 0.02],
            true,
        ),
    ];
    for (robot, x, qd, mechanism) in cases {
        let pose = Pose::from_array(x);
        let q = robot
            .evaluate(&State {
                pose,
                ..State::default()
            })
            .unwrap()
            .q;
        let bias = robot
            .inverse_dynamics_joint(&q, &qd, &[0.0; 6], Some(&pose))
            .unwrap();
        let h = 1e-6;
        let d_m: Vec<[[f64; 6]; 6]> = (0..6)
            .map(|k| {
                let (mut up, mut down) = (q, q);
                up[k] += h;
                down[k] -= h;
                let (a, b) = (
                    robot.joint_inertia(&up, Some(&pose)).unwrap(),
                    robot.joint_inertia(&down, Some(&pose)).unwrap(),
                );
                std::array::from_fn(|i| std::array::from_fn(|j| (a[i][j] - b[i][j]) / (2.0 * h)))
            })
            .collect();
        let christoffel: [f64; 6] = std::array::from_fn(|i| {
            let mut c = 0.0;
            for j in 0..6 {
                for k in 0..6 {
                    c += (d_m[k][i][j] - 0.5 * d_m[i][j][k]) * qd[j] * qd[k];
                }
            }
            c
        });
        let scale = bias.iter().fold(0.0f64, |m, b| m.max(b.abs()));
        let off = (0..6).fold(0.0f64, |m, i| m.max((bias[i] - christoffel[i]).abs()));
        let name = format!("{} ({})", robot.mechanism(), robot.model_name());
        println!(
            "{name}: bias {scale:.3e} N, Christoffel form off by {:.1e} relative",
            off / scale
        );
        assert!(scale > 1e-3, "{name}: the test needs a bias to compare");
        if mechanism {
            assert!(off < 1e-6 * scale, "{name}: {bias:?} vs {christoffel:?}");
        } else {
            assert!(off > 1e-2 * scale, "{name}: {bias:?} vs {christoffel:?}");
        }
    }
}

/// A state of the default robot with `β = π/2 - s`, so that `|r11|` and `|r33|` are about `s`.
fn near_singular(s: f64) -> State {
    let mut state = State::default();
    state.pose.alpha = 0.1;
    state.pose.beta = std::f64::consts::FRAC_PI_2 - s;
    state.pose.gamma = -0.2;
    state.twist.omega = [0.3, -0.2, 0.1];
    state.accel.linear = [0.5, -1.0, 0.2];
    state
}

/// Where `1e-8` cannot be met the joint-space calls refuse, each at its own bound (the growth
/// of its error against the 50-digit reference, `python/tests/test_accuracy.py`), and serve
/// beyond it.
#[test]
fn near_eq16s_singularities_the_joint_space_refuses_where_its_bound_cannot_be_met() {
    use c5_runtime::{JOINT_DYNAMICS_TOLERANCE, JOINT_STATE_TOLERANCE};
    let c5 = C5::new(Robot::default()).unwrap();
    fn ill<T>(result: Result<T, Error>, what: &str, bound: f64) {
        match result {
            Err(Error::IllConditioned {
                what: w, bound: b, ..
            }) => assert!(w == what && b == bound, "{w} {b}"),
            other => panic!("{what}: expected a refusal, got {:?}", other.map(|_| ())),
        }
    }
    for s in [3e-4, 1e-5, 1e-6] {
        let [q, qd, qdd] = actuators(&c5, &near_singular(s));
        let motion = "platform motion from the actuators";
        ill(c5.joint_state(&q, &qd, &qdd), motion, JOINT_STATE_TOLERANCE);
        ill(
            c5.joint_state(&q, &[0.0; 6], &qdd),
            motion,
            JOINT_STATE_TOLERANCE,
        );
        // At rest the motion is zero exactly, and the pose is served.
        let rest = c5.joint_state(&q, &[0.0; 6], &[0.0; 6]).unwrap();
        assert_eq!(rest.twist.to_array(), [0.0; 6]);
        assert_eq!(rest.accel.to_array(), [0.0; 6]);
        assert!(c5.inverse_dynamics_joint(&q, &qd, &qdd).is_ok());
        assert!(c5.joint_inertia(&q).is_ok());
    }
    for s in [3e-8, 1e-8] {
        let [q, qd, qdd] = actuators(&c5, &near_singular(s));
        let dynamics = "joint-space dynamics";
        ill(
            c5.inverse_dynamics_joint(&q, &qd, &qdd),
            dynamics,
            JOINT_DYNAMICS_TOLERANCE,
        );
        ill(c5.joint_inertia(&q), dynamics, JOINT_DYNAMICS_TOLERANCE);
        ill(c5.joint_bias(&q, &qd), dynamics, JOINT_DYNAMICS_TOLERANCE);
        let batch = c5.inverse_dynamics_joint_many(&[[q, qd, qdd]; 5]);
        assert!(matches!(batch, Err((0, Error::IllConditioned { .. }))));
        assert!(c5.forward_kinematics(&q).is_ok());
    }
    let [q, qd, qdd] = actuators(&c5, &near_singular(2e-3));
    assert!(c5.joint_state(&q, &qd, &qdd).is_ok());
}
