//! Every kernel of the C output, compiled with `-ffp-contract=off`, computes what the Rust
//! kernel computes (the same program), to the bit, on 10 000 inputs each, both models, both
//! precisions, and both arithmetic paths of the `f64` kernels: `{kernel}_separate` against the
//! C built as it comes, `{kernel}_fused` against the C built with `C5_FUSED_MULTIPLY_ADD`. The
//! C kernels are linked to the Rust kernels' sine and cosine (`build.rs`): the two programs are
//! compared, not two maths libraries.

mod support;

use c5_c_output_test::ffi::KERNELS;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use support::input;

const INPUTS: usize = 10_000;

#[test]
fn every_c_kernel_equals_its_rust_kernel() {
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let mut checked = 0;
    let fused = c5_generated::fma::available();
    for kernel in KERNELS.iter().filter(|k| fused || k.path != "fused") {
        for _ in 0..INPUTS {
            let pose: [f64; 6] = std::array::from_fn(|k| {
                rng.gen_range(if k < 3 { -0.5..=0.5 } else { -0.08..=0.08 })
            });
            let values: Vec<f64> = kernel
                .inputs
                .iter()
                .flat_map(|name| input(&mut rng, name, &pose))
                .collect();
            let (c, rust) = ((kernel.c)(&values), (kernel.rust)(&values));
            assert_eq!(c.len(), rust.len());
            // The same instructions on the same values: equal to the bit, not merely close (the
            // C kernel's instructions are in another order, `c5_codegen::schedule`).
            for (k, (a, b)) in c.iter().zip(&rust).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "{} {} {} ({}), output {k} at {values:?}: C {a:e}, Rust {b:e}",
                    kernel.model,
                    kernel.scalar,
                    kernel.name,
                    kernel.path
                );
            }
        }
        checked += 1;
    }
    // 13 pose-setting and 8 joint-setting kernels per model, 7 more for the paper model, two
    // precisions, and the FMA twins of the `f64` ones where the CPU has FMA.
    let per_precision = 21 + 21 + 7;
    assert_eq!(checked, if fused { 3 } else { 2 } * per_precision);
}
