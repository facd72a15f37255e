//! Chains (smooth terrain): a box, a rounded box and a capsule slide over the
//! 20 seams of a flat chain without snagging, at 2, 4 and 8 m/s, both placed
//! on the chain and landing on it from a fall; the same segments without
//! neighbours do snag (so the test can fail); `Space::add_chain` validates
//! and adds all or nothing.
//!
//! # What a snag is
//!
//! The ground is flat and frictionless (friction 0), gravity (0, −10) m/s²,
//! dt = 1/60 s, default settings. On an unbroken flat frictionless floor,
//! physics keeps the horizontal velocity `vx = v0`, and once the body has
//! landed, `vy = 0` and the body flat: the floor can only push straight up.
//! A seam that catches pushes back through a contact whose normal is tilted
//! against the motion (the free end of the next segment), which turns part
//! of the velocity into a loss of speed or an upward hop, or trips the body
//! over. A body sliding over the seams is **snagged** if one of these holds
//! at any step after its first contact with the floor:
//!
//! * it lost more than `SNAG = 1%` of its speed: `v0 − vx > 0.01·v0`;
//! * it moves up faster than 1% of its speed: `vy > 0.01·v0` (from the
//!   step after the first contact: the landing impact stops the fall);
//! * it tilts by more than `TILT = 0.04 rad`;
//! * it does not reach the 20th seam.
//!
//! 1% of `v0` is the velocity change of a deflection of the motion by
//! 0.57°. The floor's own contacts are far below it: their normal is
//! vertical to within the rounding of a unit vector (≲ 2^-30), which over
//! the whole run (≤ 800 steps, each carrying at most a few times the weight
//! `g·dt` of impulse) moves `vx` by less than 10^-5 m/s, 0.0005% of the
//! slowest `v0`; the test checks that floor: the same slide over one
//! unbroken segment stays below 10^-6 of `v0`. The tilt bound is the angle
//! that moves a corner of the 0.5 m wide riders by 1 cm (`atan(0.01/0.25)`),
//! the resting-penetration tolerance a platformer asks for: a body tripped
//! by a seam turns much further (the loose segments below tip boxes over).
//!
//! What the chain leaves (measured, printed by the test): no speed lost at
//! all, hops below 2·10^-5 of `v0`, and a rocking of up to 0.01 rad of a
//! body that has landed or rides tilted. The rocking comes from the joints
//! (an unbroken segment shows none, < 10^-6): a contact at a joint vertex
//! whose normal points into the neighbouring segment is left to the
//! neighbour or given the chain's normal at the joint (the neighbour rule,
//! `src/collision/pairs.rs`), so as a body crosses a joint its contacts
//! move from one segment's to the other's and it can pivot slightly before
//! it settles. That the joints never let a body through is
//! `tests/regressions/chain_fall_through.rs`.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::shape::mass::{moment_for_box, moment_for_segment};
use tamias2d::shape::{Chain, ChainError, ChainKind, Shape, ShapeError};
use tamias2d::space::{Settings, Space, SpaceError};
use tamias2d::{real, Real, Vect};

/// The snag bound, as a fraction of the slide speed (see the module docs).
const SNAG: f64 = 0.01;
/// The tilt bound (rad): the angle that lifts or sinks a corner at the
/// riders' half width (0.25 m) by 1 cm, the resting-penetration tolerance a
/// platformer asks for (see the module docs).
const TILT: f64 = 0.04;
/// Seams crossed: the chain has 21 segments of 1 m.
const SEAMS: i32 = 20;

#[derive(Clone, Copy, Debug)]
enum Rider {
    /// A 0.5 m × 0.5 m box, sharp corners.
    Box,
    /// A 0.4 m × 0.4 m box rounded by 0.05 m (0.5 m × 0.5 m outside).
    RoundedBox,
    /// A lying capsule: a segment shape from (−0.25, 0) to (0.25, 0) with
    /// radius 0.25 (1 m long outside, 0.5 m tall).
    Capsule,
}

/// Makes a rider's shape on its body.
type MakeShape = fn(BodyHandle) -> Result<Shape, ShapeError>;

impl Rider {
    /// Half height: the centre's height above the floor when touching it.
    fn half_height(self) -> Real {
        real!(0.25)
    }

    /// Distance from the centre to the farthest point of the shape.
    fn reach(self) -> f64 {
        match self {
            Rider::Box | Rider::RoundedBox => 0.5f64.sqrt() * 0.5,
            Rider::Capsule => 0.5,
        }
    }

    fn add(self, space: &mut Space, at: Vect) -> BodyHandle {
        let m = Real::ONE;
        let (body, shape): (Body, MakeShape) = match self {
            Rider::Box => (
                Body::new(m, moment_for_box(m, real!(0.5), real!(0.5))).unwrap(),
                |b| Shape::box_shape_new(b, real!(0.5), real!(0.5), Real::ZERO),
            ),
            Rider::RoundedBox => (
                Body::new(m, moment_for_box(m, real!(0.5), real!(0.5))).unwrap(),
                |b| Shape::box_shape_new(b, real!(0.4), real!(0.4), real!(0.05)),
            ),
            Rider::Capsule => {
                let (a, b) = (
                    Vect::new(real!(-0.25), Real::ZERO),
                    Vect::new(real!(0.25), Real::ZERO),
                );
                (
                    Body::new(m, moment_for_segment(m, a, b, real!(0.25))).unwrap(),
                    |h| {
                        Shape::segment_shape_new(
                            h,
                            Vect::new(real!(-0.25), Real::ZERO),
                            Vect::new(real!(0.25), Real::ZERO),
                            real!(0.25),
                        )
                    },
                )
            }
        };
        let h = space.add_body(body).unwrap();
        space.body_mut(h).unwrap().set_position(at);
        space.add_shape(shape(h).unwrap()).unwrap();
        h
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Floor {
    /// `add_chain`: 21 segments with neighbours.
    Chain,
    /// The same 21 segments added one by one, without neighbours.
    LooseSegments,
    /// One unbroken segment over the same span (the reference).
    Unbroken,
}

/// Worst deviations of one slide, as fractions of `v0`.
#[derive(Clone, Copy, Debug, Default)]
struct Slide {
    speed_lost: f64,
    hop: f64,
    spin: f64,
    /// Largest |angle| (rad).
    tilt: f64,
    /// Seams the centre passed.
    seams: i32,
}

fn floor_points() -> Vec<Vect> {
    (0..=SEAMS + 1).map(|x| Vect::from_ints(x, 0)).collect()
}

/// A space with the default settings and gravity (0, −10) and the floor on
/// a static body.
fn world(floor: Floor) -> Space {
    let mut space = Space::new();
    space
        .set_settings(Settings {
            gravity: Vect::from_ints(0, -10),
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    let points = floor_points();
    match floor {
        Floor::Chain => {
            let chain = Chain::new(&points, ChainKind::Open).unwrap();
            assert_eq!(space.add_chain(ground, &chain).unwrap().len(), 21);
        }
        Floor::LooseSegments => {
            for w in points.windows(2) {
                space
                    .add_shape(Shape::segment_shape_new(ground, w[0], w[1], Real::ZERO).unwrap())
                    .unwrap();
            }
        }
        Floor::Unbroken => {
            let (a, b) = (points[0], points[points.len() - 1]);
            space
                .add_shape(Shape::segment_shape_new(ground, a, b, Real::ZERO).unwrap())
                .unwrap();
        }
    }
    space
}

/// Slides `rider` at `v0` m/s from x = 0.5 m until its centre has passed 20
/// seams (x = 20.5 m), starting either resting on the floor or `drop` metres
/// above it (already moving at `v0`), and returns the worst deviations.
fn slide(rider: Rider, floor: Floor, v0: i32, drop: Real) -> Slide {
    let mut space = world(floor);
    let start = Vect::new(real!(0.5), rider.half_height() + drop);
    let h = rider.add(&mut space, start);
    let v0r = Real::from_int(v0);
    space
        .body_mut(h)
        .unwrap()
        .set_velocity(Vect::new(v0r, Real::ZERO));
    let dt = Real::ONE / Real::from_int(60);
    let v0f = f64::from(v0);
    let mut out = Slide::default();
    let mut landed = false;
    // 20 m at v0, plus the fall (≤ 1 s), plus 1 s: a snag that stops the
    // body shows as lost speed long before the step budget runs out.
    let steps = 20 * 60 / v0 + 120;
    for _ in 0..steps {
        space.step(dt).unwrap();
        let b = space.body(h).unwrap();
        let (vx, vy) = b.velocity().to_f64();
        let w = b.angular_velocity().to_f64();
        let touching = !space.arbiters().is_empty();
        if touching || landed {
            out.speed_lost = out.speed_lost.max((v0f - vx) / v0f);
            out.spin = out.spin.max(w.abs() * rider.reach() / v0f);
            out.tilt = out.tilt.max(b.angle().to_f64().abs());
        }
        if landed {
            out.hop = out.hop.max(vy / v0f);
        }
        landed |= touching;
        let x = b.position().x.to_f64();
        out.seams = (x.floor() as i32).clamp(0, SEAMS);
        if x > 20.5 {
            break;
        }
    }
    out
}

const RIDERS: [Rider; 3] = [Rider::Box, Rider::RoundedBox, Rider::Capsule];
const SPEEDS: [i32; 3] = [2, 4, 8];
/// Drop heights: resting on the floor, and landing from 1 m (4.5 m/s).
const DROPS: [Real; 2] = [Real::ZERO, Real::ONE];

impl Slide {
    /// The snag test of the module docs.
    fn snagged(&self) -> bool {
        self.speed_lost > SNAG || self.hop > SNAG || self.tilt > TILT || self.seams < SEAMS
    }
}

#[test]
fn box_rounded_box_and_capsule_slide_over_20_seams_of_a_chain_without_snagging() {
    for rider in RIDERS {
        for v0 in SPEEDS {
            for drop in DROPS {
                let s = slide(rider, Floor::Chain, v0, drop);
                println!("chain {rider:?} v0 = {v0} m/s, drop {drop} m: {s:?}");
                assert!(!s.snagged(), "{rider:?} at {v0} m/s, drop {drop} m: {s:?}");
            }
        }
    }
}

#[test]
fn the_same_slide_over_one_unbroken_segment_is_at_the_noise_floor() {
    // The reference: no seams at all. Its deviations are rounding only,
    // six orders of magnitude below the snag bound.
    for rider in RIDERS {
        for v0 in SPEEDS {
            for drop in DROPS {
                let s = slide(rider, Floor::Unbroken, v0, drop);
                assert!(
                    s.speed_lost.max(s.hop).max(s.spin).max(s.tilt) < 1e-6,
                    "{rider:?} at {v0} m/s, drop {drop} m: {s:?}"
                );
            }
        }
    }
}

#[test]
fn without_neighbours_the_same_segments_snag() {
    // The test can fail: the same 21 segments added one by one catch every
    // rider that lands on them, at every speed.
    for rider in RIDERS {
        for v0 in SPEEDS {
            let s = slide(rider, Floor::LooseSegments, v0, Real::ONE);
            println!("loose {rider:?} v0 = {v0} m/s, drop 1 m: {s:?}");
            assert!(s.snagged(), "{rider:?} at {v0} m/s: {s:?}");
            assert!(
                s.speed_lost > SNAG,
                "{rider:?} at {v0} m/s loses speed at a seam: {s:?}"
            );
        }
    }
}

#[test]
fn add_chain_adds_segments_with_neighbours_in_order() {
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    let points = [
        Vect::from_ints(0, 0),
        Vect::from_ints(3, 0),
        Vect::from_ints(3, 2),
        Vect::from_ints(0, 2),
    ];
    let chain = Chain::new(&points, ChainKind::Loop)
        .unwrap()
        .with_radius(real!(0.125))
        .unwrap()
        .with_material(real!(0.7), Real::ZERO)
        .unwrap();
    let handles = space.add_chain(ground, &chain).unwrap();
    assert_eq!(handles.len(), 4);
    for (i, h) in handles.iter().enumerate() {
        let shape = space.shape(*h).unwrap();
        assert_eq!(shape.body(), ground);
        assert_eq!(shape.material.friction, real!(0.7));
        let seg = *shape.segment().unwrap();
        let (prev, a, b, next) = (
            points[(i + 3) % 4],
            points[i],
            points[(i + 1) % 4],
            points[(i + 2) % 4],
        );
        // The same segment as set up by hand with `set_segment_neighbors`.
        let mut by_hand = Shape::segment_shape_new(ground, a, b, real!(0.125)).unwrap();
        by_hand.set_segment_neighbors(prev, next).unwrap();
        assert_eq!(&seg, by_hand.segment().unwrap(), "segment {i}");
    }
}

#[test]
fn add_chain_errors_leave_the_space_unchanged() {
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    let chain = Chain::new(&floor_points(), ChainKind::Open).unwrap();
    // A body of another space, and a removed body.
    let mut other = Space::new();
    let foreign = other.add_body(Body::new_static()).unwrap();
    assert_eq!(
        space.add_chain(foreign, &chain),
        Err(SpaceError::ForeignHandle)
    );
    let gone = space.add_body(Body::new_static()).unwrap();
    space.remove_body(gone).unwrap();
    assert_eq!(
        space.add_chain(gone, &chain),
        Err(SpaceError::StaleBody(gone))
    );
    assert_eq!(space.shapes().count(), 0);
    // Bad points are refused when the chain is made, before any space.
    assert_eq!(
        Chain::new(&[Vect::ZERO], ChainKind::Open),
        Err(ShapeError::Chain(ChainError::TooFewPoints {
            count: 1,
            needed: 2
        }))
    );
    assert_eq!(space.add_chain(ground, &chain).unwrap().len(), 21);
}
