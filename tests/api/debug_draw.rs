//! Debug drawing (`tamias2d::debug_draw`, feature `debug-draw`) of standard
//! scenes: what is drawn, where, and that drawing changes nothing.
#![cfg(feature = "debug-draw")]

use tamias2d::body::BodyType;
use tamias2d::debug_draw::{Color, DebugDraw, DebugDrawOptions, Point, ShapeStyle};
use tamias2d::Vect;
use tamias2d_scenes as scenes;

/// A world point as drawn.
fn point(v: Vect) -> Point {
    [v.x.to_f64(), v.y.to_f64()]
}

/// Records every call.
#[derive(Default)]
struct Log {
    circles: Vec<(Point, f64, ShapeStyle)>,
    segments: usize,
    polygons: Vec<(usize, ShapeStyle)>,
    dots: usize,
}

impl DebugDraw for Log {
    fn circle(&mut self, center: Point, radius: f64, _rot: Point, style: ShapeStyle) {
        self.circles.push((center, radius, style));
    }
    fn segment(&mut self, _a: Point, _b: Point, _radius: f64, _style: ShapeStyle) {
        self.segments += 1;
    }
    fn polygon(&mut self, verts: &[Point], _radius: f64, style: ShapeStyle) {
        self.polygons.push((verts.len(), style));
    }
    fn dot(&mut self, _p: Point, _size: f64, _color: Color) {
        self.dots += 1;
    }
}

#[test]
fn debug_draw_pyramid_draws_ground_and_every_box() {
    let scene = scenes::builtin("pyramid_20").unwrap().build().unwrap();
    let mut log = Log::default();
    scene
        .space
        .debug_draw(&mut log, &DebugDrawOptions::default());
    assert_eq!(log.segments, 1);
    assert_eq!(log.polygons.len(), 210);
    assert!(log.polygons.iter().all(|(n, _)| *n == 4));
    let grey = DebugDrawOptions::default().static_style;
    assert!(log.polygons.iter().all(|(_, s)| *s != grey));
    assert_eq!(log.dots, 0, "contacts are off by default");
}

#[test]
fn debug_draw_contacts_after_settling_and_state_unchanged() {
    let mut scene = scenes::builtin("stack_10").unwrap().build().unwrap();
    scene.step_n(30).unwrap();
    let before = scene.space.checksum();
    let mut log = Log::default();
    let options = DebugDrawOptions {
        contacts: true,
        ..DebugDrawOptions::default()
    };
    scene.space.debug_draw(&mut log, &options);
    assert!(log.dots >= 10, "a resting stack has contacts: {}", log.dots);
    assert_eq!(scene.space.checksum(), before);
}

#[test]
fn debug_draw_circle_in_world_space() {
    let scene = scenes::builtin("free_fall").unwrap().build().unwrap();
    let mut log = Log::default();
    scene
        .space
        .debug_draw(&mut log, &DebugDrawOptions::default());
    let (_, ball) = scene
        .space
        .bodies()
        .find(|(_, b)| b.body_type() == BodyType::Dynamic)
        .unwrap();
    let [x, y] = point(ball.position());
    assert!(log
        .circles
        .iter()
        .any(|(c, r, _)| c[0] == x && c[1] == y && *r > 0.0));
}

#[test]
fn debug_draw_joints_as_lines_between_anchors_and_state_unchanged() {
    let mut scene = scenes::builtin("chain_100").unwrap().build().unwrap();
    scene.step_n(3).unwrap();
    let before = scene.space.checksum();
    let only_joints = DebugDrawOptions {
        shapes: false,
        ..DebugDrawOptions::default()
    };
    let mut log = Log::default();
    scene.space.debug_draw(&mut log, &only_joints);
    // One line and two anchor dots per pivot joint.
    assert_eq!((log.segments, log.dots), (100, 200));
    assert_eq!(scene.space.checksum(), before);
    let mut log = Log::default();
    let no_joints = DebugDrawOptions {
        joints: false,
        ..only_joints
    };
    scene.space.debug_draw(&mut log, &no_joints);
    assert_eq!((log.segments, log.dots), (0, 0));
}
