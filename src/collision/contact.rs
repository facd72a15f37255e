//! Closest points on an edge of the Minkowski difference, and contact points
//! from two support edges (MIS `closestT`, `lerpT`, `closestPointsNew`,
//! `ClosestPoints`, `contactPoints`).
//!
//! An edge of `B − A` is parameterised as `p(t) = (v0(1 − t) + v1(1 + t)) / 2`
//! with `t ∈ [−1, 1]` (the MIS form: the midpoint is `t = 0`, the ends are
//! exactly `v0` and `v1`). The same `t` applied to the A and B support points
//! gives the closest points on each shape.
//!
//! Contact points come from clipping: the support edge of A along the normal
//! and the support edge of B against it are projected on the tangent axis, and
//! each end of their common interval gives one contact pair (so at most two).
//! This is Chipmunk's manifold construction, which keeps the feature ids of
//! the edge endpoints so contacts can be matched from step to step.
//!
//! Cost: `closest_points_new` does one 128-bit division (`closest_t`) and one
//! multiply-only normalisation; `contact_points` at most eight `mul_div`s
//! (only for clip points inside an edge). GJK and EPA call them once per pair.
use super::info::{CollisionInfo, WarmStartId, CONTACT_TOLERANCE};
use super::support::{Edge, MinkowskiPoint};
use crate::math::exact;
use crate::math::{FixedArith, Real, Saturating, Unsaturated, Vect};

/// Closest points between two shape cores (MIS `ClosestPoints`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClosestPoints {
    /// Point on A's core.
    pub a: Vect,
    /// Point on B's core.
    pub b: Vect,
    /// Unit normal from A toward B: the direction to move B to separate the
    /// shapes (or to bring them closer, when `d > 0`).
    pub n: Vect,
    /// Signed core distance along `n`: positive when the cores are apart,
    /// negative (minus the penetration depth) when they overlap.
    pub d: Real,
    /// Warm-start id: the vertex indices of the edge's two Minkowski points,
    /// `(v0.id & 0xFFFF) << 16 | (v1.id & 0xFFFF)`.
    pub warm_start_id: WarmStartId,
    /// True if GJK or EPA stopped at its iteration cap (the answer is the best
    /// found so far).
    pub hit_iteration_cap: bool,
}

/// MIS `closestT`: the `t ∈ [−1, 1]` of the point of segment `a b` closest to
/// the origin. With `δ = b − a`, `|p(t)|²` is least at
/// `t = −δ·(a + b) / |δ|²`; clamped to the segment. A zero-length segment
/// gives 0. One rounding (exact 128-bit numerator and denominator).
#[inline]
pub fn closest_t(a: Vect, b: Vect) -> Real {
    let delta = b - a;
    let num = exact::dot(delta, a + b);
    exact::unit_ratio(num.saturating_neg(), exact::len_sq(delta))
}

/// MIS `lerpT`: `p(t) = a(1 − t)/2 + b(1 + t)/2` with `t` clamped to
/// `[−1, 1]`. Each component is rounded once; the weights sum to exactly 1,
/// so `t = ±1` gives exactly `a` or `b`, and `a == b` gives exactly `a`.
#[inline]
pub fn lerp_t(a: Vect, b: Vect, t: Real) -> Vect {
    let t = t.clamp(-Real::ONE, Real::ONE);
    let ht = t * Real::HALF;
    let (wa, wb) = (Real::HALF - ht, Real::HALF + ht);
    Vect::new(
        Real::mul_add2(a.x, wa, b.x, wb),
        Real::mul_add2(a.y, wa, b.y, wb),
    )
}

/// Where the origin projects on the edge `v0 → v1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Nearest {
    /// At or before `v0` (also for a zero-length edge).
    V0,
    /// At or past `v1`.
    V1,
    /// Strictly between the two.
    Interior,
}

/// The feature of the edge `v0 → v1` nearest the origin, from the exact signs
/// of `v0 · (v1 − v0)` and `v1 · (v1 − v0)` (no rounding, so GJK's search
/// direction and `closest_points_new`'s choice of normal agree).
#[inline]
pub(crate) fn nearest_feature(v0: Vect, v1: Vect) -> Nearest {
    let delta = v1 - v0;
    if exact::dot(v0, delta) >= 0 {
        Nearest::V0
    } else if exact::dot(v1, delta) <= 0 {
        Nearest::V1
    } else {
        Nearest::Interior
    }
}

/// Packs two Minkowski ids into a warm-start id.
#[inline]
pub(crate) fn pack_id(v0: &MinkowskiPoint, v1: &MinkowskiPoint) -> WarmStartId {
    ((v0.id & 0xFFFF) << 16) | (v1.id & 0xFFFF)
}

/// MIS `closestPointsNew`: closest points for the edge `v0 → v1` of the
/// Minkowski difference, which GJK orients with the origin on its left (EPA
/// passes its closest hull edge reversed, so the same holds).
///
/// The normal is the edge normal `rperp(v1 − v0)` when the closest point is
/// inside the edge, the origin is strictly behind the edge line (overlap) or
/// the origin is the closest point itself (touching); the distance is then
/// `n · p`. Otherwise the closest point is a vertex of a separated pair: the
/// normal is `p / |p|` and the distance `|p|` (the separating axis of two
/// corners is not an edge normal). If `v1 − v0` is zero the normal is
/// `p / |p|`, and `(1, 0)` if `p` is zero too (callers with more context may
/// replace it).
///
/// The vertex case includes the origin *on the edge line but past its end*
/// (`rperp(v1 − v0) · p = 0` with `t = ±1`): the shapes are then `|p|` apart,
/// not touching. Treating that exact-zero tie as overlap reported a contact
/// at distance 0 between shapes far apart, and only when GJK happened to end
/// on such a collinear edge, which depends on where it started (the
/// warm-start id): the two known `collide_pair` fuzz findings.
pub fn closest_points_new(v0: &MinkowskiPoint, v1: &MinkowskiPoint) -> ClosestPoints {
    let t = closest_t(v0.ab, v1.ab);
    let p = lerp_t(v0.ab, v1.ab, t);
    let a = lerp_t(v0.a, v1.a, t);
    let b = lerp_t(v0.b, v1.b, t);
    let id = pack_id(v0, v1);
    let edge_normal = (v1.ab - v0.ab).rperp();
    // Exact region test. Outside the interior the exact `t` is beyond ±1, so
    // the rounded one is exactly ±1 and `p` exactly `v0` or `v1`: the side
    // test below is then the exact sign of `rperp(v1 − v0) · v0`.
    let interior = nearest_feature(v0.ab, v1.ab) == Nearest::Interior;
    let behind = exact::dot(edge_normal, p) < 0;
    let use_edge = edge_normal != Vect::ZERO && (interior || behind || p == Vect::ZERO);
    let (n, d) = if use_edge {
        let n = exact::unit_or(edge_normal, Vect::X);
        (n, n.dot(p))
    } else {
        exact::normalize(p).unwrap_or((Vect::X, Real::ZERO))
    };
    ClosestPoints {
        a,
        b,
        n,
        d,
        warm_start_id: id,
        hit_iteration_cap: false,
    }
}

/// Feature id of a contact between feature `fa` of A and `fb` of B.
#[inline]
pub(crate) fn contact_id(fa: u32, fb: u32) -> u32 {
    ((fa & 0xFFFF) << 16) | (fb & 0xFFFF)
}

/// The point of edge `a → b` whose tangent coordinate is `s`, clamped to the
/// edge (`sa`, `sb` are the coordinates of `a` and `b`). Each component is
/// `a + (b − a)·(s − sa)/(sb − sa)` rounded once (`mul_div`), and the clamped
/// ends are exactly `a` or `b`. An edge parallel to the normal (zero extent
/// along the tangent) gives its endpoint furthest along `toward`, the side
/// facing the other shape. In the arithmetic `ar` (the saturating `Real`
/// operators, or the fast path that gives their bits unless it overflowed).
#[inline(always)]
fn point_on_edge<A: FixedArith>(
    a: Vect,
    b: Vect,
    (sa, sb): (Real, Real),
    s: Real,
    toward: Vect,
    ar: &mut A,
) -> Vect {
    let (num, den) = (ar.sub(s, sa), ar.sub(sb, sa));
    let d = Vect::new(ar.sub(b.x, a.x), ar.sub(b.y, a.y));
    if den.is_zero() {
        if exact::dot(d, toward) > 0 {
            b
        } else {
            a
        }
    } else if num.is_zero() || num.is_negative() != den.is_negative() {
        a
    } else if num.abs() >= den.abs() {
        b
    } else {
        // `mul_div` and `abs` are the same functions in both arithmetics.
        let (x, y) = (d.x.mul_div(num, den), d.y.mul_div(num, den));
        Vect::new(ar.add(a.x, x), ar.add(a.y, y))
    }
}

/// MIS `contactPoints`: if the shapes touch (`points.d ≤ r₁ + r₂`), pushes up
/// to two contacts (and sets the normal if it pushed any) found by clipping the support edge
/// `e1` of A (facing `n`) against the support edge `e2` of B (facing `−n`).
///
/// Derivation. Let `s(p) = p × n`, the coordinate of `p` along `rperp(n)`.
/// Both edges run counter-clockwise around their shape, so `e1` runs in
/// decreasing `s` and `e2` in increasing `s`; their overlap is
/// `[max(s(e1.b), s(e2.a)), min(s(e1.a), s(e2.b))]`. At the upper end the pair
/// is (e1 at `s(e2.b)`, e2 at `s(e1.a)`), at the lower end (e1 at `s(e2.a)`,
/// e2 at `s(e1.b)`), each clamped onto its edge, so disjoint projections still
/// give the nearest endpoints (an edge parallel to `n` contributes its end
/// nearest the other shape). Each point is moved out by its radius along
/// `±n`; a pair is a contact if its separation `(p2 − p1)·n ≤ 0`. A second pair
/// identical to the first (corner against corner) is dropped.
///
/// The clipping runs in [`Unsaturated`] arithmetic first, and again in the
/// saturating operators only if that overflowed: the bits of the
/// saturating formulas either way, without a saturation test per
/// operation.
pub fn contact_points(e1: &Edge, e2: &Edge, points: &ClosestPoints, info: &mut CollisionInfo) {
    let min_dist = e1.radius + e2.radius;
    if points.d > min_dist + CONTACT_TOLERANCE {
        return;
    }
    let mut fast = Unsaturated::new();
    let pairs = clip(e1, e2, points.n, &mut fast);
    let pairs = if fast.overflowed() {
        clip_saturating(e1, e2, points.n)
    } else {
        pairs
    };
    for (p1, p2, dist, id) in pairs.iter().flatten() {
        info.push_contact(*p1, *p2, *dist, *id);
    }
    if info.count > 0 {
        info.normal = points.n;
    }
}

/// The contact pairs of two support edges along `n`, at the upper and the
/// lower end of their overlap: points on A and on B, separation and
/// feature id (`None`: apart, or the same pair as the first).
type Clipped = [Option<(Vect, Vect, Real, u32)>; 2];

/// [`clip`] in the saturating operators, out of line: inlined, the
/// compiler kept the fast path's products alive for it.
#[cold]
#[inline(never)]
fn clip_saturating(e1: &Edge, e2: &Edge, n: Vect) -> Clipped {
    clip(e1, e2, n, &mut Saturating)
}

/// The clipping of [`contact_points`], in the arithmetic `ar`.
#[inline(always)]
fn clip<A: FixedArith>(e1: &Edge, e2: &Edge, n: Vect, ar: &mut A) -> Clipped {
    let cross = |p: Vect, ar: &mut A| ar.mul_sub2(p.x, n.y, p.y, n.x);
    let (s1a, s1b) = (cross(e1.a.p, ar), cross(e1.b.p, ar));
    let (s2a, s2b) = (cross(e2.a.p, ar), cross(e2.b.p, ar));
    // A zero radius (a polygon's) moves nothing: `n·0` is exactly 0.
    let out = |r: Real, ar: &mut A| {
        if r.is_zero() {
            Vect::ZERO
        } else {
            Vect::new(ar.mul(n.x, r), ar.mul(n.y, r))
        }
    };
    let (out1, out2) = (out(e1.radius, ar), out(e2.radius, ar));
    let ends = [
        (s2b, s1a, contact_id(e1.a.index, e2.b.index)),
        (s2a, s1b, contact_id(e1.b.index, e2.a.index)),
    ];
    let mut pairs: Clipped = [None; 2];
    let mut first: Option<(Vect, Vect)> = None;
    for (&(s_on_1, s_on_2, id), slot) in ends.iter().zip(&mut pairs) {
        let q1 = point_on_edge(e1.a.p, e1.b.p, (s1a, s1b), s_on_1, n, ar);
        let q2 = point_on_edge(e2.a.p, e2.b.p, (s2a, s2b), s_on_2, -n, ar);
        let p1 = Vect::new(ar.add(q1.x, out1.x), ar.add(q1.y, out1.y));
        let p2 = Vect::new(ar.sub(q2.x, out2.x), ar.sub(q2.y, out2.y));
        let gap = Vect::new(ar.sub(p2.x, p1.x), ar.sub(p2.y, p1.y));
        let dist = ar.mul_add2(gap.x, n.x, gap.y, n.y);
        if dist <= CONTACT_TOLERANCE && first != Some((p1, p2)) {
            *slot = Some((p1, p2, dist, id));
            first = Some((p1, p2));
        }
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{EdgePoint, SupportPoint};
    use crate::real;

    fn mp(a: Vect, b: Vect, ia: u32, ib: u32) -> MinkowskiPoint {
        MinkowskiPoint::new(
            SupportPoint { p: a, index: ia },
            SupportPoint { p: b, index: ib },
        )
    }

    #[test]
    fn closest_t_and_lerp_t_hit_ends_exactly() {
        let a = Vect::from_ints(-3, 2);
        let b = Vect::from_ints(5, 2);
        let t = closest_t(a, b);
        // Closest point (0, 2): t = (0 − (−3))/8·2 − 1 = −0.25.
        assert_eq!(t, real!(-0.25));
        assert_eq!(lerp_t(a, b, t), Vect::from_ints(0, 2));
        assert_eq!(lerp_t(a, b, -Real::ONE), a);
        assert_eq!(lerp_t(a, b, Real::ONE), b);
        assert_eq!(lerp_t(a, a, real!(0.3)), a);
        assert_eq!(
            closest_t(Vect::from_ints(1, 0), Vect::from_ints(2, 0)),
            -Real::ONE
        );
        assert_eq!(closest_t(a, a), Real::ZERO);
    }

    #[test]
    fn closest_points_new_edge_and_vertex_cases() {
        // Edge of B − A at y = 2 from x = 3 to x = −3 (origin on the left).
        let v0 = mp(Vect::ZERO, Vect::from_ints(3, 2), 0, 0);
        let v1 = mp(Vect::ZERO, Vect::from_ints(-3, 2), 0, 1);
        let c = closest_points_new(&v0, &v1);
        assert_eq!((c.n, c.d), (Vect::Y, Real::TWO));
        assert_eq!(c.b, Vect::from_ints(0, 2));
        assert_eq!(c.warm_start_id, 1);
        // Vertex case: closest point (3, 4), normal along it.
        let v0 = mp(Vect::ZERO, Vect::from_ints(3, 4), 0, 0);
        let v1 = mp(Vect::ZERO, Vect::from_ints(3, 9), 0, 1);
        let c = closest_points_new(&v0, &v1);
        assert_eq!(c.d, Real::from_int(5));
        assert_eq!(c.b, Vect::from_ints(3, 4));
    }

    #[test]
    fn closest_points_new_origin_on_edge_line_past_its_end() {
        // Edge (1, 0) → (3, 0) of B − A: the origin is on its line, 1 before
        // v0. The closest point is the vertex: distance 1, normal along it,
        // whichever way the edge runs (not "touching" with the edge normal).
        let v0 = mp(Vect::ZERO, Vect::from_ints(1, 0), 0, 0);
        let v1 = mp(Vect::ZERO, Vect::from_ints(3, 0), 0, 1);
        for (x, y) in [(&v0, &v1), (&v1, &v0)] {
            let c = closest_points_new(x, y);
            assert_eq!((c.n, c.d), (Vect::X, Real::ONE));
            assert_eq!(c.b, Vect::from_ints(1, 0));
        }
        // The origin at the vertex itself: touching, along the edge normal.
        let v0 = mp(Vect::ZERO, Vect::ZERO, 0, 0);
        let c = closest_points_new(&v0, &v1);
        assert_eq!((c.n, c.d), (-Vect::Y, Real::ZERO));
        // Edge (3, −1) → (1, −1), normal +y: the origin is strictly behind
        // its line (overlap, as EPA sees it), so the edge normal is kept even
        // at a vertex; seen the other way round the edge is a separated one.
        let v0 = mp(Vect::ZERO, Vect::from_ints(3, -1), 0, 0);
        let v1 = mp(Vect::ZERO, Vect::from_ints(1, -1), 0, 1);
        let c = closest_points_new(&v0, &v1);
        assert_eq!((c.n, c.d), (Vect::Y, -Real::ONE));
        let c = closest_points_new(&v1, &v0);
        assert!(c.d > Real::ONE && c.n.x.is_positive() && c.n.y.is_negative());
    }

    /// A raw coordinate: anything, the extremes, or a scene-like value.
    fn raw() -> impl proptest::strategy::Strategy<Value = i64> {
        use proptest::prelude::*;
        prop_oneof![
            any::<i64>(),
            Just(i64::MIN),
            Just(i64::MAX),
            -(1i64 << 40)..(1i64 << 40),
            -(1i64 << 33)..(1i64 << 33),
        ]
    }

    /// The clipping in `Real`'s operators, as it was written before the
    /// fast path: the reference both arithmetics are checked against.
    fn clip_reference(e1: &Edge, e2: &Edge, n: Vect) -> Clipped {
        fn on_edge(a: Vect, b: Vect, (sa, sb): (Real, Real), s: Real, toward: Vect) -> Vect {
            let (num, den) = (s - sa, sb - sa);
            if den.is_zero() {
                if exact::dot(b - a, toward) > 0 {
                    b
                } else {
                    a
                }
            } else if num.is_zero() || num.is_negative() != den.is_negative() {
                a
            } else if num.abs() >= den.abs() {
                b
            } else {
                let d = b - a;
                a + Vect::new(d.x.mul_div(num, den), d.y.mul_div(num, den))
            }
        }
        let (s1a, s1b) = (e1.a.p.cross(n), e1.b.p.cross(n));
        let (s2a, s2b) = (e2.a.p.cross(n), e2.b.p.cross(n));
        let (out1, out2) = (n.mult(e1.radius), n.mult(e2.radius));
        let ends = [
            (s2b, s1a, contact_id(e1.a.index, e2.b.index)),
            (s2a, s1b, contact_id(e1.b.index, e2.a.index)),
        ];
        let mut pairs: Clipped = [None; 2];
        let mut first = None;
        for ((s_on_1, s_on_2, id), slot) in ends.into_iter().zip(&mut pairs) {
            let p1 = on_edge(e1.a.p, e1.b.p, (s1a, s1b), s_on_1, n) + out1;
            let p2 = on_edge(e2.a.p, e2.b.p, (s2a, s2b), s_on_2, -n) - out2;
            let dist = (p2 - p1).dot(n);
            if dist <= CONTACT_TOLERANCE && first != Some((p1, p2)) {
                *slot = Some((p1, p2, dist, id));
                first = Some((p1, p2));
            }
        }
        pairs
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]
        /// The fast clipping gives the saturating operators' contacts on
        /// any input: in scene ranges, near the extremes and past them
        /// (where the fast path overflows and the saturating one runs).
        #[test]
        fn clipping_is_the_saturating_formulas(v in proptest::collection::vec(raw(), 12)) {
            let x = |k: usize| Real::from_bits(v.get(k).copied().unwrap_or(0));
            let edge = |k: usize, radius: Real| Edge {
                a: EdgePoint { p: Vect::new(x(k), x(k + 1)), index: 1 },
                b: EdgePoint { p: Vect::new(x(k + 2), x(k + 3)), index: 2 },
                radius,
                normal: Vect::ZERO,
            };
            let n = Vect::new(x(8), x(9));
            // With rounded shapes' radii, and with polygons' zero ones.
            for (r1, r2) in [(x(10).abs(), x(11).abs()), (Real::ZERO, Real::ZERO)] {
                let (e1, e2) = (edge(0, r1), edge(4, r2));
                let want = clip_reference(&e1, &e2, n);
                proptest::prop_assert_eq!(clip_saturating(&e1, &e2, n), want);
                let mut fast = Unsaturated::new();
                let got = clip(&e1, &e2, n, &mut fast);
                if !fast.overflowed() {
                    proptest::prop_assert_eq!(got, want);
                }
            }
        }
    }

    #[test]
    fn contact_points_clip_two_overlapping_edges() {
        // A's top edge (y = 0, from x = 2 to x = −2), B's bottom edge
        // (y = −0.5, from x = −1 to x = 1): B sinks 0.5 into A.
        let e1 = Edge {
            a: EdgePoint {
                p: Vect::from_ints(2, 0),
                index: 1,
            },
            b: EdgePoint {
                p: Vect::from_ints(-2, 0),
                index: 2,
            },
            radius: Real::ZERO,
            normal: Vect::Y,
        };
        let e2 = Edge {
            a: EdgePoint {
                p: Vect::new(-Real::ONE, -Real::HALF),
                index: 3,
            },
            b: EdgePoint {
                p: Vect::new(Real::ONE, -Real::HALF),
                index: 0,
            },
            radius: Real::ZERO,
            normal: -Vect::Y,
        };
        let pts = ClosestPoints {
            n: Vect::Y,
            d: -Real::HALF,
            ..ClosestPoints::default()
        };
        let mut info = CollisionInfo::new(0);
        contact_points(&e1, &e2, &pts, &mut info);
        assert_eq!(info.count, 2);
        let c = info.contacts();
        assert_eq!(c[0].point_a, Vect::from_ints(1, 0));
        assert_eq!(c[0].point_b, Vect::new(Real::ONE, -Real::HALF));
        assert_eq!(c[0].distance, -Real::HALF);
        assert_eq!(c[0].feature_id, 1 << 16);
        assert_eq!(c[1].point_a, Vect::from_ints(-1, 0));
        assert_eq!(c[1].feature_id, (2 << 16) | 3);
    }
}
