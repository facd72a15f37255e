//! Limits for untrusted bytes: every loading path (full snapshots, frames,
//! replays) refuses input over `Limits` with an error naming the limit and
//! the value, and leaves the live world untouched; `Limits::TRUSTED` lifts
//! them; a step whose broadphase finds more candidate pairs than the limit
//! stops with an error instead of running for seconds (a frame's candidate
//! pairs are left to that check: counting them at every frame load would
//! add about 40% to it).
//!
//! The forged inputs are the ones that froze a receiver before limits
//! existed: settings of 1,024 iterations × 64 sub-steps (1.7–2.6 s per
//! step), and circles piled within millimetres of each other (millions of
//! candidate pairs, seconds per step). Their worst step times under the
//! default limits are measured by `perf/src/bin/untrusted_worst_step.rs`.
use tamias2d::body::Body;
use tamias2d::limits::{LimitError, Limits};
use tamias2d::math::{Real, Vect};
use tamias2d::replay::{Recorder, Replay, ReplayError};
use tamias2d::shape::Shape;
use tamias2d::snapshot::{self, SnapshotError};
use tamias2d::space::{Settings, Space, SpaceError};

fn dt() -> Real {
    Real::ratio(1, 60)
}

/// A floor (the level) and `n` circles placed by `at`, built trusted.
fn world(n: u32, at: impl Fn(u32) -> Vect) -> Space {
    let mut w = Space::new();
    w.set_limits(Limits::TRUSTED);
    w.set_gravity(Vect::from_ints(0, -10));
    let floor = w.add_body(Body::new_static()).unwrap();
    w.add_shape(
        Shape::segment_shape_new(
            floor,
            Vect::from_ints(-100, 0),
            Vect::from_ints(100, 0),
            Real::ZERO,
        )
        .unwrap(),
    )
    .unwrap();
    for i in 0..n {
        let b = w
            .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
            .unwrap();
        w.body_mut(b).unwrap().set_position(at(i));
        w.add_shape(Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).unwrap())
            .unwrap();
    }
    w
}

/// Circles in a row, apart: a small normal world.
fn row(n: u32) -> Space {
    world(n, |i| Vect::from_ints(2 * i as i32 - 20, 1))
}

/// `n` circles within 2^-13 m of each other: n(n-1)/2 candidate pairs.
fn pile(n: u32) -> Space {
    world(n, |i| {
        Vect::new(Real::from_bits(i64::from(i) << 19), Real::from_int(5))
    })
}

fn with_passes(mut w: Space, iterations: u32, substeps: u32) -> Space {
    let s = Settings {
        iterations,
        substeps,
        ..*w.settings()
    };
    w.set_settings(s).unwrap();
    w
}

/// A receiver with the floor as its level, under `limits`, stepped once.
fn receiver(limits: Limits) -> Space {
    let mut w = row(3);
    w.set_limits(limits);
    w.step(dt()).unwrap();
    w
}

fn limit_of(e: &SnapshotError) -> &'static str {
    match e {
        SnapshotError::OverLimit(LimitError { limit, .. }) => limit,
        other => panic!("not a limit error: {other}"),
    }
}

/// Every path refuses `forged` for `limit` and leaves the receiver as it
/// was; a trusting receiver takes it.
fn refused_everywhere(forged: &Space, limits: Limits, limit: &str) {
    let snap = snapshot::save(forged);
    let frame = snapshot::save_frame(forged);
    assert_eq!(
        limit_of(&snapshot::load_with(&snap, &limits).unwrap_err()),
        limit
    );
    assert_eq!(
        limit_of(&snapshot::decode_state_with(&snap, &limits).unwrap_err()),
        limit
    );
    let mut live = receiver(limits);
    let before = live.checksum();
    let e = live.load_snapshot(&snap).unwrap_err();
    assert_eq!(limit_of(&e), limit);
    assert!(e.to_string().contains(limit), "{e}");
    assert_eq!(
        live.checksum(),
        before,
        "a refused snapshot changed the world"
    );
    if limit == "candidate pairs" {
        // A frame is checked for counts and settings only; its first step
        // stops at the pair limit, at a cost bounded by it.
        let mut taken = live.clone();
        taken.load_frame_snapshot(&frame).unwrap();
        let Err(SpaceError::OverLimit(e)) = taken.step(dt()) else {
            panic!("a step over the pair limit ran");
        };
        assert_eq!(e.limit, limit);
    } else {
        let e = live.load_frame_snapshot(&frame).unwrap_err();
        assert_eq!(limit_of(&e), limit);
        assert_eq!(live.checksum(), before, "a refused frame changed the world");
    }
    live.step(dt()).unwrap();
    // A replay starting there is refused at its start.
    let mut rec = Recorder::new(forged, dt());
    rec.record_frame(forged, &[]).unwrap();
    let replay = Replay::from_bytes(&rec.finish().to_bytes()).unwrap();
    let mut verifier = Space::new();
    verifier.set_limits(limits);
    assert!(matches!(
        replay.verify_on(&mut verifier),
        Err(ReplayError::Start(_))
    ));
    // Trusted, everything loads.
    snapshot::load_with(&snap, &Limits::TRUSTED).unwrap();
    let mut trusting = receiver(Limits::TRUSTED);
    trusting.load_snapshot(&snap).unwrap();
    trusting.load_frame_snapshot(&frame).unwrap();
}

#[test]
fn settings_asking_for_too_many_solver_passes_are_refused() {
    // The reported input: sub-steps are checked first (each one costs
    // about a whole step), then iterations x sub-steps.
    refused_everywhere(
        &with_passes(row(3), 1024, 64),
        Limits::UNTRUSTED,
        "sub-steps",
    );
    let passes = u32::try_from(Limits::UNTRUSTED.max_solver_passes).unwrap();
    let substeps = u32::try_from(Limits::UNTRUSTED.max_substeps).unwrap();
    for (iterations, substeps) in [
        (1024, 1),
        (passes / substeps + 1, substeps),
        (passes + 1, 1),
    ] {
        refused_everywhere(
            &with_passes(row(3), iterations, substeps),
            Limits::UNTRUSTED,
            "solver passes (iterations x sub-steps)",
        );
    }
    // At the limits is fine.
    for (iterations, substeps) in [(passes, 1), (passes / substeps, substeps)] {
        snapshot::load(&snapshot::save(&with_passes(row(3), iterations, substeps))).unwrap();
    }
}

#[test]
fn a_pile_with_too_many_candidate_pairs_is_refused() {
    // 600 circles on one spot: 179,700 pairs, over the default 65,536.
    refused_everywhere(&pile(600), Limits::UNTRUSTED, "candidate pairs");
    // With a lower limit the count is exact: 20 circles, 190 pairs (+ none
    // with the floor, 5 m below).
    let limits = Limits {
        max_pairs: 189,
        ..Limits::UNTRUSTED
    };
    refused_everywhere(&pile(20), limits, "candidate pairs");
    let limits = Limits {
        max_pairs: 190,
        ..Limits::UNTRUSTED
    };
    snapshot::load_with(&snapshot::save(&pile(20)), &limits).unwrap();
}

#[test]
fn counts_and_bytes_over_their_limits_are_refused() {
    let forged = row(10);
    for (limits, limit) in [
        (
            Limits {
                max_bodies: 10,
                ..Limits::UNTRUSTED
            },
            "bodies",
        ),
        (
            Limits {
                max_shapes: 10,
                ..Limits::UNTRUSTED
            },
            "shapes",
        ),
        (
            Limits {
                max_bytes: 100,
                ..Limits::UNTRUSTED
            },
            "bytes",
        ),
    ] {
        refused_everywhere(&forged, limits, limit);
    }
    let e = snapshot::load_with(
        &snapshot::save(&forged),
        &Limits {
            max_bodies: 10,
            ..Limits::UNTRUSTED
        },
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "snapshot over a limit: bodies: 11 over the limit of 10"
    );
}

#[test]
fn a_step_over_the_pair_limit_stops_with_an_error() {
    // Built through the API (not loaded): the step itself holds the limit.
    let mut w = pile(40); // 780 pairs
    w.set_limits(Limits {
        max_pairs: 500,
        ..Limits::UNTRUSTED
    });
    let err = w.step(dt()).unwrap_err();
    let SpaceError::OverLimit(e) = &err else {
        panic!("not a limit error: {err}");
    };
    assert_eq!((e.limit, e.max), ("candidate pairs", 500));
    // The world stays valid; with the limit lifted it steps.
    w.validate().unwrap();
    w.set_limits(Limits::TRUSTED);
    w.step(dt()).unwrap();
    // Under the limit, the same bits as a trusted world.
    let (mut a, mut b) = (pile(30), pile(30)); // 435 pairs
    a.set_limits(Limits {
        max_pairs: 500,
        ..Limits::UNTRUSTED
    });
    for _ in 0..30 {
        a.step(dt()).unwrap();
        b.step(dt()).unwrap();
    }
    assert_eq!(a.checksum(), b.checksum());
}

#[test]
fn frames_with_other_settings_are_refused_when_asked() {
    let sender = with_passes(row(3), 12, 1);
    let frame = snapshot::save_frame(&sender);
    let mut strict = receiver(Limits {
        same_settings: true,
        ..Limits::UNTRUSTED
    });
    let before = strict.checksum();
    let e = strict.load_frame_snapshot(&frame).unwrap_err();
    assert!(e.to_string().contains("settings differ"), "{e}");
    assert_eq!(strict.checksum(), before);
    // The default accepts them (a game may change settings between frames).
    receiver(Limits::UNTRUSTED)
        .load_frame_snapshot(&frame)
        .unwrap();
}

#[test]
fn replays_over_the_frame_limit_are_refused() {
    let w = row(2);
    let mut rec = Recorder::new(&w, dt());
    let mut run = w.clone();
    for _ in 0..5 {
        run.step(dt()).unwrap();
        rec.record_frame(&run, &[]).unwrap();
    }
    let bytes = rec.finish().to_bytes();
    let limits = Limits {
        max_replay_frames: 4,
        ..Limits::UNTRUSTED
    };
    let Err(ReplayError::OverLimit(e)) = <Replay>::from_bytes_with(&bytes, &limits) else {
        panic!("a replay over the frame limit loaded");
    };
    assert_eq!((e.limit, e.value, e.max), ("replay frames", 5, 4));
    // Verifying on a world with that limit refuses it too.
    let replay = Replay::from_bytes(&bytes).unwrap();
    let mut verifier = Space::new();
    verifier.set_limits(limits);
    assert!(matches!(
        replay.verify_on(&mut verifier),
        Err(ReplayError::OverLimit(_))
    ));
    let mut verifier = Space::new();
    assert_eq!(replay.verify_on(&mut verifier).unwrap().frames, 5);
}
