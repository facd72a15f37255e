//! Polygon constructors and the MIS PolyShape routines (§7.9–7.12).
//!
//! Two ways in, as in Chipmunk:
//! * [`Poly::from_points`] / [`Shape::poly_shape_new`] take any points, place
//!   them with a [`Transform`] and keep their convex hull;
//! * [`Poly::from_ccw`] / [`Shape::poly_shape_new_raw`] take vertices that
//!   must already be convex and counter-clockwise, and check them.
//!
//! Both validate with exact orientation tests ([`orientation`]), the same
//! ones the hull uses, so a hull is always accepted as a raw polygon. Where
//! Chipmunk has undefined behaviour (a concave "raw" polygon, a zero-area
//! hull) or raises an MIS exception (wrong shape kind, bad index), we return a
//! [`ShapeError`].
use super::hull::{convex_hull, orientation};
use super::{Geometry, Poly, Shape, ShapeError, MAX_POLY_VERTICES};
use crate::body::BodyHandle;
use crate::math::{Real, Transform, Vect, BB};

/// Rejects vertex sets whose extent does not fit a `Real` difference (span of
/// 2^31 or more on an axis): the exact orientation tests, the edge normals
/// and the mass integrals all work on vertex differences.
fn check_extent(verts: &[Vect]) -> Result<(), ShapeError> {
    let mut it = verts.iter();
    let Some(first) = it.next() else {
        return Ok(());
    };
    let (lo, hi) = it.fold((*first, *first), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
    let fits = |a: Real, b: Real| a.to_bits().checked_sub(b.to_bits()).is_some();
    if fits(hi.x, lo.x) && fits(hi.y, lo.y) {
        Ok(())
    } else {
        Err(ShapeError::OutOfRange("polygon extent"))
    }
}

fn check_radius(radius: Real) -> Result<(), ShapeError> {
    if radius.is_negative() {
        Err(ShapeError::Negative("radius"))
    } else {
        Ok(())
    }
}

impl Poly {
    /// A polygon from vertices that must already be convex and
    /// counter-clockwise (MIS `polyShapeNewRaw`): checked, not repaired.
    ///
    /// Checks are exact (integer orientation on the raw bits): every vertex
    /// must lie strictly left of every edge it is not on. That rejects
    /// collinear and repeated vertices, clockwise order and self-overlapping
    /// "stars" whose corners all turn left.
    ///
    /// Errors: a negative radius ([`ShapeError::Negative`]); more than
    /// [`MAX_POLY_VERTICES`] ([`ShapeError::TooManyVertices`]); fewer than 3
    /// vertices, repeated consecutive vertices or zero area
    /// ([`ShapeError::DegeneratePolygon`]); a span of 2^31 or more
    /// ([`ShapeError::OutOfRange`]); anything not strictly convex and
    /// counter-clockwise ([`ShapeError::NotConvex`]).
    pub fn from_ccw(verts: &[Vect], radius: Real) -> Result<Poly, ShapeError> {
        check_radius(radius)?;
        let n = verts.len();
        if n > MAX_POLY_VERTICES {
            return Err(ShapeError::TooManyVertices(n));
        }
        if n < 3 {
            return Err(ShapeError::DegeneratePolygon);
        }
        check_extent(verts)?;
        let first = verts.first().copied().unwrap_or(Vect::ZERO);
        let edges = || verts.iter().zip(verts.iter().cycle().skip(1)).take(n);
        if edges().any(|(a, b)| a == b) {
            return Err(ShapeError::DegeneratePolygon);
        }
        // Twice the signed area, exactly (a fan from the first vertex). It
        // only classifies the failure: zero area is degenerate, negative is
        // clockwise. Saturation can only happen outside the checked extent.
        let twice_area = edges().fold(0i128, |acc, (a, b)| {
            acc.saturating_add(orientation(first, *a, *b))
        });
        if twice_area == 0 {
            return Err(ShapeError::DegeneratePolygon);
        }
        // n ≤ 8, so the full check is at most 8 × 8 orientation tests.
        let convex = twice_area > 0
            && edges().all(|(a, b)| {
                verts
                    .iter()
                    .all(|p| p == a || p == b || orientation(*a, *b, *p) > 0)
            });
        if !convex {
            return Err(ShapeError::NotConvex);
        }
        Ok(Poly::from_ccw_unchecked(verts, radius))
    }

    /// The convex hull of `points` placed by `transform`, with rounding
    /// `radius` (MIS `polyShapeNew`; Chipmunk `cpPolyShapeInit` with hull
    /// tolerance 0). Interior, repeated and collinear points are dropped.
    ///
    /// Errors: a negative radius; a transformed point that saturates or a
    /// point set spanning 2^31 or more ([`ShapeError::OutOfRange`]); a hull of
    /// fewer than 3 points, i.e. zero area ([`ShapeError::DegeneratePolygon`]);
    /// a hull of more than [`MAX_POLY_VERTICES`]
    /// ([`ShapeError::TooManyVertices`] with the hull's size).
    pub fn from_points(
        points: &[Vect],
        transform: &Transform,
        radius: Real,
    ) -> Result<Poly, ShapeError> {
        check_radius(radius)?;
        let placed: Vec<Vect> = points.iter().map(|p| transform.point(*p)).collect();
        if placed.iter().any(|p| p.is_saturated()) {
            return Err(ShapeError::OutOfRange("transformed vertex"));
        }
        check_extent(&placed)?;
        let hull = convex_hull(&placed, Real::ZERO);
        if hull.len() < 3 {
            return Err(ShapeError::DegeneratePolygon);
        }
        if hull.len() > MAX_POLY_VERTICES {
            return Err(ShapeError::TooManyVertices(hull.len()));
        }
        // The hull is exactly strictly convex and counter-clockwise, so this
        // check passes; it stays as the single gate into `Poly`.
        Poly::from_ccw(&hull, radius)
    }

    /// A `width × height` box centred on the origin with rounding `radius`
    /// (MIS `boxShapeNew`). A zero width or height is degenerate.
    pub fn new_box(width: Real, height: Real, radius: Real) -> Result<Poly, ShapeError> {
        if width.is_negative() || height.is_negative() {
            return Err(ShapeError::Negative("box size"));
        }
        let (hw, hh) = (width * Real::HALF, height * Real::HALF);
        Poly::from_bb(BB::new(-hw, -hh, hw, hh), radius)
    }

    /// The box `bb` with rounding `radius` (MIS `boxShapeNew2`); vertices in
    /// Chipmunk's order, starting at the bottom-right corner.
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

impl Shape {
    /// MIS `polyShapeNew`: a polygon shape from the convex hull of `points`
    /// placed by `transform` (body coordinates). See [`Poly::from_points`]
    /// for the errors.
    pub fn poly_shape_new(
        body: BodyHandle,
        points: &[Vect],
        transform: &Transform,
        radius: Real,
    ) -> Result<Shape, ShapeError> {
        let poly = Poly::from_points(points, transform, radius)?;
        Shape::checked(body, Geometry::Poly(poly))
    }

    /// MIS `polyShapeNewRaw`: a polygon shape from vertices that are already
    /// convex and counter-clockwise. See [`Poly::from_ccw`] for the errors.
    pub fn poly_shape_new_raw(
        body: BodyHandle,
        verts: &[Vect],
        radius: Real,
    ) -> Result<Shape, ShapeError> {
        let poly = Poly::from_ccw(verts, radius)?;
        Shape::checked(body, Geometry::Poly(poly))
    }

    /// MIS `boxShapeNew`: a `width × height` box centred on the body origin.
    pub fn box_shape_new(
        body: BodyHandle,
        width: Real,
        height: Real,
        radius: Real,
    ) -> Result<Shape, ShapeError> {
        let poly = Poly::new_box(width, height, radius)?;
        Shape::checked(body, Geometry::Poly(poly))
    }

    /// MIS `boxShapeNew2`: the box `bb` (body coordinates).
    pub fn box_shape_new2(body: BodyHandle, bb: BB, radius: Real) -> Result<Shape, ShapeError> {
        let poly = Poly::from_bb(bb, radius)?;
        Shape::checked(body, Geometry::Poly(poly))
    }

    /// The polygon geometry, or [`ShapeError::NotPolyShape`].
    pub fn poly(&self) -> Result<&Poly, ShapeError> {
        match &self.geometry {
            Geometry::Poly(p) => Ok(p),
            Geometry::Circle(_) | Geometry::Segment(_) => Err(ShapeError::NotPolyShape),
        }
    }

    /// MIS `polyShapeGetCount`: the number of vertices.
    pub fn poly_count(&self) -> Result<usize, ShapeError> {
        self.poly().map(Poly::count)
    }

    /// MIS `polyShapeGetVert`: vertex `index` in body coordinates; an index at
    /// or past the count is [`ShapeError::IndexOutOfBounds`] (MIS exception).
    pub fn poly_vert(&self, index: usize) -> Result<Vect, ShapeError> {
        let poly = self.poly()?;
        poly.verts()
            .get(index)
            .copied()
            .ok_or(ShapeError::IndexOutOfBounds {
                index,
                count: poly.count(),
            })
    }

    /// MIS `polyShapeGetRadius`: the rounding radius.
    pub fn poly_radius(&self) -> Result<Real, ShapeError> {
        self.poly().map(Poly::radius)
    }

    /// MIS `polyShapeSetVerts`: replaces the vertices by the hull of `points`
    /// placed by `transform`, keeping the radius. On error the shape is
    /// unchanged. The owning body's mass is recomputed by the space.
    pub fn set_poly_verts(
        &mut self,
        points: &[Vect],
        transform: &Transform,
    ) -> Result<(), ShapeError> {
        let radius = self.poly()?.radius();
        let new = Poly::from_points(points, transform, radius)?;
        self.replace_geometry(Geometry::Poly(new))
    }

    /// MIS `polyShapeSetVertsRaw`: replaces the vertices by `verts`, which
    /// must be convex and counter-clockwise, keeping the radius. On error the
    /// shape is unchanged.
    pub fn set_poly_verts_raw(&mut self, verts: &[Vect]) -> Result<(), ShapeError> {
        let radius = self.poly()?.radius();
        let new = Poly::from_ccw(verts, radius)?;
        self.replace_geometry(Geometry::Poly(new))
    }

    /// MIS `polyShapeSetRadius`: sets the rounding radius (≥ 0).
    /// Errors outside the extent rule ([`Geometry::check_extent`]), leaving
    /// the shape unchanged.
    pub fn set_poly_radius(&mut self, radius: Real) -> Result<(), ShapeError> {
        let mut poly = *self.poly()?;
        check_radius(radius)?;
        poly.radius = radius;
        self.replace_geometry(Geometry::Poly(poly))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arena::Handle;
    use crate::real;
    use crate::shape::Circle;

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    fn body() -> BodyHandle {
        Handle::from_raw_parts(0, 0)
    }

    #[test]
    fn from_ccw_accepts_square_and_rejects_bad_input() {
        let sq = [v(0, 0), v(1, 0), v(1, 1), v(0, 1)];
        let p = Poly::from_ccw(&sq, Real::ZERO).unwrap();
        assert_eq!(p.verts(), &sq);
        assert_eq!(p.normals(), &[v(0, -1), v(1, 0), v(0, 1), v(-1, 0)]);
        let cw = [v(0, 0), v(0, 1), v(1, 1), v(1, 0)];
        assert_eq!(Poly::from_ccw(&cw, Real::ZERO), Err(ShapeError::NotConvex));
        let line = [v(0, 0), v(1, 1), v(2, 2)];
        assert_eq!(
            Poly::from_ccw(&line, Real::ZERO),
            Err(ShapeError::DegeneratePolygon)
        );
        let dup = [v(0, 0), v(1, 0), v(1, 0), v(0, 1)];
        assert_eq!(
            Poly::from_ccw(&dup, Real::ZERO),
            Err(ShapeError::DegeneratePolygon)
        );
        assert_eq!(
            Poly::from_ccw(&sq, -Real::ONE),
            Err(ShapeError::Negative("radius"))
        );
        let far = [
            Vect::new(Real::MIN, Real::ZERO),
            Vect::new(Real::MAX, Real::ZERO),
            Vect::new(Real::ZERO, Real::ONE),
        ];
        assert_eq!(
            Poly::from_ccw(&far, Real::ZERO),
            Err(ShapeError::OutOfRange("polygon extent"))
        );
    }

    #[test]
    fn from_ccw_rejects_pentagram_whose_corners_all_turn_left() {
        // Pentagon vertices taken every second one: all left turns, winds twice.
        let pentagon = [v(10, 0), v(3, 9), v(-8, 6), v(-8, -6), v(3, -9)];
        let star: Vec<Vect> = [0usize, 2, 4, 1, 3]
            .iter()
            .filter_map(|i| pentagon.get(*i).copied())
            .collect();
        assert!(Poly::from_ccw(&pentagon, Real::ZERO).is_ok());
        assert_eq!(
            Poly::from_ccw(&star, Real::ZERO),
            Err(ShapeError::NotConvex)
        );
    }

    #[test]
    fn from_points_takes_hull_and_applies_transform() {
        let pts = [v(1, 1), v(0, 0), v(2, 0), v(2, 2), v(0, 2), v(1, 0)];
        let t = Transform::translate(v(10, 20));
        let p = Poly::from_points(&pts, &t, real!(0.5)).unwrap();
        assert_eq!(p.verts(), &[v(10, 20), v(12, 20), v(12, 22), v(10, 22)]);
        assert_eq!(p.radius(), real!(0.5));
        let line = [v(0, 0), v(1, 1), v(3, 3)];
        assert_eq!(
            Poly::from_points(&line, &Transform::IDENTITY, Real::ZERO),
            Err(ShapeError::DegeneratePolygon)
        );
        assert_eq!(
            Poly::from_points(&[], &Transform::IDENTITY, Real::ZERO),
            Err(ShapeError::DegeneratePolygon)
        );
    }

    #[test]
    fn from_points_too_many_hull_vertices_is_an_error() {
        // 9 points on a convex curve (parabola).
        let pts: Vec<Vect> = (0..9).map(|i| v(i, i * i)).collect();
        assert_eq!(
            Poly::from_points(&pts, &Transform::IDENTITY, Real::ZERO),
            Err(ShapeError::TooManyVertices(9))
        );
        assert!(Poly::from_points(
            pts.get(..8).unwrap_or(&[]),
            &Transform::IDENTITY,
            Real::ZERO
        )
        .is_ok());
    }

    #[test]
    fn box_shapes_have_chipmunk_vertex_order() {
        let s = Shape::box_shape_new(body(), Real::TWO, Real::from_int(4), Real::ZERO).unwrap();
        assert_eq!(s.poly_count(), Ok(4));
        assert_eq!(s.poly_vert(0), Ok(v(1, -2)));
        assert_eq!(s.poly_vert(2), Ok(v(-1, 2)));
        assert_eq!(
            s.poly_vert(4),
            Err(ShapeError::IndexOutOfBounds { index: 4, count: 4 })
        );
        let bb = BB::new(Real::ZERO, Real::ZERO, Real::ONE, Real::TWO);
        let s2 = Shape::box_shape_new2(body(), bb, real!(0.25)).unwrap();
        assert_eq!(s2.poly_radius(), Ok(real!(0.25)));
        assert_eq!(s2.poly_vert(1), Ok(v(1, 2)));
    }

    #[test]
    fn poly_accessors_on_other_kinds_are_not_poly_shape() {
        let mut c =
            Shape::from_geometry(body(), Geometry::Circle(Circle::new(Real::ONE, Vect::ZERO)));
        assert_eq!(c.poly_count(), Err(ShapeError::NotPolyShape));
        assert_eq!(c.poly_vert(0), Err(ShapeError::NotPolyShape));
        assert_eq!(c.poly_radius(), Err(ShapeError::NotPolyShape));
        assert_eq!(c.set_poly_radius(Real::ONE), Err(ShapeError::NotPolyShape));
        assert_eq!(
            c.set_poly_verts(&[v(0, 0), v(1, 0), v(0, 1)], &Transform::IDENTITY),
            Err(ShapeError::NotPolyShape)
        );
        assert_eq!(
            c.set_poly_verts_raw(&[v(0, 0), v(1, 0), v(0, 1)]),
            Err(ShapeError::NotPolyShape)
        );
    }

    #[test]
    fn poly_setters_replace_or_leave_unchanged() {
        let mut s =
            Shape::poly_shape_new_raw(body(), &[v(0, 0), v(1, 0), v(0, 1)], Real::ONE).unwrap();
        s.set_poly_verts(
            &[v(0, 0), v(2, 0), v(2, 2), v(0, 2), v(1, 1)],
            &Transform::IDENTITY,
        )
        .unwrap();
        assert_eq!(s.poly_count(), Ok(4));
        assert_eq!(s.poly_radius(), Ok(Real::ONE));
        let before = s.clone();
        assert_eq!(
            s.set_poly_verts_raw(&[v(0, 0), v(0, 1), v(1, 0)]),
            Err(ShapeError::NotConvex)
        );
        assert_eq!(
            s.set_poly_radius(-Real::ONE),
            Err(ShapeError::Negative("radius"))
        );
        assert_eq!(s, before);
        s.set_poly_verts_raw(&[v(0, 0), v(3, 0), v(0, 3)]).unwrap();
        assert_eq!(s.poly_vert(1), Ok(v(3, 0)));
        s.set_poly_radius(Real::ZERO).unwrap();
        assert_eq!(s.poly_radius(), Ok(Real::ZERO));
    }
}
