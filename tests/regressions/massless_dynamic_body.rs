//! Regression: a dynamic body with no explicit mass whose shapes have no
//! mass or density got infinite mass (inverse mass 0); gravity still moved
//! it, no contact could stop it, and it fell through the floor silently
//! (only `StepStats::massless_dynamic_bodies` counted it). Cause: the mass
//! is summed from the shapes, which are added after the body, and nothing
//! checked the sum before simulating. Fix: `Space::step` refuses, before
//! changing anything, with `SpaceError::MasslessDynamicBody(handle)` naming
//! the first such body in slot order (as Chipmunk's `cpBodyUpdateVelocity`
//! asserts a positive mass). Adding the body and its massless shapes stays
//! allowed: a body may get its mass from shapes added later.
use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::space::{Space, SpaceError};

fn ground(space: &mut Space) {
    let g = space.add_body(Body::new_static()).unwrap();
    let seg =
        Shape::segment_shape_new(g, Vect::from_ints(-5, 0), Vect::from_ints(5, 0), Real::ZERO)
            .unwrap();
    space.add_shape(seg).unwrap();
}

#[test]
fn step_refuses_a_dynamic_body_without_mass_and_changes_nothing() {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    ground(&mut space);
    let massive = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    space
        .add_shape(Shape::circle_shape_new(massive, Real::HALF, Vect::ZERO).unwrap())
        .unwrap();
    let ghost = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap())
        .unwrap();
    space
        .add_shape(Shape::circle_shape_new(ghost, Real::HALF, Vect::ZERO).unwrap())
        .unwrap();
    space
        .body_mut(ghost)
        .unwrap()
        .set_position(Vect::from_ints(0, 2));
    let before = space.checksum();
    let err = space.step(Real::ratio(1, 60)).unwrap_err();
    assert_eq!(err, SpaceError::MasslessDynamicBody(ghost));
    assert!(err.to_string().contains("no mass"), "{err}");
    assert_eq!(space.checksum(), before, "a refused step changed the world");
    assert_eq!(space.stamp(), 0);
    assert_eq!(space.steps(), 0);
    // The handle in the error is valid for this space.
    let SpaceError::MasslessDynamicBody(h) = err else {
        unreachable!()
    };
    assert!(space.body(h).is_some());

    // Giving the shape a density fixes it: the body now rests on the ground.
    let sh = space.body_shapes(ghost).next().unwrap().0;
    space
        .modify_shape(sh, |s| s.set_density(Real::ONE))
        .unwrap();
    for _ in 0..120 {
        space.step(Real::ratio(1, 60)).unwrap();
        assert_eq!(space.last_step_stats().massless_dynamic_bodies, 0);
    }
    assert!(space.body(ghost).unwrap().position().y > Real::ZERO);
}

#[test]
fn a_dynamic_body_without_shapes_or_mass_is_refused_too() {
    let mut space = Space::new();
    let h = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap())
        .unwrap();
    assert_eq!(
        space.step(Real::ratio(1, 60)),
        Err(SpaceError::MasslessDynamicBody(h))
    );
    // A zero step does nothing and so checks nothing (as before).
    assert_eq!(space.step(Real::ZERO), Ok(()));
    // Static and kinematic bodies never have mass: fine.
    space.remove_body(h).unwrap();
    space.add_body(Body::new_static()).unwrap();
    space.add_body(Body::new_kinematic()).unwrap();
    assert_eq!(space.step(Real::ratio(1, 60)), Ok(()));
}
