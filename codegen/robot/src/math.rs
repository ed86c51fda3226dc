//! The elementary functions the description's checks need: the standard library's, or
//! `libm`'s without it.

/// `√x`.
pub fn sqrt(x: f64) -> f64 {
    #[cfg(feature = "std")]
    return x.sqrt();
    #[cfg(not(feature = "std"))]
    return libm::sqrt(x);
}

/// `(sin x, cos x)`.
pub fn sin_cos(x: f64) -> (f64, f64) {
    #[cfg(feature = "std")]
    return x.sin_cos();
    #[cfg(not(feature = "std"))]
    return libm::sincos(x);
}

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("c5-robot needs square roots: enable the `std` feature or the `libm` feature");

/// `atan2(y, x)`.
pub fn atan2(y: f64, x: f64) -> f64 {
    #[cfg(feature = "std")]
    return y.atan2(x);
    #[cfg(not(feature = "std"))]
    return libm::atan2(y, x);
}
