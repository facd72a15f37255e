//! The `Real`/`Vect` layer of [`math::exact`](super): exact sums and
//! squares of raw `Real` bits, the exact vector predicates and the precise
//! normalisation of the collision code.
use super::int::{sum_sq, wide_mul, wide_mul_u64};
use crate::math::real::Real;
use crate::math::vect::Vect;

/// `a + b` on raw bits (units of 2^-32), exact.
#[inline]
pub(crate) fn raw_sum(a: Real, b: Real) -> i128 {
    // |a|, |b| ≤ 2^63: the sum needs 65 bits, never saturates.
    i128::from(a.to_bits()).saturating_add(i128::from(b.to_bits()))
}

/// `a − b` on raw bits (units of 2^-32), exact.
#[inline]
pub(crate) fn raw_diff(a: Real, b: Real) -> i128 {
    // |a|, |b| ≤ 2^63: the difference needs 65 bits, never saturates.
    i128::from(a.to_bits()).saturating_sub(i128::from(b.to_bits()))
}

/// `|a|²` of raw bits (units of 2^-64), exact: at most 2^126.
#[inline]
pub(crate) fn raw_sq(a: Real) -> u128 {
    let m = u128::from(a.to_bits().unsigned_abs());
    // m ≤ 2^63: m² ≤ 2^126, never saturates.
    m.saturating_mul(m)
}

/// A wide raw value as a `Real`, saturated to `Real::MIN`/`Real::MAX`.
#[inline]
pub(crate) fn saturate_to_real(raw: i128) -> Real {
    Real::from_bits(i64::try_from(raw).unwrap_or(if raw < 0 { i64::MIN } else { i64::MAX }))
}

/// Raw bits of a `Real` widened to `i128`.
#[inline(always)]
fn w(r: Real) -> i128 {
    i128::from(r.to_bits())
}

/// `a · b`, exact, in units of 2^-64.
#[inline(always)]
pub(crate) fn dot(a: Vect, b: Vect) -> i128 {
    let (ax, ay, bx, by) = (a.x.to_bits(), a.y.to_bits(), b.x.to_bits(), b.y.to_bits());
    wide_mul(ax, bx).saturating_add(wide_mul(ay, by))
}

/// `a · n` exactly, for `n` within the unit square (both components in
/// `[−1, 1]`, which the caller guarantees): each product is below `2^95`
/// in magnitude and their sum below `2^96`, so the sum cannot saturate
/// and needs no test ([`dot`]'s value).
#[inline(always)]
pub(crate) fn dot_unit(a: Vect, n: Vect) -> i128 {
    let (ax, ay, nx, ny) = (a.x.to_bits(), a.y.to_bits(), n.x.to_bits(), n.y.to_bits());
    wide_mul(ax, nx).wrapping_add(wide_mul(ay, ny))
}

/// `a × b` (z of the 3D cross product), exact, in units of 2^-64.
#[inline(always)]
pub(crate) fn cross(a: Vect, b: Vect) -> i128 {
    let (ax, ay, bx, by) = (a.x.to_bits(), a.y.to_bits(), b.x.to_bits(), b.y.to_bits());
    wide_mul(ax, by).saturating_sub(wide_mul(ay, bx))
}

/// `|v|²`, exact, in units of 2^-64 (never overflows: each square < 2^126).
#[inline(always)]
pub(crate) fn len_sq(v: Vect) -> u128 {
    sum_sq(v.x.to_bits(), v.y.to_bits())
}

/// `num / den` as a `Real` clamped to `[-1, 1]`, rounded to nearest.
/// `den == 0` gives 0. Both arguments are in the same units (they cancel).
pub(crate) fn unit_ratio(num: i128, den: u128) -> Real {
    const ONE_BITS: u128 = 1 << 32;
    if den == 0 {
        return Real::ZERO;
    }
    let mag = num.unsigned_abs();
    let q = if mag >= den {
        ONE_BITS
    } else {
        // Shift the numerator up by 32 fractional bits if it has room, else
        // shift the denominator down (then den > mag ≥ 2^95, so den >> 32 is
        // still ≥ 2^63 and the quotient keeps full precision).
        let (n, d) = if mag.leading_zeros() >= 33 {
            (mag << 32, den)
        } else {
            (mag, den >> 32)
        };
        // Never saturates: n < 2^127 and d/2 < 2^127 (first case) or n ≤ 2^127
        // and d/2 < 2^95 (second). d ≠ 0: den ≠ 0, resp. d ≥ 2^63.
        n.saturating_add(d / 2)
            .checked_div(d)
            .unwrap_or(ONE_BITS)
            .min(ONE_BITS)
    };
    // q ≤ 2^32 fits an i64.
    let q = i64::try_from(q).unwrap_or(1 << 32);
    // q ≥ 0: the negation never saturates.
    Real::from_bits(if num < 0 { q.saturating_neg() } else { q })
}

/// `v · (num / den)` for `0 < num < den` (same units), each component
/// rounded once. Both are shifted right together until `den < 2^62`, so the
/// products fit an `i128`; that drops only bits below 2^-62 relative.
pub(crate) fn scale_by_ratio(v: Vect, num: i128, den: u128) -> Vect {
    // leading_zeros ≤ 128: the first subtraction never saturates.
    let k = 128u32
        .saturating_sub(den.leading_zeros())
        .saturating_sub(62);
    let d = i128::try_from(den >> k).unwrap_or(i128::MAX);
    let n = num >> k;
    if d == 0 {
        return Vect::ZERO;
    }
    let comp = |c: Real| -> Real {
        // |c| ≤ 2^63 and |n| ≤ d < 2^62 (0 < num < den): the product is below
        // 2^125 and the rounded sum below 2^126, neither saturates; d > 0.
        let p = w(c).saturating_mul(n);
        let da = d.unsigned_abs();
        let q = p
            .unsigned_abs()
            .saturating_add(da / 2)
            .checked_div(da)
            .unwrap_or(0);
        let q = i64::try_from(q).unwrap_or(i64::MAX);
        // q ≥ 0: the negation never saturates.
        Real::from_bits(if p < 0 { q.saturating_neg() } else { q })
    };
    Vect::new(comp(v.x), comp(v.y))
}

/// Starting guesses for [`rsqrt_q60`]: entry `b` (for `b` in 8..32) is
/// `1/√x` in Q60 at the middle of the bucket `x ∈ [b/32, (b+1)/32)`, i.e.
/// `√(2^126 / (2b + 1))`, computed at compile time with integers (the
/// indexing and the cast run in const evaluation: b < 32, r < 2^62).
// Const evaluation: an out-of-range index would fail the build, never run.
#[allow(clippy::indexing_slicing)]
const RSQRT_SEED: [u64; 32] = {
    let mut t = [0u64; 32];
    let mut b = 8;
    while b < 32 {
        let r = ((1u128 << 126) / (2 * b as u128 + 1)).isqrt();
        t[b] = r as u64;
        b += 1;
    }
    t
};

/// `1/√x` in Q60 for `x = m / 2^64`, `m ∈ [2^62, 2^64)` (so `1/√x ∈ (1, 2]`).
///
/// Newton's iteration for the reciprocal square root, `y ← y(3 − x·y²)/2`,
/// uses only multiplications: from the table's ≤ 3% start, four steps reach
/// the Q60 resolution (error 3% → 1e-3 → 2e-6 → 5e-12 → below 2^-58). The
/// iterates stay at most about 2^61 (the seeds are below 2^61, and a step
/// never exceeds `1/√x ≤ 2`, the maximum of `y(3 − x·y²)/2`, by more than its
/// truncations), so every product is of two values below 2^64 and is formed
/// by one widening multiply ([`wide_mul_u64`], exact). `y²/2^60` is checked
/// to fit 64 bits before it is used as a factor; if it did not (it cannot
/// for the iterates above), the exact `u128` product is formed instead, so
/// the result is the exact truncated iteration in every case (the same bits
/// as the former all-`u128` form; unit test
/// `normalize_is_the_all_u128_kernel_bit_for_bit`).
#[inline]
fn rsqrt_q60(m: u64) -> u64 {
    let bucket = usize::try_from(m >> 59).unwrap_or(31);
    let mut y = RSQRT_SEED.get(bucket).copied().unwrap_or(1 << 60);
    for _ in 0..4 {
        let y2 = wide_mul_u64(y, y) >> 60; // < 2^68 (≤ 2^62 in practice)
        let xy2 = match u64::try_from(y2) {
            Ok(y2) => wide_mul_u64(m, y2) >> 64,
            // m·y2 < 2^132 could saturate here; the saturated value is what
            // the all-u128 form computes too.
            Err(_) => u128::from(m).saturating_mul(y2) >> 64,
        };
        // xy2 < 2^64 and t ≤ 3·2^60: both fit 64 bits.
        let t = u64::try_from((3u128 << 60).saturating_sub(xy2)).unwrap_or(3 << 60);
        // y < 2^64, t < 2^62: y·t < 2^126, exact.
        y = u64::try_from(wide_mul_u64(y, t) >> 61).unwrap_or(1 << 61);
    }
    y
}

/// `(v / |v|, |v|)`, or `None` for the zero vector.
///
/// The vector is first scaled by a power of two (exact) so its larger
/// component has 62 significant bits; `|v|²` is then formed exactly on 128
/// bits and `1/|v|` comes from [`rsqrt_q60`] (multiplications only: no square
/// root, no division, ~4× cheaper than an integer `isqrt` plus two 128-bit
/// divisions). Each component of the unit vector is within 0.5 ulp (+2^-25
/// ulp) of the true value even for tiny vectors (a separation of a few ulp
/// still gives a unit normal), so `||n| − 1| < 1 ulp`; the length is within
/// 0.5 ulp + 2^-56 relative (exact to the ulp below 2^24 units).
///
/// Every factor is below 2^64 (the scaled components, `m`, `1/|v|` in Q60),
/// so every product is one exact 64 × 64 → 128-bit multiply: the same
/// values the former form computed with `u128` multiplies (which also
/// multiplied and tested the zero high halves), bit for bit.
pub(crate) fn normalize(v: Vect) -> Option<(Vect, Real)> {
    let (x, y) = (v.x.to_bits(), v.y.to_bits());
    let big = x.unsigned_abs().max(y.unsigned_abs());
    if big == 0 {
        return None;
    }
    // big ≤ 2^63; put its top bit at position 61 (or leave it if higher):
    // both scaled magnitudes then stay below 2^62 (or ≤ 2^63 unscaled), so
    // they fit a u64 and the shifts lose no bit.
    let shift = big.leading_zeros().saturating_sub(2);
    let (xa, ya) = (x.unsigned_abs() << shift, y.unsigned_abs() << shift);
    // Each square ≤ 2^126, the sum < 2^127 + 1: exact in a u128 (never
    // saturates).
    let sq = wide_mul_u64(xa, xa).saturating_add(wide_mul_u64(ya, ya));
    // Even k with m = sq >> k in [2^62, 2^64): sq has 123..=127 bits.
    // (leading_zeros ≤ 128: the first subtraction never saturates.)
    let k = 128u32.saturating_sub(sq.leading_zeros()).saturating_sub(63) & !1;
    let m = u64::try_from(sq >> k).unwrap_or(u64::MAX);
    let r = rsqrt_q60(m);
    // 1/|v_s| = r · 2^-(60 + 32 + k/2); the Real unit component is
    // c_s · 2^32 / |v_s| = c_s · r >> (60 + k/2). |c_s| ≤ 2^63, r ≤ 2^61.
    // k ≤ 64, so 60 ≤ down ≤ 92; p < 2^124 and the rounding bias ≤ 2^91: none
    // of these operations saturates.
    let down = 60u32.saturating_add(k / 2);
    let half = 1u128 << down.saturating_sub(1);
    let unit = |mag: u64, negative: bool| -> Real {
        let p = wide_mul_u64(mag, r);
        let q = i64::try_from(p.saturating_add(half) >> down).unwrap_or(i64::MAX);
        // q ≥ 0: the negation never saturates.
        Real::from_bits(if negative { q.saturating_neg() } else { q })
    };
    // |v_s| = √x · 2^(32 + k/2) with √x = x · r = m·r >> 60 in Q64 (≤ 2^65);
    // in raw units of v: √x_q64 · 2^(32 + k/2 − 64 − shift), a right shift
    // since k/2 ≤ 32.
    // m < 2^64, r ≤ 2^61: the product is exact.
    let root_q64 = wide_mul_u64(m, r) >> 60;
    // shift ≤ 61 and k/2 ≤ 32: 0 ≤ e ≤ 93, never saturates.
    let e = 32u32.saturating_add(shift).saturating_sub(k / 2);
    let length = if e > 0 {
        // root_q64 < 2^65 and e − 1 < 93: never saturates.
        root_q64.saturating_add(1u128 << e.saturating_sub(1)) >> e
    } else {
        root_q64
    };
    let length = i64::try_from(length).unwrap_or(i64::MAX);
    Some((
        Vect::new(unit(xa, x < 0), unit(ya, y < 0)),
        Real::from_bits(length),
    ))
}

/// `normalize(v)` with a fallback for the zero vector.
#[inline]
pub(crate) fn unit_or(v: Vect, fallback: Vect) -> Vect {
    normalize(v).map_or(fallback, |(n, _)| n)
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    #[test]
    fn dot_unit_is_the_exact_dot_within_the_unit_square() {
        let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
        let unit = [
            -(1i64 << 32),
            -(1 << 32) + 1,
            -1,
            0,
            1,
            (1 << 32) - 1,
            1 << 32,
        ];
        for x in edges {
            for y in edges {
                for nx in unit {
                    for ny in unit {
                        let v = Vect::new(Real::from_bits(x), Real::from_bits(y));
                        let n = Vect::new(Real::from_bits(nx), Real::from_bits(ny));
                        assert_eq!(dot_unit(v, n), dot(v, n), "{v:?} {n:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn raw_helpers_are_exact_at_the_range_edges() {
        let (max, min) = (Real::MAX, Real::MIN);
        assert_eq!(raw_sum(max, max), 2 * i128::from(i64::MAX));
        assert_eq!(raw_sum(min, min), 2 * i128::from(i64::MIN));
        // Keys near the top of the range stay distinct (the static tree's sort).
        assert!(raw_sum(max - Real::ONE, max) < raw_sum(max, max));
        assert_eq!(raw_diff(max, min), i128::from(u64::MAX));
        assert_eq!(raw_diff(min, max), -i128::from(u64::MAX));
        assert_eq!(wide_mul(i64::MIN, i64::MIN), 1 << 126);
        assert_eq!(wide_mul(i64::MIN, i64::MAX), -(1 << 126) + (1 << 63));
        assert_eq!(raw_sq(min), 1 << 126);
        assert_eq!(saturate_to_real(1 << 64), max);
        assert_eq!(saturate_to_real(-(1 << 64)), min);
        assert_eq!(saturate_to_real(-5), Real::from_bits(-5));
    }

    #[test]
    fn unit_ratio_clamps_and_rounds() {
        assert_eq!(unit_ratio(1, 2), Real::HALF);
        assert_eq!(unit_ratio(-1, 2), -Real::HALF);
        assert_eq!(unit_ratio(5, 2), Real::ONE);
        assert_eq!(unit_ratio(-5, 2), -Real::ONE);
        assert_eq!(unit_ratio(7, 0), Real::ZERO);
        // Huge numerator: the denominator is shifted instead.
        let big = 1i128 << 120;
        assert_eq!(unit_ratio(big, (big as u128) * 4), Real::from_bits(1 << 30));
    }

    #[test]
    fn normalize_tiny_vectors_exactly() {
        let tiny = Vect::new(Real::DELTA, Real::DELTA);
        let (n, len) = normalize(tiny).unwrap_or_default();
        let expect = (0.5f64).sqrt();
        assert!((n.x.to_f64() - expect).abs() <= 2.4e-10, "{n:?}");
        assert_eq!(len, Real::DELTA); // √2 ulp rounds to 1 ulp
        assert!(normalize(Vect::ZERO).is_none());
        let (n, len) = normalize(Vect::from_ints(3, 4)).unwrap_or_default();
        assert_eq!(len, Real::from_int(5));
        assert!((n.x.to_f64() - 0.6).abs() <= 1.2e-10);
        let (n, _) = normalize(Vect::new(Real::MIN, Real::MIN)).unwrap_or_default();
        assert!((n.x.to_f64() + expect).abs() <= 2.4e-10);
    }

    /// The exact reference: 128-bit integer square root and divisions.
    fn normalize_reference(v: Vect) -> (i64, i64, i64) {
        let (x, y) = (w(v.x), w(v.y));
        let shift = x
            .unsigned_abs()
            .max(y.unsigned_abs())
            .leading_zeros()
            .saturating_sub(66);
        let (xs, ys) = (x << shift, y << shift);
        let len = (xs.unsigned_abs().pow(2) + ys.unsigned_abs().pow(2)).isqrt();
        let unit = |c: i128| {
            let q = ((c.unsigned_abs() << 32) + len / 2) / len;
            if c < 0 {
                -(q as i64)
            } else {
                q as i64
            }
        };
        let half = if shift == 0 { 0 } else { 1u128 << (shift - 1) };
        let length = i64::try_from((len + half) >> shift).unwrap_or(i64::MAX);
        (unit(xs), unit(ys), length)
    }

    #[test]
    fn normalize_matches_exact_reference_within_one_raw_unit() {
        // A deterministic spread of magnitudes and directions (xorshift).
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for i in 0..200_000u32 {
            let bits = i % 64;
            let x = (next() as i64) >> bits;
            let y = (next() as i64) >> (next() % 64) as u32;
            let v = Vect::new(Real::from_bits(x), Real::from_bits(y));
            let Some((n, len)) = normalize(v) else {
                assert_eq!((x, y), (0, 0));
                continue;
            };
            let (rx, ry, rl) = normalize_reference(v);
            assert!((n.x.to_bits() - rx).abs() <= 1, "{v:?}: {n:?} vs {rx} {ry}");
            assert!((n.y.to_bits() - ry).abs() <= 1, "{v:?}: {n:?} vs {rx} {ry}");
            assert!(
                (len.to_bits() - rl).abs() <= 1 + (rl >> 56),
                "{v:?}: {len:?} vs {rl}"
            );
        }
        for v in [
            Vect::new(Real::MIN, Real::MIN),
            Vect::new(Real::MAX, Real::MIN),
            Vect::new(Real::MIN, Real::ZERO),
            Vect::new(Real::DELTA, Real::ZERO),
            Vect::new(Real::ZERO, -Real::DELTA),
        ] {
            let (n, len) = normalize(v).unwrap_or_default();
            let (rx, ry, rl) = normalize_reference(v);
            assert!(
                (n.x.to_bits() - rx).abs() <= 1 && (n.y.to_bits() - ry).abs() <= 1,
                "{v:?}"
            );
            assert!(
                (len.to_bits() - rl).abs() <= 1 + (rl >> 56),
                "{v:?} {len:?} {rl}"
            );
        }
        assert_eq!(normalize(Vect::X), Some((Vect::X, Real::ONE)));
        assert_eq!(normalize(-Vect::Y), Some((-Vect::Y, Real::ONE)));
    }

    // The all-`u128` kernel `normalize` had before its multiplies became
    // 64 × 64 → 128 (kept to prove the two give the same bits).
    /// `1/√x` in Q60 for `x = m / 2^64`, `m ∈ [2^62, 2^64)` (so `1/√x ∈ (1, 2]`).
    ///
    /// Newton's iteration for the reciprocal square root, `y ← y(3 − x·y²)/2`,
    /// uses only multiplications: from the table's ≤ 3% start, four steps reach
    /// the Q60 resolution (error 3% → 1e-3 → 2e-6 → 5e-12 → below 2^-58). All
    /// products fit a u128 (none saturates): the iterates stay at most about 2^61
    /// (the seeds are below 2^61, and a step never exceeds `1/√x ≤ 2`, the
    /// maximum of `y(3 − x·y²)/2`, by more than its truncations).
    fn rsqrt_q60_u128(m: u64) -> u64 {
        let bucket = usize::try_from(m >> 59).unwrap_or(31);
        let mut y = RSQRT_SEED.get(bucket).copied().unwrap_or(1 << 60);
        for _ in 0..4 {
            let y2 = u128::from(y).saturating_mul(u128::from(y)) >> 60; // ≤ 2^62
            let xy2 = u128::from(m).saturating_mul(y2) >> 64; // x·y², ≈ 2^60; m·y2 < 2^127
            let t = (3u128 << 60).saturating_sub(xy2);
            // y < 2^64, t < 2^62: y·t < 2^126.
            y = u64::try_from(u128::from(y).saturating_mul(t) >> 61).unwrap_or(1 << 61);
        }
        y
    }

    /// `(v / |v|, |v|)`, or `None` for the zero vector.
    ///
    /// The vector is first scaled by a power of two (exact) so its larger
    /// component has 62 significant bits; `|v|²` is then formed exactly on 128
    /// bits and `1/|v|` comes from [`rsqrt_q60`] (multiplications only: no square
    /// root, no division, ~4× cheaper than an integer `isqrt` plus two 128-bit
    /// divisions). Each component of the unit vector is within 0.5 ulp (+2^-25
    /// ulp) of the true value even for tiny vectors (a separation of a few ulp
    /// still gives a unit normal), so `||n| − 1| < 1 ulp`; the length is within
    /// 0.5 ulp + 2^-56 relative (exact to the ulp below 2^24 units).
    fn normalize_u128(v: Vect) -> Option<(Vect, Real)> {
        let (x, y) = (w(v.x), w(v.y));
        let big = x.unsigned_abs().max(y.unsigned_abs());
        if big == 0 {
            return None;
        }
        // big ≤ 2^63; put its top bit at position 61 (or leave it if higher).
        let shift = big.leading_zeros().saturating_sub(66);
        let (xs, ys) = (x << shift, y << shift);
        let (xa, ya) = (xs.unsigned_abs(), ys.unsigned_abs());
        // Each square ≤ 2^126, the sum < 2^127 + 1: exact in a u128 (never
        // saturates).
        let sq = xa.saturating_mul(xa).saturating_add(ya.saturating_mul(ya));
        // Even k with m = sq >> k in [2^62, 2^64): sq has 123..=127 bits.
        // (leading_zeros ≤ 128: the first subtraction never saturates.)
        let k = 128u32.saturating_sub(sq.leading_zeros()).saturating_sub(63) & !1;
        let m = u64::try_from(sq >> k).unwrap_or(u64::MAX);
        let r = u128::from(rsqrt_q60_u128(m));
        // 1/|v_s| = r · 2^-(60 + 32 + k/2); the Real unit component is
        // c_s · 2^32 / |v_s| = c_s · r >> (60 + k/2). |c_s| ≤ 2^63, r ≤ 2^61.
        // k ≤ 64, so 60 ≤ down ≤ 92; p < 2^124 and the rounding bias ≤ 2^91: none
        // of these operations saturates.
        let down = 60u32.saturating_add(k / 2);
        let unit = |c: i128| -> Real {
            let p = c.unsigned_abs().saturating_mul(r);
            let half = 1u128 << down.saturating_sub(1);
            let q = i64::try_from(p.saturating_add(half) >> down).unwrap_or(i64::MAX);
            // q ≥ 0: the negation never saturates.
            Real::from_bits(if c < 0 { q.saturating_neg() } else { q })
        };
        // |v_s| = √x · 2^(32 + k/2) with √x = x · r = m·r >> 60 in Q64 (≤ 2^65);
        // in raw units of v: √x_q64 · 2^(32 + k/2 − 64 − shift), a right shift
        // since k/2 ≤ 32.
        // m < 2^64, r ≤ 2^61: the product never saturates.
        let root_q64 = u128::from(m).saturating_mul(r) >> 60;
        // shift ≤ 61 and k/2 ≤ 32: 0 ≤ e ≤ 93, never saturates.
        let e = 32u32.saturating_add(shift).saturating_sub(k / 2);
        let length = if e > 0 {
            // root_q64 < 2^65 and e − 1 < 93: never saturates.
            root_q64.saturating_add(1u128 << e.saturating_sub(1)) >> e
        } else {
            root_q64
        };
        let length = i64::try_from(length).unwrap_or(i64::MAX);
        Some((Vect::new(unit(xs), unit(ys)), Real::from_bits(length)))
    }

    fn same_bits_as_u128_kernel(v: Vect) {
        assert_eq!(normalize(v), normalize_u128(v), "{v:?}");
    }

    #[test]
    fn normalize_is_the_all_u128_kernel_bit_for_bit() {
        let edges = [
            0,
            1,
            -1,
            2,
            3,
            i64::MAX,
            i64::MIN,
            i64::MIN + 1,
            i64::MAX - 1,
            1 << 61,
            (1 << 61) - 1,
            1 << 62,
            (1 << 62) - 1,
            -(1 << 62),
            1 << 32,
            -(1 << 32),
            (1 << 32) + 1,
            0x5555_5555_5555_5555,
            -0x5555_5555_5555_5555,
        ];
        for &x in &edges {
            for &y in &edges {
                same_bits_as_u128_kernel(Vect::new(Real::from_bits(x), Real::from_bits(y)));
            }
        }
        // Every seed bucket's ends, at several scales.
        for b in 8u64..32 {
            for m in [b << 59, (b << 59) | ((1 << 59) - 1)] {
                assert_eq!(rsqrt_q60(m), rsqrt_q60_u128(m), "{m}");
            }
        }
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for i in 0..200_000u32 {
            let x = (next() as i64) >> (i % 64);
            let y = (next() as i64) >> (next() % 64) as u32;
            same_bits_as_u128_kernel(Vect::new(Real::from_bits(x), Real::from_bits(y)));
            let m = next() | (1 << 62);
            assert_eq!(rsqrt_q60(m), rsqrt_q60_u128(m), "{m}");
        }
    }

    proptest::proptest! {
        #[test]
        fn normalize_u64_products_are_the_u128_ones(x: i64, y: i64, sx in 0u32..64, sy in 0u32..64) {
            same_bits_as_u128_kernel(Vect::new(Real::from_bits(x >> sx), Real::from_bits(y >> sy)));
        }
    }

    #[test]
    fn predicates_are_exact_for_ulp_sized_differences() {
        let a = Vect::new(Real::from_int(10_000), Real::DELTA);
        let b = Vect::new(Real::from_int(10_000), Real::ZERO);
        assert!(cross(b, a) > 0);
        assert!(dot(a, Vect::Y) > dot(b, Vect::Y));
    }
}
