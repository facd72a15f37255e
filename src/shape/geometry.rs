//! Shape geometry: circle, segment and convex polygon, in body-local space or
//! (after [`Geometry::to_world`]) in world space.
//!
//! Geometry is a small `Copy` value with inline vertex storage (at most
//! [`MAX_POLY_VERTICES`]): moving shapes into world space each step allocates
//! nothing, and snapshots hold plain values.
use core::hash::Hash;

use serde::{Deserialize, Serialize};

use super::ShapeError;
use crate::math::{Real, Rot, Vect, BB};

/// The most vertices a polygon may have (Box2D uses the same bound). Inline
/// storage keeps geometry `Copy` and the per-step world-space update free of
/// allocation; rounder shapes are better made of circles or rounded polygons.
pub const MAX_POLY_VERTICES: usize = 8;

/// A circle: centre offset from the body origin and radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Circle {
    /// Centre, in body coordinates (world coordinates once transformed).
    pub offset: Vect,
    /// Radius, ≥ 0.
    pub radius: Real,
}

/// A segment from `a` to `b` with a rounding radius (a capsule when r > 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Segment {
    /// First endpoint.
    pub a: Vect,
    /// Second endpoint.
    pub b: Vect,
    /// Unit normal, `rperp(b − a)` normalised (Chipmunk's convention: the
    /// right-hand side of a → b). Zero for a zero-length segment.
    pub normal: Vect,
    /// Rounding radius, ≥ 0.
    pub radius: Real,
    /// Tangent towards the previous neighbour (`prev − a`), or zero if none.
    /// Contacts whose normal points into a neighbour are rejected, so a chain
    /// of segments behaves like smooth terrain.
    pub a_tangent: Vect,
    /// Tangent towards the next neighbour (`next − b`), or zero if none.
    pub b_tangent: Vect,
}

/// A convex polygon with counter-clockwise vertices and a rounding radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Poly {
    /// Number of used entries of `verts`/`normals` (3..=MAX_POLY_VERTICES).
    pub(crate) count: u8,
    /// Vertices, counter-clockwise; entries past `count` are zero.
    pub(crate) verts: [Vect; MAX_POLY_VERTICES],
    /// `normals[i]` is the outward unit normal of edge `verts[i] → verts[i+1]`.
    pub(crate) normals: [Vect; MAX_POLY_VERTICES],
    /// Rounding radius, ≥ 0.
    pub(crate) radius: Real,
}

/// The geometry of one shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Geometry {
    /// A circle.
    Circle(Circle),
    /// A segment (capsule).
    Segment(Segment),
    /// A convex polygon.
    Poly(Poly),
}

/// The kind (and a polygon's vertex count) in one word, then the fields.
impl Hash for Geometry {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        self.hash_with_tag(h, 0);
    }
}

impl Geometry {
    /// [`Hash`]: one word holding `bits` (below 2^8: a caller's own small
    /// fields, see `Shape`'s hash), the kind and a polygon's vertex count,
    /// then the fields.
    #[inline(always)]
    pub(crate) fn hash_with_tag<H: core::hash::Hasher>(&self, h: &mut H, bits: u64) {
        match self {
            Geometry::Circle(c) => {
                h.write_u64(bits);
                c.hash(h);
            }
            Geometry::Segment(s) => {
                h.write_u64(bits | 1 << 8);
                s.hash(h);
            }
            Geometry::Poly(p) => {
                h.write_u64(bits | 2 << 8 | u64::from(p.count) << 16);
                p.hash_fields(h);
            }
        }
    }
}

/// The vertex count, the radius and every vertex slot (the slots past the
/// count are zero in every valid polygon), mixed; the normals are folded
/// into one word by exclusive or. In every valid polygon (validation
/// rebuilds the polygon from its vertices and compares) the normals follow
/// from the vertices, so they carry no information of their own; a change
/// of any one of their numbers still changes the fold, hence the checksum,
/// at a fraction of the cost of a word each (a polygon is hashed every
/// frame).
impl Hash for Poly {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        h.write_u8(self.count);
        self.hash_fields(h);
    }
}

impl Poly {
    /// [`Hash`] but the count: the radius, the vertex slots, the normals'
    /// fold.
    #[inline(always)]
    fn hash_fields<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Poly {
            count: _, // hashed by the caller
            verts,
            normals,
            radius,
        } = self;
        radius.hash(h);
        // Fixed length, no branch: straight-line code.
        for v in verts {
            v.hash(h);
        }
        let fold = normals
            .iter()
            .fold(0, |z, n| z ^ n.x.to_bits() ^ n.y.to_bits());
        h.write_i64(fold);
    }
}

/// Which kind of geometry; also the collision-table order (circle < segment < poly).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum ShapeKind {
    /// [`Circle`].
    Circle,
    /// [`Segment`].
    Segment,
    /// [`Poly`].
    Poly,
}

impl Circle {
    /// A circle with the given radius and offset (validation happens in the
    /// shape constructors).
    pub const fn new(radius: Real, offset: Vect) -> Circle {
        Circle { offset, radius }
    }

    /// Moved into world space.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Circle {
        Circle {
            offset: pos + rot.apply(self.offset),
            radius: self.radius,
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        BB::for_circle(self.offset, self.radius)
    }
}

impl Segment {
    /// A segment without neighbours.
    pub fn new(a: Vect, b: Vect, radius: Real) -> Segment {
        Segment {
            a,
            b,
            normal: (b - a).rperp().normalize(),
            radius,
            a_tangent: Vect::ZERO,
            b_tangent: Vect::ZERO,
        }
    }

    /// Sets the neighbours `prev` (joined at `a`) and `next` (joined at `b`),
    /// MIS/Chipmunk `segmentShapeSetNeighbors`.
    pub fn with_neighbors(mut self, prev: Vect, next: Vect) -> Segment {
        self.a_tangent = prev - self.a;
        self.b_tangent = next - self.b;
        self
    }

    /// Moved into world space.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Segment {
        Segment {
            a: pos + rot.apply(self.a),
            b: pos + rot.apply(self.b),
            normal: rot.apply(self.normal),
            radius: self.radius,
            a_tangent: rot.apply(self.a_tangent),
            b_tangent: rot.apply(self.b_tangent),
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        BB::for_point(self.a).expand(self.b).grow(self.radius)
    }
}

/// The index after `i` around a closed polygon of `n` vertices: `i + 1`, or
/// 0 after the last (the same as `(i + 1) % n` for `i < n`; 0 otherwise).
#[inline]
pub(crate) fn next_index(i: usize, n: usize) -> usize {
    match i.checked_add(1) {
        Some(j) if j < n => j,
        _ => 0,
    }
}

impl Poly {
    /// Builds a polygon from vertices that are already convex and
    /// counter-clockwise, without checks. Callers in this crate validate
    /// first (see `shape::poly`); `verts.len()` must be in `1..=MAX`.
    pub(crate) fn from_ccw_unchecked(verts: &[Vect], radius: Real) -> Poly {
        let mut p = Poly {
            count: 0,
            verts: [Vect::ZERO; MAX_POLY_VERTICES],
            normals: [Vect::ZERO; MAX_POLY_VERTICES],
            radius,
        };
        for (slot, v) in p.verts.iter_mut().zip(verts) {
            *slot = *v;
            // At most `MAX_POLY_VERTICES` slots: never saturates.
            p.count = p.count.saturating_add(1);
        }
        p.compute_normals();
        p
    }

    fn compute_normals(&mut self) {
        let n = self.count();
        for i in 0..n {
            let a = self.vert(i);
            let b = self.vert(next_index(i, n));
            if let Some(slot) = self.normals.get_mut(i) {
                *slot = (b - a).rperp().normalize();
            }
        }
    }

    /// Number of vertices.
    #[inline]
    pub fn count(&self) -> usize {
        usize::from(self.count).min(MAX_POLY_VERTICES)
    }

    /// The vertices, counter-clockwise.
    #[inline]
    pub fn verts(&self) -> &[Vect] {
        self.verts.get(..self.count()).unwrap_or(&[])
    }

    /// The outward edge normals (`normals()[i]` belongs to edge i → i+1).
    #[inline]
    pub fn normals(&self) -> &[Vect] {
        self.normals.get(..self.count()).unwrap_or(&[])
    }

    /// Vertex `i` (wrapping past the end is the caller's job); out of range gives zero.
    #[inline]
    pub fn vert(&self, i: usize) -> Vect {
        self.verts.get(i).copied().unwrap_or(Vect::ZERO)
    }

    /// Normal of edge `i`; out of range gives zero.
    #[inline]
    pub fn normal(&self, i: usize) -> Vect {
        self.normals.get(i).copied().unwrap_or(Vect::ZERO)
    }

    /// Rounding radius.
    #[inline]
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// Moved into world space (normals are rotated, not recomputed, so the
    /// result is exact up to one rounding per component).
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Poly {
        let mut out = *self;
        let n = self.count();
        for (dst, src) in out.verts.iter_mut().zip(&self.verts).take(n) {
            *dst = pos + rot.apply(*src);
        }
        for (dst, src) in out.normals.iter_mut().zip(&self.normals).take(n) {
            *dst = rot.apply(*src);
        }
        out
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        let mut it = self.verts().iter();
        let first = it.next().copied().unwrap_or(Vect::ZERO);
        it.fold(BB::for_point(first), |bb, v| bb.expand(*v))
            .grow(self.radius)
    }
}

impl Geometry {
    /// The kind of geometry.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Geometry::Circle(_) => ShapeKind::Circle,
            Geometry::Segment(_) => ShapeKind::Segment,
            Geometry::Poly(_) => ShapeKind::Poly,
        }
    }

    /// Moved into world space by a rigid placement.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Geometry {
        match self {
            Geometry::Circle(c) => Geometry::Circle(c.to_world(pos, rot)),
            Geometry::Segment(s) => Geometry::Segment(s.to_world(pos, rot)),
            Geometry::Poly(p) => Geometry::Poly(p.to_world(pos, rot)),
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        match self {
            Geometry::Circle(c) => c.bb(),
            Geometry::Segment(s) => s.bb(),
            Geometry::Poly(p) => p.bb(),
        }
    }

    /// Rounding radius (the circle's radius for circles).
    pub fn radius(&self) -> Real {
        match self {
            Geometry::Circle(c) => c.radius,
            Geometry::Segment(s) => s.radius,
            Geometry::Poly(p) => p.radius,
        }
    }

    /// The extent rule every shape obeys (checked by every constructor and
    /// setter of [`Shape`](super::Shape) and by [`Geometry::validate`]): the
    /// local bounding box, rounding radius included, lies inside the `Real`
    /// range and spans *less than 2^31 m* on each axis. Then the difference
    /// of any two points of the shape fits a `Real` (edge vectors, segment
    /// directions, support-point differences), and so does the sum of two
    /// shapes' radii (each below 2^30 m), the contact distance of two
    /// rounded shapes. A circle's radius is thus below 2^30 m, a segment
    /// shorter than 2^31 m − 2r. Errors with
    /// [`ShapeError::OutOfRange`]`("shape extent")`.
    pub fn check_extent(&self) -> Result<(), ShapeError> {
        let fits = match self {
            Geometry::Circle(c) => extent_fits(&[c.offset], c.radius),
            Geometry::Segment(s) => extent_fits(&[s.a, s.b], s.radius),
            Geometry::Poly(p) => extent_fits(p.verts(), p.radius),
        };
        if fits {
            Ok(())
        } else {
            Err(ShapeError::OutOfRange("shape extent"))
        }
    }

    /// Checks stored geometry (snapshot loading, `Space::validate`): radius
    /// ≥ 0; the extent rule ([`Geometry::check_extent`]); a segment's normal is exactly the one [`Segment::new`] computes
    /// from its endpoints; a polygon has 3..=[`MAX_POLY_VERTICES`] vertices,
    /// is strictly convex and counter-clockwise, and equals what
    /// [`Poly::from_ccw`] builds from its vertices (same normals, zeros past
    /// `count`). Returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.radius().is_negative() {
            return Err("negative radius".into());
        }
        self.check_extent().map_err(|e| e.to_string())?;
        match self {
            Geometry::Circle(_) => Ok(()),
            Geometry::Segment(s) => {
                if Segment::new(s.a, s.b, s.radius).normal == s.normal {
                    Ok(())
                } else {
                    Err("segment normal does not match its endpoints".into())
                }
            }
            Geometry::Poly(p) => {
                let n = usize::from(p.count);
                if !(3..=MAX_POLY_VERTICES).contains(&n) {
                    return Err(format!(
                        "polygon has {n} vertices (3..={MAX_POLY_VERTICES})"
                    ));
                }
                match Poly::from_ccw(p.verts(), p.radius) {
                    Ok(rebuilt) if rebuilt == *p => Ok(()),
                    Ok(_) => {
                        Err("polygon normals or unused entries do not match its vertices".into())
                    }
                    Err(e) => Err(format!("polygon: {e}")),
                }
            }
        }
    }
}

/// The extent rule of [`Geometry::check_extent`] for core points grown by
/// `radius`, on exact 128-bit raw values: raw coordinates are within ±2^63
/// and a valid radius in [0, 2^63), so no sum or difference below comes
/// near the `i128` range (the saturating forms never saturate).
fn extent_fits(points: &[Vect], radius: Real) -> bool {
    let r = i128::from(radius.to_bits());
    let (min, max) = (i128::from(i64::MIN), i128::from(i64::MAX));
    let axis = |coord: fn(&Vect) -> Real| {
        let mut it = points.iter().map(|p| i128::from(coord(p).to_bits()));
        let Some(first) = it.next() else {
            return true;
        };
        let (lo, hi) = it.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let (lo, hi) = (lo.saturating_sub(r), hi.saturating_add(r));
        lo >= min && hi <= max && hi.saturating_sub(lo) <= max
    };
    axis(|p| p.x) && axis(|p| p.y)
}
