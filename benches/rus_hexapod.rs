//! The rotary hexapod's kernels (docs/rus-hexapod.toml), in one run: the `*_params` kernels
//! the runtime calls for any rotary hexapod, the runtime's forward dynamics (its checks and
//! the legs' hold included) and its forward kinematics from a warm start.
//!
//! `cargo bench -p c5-benches --bench rus_hexapod` (pin it: `taskset -c 0`). Inputs cycle
//! through seeded states about the home pose behind `black_box`.

mod calibration_group;

use c5_generated::f64::rus_hexapod as k;
use c5_generated::manifest::Kernel;
use c5_runtime::{Acceleration, Pose, RusHexapod, State, Twist};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rand::{Rng, SeedableRng};

/// Seeded states about the home pose: |α|,|β|,|γ| ≤ 0.1 rad, ±15 mm.
fn states(home: &Pose) -> Vec<State> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    (0..256)
        .map(|_| State {
            pose: Pose {
                alpha: u(0.1),
                beta: u(0.1),
                gamma: u(0.1),
                center: [u(0.015), u(0.015), home.center[2] + u(0.015)],
            },
            twist: Twist {
                omega: [u(1.0), u(1.0), u(1.0)],
                velocity: [u(0.2), u(0.2), u(0.2)],
            },
            accel: Acceleration {
                omega_dot: [u(5.0), u(5.0), u(5.0)],
                linear: [u(1.0), u(1.0), u(1.0)],
            },
        })
        .collect()
}

/// The counted operations of a kernel, criterion's throughput (`Gelem/s` = operations per ns).
fn ops(kernel: Kernel) -> Throughput {
    let c = c5_generated::manifest::entry("rus-hexapod", kernel, true)
        .expect("in the manifest")
        .count;
    Throughput::Elements(u64::from(c.mul + c.div + c.add + c.neg))
}

fn bench(c: &mut Criterion) {
    let hexapod = RusHexapod::new(c5_robot::RusHexapod::example()).expect("a valid example");
    let params = hexapod.parameters();
    let cases = states(&hexapod.home());
    let arrays: Vec<_> = cases
        .iter()
        .map(|s| (s.pose.to_array(), s.twist.to_array(), s.accel.to_array()))
        .collect();
    let torques: Vec<[f64; 6]> = cases
        .iter()
        .map(|s| hexapod.inverse_dynamics(s).expect("a regular state"))
        .collect();
    let mut i = 0;
    let mut g = c.benchmark_group("rus_hexapod");
    g.throughput(ops(Kernel::InverseDynamics));
    g.bench_function("inverse_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics_params(x, v, a, params).0
        })
    });
    g.throughput(ops(Kernel::ForwardDynamics));
    g.bench_function("forward_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _) = black_box(&arrays[i]);
            k::forward_dynamics_params(x, v, &torques[i], params).0
        })
    });
    g.throughput(Throughput::Elements(1));
    g.bench_function("forward_dynamics_runtime", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            hexapod.forward_dynamics(&s.pose, &s.twist, &torques[i])
        })
    });
    // A controller's case: the previous sample's pose, 1 ms of a brisk motion away.
    let readings: Vec<([f64; 6], Pose)> = cases
        .iter()
        .map(|s| {
            let (q, _) = hexapod.inverse_kinematics(&s.pose).expect("regular");
            let mut previous = s.pose;
            previous.alpha -= 1e-3 * s.twist.omega[0];
            previous.beta -= 1e-3 * s.twist.omega[1];
            previous.gamma -= 1e-3 * s.twist.omega[2];
            for k in 0..3 {
                previous.center[k] -= 1e-3 * s.twist.velocity[k];
            }
            (q, previous)
        })
        .collect();
    g.bench_function("forward_kinematics_warm", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            let (q, near) = black_box(&readings[i]);
            hexapod.forward_kinematics(q, Some(near))
        })
    });
    g.finish();
}

/// Kinematic calibration: a whole fit of the geometry to 60 planned poses of a robot built
/// 1.5 mm (1.5 mrad) off its file, measured with a tracker's noise, and the plan.
fn calibration(c: &mut Criterion) {
    use c5_runtime::calibrate::Nominal;
    use c5_runtime::Description;
    let robot = Description::RusHexapod(c5_robot::RusHexapod::example());
    let truth = Nominal::new(calibration_group::as_built(&robot)).unwrap();
    let nominal = Nominal::new(robot).unwrap();
    let mut g = c.benchmark_group("rus_hexapod_calibration");
    calibration_group::fit_and_plan(&mut g, &nominal, &truth);
    g.finish();
}

criterion_group!(benches, bench, calibration);
criterion_main!(benches);
