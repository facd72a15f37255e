//! The MIS Shape module (§7): what a body collides with.
//!
//! A [`Shape`] is geometry ([`Geometry`]: circle, segment or convex polygon,
//! in body-local coordinates) plus the data every shape kind shares: the
//! owning body, material (friction, elasticity, surface velocity), collision
//! filter and type, sensor flag, and mass or density.
//!
//! Constructors follow the MIS/Chipmunk names (`circle_shape_new`,
//! `segment_shape_new`, `poly_shape_new`, `poly_shape_new_raw`,
//! `box_shape_new`, `box_shape_new2`; `capsule` names a rounded segment) and
//! validate their input: bad input is a [`ShapeError`], never a panic.
pub mod chain;
mod error;
pub mod geometry;
pub mod hull;
pub mod mass;
pub mod poly;
pub mod query;
mod reach;

use serde::{Deserialize, Serialize};

pub use chain::{Chain, ChainKind};
pub use error::{ChainError, ShapeError, MAX_POLY_VERTICES};
pub use geometry::{Circle, Geometry, Poly, Segment, ShapeKind};

use crate::arena::Handle;
use crate::body::BodyHandle;
use crate::compact;
use crate::math::{Real, Vect, BB};

/// A collision type: selects collision handlers (MIS `CollisionType`).
pub type CollisionType = u32;

/// Handle of a shape in a [`Space`](crate::space::Space) (also exported as
/// `space::ShapeHandle`).
pub type ShapeHandle = Handle<Shape>;

/// The wildcard collision type (Chipmunk `CP_WILDCARD_COLLISION_TYPE`, `~0`).
pub const WILDCARD_COLLISION_TYPE: CollisionType = u32::MAX;

/// Collision filter (Chipmunk `cpShapeFilter`). Two shapes are rejected if
/// they share a non-zero `group`, or if either one's `categories` misses the
/// other's `mask`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ShapeFilter {
    /// Shapes in the same non-zero group never collide.
    pub group: u32,
    /// Bits: the categories this shape belongs to.
    pub categories: u32,
    /// Bits: the categories this shape collides with.
    pub mask: u32,
}

impl ShapeFilter {
    /// Collides with everything (Chipmunk `CP_SHAPE_FILTER_ALL`).
    pub const ALL: ShapeFilter = ShapeFilter {
        group: 0,
        categories: u32::MAX,
        mask: u32::MAX,
    };
    /// Collides with nothing (Chipmunk `CP_SHAPE_FILTER_NONE`).
    pub const NONE: ShapeFilter = ShapeFilter {
        group: 0,
        categories: 0,
        mask: 0,
    };

    /// True if the filters reject the pair.
    #[inline]
    pub fn rejects(&self, other: &ShapeFilter) -> bool {
        (self.group != 0 && self.group == other.group)
            || (self.categories & other.mask) == 0
            || (other.categories & self.mask) == 0
    }
}

impl Default for ShapeFilter {
    fn default() -> Self {
        ShapeFilter::ALL
    }
}

/// Surface material: the arbiter multiplies the two shapes' values.
///
/// Valid ranges (checked by [`Material::validate`] wherever a material
/// enters a space: `Space::add_shape`, `Space::modify_shape`,
/// [`Shape::with_material`] and snapshot validation): friction ≥ 0 (a
/// negative friction would push a sliding body forward); elasticity in
/// [0, 1] (Chipmunk accepts more, but above 1 every bounce adds energy
/// without bound; 1 is a perfect bounce); any surface velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Material {
    /// Coulomb friction coefficient, ≥ 0.
    pub friction: Real,
    /// Restitution (elasticity), in [0, 1]; 1 is a perfect bounce.
    pub elasticity: Real,
    /// Surface velocity (conveyor belts), in world coordinates.
    pub surface_velocity: Vect,
}

impl Material {
    /// Checks the ranges: friction ≥ 0 ([`ShapeError::Negative`]),
    /// elasticity in [0, 1] ([`ShapeError::Negative`],
    /// [`ShapeError::AboveOne`]); every surface velocity is valid.
    pub fn validate(&self) -> Result<(), ShapeError> {
        if self.friction.is_negative() {
            return Err(ShapeError::Negative("friction"));
        }
        if self.elasticity.is_negative() {
            return Err(ShapeError::Negative("elasticity"));
        }
        if self.elasticity > Real::ONE {
            return Err(ShapeError::AboveOne("elasticity"));
        }
        Ok(())
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            friction: Real::ZERO,
            elasticity: Real::ZERO,
            surface_velocity: Vect::ZERO,
        }
    }
}

/// Mass properties of a shape (Chipmunk `cpShapeMassInfo`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MassInfo {
    /// Mass.
    pub mass: Real,
    /// Moment of inertia per unit mass about the centroid.
    pub moment_per_mass: Real,
    /// Centroid in body coordinates.
    pub cog: Vect,
    /// Area (including the rounding radius).
    pub area: Real,
}

/// How the shape's mass is given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MassSpec {
    /// Massless (static terrain, or a body whose mass is set explicitly).
    None,
    /// A fixed mass.
    Mass(Real),
    /// Mass = density · area.
    Density(Real),
}

/// A collision shape attached to a body.
///
/// Serde: a binary serializer (snapshots) gets the compact form of
/// [`snapshot`](crate::snapshot) format version 6 (see the `Serialize`
/// impl); a human-readable one every field, as a derive would.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Shape {
    pub(crate) body: BodyHandle,
    pub(crate) geometry: Geometry,
    /// Friction, elasticity and surface velocity.
    pub material: Material,
    /// Collision filter.
    pub filter: ShapeFilter,
    /// Selects the collision handler.
    pub collision_type: CollisionType,
    /// Sensors report contacts to handlers but never push bodies apart.
    pub sensor: bool,
    pub(crate) mass_spec: MassSpec,
}

/// The field-by-field serde form of [`Shape`] (a derive's), used for
/// human-readable formats.
#[derive(Serialize, Deserialize)]
#[serde(remote = "Shape", rename = "Shape")]
struct ShapeFields {
    body: BodyHandle,
    geometry: Geometry,
    material: Material,
    filter: ShapeFilter,
    collision_type: CollisionType,
    sensor: bool,
    mass_spec: MassSpec,
}

/// Words of the compact form (bit `i` of the head is word `i`): friction,
/// elasticity, surface velocity (x, y), the mass or density.
const SHAPE_WORDS: usize = 5;
/// Head bits above the presence mask: the mass specification's kind (2
/// bits: none, mass, density), then one bit each.
const SHAPE_MASS_SHIFT: u32 = 8;
const SHAPE_SENSOR: u32 = 1 << 10;
const SHAPE_FILTER: u32 = 1 << 11;
const SHAPE_COLLISION_TYPE: u32 = 1 << 12;
const SHAPE_HEAD: u32 = ((1 << SHAPE_WORDS) - 1)
    | (3 << SHAPE_MASS_SHIFT)
    | SHAPE_SENSOR
    | SHAPE_FILTER
    | SHAPE_COLLISION_TYPE;

/// Binary (snapshot format 6): a tuple of
/// * a `u32` head: bits 0..5 the presence mask of the words below, bits
///   8–9 the mass specification (0 none, 1 mass, 2 density), bit 10
///   `sensor`, bit 11 "filter stored", bit 12 "collision type stored";
/// * the body handle (slot, generation: two `u32`);
/// * the filter (group, categories, mask: three `u32`) unless it is
///   [`ShapeFilter::ALL`], and the collision type (`u32`) unless it is 0;
/// * the non-zero words as raw `i64`: friction, elasticity, surface
///   velocity (x, y), the mass or density (never present without one);
/// * the geometry in its compact form ([`Geometry`]'s `Serialize`).
///
/// A shape caches nothing: every field is stored (the defaults, left out,
/// come back as the values they stand for). Human-readable: the derive's
/// form.
impl Serialize for Shape {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        if s.is_human_readable() {
            return ShapeFields::serialize(self, s);
        }
        let (kind, spec): (u32, Real) = match self.mass_spec {
            MassSpec::None => (0, Real::ZERO),
            MassSpec::Mass(m) => (1, m),
            MassSpec::Density(d) => (2, d),
        };
        let m = &self.material;
        let words = [
            m.friction,
            m.elasticity,
            m.surface_velocity.x,
            m.surface_velocity.y,
            spec,
        ];
        let mask = compact::mask_of(&words);
        let filter = self.filter != ShapeFilter::ALL;
        let collision_type = self.collision_type != 0;
        let flag = |on: bool, bit: u32| if on { bit } else { 0 };
        let head = mask
            | kind << SHAPE_MASS_SHIFT
            | flag(self.sensor, SHAPE_SENSOR)
            | flag(filter, SHAPE_FILTER)
            | flag(collision_type, SHAPE_COLLISION_TYPE);
        let len = compact::count(mask)
            .saturating_add(usize::from(filter))
            .saturating_add(usize::from(collision_type))
            .saturating_add(3);
        let mut t = compact::tuple(s, len)?;
        t.serialize_element(&head)?;
        t.serialize_element(&self.body)?;
        if filter {
            t.serialize_element(&self.filter)?;
        }
        if collision_type {
            t.serialize_element(&self.collision_type)?;
        }
        compact::write_words(&mut t, &words, mask, 0)?;
        t.serialize_element(&self.geometry)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for Shape {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Shape, D::Error> {
        if d.is_human_readable() {
            ShapeFields::deserialize(d)
        } else {
            compact::deserialize(d)
        }
    }
}

impl compact::Compact for Shape {
    const EXPECTING: &'static str = "a compact shape";
    const MAX_ELEMENTS: usize = 5 + SHAPE_WORDS;

    fn read<'de, A: serde::de::SeqAccess<'de>>(
        r: &mut compact::Reader<'de, A>,
    ) -> Result<Shape, A::Error> {
        let head: u32 = r.next()?;
        r.check_head(head, SHAPE_HEAD)?;
        let body: BodyHandle = r.next()?;
        let filter = if head & SHAPE_FILTER != 0 {
            let f: ShapeFilter = r.next()?;
            if f == ShapeFilter::ALL {
                return Err(r.error("the default filter stored"));
            }
            f
        } else {
            ShapeFilter::ALL
        };
        let collision_type = if head & SHAPE_COLLISION_TYPE != 0 {
            let c: CollisionType = r.next()?;
            if c == 0 {
                return Err(r.error("collision type 0 stored"));
            }
            c
        } else {
            0
        };
        let mut w = [Real::ZERO; SHAPE_WORDS];
        r.words(head, None, &mut w)?;
        let [friction, elasticity, sv_x, sv_y, spec] = w;
        let mass_spec = match (head >> SHAPE_MASS_SHIFT) & 3 {
            0 if spec.is_zero() => MassSpec::None,
            1 => MassSpec::Mass(spec),
            2 => MassSpec::Density(spec),
            _ => return Err(r.error("bad mass specification")),
        };
        let geometry: Geometry = r.next()?;
        Ok(Shape {
            body,
            geometry,
            material: Material {
                friction,
                elasticity,
                surface_velocity: Vect::new(sv_x, sv_y),
            },
            filter,
            collision_type,
            sensor: head & SHAPE_SENSOR != 0,
            mass_spec,
        })
    }
}

impl Shape {
    /// A shape from validated geometry with default material and filter.
    pub(crate) fn from_geometry(body: BodyHandle, geometry: Geometry) -> Shape {
        Shape {
            body,
            geometry,
            material: Material::default(),
            filter: ShapeFilter::ALL,
            collision_type: 0,
            sensor: false,
            mass_spec: MassSpec::None,
        }
    }

    /// A shape from geometry that passed its constructor's checks, after the
    /// extent rule ([`Geometry::check_extent`]).
    pub(crate) fn checked(body: BodyHandle, geometry: Geometry) -> Result<Shape, ShapeError> {
        geometry.check_extent()?;
        Ok(Shape::from_geometry(body, geometry))
    }

    /// Replaces the geometry if it obeys the extent rule; otherwise leaves
    /// the shape unchanged.
    pub(crate) fn replace_geometry(&mut self, geometry: Geometry) -> Result<(), ShapeError> {
        geometry.check_extent()?;
        self.geometry = geometry;
        Ok(())
    }

    /// MIS `circleShapeNew`: a circle of `radius` centred at `offset` (body
    /// coordinates). Errors on a negative radius, and on a circle outside
    /// the extent rule ([`Geometry::check_extent`]: radius below 2^30 m).
    pub fn circle_shape_new(
        body: BodyHandle,
        radius: Real,
        offset: Vect,
    ) -> Result<Shape, ShapeError> {
        check_radius(radius)?;
        Shape::checked(body, Geometry::Circle(Circle::new(radius, offset)))
    }

    /// Chipmunk `segmentShapeNew`: a segment (capsule) from `a` to `b`.
    /// Errors on a negative radius and outside the extent rule
    /// ([`Geometry::check_extent`]).
    pub fn segment_shape_new(
        body: BodyHandle,
        a: Vect,
        b: Vect,
        radius: Real,
    ) -> Result<Shape, ShapeError> {
        check_radius(radius)?;
        Shape::checked(body, Geometry::Segment(Segment::new(a, b, radius)))
    }

    /// A capsule: the segment from `a` to `b` (body coordinates) rounded by
    /// `radius`, the usual shape of a walking character: its round ends
    /// have no corner to catch on steps and seams. A named form of [`segment_shape_new`](Self::segment_shape_new):
    /// the same shape, with the same errors. Its area is
    /// [`area_for_capsule`](mass::area_for_capsule); its exact moment
    /// [`moment_for_capsule`](mass::moment_for_capsule) (a shape's
    /// automatic mass keeps Chipmunk's box approximation of a segment, see
    /// there). A radius of 0 gives a sharp segment.
    pub fn capsule(body: BodyHandle, a: Vect, b: Vect, radius: Real) -> Result<Shape, ShapeError> {
        Shape::segment_shape_new(body, a, b, radius)
    }

    /// The body the shape is attached to.
    pub fn body(&self) -> BodyHandle {
        self.body
    }

    /// The local geometry.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The kind of geometry.
    pub fn kind(&self) -> ShapeKind {
        self.geometry.kind()
    }

    /// Bounding box of the local geometry.
    pub fn local_bb(&self) -> BB {
        self.geometry.bb()
    }

    /// MIS `get_center` for circles / `circleShapeGetOffset`: the circle's centre offset.
    pub fn circle_offset(&self) -> Result<Vect, ShapeError> {
        match &self.geometry {
            Geometry::Circle(c) => Ok(c.offset),
            Geometry::Segment(_) | Geometry::Poly(_) => Err(ShapeError::NotCircleShape),
        }
    }

    /// MIS `circleShapeGetRadius`.
    pub fn circle_radius(&self) -> Result<Real, ShapeError> {
        match &self.geometry {
            Geometry::Circle(c) => Ok(c.radius),
            Geometry::Segment(_) | Geometry::Poly(_) => Err(ShapeError::NotCircleShape),
        }
    }

    /// MIS `circleShapeSetRadius` (Chipmunk's unsafe setter, made safe): the
    /// owning body's mass is recomputed by the space.
    pub fn set_circle_radius(&mut self, radius: Real) -> Result<(), ShapeError> {
        check_radius(radius)?;
        match self.geometry {
            Geometry::Circle(c) => self.replace_geometry(Geometry::Circle(Circle { radius, ..c })),
            Geometry::Segment(_) | Geometry::Poly(_) => Err(ShapeError::NotCircleShape),
        }
    }

    /// Chipmunk `circleShapeSetOffset` (extent rule as the constructor).
    pub fn set_circle_offset(&mut self, offset: Vect) -> Result<(), ShapeError> {
        match self.geometry {
            Geometry::Circle(c) => self.replace_geometry(Geometry::Circle(Circle { offset, ..c })),
            Geometry::Segment(_) | Geometry::Poly(_) => Err(ShapeError::NotCircleShape),
        }
    }

    /// The segment geometry.
    pub fn segment(&self) -> Result<&Segment, ShapeError> {
        match &self.geometry {
            Geometry::Segment(s) => Ok(s),
            Geometry::Circle(_) | Geometry::Poly(_) => Err(ShapeError::NotSegmentShape),
        }
    }

    /// Chipmunk `segmentShapeSetEndpoints`.
    /// Errors outside the extent rule, leaving the shape unchanged.
    pub fn set_segment_endpoints(&mut self, a: Vect, b: Vect) -> Result<(), ShapeError> {
        match self.geometry {
            Geometry::Segment(s) => self.replace_geometry(Geometry::Segment(Segment {
                a_tangent: s.a_tangent,
                b_tangent: s.b_tangent,
                ..Segment::new(a, b, s.radius)
            })),
            Geometry::Circle(_) | Geometry::Poly(_) => Err(ShapeError::NotSegmentShape),
        }
    }

    /// Chipmunk `segmentShapeSetRadius` (extent rule as the constructor).
    pub fn set_segment_radius(&mut self, radius: Real) -> Result<(), ShapeError> {
        check_radius(radius)?;
        match self.geometry {
            Geometry::Segment(s) => {
                self.replace_geometry(Geometry::Segment(Segment { radius, ..s }))
            }
            Geometry::Circle(_) | Geometry::Poly(_) => Err(ShapeError::NotSegmentShape),
        }
    }

    /// Chipmunk `segmentShapeSetNeighbors`: `prev` joins at `a`, `next` at `b`
    /// (smooth terrain: no catching on the seams).
    pub fn set_segment_neighbors(&mut self, prev: Vect, next: Vect) -> Result<(), ShapeError> {
        match &mut self.geometry {
            Geometry::Segment(s) => {
                *s = s.with_neighbors(prev, next);
                Ok(())
            }
            Geometry::Circle(_) | Geometry::Poly(_) => Err(ShapeError::NotSegmentShape),
        }
    }

    /// Gives the shape a fixed mass (Chipmunk `cpShapeSetMass`).
    pub fn set_mass(&mut self, mass: Real) -> Result<(), ShapeError> {
        if mass.is_negative() {
            return Err(ShapeError::Negative("mass"));
        }
        self.mass_spec = MassSpec::Mass(mass);
        Ok(())
    }

    /// Gives the shape a density; mass = density · area (Chipmunk `cpShapeSetDensity`).
    pub fn set_density(&mut self, density: Real) -> Result<(), ShapeError> {
        if density.is_negative() {
            return Err(ShapeError::Negative("density"));
        }
        self.mass_spec = MassSpec::Density(density);
        Ok(())
    }

    /// How the mass is specified.
    pub fn mass_spec(&self) -> MassSpec {
        self.mass_spec
    }

    /// Builder form of the material setters.
    /// Errors as [`Material::validate`].
    pub fn with_material(mut self, friction: Real, elasticity: Real) -> Result<Shape, ShapeError> {
        let material = Material {
            friction,
            elasticity,
            ..self.material
        };
        material.validate()?;
        self.material = material;
        Ok(self)
    }
}

fn check_radius(radius: Real) -> Result<(), ShapeError> {
    if radius.is_negative() {
        Err(ShapeError::Negative("radius"))
    } else {
        Ok(())
    }
}

/// Every field, the small ones packed into words (filter and collision
/// type; sensor flag and mass kind with the geometry's kind), then the
/// numbers: the checksum costs per word, and a shape is hashed every frame.
impl core::hash::Hash for Shape {
    #[inline(always)]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Shape {
            body,
            geometry,
            material:
                Material {
                    friction,
                    elasticity,
                    surface_velocity,
                },
            filter:
                ShapeFilter {
                    group,
                    categories,
                    mask,
                },
            collision_type,
            sensor,
            mass_spec,
        } = self;
        let (mass_kind, mass_value): (u64, Real) = match mass_spec {
            MassSpec::None => (0, Real::ZERO),
            MassSpec::Mass(m) => (1, *m),
            MassSpec::Density(d) => (2, *d),
        };
        body.hash(h);
        mass_value.hash(h);
        h.write_u64(u64::from(*group) | u64::from(*categories) << 32);
        h.write_u64(u64::from(*mask) | u64::from(*collision_type) << 32);
        friction.hash(h);
        elasticity.hash(h);
        surface_velocity.hash(h);
        geometry.hash_with_tag(h, mass_kind | u64::from(*sensor) << 2);
    }
}
