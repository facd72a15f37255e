//! Shape casts on the space (Box2D's and Rapier's shape casts; Chipmunk
//! has only the swept circle of its segment query): move a shape along a
//! straight translation and find what it touches first
//! ([`Space::shape_cast`]), everything it touches on the way
//! ([`Space::shape_cast_all`]), or the same for a shape of the space cast
//! from where its body is, ignoring that body ([`Space::shape_cast_from`],
//! [`Space::shape_cast_all_from`]). What a kinematic character needs to
//! move and slide without passing through anything.
//!
//! # What is cast
//! A [`ShapeCast`]: any geometry (circle, capsule, polygon, rounded
//! polygon, segment) in its own frame, placed by a position and a rotation
//! (it need not be in the space), and a translation. Only the translation
//! is swept: the shape does not turn on the way.
//!
//! # How
//! The shapes are found as the other queries find them
//! ([`query`](super::query)): through the broadphase when it is current,
//! else by a scan, each placed at its body's current pose. The box the
//! cast sweeps selects the candidates, and the static tree's walk skips
//! every node whose box the path of the cast shape's box cannot reach
//! (the separating-axis test of a segment and a box, on the node grown by
//! the cast shape's box). Each candidate is then cast exactly
//! ([`collision::shape_cast`](crate::collision::shape_cast): a ray against
//! the two shapes' Minkowski difference, in fixed point, with no iteration
//! and an exact judge of misses): a path that touches a shape is never
//! reported as a miss, and the reported fraction is never past the first
//! contact by more than [`CAST_TOLERANCE`](crate::collision::CAST_TOLERANCE)
//! of overlap (plus `2^-26` of the translation's length).
//!
//! # Semantics
//! * **Filter:** a shape is skipped when its filter and the cast's reject
//!   each other, as for every query ([`ShapeFilter::rejects`]); shapes of
//!   [`ShapeCast::ignore_body`] are skipped too.
//! * **Sensors** are reported by the "all" casts and skipped by the
//!   "first" ones, as for the segment queries: a sensor does not block a
//!   cast.
//! * **Start in contact:** a shape the cast shape already touches or
//!   overlaps is hit at fraction 0 with the normal of least penetration,
//!   or, with [`StartContact::HitIfApproaching`], only if the translation
//!   goes deeper into it (see [`StartContact`]).
//! * **Order:** the first hit is the one with the least fraction, the
//!   lowest shape handle on a tie; "all" hits are sorted by fraction, ties
//!   by handle. Nothing depends on a hash or an address.
//! * **A zero translation** is an overlap test: every shape the cast shape
//!   touches, at fraction 0.
use super::query::line_may_touch;
use super::{ShapeHandle, Space, SpaceError};
use crate::body::BodyHandle;
use crate::collision::{cast_entry, hit_point, shape_cast, ShapeCastInfo, StartContact};
use crate::math::{Real, Rot, Vect, BB};
use crate::shape::{Geometry, Shape, ShapeFilter};

/// A shape moved along a translation, for the casts of [`Space`]: the
/// query a character mover or a "will it fit" test asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShapeCast {
    /// The shape, in its own frame (body coordinates for a shape of the
    /// space).
    pub geometry: Geometry,
    /// Where the frame's origin is at the start.
    pub position: Vect,
    /// The frame's rotation (kept for the whole cast).
    pub rotation: Rot,
    /// The motion: the cast goes from `position` to `position + translation`.
    pub translation: Vect,
    /// Shapes of this body are never hit (a character's own body).
    pub ignore_body: Option<BodyHandle>,
    /// What happens with a shape it touches at the start.
    pub start: StartContact,
}

impl ShapeCast {
    /// A cast of `geometry` placed at `position` and `rotation`, moved by
    /// `translation`; no body ignored, [`StartContact::Hit`].
    pub fn new(geometry: Geometry, position: Vect, rotation: Rot, translation: Vect) -> ShapeCast {
        ShapeCast {
            geometry,
            position,
            rotation,
            translation,
            ignore_body: None,
            start: StartContact::Hit,
        }
    }

    /// The same cast, never hitting the shapes of `body`.
    pub fn ignoring_body(self, body: BodyHandle) -> ShapeCast {
        ShapeCast {
            ignore_body: Some(body),
            ..self
        }
    }

    /// The same cast with another rule for shapes touched at the start.
    pub fn with_start(self, start: StartContact) -> ShapeCast {
        ShapeCast { start, ..self }
    }

    /// The cast shape in world coordinates at the start (placed as the
    /// space places a shape on a body).
    pub fn start_geometry(&self) -> Geometry {
        self.geometry.to_world(self.position, self.rotation)
    }
}

/// The box `node` grown by how far the box `bb` reaches from its point
/// `c`: the box's translated copy meets `node` exactly when `c`, moved
/// the same way, lies in the grown box. Additions only: exact (saturating
/// far outside the range).
fn grown_by_box(node: &BB, bb: &BB, c: Vect) -> BB {
    BB {
        l: node.l - (bb.r - c.x),
        b: node.b - (bb.t - c.y),
        r: node.r + (c.x - bb.l),
        t: node.t + (c.y - bb.b),
    }
}

impl Space {
    /// The shapes a cast may touch, with their world geometry, in slot
    /// order (sensors included): through the broadphase as for the other
    /// queries, keeping the boxes the path of `start`'s box reaches.
    fn cast_candidates<'a>(
        &'a self,
        cast: &'a ShapeCast,
        start: &Geometry,
        filter: ShapeFilter,
    ) -> impl Iterator<Item = (ShapeHandle, &'a Shape, Geometry)> + 'a {
        let d = cast.translation;
        let bb = start.bb();
        let end = BB {
            l: bb.l + d.x,
            b: bb.b + d.y,
            r: bb.r + d.x,
            t: bb.t + d.y,
        };
        let c = bb.center();
        let reaches =
            move |node: &BB| line_may_touch(c, c + d, Real::ZERO, &grown_by_box(node, &bb, c));
        self.query_candidates_where(bb.merge(&end), reaches, filter)
            .filter(move |(_, shape, world)| {
                cast.ignore_body != Some(shape.body) && reaches(&world.bb())
            })
    }

    /// Box2D `b2World_CastShape` / Rapier `cast_shape`: the first shape the
    /// cast shape touches on its way (least fraction; the lowest handle on
    /// a tie), with where and how. Sensors are skipped.
    pub fn shape_cast(
        &self,
        cast: &ShapeCast,
        filter: ShapeFilter,
    ) -> Option<(ShapeHandle, ShapeCastInfo)> {
        let start = cast.start_geometry();
        let d = cast.translation;
        let mut best: Option<(ShapeHandle, Real, Vect, Geometry)> = None;
        for (h, _, world) in self
            .cast_candidates(cast, &start, filter)
            .filter(|(_, s, _)| !s.sensor)
        {
            let Some((fraction, normal)) = cast_entry(&start, d, &world, cast.start) else {
                continue;
            };
            // Strict: candidates come in slot (handle) order.
            if best.as_ref().is_none_or(|first| fraction < first.1) {
                best = Some((h, fraction, normal, world));
            }
        }
        // The point of the first hit only (the same as `shape_cast_all`'s).
        let (h, fraction, normal, world) = best?;
        let point = hit_point(&start, d, &world, fraction);
        Some((
            h,
            ShapeCastInfo {
                fraction,
                point,
                normal,
            },
        ))
    }

    /// Every shape the cast shape touches on its way, sorted by fraction
    /// (ties by handle). Sensors included.
    pub fn shape_cast_all(
        &self,
        cast: &ShapeCast,
        filter: ShapeFilter,
    ) -> Vec<(ShapeHandle, ShapeCastInfo)> {
        let start = cast.start_geometry();
        let mut hits: Vec<(ShapeHandle, ShapeCastInfo)> = self
            .cast_candidates(cast, &start, filter)
            .filter_map(|(h, _, world)| {
                shape_cast(&start, cast.translation, &world, cast.start).map(|hit| (h, hit))
            })
            .collect();
        // Stable: equal fractions stay in slot (handle) order.
        hits.sort_by_key(|(_, hit)| hit.fraction);
        hits
    }

    /// The cast of `shape` from where its body is now (position and
    /// rotation), moved by `translation`, ignoring the shapes of its own
    /// body: the starting point of [`shape_cast_from`](Self::shape_cast_from),
    /// to change before casting (the start rule, another body to ignore).
    /// Errors: a stale or foreign shape handle, or a shape whose body is
    /// gone.
    pub fn shape_cast_of(
        &self,
        shape: ShapeHandle,
        translation: Vect,
    ) -> Result<ShapeCast, SpaceError> {
        self.check_origin(shape)?;
        let s = self
            .state
            .shapes
            .get(shape)
            .ok_or(SpaceError::StaleShape(shape))?;
        let body = self
            .state
            .bodies
            .get(s.body)
            .ok_or(SpaceError::StaleBody(s.body))?;
        Ok(
            ShapeCast::new(*s.geometry(), body.position(), body.rotation(), translation)
                .ignoring_body(s.body),
        )
    }

    /// [`shape_cast`](Self::shape_cast) of a shape of the space from where
    /// its body is, ignoring its body's shapes (see
    /// [`shape_cast_of`](Self::shape_cast_of)): where a body's shape would
    /// first hit something if moved by `translation`.
    pub fn shape_cast_from(
        &self,
        shape: ShapeHandle,
        translation: Vect,
        filter: ShapeFilter,
    ) -> Result<Option<(ShapeHandle, ShapeCastInfo)>, SpaceError> {
        Ok(self.shape_cast(&self.shape_cast_of(shape, translation)?, filter))
    }

    /// [`shape_cast_all`](Self::shape_cast_all) of a shape of the space
    /// from where its body is, ignoring its body's shapes.
    pub fn shape_cast_all_from(
        &self,
        shape: ShapeHandle,
        translation: Vect,
        filter: ShapeFilter,
    ) -> Result<Vec<(ShapeHandle, ShapeCastInfo)>, SpaceError> {
        Ok(self.shape_cast_all(&self.shape_cast_of(shape, translation)?, filter))
    }
}
