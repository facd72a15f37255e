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
//! * That distance comes from exact 128-bit products (`x × y`, `|y − x|²`),
//!   not from a rounded closest point, so edges are ranked by their true
//!   distances to ~2^-61 relative whatever their length, and which face EPA
//!   stops on does not depend on the hull's history (its start) unless two
//!   faces are equally deep to that precision.
//! * Inclusion tests are exact, so every inserted point is strictly outside
//!   the hull: the hull grows strictly and the loop ends. The cap
//!   ([`WARN_EPA_ITERATIONS`]) is a guard; reaching it returns the best edge
//!   so far with `hit_iteration_cap` set.
use super::contact::{closest_points_new, nearest_feature, ClosestPoints, Nearest};
use super::support::{support, MinkowskiPoint, SupportContext, SupportShape};
use crate::math::exact;
use crate::shape::geometry::next_index;

/// EPA iteration cap (MIS `WARN_EPA_ITERATIONS`); the same reasoning as GJK.
pub const WARN_EPA_ITERATIONS: u32 = 30;

/// Hull capacity: the starting triangle plus one point per iteration.
const HULL_CAP: usize = WARN_EPA_ITERATIONS as usize + 3;

/// The squared distance from the origin to the edge `x y`, as a key that
/// orders like it, to ~2^-61 relative (see [`float_key`]).
///
/// Computed from exact 128-bit quantities: `|x|²` or `|y|²` when the origin
/// projects onto an end (the exact test GJK uses), else
/// `(x × y)² / |y − x|²`, the distance to the edge line. An earlier version
/// took `|p|²` of the closest point `p` found through the rounded edge
/// parameter `t` (`closest_t`, `lerp_t`); on an edge of length `L` one ulp of
/// `t` moves `p` by `L·2^-33`, which on long edges exceeds the depth
/// differences being ranked and made EPA stop on a face up to that much
/// deeper than the nearest one (a fuzz finding: 475 ulp on edges 2·10⁴ long).
#[inline]
fn edge_key(x: &MinkowskiPoint, y: &MinkowskiPoint) -> u128 {
    match nearest_feature(x.ab, y.ab) {
        Nearest::V0 => float_key(exact::len_sq(x.ab), 0),
        Nearest::V1 => float_key(exact::len_sq(y.ab), 0),
        Nearest::Interior => line_key(
            exact::cross(x.ab, y.ab).unsigned_abs(),
            exact::len_sq(y.ab - x.ab),
        ),
    }
}

/// `c² / l2` (for `c = |x × y|`, `l2 = |y − x|²`, both in units of 2^-64) as a
/// [`float_key`], from 64-bit leading parts: `c` and `l2` are shifted right
/// to 64 significant bits (exact below 2^64), the square is shifted left to
/// 128 bits and divided, giving a quotient of at least 64 bits. Each step
/// truncates by at most 2^-63 relative. `l2 = 0` gives 0.
#[inline]
fn line_key(c: u128, l2: u128) -> u128 {
    if c == 0 {
        return 0;
    }
    // leading_zeros ≤ 128: never saturates.
    let bits = |v: u128| 128u32.saturating_sub(v.leading_zeros());
    let sc = bits(c).saturating_sub(64);
    let cm = c >> sc;
    // cm < 2^64, so the square fits (never saturates).
    let square = cm.saturating_mul(cm);
    let up = square.leading_zeros();
    let sl = bits(l2).saturating_sub(64);
    let q = (square << up).checked_div(l2 >> sl).unwrap_or(0);
    // c²/l2 = q · 2^(2·sc − up − sl); all terms are below 2^8 (never
    // saturates).
    let exp = (sc as i32)
        .saturating_mul(2)
        .saturating_sub(up as i32)
        .saturating_sub(sl as i32);
    float_key(q, exp)
}

/// A non-negative value `m · 2^e` as a `u128` key with the same order: the
/// position of its top bit (biased by 256; the values here have top bits in
/// −128..=254) in the high 9 bits, then its leading 119 bits. Zero is 0.
#[inline]
fn float_key(m: u128, e: i32) -> u128 {
    if m == 0 {
        return 0;
    }
    // m ≠ 0: top is in 0..=127, and the shifts below in 0..=118 (none of
    // these subtractions saturates).
    let top = 127i32.saturating_sub(m.leading_zeros() as i32);
    let mantissa = if top > 118 {
        m >> top.saturating_sub(118)
    } else {
        m << 118i32.saturating_sub(top)
    };
    // |e| < 2^9 for every caller: the sum never saturates.
    let biased =
        u128::try_from(top.saturating_add(e).saturating_add(256).clamp(1, 511)).unwrap_or(1);
    (biased << 119) | mantissa
}

/// True if `q` is a strictly convex corner between `prev` and `next`.
#[inline]
fn convex(prev: &MinkowskiPoint, q: &MinkowskiPoint, next: &MinkowskiPoint) -> bool {
    exact::cross(q.ab - prev.ab, next.ab - q.ab) > 0
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
            // At most 3 iterations: never saturates.
            hull.len = hull.len.saturating_add(1);
        }
        hull
    }

    /// The index after `i`, cyclically (no division).
    #[inline]
    fn next(&self, i: usize) -> usize {
        next_index(i, self.len)
    }

    /// The index before `i`, cyclically.
    #[inline]
    fn prev(&self, i: usize) -> usize {
        if i == 0 {
            self.len.saturating_sub(1)
        } else {
            // i ≥ 1: never saturates.
            i.saturating_sub(1)
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
            // keep > 2: never saturates.
            keep = keep.saturating_sub(1);
        }
        let mut last = i;
        while keep > 2 && !convex(&self.at(self.prev(last)), &self.at(last), &p) {
            last = self.prev(last);
            // keep > 2: never saturates.
            keep = keep.saturating_sub(1);
        }
        let len = self.len;
        if let (Some(pts), Some(keys)) = (self.pts.get_mut(..len), self.keys.get_mut(..len)) {
            // first < len, so the rotations cannot fail.
            pts.rotate_left(first);
            keys.rotate_left(first);
        }
        // Survivors now occupy 0..keep (keep ≥ 2); the last one's edge now
        // ends at p, and p's edge closes the polygon. (keep ≥ 2 and
        // keep < HULL_CAP below: the ±1 never saturate.)
        let (tail, head) = (self.at(keep.saturating_sub(1)), self.at(0));
        let (key_tail, key_p) = (edge_key(&tail, &p), edge_key(&p, &head));
        if let (Some(slot), Some(k)) = (self.pts.get_mut(keep), self.keys.get_mut(keep)) {
            *slot = p;
            *k = key_p;
            self.len = keep.saturating_add(1);
            if let Some(k) = self.keys.get_mut(keep.saturating_sub(1)) {
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
    if exact::cross(v1.ab - v0.ab, v2.ab - v0.ab) < 0 {
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
        let beyond = exact::cross(delta, p.ab - e0.ab) < 0;
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
        // iteration < cap: never saturates.
        iteration = iteration.saturating_add(1);
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

    /// Exact order of `c²/l2` against `v` or against `c'²/l2'`, for values
    /// small enough that the cross products fit a `u128`.
    #[test]
    fn keys_order_like_the_exact_distances() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |bits: u32| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            u128::from(state >> (64 - bits)).max(1)
        };
        for round in 0..20_000 {
            let bits = 8 + (round % 24) as u32;
            let (c1, l1, c2, l2) = (next(bits), next(bits), next(bits), next(bits));
            // c1²/l1 vs c2²/l2 ⇔ c1²·l2 vs c2²·l1 (< 2^93).
            let exact = (c1 * c1 * l2).cmp(&(c2 * c2 * l1));
            assert_eq!(
                line_key(c1, l1).cmp(&line_key(c2, l2)),
                exact,
                "{c1} {l1} {c2} {l2}"
            );
            let v = next(2 * bits);
            let exact = (c1 * c1).cmp(&(v * l1));
            assert_eq!(
                line_key(c1, l1).cmp(&float_key(v, 0)),
                exact,
                "{c1} {l1} {v}"
            );
        }
        // Full-range operands against exact 384-bit products: whenever the
        // two distances differ by more than 2^-58 relative, the keys agree.
        fn mul(a: &[u64], b: &[u64]) -> Vec<u64> {
            let mut out = vec![0u64; a.len() + b.len()];
            for (i, x) in a.iter().enumerate() {
                let mut carry = 0u128;
                for (j, y) in b.iter().enumerate() {
                    let k = i + j;
                    let t = u128::from(*x) * u128::from(*y) + u128::from(out[k]) + carry;
                    out[k] = t as u64;
                    carry = t >> 64;
                }
                out[i + b.len()] = carry as u64;
            }
            out
        }
        let limbs = |v: u128| [v as u64, (v >> 64) as u64];
        let cmp = |x: &[u64], y: &[u64]| x.iter().rev().cmp(y.iter().rev());
        let mut checked = 0;
        for _ in 0..20_000 {
            let mut operand = || {
                let w = ((next(64) << 64) | next(64)) >> 1;
                (w >> (next(7) as u32 % 127)).max(1)
            };
            let (c1, l1, c2, l2) = (operand(), operand(), operand(), operand());
            let lhs = mul(&mul(&limbs(c1), &limbs(c1)), &limbs(l2));
            let rhs = mul(&mul(&limbs(c2), &limbs(c2)), &limbs(l1));
            // Skip near-ties: |lhs − rhs| ≤ lhs·2^-58 (compare lhs against rhs·(1 ± 2^-58)).
            let scaled = |v: &[u64], num: u128| mul(v, &limbs(num));
            let (lo, hi) = ((1u128 << 58) - 1, (1u128 << 58) + 1);
            let lhs58 = scaled(&lhs, 1 << 58);
            if cmp(&lhs58, &scaled(&rhs, lo)).is_ge() && cmp(&lhs58, &scaled(&rhs, hi)).is_le() {
                continue;
            }
            checked += 1;
            assert_eq!(
                line_key(c1, l1).cmp(&line_key(c2, l2)),
                cmp(&lhs, &rhs),
                "{c1} {l1} {c2} {l2}"
            );
        }
        assert!(checked > 19_000, "{checked}");
        // Large operands: powers of two are exact, neighbours keep their order.
        let big = 1u128 << 126;
        assert_eq!(line_key(big, big), float_key(big, 0));
        assert!(line_key(big, big) < line_key(big + (1 << 70), big));
        assert!(line_key(big, big + (1 << 70)) < line_key(big, big));
        assert_eq!(line_key(0, big), 0);
        assert_eq!(line_key(big, 0), float_key(0, 0));
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
