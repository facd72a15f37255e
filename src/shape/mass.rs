//! Mass helpers of the MIS (Chipmunk `cpMomentFor*`, `cpAreaFor*`,
//! `cpCentroidForPoly`) and the per-shape [`MassInfo`]
//! ([`Shape::mass_info`]).
//!
//! # Exactness
//! The formulas are Chipmunk 7's, but evaluated on integers: squares, cross
//! and dot products of the raw bits are exact on 128 or 256 bits, and the
//! result is **rounded once** to a `Real`. So:
//! * `area_for_poly` (radius 0) and `centroid_for_poly` are correctly rounded
//!   (within ½ ulp) for polygons spanning less than 2^23 units;
//! * `moment_for_circle`, `moment_for_segment`, `moment_for_box(2)` are
//!   correctly rounded, mass included; `moment_for_poly` keeps 32 guard bits
//!   before multiplying by the mass: error ≤ ½ ulp + |m|·2^-33 ulp;
//! * areas that involve π or lengths are within a few ulp (π is rounded to
//!   ½ ulp, lengths are exact floors); each function states its bound.
//!
//! Polygon integrals are computed on vertex differences (relative to the
//! first vertex, or to the `offset` origin for the moment), so areas and
//! centroid-relative moments are *bit-identical* under translation of the
//! vertices.
//!
//! # Range
//! Results saturate at `Real::MAX` instead of overflowing. The per-unit-mass
//! moment `(w² + h²)/12` of a square box saturates above a side of ≈ 113,500;
//! with a mass of `density · w · h` the moment `m (w² + h²)/12` saturates
//! above a side of ≈ 337 at density 1 (≈ 60 at density 1000): use metres,
//! not pixels. Areas saturate above ≈ 46,340 × 46,340.
use super::{Geometry, MassInfo, MassSpec, Shape};
use crate::math::exact::{raw_diff, raw_sq, raw_sum, saturate_to_real, I256};
use crate::math::{Real, Vect, BB};

/// `m · num / den` where `num / den` is a per-unit-mass quantity in units of
/// 2^-64 (`den` a small positive integer): exact, then **one** rounding to
/// nearest (ties away from zero), saturated.
fn mass_times(m: Real, num: u128, den: u128) -> Real {
    // A `num` of 2^127 or more only comes from saturated squares: the result
    // saturates either way. m_raw < 2^63 and num < 2^127: product < 2^190.
    let num = i128::try_from(num).unwrap_or(i128::MAX);
    let den = i128::try_from(den).unwrap_or(i128::MAX);
    // Units: 2^-32 (m) · 2^-64 (num) / 2^64 = 2^-32, raw `Real` bits.
    let q = I256::mul_i128(num, i128::from(m.to_bits())).ratio_round(I256::from_i128(den).shl(64));
    to_real(q)
}

/// A raw value as a `Real`, saturated.
#[inline]
fn to_real(raw: i128) -> Real {
    saturate_to_real(raw)
}

/// `v · 2^k`, saturated to the `i128` range.
#[inline]
fn shl_sat(v: i128, k: u32) -> i128 {
    if k == 0 || v == 0 {
        v
    } else if k < 126 && v.unsigned_abs().leading_zeros() > k.saturating_add(1) {
        // (Checked after k < 126: the `+ 1` never saturates.)
        v << k
    } else if v < 0 {
        i128::MIN
    } else {
        i128::MAX
    }
}

/// `|raw(v)|²` in units of 2^-64, exact (each square ≤ 2^126).
#[inline]
fn sq(v: Real) -> u128 {
    raw_sq(v)
}

/// The square of a wide raw value (units 2^-32), saturating.
#[inline]
fn sq_wide(v: i128) -> u128 {
    let a = v.unsigned_abs();
    a.saturating_mul(a)
}

/// `m · (w² + h² + 3·|s|²) / 12`, rounded once: the moment of a `w × h` box
/// of mass `m` centred at `s / 2`, about the origin. `s` is twice the centre
/// in raw units (kept wide so `l + r` cannot overflow).
fn box_moment(m: Real, w: Real, h: Real, s: (i128, i128)) -> Real {
    let num = sq(w)
        .saturating_add(sq(h))
        .saturating_add(sq_wide(s.0).saturating_add(sq_wide(s.1)).saturating_mul(3));
    mass_times(m, num, 12)
}

/// MIS/Chipmunk `momentForCircle`: the moment of a hollow circle (ring) of
/// mass `m`, inner radius `r1`, outer radius `r2`, centred at `offset` from
/// the axis: `m·((r1² + r2²)/2 + |offset|²)`.
///
/// Exact, rounded once (½ ulp). Saturates when the result exceeds 2^31 (for
/// `m = 1`, `r2 > 65,536`).
pub fn moment_for_circle(m: Real, r1: Real, r2: Real, offset: Vect) -> Real {
    // Units of 2^-65: (r1² + r2²) + 2|offset|², then one division by 2^33.
    let num = sq(r1)
        .saturating_add(sq(r2))
        .saturating_add(sq(offset.x).saturating_add(sq(offset.y)).saturating_mul(2));
    mass_times(m, num, 2)
}

/// MIS/Chipmunk `areaForCircle`: the area of a ring, `π·|r2² − r1²|`.
/// Rounded once from the exact product with `Real::PI` (itself within ½ ulp
/// of π): within (½ + r²/2) ulp of exact. Saturates above r ≈ 26,145.
pub fn area_for_circle(r1: Real, r2: Real) -> Real {
    let d = sq(r2).abs_diff(sq(r1));
    mass_times(Real::PI, d, 1)
}

/// MIS/Chipmunk `momentForSegment`: the moment of a segment (capsule) of mass
/// `m` from `a` to `b` with rounding `radius`, about the origin. Like
/// Chipmunk, the capsule is approximated by a box of length `|b − a| + 2r`
/// and width `2r` centred on the midpoint:
/// `m·((length² + 4r²)/12 + |midpoint|²)`.
pub fn moment_for_segment(m: Real, a: Vect, b: Vect, radius: Real) -> Real {
    let length = (b - a).length() + radius.mul_pow2(1);
    let twice_mid = (raw_sum(a.x, b.x), raw_sum(a.y, b.y));
    box_moment(m, length, radius.mul_pow2(1), twice_mid)
}

/// MIS/Chipmunk `areaForSegment`: `r·(π·r + 2·|a − b|)`, the area of a
/// capsule (a zero radius gives zero area).
pub fn area_for_segment(a: Vect, b: Vect, radius: Real) -> Real {
    radius * (Real::PI * radius + (a - b).length().mul_pow2(1))
}

/// The area of a capsule (a segment from `a` to `b` rounded by `radius`):
/// a `2r × |b − a|` rectangle and a disc, `r·(π·r + 2·|b − a|)`.
///
/// The same value as [`area_for_segment`], bit for bit, under the name a
/// character's shape goes by; it is also the area a capsule's density
/// multiplies ([`Shape::mass_info`]).
pub fn area_for_capsule(a: Vect, b: Vect, radius: Real) -> Real {
    area_for_segment(a, b, radius)
}

/// The moment of a solid capsule of mass `m` (a segment from `a` to `b`
/// rounded by `radius`, uniform density) about the origin, exactly: the
/// `2r × L` rectangle (`L = |b − a|`) plus two half discs at the ends,
/// each carried to the centre by the parallel-axis rule:
/// `m·(L³/6 + 2r²L + π·r²·(r²/2 + L²/4)) / (2L + π·r) / r + m·|midpoint|²`,
/// which is `m·L²/12` for `r = 0` and `m·r²/2` for `L = 0`.
///
/// Why not [`moment_for_segment`]: Chipmunk approximates the capsule by a
/// box of length `L + 2r`, which overstates the moment (by 18 % for
/// `L = 2r`). A shape's automatic mass ([`Shape::mass_info`]) keeps
/// Chipmunk's box for every segment, rounded or not, so that worlds built
/// before this helper step as they did; a body that wants the exact moment
/// of its capsule sets it with this (`Body::new(m, moment_for_capsule(…))`).
///
/// Exact on integers but for `L` (a floor square root, 1 ulp low at most);
/// the per-unit-mass ratio keeps 32 guard bits before the multiplication
/// by `m`: error ≤ ½ ulp + |m|·2^-33 ulp + the effect of `L`'s ulp.
/// Saturates like [`moment_for_segment`]; a negative radius counts as 0.
pub fn moment_for_capsule(m: Real, a: Vect, b: Vect, radius: Real) -> Real {
    // Raw values (units 2^-32): L < 2^63 and r < 2^63, π < 2^34.
    let len = i128::from((b - a).length().to_bits());
    let r = i128::from(radius.max(Real::ZERO).to_bits());
    let pi = i128::from(Real::PI.to_bits());
    // Each product of two raw values is below 2^126; π·r below 2^97.
    let (l2, r2, pr) = (
        len.saturating_mul(len),
        r.saturating_mul(r),
        pi.saturating_mul(r),
    );
    // 12 × (numerator / r), units 2^-128: 2L³ + 24r²L + 6πr³ + 3πrL² (the
    // cubes of two raw values are units 2^-96, hence the shifts). Every
    // term is below 2^230: no I256 overflow.
    let num = I256::mul_i128(l2, len)
        .mul_small(2)
        .shl(32)
        .add(I256::mul_i128(r2, len).mul_small(24).shl(32))
        .add(I256::mul_i128(pr, r2).mul_small(6))
        .add(I256::mul_i128(pr, l2).mul_small(3));
    // 12 × (denominator / r), units 2^-64: 24·L + 12·π·r, below 2^101.
    let den = I256::from_i128(len)
        .shl(32)
        .mul_small(24)
        .add(I256::from_i128(pr).mul_small(12));
    // |midpoint|² = |a + b|² / 4 (units 2^-64), added before the one
    // rounding of the ratio: (4·num + |a + b|²·den) / (4·den).
    let twice_mid = sq_wide(raw_sum(a.x, b.x)).saturating_add(sq_wide(raw_sum(a.y, b.y)));
    let twice_mid = i128::try_from(twice_mid).unwrap_or(i128::MAX);
    let per_mass = if den.is_zero() {
        // A point: its distance from the origin alone.
        I256::from_i128(twice_mid).ratio_round(I256::from_i128(4))
    } else {
        let den_raw = den.saturating_to_i128();
        num.mul_small(4)
            .add(I256::mul_i128(twice_mid, den_raw))
            .ratio_round(den.mul_small(4))
    };
    mass_times(m, u128::try_from(per_mass).unwrap_or(0), 1)
}

/// MIS/Chipmunk `momentForBox`: `m·(w² + h²)/12`, the moment of a solid
/// `width × height` box about its centre, exact and rounded once. For
/// `m = 1` it saturates above a side of ≈ 113,500; with a mass of
/// `density·w·h`, above a side of ≈ 337 at density 1.
pub fn moment_for_box(m: Real, width: Real, height: Real) -> Real {
    box_moment(m, width, height, (0, 0))
}

/// MIS/Chipmunk `momentForBox2`: the moment of the solid box `bb` about the
/// origin: `momentForBox` plus `m·|centre|²`.
pub fn moment_for_box2(m: Real, bb: BB) -> Real {
    let twice_center = (raw_sum(bb.l, bb.r), raw_sum(bb.b, bb.t));
    box_moment(m, bb.r - bb.l, bb.t - bb.b, twice_center)
}

/// MIS/Chipmunk `areaForPoly`: the signed area of the polygon (positive when
/// counter-clockwise) plus the rounding: `area + r·(π·|r| + perimeter)`.
///
/// The polygon part is exact and rounded once (½ ulp); the rounding term
/// `r·(π|r| + perimeter)` is computed in `Real` (each edge length is an exact
/// floor, 1 ulp low at most): total error ≤ 1 + |r|·(n + 1 + |r|/2) ulp for
/// `n` vertices, ½ ulp for `r = 0`. Translation-invariant bit for bit.
pub fn area_for_poly(verts: &[Vect], radius: Real) -> Real {
    let first = verts.first().copied().unwrap_or(Vect::ZERO);
    let rel = Relative::new(verts, first);
    let twice_area = rel.edges().fold(I256::ZERO, |acc, (p, q)| {
        acc.add(I256::from_i128(cross(p, q)))
    });
    let area = to_real(shl_sat(
        twice_area.ratio_round(I256::from_i128(2 << 32)),
        rel.twice_shift(),
    ));
    let perimeter: Real = edges(verts).map(|(a, b)| (b - a).length()).sum();
    radius * (Real::PI * radius.abs() + perimeter) + area
}

/// MIS/Chipmunk `centroidForPoly`: the centroid of the polygon's area,
/// `Σ (vᵢ + vᵢ₊₁)·(vᵢ × vᵢ₊₁) / (3·Σ vᵢ × vᵢ₊₁)`.
///
/// Exact and rounded once per component for polygons spanning less than 2^23
/// units. Where Chipmunk divides by zero (fewer than 3 vertices or zero
/// signed area) this returns the midpoint of the lowest and highest vertex
/// in (x, y) order: the centre of a segment, the point itself, or zero for
/// no vertices.
pub fn centroid_for_poly(verts: &[Vect]) -> Vect {
    let Some(first) = verts.first().copied() else {
        return Vect::ZERO;
    };
    let rel = Relative::new(verts, first);
    let mut twice_area = I256::ZERO;
    let (mut sum_x, mut sum_y) = (I256::ZERO, I256::ZERO);
    for (p, q) in rel.edges() {
        // |coords| < 2^56: c < 2^113 and the coordinate sums < 2^57, so each
        // product is < 2^170 and a sum of any realistic count fits I256.
        let c = cross(p, q);
        twice_area = twice_area.add(I256::from_i128(c));
        // (The coordinate sums never saturate.)
        sum_x = sum_x.add(I256::mul_i128(c, p.0.saturating_add(q.0)));
        sum_y = sum_y.add(I256::mul_i128(c, p.1.saturating_add(q.1)));
    }
    if twice_area.is_zero() {
        return extreme_midpoint(verts);
    }
    // (units 2^-96) / (units 2^-64) = units 2^-32: raw Real bits.
    let den = twice_area.mul_small(3);
    // The offset from the first vertex may exceed the `Real` range even when
    // the centroid does not: add it on i128.
    let place = |origin: Real, sum: I256| {
        let offset = shl_sat(sum.ratio_round(den), rel.shift);
        to_real(offset.saturating_add(i128::from(origin.to_bits())))
    };
    Vect::new(place(first.x, sum_x), place(first.y, sum_y))
}

/// MIS/Chipmunk `momentForPoly`: the moment of a solid polygon of mass `m`
/// about the origin, with `offset` added to every vertex:
/// `m·Σ (vᵢ × vᵢ₊₁)(vᵢ·vᵢ + vᵢ·vᵢ₊₁ + vᵢ₊₁·vᵢ₊₁) / (6·Σ vᵢ × vᵢ₊₁)`.
/// Pass `offset = −centroid` for the moment about the centroid.
///
/// `radius` is accepted and, as in Chipmunk 7 (whose source says "TODO
/// account for radius"), ignored: a rounded polygon gets the moment of its
/// core polygon, while its area (and so a density-derived mass) includes the
/// rounding.
///
/// The per-unit-mass ratio is exact and kept with 32 guard bits, then
/// multiplied by `m` and rounded: error ≤ ½ ulp + |m|·2^-33 ulp, while the
/// offset vertices lie within 2^23 of the origin. Beyond that they are scaled
/// down by a power of two first (relative error 2^-54; such moments have
/// saturated anyway unless `m` is tiny). Where Chipmunk divides by zero: 2 vertices give
/// [`moment_for_segment`] (as Chipmunk does), 1 vertex a point mass, zero
/// signed area the segment between the lowest and highest vertex.
pub fn moment_for_poly(m: Real, verts: &[Vect], offset: Vect, radius: Real) -> Real {
    let _ = radius;
    let at = |i: usize| verts.get(i).copied().unwrap_or(Vect::ZERO) + offset;
    match verts.len() {
        0 => return Real::ZERO,
        1 => return moment_for_circle(m, Real::ZERO, Real::ZERO, at(0)),
        2 => return moment_for_segment(m, at(0), at(1), Real::ZERO),
        _ => {}
    }
    let rel = Relative::new_offset(verts, offset);
    let mut twice_area = I256::ZERO;
    let mut sum = I256::ZERO;
    for (p, q) in rel.edges() {
        // |coords| < 2^56: a < 2^113, b < 6·2^112 < 2^115, a·b < 2^228.
        let a = cross(p, q);
        let b = dot_sum(p, q);
        twice_area = twice_area.add(I256::from_i128(a));
        sum = sum.add(I256::mul_i128(a, b));
    }
    if twice_area.is_zero() {
        let (lo, hi) = extreme_points(verts);
        return moment_for_segment(m, lo + offset, hi + offset, Real::ZERO);
    }
    // (units 2^-128) / (6·S, units 2^-64) = units 2^-64: the per-unit-mass
    // moment with 32 guard bits (< 2^95 unless it saturates anyway).
    let k = shl_sat(sum.ratio_round(twice_area.mul_small(6)), rel.twice_shift());
    // m (2^-32) · k (2^-64) / 2^64 = raw `Real` bits, rounded once more.
    to_real(I256::mul_i128(k, i128::from(m.to_bits())).ratio_round(I256::from_i128(1).shl(64)))
}

/// Mass properties of a geometry (Chipmunk's `cp*ShapeMassInfo`): area,
/// centroid in body coordinates, moment per unit mass about the centroid, and
/// the mass the specification gives (`Density(d)` → `d·area`). A
/// segment's (a capsule's) moment is Chipmunk's box of length
/// `|b − a| + 2r` and width `2r`, as it always was;
/// [`moment_for_capsule`] is the exact one.
pub fn shape_mass_info(geometry: &Geometry, spec: MassSpec) -> MassInfo {
    let (area, cog, moment_per_mass) = match geometry {
        Geometry::Circle(c) => (
            area_for_circle(Real::ZERO, c.radius),
            c.offset,
            moment_for_circle(Real::ONE, Real::ZERO, c.radius, Vect::ZERO),
        ),
        Geometry::Segment(s) => {
            let r2 = s.radius.mul_pow2(1);
            (
                area_for_segment(s.a, s.b, s.radius),
                midpoint(s.a, s.b),
                moment_for_box(Real::ONE, (s.b - s.a).length() + r2, r2),
            )
        }
        Geometry::Poly(p) => {
            let cog = centroid_for_poly(p.verts());
            (
                area_for_poly(p.verts(), p.radius),
                cog,
                moment_for_poly(Real::ONE, p.verts(), -cog, p.radius),
            )
        }
    };
    let mass = match spec {
        MassSpec::None => Real::ZERO,
        MassSpec::Mass(m) => m,
        MassSpec::Density(d) => d * area,
    };
    MassInfo {
        mass,
        moment_per_mass,
        cog,
        area,
    }
}

/// The mass method of [`Shape`], defined here beside the formulas it uses
/// so that the shape module itself does not call into this one.
impl Shape {
    /// Mass properties: area, centroid and moment per unit mass from the
    /// geometry, mass from the mass specification.
    pub fn mass_info(&self) -> MassInfo {
        shape_mass_info(&self.geometry, self.mass_spec)
    }
}

/// The edges `(vᵢ, vᵢ₊₁)` of a closed polygon, the last one closing it.
fn edges(verts: &[Vect]) -> impl Iterator<Item = (Vect, Vect)> + '_ {
    verts
        .iter()
        .zip(verts.iter().cycle().skip(1))
        .take(verts.len())
        .map(|(a, b)| (*a, *b))
}

/// The lowest and highest vertex in (x, y) order (zero for none).
fn extreme_points(verts: &[Vect]) -> (Vect, Vect) {
    let key = |p: &&Vect| (p.x, p.y);
    let lo = verts.iter().min_by_key(key).copied().unwrap_or(Vect::ZERO);
    let hi = verts.iter().max_by_key(key).copied().unwrap_or(Vect::ZERO);
    (lo, hi)
}

/// The midpoint of [`extreme_points`].
fn extreme_midpoint(verts: &[Vect]) -> Vect {
    let (lo, hi) = extreme_points(verts);
    midpoint(lo, hi)
}

/// `(a + b) / 2` computed exactly and rounded to nearest, ties away from
/// zero: symmetric in `a`, `b` and under negation (unlike `a.lerp(b, ½)`).
fn midpoint(a: Vect, b: Vect) -> Vect {
    let mid = |a: Real, b: Real| {
        let s = raw_sum(a, b);
        // |s| ≤ 2^64, so the rounded half fits i64 (saturating at 2^63);
        // q ≥ 0, so its negation never saturates.
        let q = i64::try_from(s.unsigned_abs().div_ceil(2)).unwrap_or(i64::MAX);
        Real::from_bits(if s < 0 { q.saturating_neg() } else { q })
    };
    Vect::new(mid(a.x, b.x), mid(a.y, b.y))
}

/// Exact `p × q` of wide raw coordinates below 2^56 (result < 2^113).
// Products below 2^112, their difference below 2^113: no overflow.
#[allow(clippy::arithmetic_side_effects)]
#[inline]
fn cross(p: (i128, i128), q: (i128, i128)) -> i128 {
    p.0 * q.1 - p.1 * q.0
}

/// `p·p + p·q + q·q` of wide raw coordinates below 2^56, exact (< 2^115).
// Six products below 2^112 each: the sum is below 6·2^112 < 2^115.
#[allow(clippy::arithmetic_side_effects)]
#[inline]
fn dot_sum(p: (i128, i128), q: (i128, i128)) -> i128 {
    p.0 * p.0 + p.1 * p.1 + p.0 * q.0 + p.1 * q.1 + q.0 * q.0 + q.1 * q.1
}

/// Polygon vertices as exact wide raw coordinates relative to an origin,
/// scaled down by `2^shift` if needed so every coordinate is below 2^56 in
/// magnitude (the bound all the products above rely on).
struct Relative {
    points: Vec<(i128, i128)>,
    shift: u32,
}

/// Coordinates below `2^REL_BITS` (raw) keep every polygon product in range.
const REL_BITS: u32 = 56;

impl Relative {
    /// `verts − origin`, exact on i128 (differences of i64 fit in 65 bits).
    fn new(verts: &[Vect], origin: Vect) -> Relative {
        Relative::scaled(
            verts
                .iter()
                .map(|v| (raw_diff(v.x, origin.x), raw_diff(v.y, origin.y)))
                .collect(),
        )
    }

    /// `verts + offset`, exact on i128.
    fn new_offset(verts: &[Vect], offset: Vect) -> Relative {
        Relative::scaled(
            verts
                .iter()
                .map(|v| (raw_sum(v.x, offset.x), raw_sum(v.y, offset.y)))
                .collect(),
        )
    }

    fn scaled(mut points: Vec<(i128, i128)>) -> Relative {
        let max = points
            .iter()
            .map(|(x, y)| x.unsigned_abs().max(y.unsigned_abs()))
            .max()
            .unwrap_or(0);
        // (leading_zeros ≤ BITS: never saturates.)
        let bits = u128::BITS.saturating_sub(max.leading_zeros());
        let shift = bits.saturating_sub(REL_BITS - 1);
        if let Some(below) = shift.checked_sub(1) {
            // Round to nearest, ties away from zero (symmetric).
            let half = 1u128 << below;
            let down = |v: i128| {
                // |v| < 2^65 and half < 2^65: the sum never saturates and the
                // shifted magnitude fits i128, so its negation is exact.
                let m = (v.unsigned_abs().saturating_add(half) >> shift) as i128;
                if v < 0 {
                    m.saturating_neg()
                } else {
                    m
                }
            };
            for p in &mut points {
                *p = (down(p.0), down(p.1));
            }
        }
        Relative { points, shift }
    }

    /// `2 · shift`, the scale of products of two coordinates.
    fn twice_shift(&self) -> u32 {
        // shift ≤ 128 − (REL_BITS − 1) = 73: never saturates.
        self.shift.saturating_mul(2)
    }

    fn edges(&self) -> impl Iterator<Item = ((i128, i128), (i128, i128))> + '_ {
        let p = &self.points;
        p.iter()
            .zip(p.iter().cycle().skip(1))
            .take(p.len())
            .map(|(a, b)| (*a, *b))
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::real;
    use crate::shape::{Circle, Poly, Segment};

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    fn unit_square() -> [Vect; 4] {
        [v(0, 0), v(1, 0), v(1, 1), v(0, 1)]
    }

    fn close(a: Real, b: f64, ulps: f64) -> bool {
        (a.to_f64() - b).abs() <= ulps * 2f64.powi(-32)
    }

    #[test]
    fn unit_box_area_is_one_and_moment_is_one_sixth() {
        assert_eq!(area_for_poly(&unit_square(), Real::ZERO), Real::ONE);
        assert_eq!(
            centroid_for_poly(&unit_square()),
            Vect::new(Real::HALF, Real::HALF)
        );
        let c = centroid_for_poly(&unit_square());
        assert_eq!(
            moment_for_poly(Real::ONE, &unit_square(), -c, Real::ZERO),
            Real::ratio(1, 6)
        );
        assert_eq!(
            moment_for_box(Real::ONE, Real::ONE, Real::ONE),
            Real::ratio(1, 6)
        );
        // About the corner: 1/6 + |(½, ½)|² = 2/3.
        assert_eq!(
            moment_for_poly(Real::ONE, &unit_square(), Vect::ZERO, Real::ZERO),
            Real::ratio(2, 3)
        );
    }

    #[test]
    fn box2_adds_parallel_axis_term() {
        let bb = BB::new(Real::ZERO, Real::ZERO, Real::TWO, Real::from_int(4));
        // (4 + 16)/12 + |(1, 2)|² = 5/3 + 5 = 20/3, times 3.
        assert_eq!(moment_for_box2(Real::from_int(3), bb), Real::from_int(20));
        assert_eq!(
            moment_for_box(Real::from_int(12), Real::from_int(3), Real::from_int(4)),
            Real::from_int(25)
        );
    }

    #[test]
    fn circle_area_and_moment() {
        assert!(close(
            area_for_circle(Real::ZERO, Real::TWO),
            4.0 * core::f64::consts::PI,
            4.0
        ));
        assert!(close(
            area_for_circle(Real::TWO, Real::ONE),
            3.0 * core::f64::consts::PI,
            4.0
        ));
        assert_eq!(
            moment_for_circle(Real::TWO, Real::ZERO, Real::ONE, Vect::ZERO),
            Real::ONE
        );
        // 1·((1 + 4)/2 + 25) = 27.5
        assert_eq!(
            moment_for_circle(Real::ONE, Real::ONE, Real::TWO, v(3, 4)),
            real!(27.5)
        );
    }

    #[test]
    fn segment_area_and_moment() {
        // r(πr + 2·len) = 1·(π + 4)
        assert!(close(
            area_for_segment(v(0, 0), v(2, 0), Real::ONE),
            core::f64::consts::PI + 4.0,
            4.0
        ));
        assert_eq!(area_for_segment(v(0, 0), v(2, 0), Real::ZERO), Real::ZERO);
        // Thin rod of length 2 about its centre: 4/12 = 1/3; offset (1,0) adds 1.
        assert_eq!(
            moment_for_segment(Real::ONE, v(0, 0), v(2, 0), Real::ZERO),
            Real::ratio(4, 3)
        );
        // Chipmunk: 2 vertices in momentForPoly are a segment.
        assert_eq!(
            moment_for_poly(Real::ONE, &[v(0, 0), v(2, 0)], Vect::ZERO, Real::ZERO),
            Real::ratio(4, 3)
        );
    }

    #[test]
    fn poly_area_includes_radius_and_sign_follows_winding() {
        let r = real!(0.5);
        // 1 + 0.5·(π·0.5 + 4) = 3 + π/4
        assert!(close(
            area_for_poly(&unit_square(), r),
            3.0 + core::f64::consts::PI / 4.0,
            4.0
        ));
        let mut cw = unit_square();
        cw.reverse();
        assert_eq!(area_for_poly(&cw, Real::ZERO), -Real::ONE);
        // The moment formula is winding-independent.
        assert_eq!(
            moment_for_poly(Real::ONE, &cw, Vect::ZERO, Real::ZERO),
            Real::ratio(2, 3)
        );
    }

    #[test]
    fn triangle_centroid_and_moment_match_closed_form() {
        let t = [v(0, 0), v(3, 0), v(0, 3)];
        assert_eq!(centroid_for_poly(&t), v(1, 1));
        // About the centroid: (sum of squared side lengths)/36 = (9 + 9 + 18)/36.
        let c = centroid_for_poly(&t);
        assert_eq!(moment_for_poly(Real::ONE, &t, -c, Real::ZERO), Real::ONE);
    }

    #[test]
    fn degenerate_polys_are_defined() {
        assert_eq!(centroid_for_poly(&[]), Vect::ZERO);
        assert_eq!(centroid_for_poly(&[v(2, 3)]), v(2, 3));
        let line = [v(0, 0), v(1, 1), v(4, 4)];
        assert_eq!(centroid_for_poly(&line), v(2, 2));
        assert_eq!(area_for_poly(&line, Real::ZERO), Real::ZERO);
        assert_eq!(
            moment_for_poly(Real::ONE, &line, Vect::ZERO, Real::ZERO),
            moment_for_segment(Real::ONE, v(0, 0), v(4, 4), Real::ZERO)
        );
        assert_eq!(
            moment_for_poly(Real::ONE, &[], Vect::ZERO, Real::ZERO),
            Real::ZERO
        );
        assert_eq!(
            moment_for_poly(Real::TWO, &[v(3, 4)], Vect::ZERO, Real::ZERO),
            Real::from_int(50)
        );
    }

    #[test]
    fn moments_saturate_instead_of_overflowing() {
        let side = Real::from_int(400);
        let m = side * side; // density 1
        assert_eq!(moment_for_box(m, side, side), Real::MAX);
        let side = Real::from_int(300);
        assert!(!moment_for_box(side * side, side, side).is_saturated());
        assert_eq!(moment_for_box(Real::ONE, Real::MAX, Real::MAX), Real::MAX);
        let huge = [
            Vect::new(Real::MIN, Real::MIN),
            Vect::new(Real::MAX, Real::MIN),
            Vect::new(Real::MAX, Real::MAX),
        ];
        assert_eq!(
            moment_for_poly(Real::ONE, &huge, Vect::ZERO, Real::ZERO),
            Real::MAX
        );
        assert_eq!(area_for_poly(&huge, Real::ZERO), Real::MAX);
        let c = centroid_for_poly(&huge);
        assert!((c.x.to_f64() - 2f64.powi(31) / 3.0).abs() < 1.0, "{c:?}");
    }

    #[test]
    fn extreme_inputs_never_panic() {
        let vals = [Real::MIN, -Real::ONE, Real::ZERO, Real::DELTA, Real::MAX];
        for &a in &vals {
            for &b in &vals {
                let p = Vect::new(a, b);
                let q = Vect::new(b, a);
                let verts = [p, q, Vect::new(Real::MAX, a), Vect::new(b, Real::MIN)];
                let _ = moment_for_circle(a, b, a, p);
                let _ = area_for_circle(a, b);
                let _ = moment_for_segment(a, p, q, b);
                let _ = area_for_segment(p, q, a);
                let _ = moment_for_box(a, b, a);
                let _ = moment_for_box2(a, BB::new(a, b, b, a));
                let _ = moment_for_poly(a, &verts, q, b);
                let _ = area_for_poly(&verts, a);
                let _ = centroid_for_poly(&verts);
            }
        }
    }

    #[test]
    fn shape_mass_info_for_each_kind() {
        let circle = Geometry::Circle(Circle::new(Real::TWO, v(1, 0)));
        let info = shape_mass_info(&circle, MassSpec::Density(Real::ONE));
        assert_eq!(info.cog, v(1, 0));
        assert_eq!(info.moment_per_mass, Real::TWO);
        assert!(close(info.area, 4.0 * core::f64::consts::PI, 4.0));
        assert_eq!(info.mass, info.area);

        let seg = Geometry::Segment(Segment::new(v(0, 0), v(4, 0), Real::ZERO));
        let info = shape_mass_info(&seg, MassSpec::Mass(Real::TWO));
        assert_eq!(info.cog, v(2, 0));
        assert_eq!(info.mass, Real::TWO);
        assert_eq!(info.moment_per_mass, Real::ratio(4, 3));
        assert_eq!(info.area, Real::ZERO);

        let poly = Geometry::Poly(Poly::new_box(Real::TWO, Real::TWO, Real::ZERO).unwrap());
        let info = shape_mass_info(&poly, MassSpec::Density(Real::from_int(3)));
        assert_eq!(info.area, Real::from_int(4));
        assert_eq!(info.mass, Real::from_int(12));
        assert_eq!(info.cog, Vect::ZERO);
        assert_eq!(info.moment_per_mass, Real::ratio(2, 3));
        assert_eq!(shape_mass_info(&poly, MassSpec::None).mass, Real::ZERO);
    }
}
