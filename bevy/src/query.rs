//! Queries as a system parameter: hits name the entity they found.
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use tamias2d::collision::ShapeCastInfo;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::query::{PointQueryInfo, SegmentQueryInfo};
use tamias2d::shape::{ShapeFilter, ShapeHandle};
use tamias2d::space::{ShapeCast, Space};

use crate::physics::Physics;

/// A ray (or thick segment) hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The entity owning the shape hit (`None` for a body without one).
    pub entity: Option<Entity>,
    /// The shape hit.
    pub shape: ShapeHandle,
    /// Where, the surface normal, and the fraction along the ray.
    pub info: SegmentQueryInfo,
}

/// A shape-cast hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CastHit {
    /// The entity owning the shape hit.
    pub entity: Option<Entity>,
    /// The shape hit.
    pub shape: ShapeHandle,
    /// The fraction of the translation, the point and the normal.
    pub info: ShapeCastInfo,
}

/// The nearest shape to a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointHit {
    /// The entity owning the shape.
    pub entity: Option<Entity>,
    /// The shape.
    pub shape: ShapeHandle,
    /// The nearest surface point and the (signed) distance.
    pub info: PointQueryInfo,
}

/// Read-only queries on the physics world, for any system:
/// `fn aim(query: PhysicsQuery) { query.ray_first(…) }`. Every other query
/// of [`Space`] is one call away through [`space`](Self::space).
#[derive(SystemParam)]
pub struct PhysicsQuery<'w> {
    physics: Res<'w, Physics>,
}

impl PhysicsQuery<'_> {
    /// The space, for every query it has.
    pub fn space(&self) -> &Space {
        self.physics.space()
    }

    /// The physics resource (entity lookups).
    pub fn physics(&self) -> &Physics {
        &self.physics
    }

    /// The first solid shape a segment from `from` to `to`, `radius` thick,
    /// touches.
    pub fn ray_first(
        &self,
        from: Vect,
        to: Vect,
        radius: Real,
        filter: ShapeFilter,
    ) -> Option<RayHit> {
        let (shape, info) = self.space().segment_query_first(from, to, radius, filter)?;
        Some(RayHit {
            entity: self.physics.entity_of_shape(shape),
            shape,
            info,
        })
    }

    /// Every shape the segment touches, nearest first.
    pub fn ray_all(&self, from: Vect, to: Vect, radius: Real, filter: ShapeFilter) -> Vec<RayHit> {
        self.space()
            .segment_query(from, to, radius, filter)
            .into_iter()
            .map(|(shape, info)| RayHit {
                entity: self.physics.entity_of_shape(shape),
                shape,
                info,
            })
            .collect()
    }

    /// The first solid shape `cast` touches on its way.
    pub fn shape_cast(&self, cast: &ShapeCast, filter: ShapeFilter) -> Option<CastHit> {
        let (shape, info) = self.space().shape_cast(cast, filter)?;
        Some(CastHit {
            entity: self.physics.entity_of_shape(shape),
            shape,
            info,
        })
    }

    /// The nearest solid shape within `max_distance` of `point`.
    pub fn point_nearest(
        &self,
        point: Vect,
        max_distance: Real,
        filter: ShapeFilter,
    ) -> Option<PointHit> {
        let (shape, info) = self
            .space()
            .point_query_nearest(point, max_distance, filter)?;
        Some(PointHit {
            entity: self.physics.entity_of_shape(shape),
            shape,
            info,
        })
    }
}
