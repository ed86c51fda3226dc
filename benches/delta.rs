//! The Delta's kernels (docs/delta.toml), in one run: the `*_params` kernels the runtime calls
//! for any Delta (the inverse dynamics also four states a call, `_batch_x4`), the runtime's
//! forward dynamics (its checks included) and its closed-form forward kinematics.
//!
//! `cargo bench -p c5-benches --bench delta` (pin it: `taskset -c 0`). Inputs cycle through
//! seeded states about the home position behind `black_box`.

mod calibration_group;

use c5_generated::f64::delta as k;
use c5_generated::manifest::Kernel;
use c5_runtime::Delta;
use c5_runtime::Translation;
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rand::{Rng, SeedableRng};

/// Seeded states within 5 cm of home.
fn states(home: &[f64; 3]) -> Vec<Translation> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    (0..256)
        .map(|_| Translation {
            position: [home[0] + u(0.05), home[1] + u(0.05), home[2] + u(0.05)],
            velocity: [u(0.5), u(0.5), u(0.5)],
            acceleration: [u(5.0), u(5.0), u(5.0)],
        })
        .collect()
}

/// The counted operations of a kernel, criterion's throughput (`Gelem/s` = operations per ns).
fn ops(kernel: Kernel) -> Throughput {
    let c = c5_generated::manifest::entry("delta", kernel, true)
        .expect("in the manifest")
        .count;
    Throughput::Elements(u64::from(c.mul + c.div + c.add + c.neg))
}

fn bench(c: &mut Criterion) {
    let delta = Delta::new(c5_robot::Delta::example()).expect("a valid example");
    let params = delta.parameters();
    let cases = states(&delta.home());
    let torques: Vec<[f64; 3]> = cases
        .iter()
        .map(|s| delta.inverse_dynamics(s).expect("a regular state"))
        .collect();
    let angles: Vec<[f64; 3]> = cases
        .iter()
        .map(|s| {
            delta
                .inverse_kinematics(&s.position)
                .expect("a regular state")
        })
        .collect();
    let mut i = 0;
    let mut g = c.benchmark_group("delta");
    g.throughput(ops(Kernel::InverseDynamics));
    g.bench_function("inverse_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            k::inverse_dynamics_params(&s.position, &s.velocity, &s.acceleration, params).0
        })
    });
    // Four states a call, lane `l` the `l`-th state's: the throughput against the line above.
    let motions: Vec<[[f64; 3]; 3]> = cases
        .iter()
        .map(|s| [s.position, s.velocity, s.acceleration])
        .collect();
    let batches = c5_benches::lanes(&motions);
    g.throughput(match ops(Kernel::InverseDynamics) {
        Throughput::Elements(n) => Throughput::Elements(4 * n),
        other => other,
    });
    g.bench_function("inverse_dynamics_params_batch_x4", |b| {
        b.iter(|| {
            i = (i + 1) % batches.len();
            let [x, v, a] = black_box(&batches[i]);
            k::inverse_dynamics_params_x4(x, v, a, params).0
        })
    });
    g.throughput(ops(Kernel::ForwardDynamics));
    g.bench_function("forward_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            k::forward_dynamics_params(&s.position, &s.velocity, &torques[i], params).0
        })
    });
    // The dynamics with their exact Jacobians (`derivatives`), what a planner calls per step.
    g.throughput(ops(Kernel::InverseDynamicsDerivatives));
    g.bench_function("inverse_dynamics_derivatives_params", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            k::inverse_dynamics_derivatives_params(
                &s.position,
                &s.velocity,
                &s.acceleration,
                params,
            )
            .1
        })
    });
    g.throughput(ops(Kernel::ForwardDynamicsDerivatives));
    g.bench_function("forward_dynamics_derivatives_params", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            k::forward_dynamics_derivatives_params(&s.position, &s.velocity, &torques[i], params).1
        })
    });
    g.throughput(Throughput::Elements(1));
    g.bench_function("forward_dynamics_runtime", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            delta.forward_dynamics(&s.position, &s.velocity, &torques[i])
        })
    });
    g.bench_function("forward_kinematics", |b| {
        b.iter(|| {
            i = (i + 1) % angles.len();
            delta.forward_kinematics(black_box(&angles[i]))
        })
    });
    g.finish();
}

/// Kinematic calibration: a whole fit of the geometry to 60 planned poses of a robot built
/// 1.5 mm (1.5 mrad) off its file, measured with a tracker's noise, and the plan.
fn calibration(c: &mut Criterion) {
    use c5_runtime::calibrate::Nominal;
    use c5_runtime::Description;
    let robot = Description::Delta(c5_robot::Delta::example());
    let truth = Nominal::new(calibration_group::as_built(&robot)).unwrap();
    let nominal = Nominal::new(robot).unwrap();
    let mut g = c.benchmark_group("delta_calibration");
    calibration_group::fit_and_plan(&mut g, &nominal, &truth);
    g.finish();
}

criterion_group!(benches, bench, calibration);
criterion_main!(benches);
