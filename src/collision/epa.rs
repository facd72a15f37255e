//! EPA: penetration of two overlapping cores (MIS `EPA`).
//!
//! The Expanding Polytope Algorithm starts from GJK's triangle of Minkowski
//! points around the origin and grows a convex polygon inside `M = B − A`
//! (kept counter-clockwise) until its edge nearest the origin lies on the
//! boundary of `M`. That edge's distance is the penetration depth and its
//! inward normal the direction that separates B from A fastest.
//!
//! Each step: take the hull edge nearest the origin, ask for the support point
//! of `M` along its outward normal `rperp(e1 − e0)`; if that point is not
//! strictly beyond the edge (exact 128-bit cross product), the edge is on the
//! boundary: done. Otherwise insert it and drop the hull vertices it makes
//! non-convex (they form a run on each side of the new point).
//!
//! Why it is built this way:
//! * The hull is a fixed array (no allocation, no panicking index): at most
//!   one point is added per iteration, so `3 + WARN_EPA_ITERATIONS` slots
//!   always suffice.
//! * Each edge's squared distance to the origin is computed once, when the
//!   edge is created (one 128-bit division), and kept beside the vertex;
//!   finding the nearest edge is then a scan of integers. Two edges are new
//!   per iteration, so the loop costs two divisions per step, not one per edge.
//! * Inclusion tests are exact, so every inserted point is strictly outside
//!   the hull: the hull grows strictly and the loop ends. The cap
//!   ([`WARN_EPA_ITERATIONS`]) is a guard; reaching it returns the best edge
//!   so far with `hit_iteration_cap` set.
use super::contact::{closest_points_new, closest_t, lerp_t, ClosestPoints};
use super::support::{support, MinkowskiPoint, SupportContext, SupportShape};
use super::wide;
use super::WARN_EPA_ITERATIONS;

/// Hull capacity: the starting triangle plus one point per iteration.
const HULL_CAP: usize = WARN_EPA_ITERATIONS as usize + 3;

/// Squared distance from the origin to the edge `x y` (units 2^-64).
#[inline]
fn edge_key(x: &MinkowskiPoint, y: &MinkowskiPoint) -> u128 {
    wide::len_sq(lerp_t(x.ab, y.ab, closest_t(x.ab, y.ab)))
}

/// True if `q` is a strictly convex corner between `prev` and `next`.
#[inline]
fn convex(prev: &MinkowskiPoint, q: &MinkowskiPoint, next: &MinkowskiPoint) -> bool {
    wide::cross(q.ab - prev.ab, next.ab - q.ab) > 0
}

/// A counter-clockwise polygon of Minkowski points; `keys[i]` is the squared
/// distance of edge `pts[i] → pts[next(i)]` from the origin.
struct Hull {
    pts: [MinkowskiPoint; HULL_CAP],
    keys: [u128; HULL_CAP],
    len: usize,
}

impl Hull {
    /// The triangle `(v0, v1, v2)`, which must be counter-clockwise.
    #[inline(always)]
    fn triangle(v0: MinkowskiPoint, v1: MinkowskiPoint, v2: MinkowskiPoint) -> Hull {
        let mut hull = Hull {
            pts: [MinkowskiPoint::default(); HULL_CAP],
            keys: [u128::MAX; HULL_CAP],
            len: 0,
        };
        let keys = [edge_key(&v0, &v1), edge_key(&v1, &v2), edge_key(&v2, &v0)];
        for ((slot, key), (p, k)) in hull
            .pts
            .iter_mut()
            .zip(hull.keys.iter_mut())
            .zip([v0, v1, v2].into_iter().zip(keys))
        {
            *slot = p;
            *key = k;
            hull.len += 1;
        }
        hull
    }

    /// The index after `i`, cyclically (no division).
    #[inline]
    fn next(&self, i: usize) -> usize {
        if i + 1 >= self.len {
            0
        } else {
            i + 1
        }
    }

    /// The index before `i`, cyclically.
    #[inline]
    fn prev(&self, i: usize) -> usize {
        if i == 0 {
            self.len.saturating_sub(1)
        } else {
            i - 1
        }
    }

    #[inline]
    fn at(&self, i: usize) -> MinkowskiPoint {
        self.pts.get(i).copied().unwrap_or_default()
    }

    /// Index of the edge nearest the origin (the first on a tie).
    fn nearest_edge(&self) -> usize {
        let keys = self.keys.get(..self.len).unwrap_or(&[]);
        let mut best = 0;
        let mut best_key = u128::MAX;
        for (i, k) in keys.iter().enumerate() {
            if *k < best_key {
                best = i;
                best_key = *k;
            }
        }
        best
    }

    /// Inserts `p` (strictly outside edge `i → next(i)`) and removes the
    /// vertices it makes non-convex, which form a run on each side of the
    /// insertion point. In place: the survivors are rotated to the front
    /// (their outgoing edges, and so their keys, are unchanged) and `p` is
    /// appended. At least two old vertices always remain.
    fn insert(&mut self, i: usize, p: MinkowskiPoint) {
        let mut keep = self.len;
        let mut first = self.next(i);
        while keep > 2 && !convex(&p, &self.at(first), &self.at(self.next(first))) {
            first = self.next(first);
            keep -= 1;
        }
        let mut last = i;
        while keep > 2 && !convex(&self.at(self.prev(last)), &self.at(last), &p) {
            last = self.prev(last);
            keep -= 1;
        }
        let len = self.len;
        if let (Some(pts), Some(keys)) = (self.pts.get_mut(..len), self.keys.get_mut(..len)) {
            // first < len, so the rotations cannot fail.
            pts.rotate_left(first);
            keys.rotate_left(first);
        }
        // Survivors now occupy 0..keep (keep ≥ 2); the last one's edge now
        // ends at p, and p's edge closes the polygon.
        let (tail, head) = (self.at(keep - 1), self.at(0));
        let (key_tail, key_p) = (edge_key(&tail, &p), edge_key(&p, &head));
        if let (Some(slot), Some(k)) = (self.pts.get_mut(keep), self.keys.get_mut(keep)) {
            *slot = p;
            *k = key_p;
            self.len = keep + 1;
            if let Some(k) = self.keys.get_mut(keep - 1) {
                *k = key_tail;
            }
        }
    }
}

/// MIS `EPA`: the penetration of the cores, starting from a triangle of
/// Minkowski points that contains the origin (as GJK produces it; either
/// winding is accepted). The result has `d ≤ 0` and `n` from A toward B.
pub fn epa<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    v0: MinkowskiPoint,
    v1: MinkowskiPoint,
    v2: MinkowskiPoint,
) -> ClosestPoints {
    epa_capped(ctx, [v0, v1, v2], WARN_EPA_ITERATIONS)
}

/// [`epa`] with an explicit iteration cap (at most `WARN_EPA_ITERATIONS`).
pub(crate) fn epa_capped<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    tri: [MinkowskiPoint; 3],
    cap: u32,
) -> ClosestPoints {
    let [v0, mut v1, mut v2] = tri;
    if wide::cross(v1.ab - v0.ab, v2.ab - v0.ab) < 0 {
        core::mem::swap(&mut v1, &mut v2);
    }
    let mut hull = Hull::triangle(v0, v1, v2);
    let cap = cap.min(WARN_EPA_ITERATIONS);
    let mut iteration = 0;
    loop {
        let i = hull.nearest_edge();
        let (e0, e1) = (hull.at(i), hull.at(hull.next(i)));
        let delta = e1.ab - e0.ab;
        let p = support(ctx, delta.rperp());
        let beyond = wide::cross(delta, p.ab - e0.ab) < 0;
        if !beyond || p.id == e0.id || p.id == e1.id {
            // Reversed, so the origin is on the edge's left as
            // `closest_points_new` expects: n then points from A to B.
            return closest_points_new(&e1, &e0);
        }
        if iteration >= cap {
            let mut best = closest_points_new(&e1, &e0);
            best.hit_iteration_cap = true;
            return best;
        }
        if hull.len >= HULL_CAP {
            let mut best = closest_points_new(&e1, &e0);
            best.hit_iteration_cap = true;
            return best;
        }
        hull.insert(i, p);
        iteration += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Real, Vect};
    use crate::shape::Poly;

    fn square(half: i32, at: Vect) -> Poly {
        let h = Real::from_int(half);
        let v = [
            at + Vect::new(h, -h),
            at + Vect::new(h, h),
            at + Vect::new(-h, h),
            at + Vect::new(-h, -h),
        ];
        Poly::from_ccw_unchecked(&v, Real::ZERO)
    }

    fn start(ctx: &SupportContext<'_, Poly, Poly>) -> [MinkowskiPoint; 3] {
        [
            support(ctx, Vect::from_ints(1, 0)),
            support(ctx, Vect::from_ints(-1, 2)),
            support(ctx, Vect::from_ints(-1, -2)),
        ]
    }

    #[test]
    fn coincident_squares_penetrate_by_full_width() {
        let a = square(1, Vect::ZERO);
        let b = square(1, Vect::ZERO);
        let ctx = SupportContext::new(&a, &b);
        let r = epa_capped(&ctx, start(&ctx), WARN_EPA_ITERATIONS);
        assert_eq!(r.d, -Real::TWO);
        assert!(!r.hit_iteration_cap);
        // Either winding of the starting triangle gives the same answer.
        let [x, y, z] = start(&ctx);
        let r2 = epa_capped(&ctx, [x, z, y], WARN_EPA_ITERATIONS);
        assert_eq!((r2.d, r2.n), (r.d, r.n));
    }

    #[test]
    fn shallow_overlap_depth_and_normal() {
        let a = square(2, Vect::ZERO);
        let b = square(1, Vect::new(Real::ZERO, Real::from_int(2) + Real::HALF));
        let ctx = SupportContext::new(&a, &b);
        let r = epa_capped(&ctx, start(&ctx), WARN_EPA_ITERATIONS);
        assert_eq!(r.d, -Real::HALF);
        assert_eq!(r.n, Vect::Y);
    }

    #[test]
    fn cap_zero_returns_starting_edge_flagged() {
        // The starting triangle's nearest edge passes through the origin, so
        // EPA must expand at least once; with a cap of 0 it may not.
        let a = square(1, Vect::ZERO);
        let b = square(1, Vect::ZERO);
        let ctx = SupportContext::new(&a, &b);
        let r = epa_capped(&ctx, start(&ctx), 0);
        assert!(r.hit_iteration_cap);
        // Best so far: the hull lies inside M, so its nearest edge is no
        // farther from the origin than the true depth (2).
        assert!(r.d <= Real::ZERO && r.d >= -Real::TWO, "{:?}", r.d);
        assert!(r.n != Vect::ZERO);
        let full = epa_capped(&ctx, start(&ctx), 1);
        assert!(!full.hit_iteration_cap);
        assert_eq!(full.d, -Real::TWO);
    }
}
