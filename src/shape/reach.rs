//! Whether a segment comes within a distance of a shape's core, decided
//! exactly: the judge of [`segment_query`](super::query::segment_query).
//!
//! The ray cast itself clips the ray against the core's planes pushed out
//! by the reach, using the stored *unit* normals, which are rounded. For a
//! shape with no thickness (a sharp segment, whose two faces are one line)
//! or a ray that grazes a corner, that rounding alone can decide between a
//! hit and a miss. So a ray that the fast clip misses but a clip grown by
//! the rounding bound hits is judged here, with no rounding at all: every
//! test is the sign of an integer expression of the raw coordinates (dot
//! and cross products on 128 bits, their squares on 256). A ray that this
//! module says reaches the shape is always reported as a hit (see
//! `segment_query`); a ray it says misses never is, unless the fast clip
//! already found it within its rounding.
//!
//! Exact for coordinates whose differences are representable (within
//! ±2^31 m of each other); beyond that the saturated differences give a
//! defined, not exact, answer.
use super::geometry::{next_index, Geometry};
use crate::math::exact::{cross, dot, len_sq, I256};
use crate::math::{Real, Vect};

/// Whether the segment `a → b` passes within `reach` (≥ 0) of the core of
/// `g` (the circle's centre, the segment's line piece, the polygon's
/// sharp outline and inside); its rounding radius counts as part of the
/// reach.
pub(crate) fn segment_reaches(g: &Geometry, a: Vect, b: Vect, reach: Real) -> bool {
    let reach = reach.max(Real::ZERO);
    match g {
        Geometry::Circle(c) => point_within(c.offset, a, b, reach_sq(reach + c.radius)),
        Geometry::Segment(s) => segments_within(s.a, s.b, a, b, reach_sq(reach + s.radius)),
        Geometry::Poly(p) => outline_reaches(p.verts(), p.radius(), a, b, reach),
    }
}

/// [`segment_reaches`] for the convex outline of counter-clockwise
/// `verts` rounded by `radius` (a polygon's test, for the outlines of the
/// shape casts, which may have more vertices than a polygon).
pub(crate) fn outline_reaches(verts: &[Vect], radius: Real, a: Vect, b: Vect, reach: Real) -> bool {
    let r2 = reach_sq(reach.max(Real::ZERO) + radius);
    let inside = verts.iter().enumerate().all(|(i, &v0)| {
        let v1 = verts.get(next_index(i, verts.len())).copied().unwrap_or(v0);
        // Counter-clockwise: inside is the left of every edge.
        cross(v1 - v0, a - v0) >= 0
    });
    inside
        || verts.iter().enumerate().any(|(i, &v0)| {
            let v1 = verts.get(next_index(i, verts.len())).copied().unwrap_or(v0);
            segments_within(v0, v1, a, b, r2)
        })
}

/// `reach²` in units of 2^-64 (exact).
fn reach_sq(reach: Real) -> u128 {
    len_sq(Vect::new(reach, Real::ZERO))
}

/// Whether the point `p` lies within `√r2` of the segment `a → b`.
fn point_within(p: Vect, a: Vect, b: Vect, r2: u128) -> bool {
    let d = b - a;
    let f = p - a;
    let along = dot(f, d);
    if along <= 0 {
        return len_sq(f) <= r2;
    }
    let dd = len_sq(d);
    if along.unsigned_abs() >= dd {
        return len_sq(p - b) <= r2;
    }
    // Inside the span: distance² = cross(d, f)² / |d|², compared without
    // dividing. `r2 ≤ 2^126` and `dd < 2^127` fit an `i128`.
    let c = cross(d, f);
    let lhs = I256::mul_i128(c, c);
    let rhs = I256::mul_i128(
        i128::try_from(r2).unwrap_or(i128::MAX),
        i128::try_from(dd).unwrap_or(i128::MAX),
    );
    !rhs.sub(lhs).is_negative()
}

/// Whether the segments `a → b` and `c → d` come within `√r2` of each
/// other: they cross or touch, or an endpoint of one is within reach of
/// the other (the nearest points of two segments that do not cross
/// include an endpoint).
fn segments_within(a: Vect, b: Vect, c: Vect, d: Vect, r2: u128) -> bool {
    segments_touch(a, b, c, d)
        || point_within(a, c, d, r2)
        || point_within(b, c, d, r2)
        || point_within(c, a, b, r2)
        || point_within(d, a, b, r2)
}

/// Whether two segments cross or touch, by the signs of four orientations.
/// Collinear (or degenerate) segments are left to the endpoint tests of
/// [`segments_within`], which decide them exactly.
fn segments_touch(a: Vect, b: Vect, c: Vect, d: Vect) -> bool {
    let side = |p: Vect, q: Vect, r: Vect| cross(q - p, r - p).signum();
    let (o1, o2) = (side(a, b, c), side(a, b, d));
    let (o3, o4) = (side(c, d, a), side(c, d, b));
    if (o1 == 0 && o2 == 0) || (o3 == 0 && o4 == 0) {
        return false;
    }
    o1.saturating_mul(o2) <= 0 && o3.saturating_mul(o4) <= 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::geometry::{Circle, Segment};

    fn v(x: i32, y: i32) -> Vect {
        Vect::new(Real::from_int(x), Real::from_int(y))
    }

    fn seg(a: Vect, b: Vect, r: Real) -> Geometry {
        Geometry::Segment(Segment::new(a, b, r))
    }

    #[test]
    fn sharp_segment_crossed_touched_and_missed() {
        let g = seg(v(-2, -1), v(2, 1), Real::ZERO);
        assert!(segment_reaches(&g, v(0, 5), v(0, -5), Real::ZERO));
        // Ending exactly on the segment touches it.
        assert!(segment_reaches(&g, v(0, 5), v(0, 0), Real::ZERO));
        // Passing its end by one ulp misses.
        let past = Vect::new(Real::from_int(2) + Real::DELTA, Real::from_int(5));
        let below = Vect::new(Real::from_int(2) + Real::DELTA, Real::from_int(-5));
        assert!(!segment_reaches(&g, past, below, Real::ZERO));
        // Collinear: overlapping touches, disjoint misses.
        assert!(segment_reaches(&g, v(-4, -2), v(0, 0), Real::ZERO));
        assert!(!segment_reaches(&g, v(4, 2), v(6, 3), Real::ZERO));
    }

    #[test]
    fn circle_grazed_exactly_at_its_radius() {
        let g = Geometry::Circle(Circle::new(Real::ONE, v(0, 0)));
        assert!(segment_reaches(&g, v(1, 5), v(1, -5), Real::ZERO));
        let off = Real::ONE + Real::DELTA;
        assert!(!segment_reaches(
            &g,
            Vect::new(off, Real::from_int(5)),
            Vect::new(off, Real::from_int(-5)),
            Real::ZERO
        ));
        // The swept radius counts.
        assert!(segment_reaches(
            &g,
            Vect::new(off, Real::from_int(5)),
            Vect::new(off, Real::from_int(-5)),
            Real::DELTA
        ));
    }
}
