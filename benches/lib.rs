//! The workspace's criterion benches (`cargo bench --bench inverse_dynamics`, `gough_stewart`,
//! `c_vs_rust`; docs/speed.md), and what several of them share. The library uses nothing but
//! `core` and has no tests, so `cargo test` builds it in an instant and never compiles
//! criterion (docs/build-time.md).

/// The states, each its `[position, velocity, acceleration]` of `N` coordinates, four at a
/// time in the batch kernels' layout: lane `l` of every input the `l`-th state's. A remainder
/// of fewer than four is left out.
pub fn lanes<const N: usize>(states: &[[[f64; N]; 3]]) -> Vec<[[[f64; 4]; N]; 3]> {
    states
        .chunks_exact(4)
        .map(|four| {
            core::array::from_fn(|j| {
                core::array::from_fn(|e| core::array::from_fn(|l| four[l][j][e]))
            })
        })
        .collect()
}
