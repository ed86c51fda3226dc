//! Generated kernels against the nalgebra matrix form, in one run.
//!
//! `cargo bench --bench inverse_dynamics`. Inputs cycle through a fixed set of seeded random
//! states behind `black_box`, so neither the branch predictor nor constant folding by the
//! compiler can flatter a figure. Every model's kernels are benched through the kernel-set
//! trait, statically dispatched (`K: Kernels`, one instantiation per model), as
//! `generated_{model}` (and `_batch_x4`, `_runtime_params`, `_f32`). The `f64` kernels run
//! their FMA twins where the CPU has FMA; `_separate` is the same kernel with the FMA path
//! switched off (`c5_generated::fma::set_enabled(false)`), every operation rounded on its own.

use c5_generated::f32::{Consistent as Consistent32, Kernels as Kernels32, Paper as Paper32};
use c5_generated::f64::{paper as k, Consistent, Kernels, Paper};
use c5_generated::manifest::Kernel;
use c5_runtime::reference::{self as r, consistent as rc, Step6};
use c5_runtime::{Acceleration, Pose, Robot, State, Twist};
use criterion::measurement::WallTime;
use criterion::BenchmarkGroup;
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
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

/// The counted arithmetic operations (mul, div, add, neg) of a generated kernel, from its
/// manifest: set as criterion's throughput, criterion reports them per second beside each
/// median (`Gelem/s` = operations per ns).
fn ops(model: &str, kernel: Kernel, parameters: bool) -> u64 {
    let k = c5_generated::manifest::entry(model, kernel, parameters)
        .unwrap_or_else(|| panic!("{model} {kernel:?} in the manifest"));
    u64::from(k.count.mul + k.count.div + k.count.add + k.count.neg)
}

/// The inputs of the inverse-dynamics benches.
struct Cases<'a> {
    arrays: &'a [([f64; 6], [f64; 6], [f64; 6])],
    arrays32: &'a [([f32; 6], [f32; 6], [f32; 6])],
    batches: &'a [[[[f64; 4]; 6]; 3]],
    /// The same states turned beyond an eighth of a turn (`|α|` in 0.8-1.0 rad), single and batched.
    beyond: &'a [([f64; 6], [f64; 6], [f64; 6])],
    beyond_batches: &'a [[[[f64; 4]; 6]; 3]],
    params: &'a [f64; 152],
}

impl Cases<'_> {
    /// One model's inverse dynamics: single, batch, runtime parameters, `f32`.
    fn inverse_dynamics<K: Kernels, K32: Kernels32>(
        &self,
        g: &mut BenchmarkGroup<WallTime>,
        kernels: &K,
        kernels32: &K32,
    ) {
        let model = kernels.model();
        let count = ops(model, Kernel::InverseDynamics, false);
        let (arrays, batches, arrays32) = (self.arrays, self.batches, self.arrays32);
        let mut i = 0;
        g.throughput(Throughput::Elements(count));
        g.bench_function(format!("generated_{model}"), |b| {
            b.iter(|| {
                i = (i + 1) % arrays.len();
                let (x, v, a) = black_box(&arrays[i]);
                kernels.inverse_dynamics(x, v, a).0
            })
        });
        separate(|| {
            g.bench_function(format!("generated_{model}_separate"), |b| {
                b.iter(|| {
                    i = (i + 1) % arrays.len();
                    let (x, v, a) = black_box(&arrays[i]);
                    kernels.inverse_dynamics(x, v, a).0
                })
            })
        });
        g.throughput(Throughput::Elements(4 * count));
        g.bench_function(format!("generated_{model}_batch_x4"), |b| {
            b.iter(|| {
                i = (i + 1) % batches.len();
                let [x, v, a] = black_box(&batches[i]);
                kernels.inverse_dynamics_x4(x, v, a).0
            })
        });
        separate(|| {
            g.bench_function(format!("generated_{model}_batch_x4_separate"), |b| {
                b.iter(|| {
                    i = (i + 1) % batches.len();
                    let [x, v, a] = black_box(&batches[i]);
                    kernels.inverse_dynamics_x4(x, v, a).0
                })
            })
        });
        // Beyond an eighth of a turn the sines and cosines are the library's, and a batch goes
        // state by state through the single kernel.
        let (beyond, beyond_batches) = (self.beyond, self.beyond_batches);
        g.throughput(Throughput::Elements(count));
        g.bench_function(format!("generated_{model}_beyond_eighth_turn"), |b| {
            b.iter(|| {
                i = (i + 1) % beyond.len();
                let (x, v, a) = black_box(&beyond[i]);
                kernels.inverse_dynamics(x, v, a).0
            })
        });
        g.throughput(Throughput::Elements(4 * count));
        g.bench_function(
            format!("generated_{model}_batch_x4_beyond_eighth_turn"),
            |b| {
                b.iter(|| {
                    i = (i + 1) % beyond_batches.len();
                    let [x, v, a] = black_box(&beyond_batches[i]);
                    kernels.inverse_dynamics_x4(x, v, a).0
                })
            },
        );
        g.throughput(Throughput::Elements(ops(
            model,
            Kernel::InverseDynamics,
            true,
        )));
        g.bench_function(format!("generated_{model}_runtime_params"), |b| {
            b.iter(|| {
                i = (i + 1) % arrays.len();
                let (x, v, a) = black_box(&arrays[i]);
                kernels
                    .inverse_dynamics_params(x, v, a, black_box(self.params))
                    .0
            })
        });
        g.throughput(Throughput::Elements(count));
        g.bench_function(format!("generated_{model}_f32"), |b| {
            b.iter(|| {
                i = (i + 1) % arrays32.len();
                let (x, v, a) = black_box(&arrays32[i]);
                kernels32.inverse_dynamics(x, v, a).0
            })
        });
    }
}

/// Runs `bench` with the kernels' FMA path switched off (the separate roundings), then
/// restores it.
fn separate<R>(bench: impl FnOnce() -> R) -> R {
    let was = c5_generated::fma::enabled();
    c5_generated::fma::set_enabled(false);
    let r = bench();
    c5_generated::fma::set_enabled(was);
    r
}

/// One model's forward dynamics (single, batch, each with the FMA path on and off), and its
/// reference.
fn forward_dynamics_of<K: Kernels>(
    g: &mut BenchmarkGroup<WallTime>,
    kernels: &K,
    robot: &Robot,
    s: &[State],
) {
    let model = kernels.model();
    // Forces that hold the platform near its states: the inverse dynamics of each.
    let cases: Vec<_> = s
        .iter()
        .map(|st| {
            let (x, v, a) = (st.pose.to_array(), st.twist.to_array(), st.accel.to_array());
            (x, v, kernels.inverse_dynamics(&x, &v, &a).0)
        })
        .collect();
    let mut i = 0;
    g.throughput(Throughput::Elements(ops(
        model,
        Kernel::ForwardDynamics,
        false,
    )));
    g.bench_function(format!("generated_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            let (x, v, gamma) = black_box(&cases[i]);
            kernels.forward_dynamics(x, v, gamma).0
        })
    });
    separate(|| {
        g.bench_function(format!("generated_{model}_separate"), |b| {
            b.iter(|| {
                i = (i + 1) % cases.len();
                let (x, v, gamma) = black_box(&cases[i]);
                kernels.forward_dynamics(x, v, gamma).0
            })
        })
    });
    let batches: Vec<[[[f64; 4]; 6]; 3]> = cases
        .chunks_exact(4)
        .map(|c| {
            let rows = |k: usize| -> [[f64; 6]; 4] {
                std::array::from_fn(|l| [c[l].0, c[l].1, c[l].2][k])
            };
            [soa(&rows(0)), soa(&rows(1)), soa(&rows(2))]
        })
        .collect();
    g.throughput(Throughput::Elements(
        4 * ops(model, Kernel::ForwardDynamics, false),
    ));
    for (name, fma) in [("batch_x4", true), ("batch_x4_separate", false)] {
        let was = c5_generated::fma::enabled();
        c5_generated::fma::set_enabled(fma && was);
        g.bench_function(format!("generated_{model}_{name}"), |b| {
            b.iter(|| {
                i = (i + 1) % batches.len();
                let [x, v, gamma] = black_box(&batches[i]);
                kernels.forward_dynamics_x4(x, v, gamma).0
            })
        });
        c5_generated::fma::set_enabled(was);
    }
    g.throughput(Throughput::Elements(1));
    let parsed = model.parse().unwrap();
    g.bench_function(format!("reference_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let st = black_box(&s[i]);
            r::forward_dynamics(robot, parsed, &st.pose, &st.twist, &cases[i].2)
        })
    });
}

/// `[element][lane]` from four states.
fn soa(rows: &[[f64; 6]; 4]) -> [[f64; 4]; 6] {
    std::array::from_fn(|k| std::array::from_fn(|l| rows[l][k]))
}

/// States four at a time, in the batch kernels' `[element][lane]` form.
fn in_fours(arrays: &[([f64; 6], [f64; 6], [f64; 6])]) -> Vec<[[[f64; 4]; 6]; 3]> {
    arrays
        .chunks(4)
        .map(|c| {
            let col = |j: usize| -> [[f64; 6]; 4] {
                std::array::from_fn(|l| match j {
                    0 => c[l].0,
                    1 => c[l].1,
                    _ => c[l].2,
                })
            };
            [soa(&col(0)), soa(&col(1)), soa(&col(2))]
        })
        .collect()
}

fn inverse_dynamics(c: &mut Criterion) {
    let robot = Robot::default();
    let params: [f64; 152] = robot.kernel_parameters().try_into().unwrap();
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
    let beyond: Vec<_> = arrays
        .iter()
        .map(|&(mut x, v, a)| {
            x[0] = x[0].signum() * (0.8 + 0.4 * x[0].abs());
            (x, v, a)
        })
        .collect();
    let (batches, beyond_batches) = (in_fours(&arrays), in_fours(&beyond));
    let mut g = c.benchmark_group("inverse_dynamics");
    let cases = Cases {
        arrays: &arrays,
        arrays32: &arrays32,
        batches: &batches,
        beyond: &beyond,
        beyond_batches: &beyond_batches,
        params: &params,
    };
    cases.inverse_dynamics(&mut g, &Consistent, &Consistent32);
    cases.inverse_dynamics(&mut g, &Paper, &Paper32);
    let mut i = 0;
    g.throughput(Throughput::Elements(1));
    g.bench_function("reference_consistent", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let st = black_box(&s[i]);
            rc::inverse_dynamics(&robot, &st.pose, &st.twist, &st.accel)
        })
    });
    // The floor no arithmetic can lower: the kernels' own three sine-cosine pairs.
    g.throughput(Throughput::Elements(1));
    g.bench_function("trig_calls_only", |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, _, _) = black_box(&arrays[i]);
            [
                c5_generated::trig::sin_cos(x[0]),
                c5_generated::trig::sin_cos(x[1]),
                c5_generated::trig::sin_cos(x[2]),
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

fn forward_dynamics(c: &mut Criterion) {
    let robot = Robot::default();
    let s = states();
    let mut g = c.benchmark_group("forward_dynamics");
    forward_dynamics_of(&mut g, &Consistent, &robot, &s);
    forward_dynamics_of(&mut g, &Paper, &robot, &s);
    g.finish();
}

/// The identification kernels, and one sample added to the streaming estimator (the base
/// regressor and six rank-one updates of the normal equations, amortised over blocks).
fn identification(c: &mut Criterion) {
    let robot = Robot::default();
    let geometry = [
        robot.half_spacing,
        robot.gravity[0],
        robot.gravity[1],
        robot.gravity[2],
    ];
    let s = states();
    let arrays: Vec<_> = s
        .iter()
        .map(|s| (s.pose.to_array(), s.twist.to_array(), s.accel.to_array()))
        .collect();
    let mut g = c.benchmark_group("identification");
    let mut i = 0;
    for kernels in c5_generated::f64::MODELS {
        let model = kernels.model();
        let mut y = vec![0.0; 6 * kernels.base_parameters().len()];
        g.throughput(Throughput::Elements(ops(
            model,
            Kernel::BaseRegressor,
            false,
        )));
        g.bench_function(format!("base_regressor_{model}"), |b| {
            b.iter(|| {
                i = (i + 1) % arrays.len();
                let (x, v, a) = black_box(&arrays[i]);
                kernels.base_regressor_into(x, v, a, &geometry, &mut y)
            })
        });
        g.throughput(Throughput::Elements(ops(model, Kernel::Regressor, false)));
        g.bench_function(format!("regressor_{model}"), |b| {
            b.iter(|| {
                i = (i + 1) % arrays.len();
                let (x, v, a) = black_box(&arrays[i]);
                // The whole result, so that no column is optimised away.
                kernels.regressor(x, v, a, &geometry)
            })
        });
    }
    g.throughput(Throughput::Elements(1));
    let c5 = c5_runtime::C5::new(robot).unwrap();
    let mechanism = c5_runtime::ParallelRobot::as_mechanism(&c5);
    let mut identifier = c5_runtime::identify::Identifier::new(mechanism).unwrap();
    let gamma: Vec<[f64; 6]> = s
        .iter()
        .map(|st| c5.inverse_dynamics(st).unwrap())
        .collect();
    g.bench_function("identifier_add_consistent", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            identifier
                .add(black_box(&s[i]), black_box(&gamma[i]))
                .unwrap()
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

/// From what the encoders measure: the closed-form forward kinematics against Newton-Raphson
/// in nalgebra from a nearby start (what a controller would do from its previous sample), and
/// the inverse dynamics from `(q, q̇, q̈)` against the same from the platform state.
fn joint_space(c: &mut Criterion) {
    let robot = Robot::default();
    let s = states();
    let c5 = c5_runtime::C5::new(robot).unwrap();
    let joints: Vec<[[f64; 6]; 3]> = s
        .iter()
        .map(|st| {
            [
                c5.inverse_kinematics(&st.pose).unwrap().0,
                c5.joint_velocities(&st.pose, &st.twist).unwrap(),
                c5.joint_accelerations(st).unwrap(),
            ]
        })
        .collect();
    // The previous sample of a 1 kHz controller: a millimetre and a milliradian away.
    let starts: Vec<Pose> = s
        .iter()
        .map(|st| {
            let mut p = st.pose;
            p.alpha += 1e-3;
            p.gamma -= 1e-3;
            p.center[0] += 1e-3;
            p
        })
        .collect();
    let mut g = c.benchmark_group("forward_kinematics");
    let mut i = 0;
    g.throughput(Throughput::Elements(ops(
        "consistent",
        Kernel::ForwardKinematics,
        false,
    )));
    g.bench_function("generated", |b| {
        b.iter(|| {
            i = (i + 1) % joints.len();
            Consistent.forward_kinematics(black_box(&joints[i][0]))
        })
    });
    g.throughput(Throughput::Elements(1));
    g.bench_function("generated_with_angles", |b| {
        b.iter(|| {
            i = (i + 1) % joints.len();
            let (r, c, _) = Consistent.forward_kinematics(black_box(&joints[i][0]));
            (Consistent.rpy_angles(&r), c)
        })
    });
    g.bench_function("newton_nalgebra", |b| {
        b.iter(|| {
            i = (i + 1) % joints.len();
            rc::forward_kinematics_newton(
                robot.half_spacing,
                black_box(&joints[i][0]),
                black_box(&starts[i]),
                1e-12,
            )
        })
    });
    g.finish();
    let mut g = c.benchmark_group("inverse_dynamics_joint");
    joint_inverse_dynamics(&mut g, &Consistent, &joints, &s);
    joint_inverse_dynamics(&mut g, &Paper, &joints, &s);
    g.finish();
}

/// One model's inverse dynamics from the joints, and from the platform state beside it.
fn joint_inverse_dynamics<K: Kernels>(
    g: &mut BenchmarkGroup<WallTime>,
    kernels: &K,
    joints: &[[[f64; 6]; 3]],
    s: &[State],
) {
    let model = kernels.model();
    let arrays: Vec<_> = s
        .iter()
        .map(|st| (st.pose.to_array(), st.twist.to_array(), st.accel.to_array()))
        .collect();
    let mut i = 0;
    g.throughput(Throughput::Elements(ops(
        model,
        Kernel::InverseDynamicsJoint,
        false,
    )));
    g.bench_function(format!("from_joints_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % joints.len();
            let [q, qd, qdd] = black_box(&joints[i]);
            kernels.inverse_dynamics_joint(q, qd, qdd).0
        })
    });
    g.throughput(Throughput::Elements(ops(
        model,
        Kernel::InverseDynamics,
        false,
    )));
    g.bench_function(format!("from_pose_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a) = black_box(&arrays[i]);
            kernels.inverse_dynamics(x, v, a).0
        })
    });
}

/// One model's derivative kernels beside their primal kernels, and what a user would do
/// without them: one-sided finite differences of the forward dynamics, 19 calls (the point and
/// one step in each of the 18 components of the pose, the twist and the forces).
fn derivatives_of<K: Kernels>(g: &mut BenchmarkGroup<WallTime>, kernels: &K, s: &[State]) {
    let model = kernels.model();
    let arrays: Vec<_> = s
        .iter()
        .map(|s| {
            let (x, v, a) = (s.pose.to_array(), s.twist.to_array(), s.accel.to_array());
            (x, v, a, kernels.inverse_dynamics(&x, &v, &a).0)
        })
        .collect();
    let mut i = 0;
    g.bench_function(format!("inverse_dynamics_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a, _) = black_box(&arrays[i]);
            kernels.inverse_dynamics(x, v, a).0
        })
    });
    g.bench_function(format!("inverse_dynamics_derivatives_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, a, _) = black_box(&arrays[i]);
            kernels.inverse_dynamics_derivatives(x, v, a)
        })
    });
    g.bench_function(format!("forward_dynamics_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _, gamma) = black_box(&arrays[i]);
            kernels.forward_dynamics(x, v, gamma).0
        })
    });
    g.bench_function(format!("forward_dynamics_derivatives_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % arrays.len();
            let (x, v, _, gamma) = black_box(&arrays[i]);
            kernels.forward_dynamics_derivatives(x, v, gamma)
        })
    });
    g.bench_function(
        format!("forward_dynamics_finite_differences_{model}"),
        |b| {
            b.iter(|| {
                i = (i + 1) % arrays.len();
                let (x, v, _, gamma) = black_box(&arrays[i]);
                let base = kernels.forward_dynamics(x, v, gamma).0;
                let mut jacobian = [[0.0; 18]; 6];
                for k in 0..18 {
                    let (mut x, mut v, mut gamma) = (*x, *v, *gamma);
                    match k {
                        0..6 => x[k] += 1e-7,
                        6..12 => v[k - 6] += 1e-7,
                        _ => gamma[k - 12] += 1e-7,
                    }
                    let a = kernels.forward_dynamics(&x, &v, &gamma).0;
                    for r in 0..6 {
                        jacobian[r][k] = (a[r] - base[r]) * 1e7;
                    }
                }
                (base, jacobian)
            })
        },
    );
    let joints: Vec<_> = s
        .iter()
        .map(|s| {
            let x = s.pose.to_array();
            let q = k::inverse_kinematics(&x).0;
            (q, s.twist.to_array(), s.accel.to_array())
        })
        .collect();
    g.bench_function(format!("inverse_dynamics_joint_derivatives_{model}"), |b| {
        b.iter(|| {
            i = (i + 1) % joints.len();
            let (q, qd, qdd) = black_box(&joints[i]);
            kernels.inverse_dynamics_joint_derivatives(q, qd, qdd)
        })
    });
}

/// The derivative kernels (`cargo bench --bench inverse_dynamics -- derivatives/`).
fn derivatives(c: &mut Criterion) {
    let s = states();
    let mut g = c.benchmark_group("derivatives");
    derivatives_of(&mut g, &Consistent, &s);
    derivatives_of(&mut g, &Paper, &s);
    g.finish();
}

criterion_group!(
    benches,
    inverse_dynamics,
    joint_space,
    forward_dynamics,
    derivatives,
    identification,
    chapter_kernels
);
criterion_main!(benches);
