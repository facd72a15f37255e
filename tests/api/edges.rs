//! API edges of the Space: bad input is a clear error that leaves the world
//! unchanged; custom integration replaces the default one.
use tamias2d::body::{Body, BodyError};
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::{Shape, ShapeError};
use tamias2d::space::{Settings, Space, SpaceError};

fn ball_world() -> (Space, tamias2d::body::BodyHandle) {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let mut b = Body::new(Real::ONE, real!(0.125)).unwrap();
    b.set_position(Vect::from_ints(0, 10));
    let h = space.add_body(b).unwrap();
    space
        .add_shape(Shape::circle_shape_new(h, Real::HALF, Vect::ZERO).unwrap())
        .unwrap();
    (space, h)
}

#[test]
fn zero_dt_is_a_no_op_and_negative_dt_is_an_error() {
    let (mut space, _) = ball_world();
    let before = space.state().clone();
    space.step(Real::ZERO).unwrap();
    assert_eq!(space.state(), &before);
    assert_eq!(space.step(-Real::ONE), Err(SpaceError::NegativeTimeStep));
    assert_eq!(space.state(), &before);
}

#[test]
fn stale_handles_and_double_removal_are_errors() {
    let (mut space, h) = ball_world();
    space.remove_body(h).unwrap();
    assert!(space.body(h).is_none());
    assert_eq!(space.remove_body(h).unwrap_err(), SpaceError::StaleBody(h));
    let shape = Shape::circle_shape_new(h, Real::ONE, Vect::ZERO).unwrap();
    assert_eq!(
        space.add_shape(shape).unwrap_err(),
        SpaceError::StaleBody(h)
    );
    // A new body reuses the slot with a new generation: the old handle stays dead.
    let h2 = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    assert_eq!(h2.index(), h.index());
    assert!(space.body(h).is_none());
    assert!(space.body(h2).is_some());
    space.validate().unwrap();
}

#[test]
fn a_handle_from_another_space_is_rejected() {
    let (mut a, ha) = ball_world();
    let (mut b, _) = ball_world();
    // Same slot and generation in both spaces, but the handle is a's.
    let before = b.state().clone();
    let shape = Shape::circle_shape_new(ha, Real::ONE, Vect::ZERO).unwrap();
    assert_eq!(b.add_shape(shape).unwrap_err(), SpaceError::ForeignHandle);
    assert_eq!(b.remove_body(ha).unwrap_err(), SpaceError::ForeignHandle);
    assert!(b.body(ha).is_none());
    assert_eq!(b.state(), &before);
    // A clone is the same world: its owner's handles keep working on it.
    let mut copy = a.clone();
    assert!(copy.body(ha).is_some());
    assert!(copy.remove_body(ha).is_ok());
    assert!(a.remove_body(ha).is_ok());
}

#[test]
fn invalid_bodies_shapes_and_settings_are_errors() {
    assert_eq!(
        Body::new(-Real::ONE, Real::ONE).unwrap_err(),
        BodyError::IllegalBody("mass must be ≥ 0")
    );
    let (mut space, h) = ball_world();
    assert_eq!(
        Shape::circle_shape_new(h, -Real::ONE, Vect::ZERO).unwrap_err(),
        ShapeError::Negative("radius")
    );
    let bad = Settings {
        collision_bias: Real::TWO,
        ..Settings::default()
    };
    assert!(matches!(
        space.set_settings(bad),
        Err(SpaceError::InvalidSetting(_))
    ));
    let bad = Settings {
        damping: -Real::ONE,
        ..Settings::default()
    };
    assert!(matches!(
        space.set_settings(bad),
        Err(SpaceError::InvalidSetting(_))
    ));
    assert_eq!(
        space.settings(),
        &Settings {
            gravity: Vect::from_ints(0, -10),
            ..Settings::default()
        }
    );
    // A failing shape edit leaves the shape as it was.
    let (sh, before) = space
        .shapes()
        .map(|(sh, s)| (sh, s.clone()))
        .next()
        .unwrap();
    let err = space
        .modify_shape(sh, |s| s.set_circle_radius(-Real::ONE))
        .unwrap_err();
    assert_eq!(err, SpaceError::Shape(ShapeError::Negative("radius")));
    assert_eq!(space.shape(sh), Some(&before));
    let err = space.modify_shape(sh, |s| s.poly_count()).unwrap_err();
    assert_eq!(err, SpaceError::Shape(ShapeError::NotPolyShape));
}

#[test]
fn mass_is_summed_from_shape_densities() {
    let mut space = Space::new();
    let h = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap())
        .unwrap();
    let mut s = Shape::box_shape_new(h, Real::TWO, Real::ONE, Real::ZERO).unwrap();
    s.set_density(Real::from_int(3)).unwrap();
    space.add_shape(s).unwrap();
    let b = space.body(h).unwrap();
    // Area 2 at density 3: mass 6; moment m(w² + h²)/12 = 6·5/12 = 2.5.
    assert_eq!(b.mass(), Real::from_int(6));
    // The moment per unit mass, 5/12, is not representable (½ ulp), and the
    // mass multiplies that error by 6: allow 4 ulp.
    let ulp4 = Real::from_bits(4);
    assert!((b.moment() - real!(2.5)).abs() <= ulp4, "{}", b.moment());
    // A second, offset box moves the centre of gravity between the two.
    let mut s2 = Shape::box_shape_new2(
        h,
        tamias2d::BB::new(
            Real::from_int(3),
            -Real::HALF,
            Real::from_int(5),
            Real::HALF,
        ),
        Real::ZERO,
    )
    .unwrap();
    s2.set_density(Real::from_int(3)).unwrap();
    space.add_shape(s2).unwrap();
    let b = space.body(h).unwrap();
    assert_eq!(b.mass(), Real::from_int(12));
    assert_eq!(b.center_of_gravity(), Vect::from_ints(2, 0));
    // Parallel axis: 2 · (2.5 + 6·2²) = 53.
    assert!(
        (b.moment() - Real::from_int(53)).abs() <= ulp4 + ulp4,
        "{}",
        b.moment()
    );
}

#[test]
fn custom_velocity_integration_replaces_the_default() {
    let (mut space, h) = ball_world();
    // A body that ignores gravity and drifts right at 1 m/s.
    space
        .set_velocity_update_func(
            h,
            Some(Box::new(
                |body: &mut Body, _g: Vect, _damping: Real, _dt: Real| {
                    body.set_velocity(Vect::from_ints(1, 0));
                },
            )),
        )
        .unwrap();
    for _ in 0..60 {
        space.step(Real::ratio(1, 60)).unwrap();
    }
    let p = space.body(h).unwrap().position();
    assert_eq!(p.y, Real::from_int(10), "gravity was not applied");
    // 59 position updates at 1 m/s (the first step moved with v = 0).
    let expected = Real::ratio(1, 60) * Real::from_int(59);
    assert!((p.x - expected).abs() <= Real::from_bits(64), "x = {}", p.x);
    // Restoring the default brings gravity back.
    space.set_velocity_update_func(h, None).unwrap();
    space.step(Real::ratio(1, 60)).unwrap();
    assert!(space.body(h).unwrap().velocity().y < Real::ZERO);
}

#[test]
fn update_shape_takes_an_infallible_closure_and_still_refuses_bad_materials() {
    let (mut space, ball) = ball_world();
    let (sh, _) = space.shapes().next().unwrap();
    // No `Ok(())` for a change that cannot fail; the closure's value comes back.
    let old = space
        .update_shape(sh, |s| {
            let old = s.material.friction;
            s.material.friction = real!(0.25);
            s.sensor = true;
            old
        })
        .unwrap();
    assert_ne!(old, real!(0.25));
    let shape = space.shape(sh).unwrap();
    assert_eq!((shape.material.friction, shape.sensor), (real!(0.25), true));
    // A material left invalid is refused as by `modify_shape`, the shape unchanged.
    let before = space.shape(sh).cloned();
    assert!(matches!(
        space.update_shape(sh, |s| s.material.friction = -Real::ONE),
        Err(SpaceError::Shape(_))
    ));
    assert_eq!(space.shape(sh).cloned(), before);
    // A stale handle is an error, not a panic.
    space.remove_shape(sh).unwrap();
    assert_eq!(
        space.update_shape(sh, |s| s.sensor = false),
        Err(SpaceError::StaleShape(sh))
    );
    assert!(space.body(ball).is_some());
}

#[test]
fn settings_are_copy() {
    fn copy<T: Copy>(t: &T) -> T {
        *t
    }
    let (mut space, _) = ball_world();
    let checksum = space.checksum();
    let mut settings = copy(space.settings());
    settings.iterations = 12;
    // A copy, not a view: the space is unchanged until it is set.
    assert_eq!(space.settings().iterations, Settings::default().iterations);
    assert_eq!(space.checksum(), checksum);
    space.set_settings(settings).unwrap();
    // `settings` is still usable after being set (copied in).
    assert_eq!(space.settings(), &settings);
}
