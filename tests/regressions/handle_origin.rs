//! Regression: handles leaked across spaces. Only `add_body`, `add_shape`,
//! `bodies()` and `shapes()` tagged their handles with the space's origin;
//! handles from queries, `Arbiter::shapes()`/`bodies()`, `body_shapes()`,
//! `Shape::body()`, handler contexts, and every handle inside a world made
//! by `snapshot::load` had no tag (origin 0, "unknown") and were accepted by
//! *any* space: a query result of space A removed a shape of space B.
//! Cause: arenas made untagged handles, and only four accessors re-tagged
//! them. Fix: each arena carries its space's origin (not state: not
//! serialized, compared or hashed) and tags every handle it makes, and
//! rejects handles of another origin on lookup; a space puts its origin on
//! its arenas and on the handles stored in its state (shape → body,
//! arbiters) whenever a state enters it (`from_state`, `snapshot::load`,
//! `restore_state`, `load_snapshot`) and on `add_shape`.
use tamias2d_scenes::shared::Shared;

use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect, BB};
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::snapshot;
use tamias2d::space::{ShapeHandle, Space, SpaceError};

/// Ground segment (collision type 1) and a ball (type 2) resting on it.
fn world() -> Space {
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
    for _ in 0..5 {
        w.step(Real::ratio(1, 60)).unwrap();
    }
    assert!(!w.arbiters().is_empty());
    w
}

/// `h` (valid in `own`) is valid there and refused by `other`, which has
/// an object at the same slot and generation.
fn shape_belongs(own: &Space, other: &mut Space, h: ShapeHandle, what: &str) {
    assert!(own.shape(h).is_some(), "{what}: not valid in its own space");
    assert!(
        other.shape(h).is_none(),
        "{what}: resolved in another space"
    );
    assert_eq!(
        other.remove_shape(h).unwrap_err(),
        SpaceError::ForeignHandle,
        "{what}: removed a shape of another space"
    );
}

fn body_belongs(own: &Space, other: &mut Space, h: BodyHandle, what: &str) {
    assert!(own.body(h).is_some(), "{what}: not valid in its own space");
    assert!(other.body(h).is_none(), "{what}: resolved in another space");
    assert!(other.body_mut(h).is_none(), "{what}: resolved mutably");
    assert_eq!(
        other.remove_body(h).unwrap_err(),
        SpaceError::ForeignHandle,
        "{what}: removed a body of another space"
    );
}

#[test]
fn query_results_name_their_space() {
    let a = world();
    let mut b = world();
    let all = ShapeFilter::ALL;
    let p = Vect::new(Real::ZERO, Real::HALF);
    let (h, _) = a.point_query(p, Real::ONE, all)[0];
    shape_belongs(&a, &mut b, h, "point_query");
    let (h, _) = a.point_query_nearest(p, Real::ONE, all).unwrap();
    shape_belongs(&a, &mut b, h, "point_query_nearest");
    let (s0, s1) = (Vect::from_ints(-5, 5), Vect::from_ints(0, -5));
    let (h, _) = a.segment_query(s0, s1, Real::ZERO, all)[0];
    shape_belongs(&a, &mut b, h, "segment_query");
    let (h, _) = a.segment_query_first(s0, s1, Real::ZERO, all).unwrap();
    shape_belongs(&a, &mut b, h, "segment_query_first");
    let bb = BB::new(-Real::ONE, -Real::ONE, Real::ONE, Real::ONE);
    let h = a.bb_query(bb, all)[0];
    shape_belongs(&a, &mut b, h, "bb_query");
    let probe = *a.shape(h).unwrap().geometry();
    let (h, _) = a.shape_query(&probe, all)[0];
    shape_belongs(&a, &mut b, h, "shape_query");
}

#[test]
fn arbiters_body_shapes_and_shape_body_name_their_space() {
    let a = world();
    let mut b = world();
    let arb = a.arbiters()[0].clone();
    let (sa, sb) = arb.shapes();
    shape_belongs(&a, &mut b, sa, "Arbiter::shapes().0");
    shape_belongs(&a, &mut b, sb, "Arbiter::shapes().1");
    let (ba, bb) = arb.bodies();
    body_belongs(&a, &mut b, ba, "Arbiter::bodies().0");
    body_belongs(&a, &mut b, bb, "Arbiter::bodies().1");
    let ball = a.bodies().nth(1).unwrap().0;
    let (sh, shape) = a.body_shapes(ball).next().unwrap();
    shape_belongs(&a, &mut b, sh, "body_shapes");
    body_belongs(&a, &mut b, shape.body(), "Shape::body");
    // The raw arenas of the state tag their handles too.
    let (h, _) = a.state().shapes.iter().next().unwrap();
    shape_belongs(&a, &mut b, h, "state().shapes.iter()");
    let (h, _) = a.state().bodies.iter().nth(1).unwrap();
    body_belongs(&a, &mut b, h, "state().bodies.iter()");
}

#[test]
fn handler_contexts_hand_out_handles_of_their_space() {
    let mut a = world();
    let mut b = world();
    type Pair = (ShapeHandle, ShapeHandle, BodyHandle, BodyHandle);
    let seen: Shared<Vec<Pair>> = Shared::default();
    let log = Shared::clone(&seen);
    a.add_collision_handler(2, 1).pre_solve = Some(Box::new(move |ctx| {
        let (s1, s2) = ctx.shapes();
        let (b1, b2) = ctx.arbiter.bodies();
        // A lookup of a context handle in the context's arenas works.
        assert!(ctx.shapes.get(s1).is_some() && ctx.bodies.get(b1).is_some());
        log.borrow_mut().push((s1, s2, b1, b2));
        true
    }));
    a.step(Real::ratio(1, 60)).unwrap();
    let got = seen.borrow().clone();
    assert!(!got.is_empty(), "pre_solve ran");
    for (s1, s2, b1, b2) in got {
        shape_belongs(&a, &mut b, s1, "ctx.shapes().0");
        shape_belongs(&a, &mut b, s2, "ctx.shapes().1");
        body_belongs(&a, &mut b, b1, "ctx.arbiter.bodies().0");
        body_belongs(&a, &mut b, b2, "ctx.arbiter.bodies().1");
    }
}

#[test]
fn a_loaded_world_hands_out_handles_valid_for_itself() {
    let mut a = world();
    let mut loaded = snapshot::load(&snapshot::save(&a)).unwrap();
    // Every source of handles in the loaded world: valid there, foreign in `a`.
    let (sa, sb) = loaded.arbiters()[0].shapes();
    let (ba, _) = loaded.arbiters()[0].bodies();
    shape_belongs(&loaded, &mut a, sa, "loaded Arbiter::shapes");
    shape_belongs(&loaded, &mut a, sb, "loaded Arbiter::shapes");
    body_belongs(&loaded, &mut a, ba, "loaded Arbiter::bodies");
    let (sh, shape) = loaded.shapes().nth(1).unwrap();
    body_belongs(&loaded, &mut a, shape.body(), "loaded Shape::body");
    let h = loaded.point_query(
        Vect::new(Real::ZERO, Real::HALF),
        Real::ONE,
        ShapeFilter::ALL,
    )[0]
    .0;
    shape_belongs(&loaded, &mut a, h, "loaded point_query");
    // And they work for edits in the loaded world.
    let body = loaded.shape(sh).unwrap().body();
    loaded
        .body_mut(body)
        .unwrap()
        .set_velocity(Vect::from_ints(1, 0));
    loaded.remove_shape(sh).unwrap();
    loaded.validate().unwrap();
}

#[test]
fn restore_state_from_another_space_adopts_its_handles() {
    let a = world();
    let mut b = world();
    let mut c = Space::new();
    c.restore_state(a.state());
    assert_eq!(c.checksum(), a.checksum());
    let (sa, _) = c.arbiters()[0].shapes();
    shape_belongs(&c, &mut b, sa, "restored Arbiter::shapes");
    let body = c.shapes().nth(1).unwrap().1.body();
    body_belongs(&c, &mut b, body, "restored Shape::body");
    // Stepping the restored world gives the same bits as the original.
    let mut a2 = a.clone();
    for _ in 0..30 {
        a2.step(Real::ratio(1, 60)).unwrap();
        c.step(Real::ratio(1, 60)).unwrap();
    }
    assert_eq!(a2.checksum(), c.checksum());
    // A clone shares its original's origin: handles work on both.
    let h = a.arbiters()[0].shapes().0;
    assert!(a2.shape(h).is_some());
}
