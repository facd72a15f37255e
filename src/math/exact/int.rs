//! The integer layer of [`math::exact`](super): exact products of raw
//! `i64` values on `i128` and a 256-bit integer for sums of products of
//! `i128`s. Depends on nothing, so `Real` itself is built on it.

/// The exact 128-bit product of two raw values (units of 2^-64 for `Real`
/// bits): |a·b| ≤ 2^126, so it never overflows `i128` (the one product the
/// `arithmetic_side_effects` lint cannot see is bounded).
///
/// On wasm32 it is [`wide_mul_split`]: wasm has no 64×64→128 multiply, and
/// LLVM lowers an `i128` product to a call of `__multi3` (a full 128×128
/// product, its result returned through memory), which took 29 % of the
/// browser's step. The same integer either way: an exact product has one
/// value.
#[inline(always)]
#[allow(clippy::arithmetic_side_effects)]
pub(crate) const fn wide_mul(a: i64, b: i64) -> i128 {
    #[cfg(target_arch = "wasm32")]
    {
        wide_mul_split(a, b)
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        a as i128 * b as i128
    }
}

/// The exact 128-bit product of two unsigned 64-bit values: below 2^128, so
/// it never overflows `u128`. One widening multiply, where a `u128`
/// `saturating_mul` also multiplies (and tests) the high halves. On wasm32,
/// [`wide_mul_u64_split`] (see [`wide_mul`]).
#[inline(always)]
#[allow(clippy::arithmetic_side_effects)]
pub(crate) const fn wide_mul_u64(a: u64, b: u64) -> u128 {
    #[cfg(target_arch = "wasm32")]
    {
        wide_mul_u64_split(a, b)
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        a as u128 * b as u128
    }
}

/// `a·b` exactly, from four 32×32→64 partial products: the schoolbook
/// product on 32-bit halves, for targets whose only multiply is 64-bit.
/// Each partial product is below 2^64, and so is each column sum (at most
/// three values below 2^32 plus one below 2^64 − 2^33): nothing wraps.
#[inline(always)]
#[allow(clippy::arithmetic_side_effects, dead_code)]
pub(crate) const fn wide_mul_u64_split(a: u64, b: u64) -> u128 {
    const LOW: u64 = 0xffff_ffff;
    let (a0, a1, b0, b1) = (a & LOW, a >> 32, b & LOW, b >> 32);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    let mid = (p00 >> 32) + (p01 & LOW) + (p10 & LOW);
    let lo = (p00 & LOW) | (mid << 32);
    let hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    ((hi as u128) << 64) | lo as u128
}

/// The signed `a·b` from the unsigned product of the two's-complement bit
/// patterns: a negative factor counts 2^64 too much, so its partner is
/// subtracted from the high half (modulo 2^128, where the exact product
/// lives).
#[inline(always)]
#[allow(clippy::arithmetic_side_effects, dead_code)]
pub(crate) const fn wide_mul_split(a: i64, b: i64) -> i128 {
    let (au, bu) = (a as u64, b as u64);
    let p = wide_mul_u64_split(au, bu);
    let (lo, mut hi) = (p as u64, (p >> 64) as u64);
    if a < 0 {
        hi = hi.wrapping_sub(bu);
    }
    if b < 0 {
        hi = hi.wrapping_sub(au);
    }
    (((hi as u128) << 64) | lo as u128) as i128
}

/// `x² + y²` of two raw values, exact (units of 2^-64 for `Real` bits):
/// each square is at most 2^126, the sum at most 2^127, so it never
/// overflows `u128`.
#[inline(always)]
pub(crate) fn sum_sq(x: i64, y: i64) -> u128 {
    let (x, y) = (x.unsigned_abs(), y.unsigned_abs());
    // x, y ≤ 2^63: each square ≤ 2^126, the sum never saturates.
    wide_mul_u64(x, x).saturating_add(wide_mul_u64(y, y))
}

/// A 256-bit two's-complement integer, just enough for exact sums of
/// products of two `i128`: products, sums, shifts, one rounded division and
/// a rounded power-of-two division.
///
/// Additions are modulo 2^256 (two's complement on two `u128` limbs). Each
/// caller states the bound that keeps its sums below 2^255 in magnitude, so
/// they never actually wrap: the mass integrals add terms below 2^228 (a sum
/// over fewer than 2^26 vertices stays below 2^254; 2^26 vertices would take
/// 3 GiB with their wide copies, and beyond that the result is defined but
/// meaningless, never a panic), the kinetic energy three terms below 2^189.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct I256 {
    hi: u128,
    lo: u128,
}

impl I256 {
    pub(crate) const ZERO: I256 = I256 { hi: 0, lo: 0 };
    const ONE: I256 = I256 { hi: 0, lo: 1 };

    pub(crate) fn from_i128(v: i128) -> I256 {
        I256 {
            hi: if v < 0 { u128::MAX } else { 0 },
            lo: v as u128,
        }
    }

    fn from_magnitude(negative: bool, m: I256) -> I256 {
        if negative {
            m.neg()
        } else {
            m
        }
    }

    pub(crate) fn is_negative(self) -> bool {
        self.hi >> 127 == 1
    }

    pub(crate) fn is_zero(self) -> bool {
        self == I256::ZERO
    }

    /// `self + o` modulo 2^256: the carry out of the low limb goes into the
    /// high limb, and the high limb wraps as two's complement does (the
    /// intended semantics of a 256-bit integer, see the type's docs).
    pub(crate) fn add(self, o: I256) -> I256 {
        let (lo, carry) = self.lo.overflowing_add(o.lo);
        I256 {
            hi: self.hi.wrapping_add(o.hi).wrapping_add(u128::from(carry)),
            lo,
        }
    }

    pub(crate) fn sub(self, o: I256) -> I256 {
        self.add(o.neg())
    }

    pub(crate) fn neg(self) -> I256 {
        I256 {
            hi: !self.hi,
            lo: !self.lo,
        }
        .add(I256::ONE)
    }

    /// |self| as an unsigned 256-bit value (stored in the same struct).
    fn magnitude(self) -> I256 {
        if self.is_negative() {
            self.neg()
        } else {
            self
        }
    }

    /// Left shift by `k` bits (bits shifted past bit 255 are lost; `k ≥ 256`
    /// gives 0).
    // The subtractions are range-checked by the match: `128 − k` for k in
    // 1..=127, `k − 128` for k in 128..=255.
    #[allow(clippy::arithmetic_side_effects)]
    pub(crate) fn shl(self, k: u32) -> I256 {
        match k {
            0 => self,
            1..=127 => I256 {
                hi: (self.hi << k) | (self.lo >> (128 - k)),
                lo: self.lo << k,
            },
            128..=255 => I256 {
                hi: self.lo << (k - 128),
                lo: 0,
            },
            _ => I256::ZERO,
        }
    }

    /// Multiplication by a small constant (here 3 or 6).
    pub(crate) fn mul_small(self, k: u32) -> I256 {
        (0..k).fold(I256::ZERO, |acc, _| acc.add(self))
    }

    /// The exact product of two `i128`.
    // Schoolbook multiplication on 64-bit halves: each partial product of two
    // values below 2^64 is below 2^128; `mid` is below 3·2^64; and `hi` is the
    // top half of a product of two values ≤ 2^127, below 2^126 + 3·2^64.
    #[allow(clippy::arithmetic_side_effects)]
    pub(crate) fn mul_i128(a: i128, b: i128) -> I256 {
        let (x, y) = (a.unsigned_abs(), b.unsigned_abs());
        const M: u128 = u64::MAX as u128;
        let (x1, x0, y1, y0) = (x >> 64, x & M, y >> 64, y & M);
        let (p00, p01, p10, p11) = (x0 * y0, x0 * y1, x1 * y0, x1 * y1);
        let mid = (p00 >> 64) + (p01 & M) + (p10 & M);
        let m = I256 {
            hi: p11 + (p01 >> 64) + (p10 >> 64) + (mid >> 64),
            lo: (p00 & M) | (mid << 64),
        };
        I256::from_magnitude((a < 0) != (b < 0), m)
    }

    /// Unsigned comparison of magnitudes.
    fn ge_unsigned(self, o: I256) -> bool {
        (self.hi, self.lo) >= (o.hi, o.lo)
    }

    /// A magnitude below 2^256 with a sign, saturated to `i128`.
    fn signed_saturated(negative: bool, mag: I256) -> i128 {
        let mag = if mag.hi == 0 { mag.lo } else { u128::MAX };
        if negative {
            0i128.checked_sub_unsigned(mag).unwrap_or(i128::MIN)
        } else {
            i128::try_from(mag).unwrap_or(i128::MAX)
        }
    }

    /// The value saturated to `i128` (keeping its sign).
    pub(crate) fn saturating_to_i128(self) -> i128 {
        I256::signed_saturated(self.is_negative(), self.magnitude())
    }

    /// `self / den` rounded to nearest (ties away from zero), saturated to
    /// `i128`; `den == 0` follows `Real`'s division policy (0 for 0/0, else
    /// the saturated value with the sign of the numerator).
    pub(crate) fn ratio_round(self, den: I256) -> i128 {
        if den.is_zero() {
            return match (self.is_zero(), self.is_negative()) {
                (true, _) => 0,
                (false, false) => i128::MAX,
                (false, true) => i128::MIN,
            };
        }
        let negative = self.is_negative() != den.is_negative();
        let (n, d) = (self.magnitude(), den.magnitude());
        // Restoring long division, one quotient bit at a time (up to 256
        // steps, high limb first; mass properties are computed when shapes
        // change, not per step).
        let (mut q, mut r) = (I256::ZERO, I256::ZERO);
        // Both within 128 bits: the native division gives the same floor
        // quotient and remainder as the long division below.
        let native = (n.hi == 0 && d.hi == 0)
            .then(|| n.lo.checked_div(d.lo).zip(n.lo.checked_rem(d.lo)))
            .flatten();
        let limbs: &[u128] = match native {
            Some((ql, rl)) => {
                (q, r) = (I256 { hi: 0, lo: ql }, I256 { hi: 0, lo: rl });
                &[]
            }
            None => &[n.hi, n.lo],
        };
        for &limb in limbs {
            for j in (0..128u32).rev() {
                let bit = (limb >> j) & 1;
                // Leading zero bits leave `q` and `r` at zero: skipped.
                if bit == 0 && r.is_zero() && q.is_zero() {
                    continue;
                }
                // A remainder that overflows the shift is certainly ≥ d.
                let carry = r.hi >> 127;
                r = r.shl(1);
                r.lo |= bit;
                q = q.shl(1);
                if carry == 1 || r.ge_unsigned(d) {
                    r = r.sub(d);
                    q.lo |= 1;
                }
            }
        }
        // Round half up in magnitude (r ≥ d − r is 2r ≥ d without overflow).
        if r.ge_unsigned(d.sub(r)) {
            q = q.add(I256::ONE);
        }
        I256::signed_saturated(negative, q)
    }

    /// `self / 2^k` rounded to nearest (ties away from zero), saturated to
    /// `i128`, for `k` in `1..=127` (other `k` are clamped to that range).
    /// The same value as `ratio_round` by `2^k`, without the long division.
    pub(crate) fn round_shr(self, k: u32) -> i128 {
        let k = k.clamp(1, 127);
        let negative = self.is_negative();
        // A magnitude is at most 2^255, so adding half of 2^k < 2^127 to it
        // cannot carry out of the high limb.
        let m = self.magnitude().add(I256::ONE.shl(k.saturating_sub(1)));
        // Bits of the high limb that land in the low one: `hi << (128 − k)`
        // (k ≥ 1, so the shift is at most 127).
        let shifted = I256 {
            hi: m.hi >> k,
            lo: (m.lo >> k) | (m.hi << u128::BITS.saturating_sub(k)),
        };
        I256::signed_saturated(negative, shifted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ratio_round` as it was: the full 256-step long division (oracle).
    fn ratio_round_long(n0: I256, den: I256) -> i128 {
        if den.is_zero() {
            return match (n0.is_zero(), n0.is_negative()) {
                (true, _) => 0,
                (false, false) => i128::MAX,
                (false, true) => i128::MIN,
            };
        }
        let negative = n0.is_negative() != den.is_negative();
        let (n, d) = (n0.magnitude(), den.magnitude());
        let (mut q, mut r) = (I256::ZERO, I256::ZERO);
        for limb in [n.hi, n.lo] {
            for j in (0..128u32).rev() {
                let bit = (limb >> j) & 1;
                let carry = r.hi >> 127;
                r = r.shl(1);
                r.lo |= bit;
                q = q.shl(1);
                if carry == 1 || r.ge_unsigned(d) {
                    r = r.sub(d);
                    q.lo |= 1;
                }
            }
        }
        if r.ge_unsigned(d.sub(r)) {
            q = q.add(I256::ONE);
        }
        I256::signed_saturated(negative, q)
    }

    /// The native and leading-zero shortcuts give the long division's bits
    /// on numerators and denominators of every size and sign.
    #[test]
    fn ratio_round_equals_the_full_long_division() {
        let mut x = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let one = I256::from_i128(1);
        let mut checked = 0;
        for _ in 0..20_000 {
            // Random magnitudes from 1 to ~250 bits, random signs.
            let value = |next: &mut dyn FnMut() -> u64| {
                let a = i128::from(next() as i64) << (next() % 64);
                let b = i128::from(next() as i64);
                let v = I256::mul_i128(a, b).add(I256::from_i128(i128::from(next() as i64)));
                match next() % 4 {
                    0 => v.shl((next() % 64) as u32),
                    1 => I256::from_i128(i128::from((next() % 1000) as i64) - 500),
                    2 => one.shl((next() % 255) as u32),
                    _ => v,
                }
            };
            let (n, d) = (value(&mut next), value(&mut next));
            assert_eq!(n.ratio_round(d), ratio_round_long(n, d), "{n:?} / {d:?}");
            checked += 1;
        }
        assert_eq!(checked, 20_000);
        for (n, d) in [
            (7, 2),
            (-7, 2),
            (5, -3),
            (0, 9),
            (1, 3),
            (i128::MAX, 1),
            (i128::MIN, 1),
        ] {
            let (n, d) = (I256::from_i128(n), I256::from_i128(d));
            assert_eq!(n.ratio_round(d), ratio_round_long(n, d));
        }
    }

    #[test]
    fn i256_saturates_to_i128_keeping_the_sign() {
        let one = I256::from_i128(1);
        assert_eq!(I256::from_i128(i128::MAX).saturating_to_i128(), i128::MAX);
        assert_eq!(I256::from_i128(i128::MIN).saturating_to_i128(), i128::MIN);
        assert_eq!(I256::from_i128(-5).saturating_to_i128(), -5);
        assert_eq!(one.shl(127).saturating_to_i128(), i128::MAX);
        assert_eq!(one.shl(127).neg().saturating_to_i128(), i128::MIN);
        assert_eq!(one.shl(127).neg().sub(one).saturating_to_i128(), i128::MIN);
        // 2^130 − 2^130 + 7: exact in between, back in range at the end.
        let big = I256::mul_i128(1 << 65, 1 << 65);
        assert_eq!(big.saturating_to_i128(), i128::MAX);
        assert_eq!(big.neg().saturating_to_i128(), i128::MIN);
        let seven = big
            .sub(I256::mul_i128(1 << 65, 1 << 65))
            .add(I256::from_i128(7));
        assert_eq!(seven.saturating_to_i128(), 7);
    }

    #[test]
    fn i256_division_rounds_and_signs() {
        let n = I256::mul_i128(i128::MAX, 3);
        let d = I256::from_i128(i128::MAX);
        assert_eq!(n.ratio_round(d), 3);
        assert_eq!(I256::from_i128(-7).ratio_round(I256::from_i128(2)), -4);
        assert_eq!(I256::from_i128(7).ratio_round(I256::from_i128(-2)), -4);
        assert_eq!(I256::from_i128(5).ratio_round(I256::from_i128(3)), 2);
        assert_eq!(I256::from_i128(1).ratio_round(I256::ZERO), i128::MAX);
        assert_eq!(I256::from_i128(-1).ratio_round(I256::ZERO), i128::MIN);
        assert_eq!(I256::ZERO.ratio_round(I256::ZERO), 0);
        let big = I256::mul_i128(i128::MIN, i128::MIN);
        assert_eq!(big.ratio_round(I256::from_i128(1)), i128::MAX);
        assert_eq!(big.neg().ratio_round(I256::from_i128(1)), i128::MIN);
        // 2^200 / 2^190 = 2^10 exactly.
        let p = I256::mul_i128(1 << 100, 1 << 100);
        assert_eq!(p.ratio_round(I256::from_i128(1 << 100).shl(90)), 1 << 10);
    }

    #[test]
    fn i256_shifts_past_the_limb_boundary() {
        let one = I256::from_i128(1);
        assert_eq!(one.shl(0), one);
        assert_eq!(
            one.shl(127),
            I256 {
                hi: 0,
                lo: 1 << 127
            }
        );
        assert_eq!(one.shl(128), I256 { hi: 1, lo: 0 });
        assert_eq!(
            one.shl(255),
            I256 {
                hi: 1 << 127,
                lo: 0
            }
        );
        assert_eq!(one.shl(256), I256::ZERO);
        assert_eq!(one.shl(u32::MAX), I256::ZERO);
    }

    #[test]
    fn round_shr_matches_the_long_division() {
        // Values around the rounding ties and the saturation edges, both
        // signs, shifts across the limb boundary.
        let mut values = vec![
            I256::ZERO,
            I256::mul_i128(i128::MAX, i128::MAX),
            I256::mul_i128(i128::MIN, i128::MIN),
            I256::mul_i128(i128::MIN, i128::MAX),
            I256::mul_i128(1 << 100, 3 << 80).add(I256::from_i128(1 << 64)),
        ];
        for e in [0u32, 1, 2, 31, 63, 64, 65, 100, 126, 127, 128, 190] {
            let p = I256::from_i128(1).shl(e);
            for d in [-1i128, 0, 1] {
                values.push(p.add(I256::from_i128(d)));
            }
        }
        for k in [1u32, 2, 32, 64, 65, 96, 127] {
            let den = I256::from_i128(1).shl(k);
            for &v in &values {
                for v in [v, v.neg()] {
                    let half_up = v.add(I256::from_i128(1).shl(k - 1));
                    assert_eq!(v.round_shr(k), v.ratio_round(den), "{v:?} >> {k}");
                    assert_eq!(
                        half_up.round_shr(k),
                        half_up.ratio_round(den),
                        "{half_up:?} >> {k}"
                    );
                }
            }
        }
        assert_eq!(I256::from_i128(3).round_shr(1), 2);
        assert_eq!(I256::from_i128(-3).round_shr(1), -2);
        assert_eq!(I256::from_i128(5).round_shr(2), 1);
    }

    /// The split products (wasm32's) equal the native widening products on
    /// the extremes and their neighbours, every sign combination.
    #[test]
    fn split_products_equal_native_products_at_the_extremes() {
        let edges = [
            0,
            1,
            -1,
            2,
            i64::MAX,
            i64::MIN,
            i64::MAX - 1,
            i64::MIN + 1,
            1 << 32,
            -(1 << 32),
            (1 << 32) - 1,
            0xffff_ffff_ffff,
            -0x1234_5678_9abc_def0,
        ];
        for &a in &edges {
            for &b in &edges {
                assert_eq!(wide_mul_split(a, b), a as i128 * b as i128, "{a} · {b}");
                let (ua, ub) = (a as u64, b as u64);
                assert_eq!(
                    wide_mul_u64_split(ua, ub),
                    ua as u128 * ub as u128,
                    "{ua} · {ub}"
                );
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn split_products_equal_native_products(a: i64, b: i64) {
            proptest::prop_assert_eq!(wide_mul_split(a, b), a as i128 * b as i128);
            let (ua, ub) = (a as u64, b as u64);
            proptest::prop_assert_eq!(wide_mul_u64_split(ua, ub), ua as u128 * ub as u128);
        }
    }
}
