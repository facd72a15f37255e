//! Convex hull of a point set (Chipmunk `cpConvexHull`), used by
//! `poly_shape_new` to turn arbitrary points into a convex polygon.
//!
//! # Method
//! QuickHull, as Chipmunk does it: start with the chord from the leftmost to
//! the rightmost point, keep the points outside it, take the farthest one as a
//! new hull vertex and recurse on the two new chords. A chord whose
//! farthest point is within `tolerance` becomes a hull edge and its points
//! are dropped (so every dropped point lies within `tolerance` of the
//! hull; Chipmunk drops points near intermediate chords, which can leave
//! one farther out), and so are collinear points (a point must be
//! *strictly* outside a chord to survive).
//!
//! Built this way because:
//! * **Exact orientation.** Every side test is [`orientation`]: the cross
//!   product of raw `i64` bits on `i128`, with no rounding, so the hull is
//!   exactly convex and exactly contains every input point (with
//!   `tolerance = 0`). `Vect::cross` rounds to 2^-32 and would call a sliver
//!   of area 2^-33 "collinear".
//! * **Deterministic output.** The hull starts at the point with the smallest
//!   x (then smallest y), runs counter-clockwise, and ties between equally far
//!   pivots go to the one nearest the chord's start. The result therefore
//!   depends only on the *set* of points, not on their order.
//! * **No recursion.** The recursion runs on an explicit stack, and each point
//!   goes to at most one sub-problem, so any input size finishes in O(n²)
//!   worst case (O(n log n) typical) without risk of stack overflow.
//!
//! # Range
//! Orientation is exact for any input: differences of raw `i64` bits take 65
//! bits and their products 130, so the sign is decided on a 256-bit product
//! (the value is saturated to `i128` only beyond 2^127, where just its sign
//! and order matter). A fuzz-found case (extent ≥ 2^31 with saturated
//! differences) produced a duplicated vertex before this.
use crate::math::exact::{raw_diff, I256};
use crate::math::{Real, Vect};

/// Exact orientation of the triangle `a, b, c`: `(b − a) × (c − a)` in units
/// of 2^-64 (twice the signed area). Positive when `c` lies left of `a → b`
/// (a counter-clockwise turn), negative when right, zero when collinear.
///
/// Exact for every input; the value saturates to `i128` (keeping its sign)
/// only when the triangle is wider than the `Real` range.
#[inline]
pub fn orientation(a: Vect, b: Vect, c: Vect) -> i128 {
    let (abx, aby) = (raw_diff(b.x, a.x), raw_diff(b.y, a.y));
    let (acx, acy) = (raw_diff(c.x, a.x), raw_diff(c.y, a.y));
    if abx
        .unsigned_abs()
        .max(aby.unsigned_abs())
        .max(acx.unsigned_abs())
        .max(acy.unsigned_abs())
        < (1 << 63)
    {
        // Fast path: each product is below 2^126, the difference below 2^127.
        #[allow(clippy::arithmetic_side_effects)]
        let fast = abx * acy - aby * acx;
        return fast;
    }
    I256::mul_i128(abx, acy)
        .sub(I256::mul_i128(aby, acx))
        .saturating_to_i128()
}

/// `tolerance · |b − a|` in units of 2^-64: the orientation value a point
/// needs to exceed to be more than `tolerance` away from the line `a b`.
/// `tolerance` is ≥ 0 here.
fn threshold(a: Vect, b: Vect, tolerance: Real) -> i128 {
    if tolerance.is_zero() {
        return 0;
    }
    let dx = raw_diff(b.x, a.x).unsigned_abs();
    let dy = raw_diff(b.y, a.y).unsigned_abs();
    // dx, dy ≤ 2^64: saturate the (unphysical) squares beyond u128.
    let len = dx
        .saturating_mul(dx)
        .saturating_add(dy.saturating_mul(dy))
        .isqrt();
    let tol = u128::from(tolerance.to_bits().unsigned_abs());
    // tol < 2^63 and len < 2^64: the product is below 2^127.
    i128::try_from(tol.saturating_mul(len)).unwrap_or(i128::MAX)
}

/// The points strictly to the right of `a → b` (exact orientation test;
/// collinear points are not outside).
fn outside(points: impl Iterator<Item = Vect>, a: Vect, b: Vect) -> Vec<Vect> {
    points.filter(|p| orientation(b, a, *p) > 0).collect()
}

/// The point of `points` farthest right of `a → b`; ties (points on one line
/// parallel to the chord) go to the one nearest `a` along the chord, so the
/// choice never depends on the input order.
fn farthest(a: Vect, b: Vect, points: &[Vect]) -> Option<Vect> {
    let (dx, dy) = (raw_diff(b.x, a.x), raw_diff(b.y, a.y));
    // Differences take 65 bits: saturate the products and their sum (only
    // the order of nearly-equal far-away points can be affected).
    let along = |p: &Vect| {
        raw_diff(p.x, a.x)
            .saturating_mul(dx)
            .saturating_add(raw_diff(p.y, a.y).saturating_mul(dy))
    };
    points
        .iter()
        .max_by(|p, q| {
            orientation(b, a, **p)
                .cmp(&orientation(b, a, **q))
                .then_with(|| along(q).cmp(&along(p)))
        })
        .copied()
}

/// One unit of the QuickHull work list.
enum Task {
    /// Emit the hull vertices strictly between `a` and `b` (exclusive), found
    /// among `points` (all strictly right of `a → b`).
    Chain(Vect, Vect, Vec<Vect>),
    /// Emit one hull vertex.
    Vertex(Vect),
}

/// Appends to `hull`, in order, the hull vertices strictly between `a` and
/// `b` found among `points` (which all lie right of `a → b`).
fn reduce(a: Vect, b: Vect, points: Vec<Vect>, tolerance: Real, hull: &mut Vec<Vect>) {
    let mut stack = vec![Task::Chain(a, b, points)];
    while let Some(task) = stack.pop() {
        match task {
            Task::Vertex(v) => hull.push(v),
            Task::Chain(a, b, points) => {
                let Some(pivot) = farthest(a, b, &points) else {
                    continue;
                };
                // The tolerance is applied here only, to the farthest
                // point: if even it is within `tolerance` of `a → b`, the
                // chord is a hull edge and all its points are dropped, each
                // within `tolerance` of that edge. (Dropping points near an
                // intermediate chord, as Chipmunk does, can leave one farther
                // than `tolerance` outside the edges that later replace it.)
                if orientation(b, a, pivot) <= threshold(a, b, tolerance) {
                    continue;
                }
                // Each point goes to at most one side, so the work list never
                // holds more points than the input (even if saturated
                // orientations were inconsistent). The pivot itself has
                // orientation 0 against both new chords and is dropped.
                let mut left = Vec::new();
                let mut right = Vec::new();
                for p in points {
                    if orientation(pivot, a, p) > 0 {
                        left.push(p);
                    } else if orientation(b, pivot, p) > 0 {
                        right.push(p);
                    }
                }
                // Popped in reverse: left chain, pivot, right chain.
                stack.push(Task::Chain(pivot, b, right));
                stack.push(Task::Vertex(pivot));
                stack.push(Task::Chain(a, pivot, left));
            }
        }
    }
}

/// The leftmost (smallest x, then smallest y) and rightmost (largest x, then
/// largest y) points, or `None` for no points.
fn extremes(points: &[Vect]) -> Option<(Vect, Vect)> {
    let key = |p: &&Vect| (p.x, p.y);
    let first = points.iter().min_by_key(key)?;
    let last = points.iter().max_by_key(key)?;
    Some((*first, *last))
}

/// MIS/Chipmunk `convexHull`: the convex hull of `points`, counter-clockwise,
/// starting at the point with the smallest x (then smallest y).
///
/// Points within `tolerance` of a hull edge are dropped (each dropped
/// point lies within `tolerance` outside the edge it was dropped for), and so are collinear points and duplicates; a negative
/// `tolerance` counts as 0. With `tolerance = 0` every input point lies
/// exactly inside or on the result (see the module docs for the range).
///
/// Degenerate inputs give what is meaningful: no points → empty, all points
/// equal → that one point, all points on one line → its two end points.
/// The output vertices are always input points.
pub fn convex_hull(points: &[Vect], tolerance: Real) -> Vec<Vect> {
    let Some((start, end)) = extremes(points) else {
        return Vec::new();
    };
    if start == end {
        return vec![start];
    }
    let tolerance = tolerance.max(Real::ZERO);
    // Right of start → end is below the chord: the counter-clockwise way
    // from the leftmost point runs along the bottom first.
    let below = outside(points.iter().copied(), start, end);
    let above = outside(points.iter().copied(), end, start);
    let mut hull = vec![start];
    reduce(start, end, below, tolerance, &mut hull);
    hull.push(end);
    reduce(end, start, above, tolerance, &mut hull);
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real;

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    #[test]
    fn hull_square_with_interior_and_duplicates_is_the_corners_ccw() {
        let pts = [
            v(1, 1),
            v(0, 0),
            v(2, 0),
            v(2, 2),
            v(0, 2),
            v(1, 1),
            v(2, 2),
            v(0, 0),
            v(1, 0), // on an edge: collinear, dropped
            v(0, 1),
        ];
        assert_eq!(
            convex_hull(&pts, Real::ZERO),
            vec![v(0, 0), v(2, 0), v(2, 2), v(0, 2)]
        );
    }

    #[test]
    fn hull_degenerate_inputs_give_zero_one_or_two_points() {
        assert!(convex_hull(&[], Real::ZERO).is_empty());
        assert_eq!(convex_hull(&[v(3, 4)], Real::ZERO), vec![v(3, 4)]);
        assert_eq!(convex_hull(&[v(3, 4), v(3, 4)], Real::ZERO), vec![v(3, 4)]);
        let line = [v(2, 2), v(0, 0), v(1, 1), v(3, 3), v(-1, -1)];
        assert_eq!(convex_hull(&line, Real::ZERO), vec![v(-1, -1), v(3, 3)]);
        // Vertical line: start is the lowest point.
        let vertical = [v(0, 5), v(0, -2), v(0, 1)];
        assert_eq!(convex_hull(&vertical, Real::ZERO), vec![v(0, -2), v(0, 5)]);
    }

    #[test]
    fn hull_starts_at_smallest_x_then_smallest_y() {
        let pts = [v(0, 3), v(5, 0), v(0, -1), v(5, 4)];
        assert_eq!(
            convex_hull(&pts, Real::ZERO),
            vec![v(0, -1), v(5, 0), v(5, 4), v(0, 3)]
        );
    }

    #[test]
    fn a_point_dropped_for_tolerance_is_within_it_of_the_final_hull() {
        // Found by the hull proptest: Chipmunk's way dropped the second
        // point near the first chord (within 0.68 of it) but 0.945 outside
        // the edge that replaced that chord.
        let p = |x: &str, y: &str| Vect::new(Real::lit(x), Real::lit(y));
        let pts = [
            p("56.3462375812", "-55.5872626046"),
            p("56.346237581", "-56.537359312"),
            p("0", "0"),
            p("1", "-49.9293666685"),
        ];
        let tol = Real::from_bits(2_904_942_407);
        let h = convex_hull(&pts, tol);
        for (i, a) in h.iter().enumerate() {
            let b = h[(i + 1) % h.len()];
            let len = (b - *a).length();
            for q in &pts {
                // Right of a → b is outside (counter-clockwise hull).
                let out = (b - *a).cross(*q - *a) / len;
                assert!(
                    out >= -tol - Real::from_bits(4),
                    "{q:?} is {out} outside {a:?}→{b:?}"
                );
            }
        }
    }

    #[test]
    fn hull_tolerance_drops_nearly_collinear_points() {
        // (1, -0.01) is 0.01 outside the bottom edge.
        let pts = [
            v(0, 0),
            Vect::new(Real::ONE, real!(-0.01)),
            v(2, 0),
            v(1, 2),
        ];
        assert_eq!(convex_hull(&pts, Real::ZERO).len(), 4);
        assert_eq!(
            convex_hull(&pts, real!(0.02)),
            vec![v(0, 0), v(2, 0), v(1, 2)]
        );
        // Negative tolerance counts as zero.
        assert_eq!(convex_hull(&pts, -Real::ONE).len(), 4);
    }

    #[test]
    fn orientation_is_exact_below_one_ulp_of_cross() {
        // Area 2^-64: Vect::cross would round it to zero.
        let a = Vect::ZERO;
        let b = Vect::new(Real::DELTA, Real::ZERO);
        let c = Vect::new(Real::ZERO, Real::DELTA);
        assert_eq!(orientation(a, b, c), 1);
        assert_eq!(orientation(a, c, b), -1);
        assert_eq!((b - a).cross(c - a), Real::ZERO);
        // Extreme magnitudes do not overflow.
        let big = Vect::new(Real::MAX, Real::MAX);
        let low = Vect::new(Real::MIN, Real::MIN);
        assert_eq!(orientation(low, big, big), 0);
    }

    #[test]
    fn hull_extreme_coordinates_do_not_panic() {
        let (lo, hi) = (Real::MIN, Real::MAX);
        let pts = [
            Vect::new(lo, lo),
            Vect::new(hi, lo),
            Vect::new(hi, hi),
            Vect::new(lo, hi),
            Vect::new(lo, lo),
            Vect::ZERO,
            Vect::new(hi, Real::ZERO),
        ];
        for tol in [Real::ZERO, Real::ONE, Real::MAX] {
            let h = convex_hull(&pts, tol);
            assert!(!h.is_empty() && h.len() <= pts.len());
            assert!(h.iter().all(|p| pts.contains(p)));
        }
    }

    #[test]
    fn hull_independent_of_input_order() {
        let pts = [
            v(0, 0),
            v(4, 0),
            v(4, 4),
            v(0, 4),
            v(2, 5),
            v(2, -1),
            v(1, 1),
        ];
        let mut rev = pts;
        rev.reverse();
        assert_eq!(convex_hull(&pts, Real::ZERO), convex_hull(&rev, Real::ZERO));
    }
}
