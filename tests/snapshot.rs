//! Snapshots (`tamias2d::snapshot`): byte round trips continue exactly,
//! the in-memory path likewise, handles survive restores, random scripts of
//! world edits stay in lockstep across save/load/clone/restore, and no
//! malformed input is accepted or panics.
//!
//! Equality is always exact: `save` bytes (which include the checksum) or
//! `first_difference` = `None`. A lockstep engine has no tolerance.
use std::sync::OnceLock;

use proptest::prelude::*;
use tamias2d::body::{Body, BodyHandle};
use tamias2d::scenes::{self, Scene};
use tamias2d::shape::Shape;
use tamias2d::snapshot::{self, SnapshotError, Subject, FORMAT_VERSION, HEADER_LEN, MAGIC};
use tamias2d::space::{ShapeHandle, Space, WorldState};
use tamias2d::{Real, Transform, Vect};

fn build(name: &str) -> Scene {
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
    ok(space.step(dt));
}

/// The round trip of one scene. A reference scene runs `steps` steps. At
/// each fork step `k`:
/// * an in-place fork — a second scene built alongside, so its script
///   (forces, spawns, counters) is at the same step — diverges and is
///   rolled back to the reference by `load_snapshot` (even forks) or
///   `restore_state` (odd forks), then keeps stepping as a scene;
/// * `load(save(reference))` and `reference.clone()` start and step with
///   `Space::step` (no script: a fresh space is not a scene's space).
///
/// After every step each fork must equal its reference byte for byte.
fn round_trip(name: &str, steps: u32, forks: &[u32]) {
    let mut reference = build(name);
    let dt = reference.dt;
    let mut in_place: Vec<(u32, Scene)> = forks.iter().map(|&k| (k, build(name))).collect();
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
        for (i, (k, f)) in in_place.iter_mut().enumerate() {
            if t == *k {
                diverge(&mut f.space, dt);
                assert!(save(&f.space) != bytes, "{name}: diverge changed nothing");
                if i % 2 == 0 {
                    ok(f.space.load_snapshot(&bytes));
                } else {
                    f.space.restore_state(reference.space.state());
                }
                ok(f.space.validate());
            }
            if t >= *k {
                let path = if i % 2 == 0 {
                    "load_snapshot"
                } else {
                    "restore_state"
                };
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
            let loaded = ok(snapshot::load(&bytes));
            assert!(
                save(&loaded) == bytes,
                "{name}: load(save(w)) re-saves differently"
            );
            raw.push((t, loaded, reference.space.clone()));
        }
    }
    ok(reference.space.validate());
    assert_eq!(reference.space.stamp(), u64::from(steps));
}

/// Smallest size of every scene family, with steps and fork points sized
/// for debug builds (step + save of the big ones cost tens of ms there).
const ROUND_TRIPS: &[(&str, u32, &[u32])] = &[
    ("bowl_circles_100", 60, &[0, 25, 50]),
    ("bowl_boxes_100", 60, &[0, 25, 50]),
    ("bowl_hexagons_100", 60, &[0, 25, 50]),
    ("bouncy_circles_500", 20, &[0, 4, 14]),
    ("no_collide", 40, &[0, 10, 30]),
    ("pyramid_20", 16, &[0, 3, 10]),
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
];

#[test]
fn round_trips_cover_every_scene_family() {
    for (name, about) in scenes::list() {
        let family = name.trim_end_matches(|c: char| c.is_ascii_digit() || c == 'x');
        assert!(
            ROUND_TRIPS.iter().any(|(n, _, _)| n.starts_with(family)),
            "{name} ({about}): no scene of its family is round-tripped"
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
    for &(name, steps, forks) in &ROUND_TRIPS[9..] {
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
                ok(w.step(dt()));
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
            match op {
                Op::SaveLoad => b = ok(snapshot::load(&save(&b))),
                Op::Clone => b = b.clone(),
                Op::Checkpoint => checkpoint = Some((a.state().clone(), save(&b))),
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
            if let Err(e) = a.validate().and(b.validate()) {
                return Err(TestCaseError::fail(format!("op {i} {op:?}: {e}")));
            }
            prop_assert_eq!(a.checksum(), b.checksum(), "op {} {:?}", i, op);
            if let Some(d) = snapshot::first_difference(&a, &b) {
                return Err(TestCaseError::fail(format!("op {i} {op:?}: {d}")));
            }
            prop_assert!(save(&a) == save(&b), "op {} {:?}: bytes", i, op);
        }
    }
}

// ---------------------------------------------------------------------------
// Malformed input.

/// A small world at rest with arbiters, a free slot in each arena and every
/// shape kind: the base of the malformed-input tests.
fn small_world() -> Space {
    let mut w = model_world();
    for (i, kind) in [0u8, 1, 3, 0].into_iter().enumerate() {
        let x = i32::try_from(i).unwrap_or(0) * 4 - 6;
        let mut b = ok(Body::new(Real::ZERO, Real::ZERO));
        b.set_position(Vect::from_ints(x, 1));
        let h = ok(w.add_body(b));
        assert!(add_shape(&mut w, h, kind, 4).is_some());
    }
    apply(&mut w, &Op::RemoveBody { pick: 4 });
    apply(&mut w, &Op::Step { n: 55 });
    assert!(w.arbiters().len() >= 2, "resting bodies touch the ground");
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

/// `load` fails with an error `is_expected` accepts; `load_snapshot` fails
/// the same way and leaves a live world byte-identical.
fn expect_error(bytes: &[u8], what: &str, is_expected: impl Fn(&SnapshotError) -> bool) {
    let e = match snapshot::load(bytes) {
        Ok(_) => panic!("{what}: accepted"),
        Err(e) => e,
    };
    assert!(is_expected(&e), "{what}: unexpected error {e:?}");
    let mut live = live_world();
    let before = save(&live);
    assert_eq!(live.load_snapshot(bytes), Err(e), "{what}: load_snapshot");
    assert!(save(&live) == before, "{what}: live world changed");
}

#[test]
fn empty_buffer_and_short_headers_are_too_short() {
    for n in 0..HEADER_LEN {
        let bytes = small_snapshot().get(..n).unwrap_or(&[]);
        expect_error(bytes, "short", |e| *e == SnapshotError::TooShort);
    }
}

#[test]
fn every_truncation_is_an_error() {
    let bytes = small_snapshot();
    let mut live = live_world();
    let before = save(&live);
    for n in 0..bytes.len() {
        let prefix = bytes.get(..n).unwrap_or(&[]);
        let e = snapshot::load(prefix).err();
        match e {
            Some(SnapshotError::TooShort) => assert!(n < HEADER_LEN, "prefix {n}"),
            Some(SnapshotError::Decode(_)) => assert!(n >= HEADER_LEN, "prefix {n}"),
            other => panic!("prefix {n}: {other:?}"),
        }
        assert!(live.load_snapshot(prefix).is_err());
    }
    assert!(save(&live) == before, "live world changed");
    assert!(snapshot::load(bytes).is_ok());
}

#[test]
fn wrong_magic_version_and_trailing_bytes_are_named() {
    let good = small_snapshot();
    let mut bad = good.to_vec();
    bad[0] ^= 0x20;
    expect_error(&bad, "magic", |e| *e == SnapshotError::BadMagic);
    let mut bad = good.to_vec();
    bad[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    expect_error(&bad, "version", |e| {
        *e == SnapshotError::UnsupportedVersion(FORMAT_VERSION + 1)
    });
    let mut bad = good.to_vec();
    bad.extend_from_slice(&[0, 1, 2]);
    expect_error(&bad, "trailing", |e| *e == SnapshotError::TrailingBytes(3));
    let mut bad = good.to_vec();
    bad[12] ^= 1;
    expect_error(&bad, "checksum", |e| {
        matches!(e, SnapshotError::ChecksumMismatch { .. })
    });
    let not_ours = b"PNG\x0d\x0a\x1a\x0a and twenty more bytes".to_vec();
    expect_error(&not_ours, "foreign file", |e| *e == SnapshotError::BadMagic);
}

#[test]
fn a_forged_length_prefix_fails_without_allocating() {
    // The first length in the payload is the body arena's slot count, after
    // the settings (u32 + 2×8 + 3×8 + u32 = 48 bytes).
    let at = HEADER_LEN + 48;
    for len in [1u64 << 62, 1 << 40, 1 << 27, u64::MAX] {
        let mut bad = small_snapshot().to_vec();
        bad[at..at + 8].copy_from_slice(&len.to_le_bytes());
        expect_error(&bad, "forged length", |e| {
            matches!(e, SnapshotError::Decode(_))
        });
    }
}

#[test]
fn every_single_bit_flip_is_an_error() {
    // A small snapshot, every bit: the header fields give their own
    // errors; in the payload a flip breaks decoding, the layout (trailing
    // bytes), the checksum or an invariant.
    let good = small_snapshot();
    let mut bad = good.to_vec();
    for i in 0..good.len() {
        for bit in 0..8 {
            bad[i] ^= 1 << bit;
            let e = snapshot::load(&bad).err();
            let fits = matches!(
                (i, &e),
                (0..8, Some(SnapshotError::BadMagic))
                    | (8..12, Some(SnapshotError::UnsupportedVersion(_)))
                    | (12..20, Some(SnapshotError::ChecksumMismatch { .. }))
                    | (20.., Some(_))
            );
            assert!(fits, "byte {i} bit {bit}: {e:?}");
            bad[i] ^= 1 << bit;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Several flipped bits anywhere: always an error, never a panic.
    #[test]
    fn random_bit_flips_are_errors(
        flips in prop::collection::vec((any::<prop::sample::Index>(), 0u8..8), 1..6)
    ) {
        let good = small_snapshot();
        let mut bad = good.to_vec();
        for (i, bit) in &flips {
            bad[i.index(good.len())] ^= 1 << bit;
        }
        prop_assume!(bad != good);
        prop_assert!(snapshot::load(&bad).is_err());
    }

    /// Bytes overwritten in the payload and the header checksum fixed up,
    /// as a forger would: whatever decodes must either be rejected with a
    /// reason or be a valid world that steps without panicking and stays
    /// valid.
    #[test]
    fn forged_payloads_are_rejected_or_valid(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4)
    ) {
        let good = small_snapshot();
        let mut bad = good.to_vec();
        let payload_len = good.len() - HEADER_LEN;
        for (i, v) in &edits {
            bad[HEADER_LEN + i.index(payload_len)] = *v;
        }
        let sum = snapshot::payload_checksum(&bad[HEADER_LEN..]);
        bad[12..20].copy_from_slice(&sum.to_le_bytes());
        match snapshot::load(&bad) {
            Ok(mut w) => {
                prop_assert!(w.validate().is_ok());
                for _ in 0..3 {
                    prop_assert!(w.step(dt()).is_ok());
                }
                if let Err(e) = w.validate() {
                    return Err(TestCaseError::fail(format!("valid world stepped into: {e}")));
                }
            }
            Err(SnapshotError::Invalid(why)) => prop_assert!(!why.is_empty()),
            Err(SnapshotError::Decode(_) | SnapshotError::TrailingBytes(_)) => {}
            Err(e) => return Err(TestCaseError::fail(format!("unexpected {e:?}"))),
        }
    }
}

/// Snapshot of `state` after `edit` on its JSON form (fields of the state
/// types are private; serde shows them all).
fn tampered(state: &WorldState, edit: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    let mut json = ok(serde_json::to_value(state));
    edit(&mut json);
    let back: WorldState = ok(serde_json::from_value(json));
    snapshot::save_state(&back)
}

/// Indices of the first live body slot of each type, and a live shape slot
/// of each geometry kind, in the JSON form.
fn live_slot(
    json: &serde_json::Value,
    arena: &str,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> usize {
    json[arena]["slots"]
        .as_array()
        .and_then(|slots| {
            slots
                .iter()
                .position(|s| !s["value"].is_null() && pred(&s["value"]))
        })
        .unwrap_or_else(|| panic!("no such slot in {arena}"))
}

fn bump(v: &mut serde_json::Value, by: i64) {
    *v = serde_json::json!(v.as_i64().unwrap_or(0).wrapping_add(by));
}

const ONE: i64 = 1 << 32;

#[test]
fn inconsistent_snapshots_are_invalid_and_say_why() {
    let world = small_world();
    let state = world.state();
    assert!(snapshot::save_state(state) == save(&world));
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let dynamic = |j: &serde_json::Value| j["body_type"] == "Dynamic";
    let is_static = |j: &serde_json::Value| j["body_type"] == "Static";
    let poly = |j: &serde_json::Value| j["geometry"].get("Poly").is_some();
    let circle = |j: &serde_json::Value| j["geometry"].get("Circle").is_some();
    let segment = |j: &serde_json::Value| j["geometry"].get("Segment").is_some();
    let body = move |j: &mut serde_json::Value, f: &dyn Fn(&mut serde_json::Value)| {
        let i = live_slot(j, "bodies", dynamic);
        f(&mut j["bodies"]["slots"][i]["value"]);
    };
    let shape = |j: &mut serde_json::Value,
                 kind: &dyn Fn(&serde_json::Value) -> bool,
                 f: &dyn Fn(&mut serde_json::Value)| {
        let i = live_slot(j, "shapes", kind);
        f(&mut j["shapes"]["slots"][i]["value"]);
    };
    let cases: Vec<(&str, &str, Edit)> = vec![
        (
            "dangling body handle",
            "names missing body",
            Box::new(move |j| {
                shape(j, &circle, &|s| bump(&mut s["body"]["generation"], 1));
            }),
        ),
        (
            "shape body past the arena",
            "names missing body",
            Box::new(move |j| {
                shape(j, &poly, &|s| s["body"]["index"] = serde_json::json!(999));
            }),
        ),
        (
            "free list names a live slot",
            "free list names live slot",
            Box::new(|j| {
                if let Some(f) = j["bodies"]["free"].as_array_mut() {
                    f.push(serde_json::json!(0));
                }
            }),
        ),
        (
            "free list past the end",
            "past the end",
            Box::new(|j| {
                j["shapes"]["free"][0] = serde_json::json!(77);
            }),
        ),
        (
            "arena length",
            "arena length",
            Box::new(|j| bump(&mut j["bodies"]["len"], 1)),
        ),
        (
            "non-unit rotation",
            "rotation",
            Box::new(move |j| {
                body(j, &|b| b["rot"]["c"] = serde_json::json!(2 * ONE));
            }),
        ),
        (
            "negative mass",
            "mass must be ≥ 0",
            Box::new(move |j| {
                body(j, &|b| b["mass"] = serde_json::json!(-ONE));
            }),
        ),
        (
            "negative moment",
            "moment must be ≥ 0",
            Box::new(move |j| {
                body(j, &|b| b["moment"] = serde_json::json!(-ONE));
            }),
        ),
        (
            "inverse mass",
            "inverse mass",
            Box::new(move |j| {
                body(j, &|b| bump(&mut b["mass_inv"], 1));
            }),
        ),
        (
            "inverse moment",
            "inverse moment",
            Box::new(move |j| {
                body(j, &|b| bump(&mut b["moment_inv"], -1));
            }),
        ),
        (
            "static body with mass",
            "static body with a mass",
            Box::new(move |j| {
                let i = live_slot(j, "bodies", is_static);
                j["bodies"]["slots"][i]["value"]["mass"] = serde_json::json!(ONE);
            }),
        ),
        (
            "polygon of 2 vertices",
            "polygon has 2 vertices",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    s["geometry"]["Poly"]["count"] = serde_json::json!(2)
                });
            }),
        ),
        (
            "polygon of 9 vertices",
            "polygon has 9 vertices",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    s["geometry"]["Poly"]["count"] = serde_json::json!(9)
                });
            }),
        ),
        (
            "clockwise polygon",
            "not convex",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    let p = &mut s["geometry"]["Poly"];
                    let n = usize::try_from(p["count"].as_u64().unwrap_or(0)).unwrap_or(0);
                    if let Some(v) = p["verts"].as_array_mut() {
                        v[..n].reverse();
                    }
                });
            }),
        ),
        (
            "polygon normal",
            "normals",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    bump(&mut s["geometry"]["Poly"]["normals"][1]["x"], 1)
                });
            }),
        ),
        (
            "polygon unused entry",
            "unused entries",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    bump(&mut s["geometry"]["Poly"]["verts"][7]["y"], 1)
                });
            }),
        ),
        (
            "negative circle radius",
            "negative radius",
            Box::new(move |j| {
                shape(j, &circle, &|s| {
                    s["geometry"]["Circle"]["radius"] = serde_json::json!(-1)
                });
            }),
        ),
        (
            "segment normal",
            "segment normal",
            Box::new(move |j| {
                shape(j, &segment, &|s| {
                    bump(&mut s["geometry"]["Segment"]["normal"]["y"], -1)
                });
            }),
        ),
        (
            "negative density",
            "negative mass or density",
            Box::new(move |j| {
                shape(j, &circle, &|s| {
                    s["mass_spec"] = serde_json::json!({"Density": -ONE})
                });
            }),
        ),
        (
            "settings",
            "collision bias",
            Box::new(|j| {
                j["settings"]["collision_bias"] = serde_json::json!(2 * ONE);
            }),
        ),
        (
            "stamp without dt",
            "stamp 0",
            Box::new(|j| j["stamp"] = serde_json::json!(0)),
        ),
        (
            "negative dt",
            "current dt",
            Box::new(|j| j["current_dt"] = serde_json::json!(-1)),
        ),
        (
            "arbiter stamp in the future",
            "outside 1..=",
            Box::new(|j| {
                bump(&mut j["arbiters"][0]["stamp"], 1);
            }),
        ),
        (
            "arbiter order",
            "canonical order",
            Box::new(|j| {
                if let Some(a) = j["arbiters"].as_array_mut() {
                    a.swap(0, 1);
                }
            }),
        ),
        (
            "arbiter with no contacts",
            "0 contacts",
            Box::new(|j| {
                j["arbiters"][0]["count"] = serde_json::json!(0);
            }),
        ),
        (
            "arbiter with 3 contacts",
            "too many contacts",
            Box::new(|j| {
                j["arbiters"][0]["count"] = serde_json::json!(3);
            }),
        ),
        (
            "arbiter state",
            "FirstCollision",
            Box::new(|j| {
                j["arbiters"][0]["state"] = serde_json::json!("FirstCollision");
            }),
        ),
        (
            "cached arbiter that touched",
            "Cached",
            Box::new(|j| {
                j["arbiters"][0]["state"] = serde_json::json!("Cached");
            }),
        ),
        (
            "arbiter body",
            "bodies do not match",
            Box::new(|j| {
                let b = j["arbiters"][0]["body_b"].clone();
                j["arbiters"][0]["body_a"] = b;
            }),
        ),
        (
            "arbiter shape generation",
            "missing shape",
            Box::new(|j| {
                bump(&mut j["arbiters"][0]["shape_b"]["generation"], 1);
            }),
        ),
        (
            "negative normal impulse",
            "normal impulse",
            Box::new(|j| {
                j["arbiters"][0]["contacts"][0]["jn_acc"] = serde_json::json!(-1);
            }),
        ),
    ];
    for (what, expected, edit) in cases {
        let bytes = tampered(state, |j| edit(j));
        expect_error(
            &bytes,
            what,
            |e| matches!(e, SnapshotError::Invalid(why) if why.contains(expected)),
        );
    }
}

#[test]
fn an_arbiter_naming_a_removed_shape_is_invalid() {
    let world = small_world();
    let mut state = world.state().clone();
    let (sa, _) = world.arbiters()[0].shapes();
    assert!(state.shapes.remove(sa).is_some());
    expect_error(
        &snapshot::save_state(&state),
        "removed shape",
        |e| matches!(e, SnapshotError::Invalid(why) if why.contains("missing shape")),
    );
}

// ---------------------------------------------------------------------------
// Format, header, buffers, errors.

#[test]
fn format_layout_is_pinned() {
    // A change here means the byte layout changed: bump FORMAT_VERSION and
    // update the pins (and say so in the commit message).
    let empty = save(&Space::new());
    assert_eq!(&empty[..8], &MAGIC);
    assert_eq!(&empty[8..12], &FORMAT_VERSION.to_le_bytes());
    let sum = snapshot::payload_checksum(&empty[HEADER_LEN..]);
    assert_eq!(&empty[12..20], &sum.to_le_bytes());
    assert_eq!(FORMAT_VERSION, 1);
    // The empty world, field by field (little-endian, fixed-width ints,
    // every Real as its raw i64, lengths as u64, enum tags as u32).
    let expected = [
        "0a000000",         // settings.iterations: 10
        "0000000000000000", // gravity.x
        "0000000000000000", // gravity.y
        "0000000001000000", // damping: 1.0 = 2^32
        "9a99991900000000", // collision_slop: 0.1
        "d3c4750000000000", // collision_bias: 0.9^60
        "03000000",         // collision_persistence: 3
        "0000000000000000", // bodies.slots: length 0
        "0000000000000000", // bodies.free: length 0
        "00000000",         // bodies.len: 0
        "0000000000000000", // shapes.slots
        "0000000000000000", // shapes.free
        "00000000",         // shapes.len
        "0000000000000000", // arbiters: length 0
        "0000000000000000", // stamp
        "0000000000000000", // current_dt
        "0000000000000000", // prev_dt
    ]
    .concat();
    assert_eq!(hex(&empty[HEADER_LEN..]), expected);
    // Encoded sizes per object: layout only (fixed-width encoding makes
    // them independent of the values).
    let mut w = Space::new();
    let mut sizes = vec![save(&w).len()];
    let mut grow = |w: &Space| {
        sizes.push(save(w).len());
    };
    let b = ok(w.add_body(Body::new_static()));
    grow(&w);
    ok(w.add_shape(ok(Shape::circle_shape_new(b, Real::ONE, Vect::ZERO))));
    grow(&w);
    ok(w.add_shape(ok(Shape::segment_shape_new(
        b,
        Vect::ZERO,
        Vect::from_ints(1, 0),
        Real::ZERO,
    ))));
    grow(&w);
    ok(w.add_shape(ok(Shape::box_shape_new(
        b,
        Real::ONE,
        Real::ONE,
        Real::ZERO,
    ))));
    grow(&w);
    ok(w.remove_body(b));
    grow(&w);
    let per_object: Vec<usize> = sizes.windows(2).map(|p| p[1].wrapping_sub(p[0])).collect();
    // A slot is its generation (4) and option tag (1) before the value:
    // body 165; shape 65 + geometry (circle 24, segment 88, polygon 265:
    // 8 inline vertices and normals). Removing the body and its 3 shapes
    // leaves 4 empty slots (5 bytes each) and 4 free-list entries (u32).
    assert_eq!(per_object[..4], [170, 94, 158, 335]);
    let removed = [170, 94, 158, 335].iter().map(|n| n - 5 - 4).sum::<usize>();
    assert_eq!(per_object[4], 0usize.wrapping_sub(removed));
    let stepped = small_world();
    let mut state = stepped.state().clone();
    let n = state.arbiters.len();
    state.arbiters.clear();
    let per_arbiter = (save(&stepped).len() - snapshot::save_state(&state).len()) / n;
    assert_eq!(per_arbiter, 218, "bytes per arbiter");
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn header_carries_version_and_payload_checksum() {
    let bytes = save(&small_world());
    let h = ok(snapshot::header(&bytes));
    assert_eq!(h.version, FORMAT_VERSION);
    assert_eq!(h.checksum, snapshot::payload_checksum(&bytes[HEADER_LEN..]));
}

#[test]
fn payload_checksum_is_pinned() {
    // Portable: the same values on every target (little-endian words).
    let ramp: Vec<u8> = (0..=100u8).collect();
    let sums = [0, 1, 7, 8, 31, 32, 33, 101].map(|n| snapshot::payload_checksum(&ramp[..n]));
    assert_eq!(
        sums,
        [
            12947730245408373148,
            14436479948233033896,
            12207078565629506267,
            18319719879261837459,
            15647855223621101133,
            12391200441337584545,
            7315989894677512464,
            12340533633619164456,
        ]
    );
    assert_eq!(
        sums.iter().collect::<std::collections::BTreeSet<_>>().len(),
        8
    );
}

#[test]
fn save_into_reuses_the_buffer_and_matches_save() {
    let mut scene = build("stack_10");
    let mut buf = Vec::new();
    let mut capacity = 0;
    for _ in 0..5 {
        ok(scene.step());
        let n = snapshot::save_into(&scene.space, &mut buf);
        assert_eq!(n, buf.len());
        assert!(buf == save(&scene.space));
        if capacity > 0 {
            assert_eq!(buf.capacity(), capacity, "no reallocation at the same size");
        }
        capacity = buf.capacity();
    }
}

#[test]
fn errors_display_what_is_wrong() {
    let all = [
        SnapshotError::TooShort,
        SnapshotError::BadMagic,
        SnapshotError::UnsupportedVersion(9),
        SnapshotError::Decode("unexpected end".into()),
        SnapshotError::TrailingBytes(3),
        SnapshotError::ChecksumMismatch {
            stored: 1,
            computed: 2,
        },
        SnapshotError::Invalid("body #1v0: mass must be ≥ 0".into()),
    ];
    for e in all {
        let shown = e.to_string();
        let boxed: Box<dyn std::error::Error> = Box::new(e);
        assert_eq!(boxed.to_string(), shown);
        assert!(shown.len() > 10, "{shown}");
    }
    assert!(SnapshotError::UnsupportedVersion(9)
        .to_string()
        .contains('9'));
    assert!(SnapshotError::TrailingBytes(3).to_string().contains('3'));
}

// ---------------------------------------------------------------------------
// Desync diagnosis.

#[test]
fn equal_worlds_have_equal_parts_and_no_difference() {
    let w = small_world();
    let c = ok(snapshot::load(&save(&w)));
    assert_eq!(snapshot::first_difference(&w, &c), None);
    let (pa, pb) = (snapshot::checksum_parts(&w), snapshot::checksum_parts(&c));
    assert_eq!(pa, pb);
    assert_eq!(pa.first_mismatch(&pb), None);
    assert_eq!(pa.bodies.len(), w.bodies().count());
    assert_eq!(pa.shapes.len(), w.shapes().count());
}

#[test]
fn first_difference_names_the_body_and_field() {
    let w = small_world();
    let mut c = w.clone();
    let h = nth_body(&c, 2).unwrap_or_else(|| panic!("a body"));
    if let Some(b) = c.body_mut(h) {
        b.set_angular_velocity(b.angular_velocity() + Real::DELTA);
    }
    let d = snapshot::first_difference(&w, &c).unwrap_or_else(|| panic!("a difference"));
    assert_eq!((d.subject, d.field), (Subject::Body(h), "w"));
    assert!(
        d.to_string().contains("body") && d.to_string().contains(" w "),
        "{d}"
    );
    let (pa, pb) = (snapshot::checksum_parts(&w), snapshot::checksum_parts(&c));
    assert_eq!(pa.first_mismatch(&pb), Some(Subject::Body(h)));
    assert_eq!(pa.settings, pb.settings);
    assert_eq!(pa.shapes, pb.shapes);
}

#[test]
fn first_difference_names_settings_shapes_arbiters_and_counters() {
    let w = small_world();
    let mut c = w.clone();
    c.set_iterations(11);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Settings, "iterations"))
    );

    let mut c = w.clone();
    let s = nth_shape(&c, 1).unwrap_or_else(|| panic!("a shape"));
    ok(c.modify_shape(s, |x| {
        x.collision_type = 9;
        Ok(())
    }));
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Shape(s), "collision_type"))
    );
    let pa = snapshot::checksum_parts(&w);
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Shape(s))
    );

    let mut state = w.state().clone();
    state.arbiters[1].friction += Real::DELTA;
    let c = Space::from_state(state);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Arbiter(1), "friction"))
    );
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Arbiters)
    );

    let mut state = w.state().clone();
    state.prev_dt += Real::DELTA;
    let c = Space::from_state(state);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Counters, "prev_dt"))
    );
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Counters)
    );
}

#[test]
fn first_difference_names_presence_and_free_lists() {
    let w = small_world();
    let mut c = w.clone();
    let added = ok(c.add_body(Body::new_static()));
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Body(added), "presence"))
    );

    // Same live bodies, free slots pushed in another order.
    let mut a = w.clone();
    let mut b = w.clone();
    let x = ok(a.add_body(Body::new_static()));
    let y = ok(a.add_body(Body::new_static()));
    assert_eq!(
        (x, y),
        (
            ok(b.add_body(Body::new_static())),
            ok(b.add_body(Body::new_static()))
        )
    );
    ok(a.remove_body(x));
    ok(a.remove_body(y));
    ok(b.remove_body(y));
    ok(b.remove_body(x));
    let d = snapshot::first_difference(&a, &b);
    assert_eq!(d.map(|d| d.subject), Some(Subject::BodyArena));
    let pa = snapshot::checksum_parts(&a);
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&b)),
        Some(Subject::BodyArena)
    );
    assert_ne!(a.checksum(), b.checksum());
}

#[test]
fn first_difference_finds_a_desync_after_steps() {
    // The desync workflow: two peers step; one gets a one-ulp different
    // input; the first difference names the body it was applied to.
    let mut a = build("pyramid_20");
    let mut b = build("pyramid_20");
    ok(a.step_n(3));
    ok(b.step_n(3));
    let top = *b.bodies().last().unwrap_or_else(|| panic!("a body"));
    if let Some(body) = b.space.body_mut(top) {
        body.set_velocity(body.velocity() + Vect::new(Real::DELTA, Real::ZERO));
    }
    let d = snapshot::first_difference(&a.space, &b.space).map(|d| d.subject);
    assert_eq!(d, Some(Subject::Body(top)));
    ok(a.step());
    ok(b.step());
    assert_ne!(a.space.checksum(), b.space.checksum());
    assert!(snapshot::first_difference(&a.space, &b.space).is_some());
}
