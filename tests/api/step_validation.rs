//! Validation builds: the test suite steps every world with the `validate`
//! feature (the crate's self dev-dependency), so every step of every test
//! ends with `validate_state`, the checks snapshot loading makes.
use tamias2d::body::Body;
use tamias2d::shape::Shape;
use tamias2d::space::{Space, SpaceError, VALIDATES_STEPS};
use tamias2d::{Real, Vect};

#[test]
fn the_unoptimised_test_suite_validates_every_step() {
    // Optimised builds ignore the feature (timing runs measure the engine
    // alone); `cargo test` builds unoptimised.
    assert_eq!(VALIDATES_STEPS, cfg!(debug_assertions));
}

/// A world whose state breaks an invariant the step does not repair (a
/// setting out of range, put in past `set_settings` through `from_state`):
/// the step after it fails in a validation build, and the error names the
/// invariant.
#[test]
fn a_step_that_leaves_a_broken_invariant_fails_in_validation_builds() {
    let mut w = Space::new();
    let h = w
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let ball = Shape::circle_shape_new(h, Real::ONE, Vect::ZERO).unwrap_or_else(|e| panic!("{e}"));
    w.add_shape(ball).unwrap_or_else(|e| panic!("{e}"));
    let mut state = w.state().clone();
    state.settings.collision_slop = -Real::ONE;
    let mut broken = Space::from_state(state);
    let result = broken.step(Real::ONE / Real::from_int(60));
    if VALIDATES_STEPS {
        let Err(SpaceError::InvalidState(why)) = result else {
            panic!("not reported: {result:?}");
        };
        assert!(why.contains("collision slop"), "{why}");
    } else {
        assert_eq!(result, Ok(()));
    }
    // The intact world steps without complaint either way.
    assert_eq!(w.step(Real::ONE / Real::from_int(60)), Ok(()));
}
