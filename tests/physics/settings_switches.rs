//! Settings that change how a step is computed: sub-steps
//! (`Settings::substeps`) and the solver switches (`warm_starting`,
//! `friction`, `restitution`, `bias_impulses`).
//!
//! Sub-steps are pinned by their definition: one `step(dt)` with
//! `substeps = k` is bit-identical to `k` steps of the sub-steps' lengths on
//! the same world with `substeps = 1` (forces re-applied before each). The
//! switches are pinned by an equivalent scene where one exists (friction
//! off = every friction 0, restitution off = every elasticity 0, bias off =
//! `collision_bias = 1`), and by behaviour otherwise (warm starting).
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use tamias2d::limits::Limits;

use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::Shape;
use tamias2d::snapshot;
use tamias2d::space::{
    sub_step_dts, validate_state, Settings, Space, SpaceError, WorldState, MAX_SUBSTEPS,
};
use tamias2d_scenes::{self as scenes, SceneDesc, ScriptedWorld};

fn builtin(name: &str) -> SceneDesc {
    scenes::builtin(name).unwrap_or_else(|| panic!("{name} is a built-in scene"))
}

fn build(desc: &SceneDesc) -> ScriptedWorld {
    desc.build()
        .unwrap_or_else(|e| panic!("{}: {e}", desc.name))
}

/// `state` with its sub-step count replaced and its step count divided by
/// it: the only fields in which the two worlds of an equivalence differ.
fn with_substeps(state: &WorldState, substeps: u32) -> WorldState {
    let mut s = state.clone();
    s.settings.substeps = substeps;
    // The one-sub-step world took `substeps` steps per frame.
    s.steps /= u64::from(substeps);
    s
}

#[test]
fn sub_step_lengths_sum_to_the_step_exactly() {
    let dts = [
        1,
        2,
        3,
        7,
        63,
        64,
        65,
        1000,
        71_582_788,
        71_582_789,
        i64::MAX,
    ];
    for bits in dts {
        let dt = Real::from_bits(bits);
        for k in [1, 2, 3, 4, 5, 7, 10, 60, MAX_SUBSTEPS] {
            let subs: Vec<Real> = sub_step_dts(dt, k).collect();
            let sum: i128 = subs.iter().map(|d| i128::from(d.to_bits())).sum();
            assert_eq!(sum, i128::from(bits), "dt {bits} ulp in {k} sub-steps");
            let expected_len = i64::from(k).min(bits);
            assert_eq!(subs.len() as i64, expected_len, "dt {bits}, k {k}");
            let (lo, hi) = (subs.iter().min(), subs.iter().max());
            if let (Some(lo), Some(hi)) = (lo, hi) {
                assert!(hi.to_bits() - lo.to_bits() <= 1, "dt {bits}, k {k}");
                // Longer sub-steps first.
                assert!(subs.windows(2).all(|w| w[0] >= w[1]));
                assert!(lo.is_positive());
            }
        }
    }
    assert_eq!(sub_step_dts(Real::ZERO, 4).count(), 0);
    assert_eq!(sub_step_dts(-Real::ONE, 4).count(), 0);
    assert_eq!(sub_step_dts(Real::ONE, 0).collect::<Vec<_>>(), [Real::ONE]);
}

/// Steps scene `name` for `frames` frames twice: once with `substeps = k`
/// and one `step()` per frame, once with `substeps = 1` and one step per
/// sub-step (the scene's scripted forces are applied before every step, so
/// before every sub-step). Both worlds must end bit-identical.
fn check_substep_equivalence(name: &str, k: u32, frames: u32) {
    let mut desc = builtin(name);
    assert!(desc.spawns.is_empty(), "{name}: spawns count scene steps");
    let dt = desc.dt;
    desc.settings.substeps = k;
    let mut a = build(&desc);
    desc.settings.substeps = 1;
    let mut b = build(&desc);
    let subs: Vec<Real> = sub_step_dts(dt, k).collect();
    for frame in 0..frames {
        a.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        for &sub in &subs {
            b.dt = sub;
            b.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert_eq!(a.space.steps(), u64::from(frame) + 1, "{name}: steps");
        let (sa, sb) = (a.space.state(), with_substeps(b.space.state(), k));
        if *sa != sb {
            let b_space = Space::from_state(sb);
            panic!(
                "{name}, k = {k}: frame {frame} differs: {:?}",
                snapshot::first_difference(&a.space, &b_space)
            );
        }
    }
    let sb = with_substeps(b.space.state(), k);
    assert_eq!(a.space.checksum(), sb.checksum(), "{name}: checksum");
    assert_eq!(
        snapshot::save(&a.space),
        snapshot::save(&Space::from_state(sb)),
        "{name}: snapshot bytes"
    );
    assert_eq!(a.space.stamp(), u64::from(frames) * subs.len() as u64);
    assert!(a.space.validate().is_ok());
}

#[test]
fn substeps_equal_steps_of_the_sub_step_lengths() {
    // 1/60 s is 71_582_788 ulp: k = 2 and 4 divide it, k = 3 and 7 do not
    // (sub-steps of unequal length, warm starting scaled by dt / prev_dt).
    for k in [2, 3, 4, 7] {
        check_substep_equivalence("stack_10", k, 30);
        check_substep_equivalence("newtons_cradle", k, 30);
    }
    check_substep_equivalence("constant_force", 3, 30); // scripted force
    check_substep_equivalence("spin", 3, 30); // scripted torque
    check_substep_equivalence("incline_slide", 3, 30); // friction
    check_substep_equivalence("elastic_pair", 4, 60); // restitution
    check_substep_equivalence("tumbler_500", 2, 5); // kinematic rotation
    check_substep_equivalence("pyramid_20", 3, 5);
}

#[test]
fn substeps_keep_the_time_steps_of_the_last_two_sub_steps() {
    let mut desc = builtin("stack_10");
    desc.settings.substeps = 3;
    let mut scene = build(&desc);
    scene.step_n(2).unwrap_or_else(|e| panic!("{e}"));
    let subs: Vec<Real> = sub_step_dts(desc.dt, 3).collect();
    assert_eq!(subs.len(), 3);
    assert_ne!(subs[0], subs[2], "1/60 s is not a multiple of 3 ulp");
    let state = scene.space.state();
    assert_eq!(state.current_dt, subs[2]);
    assert_eq!(state.prev_dt, subs[1]);
    assert_eq!(scene.space.current_time_step(), subs[2]);
    assert_eq!(scene.space.stamp(), 6);
}

/// A ball dropped on the ground, with counting handlers on every pair and a
/// post-step callback queued from each post-solve.
struct Counted {
    space: Space,
    calls: Arc<[AtomicU32; 5]>,
}

fn counted_world(substeps: u32) -> Counted {
    let mut space = Space::new();
    let settings = Settings {
        gravity: Vect::from_ints(0, -10),
        substeps,
        ..Settings::default()
    };
    space
        .set_settings(settings)
        .unwrap_or_else(|e| panic!("{e}"));
    let ground = space
        .add_body(Body::new_static())
        .unwrap_or_else(|e| panic!("{e}"));
    let seg = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    )
    .and_then(|s| s.with_material(Real::ONE, real!(0.5)))
    .unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(seg).unwrap_or_else(|e| panic!("{e}"));
    let mut ball = Body::new(Real::ONE, real!(0.125)).unwrap_or_else(|e| panic!("{e}"));
    ball.set_position(Vect::new(Real::ZERO, real!(0.7)));
    ball.set_velocity(Vect::from_ints(1, -3));
    let ball = space.add_body(ball).unwrap_or_else(|e| panic!("{e}"));
    let circle = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)
        .and_then(|s| s.with_material(Real::ONE, real!(0.5)))
        .unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(circle).unwrap_or_else(|e| panic!("{e}"));
    let calls: Arc<[AtomicU32; 5]> = Arc::new(Default::default());
    // Both shapes keep the default collision type 0.
    let h = space.add_wildcard_handler(0);
    let c = calls.clone();
    h.begin = Some(Box::new(move |_| {
        c[0].fetch_add(1, Ordering::Relaxed);
        true
    }));
    let c = calls.clone();
    h.pre_solve = Some(Box::new(move |_| {
        c[1].fetch_add(1, Ordering::Relaxed);
        true
    }));
    let c = calls.clone();
    h.post_solve = Some(Box::new(move |ctx| {
        c[2].fetch_add(1, Ordering::Relaxed);
        let c = c.clone();
        ctx.add_post_step_callback(
            1,
            Box::new(move |_| {
                c[4].fetch_add(1, Ordering::Relaxed);
            }),
        );
    }));
    let c = calls.clone();
    h.separate = Some(Box::new(move |_| {
        c[3].fetch_add(1, Ordering::Relaxed);
    }));
    Counted { space, calls }
}

#[test]
fn substeps_run_handlers_and_callbacks_in_every_sub_step() {
    let k = 4;
    let dt = Real::ratio(1, 60);
    let mut a = counted_world(k);
    let mut b = counted_world(1);
    let subs: Vec<Real> = sub_step_dts(dt, k).collect();
    for _ in 0..90 {
        a.space.step(dt).unwrap_or_else(|e| panic!("{e}"));
        for &sub in &subs {
            b.space.step(sub).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    let counts = |c: &Counted| {
        c.calls
            .iter()
            .map(|n| n.load(Ordering::Relaxed))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        counts(&a),
        counts(&b),
        "begin, pre, post, separate, post-step"
    );
    assert!(counts(&a).iter().all(|&n| n > 0), "{:?}", counts(&a));
    // The callback queued (under one key) in a sub-step's post-solve runs
    // after that sub-step: once per sub-step with contact. Both shapes have
    // type 0, so both wildcard handlers run: two post-solves per sub-step.
    assert_eq!(counts(&a)[2], 2 * counts(&a)[4]);
    assert_eq!(*a.space.state(), with_substeps(b.space.state(), k));
}

#[test]
fn substeps_and_switches_survive_a_snapshot_round_trip() {
    let mut desc = builtin("stack_10");
    desc.settings.substeps = 5;
    desc.settings.warm_starting = false;
    desc.settings.restitution = false;
    let mut scene = build(&desc);
    scene.step_n(10).unwrap_or_else(|e| panic!("{e}"));
    let bytes = snapshot::save(&scene.space);
    // Five sub-steps are over the untrusted default (4): the game's own
    // snapshot is trusted; an untrusting load refuses it by name.
    let refused = snapshot::load(&bytes).err().map(|e| e.to_string());
    assert!(refused.is_some_and(|e| e.contains("sub-steps: 5 over the limit of 4")));
    let mut loaded =
        snapshot::load_with(&bytes, &Limits::TRUSTED).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.settings(), scene.space.settings());
    assert_eq!(loaded.settings().substeps, 5);
    assert!(!loaded.settings().warm_starting && !loaded.settings().restitution);
    assert!(loaded.settings().friction && loaded.settings().bias_impulses);
    for _ in 0..10 {
        scene.space.step(desc.dt).unwrap_or_else(|e| panic!("{e}"));
        loaded.step(desc.dt).unwrap_or_else(|e| panic!("{e}"));
    }
    assert_eq!(snapshot::save(&scene.space), snapshot::save(&loaded));
    // The scene description round-trips through JSON too.
    let json = serde_json::to_string(&desc).unwrap_or_else(|e| panic!("{e}"));
    let back: SceneDesc = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, desc);
}

#[test]
fn invalid_substeps_are_rejected() {
    let mut space = Space::new();
    for bad in [0, MAX_SUBSTEPS + 1, u32::MAX] {
        let settings = Settings {
            substeps: bad,
            ..Settings::default()
        };
        assert!(matches!(
            space.set_settings(settings),
            Err(SpaceError::InvalidSetting(_))
        ));
        assert_eq!(space.settings().substeps, 1, "unchanged on error");
        // A forged state (snapshot) is rejected by validation and loading.
        let mut state = space.state().clone();
        state.settings = settings;
        assert!(validate_state(&state).is_err());
        let bytes = snapshot::save_state(&state);
        assert!(snapshot::load(&bytes).is_err());
        // And a scene description is rejected when built.
        let mut desc = builtin("stack_10");
        desc.settings.substeps = bad;
        assert!(desc.build().is_err());
    }
    for good in [1, 2, MAX_SUBSTEPS] {
        let settings = Settings {
            substeps: good,
            ..Settings::default()
        };
        assert_eq!(space.set_settings(settings), Ok(()));
    }
}

#[test]
fn old_scene_files_load_with_the_new_settings_at_their_defaults() {
    let desc = builtin("pyramid_20");
    let json = serde_json::to_string(&desc).unwrap_or_else(|e| panic!("{e}"));
    // Defaults are not written, so existing scene files are unchanged.
    let settings = serde_json::to_string(&desc.settings).unwrap_or_else(|e| panic!("{e}"));
    for key in [
        "substeps",
        "warm_starting",
        "friction",
        "restitution",
        "bias_impulses",
    ] {
        assert!(!settings.contains(key), "{key} written at its default");
    }
    let back: SceneDesc = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, desc);
    let s = Settings::from(&back.settings);
    assert_eq!(s.substeps, 1);
    assert!(s.warm_starting && s.friction && s.restitution && s.bias_impulses);
    let text = r#"{"name": "x", "dt": "0.01", "steps": 1, "bodies": [],
        "settings": {"substeps": 3, "friction": false}}"#;
    let d: SceneDesc = serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.settings.substeps, 3);
    assert!(!d.settings.friction && d.settings.restitution);
}

/// The state of `desc`'s scene after `steps` steps.
fn bodies_after(desc: &SceneDesc, steps: u32) -> WorldState {
    let mut scene = build(desc);
    scene.step_n(steps).unwrap_or_else(|e| panic!("{e}"));
    scene.space.state().clone()
}

fn for_each_shape(desc: &mut SceneDesc, f: impl Fn(&mut tamias2d_scenes::ShapeDesc)) {
    for body in &mut desc.bodies {
        body.shapes.iter_mut().for_each(&f);
    }
}

/// Runs `a` and `b` for `steps` steps; their bodies must end equal, and
/// (for at least one scene of a test) differ from the unchanged scene.
fn same_bodies(a: &SceneDesc, b: &SceneDesc, steps: u32) -> bool {
    let (sa, sb) = (bodies_after(a, steps), bodies_after(b, steps));
    assert_eq!(sa.bodies, sb.bodies, "{}", a.name);
    let plain = builtin(&a.name);
    sa.bodies != bodies_after(&plain, steps).bodies
}

/// For each `(scene, steps)`: the scene with a switch off (`off`) steps to
/// the same bodies as the scene with the equivalent plain data (`same`),
/// and the switch changes the result in at least one of them.
fn check_switch_equivalence(
    cases: &[(&str, u32)],
    off: impl Fn(&mut SceneDesc),
    same: impl Fn(&mut SceneDesc),
    what: &str,
) {
    let mut changed = 0;
    for &(name, steps) in cases {
        let mut with_off = builtin(name);
        off(&mut with_off);
        let mut with_same = builtin(name);
        same(&mut with_same);
        changed += usize::from(same_bodies(&with_off, &with_same, steps));
    }
    assert!(changed > 0, "{what} mattered somewhere");
}

#[test]
fn friction_off_equals_zero_friction_everywhere() {
    check_switch_equivalence(
        &[
            ("incline_slide", 60),
            ("pyramid_20", 20),
            ("bowl_boxes_100", 120),
        ],
        |d| d.settings.friction = false,
        |d| for_each_shape(d, |s| s.friction = Real::ZERO),
        "friction",
    );
}

#[test]
fn restitution_off_equals_zero_elasticity_everywhere() {
    check_switch_equivalence(
        &[
            ("elastic_pair", 240),
            ("newtons_cradle", 60),
            ("bouncy_circles_500", 60),
        ],
        |d| d.settings.restitution = false,
        |d| for_each_shape(d, |s| s.elasticity = Real::ZERO),
        "restitution",
    );
}

#[test]
fn bias_impulses_off_equal_a_collision_bias_of_one() {
    check_switch_equivalence(
        &[
            ("stack_10", 120),
            ("pyramid_20", 20),
            ("bowl_boxes_100", 120),
        ],
        |d| d.settings.bias_impulses = false,
        |d| d.settings.collision_bias = Real::ONE,
        "bias impulses",
    );
}

#[test]
fn warm_starting_off_starts_the_solver_from_zero() {
    // A box resting on the ground. With no iterations the only contact
    // impulse of a step is the warm start: with it the box stays (nearly)
    // at rest; without it the box falls freely for one step.
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space
        .add_body(Body::new_static())
        .unwrap_or_else(|e| panic!("{e}"));
    let seg = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(seg).unwrap_or_else(|e| panic!("{e}"));
    let mut b = Body::new(Real::ONE, real!(0.1)).unwrap_or_else(|e| panic!("{e}"));
    b.set_position(Vect::new(Real::ZERO, real!(0.45)));
    let h = space.add_body(b).unwrap_or_else(|e| panic!("{e}"));
    let bx =
        Shape::box_shape_new(h, Real::ONE, Real::ONE, Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(bx).unwrap_or_else(|e| panic!("{e}"));
    let dt = Real::ratio(1, 60);
    for _ in 0..120 {
        space.step(dt).unwrap_or_else(|e| panic!("{e}"));
    }
    let resting = |s: &Space| s.body(h).map(Body::velocity).unwrap_or_default();
    assert!(resting(&space).y.abs() < real!(0.01), "settled");
    let mut on = space.clone();
    let mut off = space.clone();
    let mut settings = *space.settings();
    settings.iterations = 0;
    on.set_settings(settings).unwrap_or_else(|e| panic!("{e}"));
    settings.warm_starting = false;
    off.set_settings(settings).unwrap_or_else(|e| panic!("{e}"));
    on.step(dt).unwrap_or_else(|e| panic!("{e}"));
    off.step(dt).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        resting(&on).y.abs() < real!(0.01),
        "warm start holds the box"
    );
    let free_fall = resting(&space).y - Real::from_int(10) * dt;
    assert_eq!(
        resting(&off).y,
        free_fall,
        "no impulse at all without warm start"
    );
}

#[test]
fn every_switch_combination_steps_and_validates() {
    for bits in 0u32..16 {
        let mut desc = builtin("bowl_boxes_100");
        desc.settings.warm_starting = bits & 1 != 0;
        desc.settings.friction = bits & 2 != 0;
        desc.settings.restitution = bits & 4 != 0;
        desc.settings.bias_impulses = bits & 8 != 0;
        desc.settings.substeps = 1 + bits % 3;
        let mut scene = build(&desc);
        scene
            .step_n(30)
            .unwrap_or_else(|e| panic!("{bits:04b}: {e}"));
        assert_eq!(scene.space.validate(), Ok(()), "{bits:04b}");
        assert_eq!(scene.space.last_step_stats().saturated_bodies, 0);
    }
}

#[test]
fn defaults_keep_every_switch_on_and_one_sub_step() {
    let s = Settings::default();
    assert_eq!(s.substeps, 1);
    assert!(s.warm_starting && s.friction && s.restitution && s.bias_impulses);
}

#[test]
fn an_infinite_moment_body_never_rotates() {
    // Rotation-free bodies need no switch: a dynamic body with an explicit
    // mass and a zero moment has infinite moment (inverse moment 0), so no
    // contact impulse or torque turns it. Here a box lands on one corner
    // of a slope.
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space
        .add_body(Body::new_static())
        .unwrap_or_else(|e| panic!("{e}"));
    let slope = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, -3),
        Vect::from_ints(10, 3),
        Real::ZERO,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(slope).unwrap_or_else(|e| panic!("{e}"));
    let mut b = Body::new(Real::ONE, Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
    assert!(b.moment_inv().is_zero());
    b.set_position(Vect::from_ints(0, 2));
    let h = space.add_body(b).unwrap_or_else(|e| panic!("{e}"));
    let bx =
        Shape::box_shape_new(h, Real::ONE, Real::ONE, Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(bx).unwrap_or_else(|e| panic!("{e}"));
    if let Some(body) = space.body_mut(h) {
        body.apply_torque(Real::from_int(100));
    }
    let mut touched = false;
    for _ in 0..120 {
        space
            .step(Real::ratio(1, 60))
            .unwrap_or_else(|e| panic!("{e}"));
        touched |= !space.arbiters().is_empty();
        let body = space.body(h).unwrap_or_else(|| panic!("body"));
        assert_eq!(body.angle(), Real::ZERO);
        assert_eq!(body.angular_velocity(), Real::ZERO);
    }
    assert!(touched, "the box reached the slope");
}

/// A scene with spawns rolled back in place keeps its spawn schedule with
/// `substeps > 1`: the schedule counts steps (`WorldState::steps`), not
/// sub-steps (`stamp`).
#[test]
fn rollback_keeps_the_spawn_schedule_with_substeps() {
    let mut desc = builtin("rain_1000");
    desc.settings.substeps = 3;
    let mut straight = build(&desc);
    let mut rolled = build(&desc);
    straight.step_n(90).unwrap_or_else(|e| panic!("{e}"));
    rolled.step_n(40).unwrap_or_else(|e| panic!("{e}"));
    let saved = rolled.space.state().clone();
    assert_eq!(saved.steps, 40);
    assert_eq!(saved.stamp, 120);
    rolled.step_n(30).unwrap_or_else(|e| panic!("{e}"));
    rolled.restore_state(&saved);
    assert_eq!(rolled.steps_taken(), 40);
    rolled.step_n(50).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rolled.space.checksum(), straight.space.checksum());
    assert_eq!(
        straight.space.bodies().count(),
        rolled.space.bodies().count()
    );
}
