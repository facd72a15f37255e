//! Space-level queries (MIS/Chipmunk `spacePointQuery`,
//! `spacePointQueryNearest`, `spaceSegmentQuery`, `spaceSegmentQueryFirst`,
//! `spaceBBQuery`, `spaceShapeQuery`): which shapes are near a point, on a
//! ray, in a box or touching a shape. The shape casts (`cast.rs`) find
//! their candidates here too.
//!
//! # How
//! Candidates in slot order: when the static tree is current (no static
//! shape or body changed since the last step), the static shapes it finds
//! for the query's box plus every shape of the non-static bodies (from the
//! per-body shape lists); otherwise (before the first step, after a
//! restore or a change of the level, until the next step) every shape.
//! Each candidate's world geometry is computed from its body's *current*
//! position and rotation (so queries work after a body is moved by hand,
//! when the step's cache is stale), its bounding box is tested against the
//! query's box, and only then the exact geometry query
//! ([`crate::shape::query`]) or the narrowphase ([`shapes_collide`]) runs.
//! The candidates are a superset of the shapes passing the box test, so
//! both paths give the same results; the cost is set by the static shapes
//! near the query and the number of moving shapes.
//!
//! # Semantics (Chipmunk 7)
//! * **Filter:** a shape is skipped when its filter and the query's reject
//!   each other ([`ShapeFilter::rejects`]: same non-zero group, or either
//!   one's categories missing the other's mask). [`ShapeFilter::ALL`] sees
//!   every shape.
//! * **Sensors** are reported by the "all" queries ([`Space::point_query`],
//!   [`Space::segment_query`], [`Space::bb_query`], [`Space::shape_query`])
//!   and skipped by the "best" queries ([`Space::point_query_nearest`],
//!   [`Space::segment_query_first`]), as Chipmunk 7 does: a sensor reports
//!   overlaps but does not block a ray or hide a nearer solid shape.
//! * **Order:** results are in shape slot order (the canonical order), except
//!   that segment hits are sorted by `alpha` with ties in slot order; "best"
//!   queries keep the lowest slot on a tie. Nothing depends on a hash.
use super::{ShapeHandle, Space};
use crate::arena::Arena;
use crate::body::{Body, BodyType};
use crate::collision::{shapes_collide, ContactPointSet};
use crate::math::{Real, Vect, BB};
use crate::shape::query::{point_query, segment_query, PointQueryInfo, SegmentQueryInfo};
use crate::shape::{Geometry, Shape, ShapeFilter};

impl Space {
    /// Shapes accepted by `filter` whose world bounding box touches `bb`,
    /// with their world geometry, in slot order. Shapes of a missing body
    /// (impossible in a validated space) are skipped.
    fn query_candidates(
        &self,
        bb: BB,
        filter: ShapeFilter,
    ) -> impl Iterator<Item = (ShapeHandle, &Shape, Geometry)> + '_ {
        self.query_candidates_where(bb, |_| true, filter)
    }

    /// [`query_candidates`](Self::query_candidates) whose static tree walk
    /// also skips the boxes that fail `keep` (which must hold for every box
    /// that can contain a hit: the results are the same, found sooner).
    pub(super) fn query_candidates_where(
        &self,
        bb: BB,
        keep: impl Fn(&BB) -> bool,
        filter: ShapeFilter,
    ) -> impl Iterator<Item = (ShapeHandle, &Shape, Geometry)> + '_ {
        let bodies = &self.state.bodies;
        fn accept<'a>(
            bodies: &Arena<Body>,
            filter: &ShapeFilter,
            bb: &BB,
            (h, shape): (ShapeHandle, &'a Shape),
        ) -> Option<(ShapeHandle, &'a Shape, Geometry)> {
            if shape.filter.rejects(filter) {
                return None;
            }
            let body = bodies.get(shape.body)?;
            let world = shape.geometry().to_world(body.position(), body.rotation());
            world.bb().intersects(bb).then_some((h, shape, world))
        }
        // Through the broadphase when it is current, else every shape; the
        // same test either way on a superset of the hits, in slot order,
        // so the same results.
        let (slots, all) = match self.broadphase_candidates(&bb, keep) {
            Some(slots) => (slots, false),
            None => (Vec::new(), true),
        };
        let some = slots
            .into_iter()
            .filter_map(|i| self.state.shapes.get_by_index(i))
            .filter_map(move |c| accept(bodies, &filter, &bb, c));
        let every = self
            .state
            .shapes
            .iter()
            .take_while(move |_| all)
            .filter_map(move |c| accept(bodies, &filter, &bb, c));
        some.chain(every)
    }

    /// True if queries go through the broadphase right now (else they scan
    /// every shape); for tests.
    #[doc(hidden)]
    pub fn queries_use_broadphase(&self) -> bool {
        self.broadphase_candidates(&BB::for_point(Vect::ZERO), |_| true)
            .is_some()
    }

    /// The slots of the shapes whose box may touch `bb`, ascending: the
    /// static shapes the static tree finds plus every shape of the other
    /// bodies (from the per-body lists). `None` when the static tree is
    /// stale or not built (a static shape or body changed since the last
    /// step, a restored or new space, or a body handed out by `body_mut`
    /// was replaced by a static one: its shapes are in neither the tree nor
    /// the lists) or the lists are not built: then the caller scans every
    /// shape.
    fn broadphase_candidates(&self, bb: &BB, keep: impl Fn(&BB) -> bool) -> Option<Vec<u32>> {
        let bp = &self.caches.broadphase;
        if bp.statics_dirty || bp.static_builds == 0 || self.suspect_turned_static() {
            return None;
        }
        let lists = &self.caches.body_shapes;
        let mut slots = Vec::new();
        for (bh, body) in self.state.bodies.iter() {
            if body.body_type() != BodyType::Static {
                slots.extend_from_slice(lists.built(bh.index())?);
            }
        }
        bp.static_tree.query_where(bb, keep, |i| slots.push(i));
        slots.sort_unstable();
        Some(slots)
    }

    /// Chipmunk `cpSpacePointQuery`: every shape whose surface is closer to `p` than
    /// `max_distance` (strictly; a point inside a shape has a negative
    /// distance, so `max_distance = 0` finds the shapes containing `p`), with
    /// the nearest point, signed distance and gradient, in slot order.
    /// Sensors included.
    pub fn point_query(
        &self,
        p: Vect,
        max_distance: Real,
        filter: ShapeFilter,
    ) -> Vec<(ShapeHandle, PointQueryInfo)> {
        let bb = BB::for_circle(p, max_distance.max(Real::ZERO));
        self.query_candidates(bb, filter)
            .filter_map(|(h, _, world)| {
                let info = point_query(&world, p);
                (info.distance < max_distance).then_some((h, info))
            })
            .collect()
    }

    /// Chipmunk `cpSpacePointQueryNearest`: the shape whose surface is nearest to
    /// `p`, if closer than `max_distance` (strictly); the lowest slot wins a
    /// tie. Sensors are skipped.
    pub fn point_query_nearest(
        &self,
        p: Vect,
        max_distance: Real,
        filter: ShapeFilter,
    ) -> Option<(ShapeHandle, PointQueryInfo)> {
        let bb = BB::for_circle(p, max_distance.max(Real::ZERO));
        let mut best: Option<(ShapeHandle, PointQueryInfo)> = None;
        for (h, _, world) in self
            .query_candidates(bb, filter)
            .filter(|(_, s, _)| !s.sensor)
        {
            let info = point_query(&world, p);
            let limit = best.map_or(max_distance, |(_, nearest)| nearest.distance);
            if info.distance < limit {
                best = Some((h, info));
            }
        }
        best
    }

    /// Chipmunk `cpSpaceSegmentQuery`: every shape hit by the segment `a → b` swept
    /// by a circle of `radius` (0 for a ray), sorted by `alpha` (ties in slot
    /// order). A shape the query starts in (or within `radius` of) is hit at
    /// `alpha = 0`. Sensors included.
    pub fn segment_query(
        &self,
        a: Vect,
        b: Vect,
        radius: Real,
        filter: ShapeFilter,
    ) -> Vec<(ShapeHandle, SegmentQueryInfo)> {
        let bb = BB::for_point(a).expand(b).grow(radius.max(Real::ZERO));
        let mut hits: Vec<(ShapeHandle, SegmentQueryInfo)> = self
            .query_candidates_where(bb, |node| line_may_touch(a, b, radius, node), filter)
            .filter_map(|(h, _, world)| segment_query(&world, a, b, radius).map(|info| (h, info)))
            .collect();
        // Stable: equal alphas stay in slot order.
        hits.sort_by_key(|(_, info)| info.alpha);
        hits
    }

    /// Chipmunk `cpSpaceSegmentQueryFirst`: the first shape hit by the segment
    /// `a → b` swept by a circle of `radius`; the lowest slot wins a tie.
    /// Sensors are skipped.
    pub fn segment_query_first(
        &self,
        a: Vect,
        b: Vect,
        radius: Real,
        filter: ShapeFilter,
    ) -> Option<(ShapeHandle, SegmentQueryInfo)> {
        let bb = BB::for_point(a).expand(b).grow(radius.max(Real::ZERO));
        let mut best: Option<(ShapeHandle, SegmentQueryInfo)> = None;
        for (h, _, world) in self
            .query_candidates_where(bb, |node| line_may_touch(a, b, radius, node), filter)
            .filter(|(_, s, _)| !s.sensor)
        {
            let Some(info) = segment_query(&world, a, b, radius) else {
                continue;
            };
            if best.is_none_or(|(_, first)| info.alpha < first.alpha) {
                best = Some((h, info));
            }
        }
        best
    }

    /// Chipmunk `cpSpaceBBQuery`: the shapes whose world bounding box touches `bb`
    /// (a box test only, like Chipmunk), in slot order. Sensors included.
    pub fn bb_query(&self, bb: BB, filter: ShapeFilter) -> Vec<ShapeHandle> {
        self.query_candidates(bb, filter)
            .map(|(h, _, _)| h)
            .collect()
    }

    /// Chipmunk `cpSpaceShapeQuery`: the shapes touching the world-space `geometry`,
    /// each with its contact set from [`shapes_collide`] (normal from
    /// `geometry` toward the space's shape), in slot order. Sensors included.
    /// The query shape is not in the space, so nothing is excluded as "itself".
    pub fn shape_query(
        &self,
        geometry: &Geometry,
        filter: ShapeFilter,
    ) -> Vec<(ShapeHandle, ContactPointSet)> {
        self.query_candidates(geometry.bb(), filter)
            .filter_map(|(h, _, world)| {
                let set = shapes_collide(geometry, &world);
                (set.count != 0).then_some((h, set))
            })
            .collect()
    }
}

/// False only when the box `bb`, grown by `radius`, lies strictly on one
/// side of the line through `a` and `b`: then no shape inside it can meet
/// the segment swept by a circle of `radius` (with the box overlap the
/// tree already tests, the separating-axis test of a segment and a box).
/// Exact: the side of each corner is the sign of an integer cross product
/// on the raw values; coordinates too far apart for 128 bits keep the box.
pub(super) fn line_may_touch(a: Vect, b: Vect, radius: Real, bb: &BB) -> bool {
    const LIMIT: i128 = 1 << 62;
    let g = bb.grow(radius.max(Real::ZERO));
    let raw = |r: Real| i128::from(r.to_bits());
    let (ax, ay) = (raw(a.x), raw(a.y));
    // Differences of i64 values in i128: never saturate.
    let (dx, dy) = (raw(b.x).saturating_sub(ax), raw(b.y).saturating_sub(ay));
    let corners = [(g.l, g.b), (g.r, g.b), (g.r, g.t), (g.l, g.t)];
    let mut above = false;
    let mut below = false;
    for (x, y) in corners {
        let (cx, cy) = (raw(x).saturating_sub(ax), raw(y).saturating_sub(ay));
        if [dx, dy, cx, cy].iter().any(|v| v.abs() >= LIMIT) {
            return true;
        }
        // |each product| < 2^124: never saturates.
        let side = dx.saturating_mul(cy).saturating_sub(dy.saturating_mul(cx));
        above |= side >= 0;
        below |= side <= 0;
    }
    above && below
}
