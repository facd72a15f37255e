//! Snapshots (`tamias2d::snapshot`): byte round trips continue exactly,
//! the in-memory path likewise, handles survive restores, random scripts of
//! world edits stay in lockstep across save/load/clone/restore, and no
//! malformed input is accepted or panics (`snapshot/malformed.rs`); the
//! byte layout is pinned (`snapshot/format.rs`); desync diagnosis names
//! the first difference (`snapshot/diagnosis.rs`).
//!
//! Equality is always exact: `save` bytes (which include the checksum) or
//! `first_difference` = `None`. A lockstep engine has no tolerance.
use std::sync::OnceLock;

use proptest::prelude::*;
use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{Constraint, PinJoint};
use tamias2d::shape::Shape;
use tamias2d::snapshot::{
    self, SnapshotError, Subject, FORMAT_VERSION, FRAME_FORMAT_VERSION, HEADER_LEN, MAGIC,
};
use tamias2d::space::{FrameState, ShapeHandle, Space, SpaceError, WorldState};
use tamias2d::{Real, Transform, Vect};
use tamias2d_scenes::{self as scenes, ScriptedWorld};

fn build(name: &str) -> ScriptedWorld {
    scenes::builtin(name)
        .unwrap_or_else(|| panic!("{name} is a listed scene"))
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn save(space: &Space) -> Vec<u8> {
    snapshot::save(space)
}

/// Fails with the first differing field when two worlds' bytes differ.
fn assert_same(a: &Space, b: &Space, what: &str) {
    let (x, y) = (save(a), save(b));
    if x != y {
        let why = snapshot::first_difference(a, b)
            .map_or_else(|| "bytes only".to_owned(), |d| d.to_string());
        panic!("{what}: worlds differ: {why}");
    }
}

fn ok<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

/// Makes a world diverge the way a mispredicted rollback frame does: kicks
/// every dynamic body, removes one and adds another (free list and slots
/// change), and steps.
fn diverge(space: &mut Space, dt: Real) {
    let dynamic: Vec<BodyHandle> = space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .collect();
    for &h in &dynamic {
        if let Some(b) = space.body_mut(h) {
            b.set_velocity(b.velocity() + Vect::from_ints(2, 5));
            b.set_angular_velocity(b.angular_velocity() + Real::ONE);
        }
    }
    if let Some(&h) = dynamic.get(dynamic.len() / 2) {
        ok(space.remove_body(h));
    }
    let extra = ok(space.add_body(ok(Body::new(Real::ONE, Real::ONE))));
    ok(space.add_shape(ok(Shape::circle_shape_new(extra, Real::HALF, Vect::ZERO))));
    // A script may leave a dynamic body without mass, which `step` refuses.
    match space.step(dt) {
        Ok(()) | Err(SpaceError::MasslessDynamicBody(_)) => {}
        Err(e) => panic!("{e}"),
    }
}

/// The round trip of one scene. A reference scene runs `steps` steps. At
/// each fork step `k`:
/// * two in-place forks — scenes built alongside, so their scripts
///   (forces, spawns, counters) are at the same step — diverge and are
///   rolled back to the reference: the first by `load_snapshot` (even
///   forks) or `restore_state` (odd forks), the second by the frame paths
///   `load_frame_snapshot` (even) or `restore_frame` (odd); then they keep
///   stepping as scenes;
/// * `load(save(reference))` and `reference.clone()` start and step with
///   `Space::step` (no script: a fresh space is not a scene's space).
///
/// After every step each fork must equal its reference byte for byte.
fn round_trip(name: &str, steps: u32, forks: &[u32]) {
    let mut reference = build(name);
    let dt = reference.dt;
    let mut in_place: Vec<(u32, ScriptedWorld)> = forks
        .iter()
        .flat_map(|&k| [(k, build(name)), (k, build(name))])
        .collect();
    let mut frame = FrameState::default();
    let mut frame_bytes = Vec::new();
    let mut raw: Vec<(u32, Space, Space)> = Vec::new();
    for t in 0..=steps {
        if t > 0 {
            ok(reference.step());
            for (_, f) in &mut in_place {
                ok(f.step());
            }
            for (_, loaded, cloned) in &mut raw {
                ok(loaded.step(dt));
                ok(cloned.step(dt));
            }
        }
        let bytes = save(&reference.space);
        reference.space.save_frame(&mut frame);
        snapshot::save_frame_into(&reference.space, &mut frame_bytes);
        for (i, (k, f)) in in_place.iter_mut().enumerate() {
            // i = 2·fork + (0: full state, 1: frame); fork parity picks bytes or memory.
            let path = match (i % 2, (i / 2) % 2) {
                (0, 0) => "load_snapshot",
                (0, _) => "restore_state",
                (_, 0) => "load_frame_snapshot",
                _ => "restore_frame",
            };
            if t == *k {
                diverge(&mut f.space, dt);
                assert!(save(&f.space) != bytes, "{name}: diverge changed nothing");
                match path {
                    "load_snapshot" => ok(f.space.load_snapshot(&bytes)),
                    "restore_state" => f.space.restore_state(reference.space.state()),
                    "load_frame_snapshot" => {
                        ok(f.space.load_frame_snapshot(&frame_bytes));
                        // One state, one encoding: the loaded frame saves
                        // to the very bytes it came from.
                        assert!(
                            snapshot::save_frame(&f.space) == frame_bytes,
                            "{name}: a loaded frame re-saves differently"
                        );
                    }
                    _ => ok(f.space.restore_frame(&frame)),
                }
                ok(f.space.validate());
            }
            if t >= *k {
                assert_same(
                    &reference.space,
                    &f.space,
                    &format!("{name}: {path} at step {k}, now step {t}"),
                );
            }
        }
        for (k, loaded, cloned) in &raw {
            assert_same(
                cloned,
                loaded,
                &format!("{name}: load at step {k}, now step {t}"),
            );
        }
        if forks.contains(&t) {
            // The frame's two forms and its checksum agree with the world.
            assert_eq!(frame.checksum(), reference.space.checksum(), "{name}");
            assert!(
                ok(snapshot::decode_frame(&frame_bytes, &reference.space)) == frame,
                "{name}: the frame bytes decode to another frame"
            );
            let loaded = ok(snapshot::load(&bytes));
            assert!(
                save(&loaded) == bytes,
                "{name}: load(save(w)) re-saves differently"
            );
            raw.push((t, loaded, reference.space.clone()));
        }
    }
    ok(reference.space.validate());
    assert_eq!(reference.space.steps(), u64::from(steps));
}

/// The section D (joints) scenes before the section E (level) scenes at
/// the end of [`ROUND_TRIPS`].
const JOINT_SCENES: usize = 9;
/// The section E (level) scenes at the end of [`ROUND_TRIPS`].
const LEVEL_SCENES: usize = 1;

/// Smallest size of every scene family, with steps and fork points sized
/// for debug builds (step + save of the big ones cost tens of ms there).
const ROUND_TRIPS: &[(&str, u32, &[u32])] = &[
    ("bowl_circles_100", 60, &[0, 25, 50]),
    ("bowl_boxes_100", 60, &[0, 25, 50]),
    ("bowl_hexagons_100", 60, &[0, 25, 50]),
    ("bouncy_circles_500", 16, &[0, 4, 10]),
    ("no_collide", 40, &[0, 10, 30]),
    ("pyramid_20", 12, &[0, 3, 8]),
    ("many_pyramids_4x4", 7, &[2, 4]),
    ("rain_1000", 45, &[0, 15, 33]),
    ("tumbler_500", 30, &[0, 10, 22]),
    ("free_fall", 120, &[0, 1, 40, 100]),
    ("constant_force", 120, &[0, 1, 40, 100]),
    ("projectile_45", 120, &[0, 1, 40, 100]),
    ("projectile_60", 120, &[0, 1, 40, 100]),
    ("spin", 120, &[0, 1, 40, 100]),
    ("elastic_pair", 120, &[0, 1, 40, 100]),
    ("newtons_cradle", 120, &[0, 1, 40, 100]),
    ("incline_slide", 120, &[0, 1, 40, 100]),
    ("incline_stick", 120, &[0, 1, 40, 100]),
    ("stack_10", 60, &[0, 7, 30, 55]),
    // Asleep by step 100, the ball spawns at 180, the left column is
    // awake at 200 and asleep again by 480: saves across sleep and wake.
    ("sleep_wake", 480, &[0, 100, 179, 180, 200, 400]),
    ("bullets", 60, &[0, 1, 2, 3, 31]),
    ("pendulum", 120, &[0, 1, 40, 100]),
    ("chain_100", 60, &[0, 25, 50]),
    ("windmill", 150, &[0, 29, 30, 100]),
    ("gear_train", 120, &[0, 1, 40, 100]),
    ("spring_mass", 120, &[0, 1, 40, 100]),
    ("ratchet", 120, &[0, 1, 40, 100]),
    ("rope_bridge", 200, &[0, 119, 120, 150]),
    ("ragdolls_20", 60, &[0, 25, 50]),
    ("car", 120, &[0, 1, 40, 100]),
    ("level_300", 60, &[0, 25, 50]),
];

#[test]
fn round_trips_cover_every_scene_family() {
    for s in scenes::REGISTRY {
        let stands_for = s.covered_by.unwrap_or(s.name);
        assert!(
            ROUND_TRIPS.iter().any(|(n, _, _)| *n == stands_for),
            "{} ({}): {stands_for} is not round-tripped",
            s.name,
            s.about
        );
    }
}

#[test]
fn round_trip_terrain_scenes_continue_identically() {
    for &(name, steps, forks) in &ROUND_TRIPS[..5] {
        round_trip(name, steps, forks);
    }
}

#[test]
fn round_trip_stacking_scenes_continue_identically() {
    for &(name, steps, forks) in &ROUND_TRIPS[5..9] {
        round_trip(name, steps, forks);
    }
}

#[test]
fn round_trip_accuracy_scenes_continue_identically() {
    for &(name, steps, forks) in &ROUND_TRIPS[9..ROUND_TRIPS.len() - JOINT_SCENES - LEVEL_SCENES] {
        round_trip(name, steps, forks);
    }
}

#[test]
fn round_trip_joint_scenes_continue_identically() {
    let joints = ROUND_TRIPS.len() - JOINT_SCENES - LEVEL_SCENES;
    for &(name, steps, forks) in &ROUND_TRIPS[joints..ROUND_TRIPS.len() - LEVEL_SCENES] {
        round_trip(name, steps, forks);
    }
}

#[test]
fn round_trip_level_scenes_continue_identically() {
    for &(name, steps, forks) in &ROUND_TRIPS[ROUND_TRIPS.len() - LEVEL_SCENES..] {
        round_trip(name, steps, forks);
    }
}

/// The same edits on every world: add a body with a shape, remove a body,
/// add another, remove the first one's shape, step, add a third. Returns
/// the handles handed out.
fn edit(space: &mut Space, dt: Real) -> (Vec<BodyHandle>, ShapeHandle) {
    let body = |x: i32| {
        let mut b = ok(Body::new(Real::TWO, Real::ONE));
        b.set_position(Vect::from_ints(x, 60));
        b
    };
    let h1 = ok(space.add_body(body(-3)));
    let s1 = ok(space.add_shape(ok(Shape::circle_shape_new(h1, Real::ONE, Vect::ZERO))));
    let victim = space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .nth(5)
        .unwrap_or_else(|| panic!("a dynamic body"));
    ok(space.remove_body(victim));
    let h2 = ok(space.add_body(body(3)));
    ok(space.remove_shape(s1));
    for _ in 0..5 {
        ok(space.step(dt));
    }
    let h3 = ok(space.add_body(body(0)));
    (vec![h1, h2, h3], s1)
}

#[test]
fn edits_after_a_restore_give_the_same_handles_and_bytes_on_every_path() {
    let name = "bowl_circles_100";
    let mut a = build(name);
    let dt = a.dt;
    ok(a.step_n(30));
    // A free slot in each arena before the snapshot.
    let removed = a
        .space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .nth(10)
        .unwrap_or_else(|| panic!("a dynamic body"));
    ok(a.space.remove_body(removed));
    ok(a.step_n(3));
    let bytes = save(&a.space);
    let state: WorldState = a.space.state().clone();

    let mut worlds: Vec<(&str, Space)> = vec![("loaded", ok(snapshot::load(&bytes)))];
    worlds.push(("cloned", a.space.clone()));
    let mut in_place = a.space.clone();
    diverge(&mut in_place, dt);
    ok(in_place.load_snapshot(&bytes));
    worlds.push(("load_snapshot", in_place));
    let mut restored = a.space.clone();
    diverge(&mut restored, dt);
    restored.restore_state(&state);
    worlds.push(("restore_state", restored));

    let (handles, shape) = edit(&mut a.space, dt);
    assert_eq!(
        handles[0].index(),
        removed.index(),
        "the freed slot is reused"
    );
    assert_ne!(handles[0], removed, "with a new generation");
    for (what, w) in &mut worlds {
        let (h, s) = edit(w, dt);
        assert_eq!(h, handles, "{what}: body handles");
        assert_eq!(s, shape, "{what}: shape handle");
        assert_same(&a.space, w, what);
        ok(w.validate());
    }
}

/// A ball (collision type 2) above a ground segment (type 1); it lands
/// within a second.
fn ball_world() -> (Space, BodyHandle) {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(w.add_body(Body::new_static()));
    let mut seg = ok(Shape::segment_shape_new(
        ground,
        Vect::from_ints(-10, 0),
        Vect::from_ints(10, 0),
        Real::ZERO,
    ));
    seg.collision_type = 1;
    ok(w.add_shape(seg));
    let mut b = ok(Body::new(Real::ONE, Real::ONE));
    b.set_position(Vect::from_ints(0, 2));
    let ball = ok(w.add_body(b));
    let mut c = ok(Shape::circle_shape_new(ball, Real::ONE, Vect::ZERO));
    c.collision_type = 2;
    ok(w.add_shape(c));
    (w, ball)
}

/// Registers a `begin` handler for types (2, 1) that counts its calls.
fn count_begins(w: &mut Space) -> std::sync::Arc<std::sync::atomic::AtomicU32> {
    let begins = std::sync::Arc::new(std::sync::atomic::AtomicU32::new(0));
    let seen = std::sync::Arc::clone(&begins);
    w.add_collision_handler(2, 1).begin = Some(Box::new(move |_| {
        seen.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        true
    }));
    begins
}

#[test]
fn load_snapshot_keeps_handlers_and_handles() {
    let (mut w, ball) = ball_world();
    let begins = count_begins(&mut w);
    let bytes = save(&w);
    for _ in 0..60 {
        ok(w.step(dt()));
    }
    assert_eq!(begins.load(std::sync::atomic::Ordering::Relaxed), 1);
    ok(w.load_snapshot(&bytes));
    assert!(w.body(ball).is_some(), "the game's handles still work");
    for _ in 0..60 {
        ok(w.step(dt()));
    }
    assert_eq!(
        begins.load(std::sync::atomic::Ordering::Relaxed),
        2,
        "the handler survived the rollback"
    );
}

#[test]
fn a_loaded_space_takes_handlers_by_collision_type() {
    let (mut w, ball) = ball_world();
    let bytes = save(&w);
    let mut loaded = ok(snapshot::load(&bytes));
    let begins = count_begins(&mut loaded);
    for _ in 0..60 {
        ok(w.step(dt()));
        ok(loaded.step(dt()));
    }
    assert_eq!(
        begins.load(std::sync::atomic::Ordering::Relaxed),
        1,
        "re-attached handler ran"
    );
    assert_same(&w, &loaded, "a handler that accepts changes nothing");
    // Handles from the saved world belong to another space.
    assert!(loaded.body(ball).is_none());
    let raw = BodyHandle::from_raw_parts(ball.index(), ball.generation());
    assert!(loaded.body(raw).is_some(), "raw handles (origin 0) work");
}

// ---------------------------------------------------------------------------
// Model-based property test.

#[derive(Clone, Debug)]
enum Op {
    AddBody { x: i8, y: u8, kind: u8, shape: u8 },
    AddShape { pick: usize, kind: u8, size: u8 },
    RemoveBody { pick: usize },
    RemoveShape { pick: usize },
    Impulse { pick: usize, ix: i8, iy: i8 },
    Step { n: u8 },
    SaveLoad,
    Clone,
    Checkpoint,
    Rollback { bytes: bool },
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => (any::<i8>(), any::<u8>(), 0u8..4, 0u8..5)
            .prop_map(|(x, y, kind, shape)| Op::AddBody { x, y, kind, shape }),
        4 => (any::<usize>(), 0u8..4, 1u8..8).prop_map(|(pick, kind, size)| Op::AddShape { pick, kind, size }),
        1 => any::<usize>().prop_map(|pick| Op::RemoveBody { pick }),
        1 => any::<usize>().prop_map(|pick| Op::RemoveShape { pick }),
        2 => (any::<usize>(), any::<i8>(), any::<i8>()).prop_map(|(pick, ix, iy)| Op::Impulse { pick, ix, iy }),
        5 => (1u8..25).prop_map(|n| Op::Step { n }),
        1 => Just(Op::SaveLoad),
        1 => Just(Op::Clone),
        1 => Just(Op::Checkpoint),
        1 => any::<bool>().prop_map(|bytes| Op::Rollback { bytes }),
    ]
}

fn dt() -> Real {
    Real::ONE / Real::from_int(60)
}

fn model_world() -> Space {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(w.add_body(Body::new_static()));
    ok(w.add_shape(ok(ok(Shape::segment_shape_new(
        ground,
        Vect::from_ints(-40, 0),
        Vect::from_ints(40, 0),
        Real::HALF,
    ))
    .with_material(Real::ONE, Real::ZERO))));
    w
}

fn nth_body(w: &Space, pick: usize) -> Option<BodyHandle> {
    let n = w.bodies().count();
    (n > 0).then(|| w.bodies().nth(pick % n).map(|(h, _)| h))?
}

fn nth_shape(w: &Space, pick: usize) -> Option<ShapeHandle> {
    let n = w.shapes().count();
    (n > 0).then(|| w.shapes().nth(pick % n).map(|(h, _)| h))?
}

/// Adds a shape of `kind` (circle, box, segment, hexagon; other: none) and
/// size `size / 4` with density 1 to body `h`.
fn add_shape(w: &mut Space, h: BodyHandle, kind: u8, size: u8) -> Option<ShapeHandle> {
    let r = Real::from_int(i32::from(size)) / Real::from_int(4);
    let shape = match kind {
        0 => Shape::circle_shape_new(h, r, Vect::ZERO),
        1 => Shape::box_shape_new(h, r * Real::TWO, r, Real::ZERO),
        2 => Shape::segment_shape_new(h, Vect::new(-r, Real::ZERO), Vect::new(r, r), Real::DELTA),
        3 => {
            let pts: Vec<Vect> = [(2, 0), (1, 2), (-1, 2), (-2, 0), (-1, -2), (1, -2)]
                .iter()
                .map(|&(x, y)| Vect::from_ints(x, y) * (r / Real::TWO))
                .collect();
            Shape::poly_shape_new(h, &pts, &Transform::IDENTITY, Real::ZERO)
        }
        _ => return None,
    };
    let mut shape = ok(shape);
    ok(shape.set_density(Real::ONE));
    w.add_shape(shape).ok()
}

/// Whether `w` can step: no dynamic body without mass.
fn can_step(w: &Space) -> bool {
    w.bodies().all(|(_, b)| b.can_step())
}

/// Applies a world edit (not the snapshot operations) to `w`.
fn apply(w: &mut Space, op: &Op) -> Option<String> {
    match *op {
        Op::AddBody { x, y, kind, shape } => {
            let mut b = match kind {
                0 => ok(Body::new(Real::ZERO, Real::ZERO)),
                1 => Body::new_static(),
                2 => Body::new_kinematic(),
                _ => ok(Body::new(Real::TWO, Real::from_int(3))),
            };
            // Near the ground and each other, so that bodies collide.
            b.set_position(Vect::from_ints(i32::from(x) / 16, i32::from(y % 4) + 1));
            b.set_angle(Real::from_int(i32::from(x)) / Real::from_int(50));
            // Half the dynamic bodies of explicit mass are bullets.
            b.set_bullet(kind == 3 && x % 2 == 0);
            let h = w.add_body(b).ok()?;
            let s = add_shape(w, h, shape, 2 + y % 4);
            Some(format!("{h:?} {s:?}"))
        }
        Op::AddShape { pick, kind, size } => {
            let h = nth_body(w, pick)?;
            add_shape(w, h, kind, size).map(|s| format!("{s:?}"))
        }
        Op::RemoveBody { pick } => {
            let h = nth_body(w, pick)?;
            w.remove_body(h).ok().map(|_| format!("{h:?}"))
        }
        Op::RemoveShape { pick } => {
            let h = nth_shape(w, pick)?;
            w.remove_shape(h).ok().map(|_| format!("{h:?}"))
        }
        Op::Impulse { pick, ix, iy } => {
            let h = nth_body(w, pick)?;
            let b = w.body_mut(h)?;
            let at = b.position() + Vect::from_ints(0, 1);
            b.apply_impulse_at_world_point(Vect::from_ints(i32::from(ix), i32::from(iy)), at);
            None
        }
        Op::Step { n } => {
            for _ in 0..n {
                // Refused (both worlds alike) while a script leaves a
                // dynamic body without mass.
                if let Err(e) = w.step(dt()) {
                    return Some(format!("{e}"));
                }
            }
            None
        }
        Op::SaveLoad | Op::Clone | Op::Checkpoint | Op::Rollback { .. } => None,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// World `a` only ever edits and steps (and rolls back in memory);
    /// world `b` also goes through bytes, clones and in-place rollbacks by
    /// bytes after diverging. After every operation both are equal and
    /// valid, and hand out the same handles.
    #[test]
    fn scripts_stay_in_lockstep_through_save_load_clone_and_restore(
        ops in prop::collection::vec(op(), 1..60)
    ) {
        let mut a = model_world();
        let mut b = model_world();
        let mut checkpoint: Option<(WorldState, Vec<u8>)> = None;
        for (i, op) in ops.iter().enumerate() {
            // A script may leave a dynamic body without mass (its shape may
            // come later): such a world cannot step, so it does not validate
            // and its bytes do not load.
            let steppable = can_step(&a);
            match op {
                Op::SaveLoad => match snapshot::load(&save(&b)) {
                    Ok(loaded) => b = loaded,
                    Err(e) => prop_assert!(!steppable, "op {} {:?}: {}", i, op, e),
                },
                Op::Clone => b = b.clone(),
                Op::Checkpoint if steppable => checkpoint = Some((a.state().clone(), save(&b))),
                Op::Checkpoint => {}
                Op::Rollback { bytes } => {
                    if let Some((state, snap)) = &checkpoint {
                        a.restore_state(state);
                        diverge(&mut b, dt());
                        if *bytes {
                            ok(b.load_snapshot(snap));
                        } else {
                            b.restore_state(state);
                        }
                    }
                }
                _ => {
                    let ra = apply(&mut a, op);
                    let rb = apply(&mut b, op);
                    prop_assert_eq!(ra, rb, "op {} {:?}: results", i, op);
                }
            }
            match (can_step(&a), a.validate().and(b.validate())) {
                (true, Err(e)) => return Err(TestCaseError::fail(format!("op {i} {op:?}: {e}"))),
                (false, Ok(())) => {
                    return Err(TestCaseError::fail(format!(
                        "op {i} {op:?}: a world that cannot step validates"
                    )))
                }
                (false, Err(e)) => prop_assert!(e.contains("without mass"), "op {} {:?}: {}", i, op, e),
                (true, Ok(())) => {}
            }
            prop_assert_eq!(a.checksum(), b.checksum(), "op {} {:?}", i, op);
            if let Some(d) = snapshot::first_difference(&a, &b) {
                return Err(TestCaseError::fail(format!("op {i} {op:?}: {d}")));
            }
            prop_assert!(save(&a) == save(&b), "op {} {:?}: bytes", i, op);
        }
    }
}

/// A small world at rest with arbiters, a free slot in each arena and every
/// shape kind: the base of the malformed-input tests.
fn small_world() -> Space {
    let mut w = model_world();
    for (i, kind) in [0u8, 1, 3, 0].into_iter().enumerate() {
        let x = i32::try_from(i).unwrap_or(0) * 4 - 6;
        let mut b = ok(Body::new(Real::ZERO, Real::ZERO));
        b.set_position(Vect::from_ints(x, 1));
        // Two bodies stay awake (live arbiters), the others fall asleep
        // (sleep records and dormant arbiters): both are in the bytes.
        b.set_sleep_allowed(i >= 2);
        let h = ok(w.add_body(b));
        assert!(add_shape(&mut w, h, kind, 4).is_some());
    }
    apply(&mut w, &Op::RemoveBody { pick: 4 });
    apply(&mut w, &Op::Step { n: 100 });
    assert!(w.arbiters().len() >= 2, "resting bodies touch the ground");
    assert!(
        !w.state().dormant_arbiters.is_empty(),
        "sleeping bodies keep their contacts"
    );
    ok(w.validate());
    w
}

fn small_snapshot() -> &'static [u8] {
    static BYTES: OnceLock<Vec<u8>> = OnceLock::new();
    BYTES.get_or_init(|| save(&small_world()))
}

/// A live world that must come out of a failed `load_snapshot` untouched.
fn live_world() -> Space {
    let mut w = build("stack_10").space;
    ok(w.step(dt()));
    w
}

mod diagnosis;
mod format;
mod frame;
mod malformed;
