//! Generated kinematics and inverse dynamics kernels of the default C5 joint parallel robot.
//!
//! Straight-line code, no allocation, no panics, no dependencies; `no_std` with the `libm`
//! feature. [`f64`] and [`f32`] hold the same kernels from the same model. The files `f64.rs`,
//! `f32.rs`, `ops.json` and `OPS.md` are written by `cargo run -p c5-codegen -- generate`;
//! a test fails when they are stale.
//!
//! Conventions: pose `[α β γ xc yc zc]` (RPY, eq 15), twist `(ω; v_C)`, classical acceleration
//! `(ω̇; a_C)`, wrenches moment first, actuators in segment order 1..6. Kernels named `*_params`
//! take the robot's parameters as their last argument (in the order of
//! `c5_codegen::Robot::flatten`); the others have the default robot folded in.

#![cfg_attr(not(feature = "std"), no_std)]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("c5-generated needs sin and cos: enable the `std` feature or the `libm` feature");

/// `sin`, `cos` and `sqrt` through `libm` where the standard library is absent.
#[cfg(all(not(feature = "std"), feature = "libm"))]
mod float {
    pub trait Float {
        fn sin(self) -> Self;
        fn cos(self) -> Self;
        fn sqrt(self) -> Self;
    }
    impl Float for f64 {
        fn sin(self) -> Self {
            libm::sin(self)
        }
        fn cos(self) -> Self {
            libm::cos(self)
        }
        fn sqrt(self) -> Self {
            libm::sqrt(self)
        }
    }
    impl Float for f32 {
        fn sin(self) -> Self {
            libm::sinf(self)
        }
        fn cos(self) -> Self {
            libm::cosf(self)
        }
        fn sqrt(self) -> Self {
            libm::sqrtf(self)
        }
    }
}

/// The kernels in `f64`.
#[rustfmt::skip]
#[allow(clippy::all, clippy::pedantic, clippy::nursery, unused_parens)]
pub mod f64 {
    #[cfg(all(not(feature = "std"), feature = "libm"))]
    use crate::float::Float;
    include!("f64.rs");
}

/// The kernels in `f32`, from the same model (constants rounded once to `f32`).
#[rustfmt::skip]
#[allow(clippy::all, clippy::pedantic, clippy::nursery, unused_parens)]
pub mod f32 {
    #[cfg(all(not(feature = "std"), feature = "libm"))]
    use crate::float::Float;
    include!("f32.rs");
}

/// The operation-count manifest written with the kernels.
pub const OPS_JSON: &str = include_str!("../ops.json");

/// Length of the parameter vector of the `*_params` kernels.
pub const PARAMETERS: usize = 152;
