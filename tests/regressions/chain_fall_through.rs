//! Regression: bodies fell through chain terrain at its joints.
//!
//! Symptom: a 1 × 1 m box resting with a corner over a joint of an open
//! chain (`Space::add_chain`, joints every 2 m), tilted −0.05 rad, fell
//! through the chain and kept falling; the same points as loose segments
//! held it. Boxes of a game and of a pyramid standing on a chain were lost
//! the same way.
//!
//! Cause: the neighbour rule (a contact found at a joint whose normal
//! leaves the joint towards the neighbouring segment is left to that
//! neighbour) trusted the normal to say where the body is. That holds for
//! shapes whose cores are apart (the normal is then the true direction to
//! the nearest point, so the neighbour is strictly nearer and reports its
//! own contact), not for touching or overlapping cores, the resting state
//! of sharp shapes on zero-radius segments: there the normal is only one
//! segment's way out (GJK's pick among equal answers, EPA's shortest way
//! out), which may point off the end of each segment into the other. Both
//! segments then left the contact to each other and nothing held the body.
//! Now such a contact is kept, with its normal moved to the nearest one the
//! chain allows at the joint (`seam_normal` in `src/collision/pairs.rs`).
//!
//! The test: every shape kind (box, rounded box, polygon, circle, capsule)
//! resting, landing, sliding and spinning over chain joints, at 12 tilts
//! from −0.3 to 0.25 rad and with the body's corner or centre over the joint, on
//! open and loop chains with flat joints and with convex and concave ones
//! (zig-zags: every other joint a Λ, the others a V, gentle and steep). A
//! body is lost when it ends more than 1 m below the terrain; none may be.
//! The bodies of one run share a collision group, so they only meet the
//! terrain: each is its own case.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::shape::mass::{
    area_for_poly, moment_for_box, moment_for_circle, moment_for_poly, moment_for_segment,
};
use tamias2d::shape::{Chain, ChainKind, Shape, ShapeFilter};
use tamias2d::space::{Settings, Space};
use tamias2d::{real, Real, Vect};

/// Joint spacing of every terrain (m).
const SPACING: f64 = 2.0;
/// Bodies per run: one per joint, each over its own joint.
const TILTS: [f64; 12] = [
    -0.3, -0.2, -0.1, -0.05, -0.02, -0.01, 0.0, 0.01, 0.03, 0.05, 0.1, 0.25,
];
/// Where the body's centre is, from the joint (m): a corner of the 1 m
/// shapes over the joint, just past it, or the centre over it.
const OFFSETS: [f64; 4] = [-0.5, -0.47, 0.0, 0.5];
/// Free joints left and right of the bodies (sliders travel ≤ 4 m).
const MARGIN: usize = 4;
/// Steps per run (2 s at 60 Hz).
const STEPS: u32 = 120;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// 1 × 1 m, sharp corners.
    Box,
    /// 0.8 × 0.8 m rounded by 0.1 m.
    RoundedBox,
    /// An irregular pentagon about 1.2 m wide.
    Polygon,
    /// Radius 0.5 m.
    Circle,
    /// A lying capsule 1.3 m long, 0.5 m thick.
    Capsule,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Motion {
    /// Placed 1 cm above the terrain, at rest.
    Resting,
    /// Dropped from 1 m above the terrain.
    Landing,
    /// Placed 1 cm above, moving at 3 m/s along the terrain (frictionless),
    /// starting 1 m before the joint (alternately from the left and right).
    Sliding,
    /// Placed 1 cm above, turning at 6 rad/s (alternately each way).
    Spinning,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Terrain {
    /// An open flat chain.
    FlatOpen,
    /// The flat top of a closed loop (a 4 m deep box).
    FlatLoop,
    /// An open zig-zag rising and falling 0.06 m per joint (slopes 0.03:
    /// nearly flat convex and concave joints).
    GentleZigzagOpen,
    /// The zig-zag top of a closed loop rising and falling 0.8 m per joint
    /// (slopes 0.4).
    SteepZigzagLoop,
}

const KINDS: [Kind; 5] = [
    Kind::Box,
    Kind::RoundedBox,
    Kind::Polygon,
    Kind::Circle,
    Kind::Capsule,
];
const MOTIONS: [Motion; 4] = [
    Motion::Resting,
    Motion::Landing,
    Motion::Sliding,
    Motion::Spinning,
];
const TERRAINS: [Terrain; 4] = [
    Terrain::FlatOpen,
    Terrain::FlatLoop,
    Terrain::GentleZigzagOpen,
    Terrain::SteepZigzagLoop,
];

fn r(x: f64) -> Real {
    Real::from_f64(x).unwrap()
}

impl Terrain {
    /// Height of joint `i`.
    fn joint_height(self, i: usize) -> f64 {
        let odd = i % 2 == 1;
        match self {
            Terrain::FlatOpen | Terrain::FlatLoop => 0.0,
            Terrain::GentleZigzagOpen => f64::from(u8::from(odd)) * 0.06,
            Terrain::SteepZigzagLoop => f64::from(u8::from(odd)) * 0.8,
        }
    }

    /// Height of the surface at `x` (linear between joints).
    fn height(self, x: f64) -> f64 {
        let s = (x / SPACING).clamp(0.0, 1e9);
        let i = s.floor() as usize;
        let t = s - s.floor();
        self.joint_height(i) * (1.0 - t) + self.joint_height(i + 1) * t
    }

    /// Highest surface point over `[x0, x1]`.
    fn max_height(self, x0: f64, x1: f64) -> f64 {
        let mut h = self.height(x0).max(self.height(x1));
        let mut x = (x0 / SPACING).ceil() * SPACING;
        while x < x1 {
            h = h.max(self.height(x));
            x += SPACING;
        }
        h
    }

    /// The chain for `joints` joints (0 ..= joints − 1 along x).
    fn chain(self, joints: usize) -> Chain {
        let mut points: Vec<Vect> = (0..joints)
            .map(|i| Vect::new(r(i as f64 * SPACING), r(self.joint_height(i))))
            .collect();
        let kind = match self {
            Terrain::FlatOpen | Terrain::GentleZigzagOpen => ChainKind::Open,
            Terrain::FlatLoop | Terrain::SteepZigzagLoop => {
                // Down the right side, back along the bottom, up the left.
                let right = (joints - 1) as f64 * SPACING;
                points.push(Vect::new(r(right), r(-4.0)));
                points.push(Vect::new(r(0.0), r(-4.0)));
                ChainKind::Loop
            }
        };
        Chain::new(&points, kind)
            .unwrap()
            .with_material(Real::ONE, Real::ZERO)
            .unwrap()
    }
}

impl Kind {
    /// Vertices (polygons), or the segment (capsule), in body coordinates.
    fn outline(self) -> Vec<(f64, f64)> {
        match self {
            Kind::Box => vec![(0.5, -0.5), (0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5)],
            Kind::RoundedBox => vec![(0.4, -0.4), (0.4, 0.4), (-0.4, 0.4), (-0.4, -0.4)],
            Kind::Polygon => vec![
                (-0.5, -0.4),
                (0.5, -0.5),
                (0.6, 0.2),
                (0.0, 0.6),
                (-0.6, 0.2),
            ],
            Kind::Circle => vec![(0.0, 0.0)],
            Kind::Capsule => vec![(-0.4, 0.0), (0.4, 0.0)],
        }
    }

    /// Rounding radius.
    fn radius(self) -> f64 {
        match self {
            Kind::Box | Kind::Polygon => 0.0,
            Kind::RoundedBox => 0.1,
            Kind::Circle => 0.5,
            Kind::Capsule => 0.25,
        }
    }

    /// The body (density 1) and its shape.
    fn add(self, space: &mut Space, at: (f64, f64), angle: f64, friction: Real) -> BodyHandle {
        let pts: Vec<Vect> = self
            .outline()
            .iter()
            .map(|&(x, y)| Vect::new(r(x), r(y)))
            .collect();
        let rad = r(self.radius());
        let body = match self {
            Kind::Box => Body::new(Real::ONE, moment_for_box(Real::ONE, Real::ONE, Real::ONE)),
            Kind::RoundedBox | Kind::Polygon => {
                let m = area_for_poly(&pts, rad);
                Body::new(m, moment_for_poly(m, &pts, Vect::ZERO, rad))
            }
            Kind::Circle => {
                let m = r(std::f64::consts::PI * 0.25);
                Body::new(m, moment_for_circle(m, Real::ZERO, rad, Vect::ZERO))
            }
            Kind::Capsule => {
                let m = r(0.8 * 0.5 + std::f64::consts::PI * 0.0625);
                Body::new(m, moment_for_segment(m, pts[0], pts[1], rad))
            }
        }
        .unwrap();
        let h = space.add_body(body).unwrap();
        let b = space.body_mut(h).unwrap();
        b.set_position(Vect::new(r(at.0), r(at.1)));
        b.set_angle(r(angle));
        let shape = match self {
            Kind::Box | Kind::RoundedBox | Kind::Polygon => {
                Shape::poly_shape_new(h, &pts, &tamias2d::math::Transform::IDENTITY, rad)
            }
            Kind::Circle => Shape::circle_shape_new(h, rad, Vect::ZERO),
            Kind::Capsule => Shape::segment_shape_new(h, pts[0], pts[1], rad),
        }
        .unwrap()
        .with_material(friction, Real::ZERO)
        .unwrap();
        let mut shape = shape;
        shape.filter = ShapeFilter {
            group: 1,
            ..ShapeFilter::ALL
        };
        space.add_shape(shape).unwrap();
        h
    }

    /// Lowest and extreme x of the shape turned by `angle` (body origin at 0).
    fn extent(self, angle: f64) -> (f64, f64, f64) {
        let (s, c) = angle.sin_cos();
        let rad = self.radius();
        let turned: Vec<(f64, f64)> = self
            .outline()
            .iter()
            .map(|&(x, y)| (x * c - y * s, x * s + y * c))
            .collect();
        let low = turned.iter().map(|p| p.1).fold(f64::MAX, f64::min) - rad;
        let left = turned.iter().map(|p| p.0).fold(f64::MAX, f64::min) - rad;
        let right = turned.iter().map(|p| p.0).fold(f64::MIN, f64::max) + rad;
        (low, left, right)
    }
}

/// Runs one terrain, shape kind and motion with a body over each joint for
/// every tilt and offset; returns (bodies lost, bodies).
fn run(terrain: Terrain, kind: Kind, motion: Motion) -> (usize, usize) {
    let cases: Vec<(f64, f64)> = TILTS
        .iter()
        .flat_map(|&t| OFFSETS.iter().map(move |&o| (t, o)))
        .collect();
    let joints = cases.len() + 2 * MARGIN;
    let mut space = Space::new();
    space
        .set_settings(Settings {
            gravity: Vect::from_ints(0, -10),
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    space.add_chain(ground, &terrain.chain(joints)).unwrap();
    let mut bodies = Vec::new();
    for (k, &(tilt, offset)) in cases.iter().enumerate() {
        let joint = (k + MARGIN) as f64 * SPACING;
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let x = match motion {
            Motion::Sliding => joint + offset - sign,
            _ => joint + offset,
        };
        let (low, left, right) = kind.extent(tilt);
        let lift = if motion == Motion::Landing { 1.0 } else { 0.01 };
        let y = terrain.max_height(x + left, x + right) - low + lift;
        let friction = if motion == Motion::Sliding {
            Real::ZERO
        } else {
            real!(0.7)
        };
        let h = kind.add(&mut space, (x, y), tilt, friction);
        bodies.push(h);
        let b = space.body_mut(h).unwrap();
        match motion {
            Motion::Sliding => b.set_velocity(Vect::new(r(3.0 * sign), Real::ZERO)),
            Motion::Spinning => b.set_angular_velocity(r(6.0 * sign)),
            Motion::Resting | Motion::Landing => {}
        }
    }
    let dt = Real::ONE / Real::from_int(60);
    for _ in 0..STEPS {
        space.step(dt).unwrap();
    }
    let lost = bodies
        .iter()
        .filter(|&&h| {
            let (x, y) = space.body(h).unwrap().position().to_f64();
            y < terrain.height(x) - 1.0
        })
        .count();
    (lost, bodies.len())
}

#[test]
fn no_body_falls_through_chain_joints_for_any_shape_tilt_or_motion() {
    let mut lost = 0;
    let mut total = 0;
    let mut report = Vec::new();
    for terrain in TERRAINS {
        for kind in KINDS {
            for motion in MOTIONS {
                let (l, n) = run(terrain, kind, motion);
                println!("{terrain:?} {kind:?} {motion:?}: {l} of {n} lost");
                if l > 0 {
                    report.push(format!("{terrain:?} {kind:?} {motion:?}: {l} of {n}"));
                }
                lost += l;
                total += n;
            }
        }
    }
    println!("bodies lost: {lost} of {total}");
    assert_eq!(lost, 0, "bodies lost: {lost} of {total}: {report:#?}");
}
