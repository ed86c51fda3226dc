//! The `c5` program's package. The program is the binary target (`src/main.rs`); this library
//! holds no code. It exists so that the package's own tests can depend on the package with
//! every command built in (`[dev-dependencies] c5-cli = { path = ".", features = ["full"] }`):
//! a plain `cargo run --release -- simulate` builds neither the identification nor the
//! derivative kernels (docs/build-time.md), while `cargo test` runs the program with both.
