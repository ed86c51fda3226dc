use super::*;
use crate::model::Mechanism;

fn compiled(kernel: Kernel) -> crate::Program {
    crate::model::kernels::compiled(&Mechanism::delta(&Delta::example()), kernel)
}

fn near_home(offsets: [f64; 3]) -> Vec<f64> {
    let home = Delta::example().home().unwrap();
    home.iter().zip(offsets).map(|(h, d)| h + d).collect()
}

const OFFSETS: [[f64; 3]; 3] = [[0.0; 3], [0.04, -0.03, 0.05], [-0.06, 0.05, -0.04]];

/// The generated arm angles are the description's closed form (`atan2` and `acos`, which the
/// kernels do not call).
#[test]
fn the_arm_angles_are_the_descriptions() {
    let ik = compiled(Kernel::InverseKinematics);
    let robot = Delta::example();
    for offsets in OFFSETS {
        let c = near_home(offsets);
        let want = robot.actuator_angles(&[c[0], c[1], c[2]]).unwrap();
        let got = ik.eval(&c);
        for i in 0..3 {
            assert!(
                (got[i] - want[i]).abs() < 1e-14,
                "{i}: {} vs {}",
                got[i],
                want[i]
            );
        }
    }
}

/// `J⁻¹` is the derivative of the angles (central differences), and `q̈` their second time
/// derivative along `C(t) = C + v t + a t²/2` (second central differences).
#[test]
fn the_rates_and_accelerations_are_the_angles_derivatives() {
    let (ik, jinv, qdd) = (
        compiled(Kernel::InverseKinematics),
        compiled(Kernel::InverseJacobianPose),
        compiled(Kernel::JointAccelerations),
    );
    let (v, a) = ([0.3, -0.2, 0.4], [2.0, 1.0, -3.0]);
    for offsets in OFFSETS {
        let c = near_home(offsets);
        let m = jinv.eval(&c);
        let h = 1e-6;
        for j in 0..3 {
            let (mut up, mut down) = (c.clone(), c.clone());
            up[j] += h;
            down[j] -= h;
            let (qu, qd) = (ik.eval(&up), ik.eval(&down));
            for i in 0..3 {
                let fd = (qu[i] - qd[i]) / (2.0 * h);
                assert!((fd - m[3 * i + j]).abs() < 1e-7, "∂q{i}/∂c{j}");
            }
        }
        let at = |t: f64| -> Vec<f64> {
            (0..3)
                .map(|k| c[k] + v[k] * t + 0.5 * a[k] * t * t)
                .collect()
        };
        let h = 1e-4;
        let (before, now, after) = (ik.eval(&at(-h)), ik.eval(&at(0.0)), ik.eval(&at(h)));
        let got = qdd.eval(&[&c[..], &v, &a].concat());
        for i in 0..3 {
            let fd = (after[i] - 2.0 * now[i] + before[i]) / (h * h);
            assert!(
                (fd - got[i]).abs() < 1e-5 * got[i].abs().max(1.0),
                "q̈{i}: {} vs {fd}",
                got[i]
            );
        }
    }
}

/// Where the arms cannot reach (the platform far below), the reach terms are negative.
#[test]
fn the_reach_terms_go_negative_beyond_reach() {
    let terms = compiled(Kernel::SingularityTerms);
    let home = near_home([0.0; 3]);
    let inside = terms.eval(&home);
    assert!(inside.iter().all(|&t| t > 1e-3), "{inside:?}");
    let out = terms.eval(&[home[0], home[1], home[2] - 1.5]);
    assert!(out[3..6].iter().all(|&t| t < 0.0), "{out:?}");
}

/// `Y π` is the inverse dynamics with the motors' friction, and the base regressor carries the
/// same forces with the base parameters `β = B π`, at states about home.
#[test]
fn the_regressors_carry_the_inverse_dynamics_and_friction() {
    use crate::model::regressor::Identification;
    use crate::numeric::Lcg;
    let robot = Delta::example();
    let mechanism = Mechanism::delta(&robot);
    let identification = Identification::compile(&mechanism).unwrap();
    let [(_, full), (_, reduced)] = identification.pairs()[..] else {
        unreachable!("two kernels")
    };
    let id = compiled(Kernel::InverseDynamics);
    let base = &identification.base;
    let friction = [(3.0, 0.4), (2.5, -0.2), (1.5, 0.3)];
    let mut pi = robot.standard_inertial_parameters();
    pi.extend(friction.map(|f| f.0));
    pi.extend(friction.map(|f| f.1));
    let width = pi.len();
    assert_eq!(width, base.names.len());
    let beta: Vec<f64> = base
        .groups
        .iter()
        .map(|g| g.iter().map(|&(k, c)| c * pi[k]).sum())
        .collect();
    let nb = beta.len();
    assert!(nb < width, "{nb} base parameters of {width}");
    let geometry = &robot.kernel_parameters()[..GEOMETRY_PARAMETERS];
    let mut rng = Lcg::new(5);
    for offsets in OFFSETS {
        let mut state = near_home(offsets);
        state.extend(rng.vector(&[0.5; 3]));
        state.extend(rng.vector(&[3.0; 3]));
        let gamma = id.eval(&state);
        let qd = compiled(Kernel::JointVelocities).eval(&state[..6]);
        state.extend(geometry);
        let (y, yb) = (full.program.eval(&state), reduced.program.eval(&state));
        for i in 0..3 {
            let want = gamma[i] + friction[i].0 * qd[i] + friction[i].1 * qd[i].signum();
            let by_standard: f64 = (0..width).map(|j| y[i * width + j] * pi[j]).sum();
            let by_base: f64 = (0..nb).map(|j| yb[i * nb + j] * beta[j]).sum();
            for got in [by_standard, by_base] {
                assert!(
                    (got - want).abs() < 1e-10 * want.abs().max(1.0),
                    "arm {i}: {got} vs {want}"
                );
            }
        }
    }
}
