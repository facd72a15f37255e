//! A draw list: a space's shapes as one flat `f32` array the page paints
//! on a canvas without calling back into wasm per shape.
//!
//! Records, one after another (world coordinates, y up; a colour is
//! `0xRRGGBB` as an `f32`, exact since it is below 2²⁴):
//!
//! | kind | record |
//! |---|---|
//! | circle | `0, cx, cy, radius, cos θ, sin θ, fill` |
//! | segment | `1, ax, ay, bx, by, radius, fill` |
//! | polygon | `2, n, radius, fill, x₁, y₁, …, xₙ, yₙ` |
//! | dot | `3, x, y, size_px, colour` |
use tamias2d::debug_draw::{Color, DebugDraw, DebugDrawOptions, Point, ShapeStyle};
use tamias2d::space::Space;

/// Record kinds (the first float of a record).
pub const CIRCLE: f32 = 0.0;
/// See [`CIRCLE`].
pub const SEGMENT: f32 = 1.0;
/// See [`CIRCLE`].
pub const POLYGON: f32 = 2.0;
/// See [`CIRCLE`].
pub const DOT: f32 = 3.0;

/// A reusable draw list (no allocation once warm).
#[derive(Debug, Default)]
pub struct DrawList {
    /// The records.
    pub floats: Vec<f32>,
}

impl DrawList {
    /// Replaces the list with `space`'s shapes and joints (and contact
    /// points if `contacts`).
    pub fn fill(&mut self, space: &Space, contacts: bool) {
        self.floats.clear();
        let options = DebugDrawOptions {
            contacts,
            ..DebugDrawOptions::default()
        };
        space.debug_draw(self, &options);
    }
}

/// Every body's transform for drawing, in slot order: `x, y, cos θ, sin θ`
/// per body (4 floats), into `out` (cleared first). For a page that draws
/// its own sprites per body instead of the shapes.
pub fn transforms(space: &Space, out: &mut Vec<f32>) {
    out.clear();
    for (_, body) in space.bodies() {
        let (x, y) = body.position().to_f64();
        let (c, s) = body.rotation().to_f64();
        out.extend_from_slice(&[px(x), px(y), px(c), px(s)]);
    }
}

/// `0xRRGGBB` as an exact `f32`.
fn rgb(c: Color) -> f32 {
    // Below 2^24: every value is exact in an f32's 24-bit significand.
    (u32::from(c.r) << 16 | u32::from(c.g) << 8 | u32::from(c.b)) as f32
}

/// Drawing output only: an f64 coordinate to the canvas's f32.
#[allow(clippy::cast_possible_truncation)]
fn px(v: f64) -> f32 {
    v as f32
}

impl DebugDraw for DrawList {
    fn circle(&mut self, center: Point, radius: f64, rot: Point, style: ShapeStyle) {
        let [cx, cy] = center;
        let [c, s] = rot;
        self.floats.extend_from_slice(&[
            CIRCLE,
            px(cx),
            px(cy),
            px(radius),
            px(c),
            px(s),
            rgb(style.fill),
        ]);
    }

    fn segment(&mut self, a: Point, b: Point, radius: f64, style: ShapeStyle) {
        let ([ax, ay], [bx, by]) = (a, b);
        self.floats.extend_from_slice(&[
            SEGMENT,
            px(ax),
            px(ay),
            px(bx),
            px(by),
            px(radius),
            rgb(style.fill),
        ]);
    }

    fn polygon(&mut self, verts: &[Point], radius: f64, style: ShapeStyle) {
        // At most MAX_POLY_VERTICES: exact as an f32.
        let n = verts.len() as f32;
        self.floats
            .extend_from_slice(&[POLYGON, n, px(radius), rgb(style.fill)]);
        for &[x, y] in verts {
            self.floats.extend_from_slice(&[px(x), px(y)]);
        }
    }

    fn dot(&mut self, p: Point, size: f64, color: Color) {
        let [x, y] = p;
        self.floats
            .extend_from_slice(&[DOT, px(x), px(y), px(size), rgb(color)]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tamias2d::body::Body;
    use tamias2d::shape::Shape;
    use tamias2d::{Real, Vect};

    #[test]
    fn records_have_their_documented_lengths() -> Result<(), Box<dyn std::error::Error>> {
        let mut space = Space::new();
        let ground = space.add_body(Body::new_static())?;
        let (a, b) = (Vect::from_ints(-5, 0), Vect::from_ints(5, 0));
        space.add_shape(Shape::segment_shape_new(ground, a, b, Real::ZERO)?)?;
        let ball = space.add_body(Body::new(Real::ONE, Real::ONE)?)?;
        space.add_shape(Shape::circle_shape_new(ball, Real::ONE, Vect::ZERO)?)?;
        let boxed = space.add_body(Body::new(Real::ONE, Real::ONE)?)?;
        space.add_shape(Shape::box_shape_new(
            boxed,
            Real::ONE,
            Real::ONE,
            Real::ZERO,
        )?)?;
        let mut list = DrawList::default();
        list.fill(&space, false);
        // A segment (7), a circle (7), a 4-gon (4 + 8), in slot order.
        assert_eq!(list.floats.len(), 7 + 7 + 12);
        assert_eq!(list.floats.first(), Some(&SEGMENT));
        assert_eq!(list.floats.get(7), Some(&CIRCLE));
        assert_eq!(list.floats.get(14), Some(&POLYGON));
        assert_eq!(list.floats.get(15), Some(&4.0));
        Ok(())
    }

    #[test]
    fn colours_are_exact() {
        let c = Color::rgb(0xfe, 0x12, 0x34);
        assert_eq!(rgb(c) as u32, 0xfe1234);
        assert_eq!(rgb(Color::rgb(255, 255, 255)) as u32, 0xffffff);
    }
}
