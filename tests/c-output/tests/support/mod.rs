//! Inputs for the kernels' tests, by the names of their arguments.

use c5_generated::f64::paper;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

fn uniform(rng: &mut ChaCha8Rng, bounds: &[f64]) -> Vec<f64> {
    bounds.iter().map(|&b| rng.gen_range(-b..=b)).collect()
}

/// Plausible values for an input, by its name: poses and motions in the workspace, forces of
/// the robot's size, the chapter-setting vectors `P_i2` of a real pose, the actuators'
/// positions of a real pose and plausible rates, the rotation of a real pose.
pub fn input(rng: &mut ChaCha8Rng, name: &str, pose: &[f64; 6]) -> Vec<f64> {
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
