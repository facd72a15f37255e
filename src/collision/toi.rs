//! Separation of two shapes that need not touch, for the time-of-impact
//! sweep of bullets (`space/ccd.rs`), and the closest points behind it,
//! for the hit point of the shape casts (`cast.rs`).
//!
//! [`separation`] is the signed distance between the two surfaces (rounding
//! radii included) and the unit direction from `a` toward `b` along which
//! it is measured. Computed like [`collide`](super::collide): both shapes
//! are first translated by minus `a`'s anchor (exact), so the result does
//! not depend on where the pair is; then a closed form for two circles and
//! GJK ([`gjk`](super::gjk)) on the cores for every other pair, minus the
//! two radii. Overlapping cores go through EPA and give a negative value.
//!
//! The sweep needs a *lower* bound of the distance (an overestimate could
//! step a bullet past a wall). GJK's answer is exact up to rounding (a few
//! ulp); when GJK or EPA stops at its iteration cap (never seen in
//! practice, see [`WARN_GJK_ITERATIONS`](super::WARN_GJK_ITERATIONS)) its
//! best-so-far edge is an upper bound, so the answer is replaced by the gap
//! between the two bounding boxes, which never exceeds the true distance,
//! and no direction (`Vect::ZERO`: the sweep then uses its full motion
//! bound).
use super::canonical::{anchor_of, is_empty, moved};
use super::gjk::gjk;
use super::support::{SupportContext, SupportShape};
use crate::math::{Real, Vect};
use crate::shape::Geometry;

/// Signed distance between the surfaces of `a` and `b` (negative when they
/// overlap) and the unit direction from `a` toward `b` it is measured
/// along (see the module docs for when that is zero). An empty polygon
/// (corrupt data only) is infinitely far (`Real::MAX`).
pub fn separation(a: &Geometry, b: &Geometry) -> (Real, Vect) {
    if is_empty(a) || is_empty(b) {
        return (Real::MAX, Vect::ZERO);
    }
    match closest_cores(a, b) {
        Some(c) => (c.d - a.radius() - b.radius(), c.n),
        None => (box_gap(a, b), Vect::ZERO),
    }
}

/// The cores' closest points (their deepest ones when they overlap) and
/// what [`separation`] measures between them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoreClosest {
    /// Signed core distance (the radii not subtracted).
    pub(crate) d: Real,
    /// Unit direction from `a` toward `b`.
    pub(crate) n: Vect,
    /// The point of `b`'s core, in the caller's coordinates.
    pub(crate) b: Vect,
}

/// The computation of [`separation`] with the closest points kept (the
/// shape casts put their hit point on `b`'s surface from them): translated
/// by `a`'s anchor, a closed form for two circles, GJK for the rest.
/// `None` when GJK stopped at its cap or a polygon is empty.
pub(crate) fn closest_cores(a: &Geometry, b: &Geometry) -> Option<CoreClosest> {
    if is_empty(a) || is_empty(b) {
        return None;
    }
    let anchor = anchor_of(a);
    let (ma, mb) = (moved(a, anchor), moved(b, anchor));
    let c = match (&ma, &mb) {
        (Geometry::Circle(x), Geometry::Circle(y)) => {
            let (n, d) = (y.offset - x.offset).normalize_with_length();
            Some(CoreClosest {
                d,
                n: if n == Vect::ZERO { Vect::X } else { n },
                b: y.offset,
            })
        }
        (Geometry::Circle(x), Geometry::Segment(y)) => core(x, y),
        (Geometry::Circle(x), Geometry::Poly(y)) => core(x, y),
        (Geometry::Segment(x), Geometry::Circle(y)) => core(x, y),
        (Geometry::Segment(x), Geometry::Segment(y)) => core(x, y),
        (Geometry::Segment(x), Geometry::Poly(y)) => core(x, y),
        (Geometry::Poly(x), Geometry::Circle(y)) => core(x, y),
        (Geometry::Poly(x), Geometry::Segment(y)) => core(x, y),
        (Geometry::Poly(x), Geometry::Poly(y)) => core(x, y),
    }?;
    Some(CoreClosest {
        b: c.b + anchor,
        ..c
    })
}

/// Core distance, normal and `b`'s closest point by GJK; `None` if it
/// stopped at its cap.
fn core<A: SupportShape, B: SupportShape>(a: &A, b: &B) -> Option<CoreClosest> {
    let r = gjk(&SupportContext::new(a, b), 0);
    (!r.hit_iteration_cap).then_some(CoreClosest {
        d: r.d,
        n: r.n,
        b: r.b,
    })
}

/// The larger of the two axis gaps between the shapes' bounding boxes (0
/// when they overlap): a lower bound of the distance between the shapes.
fn box_gap(a: &Geometry, b: &Geometry) -> Real {
    let (x, y) = (a.bb(), b.bb());
    let gx = (y.l - x.r).max(x.l - y.r);
    let gy = (y.b - x.t).max(x.b - y.t);
    gx.max(gy).max(Real::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real;
    use crate::shape::{Circle, Poly, Segment};

    fn square(at: Vect, h: Real) -> Geometry {
        let v = [
            at + Vect::new(h, -h),
            at + Vect::new(h, h),
            at + Vect::new(-h, h),
            at + Vect::new(-h, -h),
        ];
        Geometry::Poly(Poly::from_ccw_unchecked(&v, Real::ZERO))
    }

    #[test]
    fn separated_pairs_of_every_kind() {
        let c = Geometry::Circle(Circle::new(Real::HALF, Vect::from_ints(0, 0)));
        let far = Geometry::Circle(Circle::new(Real::ONE, Vect::from_ints(3, 4)));
        assert_eq!(
            separation(&c, &far),
            (real!(3.5), Vect::new(real!(0.6), real!(0.8)))
        );
        let seg = Geometry::Segment(Segment::new(
            Vect::from_ints(-5, 2),
            Vect::from_ints(5, 2),
            Real::HALF,
        ));
        assert_eq!(separation(&c, &seg), (Real::ONE, Vect::Y));
        assert_eq!(separation(&seg, &c), (Real::ONE, -Vect::Y));
        let sq = square(Vect::from_ints(4, 0), Real::ONE);
        assert_eq!(separation(&c, &sq), (real!(2.5), Vect::X));
        assert_eq!(separation(&sq, &seg).0, Real::ZERO + real!(0.5));
    }

    #[test]
    fn overlap_is_negative_and_far_from_the_origin_the_same() {
        let c = Geometry::Circle(Circle::new(Real::HALF, Vect::ZERO));
        let sq = square(Vect::new(real!(1.25), Real::ZERO), Real::ONE);
        assert_eq!(separation(&c, &sq), (-real!(0.25), Vect::X));
        let off = Vect::from_ints(1_000_000, -2_000_000);
        let c2 = Geometry::Circle(Circle::new(Real::HALF, off));
        let sq2 = square(off + Vect::new(real!(1.25), Real::ZERO), Real::ONE);
        assert_eq!(separation(&c2, &sq2), separation(&c, &sq));
    }

    #[test]
    fn box_gap_is_a_lower_bound() {
        let c = Geometry::Circle(Circle::new(Real::HALF, Vect::ZERO));
        let far = Geometry::Circle(Circle::new(Real::ONE, Vect::from_ints(3, 4)));
        assert_eq!(box_gap(&c, &far), real!(2.5));
        assert!(box_gap(&c, &far) <= separation(&c, &far).0);
        assert_eq!(box_gap(&c, &c), Real::ZERO);
    }
}
