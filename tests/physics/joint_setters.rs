//! Joints driven in place (Chipmunk's `cp…Set…` routines): every setter
//! keeps the accumulated impulse (the warm start), refuses what the
//! constructor refuses and then leaves the joint unchanged, wakes the
//! joint's island through `Space::modify_constraint`, and a world whose
//! joints were changed snapshots and steps like any other.
use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{
    Constraint, ConstraintError, ConstraintHandle, DampedRotarySpring, DampedSpring, GearJoint,
    GrooveJoint, Joint, JointKind, PinJoint, PivotJoint, RatchetJoint, RotaryLimitJoint,
    SimpleMotor, SlideJoint,
};
use tamias2d::shape::Shape;
use tamias2d::snapshot;
use tamias2d::space::{Settings, Space, SpaceError, SLEEP_NEVER};
use tamias2d::{real, Real, Vect};

fn ok<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

const DT: Real = Real::ratio(1, 60);

fn dynamic(space: &mut Space, p: Vect) -> BodyHandle {
    let mut b = ok(Body::new(Real::ONE, Real::ONE));
    b.set_position(p);
    ok(space.add_body(b))
}

fn no_sleep(space: &mut Space) {
    let settings = Settings {
        sleep_time_threshold: SLEEP_NEVER,
        ..*space.settings()
    };
    ok(space.set_settings(settings));
}

/// A wheel on a pivot at its centre, turned by a motor against a damped
/// rotary spring (a load that makes the motor's impulse carry over from
/// step to step), solved with one iteration so that the warm start shows
/// (more iterations converge from either start, and hide it).
fn motor_world() -> (Space, ConstraintHandle, BodyHandle) {
    let mut space = Space::new();
    no_sleep(&mut space);
    let settings = Settings {
        iterations: 1,
        ..*space.settings()
    };
    ok(space.set_settings(settings));
    let ground = ok(space.add_body(Body::new_static()));
    let wheel = dynamic(&mut space, Vect::from_ints(0, 2));
    ok(space.add_constraint(ok(space.pivot_joint(ground, wheel, Vect::from_ints(0, 2)))));
    let load = ok(DampedRotarySpring::new(
        Real::ZERO,
        Real::from_int(40),
        Real::ONE,
    ));
    ok(space.add_constraint(ok(Constraint::new(ground, wheel, load))));
    let mut motor = ok(Constraint::new(
        ground,
        wheel,
        ok(SimpleMotor::new(Real::ZERO)),
    ));
    ok(motor.set_max_force(Real::from_int(50)));
    let motor = ok(space.add_constraint(motor));
    (space, motor, wheel)
}

/// The rate of frame `f`: a sweep up and down, a new value every frame.
fn rate(f: i32) -> Real {
    Real::ratio((f % 40) - 20, 4)
}

fn motor_of(space: &Space, h: ConstraintHandle) -> (Real, Real) {
    let c = space.constraint(h).expect("motor");
    let m = c.joint::<SimpleMotor>().expect("a motor");
    (m.rate(), c.impulse())
}

#[test]
fn a_motor_driven_every_frame_keeps_its_warm_start() {
    let (mut kept, motor, wheel) = motor_world();
    let (mut reset, motor_b, wheel_b) = motor_world();
    let mut nonzero = 0;
    let mut first_difference = None;
    for f in 0..240 {
        let r = rate(f);
        // In place: the accumulated impulse right after the change is the
        // one before it.
        let (_, before) = motor_of(&kept, motor);
        ok(kept.modify_constraint(motor, |c| c.joint_mut::<SimpleMotor>()?.set_rate(r)));
        assert_eq!(motor_of(&kept, motor), (r, before), "frame {f}");
        if before != Real::ZERO {
            nonzero += 1;
        }
        // A new kind: the impulse starts from zero.
        ok(reset.modify_constraint(motor_b, |c| c.set_kind(SimpleMotor::new(r)?)));
        assert_eq!(motor_of(&reset, motor_b), (r, Real::ZERO), "frame {f}");
        ok(kept.step(DT));
        ok(reset.step(DT));
        let w = |s: &Space, b| s.body(b).map(Body::angular_velocity);
        if first_difference.is_none() && w(&kept, wheel) != w(&reset, wheel_b) {
            first_difference = Some(f);
        }
    }
    let w = |s: &Space, b| s.body(b).map_or(0.0, |b| b.angular_velocity().to_f64());
    println!(
        "motor driven every frame: {nonzero} of 240 changes kept a non-zero impulse; the \
         motion first differs from set_kind at frame {first_difference:?}; final ω {:.6} \
         (set_rate) against {:.6} (set_kind)",
        w(&kept, wheel),
        w(&reset, wheel_b)
    );
    // The motor works against its load every frame, so the impulse carried
    // over is never zero after the first step ...
    assert!(nonzero >= 239, "{nonzero} frames with a warm start");
    // ... and throwing it away every frame changes the motion.
    assert!(
        first_difference.is_some_and(|f| f < 5),
        "set_kind and set_rate moved the wheel alike until {first_difference:?}"
    );
    assert_ne!(kept.checksum(), reset.checksum());
}

#[test]
fn the_motor_follows_its_new_rate() {
    // Unbounded torque and no load: the wheel turns at −rate (Chipmunk's
    // sign) the step after the change, whatever the rate was.
    let mut space = Space::new();
    no_sleep(&mut space);
    let ground = ok(space.add_body(Body::new_static()));
    let wheel = dynamic(&mut space, Vect::ZERO);
    let motor = ok(space.add_constraint(ok(Constraint::new(
        ground,
        wheel,
        ok(SimpleMotor::new(Real::ONE)),
    ))));
    for r in [3, -2, 0, 7] {
        let r = Real::from_int(r);
        ok(space.modify_constraint(motor, |c| c.joint_mut::<SimpleMotor>()?.set_rate(r)));
        ok(space.step(DT));
        let w = space.body(wheel).map_or(Real::MAX, Body::angular_velocity);
        assert!((w + r).abs() <= real!(0.000001), "rate {r}: ω = {w}");
    }
}

/// One joint of each kind, indices 0 to 9 in the order of
/// `JointKind`'s variants but for the motor (5), each loaded so that it
/// carries an impulse: bodies hanging from the ground (pivot, pin, taut
/// slide, spring, groove), a wheel where a motor fights a rotary spring,
/// and pendulums on pivots held by a gear, a rotary limit (past which
/// gravity swings them) and a ratchet (whose free direction is the other).
fn all_kinds() -> (Space, Vec<ConstraintHandle>) {
    let mut space = Space::new();
    no_sleep(&mut space);
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(space.add_body(Body::new_static()));
    let at = |x: i32, y: i32| Vect::from_ints(x, y);
    // A body at (x, y), and a pendulum: a body at (x, 0) on a pivot 1 m to
    // its right (gravity turns it counter-clockwise).
    let body = |space: &mut Space, x: i32, y: i32| dynamic(space, at(x, y));
    let (a, b, c, d) = (
        body(&mut space, 0, 0),
        body(&mut space, 4, -1),
        body(&mut space, 8, -1),
        body(&mut space, 12, -2),
    );
    let (e, f, g, h, k) = (
        body(&mut space, 16, 0),
        body(&mut space, 20, 0),
        body(&mut space, 24, 0),
        body(&mut space, 28, 0),
        body(&mut space, 32, 0),
    );
    let kinds: Vec<(BodyHandle, JointKind)> = vec![
        (a, ok(PivotJoint::new(at(1, 0), at(1, 0))).into()),
        (b, ok(PinJoint::new(at(4, 0), Vect::ZERO, Real::ONE)).into()),
        (
            c,
            ok(SlideJoint::new(at(8, 0), Vect::ZERO, Real::HALF, Real::ONE)).into(),
        ),
        (
            d,
            ok(DampedSpring::new(
                at(12, 0),
                Vect::ZERO,
                Real::TWO,
                Real::from_int(20),
                Real::ONE,
            ))
            .into(),
        ),
        (
            e,
            ok(DampedRotarySpring::new(
                Real::HALF,
                Real::from_int(20),
                Real::ONE,
            ))
            .into(),
        ),
        (e, ok(SimpleMotor::new(Real::ONE)).into()),
        (f, ok(GearJoint::new(Real::ZERO, Real::TWO)).into()),
        (g, ok(RotaryLimitJoint::new(-Real::HALF, Real::HALF)).into()),
        (
            h,
            ok(GrooveJoint::new(at(23, 0), at(33, 0), Vect::ZERO)).into(),
        ),
        (k, ok(RatchetJoint::new(Real::ZERO, real!(-0.3))).into()),
    ];
    let mut handles = Vec::new();
    for (body, kind) in kinds {
        let mut c = ok(Constraint::new(ground, body, kind));
        ok(c.set_max_force(Real::from_int(200)));
        handles.push(ok(space.add_constraint(c)));
    }
    // The supports: the wheel on its centre, the pendulums 1 m to the right.
    ok(space.add_constraint(ok(space.pivot_joint(ground, e, at(16, 0)))));
    for (body, x) in [(f, 21), (g, 25), (k, 33)] {
        ok(space.add_constraint(ok(space.pivot_joint(ground, body, at(x, 0)))));
    }
    for _ in 0..30 {
        ok(space.step(DT));
    }
    (space, handles)
}

/// Applies `set` to the joint of kind `T` at `h` through the space and
/// checks the warm start survived: the impulse is the one before, and the
/// rest of the constraint is as `set` made it on a copy.
fn set_keeps_impulse<T: Joint>(
    space: &mut Space,
    h: ConstraintHandle,
    set: impl Fn(&mut T) -> Result<(), ConstraintError>,
) {
    let before = *space.constraint(h).expect("live");
    let mut expected = before;
    ok(set(ok(expected.joint_mut::<T>())));
    ok(space.modify_constraint(h, |c| set(c.joint_mut::<T>()?)));
    let after = *space.constraint(h).expect("live");
    assert_eq!(after, expected, "{}", T::NAME);
    assert_eq!(after.impulse(), before.impulse(), "{}", T::NAME);
    assert_ne!(after, before, "{}: the setter changed nothing", T::NAME);
}

#[test]
fn every_setter_keeps_the_impulse_and_sets_its_value() {
    let (mut space, h) = all_kinds();
    for &c in &h {
        let impulse = space.constraint(c).map_or(Real::ZERO, Constraint::impulse);
        assert_ne!(impulse, Real::ZERO, "{c:?} carries no impulse to keep");
    }
    let v = |x, y| {
        Vect::new(
            real!(0.25) * Real::from_int(x),
            real!(0.25) * Real::from_int(y),
        )
    };
    let s = &mut space;
    set_keeps_impulse::<PivotJoint>(s, h[0], |j| j.set_anchor_a(v(1, 1)));
    set_keeps_impulse::<PivotJoint>(s, h[0], |j| j.set_anchor_b(v(-1, 1)));
    set_keeps_impulse::<PinJoint>(s, h[1], |j| j.set_anchor_a(v(1, 2)));
    set_keeps_impulse::<PinJoint>(s, h[1], |j| j.set_anchor_b(v(2, 1)));
    set_keeps_impulse::<PinJoint>(s, h[1], |j| j.set_dist(real!(1.5)));
    set_keeps_impulse::<SlideJoint>(s, h[2], |j| j.set_anchor_a(v(1, 3)));
    set_keeps_impulse::<SlideJoint>(s, h[2], |j| j.set_anchor_b(v(3, 1)));
    set_keeps_impulse::<SlideJoint>(s, h[2], |j| j.set_min(real!(0.75)));
    set_keeps_impulse::<SlideJoint>(s, h[2], |j| j.set_max(real!(1.25)));
    set_keeps_impulse::<SlideJoint>(s, h[2], |j| j.set_limits(Real::TWO, Real::from_int(3)));
    set_keeps_impulse::<DampedSpring>(s, h[3], |j| j.set_anchor_a(v(0, 1)));
    set_keeps_impulse::<DampedSpring>(s, h[3], |j| j.set_anchor_b(v(0, -1)));
    set_keeps_impulse::<DampedSpring>(s, h[3], |j| j.set_rest_length(Real::ONE));
    set_keeps_impulse::<DampedSpring>(s, h[3], |j| j.set_stiffness(Real::from_int(30)));
    set_keeps_impulse::<DampedSpring>(s, h[3], |j| j.set_damping(Real::TWO));
    set_keeps_impulse::<DampedRotarySpring>(s, h[4], |j| j.set_rest_angle(Real::ONE));
    set_keeps_impulse::<DampedRotarySpring>(s, h[4], |j| j.set_stiffness(Real::from_int(5)));
    set_keeps_impulse::<DampedRotarySpring>(s, h[4], |j| j.set_damping(Real::ZERO));
    set_keeps_impulse::<SimpleMotor>(s, h[5], |j| j.set_rate(-Real::TWO));
    set_keeps_impulse::<GearJoint>(s, h[6], |j| j.set_phase(Real::HALF));
    set_keeps_impulse::<GearJoint>(s, h[6], |j| j.set_ratio(-Real::ONE));
    set_keeps_impulse::<RotaryLimitJoint>(s, h[7], |j| j.set_min(-Real::ONE));
    set_keeps_impulse::<RotaryLimitJoint>(s, h[7], |j| j.set_max(Real::ONE));
    set_keeps_impulse::<RotaryLimitJoint>(s, h[7], |j| j.set_limits(Real::TWO, Real::from_int(3)));
    set_keeps_impulse::<GrooveJoint>(s, h[8], |j| j.set_groove_a(v(-8, 1)));
    set_keeps_impulse::<GrooveJoint>(s, h[8], |j| j.set_groove_b(v(8, 1)));
    set_keeps_impulse::<GrooveJoint>(s, h[8], |j| j.set_groove(v(8, 1), v(-8, 1)));
    set_keeps_impulse::<GrooveJoint>(s, h[8], |j| j.set_anchor_b(v(0, 1)));
    set_keeps_impulse::<RatchetJoint>(s, h[9], |j| j.set_angle(Real::ONE));
    set_keeps_impulse::<RatchetJoint>(s, h[9], |j| j.set_phase(real!(0.1)));
    set_keeps_impulse::<RatchetJoint>(s, h[9], |j| j.set_ratchet(real!(-0.2)));
    // The getters read what was set.
    let c = |i: usize| *space.constraint(h[i]).expect("live");
    let pin = *c(1).joint::<PinJoint>().expect("pin");
    assert_eq!(
        (pin.anchor_a(), pin.anchor_b(), pin.dist()),
        (v(1, 2), v(2, 1), real!(1.5))
    );
    let slide = *c(2).joint::<SlideJoint>().expect("slide");
    assert_eq!((slide.min(), slide.max()), (Real::TWO, Real::from_int(3)));
    let spring = *c(3).joint::<DampedSpring>().expect("spring");
    assert_eq!(
        (spring.rest_length(), spring.stiffness(), spring.damping()),
        (Real::ONE, Real::from_int(30), Real::TWO)
    );
    let gear = *c(6).joint::<GearJoint>().expect("gear");
    assert_eq!((gear.phase(), gear.ratio()), (Real::HALF, -Real::ONE));
    let groove = *c(8).joint::<GrooveJoint>().expect("groove");
    assert_eq!((groove.groove_a(), groove.groove_b()), (v(8, 1), v(-8, 1)));
    let ratchet = *c(9).joint::<RatchetJoint>().expect("ratchet");
    assert_eq!(
        (ratchet.angle(), ratchet.phase(), ratchet.ratchet()),
        (Real::ONE, real!(0.1), real!(-0.2))
    );
    // The changed world still steps (the new parameters act from the next
    // step on).
    for _ in 0..60 {
        ok(space.step(DT));
    }
}

/// Checks that `set` is refused with `err` both on the kind itself and
/// through the space, leaving the constraint and the world unchanged.
fn refused<T: Joint>(
    space: &mut Space,
    h: ConstraintHandle,
    err: ConstraintError,
    set: impl Fn(&mut T) -> Result<(), ConstraintError>,
) {
    let before = *space.constraint(h).expect("live");
    let checksum = space.checksum();
    let mut copy = before;
    assert_eq!(set(ok(copy.joint_mut::<T>())), Err(err), "{}", T::NAME);
    assert_eq!(
        copy,
        before,
        "{}: a refused value changed the joint",
        T::NAME
    );
    assert_eq!(
        space.modify_constraint(h, |c| set(c.joint_mut::<T>()?)),
        Err(SpaceError::Constraint(err)),
        "{}",
        T::NAME
    );
    assert_eq!(space.constraint(h), Some(&before), "{}", T::NAME);
    assert_eq!(space.checksum(), checksum, "{}", T::NAME);
}

#[test]
fn setters_refuse_what_the_constructors_refuse_and_change_nothing() {
    use ConstraintError::{Negative, NotPositive, Saturated, Zero};
    let (mut space, h) = all_kinds();
    let s = &mut space;
    let far = Vect::new(Real::MAX, Real::ZERO);
    let low = Vect::new(Real::MIN, Real::ZERO);
    // The constructors' own errors, for comparison.
    assert_eq!(
        DampedSpring::new(Vect::ZERO, Vect::ZERO, Real::ONE, -Real::ONE, Real::ONE),
        Err(Negative("stiffness"))
    );
    assert_eq!(GearJoint::new(Real::ZERO, Real::ZERO), Err(Zero("ratio")));
    refused::<PivotJoint>(s, h[0], Saturated("anchor_a"), |j| j.set_anchor_a(far));
    refused::<PivotJoint>(s, h[0], Saturated("anchor_b"), |j| j.set_anchor_b(low));
    refused::<PinJoint>(s, h[1], NotPositive("dist"), |j| j.set_dist(Real::ZERO));
    refused::<PinJoint>(s, h[1], NotPositive("dist"), |j| j.set_dist(-Real::ONE));
    refused::<PinJoint>(s, h[1], Saturated("anchor_b"), |j| j.set_anchor_b(far));
    refused::<SlideJoint>(s, h[2], Negative("min"), |j| j.set_min(-Real::ONE));
    refused::<SlideJoint>(s, h[2], Negative("max - min"), |j| j.set_max(real!(0.25)));
    refused::<SlideJoint>(s, h[2], Negative("max - min"), |j| j.set_min(Real::TWO));
    refused::<SlideJoint>(s, h[2], Negative("max - min"), |j| {
        j.set_limits(Real::TWO, Real::ONE)
    });
    refused::<DampedSpring>(s, h[3], Negative("stiffness"), |j| {
        j.set_stiffness(-Real::ONE)
    });
    refused::<DampedSpring>(s, h[3], Negative("damping"), |j| j.set_damping(-Real::ONE));
    refused::<DampedSpring>(s, h[3], Negative("rest_length"), |j| {
        j.set_rest_length(-Real::ONE)
    });
    refused::<DampedSpring>(s, h[3], Saturated("stiffness"), |j| {
        j.set_stiffness(Real::MAX)
    });
    refused::<DampedSpring>(s, h[3], Saturated("anchor_a"), |j| j.set_anchor_a(far));
    refused::<DampedRotarySpring>(s, h[4], Negative("stiffness"), |j| {
        j.set_stiffness(-Real::ONE)
    });
    refused::<DampedRotarySpring>(s, h[4], Negative("damping"), |j| j.set_damping(-Real::ONE));
    refused::<DampedRotarySpring>(s, h[4], Saturated("rest_angle"), |j| {
        j.set_rest_angle(Real::MIN)
    });
    refused::<SimpleMotor>(s, h[5], Saturated("rate"), |j| j.set_rate(Real::MAX));
    refused::<GearJoint>(s, h[6], Zero("ratio"), |j| j.set_ratio(Real::ZERO));
    refused::<GearJoint>(s, h[6], Saturated("phase"), |j| j.set_phase(Real::MAX));
    refused::<RotaryLimitJoint>(s, h[7], Negative("max - min"), |j| j.set_max(-Real::ONE));
    refused::<RotaryLimitJoint>(s, h[7], Negative("max - min"), |j| j.set_min(Real::ONE));
    refused::<RotaryLimitJoint>(s, h[7], Saturated("min"), |j| {
        j.set_limits(Real::MIN, Real::ZERO)
    });
    refused::<GrooveJoint>(s, h[8], NotPositive("groove length"), |j| {
        j.set_groove_a(Vect::from_ints(33, 0))
    });
    refused::<GrooveJoint>(s, h[8], NotPositive("groove length"), |j| {
        j.set_groove(Vect::X, Vect::X)
    });
    refused::<RatchetJoint>(s, h[9], Zero("ratchet"), |j| j.set_ratchet(Real::ZERO));
    refused::<RatchetJoint>(s, h[9], Saturated("angle"), |j| j.set_angle(Real::MAX));
    // The shared parameters: `Constraint`'s own setters.
    let before = *s.constraint(h[0]).expect("live");
    for (err, result) in [
        (
            Negative("max_force"),
            s.modify_constraint(h[0], |c| c.set_max_force(-Real::ONE)),
        ),
        (
            Negative("max_bias"),
            s.modify_constraint(h[0], |c| c.set_max_bias(-Real::ONE)),
        ),
        (
            ConstraintError::ErrorBiasRange,
            s.modify_constraint(h[0], |c| c.set_error_bias(Real::TWO)),
        ),
    ] {
        assert_eq!(result, Err(SpaceError::Constraint(err)));
    }
    assert_eq!(s.constraint(h[0]), Some(&before));
    // A constraint of another kind.
    assert_eq!(
        s.modify_constraint(h[0], |c| c.joint_mut::<SimpleMotor>()?.set_rate(Real::ONE)),
        Err(SpaceError::Constraint(ConstraintError::WrongKind {
            expected: "simple_motor",
            found: "pivot",
        }))
    );
    // A change that fails after a valid one is undone as a whole.
    assert!(s
        .modify_constraint(h[3], |c| {
            let spring = c.joint_mut::<DampedSpring>()?;
            spring.set_rest_length(Real::from_int(4))?;
            spring.set_stiffness(-Real::ONE)
        })
        .is_err());
    assert_eq!(
        s.constraint(h[3])
            .and_then(|c| c.joint::<DampedSpring>())
            .map(DampedSpring::rest_length),
        Some(Real::TWO)
    );
}

/// A body hanging from a static ceiling on a damped spring, and a box
/// resting on the ground, which is the same static body; both asleep.
fn sleeping_world() -> (Space, ConstraintHandle, BodyHandle, BodyHandle) {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(space.add_body(Body::new_static()));
    let floor = ok(Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    ));
    ok(space.add_shape(ok(floor.with_material(Real::ONE, Real::ZERO))));
    let crate_ = dynamic(&mut space, Vect::new(Real::from_int(5), Real::HALF));
    let shape = ok(Shape::box_shape_new(
        crate_,
        Real::ONE,
        Real::ONE,
        Real::ZERO,
    ));
    ok(space.add_shape(ok(shape.with_material(Real::ONE, Real::ZERO))));
    let bob = dynamic(&mut space, Vect::from_ints(-5, 5));
    let spring = ok(DampedSpring::new(
        Vect::from_ints(-5, 8),
        Vect::ZERO,
        Real::from_int(3),
        Real::from_int(100),
        Real::from_int(20),
    ));
    let spring = ok(space.add_constraint(ok(Constraint::new(ground, bob, spring))));
    for _ in 0..600 {
        ok(space.step(DT));
    }
    let asleep = |s: &Space, b| s.body(b).is_some_and(Body::is_sleeping);
    assert!(
        asleep(&space, bob) && asleep(&space, crate_),
        "the world sleeps"
    );
    (space, spring, bob, crate_)
}

#[test]
fn changing_a_joint_wakes_its_body_and_only_its_island() {
    let asleep = |s: &Space, b| s.body(b).is_some_and(Body::is_sleeping);
    let (mut space, spring, bob, crate_) = sleeping_world();
    // A refused change wakes nothing.
    let err = space.modify_constraint(spring, |c| {
        c.joint_mut::<DampedSpring>()?.set_stiffness(-Real::ONE)
    });
    assert!(err.is_err());
    assert!(asleep(&space, bob), "a refused change woke the body");
    // A longer rest length: the bob wakes (and drops), the crate on the
    // same static body sleeps on (a joint's change moves its bodies only).
    ok(space.modify_constraint(spring, |c| {
        c.joint_mut::<DampedSpring>()?
            .set_rest_length(Real::from_int(4))
    }));
    assert!(!asleep(&space, bob), "the jointed body sleeps on");
    assert!(asleep(&space, crate_), "the pile on the static body woke");
    let y0 = space.body(bob).map_or(Real::ZERO, |b| b.position().y);
    for _ in 0..30 {
        ok(space.step(DT));
    }
    let y1 = space.body(bob).map_or(Real::ZERO, |b| b.position().y);
    assert!(y1 < y0 - real!(0.5), "the bob did not drop: {y0} → {y1}");
    assert!(asleep(&space, crate_));
    // `constraint_mut` wakes the same way.
    let (mut space, spring, bob, crate_) = sleeping_world();
    let c = space.constraint_mut(spring).expect("live");
    ok(c.joint_mut::<DampedSpring>()
        .and_then(|j| j.set_damping(Real::ONE)));
    assert!(!asleep(&space, bob));
    assert!(asleep(&space, crate_));
}

#[test]
fn a_world_with_changed_joints_snapshots_to_the_same_checksum() {
    let (mut space, h) = all_kinds();
    ok(space.modify_constraint(h[5], |c| {
        c.joint_mut::<SimpleMotor>()?.set_rate(real!(-1.5))
    }));
    ok(space.modify_constraint(h[3], |c| {
        let spring = c.joint_mut::<DampedSpring>()?;
        spring.set_stiffness(Real::from_int(50))?;
        spring.set_rest_length(real!(1.5))
    }));
    ok(space.modify_constraint(h[8], |c| {
        c.joint_mut::<GrooveJoint>()?
            .set_groove(Vect::from_ints(-3, 1), Vect::from_ints(3, 1))
    }));
    ok(space.modify_constraint(h[1], |c| c.set_max_force(Real::from_int(80))));
    let bytes = snapshot::save(&space);
    let mut copy = ok(snapshot::load(&bytes));
    assert_eq!(copy.checksum(), space.checksum());
    // The copy is another space: its handles are the slots without the
    // first space's origin tag (accepted by both).
    let h: Vec<ConstraintHandle> = h
        .iter()
        .map(|c| ConstraintHandle::from_raw_parts(c.index(), c.generation()))
        .collect();
    assert_eq!(snapshot::first_difference(&space, &copy), None);
    // And both go on alike, the changes included.
    for f in 0..120 {
        let r = rate(f);
        for s in [&mut space, &mut copy] {
            ok(s.modify_constraint(h[5], |c| c.joint_mut::<SimpleMotor>()?.set_rate(r)));
            ok(s.step(DT));
        }
        assert_eq!(copy.checksum(), space.checksum(), "frame {f}");
    }
    assert_eq!(snapshot::save(&copy), snapshot::save(&space));
}
