//! Generated kinematics and inverse dynamics kernels of the default C5 joint parallel robot.
//!
//! Straight-line code, no allocation, no panics, no branches, no dependencies; `no_std` with
//! the `libm` feature. Two models, one module each, the same kernel names and arguments:
//!
//! - [`f64::consistent`]: the mechanism eq 16 describes (the plates slide in the platform plane
//!   of normal `m_i = R e_k`): rates and accelerations are the exact derivatives of eq 16 and the
//!   forces close the power balance. Use this one to command a robot.
//! - [`f64::paper`]: the chapter as published (eq 22's `J⁻¹`, the projection of eqs 43-48,
//!   Khalil's model), right only at zero orientation; it also holds the chapter-setting kernels
//!   (`pi1`, `jacobian`, `step6_factored`, ... with the vectors `P_i2` as inputs).
//!
//! With the feature `regressor`, each `f64` model also has its identification kernels:
//! `regressor` (`Γ = Y π` over the 142 standard parameters, named in `STANDARD_PARAMETERS`),
//! `base_regressor` (`Γ = Y_b β` over the base parameters, named in `BASE_PARAMETERS`, with
//! `BASE_RELATIONS` and `BASE_OF_STANDARD` saying what each groups), for any robot of the
//! family (geometry and gravity are their `params`).
//!
//! `f32` (feature `f32`) holds the same kernels in single precision. With the feature `batch`,
//! `inverse_dynamics` and `forward_dynamics` also come in batch form (`_x4` in `f64`, `_x8` in
//! `f32`): several states at once, in structure-of-arrays form, each lane computing exactly what
//! the single-state kernel computes, in AVX2 instructions where the CPU has them (with `std`).
//! With the feature `fma` (it needs `std`), every `f64` kernel has an FMA twin: `{kernel}_fused`
//! folds the products a sum reads once into it (`mul_add`, one rounding instead of two),
//! `{kernel}_separate` rounds every operation on its own, and `{kernel}` runs the fused twin
//! where the CPU has FMA (x86, checked once at run time), so do the batch kernels' lanes. The
//! twins agree to a few units in the last place; [`fma::set_enabled`]`(false)` makes every
//! kernel of the process take the separate path, the same bits on every machine. Each body is
//! written once, as `{kernel}_separate` with its folded products marked, and its
//! `#[fma_twin]` attribute (`c5-fma-twin-macro`) writes both paths from it; without `fma` the
//! marks are [`fma::marks`]' plain functions.
//! Trigonometry comes from the standard library (`std`, the default) or from `libm` (feature
//! `libm`, also without `std`; its `sincos` is twice as fast as the standard library's pair of
//! calls); an `f64` sine-cosine pair within an eighth of a turn is computed inline (`eighth_turn`). The files under `src/f64`,
//! `src/f32`, `ops.json` and `OPS.md` are written by `cargo run -p c5-codegen -- generate`;
//! a test fails when they are stale.
//!
//! Conventions: pose `[α β γ xc yc zc]` (RPY, eq 15, `R = Rx(α) Ry(β) Rz(γ)`), twist `(ω; v_C)`,
//! classical acceleration `(ω̇; a_C)`, wrenches moment first, base frame, SI units; actuators in
//! segment order 1..6, `Q_i1` the position of the ball centre along the actuator axis
//! (`B_i = A_i + Q_i1 n_i`, zero at the home pose, negative on the far side of `A_i`), and a
//! positive force `Γ_i` pushes the rod along `+n_i`. Kernels named `*_params` take the robot's
//! parameters as their last argument (`c5_robot::Robot::kernel_parameters`: each body's first
//! moment `m c` and inertia about its reference point); the others
//! have the chapter's robot folded in. Kernels that divide by `r11`, `r22`, `r33` (eq 16)
//! return them as their last result: check them before trusting the others.
//!
//! # Example
//!
//! ```
//! use c5_generated::f64::consistent as k;
//!
//! // At rest, 10°/15°/20° of roll, pitch and yaw, centre at the origin.
//! let pose = [10f64.to_radians(), 15f64.to_radians(), 20f64.to_radians(), 0.0, 0.0, 0.0];
//! let (gamma, r) = k::inverse_dynamics(&pose, &[0.0; 6], &[0.0; 6]);
//! assert!(r.iter().all(|d| d.abs() > 1e-9), "not singular");
//! // The vertical actuators carry most of the weight; the others are loaded too once the
//! // platform is turned.
//! assert!((gamma[4] - 80.39).abs() < 0.01 && (gamma[0] + 8.02).abs() < 0.01);
//! ```

#![cfg_attr(not(feature = "std"), no_std)]

pub mod eighth_turn;
pub mod fma;
pub mod guard;
pub mod legged;
#[cfg(feature = "batch")]
mod sincos;

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("c5-generated needs sin and cos: enable the `std` feature or the `libm` feature");

/// The elementary functions the kernels call: from `libm` when its feature is on (its `sincos`
/// computes a sine and a cosine in about the time the standard library takes for one of them),
/// else from the standard library; except the `f64` sine-cosine pair within `π/4`, inline
/// ([`crate::eighth_turn`], equal to `libm::sincos` there bit for bit). Public so that code compiled
/// elsewhere (the C output, in its test) can use exactly the same ones.
pub mod trig {
    /// `f64` and `f32`.
    pub trait Elementary: Copy {
        fn sin_(self) -> Self;
        fn cos_(self) -> Self;
        fn sqrt_(self) -> Self;
        fn atan_(self) -> Self;
        fn sin_cos_(self) -> (Self, Self);
    }

    macro_rules! elementary {
        ($t:ty, $sin:ident, $cos:ident, $sqrt:ident, $atan:ident, $sincos:ident) => {
            impl Elementary for $t {
                #[cfg(feature = "libm")]
                #[inline(always)]
                fn atan_(self) -> Self {
                    libm::$atan(self)
                }
                #[cfg(not(feature = "libm"))]
                #[inline(always)]
                fn atan_(self) -> Self {
                    self.atan()
                }
                #[cfg(feature = "libm")]
                #[inline(always)]
                fn sin_(self) -> Self {
                    libm::$sin(self)
                }
                #[cfg(feature = "libm")]
                #[inline(always)]
                fn cos_(self) -> Self {
                    libm::$cos(self)
                }
                #[cfg(feature = "libm")]
                #[inline(always)]
                fn sqrt_(self) -> Self {
                    libm::$sqrt(self)
                }
                #[cfg(feature = "libm")]
                #[inline(always)]
                fn sin_cos_(self) -> (Self, Self) {
                    $sincos(self)
                }
                #[cfg(not(feature = "libm"))]
                #[inline(always)]
                fn sin_(self) -> Self {
                    self.sin()
                }
                #[cfg(not(feature = "libm"))]
                #[inline(always)]
                fn cos_(self) -> Self {
                    self.cos()
                }
                #[cfg(not(feature = "libm"))]
                #[inline(always)]
                fn sqrt_(self) -> Self {
                    self.sqrt()
                }
                #[cfg(not(feature = "libm"))]
                #[inline(always)]
                fn sin_cos_(self) -> (Self, Self) {
                    $sincos(self)
                }
            }
        };
    }

    elementary!(f64, sin, cos, sqrt, atan, sin_cos_f64);

    /// `(sin x, cos x)` of `f64`: inline within `π/4` ([`crate::eighth_turn`]), the library's beyond.
    #[inline(always)]
    fn sin_cos_f64(x: f64) -> (f64, f64) {
        if x.abs() <= crate::eighth_turn::RANGE {
            crate::eighth_turn::sin_cos(x)
        } else {
            beyond_an_eighth_turn(x)
        }
    }

    #[cfg(feature = "libm")]
    #[inline(never)]
    fn beyond_an_eighth_turn(x: f64) -> (f64, f64) {
        libm::sincos(x)
    }

    #[cfg(not(feature = "libm"))]
    #[inline(never)]
    fn beyond_an_eighth_turn(x: f64) -> (f64, f64) {
        x.sin_cos()
    }

    elementary!(f32, sinf, cosf, sqrtf, atanf, sin_cos_f32);

    #[cfg(feature = "libm")]
    #[inline(always)]
    fn sin_cos_f32(x: f32) -> (f32, f32) {
        libm::sincosf(x)
    }

    #[cfg(not(feature = "libm"))]
    #[inline(always)]
    fn sin_cos_f32(x: f32) -> (f32, f32) {
        x.sin_cos()
    }

    /// `sin x`.
    #[inline(always)]
    pub fn sin<T: Elementary>(x: T) -> T {
        x.sin_()
    }
    /// `cos x`.
    #[inline(always)]
    pub fn cos<T: Elementary>(x: T) -> T {
        x.cos_()
    }
    /// `√x`.
    #[inline(always)]
    pub fn sqrt<T: Elementary>(x: T) -> T {
        x.sqrt_()
    }
    /// `atan x`.
    #[inline(always)]
    pub fn atan<T: Elementary>(x: T) -> T {
        x.atan_()
    }
    /// `(sin x, cos x)`, equal to `(sin(x), cos(x))` bit for bit.
    #[inline(always)]
    pub fn sin_cos<T: Elementary>(x: T) -> (T, T) {
        x.sin_cos_()
    }
}

/// The lane types of the batch kernels: a value per state, every operation lane by lane (LLVM
/// turns them into vector instructions) and rounded as in the single-state kernel, the
/// elementary functions those of [`trig`] (the `f64` sine-cosine pairs within an eighth of a turn
/// four lanes at once), so a lane computes exactly what the single-state kernel does.
#[cfg(feature = "batch")]
pub mod lanes {
    use core::ops::{Add, Div, Mul, Neg, Sub};

    macro_rules! lanes {
        ($name:ident, $t:ty, $n:literal) => {
            #[doc = concat!("`", stringify!($n), "` values of `", stringify!($t), "`, one per state.")]
            // Aligned to the vector width: the batch kernels keep one in memory so that LLVM
            // aligns their frames, and with them the lane vectors they spill.
            #[derive(Clone, Copy, Debug, PartialEq)]
            #[repr(C, align(32))]
            pub struct $name(pub [$t; $n]);

            impl $name {
                /// The same value in every lane.
                #[inline(always)]
                pub fn splat(x: $t) -> Self {
                    $name([x; $n])
                }
                #[inline(always)]
                pub fn sin(self) -> Self {
                    $name(self.0.map(crate::trig::sin))
                }
                #[inline(always)]
                pub fn cos(self) -> Self {
                    $name(self.0.map(crate::trig::cos))
                }
                #[inline(always)]
                pub fn sqrt(self) -> Self {
                    $name(self.0.map(crate::trig::sqrt))
                }
                #[inline(always)]
                pub fn atan(self) -> Self {
                    $name(self.0.map(crate::trig::atan))
                }
                /// `-1`, `0` or `1`, lane by lane.
                #[inline(always)]
                pub fn sign(self) -> Self {
                    $name(self.0.map(|x| (i8::from(x > 0.0) - i8::from(x < 0.0)) as $t))
                }
            }

            lanes!(@op $name, Add, add, +);
            lanes!(@op $name, Sub, sub, -);
            lanes!(@op $name, Mul, mul, *);
            lanes!(@op $name, Div, div, /);

            impl Neg for $name {
                type Output = Self;
                #[inline(always)]
                fn neg(self) -> Self {
                    $name(self.0.map(|x| -x))
                }
            }
        };
        (@op $name:ident, $trait:ident, $method:ident, $op:tt) => {
            impl $trait for $name {
                type Output = Self;
                #[inline(always)]
                fn $method(self, rhs: Self) -> Self {
                    $name(core::array::from_fn(|l| self.0[l] $op rhs.0[l]))
                }
            }
        };
    }

    lanes!(F64x4, f64, 4);
    lanes!(F32x8, f32, 8);

    impl F64x4 {
        /// `a·b + c` lane by lane with one rounding (`f64::mul_add`): the FMA twins' lanes, one
        /// `vfmadd` on x86-64 (left to the vectoriser, a lane-by-lane `mul_add` came out
        /// partly scalar and made the paper model's batch inverse dynamics 30 % slower).
        ///
        /// # Safety
        /// The CPU must have FMA (`is_x86_feature_detected!("fma")`), and the caller is
        /// compiled with it (`#[target_feature(enable = "fma")]`) for this to inline.
        #[cfg(feature = "fma")]
        #[inline(always)]
        pub unsafe fn mul_add(a: Self, b: Self, c: Self) -> Self {
            #[cfg(target_arch = "x86_64")]
            {
                use core::arch::x86_64::{__m256d, _mm256_fmadd_pd};
                // SAFETY: `F64x4` is 32 aligned bytes of four `f64`, as `__m256d`; the caller
                // guarantees FMA (and with it AVX).
                unsafe {
                    let [a, b, c] = [a, b, c].map(|v| core::mem::transmute::<Self, __m256d>(v));
                    core::mem::transmute::<__m256d, Self>(_mm256_fmadd_pd(a, b, c))
                }
            }
            #[cfg(not(target_arch = "x86_64"))]
            F64x4(core::array::from_fn(|l| a.0[l].mul_add(b.0[l], c.0[l])))
        }

        /// `(sin, cos)` of the four lanes, each equal to [`crate::trig::sin_cos`] of it; in
        /// vector instructions when all four are within an eighth of a turn.
        #[inline(always)]
        pub fn sin_cos(self) -> (Self, Self) {
            crate::sincos::sin_cos_lanes(self)
        }

        /// Whether all four lanes lie within an eighth of a turn, where
        /// [`F64x4::sin_cos_eighth_turn`] is the library's sine and cosine.
        #[inline(always)]
        pub fn within_eighth_turn(self) -> bool {
            crate::sincos::within_eighth_turn(self)
        }

        /// `(sin, cos)` of four lanes [`F64x4::within_eighth_turn`], in vector instructions,
        /// each equal to [`crate::trig::sin_cos`] of it (only there).
        #[inline(always)]
        pub fn sin_cos_eighth_turn(self) -> (Self, Self) {
            crate::sincos::sin_cos_eighth_turn(self)
        }
    }

    impl F32x8 {
        /// `(sin, cos)` lane by lane, the library's.
        #[inline(always)]
        pub fn sin_cos(self) -> (Self, Self) {
            let (mut s, mut c) = ([0.0; 8], [0.0; 8]);
            for l in 0..8 {
                (s[l], c[l]) = crate::trig::sin_cos(self.0[l]);
            }
            (F32x8(s), F32x8(c))
        }
    }
}

#[rustfmt::skip]
pub mod f64;

#[cfg(feature = "f32")]
#[rustfmt::skip]
pub mod f32;

include!("parameters.rs");

/// The operation-count manifest written with the kernels (`ops.json` as constants): every
/// kernel's counted operations, for the audit and the operation budget.
pub mod manifest {
    /// The chapter's published count (a division counted as a multiplication).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct ChapterCount {
        pub m: u32,
        pub a: u32,
    }

    /// A kernel's counted operations.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Count {
        pub mul: u32,
        pub div: u32,
        /// Additions and subtractions.
        pub add: u32,
        pub neg: u32,
        /// Calls to elementary functions, by name (`sin_cos` computes a pair).
        pub calls: &'static [(&'static str, u32)],
    }

    impl Count {
        /// The chapter's `m`: multiplications and divisions.
        pub const fn chapter_m(&self) -> u32 {
            self.mul + self.div
        }
        /// The chapter's `a`: additions and subtractions.
        pub const fn chapter_a(&self) -> u32 {
            self.add
        }
    }

    /// One generated kernel.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Entry {
        /// What it computes.
        pub kernel: Kernel,
        /// Whether the robot's parameters are its `params` argument (`*_params`).
        pub parameters: bool,
        /// The function's name.
        pub name: &'static str,
        /// The model whose equations it computes (`consistent`, `paper`).
        pub model: &'static str,
        /// `chapter` (the vectors `P_i2` as inputs, the chapter's setting) or `pose` (from the
        /// platform state, end to end).
        pub setting: &'static str,
        /// The chapter's equations (or the consistent model's, docs/models.md) it computes.
        pub equations: &'static [&'static str],
        pub count: Count,
        pub chapter: Option<ChapterCount>,
    }

    include!("manifest.rs");

    /// The entry of `model`'s `kernel`, folded or with the robot's parameters as inputs.
    pub fn entry(model: &str, kernel: Kernel, parameters: bool) -> Option<&'static Entry> {
        KERNELS
            .iter()
            .find(|e| e.model == model && e.kernel == kernel && e.parameters == parameters)
    }
}
