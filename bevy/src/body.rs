//! The components that declare a body and its collider.
//!
//! Both are declarations with a link: what to build, and (once built) the
//! handle in the space. The link is what lets rollback restore a component
//! without building it again.
use bevy_ecs::component::Component;
use bevy_transform::components::Transform;
use tamias2d::body::{Body, BodyHandle, BodyType};
use tamias2d::math::Transform as Placement;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::{CollisionType, Shape, ShapeFilter, ShapeHandle};

use crate::hooks;

/// A rigid body, built into [`Physics`](crate::Physics)' space when the
/// component is inserted, removed from it when the component is removed or
/// the entity despawned.
///
/// The values here are the body's *initial* state: once built, the space
/// owns the body (move it through [`Physics`](crate::Physics)); the
/// component keeps the handle ([`RigidBody::handle`]).
#[derive(Component, Clone, Debug, PartialEq)]
#[component(on_add = hooks::body_added, on_remove = hooks::body_removed)]
#[require(Transform)]
pub struct RigidBody {
    pub(crate) body_type: BodyType,
    pub(crate) position: Vect,
    pub(crate) angle: Real,
    pub(crate) velocity: Vect,
    pub(crate) angular_velocity: Real,
    /// Explicit mass and moment; `None` sums them from the colliders'
    /// densities.
    pub(crate) mass: Option<(Real, Real)>,
    pub(crate) handle: Option<BodyHandle>,
}

impl RigidBody {
    fn of_type(body_type: BodyType) -> RigidBody {
        RigidBody {
            body_type,
            position: Vect::ZERO,
            angle: Real::ZERO,
            velocity: Vect::ZERO,
            angular_velocity: Real::ZERO,
            mass: None,
            handle: None,
        }
    }

    /// A dynamic body: its mass and moment come from its collider's density
    /// unless [`with_mass`](Self::with_mass) sets them.
    pub fn dynamic() -> RigidBody {
        RigidBody::of_type(BodyType::Dynamic)
    }

    /// A kinematic body: moved by its velocity, pushes dynamic bodies,
    /// nothing pushes it.
    pub fn kinematic() -> RigidBody {
        RigidBody::of_type(BodyType::Kinematic)
    }

    /// A static body: never moves (the level).
    pub fn fixed() -> RigidBody {
        RigidBody::of_type(BodyType::Static)
    }

    /// Placed at `position` (world units, fixed point).
    pub fn at(mut self, position: Vect) -> RigidBody {
        self.position = position;
        self
    }

    /// Turned by `angle` radians.
    pub fn with_angle(mut self, angle: Real) -> RigidBody {
        self.angle = angle;
        self
    }

    /// Starting with this velocity.
    pub fn with_velocity(mut self, velocity: Vect) -> RigidBody {
        self.velocity = velocity;
        self
    }

    /// Starting with this angular velocity (radians per second).
    pub fn with_angular_velocity(mut self, angular_velocity: Real) -> RigidBody {
        self.angular_velocity = angular_velocity;
        self
    }

    /// An explicit mass and moment (dynamic bodies); a zero moment with a
    /// positive mass is fixed rotation.
    pub fn with_mass(mut self, mass: Real, moment: Real) -> RigidBody {
        self.mass = Some((mass, moment));
        self
    }

    /// The body's handle in the space, once built (`None` before, or if
    /// building failed: see [`PhysicsErrors`](crate::PhysicsErrors)).
    pub fn handle(&self) -> Option<BodyHandle> {
        self.handle
    }

    /// The body this declaration describes, not yet in a space.
    pub(crate) fn to_body(&self) -> Result<Body, String> {
        let mut body = match self.body_type {
            BodyType::Dynamic => {
                let (mass, moment) = self.mass.unwrap_or((Real::ZERO, Real::ZERO));
                Body::new(mass, moment).map_err(|e| e.to_string())?
            }
            BodyType::Kinematic => Body::new_kinematic(),
            BodyType::Static => Body::new_static(),
        };
        body.set_position(self.position);
        body.set_angle(self.angle);
        body.set_velocity(self.velocity);
        body.set_angular_velocity(self.angular_velocity);
        Ok(body)
    }
}

/// The geometry of one part of a [`Collider`], in the body's frame.
#[derive(Clone, Debug, PartialEq)]
pub enum ColliderShape {
    /// A circle of `radius` centred at `offset`.
    Circle {
        /// Radius.
        radius: Real,
        /// Centre in the body's frame.
        offset: Vect,
    },
    /// A box `width` × `height` centred on the body, corners rounded by
    /// `radius`.
    Box {
        /// Full width.
        width: Real,
        /// Full height.
        height: Real,
        /// Corner radius.
        radius: Real,
    },
    /// The convex hull of `points`, rounded by `radius`.
    Polygon {
        /// Points (their hull is taken).
        points: Vec<Vect>,
        /// Corner radius.
        radius: Real,
    },
    /// A segment from `a` to `b`, `radius` thick.
    Segment {
        /// First end.
        a: Vect,
        /// Second end.
        b: Vect,
        /// Thickness (a radius).
        radius: Real,
    },
    /// A capsule: the segment `a`–`b` grown by `radius`.
    Capsule {
        /// First end of the core segment.
        a: Vect,
        /// Second end of the core segment.
        b: Vect,
        /// Radius.
        radius: Real,
    },
}

/// The shapes of a body and their material. Sits on the same entity as
/// its [`RigidBody`]; built with it, or attached to it when inserted later.
///
/// Defaults: density 1, friction 0.6, elasticity 0, solid, collides with
/// everything.
#[derive(Component, Clone, Debug, PartialEq)]
#[component(on_add = hooks::collider_added, on_remove = hooks::collider_removed)]
pub struct Collider {
    pub(crate) parts: Vec<ColliderShape>,
    pub(crate) density: Real,
    pub(crate) friction: Real,
    pub(crate) elasticity: Real,
    pub(crate) sensor: bool,
    pub(crate) filter: ShapeFilter,
    pub(crate) collision_type: CollisionType,
    pub(crate) handles: Vec<ShapeHandle>,
}

impl Collider {
    /// A collider made of these parts (a compound shape).
    pub fn compound(parts: Vec<ColliderShape>) -> Collider {
        Collider {
            parts,
            density: Real::ONE,
            friction: Real::ratio(3, 5),
            elasticity: Real::ZERO,
            sensor: false,
            filter: ShapeFilter::ALL,
            collision_type: 0,
            handles: Vec::new(),
        }
    }

    /// A circle centred on the body.
    pub fn circle(radius: Real) -> Collider {
        Collider::compound(vec![ColliderShape::Circle {
            radius,
            offset: Vect::ZERO,
        }])
    }

    /// A `width` × `height` box centred on the body.
    pub fn rectangle(width: Real, height: Real) -> Collider {
        Collider::compound(vec![ColliderShape::Box {
            width,
            height,
            radius: Real::ZERO,
        }])
    }

    /// The convex hull of `points`, rounded by `radius`.
    pub fn polygon(points: Vec<Vect>, radius: Real) -> Collider {
        Collider::compound(vec![ColliderShape::Polygon { points, radius }])
    }

    /// A segment `radius` thick (ground, walls).
    pub fn segment(a: Vect, b: Vect, radius: Real) -> Collider {
        Collider::compound(vec![ColliderShape::Segment { a, b, radius }])
    }

    /// A capsule around the segment `a`–`b`.
    pub fn capsule(a: Vect, b: Vect, radius: Real) -> Collider {
        Collider::compound(vec![ColliderShape::Capsule { a, b, radius }])
    }

    /// Mass per unit area (dynamic bodies without an explicit mass).
    pub fn with_density(mut self, density: Real) -> Collider {
        self.density = density;
        self
    }

    /// Friction and elasticity.
    pub fn with_material(mut self, friction: Real, elasticity: Real) -> Collider {
        self.friction = friction;
        self.elasticity = elasticity;
        self
    }

    /// A sensor: reports contacts, never collides.
    pub fn sensor(mut self) -> Collider {
        self.sensor = true;
        self
    }

    /// Which shapes it collides with.
    pub fn with_filter(mut self, filter: ShapeFilter) -> Collider {
        self.filter = filter;
        self
    }

    /// The collision type its contacts are reported with.
    pub fn with_collision_type(mut self, collision_type: CollisionType) -> Collider {
        self.collision_type = collision_type;
        self
    }

    /// The shapes' handles in the space, once built (empty before).
    pub fn handles(&self) -> &[ShapeHandle] {
        &self.handles
    }

    /// The shapes this declaration describes, on `body`, not yet in a
    /// space. The first invalid part is an error naming it.
    pub(crate) fn to_shapes(&self, body: BodyHandle) -> Result<Vec<Shape>, String> {
        let mut shapes = Vec::with_capacity(self.parts.len());
        for (i, part) in self.parts.iter().enumerate() {
            let shape = match part {
                ColliderShape::Circle { radius, offset } => {
                    Shape::circle_shape_new(body, *radius, *offset)
                }
                ColliderShape::Box {
                    width,
                    height,
                    radius,
                } => Shape::box_shape_new(body, *width, *height, *radius),
                ColliderShape::Polygon { points, radius } => {
                    Shape::poly_shape_new(body, points, &Placement::IDENTITY, *radius)
                }
                ColliderShape::Segment { a, b, radius } => {
                    Shape::segment_shape_new(body, *a, *b, *radius)
                }
                ColliderShape::Capsule { a, b, radius } => Shape::capsule(body, *a, *b, *radius),
            };
            let mut shape = shape
                .and_then(|s| s.with_material(self.friction, self.elasticity))
                .map_err(|e| format!("collider part {i}: {e}"))?;
            shape
                .set_density(self.density)
                .map_err(|e| format!("collider part {i}: {e}"))?;
            shape.sensor = self.sensor;
            shape.filter = self.filter;
            shape.collision_type = self.collision_type;
            shapes.push(shape);
        }
        Ok(shapes)
    }
}
