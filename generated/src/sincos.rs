//! `sin` and `cos` of several arguments together, branch-free, so that four lanes run as
//! vector instructions and a batch kernel pays for about one library sine-cosine pair where it
//! paid for four.
//!
//! The algorithm is fdlibm's (as in musl and the `libm` crate): the argument is reduced by
//! `π/2` with a two-part Cody-Waite reduction (`π/2` to 118 bits), then `__sin` and `__cos`,
//! fdlibm's minimax polynomials on `[-π/4, π/4]` with the reduction's tail as a correction,
//! give both results of every quadrant; the quadrant picks and signs them. fdlibm branches on
//! the quadrant and on cancellation; here the quadrant is a select on the bits of the rounded
//! quotient, and the cancellation that makes fdlibm reduce a third time cannot occur below
//! [`FAST_RANGE`] (the nearest a double of `|x| ≤ 64` comes to a multiple of `π/2` leaves
//! about 60 bits after the 118-bit reduction). Batches with a larger or non-finite argument
//! go to the library lane by lane. Both results are within one unit in the last place of the
//! library's (tests compare them), so a batch lane agrees with the single-state kernel, which
//! calls the library, to about that.

/// Arguments of at most this magnitude (radians) take the branch-free path.
pub const FAST_RANGE: f64 = 64.0;

/// `1.5 · 2⁵²`: added to a value below `2⁵¹` it rounds it to an integer held in the low bits.
const TO_INT: f64 = 6_755_399_441_055_744.0;
/// `2/π`.
const INV_PIO2: f64 = f64::from_bits(0x3FE4_5F30_6DC9_C883);
/// The first 33 bits of `π/2`: its products with small integers are exact.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// The next 33 bits of `π/2`.
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000);
/// `π/2 − PIO2_1 − PIO2_2`.
const PIO2_2T: f64 = f64::from_bits(0x3BA3_198A_2E03_7073);

// fdlibm's `__sin` coefficients.
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);
// fdlibm's `__cos` coefficients.
const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

/// What the algorithm needs of a value: arithmetic, and a per-lane choice on the bits of the
/// rounded quotient (`f64`, or several lanes of it).
pub(crate) trait Lanes:
    Copy + core::ops::Add<Output = Self> + core::ops::Sub<Output = Self> + core::ops::Mul<Output = Self>
{
    fn splat(x: f64) -> Self;
    /// `a` where `bit` of `key`'s representation is set, else `b`, lane by lane.
    fn select(key: Self, bit: u64, a: Self, b: Self) -> Self;
    /// `x` negated where `bit` of `key`'s representation is set, lane by lane.
    fn negate_where(key: Self, bit: u64, x: Self) -> Self;
}

impl Lanes for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn select(key: Self, bit: u64, a: Self, b: Self) -> Self {
        // A mask, not a branch: the quadrant of a robot's angle is anything but predictable.
        let mask = 0u64.wrapping_sub(u64::from(key.to_bits() & bit != 0));
        f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
    }
    #[inline(always)]
    fn negate_where(key: Self, bit: u64, x: Self) -> Self {
        let sign = (key.to_bits() & bit) << (63 - bit.trailing_zeros());
        f64::from_bits(x.to_bits() ^ sign)
    }
}

/// `N` lanes of `f64`, every operation lane by lane (LLVM turns them into vector instructions).
#[derive(Clone, Copy)]
pub(crate) struct Wide<const N: usize>(pub [f64; N]);

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> core::ops::$trait for Wide<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                Wide(core::array::from_fn(|l| self.0[l] $op rhs.0[l]))
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);

impl<const N: usize> Lanes for Wide<N> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Wide([x; N])
    }
    #[inline(always)]
    fn select(key: Self, bit: u64, a: Self, b: Self) -> Self {
        Wide(core::array::from_fn(|l| {
            f64::select(key.0[l], bit, a.0[l], b.0[l])
        }))
    }
    #[inline(always)]
    fn negate_where(key: Self, bit: u64, x: Self) -> Self {
        Wide(core::array::from_fn(|l| {
            f64::negate_where(key.0[l], bit, x.0[l])
        }))
    }
}

/// `(sin x, cos x)` for `|x| ≤ FAST_RANGE`, lane by lane, without a branch.
#[inline(always)]
pub(crate) fn reduced<T: Lanes>(x: T) -> (T, T) {
    let k = T::splat;
    // `key` holds the quotient `n = rint(x · 2/π)` in its low bits, `n` is it as a value.
    let key = x * k(INV_PIO2) + k(TO_INT);
    let n = key - k(TO_INT);
    // x − n·π/2 = y0 + y1, to 118 bits of π/2 (fdlibm's second round).
    let r = x - n * k(PIO2_1);
    let w = n * k(PIO2_2);
    let t = r - w;
    let w = n * k(PIO2_2T) - ((r - t) - w);
    let y0 = t - w;
    let y1 = (t - y0) - w;
    // fdlibm's __sin(y0, y1, 1) and __cos(y0, y1).
    let z = y0 * y0;
    let zz = z * z;
    let rs = k(S2) + z * (k(S3) + z * k(S4)) + z * zz * (k(S5) + z * k(S6));
    let v = z * y0;
    let sine = y0 - ((z * (k(0.5) * y1 - v * rs) - y1) - v * k(S1));
    let rc = z * (k(C1) + z * (k(C2) + z * k(C3))) + zz * zz * (k(C4) + z * (k(C5) + z * k(C6)));
    let hz = k(0.5) * z;
    let one_minus_hz = k(1.0) - hz;
    let cosine = one_minus_hz + (((k(1.0) - one_minus_hz) - hz) + (z * rc - y0 * y1));
    // Quadrant n mod 4: sin is (s, c, −s, −c)[n], cos is (c, −s, −c, s)[n].
    let sin = T::negate_where(key, 2, T::select(key, 1, cosine, sine));
    let cos = T::negate_where(key + k(1.0), 2, T::select(key, 1, sine, cosine));
    (sin, cos)
}

/// `(sin x, cos x)` of `N` values at once.
#[inline(always)]
pub fn sin_cos_lanes<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    if x.iter().all(|v| v.abs() <= FAST_RANGE) {
        let (s, c) = reduced(Wide(x));
        (s.0, c.0)
    } else {
        outside_the_range(x)
    }
}

#[cold]
#[inline(never)]
fn outside_the_range<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    for l in 0..N {
        (s[l], c[l]) = crate::trig::sin_cos(x[l]);
    }
    (s, c)
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    /// Distance in units in the last place (of the larger magnitude).
    fn ulps(a: f64, b: f64) -> f64 {
        if a == b {
            return 0.0;
        }
        let scale = a.abs().max(b.abs());
        let ulp = f64::from_bits(scale.to_bits() + 1) - scale;
        (a - b).abs() / ulp
    }

    fn check(x: f64) {
        let (s, c) = reduced(x);
        let (es, ec) = (x.sin(), x.cos());
        assert!(ulps(s, es) <= 1.0, "sin({x:e}) = {s:e}, library {es:e}");
        assert!(ulps(c, ec) <= 1.0, "cos({x:e}) = {c:e}, library {ec:e}");
    }

    #[test]
    fn within_one_ulp_of_the_library_over_the_fast_range() {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        for _ in 0..1_000_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            check((2.0 * u - 1.0) * FAST_RANGE);
            check((2.0 * u - 1.0) * 4.0);
        }
    }

    #[test]
    fn within_one_ulp_next_to_the_multiples_of_half_pi_and_at_the_edges() {
        for n in -41_i32..=41 {
            let x = f64::from(n) * core::f64::consts::FRAC_PI_2;
            let mut y = x;
            for _ in 0..64 {
                check(y);
                y = y.next_up();
            }
            let mut y = x;
            for _ in 0..64 {
                check(y);
                y = y.next_down();
            }
        }
        for x in [
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            5e-324,
            1e-9,
            FAST_RANGE,
            -FAST_RANGE,
        ] {
            check(x);
        }
        assert_eq!(reduced(-0.0).0.to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn lanes_compute_the_scalar_bits_and_the_library_answers_outside_the_range() {
        let xs = [0.3, -2.0, 1e6, f64::NAN];
        let ys = [0.3, -2.0, 0.7, 63.9];
        let (s, c) = sin_cos_lanes(xs);
        let (s2, c2) = sin_cos_lanes(ys);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan();
        for l in 0..4 {
            let library = crate::trig::sin_cos(xs[l]);
            assert!(same(s[l], library.0) && same(c[l], library.1), "lane {l}");
            assert_eq!(s2[l].to_bits(), reduced(ys[l]).0.to_bits());
            assert_eq!(c2[l].to_bits(), reduced(ys[l]).1.to_bits());
        }
    }
}
