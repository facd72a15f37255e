//! Regression: in a collision handler, `ctx.shapes()` is in the handler's
//! order (shape a has the handler's `type_a`, swapped from the arbiter's
//! canonical order when needed), but the bodies were only available as
//! `ctx.arbiter.bodies()`, in the arbiter's order: for a swapped pair the
//! first body was not the first shape's body. Fix: `ctx.bodies()`, the two
//! bodies in the order of `ctx.shapes()` (Chipmunk's `cpArbiterGetBodies`
//! follows `cpArbiterGetShapes` the same way); `Arbiter::shapes()` and
//! `Arbiter::bodies()` stay in one (canonical) order.
use tamias2d_scenes::shared::Shared;

use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::space::{ShapeHandle, Space};

type Seen = Shared<Vec<(bool, ShapeHandle, ShapeHandle, BodyHandle, BodyHandle)>>;

/// Ground (type 1) added first, so the arbiter's shape a is the ground; a
/// ball (type 2) resting on it.
fn world() -> (Space, BodyHandle, BodyHandle) {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let g = w.add_body(Body::new_static()).unwrap();
    let mut seg = Shape::segment_shape_new(
        g,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    )
    .unwrap();
    seg.collision_type = 1;
    w.add_shape(seg).unwrap();
    let b = w
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    w.body_mut(b)
        .unwrap()
        .set_position(Vect::new(Real::ZERO, Real::HALF));
    let mut c = Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).unwrap();
    c.collision_type = 2;
    w.add_shape(c).unwrap();
    (w, g, b)
}

fn check(w: &mut Space, seen: &Seen) {
    w.step(Real::ratio(1, 60)).unwrap();
    let got = seen.borrow().clone();
    assert!(!got.is_empty(), "the handler ran");
    for (_, s1, s2, b1, b2) in got {
        assert_eq!(w.shape(s1).unwrap().body(), b1);
        assert_eq!(w.shape(s2).unwrap().body(), b2);
    }
}

fn recorder(seen: &Seen) -> tamias2d::space::handlers::FilterFn {
    let log = Shared::clone(seen);
    Box::new(move |ctx| {
        let (s1, s2) = ctx.shapes();
        let (b1, b2) = ctx.bodies();
        log.borrow_mut().push((ctx.swapped(), s1, s2, b1, b2));
        true
    })
}

#[test]
fn swapped_pair_handler_sees_bodies_in_its_shape_order() {
    let (mut w, ground, ball) = world();
    let seen: Seen = Shared::default();
    w.add_collision_handler(2, 1).pre_solve = Some(recorder(&seen));
    check(&mut w, &seen);
    let (swapped, _, _, b1, b2) = seen.borrow()[0];
    assert!(
        swapped,
        "the handler's (2, 1) is the arbiter's (1, 2) swapped"
    );
    assert_eq!((b1, b2), (ball, ground));
    // The arbiter's own accessors agree with each other (canonical order).
    let arb = &w.arbiters()[0];
    let (sa, sb) = arb.shapes();
    assert_eq!(
        arb.bodies(),
        (w.shape(sa).unwrap().body(), w.shape(sb).unwrap().body())
    );
}

#[test]
fn unswapped_and_wildcard_handlers_agree_too() {
    let (mut w, ground, _) = world();
    let seen: Seen = Shared::default();
    w.add_collision_handler(1, 2).begin = Some(recorder(&seen));
    check(&mut w, &seen);
    assert_eq!(seen.borrow()[0].3, ground);

    // The wildcard of type 2 (the arbiter's shape b) runs swapped.
    let (mut w, _, ball) = world();
    let seen: Seen = Shared::default();
    w.add_wildcard_handler(2).begin = Some(recorder(&seen));
    check(&mut w, &seen);
    assert!(seen.borrow()[0].0);
    assert_eq!(seen.borrow()[0].3, ball);
}
