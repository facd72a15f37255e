//! Replays: a run the game drives is recorded, then verified by re-running
//! the game's own step; tampering is caught at the right frame (inputs by
//! the input-log digest even when they change nothing, checksums with the
//! first differing body); a game with collision handlers verifies in a
//! second process; scripted scenes replay through their scripted world;
//! malformed bytes are errors, never panics.
use std::process::Command;

use tamias2d::body::{Body, BodyHandle};
use tamias2d::checksum::checksum_of;
use tamias2d::replay::{
    apply_inputs, Input, Recorder, Replay, ReplayError, Simulation, FORMAT_VERSION, HEADER_LEN,
    MAGIC,
};
use tamias2d::shape::Shape;
use tamias2d::space::{Space, SpaceError};
use tamias2d::{real, snapshot, Real, Vect};
use tamias2d_scenes::{self as scenes, ScriptedWorld};

/// A few impulses and forces on the two balls of `elastic_pair`, which
/// start apart: an input changes its own body only, until they meet. The
/// world is the scene's plain space, stepped with the default step.
fn record_elastic_pair(frames: u32, digest_every: u32) -> (Replay, [BodyHandle; 2]) {
    let world = scenes::builtin("elastic_pair")
        .expect("registered scene")
        .build()
        .expect("builds");
    let dt = world.dt;
    let mut space = world.space;
    let mut rec = Recorder::new(&space, dt).with_body_digests(digest_every);
    let balls: Vec<BodyHandle> = space.bodies().map(|(h, _)| h).collect();
    let [a, b] = balls[..] else {
        panic!("elastic_pair has two bodies, got {}", balls.len());
    };
    for f in 0..frames {
        let mut inputs = Vec::new();
        if f % 3 == 0 {
            let p = space.body(b).expect("live").position();
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
        space.advance(dt, &inputs).expect("steps");
        rec.record_frame(&space, &inputs).expect("records");
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
    let mut world = scenes::builtin("constant_force")
        .expect("registered")
        .build()
        .expect("builds");
    let mut plain = scenes::builtin("constant_force")
        .expect("registered")
        .build()
        .expect("builds");
    let mut rec = Recorder::new(&world, world.dt);
    for _ in 0..20 {
        world.step().expect("steps");
        plain.step().expect("steps");
        assert_eq!(
            rec.record_frame(&world, &[]).expect("records"),
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
    // The input log says which frame's inputs changed.
    match replay.verify() {
        Err(ReplayError::InputMismatch { frame }) => assert_eq!(frame as usize, f),
        other => panic!("expected an input mismatch at frame {f}, got {other:?}"),
    }
    // With the digests recomputed (a forger, or a game that really sent
    // other inputs), the checksums still catch it and name the body.
    rechain(&mut replay);
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
    rechain(&mut replay);
    match replay.verify() {
        Err(ReplayError::Diverged { frame: 9, body, .. }) => assert_eq!(body, None),
        other => panic!("expected a divergence at frame 9, got {other:?}"),
    }
}

/// Recomputes the input-log digests after an edit of the inputs, as a
/// recorder fed those inputs would have written them.
fn rechain(replay: &mut Replay) {
    let mut rec = Recorder::new(&Space::new(), replay.dt);
    for f in &replay.frames {
        rec.record_frame(&Space::new(), &f.inputs).expect("records");
    }
    let digests = rec.finish();
    for (f, d) in replay.frames.iter_mut().zip(&digests.frames) {
        f.input_digest = d.input_digest;
    }
    replay.input_digest = digests.input_digest;
}

#[test]
fn input_for_a_missing_body_is_an_error_and_changes_nothing() {
    let (replay, [live, _]) = record_elastic_pair(2, 0);
    let live = BodyHandle::from_raw_parts(live.index(), live.generation());
    let mut space = snapshot::load(&replay.start).expect("loads");
    let before = space.checksum();
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
    assert!(matches!(
        apply_inputs(&mut space, &inputs),
        Err(SpaceError::StaleBody(b)) if b == ghost
    ));
    assert_eq!(space.checksum(), before, "nothing applied");

    let mut replay = replay;
    replay.frames[1].inputs.push(Input::Force {
        body: ghost,
        force: Vect::X,
    });
    rechain(&mut replay);
    match replay.verify() {
        Err(ReplayError::Step { frame: 1, error }) => assert!(
            matches!(
                error.downcast_ref::<SpaceError>(),
                Some(SpaceError::StaleBody(b)) if *b == ghost
            ),
            "{error}"
        ),
        other => panic!("expected a step error at frame 1, got {other:?}"),
    }
}

#[test]
fn start_problems_are_reported() {
    let (mut replay, _) = record_elastic_pair(3, 0);
    replay.initial_checksum ^= 1;
    assert!(matches!(
        replay.verify(),
        Err(ReplayError::StartMismatch { .. })
    ));
    replay.initial_checksum ^= 1;
    let zero_dt = Replay {
        dt: Real::ZERO,
        ..replay.clone()
    };
    assert!(matches!(zero_dt.verify(), Err(ReplayError::TimeStep)));
    let bad_snapshot = Replay {
        start: vec![1, 2, 3],
        ..replay.clone()
    };
    assert!(matches!(bad_snapshot.verify(), Err(ReplayError::Start(_))));
    // Removing the last frame leaves every frame's digest valid; the whole
    // log's digest catches it.
    let mut short = replay;
    short.frames.pop();
    assert!(matches!(short.verify(), Err(ReplayError::InputLog { .. })));
}

#[test]
fn an_input_that_changes_nothing_is_still_reported_at_its_frame() {
    let (mut replay, [a, _]) = record_elastic_pair(30, 1);
    // A zero force: the world after the frame is the same bits. (Replays
    // name bodies by slot and generation.)
    replay.frames[12].inputs.push(Input::Force {
        body: BodyHandle::from_raw_parts(a.index(), a.generation()),
        force: Vect::ZERO,
    });
    match replay.verify() {
        Err(ReplayError::InputMismatch { frame }) => assert_eq!(frame, 12),
        other => panic!("expected an input mismatch at frame 12, got {other:?}"),
    }
    // And it really changes nothing: with the log re-digested, it verifies.
    rechain(&mut replay);
    assert_eq!(replay.verify().expect("same world").frames, 30);
}

#[test]
fn scripted_scenes_replay_through_their_scripted_world() {
    // Scripted forces (constant_force), a scripted torque (spin) and
    // spawns by step (rain_1000: rows every 10 steps), with a player input
    // on top; the start (saved mid-run) holds the script.
    for (name, before, frames) in [
        ("constant_force", 30, 40),
        ("spin", 10, 30),
        ("rain_1000", 25, 30),
    ] {
        let mut world = scenes::builtin(name)
            .expect("registered")
            .build()
            .expect("builds");
        world.step_n(before).expect("steps");
        let first = *world.bodies().last().expect("a body");
        let mut rec = Recorder::new(&world, world.dt).with_body_digests(5);
        for f in 0..frames {
            let inputs = if f % 4 == 0 {
                vec![Input::Velocity {
                    body: first,
                    velocity: Vect::from_ints(0, 0),
                }]
            } else {
                vec![]
            };
            world.advance(world.dt, &inputs).expect("steps");
            rec.record_frame(&world, &inputs).expect("records");
        }
        let replay = Replay::from_bytes(&rec.finish().to_bytes()).expect("decodes");
        let mut again = ScriptedWorld::load(&replay.start).expect("loads");
        let report = replay.verify_on(&mut again).expect("verifies");
        // Back to the start, for the plain-space check below.
        again.load_in_place(&replay.start).expect("loads");
        assert_eq!(report.frames, frames, "{name}");
        assert_eq!(report.final_checksum, world.space.checksum(), "{name}");
        // Without its script (a plain space, default step) it diverges:
        // the script is part of the replay's world.
        let plain = Replay {
            start: snapshot::save(&again.space),
            ..replay.clone()
        };
        assert!(
            matches!(plain.verify(), Err(ReplayError::Diverged { .. })),
            "{name}: a plain space replays the scripted run"
        );
    }
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
        <Replay>::read_file(path.with_extension("missing")),
        Err(ReplayError::Io(_))
    ));
}

#[test]
fn truncated_bytes_are_errors() {
    let (replay, _) = record_elastic_pair(12, 3);
    let bytes = replay.to_bytes();
    for len in 0..bytes.len() {
        let err = <Replay>::from_bytes(&bytes[..len]).expect_err("truncated");
        if len < HEADER_LEN {
            assert!(matches!(err, ReplayError::TooShort), "{len}: {err}");
        } else {
            assert!(matches!(err, ReplayError::Corrupt { .. }), "{len}: {err}");
        }
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(<Replay>::from_bytes(&longer).is_err());
}

#[test]
fn corrupted_header_or_payload_is_an_error() {
    let (replay, _) = record_elastic_pair(12, 3);
    let bytes = replay.to_bytes();
    let mut bad = bytes.clone();
    bad[0] ^= 0x20;
    assert!(matches!(
        <Replay>::from_bytes(&bad),
        Err(ReplayError::BadMagic)
    ));
    let mut bad = bytes.clone();
    bad[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    assert!(matches!(
        <Replay>::from_bytes(&bad),
        Err(ReplayError::UnsupportedVersion(v)) if v == FORMAT_VERSION + 1
    ));
    for i in HEADER_LEN..bytes.len() {
        let mut bad = bytes.clone();
        bad[i] ^= 0x01;
        assert!(
            matches!(<Replay>::from_bytes(&bad), Err(ReplayError::Corrupt { .. })),
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
        <Replay>::from_bytes(&with_payload(&bytes, &[])),
        Err(ReplayError::Decode(_))
    ));
}

// --- A game with collision handlers, verified in a second process --------

const BALL: u32 = 1;
const PLATFORM: u32 = 2;
const COIN: u32 = 3;

/// The game's time step.
fn game_dt() -> Real {
    Real::ratio(1, 60)
}

/// The game's world: a one-way platform at y = 4 (its `begin` handler
/// ignores the ball coming from below), a sensor coin above it whose
/// handler counts touches, and a ball below the platform. Returns the
/// space and the ball.
fn game_world() -> (Space, BodyHandle) {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space.add_body(Body::new_static()).expect("body");
    let mut platform = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-3, 4),
        Vect::from_ints(3, 4),
        real!(0.1),
    )
    .expect("segment")
    .with_material(Real::ONE, Real::ZERO)
    .expect("material");
    platform.collision_type = PLATFORM;
    space.add_shape(platform).expect("shape");
    let floor = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-20, 0),
        Vect::from_ints(20, 0),
        real!(0.1),
    )
    .expect("segment");
    space.add_shape(floor).expect("shape");
    let mut coin =
        Shape::circle_shape_new(ground, Real::HALF, Vect::from_ints(0, 7)).expect("circle");
    coin.collision_type = COIN;
    coin.sensor = true;
    space.add_shape(coin).expect("shape");
    let mut body = Body::new(Real::ONE, real!(0.125)).expect("body");
    body.set_position(Vect::from_ints(0, 1));
    let ball = space.add_body(body).expect("body");
    let mut shape = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)
        .expect("circle")
        .with_material(Real::ONE, Real::ZERO)
        .expect("material");
    shape.collision_type = BALL;
    space.add_shape(shape).expect("shape");
    space.add_collision_handler(PLATFORM, BALL).begin =
        Some(Box::new(|ctx| ctx.normal().y.is_positive()));
    space.add_collision_handler(BALL, COIN).begin = Some(Box::new(|_| true));
    (space, ball)
}

/// The game's own step.
fn game_step(space: &mut Space, inputs: &[Input]) -> Result<(), SpaceError> {
    apply_inputs(space, inputs)?;
    space.step(game_dt())
}

/// The player's inputs: jumps up through the platform, then walks.
fn game_inputs(ball: BodyHandle, frame: u32) -> Vec<Input> {
    match frame {
        5 | 130 => vec![Input::Impulse {
            body: ball,
            impulse: Vect::from_ints(0, 12),
            point: Vect::ZERO,
        }],
        100..=110 => vec![Input::Force {
            body: ball,
            force: Vect::from_ints(3, 0),
        }],
        _ => vec![],
    }
}

/// Records 180 frames of the game.
fn record_game() -> Replay {
    let (mut space, ball) = game_world();
    let mut rec = Recorder::new(&space, game_dt()).with_body_digests(10);
    for frame in 0..180 {
        let inputs = game_inputs(ball, frame);
        game_step(&mut space, &inputs).expect("steps");
        rec.record_frame(&space, &inputs).expect("records");
    }
    let ball_y = space.body(ball).expect("ball").position().y;
    assert!(
        ball_y > Real::from_int(4),
        "the ball jumped through the platform and rests on it: y = {ball_y}"
    );
    rec.finish()
}

/// Runs `child_verifies_the_replay_in_TAMIAS_REPLAY_FILE` of this test
/// binary in a new process on `file`; returns its result line.
fn verify_in_second_process(file: &std::path::Path) -> String {
    // The child's name as the harness knows it: its path in this test
    // program, without the crate name (`replay::child_…` in the
    // `determinism` program).
    let child = "child_verifies_the_replay_in_tamias_replay_file";
    let child = module_path!().split_once("::").map_or_else(
        || child.to_owned(),
        |(_, module)| format!("{module}::{child}"),
    );
    let out = Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "--exact",
            child.as_str(),
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("TAMIAS_REPLAY_FILE", file)
        .output()
        .expect("second process");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
        .lines()
        .find_map(|l| l.find("replay: ").map(|i| l[i..].to_owned()))
        .unwrap_or_else(|| panic!("no result line in {stdout}"))
}

/// The second process: builds the game (handlers included) and verifies
/// the replay file with the game's own step. Does nothing when not run by
/// [`verify_in_second_process`].
#[test]
#[ignore = "run by game_with_handlers_replays_in_a_second_process"]
fn child_verifies_the_replay_in_tamias_replay_file() {
    let Some(file) = std::env::var_os("TAMIAS_REPLAY_FILE") else {
        return;
    };
    let (mut space, _) = game_world();
    let result = Replay::read_file(file).and_then(|r| r.verify_with(&mut space, game_step));
    match result {
        Ok(report) => println!(
            "replay: ok {} frames {:#018x}",
            report.frames, report.final_checksum
        ),
        Err(e) => println!("replay: error {e:?}"),
    }
}

#[test]
fn game_with_handlers_replays_in_a_second_process() {
    let replay = record_game();
    let dir = std::env::temp_dir().join(format!("tamias2d-game-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("game.replay");
    replay.write_file(&file).expect("writes");
    let last = replay.frames.last().expect("frames").checksum;
    assert_eq!(
        verify_in_second_process(&file),
        format!("replay: ok 180 frames {last:#018x}")
    );

    // The handlers are part of the game: the default step (a plain space
    // without them) does not reproduce the run.
    assert!(matches!(replay.verify(), Err(ReplayError::Diverged { .. })));

    // A tampered input that changes nothing (a zero force at frame 42) is
    // reported at its frame, by the other process too.
    let mut tampered = replay.clone();
    tampered.frames[42].inputs.push(Input::Force {
        body: BodyHandle::from_raw_parts(1, 0),
        force: Vect::ZERO,
    });
    let file2 = dir.join("tampered.replay");
    tampered.write_file(&file2).expect("writes");
    assert_eq!(
        verify_in_second_process(&file2),
        "replay: error InputMismatch { frame: 42 }"
    );
    // A tampered jump too (it would change the world from frame 130 on).
    let mut tampered = replay;
    if let Some(Input::Impulse { impulse, .. }) = tampered.frames[130].inputs.first_mut() {
        impulse.y = Real::from_int(11);
    }
    tampered.write_file(&file2).expect("writes");
    assert_eq!(
        verify_in_second_process(&file2),
        "replay: error InputMismatch { frame: 130 }"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
