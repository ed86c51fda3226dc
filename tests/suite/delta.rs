//! The Delta through the runtime, against mechanics: the arm angles the description's closed
//! form, `J⁻¹` and `q̈` their derivatives (central differences), `J⁻¹ J = I`, the forward
//! kinematics and dynamics undoing the inverse ones, the motors' motion giving back the
//! platform's, the holding torques the statics by virtual work on the potential energy of
//! every body placed by the description alone, and `M_x`, `M_q` their kinetic energy. Pinocchio's closed-loop dynamics on the
//! exported robot checks the same kernels from Python (python/tests/test_delta.py).

use crate::support;

use c5_robot::Delta as Description;
use c5_runtime::Translation;
use c5_runtime::{Delta, Error};
use nalgebra::{Matrix3, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use support::{rel_err, rng};

/// The example with every joint moved by millimetres, other masses, tilted gravity, encoder
/// offsets: a robot no generated file folds in.
pub(crate) fn jittered(r: &mut ChaCha8Rng) -> Description {
    let mut robot = Description::example();
    robot.gravity = [0.3, -0.2, -9.8];
    robot.platform.mass = 0.9;
    for arm in &mut robot.arms {
        for x in arm.base.iter_mut().chain(&mut arm.platform) {
            *x += r.gen_range(-0.004..0.004);
        }
        arm.axis[2] += r.gen_range(-0.05..0.05);
        arm.crank.mass *= r.gen_range(0.8..1.2);
        arm.rod.mass *= r.gen_range(0.8..1.2);
        arm.encoder_offset = r.gen_range(-0.1..0.1);
    }
    robot.validate().expect("a valid Delta");
    robot
}

fn robots() -> Vec<Delta> {
    let mut r = rng(43);
    [Description::example(), jittered(&mut r)]
        .into_iter()
        .map(|d| Delta::new(d).unwrap())
        .collect()
}

/// A state within 5 cm of home.
fn near_home(r: &mut ChaCha8Rng, robot: &Delta) -> Translation {
    let home = robot.home();
    Translation {
        position: core::array::from_fn(|k| home[k] + r.gen_range(-0.05..0.05)),
        velocity: core::array::from_fn(|_| r.gen_range(-0.5..0.5)),
        acceleration: core::array::from_fn(|_| r.gen_range(-5.0..5.0)),
    }
}

/// The state at time `t` of `C + t v + t² a/2`.
fn along(s: &Translation, t: f64) -> Translation {
    Translation {
        position: core::array::from_fn(|k| {
            s.position[k] + t * s.velocity[k] + 0.5 * t * t * s.acceleration[k]
        }),
        velocity: core::array::from_fn(|k| s.velocity[k] + t * s.acceleration[k]),
        acceleration: s.acceleration,
    }
}

#[test]
fn the_arm_angles_are_the_descriptions_and_the_jacobians_invert() {
    for robot in robots() {
        let mut r = rng(3);
        for _ in 0..50 {
            let s = near_home(&mut r, &robot);
            let q = robot.inverse_kinematics(&s.position).unwrap();
            let want = robot.robot().actuator_angles(&s.position).unwrap();
            assert!(rel_err(&q, &want, 1.0) < 1e-14, "{q:?} vs {want:?}");
            let jinv = Matrix3::from(robot.inverse_jacobian(&s.position).unwrap()).transpose();
            let jac = Matrix3::from(robot.jacobian(&s.position).unwrap()).transpose();
            let off = (jinv * jac - Matrix3::identity()).abs().max();
            assert!(off < 1e-12, "J⁻¹ J - I: {off:e}");
        }
    }
}

/// `q̇ = J⁻¹ v_C` is the rate of the arm angles, and `q̈` the rate of `q̇`, along a motion.
#[test]
fn the_rates_and_accelerations_are_the_angles_derivatives() {
    let h = 1e-6;
    for robot in robots() {
        let mut r = rng(4);
        for _ in 0..20 {
            let s = near_home(&mut r, &robot);
            let q_at = |t: f64| robot.inverse_kinematics(&along(&s, t).position).unwrap();
            let (up, down) = (q_at(h), q_at(-h));
            let fd: [f64; 3] = core::array::from_fn(|i| (up[i] - down[i]) / (2.0 * h));
            let qd = robot.joint_velocities(&s.position, &s.velocity).unwrap();
            assert!(rel_err(&qd, &fd, 1.0) < 1e-8, "{qd:?} vs {fd:?}");
            let qd_at = |t: f64| {
                let s = along(&s, t);
                robot.joint_velocities(&s.position, &s.velocity).unwrap()
            };
            let (up, down) = (qd_at(h), qd_at(-h));
            let fd: [f64; 3] = core::array::from_fn(|i| (up[i] - down[i]) / (2.0 * h));
            let qdd = robot.joint_accelerations(&s).unwrap();
            assert!(rel_err(&qdd, &fd, 1.0) < 1e-7, "{qdd:?} vs {fd:?}");
        }
    }
}

/// The forward kinematics returns the position of the inverse's angles, the forward dynamics
/// the acceleration the inverse dynamics was given, the motors' motion the platform's.
#[test]
fn the_forward_models_undo_the_inverse_ones() {
    for robot in robots() {
        let mut r = rng(5);
        for _ in 0..30 {
            let s = near_home(&mut r, &robot);
            let q = robot.inverse_kinematics(&s.position).unwrap();
            let found = robot.forward_kinematics(&q).unwrap();
            assert!(rel_err(&found, &s.position, 1.0) < 1e-13, "{found:?}");
            let gamma = robot.inverse_dynamics(&s).unwrap();
            let accel = robot
                .forward_dynamics(&s.position, &s.velocity, &gamma)
                .unwrap();
            assert!(rel_err(&accel, &s.acceleration, 1.0) < 1e-11, "{accel:?}");
            let qd = robot.joint_velocities(&s.position, &s.velocity).unwrap();
            let qdd = robot.joint_accelerations(&s).unwrap();
            let joint = robot.joint_state(&q, &qd, &qdd, None).unwrap();
            assert!(rel_err(&joint.velocity, &s.velocity, 1.0) < 1e-12);
            assert!(rel_err(&joint.acceleration, &s.acceleration, 1.0) < 1e-10);
        }
    }
}

/// The potential energy of every body at the platform position `c`, placed by the
/// description's own closed forms (crank angle, elbow, the rods' direction).
fn potential(robot: &Description, c: &[f64; 3]) -> f64 {
    let g = Vector3::from(robot.gravity);
    let at = |p: Vector3<f64>, mass: f64| -mass * g.dot(&p);
    let centre = Vector3::from(*c);
    let mut u = at(
        centre + Vector3::from(robot.platform.centre_of_mass),
        robot.platform.mass,
    );
    for arm in &robot.arms {
        let ball = centre + Vector3::from(arm.platform);
        let theta = arm.crank_angle(ball.into()).unwrap();
        let (r, _, _) = arm.axes();
        let base = Vector3::from(arm.base);
        let elbow = Vector3::from(arm.elbow(theta));
        let along = (elbow - base) / arm.crank.length;
        u += at(base + along * arm.crank.com, arm.crank.mass);
        let rod = (ball - elbow) / arm.rod.length;
        let half = 0.5 * arm.rod.separation.unwrap();
        for offset in [half, -half] {
            let com = elbow + Vector3::from(r) * offset + rod * arm.rod.com;
            u += at(com, arm.rod.mass);
        }
    }
    u
}

/// At rest the torques hold the robot: `Γ = (∂θ/∂C)⁻ᵀ ∂U/∂C`, both by central differences of
/// the description's closed forms.
#[test]
fn the_holding_torques_are_the_statics_by_virtual_work() {
    let h = 1e-6;
    for robot in robots() {
        let mut r = rng(6);
        for _ in 0..10 {
            let mut s = near_home(&mut r, &robot);
            s.velocity = [0.0; 3];
            s.acceleration = [0.0; 3];
            let description = robot.robot();
            let mut jinv = Matrix3::zeros();
            let mut grad = Vector3::zeros();
            for j in 0..3 {
                let (mut up, mut down) = (s.position, s.position);
                up[j] += h;
                down[j] -= h;
                let (qu, qd) = (
                    description.actuator_angles(&up).unwrap(),
                    description.actuator_angles(&down).unwrap(),
                );
                for i in 0..3 {
                    jinv[(i, j)] = (qu[i] - qd[i]) / (2.0 * h);
                }
                grad[j] = (potential(description, &up) - potential(description, &down)) / (2.0 * h);
            }
            let want = jinv.transpose().lu().solve(&grad).unwrap();
            let gamma = robot.inverse_dynamics(&s).unwrap();
            assert!(
                rel_err(&gamma, want.as_slice(), 1.0) < 1e-7,
                "{gamma:?} vs {want}"
            );
        }
    }
}

/// A body placed at a platform position: its centre of mass, its frame (columns its axes, base
/// frame), its mass and its principal moments about the centre of mass in that frame.
struct Placed {
    com: Vector3<f64>,
    frame: Matrix3<f64>,
    mass: f64,
    inertia: [f64; 3],
}

/// Every body at the platform position `c`, placed by the description's closed forms: the
/// platform (which does not turn), each crank (`x''` along it, `z'' = r`) and each rod of each
/// parallelogram (`z' = u`, `y' ∥ u × r`).
fn placed(robot: &Description, c: &[f64; 3]) -> Vec<Placed> {
    let centre = Vector3::from(*c);
    let frame = |x: Vector3<f64>, z: Vector3<f64>| {
        let y = z.cross(&x).normalize();
        Matrix3::from_columns(&[y.cross(&z), y, z])
    };
    let mut bodies = vec![Placed {
        com: centre + Vector3::from(robot.platform.centre_of_mass),
        frame: Matrix3::identity(),
        mass: robot.platform.mass,
        inertia: [0.0; 3],
    }];
    for arm in &robot.arms {
        let ball = centre + Vector3::from(arm.platform);
        let elbow = Vector3::from(arm.elbow(arm.crank_angle(ball.into()).unwrap()));
        let (r, _, _) = arm.axes();
        let (r, base) = (Vector3::from(r), Vector3::from(arm.base));
        let along = (elbow - base) / arm.crank.length;
        bodies.push(Placed {
            com: base + along * arm.crank.com,
            frame: frame(along, r),
            mass: arm.crank.mass,
            inertia: arm.crank.inertia,
        });
        let u = (ball - elbow) / arm.rod.length;
        let half = 0.5 * arm.rod.separation.unwrap();
        for offset in [half, -half] {
            bodies.push(Placed {
                com: elbow + r * offset + u * arm.rod.com,
                frame: frame(r.cross(&u), u),
                mass: arm.rod.mass,
                inertia: arm.rod.inertia,
            });
        }
    }
    bodies
}

/// The bodies' kinetic energy at the state `s`, each body's velocity and angular velocity
/// (`Rᵀ Ṙ`, in its frame) by central differences of its placement along the motion.
fn kinetic_energy(robot: &Description, s: &Translation) -> f64 {
    let h = 1e-6;
    let (before, after) = (
        placed(robot, &along(s, -h).position),
        placed(robot, &along(s, h).position),
    );
    let here = placed(robot, &s.position);
    here.iter()
        .zip(before.iter().zip(&after))
        .map(|(body, (b, a))| {
            let v = (a.com - b.com) / (2.0 * h);
            let spin = body.frame.transpose() * (a.frame - b.frame) / (2.0 * h);
            let w = [spin[(2, 1)], spin[(0, 2)], spin[(1, 0)]];
            let rotation: f64 = (0..3).map(|k| body.inertia[k] * w[k] * w[k]).sum();
            0.5 * (body.mass * v.norm_squared() + rotation)
        })
        .sum()
}

/// `½ vᵀ M_x v` and `½ q̇ᵀ M_q q̇` are the kinetic energy of every body placed by the
/// description alone, `M_x` and `M_q` symmetric positive definite; the forces are
/// `Jᵀ (M_x a_C + h)` and `M_q q̈ + c_q`, each term from its own kernel.
#[test]
fn the_task_and_joint_inertia_give_the_bodies_kinetic_energy() {
    let matrix = |m: [[f64; 3]; 3]| Matrix3::from_fn(|i, j| m[i][j]);
    for robot in robots() {
        let mut r = rng(8);
        for _ in 0..10 {
            let s = near_home(&mut r, &robot);
            let m_x = matrix(robot.task_inertia(&s.position).unwrap());
            assert_eq!(m_x, m_x.transpose());
            assert!(m_x.cholesky().is_some(), "positive definite");
            let energy = kinetic_energy(robot.robot(), &s);
            let v = Vector3::from(s.velocity);
            assert!((0.5 * v.dot(&(m_x * v)) - energy).abs() < 1e-9 * energy);
            let q = robot.inverse_kinematics(&s.position).unwrap();
            let qd = Vector3::from(robot.joint_velocities(&s.position, &s.velocity).unwrap());
            let m_q = matrix(robot.joint_inertia(&q, None).unwrap());
            assert!((0.5 * qd.dot(&(m_q * qd)) - energy).abs() < 1e-9 * energy);

            let gamma = robot.inverse_dynamics(&s).unwrap();
            let h = Vector3::from(robot.task_bias(&s.position, &s.velocity).unwrap());
            let jac = matrix(robot.jacobian(&s.position).unwrap());
            let task = jac.transpose() * (m_x * Vector3::from(s.acceleration) + h);
            assert!(
                rel_err(&gamma, task.as_slice(), 1.0) < 1e-12,
                "{gamma:?} {task}"
            );
            let qdd = Vector3::from(robot.joint_accelerations(&s).unwrap());
            let c_q = robot.joint_bias(&q, qd.as_ref(), None).unwrap();
            let joint = m_q * qdd + Vector3::from(c_q);
            assert!(
                rel_err(&gamma, joint.as_slice(), 1.0) < 1e-10,
                "{gamma:?} {joint}"
            );
        }
    }
}

/// A platform beyond an arm's reach, angles whose spheres miss, non-finite inputs: typed
/// errors naming the term.
#[test]
fn bad_states_are_refused() {
    let robot = Delta::new(Description::example()).unwrap();
    let mut low = robot.home();
    low[2] -= 1.5;
    match robot.inverse_kinematics(&low) {
        Err(Error::Singularity { term, value, .. }) => {
            assert!(term.contains("beyond the reach of arm 1"), "{term}");
            assert!(value < 0.0);
        }
        other => panic!("{other:?}"),
    }
    // Rods of 0.3 m from upper arms held straight out (0.417 m from the axis): the arms'
    // spheres cannot meet.
    let mut short = Description::example();
    short.arms.iter_mut().for_each(|a| a.rod.length = 0.3);
    let short = Delta::new(short).unwrap();
    match short.forward_kinematics(&[0.0; 3]) {
        Err(Error::Singularity { term, value, .. }) => {
            assert!(term.contains("spheres do not meet"), "{term}");
            assert!(value < 0.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        robot.forward_dynamics(&robot.home(), &[0.0; 3], &[f64::NAN, 0.0, 0.0]),
        Err(Error::NonFinite { input: "gamma", .. })
    ));
}

/// The Delta's inverse dynamics four states a call: each lane of the batch kernel is the
/// single-state kernel's result to the bit, and through the runtime every state gets what the
/// single-state call gives it.
#[test]
fn the_batch_inverse_dynamics_is_the_single_states_to_the_bit() {
    use c5_generated::f64::delta as kernels;
    use c5_runtime::ParallelRobot;
    let robot = Delta::new(Description::example()).unwrap();
    let params = robot.parameters();
    let mut r = rng(29);
    let mut states: Vec<Translation> = (0..10).map(|_| near_home(&mut r, &robot)).collect();
    for four in states.chunks_exact(4) {
        let column = |j: usize| {
            let part = |s: &Translation| [s.position, s.velocity, s.acceleration][j];
            std::array::from_fn(|e| std::array::from_fn(|l| part(&four[l])[e]))
        };
        let (gamma, guard) =
            kernels::inverse_dynamics_params_x4(&column(0), &column(1), &column(2), params);
        for (l, s) in four.iter().enumerate() {
            let (single, single_guard) =
                kernels::inverse_dynamics_params(&s.position, &s.velocity, &s.acceleration, params);
            for e in 0..3 {
                assert_eq!(gamma[e][l].to_bits(), single[e].to_bits(), "lane {l}, Γ{e}");
            }
            for (e, term) in single_guard.iter().enumerate() {
                assert_eq!(guard[e][l].to_bits(), term.to_bits(), "lane {l}, term {e}");
            }
        }
    }
    // A non-finite state in the second group, one beyond the arms' reach in the first.
    states[5].velocity[2] = f64::INFINITY;
    states[2].position[2] -= 2.0;
    assert!(robot.inverse_dynamics(&states[2]).is_err());
    let mut served = Vec::new();
    ParallelRobot::inverse_dynamics_each(&robot, states.len(), &|k| states[k], &mut |k, g| {
        served.push((k, g))
    });
    assert_eq!(served.len(), states.len());
    for (k, result) in served {
        match (result, robot.inverse_dynamics(&states[k])) {
            (Ok(batch), Ok(single)) => {
                assert_eq!(batch.map(f64::to_bits), single.map(f64::to_bits))
            }
            (Err(batch), Err(single)) => assert_eq!(batch.to_string(), single.to_string()),
            (batch, single) => panic!("state {k}: {batch:?} against {single:?}"),
        }
    }
}

/// The Delta's derivative kernels against central differences of its inverse and forward
/// dynamics (other kernels, differentiated by nothing), on the example and a jittered robot:
/// every Jacobian to 1e-6 of its largest entry (the differences' own error is about 1e-8);
/// `∂Γ/∂a_C · ∂a_C/∂Γ = I`; and the values the primal kernels' to 1e-12.
#[test]
fn the_derivatives_are_the_dynamics_central_differences() {
    type Columns = [[f64; 3]; 3];
    /// `∂f/∂x_j` by central differences, as columns.
    fn columns(f: &dyn Fn(&[f64; 3]) -> [f64; 3], x: &[f64; 3], h: f64) -> Columns {
        core::array::from_fn(|j| {
            let (mut up, mut down) = (*x, *x);
            up[j] += h;
            down[j] -= h;
            let (fu, fd) = (f(&up), f(&down));
            core::array::from_fn(|i| (fu[i] - fd[i]) / (2.0 * h))
        })
    }
    /// The largest difference between a row-major Jacobian and one given by columns, relative
    /// to the Jacobian's largest entry.
    fn gap(exact: &[[f64; 3]; 3], numeric: &Columns) -> f64 {
        let largest = exact.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = (0..9)
            .map(|ij| (exact[ij / 3][ij % 3] - numeric[ij % 3][ij / 3]).abs())
            .fold(0.0, f64::max);
        worst / largest.max(1e-300)
    }
    for robot in robots() {
        let mut r = rng(61);
        for _ in 0..20 {
            let s = near_home(&mut r, &robot);
            let d = robot.inverse_dynamics_derivatives(&s).unwrap();
            let gamma = robot.inverse_dynamics(&s).unwrap();
            assert!(rel_err(&d.gamma, &gamma, 1.0) < 1e-12);
            let id = |m: Translation| robot.inverse_dynamics(&m).unwrap();
            let at_position = |x: &[f64; 3]| id(Translation { position: *x, ..s });
            let at_velocity = |x: &[f64; 3]| id(Translation { velocity: *x, ..s });
            let at_accel = |x: &[f64; 3]| {
                id(Translation {
                    acceleration: *x,
                    ..s
                })
            };
            let f = robot
                .forward_dynamics_derivatives(&s.position, &s.velocity, &gamma)
                .unwrap();
            assert!(rel_err(&f.accel, &s.acceleration, 1.0) < 1e-9);
            let fd =
                |p: [f64; 3], v: [f64; 3], g: [f64; 3]| robot.forward_dynamics(&p, &v, &g).unwrap();
            for (exact, numeric, what) in [
                (d.d_pose, columns(&at_position, &s.position, 1e-6), "∂Γ/∂C"),
                (
                    d.d_twist,
                    columns(&at_velocity, &s.velocity, 1e-5),
                    "∂Γ/∂v_C",
                ),
                (
                    d.d_accel,
                    columns(&at_accel, &s.acceleration, 1e-4),
                    "∂Γ/∂a_C",
                ),
                (
                    f.d_pose,
                    columns(&|x| fd(*x, s.velocity, gamma), &s.position, 1e-6),
                    "∂a_C/∂C",
                ),
                (
                    f.d_twist,
                    columns(&|x| fd(s.position, *x, gamma), &s.velocity, 1e-5),
                    "∂a_C/∂v_C",
                ),
                (
                    f.d_gamma,
                    columns(&|x| fd(s.position, s.velocity, *x), &gamma, 1e-3),
                    "∂a_C/∂Γ",
                ),
            ] {
                let e = gap(&exact, &numeric);
                assert!(e < 1e-6, "{what}: {e:e}");
            }
            let product =
                Matrix3::from(d.d_accel).transpose() * Matrix3::from(f.d_gamma).transpose();
            let off = (product - Matrix3::identity()).abs().max();
            assert!(off < 1e-10, "∂Γ/∂a_C ∂a_C/∂Γ - I: {off:e}");
        }
    }
}
