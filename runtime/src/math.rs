//! The few elementary functions the runtime needs, from `std` or, without it, from `libm`.

#[cfg(feature = "std")]
mod imp {
    pub fn sin_cos(x: f64) -> (f64, f64) {
        x.sin_cos()
    }
    pub fn sqrt(x: f64) -> f64 {
        x.sqrt()
    }
    pub fn atan2(y: f64, x: f64) -> f64 {
        y.atan2(x)
    }
    pub fn asin(x: f64) -> f64 {
        x.asin()
    }
    pub fn acos(x: f64) -> f64 {
        x.acos()
    }
    pub fn exp(x: f64) -> f64 {
        x.exp()
    }
    pub fn round(x: f64) -> f64 {
        x.round()
    }
}

#[cfg(all(not(feature = "std"), feature = "libm"))]
mod imp {
    pub fn sin_cos(x: f64) -> (f64, f64) {
        (libm::sin(x), libm::cos(x))
    }
    pub fn sqrt(x: f64) -> f64 {
        libm::sqrt(x)
    }
    pub fn atan2(y: f64, x: f64) -> f64 {
        libm::atan2(y, x)
    }
    pub fn asin(x: f64) -> f64 {
        libm::asin(x)
    }
    pub fn acos(x: f64) -> f64 {
        libm::acos(x)
    }
    pub fn exp(x: f64) -> f64 {
        libm::exp(x)
    }
    pub fn round(x: f64) -> f64 {
        libm::round(x)
    }
}

pub use imp::*;
