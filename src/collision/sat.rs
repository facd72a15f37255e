//! Polygon–polygon contacts by separating axes (the approach of Box2D's
//! `b2CollidePolygons`), the fast path of [`poly_to_poly`](super::poly_to_poly).
//!
//! In 2D the faces of the Minkowski difference of two convex polygons are
//! exactly their edges, so the axis GJK + EPA would find is one of the two
//! polygons' edge normals, which the geometry already stores. For each edge
//! `i` of `A` (vertex `pᵢ`, outward unit normal `nᵢ`) the separation along
//! `nᵢ` is `minⱼ (qⱼ − pᵢ)·nᵢ` over the vertices `qⱼ` of `B`; the axis of
//! *maximum* separation over both polygons is the axis of minimum
//! penetration when the cores overlap (EPA's answer) and a lower bound of the
//! core distance when they do not. Each separation is a dot-product minimum
//! on exact 128-bit products (`exact::dot`): no division, no square root, no
//! rounding in any decision.
//!
//! Which answer, and why it equals the old path's:
//! * **Cores overlap or touch** (`sep ≤ 0`): the normal is the reference
//!   face's stored normal (`nᵢ` on `A`, or `−nⱼ` for a face of `B`), pointing
//!   from `A` to `B`. Contacts come from the same clipping as before
//!   ([`contact_points`] on the support edges of both polygons along that
//!   normal), so points, distances and feature ids are exactly what the GJK +
//!   EPA path gives for the same normal; EPA's normal is the same face's
//!   normal, computed from the same edge by a different (equally exact)
//!   normalisation, so it agrees to an ulp or two.
//! * **Cores apart but within the radius sum + [`CONTACT_TOLERANCE`]**
//!   (rounded polygons, or sharp ones a hair apart): the best face gives the
//!   core distance only if a vertex of the other polygon at that separation
//!   projects onto the face (a vertex–face pair). That is checked exactly
//!   (on an exact tie of the two polygons' best separations, both faces are
//!   tried, A's first: a short box above a long one is realised by the long
//!   one's face only); if it fails the closest features are two vertices
//!   (or a vertex and an edge of the other polygon at a different
//!   separation), whose normal is not a face normal, and we return `false`
//!   so the caller falls back to GJK.
//! * **Further apart:** no contact, decided exactly, no GJK.
//! * **Check:** the deepest clipped contact must be as deep as the axis says
//!   (within 64 ulp + 2^-20 relative), and a touching axis must give a
//!   contact. Slivers can break this (nearly collinear edges whose rounded
//!   normals make the support edge a neighbour of the reference face, or a
//!   deepest vertex clipped off by a short face); such a pair gets the GJK
//!   path's answer.
//!
//! Tie-breaking is fixed: among equal separations the lower edge index wins,
//! and `A`'s face wins over `B`'s unless `B`'s separation is strictly larger
//! (exact comparison; no tolerance is needed because nothing here rounds).
//! Which polygon is `A` is fixed by the canonical order of `poly_to_poly`, so
//! the path stays swap-exact. The warm-start id is neither read nor changed:
//! the answer does not depend on it (it is still passed on to the GJK
//! fallback).
//!
//! Degenerate polygons (fewer than 3 vertices, or a zero stored normal, which
//! only unchecked construction can produce) take the GJK path.
use super::contact::{contact_points, ClosestPoints};
use super::info::{CollisionInfo, CONTACT_TOLERANCE};
use super::support::{support_edge_for_poly, support_edge_for_poly_unit};
use crate::math::exact;
use crate::math::{Real, Vect};
use crate::shape::Poly;
use core::cmp::Ordering;

/// The best axis of one polygon against the other.
#[derive(Clone, Copy, Debug)]
struct Axis {
    /// Separation in units of 2^-64 (exact).
    sep: i128,
    /// Edge index on the polygon owning the axis.
    edge: usize,
}

impl Axis {
    /// Takes face `edge` at separation `sep` if it is strictly further out
    /// (the lower index wins a tie); true if the pair is then known apart
    /// (`sep > limit`) and the search can stop.
    #[inline(always)]
    fn take(&mut self, sep: i128, edge: usize, limit: i128) -> bool {
        if sep > self.sep {
            *self = Axis { sep, edge };
            return sep > limit;
        }
        false
    }
}

/// `r`'s raw bits in units of 2^-64 (the units of `exact::dot`).
#[inline]
fn wide_of(r: Real) -> i128 {
    i128::from(r.to_bits()) << 32
}

/// A 2^-64-unit value as a `Real`, rounded toward −∞ and saturated.
#[inline]
fn real_of(x: i128) -> Real {
    let raw = x >> 32;
    Real::from_bits(i64::try_from(raw).unwrap_or(if raw < 0 { i64::MIN } else { i64::MAX }))
}

/// Minimum over the vertices of `b` of `v · n`, exact.
#[inline]
fn min_dot(b: &Poly, n: Vect) -> i128 {
    b.verts()
        .iter()
        .fold(i128::MAX, |m, v| m.min(exact::dot(*v, n)))
}

/// The edge normal of `a` along which `b` is furthest out (lowest index on
/// a tie), stopping early once a separation exceeds `limit` (the pair is then
/// apart). `None` if `a` has a zero normal.
///
/// A polygon of 4, 6 or 8 faces in opposite pairs (a box, a regular hexagon
/// or octagon: normal `i + count/2` exactly `−nᵢ`) gets both separations of
/// a pair from one pass over `b`'s vertices, since `min (q · −n) =
/// −max (q · n)` exactly; the answer is the same as
/// [`max_separation_by_faces`]'s (checked by the tests).
#[inline]
fn max_separation(a: &Poly, b: &Poly, limit: i128) -> Option<Axis> {
    let paired = match a.count() {
        4 => Ok(max_separation_box(a, b, limit)),
        6 => max_separation_paired::<6>(a, b, limit),
        8 => max_separation_paired::<8>(a, b, limit),
        _ => Err(()),
    };
    paired.unwrap_or_else(|()| max_separation_by_faces(a, b, limit))
}

/// [`max_separation`] for a box (four faces: normals 2 and 3 exactly
/// `−n₀` and `−n₁`), written out: two passes, the second only if the first
/// face does not already show the pair apart.
#[inline]
fn max_separation_box(a: &Poly, b: &Poly, limit: i128) -> Option<Axis> {
    let (Ok(&[n0, n1, n2, n3]), Ok(&[p0, p1, p2, p3])) = (
        <&[Vect; 4]>::try_from(a.normals()),
        <&[Vect; 4]>::try_from(a.verts()),
    ) else {
        return max_separation_by_faces(a, b, limit);
    };
    // Within the unit square each product of a dot product stays below
    // 2^95: nothing saturates, and negating a dot product is exact.
    let within = |r: Real| (-Real::ONE..=Real::ONE).contains(&r);
    let unit = |n: Vect| within(n.x) && within(n.y);
    if n2 != -n0
        || n3 != -n1
        || !unit(n0)
        || !unit(n1)
        || n0 == Vect::ZERO
        || n1 == Vect::ZERO
        || b.verts().is_empty()
    {
        return max_separation_by_faces(a, b, limit);
    }
    // Unit normals: every dot product is below `2^96` in magnitude, so
    // the differences and negations below are exact without saturation
    // tests (the saturating operators' values).
    let range = |n: Vect| {
        b.verts()
            .iter()
            .fold((i128::MAX, i128::MIN), |(lo, hi), v| {
                let d = exact::dot_unit(*v, n);
                (lo.min(d), hi.max(d))
            })
    };
    let mut best = Axis {
        sep: i128::MIN,
        edge: 0,
    };
    // Face by face in index order, as `max_separation_by_faces`: the second
    // pass only if the first face does not already show the pair apart.
    let (min0, max0) = range(n0);
    if best.take(min0.wrapping_sub(exact::dot_unit(p0, n0)), 0, limit) {
        return Some(best);
    }
    let (min1, max1) = range(n1);
    let rest = [
        (min1, n1, p1),
        (max0.wrapping_neg(), n2, p2),
        (max1.wrapping_neg(), n3, p3),
    ];
    for (edge, (min, n, p)) in (1..).zip(rest) {
        if best.take(min.wrapping_sub(exact::dot_unit(p, n)), edge, limit) {
            break;
        }
    }
    Some(best)
}

/// [`max_separation`] for a polygon of `N` faces in opposite pairs; `Err`
/// if `a`'s faces are not (then the caller goes face by face).
#[inline(always)]
fn max_separation_paired<const N: usize>(
    a: &Poly,
    b: &Poly,
    limit: i128,
) -> Result<Option<Axis>, ()> {
    let (Ok(normals), Ok(verts)) = (
        <&[Vect; N]>::try_from(a.normals()),
        <&[Vect; N]>::try_from(a.verts()),
    ) else {
        return Err(());
    };
    let half = N / 2;
    // Within the unit square each product of a dot product stays below
    // 2^95: nothing saturates, and negating a dot product is exact.
    let within = |r: Real| (-Real::ONE..=Real::ONE).contains(&r);
    let paired = (0..half).all(
        |i| match (normals.get(i), normals.get(i.wrapping_add(half))) {
            (Some(n), Some(m)) => *m == -*n && within(n.x) && within(n.y),
            _ => false,
        },
    );
    if !paired || b.verts().is_empty() {
        return Err(());
    }
    let mut best = Axis {
        sep: i128::MIN,
        edge: 0,
    };
    // The minima of the pairs' second faces, known once the first face's
    // pass has run. Unit normals: the dot products, their differences
    // and negations are exact without saturation tests (as in
    // `max_separation_box`).
    let mut opposite = [i128::MAX; N];
    for (i, (n, p)) in normals.iter().zip(verts).enumerate() {
        if *n == Vect::ZERO {
            return Ok(None);
        }
        let min = if i < half {
            let (min, max) = b
                .verts()
                .iter()
                .fold((i128::MAX, i128::MIN), |(lo, hi), v| {
                    let d = exact::dot_unit(*v, *n);
                    (lo.min(d), hi.max(d))
                });
            if let Some(o) = opposite.get_mut(i) {
                *o = max.wrapping_neg();
            }
            min
        } else {
            opposite
                .get(i.wrapping_sub(half))
                .copied()
                .unwrap_or(i128::MAX)
        };
        if best.take(min.wrapping_sub(exact::dot_unit(*p, *n)), i, limit) {
            break;
        }
    }
    Ok(Some(best))
}

/// [`max_separation`] face by face: one pass over `b`'s vertices per face.
#[inline]
fn max_separation_by_faces(a: &Poly, b: &Poly, limit: i128) -> Option<Axis> {
    let mut best = Axis {
        sep: i128::MIN,
        edge: 0,
    };
    for (i, (n, p)) in a.normals().iter().zip(a.verts()).enumerate() {
        if *n == Vect::ZERO {
            return None;
        }
        if best.take(min_dot(b, *n).saturating_sub(exact::dot(*p, *n)), i, limit) {
            break;
        }
    }
    Some(best)
}

/// True if a vertex of `inc` at exactly separation `sep` from the face
/// `p0 → p1` (normal `n`) projects onto that face (ends included): the face
/// then realises the core distance.
#[inline]
fn face_realises_distance(inc: &Poly, (p0, p1): (Vect, Vect), n: Vect, sep: i128) -> bool {
    let base = exact::dot(p0, n);
    let edge = p1 - p0;
    let len_sq = exact::dot(edge, edge);
    // The projection only for a vertex at the separation (one or two).
    inc.verts().iter().any(|v| {
        exact::dot(*v, n).saturating_sub(base) == sep && {
            let along = exact::dot(*v - p0, edge);
            along >= 0 && along <= len_sq
        }
    })
}

/// Contacts of two polygons in canonical order by separating axes, with
/// the contact points in the frame whose origin is `anchor` (the pair as
/// if every vertex were moved by `−anchor`). Returns `false` (leaving
/// `info` untouched) when the caller must use GJK instead: degenerate
/// polygons, or cores apart within contact range whose closest features
/// are not a vertex and a face (see the module docs).
///
/// Only the two support edges are moved. Everything before them is a
/// difference of exact dot products, which moving both polygons by the
/// same vector leaves unchanged, so the answer is the moved pair's as
/// long as no moved coordinate saturates. The caller guarantees that
/// (`collide_polys` checks it; `poly_to_poly` passes a zero anchor), and
/// the two edges are moved without saturation tests. That spares the
/// narrowphase a copy of both polygons per pair.
pub(crate) fn poly_to_poly_sat(a: &Poly, b: &Poly, anchor: Vect, info: &mut CollisionInfo) -> bool {
    sat_into::<false>(a, b, anchor, info)
}

/// [`poly_to_poly_sat`] into a fresh `info` (`CollisionInfo::new` of its
/// warm-start id, as `collide_polys` passes): nothing to save and put
/// back but the id, where the general form copies the whole answer.
pub(crate) fn poly_to_poly_sat_fresh(
    a: &Poly,
    b: &Poly,
    anchor: Vect,
    info: &mut CollisionInfo,
) -> bool {
    sat_into::<true>(a, b, anchor, info)
}

/// [`poly_to_poly_sat`]; `FRESH`: `info` is `CollisionInfo::new` of its id.
#[inline(always)]
fn sat_into<const FRESH: bool>(a: &Poly, b: &Poly, anchor: Vect, info: &mut CollisionInfo) -> bool {
    if a.count() < 3 || b.count() < 3 {
        return false;
    }
    let min_dist = a.radius() + b.radius();
    let limit = wide_of(min_dist + CONTACT_TOLERANCE);
    let Some(on_a) = max_separation(a, b, limit) else {
        return false;
    };
    if on_a.sep > limit {
        return true;
    }
    let Some(on_b) = max_separation(b, a, limit) else {
        return false;
    };
    if on_b.sep > limit {
        return true;
    }
    // Reference face: A's unless B's separation is strictly larger. Cores
    // apart: the face must realise the distance (module docs); when the two
    // separations tie exactly, either face may be the one that does.
    let face_a = || {
        let n = a.normal(on_a.edge);
        let face = (a.vert(on_a.edge), a.vert(next(on_a.edge, a.count())));
        (on_a.sep <= 0 || face_realises_distance(b, face, n, on_a.sep)).then_some((on_a.sep, n))
    };
    let face_b = || {
        let n = b.normal(on_b.edge);
        let face = (b.vert(on_b.edge), b.vert(next(on_b.edge, b.count())));
        (on_b.sep <= 0 || face_realises_distance(a, face, n, on_b.sep)).then_some((on_b.sep, -n))
    };
    let chosen = match on_b.sep.cmp(&on_a.sep) {
        Ordering::Greater => face_b(),
        Ordering::Less => face_a(),
        Ordering::Equal => face_a().or_else(face_b),
    };
    let Some((sep, n)) = chosen else {
        return false;
    };
    let points = ClosestPoints {
        n,
        d: real_of(sep),
        ..ClosestPoints::default()
    };
    // The caller checked that no vertex moved by `−anchor` saturates.
    let within = |r: Real| (-Real::ONE..=Real::ONE).contains(&r);
    let support = if within(n.x) && within(n.y) {
        support_edge_for_poly_unit
    } else {
        support_edge_for_poly
    };
    let e1 = support(a, n).moved_unsaturated(anchor);
    let e2 = support(b, -n).moved_unsaturated(anchor);
    // The contacts go straight into `info` (kept to put back if GJK must
    // decide): clipping into a local and copying it whole made the copy
    // wait on the contacts' part-by-part stores on every call.
    let before = if FRESH { None } else { Some(*info) };
    if !FRESH {
        *info = CollisionInfo::new(info.warm_start_id);
    }
    contact_points(&e1, &e2, &points, info);
    // The deepest contact must be as deep as the axis says (the support
    // vertex lies on the incident edge inside the reference face's slab).
    // Slivers break this: nearly collinear edges whose rounded normals make
    // `support_edge_for_poly` pick a neighbour of the reference face, or a
    // deepest vertex clipped off by a short face. GJK then decides.
    let expected = real_of(sep) - min_dist;
    let deepest = info.contacts().iter().map(|c| c.distance).min();
    let slack = Real::from_bits(SLACK_ULP) + Real::from_bits(expected.abs().to_bits() >> 20);
    match deepest {
        Some(d) if d <= expected + slack => true,
        None if expected > CONTACT_TOLERANCE - slack => true,
        _ => {
            *info = before.unwrap_or(CollisionInfo::new(info.warm_start_id));
            false
        }
    }
}

/// Rounding allowed between the axis separation and the deepest clipped
/// contact, in ulp (each clipped point and distance is rounded once or twice).
const SLACK_ULP: i64 = 64;

/// The index after `i` on a polygon of `count ≥ 1` vertices.
#[inline]
fn next(i: usize, count: usize) -> usize {
    let j = i.saturating_add(1);
    if j >= count {
        0
    } else {
        j
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real;

    fn rect(l: i32, b: i32, r: i32, t: i32, radius: Real) -> Poly {
        let v = [
            Vect::from_ints(r, b),
            Vect::from_ints(r, t),
            Vect::from_ints(l, t),
            Vect::from_ints(l, b),
        ];
        Poly::from_ccw_unchecked(&v, radius)
    }

    #[test]
    fn separation_is_exact_and_picks_lowest_edge_on_tie() {
        let a = rect(0, 0, 2, 2, Real::ZERO);
        let b = rect(3, 0, 5, 2, Real::ZERO);
        let s = max_separation(&a, &b, i128::MAX).unwrap();
        assert_eq!((real_of(s.sep), s.edge), (Real::ONE, 0));
        // A box inside a wider one, centred: up (edge 1) and down (edge 3)
        // are equally deep; the lower edge index wins.
        let outer = rect(-2, -1, 2, 1, Real::ZERO);
        let inner = rect(-1, -1, 1, 1, Real::ZERO);
        let s = max_separation(&inner, &outer, i128::MAX).unwrap();
        assert_eq!((real_of(s.sep), s.edge), (-Real::TWO, 1));
    }

    /// A box of half-extents `w × h` turned by `angle` and moved to `at`.
    /// Its corners are rotated one by one; rotation rounds symmetrically
    /// under negation (ties away from zero), so opposite corners, edges and
    /// normals stay exact negatives unless something saturates.
    fn turned_box(w: i64, h: i64, angle: i64, at: Vect) -> Poly {
        let rot = Vect::for_angle(Real::from_bits(angle));
        let (w, h) = (Real::from_bits(w), Real::from_bits(h));
        let corners =
            [(w, -h), (w, h), (-w, h), (-w, -h)].map(|(x, y)| at + rot.rotate(Vect::new(x, y)));
        Poly::from_ccw_unchecked(&corners, Real::ZERO)
    }

    /// A regular polygon of `n` (even) vertices, radius `r`, turned by
    /// `angle`, centrally symmetric (vertex `k + n/2` is exactly `−v_k`
    /// before the move, so its opposite normals are exact negatives unless
    /// the move saturates), moved to `at`.
    fn turned_regular(n: i32, r: i64, angle: i64, at: Vect) -> Poly {
        let rot = Vect::for_angle(Real::from_bits(angle));
        let step = Real::TAU / Real::from_int(n);
        let half: Vec<Vect> = (0..n / 2)
            .map(|k| rot.rotate(Vect::for_angle(step * Real::from_int(k)).mult(Real::from_bits(r))))
            .collect();
        let corners: Vec<Vect> = half
            .iter()
            .copied()
            .chain(half.iter().map(|v| -*v))
            .map(|v| at + v)
            .collect();
        Poly::from_ccw_unchecked(&corners, Real::ZERO)
    }

    /// The separation of face `k` of `a` against `b` (the face-by-face
    /// pass's value for that face).
    fn face_sep(a: &Poly, b: &Poly, k: usize) -> i128 {
        let k = k % a.count().max(1);
        min_dot(b, a.normal(k)).saturating_sub(exact::dot(a.vert(k), a.normal(k)))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]
        /// The paired-face passes (a box; a hexagon or octagon) give what
        /// the face-by-face pass gives, for any other polygon and any limit
        /// (turned, far out, tiny enough for zero normals, against a box or
        /// a triangle; limits at a face's separation ±1, so that the search
        /// stops early at any face).
        #[test]
        fn paired_passes_are_the_face_by_face_pass(
            (w, h, angle) in (
                proptest::prop_oneof![0i64..4, 1i64..(1 << 36)],
                1i64..(1 << 36),
                proptest::prop_oneof![proptest::strategy::Just(0i64), -(14i64 << 30)..(14i64 << 30)],
            ),
            (bw, bh, bangle) in (1i64..(1 << 36), 1i64..(1 << 36), -(14i64 << 30)..(14i64 << 30)),
            (ax, ay, bx, by) in (-(1i64 << 36)..(1 << 36), -(1i64 << 36)..(1 << 36), -(1i64 << 36)..(1 << 36), -(1i64 << 36)..(1 << 36)),
            far in proptest::prelude::any::<bool>(),
            kind in 0u8..3,
            triangle in proptest::prelude::any::<bool>(),
            (open, face, delta) in (proptest::prelude::any::<bool>(), 0usize..8, -1i128..=1),
        ) {
            let shift = if far { Real::MAX - Real::from_int(8) } else { Real::ZERO };
            let at_a = Vect::new(Real::from_bits(ax) + shift, Real::from_bits(ay));
            let a = match kind {
                0 => turned_box(w, h, angle, at_a),
                1 => turned_regular(6, w, angle, at_a),
                _ => turned_regular(8, w, angle, at_a),
            };
            let at_b = Vect::new(Real::from_bits(bx) + shift, Real::from_bits(by));
            let b = if triangle {
                let (p, q) = (Real::from_bits(bw), Real::from_bits(bh));
                Poly::from_ccw_unchecked(
                    &[at_b, at_b + Vect::new(p, Real::ZERO), at_b + Vect::new(Real::ZERO, q)],
                    Real::ZERO,
                )
            } else {
                turned_box(bw, bh, bangle, at_b)
            };
            if !far {
                // Rounding is symmetric under negation: without saturation
                // these polygons pair, and the paired passes run.
                let n = a.normals();
                let h = n.len() / 2;
                proptest::prop_assert!((0..h).all(|i| n[i + h] == -n[i]), "{n:?}");
            }
            for (x, y) in [(&a, &b), (&b, &a)] {
                let limit = if open {
                    i128::MAX
                } else {
                    face_sep(x, y, face).saturating_add(delta)
                };
                let (got, want) = (max_separation(x, y, limit), max_separation_by_faces(x, y, limit));
                proptest::prop_assert_eq!(got.map(|s| (s.sep, s.edge)), want.map(|s| (s.sep, s.edge)));
            }
        }
    }

    #[test]
    fn a_box_with_opposite_normals_takes_the_paired_pass() {
        // An axis-aligned box's normals are exact negatives in pairs: the
        // paired pass runs (and answers as the face-by-face one).
        let a = rect(0, 0, 2, 2, Real::ZERO);
        let n = a.normals();
        assert!(n[2] == -n[0] && n[3] == -n[1]);
        let b = rect(3, 1, 5, 4, Real::ZERO);
        for limit in [i128::MAX, 0, 1 << 64] {
            let (got, want) = (
                max_separation(&a, &b, limit),
                max_separation_by_faces(&a, &b, limit),
            );
            assert_eq!(got.map(|s| (s.sep, s.edge)), want.map(|s| (s.sep, s.edge)));
        }
    }

    #[test]
    fn corner_to_corner_gap_falls_back() {
        let a = rect(0, 0, 1, 1, real!(0.25));
        let b = rect(1, 1, 2, 2, real!(0.25));
        // Moved diagonally by 0.1: cores apart along the diagonal, no face
        // realises the distance.
        let b = Poly::from_ccw_unchecked(
            &b.verts()
                .iter()
                .map(|v| *v + Vect::new(real!(0.1), real!(0.1)))
                .collect::<Vec<_>>(),
            real!(0.25),
        );
        let mut info = CollisionInfo::new(0);
        assert!(!poly_to_poly_sat(&a, &b, Vect::ZERO, &mut info));
        assert_eq!(info, CollisionInfo::new(0));
    }

    #[test]
    fn short_box_above_long_one_uses_the_long_face_on_a_tie() {
        // Rounded boxes, cores 0.09 apart: the short box sorts first, its
        // bottom face ties with the floor's top and does not realise the
        // distance (the floor's corners are outside it); the floor's does.
        let top = Poly::from_ccw_unchecked(
            &[
                Vect::new(Real::ONE, real!(0.09)),
                Vect::new(Real::ONE, real!(1.09)),
                Vect::new(-Real::ONE, real!(1.09)),
                Vect::new(-Real::ONE, real!(0.09)),
            ],
            real!(0.05),
        );
        let floor = rect(-5, -1, 5, 0, real!(0.05));
        let mut info = CollisionInfo::new(0);
        assert!(poly_to_poly_sat(&top, &floor, Vect::ZERO, &mut info));
        assert_eq!((info.count, info.normal), (2, -Vect::Y));
        for c in info.contacts() {
            assert_eq!(c.distance, real!(-0.01));
        }
    }

    #[test]
    fn far_apart_is_decided_without_gjk() {
        let a = rect(0, 0, 1, 1, Real::ZERO);
        let b = rect(5, 5, 6, 6, Real::ZERO);
        let mut info = CollisionInfo::new(7);
        assert!(poly_to_poly_sat(&a, &b, Vect::ZERO, &mut info));
        assert_eq!(info, CollisionInfo::new(7));
    }
}
