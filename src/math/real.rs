//! `Real`: the one number type of the simulation, I32F32 fixed point with a
//! defined result for every operation.
//!
//! # Arithmetic policy (see `docs/numerics.md`)
//! `fixed`'s own operators panic in debug builds and wrap in release builds on
//! overflow, and always panic on division by zero. A lockstep engine needs the
//! *same* bytes in both builds and no panic on any input, so every operator of
//! `Real` is explicit:
//!
//! * `+`, `-`, unary `-`, `abs`: **saturating** at `Real::MIN`/`Real::MAX`.
//! * `*`: exact 128-bit product, **rounded to nearest, ties away from zero**,
//!   then saturated. Rounding to nearest (instead of `fixed`'s floor) keeps a
//!   damped negative velocity from sticking at −1 ulp and makes mirrored scenes
//!   stay mirrored: `(-a) * b == -(a * b)` exactly.
//! * `/`: exact 128-bit quotient, rounded to nearest (ties away from zero),
//!   saturated. **Division by zero** gives `0` for `0 / 0` and the saturated
//!   value with the sign of the dividend otherwise (the limit of `a / ε`).
//! * `sqrt`: floor of the exact root (integer square root on 128 bits, full
//!   range); negative input gives `0`.
//! * `sin_cos`, `atan2`: defined in [`trig`](super::trig), beside the integer
//!   routines they call.
//!
//! Saturation is the only deviation from exact arithmetic, and it happens only
//! outside the documented safe envelope.
use core::cmp::Ordering;
use core::fmt;
use core::iter::Sum;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use fixed::types::I32F32;
use serde::{Deserialize, Serialize};

use super::exact::int::wide_mul;

/// Number of fractional bits of [`Real`].
pub const FRAC_BITS: u32 = 32;

/// I32F32 fixed-point number (range ±2^31, resolution 2^-32) with saturating,
/// round-to-nearest arithmetic that never panics.
///
/// Serialized as its raw `i64` bits, so snapshots are exact and portable.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Real(i64);

/// Error for a value that cannot become a [`Real`] at the API edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RealError {
    /// NaN or ±infinity.
    NotFinite,
    /// Finite, but outside `[Real::MIN, Real::MAX]`.
    OutOfRange,
}

impl fmt::Display for RealError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RealError::NotFinite => f.write_str("value is NaN or infinite"),
            RealError::OutOfRange => f.write_str("value is outside the I32F32 range ±2^31"),
        }
    }
}

impl std::error::Error for RealError {}

/// Saturates an `i128` raw value into the `i64` range of `Real`.
#[inline(always)]
const fn saturate(v: i128) -> i64 {
    if v > i64::MAX as i128 {
        i64::MAX
    } else if v < i64::MIN as i128 {
        i64::MIN
    } else {
        v as i64
    }
}

/// Shifts a 128-bit product right by [`FRAC_BITS`], rounding to nearest with
/// ties away from zero (symmetric under negation), and saturates to `i64`.
/// `p` must be at most 2^127 − 2^31 in magnitude: true for one product of
/// two `i64` (≤ 2^126); sums of products saturate before calling this.
#[inline(always)]
const fn round_shift_sat(p: i128) -> i64 {
    // Adding half minus one for negatives makes the arithmetic shift (a floor)
    // round ties away from zero on both sides.
    let half = 1i128 << (FRAC_BITS - 1);
    // No overflow: |p| ≤ 2^127 − 2^31 (precondition) and the bias is < 2^31.
    #[allow(clippy::arithmetic_side_effects)]
    let r = (p + half - (p < 0) as i128) >> FRAC_BITS;
    // r fits in i64 iff its upper 64 bits are the sign extension of the lower.
    let lo = r as i64;
    let hi = (r >> 64) as i64;
    if hi == (lo >> 63) {
        lo
    } else if hi < 0 {
        i64::MIN
    } else {
        i64::MAX
    }
}

/// True when `p` lies in `[−2^93, 2^93)` (its high word in `[−2^29, 2^29)`):
/// then `p` plus the rounding bias cannot wrap and the rounded quotient
/// fits `i64`, so [`round_in_range`] is exact. Far beyond any sum a scene
/// forms (results of `2^29` units); outside it the saturating path runs.
#[inline(always)]
const fn in_round_range(p: i128) -> bool {
    let hi = (p >> 64) as i64;
    (hi ^ (hi >> 63)) < (1 << 29)
}

/// [`round_shift_sat`] for `p` with [`in_round_range`]: the same bits
/// without the saturation tests (nothing can saturate).
#[inline(always)]
const fn round_in_range(p: i128) -> i64 {
    let bias = (1i128 << (FRAC_BITS - 1)).wrapping_sub((p < 0) as i128);
    (p.wrapping_add(bias) >> FRAC_BITS) as i64
}

/// Clamps a sum of products so that [`round_shift_sat`] may take it.
#[inline(always)]
const fn clamp_sum(p: i128) -> i128 {
    const LIM: i128 = i128::MAX - (1 << 32);
    if p > LIM {
        LIM
    } else if p < -LIM {
        -LIM
    } else {
        p
    }
}

/// Rounds `n / d` to nearest, ties away from zero; `d` must be non-zero.
// No overflow or panic: callers pass d ≠ 0 (checked before every call) and
// |n| < 2^127, so n_abs + d_abs/2 < 2^128 and q < 2^127 fits i128 (and −q).
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
const fn div_round(n: i128, d: i128) -> i128 {
    let (n_abs, d_abs) = (n.unsigned_abs(), d.unsigned_abs());
    let num = n_abs + d_abs / 2;
    // The same floor quotient in one 64-bit division where both fit 64
    // bits (d_abs ≤ num, or the quotient is 0 either way): the 128-bit
    // one is a library call, and on wasm32 a long division.
    let q = if num >> 64 == 0 && d_abs >> 64 == 0 {
        ((num as u64) / (d_abs as u64)) as u128
    } else {
        num / d_abs
    };
    // q < 2^127 because n_abs < 2^127 and d_abs >= 1.
    let q = q as i128;
    if (n < 0) != (d < 0) {
        -q
    } else {
        q
    }
}

impl Real {
    /// 0.
    pub const ZERO: Real = Real(0);
    /// 1.
    pub const ONE: Real = Real(1 << FRAC_BITS);
    /// 0.5.
    pub const HALF: Real = Real(1 << (FRAC_BITS - 1));
    /// 2.
    pub const TWO: Real = Real(2 << FRAC_BITS);
    /// The smallest positive value, 2^-32 (one ulp).
    pub const DELTA: Real = Real(1);
    /// The largest value, 2^31 − 2^-32.
    pub const MAX: Real = Real(i64::MAX);
    /// The smallest value, −2^31.
    pub const MIN: Real = Real(i64::MIN);
    /// π truncated to 32 fractional bits (`fixed`'s constant; 0.52 ulp below π).
    pub const PI: Real = Real(I32F32::PI.to_bits());
    /// 2π rounded to nearest.
    pub const TAU: Real = Real(I32F32::TAU.to_bits());
    /// π/2 rounded to nearest.
    pub const FRAC_PI_2: Real = Real(I32F32::FRAC_PI_2.to_bits());

    /// The value whose raw two's-complement bits are `bits` (value = bits · 2^-32).
    #[inline(always)]
    pub const fn from_bits(bits: i64) -> Real {
        Real(bits)
    }

    /// The raw bits (value · 2^32).
    #[inline(always)]
    pub const fn to_bits(self) -> i64 {
        self.0
    }

    /// An integer as a `Real` (exact: every `i32` is representable).
    #[inline(always)]
    pub const fn from_int(v: i32) -> Real {
        Real((v as i64) << FRAC_BITS)
    }

    /// `num / den` as a `Real`, rounded to nearest; `den == 0` follows the
    /// division policy. Handy for exact-ish constants such as `1/60`.
    #[inline]
    pub const fn ratio(num: i32, den: i32) -> Real {
        Real::from_int(num).div_const(Real::from_int(den))
    }

    /// Parses a decimal literal at compile time (use the [`real!`](crate::real)
    /// macro). Panics only in const evaluation, i.e. as a compile error.
    pub const fn lit(src: &str) -> Real {
        Real(I32F32::lit(src).to_bits())
    }

    /// The `fixed` value with the same bits.
    #[inline(always)]
    pub const fn to_fixed(self) -> I32F32 {
        I32F32::from_bits(self.0)
    }

    /// The `Real` with the same bits as a `fixed` value.
    #[inline(always)]
    pub const fn from_fixed(v: I32F32) -> Real {
        Real(v.to_bits())
    }

    /// Converts an `f64` at the API edge (setup, scene files), rounding to
    /// nearest, ties to even; NaN and ±∞ are [`RealError::NotFinite`],
    /// values outside ±2^31 [`RealError::OutOfRange`].
    ///
    /// Deterministic for the same `f64` *bits*: the conversion is exact
    /// integer work on the float's bits, so every platform and build makes
    /// the same `Real` of the same `f64`. The `f64` arithmetic done *before*
    /// it is not covered: transcendental functions (`sin`, `powf`, `exp`)
    /// differ between platform math libraries, and targets without SSE2
    /// (32-bit x86 on x87) round intermediate results differently. Feed it
    /// literals, parsed text or values sent over the network as bits, and do
    /// the arithmetic in `Real` (or use the [`real!`](crate::real) macro).
    pub fn from_f64(v: f64) -> Result<Real, RealError> {
        if !v.is_finite() {
            return Err(RealError::NotFinite);
        }
        I32F32::checked_from_num(v)
            .map(Real::from_fixed)
            .ok_or(RealError::OutOfRange)
    }

    /// Converts an `f32` at the API edge, rounding to nearest.
    pub fn from_f32(v: f32) -> Result<Real, RealError> {
        Real::from_f64(f64::from(v))
    }

    /// Converts to `f64` for rendering and reports (output only: the
    /// simulation never reads floats). Exact for |v| < 2^21 (53 significant
    /// bits); above, rounded to nearest (relative error ≤ 2^-53).
    pub fn to_f64(self) -> f64 {
        self.to_fixed().to_num::<f64>()
    }

    /// Converts to `f32` for rendering (output only), rounded to nearest
    /// (relative error ≤ 2^-24).
    pub fn to_f32(self) -> f32 {
        self.to_fixed().to_num::<f32>()
    }

    /// Saturating addition.
    #[inline(always)]
    pub const fn add_const(self, rhs: Real) -> Real {
        Real(self.0.saturating_add(rhs.0))
    }

    /// Saturating subtraction.
    #[inline(always)]
    pub const fn sub_const(self, rhs: Real) -> Real {
        Real(self.0.saturating_sub(rhs.0))
    }

    /// Round-to-nearest, saturating multiplication.
    #[inline(always)]
    pub const fn mul_const(self, rhs: Real) -> Real {
        Real(round_shift_sat(wide_mul(self.0, rhs.0)))
    }

    /// `self · rhs` rounded like `*` (nearest, ties away from zero) in one
    /// 64-bit multiply, for factors whose raw product is at most `2^62` in
    /// magnitude (one factor at most 1 and the other at most 1/4, say):
    /// then neither the product nor its rounding bias can wrap and nothing
    /// saturates, so the bits are those of `*` without its 128-bit product
    /// and saturation tests. Crate-private: the bound is the caller's
    /// promise, and a broken one would wrap silently.
    #[inline(always)]
    pub(crate) const fn mul_small(self, rhs: Real) -> Real {
        let p = self.0.wrapping_mul(rhs.0);
        let bias = (1i64 << (FRAC_BITS - 1)).wrapping_sub((p < 0) as i64);
        Real(p.wrapping_add(bias) >> FRAC_BITS)
    }

    /// Round-to-nearest, saturating division; see the module docs for `/ 0`.
    #[inline]
    pub const fn div_const(self, rhs: Real) -> Real {
        if rhs.0 == 0 {
            return match self.0.signum() {
                0 => Real::ZERO,
                1 => Real::MAX,
                _ => Real::MIN,
            };
        }
        Real(saturate(div_round(
            (self.0 as i128) << FRAC_BITS,
            rhs.0 as i128,
        )))
    }

    /// `a·b + c·d` with a single rounding (exact 128-bit accumulation).
    /// The building block of dot and cross products.
    #[inline(always)]
    pub const fn mul_add2(a: Real, b: Real, c: Real, d: Real) -> Real {
        let (p, q) = (wide_mul(a.0, b.0), wide_mul(c.0, d.0));
        // Each product lies in [−2^126 + 2^63, 2^126]: the wrapping sum is
        // exact except when both are 2^126, where it wraps to −2^127 and
        // fails the range test. So in range it is the exact sum.
        let sum = p.wrapping_add(q);
        if in_round_range(sum) {
            Real(round_in_range(sum))
        } else {
            Real(round_shift_sat(clamp_sum(p.saturating_add(q))))
        }
    }

    /// `a·b − c·d` with a single rounding.
    #[inline(always)]
    pub const fn mul_sub2(a: Real, b: Real, c: Real, d: Real) -> Real {
        let (p, q) = (wide_mul(a.0, b.0), wide_mul(c.0, d.0));
        // Both products lie in [−2^126 + 2^63, 2^126]: the difference never wraps.
        let diff = p.wrapping_sub(q);
        if in_round_range(diff) {
            Real(round_in_range(diff))
        } else {
            Real(round_shift_sat(clamp_sum(p.saturating_sub(q))))
        }
    }

    /// `x₀y₀ + x₁y₁ + x₂y₂ + x₃y₃` with a single rounding: the solver's
    /// relative velocity along a direction in one operation.
    #[inline(always)]
    pub const fn dot4(x: [Real; 4], y: [Real; 4]) -> Real {
        // Each product is below 2^126 in magnitude; saturating adds keep the
        // sum defined even in the (unphysical) case that it exceeds i128.
        let p0 = wide_mul(x[0].0, y[0].0);
        let p1 = wide_mul(x[1].0, y[1].0);
        let p2 = wide_mul(x[2].0, y[2].0);
        let p3 = wide_mul(x[3].0, y[3].0);
        // Fast path: each half sum wraps only at −2^127 (see `mul_add2`),
        // which fails the range test; two halves in range (below 2^93)
        // add exactly.
        let (h01, h23) = (p0.wrapping_add(p1), p2.wrapping_add(p3));
        if in_round_range(h01) && in_round_range(h23) {
            let sum = h01.wrapping_add(h23);
            if in_round_range(sum) {
                return Real(round_in_range(sum));
            }
        }
        let sum = p0.saturating_add(p1).saturating_add(p2).saturating_add(p3);
        Real(round_shift_sat(clamp_sum(sum)))
    }

    /// `self · num / den` with one rounding and no intermediate overflow.
    /// `den == 0` follows the division policy.
    #[inline]
    pub const fn mul_div(self, num: Real, den: Real) -> Real {
        if den.0 == 0 {
            return self.mul_const(num).div_const(Real::ZERO);
        }
        let p = wide_mul(self.0, num.0);
        // |p| < 2^126, so the quotient needs no shift: (a·2^32)(b·2^32)/(d·2^32).
        Real(saturate(div_round(p, den.0 as i128)))
    }

    /// Saturating absolute value (`abs(MIN) == MAX`).
    #[inline(always)]
    pub const fn abs(self) -> Real {
        Real(self.0.saturating_abs())
    }

    /// −1, 0 or 1.
    #[inline(always)]
    pub const fn signum(self) -> Real {
        Real::from_int(self.0.signum() as i32)
    }

    /// True for values below zero.
    #[inline(always)]
    pub const fn is_negative(self) -> bool {
        self.0 < 0
    }

    /// True for values above zero.
    #[inline(always)]
    pub const fn is_positive(self) -> bool {
        self.0 > 0
    }

    /// True for exactly zero.
    #[inline(always)]
    pub const fn is_zero(self) -> bool {
        self.0 == 0
    }

    /// True for `MIN` or `MAX`: the value may be the result of saturation.
    #[inline(always)]
    pub const fn is_saturated(self) -> bool {
        self.0 == i64::MAX || self.0 == i64::MIN
    }

    /// The smaller of the two.
    #[inline(always)]
    pub const fn min(self, other: Real) -> Real {
        if self.0 <= other.0 {
            self
        } else {
            other
        }
    }

    /// The larger of the two.
    #[inline(always)]
    pub const fn max(self, other: Real) -> Real {
        if self.0 >= other.0 {
            self
        } else {
            other
        }
    }

    /// Clamps into `[lo, hi]`; if `lo > hi`, `hi` wins (never panics).
    #[inline(always)]
    pub const fn clamp(self, lo: Real, hi: Real) -> Real {
        self.max(lo).min(hi)
    }

    /// Multiplies by `2^k` exactly (saturating); `k` in `0..=63`.
    #[inline(always)]
    pub const fn mul_pow2(self, k: u32) -> Real {
        Real(saturate((self.0 as i128) << (k & 63)))
    }

    /// The square: `self * self` (saturating above |x| ≈ 46,340).
    #[inline(always)]
    pub const fn square(self) -> Real {
        self.mul_const(self)
    }

    /// `1 / self` under the division policy.
    #[inline(always)]
    pub const fn recip(self) -> Real {
        Real::ONE.div_const(self)
    }

    /// Floor of the exact square root, over the whole range; negative input
    /// gives 0. Integer square root on 128 bits: deterministic everywhere.
    #[inline]
    pub const fn sqrt(self) -> Real {
        if self.0 <= 0 {
            return Real::ZERO;
        }
        // sqrt(v · 2^32) · 2^16 = sqrt(v · 2^64): the root of the raw bits
        // shifted by 32 is the raw root.
        let wide = (self.0 as u128) << FRAC_BITS;
        Real(wide.isqrt() as i64)
    }

    /// The floor as an integer-valued `Real`.
    #[inline(always)]
    pub const fn floor(self) -> Real {
        Real(self.0 & !((1i64 << FRAC_BITS) - 1))
    }

    /// The integer part toward −∞ as an `i64`.
    #[inline(always)]
    pub const fn floor_int(self) -> i64 {
        self.0 >> FRAC_BITS
    }
}

impl fmt::Debug for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.to_fixed(), f)
    }
}

impl fmt::Display for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.to_fixed(), f)
    }
}

impl From<i32> for Real {
    fn from(v: i32) -> Real {
        Real::from_int(v)
    }
}

impl From<I32F32> for Real {
    fn from(v: I32F32) -> Real {
        Real::from_fixed(v)
    }
}

impl From<Real> for I32F32 {
    fn from(v: Real) -> I32F32 {
        v.to_fixed()
    }
}

impl TryFrom<f64> for Real {
    type Error = RealError;
    fn try_from(v: f64) -> Result<Real, RealError> {
        Real::from_f64(v)
    }
}

impl TryFrom<f32> for Real {
    type Error = RealError;
    fn try_from(v: f32) -> Result<Real, RealError> {
        Real::from_f32(v)
    }
}

macro_rules! forward_binop {
    ($Trait:ident, $method:ident, $Assign:ident, $assign:ident, $impl_fn:ident) => {
        impl $Trait for Real {
            type Output = Real;
            #[inline(always)]
            fn $method(self, rhs: Real) -> Real {
                self.$impl_fn(rhs)
            }
        }
        impl $Assign for Real {
            #[inline(always)]
            fn $assign(&mut self, rhs: Real) {
                *self = self.$impl_fn(rhs);
            }
        }
    };
}

forward_binop!(Add, add, AddAssign, add_assign, add_const);
forward_binop!(Sub, sub, SubAssign, sub_assign, sub_const);
forward_binop!(Mul, mul, MulAssign, mul_assign, mul_const);
forward_binop!(Div, div, DivAssign, div_assign, div_const);

impl Neg for Real {
    type Output = Real;
    #[inline(always)]
    fn neg(self) -> Real {
        Real(self.0.saturating_neg())
    }
}

impl Sum for Real {
    fn sum<I: Iterator<Item = Real>>(iter: I) -> Real {
        iter.fold(Real::ZERO, |a, b| a + b)
    }
}

/// Compares by value; exists so generic code can use `partial_cmp` too.
pub fn cmp(a: Real, b: Real) -> Ordering {
    a.0.cmp(&b.0)
}

/// A `Real` from a decimal literal, parsed at compile time:
/// `real!(0.5)`, `real!(-9.81)`, `real!(1e-3)` is not supported (no exponent).
#[macro_export]
macro_rules! real {
    (- $lit:literal) => {{
        const R: $crate::Real = $crate::Real::lit(concat!("-", stringify!($lit)));
        R
    }};
    ($lit:literal) => {{
        const R: $crate::Real = $crate::Real::lit(stringify!($lit));
        R
    }};
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The sums of products as they were before their in-range fast path:
    /// saturating 128-bit sums, clamped, rounded with saturation.
    fn mul_add2_reference(a: Real, b: Real, c: Real, d: Real) -> Real {
        let p = wide_mul(a.0, b.0).saturating_add(wide_mul(c.0, d.0));
        Real(round_shift_sat(clamp_sum(p)))
    }
    fn mul_sub2_reference(a: Real, b: Real, c: Real, d: Real) -> Real {
        let p = wide_mul(a.0, b.0).saturating_sub(wide_mul(c.0, d.0));
        Real(round_shift_sat(clamp_sum(p)))
    }
    fn dot4_reference(x: [Real; 4], y: [Real; 4]) -> Real {
        let p = |i: usize| wide_mul(x[i].0, y[i].0);
        let sum = p(0)
            .saturating_add(p(1))
            .saturating_add(p(2))
            .saturating_add(p(3));
        Real(round_shift_sat(clamp_sum(sum)))
    }

    /// Raw values over the whole range: extremes, the edge of the fast
    /// range (products near 2^93), ties and small values.
    fn any_raw() -> impl Strategy<Value = i64> {
        prop_oneof![
            any::<i64>(),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| v >> s),
            (-64i64..64),
            (-8i64..8).prop_map(|k| k << 31),
            (-4i64..4).prop_map(|k| (1i64 << 46).wrapping_add(k)),
            (-4i64..4).prop_map(|k| (-1i64 << 46).wrapping_add(k)),
            Just(i64::MIN),
            Just(i64::MAX),
        ]
    }

    /// `div_round` as it was: one 128-bit division.
    #[allow(clippy::arithmetic_side_effects)]
    fn div_round_reference(n: i128, d: i128) -> i128 {
        let (n_abs, d_abs) = (n.unsigned_abs(), d.unsigned_abs());
        let q = ((n_abs + d_abs / 2) / d_abs) as i128;
        if (n < 0) != (d < 0) {
            -q
        } else {
            q
        }
    }

    proptest! {
        /// The 64-bit division path gives the 128-bit quotient: products
        /// of raw values over the whole range (`mul_div`'s numerators),
        /// shifted values (`div`'s), around 2^64.
        #[test]
        fn div_round_matches_the_128_bit_division(
            (a, b, d) in (any_raw(), any_raw(), any_raw()),
            shift in 0u32..64,
            near in -3i128..3,
        ) {
            let d = if d == 0 { 1 } else { d };
            for n in [
                wide_mul(a, b),
                i128::from(a) << shift,
                (1i128 << 64) + near,
                -(1i128 << 64) + near,
                (1i128 << 64) - i128::from(d.unsigned_abs() / 2) + near,
            ] {
                prop_assert_eq!(div_round(n, i128::from(d)), div_round_reference(n, i128::from(d)));
            }
        }

        #[test]
        fn sums_of_products_match_the_saturating_reference(
            v in proptest::array::uniform8(any_raw())
        ) {
            let [a, b, c, d, e, f, g, h] = v.map(Real::from_bits);
            prop_assert_eq!(Real::mul_add2(a, b, c, d), mul_add2_reference(a, b, c, d));
            prop_assert_eq!(Real::mul_sub2(a, b, c, d), mul_sub2_reference(a, b, c, d));
            let (x, y) = ([a, b, c, d], [e, f, g, h]);
            prop_assert_eq!(Real::dot4(x, y), dot4_reference(x, y));
            prop_assert_eq!(Real::dot4(x, x), dot4_reference(x, x));
        }
    }

    #[test]
    fn sums_of_products_at_the_edges() {
        let edges = [
            i64::MIN,
            i64::MIN + 1,
            i64::MAX,
            -(1 << 46),
            (1 << 46) - 1,
            1 << 46,
            -(1 << 31),
            1 << 31,
            -1,
            0,
            1,
        ]
        .map(Real::from_bits);
        for &a in &edges {
            for &b in &edges {
                for &c in &edges {
                    for &d in &edges {
                        assert_eq!(Real::mul_add2(a, b, c, d), mul_add2_reference(a, b, c, d));
                        assert_eq!(Real::mul_sub2(a, b, c, d), mul_sub2_reference(a, b, c, d));
                        let (x, y) = ([a, b, c, d], [d, c, b, a]);
                        assert_eq!(Real::dot4(x, y), dot4_reference(x, y));
                        let (x, y) = ([a, a, c, c], [b, b, d, d]);
                        assert_eq!(Real::dot4(x, y), dot4_reference(x, y));
                    }
                }
            }
        }
    }

    fn r(v: f64) -> Real {
        Real::from_f64(v).unwrap()
    }

    #[test]
    fn mul_rounds_to_nearest_and_is_symmetric() {
        let tiny = Real::DELTA;
        // 1 ulp · 0.5 = 0.5 ulp: ties away from zero.
        assert_eq!(tiny * Real::HALF, Real::DELTA);
        assert_eq!((-tiny) * Real::HALF, -Real::DELTA);
        // 1 ulp · 0.25 rounds to 0 on both sides (floor would give −1 ulp).
        let quarter = real!(0.25);
        assert_eq!(tiny * quarter, Real::ZERO);
        assert_eq!((-tiny) * quarter, Real::ZERO);
        let a = r(-3.75);
        let b = r(1.1);
        assert_eq!((-a) * b, -(a * b));
    }

    #[test]
    fn mul_saturates_instead_of_wrapping() {
        let big = Real::from_int(100_000);
        assert_eq!(big * big, Real::MAX);
        assert_eq!(big * -big, Real::MIN);
        assert_eq!(Real::MAX + Real::ONE, Real::MAX);
        assert_eq!(Real::MIN - Real::ONE, Real::MIN);
        assert_eq!(-Real::MIN, Real::MAX);
    }

    #[test]
    fn div_by_zero_is_defined() {
        assert_eq!(Real::ONE / Real::ZERO, Real::MAX);
        assert_eq!(-Real::ONE / Real::ZERO, Real::MIN);
        assert_eq!(Real::ZERO / Real::ZERO, Real::ZERO);
        assert_eq!(Real::MIN / -Real::DELTA, Real::MAX);
    }

    #[test]
    fn div_rounds_to_nearest() {
        assert_eq!(
            Real::ONE / Real::from_int(3),
            Real::from_bits(1_431_655_765)
        );
        assert_eq!(
            Real::TWO / Real::from_int(3),
            Real::from_bits(2_863_311_531)
        );
        assert_eq!(
            -Real::TWO / Real::from_int(3),
            Real::from_bits(-2_863_311_531)
        );
        assert_eq!(Real::ratio(1, 60), Real::from_bits(71_582_788));
    }

    #[test]
    fn sqrt_is_floor_of_exact_root_over_full_range() {
        assert_eq!(Real::from_int(4).sqrt(), Real::TWO);
        assert_eq!(Real::from_int(-4).sqrt(), Real::ZERO);
        assert_eq!(Real::MAX.sqrt(), Real::from_bits(199_032_864_766_430)); // √2^31 ≈ 46340.95
        assert_eq!(Real::DELTA.sqrt(), Real::from_bits(65_536));
        let two = Real::TWO.sqrt();
        assert!((two.to_f64() - 2f64.sqrt()).abs() < 2.4e-10);
    }

    #[test]
    fn literal_macro_parses_negative_and_fraction() {
        assert_eq!(real!(-0.5), -Real::HALF);
        assert_eq!(real!(2), Real::TWO);
        assert_eq!(real!(0.1), r(0.1));
    }

    #[test]
    fn conversions_reject_bad_floats() {
        assert_eq!(Real::from_f64(f64::NAN), Err(RealError::NotFinite));
        assert_eq!(Real::from_f64(f64::INFINITY), Err(RealError::NotFinite));
        assert_eq!(Real::from_f64(3e9), Err(RealError::OutOfRange));
        assert_eq!(Real::from_f32(-1.5), Ok(r(-1.5)));
    }

    #[test]
    fn mul_add2_rounds_once() {
        let a = Real::DELTA;
        // 0.5 ulp + 0.5 ulp = 1 ulp exactly; two roundings would give 2.
        assert_eq!(Real::mul_add2(a, Real::HALF, a, Real::HALF), Real::DELTA);
        assert_eq!(
            Real::mul_div(Real::from_int(3), Real::from_int(4), Real::from_int(6)),
            Real::TWO
        );
    }
}
