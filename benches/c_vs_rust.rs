//! The generated kernels in C (`gcc -O3 -march=native -std=c99`) against the same kernels in
//! Rust (the default target: their FMA twins where the CPU has FMA, `rust_*`, and the separate
//! path, `rust_*_separate`), and both against the SymPy baseline (`sympy/generate.py`) built
//! `gcc -O3 -march=native` twice: `-std=c99` (`sympy_*`, no contraction) and GCC's default GNU
//! mode (`sympy_gnu_*`, `a * b + c` contracted into fused multiply-adds), in one run; the paper
//! model's SymPy baseline twice, regrouped as ours (`sympy_paper`) and leg by leg as the chapter
//! computes it (`sympy_paper_by_legs`):
//! `cargo bench --bench c_vs_rust`.

use c5_c_output_test::native;
use c5_generated::f64::{consistent, paper};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};

type Inputs = ([f64; 6], [f64; 6], [f64; 6]);

fn states() -> Vec<Inputs> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    (0..256)
        .map(|_| {
            (
                [u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)],
                [u(1.0), u(1.0), u(1.0), u(0.5), u(0.5), u(0.5)],
                [u(5.0), u(5.0), u(5.0), u(2.0), u(2.0), u(2.0)],
            )
        })
        .collect()
}

fn inverse_dynamics(c: &mut Criterion) {
    let s = states();
    let mut g = c.benchmark_group("inverse_dynamics_c");
    let mut i = 0;
    g.bench_function("rust_consistent", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            consistent::inverse_dynamics(x, v, a).0
        })
    });
    g.bench_function("rust_consistent_separate", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            consistent::inverse_dynamics_separate(x, v, a).0
        })
    });
    g.bench_function("c_consistent", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            let (mut gamma, mut r) = ([0.0; 6], [0.0; 3]);
            unsafe {
                native::native_consistent_inverse_dynamics(
                    x.as_ptr(),
                    v.as_ptr(),
                    a.as_ptr(),
                    gamma.as_mut_ptr(),
                    r.as_mut_ptr(),
                )
            };
            gamma
        })
    });
    g.bench_function("rust_paper", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            paper::inverse_dynamics(x, v, a).0
        })
    });
    g.bench_function("rust_paper_separate", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            paper::inverse_dynamics_separate(x, v, a).0
        })
    });
    g.bench_function("c_paper", |b| {
        b.iter(|| {
            i = (i + 1) % s.len();
            let (x, v, a) = black_box(&s[i]);
            let (mut gamma, mut r) = ([0.0; 6], [0.0; 3]);
            unsafe {
                native::native_paper_inverse_dynamics(
                    x.as_ptr(),
                    v.as_ptr(),
                    a.as_ptr(),
                    gamma.as_mut_ptr(),
                    r.as_mut_ptr(),
                )
            };
            gamma
        })
    });
    for (name, kernel) in [
        (
            "sympy_consistent",
            native::sympy_consistent_inverse_dynamics
                as unsafe extern "C" fn(*const f64, *const f64, *const f64, *mut f64),
        ),
        ("sympy_paper", native::sympy_paper_inverse_dynamics),
        (
            "sympy_paper_by_legs",
            native::sympy_paper_by_legs_inverse_dynamics,
        ),
        (
            "sympy_gnu_consistent",
            native::sympy_gnu_consistent_inverse_dynamics,
        ),
        ("sympy_gnu_paper", native::sympy_gnu_paper_inverse_dynamics),
        (
            "sympy_gnu_paper_by_legs",
            native::sympy_gnu_paper_by_legs_inverse_dynamics,
        ),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) % s.len();
                let (x, v, a) = black_box(&s[i]);
                let mut gamma = [0.0; 6];
                unsafe { kernel(x.as_ptr(), v.as_ptr(), a.as_ptr(), gamma.as_mut_ptr()) };
                gamma
            })
        });
    }
    g.finish();
}

criterion_group!(benches, inverse_dynamics);
criterion_main!(benches);
