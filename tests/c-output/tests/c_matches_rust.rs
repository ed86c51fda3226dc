//! Every kernel of the C output, compiled with `-ffp-contract=off`, computes what the Rust
//! kernel computes (the same program), to the bit, on 10 000 inputs each, both models, both
//! precisions. The
//! C kernels are linked to the Rust kernels' sine and cosine (`build.rs`): the two programs are
//! compared, not two maths libraries.

use c5_c_output_test::ffi::KERNELS;
use c5_generated::f64::paper;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const INPUTS: usize = 10_000;

fn uniform(rng: &mut ChaCha8Rng, bounds: &[f64]) -> Vec<f64> {
    bounds.iter().map(|&b| rng.gen_range(-b..=b)).collect()
}

/// Plausible values for an input, by its name: poses and motions in the workspace, forces of
/// the robot's size, the chapter-setting vectors `P_i2` of a real pose, the actuators'
/// positions of a real pose and plausible rates, the rotation of a real pose.
fn input(rng: &mut ChaCha8Rng, name: &str, pose: &[f64; 6]) -> Vec<f64> {
    match name {
        "pose" => pose.to_vec(),
        "twist" => uniform(rng, &[1.0, 1.0, 1.0, 0.5, 0.5, 0.5]),
        "accel" | "vdot" => uniform(rng, &[5.0, 5.0, 5.0, 2.0, 2.0, 2.0]),
        "forces" => uniform(rng, &[60.0, 60.0, 60.0, 60.0, 150.0, 150.0]),
        "k" => uniform(rng, &[5.0, 5.0, 5.0, 100.0, 100.0, 100.0]),
        "p" => paper::inverse_kinematics(pose)
            .1
            .iter()
            .flatten()
            .copied()
            .collect(),
        "p1" => paper::inverse_kinematics(pose).1[0].to_vec(),
        "q" => paper::inverse_kinematics(pose).0.to_vec(),
        "qd" => uniform(rng, &[0.5; 6]),
        "qdd" => uniform(rng, &[2.0; 6]),
        "r" => paper::forward_kinematics(&paper::inverse_kinematics(pose).0)
            .0
            .iter()
            .flatten()
            .copied()
            .collect(),
        other => panic!("no values for the input `{other}`"),
    }
}

#[test]
fn every_c_kernel_equals_its_rust_kernel() {
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let mut checked = 0;
    for kernel in KERNELS {
        for _ in 0..INPUTS {
            let pose: [f64; 6] = std::array::from_fn(|k| {
                rng.gen_range(if k < 3 { -0.5..=0.5 } else { -0.08..=0.08 })
            });
            let values: Vec<f64> = kernel
                .inputs
                .iter()
                .flat_map(|name| input(&mut rng, name, &pose))
                .collect();
            let (c, rust) = ((kernel.c)(&values), (kernel.rust)(&values));
            assert_eq!(c.len(), rust.len());
            // The same instructions on the same values: equal to the bit, not merely close (the
            // C kernel's instructions are in another order, `c5_codegen::schedule`).
            for (k, (a, b)) in c.iter().zip(&rust).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "{} {} {}, output {k} at {values:?}: C {a:e}, Rust {b:e}",
                    kernel.model,
                    kernel.scalar,
                    kernel.name
                );
            }
        }
        checked += 1;
    }
    // 12 pose-setting and 8 joint-setting kernels per model, 7 more for the paper model, two
    // precisions.
    assert_eq!(checked, 2 * (20 + 20 + 7));
}
