//! Deterministic trigonometry on [`Real`]: [`sin_cos`], [`sin`], [`cos`] and
//! [`atan2`], in pure integer arithmetic (no floats, no `unsafe`, no panics).
//!
//! # Why our own routines
//! The `cordic` crate (0.1.5) was measured unfit for a lockstep engine:
//! its `sqrt` loops forever for `x ≥ 2^30` and for negative `x`; its `atan2`
//! is wrong or panics when `|y/x| ≥ 2^31` (`atan2(1, 2^-32)` returns 0
//! instead of π/2); its `sin_cos` does no exact range reduction, so the error
//! grows with the angle (up to 3·10⁻² at 10⁹ rad), and it costs 150–200 ns per
//! call. The routines below are defined for every input bit pattern and are
//! (almost) correctly rounded.
//!
//! # Method
//! All intermediate values are fixed point with 62 fractional bits ("Q62")
//! or wider; the result is rounded to nearest only once, at the end.
//!
//! * **`sin_cos`**: exact range reduction of the raw bits `b` (angle
//!   `b·2^-32`, any `i64`): the quadrant `k = round(|angle|·2/π)` comes from a
//!   64×64-bit product with 2/π in Q64, and the remainder
//!   `r = |angle| − k·π/2` is computed in `i128` with π/2 in Q94 (95
//!   significant bits). For the largest angle (2^31 rad, `k < 2^31`) the error
//!   of `r` is below 2^-64, so huge angles are as accurate as small ones.
//!   `sin r` and `cos r` (`|r| ≤ π/4`) are Taylor polynomials up to degree 15
//!   and 16 evaluated by Horner's rule in Q62 with `i128` products (truncation
//!   error < 2^-54, far below the output resolution, so no minimax fit is
//!   needed). The quadrant picks/negates the two results. Odd/even symmetry is
//!   exact: `sin(-a) == -sin(a)` and `cos(-a) == cos(a)` bit for bit.
//! * **`atan2`**: signs are stripped (`unsigned_abs`, so `i64::MIN` is fine)
//!   and the octant is folded to `0 ≤ n ≤ d`. Both magnitudes are scaled by the
//!   same power of two so that `d` has its top bit at bit 55 (exact for small
//!   inputs; for large inputs the ratio changes by < 2^-55). A 16-entry table
//!   splits `[0, 1]`: with `i = ⌊16n/d⌋` and `c = (2i+1)/32`,
//!   `atan(n/d) = atan(c) + atan(u)`, `u = (32n − (2i+1)d) / (32d + (2i+1)n)`,
//!   `|u| ≤ 1/32` (one `u128` division). `atan(u)` is its odd Taylor series up
//!   to `u^9` (truncation < 2^-58). The octant is unfolded with π/2 and π in
//!   Q62. Any ratio works, including `|y/x| ≥ 2^31`: `atan2(1 ulp, x)` and
//!   `atan2(y, 1 ulp)` are as accurate as `atan2(1, 1)`. Conventions:
//!   `atan2(0, 0) = 0`, `atan2(0, x < 0) = π` (our zero has no sign),
//!   `atan2(±y, 0) = ±π/2`, and `atan2(-y, x) == -atan2(y, x)` exactly.
//!
//! # Accuracy (measured)
//! Against an `f64` oracle evaluated at the exact input value (angles with
//! more than 53 significant bits are split into two exactly representable
//! parts), over dense sweeps of `[-2π, 2π]` and `[-π, π]`, circles of radius
//! 2^-31 … 2^30, random bits over the whole `i64` range, every magnitude, and
//! the Reals nearest to `k·π/2` up to 2^31 rad (the hardest cases for range
//! reduction), 2·10⁶ points per category, reproducible with
//! `cargo test --release --test geometry -- --nocapture math_trig::max_error`
//! (`TRIG_SWEEP_N=40000000` for the bigger sweep quoted here):
//!
//! | quantity                         | max error (ulp = 2^-32) |
//! |----------------------------------|-------------------------|
//! | `sin`, `cos`                     | 0.5000005               |
//! | `atan2` (vs exact, clamped ±`Real::PI`) | 0.5000000        |
//! | `atan2` near ±π (vs exact π)     | 0.522                   |
//! | `sin² + cos² − 1` (exact sum)    | 1.414 (≈ √2, expected)  |
//! | `atan2(sin a, cos a) − a`        | 1.0                     |
//!
//! The 5·10⁻⁷ ulp above 0.5 is the oracle's own `f64` rounding (2^-53); an
//! offline check of 10⁵ `sin_cos` and 10⁵ `atan2` results of the same kinds
//! against 200-bit `mpmath` found all of them correctly rounded (max 0.49999
//! ulp). The internal error budget is ~2^-59, so results are correctly
//! rounded except within ~2^-27 ulp of a rounding tie.
//!
//! `Real::PI` is π *truncated* (`13493037704`, 0.522 ulp below π), not
//! rounded; `atan2` clamps its result to `[-Real::PI, Real::PI]`, so
//! `atan2(0, -1) == Real::PI` and the range invariant holds, at the price of
//! 0.522 ulp for angles within half an ulp of ±π.
//!
//! The tests enforce 0.501 ulp (`sin`, `cos`, clamped `atan2`), well inside
//! the contract targets of 2 ulp (`sin_cos`) and 4 ulp (`atan2`).
//!
//! # Cost
//! About 19 ns per `sin_cos` (independent of the angle's size) and 16 ns per
//! `atan2` in release builds on the development machine (Xeon, x86-64):
//! `cargo test --release --test geometry -- --ignored --nocapture math_trig::timing`.
use super::exact::int::wide_mul;
use super::Real;

/// 2/π in Q64, rounded to nearest (< 2^64).
const TWO_OVER_PI_Q64: u128 = 11_743_562_013_128_004_906;
/// π/2 in Q94, rounded to nearest (95 significant bits).
const FRAC_PI_2_Q94: i128 = 31_112_826_664_028_885_653_815_243_078;
/// π/2 in Q62, rounded to nearest.
const FRAC_PI_2_Q62: u64 = 7_244_019_458_077_122_842;
/// π in Q62, rounded to nearest (needs the full `u64`).
const PI_Q62: u64 = 14_488_038_916_154_245_685;
/// 1 in Q62.
const ONE_Q62: i64 = 1 << 62;

/// Taylor coefficients of `(sin x − x) / x³` in powers of `x²`, highest first:
/// −1/15!, 1/13!, −1/11!, 1/9!, −1/7!, 1/5!, −1/3! in Q62.
const SIN_COEFFS_Q62: [i64; 7] = [
    -3_526_632,
    740_592_679,
    -115_532_457_973,
    12_708_570_377_060,
    -915_017_067_148_291,
    38_430_716_820_228_233,
    -768_614_336_404_564_651,
];

/// Taylor coefficients of `(cos x − 1) / x²` in powers of `x²`, highest
/// first: 1/16!, −1/14!, …, 1/4!, −1/2! in Q62.
const COS_COEFFS_Q62: [i64; 8] = [
    220_414,
    -52_899_477,
    9_627_704_831,
    -1_270_857_037_706,
    114_377_133_393_536,
    -6_405_119_470_038_039,
    192_153_584_101_141_163,
    -2_305_843_009_213_693_952,
];

/// Taylor coefficients of `(atan u − u) / u³` in powers of `u²`, highest
/// first: 1/9, −1/7, 1/5, −1/3 in Q62.
const ATAN_COEFFS_Q62: [i64; 4] = [
    512_409_557_603_043_100,
    -658_812_288_346_769_701,
    922_337_203_685_477_581,
    -1_537_228_672_809_129_301,
];

/// `atan((2i + 1) / 32)` for `i = 0..16` in Q62, rounded to nearest.
const ATAN_MID_Q62: [i64; 16] = [
    144_068_303_048_368_715,
    431_085_564_716_663_715,
    714_796_307_632_436_780,
    993_162_092_656_742_658,
    1_264_374_201_036_404_774,
    1_526_911_147_692_607_963,
    1_779_569_711_216_534_894,
    2_021_470_584_462_503_821,
    2_252_042_854_410_229_708,
    2_470_993_194_618_540_525,
    2_678_265_955_860_898_238,
    2_873_999_636_550_248_571,
    3_058_483_968_841_891_186,
    3_232_120_473_793_924_516,
    3_395_388_091_196_947_616,
    3_548_814_510_496_411_477,
];

/// Q62 product rounded to nearest; callers keep `|a|, |b| ≤ 2^62`.
// For any two i64, |a·b| ≤ 2^126, so adding 2^61 cannot overflow `i128`.
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
fn mul_q62(a: i64, b: i64) -> i64 {
    ((wide_mul(a, b) + (1 << 61)) >> 62) as i64
}

/// Horner evaluation of `coeffs` (highest power first) at `z` in Q62.
// Every coefficient is below 2^62 · 0.6 and z ≤ (π/4 + ε)² < 0.62 (Q62), so
// each partial sum stays below 2^62 · 0.6 / (1 − 0.62) < 2^63: no overflow.
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
fn horner_q62(coeffs: &[i64], z: i64) -> i64 {
    coeffs.iter().fold(0, |p, &c| c + mul_q62(z, p))
}

/// Rounds a non-negative Q62 value to Q32 (the bits of a `Real`).
// Callers pass sin or cos in Q62, at most 2^62: adding 2^29 cannot overflow.
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
fn q62_to_q32(v: i64) -> i64 {
    (v + (1 << 29)) >> 30
}

/// `(sin x, cos x)` in Q32 for `0 ≤ x ≤ π/4 + ε` given in Q62.
// x < 2^62 and the polynomial terms are below x (sin) and 1 (cos) in Q62:
// both sums stay below 2^63.
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
fn sin_cos_q62(x: i64) -> (i64, i64) {
    let z = mul_q62(x, x);
    let s = x + mul_q62(x, mul_q62(z, horner_q62(&SIN_COEFFS_Q62, z)));
    let c = ONE_Q62 + mul_q62(z, horner_q62(&COS_COEFFS_Q62, z));
    (q62_to_q32(s), q62_to_q32(c))
}

/// Sine and cosine of `angle` (radians), valid for every value of `Real`.
///
/// Exact range reduction plus a Q62 polynomial: correctly rounded (error
/// ≤ 0.5 ulp) except within ~2^-27 ulp of a rounding tie, for every input
/// (see the [module docs](self)), and
/// `sin(-a) == -sin(a)`, `cos(-a) == cos(a)` exactly.
// Ranges are stated at each step below (products below 2^127 in u128/i128,
// remainders below 2^126); the negated values are sines and cosines in Q32,
// at most 2^32 in magnitude.
#[allow(clippy::arithmetic_side_effects)]
#[must_use]
pub fn sin_cos(angle: Real) -> (Real, Real) {
    let bits = angle.to_bits();
    // |angle| = a · 2^-32 with a ≤ 2^63; the sign is reapplied at the end so
    // that odd/even symmetry is exact.
    let a = bits.unsigned_abs();
    // k = round(|angle| · 2/π) = round(a · (2/π·2^64) / 2^96) < 2^31;
    // a · 2/π·2^64 < 2^63 · 2^64 fits u128.
    let k = ((a as u128 * TWO_OVER_PI_Q64 + (1 << 95)) >> 96) as u64;
    // r = |angle| − k·π/2 in Q94: a·2^62 ≤ 2^125 and k·π/2·2^94 < 2^126.
    let r = ((a as i128) << 62) - k as i128 * FRAC_PI_2_Q94;
    // To Q62 (|r| ≤ π/4 + ε < 2^62).
    let r = ((r + (1 << 31)) >> 32) as i64;
    let (s, c) = sin_cos_q62(r.saturating_abs());
    let s = if r < 0 { -s } else { s };
    let (sin, cos) = match k & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    };
    let sin = if bits < 0 { -sin } else { sin };
    (Real::from_bits(sin), Real::from_bits(cos))
}

/// Sine of `angle` (radians); see [`sin_cos`].
#[must_use]
pub fn sin(angle: Real) -> Real {
    sin_cos(angle).0
}

/// Cosine of `angle` (radians); see [`sin_cos`].
#[must_use]
pub fn cos(angle: Real) -> Real {
    sin_cos(angle).1
}

/// `atan(n / d)` in Q62 for `0 ≤ n ≤ d`, `2^55 ≤ d < 2^56`; in `[0, π/4]`.
// Ranges are stated at each step below (m ≤ 31, every term below 2^62, the
// shifted numerator below 2^123, |u| ≤ 2^57, mid < 2^62): no overflow.
#[allow(clippy::arithmetic_side_effects)]
#[inline(always)]
fn atan_unit_q62(n: u64, d: u64) -> i64 {
    if n == 0 {
        return 0;
    }
    // i = ⌊16 n / d⌋ ∈ 0..=16, clamped to 15 (n = d); t = n/d ∈ [i/16, (i+1)/16].
    let i = (n << 4).checked_div(d).unwrap_or(0).min(15);
    let m = 2 * i + 1;
    // u = (t − c) / (1 + t·c) with c = m/32: |u| ≤ 1/32 and |num| ≤ d.
    // 32n < 2^61, m·d < 2^61, den < 63·2^56 < 2^62.
    let num = (n << 5) as i64 - (m * d) as i64;
    let den = (d << 5) + m * n;
    let u = ((u128::from(num.unsigned_abs()) << 62) + u128::from(den / 2))
        .checked_div(u128::from(den))
        .unwrap_or(0) as i64;
    // atan(u) = u + u·w·P(w), w = u², |u| ≤ 2^57 in Q62.
    let w = mul_q62(u, u);
    let atan_u = u + mul_q62(u, mul_q62(w, horner_q62(&ATAN_COEFFS_Q62, w)));
    let mid = ATAN_MID_Q62.get(i as usize).copied().unwrap_or(0);
    let t = if num < 0 { mid - atan_u } else { mid + atan_u };
    t.max(0)
}

/// Four-quadrant arctangent of `y / x` in `[-π, π]`, for every pair of
/// values (including `i64::MIN` bits and any ratio).
///
/// `atan2(0, 0) = 0`, `atan2(0, x < 0) = Real::PI`, `atan2(±y, 0) = ±π/2` and
/// `atan2(-y, x) == -atan2(y, x)` for `y ≠ 0` exactly. Correctly rounded
/// (≤ 0.5 ulp) except near ties and within half an ulp of ±π, where the
/// result is clamped to `±Real::PI` (π truncated, error ≤ 0.522 ulp); see the
/// [module docs](self).
// `lz − 8` and `8 − lz` are taken on the side of the test that keeps them
// non-negative; θ ≤ π·2^62 < 2^64 − 2^29; r ≥ 0, so −r is exact.
#[allow(clippy::arithmetic_side_effects)]
#[must_use]
pub fn atan2(y: Real, x: Real) -> Real {
    let (yb, xb) = (y.to_bits(), x.to_bits());
    let (ay, ax) = (yb.unsigned_abs(), xb.unsigned_abs());
    if ay == 0 && ax == 0 {
        return Real::ZERO;
    }
    // Fold to the first octant: 0 ≤ n ≤ d, d > 0.
    let steep = ay > ax;
    let (n, d) = if steep { (ax, ay) } else { (ay, ax) };
    // Same power-of-two scale for both so that d ∈ [2^55, 2^56).
    let lz = d.leading_zeros();
    let (n, d) = if lz >= 8 {
        (n << (lz - 8), d << (lz - 8))
    } else {
        (n >> (8 - lz), d >> (8 - lz))
    };
    // θ ∈ [0, π] in Q62 (u64: π·2^62 < 2^64).
    let mut theta = atan_unit_q62(n, d) as u64;
    if steep {
        theta = FRAC_PI_2_Q62.saturating_sub(theta);
    }
    if xb < 0 {
        theta = PI_Q62.saturating_sub(theta);
    }
    // Clamped to `Real::PI` (π truncated, 0.52 ulp below π) so that the
    // result always lies in `[-Real::PI, Real::PI]`.
    let r = (((theta + (1 << 29)) >> 30) as i64).min(Real::PI.to_bits());
    Real::from_bits(if yb < 0 { -r } else { r })
}

/// The trigonometric methods of [`Real`], defined here beside the routines
/// they call so that `real.rs` stays below this module.
impl Real {
    /// Sine and cosine of an angle in radians, over the whole range.
    /// See [`trig`](self) for method and error bound.
    #[inline]
    pub fn sin_cos(self) -> (Real, Real) {
        sin_cos(self)
    }

    /// Four-quadrant arctangent of `self / x` in `[-π, π]`; `atan2(0, 0) = 0`.
    #[inline]
    pub fn atan2(self, x: Real) -> Real {
        atan2(self, x)
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    const ULP: f64 = 1.0 / 4_294_967_296.0;

    fn r(v: f64) -> Real {
        Real::from_f64(v).unwrap()
    }

    fn err_ulp(got: Real, want: f64) -> f64 {
        (got.to_f64() - want).abs() / ULP
    }

    /// sin and cos of the exact value of `a`, even when `a` has more than 53
    /// significant bits.
    fn oracle_sin_cos(a: Real) -> (f64, f64) {
        let b = a.to_bits();
        let lo = b & 0x7ff;
        let hi = (b - lo) as f64 * ULP;
        let lo = lo as f64 * ULP;
        let (sh, ch) = hi.sin_cos();
        let (sl, cl) = lo.sin_cos();
        (sh * cl + ch * sl, ch * cl - sh * sl)
    }

    fn check_sin_cos(a: Real) {
        let (s, c) = sin_cos(a);
        let (ws, wc) = oracle_sin_cos(a);
        assert!(err_ulp(s, ws) <= 0.51, "sin({a:?}) = {s:?}, want {ws}");
        assert!(err_ulp(c, wc) <= 0.51, "cos({a:?}) = {c:?}, want {wc}");
    }

    #[test]
    fn constants_match_real() {
        // Real::PI is π truncated (…704.52 → …704); PI_Q62 rounds to …705.
        assert_eq!(((PI_Q62 + (1 << 29)) >> 30) as i64, 13_493_037_705);
        assert_eq!((PI_Q62 as f64 / 2f64.powi(62)), std::f64::consts::PI);
        assert_eq!(FRAC_PI_2_Q62 * 2 + 1, PI_Q62);
        assert_eq!(q62_to_q32(FRAC_PI_2_Q62 as i64), Real::FRAC_PI_2.to_bits());
        assert_eq!(
            ((FRAC_PI_2_Q94 + (1 << 61)) >> 62) as i64,
            Real::FRAC_PI_2.to_bits()
        );
    }

    #[test]
    fn sin_cos_hand_checked() {
        assert_eq!(sin_cos(Real::ZERO), (Real::ZERO, Real::ONE));
        assert_eq!(sin(Real::FRAC_PI_2), Real::ONE);
        assert!(cos(Real::FRAC_PI_2).abs() <= Real::DELTA);
        assert_eq!(cos(Real::PI), -Real::ONE);
        assert!(sin(Real::PI).abs() <= Real::DELTA);
        assert_eq!(cos(Real::TAU), Real::ONE);
        // sin(π/6) = 1/2, cos(π/3) = 1/2.
        assert!((sin(r(std::f64::consts::FRAC_PI_6)) - Real::HALF).abs() <= Real::DELTA);
        assert!((cos(r(std::f64::consts::FRAC_PI_3)) - Real::HALF).abs() <= Real::DELTA);
        // Tiny angles: sin(1 ulp) = 1 ulp, cos(1 ulp) = 1.
        assert_eq!(sin_cos(Real::DELTA), (Real::DELTA, Real::ONE));
        for a in [0.5, 1.0, 2.0, 3.0, -1.0, -2.5, 100.0, 12345.678] {
            check_sin_cos(r(a));
        }
    }

    #[test]
    fn sin_cos_symmetry_is_exact() {
        for b in [1i64, 7, 1 << 32, 123_456_789_012, i64::MAX, 6_746_518_852] {
            let (s, c) = sin_cos(Real::from_bits(b));
            let (sn, cn) = sin_cos(Real::from_bits(-b));
            assert_eq!(sn, -s);
            assert_eq!(cn, c);
        }
    }

    #[test]
    fn sin_cos_huge_angles() {
        for a in [
            Real::MAX,
            Real::MIN,
            Real::from_int(1_000_000_000),
            Real::from_int(-1_000_000_000),
            Real::from_bits(i64::MAX - 12_345),
            Real::from_bits(0x7123_4567_89ab_cdef),
            // The Real nearest to 1_367_130_551 · π/2 (close to a zero of cos).
            Real::from_bits(((1_367_130_551i128 * FRAC_PI_2_Q94 + (1 << 61)) >> 62) as i64),
        ] {
            check_sin_cos(a);
            let (s, c) = sin_cos(a);
            let norm = Real::mul_add2(s, s, c, c);
            assert!((norm - Real::ONE).abs() <= Real::from_bits(2));
        }
        // 10⁹ rad, where the `cordic` crate is off by 3·10⁻²:
        let (s, c) = sin_cos(Real::from_int(1_000_000_000));
        assert!(err_ulp(s, 0.545_843_449_448_699_6f64) < 1.0);
        assert!(err_ulp(c, 0.837_887_181_363_902_3f64) < 1.0);
    }

    #[test]
    fn atan2_hand_checked() {
        assert_eq!(atan2(Real::ZERO, Real::ZERO), Real::ZERO);
        assert_eq!(atan2(Real::ZERO, Real::ONE), Real::ZERO);
        assert_eq!(atan2(Real::ZERO, -Real::ONE), Real::PI);
        assert_eq!(atan2(Real::ONE, Real::ZERO), Real::FRAC_PI_2);
        assert_eq!(atan2(-Real::ONE, Real::ZERO), -Real::FRAC_PI_2);
        let pi_4 = std::f64::consts::FRAC_PI_4;
        assert!(err_ulp(atan2(Real::ONE, Real::ONE), pi_4) <= 0.5);
        assert!(err_ulp(atan2(-Real::ONE, -Real::ONE), -3.0 * pi_4) <= 0.5);
        assert!(err_ulp(atan2(Real::from_int(3), Real::from_int(-3)), 3.0 * pi_4) <= 0.5);
        assert!(err_ulp(atan2(r(1.0), r(3f64.sqrt())), std::f64::consts::FRAC_PI_6) <= 0.51);
        // |y/x| = 2^32: atan2(1, 2^-32) ≈ π/2 − 2^-32.
        let got = atan2(Real::ONE, Real::DELTA);
        assert!(err_ulp(got, 1f64.atan2(ULP)) <= 0.51);
        assert!(got < Real::FRAC_PI_2);
        assert!(err_ulp(atan2(Real::DELTA, Real::ONE), ULP) <= 0.51);
        // π − 2^-63 rad: clamped to Real::PI (π truncated).
        assert_eq!(atan2(Real::DELTA, -Real::MAX), Real::PI);
        assert_eq!(atan2(-Real::DELTA, -Real::MAX), -Real::PI);
        assert_eq!(atan2(Real::MAX, Real::DELTA), Real::FRAC_PI_2);
        assert_eq!(atan2(Real::DELTA, Real::MAX), Real::ZERO);
    }

    #[test]
    fn atan2_extreme_components() {
        let min = Real::MIN;
        let pi_4 = std::f64::consts::FRAC_PI_4;
        assert!(err_ulp(atan2(min, min), -3.0 * pi_4) <= 0.5);
        assert!(err_ulp(atan2(min, Real::MAX), -pi_4) <= 0.51);
        assert!(err_ulp(atan2(Real::MAX, min), 3.0 * pi_4) <= 0.51);
        assert_eq!(atan2(min, Real::ZERO), -Real::FRAC_PI_2);
        assert_eq!(atan2(Real::ZERO, min), Real::PI);
        assert_eq!(atan2(min, Real::DELTA), -Real::FRAC_PI_2);
        // −π/2 − 2^-63 rad rounds to −π/2.
        assert_eq!(atan2(min, -Real::DELTA), -Real::FRAC_PI_2);
        assert_eq!(atan2(Real::DELTA, min), Real::PI);
        for (y, x) in [
            (min, Real::ONE),
            (Real::from_int(-7), min),
            (min, r(-0.001)),
        ] {
            assert!(err_ulp(atan2(y, x), y.to_f64().atan2(x.to_f64())) <= 0.51);
        }
    }

    #[test]
    fn atan2_inverts_sin_cos() {
        for a in [-3.0, -1.0, -0.25, 0.1, 0.785, 1.5, 2.9] {
            let a = r(a);
            let (s, c) = sin_cos(a);
            assert!((atan2(s, c) - a).abs() <= Real::from_bits(2));
        }
    }
}
