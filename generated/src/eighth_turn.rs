//! `sin` and `cos` of an argument within `π/4`, inline: fdlibm's kernel polynomials (`__sin`,
//! `__cos`), the arithmetic musl's `sincos` (and the `libm` crate, its port) does there, so the
//! results equal `libm::sincos`'s bit for bit. Robot angles mostly lie there; the kernels call
//! the library beyond (see [`crate::trig`]). Inline, a pair costs no call and overlaps with the
//! kernel's arithmetic (glibc's `sincos` took twice as long as `libm`'s here; see the README).

/// Arguments of at most this magnitude take the inline path.
pub const RANGE: f64 = core::f64::consts::FRAC_PI_4;

// fdlibm's `__sin` coefficients.
pub(crate) const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
pub(crate) const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
pub(crate) const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
pub(crate) const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
pub(crate) const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
pub(crate) const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);
// fdlibm's `__cos` coefficients.
pub(crate) const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
pub(crate) const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
pub(crate) const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
pub(crate) const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
pub(crate) const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
pub(crate) const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

/// What the kernel needs of a value (`f64`, or lanes of it).
pub(crate) trait Arith:
    Copy + core::ops::Add<Output = Self> + core::ops::Sub<Output = Self> + core::ops::Mul<Output = Self>
{
    fn splat(x: f64) -> Self;
    /// `a` where `z` is zero, else `b`, lane by lane.
    fn where_zero(z: Self, a: Self, b: Self) -> Self;
}

impl Arith for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn where_zero(z: Self, a: Self, b: Self) -> Self {
        if z == 0.0 {
            a
        } else {
            b
        }
    }
}

/// `(sin x, cos x)` for `|x| ≤ RANGE`, lane by lane (musl's `__sin(x, 0, 0)` and `__cos(x, 0)`).
#[inline(always)]
pub(crate) fn kernel<T: Arith>(x: T) -> (T, T) {
    let k = T::splat;
    let z = x * x;
    let w = z * z;
    let rs = k(S2) + z * (k(S3) + z * k(S4)) + z * w * (k(S5) + z * k(S6));
    let rc = z * (k(C1) + z * (k(C2) + z * k(C3))) + w * w * (k(C4) + z * (k(C5) + z * k(C6)));
    let hz = k(0.5) * z;
    let one_minus_hz = k(1.0) - hz;
    // musl returns a tiny argument as its own sine; the polynomial would turn −0 into +0.
    let sine = T::where_zero(z, x, x + z * x * (k(S1) + z * rs));
    (
        sine,
        one_minus_hz + (((k(1.0) - one_minus_hz) - hz) + z * rc),
    )
}

/// `(sin x, cos x)` for `|x| ≤ RANGE`.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    kernel(x)
}
