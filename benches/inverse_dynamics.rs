//! Generated kernels against the nalgebra matrix form, in one run.
//!
//! `cargo bench --bench inverse_dynamics`. Inputs cycle through a fixed set of seeded random
//! states behind `black_box`, so neither the branch predictor nor constant folding by the
//! compiler can flatter a figure.

use c5_generated::{f32 as k32, f64 as k};
use c5_runtime::reference::{self as r, Step6};
use c5_runtime::{Acceleration, Pose, Robot, State, Twist};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};

fn states() -> Vec<State> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    (0..256)
        .map(|_| State {
            pose: Pose::from_array([u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)]),
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

fn inverse_dynamics(c: &mut Criterion) {
    let robot = Robot::default();
    let params: [f64; 152] = robot.flatten().try_into().unwrap();
    let s = states();
    let arrays: Vec<_> = s
        .iter()
        .map(|s| (s.pose.to_array(), s.twist.to_array(), s.accel.to_array()))
        .collect();
    let arrays32: Vec<_> = arrays
        .iter()
        .map(|(x, v, a)| {
            (
                x.map(|e| e as f32),
                v.map(|e| e as f32),
                a.map(|e| e as f32),
            )
        })
        .collect();
    let mut g = c.benchmark_group("inverse_dynamics");
    let mut i = 0;
    g.bench_function("generated", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics(x, v, a).0
        })
    });
    g.bench_function("generated_runtime_params", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            k::inverse_dynamics_params(x, v, a, black_box(&params)).0
        })
    });
    g.bench_function("generated_f32", |b| {
        b.iter(|| {
            i = (i + 1) % arrays32.len();
            let (x, v, a) = black_box(&arrays32[i]);
            k32::inverse_dynamics(x, v, a).0
        })
    });
    // The floor no arithmetic can lower: the kernel's own six calls (3 sin, 3 cos).
    g.bench_function("trig_calls_only", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, _, _) = black_box(&arrays[i]);
            [
                x[0].sin(),
                x[1].sin(),
                x[2].sin(),
                x[0].cos(),
                x[1].cos(),
                x[2].cos(),
            ]
        })
    });
    g.bench_function("reference", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let st = black_box(&s[i]);
            r::inverse_dynamics(&robot, &st.pose, &st.twist, &st.accel, Step6::Khalil)
        })
    });
    g.bench_function("reference_factored", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let st = black_box(&s[i]);
            r::inverse_dynamics(&robot, &st.pose, &st.twist, &st.accel, Step6::Factored)
        })
    });
    g.finish();
}

fn chapter_kernels(c: &mut Criterion) {
    let l = Robot::default().half_spacing;
    let s = states();
    let ps: Vec<[nalgebra::Vector3<f64>; 6]> = s.iter().map(|s| r::p_i2(l, &s.pose)).collect();
    let arrays: Vec<[[f64; 3]; 6]> = ps
        .iter()
        .map(|p| std::array::from_fn(|i| p[i].into()))
        .collect();
    let mut i = 0;
    macro_rules! pair {
        ($group:literal, $gen:expr, $reference:expr) => {{
            let mut g = c.benchmark_group($group);
            g.bench_function("generated", |b| {
                b.iter(|| {
                    i = (i + 1) % arrays.len();
                    $gen(black_box(&arrays[i]), black_box(&s[i]))
                })
            });
            g.bench_function("reference", |b| {
                b.iter(|| {
                    i = (i + 1) % ps.len();
                    $reference(black_box(&ps[i]), black_box(&s[i]))
                })
            });
            g.finish();
        }};
    }
    pair!("inverse_jacobian", |p, _| k::inverse_jacobian(p), |p, _| {
        r::inverse_jacobian(p)
    });
    pair!("pi1", |p, _| k::pi1(p), |p, _| r::pi1(p));
    pair!("jacobian", |p, _| k::jacobian(p), |p, _| r::jacobian(p));
    pair!(
        "joint_accelerations",
        |p: &[[f64; 3]; 6], st: &State| k::joint_accelerations_segment(
            &p[0],
            &r::spatial_acceleration(&st.twist, &st.accel).into()
        ),
        |p: &[nalgebra::Vector3<f64>; 6], st: &State| {
            let vdot = r::spatial_acceleration(&st.twist, &st.accel);
            r::joint_accelerations_projection(&nalgebra::Vector3::zeros(), &p[0], &vdot, 0)
        }
    );
    pair!(
        "step6",
        |p, st: &State| k::step6_factored(p, &st.accel.to_array()),
        |p: &[nalgebra::Vector3<f64>; 6], st: &State| r::inverse_jacobian(p)
            .transpose()
            .lu()
            .solve(&st.accel.to_vector())
    );
}

criterion_group!(benches, inverse_dynamics, chapter_kernels);
criterion_main!(benches);
