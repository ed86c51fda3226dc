//! The SymPy baseline of the bench computes the inverse dynamics our kernels compute, so the
//! comparison is between two ways of computing one thing; the chapter's leg-by-leg recursion,
//! written independently in SymPy, also checks the regrouped paper model.

use c5_c_output_test::native;
use c5_generated::f64::{consistent, paper};
use rand::{Rng, SeedableRng};

#[test]
fn the_sympy_baseline_computes_our_inverse_dynamics() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(52);
    let mut u = |b: f64| rng.gen_range(-b..=b);
    for _ in 0..10_000 {
        let x = [u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)];
        let v = [u(1.0), u(1.0), u(1.0), u(0.5), u(0.5), u(0.5)];
        let a = [u(5.0), u(5.0), u(5.0), u(2.0), u(2.0), u(2.0)];
        type Kernel = unsafe extern "C" fn(*const f64, *const f64, *const f64, *mut f64);
        let paper = paper::inverse_dynamics(&x, &v, &a).0;
        let cases: [(Kernel, [f64; 6]); 3] = [
            (
                native::sympy_consistent_inverse_dynamics,
                consistent::inverse_dynamics(&x, &v, &a).0,
            ),
            (native::sympy_paper_inverse_dynamics, paper),
            (native::sympy_paper_by_legs_inverse_dynamics, paper),
        ];
        for (sympy, want) in cases {
            let mut got = [0.0; 6];
            unsafe { sympy(x.as_ptr(), v.as_ptr(), a.as_ptr(), got.as_mut_ptr()) };
            let scale = want.iter().fold(1.0_f64, |m, w| m.max(w.abs()));
            for k in 0..6 {
                assert!(
                    (got[k] - want[k]).abs() < 1e-10 * scale,
                    "{got:?} vs {want:?}"
                );
            }
        }
    }
}
