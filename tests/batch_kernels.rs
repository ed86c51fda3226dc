//! The batch kernels compute, lane by lane, exactly what the single-state kernels compute:
//! both models, both precisions, folded and with the robot's parameters as inputs, and for
//! `f64` on each arithmetic path (the FMA twins where the CPU has FMA, and the separate
//! roundings): the path is switched for the whole process, so the `f64` check is one test.
//! And the elementary functions under them: the inline sine-cosine pair within `π/4` is
//! `libm::sincos` bit for bit, and the lanes' pair is the single state's. (They live here, not
//! as unit tests of `c5-generated`, whose test build would compile its kernels a second time.)

mod support;

use c5_generated::{f32 as k32, f64 as k64};
use c5_runtime::{Robot, State};
use support::*;

const BATCHES: usize = 2_500;

/// Transposes states into structure-of-arrays form, `[element][lane]`.
fn soa<const N: usize, T: Copy + Default>(rows: &[[T; 6]; N]) -> [[T; N]; 6] {
    std::array::from_fn(|k| std::array::from_fn(|l| rows[l][k]))
}

macro_rules! check {
    ($lanes:literal, $t:ty, $single:path, $batch:path, $args:expr $(, $p:expr)?) => {{
        let states: [[[$t; 6]; 3]; $lanes] = $args;
        let column = |j: usize| -> [[$t; 6]; $lanes] { std::array::from_fn(|l| states[l][j]) };
        let (x, v, a) = (soa(&column(0)), soa(&column(1)), soa(&column(2)));
        let (gamma, r) = $batch(&x, &v, &a $(, $p)?);
        for l in 0..$lanes {
            let s = &states[l];
            let (g1, r1) = $single(&s[0], &s[1], &s[2] $(, $p)?);
            for k in 0..6 {
                assert_eq!(gamma[k][l].to_bits(), g1[k].to_bits(), "lane {l}, output {k}");
            }
            for k in 0..3 {
                assert_eq!(r[k][l].to_bits(), r1[k].to_bits());
            }
        }
    }};
}

fn state_arrays(s: &State) -> [[f64; 6]; 3] {
    [s.pose.to_array(), s.twist.to_array(), s.accel.to_array()]
}

#[test]
fn every_lane_of_the_f64_batch_kernels_is_the_single_state_kernel_on_each_path() {
    let fused = c5_generated::fma::enabled();
    f64_lanes_equal_single_states();
    if fused {
        c5_generated::fma::set_enabled(false);
        f64_lanes_equal_single_states();
        c5_generated::fma::set_enabled(true);
    }
}

fn f64_lanes_equal_single_states() {
    let mut rng = rng(41);
    let mut vectorised = 0;
    for n in 0..BATCHES {
        let robot = if n % 2 == 0 {
            random_robot(&mut rng)
        } else {
            Robot::default()
        };
        let params: [f64; 152] = robot.kernel_parameters().try_into().unwrap();
        // Every other pair of batches turns beyond an eighth of a turn (to 1.25 rad), where a batch
        // with a lane beyond goes state by state through the single kernel instead of four
        // lanes at once.
        let turn = if n % 4 < 2 { 1.0 } else { 2.5 };
        let states: [[[f64; 6]; 3]; 4] = std::array::from_fn(|_| {
            let mut s = state_arrays(&random_state(&mut rng));
            for angle in &mut s[0][..3] {
                *angle *= turn;
            }
            s
        });
        if states.iter().all(|s| {
            s[0][..3]
                .iter()
                .all(|a| a.abs() <= std::f64::consts::FRAC_PI_4)
        }) {
            vectorised += 1;
        }
        // Forces of the robot's size for the forward dynamics.
        let forces: [[[f64; 6]; 3]; 4] = std::array::from_fn(|l| {
            let mut s = states[l];
            s[2] = s[2].map(|x| 30.0 * x);
            s
        });
        check!(
            4,
            f64,
            k64::consistent::inverse_dynamics,
            k64::consistent::inverse_dynamics_x4,
            states
        );
        check!(
            4,
            f64,
            k64::paper::inverse_dynamics,
            k64::paper::inverse_dynamics_x4,
            states
        );
        check!(
            4,
            f64,
            k64::consistent::inverse_dynamics_params,
            k64::consistent::inverse_dynamics_params_x4,
            states,
            &params
        );
        check!(
            4,
            f64,
            k64::paper::inverse_dynamics_params,
            k64::paper::inverse_dynamics_params_x4,
            states,
            &params
        );
        check!(
            4,
            f64,
            k64::consistent::forward_dynamics,
            k64::consistent::forward_dynamics_x4,
            forces
        );
        check!(
            4,
            f64,
            k64::paper::forward_dynamics_params,
            k64::paper::forward_dynamics_params_x4,
            forces,
            &params
        );
    }
    // Both ways through the batch kernels: four lanes at once, and state by state.
    assert!(
        (BATCHES / 4..BATCHES).contains(&vectorised),
        "{vectorised} of {BATCHES} batches within an eighth of a turn"
    );
}

#[test]
fn every_lane_of_the_f32_batch_kernels_is_the_single_state_kernel() {
    let mut rng = rng(42);
    for _ in 0..BATCHES {
        let states: [[[f32; 6]; 3]; 8] = std::array::from_fn(|_| {
            state_arrays(&random_state(&mut rng)).map(|a| a.map(|x| x as f32))
        });
        check!(
            8,
            f32,
            k32::consistent::inverse_dynamics,
            k32::consistent::inverse_dynamics_x8,
            states
        );
        check!(
            8,
            f32,
            k32::paper::inverse_dynamics,
            k32::paper::inverse_dynamics_x8,
            states
        );
    }
}

/// Within `π/4` the kernels' inline sine-cosine pair (`trig::sin_cos`, `crate::eighth_turn`'s
/// polynomials) is `libm::sincos`, bit for bit, on a million seeded arguments and the ends.
#[test]
fn the_inline_sine_and_cosine_are_libms_bit_for_bit_within_pi_over_4() {
    let range = c5_generated::eighth_turn::RANGE;
    let mut state = 0x9E37_79B9_7F4A_7C15_u64;
    let mut xs = vec![0.0, -0.0, 1e-300, 5e-324, 1e-9, range, -range];
    for _ in 0..1_000_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        xs.push((2.0 * u - 1.0) * range);
    }
    for x in xs {
        let (s, c) = c5_generated::trig::sin_cos(x);
        let (ls, lc) = libm::sincos(x);
        assert_eq!(
            (s.to_bits(), c.to_bits()),
            (ls.to_bits(), lc.to_bits()),
            "x = {x:e}"
        );
    }
}

#[test]
fn four_lanes_are_within_an_eighth_turn_when_each_lies_within_pi_over_4() {
    use c5_generated::lanes::F64x4;
    let r = c5_generated::eighth_turn::RANGE;
    assert!(F64x4([0.0, -0.0, r, -r]).within_eighth_turn());
    assert!(!F64x4([0.0, 0.0, 0.0, r.next_up()]).within_eighth_turn());
    assert!(!F64x4([-r.next_up(), 0.0, 0.0, 0.0]).within_eighth_turn());
    assert!(!F64x4([0.0, f64::NAN, 0.0, 0.0]).within_eighth_turn());
}

#[test]
fn every_lanes_sine_and_cosine_is_the_single_states() {
    use c5_generated::lanes::F64x4;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan();
    for xs in [
        [0.3, -0.0, 0.785, -1e-300],
        [0.3, -2.0, 0.7, 63.9],
        [1e6, f64::NAN, 0.0, f64::INFINITY],
    ] {
        let (s, c) = F64x4(xs).sin_cos();
        for l in 0..4 {
            let one = c5_generated::trig::sin_cos(xs[l]);
            assert!(
                same(s.0[l], one.0) && same(c.0[l], one.1),
                "{xs:?}, lane {l}"
            );
        }
    }
}
