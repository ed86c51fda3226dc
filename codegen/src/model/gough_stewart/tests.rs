use super::*;
use crate::model::Mechanism;

fn compiled(kernel: Kernel) -> crate::Program {
    crate::model::kernels::compiled(&Mechanism::gough_stewart(&GoughStewart::example()), kernel)
}

/// The Newton step cancels the residual to first order (`legged::newton::check_step`).
#[test]
fn the_newton_step_cancels_the_residual_to_first_order() {
    let (ik, step) = (
        compiled(Kernel::InverseKinematics),
        compiled(Kernel::ForwardKinematicsStep),
    );
    let home = GoughStewart::example().home();
    let pose: Vec<f64> = home
        .iter()
        .zip([0.1, -0.05, 0.2, 0.01, 0.02, -0.03])
        .map(|(h, d)| h + d)
        .collect();
    crate::model::legged::newton::check_step(&ik, &step, &pose);
}

/// Every singularity term is in `(0, 1]` at home: the U joints' sines, and the pivots over
/// their diagonal entries.
#[test]
fn the_singularity_terms_are_sines_and_ratios() {
    let terms = compiled(Kernel::SingularityTerms).eval(&GoughStewart::example().home());
    assert_eq!(terms.len(), 12);
    assert!(
        terms.iter().all(|&t| t > 0.0 && t <= 1.0 + 1e-15),
        "{terms:?}"
    );
}
