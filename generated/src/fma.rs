//! Whether the `f64` kernels run their FMA twins: where the CPU has fused multiply-add and AVX2
//! (x86, detected once) and the `fma` feature is on, unless [`set_enabled`]`(false)` said
//! otherwise.
//!
//! The twins fold each product that only a sum reads into it (one rounding instead of two),
//! the same products in the single kernels, their batch lanes and the C output's `fma` path, so
//! every path is bit-exact against itself; the fused and separate paths differ by a few units in
//! the last place. The separate path computes the same bits on every machine.

#[cfg(all(feature = "fma", any(target_arch = "x86", target_arch = "x86_64")))]
mod switch {
    use core::sync::atomic::{AtomicU8, Ordering};

    const UNKNOWN: u8 = 0;
    const ON: u8 = 1;
    const OFF: u8 = 2;

    static STATE: AtomicU8 = AtomicU8::new(UNKNOWN);

    pub fn available() -> bool {
        // AVX2 too: the batch kernels' FMA lanes are compiled for both (every x86 core with
        // FMA has had AVX2 since 2015), so no third instantiation is needed for the few without.
        std::is_x86_feature_detected!("fma") && std::is_x86_feature_detected!("avx2")
    }

    #[inline]
    pub fn enabled() -> bool {
        match STATE.load(Ordering::Relaxed) {
            ON => true,
            OFF => false,
            _ => {
                let on = available();
                // A racing `set_enabled` wins: only the undecided state is replaced.
                let _ = STATE.compare_exchange(
                    UNKNOWN,
                    if on { ON } else { OFF },
                    Ordering::Relaxed,
                    Ordering::Relaxed,
                );
                STATE.load(Ordering::Relaxed) == ON
            }
        }
    }

    pub fn set_enabled(yes: bool) -> bool {
        let on = yes && available();
        STATE.store(if on { ON } else { OFF }, Ordering::Relaxed);
        on
    }
}

#[cfg(not(all(feature = "fma", any(target_arch = "x86", target_arch = "x86_64"))))]
mod switch {
    pub fn available() -> bool {
        false
    }

    #[inline]
    pub fn enabled() -> bool {
        false
    }

    pub fn set_enabled(_yes: bool) -> bool {
        false
    }
}

/// Whether the kernels can take the FMA path here: the `fma` feature is on and the CPU (x86)
/// has fused multiply-add (and AVX2, which every x86 core with FMA since 2015 has).
pub fn available() -> bool {
    switch::available()
}

/// Whether the kernels take the FMA path: [`available`], unless [`set_enabled`] turned it off.
#[inline]
pub fn enabled() -> bool {
    switch::enabled()
}

/// Turns the FMA path on (where [`available`]) or off, for every kernel of the process, and
/// returns whether it is now on. Call it at start-up, before the kernels run on other threads:
/// a kernel running while the switch flips may take either path.
pub fn set_enabled(yes: bool) -> bool {
    switch::set_enabled(yes)
}

/// The marks of a kernel body written once for both paths (`c5_fma_twin`'s notation), as the
/// separate path reads them where the `fma` feature is off and `#[fma_twin]` does not expand
/// them: a folded product rounded where it is computed, and the sum that reads it rounded
/// again. With the feature on, `#[fma_twin]` writes the same arithmetic in place.
pub mod marks {
    use core::ops::{Add, Mul, Sub};

    /// `a·b`, a product that one sum alone reads.
    #[inline(always)]
    pub fn product<T: Mul<Output = T>>(a: T, b: T) -> T {
        a * b
    }

    /// The sums that read a folded product `p` (`self`).
    pub trait Folded: Copy + Add<Output = Self> + Sub<Output = Self> {
        /// `p + c`.
        #[inline(always)]
        fn plus(self, c: Self) -> Self {
            self + c
        }

        /// `c + p`.
        #[inline(always)]
        fn added_to(self, c: Self) -> Self {
            c + self
        }

        /// `p − c`.
        #[inline(always)]
        fn minus(self, c: Self) -> Self {
            self - c
        }

        /// `c − p`.
        #[inline(always)]
        fn subtracted_from(self, c: Self) -> Self {
            c - self
        }
    }

    impl<T: Copy + Add<Output = T> + Sub<Output = T>> Folded for T {}
}
