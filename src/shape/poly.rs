//! Polygon constructors: validated convex polygons and boxes.
use super::{Poly, ShapeError, MAX_POLY_VERTICES};
use crate::math::{Real, Vect, BB};

impl Poly {
    /// A polygon from vertices that must already be convex and
    /// counter-clockwise (MIS `polyShapeNewRaw`): checked, not repaired.
    /// Errors: fewer than 3 vertices or zero area ([`ShapeError::DegeneratePolygon`]),
    /// more than [`MAX_POLY_VERTICES`], a reflex or clockwise corner
    /// ([`ShapeError::NotConvex`]), a negative radius.
    pub fn from_ccw(verts: &[Vect], radius: Real) -> Result<Poly, ShapeError> {
        if radius.is_negative() {
            return Err(ShapeError::Negative("radius"));
        }
        let n = verts.len();
        if n > MAX_POLY_VERTICES {
            return Err(ShapeError::TooManyVertices(n));
        }
        if n < 3 {
            return Err(ShapeError::DegeneratePolygon);
        }
        let at = |i: usize| verts.get(i % n).copied().unwrap_or(Vect::ZERO);
        let mut twice_area = Real::ZERO;
        for i in 0..n {
            let (a, b, c) = (at(i), at(i + 1), at(i + 2));
            if a == b {
                return Err(ShapeError::DegeneratePolygon);
            }
            // Every corner must turn left (strictly: collinear corners would
            // give zero-length normals' neighbours and duplicate features).
            if (b - a).cross(c - b) <= Real::ZERO {
                return Err(ShapeError::NotConvex);
            }
            twice_area += (a - at(0)).cross(b - at(0));
        }
        if twice_area <= Real::ZERO {
            return Err(ShapeError::DegeneratePolygon);
        }
        Ok(Poly::from_ccw_unchecked(verts, radius))
    }

    /// A `width × height` box centred on the origin with rounding `radius`
    /// (MIS `boxShapeNew`).
    pub fn new_box(width: Real, height: Real, radius: Real) -> Result<Poly, ShapeError> {
        if width.is_negative() || height.is_negative() {
            return Err(ShapeError::Negative("box size"));
        }
        let (hw, hh) = (width * Real::HALF, height * Real::HALF);
        Poly::from_bb(BB::new(-hw, -hh, hw, hh), radius)
    }

    /// The box `bb` with rounding `radius` (MIS `boxShapeNew2`).
    pub fn from_bb(bb: BB, radius: Real) -> Result<Poly, ShapeError> {
        let verts = [
            Vect::new(bb.r, bb.b),
            Vect::new(bb.r, bb.t),
            Vect::new(bb.l, bb.t),
            Vect::new(bb.l, bb.b),
        ];
        Poly::from_ccw(&verts, radius)
    }
}
