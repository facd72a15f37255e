//! Frame snapshots (`Space::save_frame` / `restore_frame`, the bytes of
//! `snapshot::save_frame_into` / `Space::load_frame_snapshot`): the level
//! is named by its digest, a frame of another level is refused with the
//! world untouched, malformed frame bytes are errors, and a frame costs
//! what the moving part of the world holds, whatever the level's size.
//! (Continuing after a frame restore equals the straight run for every
//! scene: `round_trip` in `main.rs`.)
use super::*;

/// A level of `segments` static segments in one row, one box resting on it.
fn level_world(segments: i32) -> Space {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(w.add_body(Body::new_static()));
    for i in 0..segments {
        let x = i - segments / 2;
        ok(w.add_shape(ok(Shape::segment_shape_new(
            ground,
            Vect::from_ints(x, 0),
            Vect::from_ints(x + 1, 0),
            Real::ZERO,
        ))));
    }
    let b = ok(w.add_body(ok(Body::new(Real::ONE, Real::ONE))));
    ok(w.body_mut(b).ok_or("box")).set_position(Vect::new(Real::ZERO, Real::HALF));
    ok(w.add_shape(ok(ok(Shape::box_shape_new(
        b,
        Real::ONE,
        Real::ONE,
        Real::ZERO,
    ))
    .with_material(Real::ONE, Real::ZERO))));
    for _ in 0..30 {
        ok(w.step(dt()));
    }
    w
}

#[test]
fn a_frame_holds_the_moving_part_only() {
    let small = level_world(10);
    let big = level_world(3_000);
    let (a, b) = (snapshot::save_frame(&small), snapshot::save_frame(&big));
    assert!(!small.arbiters().is_empty(), "the box rests on the level");
    // The same moving part; the level's slots are not in the bytes. Only
    // numbers that count or name level slots grow with it: the parts' slot
    // counts and lengths, and the handle of the segment under the box, each
    // written in as few bytes as its value needs (11 → 1 byte, 3,001 → 2).
    assert!(
        b.len().abs_diff(a.len()) <= 8,
        "frame size depends on the level: {} vs {} bytes",
        a.len(),
        b.len()
    );
    // The goal for one moving box on a big level: ≤ 2 KB.
    eprintln!(
        "one box on 3,000 segments: frame {} bytes, full snapshot {}",
        b.len(),
        snapshot::save(&big).len()
    );
    assert!(b.len() <= 2048, "{} bytes", b.len());
    assert!(snapshot::save(&big).len() > 100 * b.len());
    let mut f = FrameState::default();
    big.save_frame(&mut f);
    assert_eq!(f.body_slots(), 1, "only the box's slot");
    assert_eq!(f.checksum(), big.checksum());
    assert_ne!(small.level_digest(), big.level_digest());
}

#[test]
fn a_frame_of_another_level_is_refused_and_the_world_untouched() {
    let mut w = level_world(10);
    let mut other = level_world(11);
    let mut f = FrameState::default();
    w.save_frame(&mut f);
    let bytes = snapshot::save_frame(&w);
    let before = save(&other);
    let e = other.restore_frame(&f);
    assert!(
        matches!(e, Err(SpaceError::LevelMismatch { frame, world })
            if frame == w.level_digest() && world == other.level_digest()),
        "{e:?}"
    );
    let e = other.load_frame_snapshot(&bytes);
    match &e {
        Err(SnapshotError::LevelMismatch { .. }) => {
            assert!(e
                .as_ref()
                .err()
                .is_some_and(|e| e.to_string().contains("another level")));
        }
        _ => panic!("{e:?}"),
    }
    assert!(save(&other) == before, "a refused frame changed the world");
    // The right world takes it.
    ok(w.step(dt()));
    ok(w.load_frame_snapshot(&bytes));
    ok(w.restore_frame(&f));
    ok(w.validate());
}

#[test]
fn a_level_change_refuses_older_frames_until_undone() {
    let mut w = level_world(10);
    let mut f = FrameState::default();
    w.save_frame(&mut f);
    let reference = save(&w);
    let (seg, _) = ok(w
        .shapes()
        .find(|(_, s)| w.body(s.body()).is_some_and(|b| !b.is_dynamic()))
        .ok_or("a level segment"));
    let digest = w.level_digest();
    let friction = ok(w.shape(seg).ok_or("segment")).material.friction;
    // Reshape a level segment: the digest changes, old frames are refused.
    ok(w.modify_shape(seg, |s| {
        s.material.friction = Real::HALF;
        Ok(())
    }));
    assert_ne!(w.level_digest(), digest);
    assert!(matches!(
        w.restore_frame(&f),
        Err(SpaceError::LevelMismatch { .. })
    ));
    // Undone, the level has its digest again and the frame restores to the
    // saved world exactly.
    ok(w.modify_shape(seg, |s| {
        s.material.friction = friction;
        Ok(())
    }));
    assert_eq!(w.level_digest(), digest);
    ok(w.step(dt()));
    ok(w.restore_frame(&f));
    assert!(save(&w) == reference, "restore after undo differs");
}

#[test]
fn the_level_digest_follows_every_change_of_the_level() {
    let mut w = level_world(10);
    let fresh = |w: &Space| Space::from_state(w.state().clone()).level_digest();
    // A body that touches nothing (replacing a touching body in place
    // would leave its arbiters to a static pair: not what this tests).
    let box_h = ok(w.add_body(ok(Body::new(Real::ONE, Real::ONE))));
    ok(w.add_shape(ok(Shape::circle_shape_new(box_h, Real::HALF, Vect::ZERO))));
    ok(w.body_mut(box_h).ok_or("box")).set_position(Vect::from_ints(3, 30));
    ok(w.step(dt()));
    let d0 = w.level_digest();
    // Moving a dynamic body is not a level change.
    ok(w.body_mut(box_h).ok_or("box")).set_position(Vect::from_ints(3, 30));
    assert_eq!(w.level_digest(), d0);
    // A dynamic body replaced in place by a static one is (its shape joins
    // the level: the step's check under the `validate` feature asserts
    // that its cache entry became static).
    let mut s = Body::new_static();
    s.set_position(Vect::from_ints(3, 30));
    *ok(w.body_mut(box_h).ok_or("box")) = s;
    assert_ne!(w.level_digest(), d0);
    assert_eq!(w.level_digest(), fresh(&w));
    ok(w.step(dt()));
    assert_eq!(w.level_digest(), fresh(&w));
    // Adding a static body, removing it again (other generations).
    let d1 = w.level_digest();
    let extra = ok(w.add_body(Body::new_static()));
    assert_ne!(w.level_digest(), d1);
    ok(w.remove_body(extra));
    assert_eq!(w.level_digest(), fresh(&w));
    // The world checksum sees the level through the digest.
    let c = w.checksum();
    let ground = ok(w
        .bodies()
        .find(|(_, b)| !b.is_dynamic())
        .map(|(h, _)| h)
        .ok_or("ground"));
    ok(w.body_mut(ground).ok_or("ground")).set_position(Vect::from_ints(0, 1));
    assert_ne!(w.checksum(), c);
    assert_eq!(w.level_digest(), fresh(&w));
}

/// Frame bytes with the header's payload checksum recomputed, so that a
/// damaged payload reaches decoding and validation.
fn resealed(mut bytes: Vec<u8>) -> Vec<u8> {
    let sum = snapshot::payload_checksum(bytes.get(HEADER_LEN..).unwrap_or(&[]));
    if let Some(h) = bytes.get_mut(12..20) {
        h.copy_from_slice(&sum.to_le_bytes());
    }
    bytes
}

#[test]
fn damaged_frames_are_errors_or_valid_worlds_and_never_touch_the_world_on_error() {
    let source = small_world();
    let bytes = snapshot::save_frame(&source);
    let mut live = source.clone();
    ok(live.step(dt()));
    let before = save(&live);
    let mut accepted = 0u32;
    let mut refused = 0u32;
    let mut check = |damaged: &[u8]| {
        let mut w = live.clone();
        match w.load_frame_snapshot(damaged) {
            Ok(()) => {
                accepted += 1;
                if let Err(e) = w.validate() {
                    panic!("an invalid frame was accepted: {e}");
                }
                for _ in 0..2 {
                    let _ = w.step(dt());
                }
            }
            Err(e) => {
                refused += 1;
                assert!(!e.to_string().is_empty());
                assert!(
                    save(&w) == before,
                    "a failed frame load changed the world: {e}"
                );
            }
        }
    };
    for len in 0..bytes.len() {
        check(bytes.get(..len).unwrap_or(&[]));
    }
    for i in 0..bytes.len() {
        for bit in [0u8, 3, 7] {
            let mut b = bytes.clone();
            if let Some(x) = b.get_mut(i) {
                *x ^= 1 << bit;
            }
            // Unsealed: the header checksum catches it (or the header does).
            let mut w = live.clone();
            assert!(w.load_frame_snapshot(&b).is_err(), "flip at {i} accepted");
            check(&resealed(b));
        }
    }
    assert!(
        refused > 0 && accepted > 0,
        "{refused} refused, {accepted} accepted"
    );
}

#[test]
fn queries_stay_on_the_broadphase_and_agree_after_a_frame_restore() {
    let mut w = level_world(50);
    let extra = ok(w.add_body(ok(Body::new(Real::ZERO, Real::ZERO))));
    ok(w.body_mut(extra).ok_or("extra")).set_position(Vect::from_ints(2, 3));
    let mut circle = ok(ok(Shape::circle_shape_new(extra, Real::HALF, Vect::ZERO))
        .with_material(Real::ONE, Real::ZERO));
    ok(circle.set_density(Real::ONE));
    ok(w.add_shape(circle));
    ok(w.step(dt()));
    let mut f = FrameState::default();
    w.save_frame(&mut f);
    let bytes = snapshot::save_frame(&w);
    let reference = save(&w);
    // Diverge: the extra body goes, another comes.
    ok(w.remove_body(extra));
    let other = ok(w.add_body(ok(Body::new(Real::ONE, Real::ONE))));
    ok(w.add_shape(ok(Shape::circle_shape_new(other, Real::ONE, Vect::ZERO))));
    ok(w.step(dt()));
    for path in 0..2 {
        if path == 0 {
            ok(w.restore_frame(&f));
        } else {
            ok(w.load_frame_snapshot(&bytes));
        }
        assert!(save(&w) == reference);
        assert!(
            w.queries_use_broadphase(),
            "path {path}: queries scan everything"
        );
        // The same answers as a scan of every shape (a fresh space scans).
        let scan = Space::from_state(w.state().clone());
        assert!(!scan.queries_use_broadphase());
        for x in -5..5 {
            let (a, b) = (Vect::from_ints(x, 5), Vect::from_ints(x + 1, -1));
            let got: Vec<_> = w
                .segment_query(a, b, Real::ZERO, tamias2d::shape::ShapeFilter::ALL)
                .into_iter()
                .map(|(h, info)| (h, info.alpha))
                .collect();
            let want: Vec<_> = scan
                .segment_query(a, b, Real::ZERO, tamias2d::shape::ShapeFilter::ALL)
                .into_iter()
                .map(|(h, info)| (h, info.alpha))
                .collect();
            assert_eq!(got, want, "path {path}, ray at x = {x}");
        }
        // The per-body shape lists are right: a shape added now sums the
        // body's mass from both of its shapes.
        let mut v = w.clone();
        let mut s = ok(Shape::circle_shape_new(
            extra,
            Real::HALF,
            Vect::from_ints(1, 0),
        ));
        ok(s.set_density(Real::ONE));
        ok(w.add_shape(s.clone()));
        ok(v.add_shape(s));
        let (m1, m2) = (
            ok(w.body(extra).ok_or("extra")).mass(),
            ok(v.body(extra).ok_or("extra")).mass(),
        );
        assert_eq!(m1, m2);
        ok(w.restore_frame(&f));
    }
}

#[test]
fn a_frame_restore_rebuilds_nothing_of_the_level() {
    let mut w = level_world(200);
    let mut f = FrameState::default();
    w.save_frame(&mut f);
    let bytes = snapshot::save_frame(&w);
    let builds = w.static_tree_builds();
    for _ in 0..5 {
        ok(w.step(dt()));
        ok(w.restore_frame(&f));
        ok(w.step(dt()));
        ok(w.load_frame_snapshot(&bytes));
    }
    ok(w.step(dt()));
    assert_eq!(
        w.static_tree_builds(),
        builds,
        "a frame restore rebuilt the static tree"
    );
    // A full restore checks the static boxes (the level may differ) but
    // rebuilds only when they changed.
    let state = w.state().clone();
    w.restore_state(&state);
    ok(w.step(dt()));
    assert_eq!(w.static_tree_builds(), builds);
}
