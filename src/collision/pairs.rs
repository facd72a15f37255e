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
//! Segments with neighbours (`a_tangent`/`b_tangent` non-zero) apply the
//! neighbour rule to a contact found at an endpoint whose normal leaves it
//! towards the neighbour. Without the rule a body sliding along a chain of
//! segments catches on every seam: the free end of the next segment pushes
//! back against the motion. With the shapes' cores strictly apart, the
//! normal is the true direction to the other shape's nearest point, so the
//! neighbour is nearer and reports a contact of its own: this one is
//! rejected (Chipmunk's smooth-terrain rule). With the cores touching or
//! overlapping (sharp shapes resting on zero-radius segments) the normal is
//! only this segment's way out and says nothing about the neighbour; both
//! segments of a joint can each point into the other, so rejecting there
//! could drop the only contact holding a body. That contact is kept, with
//! its normal moved to the nearest one the chain allows at the joint (the
//! ghost-vertex idea of Box2D's chain segments): the segment's own face
//! normal at a flat or concave joint, the neighbour's at a convex one.
//! Either way no contact at a joint pushes against motion along the chain,
//! and a contact is rejected only when the neighbour will report one.
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
use super::canonical::{compare_circles, compare_polys, compare_segments};
use super::contact::{contact_points, ClosestPoints};
use super::gjk::gjk;
use super::info::{swap_id_shapes, CollisionInfo, CONTACT_TOLERANCE};
use super::sat::poly_to_poly_sat;
use super::support::{support_edge_for_poly, support_edge_for_segment, SupportContext};
use crate::math::exact;
use crate::math::exact::raw_sq;
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

/// The neighbour rule (see the module docs) for a contact that `seg` found
/// at `at` with normal `n` (from the first shape toward the second;
/// `seg_is_first` says which one `seg` is) and core distance `d`. Returns
/// the normal to make the contact with, or `None` to leave it to the
/// neighbour.
///
/// `toward` is any positive multiple of the direction from `at` to the
/// other shape's centre (for polygons and segments the sum of their
/// vertices minus `at` each; only its side of the segment's line matters).
///
/// Only a contact at a joint endpoint whose normal leaves the endpoint
/// towards the neighbour (`outward · tangent > 0`) is touched:
///
/// * cores strictly apart (`d > 0`): the normal is then the true direction
///   from the endpoint to the other shape's nearest point, and since it has
///   a component along the neighbour, points of the neighbour next to the
///   joint are strictly closer: the neighbour reports a contact of its own,
///   nearer than this one. Rejected.
/// * cores touching or overlapping (`d ≤ 0`): the normal is only the way
///   out of this one segment (GJK's pick among equal answers when
///   touching, EPA's shortest way out when overlapping), which may be off
///   the end of the segment and into the neighbour, while the neighbour's
///   own answer points off its end into this segment: each would leave the
///   contact to the other and the body falls through. The contact is kept,
///   with the normal moved to the nearest direction the chain allows at
///   the joint on the other shape's side: this segment's own face normal
///   at a flat or concave joint (the neighbour turns towards the other
///   shape), the neighbour's face normal at a convex one (it falls away;
///   between the two faces' normals is the joint's own range).
fn seam_normal(
    seg: &Segment,
    at: Vect,
    n: Vect,
    seg_is_first: bool,
    d: Real,
    toward: Vect,
) -> Option<Vect> {
    let outward = if seg_is_first { n } else { -n };
    let (tangent, along) = if at == seg.a {
        (seg.a_tangent, seg.b - seg.a)
    } else if at == seg.b {
        (seg.b_tangent, seg.a - seg.b)
    } else {
        return Some(n);
    };
    if tangent == Vect::ZERO || exact::dot(outward, tangent) <= 0 {
        return Some(n);
    }
    if d.is_positive() {
        return None;
    }
    // The other shape's side of the segment's line: from its centre, else
    // from the normal, else the segment's normal.
    let side = match exact::dot(seg.normal, toward) {
        0 => exact::dot(seg.normal, outward),
        s => s,
    };
    let face = if side < 0 { -seg.normal } else { seg.normal };
    let snapped = if exact::dot(face, tangent) < 0 {
        // Convex: the neighbour's face normal on the side away from this
        // segment (`along`), the edge of the joint's range nearest `n`.
        let m = exact::unit_or(tangent.perp(), face);
        if exact::dot(m, along) > 0 {
            -m
        } else {
            m
        }
    } else {
        face
    };
    if snapped == Vect::ZERO {
        return Some(n);
    }
    Some(if seg_is_first { snapped } else { -snapped })
}

/// Sum of `points` minus `at` each: a positive multiple of the direction
/// from `at` to their centroid.
fn toward(points: &[Vect], at: Vect) -> Vect {
    points.iter().fold(Vect::ZERO, |sum, p| sum + (*p - at))
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
    if exact::len_sq(delta) > sq(min_dist + CONTACT_TOLERANCE) {
        return;
    }
    let (n, dist) = exact::normalize(delta).unwrap_or((Vect::X, Real::ZERO));
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
    let (num, den) = (exact::dot(a.offset - b.a, seg), exact::len_sq(seg));
    let closest = if num <= 0 {
        b.a
    } else if num.unsigned_abs() >= den {
        b.b
    } else {
        b.a + exact::scale_by_ratio(seg, num, den)
    };
    let min_dist = a.radius + b.radius;
    let delta = closest - a.offset;
    if exact::len_sq(delta) > sq(min_dist + CONTACT_TOLERANCE) {
        return;
    }
    let (n, dist) = exact::normalize(delta).unwrap_or_else(|| {
        let n = if b.normal == Vect::ZERO {
            Vect::X
        } else {
            b.normal
        };
        (n, Real::ZERO)
    });
    let Some(m) = seam_normal(b, closest, n, false, dist, a.offset - closest) else {
        return;
    };
    // A snapped normal measures the separation along itself.
    let dist = if m == n {
        dist
    } else {
        (closest - a.offset).dot(m)
    };
    if dist > min_dist + CONTACT_TOLERANCE {
        return;
    }
    info.normal = m;
    let pa = a.offset + m.mult(a.radius);
    let pb = closest - m.mult(b.radius);
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
    if points.d.is_zero() && a.normal != Vect::ZERO && exact::cross(a.b - a.a, b.b - b.a) == 0 {
        points.n = a.normal;
    }
    if points.d > a.radius + b.radius + CONTACT_TOLERANCE {
        return;
    }
    let n = points.n;
    let Some(na) = seam_normal(
        a,
        points.a,
        n,
        true,
        points.d,
        toward(&[b.a, b.b], points.a),
    ) else {
        return;
    };
    let Some(nb) = seam_normal(
        b,
        points.b,
        n,
        false,
        points.d,
        toward(&[a.a, a.b], points.b),
    ) else {
        return;
    };
    points.n = if na == n { nb } else { na };
    let e1 = support_edge_for_segment(a, points.n);
    let e2 = support_edge_for_segment(b, -points.n);
    contact_points(&e1, &e2, &points, info);
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
    let mut points = gjk(&SupportContext::new(a, b), info.warm_start_id);
    note(info, &points);
    if points.d > a.radius + b.radius() + CONTACT_TOLERANCE {
        return;
    }
    let side = toward(b.verts(), points.a);
    let Some(n) = seam_normal(a, points.a, points.n, true, points.d, side) else {
        return;
    };
    points.n = n;
    let e1 = support_edge_for_segment(a, n);
    let e2 = support_edge_for_poly(b, -n);
    contact_points(&e1, &e2, &points, info);
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
    if !poly_to_poly_sat(a, b, Vect::ZERO, info) {
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

pub(crate) fn poly_to_poly_gjk_ordered(a: &Poly, b: &Poly, info: &mut CollisionInfo) {
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
        // The chained segment lets it slide: the box's core overlaps the
        // segment, so the contact is kept (it may be all that holds the box)
        // but with the chain's own normal, which cannot push back.
        let mut info = CollisionInfo::new(0);
        segment_to_poly(&chained, &sunk, &mut info);
        assert_eq!(info.count, 2, "chained segment holds the box");
        assert_eq!(info.normal, Vect::Y, "straight up, not against the motion");
        for c in info.contacts() {
            assert_eq!(c.distance, real!(-0.1));
            assert!(c.point_a.x >= Real::ZERO, "on the segment: {c:?}");
        }
        // Cores apart (a rounded box over the left neighbour, its core
        // corner 0.1 before the joint and 0.2 up, radius 0.25): the normal is
        // the true direction from the joint, the neighbour is nearer, so the
        // contact is left to the neighbour.
        let lifted = Poly::from_ccw_unchecked(
            &crate_box
                .verts()
                .iter()
                .map(|v| *v + Vect::new(real!(-0.1), real!(0.2)))
                .collect::<Vec<_>>(),
            real!(0.25),
        );
        let mut info = CollisionInfo::new(0);
        segment_to_poly(&second, &lifted, &mut info);
        assert!(info.count > 0, "free segment end touches the rounded box");
        let mut info = CollisionInfo::new(0);
        segment_to_poly(&chained, &lifted, &mut info);
        assert_eq!(info.count, 0, "left to the neighbour");
    }

    #[test]
    fn a_contact_both_segments_of_a_joint_would_leave_to_the_other_is_kept() {
        // Flat chain (−2,0) → (0,0) → (2,0) and a unit box tilted by about
        // −0.05 rad, its low corner on the joint, the box over the left
        // segment and touching the chain only there (the box that fell through).
        let left = Segment::new(Vect::from_ints(-2, 0), Vect::ZERO, Real::ZERO)
            .with_neighbors(Vect::from_ints(-4, 0), Vect::from_ints(2, 0));
        let right = Segment::new(Vect::ZERO, Vect::from_ints(2, 0), Real::ZERO)
            .with_neighbors(Vect::from_ints(-2, 0), Vect::from_ints(4, 0));
        let corners = [
            Vect::ZERO,
            Vect::new(real!(0.05), Real::ONE),
            Vect::new(real!(-0.95), real!(1.05)),
            Vect::new(-Real::ONE, real!(0.05)),
        ];
        let tilted = Poly::from_ccw_unchecked(&corners, Real::ZERO);
        let mut held = 0;
        for (seg, tangent) in [(&left, left.b_tangent), (&right, right.a_tangent)] {
            // The mechanism: each segment's own answer (cores touching) is
            // at the joint and leaves it towards the other segment, so the
            // plain neighbour rule dropped both and the box fell.
            let raw = gjk(&SupportContext::new(seg, &tilted), 0);
            assert_eq!((raw.a, raw.d), (Vect::ZERO, Real::ZERO), "{raw:?}");
            assert!(exact::dot(raw.n, tangent) > 0, "{raw:?}");
            let mut info = CollisionInfo::new(0);
            segment_to_poly(seg, &tilted, &mut info);
            held += info.count;
            if info.count > 0 {
                assert_eq!(info.normal, Vect::Y, "the chain's normal: {info:?}");
            }
        }
        assert!(held > 0, "a segment holds the box");
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
