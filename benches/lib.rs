//! The workspace's criterion benches (`cargo bench --bench inverse_dynamics`, `gough_stewart`,
//! `c_vs_rust`; docs/speed.md). This library is empty: cargo needs one target that is not a
//! bench, and this one has no tests, so `cargo test` leaves the package alone.
