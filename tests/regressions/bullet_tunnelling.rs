//! Polygon bullets passed through static geometry: a 0.2 × 0.1 m box
//! bullet turned 0.3 rad, fired at a static segment at 450 m/s, ended
//! metres beyond it still moving; about one box bullet in four over many
//! angles and speeds ended on the wrong side of a thin segment or a 2 cm
//! static box, while round bullets never did.
//!
//! Cause: see the module docs of `src/space/ccd.rs` ("A pair that
//! already touches"). This test fires every bullet shape kind (box,
//! rounded box, polygon, capsule, circle) at every target kind (a thin
//! static segment, a 2 cm static box, a kinematic wall moving toward the
//! bullets) over angles in `[0, π)`, speeds from 50 to 2,000 m/s, with
//! and without spin, head-on and 0.6 rad off the normal, and counts the bullets whose centroid is ever on the
//! wrong side of the target's mid-plane at the end of a step: none may be.
use tamias2d::body::{Body, BodyHandle};
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::space::Space;
use tamias2d::{Real, Rot, Vect};

fn ok<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

fn dt() -> Real {
    Real::ONE / Real::from_int(60)
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Box,
    RoundedBox,
    Polygon,
    Capsule,
    Circle,
}

const KINDS: [Kind; 5] = [
    Kind::Box,
    Kind::RoundedBox,
    Kind::Polygon,
    Kind::Capsule,
    Kind::Circle,
];

#[derive(Clone, Copy, Debug)]
enum Target {
    /// A static segment of radius 0.
    Segment,
    /// A static box 2 cm thick.
    ThinBox,
    /// A kinematic box 5 cm thick moving at −100 m/s toward the bullets.
    Kinematic,
}

/// The kinematic wall's speed toward the bullets.
const WALL_SPEED: i32 = 100;

fn milli(m: i32) -> Real {
    Real::ratio(m, 1000)
}

fn shape(kind: Kind, h: BodyHandle) -> Shape {
    let s = match kind {
        Kind::Box => Shape::box_shape_new(h, milli(200), milli(100), Real::ZERO),
        Kind::RoundedBox => Shape::box_shape_new(h, milli(200), milli(100), milli(20)),
        Kind::Polygon => Shape::poly_shape_new_raw(
            h,
            &[
                Vect::new(-milli(100), -milli(50)),
                Vect::new(milli(120), Real::ZERO),
                Vect::new(-milli(60), milli(70)),
            ],
            Real::ZERO,
        ),
        Kind::Capsule => Shape::segment_shape_new(
            h,
            Vect::new(-milli(100), Real::ZERO),
            Vect::new(milli(100), Real::ZERO),
            milli(25),
        ),
        Kind::Circle => Shape::circle_shape_new(h, milli(50), Vect::new(milli(30), Real::ZERO)),
    };
    let mut s = ok(s);
    ok(s.set_density(Real::ONE));
    // Bullets never touch each other: only the wall matters.
    s.filter = ShapeFilter {
        group: 1,
        ..ShapeFilter::ALL
    };
    s
}

/// One shot: its shape, angle (`k/angles · π`), speed, spin (rad/s) and
/// direction (mrad from the target's normal).
#[derive(Clone, Copy, Debug)]
struct Shot {
    kind: Kind,
    angle: Real,
    speed: i32,
    spin: i32,
    dir: i32,
}

/// Fires `shots` (one row each, 1 m apart, the target 200 m taller than
/// the rows at each end) at `target` centred on
/// x = 0; returns the shots whose centre of gravity (their shape's
/// centroid) was beyond the target's mid-plane at the end of any of
/// `steps` steps.
fn wrong_side(target: Target, shots: &[Shot], steps: usize) -> Vec<Shot> {
    let mut w = Space::new();
    let rows = i32::try_from(shots.len()).unwrap_or(i32::MAX);
    let height = Real::from_int(rows.saturating_add(400));
    let wall = match target {
        Target::Segment | Target::ThinBox => ok(w.add_body(Body::new_static())),
        Target::Kinematic => {
            let k = ok(w.add_body(Body::new_kinematic()));
            ok(w.body_mut(k).ok_or("wall")).set_velocity(Vect::from_ints(-WALL_SPEED, 0));
            k
        }
    };
    let top = Vect::new(Real::ZERO, height * Real::HALF);
    let wall_shape = match target {
        Target::Segment => Shape::segment_shape_new(wall, -top, top, Real::ZERO),
        Target::ThinBox => Shape::box_shape_new(wall, milli(20), height, Real::ZERO),
        Target::Kinematic => Shape::box_shape_new(wall, milli(50), height, Real::ZERO),
    };
    ok(w.add_shape(ok(wall_shape)));
    let closing = |s: &Shot| match target {
        Target::Kinematic => s.speed + WALL_SPEED,
        Target::Segment | Target::ThinBox => s.speed,
    };
    let handles: Vec<BodyHandle> = shots
        .iter()
        .zip(0..)
        .map(|(s, i)| {
            let mut b = ok(Body::new(Real::ZERO, Real::ZERO));
            // Start 0.3 m plus a phase of one step's closing motion away,
            // the phase spread over the shots (37 is prime to 64).
            let phase = Real::ratio(i * 37 % 64, 64);
            let travel = Real::from_int(closing(s)) * dt();
            let x = -(milli(300) + travel * phase);
            b.set_position(Vect::new(
                x,
                Real::from_int(i) - Real::from_int(rows) * Real::HALF,
            ));
            b.set_angle(s.angle);
            let dir = Rot::from_angle(milli(s.dir)).as_vect();
            b.set_velocity(dir * Real::from_int(s.speed));
            b.set_angular_velocity(Real::from_int(s.spin));
            b.set_bullet(true);
            let h = ok(w.add_body(b));
            ok(w.add_shape(shape(s.kind, h)));
            h
        })
        .collect();
    let mut beyond = vec![false; shots.len()];
    for _ in 0..steps {
        ok(w.step(dt()));
        let wall_x = w.body(wall).map_or(Real::ZERO, |b| b.position().x);
        for (flag, &h) in beyond.iter_mut().zip(&handles) {
            let x = w
                .body(h)
                .map_or(Real::ZERO, |b| b.local_to_world(b.center_of_gravity()).x);
            *flag |= x > wall_x;
        }
    }
    shots
        .iter()
        .zip(&beyond)
        .filter(|(_, &b)| b)
        .map(|(s, _)| *s)
        .collect()
}

/// Every kind at `angles` angles in `[0, π)`, each speed, spin and
/// direction.
fn shots(angles: i32, speeds: &[i32], spins: &[i32], dirs: &[i32]) -> Vec<Shot> {
    let mut out = Vec::new();
    for kind in KINDS {
        for k in 0..angles {
            for &speed in speeds {
                for &spin in spins {
                    for &dir in dirs {
                        out.push(Shot {
                            kind,
                            angle: Real::PI * Real::ratio(k, angles),
                            speed,
                            spin,
                            dir,
                        });
                    }
                }
            }
        }
    }
    out
}

#[test]
fn no_bullet_of_any_kind_ends_on_the_wrong_side() {
    // Fewer cases in unoptimised builds (`cargo test` in CI), every kind,
    // target, spin and the speed range still covered.
    let (angles, speeds): (i32, &[i32]) = if cfg!(debug_assertions) {
        (12, &[50, 170, 450, 1100, 2000])
    } else {
        (48, &[50, 90, 170, 300, 450, 700, 1100, 1500, 2000])
    };
    let all = shots(angles, speeds, &[0, 60], &[0, -600]);
    let mut report = String::new();
    let mut total = 0;
    for target in [Target::Segment, Target::ThinBox, Target::Kinematic] {
        let bad = wrong_side(target, &all, 8);
        for kind in KINDS {
            let n = bad
                .iter()
                .filter(|s| core::mem::discriminant(&s.kind) == core::mem::discriminant(&kind))
                .count();
            let of = all.len() / KINDS.len();
            report.push_str(&format!("{target:?} {kind:?}: {n} of {of}\n"));
        }
        total += bad.len();
    }
    println!("{report}");
    assert_eq!(total, 0, "bullets on the wrong side:\n{report}");
}

#[test]
fn the_issue_shot_stops_at_the_segment() {
    // The reported shot: the box turned 0.3 rad at 450 m/s into a static
    // segment, 32 start phases.
    let shot = Shot {
        kind: Kind::Box,
        angle: milli(300),
        speed: 450,
        spin: 0,
        dir: 0,
    };
    let bad = wrong_side(Target::Segment, &[shot; 32], 10);
    assert_eq!(bad.len(), 0, "{} of 32 passed", bad.len());
}

#[test]
fn a_pair_a_begin_handler_rejects_still_lets_the_bullet_through() {
    // A one-way wall (its begin handler rejects every contact): the sweep
    // stops the bullet at the wall once, then lets it through.
    let mut w = Space::new();
    let wall = ok(w.add_body(Body::new_static()));
    let top = Vect::from_ints(0, 10);
    let mut s = ok(Shape::segment_shape_new(wall, -top, top, Real::ZERO));
    s.collision_type = 7;
    ok(w.add_shape(s));
    w.add_collision_handler(7, 0).begin = Some(Box::new(|_| false));
    let mut b = ok(Body::new(Real::ZERO, Real::ZERO));
    b.set_position(Vect::from_ints(-1, 0));
    b.set_angle(milli(300));
    b.set_velocity(Vect::from_ints(450, 0));
    b.set_bullet(true);
    let h = ok(w.add_body(b));
    ok(w.add_shape(shape(Kind::Box, h)));
    for _ in 0..10 {
        ok(w.step(dt()));
    }
    let x = w.body(h).map_or(Real::ZERO, |b| b.position().x);
    assert!(x > Real::from_int(10), "x = {x:?}");
}
