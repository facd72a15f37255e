//! The step keeps static shapes' world-space cache entries (and the static
//! tree) from earlier steps and rewrites them only when statics changed. A
//! change a stale entry would miss gives different bits, so each case
//! changes a static shape or body through the API between two steps and
//! then checks that the world steps exactly like its clone (`Space::clone`
//! starts with empty caches, rebuilt from the state on its first step).
use tamias2d::body::{Body, BodyHandle};
use tamias2d::shape::{Shape, ShapeHandle};
use tamias2d::space::Space;
use tamias2d::{Real, Vect};

fn dt() -> Real {
    Real::ONE / Real::from_int(60)
}

struct World {
    space: Space,
    ground: BodyHandle,
    floor: ShapeHandle,
    resting: BodyHandle,
    falling: BodyHandle,
}

fn ball(space: &mut Space, x: i32, y: i32) -> BodyHandle {
    let b = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    if let Some(body) = space.body_mut(b) {
        body.set_position(Vect::from_ints(x, y));
    }
    let mut c =
        Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).unwrap_or_else(|e| panic!("{e}"));
    c.set_density(Real::ONE).unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(c).unwrap_or_else(|e| panic!("{e}"));
    b
}

/// A static floor with a wall, three balls resting on the floor and one
/// falling from high up, stepped until the balls rest.
fn world() -> World {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space
        .add_body(Body::new_static())
        .unwrap_or_else(|e| panic!("{e}"));
    let floor = space
        .add_shape(
            Shape::segment_shape_new(
                ground,
                Vect::from_ints(-20, 0),
                Vect::from_ints(20, 0),
                Real::ZERO,
            )
            .unwrap_or_else(|e| panic!("{e}")),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    space
        .add_shape(
            Shape::segment_shape_new(
                ground,
                Vect::from_ints(-20, 0),
                Vect::from_ints(-20, 10),
                Real::ZERO,
            )
            .unwrap_or_else(|e| panic!("{e}")),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let resting = ball(&mut space, 0, 1);
    ball(&mut space, 2, 1);
    ball(&mut space, -2, 1);
    let falling = ball(&mut space, 10, 1000);
    for _ in 0..60 {
        space.step(dt()).unwrap_or_else(|e| panic!("{e}"));
    }
    World {
        space,
        ground,
        floor,
        resting,
        falling,
    }
}

/// Steps the changed world and its clone (fresh caches) side by side.
fn steps_like_its_clone(space: &mut Space, what: &str) {
    let mut fresh = space.clone();
    for i in 0..60 {
        space.step(dt()).unwrap_or_else(|e| panic!("{e}"));
        fresh.step(dt()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            space.state() == fresh.state(),
            "{what}: step {i} differs from a world with fresh caches"
        );
    }
}

fn height(space: &Space, b: BodyHandle) -> Real {
    space
        .body(b)
        .unwrap_or_else(|| panic!("body exists"))
        .position()
        .y
}

#[test]
fn static_body_moved_by_body_mut_then_step() {
    let mut w = world();
    let before = height(&w.space, w.resting);
    if let Some(g) = w.space.body_mut(w.ground) {
        g.set_position(Vect::from_ints(0, -5));
    }
    steps_like_its_clone(&mut w.space, "static body moved");
    // The floor went away from under the ball: it fell.
    assert!(height(&w.space, w.resting) < before - Real::ONE);
}

#[test]
fn static_shape_modified_then_step() {
    let mut w = world();
    let before = height(&w.space, w.resting);
    w.space
        .modify_shape(w.floor, |s| {
            let y = Real::ONE / Real::from_int(4);
            s.set_segment_endpoints(
                Vect::new(Real::from_int(-20), y),
                Vect::new(Real::from_int(20), y),
            )
        })
        .unwrap_or_else(|e| panic!("{e}"));
    steps_like_its_clone(&mut w.space, "static shape modified");
    // The floor rose a quarter of the ball's size: the ball was pushed up.
    assert!(height(&w.space, w.resting) > before);
}

#[test]
fn static_shape_removed_and_slot_reused_then_step() {
    let mut w = world();
    w.space
        .remove_shape(w.floor)
        .unwrap_or_else(|e| panic!("{e}"));
    let raised = Shape::segment_shape_new(
        w.ground,
        Vect::from_ints(-20, 1),
        Vect::from_ints(20, 1),
        Real::ZERO,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    w.space.add_shape(raised).unwrap_or_else(|e| panic!("{e}"));
    steps_like_its_clone(&mut w.space, "static shape replaced");
}

#[test]
fn dynamic_body_replaced_by_a_static_one_in_place_then_step() {
    let mut w = world();
    if let Some(b) = w.space.body_mut(w.falling) {
        let mut s = Body::new_static();
        s.set_position(Vect::from_ints(0, 3));
        *b = s;
    }
    steps_like_its_clone(&mut w.space, "body made static in place");
}

#[test]
fn static_body_moved_by_a_custom_position_integrator() {
    // A custom integrator on a static body moves it during the step; the
    // same motion applied through `body_mut` before each step must give the
    // same bits (the second world is checked against fresh caches above).
    let mut a = world();
    let mut b = world();
    let lift = Vect::new(Real::ZERO, Real::ONE / Real::from_int(50));
    a.space
        .set_position_update_func(
            a.ground,
            Some(Box::new(move |body: &mut Body, _dt: Real| {
                body.set_position(body.position() + lift);
            })),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    for i in 0..60 {
        if let Some(g) = b.space.body_mut(b.ground) {
            g.set_position(g.position() + lift);
        }
        a.space.step(dt()).unwrap_or_else(|e| panic!("{e}"));
        b.space.step(dt()).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            a.space.state() == b.space.state(),
            "step {i}: integrator and body_mut differ: {:?}",
            tamias2d::snapshot::first_difference(&a.space, &b.space)
        );
    }
    assert!(height(&a.space, a.resting) > Real::ONE);
}

#[test]
fn restore_state_after_moving_a_static_body() {
    let mut w = world();
    let saved = w.space.state().clone();
    if let Some(g) = w.space.body_mut(w.ground) {
        g.set_position(Vect::from_ints(3, -2));
    }
    for _ in 0..10 {
        w.space.step(dt()).unwrap_or_else(|e| panic!("{e}"));
    }
    w.space.restore_state(&saved);
    steps_like_its_clone(&mut w.space, "restored");
}
