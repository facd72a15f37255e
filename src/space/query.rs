//! Space-level queries (MIS/Chipmunk `spacePointQuery`,
//! `spacePointQueryNearest`, `spaceSegmentQuery`, `spaceSegmentQueryFirst`,
//! `spaceBBQuery`, `spaceShapeQuery`): which shapes are near a point, on a
//! ray, in a box or touching a shape.
//!
//! # How
//! A linear scan over the shapes in slot order: each shape's world geometry
//! is computed from its body's *current* position and rotation (so queries
//! work before the first step and after a body is moved by hand, when the
//! step's cache is stale), its bounding box is tested against the query's
//! box, and only then the exact geometry query ([`crate::shape::query`]) or
//! the narrowphase ([`shapes_collide`]) runs. Queries are not part of the
//! step, so a linear scan is acceptable; the cost is one rigid transform per
//! shape accepted by the filter.
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
        let bodies = &self.state.bodies;
        self.state.shapes.iter().filter_map(move |(h, shape)| {
            if shape.filter.rejects(&filter) {
                return None;
            }
            let body = bodies.get(shape.body)?;
            let world = shape.geometry().to_world(body.position(), body.rotation());
            world.bb().intersects(&bb).then_some((h, shape, world))
        })
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
            .query_candidates(bb, filter)
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
            .query_candidates(bb, filter)
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
