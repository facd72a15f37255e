//! GJK: closest points between two convex cores (MIS `GJK`).
//!
//! The 2D distance form of Gilbert–Johnson–Keerthi works on one edge
//! `(v0, v1)` of the Minkowski difference `M = B − A` at a time:
//!
//! 1. Orient the edge so the origin is on its left (`v0 × v1 ≥ 0`).
//! 2. Find the feature of the edge nearest the origin (vertex `v0`, vertex
//!    `v1` or the interior) and the direction `n` from it toward the origin:
//!    `−v0`, `−v1` or `perp(v1 − v0)`.
//! 3. Ask for the support point `p` of `M` along `n`.
//!    * If the triangle `(v0, v1, p)` strictly contains the origin, the cores
//!      overlap: hand the triangle to EPA for the penetration.
//!    * If `p` is no further along `n` than the edge, the edge holds the
//!      closest point of `M`: done.
//!    * Otherwise keep the sub-edge `(v0, p)` or `(p, v1)` whose Voronoi
//!      region holds the origin, and repeat.
//!
//! Why it is built this way: every test in steps 1–3 is the sign of an exact
//! 128-bit dot or cross product, and the search directions are exact (a
//! negated point or a perpendicular), so there is no division in the loop and
//! no rounding can make the distance stop decreasing: on exact predicates the
//! loop terminates. The one division and square root happen once, in
//! `closest_points_new`, on the final edge. [`WARN_GJK_ITERATIONS`] is a hard
//! cap all the same; reaching it returns the best edge so far and sets
//! `hit_iteration_cap`.
//!
//! Warm start (MIS `CollisionID`): the id of the last answer holds the vertex
//! indices of its edge; starting there usually ends GJK in one iteration.
use super::contact::{closest_points_new, nearest_feature, pack_id, ClosestPoints, Nearest};
use super::epa::epa;
use super::info::WarmStartId;
use super::support::{support, MinkowskiPoint, SupportContext, SupportPoint, SupportShape};
use crate::math::exact;
use crate::math::Vect;

/// GJK iteration cap (MIS `WARN_GJK_ITERATIONS`). Two polygons of at most 8
/// vertices have a Minkowski difference of at most 16 vertices, and GJK on
/// exact predicates visits each edge at most once, so 30 is never reached in
/// practice; Chipmunk uses the same number as its hard limit.
pub const WARN_GJK_ITERATIONS: u32 = 30;

/// MIS `GJK`: closest points of the cores of `ctx.a` and `ctx.b`, or (through
/// EPA) their penetration. `id` is the warm-start id of the previous answer for
/// this pair, or 0; the new one is in the result.
pub fn gjk<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    id: WarmStartId,
) -> ClosestPoints {
    gjk_capped(ctx, id, WARN_GJK_ITERATIONS)
}

/// The Minkowski point of vertex `ia` of A and `ib` of B, if both exist.
fn point_at<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    ia: u32,
    ib: u32,
) -> Option<MinkowskiPoint> {
    let a = ctx.a.point(ia)?;
    let b = ctx.b.point(ib)?;
    Some(MinkowskiPoint::new(
        SupportPoint { p: a, index: ia },
        SupportPoint { p: b, index: ib },
    ))
}

/// The edge stored in a warm-start id, if the id is non-zero, names existing
/// vertices and describes a non-degenerate pair of index pairs.
fn warm_start<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    id: WarmStartId,
) -> Option<(MinkowskiPoint, MinkowskiPoint)> {
    let (hi, lo) = (id >> 16, id & 0xFFFF);
    if id == 0 || hi == lo {
        return None;
    }
    let v0 = point_at(ctx, (hi >> 8) & 0xFF, hi & 0xFF)?;
    let v1 = point_at(ctx, (lo >> 8) & 0xFF, lo & 0xFF)?;
    Some((v0, v1))
}

/// First edge without a cache: the support points on either side of the line
/// through the two cores' centres (Chipmunk's choice; `+x` if they coincide).
fn cold_start<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
) -> (MinkowskiPoint, MinkowskiPoint) {
    let axis = (ctx.a.center() - ctx.b.center()).perp();
    let axis = if axis == Vect::ZERO { Vect::X } else { axis };
    (support(ctx, axis), support(ctx, -axis))
}

/// True to keep `(v0, p)`, false to keep `(p, v1)`: the sub-edge of the
/// triangle `(v0, v1, p)` whose Voronoi region holds the origin. The origin is
/// outside the triangle and nearer to `p`'s two edges than to `v0 v1`.
fn keep_first(v0: Vect, v1: Vect, p: Vect) -> bool {
    let (to_v0, to_v1) = (v0 - p, v1 - p);
    // Does the origin project onto the inside of each edge, seen from p?
    let along_v0 = exact::dot(p, to_v0) < 0;
    let along_v1 = exact::dot(p, to_v1) < 0;
    match (along_v0, along_v1) {
        (true, false) => true,
        (false, true) => false,
        // Vertex region of p: both edges share the closest point.
        (false, false) => true,
        // Keep (v0, p) unless the origin is strictly on v1's side of line p v0.
        (true, true) => {
            let v1_side = exact::cross(to_v0, to_v1).signum();
            let o_side = exact::cross(p, to_v0).signum();
            // Signs in {−1, 0, 1}: the product never saturates.
            v1_side.saturating_mul(o_side) <= 0
        }
    }
}

/// The answer when the origin coincides with a point `v` of `M` (the cores
/// touch exactly at a vertex): no direction is defined by the simplex, so the
/// normal is the centre-to-centre direction (`+x` if the centres coincide).
fn touching<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    v: &MinkowskiPoint,
    id: WarmStartId,
) -> ClosestPoints {
    ClosestPoints {
        a: v.a,
        b: v.b,
        n: exact::unit_or(ctx.b.center() - ctx.a.center(), Vect::X),
        d: crate::math::Real::ZERO,
        warm_start_id: id,
        hit_iteration_cap: false,
    }
}

/// [`gjk`] with an explicit iteration cap (tests exercise small caps).
pub(crate) fn gjk_capped<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    id: WarmStartId,
    cap: u32,
) -> ClosestPoints {
    let (mut v0, mut v1, mut warm) = match warm_start(ctx, id) {
        Some((v0, v1)) => (v0, v1, true),
        None => {
            let (v0, v1) = cold_start(ctx);
            (v0, v1, false)
        }
    };
    let mut iteration = 0;
    loop {
        if exact::cross(v0.ab, v1.ab) < 0 {
            core::mem::swap(&mut v0, &mut v1);
        }
        if iteration >= cap {
            let mut best = closest_points_new(&v0, &v1);
            best.hit_iteration_cap = true;
            return best;
        }
        let n = match nearest_feature(v0.ab, v1.ab) {
            Nearest::V0 => -v0.ab,
            Nearest::V1 => -v1.ab,
            Nearest::Interior => (v1.ab - v0.ab).perp(),
        };
        if n == Vect::ZERO {
            // The origin is a simplex vertex. Cached points need not lie on
            // the boundary of M, so retry from a cold start; support points
            // do, so the cores touch exactly.
            if warm {
                (v0, v1) = cold_start(ctx);
                warm = false;
                continue;
            }
            let v = if v0.ab == Vect::ZERO { v0 } else { v1 };
            return touching(ctx, &v, pack_id(&v0, &v1));
        }
        let p = support(ctx, n);
        if exact::cross(v1.ab, p.ab) > 0 && exact::cross(p.ab, v0.ab) > 0 {
            // (v0, v1, p) is counter-clockwise and holds the origin.
            return epa(ctx, v0, v1, p);
        }
        let edge_reach = exact::dot(v0.ab, n).max(exact::dot(v1.ab, n));
        if p.id == v0.id || p.id == v1.id || exact::dot(p.ab, n) <= edge_reach {
            return closest_points_new(&v0, &v1);
        }
        if keep_first(v0.ab, v1.ab, p.ab) {
            v1 = p;
        } else {
            v0 = p;
        }
        // iteration < cap (checked above): never saturates.
        iteration = iteration.saturating_add(1);
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::math::Real;
    use crate::real;
    use crate::shape::{Circle, Poly, Segment};

    fn boxed(w: i32, h: i32, at: Vect) -> Poly {
        let (hw, hh) = (
            Real::from_int(w) * Real::HALF,
            Real::from_int(h) * Real::HALF,
        );
        let v = [
            at + Vect::new(hw, -hh),
            at + Vect::new(hw, hh),
            at + Vect::new(-hw, hh),
            at + Vect::new(-hw, -hh),
        ];
        Poly::from_ccw(&v, Real::ZERO).unwrap_or_else(|_| Poly::from_ccw_unchecked(&v, Real::ZERO))
    }

    #[test]
    fn separated_boxes_distance_and_normal() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(2, 2, Vect::from_ints(5, 1));
        let r = gjk(&SupportContext::new(&a, &b), 0);
        assert_eq!(r.d, Real::from_int(3));
        assert_eq!(r.n, Vect::X);
        assert!(!r.hit_iteration_cap);
        // Warm start from the answer gives the same answer.
        let again = gjk(&SupportContext::new(&a, &b), r.warm_start_id);
        assert_eq!((again.d, again.n), (r.d, r.n));
    }

    #[test]
    fn corner_to_corner_uses_vertex_normal() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(2, 2, Vect::from_ints(5, 6));
        let r = gjk(&SupportContext::new(&a, &b), 0);
        // Corners (1,1) and (4,5): distance 5, normal (0.6, 0.8).
        assert_eq!(r.d, Real::from_int(5));
        assert!((r.n.x.to_f64() - 0.6).abs() < 1e-9 && (r.n.y.to_f64() - 0.8).abs() < 1e-9);
        assert_eq!(r.a, Vect::from_ints(1, 1));
        assert_eq!(r.b, Vect::from_ints(4, 5));
    }

    #[test]
    fn overlapping_boxes_go_through_epa() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(2, 2, Vect::new(real!(1.5), Real::ZERO));
        let r = gjk(&SupportContext::new(&a, &b), 0);
        assert_eq!(r.d, -Real::HALF);
        assert_eq!(r.n, Vect::X);
    }

    #[test]
    fn circle_point_against_segment_core() {
        let c = Circle::new(Real::ONE, Vect::from_ints(1, 3));
        let s = Segment::new(Vect::from_ints(-2, 0), Vect::from_ints(4, 0), Real::ZERO);
        let r = gjk(&SupportContext::new(&c, &s), 0);
        assert_eq!(
            (r.d, r.n, r.b),
            (Real::from_int(3), -Vect::Y, Vect::from_ints(1, 0))
        );
    }

    #[test]
    fn exact_corner_touch_is_zero_distance() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(2, 2, Vect::from_ints(2, 2));
        let r = gjk(&SupportContext::new(&a, &b), 0);
        assert_eq!(r.d, Real::ZERO);
        assert!(r.n.x.is_positive() && r.n.y.is_positive(), "{:?}", r.n);
    }

    #[test]
    fn bad_warm_start_ids_fall_back_to_cold_start() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(2, 2, Vect::from_ints(5, 1));
        for id in [0xFFFF_FFFF, 0x0909_0101, 0x0000_0001, 0x0101_0101] {
            let r = gjk(&SupportContext::new(&a, &b), id);
            assert_eq!(r.d, Real::from_int(3), "id {id:#x}");
        }
    }

    #[test]
    fn iteration_cap_returns_best_edge_and_flags() {
        let a = boxed(2, 2, Vect::ZERO);
        let b = boxed(3, 1, Vect::from_ints(7, 4));
        let ctx = SupportContext::new(&a, &b);
        let full = gjk(&ctx, 0);
        assert!(!full.hit_iteration_cap);
        let capped = gjk_capped(&ctx, 0, 0);
        assert!(capped.hit_iteration_cap);
        // The best-so-far answer is a valid upper bound on the distance.
        assert!(capped.d >= full.d);
        assert!(capped.n != Vect::ZERO);
    }
}
