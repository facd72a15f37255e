//! The six shape-pair functions (MIS `ShapeToShape`, the `CollisionFuncs`
//! table): circle–circle, circle–segment, segment–segment, circle–poly,
//! segment–poly, poly–poly. Each takes the pair in kind order
//! (circle < segment < poly) and fills a [`CollisionInfo`] whose normal points
//! from the first shape toward the second.
//!
//! Circle–circle and circle–segment have closed forms (a point against a
//! point or a segment), so they skip GJK. The other pairs run GJK on the
//! cores, subtract the rounding radii from the core distance, and, except for
//! circle–poly (one contact at the closest points), clip the two support
//! edges against each other for up to two contacts.
//!
//! Segments with neighbours (`a_tangent`/`b_tangent` non-zero) reject a
//! contact found at an endpoint whose normal points into the neighbour: the
//! other shape is then over the neighbouring segment, which reports the
//! contact itself. Without this rule a body sliding along a chain of
//! segments catches on every seam (Chipmunk's smooth-terrain rule).
//!
//! The functions work in whatever frame they are given; [`collide`](super::collide)
//! calls them on shapes moved next to the origin.
//!
//! **Swap symmetry.** The three same-kind functions put their pair in a
//! canonical order first (lexicographic on the shapes' data, the order
//! `collide` uses), run the computation on that order and mirror the answer
//! back if they swapped. So `f(b, a)` runs exactly the computation of
//! `f(a, b)`, and its answer is the exact mirror: normal negated bit for bit,
//! points, feature-id halves and warm-start id bytes swapped. GJK and EPA
//! alone are not swap-exact (their starting direction, tie-breaks and
//! roundings depend on which shape is `a`); this is where exactness comes
//! from. Two identical shapes are the same computation in both orders and
//! cannot give opposite normals.
use super::contact::{contact_points, ClosestPoints};
use super::gjk::gjk;
use super::sat::poly_to_poly_sat;
use super::support::{support_edge_for_poly, support_edge_for_segment, SupportContext};
use super::{compare_circles, compare_polys, compare_segments, swap_id_shapes};
use super::{CollisionInfo, CONTACT_TOLERANCE};
use crate::math::wide;
use crate::math::wide::raw_sq;
use crate::math::{Real, Vect};
use crate::shape::{Circle, Poly, Segment};
use core::cmp::Ordering;

/// `(r as unsigned raw)²`, exact, in units of 2^-64 (negative radii count as 0).
#[inline]
pub(super) fn sq(r: Real) -> u128 {
    // Non-negative: the exact square of the raw bits (≤ 2^126).
    raw_sq(r.max(Real::ZERO))
}

/// Records GJK's warm-start id and cap flag in the info.
#[inline]
fn note(info: &mut CollisionInfo, points: &ClosestPoints) {
    info.warm_start_id = points.warm_start_id;
    info.hit_iteration_cap |= points.hit_iteration_cap;
}

/// Runs `f` on a same-kind pair in canonical order: directly if `order` is
/// not `Greater`, else on the swapped pair (`f` then receives `true` and must
/// swap its arguments), with the warm-start id converted, mirroring the
/// answer back.
#[inline]
fn in_canonical_order(
    info: &mut CollisionInfo,
    order: Ordering,
    f: impl FnOnce(bool, &mut CollisionInfo),
) {
    if order == Ordering::Greater {
        let mut swapped = CollisionInfo::new(swap_id_shapes(info.warm_start_id));
        f(true, &mut swapped);
        *info = swapped.mirrored();
    } else {
        f(false, info);
    }
}

/// False if `n` (pointing from the segment toward the other shape when
/// `seg_is_first`, the reverse otherwise) leaves endpoint `at` of `seg`
/// towards that endpoint's neighbour.
fn segment_allows(seg: &Segment, at: Vect, n: Vect, seg_is_first: bool) -> bool {
    let outward = if seg_is_first { n } else { -n };
    let into = |tangent: Vect| wide::dot(outward, tangent) > 0;
    let rejected = (at == seg.a && into(seg.a_tangent)) || (at == seg.b && into(seg.b_tangent));
    !rejected
}

/// MIS `CircleToCircle`: closed form, swap-exact (see the module docs).
///
/// Coincident centres use the normal `+x` from the first circle of the
/// canonical order (the smaller radius) to the other, so the swapped call gets
/// `−x`. Why not something cleverer: the two circles differ at most in their
/// radius (the function sees them translated next to the origin, so the
/// common centre is no information either), and in the case that matters, a
/// pile of equal circles spawned at one point, they are identical, so every
/// pair of the pile gets the same normal whatever the rule and the pile can
/// only spread along one line. Breaking that needs data the narrow phase
/// does not have (which shape is which); a radius-derived direction would
/// only help piles of mixed sizes. See `docs/numerics.md`, "Many bodies at
/// one point".
pub fn circle_to_circle(a: &Circle, b: &Circle, info: &mut CollisionInfo) {
    in_canonical_order(info, compare_circles(a, b), |swap, info| {
        let (a, b) = if swap { (b, a) } else { (a, b) };
        circle_to_circle_ordered(a, b, info);
    });
}

/// [`circle_to_circle`] for circles already in canonical order.
pub(crate) fn circle_to_circle_ordered(a: &Circle, b: &Circle, info: &mut CollisionInfo) {
    let min_dist = a.radius + b.radius;
    let delta = b.offset - a.offset;
    if wide::len_sq(delta) > sq(min_dist + CONTACT_TOLERANCE) {
        return;
    }
    let (n, dist) = wide::normalize(delta).unwrap_or((Vect::X, Real::ZERO));
    info.normal = n;
    let pa = a.offset + n.mult(a.radius);
    let pb = b.offset - n.mult(b.radius);
    info.push_contact(pa, pb, dist - min_dist, 0);
}

/// MIS `CircleToSegment`: closed form against the nearest point of the
/// segment core. A centre exactly on the core uses the segment normal.
pub fn circle_to_segment(a: &Circle, b: &Segment, info: &mut CollisionInfo) {
    let seg = b.b - b.a;
    // Nearest point a + seg·t, t = (c − a)·seg / |seg|² from exact 128-bit
    // numerator and denominator, one rounding per component; the clamped
    // ends are exactly the endpoints (the neighbour rule tests for them).
    let (num, den) = (wide::dot(a.offset - b.a, seg), wide::len_sq(seg));
    let closest = if num <= 0 {
        b.a
    } else if num.unsigned_abs() >= den {
        b.b
    } else {
        b.a + wide::scale_by_ratio(seg, num, den)
    };
    let min_dist = a.radius + b.radius;
    let delta = closest - a.offset;
    if wide::len_sq(delta) > sq(min_dist + CONTACT_TOLERANCE) {
        return;
    }
    let (n, dist) = wide::normalize(delta).unwrap_or_else(|| {
        let n = if b.normal == Vect::ZERO {
            Vect::X
        } else {
            b.normal
        };
        (n, Real::ZERO)
    });
    if !segment_allows(b, closest, n, false) {
        return;
    }
    info.normal = n;
    let pa = a.offset + n.mult(a.radius);
    let pb = closest - n.mult(b.radius);
    info.push_contact(pa, pb, dist - min_dist, 0);
}

/// MIS `SegmentToSegment`: GJK on the two cores, then edge clipping;
/// swap-exact (see the module docs).
pub fn segment_to_segment(a: &Segment, b: &Segment, info: &mut CollisionInfo) {
    in_canonical_order(info, compare_segments(a, b), |swap, info| {
        let (a, b) = if swap { (b, a) } else { (a, b) };
        segment_to_segment_ordered(a, b, info);
    });
}

fn segment_to_segment_ordered(a: &Segment, b: &Segment, info: &mut CollisionInfo) {
    let mut points = gjk(&SupportContext::new(a, b), info.warm_start_id);
    note(info, &points);
    // Collinear cores that overlap: the Minkowski difference has no area,
    // GJK ends at distance 0 and its normal depends on where it started
    // (the warm-start id). Every direction across the common line separates
    // them at depth 0, so take the first segment's own normal: the answer no
    // longer depends on the start (fuzz finding, regression test
    // `collinear_overlapping_segments_agree_for_every_warm_start`).
    if points.d.is_zero() && a.normal != Vect::ZERO && wide::cross(a.b - a.a, b.b - b.a) == 0 {
        points.n = a.normal;
    }
    let n = points.n;
    if points.d <= a.radius + b.radius + CONTACT_TOLERANCE
        && segment_allows(a, points.a, n, true)
        && segment_allows(b, points.b, n, false)
    {
        let e1 = support_edge_for_segment(a, n);
        let e2 = support_edge_for_segment(b, -n);
        contact_points(&e1, &e2, &points, info);
    }
}

/// MIS `CircleToPoly`: GJK from the centre to the polygon core; one contact.
pub fn circle_to_poly(a: &Circle, b: &Poly, info: &mut CollisionInfo) {
    let points = gjk(&SupportContext::new(a, b), info.warm_start_id);
    note(info, &points);
    let min_dist = a.radius + b.radius();
    if points.d <= min_dist + CONTACT_TOLERANCE {
        let n = points.n;
        info.normal = n;
        let pa = points.a + n.mult(a.radius);
        let pb = points.b - n.mult(b.radius());
        info.push_contact(pa, pb, points.d - min_dist, 0);
    }
}

/// MIS `SegmentToPoly`: GJK, the neighbour rule, then edge clipping.
pub fn segment_to_poly(a: &Segment, b: &Poly, info: &mut CollisionInfo) {
    let points = gjk(&SupportContext::new(a, b), info.warm_start_id);
    note(info, &points);
    let n = points.n;
    if points.d <= a.radius + b.radius() + CONTACT_TOLERANCE && segment_allows(a, points.a, n, true)
    {
        let e1 = support_edge_for_segment(a, n);
        let e2 = support_edge_for_poly(b, -n);
        contact_points(&e1, &e2, &points, info);
    }
}

/// MIS `PolyToPoly`: separating axes over the stored edge normals, then
/// edge clipping (`sat.rs`); GJK (EPA when the cores overlap) only
/// for cores apart within contact range whose closest features are not a
/// vertex and a face, and for degenerate polygons. Swap-exact (see the
/// module docs).
pub fn poly_to_poly(a: &Poly, b: &Poly, info: &mut CollisionInfo) {
    in_canonical_order(info, compare_polys(a, b), |swap, info| {
        let (a, b) = if swap { (b, a) } else { (a, b) };
        poly_to_poly_ordered(a, b, info);
    });
}

/// [`poly_to_poly`] for polygons already in canonical order.
pub(crate) fn poly_to_poly_ordered(a: &Poly, b: &Poly, info: &mut CollisionInfo) {
    if !poly_to_poly_sat(a, b, info) {
        poly_to_poly_gjk_ordered(a, b, info);
    }
}

/// The GJK + EPA form of [`poly_to_poly`] (the path before separating axes),
/// kept as the reference the fast path is tested against and as its fallback.
/// Same contract, swap-exact.
pub fn poly_to_poly_gjk(a: &Poly, b: &Poly, info: &mut CollisionInfo) {
    in_canonical_order(info, compare_polys(a, b), |swap, info| {
        let (a, b) = if swap { (b, a) } else { (a, b) };
        poly_to_poly_gjk_ordered(a, b, info);
    });
}

fn poly_to_poly_gjk_ordered(a: &Poly, b: &Poly, info: &mut CollisionInfo) {
    let points = gjk(&SupportContext::new(a, b), info.warm_start_id);
    note(info, &points);
    let n = points.n;
    if points.d <= a.radius() + b.radius() + CONTACT_TOLERANCE {
        let e1 = support_edge_for_poly(a, n);
        let e2 = support_edge_for_poly(b, -n);
        contact_points(&e1, &e2, &points, info);
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::real;

    fn circle(r: Real, x: Real, y: Real) -> Circle {
        Circle::new(r, Vect::new(x, y))
    }

    fn rect(l: i32, b: i32, r: i32, t: i32) -> Poly {
        let v = [
            Vect::from_ints(r, b),
            Vect::from_ints(r, t),
            Vect::from_ints(l, t),
            Vect::from_ints(l, b),
        ];
        Poly::from_ccw_unchecked(&v, Real::ZERO)
    }

    #[test]
    fn circle_circle_overlap_depth_and_points() {
        let a = circle(Real::ONE, Real::ZERO, Real::ZERO);
        let b = circle(Real::ONE, real!(1.5), Real::ZERO);
        let mut info = CollisionInfo::new(0);
        circle_to_circle(&a, &b, &mut info);
        assert_eq!(info.count, 1);
        assert_eq!(info.normal, Vect::X);
        let c = info.contacts()[0];
        assert_eq!(c.distance, -Real::HALF);
        assert_eq!(c.point_a, Vect::X);
        assert_eq!(c.point_b, Vect::new(Real::HALF, Real::ZERO));
    }

    #[test]
    fn circle_circle_touching_counts_apart_does_not() {
        let a = circle(Real::ONE, Real::ZERO, Real::ZERO);
        let mut info = CollisionInfo::new(0);
        circle_to_circle(&a, &circle(Real::ONE, Real::TWO, Real::ZERO), &mut info);
        assert_eq!((info.count, info.contacts()[0].distance), (1, Real::ZERO));
        // Within the contact tolerance: still touching, with its true distance.
        let mut info = CollisionInfo::new(0);
        circle_to_circle(
            &a,
            &circle(Real::ONE, Real::TWO + Real::DELTA, Real::ZERO),
            &mut info,
        );
        assert_eq!((info.count, info.contacts()[0].distance), (1, Real::DELTA));
        let mut info = CollisionInfo::new(0);
        let apart = Real::TWO + CONTACT_TOLERANCE + Real::DELTA;
        circle_to_circle(&a, &circle(Real::ONE, apart, Real::ZERO), &mut info);
        assert_eq!(info.count, 0);
    }

    #[test]
    fn coincident_circles_pick_plus_x_from_the_smaller() {
        let a = circle(Real::ONE, Real::ZERO, Real::ZERO);
        let mut info = CollisionInfo::new(0);
        circle_to_circle(&a, &a, &mut info);
        assert_eq!(
            (info.normal, info.contacts()[0].distance),
            (Vect::X, -Real::TWO)
        );
        let p = circle(Real::ZERO, Real::ZERO, Real::ZERO);
        let mut info = CollisionInfo::new(0);
        circle_to_circle(&p, &p, &mut info);
        assert_eq!((info.count, info.normal), (1, Vect::X));
        // Different radii: +x from the smaller one, so swapping mirrors.
        let big = circle(Real::TWO, Real::ZERO, Real::ZERO);
        let mut small_first = CollisionInfo::new(0);
        circle_to_circle(&a, &big, &mut small_first);
        let mut big_first = CollisionInfo::new(0);
        circle_to_circle(&big, &a, &mut big_first);
        assert_eq!(small_first.normal, Vect::X);
        assert_eq!(big_first, small_first.mirrored());
        assert_eq!(big_first.contacts()[0].point_a, Vect::from_ints(-2, 0));
    }

    #[test]
    fn circle_resting_on_segment() {
        let ground = Segment::new(Vect::from_ints(-10, 0), Vect::from_ints(10, 0), real!(0.5));
        let ball = circle(Real::ONE, Real::from_int(3), real!(1.25));
        let mut info = CollisionInfo::new(0);
        circle_to_segment(&ball, &ground, &mut info);
        assert_eq!(info.count, 1);
        assert_eq!(info.normal, -Vect::Y);
        let c = info.contacts()[0];
        assert_eq!(c.distance, real!(-0.25));
        assert_eq!(c.point_a, Vect::new(Real::from_int(3), real!(0.25)));
        assert_eq!(c.point_b, Vect::new(Real::from_int(3), Real::HALF));
    }

    #[test]
    fn segment_neighbours_reject_seam_contacts() {
        // Chain (−2,0) → (0,0) → (2,0); the ball sits over the first segment,
        // just past the seam, touching the second one only at its endpoint a.
        let second = Segment::new(Vect::ZERO, Vect::from_ints(2, 0), Real::ZERO);
        let ball = circle(Real::ONE, real!(-0.3), real!(0.8));
        let mut info = CollisionInfo::new(0);
        circle_to_segment(&ball, &second, &mut info);
        assert_eq!(info.count, 1, "no neighbours: endpoint contact");
        let chained = second.with_neighbors(Vect::from_ints(-2, 0), Vect::from_ints(4, 0));
        let mut info = CollisionInfo::new(0);
        circle_to_segment(&ball, &chained, &mut info);
        assert_eq!(info.count, 0, "neighbour on the left takes it");
        // A convex corner (hill top): the neighbour falls away, so keep it.
        let hill = second.with_neighbors(Vect::from_ints(-2, -1), Vect::from_ints(4, -1));
        let mut info = CollisionInfo::new(0);
        circle_to_segment(
            &circle(Real::ONE, real!(-0.1), real!(0.5)),
            &hill,
            &mut info,
        );
        assert_eq!(info.count, 1);
        // The same rule for a box sliding over the seam (segment first).
        let crate_box = rect(-1, 0, 0, 1);
        let sunk = Poly::from_ccw_unchecked(
            &crate_box
                .verts()
                .iter()
                .map(|v| *v + Vect::new(real!(0.05), real!(-0.1)))
                .collect::<Vec<_>>(),
            Real::ZERO,
        );
        let mut info = CollisionInfo::new(0);
        segment_to_poly(&second, &sunk, &mut info);
        assert!(info.count > 0, "free segment end catches the box");
        assert_eq!(
            info.normal,
            -Vect::X,
            "the catch: a normal against the motion"
        );
        let mut info = CollisionInfo::new(0);
        segment_to_poly(&chained, &sunk, &mut info);
        assert_eq!(info.count, 0, "chained segment lets it slide");
    }

    #[test]
    fn box_resting_on_box_gives_two_contacts() {
        let ground = rect(-5, -1, 5, 0);
        // 2×1 box sunk 0.25 into the ground.
        let v = [
            Vect::new(Real::ONE, real!(-0.25)),
            Vect::new(Real::ONE, real!(0.75)),
            Vect::new(-Real::ONE, real!(0.75)),
            Vect::new(-Real::ONE, real!(-0.25)),
        ];
        let top = Poly::from_ccw_unchecked(&v, Real::ZERO);
        let mut info = CollisionInfo::new(0);
        poly_to_poly(&ground, &top, &mut info);
        assert_eq!(info.count, 2);
        assert_eq!(info.normal, Vect::Y);
        for c in info.contacts() {
            assert_eq!(c.distance, real!(-0.25));
            assert_eq!(c.point_a.y, Real::ZERO);
            assert_eq!(c.point_b.y, real!(-0.25));
        }
        // The pair runs in canonical order (the box first: its first vertex
        // has the smaller x), so the contacts come in the box's clipping order.
        let xs: Vec<_> = info.contacts().iter().map(|c| c.point_a.x).collect();
        assert_eq!(xs, vec![-Real::ONE, Real::ONE]);
        // Ids name (ground vertex, box vertex): ground top edge 1 → 2, box bottom 3 → 0.
        let ids: Vec<_> = info.contacts().iter().map(|c| c.feature_id).collect();
        assert_eq!(ids, vec![(2 << 16) | 3, 1 << 16]);
        // The other order is the exact mirror.
        let mut swapped = CollisionInfo::new(0);
        poly_to_poly(&top, &ground, &mut swapped);
        assert_eq!(swapped, info.mirrored());
    }

    #[test]
    fn rounded_boxes_touch_through_radius() {
        let mut a = rect(0, 0, 1, 1);
        a.radius = real!(0.25);
        let mut b = rect(0, 0, 1, 1);
        b.radius = real!(0.25);
        for v in b.verts.iter_mut() {
            *v += Vect::new(real!(1.4), Real::ZERO);
        }
        let mut info = CollisionInfo::new(0);
        poly_to_poly(&a, &b, &mut info);
        assert_eq!(info.count, 2);
        assert_eq!(info.normal, Vect::X);
        for c in info.contacts() {
            assert_eq!(c.distance, real!(-0.1));
            assert_eq!(c.point_a.x, real!(1.25));
            assert_eq!(c.point_b.x, real!(1.15));
        }
    }

    #[test]
    fn crossing_segments_and_parallel_capsules() {
        let a = Segment::new(Vect::from_ints(-1, 0), Vect::from_ints(1, 0), real!(0.125));
        let b = Segment::new(Vect::from_ints(0, -1), Vect::from_ints(0, 1), real!(0.125));
        let mut info = CollisionInfo::new(0);
        segment_to_segment(&a, &b, &mut info);
        assert!(info.count >= 1);
        let h = real!(0.1875);
        let c = Segment::new(
            Vect::new(Real::ZERO, h),
            Vect::new(Real::TWO, h),
            real!(0.125),
        );
        let mut info = CollisionInfo::new(0);
        segment_to_segment(&a, &c, &mut info);
        assert_eq!(info.count, 2);
        assert_eq!(info.normal, Vect::Y);
        for p in info.contacts() {
            assert_eq!(p.distance, real!(-0.0625));
        }
    }

    #[test]
    fn circle_against_poly_face_and_corner() {
        let b = rect(0, 0, 2, 2);
        let above = circle(Real::HALF, Real::ONE, real!(2.25));
        let mut info = CollisionInfo::new(0);
        circle_to_poly(&above, &b, &mut info);
        assert_eq!(info.count, 1);
        assert_eq!(info.normal, -Vect::Y);
        assert_eq!(info.contacts()[0].distance, real!(-0.25));
        let corner = circle(Real::ONE, real!(2.5), real!(2.5));
        let mut info = CollisionInfo::new(0);
        circle_to_poly(&corner, &b, &mut info);
        assert_eq!(info.count, 1);
        let d = info.contacts()[0].distance.to_f64();
        assert!((d - (0.5f64.sqrt() - 1.0)).abs() < 1e-9, "{d}");
        let (nx, ny) = info.normal.to_f64();
        assert!((nx + 0.5f64.sqrt()).abs() < 1e-9 && (ny + 0.5f64.sqrt()).abs() < 1e-9);
        assert_eq!(info.contacts()[0].point_b, Vect::from_ints(2, 2));
    }
}
