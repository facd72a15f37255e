//! Debug drawing: the world's shapes, and optionally its contact points, in
//! world space, handed to any renderer through the [`DebugDraw`] trait
//! (Chipmunk's `cpSpaceDebugDraw`). Compiled only with the `debug-draw`
//! cargo feature, so library users who do not draw pay nothing.
//!
//! [`Space::debug_draw`] walks the shapes in arena order (the order they were
//! added, reusing freed slots), moves each one into world space with its
//! body's position and rotation, picks its colours from
//! [`DebugDrawOptions`] (static grey, kinematic blue, dynamic bodies from a
//! palette by body slot, so neighbouring boxes differ), and calls one trait
//! method per shape. Then it draws every joint (constraint), in slot order,
//! with the same primitives: a thin line (a segment of radius 0) between
//! the two world anchors and a dot on each (pin, slide, pivot, damped
//! spring); the groove on body a and a dot on b's pivot (groove); a line
//! between the two centres of gravity with a dot on each (the angular
//! kinds: rotary limit, ratchet, gear, motor, rotary spring). Then, if
//! asked, it draws a dot on every contact point of every touching,
//! non-sensor arbiter.
//!
//! Coordinates are `f64` **for output only**: they are converted from the
//! exact `Real` state when drawn and never flow back into the simulation, so
//! drawing cannot change a step (a test checks that the checksum is
//! unchanged). Drawing allocates nothing. The y axis points up, as in the
//! world; flipping it for an image is the renderer's job.
//!
//! ```
//! use tamias2d::debug_draw::{Color, DebugDraw, DebugDrawOptions, Point, ShapeStyle};
//! use tamias2d::body::Body;
//! use tamias2d::shape::Shape;
//! use tamias2d::space::Space;
//! use tamias2d::{Real, Vect};
//!
//! /// Counts what would be drawn.
//! #[derive(Default)]
//! struct Count { circles: usize, segments: usize, polygons: usize, dots: usize }
//! impl DebugDraw for Count {
//!     fn circle(&mut self, _: Point, _: f64, _: Point, _: ShapeStyle) { self.circles += 1 }
//!     fn segment(&mut self, _: Point, _: Point, _: f64, _: ShapeStyle) { self.segments += 1 }
//!     fn polygon(&mut self, _: &[Point], _: f64, _: ShapeStyle) { self.polygons += 1 }
//!     fn dot(&mut self, _: Point, _: f64, _: Color) { self.dots += 1 }
//! }
//!
//! let mut space = Space::new();
//! let ground = space.add_body(Body::new_static())?;
//! let (a, b) = (Vect::from_ints(-5, 0), Vect::from_ints(5, 0));
//! space.add_shape(Shape::segment_shape_new(ground, a, b, Real::ZERO)?)?;
//! for i in 0..3 {
//!     let mut body = Body::new(Real::ONE, Real::ONE)?;
//!     body.set_position(Vect::from_ints(2 * i - 2, 1));
//!     let h = space.add_body(body)?;
//!     space.add_shape(Shape::box_shape_new(h, Real::ONE, Real::ONE, Real::ZERO)?)?;
//! }
//! let mut count = Count::default();
//! space.debug_draw(&mut count, &DebugDrawOptions::default());
//! assert_eq!((count.segments, count.polygons), (1, 3)); // the ground, the boxes
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
use crate::arbiter::ArbiterState;
use crate::body::{Body, BodyType};
use crate::constraint::JointKind;
use crate::math::{Real, Vect};
use crate::shape::{Geometry, Shape, MAX_POLY_VERTICES};
use crate::space::Space;

/// A point `[x, y]` in world coordinates, y up.
pub type Point = [f64; 2];

/// An sRGB colour with straight (not premultiplied) alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Color {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
    /// Alpha (255: opaque).
    pub a: u8,
}

impl Color {
    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Color {
        Color { r, g, b, a: 255 }
    }

    /// The same colour with alpha `a`.
    pub const fn with_alpha(self, a: u8) -> Color {
        Color { a, ..self }
    }

    /// The same colour at 60% brightness: the default outline of a fill.
    pub const fn darker(self) -> Color {
        // u8 · 3 / 5 fits in u16 and is ≤ 153: the casts are lossless, and
        // the product (≤ 765) cannot overflow.
        #[allow(clippy::arithmetic_side_effects)]
        const fn dim(c: u8) -> u8 {
            (c as u16 * 3 / 5) as u8
        }
        Color {
            r: dim(self.r),
            g: dim(self.g),
            b: dim(self.b),
            a: self.a,
        }
    }
}

/// How one shape is painted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShapeStyle {
    /// Interior.
    pub fill: Color,
    /// Outline (and a circle's rotation mark).
    pub outline: Color,
}

impl ShapeStyle {
    /// `fill` with its [darker](Color::darker) outline.
    pub const fn filled(fill: Color) -> ShapeStyle {
        ShapeStyle {
            fill,
            outline: fill.darker(),
        }
    }
}

/// A renderer: receives world-space primitives from [`Space::debug_draw`].
pub trait DebugDraw {
    /// A circle of `radius` centred on `center`; `rot` is the unit vector
    /// `(cos θ, sin θ)` of the body's angle, for a mark that shows spin.
    fn circle(&mut self, center: Point, radius: f64, rot: Point, style: ShapeStyle);

    /// A segment from `a` to `b` rounded by `radius` (a capsule when > 0).
    fn segment(&mut self, a: Point, b: Point, radius: f64, style: ShapeStyle);

    /// A convex polygon, counter-clockwise (in a y-up frame), rounded by
    /// `radius`.
    fn polygon(&mut self, verts: &[Point], radius: f64, style: ShapeStyle);

    /// A dot of `size` output pixels (a screen-space size: contact markers
    /// stay visible at any zoom).
    fn dot(&mut self, p: Point, size: f64, color: Color);
}

/// Number of colours dynamic bodies cycle through.
pub const DYNAMIC_PALETTE_LEN: usize = 6;

/// What [`Space::debug_draw`] draws, and in which colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DebugDrawOptions {
    /// Draw the shapes.
    pub shapes: bool,
    /// Draw a dot on each contact point of each touching arbiter.
    pub contacts: bool,
    /// Draw the joints (see the module docs).
    pub joints: bool,
    /// Joint lines and anchor dots.
    pub joint_style: ShapeStyle,
    /// Joint anchor dot size in output pixels.
    pub joint_anchor_size: f64,
    /// Shapes of static bodies.
    pub static_style: ShapeStyle,
    /// Shapes of kinematic bodies.
    pub kinematic_style: ShapeStyle,
    /// Fills of dynamic bodies: body slot `i` uses entry `i mod len`, so a
    /// body keeps its colour for its whole life and neighbours differ.
    pub dynamic_fills: [Color; DYNAMIC_PALETTE_LEN],
    /// Shapes of sleeping dynamic bodies (one shade for all, as Box2D's
    /// grey: a glance shows which islands rest).
    pub sleeping_style: ShapeStyle,
    /// Sensor shapes are drawn with their body's colours at this alpha.
    pub sensor_alpha: u8,
    /// Contact dots.
    pub contact_color: Color,
    /// Contact dot size in output pixels.
    pub contact_size: f64,
}

impl Default for DebugDrawOptions {
    /// Shapes and joints on, contacts off; teal joints; grey static, blue kinematic, warm and cool
    /// tones for dynamic bodies, slate for sleeping ones, red contact dots.
    fn default() -> DebugDrawOptions {
        DebugDrawOptions {
            shapes: true,
            contacts: false,
            joints: true,
            joint_style: ShapeStyle::filled(Color::rgb(60, 160, 170)),
            joint_anchor_size: 3.0,
            static_style: ShapeStyle::filled(Color::rgb(150, 150, 150)),
            kinematic_style: ShapeStyle::filled(Color::rgb(90, 140, 230)),
            dynamic_fills: [
                Color::rgb(240, 170, 60),
                Color::rgb(95, 190, 120),
                Color::rgb(225, 110, 95),
                Color::rgb(110, 185, 215),
                Color::rgb(230, 205, 85),
                Color::rgb(180, 130, 210),
            ],
            sleeping_style: ShapeStyle::filled(Color::rgb(125, 125, 140)),
            sensor_alpha: 96,
            contact_color: Color::rgb(220, 30, 30),
            contact_size: 4.0,
        }
    }
}

impl DebugDrawOptions {
    /// The style of a shape of `body` (whose slot is `slot`).
    fn style(&self, body: &Body, slot: u32, sensor: bool) -> ShapeStyle {
        let style = match body.body_type() {
            BodyType::Static => self.static_style,
            BodyType::Kinematic => self.kinematic_style,
            BodyType::Dynamic if body.is_sleeping() => self.sleeping_style,
            BodyType::Dynamic => {
                let n = self.dynamic_fills.len();
                // A u32 always fits in usize on the targets we support (≥ 32 bits).
                // (n is the palette's non-zero length: never `None`.)
                let i = usize::try_from(slot)
                    .unwrap_or(0)
                    .checked_rem(n)
                    .unwrap_or(0);
                ShapeStyle::filled(
                    self.dynamic_fills
                        .get(i)
                        .copied()
                        .unwrap_or(Color::rgb(0, 0, 0)),
                )
            }
        };
        if sensor {
            ShapeStyle {
                fill: style.fill.with_alpha(self.sensor_alpha),
                outline: style.outline.with_alpha(self.sensor_alpha),
            }
        } else {
            style
        }
    }
}

fn point(v: Vect) -> Point {
    [v.x.to_f64(), v.y.to_f64()]
}

fn length(r: Real) -> f64 {
    r.to_f64()
}

impl Space {
    /// Draws the world into `out` as `options` say (see the module docs).
    /// Reads the state only: drawing never changes a step.
    pub fn debug_draw(&self, out: &mut impl DebugDraw, options: &DebugDrawOptions) {
        if options.shapes {
            for (_, shape) in self.shapes() {
                if let Some(body) = self.body(shape.body()) {
                    draw_shape(out, shape, body, options);
                }
            }
        }
        if options.joints {
            self.draw_joints(out, options);
        }
        if options.contacts {
            self.draw_contacts(out, options);
        }
    }

    /// Every joint as lines and anchor dots (see the module docs).
    fn draw_joints(&self, out: &mut impl DebugDraw, options: &DebugDrawOptions) {
        let style = options.joint_style;
        let (size, dot_color) = (options.joint_anchor_size, style.outline);
        for (_, c) in self.constraints() {
            let (Some(a), Some(b)) = (self.body(c.body_a()), self.body(c.body_b())) else {
                continue;
            };
            let anchors = match c.kind() {
                JointKind::Pin(j) => Some((j.anchor_a(), j.anchor_b())),
                JointKind::Slide(j) => Some((j.anchor_a(), j.anchor_b())),
                JointKind::Pivot(j) => Some((j.anchor_a(), j.anchor_b())),
                JointKind::DampedSpring(j) => Some((j.anchor_a(), j.anchor_b())),
                JointKind::Groove(j) => {
                    let (ga, gb) = (
                        a.local_to_world(j.groove_a()),
                        a.local_to_world(j.groove_b()),
                    );
                    out.segment(point(ga), point(gb), 0.0, style);
                    out.dot(point(b.local_to_world(j.anchor_b())), size, dot_color);
                    continue;
                }
                JointKind::RotaryLimit(_)
                | JointKind::Ratchet(_)
                | JointKind::Gear(_)
                | JointKind::SimpleMotor(_)
                | JointKind::DampedRotarySpring(_) => None,
            };
            let (pa, pb) = match anchors {
                Some((anchor_a, anchor_b)) => {
                    (a.local_to_world(anchor_a), b.local_to_world(anchor_b))
                }
                None => (a.center(), b.center()),
            };
            out.segment(point(pa), point(pb), 0.0, style);
            out.dot(point(pa), size, dot_color);
            out.dot(point(pb), size, dot_color);
        }
    }

    /// A dot on each contact point of each touching, solid arbiter, at body
    /// a's centre of gravity plus the contact's `r1`.
    fn draw_contacts(&self, out: &mut impl DebugDraw, options: &DebugDrawOptions) {
        for arb in self.arbiters() {
            let touching = matches!(
                arb.state(),
                ArbiterState::FirstCollision | ArbiterState::Normal
            );
            if !touching || arb.sensor {
                continue;
            }
            let Some(a) = self.body(arb.body_a) else {
                continue;
            };
            for c in arb.contacts() {
                out.dot(
                    point(a.center() + c.r1),
                    options.contact_size,
                    options.contact_color,
                );
            }
        }
    }
}

/// One shape in world space, with its body's style.
fn draw_shape(out: &mut impl DebugDraw, shape: &Shape, body: &Body, options: &DebugDrawOptions) {
    let rot = body.rotation();
    let style = options.style(body, shape.body().index(), shape.sensor);
    match shape.geometry().to_world(body.position(), rot) {
        Geometry::Circle(c) => out.circle(
            point(c.offset),
            length(c.radius),
            point(rot.as_vect()),
            style,
        ),
        Geometry::Segment(s) => out.segment(point(s.a), point(s.b), length(s.radius), style),
        Geometry::Poly(p) => {
            let mut verts = [[0.0; 2]; MAX_POLY_VERTICES];
            for (dst, v) in verts.iter_mut().zip(p.verts()) {
                *dst = point(*v);
            }
            let n = p.count();
            out.polygon(verts.get(..n).unwrap_or(&[]), length(p.radius()), style);
        }
    }
}
