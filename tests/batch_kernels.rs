//! The batch kernels compute, lane by lane, what the single-state kernels compute: both
//! models, both precisions, folded and with the robot's parameters as inputs. The `f64` lanes
//! take their sines and cosines from a vectorised routine within one unit in the last place of
//! the library's, so they agree to 1e-15 of the largest output; the `f32` lanes call the
//! library and agree to the bit.

mod support;

use c5_generated::{f32 as k32, f64 as k64};
use c5_runtime::{Robot, State};
use support::*;

const BATCHES: usize = 2_500;

/// Transposes states into structure-of-arrays form, `[element][lane]`.
fn soa<const N: usize, T: Copy + Default>(rows: &[[T; 6]; N]) -> [[T; N]; 6] {
    std::array::from_fn(|k| std::array::from_fn(|l| rows[l][k]))
}

/// The worst difference between a lane of a batch kernel and the single-state kernel, relative
/// to the largest output of the single-state kernel (forces, or accelerations, and divisors).
macro_rules! worst_lane_error {
    ($lanes:literal, $t:ty, $single:path, $batch:path, $args:expr $(, $p:expr)?) => {{
        let states: [[[$t; 6]; 3]; $lanes] = $args;
        let column = |j: usize| -> [[$t; 6]; $lanes] { std::array::from_fn(|l| states[l][j]) };
        let (x, v, a) = (soa(&column(0)), soa(&column(1)), soa(&column(2)));
        let (batch, batch_r) = $batch(&x, &v, &a $(, $p)?);
        let mut worst: f64 = 0.0;
        for l in 0..$lanes {
            let s = &states[l];
            let (single, single_r) = $single(&s[0], &s[1], &s[2] $(, $p)?);
            let pairs: Vec<(f64, f64)> = (0..6)
                .map(|k| (f64::from(batch[k][l]), f64::from(single[k])))
                .chain((0..3).map(|k| (f64::from(batch_r[k][l]), f64::from(single_r[k]))))
                .collect();
            let scale = pairs.iter().fold(0.0_f64, |m, p| m.max(p.1.abs()));
            let err = pairs.iter().fold(0.0_f64, |m, p| m.max((p.0 - p.1).abs()));
            worst = worst.max(err / scale);
        }
        worst
    }};
}

fn state_arrays(s: &State) -> [[f64; 6]; 3] {
    [s.pose.to_array(), s.twist.to_array(), s.accel.to_array()]
}

#[test]
fn every_lane_of_the_f64_batch_kernels_is_the_single_state_kernel() {
    let mut rng = rng(41);
    let mut worst: f64 = 0.0;
    for n in 0..BATCHES {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let params: [f64; 152] = robot.kernel_parameters().try_into().unwrap();
        let states: [[[f64; 6]; 3]; 4] =
            std::array::from_fn(|_| state_arrays(&random_state(&mut rng)));
        // Forces of the robot's size for the forward dynamics.
        let forces: [[[f64; 6]; 3]; 4] = std::array::from_fn(|l| {
            let mut s = states[l];
            s[2] = s[2].map(|x| 30.0 * x);
            s
        });
        let errors = [
            worst_lane_error!(
                4,
                f64,
                k64::consistent::inverse_dynamics,
                k64::consistent::inverse_dynamics_x4,
                states
            ),
            worst_lane_error!(
                4,
                f64,
                k64::paper::inverse_dynamics,
                k64::paper::inverse_dynamics_x4,
                states
            ),
            worst_lane_error!(
                4,
                f64,
                k64::consistent::inverse_dynamics_params,
                k64::consistent::inverse_dynamics_params_x4,
                states,
                &params
            ),
            worst_lane_error!(
                4,
                f64,
                k64::paper::inverse_dynamics_params,
                k64::paper::inverse_dynamics_params_x4,
                states,
                &params
            ),
            worst_lane_error!(
                4,
                f64,
                k64::consistent::forward_dynamics,
                k64::consistent::forward_dynamics_x4,
                forces
            ),
            worst_lane_error!(
                4,
                f64,
                k64::paper::forward_dynamics_params,
                k64::paper::forward_dynamics_params_x4,
                forces,
                &params
            ),
        ];
        worst = errors.into_iter().fold(worst, f64::max);
    }
    println!("worst lane difference: {worst:e}");
    assert!(worst <= 1e-15, "a lane differs by {worst:e}");
}

#[test]
fn every_lane_of_the_f32_batch_kernels_is_the_single_state_kernel_to_the_bit() {
    let mut rng = rng(42);
    for _ in 0..BATCHES {
        let states: [[[f32; 6]; 3]; 8] = std::array::from_fn(|_| {
            state_arrays(&random_state(&mut rng)).map(|a| a.map(|x| x as f32))
        });
        let consistent = worst_lane_error!(
            8,
            f32,
            k32::consistent::inverse_dynamics,
            k32::consistent::inverse_dynamics_x8,
            states
        );
        let paper = worst_lane_error!(
            8,
            f32,
            k32::paper::inverse_dynamics,
            k32::paper::inverse_dynamics_x8,
            states
        );
        assert_eq!((consistent, paper), (0.0, 0.0));
    }
}
