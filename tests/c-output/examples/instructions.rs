//! Calls each inverse dynamics kernel 10 000 times, in one function per kernel, for
//! `valgrind --tool=callgrind`: instructions per call are repeatable where timings on a shared
//! machine are not.
//!
//! ```sh
//! cargo build --release -p c5-c-output-test --example instructions
//! valgrind --tool=callgrind --callgrind-out-file=cg.out target/release/examples/instructions
//! callgrind_annotate --inclusive=yes cg.out | grep run_
//! ```

use c5_c_output_test::native;
use c5_generated::f64::{consistent, paper};
use std::hint::black_box;

const CALLS: usize = 10_000;

type CKernel = unsafe extern "C" fn(*const f64, *const f64, *const f64, *mut f64, *mut f64);
type SympyKernel = unsafe extern "C" fn(*const f64, *const f64, *const f64, *mut f64);
type RustKernel = fn(&[f64; 6], &[f64; 6], &[f64; 6]) -> ([f64; 6], [f64; 3]);

fn inputs(k: usize) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let f = |j: usize| ((k * 7 + j) as f64 * 0.37).sin();
    (
        [
            0.4 * f(1),
            0.4 * f(2),
            0.4 * f(3),
            0.05 * f(4),
            0.05 * f(5),
            0.05 * f(6),
        ],
        [f(7), f(8), f(9), 0.3 * f(10), 0.3 * f(11), 0.3 * f(12)],
        [3.0 * f(13), 3.0 * f(14), 3.0 * f(15), f(16), f(17), f(18)],
    )
}

#[inline(never)]
fn run_rust(kernel: RustKernel) -> f64 {
    let mut sum = 0.0;
    for k in 0..CALLS {
        let (x, v, a) = inputs(k % 64);
        sum += kernel(black_box(&x), black_box(&v), black_box(&a)).0[0];
    }
    sum
}

#[inline(never)]
fn run_c(kernel: CKernel) -> f64 {
    let mut sum = 0.0;
    for k in 0..CALLS {
        let (x, v, a) = inputs(k % 64);
        let (mut g, mut r) = ([0.0; 6], [0.0; 3]);
        unsafe {
            kernel(
                x.as_ptr(),
                v.as_ptr(),
                a.as_ptr(),
                g.as_mut_ptr(),
                r.as_mut_ptr(),
            )
        };
        sum += g[0];
    }
    sum
}

#[inline(never)]
fn run_sympy(kernel: SympyKernel) -> f64 {
    let mut sum = 0.0;
    for k in 0..CALLS {
        let (x, v, a) = inputs(k % 64);
        let mut g = [0.0; 6];
        unsafe { kernel(x.as_ptr(), v.as_ptr(), a.as_ptr(), g.as_mut_ptr()) };
        sum += g[0];
    }
    sum
}

#[inline(never)]
fn run_inputs_only() -> f64 {
    let mut sum = 0.0;
    for k in 0..CALLS {
        let (x, v, a) = inputs(k % 64);
        sum += black_box(x[0] + v[0] + a[0]);
    }
    sum
}

#[inline(never)]
fn run_rust_consistent() -> f64 {
    run_rust(consistent::inverse_dynamics)
}
#[inline(never)]
fn run_rust_paper() -> f64 {
    run_rust(paper::inverse_dynamics)
}
#[inline(never)]
fn run_c_consistent() -> f64 {
    run_c(native::native_consistent_inverse_dynamics)
}
#[inline(never)]
fn run_c_paper() -> f64 {
    run_c(native::native_paper_inverse_dynamics)
}
#[inline(never)]
fn run_sympy_consistent() -> f64 {
    run_sympy(native::sympy_consistent_inverse_dynamics)
}
#[inline(never)]
fn run_sympy_paper() -> f64 {
    run_sympy(native::sympy_paper_inverse_dynamics)
}

fn main() {
    let total = run_inputs_only()
        + run_rust_consistent()
        + run_rust_paper()
        + run_c_consistent()
        + run_c_paper()
        + run_sympy_consistent()
        + run_sympy_paper();
    println!("{total}");
}
