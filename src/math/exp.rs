//! Deterministic `log2`, `exp2` and `pow` on [`Real`], for the few settings
//! that are defined per second but applied per step (Chipmunk's
//! `damping^dt` and `1 − collision_bias^dt`). Called when `dt` changes, never
//! inside the step's loops.
//!
//! Method: bit-by-bit logarithm (square the mantissa, read off one bit of the
//! result per squaring) and bit-by-bit exponential (multiply the factors
//! `2^(2^-i)` of the set fraction bits). Both work on 62 fractional bits, so
//! the result is within 1–2 ulp of exact. The factor table is built at
//! compile time by repeated integer square roots of 2: no float, no table
//! typed by hand.
use super::real::{Real, FRAC_BITS};

/// Working precision (fractional bits).
const Q: u32 = 62;
const ONE_Q: u128 = 1 << Q;

/// `TABLE[i] = 2^(2^-i)` in Q62, for i = 0..=32 (`TABLE[0] = 2`).
const TABLE: [u128; 33] = build_table();

// Only called in const evaluation (`TABLE`): an out-of-range index or an
// overflow would fail the build, never run (and there is none: i in 1..33,
// each entry below 2^64 before the shift by 62).
#[allow(clippy::indexing_slicing, clippy::arithmetic_side_effects)]
const fn build_table() -> [u128; 33] {
    let mut t = [0u128; 33];
    t[0] = 2 << Q;
    let mut i = 1;
    while i < 33 {
        // sqrt(x · 2^62) · 2^31 = sqrt(x) in Q62 when x is in Q62.
        t[i] = (t[i - 1] << Q).isqrt();
        i += 1;
    }
    t
}

/// `log2(x)`; `x ≤ 0` gives `Real::MIN` (the limit towards 0).
// Integer ranges (raw in 1..2^63): msb in 0..=62, e in −32..=30, the
// mantissa m in [2^62, 2^63) so m·m < 2^126, Q − i in 28..=61, frac < 2^62,
// and (e << 32) + frac32 within ±2^38: no operation overflows.
#[allow(clippy::arithmetic_side_effects)]
pub fn log2(x: Real) -> Real {
    let raw = x.to_bits();
    if raw <= 0 {
        return Real::MIN;
    }
    let raw = raw as u64;
    // x = m · 2^e with m in [1, 2).
    let msb = 63 - raw.leading_zeros() as i64; // position of the top bit of raw
    let e = msb - FRAC_BITS as i64;
    // m in Q62.
    let mut m: u128 = (raw as u128) << (Q as i64 - msb) as u32;
    let mut frac: u128 = 0;
    for i in 1..=(FRAC_BITS + 2) {
        m = (m * m) >> Q;
        if m >= 2 * ONE_Q {
            m >>= 1;
            frac |= 1 << (Q - i);
        }
    }
    // frac is in Q62 with 34 significant bits: round to Q32.
    let frac32 = ((frac + (1 << (Q - FRAC_BITS - 1))) >> (Q - FRAC_BITS)) as i64;
    Real::from_bits((e << FRAC_BITS) + frac32)
}

/// `2^y`; saturates at `Real::MAX` for y ≥ 31 and rounds to 0 far below.
// Integer ranges (k in −40..=30 past the early returns): bit in 0..=31,
// acc < 2^63 and every factor < 2^63 so acc·factor < 2^126, shift in 0..=70
// so s − 1 is in 0..=69 and acc + 2^(s−1) < 2^70: no operation overflows.
#[allow(clippy::arithmetic_side_effects)]
pub fn exp2(y: Real) -> Real {
    let k = y.floor_int(); // integer part (toward −∞)
    if k >= 31 {
        return Real::MAX;
    }
    if k < -40 {
        return Real::ZERO;
    }
    let f = (y.to_bits() & ((1i64 << FRAC_BITS) - 1)) as u64; // fraction in [0, 1), Q32
    let mut acc: u128 = ONE_Q;
    for (i, factor) in TABLE.iter().enumerate().skip(1) {
        let bit = FRAC_BITS as usize - i;
        if (f >> bit) & 1 == 1 {
            acc = (acc * factor + (ONE_Q >> 1)) >> Q;
        }
        if bit == 0 {
            break;
        }
    }
    // acc in Q62 · 2^k → Q32: shift by (Q − 32 − k), rounding to nearest.
    let shift = Q as i64 - FRAC_BITS as i64 - k;
    let v = if shift > 0 {
        let s = shift as u32;
        (acc + (1 << (s - 1))) >> s
    } else {
        acc << (-shift) as u32
    };
    Real::from_bits(i64::try_from(v).unwrap_or(i64::MAX))
}

/// `base^y` for `base > 0` (`base ≤ 0` gives 0, `y = 0` gives 1).
pub fn pow(base: Real, y: Real) -> Real {
    if y.is_zero() {
        return Real::ONE;
    }
    if !base.is_positive() {
        return Real::ZERO;
    }
    if base == Real::ONE {
        return Real::ONE;
    }
    exp2(log2(base) * y)
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::real;

    fn close(a: Real, b: f64, ulps: f64) {
        let err = (a.to_f64() - b).abs() * 4294967296.0;
        assert!(err <= ulps, "{a} vs {b}: {err} ulp");
    }

    #[test]
    fn log2_exact_powers_and_values() {
        assert_eq!(log2(Real::ONE), Real::ZERO);
        assert_eq!(log2(Real::from_int(8)), Real::from_int(3));
        assert_eq!(log2(real!(0.25)), Real::from_int(-2));
        close(log2(Real::from_int(3)), 3f64.log2(), 1.0);
        close(log2(real!(0.9)), 0.9f64.log2(), 2.0);
        assert_eq!(log2(Real::ZERO), Real::MIN);
    }

    #[test]
    fn exp2_values_and_limits() {
        assert_eq!(exp2(Real::ZERO), Real::ONE);
        assert_eq!(exp2(Real::from_int(5)), Real::from_int(32));
        assert_eq!(exp2(Real::from_int(-1)), Real::HALF);
        close(exp2(Real::HALF), 2f64.sqrt(), 1.0);
        close(exp2(real!(-0.152)), 2f64.powf(-0.152), 1.0);
        assert_eq!(exp2(Real::from_int(40)), Real::MAX);
        assert_eq!(exp2(Real::from_int(-100)), Real::ZERO);
    }

    #[test]
    fn pow_matches_chipmunk_bias_default() {
        // 0.9^60 then back: (0.9^60)^(1/60) = 0.9.
        let bias = pow(real!(0.9), Real::from_int(60));
        close(bias, 0.9f64.powi(60), 8.0);
        close(pow(bias, Real::ratio(1, 60)), 0.9, 64.0);
        assert_eq!(pow(Real::ONE, real!(0.3)), Real::ONE);
        assert_eq!(pow(Real::ZERO, real!(0.3)), Real::ZERO);
    }
}
