//! `Vect`, the 2D vector of the MIS Vector module (§9), in [`Real`].
//!
//! Sign convention: Chipmunk's. [`Vect::perp`] turns a vector 90°
//! counter-clockwise, `(x, y) → (−y, x)`, and [`Vect::rperp`] turns it
//! clockwise, `(x, y) → (y, −x)`. (The MIS text has the two words swapped; we
//! follow Chipmunk, whose routine names the MIS keeps.)
//!
//! Dot and cross products accumulate exactly on 128 bits and round once.
//! Lengths use a 128-bit integer square root, so they are exact (floor) and
//! never overflow, even for vectors whose squared length does not fit.
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use serde::{Deserialize, Serialize};

use super::exact::int::{sum_sq, wide_mul};
use super::real::{Real, FRAC_BITS};

/// A 2D vector (or point) of [`Real`]s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Vect {
    /// x component.
    pub x: Real,
    /// y component.
    pub y: Real,
}

/// Exact `|v|²` in units of 2^-64.
#[inline(always)]
fn len_sq_raw(v: Vect) -> u128 {
    sum_sq(v.x.to_bits(), v.y.to_bits())
}

impl Vect {
    /// The zero vector (MIS `zeroVect`).
    pub const ZERO: Vect = Vect::new(Real::ZERO, Real::ZERO);
    /// (1, 0).
    pub const X: Vect = Vect::new(Real::ONE, Real::ZERO);
    /// (0, 1).
    pub const Y: Vect = Vect::new(Real::ZERO, Real::ONE);

    /// MIS `vect`: a vector from two components.
    #[inline(always)]
    pub const fn new(x: Real, y: Real) -> Vect {
        Vect { x, y }
    }

    /// A vector from two integers (exact).
    #[inline(always)]
    pub const fn from_ints(x: i32, y: i32) -> Vect {
        Vect::new(Real::from_int(x), Real::from_int(y))
    }

    /// A vector from `f64`s at the API edge; errors on non-finite or
    /// out-of-range components. Deterministic for the same `f64` bits (see
    /// [`Real::from_f64`], also for what is not).
    pub fn from_f64(x: f64, y: f64) -> Result<Vect, super::RealError> {
        Ok(Vect::new(Real::from_f64(x)?, Real::from_f64(y)?))
    }

    /// `(x, y)` as `f64` for rendering and reports (output only; see
    /// [`Real::to_f64`]).
    pub fn to_f64(self) -> (f64, f64) {
        (self.x.to_f64(), self.y.to_f64())
    }

    /// `(x, y)` as `f32` for rendering (output only; see [`Real::to_f32`]).
    pub fn to_f32(self) -> (f32, f32) {
        (self.x.to_f32(), self.y.to_f32())
    }

    /// MIS `vectEqual`: exact equality.
    #[inline(always)]
    pub fn equal(self, other: Vect) -> bool {
        self == other
    }

    /// MIS `vectMult`: scalar multiple.
    #[inline(always)]
    pub fn mult(self, s: Real) -> Vect {
        Vect::new(self.x * s, self.y * s)
    }

    /// MIS `vectDot`, rounded once.
    #[inline(always)]
    pub fn dot(self, other: Vect) -> Real {
        Real::mul_add2(self.x, other.x, self.y, other.y)
    }

    /// MIS `vectCross`: z of the 3D cross product, `x₁y₂ − y₁x₂`, rounded once.
    #[inline(always)]
    pub fn cross(self, other: Vect) -> Real {
        Real::mul_sub2(self.x, other.y, self.y, other.x)
    }

    /// MIS `vectPerp`: turned 90° counter-clockwise (Chipmunk convention).
    #[inline(always)]
    pub fn perp(self) -> Vect {
        Vect::new(-self.y, self.x)
    }

    /// MIS `vectRPerp`: turned 90° clockwise (Chipmunk convention).
    #[inline(always)]
    pub fn rperp(self) -> Vect {
        Vect::new(self.y, -self.x)
    }

    /// MIS `vectProject`: projection of `self` onto `other`;
    /// projecting onto the zero vector gives zero.
    pub fn project(self, other: Vect) -> Vect {
        let len_sq = len_sq_raw(other);
        if len_sq == 0 {
            return Vect::ZERO;
        }
        // t = (self·other)/|other|², with both on 128 bits: no overflow, one rounding.
        let dot = wide_mul(self.x.to_bits(), other.x.to_bits())
            .saturating_add(wide_mul(self.y.to_bits(), other.y.to_bits()));
        let t = wide_ratio(dot, len_sq);
        other.mult(t)
    }

    /// MIS `vectForAngle`: the unit vector at `angle` radians from +x.
    pub fn for_angle(angle: Real) -> Vect {
        let (s, c) = angle.sin_cos();
        Vect::new(c, s)
    }

    /// MIS `vectToAngle`: the angle of the vector from +x, in `[-π, π]`.
    pub fn to_angle(self) -> Real {
        self.y.atan2(self.x)
    }

    /// MIS `vectRotate`: complex multiplication `self · other`.
    #[inline(always)]
    pub fn rotate(self, other: Vect) -> Vect {
        Vect::new(
            Real::mul_sub2(self.x, other.x, self.y, other.y),
            Real::mul_add2(self.x, other.y, self.y, other.x),
        )
    }

    /// MIS `vectUnrotate`: inverse of [`rotate`](Self::rotate) for a unit
    /// `other` (multiplication by its conjugate).
    #[inline(always)]
    pub fn unrotate(self, other: Vect) -> Vect {
        Vect::new(
            Real::mul_add2(self.x, other.x, self.y, other.y),
            Real::mul_sub2(self.y, other.x, self.x, other.y),
        )
    }

    /// MIS `vectLengthSq` (saturates once |v| > 46,340).
    #[inline(always)]
    pub fn length_sq(self) -> Real {
        self.dot(self)
    }

    /// MIS `vectLength`: floor of the exact length, never overflows inside
    /// the computation (saturates only if the length itself exceeds `Real::MAX`).
    #[inline]
    pub fn length(self) -> Real {
        let root = len_sq_raw(self).isqrt();
        Real::from_bits(i64::try_from(root).unwrap_or(i64::MAX))
    }

    /// MIS `vectNormalize`: the unit vector along `self`; zero stays zero.
    /// The components are scaled up to 62 bits before the 128-bit root, so
    /// huge and tiny vectors alike normalise to within about 1 ulp per component.
    pub fn normalize(self) -> Vect {
        let (v, _) = self.normalize_with_length();
        v
    }

    /// `(normalize(self), length(self))` sharing the one square root.
    pub fn normalize_with_length(self) -> (Vect, Real) {
        let (x, y) = (self.x.to_bits() as i128, self.y.to_bits() as i128);
        let mag = x.unsigned_abs().max(y.unsigned_abs());
        if mag == 0 {
            return (Vect::ZERO, Real::ZERO);
        }
        // Scale both components up so the larger has its top bit at bit 62:
        // direction is scale-free, and the root then has ~31 significant bits
        // however short the vector is.
        let shift = mag.leading_zeros().saturating_sub(128 - 63);
        let (xs, ys) = (x << shift, y << shift);
        // |xs|, |ys| < 2^63 after the scaling: each square is below 2^126 and
        // their sum below 2^127.
        #[allow(clippy::arithmetic_side_effects)]
        let sq = (xs * xs) as u128 + (ys * ys) as u128;
        let len = sq.isqrt();
        let scale = |c: i128| -> Real { Real::from_bits(div_round_wide(c << FRAC_BITS, len)) };
        let len_real = Real::from_bits(i64::try_from(len >> shift).unwrap_or(i64::MAX));
        (Vect::new(scale(xs), scale(ys)), len_real)
    }

    /// MIS `vectClamp`: `self` if its length is at most `len`, otherwise
    /// shrunk to length `len` (a negative `len` counts as 0).
    pub fn clamp(self, len: Real) -> Vect {
        let len = len.max(Real::ZERO);
        let (unit, l) = self.normalize_with_length();
        if l <= len {
            self
        } else {
            unit.mult(len)
        }
    }

    /// MIS `vectLerp`: `self + (other − self)·t`.
    #[inline]
    pub fn lerp(self, other: Vect, t: Real) -> Vect {
        self + (other - self).mult(t)
    }

    /// MIS `vectDistSq`.
    #[inline]
    pub fn dist_sq(self, other: Vect) -> Real {
        (self - other).length_sq()
    }

    /// MIS `vectDist`.
    #[inline]
    pub fn dist(self, other: Vect) -> Real {
        (self - other).length()
    }

    /// MIS `vectNear`: true if the distance is strictly less than `dist`.
    pub fn near(self, other: Vect, dist: Real) -> bool {
        // Compare squares on 128 bits: exact, no overflow, no square root.
        let d = self - other;
        let lim = dist.max(Real::ZERO).to_bits().unsigned_abs() as u128;
        // lim < 2^63: the square is below 2^126.
        #[allow(clippy::arithmetic_side_effects)]
        let lim_sq = lim * lim;
        len_sq_raw(d) < lim_sq
    }

    /// Component-wise minimum.
    #[inline]
    pub fn min(self, other: Vect) -> Vect {
        Vect::new(self.x.min(other.x), self.y.min(other.y))
    }

    /// Component-wise maximum.
    #[inline]
    pub fn max(self, other: Vect) -> Vect {
        Vect::new(self.x.max(other.x), self.y.max(other.y))
    }

    /// True if either component is `Real::MIN`/`MAX` (possibly saturated).
    #[inline]
    pub fn is_saturated(self) -> bool {
        self.x.is_saturated() || self.y.is_saturated()
    }
}

/// `n / d` (d > 0) rounded to nearest, ties away from zero, saturated to i64
/// (`d = 0` gives the saturated value, as `Real`'s division does).
#[inline]
fn div_round_wide(n: i128, d: u128) -> i64 {
    // The caller's n is below 2^96 and d below 2^64: the sum never saturates.
    let q = n
        .unsigned_abs()
        .saturating_add(d / 2)
        .checked_div(d)
        .unwrap_or(u128::MAX);
    let q = i64::try_from(q).unwrap_or(i64::MAX);
    if n < 0 {
        q.saturating_neg()
    } else {
        q
    }
}

/// `n / d` where both are in units of 2^-64: a `Real` (units 2^-32).
fn wide_ratio(n: i128, d: u128) -> Real {
    // Shifting n left by 32 may overflow i128; scale d down instead when needed.
    let n_abs = n.unsigned_abs();
    let (n_shifted, d_used) = if n_abs.leading_zeros() > FRAC_BITS {
        (n_abs << FRAC_BITS, d)
    } else {
        (n_abs, (d >> FRAC_BITS).max(1))
    };
    // Either n_shifted < 2^127 and d_used ≤ 2^127, or n_shifted ≤ 2^127 and
    // d_used < 2^96: the sum never saturates. d_used = 0 only for d = 0,
    // which the caller excludes; it would saturate like `Real`'s division.
    let q = n_shifted
        .saturating_add(d_used / 2)
        .checked_div(d_used)
        .unwrap_or(u128::MAX);
    let q = i64::try_from(q).unwrap_or(i64::MAX);
    Real::from_bits(if n < 0 { q.saturating_neg() } else { q })
}

/// MIS `vectAdd` (saturating).
impl Add for Vect {
    type Output = Vect;
    #[inline(always)]
    fn add(self, rhs: Vect) -> Vect {
        Vect::new(self.x + rhs.x, self.y + rhs.y)
    }
}

/// MIS `vectSub` (saturating).
impl Sub for Vect {
    type Output = Vect;
    #[inline(always)]
    fn sub(self, rhs: Vect) -> Vect {
        Vect::new(self.x - rhs.x, self.y - rhs.y)
    }
}

impl AddAssign for Vect {
    #[inline(always)]
    fn add_assign(&mut self, rhs: Vect) {
        *self = *self + rhs;
    }
}

impl SubAssign for Vect {
    #[inline(always)]
    fn sub_assign(&mut self, rhs: Vect) {
        *self = *self - rhs;
    }
}

/// MIS `vectNeg` (saturating).
impl Neg for Vect {
    type Output = Vect;
    #[inline(always)]
    fn neg(self) -> Vect {
        Vect::new(-self.x, -self.y)
    }
}

impl Mul<Real> for Vect {
    type Output = Vect;
    #[inline(always)]
    fn mul(self, s: Real) -> Vect {
        self.mult(s)
    }
}

impl Mul<Vect> for Real {
    type Output = Vect;
    #[inline(always)]
    fn mul(self, v: Vect) -> Vect {
        v.mult(self)
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::real;

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    #[test]
    fn perp_turns_counter_clockwise_like_chipmunk() {
        assert_eq!(v(1, 0).perp(), v(0, 1));
        assert_eq!(v(1, 0).rperp(), v(0, -1));
        assert_eq!(v(3, 4).perp().perp(), v(-3, -4));
    }

    #[test]
    fn add_sub_mult_neg_dot_cross() {
        assert_eq!(v(1, 2) + v(3, 4), v(4, 6));
        assert_eq!(v(1, 2) - v(3, 4), v(-2, -2));
        assert_eq!(v(1, 2).mult(real!(0.5)), Vect::new(real!(0.5), Real::ONE));
        assert_eq!(-v(1, -2), v(-1, 2));
        assert_eq!(v(1, 2).dot(v(3, 4)), Real::from_int(11));
        assert_eq!(v(1, 2).cross(v(3, 4)), Real::from_int(-2));
        assert!(v(1, 2).equal(v(1, 2)));
        assert!(!v(1, 2).equal(v(2, 1)));
    }

    #[test]
    fn project_onto_axis_and_zero() {
        assert_eq!(v(3, 4).project(v(2, 0)), v(3, 0));
        assert_eq!(v(3, 4).project(Vect::ZERO), Vect::ZERO);
        // Large vectors: the 128-bit path does not overflow.
        assert_eq!(v(1_000_000, 5).project(v(1_000_000, 0)), v(1_000_000, 0));
    }

    #[test]
    fn rotate_unrotate_are_inverse_for_unit_vectors() {
        let r = v(0, 1);
        assert_eq!(v(2, 3).rotate(r), v(-3, 2));
        assert_eq!(v(2, 3).rotate(r).unrotate(r), v(2, 3));
    }

    #[test]
    fn length_exact_and_without_overflow() {
        assert_eq!(v(3, 4).length(), Real::from_int(5));
        assert_eq!(v(3, 4).length_sq(), Real::from_int(25));
        // 1e6² overflows length_sq but not length.
        assert_eq!(v(600_000, 800_000).length(), Real::from_int(1_000_000));
        assert_eq!(v(600_000, 800_000).length_sq(), Real::MAX);
        assert_eq!(v(3, 4).dist(Vect::ZERO), Real::from_int(5));
        assert_eq!(v(3, 4).dist_sq(v(0, 0)), Real::from_int(25));
    }

    #[test]
    fn normalize_unit_zero_and_extremes() {
        assert_eq!(v(3, 4).normalize(), Vect::new(real!(0.6), real!(0.8)));
        assert_eq!(Vect::ZERO.normalize(), Vect::ZERO);
        let tiny = Vect::new(Real::DELTA, Real::ZERO);
        assert_eq!(tiny.normalize(), Vect::X);
        // A diagonal of 1 ulp: (√½, √½), not (1, 1).
        let diag = Vect::new(Real::DELTA, Real::DELTA).normalize();
        assert!((diag.x.to_f64() - 0.5f64.sqrt()).abs() < 1e-9, "{diag:?}");
        let huge = Vect::new(Real::MIN, Real::MIN);
        let n = huge.normalize();
        assert!((n.x.to_f64() + 0.5f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn clamp_lerp_near() {
        assert_eq!(v(3, 4).clamp(Real::from_int(10)), v(3, 4));
        // 0.6 and 0.8 are not exact in binary: within 4 ulp of (3, 4).
        let c = v(30, 40).clamp(Real::from_int(5)) - v(3, 4);
        assert!(
            c.x.abs() <= Real::from_bits(4) && c.y.abs() <= Real::from_bits(4),
            "{c:?}"
        );
        assert_eq!(v(3, 4).clamp(-Real::ONE), Vect::ZERO);
        assert_eq!(
            v(0, 0).lerp(v(10, 20), real!(0.25)),
            Vect::new(real!(2.5), Real::from_int(5))
        );
        assert!(v(0, 0).near(v(3, 4), real!(5.01)));
        assert!(!v(0, 0).near(v(3, 4), Real::from_int(5)));
    }
}
