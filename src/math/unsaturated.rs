//! Exact I32F32 arithmetic that *detects* overflow instead of saturating.
//!
//! [`Real`]'s operators saturate, and every saturation check costs a few
//! instructions on every operation (measured: the checks are about a third of
//! all instructions of a resting-pyramid step). In hot loops where overflow
//! is rare but must still be handled exactly, [`Unsaturated`] computes with
//! plain (wrapping) integer operations, the same round-to-nearest,
//! ties-away-from-zero products as [`Real`], and a sticky record of whether
//! any result may have left the `i64` range (an overflow bit for additions;
//! for products, the OR of their high words, tested once at the end). The
//! caller runs the fast computation on copies; if the record is clear no
//! operation could have saturated, so the result is bit-identical to the
//! [`Real`] computation (wrapping and saturating arithmetic agree on every
//! in-range result); if it is set (conservatively: a false alarm costs only
//! the rerun), the caller discards the copies and runs the saturating
//! version. `Bounded` goes one step further for kernels whose constants a
//! range check (`below_2_62`) accepted once per step. The solver's fast
//! path is tested against the saturating one on random and extreme inputs.
use super::exact::int::wide_mul;
use super::real::{Real, FRAC_BITS};

/// `2^(FRAC_BITS − 1)`: the rounding half.
const HALF: i128 = 1 << (FRAC_BITS - 1);

/// Products whose high word is recorded at or above this (`|p| ≥ 2^93`,
/// results of `2^29` and more) raise the flag: far beyond any value a
/// scene reaches, and far enough below `i64`'s edge that rounding cannot
/// reach it (see [`Unsaturated::round`]).
const WIDE_LIMIT: u64 = 1 << 29;

/// Sums of products in 64-bit pieces ([`SplitSum`]) instead of `i128`:
/// on wasm32, whose only multiply is 64-bit. There an exact 128-bit
/// product is four partial products plus carries, and the `i128`
/// additions and shifts around it are several operations each; the
/// pieces need neither. Elsewhere the compiler drops the pieces' code.
const SPLIT: bool = cfg!(target_arch = "wasm32");

/// A sum of up to four exact products `Σ xᵢ·yᵢ` (raw `Real` bits) in
/// 64-bit pieces: with `x = xₕ·2^32 + xₗ` (`xₕ` signed, `0 ≤ xₗ < 2^32`),
/// `x·y = xₕyₕ·2^64 + (xₕyₗ + xₗyₕ)·2^32 + xₗyₗ`, so the sum is
/// `(high + Σ ⌊xₗyₗ / 2^32⌋)·2^32 + Σ (xₗyₗ mod 2^32)`.
///
/// The record is `(|xₕ| + 1)(|yₕ| + 1)` per product (one's complement for
/// negative halves, so it bounds `|x·y| < record·2^64`), OR-ed. While
/// every record is below `2^27`, each product is below `2^91` and its
/// `high` part below `3·2^59`: four of them add without wrapping, the sum
/// is below `2^93` and the rounded result within `[−2^61, 2^61]`, exactly
/// the result and the bound of the `i128` form. [`round`](Self::round)
/// puts the record into [`Unsaturated`]'s, scaled so that its limits
/// (`2^29`, and `Ranged`'s `2^28`) stand for records of `2^27` and `2^26`:
/// stricter than the `i128` form's, so at worst a false alarm (the
/// saturating rerun), never a bit.
#[derive(Clone, Copy, Debug, Default)]
struct SplitSum {
    /// `Σ (xₕyₕ·2^32 + xₕyₗ + xₗyₕ)`, in units of `2^32` of the sum.
    high: i64,
    /// `Σ ⌊xₗyₗ / 2^32⌋`.
    carries: u64,
    /// `Σ (xₗyₗ mod 2^32)`.
    low: u64,
    record: u64,
}

impl SplitSum {
    /// The sum plus `a·b`.
    #[inline(always)]
    fn plus(self, a: Real, b: Real) -> SplitSum {
        self.add(a.to_bits(), b.to_bits())
    }

    /// The sum minus `a·b` (`a·(−b)`: for `b = i64::MIN` the negation
    /// wraps, but that factor's record, `2^31` at least, raises the flag).
    #[inline(always)]
    fn minus(self, a: Real, b: Real) -> SplitSum {
        self.add(a.to_bits(), b.to_bits().wrapping_neg())
    }

    #[inline(always)]
    fn add(self, x: i64, y: i64) -> SplitSum {
        const LOW: i64 = 0xffff_ffff;
        let (xh, xl, yh, yl) = (x >> 32, x & LOW, y >> 32, y & LOW);
        let high = xh
            .wrapping_mul(yh)
            .wrapping_shl(32)
            .wrapping_add(xh.wrapping_mul(yl))
            .wrapping_add(xl.wrapping_mul(yh));
        // Both factors below 2^32: the product below 2^64.
        let ll = (xl as u64).wrapping_mul(yl as u64);
        // |h| + 1 for h ≥ 0, |h| for h < 0: at most 2^31 each.
        let size = |h: i64| ((h ^ (h >> 63)) as u64).wrapping_add(1);
        SplitSum {
            high: self.high.wrapping_add(high),
            carries: self.carries.wrapping_add(ll >> 32),
            low: self.low.wrapping_add(ll & LOW as u64),
            record: self.record | size(xh).wrapping_mul(size(yh)),
        }
    }

    /// The sum rounded as `Real`'s products (to nearest, ties away from
    /// zero), its record added to `u`'s.
    #[inline(always)]
    fn round(self, u: &mut Unsaturated) -> Real {
        // At most four terms: the carries below 2^34, the low sums below
        // 2^34, so these additions do not wrap while the record is clear.
        let high = self
            .high
            .wrapping_add(self.carries as i64)
            .wrapping_add((self.low >> 32) as i64);
        let low = self.low & 0xffff_ffff;
        // The sum is high·2^32 + low with 0 ≤ low < 2^32: negative exactly
        // when `high` is.
        let negative = u64::from(high < 0);
        // low + 2^31 − negative < 2^33: no wrap.
        let up = low.wrapping_add(1 << 31).wrapping_sub(negative) >> 32;
        // Records reach 2^62 (two factors of 2^31): capped before scaling.
        u.wide |= self.record.min(1 << 60) << 2;
        Real::from_bits(high.wrapping_add(up as i64))
    }
}

/// A sticky overflow flag and the operations that raise it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unsaturated {
    /// An addition or a 128-bit sum wrapped.
    overflow: bool,
    /// The bitwise OR of `|hi|` (one's complement) over the high words of
    /// every rounded 128-bit product: a cheap, conservative range record
    /// (see [`Unsaturated::round`]).
    wide: u64,
}

impl Unsaturated {
    /// A clear flag.
    #[inline(always)]
    pub const fn new() -> Unsaturated {
        Unsaturated {
            overflow: false,
            wide: 0,
        }
    }

    /// True if any operation since [`Unsaturated::new`] left the range:
    /// the results are then meaningless and must be recomputed with [`Real`].
    #[inline(always)]
    pub const fn overflowed(self) -> bool {
        self.overflow | (self.wide >= WIDE_LIMIT)
    }

    /// `a + b`.
    #[inline(always)]
    pub fn add(&mut self, a: Real, b: Real) -> Real {
        let (r, o) = a.to_bits().overflowing_add(b.to_bits());
        self.overflow |= o;
        Real::from_bits(r)
    }

    /// `a − b`.
    #[inline(always)]
    pub fn sub(&mut self, a: Real, b: Real) -> Real {
        let (r, o) = a.to_bits().overflowing_sub(b.to_bits());
        self.overflow |= o;
        Real::from_bits(r)
    }

    /// Rounds a 128-bit sum of products like `Real` does (nearest, ties away
    /// from zero), recording its size for [`overflowed`](Self::overflowed).
    ///
    /// Why this is exact without a check per product: the high word `hi`
    /// of `p` is recorded as `hi ^ (hi >> 63)` (`|hi|` for `hi ≥ 0`,
    /// `|hi| − 1` below), OR-ed into one word, and tested once at the end
    /// against [`WIDE_LIMIT`]. Below it every recorded `p` lies in
    /// `[−2^93, 2^93)`, so `p + HALF − [p < 0]` cannot wrap and the
    /// rounded quotient lies in `[−2^61, 2^61]`: it fits `i64`, which
    /// is the saturating operator's result bit for bit. Above it the caller
    /// reruns saturating (a false alarm only costs that rerun, never a
    /// bit). This is an XOR and an OR per product (the sign shift is shared
    /// with the rounding bias) instead of an `i128` overflow test and a
    /// range comparison.
    #[inline(always)]
    fn round(&mut self, p: i128) -> Real {
        let hi = (p >> 64) as i64;
        let negative = hi >> 63; // 0 or −1
        self.wide |= (hi ^ negative) as u64;
        let biased = p.wrapping_add(HALF.wrapping_add(i128::from(negative)));
        Real::from_bits((biased >> FRAC_BITS) as i64)
    }

    /// `a · b`, rounded as [`Real`]'s `*`.
    #[inline(always)]
    pub fn mul(&mut self, a: Real, b: Real) -> Real {
        if SPLIT {
            return SplitSum::default().plus(a, b).round(self);
        }
        // |a·b| ≤ 2^126: the product itself never overflows i128.
        self.round(wide_mul(a.to_bits(), b.to_bits()))
    }

    /// `a·b + c·d` with one rounding, as [`Real::mul_add2`].
    #[inline(always)]
    pub fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        if SPLIT {
            return SplitSum::default().plus(a, b).plus(c, d).round(self);
        }
        let p = wide_mul(a.to_bits(), b.to_bits());
        let q = wide_mul(c.to_bits(), d.to_bits());
        // Each product lies in [−2^126 + 2^63, 2^126], so the sum wraps
        // only when both are 2^126 (every factor `i64::MIN`): it becomes
        // −2^127, whose high word `round` records as far out of range.
        self.round(p.wrapping_add(q))
    }

    /// `a·b − c·d` with one rounding, as [`Real::mul_sub2`].
    #[inline(always)]
    pub fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        if SPLIT {
            return SplitSum::default().plus(a, b).minus(c, d).round(self);
        }
        let p = wide_mul(a.to_bits(), b.to_bits());
        let q = wide_mul(c.to_bits(), d.to_bits());
        // Both products lie in [−2^126 + 2^63, 2^126]: the difference is
        // within (−2^127, 2^127) and never wraps.
        self.round(p.wrapping_sub(q))
    }

    /// `Σ xᵢ·yᵢ` over four terms with one rounding, as [`Real::dot4`].
    #[inline(always)]
    pub fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        let [x0, x1, x2, x3] = x;
        let [y0, y1, y2, y3] = y;
        if SPLIT {
            let sum = SplitSum::default().plus(x0, y0).plus(x1, y1);
            return sum.plus(x2, y2).plus(x3, y3).round(self);
        }
        let p = |a: Real, b: Real| wide_mul(a.to_bits(), b.to_bits());
        let (s, o1) = p(x0, y0).overflowing_add(p(x1, y1));
        let (s, o2) = s.overflowing_add(p(x2, y2));
        let (s, o3) = s.overflowing_add(p(x3, y3));
        self.overflow |= o1 | o2 | o3;
        self.round(s)
    }
}

/// The arithmetic of a hot loop written once and run in two modes:
/// [`Saturating`] (the [`Real`] operators, the reference) and
/// [`Unsaturated`] (the fast path with an overflow flag). The same
/// sequence of calls gives the same bits in both modes unless the flag is
/// raised.
pub trait FixedArith {
    /// `a + b`.
    fn add(&mut self, a: Real, b: Real) -> Real;
    /// `a − b`.
    fn sub(&mut self, a: Real, b: Real) -> Real;
    /// `a · b`.
    fn mul(&mut self, a: Real, b: Real) -> Real;
    /// `a·b + c·d`, one rounding.
    fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real;
    /// `a·b − c·d`, one rounding.
    fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real;
    /// `Σ xᵢ·yᵢ` over four terms, one rounding.
    fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real;

    /// [`dot4`](Self::dot4) where one factor of every product is a
    /// constant of the kernel that `below_2_62` accepted. Only
    /// `Bounded` uses the promise; the others compute `dot4`.
    #[inline(always)]
    fn dot4_bounded(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        self.dot4(x, y)
    }

    /// `−c` for a constant `c` of the kernel, as `Real`'s saturating `−`.
    /// `Bounded` negates without the saturation test (`below_2_62`
    /// accepted `c`, so `c ≠ i64::MIN`).
    #[inline(always)]
    fn neg_const(&mut self, c: Real) -> Real {
        -c
    }
}

/// True when every value is below `2^62` in magnitude (raw bits): the
/// promise [`Bounded`] relies on, checked once per step for a kernel's
/// constants (normals, lever arms, `I⁻¹·(r × n)`) instead of once per
/// operation in every iteration.
#[inline(always)]
pub(crate) fn below_2_62(values: &[Real]) -> bool {
    let or = values
        .iter()
        .fold(0u64, |acc, v| acc | v.to_bits().unsigned_abs());
    or < 1 << 62
}

/// [`Unsaturated`] for a kernel whose constants [`below_2_62`] accepted:
/// the same operations and the same flag, except that the 4-term dot
/// products with such a constant in every product add their 128-bit
/// products without overflow tests (each is below `2^63 · 2^62`, so the
/// sum of four stays below `2^127`), and the constants' negations need no
/// saturation test. The same bits as [`Unsaturated`] and [`Saturating`]
/// whenever the flag stays clear.
///
/// Crate-private: the promise is the caller's (the solver's pre-step checks
/// it), and a wrong promise would wrap silently.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Bounded(pub(crate) Unsaturated);

impl FixedArith for Bounded {
    #[inline(always)]
    fn add(&mut self, a: Real, b: Real) -> Real {
        self.0.add(a, b)
    }
    #[inline(always)]
    fn sub(&mut self, a: Real, b: Real) -> Real {
        self.0.sub(a, b)
    }
    #[inline(always)]
    fn mul(&mut self, a: Real, b: Real) -> Real {
        self.0.mul(a, b)
    }
    #[inline(always)]
    fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        self.0.mul_add2(a, b, c, d)
    }
    #[inline(always)]
    fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        self.0.mul_sub2(a, b, c, d)
    }
    #[inline(always)]
    fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        self.0.dot4(x, y)
    }
    #[inline(always)]
    fn dot4_bounded(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        if SPLIT {
            return self.0.dot4(x, y);
        }
        let [x0, x1, x2, x3] = x;
        let [y0, y1, y2, y3] = y;
        let p = |a: Real, b: Real| wide_mul(a.to_bits(), b.to_bits());
        let sum = p(x0, y0)
            .wrapping_add(p(x1, y1))
            .wrapping_add(p(x2, y2))
            .wrapping_add(p(x3, y3));
        self.0.round(sum)
    }
    #[inline(always)]
    fn neg_const(&mut self, c: Real) -> Real {
        Real::from_bits(c.to_bits().wrapping_neg())
    }
}

/// The bound [`Ranged`] checks a manifold's state against (raw bits,
/// `2^26` in `Real` units): see [`Ranged`].
pub(crate) const RANGED_INPUT: u64 = 1 << 58;

/// `Ranged`'s product record limit: a recorded high word below `2^28`
/// means `|p| < 2^92`, a rounded result of at most `2^60`.
const RANGED_WIDE_LIMIT: u64 = 1 << 28;

/// [`Bounded`] for a kernel whose *inputs* a range check accepted once
/// (every state value below [`RANGED_INPUT`], checked per manifold by the
/// caller) and whose additions are few and shallow enough that, with every
/// rounded product at most `2^60` (this type's tighter product record), no
/// sum can leave `i64`: additions and subtractions are then plain wrapping
/// operations without a flag (the same bits as the saturating ones, which
/// agree on every in-range result). The caller proves the depth bound for
/// its kernel; a false alarm of the product record only costs the
/// saturating rerun, never a bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Ranged(pub(crate) Unsaturated);

impl Ranged {
    /// A clear record.
    #[inline(always)]
    pub(crate) const fn new() -> Ranged {
        Ranged(Unsaturated::new())
    }

    /// True if a product left the window (or a checked operation wrapped).
    #[inline(always)]
    pub(crate) const fn overflowed(self) -> bool {
        self.0.overflow | (self.0.wide >= RANGED_WIDE_LIMIT)
    }
}

/// The OR of `|v|` (one's complement) over `values`, to compare with
/// [`RANGED_INPUT`] once: 3 instructions a value.
#[inline(always)]
pub(crate) fn range_record(values: &[Real]) -> u64 {
    values.iter().fold(0u64, |acc, v| {
        let x = v.to_bits();
        acc | (x ^ (x >> 63)) as u64
    })
}

impl FixedArith for Ranged {
    #[inline(always)]
    fn add(&mut self, a: Real, b: Real) -> Real {
        Real::from_bits(a.to_bits().wrapping_add(b.to_bits()))
    }
    #[inline(always)]
    fn sub(&mut self, a: Real, b: Real) -> Real {
        Real::from_bits(a.to_bits().wrapping_sub(b.to_bits()))
    }
    #[inline(always)]
    fn mul(&mut self, a: Real, b: Real) -> Real {
        self.0.mul(a, b)
    }
    #[inline(always)]
    fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        self.0.mul_add2(a, b, c, d)
    }
    #[inline(always)]
    fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        self.0.mul_sub2(a, b, c, d)
    }
    #[inline(always)]
    fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        self.0.dot4(x, y)
    }
    #[inline(always)]
    fn dot4_bounded(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        Bounded(Unsaturated::new()).dot4_bounded_into(&mut self.0, x, y)
    }
    #[inline(always)]
    fn neg_const(&mut self, c: Real) -> Real {
        Real::from_bits(c.to_bits().wrapping_neg())
    }
}

impl Bounded {
    /// [`FixedArith::dot4_bounded`] recording into `u`.
    #[inline(always)]
    fn dot4_bounded_into(self, u: &mut Unsaturated, x: [Real; 4], y: [Real; 4]) -> Real {
        if SPLIT {
            return u.dot4(x, y);
        }
        let [x0, x1, x2, x3] = x;
        let [y0, y1, y2, y3] = y;
        let p = |a: Real, b: Real| wide_mul(a.to_bits(), b.to_bits());
        let sum = p(x0, y0)
            .wrapping_add(p(x1, y1))
            .wrapping_add(p(x2, y2))
            .wrapping_add(p(x3, y3));
        u.round(sum)
    }
}

/// [`FixedArith`] by [`Real`]'s saturating operators.
#[derive(Clone, Copy, Debug, Default)]
pub struct Saturating;

impl FixedArith for Saturating {
    #[inline(always)]
    fn add(&mut self, a: Real, b: Real) -> Real {
        a + b
    }
    #[inline(always)]
    fn sub(&mut self, a: Real, b: Real) -> Real {
        a - b
    }
    #[inline(always)]
    fn mul(&mut self, a: Real, b: Real) -> Real {
        a * b
    }
    #[inline(always)]
    fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        Real::mul_add2(a, b, c, d)
    }
    #[inline(always)]
    fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        Real::mul_sub2(a, b, c, d)
    }
    #[inline(always)]
    fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        Real::dot4(x, y)
    }
}

impl FixedArith for Unsaturated {
    #[inline(always)]
    fn add(&mut self, a: Real, b: Real) -> Real {
        Unsaturated::add(self, a, b)
    }
    #[inline(always)]
    fn sub(&mut self, a: Real, b: Real) -> Real {
        Unsaturated::sub(self, a, b)
    }
    #[inline(always)]
    fn mul(&mut self, a: Real, b: Real) -> Real {
        Unsaturated::mul(self, a, b)
    }
    #[inline(always)]
    fn mul_add2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        Unsaturated::mul_add2(self, a, b, c, d)
    }
    #[inline(always)]
    fn mul_sub2(&mut self, a: Real, b: Real, c: Real, d: Real) -> Real {
        Unsaturated::mul_sub2(self, a, b, c, d)
    }
    #[inline(always)]
    fn dot4(&mut self, x: [Real; 4], y: [Real; 4]) -> Real {
        Unsaturated::dot4(self, x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn r(bits: i64) -> Real {
        Real::from_bits(bits)
    }

    /// Either the flag is raised, or the result equals the saturating one.
    fn agrees(u: Unsaturated, fast: Real, exact: Real) -> bool {
        u.overflowed() || fast == exact
    }

    #[test]
    fn extremes_raise_the_flag() {
        let mut u = Unsaturated::new();
        u.add(Real::MAX, Real::DELTA);
        assert!(u.overflowed());
        let mut u = Unsaturated::new();
        u.mul(Real::MIN, Real::MIN);
        assert!(u.overflowed());
        let mut u = Unsaturated::new();
        u.mul_add2(Real::MIN, Real::MIN, Real::MIN, Real::MIN);
        assert!(u.overflowed());
        // The widest differences: 2^126 − (−2^126 + 2^63) and its negation.
        for (a, b, c, d) in [
            (Real::MIN, Real::MIN, Real::MIN, Real::MAX),
            (Real::MIN, Real::MAX, Real::MIN, Real::MIN),
        ] {
            let mut u = Unsaturated::new();
            u.mul_sub2(a, b, c, d);
            assert!(u.overflowed());
        }
        let mut u = Unsaturated::new();
        assert_eq!(u.mul(Real::TWO, Real::HALF), Real::ONE);
        assert!(!u.overflowed());
    }

    #[test]
    fn bounded_constants_stop_below_2_62() {
        let raw = |bits: i64| [Real::from_bits(bits)];
        assert!(below_2_62(&raw((1 << 62) - 1)));
        assert!(below_2_62(&raw(1 - (1 << 62))));
        assert!(!below_2_62(&raw(1 << 62)));
        assert!(!below_2_62(&raw(-(1 << 62))));
        assert!(!below_2_62(&raw(i64::MIN)));
        assert!(!below_2_62(&[Real::ONE, Real::MAX, Real::ZERO]));
        // At the edge, four products with the widest variable stay exact
        // (flagged by the rounding, never wrapped into a wrong value).
        for (c, v) in [((1i64 << 62) - 1, i64::MIN), (1 - (1 << 62), i64::MIN)] {
            let (c, v) = (Real::from_bits(c), Real::from_bits(v));
            let mut u = Bounded(Unsaturated::new());
            let got = u.dot4_bounded([v; 4], [c; 4]);
            assert!(agrees(u.0, got, Real::dot4([v; 4], [c; 4])));
            assert!(u.0.overflowed());
            assert_eq!(u.neg_const(c), -c);
        }
    }

    #[test]
    fn ties_round_away_from_zero_like_real() {
        for raw in [-3i64, -1, 1, 3, -(1 << 33) - 1, (1 << 33) + 1] {
            let (x, half) = (r(raw), Real::HALF);
            let mut u = Unsaturated::new();
            assert_eq!(u.mul(x, half), x * half, "{raw}");
            assert_eq!(
                u.mul_add2(x, half, x, half),
                Real::mul_add2(x, half, x, half)
            );
            assert_eq!(
                u.mul_sub2(x, half, -x, half),
                Real::mul_sub2(x, half, -x, half)
            );
            assert!(!u.overflowed());
        }
    }

    /// Magnitudes spread over the whole range, extremes included.
    fn any_bits() -> impl Strategy<Value = i64> {
        prop_oneof![
            any::<i64>(),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| v >> s),
            (-64i64..64),
            (-8i64..8).prop_map(|k| k << 31),
            Just(i64::MIN),
            Just(i64::MAX),
        ]
    }

    /// The wasm32 form, run here: either its flag is raised, or each
    /// operation gives the saturating operator's bits; and where
    /// `Ranged`'s tighter limit holds, the result is within `2^60`.
    fn split_agrees(u: Unsaturated, fast: Real, exact: Real) -> bool {
        let ranged = Ranged(u);
        agrees(u, fast, exact) && (ranged.overflowed() || fast.to_bits().unsigned_abs() <= 1 << 60)
    }

    #[test]
    fn split_sums_flag_the_extremes() {
        let split = |terms: &[(Real, Real)]| {
            let mut u = Unsaturated::new();
            let sum = terms
                .iter()
                .fold(SplitSum::default(), |s, &(a, b)| s.plus(a, b));
            (sum.round(&mut u), u)
        };
        for (a, b) in [
            (Real::MIN, Real::MIN),
            (Real::MAX, Real::MAX),
            (Real::MIN, Real::MAX),
        ] {
            assert!(split(&[(a, b)]).1.overflowed());
            assert!(split(&[(a, b), (a, b), (a, b), (a, b)]).1.overflowed());
        }
        // Minus a product with `MIN`: the negation wraps, the flag is up.
        let mut u = Unsaturated::new();
        let _ = SplitSum::default()
            .minus(Real::ONE, Real::MIN)
            .round(&mut u);
        assert!(u.overflowed());
        // Ties go away from zero, both signs.
        for raw in [-3i64, -1, 1, 3, -(1 << 33) - 1, (1 << 33) + 1] {
            let (got, u) = split(&[(r(raw), Real::HALF)]);
            assert_eq!(got, r(raw) * Real::HALF, "{raw}");
            assert!(!u.overflowed());
        }
        assert_eq!(split(&[]).0, Real::ZERO);
    }

    proptest! {
        #[test]
        fn split_sums_match_the_saturating_operations(
            a in any_bits(), b in any_bits(), c in any_bits(), d in any_bits()
        ) {
            let (a, b, c, d) = (r(a), r(b), r(c), r(d));
            let run = |sum: SplitSum| {
                let mut u = Unsaturated::new();
                (sum.round(&mut u), u)
            };
            let zero = SplitSum::default();
            let (v, u) = run(zero.plus(a, b));
            prop_assert!(split_agrees(u, v, a * b));
            let (v, u) = run(zero.plus(a, b).plus(c, d));
            prop_assert!(split_agrees(u, v, Real::mul_add2(a, b, c, d)));
            let (v, u) = run(zero.plus(a, b).minus(c, d));
            prop_assert!(split_agrees(u, v, Real::mul_sub2(a, b, c, d)));
            let (v, u) = run(zero.plus(a, d).plus(b, c).plus(c, b).plus(d, a));
            prop_assert!(split_agrees(u, v, Real::dot4([a, b, c, d], [d, c, b, a])));
        }

        /// Values of ordinary scenes (below 2^12 = 4,096 in `Real` units)
        /// never raise the split form's flag, nor `Ranged`'s.
        #[test]
        fn split_sums_of_small_values_never_flag(
            x in prop::array::uniform4(-(1i64 << 44)..(1i64 << 44)),
            y in prop::array::uniform4(-(1i64 << 44)..(1i64 << 44)),
        ) {
            let sum = (0..4).fold(SplitSum::default(), |s, k| s.plus(r(x[k]), r(y[k])));
            let mut u = Unsaturated::new();
            let v = sum.round(&mut u);
            prop_assert!(!u.overflowed() && !Ranged(u).overflowed());
            prop_assert_eq!(v, Real::dot4(x.map(r), y.map(r)));
        }

        #[test]
        fn matches_the_saturating_operations(
            a in any_bits(), b in any_bits(), c in any_bits(), d in any_bits()
        ) {
            let (a, b, c, d) = (r(a), r(b), r(c), r(d));
            let mut u = Unsaturated::new();
            let v = u.add(a, b);
            prop_assert!(agrees(u, v, a + b));
            let mut u = Unsaturated::new();
            let v = u.sub(a, b);
            prop_assert!(agrees(u, v, a - b));
            let mut u = Unsaturated::new();
            let v = u.mul(a, b);
            prop_assert!(agrees(u, v, a * b));
            let mut u = Unsaturated::new();
            let v = u.mul_add2(a, b, c, d);
            prop_assert!(agrees(u, v, Real::mul_add2(a, b, c, d)));
            let mut u = Unsaturated::new();
            let v = u.mul_sub2(a, b, c, d);
            prop_assert!(agrees(u, v, Real::mul_sub2(a, b, c, d)));
            let mut u = Unsaturated::new();
            let v = u.dot4([a, b, c, d], [d, c, b, a]);
            prop_assert!(agrees(u, v, Real::dot4([a, b, c, d], [d, c, b, a])));
        }

        /// In range the flag stays clear (no false alarms that would send
        /// ordinary scenes down the slow path).
        #[test]
        fn small_values_never_flag(
            a in -(1i64 << 45)..(1i64 << 45), b in -(1i64 << 45)..(1i64 << 45)
        ) {
            let mut u = Unsaturated::new();
            let _ = u.add(r(a), r(b));
            let _ = u.mul(r(a), r(b));
            let _ = u.dot4([r(a); 4], [r(b); 4]);
            prop_assert!(!u.overflowed());
        }
    }
}
