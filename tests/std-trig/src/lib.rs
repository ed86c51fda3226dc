//! Nothing but its tests: the generated kernels built with `std` alone, whose sines and
//! cosines beyond π/4 and arc tangents come from the standard library, not from `libm` (the
//! runtime turns `libm` on, so every other test of the workspace runs the `libm` path).
