use super::*;
use crate::model::Mechanism;

fn compiled(kernel: Kernel) -> crate::Program {
    crate::model::kernels::compiled(&Mechanism::gough_stewart(&GoughStewart::example()), kernel)
}

/// The Newton step's Jacobian is the derivative of its residual, and its residual is zero at
/// the pose of the positions given.
#[test]
fn the_newton_step_is_the_residuals_derivative() {
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
    let q = ik.eval(&pose)[..6].to_vec();
    let at = |x: &[f64]| step.eval(&[x, &q[..]].concat());
    let out = at(&pose);
    assert!(out[..6].iter().all(|r| r.abs() < 1e-15), "{:?}", &out[..6]);
    for j in 0..6 {
        let h = 1e-6;
        let (mut up, mut down) = (pose.clone(), pose.clone());
        up[j] += h;
        down[j] -= h;
        let (a, b) = (at(&up), at(&down));
        for i in 0..6 {
            // The residual falls as q(X) rises.
            let fd = -(a[i] - b[i]) / (2.0 * h);
            let exact = out[6 + 6 * i + j];
            assert!((fd - exact).abs() < 1e-8, "∂q{i}/∂x{j}: {exact} vs {fd}");
        }
    }
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
