//! Regression: a rollback lost custom integrators. A body with a custom
//! velocity integrator (floating: gravity cancelled), removed after a save,
//! came back from `restore_state` without it and fell (y 10 → 9.99), so
//! the peer that rolled back desynced. Cause: `remove_body` dropped the
//! body's integrators, and closures are not in the saved state. Fix, for
//! each kind of callback:
//! * integrators are keyed by body handle and survive `remove_body`, so a
//!   rollback that brings the body back brings them back; `add_body` clears
//!   any left under the handle it returns (a new body starts with the
//!   default integration, even when a rollback re-issues a handle), and
//!   `prune_integrators` drops those of bodies no longer present (for when
//!   the removal is older than the game's rollback window);
//! * collision handlers are keyed by collision type: nothing to restore;
//! * post-step callbacks still pending when a state is restored belong to
//!   the abandoned frames: `restore_state` discards them.
use tamias2d_scenes::shared::Shared;

use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::space::Space;

fn dt() -> Real {
    Real::ratio(1, 60)
}

fn ball(w: &mut Space, y: i32) -> BodyHandle {
    let b = w
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    w.body_mut(b).unwrap().set_position(Vect::from_ints(0, y));
    w.add_shape(Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).unwrap())
        .unwrap();
    b
}

/// A velocity integrator without gravity: the body floats.
fn float(w: &mut Space, h: BodyHandle) {
    w.set_velocity_update_func(
        h,
        Some(Box::new(|body, _gravity, damping, dt| {
            body.update_velocity(Vect::ZERO, damping, dt)
        })),
    )
    .unwrap();
}

fn world() -> Space {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    w
}

#[test]
fn a_removed_body_comes_back_with_its_integrator() {
    let mut w = world();
    let h = ball(&mut w, 10);
    float(&mut w, h);
    let saved = w.state().clone();
    w.remove_body(h).unwrap();
    w.step(dt()).unwrap();
    w.restore_state(&saved);
    for _ in 0..60 {
        w.step(dt()).unwrap();
    }
    assert_eq!(
        w.body(h).unwrap().position(),
        Vect::from_ints(0, 10),
        "it fell"
    );

    // The same through bytes.
    let mut w = world();
    let h = ball(&mut w, 10);
    float(&mut w, h);
    let bytes = tamias2d::snapshot::save(&w);
    w.remove_body(h).unwrap();
    w.load_snapshot(&bytes).unwrap();
    w.step(dt()).unwrap();
    w.step(dt()).unwrap();
    assert_eq!(w.body(h).unwrap().position(), Vect::from_ints(0, 10));
}

#[test]
fn a_body_added_under_a_reissued_handle_starts_with_the_default_integration() {
    let mut w = world();
    let saved = w.state().clone();
    let x = ball(&mut w, 10);
    float(&mut w, x);
    w.restore_state(&saved);
    // Deterministic handles: the next body gets x's handle again.
    let y = ball(&mut w, 10);
    assert_eq!(x, y);
    // Positions move with the previous step's velocity: two steps to fall.
    w.step(dt()).unwrap();
    w.step(dt()).unwrap();
    assert!(
        w.body(y).unwrap().position().y < Real::from_int(10),
        "y inherited x's integrator"
    );
}

#[test]
fn prune_integrators_drops_those_of_absent_bodies() {
    let mut w = world();
    let h = ball(&mut w, 10);
    float(&mut w, h);
    let keep = ball(&mut w, 20);
    float(&mut w, keep);
    let saved = w.state().clone();
    w.remove_body(h).unwrap();
    w.prune_integrators();
    w.restore_state(&saved);
    w.step(dt()).unwrap();
    w.step(dt()).unwrap();
    assert!(
        w.body(h).unwrap().position().y < Real::from_int(10),
        "pruned: default integration"
    );
    assert_eq!(
        w.body(keep).unwrap().position(),
        Vect::from_ints(0, 20),
        "present: kept"
    );
}

#[test]
fn handlers_survive_a_rollback_of_a_removed_body() {
    let mut w = world();
    let g = w.add_body(Body::new_static()).unwrap();
    let mut seg =
        Shape::segment_shape_new(g, Vect::from_ints(-5, 0), Vect::from_ints(5, 0), Real::ZERO)
            .unwrap();
    seg.collision_type = 1;
    w.add_shape(seg).unwrap();
    let b = w
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    w.body_mut(b).unwrap().set_position(Vect::from_ints(0, 1));
    let mut c = Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).unwrap();
    c.collision_type = 2;
    w.add_shape(c).unwrap();
    let begins = Shared::new(0);
    let n = Shared::clone(&begins);
    w.add_collision_handler(2, 1).begin = Some(Box::new(move |_| {
        n.set(n.get() + 1);
        true
    }));
    let saved = w.state().clone();
    w.remove_body(b).unwrap();
    w.restore_state(&saved);
    for _ in 0..60 {
        w.step(dt()).unwrap();
    }
    assert_eq!(begins.get(), 1);
}

#[test]
fn pending_post_step_callbacks_are_discarded_by_a_rollback() {
    let mut w = world();
    ball(&mut w, 10);
    let saved = w.state().clone();
    let ran = Shared::new(0);
    let r = Shared::clone(&ran);
    assert!(w.add_post_step_callback(7, Box::new(move |_| r.set(r.get() + 1))));
    w.restore_state(&saved);
    w.step(dt()).unwrap();
    assert_eq!(ran.get(), 0, "a callback of the abandoned frames ran");
    // Without a rollback it runs after the next step.
    let r = Shared::clone(&ran);
    assert!(w.add_post_step_callback(7, Box::new(move |_| r.set(r.get() + 1))));
    w.step(dt()).unwrap();
    assert_eq!(ran.get(), 1);
}
