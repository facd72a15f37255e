//! Regression: states that pass validation but can never step.
//!
//! Symptom: a full snapshot or a frame holding a dynamic body with zero
//! mass loaded without error and passed `Space::validate`, and then every
//! `step` returned `SpaceError::MasslessDynamicBody`. Cause: the step's
//! precondition (a dynamic body has an inverse mass above zero) was its
//! own check, not one of the state's invariants. Now one rule,
//! `Body::can_step`, is both the step's precondition and an invariant of
//! `validate_state`, which every loading path runs: full snapshots
//! (`snapshot::load`, `Space::load_snapshot`, `decode_state`), frames
//! (`Space::load_frame_snapshot`), and the checked state paths
//! (`Space::try_from_state`, `Space::try_restore_state`). A refused load
//! leaves the live world as it was.
use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::snapshot;
use tamias2d::space::{Space, SpaceError};

/// A falling box with mass (the world every load below targets).
fn healthy() -> Space {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let b = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    space
        .add_shape(Shape::box_shape_new(b, Real::ONE, Real::ONE, Real::ZERO).unwrap())
        .unwrap();
    space
}

/// The same world plus a dynamic body without mass: with no shape, and
/// with a shape of no density (the two ways the API makes one).
fn with_massless(shape: bool) -> Space {
    let mut space = healthy();
    let ghost = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap())
        .unwrap();
    if shape {
        space
            .add_shape(Shape::circle_shape_new(ghost, Real::HALF, Vect::ZERO).unwrap())
            .unwrap();
    }
    space
}

fn assert_names_the_rule(why: &str) {
    assert!(why.contains("without mass"), "unclear error: {why}");
}

#[test]
fn validation_refuses_every_state_the_step_refuses() {
    for shape in [false, true] {
        let bad = with_massless(shape);
        assert!(bad.clone().step(Real::ratio(1, 60)).is_err());
        assert_names_the_rule(&bad.validate().unwrap_err());
        assert_names_the_rule(&tamias2d::space::validate_state(bad.state()).unwrap_err());
    }
}

#[test]
fn full_snapshots_with_a_massless_body_are_refused_and_change_nothing() {
    for shape in [false, true] {
        let bytes = snapshot::save(&with_massless(shape));
        assert_names_the_rule(&snapshot::load(&bytes).unwrap_err().to_string());
        assert_names_the_rule(&snapshot::decode_state(&bytes).unwrap_err().to_string());
        let mut live = healthy();
        live.step(Real::ratio(1, 60)).unwrap();
        let before = live.checksum();
        assert!(live.load_snapshot(&bytes).is_err());
        assert_eq!(live.checksum(), before);
        live.step(Real::ratio(1, 60)).unwrap();
    }
}

#[test]
fn frames_with_a_massless_body_are_refused_and_change_nothing() {
    for shape in [false, true] {
        let bytes = snapshot::save_frame(&with_massless(shape));
        let mut live = healthy();
        live.step(Real::ratio(1, 60)).unwrap();
        let before = live.checksum();
        let err = live.load_frame_snapshot(&bytes).unwrap_err();
        assert_names_the_rule(&err.to_string());
        assert_eq!(live.checksum(), before);
        live.step(Real::ratio(1, 60)).unwrap();
    }
}

#[test]
fn checked_state_paths_refuse_a_massless_body() {
    let bad = with_massless(true);
    let Err(SpaceError::RejectedState(why)) = Space::try_from_state(bad.state().clone()) else {
        panic!("try_from_state accepted a state that cannot step");
    };
    assert_names_the_rule(&why);
    let mut live = healthy();
    let before = live.checksum();
    let Err(SpaceError::RejectedState(why)) = live.try_restore_state(bad.state()) else {
        panic!("try_restore_state accepted a state that cannot step");
    };
    assert_names_the_rule(&why);
    assert_eq!(live.checksum(), before);
    // A good state passes both and steps.
    let good = healthy();
    Space::try_from_state(good.state().clone())
        .unwrap()
        .step(Real::ratio(1, 60))
        .unwrap();
    live.try_restore_state(good.state()).unwrap();
    live.step(Real::ratio(1, 60)).unwrap();
}
