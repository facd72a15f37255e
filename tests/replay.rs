//! Replays: record then verify; tampering is caught at the right frame and
//! body; malformed bytes are errors, never panics.
use tamias2d::body::BodyHandle;
use tamias2d::checksum::checksum_of;
use tamias2d::replay::{
    Input, Recorder, Replay, ReplayError, Start, FORMAT_VERSION, HEADER_LEN, MAGIC,
};
use tamias2d_scenes::{self as scenes, BodyDesc, ShapeDesc};
use tamias2d::{real, snapshot, Real, Vect};

/// A few impulses and forces on the two balls of `elastic_pair`, which
/// start apart: an input changes its own body only, until they meet.
fn record_elastic_pair(frames: u32, digest_every: u32) -> (Replay, [BodyHandle; 2]) {
    let start = Start::builtin("elastic_pair").expect("listed scene");
    let mut rec = Recorder::new(start)
        .expect("builds")
        .with_body_digests(digest_every);
    let balls: Vec<BodyHandle> = rec.space().bodies().map(|(h, _)| h).collect();
    let [a, b] = balls[..] else {
        panic!("elastic_pair has two bodies, got {}", balls.len());
    };
    for f in 0..frames {
        let mut inputs = Vec::new();
        if f % 3 == 0 {
            let p = rec.space().body(b).expect("live").position();
            inputs.push(Input::Impulse {
                body: b,
                impulse: Vect::new(Real::ZERO, real!(0.25)),
                point: p + Vect::from_ints(0, 1),
            });
        }
        if f % 5 == 1 {
            inputs.push(Input::Force {
                body: a,
                force: Vect::from_ints(0, -3),
            });
            inputs.push(Input::Torque {
                body: a,
                torque: real!(0.5),
            });
        }
        if f == 7 {
            inputs.push(Input::AngularVelocity {
                body: b,
                w: real!(-1.5),
            });
        }
        rec.record_frame(&inputs).expect("records");
    }
    assert_eq!(rec.frames(), frames);
    (rec.finish(), [a, b])
}

fn impulse_frame(replay: &Replay) -> usize {
    replay
        .frames
        .iter()
        .position(|f| matches!(f.inputs.first(), Some(Input::Impulse { .. })))
        .expect("an impulse")
}

#[test]
fn record_then_verify_passes_and_survives_bytes() {
    let (replay, _) = record_elastic_pair(40, 1);
    let report = replay.verify().expect("verifies");
    assert_eq!(report.frames, 40);
    assert_eq!(
        Some(report.final_checksum),
        replay.frames.last().map(|f| f.checksum)
    );
    let bytes = replay.to_bytes();
    assert_eq!(bytes.get(..8), Some(&MAGIC[..]));
    assert_eq!(bytes.get(8..12), Some(&FORMAT_VERSION.to_le_bytes()[..]));
    let back = Replay::from_bytes(&bytes).expect("decodes");
    assert_eq!(back, replay);
    assert_eq!(
        back.verify().expect("verifies").final_checksum,
        report.final_checksum
    );
}

#[test]
fn recorded_checksums_match_a_plain_run_of_the_scene() {
    let (replay, _) = record_elastic_pair(0, 0);
    let mut rec = Recorder::new(replay.start.clone()).expect("builds");
    let mut plain = scenes::builtin("elastic_pair")
        .expect("listed")
        .build()
        .expect("builds");
    for _ in 0..20 {
        plain.step().expect("steps");
        assert_eq!(
            rec.record_frame(&[]).expect("records"),
            plain.space.checksum()
        );
    }
}

#[test]
fn tampered_checksum_diverges_at_that_frame() {
    let (mut replay, _) = record_elastic_pair(30, 1);
    let original = replay.frames[17].checksum;
    replay.frames[17].checksum ^= 1;
    match replay.verify() {
        Err(ReplayError::Diverged {
            frame,
            body,
            expected,
            actual,
        }) => {
            assert_eq!(frame, 17);
            assert_eq!(expected, original ^ 1);
            assert_eq!(actual, original);
            assert_eq!(body, None, "the bodies themselves match their digests");
        }
        other => panic!("expected a divergence at frame 17, got {other:?}"),
    }
}

#[test]
fn tampered_input_names_the_body_it_moves() {
    let (mut replay, [_, b]) = record_elastic_pair(30, 1);
    let f = impulse_frame(&replay);
    if let Some(Input::Impulse { impulse, .. }) = replay.frames[f].inputs.first_mut() {
        impulse.x += Real::DELTA;
    }
    match replay.verify() {
        Err(ReplayError::Diverged { frame, body, .. }) => {
            assert_eq!(frame as usize, f);
            assert_eq!(body, Some(b));
        }
        other => panic!("expected a divergence at frame {f}, got {other:?}"),
    }
}

#[test]
fn divergence_between_digest_frames_names_no_body() {
    let (mut replay, _) = record_elastic_pair(30, 4);
    assert!(replay.frames[8].bodies.is_some());
    assert!(replay.frames[9].bodies.is_none());
    replay.frames[9].inputs.push(Input::Torque {
        body: BodyHandle::from_raw_parts(0, 0),
        torque: Real::ONE,
    });
    match replay.verify() {
        Err(ReplayError::Diverged { frame: 9, body, .. }) => assert_eq!(body, None),
        other => panic!("expected a divergence at frame 9, got {other:?}"),
    }
}

#[test]
fn input_for_a_missing_body_is_an_error_and_changes_nothing() {
    let mut rec = Recorder::new(Start::builtin("elastic_pair").expect("listed")).expect("builds");
    rec.record_frame(&[]).expect("records");
    let before = rec.space().checksum();
    let live = rec.space().bodies().map(|(h, _)| h).next().expect("a body");
    let ghost = BodyHandle::from_raw_parts(99, 0);
    let inputs = [
        Input::Velocity {
            body: live,
            velocity: Vect::from_ints(5, 5),
        },
        Input::Force {
            body: ghost,
            force: Vect::X,
        },
    ];
    match rec.record_frame(&inputs) {
        Err(ReplayError::MissingBody { frame: 1, body }) => assert_eq!(body, ghost),
        other => panic!("expected MissingBody, got {other:?}"),
    }
    assert_eq!(rec.space().checksum(), before, "nothing applied, no step");
    assert_eq!(rec.frames(), 1);

    let mut replay = rec.finish();
    replay.frames[0].inputs.push(Input::Force {
        body: ghost,
        force: Vect::X,
    });
    assert!(matches!(
        replay.verify(),
        Err(ReplayError::MissingBody { frame: 0, .. })
    ));
}

#[test]
fn start_problems_are_reported() {
    let (mut replay, _) = record_elastic_pair(3, 0);
    replay.initial_checksum ^= 1;
    assert!(matches!(
        replay.verify(),
        Err(ReplayError::StartMismatch { .. })
    ));
    let unknown = Replay {
        start: Start::Builtin {
            name: "no_such_scene".into(),
            dt: real!(0.01),
        },
        ..replay.clone()
    };
    assert!(matches!(
        unknown.verify(),
        Err(ReplayError::UnknownScene(_))
    ));
    let zero_dt = Replay {
        start: Start::Builtin {
            name: "elastic_pair".into(),
            dt: Real::ZERO,
        },
        ..replay.clone()
    };
    assert!(matches!(zero_dt.verify(), Err(ReplayError::ScriptedWorld(_))));
    let bad_snapshot = Replay {
        start: Start::Snapshot {
            bytes: vec![1, 2, 3],
            dt: real!(0.01),
        },
        ..replay
    };
    assert!(matches!(
        bad_snapshot.verify(),
        Err(ReplayError::Snapshot(_))
    ));
}

#[test]
fn scene_description_start_round_trips() {
    let mut desc = scenes::builtin("bowl_circles_100").expect("listed");
    desc.name = "custom".into();
    desc.bodies.truncate(12);
    let player = BodyDesc::dynamic(Vect::from_ints(0, 100), Real::from_int(4), real!(50))
        .labeled("player")
        .with_shape(ShapeDesc::circle(real!(6.5)).material(real!(0.7), real!(0.25)));
    desc.bodies.push(player);
    let mut rec = Recorder::new(Start::ScriptedWorld(Box::new(desc))).expect("builds");
    let player = rec.body("player").expect("labelled");
    for f in 0..60 {
        let inputs: &[Input] = if f % 10 == 0 {
            &[Input::Velocity {
                body: player,
                velocity: Vect::from_ints(30, 40),
            }]
        } else {
            &[]
        };
        rec.record_frame(inputs).expect("records");
    }
    let replay = rec.finish();
    let back = Replay::from_bytes(&replay.to_bytes()).expect("decodes");
    assert_eq!(back, replay);
    assert_eq!(back.verify().expect("verifies").frames, 60);
}

#[test]
fn snapshot_start_round_trips() {
    let mut scene = scenes::builtin("stack_10")
        .expect("listed")
        .build()
        .expect("builds");
    scene.step_n(25).expect("steps");
    let start = Start::Snapshot {
        bytes: snapshot::save(&scene.space),
        dt: scene.dt,
    };
    let top = scene.bodies().last().copied().expect("a box");
    let mut rec = Recorder::new(start).expect("loads").with_body_digests(1);
    assert_eq!(rec.space().checksum(), scene.space.checksum());
    for f in 0..40 {
        let inputs = [Input::Force {
            body: top,
            force: Vect::new(Real::from_int(f % 7 - 3), Real::ZERO),
        }];
        rec.record_frame(&inputs).expect("records");
    }
    let replay = rec.finish();
    let back = Replay::from_bytes(&replay.to_bytes()).expect("decodes");
    assert_eq!(back.verify().expect("verifies").frames, 40);
}

#[test]
fn file_round_trip() {
    let (replay, _) = record_elastic_pair(10, 2);
    let path = std::env::temp_dir().join(format!("tamias2d-replay-{}.bin", std::process::id()));
    replay.write_file(&path).expect("writes");
    let back = Replay::read_file(&path).expect("reads");
    let _ = std::fs::remove_file(&path);
    assert_eq!(back, replay);
    assert!(matches!(
        Replay::read_file(path.with_extension("missing")),
        Err(ReplayError::Io(_))
    ));
}

#[test]
fn truncated_bytes_are_errors() {
    let (replay, _) = record_elastic_pair(12, 3);
    let bytes = replay.to_bytes();
    for len in 0..bytes.len() {
        let err = Replay::from_bytes(&bytes[..len]).expect_err("truncated");
        if len < HEADER_LEN {
            assert!(matches!(err, ReplayError::TooShort), "{len}: {err}");
        } else {
            assert!(matches!(err, ReplayError::Corrupt { .. }), "{len}: {err}");
        }
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(Replay::from_bytes(&longer).is_err());
}

#[test]
fn corrupted_header_or_payload_is_an_error() {
    let (replay, _) = record_elastic_pair(12, 3);
    let bytes = replay.to_bytes();
    let mut bad = bytes.clone();
    bad[0] ^= 0x20;
    assert!(matches!(
        Replay::from_bytes(&bad),
        Err(ReplayError::BadMagic)
    ));
    let mut bad = bytes.clone();
    bad[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    assert!(matches!(
        Replay::from_bytes(&bad),
        Err(ReplayError::UnsupportedVersion(v)) if v == FORMAT_VERSION + 1
    ));
    for i in HEADER_LEN..bytes.len() {
        let mut bad = bytes.clone();
        bad[i] ^= 0x01;
        assert!(
            matches!(Replay::from_bytes(&bad), Err(ReplayError::Corrupt { .. })),
            "flip at {i}"
        );
    }
}

/// Replaces the payload and writes a matching digest, so that the decoder
/// and the verifier (not the digest check) see the damage.
fn with_payload(bytes: &[u8], payload: &[u8]) -> Vec<u8> {
    let mut out = bytes[..HEADER_LEN].to_vec();
    out[12..HEADER_LEN].copy_from_slice(&checksum_of(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

#[test]
fn damaged_payload_with_a_valid_digest_never_panics() {
    let (replay, _) = record_elastic_pair(8, 2);
    let bytes = replay.to_bytes();
    let payload = &bytes[HEADER_LEN..];
    let mut rng = tamias2d_scenes::rng::SplitMix64::new(7);
    let mut decoded = 0;
    for round in 0..400 {
        let mut damaged = payload.to_vec();
        match round % 4 {
            0 => {
                // Truncate.
                let cut = (rng.next_u64() % payload.len() as u64) as usize;
                damaged.truncate(cut);
            }
            1 => {
                // Flip one bit.
                let i = (rng.next_u64() % payload.len() as u64) as usize;
                damaged[i] ^= 1 << (rng.next_u64() % 8);
            }
            2 => {
                // Overwrite 8 bytes with random ones (lengths, tags).
                let i = (rng.next_u64() % payload.len() as u64) as usize;
                for b in damaged.iter_mut().skip(i).take(8) {
                    *b = rng.next_u64() as u8;
                }
            }
            _ => {
                // A huge length prefix where the start's tag ends.
                for b in damaged.iter_mut().skip(4).take(8) {
                    *b = 0xff;
                }
            }
        }
        if let Ok(r) = Replay::from_bytes(&with_payload(&bytes, &damaged)) {
            decoded += 1;
            // Decodes to some replay: verifying it is an answer, never a panic.
            let _ = r.verify();
        }
    }
    // Most damage is caught by decoding; some yields other valid replays.
    assert!(decoded < 400);
    assert!(matches!(
        Replay::from_bytes(&with_payload(&bytes, &[])),
        Err(ReplayError::Decode(_))
    ));
}
