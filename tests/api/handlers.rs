//! Collision handler semantics (MIS `spaceAddCollisionHandler`, Chipmunk's
//! begin / pre-solve / post-solve / separate contract) and post-step callbacks.
use tamias2d_scenes::shared::Shared;

use tamias2d::arbiter::ArbiterState;
use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::Shape;
use tamias2d::space::{ShapeHandle, Space};

const BALL: u32 = 1;
const GROUND: u32 = 2;

struct World {
    space: Space,
    ball: BodyHandle,
    ball_shape: ShapeHandle,
}

/// A ball of radius 0.5 at height `y` over a static ground segment; both
/// with elasticity `e` (so `e = 1` bounces forever, `e = 0` rests).
fn world(y: i32, e: Real) -> World {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut seg = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    )
    .unwrap()
    .with_material(Real::ONE, e)
    .unwrap();
    seg.collision_type = GROUND;
    space.add_shape(seg).unwrap();
    let mut b = Body::new(Real::ONE, real!(0.125)).unwrap();
    b.set_position(Vect::from_ints(0, y));
    let ball = space.add_body(b).unwrap();
    let mut c = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)
        .unwrap()
        .with_material(Real::ONE, e)
        .unwrap();
    c.collision_type = BALL;
    let ball_shape = space.add_shape(c).unwrap();
    World {
        space,
        ball,
        ball_shape,
    }
}

fn counter() -> Shared<u32> {
    Shared::new(0)
}

fn run(space: &mut Space, steps: u32) {
    for _ in 0..steps {
        space.step(Real::ratio(1, 60)).unwrap();
    }
}

#[test]
fn bouncing_ball_begins_and_separates_in_pairs() {
    let mut w = world(2, Real::ONE);
    let (begins, separates) = (counter(), counter());
    let h = w.space.add_collision_handler(BALL, GROUND);
    let b = begins.clone();
    h.begin = Some(Box::new(move |ctx| {
        assert!(ctx.arbiter.is_first_contact());
        b.set(b.get() + 1);
        true
    }));
    let s = separates.clone();
    h.separate = Some(Box::new(move |_| s.set(s.get() + 1)));
    run(&mut w.space, 400);
    // A perfectly elastic ball bounces again and again: each touch is one
    // begin, each lift-off one separate.
    assert!(begins.get() >= 3, "begins = {}", begins.get());
    let touching = u32::from(
        w.space
            .arbiters()
            .iter()
            .any(|a| a.state() != ArbiterState::Cached),
    );
    assert_eq!(begins.get(), separates.get() + touching);
}

#[test]
fn handler_sees_its_own_type_order_even_when_swapped() {
    let mut w = world(1, Real::ZERO);
    let ok = counter();
    let o = ok.clone();
    let ball_shape = w.ball_shape;
    // Registered as (GROUND, BALL): the arbiter's canonical order is the
    // other way round, so the context must swap.
    w.space.add_collision_handler(GROUND, BALL).pre_solve = Some(Box::new(move |ctx| {
        let (a, b) = ctx.shapes();
        assert_eq!(b, ball_shape);
        assert_ne!(a, ball_shape);
        // The normal points from the ground (a) to the ball (b): up.
        assert!(ctx.normal().y > real!(0.99));
        o.set(o.get() + 1);
        true
    }));
    run(&mut w.space, 60);
    assert!(ok.get() > 0);
}

#[test]
fn pre_solve_false_lets_the_ball_fall_through() {
    let mut w = world(1, Real::ZERO);
    w.space.add_collision_handler(BALL, GROUND).pre_solve = Some(Box::new(|_| false));
    run(&mut w.space, 120);
    let y = w.space.body(w.ball).unwrap().position().y;
    assert!(
        y < Real::from_int(-5),
        "ball should have fallen through, y = {y}"
    );
}

#[test]
fn begin_false_ignores_the_pair_until_separation() {
    let mut w = world(1, Real::ZERO);
    let pre = counter();
    let p = pre.clone();
    let h = w.space.add_collision_handler(BALL, GROUND);
    h.begin = Some(Box::new(|_| false));
    h.pre_solve = Some(Box::new(move |_| {
        p.set(p.get() + 1);
        true
    }));
    run(&mut w.space, 120);
    assert_eq!(pre.get(), 0, "pre-solve must not run for an ignored pair");
    assert!(w.space.body(w.ball).unwrap().position().y < Real::ZERO);
}

#[test]
fn wildcard_handlers_fire_for_every_partner() {
    let mut w = world(1, Real::ZERO);
    let (ball_hits, ground_hits) = (counter(), counter());
    let b = ball_hits.clone();
    w.space.add_wildcard_handler(BALL).begin = Some(Box::new(move |_| {
        b.set(b.get() + 1);
        true
    }));
    let g = ground_hits.clone();
    w.space.add_wildcard_handler(GROUND).begin = Some(Box::new(move |_| {
        g.set(g.get() + 1);
        true
    }));
    run(&mut w.space, 60);
    assert_eq!(ball_hits.get(), 1);
    assert_eq!(ground_hits.get(), 1);
    // Both accepted: the ball rests on the ground.
    let y = w.space.body(w.ball).unwrap().position().y;
    assert!(y > real!(0.35) && y <= Real::HALF, "y = {y}");
}

#[test]
fn post_solve_sees_the_impulse_that_holds_the_ball_up() {
    let mut w = world(1, Real::ZERO);
    let last = Shared::new(Vect::ZERO);
    let l = last.clone();
    w.space.add_collision_handler(BALL, GROUND).post_solve = Some(Box::new(move |ctx| {
        l.set(ctx.arbiter.total_impulse());
    }));
    run(&mut w.space, 180);
    // Resting: the contact impulse per step carries the weight, m·g·dt = 1/6.
    let j = last.get().length();
    let weight = Real::from_int(10) * Real::ratio(1, 60);
    assert!(
        (j - weight).abs() < real!(0.001),
        "impulse {j} vs weight·dt {weight}"
    );
}

#[test]
fn removing_the_ball_from_a_post_step_callback_is_safe_and_calls_separate() {
    let mut w = world(1, Real::ZERO);
    let separates = counter();
    let ball = w.ball;
    let h = w.space.add_collision_handler(BALL, GROUND);
    h.begin = Some(Box::new(move |ctx| {
        ctx.add_post_step_callback(
            7,
            Box::new(move |space: &mut Space| {
                space.remove_body(ball).unwrap();
            }),
        );
        true
    }));
    let s = separates.clone();
    h.separate = Some(Box::new(move |_| s.set(s.get() + 1)));
    run(&mut w.space, 120);
    assert!(w.space.body(ball).is_none());
    assert_eq!(w.space.shape(w.ball_shape), None);
    assert_eq!(
        separates.get(),
        1,
        "removal of a touching pair calls separate"
    );
    assert!(w.space.arbiters().is_empty());
    w.space.validate().unwrap();
}

#[test]
fn post_step_keys_are_deduplicated() {
    let mut space = Space::new();
    let ran = counter();
    let (r1, r2) = (ran.clone(), ran.clone());
    assert!(space.add_post_step_callback(1, Box::new(move |_| r1.set(r1.get() + 1))));
    assert!(!space.add_post_step_callback(1, Box::new(move |_| r2.set(r2.get() + 10))));
    space.step(Real::ratio(1, 60)).unwrap();
    assert_eq!(ran.get(), 1);
}

#[test]
fn sensors_report_but_do_not_collide() {
    let mut w = world(1, Real::ZERO);
    w.space
        .modify_shape(w.ball_shape, |s| {
            s.sensor = true;
            Ok(())
        })
        .unwrap();
    let (begins, posts) = (counter(), counter());
    let b = begins.clone();
    let p = posts.clone();
    let h = w.space.add_collision_handler(BALL, GROUND);
    h.begin = Some(Box::new(move |_| {
        b.set(b.get() + 1);
        true
    }));
    h.post_solve = Some(Box::new(move |_| p.set(p.get() + 1)));
    run(&mut w.space, 120);
    assert_eq!(begins.get(), 1);
    assert_eq!(posts.get(), 0, "sensors are never solved, so no post-solve");
    assert!(w.space.body(w.ball).unwrap().position().y < Real::ZERO);
}

#[test]
fn locked_space_rejects_changes_from_handlers_paths() {
    // Outside the step the space is unlocked and accepts changes.
    let mut w = world(1, Real::ZERO);
    assert!(!w.space.is_locked());
    assert!(w.space.remove_shape(w.ball_shape).is_ok());
    assert!(
        w.space.remove_shape(w.ball_shape).is_err(),
        "removing twice is an error"
    );
}

/// Callbacks are `Send + Sync`, so a `Space` is: a game can move its world
/// to another thread, share it with a query thread, or keep it as a Bevy
/// resource.
#[test]
fn a_space_is_send_and_sync() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Space>();
    send_sync::<tamias2d::space::FrameState>();
}
