//! The C output of `c5-codegen`, compiled and linked, beside the Rust kernels: `ffi::KERNELS`
//! lists every kernel of both models in both precisions with its C function and its Rust
//! kernel, each as `fn(&[f64]) -> Vec<f64>` over flattened inputs and outputs.

// The sine, cosine and arc tangent of the Rust kernels, for the C kernels of the test build
// (`build.rs`); the square root is correctly rounded in both languages.
#[no_mangle]
extern "C" fn c5_test_sin(x: f64) -> f64 {
    c5_generated::trig::sin(x)
}
#[no_mangle]
extern "C" fn c5_test_cos(x: f64) -> f64 {
    c5_generated::trig::cos(x)
}
#[no_mangle]
extern "C" fn c5_test_sinf(x: f32) -> f32 {
    c5_generated::trig::sin(x)
}
#[no_mangle]
extern "C" fn c5_test_cosf(x: f32) -> f32 {
    c5_generated::trig::cos(x)
}
#[no_mangle]
extern "C" fn c5_test_atan(x: f64) -> f64 {
    c5_generated::trig::atan(x)
}
#[no_mangle]
extern "C" fn c5_test_atanf(x: f32) -> f32 {
    c5_generated::trig::atan(x)
}

/// One kernel in both languages.
pub struct Kernel {
    pub model: &'static str,
    pub scalar: &'static str,
    /// `"separate"` or `"fused"` for `f64` kernels (their two arithmetic paths; the fused one
    /// runs only where `c5_generated::fma::available()`), `"only"` for `f32` kernels.
    pub path: &'static str,
    pub name: &'static str,
    /// The names of its inputs, in order.
    pub inputs: &'static [&'static str],
    pub c: fn(&[f64]) -> Vec<f64>,
    pub rust: fn(&[f64]) -> Vec<f64>,
}

/// Flattened values of a kernel's argument, as `f64`.
pub trait Flat {
    fn flat_into(&self, out: &mut Vec<f64>);
    fn from_flat(values: &[f64]) -> Self;
}

macro_rules! flat_impls {
    ($($t:ty),*) => {$(
        impl<const N: usize> Flat for [$t; N] {
            fn flat_into(&self, out: &mut Vec<f64>) {
                out.extend(self.iter().map(|&x| f64::from(x)));
            }
            fn from_flat(values: &[f64]) -> Self {
                std::array::from_fn(|i| values[i] as $t)
            }
        }
        impl<const R: usize, const C: usize> Flat for [[$t; C]; R] {
            fn flat_into(&self, out: &mut Vec<f64>) {
                out.extend(self.iter().flatten().map(|&x| f64::from(x)));
            }
            fn from_flat(values: &[f64]) -> Self {
                std::array::from_fn(|r| std::array::from_fn(|c| values[r * C + c] as $t))
            }
        }
    )*};
}

flat_impls!(f64, f32);

fn flat<T: Flat>(x: &T, out: &mut Vec<f64>) {
    x.flat_into(out);
}

fn unflat<T: Flat>(values: &[f64]) -> T {
    T::from_flat(values)
}

#[allow(clippy::all, unused)]
pub mod ffi {
    use super::{flat, unflat, Kernel};
    include!(concat!(env!("OUT_DIR"), "/ffi.rs"));
}

/// The bench's kernels: `-O3 -march=native`, as a user would build them for speed (`-std=c99`,
/// except the `sympy_gnu_*` build).
pub mod native {
    extern "C" {
        pub fn native_consistent_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
            r: *mut f64,
        );
        pub fn native_paper_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
            r: *mut f64,
        );
        /// The SymPy baseline (`sympy/generate.py`).
        pub fn sympy_consistent_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
        /// The SymPy baseline (`sympy/generate.py`).
        pub fn sympy_paper_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
        /// The SymPy baseline of the paper model leg by leg, as the chapter computes it.
        pub fn sympy_paper_by_legs_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
        /// The SymPy baseline built in GCC's default GNU mode (`a * b + c` contracted into
        /// fused multiply-adds).
        pub fn sympy_gnu_consistent_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
        /// The SymPy baseline built in GCC's default GNU mode.
        pub fn sympy_gnu_paper_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
        /// The chapter's leg-by-leg SymPy baseline built in GCC's default GNU mode.
        pub fn sympy_gnu_paper_by_legs_inverse_dynamics(
            pose: *const f64,
            twist: *const f64,
            accel: *const f64,
            gamma: *mut f64,
        );
    }
}
