//! The matrix-form reference, written with `nalgebra` straight from the chapter (the paper
//! model, [`paper`], whose items are re-exported here) and from docs/models.md (the consistent
//! model, [`consistent`]), and the Gough-Stewart platform leg by leg ([`gough_stewart`]).
//!
//! Each is deliberately independent of the generator's symbolic model, so the two can check
//! each other.

pub mod consistent;
pub mod gough_stewart;
pub mod paper;

pub use paper::*;
