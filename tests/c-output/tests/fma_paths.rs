//! The two arithmetic paths of every `f64` kernel agree: `{kernel}_fused` (products folded
//! into the sums that read them, one rounding each) against `{kernel}_separate` (every
//! operation rounded on its own), on 10 000 poses of the workspace box and 2 000 at each of
//! three distances (1e-2, 1e-4, 1e-6) from a singularity of eq 16, both models.
//!
//! The bound is normwise per kernel: `|fused - separate|∞ ≤ 1e-14 · |separate|∞ / s^p`, with
//! `s` the smallest singularity term at the pose (`|r11|`, `|r22|`, `|r33|` and the forward
//! term `1 + abc`). A fused operation differs from its separate form by at most an ulp of the
//! product it folds, and the kernels divide by `s`, so `p = 1` for every kernel but one: in the
//! box (`s ≥ 0.77`) they agree to 3e-15. The consistent model's forward dynamics solves
//! `M_x a = J⁻ᵀ Γ - h` with `M_x ≈ J⁻ᵀ diag(m) J⁻¹`, whose condition number grows as `1/s⁴`
//! near an inverse singularity: its rounding errors, on either path, grow as `1/s³` (measured:
//! 3e-11 relative at `s = 0.02`, 2e-4 at `1e-4`, 10 at `1e-6`), so `p = 3` for it. Both paths
//! are then equally inaccurate; the difference between them only shows it. The paper model's
//! forward dynamics does not square the conditioning and keeps `p = 1`. The consistent model's
//! `joint_bias` and `inverse_dynamics_joint` take `p = 2` (see [`amplification`]).

mod support;

use c5_c_output_test::ffi::KERNELS;
use c5_generated::f64::paper;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use support::input;

/// Normwise relative agreement of the two paths, per unit of `1/s^p`.
const TOLERANCE: f64 = 1e-14;

/// The power `p` of the singular distance by which the kernel's rounding errors grow.
fn amplification(model: &str, kernel: &str) -> i32 {
    match (model, kernel) {
        ("consistent", "forward_dynamics") => 3,
        // The platform's motion from the actuators kept whole (`Expr::keep_where_cheaper`),
        // which the optimizer chose for fewer operations, divides by `s` twice on some paths:
        // with `p = 1` they differed by up to 3.3e-13 at `s = 1.1e-6` (8 of 16 000 poses past
        // 1e-14), well inside `p = 2`.
        ("consistent", "joint_bias" | "inverse_dynamics_joint") => 2,
        _ => 1,
    }
}

/// A pose of the workspace box.
fn workspace_pose(rng: &mut ChaCha8Rng) -> [f64; 6] {
    std::array::from_fn(|k| rng.gen_range(if k < 3 { -0.5..=0.5 } else { -0.08..=0.08 }))
}

/// A pose whose `r11` (`β` near π/2: `r11 = cos β cos γ`, `r33 = cos β cos α`) is about
/// `distance`.
fn near_singular_pose(rng: &mut ChaCha8Rng, distance: f64) -> [f64; 6] {
    let mut x = workspace_pose(rng);
    x[1] = std::f64::consts::FRAC_PI_2 - distance * rng.gen_range(1.0..2.0);
    x
}

/// The smallest singularity term at `pose`: eq 16's divisors, and the forward term
/// `1 + abc` of the actuator positions the pose gives.
fn singular_distance(pose: &[f64; 6]) -> f64 {
    let (q, _, r) = paper::inverse_kinematics(pose);
    let forward = paper::forward_kinematics(&q).2[0];
    r.iter().map(|x| x.abs()).fold(forward.abs(), f64::min)
}

fn norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn the_fused_and_separate_paths_agree_within_the_stated_bound() {
    if !c5_generated::fma::available() {
        eprintln!("this CPU has no FMA: the fused twins cannot run here");
        return;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut pairs = 0;
    let mut worst = 0.0_f64;
    // Kernels whose two paths computed different bits somewhere: the twins do fuse.
    let mut differing = Vec::new();
    for fused in KERNELS.iter().filter(|k| k.path == "fused") {
        let separate = KERNELS
            .iter()
            .find(|k| k.path == "separate" && k.model == fused.model && k.name == fused.name)
            .unwrap_or_else(|| panic!("{} {}: no separate path", fused.model, fused.name));
        let power = amplification(fused.model, fused.name);
        let mut cases: Vec<[f64; 6]> = (0..10_000).map(|_| workspace_pose(&mut rng)).collect();
        for distance in [1e-2, 1e-4, 1e-6] {
            cases.extend((0..2_000).map(|_| near_singular_pose(&mut rng, distance)));
        }
        for pose in cases {
            let values: Vec<f64> = fused
                .inputs
                .iter()
                .flat_map(|name| input(&mut rng, name, &pose))
                .collect();
            let (f, s) = ((fused.rust)(&values), (separate.rust)(&values));
            let scale = norm(&s);
            assert!(
                scale.is_finite(),
                "{} {} at {pose:?}",
                fused.model,
                fused.name
            );
            let diff: Vec<f64> = f.iter().zip(&s).map(|(a, b)| a - b).collect();
            let distance = singular_distance(&pose);
            let ratio = norm(&diff) / scale.max(f64::MIN_POSITIVE) * distance.powi(power);
            worst = worst.max(ratio);
            if diff.iter().any(|&d| d != 0.0) && !differing.contains(&(fused.model, fused.name)) {
                differing.push((fused.model, fused.name));
            }
            assert!(
                ratio <= TOLERANCE,
                "{} {}: fused and separate differ by {:e} of {scale:e} at {pose:?} \
                 (distance to a singularity {distance:e})",
                fused.model,
                fused.name,
                norm(&diff),
            );
        }
        pairs += 1;
    }
    eprintln!("worst normwise difference times s^p: {worst:e}");
    // 13 pose-setting and 8 joint-setting kernels per model, 7 more for the paper model.
    assert_eq!(pairs, 21 + 21 + 7);
    for model in ["consistent", "paper"] {
        for kernel in [
            "inverse_dynamics",
            "forward_dynamics",
            "inverse_dynamics_joint",
        ] {
            assert!(
                differing.contains(&(model, kernel)),
                "{model} {kernel}: the fused twin computed the separate path's bits everywhere"
            );
        }
    }
}
