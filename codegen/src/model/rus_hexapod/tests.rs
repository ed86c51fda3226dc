use super::*;
use crate::model::Mechanism;

fn compiled(kernel: Kernel) -> crate::Program {
    crate::model::kernels::compiled(&Mechanism::rus_hexapod(&RusHexapod::example()), kernel)
}

fn near_home(offsets: [f64; 6]) -> Vec<f64> {
    RusHexapod::example()
        .home()
        .unwrap()
        .iter()
        .zip(offsets)
        .map(|(h, d)| h + d)
        .collect()
}

/// The generated crank angles are the description's closed form (`atan2` and `acos`, which
/// the kernels do not call) at poses around home.
#[test]
fn the_crank_angles_are_the_descriptions() {
    let ik = compiled(Kernel::InverseKinematics);
    let robot = RusHexapod::example();
    for offsets in [
        [0.0; 6],
        [0.1, -0.05, 0.2, 0.01, 0.02, -0.03],
        [-0.12, 0.08, -0.3, -0.02, 0.01, 0.04],
    ] {
        let pose = near_home(offsets);
        let want = robot
            .actuator_angles(&pose.clone().try_into().unwrap())
            .unwrap();
        let got = ik.eval(&pose);
        for i in 0..6 {
            assert!(
                (got[i] - want[i]).abs() < 1e-14,
                "{i}: {} vs {}",
                got[i],
                want[i]
            );
        }
    }
}

/// The Newton step cancels the residual to first order (`legged::newton::check_step`).
#[test]
fn the_newton_step_cancels_the_residual_to_first_order() {
    let (ik, step) = (
        compiled(Kernel::InverseKinematics),
        compiled(Kernel::ForwardKinematicsStep),
    );
    let pose = near_home([0.1, -0.05, 0.2, 0.01, 0.02, -0.03]);
    crate::model::legged::newton::check_step(&ik, &step, &pose);
}

/// At home every U joint's sine and every crank's reach term is in `(0, 1]`, and the pivots
/// over their diagonal entries too.
#[test]
fn the_singularity_terms_are_sines_and_ratios() {
    let terms = compiled(Kernel::SingularityTerms).eval(&near_home([0.0; 6]));
    assert_eq!(terms.len(), 18);
    assert!(
        terms.iter().all(|&t| t > 0.0 && t <= 1.0 + 1e-15),
        "{terms:?}"
    );
}

/// Beyond a crank's reach its term is negative: the platform lifted out of the legs' reach.
#[test]
fn a_ball_out_of_reach_has_a_negative_term() {
    let terms = compiled(Kernel::SingularityTerms).eval(&near_home([0.0, 0.0, 0.0, 0.0, 0.0, 0.2]));
    assert!(terms[6..12].iter().all(|&t| t < 0.0), "{terms:?}");
}
