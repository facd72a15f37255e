//! Extreme scenes, part 0: diagnostics and degenerate input.
//!
//! * **Diagnostics.** `StepStats::saturated_bodies` counts the bodies whose
//!   position, velocity or angular velocity sits at `Real::MIN`/`MAX` after
//!   a step: a scene that leaves the representable range is visible to the
//!   game the step it happens, and coordinates saturate, never wrap.
//! * **Degenerate input** (zero mass, zero area, points, needles, NaN,
//!   out-of-range numbers) is an error or a defined behaviour, never a panic.
//!
//! The other parts: `translation.rs` (far from the origin),
//! `scale.rs` (sizes and masses), `motion.rs` (speed,
//! overlap, time steps), and `report.rs`, the envelope report behind
//! `docs/numerics.md`. Shared helpers: `common.rs`.
#![allow(clippy::float_arithmetic)]

use super::common::{build, int, lone_ball, trace_x, Watch, FRICTION};
use tamias2d::body::Body;
use tamias2d::math::{RealError, Transform};
use tamias2d::real;
use tamias2d::shape::{Shape, ShapeError};
use tamias2d::space::{Space, SpaceError};
use tamias2d::{Real, Vect};
use tamias2d_scenes::{
    self as scenes, BodyDesc, BodyKind, BodyPath, SceneDesc, SceneError, SettingsDesc, ShapeDesc,
};

// ---------------------------------------------------------------------------
// Diagnostics: StepStats::saturated_bodies.
// ---------------------------------------------------------------------------

#[test]
fn saturation_counter_is_zero_inside_the_envelope() {
    for name in ["stack_10", "pyramid_20", "newtons_cradle", "projectile_45"] {
        let mut s = build(&scenes::builtin(name).unwrap_or_else(|| panic!("{name}")));
        let w = Watch::run(&mut s, 60);
        assert_eq!(w.saturated, 0, "{name}");
    }
}

#[test]
fn body_launched_out_of_range_saturates_is_counted_and_never_wraps() {
    // 10 m from the edge at 1000 m/s: the first step would carry it 6.7 m
    // past 2^31. It stops at Real::MAX (wrapping would put it at −2^31),
    // and keeps its velocity: the game sees where it is and how it moves.
    let start = int((1 << 31) - 10);
    let mut s = lone_ball(Vect::new(start, Real::ZERO), Vect::from_ints(1000, 0));
    for (i, (x, saturated)) in trace_x(&mut s, 10).into_iter().enumerate() {
        assert_eq!(x, Real::MAX, "step {}", i + 1);
        assert_eq!(saturated, 1, "step {}", i + 1);
    }
    let h = s.bodies()[0];
    let v = s.space.body(h).map(|b| b.velocity());
    assert_eq!(v, Some(Vect::from_ints(1000, 0)));
}

#[test]
fn body_at_the_speed_limit_is_counted_from_the_step_it_reaches_the_edge() {
    // v = 2^31 − 2 ulp m/s (not itself saturated) covers 35,791,394 m per
    // step: the centre reaches 2^31 at step 61. Before that the counter is
    // 0 and x grows every step; from then on x = MAX and the counter is 1.
    let v = Real::from_bits(i64::MAX - 1);
    let mut s = lone_ball(Vect::ZERO, Vect::new(v, Real::ZERO));
    let trace = trace_x(&mut s, 70);
    let first = trace
        .iter()
        .position(|&(_, n)| n > 0)
        .unwrap_or_else(|| panic!("never saturated"));
    assert_eq!(first + 1, 61, "saturated at step {}", first + 1);
    let mut prev = Real::ZERO;
    for (i, &(x, n)) in trace.iter().enumerate() {
        assert!(x > prev || x == Real::MAX, "x went back at step {}", i + 1);
        assert_eq!(n, u32::from(i >= first), "counter at step {}", i + 1);
        assert_eq!(x == Real::MAX, i >= first, "x at step {}", i + 1);
        prev = x;
    }
    // The position is MAX but the velocity is not: the counter names the
    // body, the game decides what to do (remove it, wrap its world, …).
    let h = s.bodies()[0];
    assert!(!s.space.body(h).is_some_and(|b| b.velocity().is_saturated()));
}

#[test]
fn velocity_and_spin_saturation_are_counted() {
    // A force of Real::MAX on a 1 kg ball adds (MAX·dt) m/s per step: the
    // velocity saturates at step 61 and stays there; it never flips sign.
    let mut s = lone_ball(Vect::ZERO, Vect::ZERO);
    let h = s.bodies()[0];
    let mut first = None;
    for i in 1..=70 {
        if let Some(b) = s.space.body_mut(h) {
            b.set_position(Vect::ZERO); // keep the position in range
            b.apply_force(Vect::new(Real::MAX, Real::ZERO));
        }
        s.step().unwrap_or_else(|e| panic!("step {i}: {e}"));
        let b = s.space.body(h).unwrap_or_else(|| panic!("ball is gone"));
        assert!(
            !b.velocity().x.is_negative(),
            "velocity wrapped at step {i}"
        );
        let n = s.space.last_step_stats().saturated_bodies;
        if n > 0 && first.is_none() {
            first = Some(i);
        }
        assert_eq!(n, u32::from(b.velocity().x == Real::MAX), "step {i}");
    }
    assert!(
        first.is_some_and(|i| i <= 62),
        "velocity saturated at {first:?}"
    );
    // Spin: angular velocity at Real::MAX is counted at once.
    let mut s = lone_ball(Vect::ZERO, Vect::ZERO);
    let h = s.bodies()[0];
    if let Some(b) = s.space.body_mut(h) {
        b.set_angular_velocity(Real::MAX);
    }
    s.step().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.space.last_step_stats().saturated_bodies, 1);
}

#[test]
fn continuous_angle_saturates_without_affecting_the_rotation() {
    // `Body::angle()` counts whole turns, so it is the one state value a
    // scene inside the envelope can saturate: 60 rad/s for 414 days. It
    // stops at Real::MAX while the rotation (a unit complex number, what
    // the simulation uses) keeps turning. Not counted by
    // `saturated_bodies`, which watches position and velocities.
    let mut s = lone_ball(Vect::ZERO, Vect::ZERO);
    let h = s.bodies()[0];
    if let Some(b) = s.space.body_mut(h) {
        b.set_angle(Real::MAX - Real::ONE);
        b.set_angular_velocity(Real::from_int(60));
    }
    let rot0 = s.space.body(h).map(|b| b.rotation());
    s.step_n(10).unwrap_or_else(|e| panic!("{e}"));
    let b = s.space.body(h).unwrap_or_else(|| panic!("ball is gone"));
    assert_eq!(b.angle(), Real::MAX);
    assert_ne!(Some(b.rotation()), rot0);
    // Ten steps of 60·dt ≈ 1 rad: the rotation turned by 10 rad (read in
    // (−π, π] as 10 − 2·2π), to within 2^-20 rad.
    let turned = rot0.map_or(Real::ZERO, |r0| r0.inv().compose(b.rotation()).angle());
    let want = Real::from_int(10) - Real::TWO * Real::TAU;
    assert!(
        (turned - want).abs() < Real::from_bits(1 << 12),
        "turned {turned}, want {want}"
    );
    assert_eq!(s.space.last_step_stats().saturated_bodies, 0);
}

// ---------------------------------------------------------------------------
// Degenerate input: errors, not panics.
// ---------------------------------------------------------------------------

#[test]
fn degenerate_shapes_and_numbers_are_errors_not_panics() {
    let mut space = Space::new();
    let body = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let p = Vect::from_ints;
    let id = Transform::IDENTITY;
    // Zero area.
    let collinear = [p(0, 0), p(1, 1), p(2, 2), p(3, 3)];
    assert_eq!(
        Shape::poly_shape_new(body, &collinear, &id, Real::ZERO).err(),
        Some(ShapeError::DegeneratePolygon)
    );
    assert_eq!(
        Shape::poly_shape_new(body, &[p(0, 0), p(1, 0)], &id, Real::ONE).err(),
        Some(ShapeError::DegeneratePolygon)
    );
    assert_eq!(
        Shape::poly_shape_new(body, &[p(2, 2); 5], &id, Real::ZERO).err(),
        Some(ShapeError::DegeneratePolygon)
    );
    assert_eq!(
        Shape::box_shape_new(body, Real::ZERO, Real::ONE, Real::ZERO).err(),
        Some(ShapeError::DegeneratePolygon)
    );
    // Negative sizes.
    assert_eq!(
        Shape::circle_shape_new(body, -Real::ONE, Vect::ZERO).err(),
        Some(ShapeError::Negative("radius"))
    );
    assert_eq!(
        Shape::box_shape_new(body, -Real::ONE, Real::ONE, Real::ZERO).err(),
        Some(ShapeError::Negative("box size"))
    );
    // Out of range: a polygon spanning 2^31 m, a transform that saturates.
    let wide = [
        Vect::new(Real::MIN, Real::ZERO),
        Vect::new(Real::MAX, Real::ZERO),
        Vect::new(Real::ZERO, Real::ONE),
    ];
    assert_eq!(
        Shape::poly_shape_new_raw(body, &wide, Real::ZERO).err(),
        Some(ShapeError::OutOfRange("polygon extent"))
    );
    let far = Transform::translate(Vect::new(Real::MAX, Real::ZERO));
    let tri = [p(0, 0), p(1, 0), p(0, 1)];
    assert_eq!(
        Shape::poly_shape_new(body, &tri, &far, Real::ZERO).err(),
        Some(ShapeError::OutOfRange("transformed vertex"))
    );
    // Numbers at the API edge.
    assert_eq!(Real::from_f64(f64::NAN), Err(RealError::NotFinite));
    assert_eq!(Real::from_f64(f64::NEG_INFINITY), Err(RealError::NotFinite));
    assert_eq!(Real::from_f64(3e9), Err(RealError::OutOfRange));
    assert_eq!(Real::from_f64(-2_147_483_648.5), Err(RealError::OutOfRange));
    // Masses and time steps.
    assert!(Body::new(-Real::ONE, Real::ONE).is_err());
    let mut b = Body::new(Real::ONE, Real::ONE).unwrap_or_else(|e| panic!("{e}"));
    assert!(b.set_mass(Real::ZERO).is_err());
    assert!(b.set_moment(-Real::DELTA).is_err());
    assert_eq!(space.step(-Real::DELTA), Err(SpaceError::NegativeTimeStep));
    let before = space.state().clone();
    space.step(Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(space.state(), &before, "dt = 0 is a no-op");
    space.validate().unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn zero_mass_and_zero_area_bodies_are_scene_errors() {
    let one = |shape: ShapeDesc| {
        let mut d = SceneDesc::new("one", Real::ratio(1, 60), 1);
        d.bodies
            .push(BodyDesc::new(BodyKind::Dynamic, Vect::ZERO).with_shape(shape));
        d.build().err()
    };
    let massless = Some(SceneError::Massless(BodyPath::Initial(0)));
    // A point and a line have zero area: density gives them no mass.
    assert_eq!(
        one(ShapeDesc::circle(Real::ZERO).density(Real::ONE)),
        massless
    );
    let line = ShapeDesc::segment(Vect::ZERO, Vect::from_ints(1, 0), Real::ZERO);
    assert_eq!(one(line.density(Real::ONE)), massless);
    // Zero density, no density.
    assert_eq!(
        one(ShapeDesc::circle(Real::ONE).density(Real::ZERO)),
        massless
    );
    assert_eq!(one(ShapeDesc::circle(Real::ONE)), massless);
    // A 1 mm box at density 1: mass 10^-6 kg, moment 1.7e-13 kg·m², below
    // half an ulp, so it rounds to zero.
    let tiny = ShapeDesc::box_shape(real!(0.001), real!(0.001), Real::ZERO).density(Real::ONE);
    assert_eq!(one(tiny), massless);
}

#[test]
fn point_and_needle_shapes_collide_without_panicking() {
    // Degenerate but valid shapes with an explicit mass: a circle of radius
    // 0 (a point), a zero-length segment of radius 0 (a point) and of radius
    // 0.1 (a small ball), and a needle (a triangle 1 m long and 2^-20 m
    // wide), dropped onto a 1 m thick static box and onto each other. They
    // land and stay above the ground's top face within the slop.
    let mut d = SceneDesc::new("points", Real::ratio(1, 60), 0);
    d.settings = SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10);
    let ground = ShapeDesc::box_at(
        int(20),
        Real::ONE,
        Real::ZERO,
        Vect::new(Real::ZERO, -Real::HALF),
    )
    .material(FRICTION, Real::ZERO);
    d.bodies.push(BodyDesc::static_body().with_shape(ground));
    let needle = vec![
        Vect::ZERO,
        Vect::new(Real::ONE, Real::ZERO),
        Vect::new(Real::ZERO, Real::from_bits(1 << 12)),
    ];
    let shapes = [
        ShapeDesc::circle(Real::ZERO),
        ShapeDesc::segment(Vect::ZERO, Vect::ZERO, Real::ZERO),
        ShapeDesc::segment(Vect::ZERO, Vect::ZERO, real!(0.1)),
        ShapeDesc::poly(needle, Real::ZERO),
    ];
    for (i, shape) in shapes.into_iter().enumerate() {
        for layer in 0..2 {
            let x = int(3 * i as i64 - 4);
            let y = int(1 + 2 * layer);
            let body = BodyDesc::dynamic(Vect::new(x, y), Real::ONE, real!(0.1))
                .with_shape(shape.clone().material(FRICTION, Real::ZERO));
            d.bodies.push(body);
        }
    }
    let mut s = build(&d);
    let w = Watch::run(&mut s, 300);
    assert_eq!(w.saturated, 0);
    assert!(w.max_speed < 10.0, "speed {}", w.max_speed);
    for (h, b) in s.space.bodies().skip(1) {
        let y = b.position().y.to_f64();
        assert!(y > -0.11 && y < 3.0, "body {h:?} at y = {y}");
    }
    s.space.validate().unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn raw_space_dynamic_body_without_mass_is_refused_by_step() {
    // Scenes reject a dynamic body without mass (`SceneError::Massless`),
    // and the raw `Space` API accepts `Body::new(0, 0)` with only massless
    // shapes (a body may get its shapes later), but `step` refuses to run
    // it: with infinite mass it would fall through the ground (see
    // `tests/regressions/massless_dynamic_body.rs`).
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ghost = space
        .add_body(Body::new(Real::ZERO, Real::ZERO).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let ball =
        Shape::circle_shape_new(ghost, Real::HALF, Vect::ZERO).unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(ball).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        space.step(Real::ratio(1, 60)),
        Err(SpaceError::MasslessDynamicBody(ghost))
    );
    assert_eq!(space.stamp(), 0);
    // The same rule is a state invariant: validation refuses what the step
    // refuses, so no loaded state can be one that never steps.
    let why = space.validate().unwrap_err();
    assert!(why.contains("without mass"), "{why}");
}
