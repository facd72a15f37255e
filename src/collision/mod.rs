//! The MIS Collision Solver (§10), narrow phase: contacts between two shapes.
//!
//! [`collide`] takes two world-space geometries and returns a
//! [`CollisionInfo`]: a unit normal from `a` toward `b` and up to
//! [`MAX_CONTACTS_PER_ARBITER`] contacts, each a pair of surface points with
//! their signed separation and a feature id that stays the same while the
//! same features touch (so the solver can warm-start from last step's
//! impulses). [`shapes_collide`] is the MIS/Chipmunk convenience form.
//!
//! Pipeline, and why:
//! 1. **Order the pair.** The pair functions exist for circle < segment <
//!    poly; a pair in the other order is swapped and the answer swapped back.
//!    Two shapes of the same kind are ordered by their coordinates (the
//!    same-kind pair functions also do this themselves, so they are
//!    swap-exact when called directly), so `collide(b, a)` runs exactly the
//!    computation of `collide(a, b)` and its answer is the exact mirror
//!    (normal negated bit for bit, points and id halves swapped), provided
//!    the warm-start id is the same one seen from the other side (as an
//!    arbiter's is). This is the only source of swap exactness: GJK and EPA
//!    on their own are not swap-exact (start direction, tie-breaks, rounding).
//! 2. **Move next to the origin.** Both shapes are translated by minus the
//!    first shape's anchor (centre, endpoint `a` or vertex 0) before any
//!    product is formed, and the contact points are translated back at the
//!    end. Fixed-point addition is exact, so translating a scene moves every
//!    contact point by exactly the same vector and leaves normals, distances
//!    and ids bit-identical; the products also stay small (no saturation far
//!    from the origin, where `x²` would overflow past 46,340).
//! 3. **Dispatch** on the kinds with an exhaustive `match` to one of the six
//!    pair functions (`pairs.rs`): closed forms for circle–circle and
//!    circle–segment, separating axes with edge clipping for poly–poly
//!    (`sat.rs`, falling back to GJK for a corner near a corner), GJK
//!    ([`gjk`]) with EPA ([`epa`]) and edge clipping ([`contact_points`]) for
//!    the rest.
//!
//! Beside the contacts, two swept questions: [`separation`] (`toi.rs`), the
//! signed distance the bullets' time of impact advances on, and
//! [`shape_cast`] (`cast.rs`), where one geometry moved along a translation
//! first touches another: a ray against their Minkowski difference, exact
//! and without iteration.
//!
//! Nothing here panics, allocates or loops without a bound; GJK and EPA stop
//! at [`WARN_GJK_ITERATIONS`] / [`WARN_EPA_ITERATIONS`] and report it in
//! [`CollisionInfo::hit_iteration_cap`].
mod canonical;
mod cast;
mod contact;
mod epa;
mod gjk;
mod info;
mod pairs;
mod sat;
mod support;
mod toi;

use core::cmp::Ordering;

pub(crate) use cast::{cast_entry, hit_point};
pub use cast::{shape_cast, ShapeCastInfo, StartContact, CAST_TOLERANCE};
pub use contact::{closest_points_new, closest_t, contact_points, lerp_t, ClosestPoints};
pub use epa::{epa, WARN_EPA_ITERATIONS};
pub use gjk::{gjk, WARN_GJK_ITERATIONS};
pub use info::{CollisionInfo, Contact, ContactPoint, ContactPointSet, WarmStartId};
pub use info::{CONTACT_TOLERANCE, MAX_CONTACTS_PER_ARBITER};
pub use pairs::{
    circle_to_circle, circle_to_poly, circle_to_segment, poly_to_poly, poly_to_poly_gjk,
    segment_to_poly, segment_to_segment,
};
pub use support::{
    circle_support_point, poly_support_index, poly_support_point, segment_support_point, support,
    support_edge_for_poly, support_edge_for_segment, Edge, EdgePoint, MinkowskiPoint,
    SupportContext, SupportPoint, SupportShape,
};
pub use toi::separation;

use canonical::{
    anchor_of, comes_after, compare_circles, compare_polys, is_empty, moved, moved_poly,
};
use info::swap_id_shapes;

use crate::math::{exact, Real, Vect};
use crate::shape::{Circle, Geometry, Poly};

/// MIS `shapesCollide`: the contacts of two world-space geometries.
pub fn shapes_collide(a: &Geometry, b: &Geometry) -> ContactPointSet {
    let info = collide(a, b, 0);
    let mut set = ContactPointSet {
        count: info.count,
        normal: info.normal,
        ..ContactPointSet::default()
    };
    for (dst, src) in set.points.iter_mut().zip(info.contacts()) {
        *dst = ContactPoint {
            point_a: src.point_a,
            point_b: src.point_b,
            distance: src.distance,
        };
    }
    set
}

/// MIS `collide`: contacts between two world-space geometries, in the
/// caller's order (`normal` from `a` toward `b`). `warm_start_id` is the warm-start id
/// the previous call on this pair returned, or 0.
pub fn collide(a: &Geometry, b: &Geometry, warm_start_id: WarmStartId) -> CollisionInfo {
    match (a, b) {
        (Geometry::Circle(x), Geometry::Circle(y)) => collide_circles(x, y, warm_start_id),
        (Geometry::Poly(x), Geometry::Poly(y)) => collide_polys(x, y, warm_start_id),
        _ => collide_general(a, b, warm_start_id),
    }
}

/// [`collide`] for any pair: canonical order, translation next to the
/// origin, the pair function, and back.
fn collide_general(a: &Geometry, b: &Geometry, warm_start_id: WarmStartId) -> CollisionInfo {
    let swap = comes_after(a, b);
    let (first, second) = if swap { (b, a) } else { (a, b) };
    let id = if swap {
        swap_id_shapes(warm_start_id)
    } else {
        warm_start_id
    };
    let anchor = anchor_of(first);
    let (first, second) = (moved(first, anchor), moved(second, anchor));
    let mut info = CollisionInfo::new(id);
    if !is_empty(&first) && !is_empty(&second) {
        dispatch(&first, &second, &mut info);
    }
    info.placed(anchor, swap)
}

/// True if every vertex coordinate of `p` lies in `[−2^61, 2^61)` raw
/// (`±2^29` units): then the difference of two such coordinates lies
/// strictly inside `(−2^62, 2^62)`, far from saturation. A sufficient
/// test for [`collide_polys`]'s exact one, in two operations a coordinate:
/// `x + 2^61` (wrapping) is below `2^62` exactly for `x` in the range, and
/// an OR of values is below `2^62` exactly when each one is.
#[inline(always)]
fn within_half_range(p: &Poly) -> bool {
    const HALF: u64 = 1 << 61;
    let bits = p.verts().iter().fold(0u64, |acc, v| {
        acc | (v.x.to_bits() as u64).wrapping_add(HALF) | (v.y.to_bits() as u64).wrapping_add(HALF)
    });
    bits < HALF << 1
}

/// [`collide`] for two polygons: the general path's steps on the two
/// polygons alone, translated into fresh copies rather than through whole
/// `Geometry` copies. When both have the same vertex count and no
/// translated coordinate is `Real::MIN` or `MAX` (so none saturated), the
/// translation subtracted the same exact value from the coordinates that
/// `compare_polys` sets side by side (vertices against vertices, component
/// by component; normals and radii are not moved), so the translated pair
/// compares as the original one: in order, and `poly_to_poly`'s own
/// comparison is skipped. Otherwise `poly_to_poly` decides again, as in the
/// general path. Same bits as the general path (unit test
/// `poly_fast_path_is_the_general_path`, proptest
/// `poly_kernel_is_the_general_path`).
fn collide_polys(a: &Poly, b: &Poly, warm_start_id: WarmStartId) -> CollisionInfo {
    let swap = compare_polys(a, b) == Ordering::Greater;
    let (first, second) = if swap { (b, a) } else { (a, b) };
    let id = if swap {
        swap_id_shapes(warm_start_id)
    } else {
        warm_start_id
    };
    let mut info = CollisionInfo::new(id);
    if first.count() == 0 || second.count() == 0 {
        return CollisionInfo::new(warm_start_id);
    }
    let anchor = first.vert(0);
    // No vertex moved by `−anchor` saturates (nor lands on `MIN` or `MAX`).
    let unsaturated = |p: &Poly| {
        p.verts().iter().all(|v| {
            let moved = *v - anchor;
            !moved.x.is_saturated() && !moved.y.is_saturated()
        })
    };
    let moves_unsaturated = within_half_range(first) && within_half_range(second)
        || unsaturated(first) && unsaturated(second);
    if first.count() == second.count() && moves_unsaturated {
        // Separating axes on the polygons where they are: their answer is
        // the moved pair's (`poly_to_poly_sat`); only GJK, whose rounding
        // depends on where the pair is, needs the moved copies.
        if !sat::poly_to_poly_sat_fresh(first, second, anchor, &mut info) {
            let (first, second) = (moved_poly(first, anchor), moved_poly(second, anchor));
            pairs::poly_to_poly_gjk_ordered(&first, &second, &mut info);
        }
    } else {
        let (first, second) = (moved_poly(first, anchor), moved_poly(second, anchor));
        poly_to_poly(&first, &second, &mut info);
    }
    info.placed(anchor, swap)
}

/// [`collide`] for two circles: the computation of the general path
/// (canonical order, translation by the first circle's centre, the closed
/// form of `circle_to_circle`, translation back, mirroring), written out for
/// two circles: nothing is copied, zeroed twice or mirrored after the fact.
/// The steps it saves, and why the bits are those of the general path (unit test
/// `circle_fast_path_is_the_general_path`, proptest
/// `circle_kernel_is_the_general_path`):
/// * the canonical order is decided once: translating both circles by the
///   first one's centre keeps the sign of every coordinate difference (a
///   saturated difference keeps its sign), so `circle_to_circle` would find
///   them in order again;
/// * the first centre translated is exactly zero, so the offset between the
///   centres is the second one translated, and `0 + n·r` is `n·r`;
/// * mirroring negates the normal and swaps the points; the feature id 0 and
///   the warm-start id (converted twice, an involution) are unchanged.
fn collide_circles(a: &Circle, b: &Circle, warm_start_id: WarmStartId) -> CollisionInfo {
    let swap = compare_circles(a, b) == Ordering::Greater;
    let (first, second) = if swap { (b, a) } else { (a, b) };
    let mut info = CollisionInfo::new(warm_start_id);
    let anchor = first.offset;
    let delta = second.offset - anchor;
    let min_dist = first.radius + second.radius;
    if exact::len_sq(delta) > pairs::sq(min_dist + CONTACT_TOLERANCE) {
        return info;
    }
    let (n, dist) = exact::normalize(delta).unwrap_or((Vect::X, Real::ZERO));
    let on_first = n.mult(first.radius) + anchor;
    let on_second = (delta - n.mult(second.radius)) + anchor;
    let (normal, point_a, point_b) = if swap {
        (-n, on_second, on_first)
    } else {
        (n, on_first, on_second)
    };
    info.normal = normal;
    info.count = 1;
    info.contacts = [
        Contact {
            point_a,
            point_b,
            distance: dist - min_dist,
            feature_id: 0,
        },
        Contact::default(),
    ];
    info
}

/// Runs the pair function for `(a, b)`; pairs out of kind order (which
/// `collide` never passes) are handled by mirroring.
fn dispatch(a: &Geometry, b: &Geometry, info: &mut CollisionInfo) {
    use Geometry::{Circle as C, Poly as P, Segment as S};
    let mirror = |info: &mut CollisionInfo, f: &dyn Fn(&mut CollisionInfo)| {
        let mut m = CollisionInfo::new(swap_id_shapes(info.warm_start_id));
        f(&mut m);
        *info = m.mirrored();
    };
    match (a, b) {
        (C(x), C(y)) => circle_to_circle(x, y, info),
        (C(x), S(y)) => circle_to_segment(x, y, info),
        (C(x), P(y)) => circle_to_poly(x, y, info),
        (S(x), S(y)) => segment_to_segment(x, y, info),
        (S(x), P(y)) => segment_to_poly(x, y, info),
        (P(x), P(y)) => poly_to_poly(x, y, info),
        (S(x), C(y)) => mirror(info, &|m| circle_to_segment(y, x, m)),
        (P(x), C(y)) => mirror(info, &|m| circle_to_poly(y, x, m)),
        (P(x), S(y)) => mirror(info, &|m| segment_to_poly(y, x, m)),
    }
}

#[cfg(test)]
mod tests;
