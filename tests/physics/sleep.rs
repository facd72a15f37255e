//! Sleeping islands (`space::sleep`): a settled pile falls asleep and stays
//! exactly where it was, a body dropped on it wakes exactly the island it
//! hits, a rollback across sleep and wake equals the straight run, the API
//! wakes what it changes, and a forged sleep state is refused.
use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::snapshot;
use tamias2d::space::{Settings, Space, SpaceError, SLEEP_NEVER};

const DT: Real = Real::lit("0.0166666666");

/// Ground from x = −30 to 30, and a column of `n` unit boxes at `x`.
fn ground(space: &mut Space) -> BodyHandle {
    let g = space.add_body(Body::new_static()).unwrap();
    let seg = Shape::segment_shape_new(
        g,
        Vect::from_ints(-30, 0),
        Vect::from_ints(30, 0),
        Real::ZERO,
    )
    .unwrap()
    .with_material(Real::ONE, Real::ZERO)
    .unwrap();
    space.add_shape(seg).unwrap();
    g
}

fn column(space: &mut Space, x: i32, n: i32) -> Vec<BodyHandle> {
    (0..n)
        .map(|i| {
            let b = space
                .add_body(
                    Body::new(
                        Real::ONE,
                        tamias2d::shape::mass::moment_for_box(Real::ONE, Real::ONE, Real::ONE),
                    )
                    .unwrap(),
                )
                .unwrap();
            space
                .body_mut(b)
                .unwrap()
                .set_position(Vect::new(Real::from_int(x), Real::HALF + Real::from_int(i)));
            let s = Shape::box_shape_new(b, Real::ONE, Real::ONE, Real::ZERO)
                .unwrap()
                .with_material(Real::ONE, Real::ZERO)
                .unwrap();
            space.add_shape(s).unwrap();
            b
        })
        .collect()
}

fn world() -> (Space, Vec<BodyHandle>, Vec<BodyHandle>) {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    ground(&mut space);
    let left = column(&mut space, -10, 3);
    let right = column(&mut space, 10, 3);
    (space, left, right)
}

fn asleep(space: &Space, bodies: &[BodyHandle]) -> bool {
    bodies.iter().all(|&b| space.body(b).unwrap().is_sleeping())
}

fn awake(space: &Space, bodies: &[BodyHandle]) -> bool {
    bodies
        .iter()
        .all(|&b| !space.body(b).unwrap().is_sleeping())
}

fn step_until(space: &mut Space, max: u32, done: impl Fn(&Space) -> bool) -> u32 {
    for n in 1..=max {
        space.step(DT).unwrap();
        if done(space) {
            return n;
        }
    }
    panic!("not reached in {max} steps");
}

#[test]
fn a_settled_pyramid_falls_asleep_and_stays_exactly_where_it_rests() {
    let mut w = tamias2d_scenes::builtin("pyramid_20")
        .unwrap()
        .build()
        .unwrap();
    let start: Vec<(BodyHandle, Vect)> = w.space.bodies().map(|(h, b)| (h, b.position())).collect();
    let dynamic = start.len() - 1;
    let mut fell_asleep_at = None;
    for n in 1..=600 {
        w.step().unwrap();
        if fell_asleep_at.is_none() && w.space.sleeping_bodies() == dynamic {
            fell_asleep_at = Some(n);
        }
    }
    let at = fell_asleep_at.expect("the pyramid never fell asleep");
    // Not before it could have settled: the default threshold is 0.5 s.
    assert!(at > 30, "asleep after {at} steps");
    let rest: Vec<Vect> = w.space.bodies().map(|(_, b)| b.position()).collect();
    w.step_n(600).unwrap();
    let later: Vec<Vect> = w.space.bodies().map(|(_, b)| b.position()).collect();
    assert_eq!(rest, later, "a sleeping pyramid moved");
    assert_eq!(w.space.sleeping_bodies(), dynamic);
    // Standing: no box moved more than 5 cm from where it was built.
    let worst = start
        .iter()
        .zip(&later)
        .map(|((_, a), b)| (*a - *b).length())
        .max()
        .unwrap();
    assert!(worst < Real::lit("0.05"), "a box moved {worst} m");
    // A sleeping pile costs nothing: no candidate pair, no contact.
    let stats = w.space.last_step_stats();
    assert_eq!((stats.candidate_pairs, stats.solver_contacts), (0, 0));
}

#[test]
fn a_ball_dropped_on_one_sleeping_pile_wakes_that_pile_only() {
    let (mut space, left, right) = world();
    step_until(&mut space, 600, |s| asleep(s, &left) && asleep(s, &right));
    let ball = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    space
        .add_shape(Shape::circle_shape_new(ball, Real::lit("0.25"), Vect::ZERO).unwrap())
        .unwrap();
    space
        .body_mut(ball)
        .unwrap()
        .set_position(Vect::new(Real::from_int(-10), Real::from_int(5)));
    assert!(
        asleep(&space, &left) && asleep(&space, &right),
        "adding a ball woke a pile"
    );
    let hit = step_until(&mut space, 120, |s| awake(s, &left));
    assert!(
        hit > 10,
        "the left pile woke before the ball could reach it ({hit} steps)"
    );
    assert!(asleep(&space, &right), "the right pile woke");
    // The left pile took the hit with its contacts: no pop, no collapse.
    for _ in 0..120 {
        space.step(DT).unwrap();
        assert!(asleep(&space, &right), "the right pile woke");
    }
    let top = space.body(left[2]).unwrap().position();
    assert!(
        (top.x - Real::from_int(-10)).abs() < Real::lit("0.05"),
        "{top:?}"
    );
    assert!(
        (top.y - Real::lit("2.5")).abs() < Real::lit("0.05"),
        "{top:?}"
    );
}

#[test]
fn a_woken_pile_does_not_pop() {
    let (mut space, left, _) = world();
    step_until(&mut space, 600, |s| asleep(s, &left));
    let before: Vec<Vect> = left
        .iter()
        .map(|&b| space.body(b).unwrap().position())
        .collect();
    space.activate_body(left[0]).unwrap();
    assert!(awake(&space, &left), "activate_body wakes the whole island");
    space.step(DT).unwrap();
    for (&b, p) in left.iter().zip(&before) {
        let body = space.body(b).unwrap();
        // Warm-started contacts hold the pile: it moves far less than one
        // step of free fall (g·dt² = 2.8 mm).
        assert!(
            (body.position() - *p).length() < Real::lit("0.0005"),
            "{:?} vs {p:?}",
            body.position()
        );
    }
}

#[test]
fn rollback_across_sleep_and_wake_equals_the_straight_run() {
    let (mut space, left, right) = world();
    step_until(&mut space, 600, |s| asleep(s, &left) && asleep(s, &right));
    let saved = snapshot::save(&space);
    let drop_ball = |space: &mut Space| {
        let ball = space
            .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
            .unwrap();
        space
            .add_shape(Shape::circle_shape_new(ball, Real::lit("0.25"), Vect::ZERO).unwrap())
            .unwrap();
        space
            .body_mut(ball)
            .unwrap()
            .set_position(Vect::from_ints(10, 5));
    };
    let mut straight = Space::new();
    straight.restore_state(space.state());
    drop_ball(&mut straight);
    for _ in 0..200 {
        straight.step(DT).unwrap();
    }
    // The other world: wake, go on, then roll back to the sleeping save.
    drop_ball(&mut space);
    for _ in 0..50 {
        space.step(DT).unwrap();
    }
    assert!(awake(&space, &right));
    space.load_snapshot(&saved).unwrap();
    assert!(asleep(&space, &right));
    drop_ball(&mut space);
    for _ in 0..200 {
        space.step(DT).unwrap();
    }
    assert_eq!(space.checksum(), straight.checksum());
    assert_eq!(space.state(), straight.state());
    // And the run slept again by the end, so both paths crossed sleep.
    assert!(asleep(&space, &left));
}

#[test]
fn the_api_wakes_what_it_changes() {
    let (mut space, left, right) = world();
    step_until(&mut space, 600, |s| asleep(s, &left) && asleep(s, &right));
    space.body(left[1]).unwrap();
    assert!(asleep(&space, &left), "reading a body wakes nothing");
    space.body_mut(left[1]).unwrap();
    assert!(awake(&space, &left) && asleep(&space, &right));

    step_until(&mut space, 600, |s| asleep(s, &left));
    let s = space.body_shapes(right[2]).next().unwrap().0;
    space.modify_shape(s, |_| Ok(())).unwrap();
    assert!(awake(&space, &right) && asleep(&space, &left));

    step_until(&mut space, 600, |s| asleep(s, &right));
    let mut settings = *space.settings();
    space.set_settings(settings).unwrap();
    assert!(asleep(&space, &right), "the same settings wake nothing");
    settings.iterations = 12;
    space.set_settings(settings).unwrap();
    assert!(awake(&space, &left) && awake(&space, &right));

    // Sleep on request, and in a group.
    space.sleep_body(left[0]).unwrap();
    assert!(asleep(&space, &left) && awake(&space, &right));
    space.sleep_body_with_group(right[0], left[0]).unwrap();
    assert!(asleep(&space, &right));
    space.activate_body(right[2]).unwrap();
    assert!(
        awake(&space, &left) && awake(&space, &right),
        "a group wakes as one"
    );
    space.validate().unwrap();
}

#[test]
fn a_body_that_may_not_sleep_keeps_its_island_awake() {
    let (mut space, left, right) = world();
    space.body_mut(left[2]).unwrap().set_sleep_allowed(false);
    step_until(&mut space, 600, |s| asleep(s, &right));
    for _ in 0..300 {
        space.step(DT).unwrap();
    }
    assert!(awake(&space, &left));
    assert!(matches!(
        space.sleep_body(left[0]),
        Err(SpaceError::Sleep(_))
    ));
}

#[test]
fn sleeping_off_never_sleeps() {
    let (mut space, left, right) = world();
    let settings = Settings {
        sleep_time_threshold: SLEEP_NEVER,
        ..*space.settings()
    };
    space.set_settings(settings).unwrap();
    for _ in 0..600 {
        space.step(DT).unwrap();
    }
    assert!(awake(&space, &left) && awake(&space, &right));
    assert_eq!(space.body(left[0]).unwrap().idle_time(), Real::ZERO);
}

#[test]
fn a_forged_sleep_state_is_refused() {
    let (mut space, left, right) = world();
    step_until(&mut space, 600, |s| asleep(s, &left) && asleep(s, &right));
    space.validate().unwrap();
    let good = space.state().clone();
    assert!(!good.dormant_arbiters.is_empty());
    let forged = |f: &dyn Fn(&mut tamias2d::space::WorldState)| {
        let mut s = good.clone();
        f(&mut s);
        let bytes = snapshot::save_state(&s);
        let mut live = Space::new();
        live.restore_state(&good);
        let before = live.checksum();
        let err = live.load_snapshot(&bytes).unwrap_err();
        assert_eq!(live.checksum(), before, "a refused load changed the world");
        err.to_string()
    };
    // A sleeping body that moves.
    let e = forged(&|s| {
        let b = s.bodies.get_mut(left[0]).unwrap();
        b.set_velocity(Vect::from_ints(1, 0));
    });
    assert!(e.contains("sleeping body has a velocity"), "{e}");
    // An island root that is not a root.
    let e = forged(&|s| {
        let b = s.bodies.get_mut(left[0]).unwrap();
        b.set_sleep_allowed(false);
    });
    assert!(e.contains("may not sleep"), "{e}");
    // A dormant arbiter duplicated into the live list.
    let e = forged(&|s| {
        let a = s.dormant_arbiters[0].clone();
        s.arbiters.push(a);
        s.arbiters
            .sort_by_key(|a| (a.shapes().0.index(), a.shapes().1.index()));
    });
    assert!(e.contains("arbiter"), "{e}");
    // Dormant arbiters out of their canonical order.
    assert!(good.dormant_arbiters.len() >= 2);
    let e = forged(&|s| s.dormant_arbiters.reverse());
    assert!(e.contains("dormant arbiter"), "{e}");
}

/// The `sleep_wake` scene does what its registry line says: both columns
/// asleep before the ball spawns, the ball wakes the left one only, and it
/// is asleep again by the end.
#[test]
fn the_sleep_wake_scene_sleeps_wakes_one_island_and_sleeps_again() {
    let mut w = tamias2d_scenes::builtin("sleep_wake")
        .unwrap()
        .build()
        .unwrap();
    let left = w.body("left_top").unwrap();
    let right = w.body("right_top").unwrap();
    let sleeping = |w: &tamias2d_scenes::ScriptedWorld, b| w.space.body(b).unwrap().is_sleeping();
    w.step_n(179).unwrap();
    assert!(
        sleeping(&w, left) && sleeping(&w, right),
        "both asleep before the ball"
    );
    let mut left_woke = false;
    while w.steps_taken() < 480 {
        w.step().unwrap();
        left_woke |= !sleeping(&w, left);
        assert!(
            sleeping(&w, right),
            "the right column woke at step {}",
            w.steps_taken()
        );
    }
    assert!(left_woke, "the ball never woke the left column");
    assert!(
        sleeping(&w, left),
        "the left column is not asleep again by step 480"
    );
    let ball = w.body("ball").unwrap();
    assert!(
        w.space.body(ball).unwrap().is_sleeping(),
        "the ball rests on the column, asleep with it"
    );
}

/// Found by the `world_ops` fuzz target: with a sleep time threshold of 0,
/// an island with a body that may not sleep fell asleep (its idle time 0
/// reached the threshold 0). Such a body, or one touching a moving
/// kinematic body, keeps its island awake at any threshold.
#[test]
fn a_zero_threshold_still_keeps_restless_islands_awake() {
    let (mut space, left, right) = world();
    let settings = Settings {
        sleep_time_threshold: Real::ZERO,
        ..*space.settings()
    };
    space.set_settings(settings).unwrap();
    space.body_mut(left[2]).unwrap().set_sleep_allowed(false);
    for _ in 0..120 {
        space.step(DT).unwrap();
        space.validate().unwrap();
    }
    assert!(awake(&space, &left));
    assert!(asleep(&space, &right));
    // A kinematic conveyor under a third column keeps it awake too.
    let belt = space.add_body(Body::new_kinematic()).unwrap();
    space
        .add_shape(Shape::box_shape_new(belt, Real::from_int(4), Real::ONE, Real::ZERO).unwrap())
        .unwrap();
    space
        .body_mut(belt)
        .unwrap()
        .set_position(Vect::from_ints(20, -5));
    space
        .body_mut(belt)
        .unwrap()
        .set_angular_velocity(Real::ONE);
    let on_belt = column(&mut space, 20, 1);
    space
        .body_mut(on_belt[0])
        .unwrap()
        .set_position(Vect::new(Real::from_int(20), Real::lit("-4.0")));
    for _ in 0..60 {
        space.step(DT).unwrap();
        space.validate().unwrap();
    }
    assert!(awake(&space, &on_belt));
}
