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
//! Nothing here panics, allocates or loops without a bound; GJK and EPA stop
//! at [`WARN_GJK_ITERATIONS`] / [`WARN_EPA_ITERATIONS`] and report it in
//! [`CollisionInfo::hit_iteration_cap`].
mod contact;
mod epa;
mod gjk;
mod pairs;
mod sat;
mod support;
mod toi;

use core::cmp::Ordering;

use serde::{Deserialize, Serialize};

pub use contact::{closest_points_new, closest_t, contact_points, lerp_t, ClosestPoints};
pub use epa::epa;
pub use gjk::gjk;
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

use crate::math::{wide, Real, Vect};
use crate::shape::{Circle, Geometry, Poly, Segment};

/// Contacts one pair can produce (Chipmunk `CP_MAX_CONTACTS_PER_ARBITER`).
pub const MAX_CONTACTS_PER_ARBITER: usize = 2;

/// Largest separation at which two shapes still count as touching (2^-20,
/// about 10^-6 m). A resting contact's separation hovers around zero by a few
/// ulp; with a strict `≤ 0` test a contact that rounds to +1 ulp vanishes for
/// a step and the body rocks on the remaining one (found by the sliding
/// incline test). A slightly separated contact gets no bias (its distance is
/// above `−slop`) and only stops approach.
pub const CONTACT_TOLERANCE: Real = Real::from_bits(1 << 12);

/// GJK iteration cap (MIS `WARN_GJK_ITERATIONS`). Two polygons of at most 8
/// vertices have a Minkowski difference of at most 16 vertices, and GJK on
/// exact predicates visits each edge at most once, so 30 is never reached in
/// practice; Chipmunk uses the same number as its hard limit.
pub const WARN_GJK_ITERATIONS: u32 = 30;

/// EPA iteration cap (MIS `WARN_EPA_ITERATIONS`); the same reasoning as GJK.
pub const WARN_EPA_ITERATIONS: u32 = 30;

/// GJK warm-start id (MIS `CollisionID`; not a feature id): the vertex indices of the last
/// closest edge of the Minkowski difference, one byte each,
/// `a₀ << 24 | b₀ << 16 | a₁ << 8 | b₁` (indices on shape `a` and `b` of the
/// caller). 0 means "no cache". Store the id a [`collide`] call returns and
/// pass it to the next call for the same pair; any value is safe (an id that
/// names missing vertices is ignored) and gives a correct answer.
///
/// The answer is not always bit-identical to a cold start's: when two
/// features of the Minkowski difference are equally deep (a box centred in a
/// wider one: pushed up or down) or equally deep to within EPA's ranking
/// precision (~2^-61 relative), GJK/EPA report the one their starting point
/// leads to, and a face made of collinear pieces gets the normal of the piece
/// GJK ends on (equal up to rounding). Either answer is right and the result
/// is still deterministic, since the id is part of the arbiter state.
/// Polygon pairs answered by separating axes (see [`poly_to_poly`]) neither
/// read nor change the id, so their answer is the same for every id.
pub type WarmStartId = u32;

/// One narrowphase contact: a pair of points on the two surfaces with its
/// feature id (an element of MIS `CollisionInfo`, per step). The arbiter
/// keeps it as an [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint),
/// the solver turns that into a
/// `solver::ContactConstraint`; the public
/// query type is [`ContactPoint`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Contact {
    /// World-space point on the surface of `a` (rounding radius included).
    pub point_a: Vect,
    /// World-space point on the surface of `b`.
    pub point_b: Vect,
    /// Signed separation `(point_b − point_a) · normal`: negative when the
    /// shapes overlap (Chipmunk's convention), 0 when they just touch; at
    /// most [`CONTACT_TOLERANCE`] above 0 for shapes a hair apart.
    pub distance: Real,
    /// Feature id, `(feature on a) << 16 | (feature on b)`, where a feature is
    /// a vertex / endpoint index (0 for a circle). The same touching features
    /// keep the same id from step to step.
    pub feature_id: u32,
}

/// The result of [`collide`] (MIS `CollisionInfo`). A per-step value, not
/// snapshot state (it holds a `usize`); arbiters keep the [`Contact`]s (as
/// [`ManifoldPoint`](crate::arbiter::ManifoldPoint)s) and `warm_start_id`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CollisionInfo {
    /// Unit normal from `a` toward `b` (zero when `count == 0`).
    pub normal: Vect,
    /// Number of valid entries of `contacts` (≤ [`MAX_CONTACTS_PER_ARBITER`]).
    pub count: usize,
    /// The contacts; entries past `count` are zero.
    pub contacts: [Contact; MAX_CONTACTS_PER_ARBITER],
    /// Warm-start id for the next call on this pair.
    pub warm_start_id: WarmStartId,
    /// True if GJK or EPA stopped at its iteration cap; the answer is then
    /// the best found, not necessarily the exact one.
    pub hit_iteration_cap: bool,
}

impl CollisionInfo {
    /// An empty info carrying the warm-start id `warm_start_id`.
    pub fn new(warm_start_id: WarmStartId) -> CollisionInfo {
        CollisionInfo {
            warm_start_id,
            ..CollisionInfo::default()
        }
    }

    /// The valid contacts.
    pub fn contacts(&self) -> &[Contact] {
        self.contacts.get(..self.count).unwrap_or(&[])
    }

    /// MIS `collisionInfoPushContact`. A third contact cannot be produced by
    /// the pair functions; it would be ignored rather than overflow.
    pub fn push_contact(&mut self, point_a: Vect, point_b: Vect, distance: Real, feature_id: u32) {
        if let Some(slot) = self.contacts.get_mut(self.count) {
            *slot = Contact {
                point_a,
                point_b,
                distance,
                feature_id,
            };
            // count < contacts.len() (the slot exists): never saturates.
            self.count = self.count.saturating_add(1);
        }
    }

    /// Moves every contact point by `offset`.
    fn translate(&mut self, offset: Vect) {
        for c in self.contacts.iter_mut().take(self.count) {
            c.point_a += offset;
            c.point_b += offset;
        }
    }

    /// The same collision seen from the other shape: normal negated, points
    /// and feature-id halves swapped, warm-start id converted.
    fn mirrored(mut self) -> CollisionInfo {
        self.mirror();
        self
    }

    /// [`mirrored`](Self::mirrored) in place.
    fn mirror(&mut self) {
        self.normal = -self.normal;
        for c in self.contacts.iter_mut().take(self.count) {
            core::mem::swap(&mut c.point_a, &mut c.point_b);
            c.feature_id = c.feature_id.rotate_left(16);
        }
        self.warm_start_id = swap_id_shapes(self.warm_start_id);
    }
}

/// A warm-start id with the roles of the two shapes exchanged (the A and B
/// bytes of each Minkowski point swap places).
#[inline]
fn swap_id_shapes(id: WarmStartId) -> WarmStartId {
    ((id & 0x00FF_00FF) << 8) | ((id >> 8) & 0x00FF_00FF)
}

/// One point pair of a [`ContactPointSet`]: the public query answer (MIS /
/// Chipmunk), without feature id. The engine's other contact types are
/// [`Contact`] (narrowphase), [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint)
/// (persistent) and `solver::ContactConstraint`
/// (solver row).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ContactPoint {
    /// Point on the surface of `a`.
    pub point_a: Vect,
    /// Point on the surface of `b`.
    pub point_b: Vect,
    /// Signed separation along the normal (negative when overlapping).
    pub distance: Real,
}

/// Contacts between two shapes without ids (MIS/Chipmunk `ContactPointSet`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ContactPointSet {
    /// Number of valid points.
    pub count: usize,
    /// Unit normal from `a` toward `b` (zero when `count == 0`).
    pub normal: Vect,
    /// The points; entries past `count` are zero.
    pub points: [ContactPoint; MAX_CONTACTS_PER_ARBITER],
}

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
    info.translate(anchor);
    if info.count == 0 {
        info.normal = Vect::ZERO;
    }
    if swap {
        info.mirror();
    }
    info
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
    let (first, second) = (moved_poly(first, anchor), moved_poly(second, anchor));
    let unsaturated = |p: &Poly| {
        p.verts()
            .iter()
            .all(|v| !v.x.is_saturated() && !v.y.is_saturated())
    };
    if first.count() == second.count() && unsaturated(&first) && unsaturated(&second) {
        pairs::poly_to_poly_ordered(&first, &second, &mut info);
    } else {
        poly_to_poly(&first, &second, &mut info);
    }
    info.translate(anchor);
    if info.count == 0 {
        info.normal = Vect::ZERO;
    }
    if swap {
        info.mirror();
    }
    info
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
    if wide::len_sq(delta) > pairs::sq(min_dist + CONTACT_TOLERANCE) {
        return info;
    }
    let (n, dist) = wide::normalize(delta).unwrap_or((Vect::X, Real::ZERO));
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

/// True if the pair must be swapped into canonical order: by kind, then (same
/// kind) by coordinates, lexicographically. Comparing coordinates is
/// unchanged by translating both shapes, so the order is too.
fn comes_after(a: &Geometry, b: &Geometry) -> bool {
    match a.kind().cmp(&b.kind()) {
        Ordering::Less => false,
        Ordering::Greater => true,
        Ordering::Equal => compare_same_kind(a, b) == Ordering::Greater,
    }
}

/// A total order on the data of two geometries of the same kind.
fn compare_same_kind(a: &Geometry, b: &Geometry) -> Ordering {
    match (a, b) {
        (Geometry::Circle(x), Geometry::Circle(y)) => compare_circles(x, y),
        (Geometry::Segment(x), Geometry::Segment(y)) => compare_segments(x, y),
        (Geometry::Poly(x), Geometry::Poly(y)) => compare_polys(x, y),
        // Different kinds never reach here; order them by kind for totality.
        (Geometry::Circle(_) | Geometry::Segment(_) | Geometry::Poly(_), _) => {
            a.kind().cmp(&b.kind())
        }
    }
}

/// The coordinates of `vs`, flattened (`x₀, y₀, x₁, …`).
fn flat(vs: &[Vect]) -> impl Iterator<Item = Real> + '_ {
    vs.iter().flat_map(|v| [v.x, v.y])
}

/// Lexicographic order on (centre, radius). Comparing coordinates is
/// unchanged by translating both shapes, so the order is too.
pub(crate) fn compare_circles(x: &Circle, y: &Circle) -> Ordering {
    (x.offset.x, x.offset.y, x.radius).cmp(&(y.offset.x, y.offset.y, y.radius))
}

/// Lexicographic order on every field (endpoints first).
pub(crate) fn compare_segments(x: &Segment, y: &Segment) -> Ordering {
    let key = |s: &Segment| {
        [
            s.a,
            s.b,
            s.normal,
            s.a_tangent,
            s.b_tangent,
            Vect::new(s.radius, Real::ZERO),
        ]
    };
    flat(&key(x)).cmp(flat(&key(y)))
}

/// Lexicographic order on (vertices, normals, radius).
/// Written as a walk over the two key sequences (the former iterator chain
/// copied its arrays; unit test `compare_polys_is_the_chained_order`).
pub(crate) fn compare_polys(x: &Poly, y: &Poly) -> Ordering {
    // The first vertex (keys 0 and 1) almost always decides.
    if x.count() == 0 || y.count() == 0 {
        return compare_poly_keys(x, y, 0);
    }
    let (a, b) = (x.vert(0), y.vert(0));
    match (a.x, a.y).cmp(&(b.x, b.y)) {
        Ordering::Equal => compare_poly_keys(x, y, 2),
        unequal => unequal,
    }
}

/// The lexicographic order of the two key sequences from key `k` on (the
/// keys before it being equal).
fn compare_poly_keys(x: &Poly, y: &Poly, mut k: usize) -> Ordering {
    loop {
        match (poly_key(x, k), poly_key(y, k)) {
            (Some(a), Some(b)) => match a.cmp(&b) {
                Ordering::Equal => k = k.saturating_add(1),
                unequal => return unequal,
            },
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
        }
    }
}

/// Element `k` of a polygon's key sequence `x₀, y₀, x₁, …` (vertices),
/// then the normals the same way, then the radius; `None` past the end.
#[inline]
fn poly_key(p: &Poly, k: usize) -> Option<Real> {
    let coord = |v: Vect, k: usize| if k % 2 == 0 { v.x } else { v.y };
    let n = p.count().saturating_mul(2);
    if k < n {
        Some(coord(p.vert(k / 2), k))
    } else if k < n.saturating_mul(2) {
        Some(coord(p.normal((k.saturating_sub(n)) / 2), k))
    } else if k == n.saturating_mul(2) {
        Some(p.radius())
    } else {
        None
    }
}

/// The point the computation is made relative to.
fn anchor_of(g: &Geometry) -> Vect {
    match g {
        Geometry::Circle(c) => c.offset,
        Geometry::Segment(s) => s.a,
        Geometry::Poly(p) => p.vert(0),
    }
}

/// True for a polygon without vertices (possible only from corrupt data).
fn is_empty(g: &Geometry) -> bool {
    match g {
        Geometry::Poly(p) => p.count() == 0,
        Geometry::Circle(_) | Geometry::Segment(_) => false,
    }
}

/// The geometry translated by `−anchor` (directions are unchanged).
fn moved(g: &Geometry, anchor: Vect) -> Geometry {
    match g {
        Geometry::Circle(c) => Geometry::Circle(Circle {
            offset: c.offset - anchor,
            ..*c
        }),
        Geometry::Segment(s) => Geometry::Segment(Segment {
            a: s.a - anchor,
            b: s.b - anchor,
            ..*s
        }),
        Geometry::Poly(p) => Geometry::Poly(moved_poly(p, anchor)),
    }
}

#[inline(always)]
fn moved_poly(p: &Poly, anchor: Vect) -> Poly {
    let n = p.count();
    // Built in place (a copy, then a loop over it, cost two extra copies).
    Poly {
        count: p.count,
        verts: core::array::from_fn(|i| {
            let v = p.verts.get(i).copied().unwrap_or(Vect::ZERO);
            if i < n {
                v - anchor
            } else {
                v
            }
        }),
        normals: p.normals,
        radius: p.radius,
    }
}

#[cfg(test)]
mod tests;
