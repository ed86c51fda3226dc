//! The Gough-Stewart platform's kernels, in one run: the folded kernels of the example hexapod
//! (`docs/hexapod.toml`), the `*_params` kernels the runtime calls for any hexapod, the
//! runtime's forward kinematics from a warm start, and the matrix-form reference (Newton-Euler
//! leg by leg in nalgebra); and kinematic calibration (the residual kernel, a whole fit, a plan).
//!
//! `cargo bench --bench gough_stewart` (pin it: `taskset -c 0`). Inputs cycle through seeded
//! states about the home pose behind `black_box`. The inverse dynamics also four states a call
//! (`_batch_x4`, the kernel) and for 256 states through the runtime, one at a time and batched.

mod calibration_group;

use c5_generated::f64::gough_stewart as k;
use c5_generated::manifest::Kernel;
use c5_runtime::reference::gough_stewart as reference;
use c5_runtime::{Acceleration, GoughStewart, ParallelRobot, Pose, State, Twist};
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rand::{Rng, SeedableRng};

/// Seeded states about the home pose: |α|,|β|,|γ| ≤ 0.25 rad, ±0.05 m.
fn states(home: &Pose) -> Vec<State> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    (0..256)
        .map(|_| State {
            pose: Pose {
                alpha: u(0.25),
                beta: u(0.25),
                gamma: u(0.25),
                center: [u(0.05), u(0.05), home.center[2] + u(0.05)],
            },
            twist: Twist {
                omega: [u(1.0), u(1.0), u(1.0)],
                velocity: [u(0.5), u(0.5), u(0.5)],
            },
            accel: Acceleration {
                omega_dot: [u(5.0), u(5.0), u(5.0)],
                linear: [u(2.0), u(2.0), u(2.0)],
            },
        })
        .collect()
}

/// The counted operations of a kernel, criterion's throughput (`Gelem/s` = operations per ns).
fn ops(kernel: Kernel, parameters: bool) -> Throughput {
    let c = c5_generated::manifest::entry("gough-stewart", kernel, parameters)
        .expect("in the manifest")
        .count;
    Throughput::Elements(u64::from(c.mul + c.div + c.add + c.neg))
}

fn bench(c: &mut Criterion) {
    let robot = c5_robot::GoughStewart::example();
    let hexapod = GoughStewart::new(robot).expect("the example is valid");
    let params = hexapod.parameters();
    let cases = states(&hexapod.home());
    let arrays: Vec<_> = cases
        .iter()
        .map(|s| (s.pose.to_array(), s.twist.to_array(), s.accel.to_array()))
        .collect();
    let forces: Vec<[f64; 6]> = cases
        .iter()
        .map(|s| hexapod.inverse_dynamics(s).expect("a regular state"))
        .collect();
    let mut i = 0;
    let mut g = c.benchmark_group("gough_stewart");
    g.throughput(ops(Kernel::InverseDynamics, false));
    g.bench_function("inverse_dynamics", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics(x, v, a).0
        })
    });
    g.throughput(ops(Kernel::InverseDynamics, true));
    g.bench_function("inverse_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics_params(x, v, a, params).0
        })
    });
    // Four states a call, lane `l` the `l`-th state's: the throughput against the line above.
    let motions: Vec<[[f64; 6]; 3]> = arrays.iter().map(|&(x, v, a)| [x, v, a]).collect();
    let batches = c5_benches::lanes(&motions);
    g.throughput(match ops(Kernel::InverseDynamics, true) {
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
    // What a caller of the runtime pays for many states, every state checked: 256 states one
    // at a time, and through the batch kernel four at a time.
    g.throughput(Throughput::Elements(cases.len() as u64));
    g.bench_function("inverse_dynamics_runtime_256_states", |b| {
        b.iter(|| {
            black_box(&cases)
                .iter()
                .map(|s| hexapod.inverse_dynamics(s).map(|g| g[0]).unwrap_or(0.0))
                .sum::<f64>()
        })
    });
    g.bench_function("inverse_dynamics_runtime_256_states_batched", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            ParallelRobot::inverse_dynamics_each(
                &hexapod,
                cases.len(),
                &|k| black_box(&cases)[k],
                &mut |_, g| sum += g.map(|g| g[0]).unwrap_or(0.0),
            );
            sum
        })
    });
    g.throughput(ops(Kernel::ForwardDynamics, false));
    g.bench_function("forward_dynamics", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _) = black_box(&arrays[i]);
            k::forward_dynamics(x, v, &forces[i]).0
        })
    });
    g.throughput(ops(Kernel::ForwardDynamics, true));
    g.bench_function("forward_dynamics_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _) = black_box(&arrays[i]);
            k::forward_dynamics_params(x, v, &forces[i], params).0
        })
    });
    // The dynamics with their exact Jacobians (`derivatives`), what a planner calls per step.
    g.throughput(ops(Kernel::InverseDynamicsDerivatives, true));
    g.bench_function("inverse_dynamics_derivatives_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics_derivatives_params(x, v, a, params).1
        })
    });
    g.throughput(ops(Kernel::ForwardDynamicsDerivatives, true));
    g.bench_function("forward_dynamics_derivatives_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _) = black_box(&arrays[i]);
            k::forward_dynamics_derivatives_params(x, v, &forces[i], params).1
        })
    });
    // What a caller of the runtime pays: the checks, and the legs' hold (the singularity
    // terms' kernel) that the forward dynamics' own guard lacks.
    g.bench_function("forward_dynamics_runtime", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let s = black_box(&cases[i]);
            hexapod.forward_dynamics(&s.pose, &s.twist, &forces[i])
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
    g.throughput(Throughput::Elements(1));
    g.bench_function("forward_kinematics_warm", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            let (q, near) = black_box(&readings[i]);
            hexapod.forward_kinematics(q, Some(near))
        })
    });
    // The forward kinematics' parts, for its floor: the Newton step's kernel (the residual
    // and its Jacobian), the residual's alone (the inverse kinematics), and the guard at the
    // pose found (the legs' hold).
    let poses: Vec<[f64; 6]> = readings.iter().map(|(_, p)| p.to_array()).collect();
    g.bench_function("forward_kinematics_step_kernel", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            k::forward_kinematics_step_params(black_box(&poses[i]), &readings[i].0, params)
        })
    });
    g.bench_function("inverse_kinematics_kernel", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            k::inverse_kinematics_params(black_box(&poses[i]), params)
        })
    });
    g.bench_function("singularity_terms_kernel", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            k::singularity_terms_params(black_box(&poses[i]), params)
        })
    });
    g.bench_function("forward_kinematics_level_start", |b| {
        b.iter(|| {
            i = (i + 1) % readings.len();
            let (q, _) = black_box(&readings[i]);
            hexapod.forward_kinematics(q, None)
        })
    });
    g.bench_function("reference_inverse_dynamics", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            reference::inverse_dynamics(&robot, black_box(&cases[i]))
        })
    });
    g.finish();
}

/// Kinematic calibration: the residual kernel once, and a whole fit of the 42 parameters to
/// 60 planned poses measured with a tracker's noise (the target: under 50 ms).
fn calibration(c: &mut Criterion) {
    use c5_runtime::calibrate::{simulate, Noise, Nominal};
    use c5_runtime::Description;
    let robot = c5_robot::GoughStewart::example();
    let hexapod = Nominal::new(Description::GoughStewart(robot)).unwrap();
    let mut truth = robot;
    for (i, leg) in truth.legs.iter_mut().enumerate() {
        leg.base[0] += 1e-3 * (i as f64 - 2.5);
        leg.platform[2] -= 0.5e-3 * i as f64;
        leg.encoder_offset = 2e-3;
    }
    let truth = Nominal::new(Description::GoughStewart(truth)).unwrap();
    let home = vec![hexapod.mechanism().home()];
    let data = simulate(&truth, &home, &Noise::default(), 2).unwrap();
    let parameters = hexapod.description().kernel_parameters();
    let geometry: [f64; k::GEOMETRY_PARAMETERS] = std::array::from_fn(|j| parameters[j]);
    let (pose, q): ([f64; 6], [f64; 6]) = (
        std::array::from_fn(|j| data[0].pose[j]),
        std::array::from_fn(|j| data[0].q[j]),
    );
    let mut g = c.benchmark_group("gough_stewart_calibration");
    g.bench_function("calibration_residuals", |b| {
        b.iter(|| k::calibration_residuals(black_box(&pose), black_box(&q), &geometry))
    });
    calibration_group::fit_and_plan(&mut g, &hexapod, &truth);
    g.finish();
}

criterion_group!(benches, bench, calibration);
criterion_main!(benches);
