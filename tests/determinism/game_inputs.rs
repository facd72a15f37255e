//! Replays of a game's own inputs: two players' pads (button masks and a
//! stick) drive a motor and a jump; the replay carries the pads, verifies
//! by re-running the game's step on them (from memory and from bytes,
//! through a step function and through the game's own world type), and
//! reports a changed button at its frame, even a button the game ignores.
use serde::{Deserialize, Serialize};
use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{Constraint, ConstraintHandle, SimpleMotor};
use tamias2d::replay::{apply_inputs, BoxError, Input, Recorder, Replay, ReplayError, Simulation};
use tamias2d::shape::Shape;
use tamias2d::space::{Space, SpaceError};
use tamias2d::{real, snapshot, Real, Vect};

/// One player's pad this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
struct Pad {
    buttons: u8,
    /// Stick, −127 to 127.
    stick: i8,
}

const JUMP: u8 = 1;
const BRAKE: u8 = 2;
/// A button the game reads nothing from.
const UNUSED: u8 = 0x80;

/// The frame's inputs: both players' pads.
type Pads = [Pad; 2];

fn dt() -> Real {
    Real::ratio(1, 60)
}

/// The game's world: a wheel on an axle turned by a motor (player 1's
/// stick sets its rate, the brake stops it) and a ball on the ground that
/// jumps (player 2's jump button, when it rests).
struct Game {
    space: Space,
    motor: ConstraintHandle,
    ball: BodyHandle,
}

impl Game {
    fn new() -> Game {
        let mut space = Space::new();
        space.set_gravity(Vect::from_ints(0, -10));
        let ground = space.add_body(Body::new_static()).expect("ground");
        let floor = Shape::segment_shape_new(
            ground,
            Vect::from_ints(-20, 0),
            Vect::from_ints(20, 0),
            Real::ZERO,
        )
        .expect("floor");
        space.add_shape(floor).expect("floor");
        let mut wheel = Body::new(Real::ONE, Real::ONE).expect("wheel");
        wheel.set_position(Vect::from_ints(-5, 3));
        let wheel = space.add_body(wheel).expect("wheel");
        let axle = space
            .pivot_joint(ground, wheel, Vect::from_ints(-5, 3))
            .expect("axle");
        space.add_constraint(axle).expect("axle");
        let mut motor =
            Constraint::new(ground, wheel, SimpleMotor::new(Real::ZERO).expect("motor"))
                .expect("motor");
        motor.set_max_force(Real::from_int(20)).expect("bounded");
        let motor = space.add_constraint(motor).expect("motor");
        let mut ball = Body::new(Real::ONE, real!(0.1)).expect("ball");
        ball.set_position(Vect::new(Real::from_int(5), Real::HALF));
        let ball = space.add_body(ball).expect("ball");
        let shape = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO).expect("ball");
        space.add_shape(shape).expect("ball");
        Game { space, motor, ball }
    }
}

/// The game's step: decode the pads into a motor rate and a jump, then
/// step. A function of the world and the pads only.
fn game_step(
    space: &mut Space,
    motor: ConstraintHandle,
    ball: BodyHandle,
    pads: &Pads,
) -> Result<(), SpaceError> {
    let [p1, p2] = *pads;
    let rate = if p1.buttons & BRAKE != 0 {
        Real::ZERO
    } else {
        Real::ratio(i32::from(p1.stick), 16)
    };
    space.modify_constraint(motor, |c| c.joint_mut::<SimpleMotor>()?.set_rate(rate))?;
    let resting = space
        .body(ball)
        .is_some_and(|b| b.position().y < real!(0.51) && b.velocity().y.abs() < real!(0.1));
    if p2.buttons & JUMP != 0 && resting {
        if let Some(b) = space.body_mut(ball) {
            b.apply_impulse_at_world_point(Vect::from_ints(1, 4), b.center());
        }
    }
    space.step(dt())
}

impl Simulation<Pads> for Game {
    fn space(&self) -> &Space {
        &self.space
    }
    fn save(&self) -> Vec<u8> {
        snapshot::save(&self.space)
    }
    fn restore(&mut self, start: &[u8]) -> Result<(), BoxError> {
        self.space.load_snapshot(start).map_err(BoxError::from)
    }
    fn advance(&mut self, _dt: Real, pads: &Pads) -> Result<(), BoxError> {
        game_step(&mut self.space, self.motor, self.ball, pads).map_err(BoxError::from)
    }
}

/// The scripted pads of frame `f`: player 1 sweeps the stick and brakes
/// now and then, player 2 jumps every 60 frames from frame 30 (a jump
/// lasts 48 frames) and presses the unused button on frame 77.
fn pads(f: u32) -> Pads {
    let stick = i8::try_from(i64::from((f * 3) % 200) - 100).expect("in range");
    let p1 = Pad {
        buttons: if f % 90 >= 80 { BRAKE } else { 0 },
        stick,
    };
    let mut p2 = Pad::default();
    if f % 60 == 30 {
        p2.buttons |= JUMP;
    }
    if f == 77 {
        p2.buttons |= UNUSED;
    }
    [p1, p2]
}

const FRAMES: u32 = 300;
/// A frame on which player 2 presses jump.
const A_JUMP: usize = 90;

/// Records a run of the game on its own world type.
fn record() -> (Replay<Pads>, Game) {
    let mut game = Game::new();
    let mut rec = Recorder::new(&game, dt()).with_body_digests(10);
    let mut jumped = 0;
    for f in 0..FRAMES {
        let p = pads(f);
        game.advance(dt(), &p).expect("steps");
        let rising = game
            .space
            .body(game.ball)
            .map_or(Real::ZERO, |b| b.velocity().y);
        if p[1].buttons & JUMP != 0 && rising > Real::TWO {
            jumped += 1;
        }
        rec.record(&game, &p).expect("records");
    }
    assert_eq!(jumped, 5, "the ball jumps at every press");
    let w = game.space.constraint(game.motor).map(Constraint::impulse);
    assert_ne!(w, Some(Real::ZERO), "the motor works");
    (rec.finish(), game)
}

#[test]
fn a_replay_of_button_inputs_verifies() {
    let (replay, live) = record();
    assert_eq!(replay.frames.len(), FRAMES as usize);
    assert_eq!(replay.frames[A_JUMP].inputs[1].buttons, JUMP);
    // In memory, through the game's world type ...
    let report = replay.verify_on(&mut Game::new()).expect("verifies");
    assert_eq!(report.frames, FRAMES);
    assert_eq!(report.final_checksum, live.space.checksum());
    // ... from bytes, through a step function on a world built again
    // (its own handles: the replay holds pads, not handles) ...
    let bytes = replay.to_bytes();
    let back: Replay<Pads> = Replay::from_bytes(&bytes).expect("decodes");
    assert_eq!(back, replay);
    let Game {
        mut space,
        motor,
        ball,
    } = Game::new();
    let report = back
        .verify_with(&mut space, |s, pads| game_step(s, motor, ball, pads))
        .expect("verifies");
    assert_eq!(report.final_checksum, live.space.checksum());
    // ... and the input type needs no annotation when the world names it.
    let report = Replay::from_bytes(&bytes)
        .and_then(|r| r.verify_on(&mut Game::new()))
        .expect("verifies");
    assert_eq!(report.frames, FRAMES);
}

/// Recomputes the input-log digests after an edit of the pads, as a
/// recorder fed those pads would have written them.
fn rechain(replay: &mut Replay<Pads>) {
    let mut rec = Recorder::<Pads>::new(&Space::new(), replay.dt);
    for f in &replay.frames {
        rec.record(&Space::new(), &f.inputs).expect("records");
    }
    let digests = rec.finish();
    for (f, d) in replay.frames.iter_mut().zip(&digests.frames) {
        f.input_digest = d.input_digest;
    }
    replay.input_digest = digests.input_digest;
}

#[test]
fn a_tampered_button_is_reported_at_its_frame() {
    let (replay, _) = record();
    // A jump taken away, a brake added, a stick moved, and the button the
    // game ignores: each at its own frame, by the input log.
    type Edit = fn(&mut Pads);
    let edits: [(usize, Edit); 4] = [
        (A_JUMP, |p| p[1].buttons &= !JUMP),
        (123, |p| p[0].buttons |= BRAKE),
        (201, |p| p[0].stick = p[0].stick.wrapping_add(1)),
        (77, |p| p[1].buttons &= !UNUSED),
    ];
    for (frame, edit) in edits {
        let mut tampered = replay.clone();
        edit(&mut tampered.frames[frame].inputs);
        match tampered.verify_on(&mut Game::new()) {
            Err(ReplayError::InputMismatch { frame: f }) => assert_eq!(f as usize, frame),
            other => panic!("frame {frame}: expected an input mismatch, got {other:?}"),
        }
        // With the log re-digested (a game that really read other
        // buttons), the checksums catch a button that acts, at its frame.
        rechain(&mut tampered);
        let result = tampered.verify_on(&mut Game::new());
        if frame == 77 {
            // The ignored button changes nothing: only the log could tell.
            assert!(result.is_ok(), "{result:?}");
        } else {
            match result {
                Err(ReplayError::Diverged { frame: f, .. }) => assert_eq!(f as usize, frame),
                other => panic!("frame {frame}: expected a divergence, got {other:?}"),
            }
        }
    }
    // Bytes of a tampered replay are reported the same way.
    let mut tampered = replay.clone();
    tampered.frames[A_JUMP].inputs[1].buttons = 0;
    let back: Replay<Pads> = Replay::from_bytes(&tampered.to_bytes()).expect("decodes");
    assert!(matches!(
        back.verify_on(&mut Game::new()),
        Err(ReplayError::InputMismatch { frame }) if frame as usize == A_JUMP
    ));
}

#[test]
fn physics_inputs_are_one_input_type_among_others() {
    // `record_frame(&[Input])` is `record(&Vec<Input>)`: the same replay.
    let mut space = Space::new();
    let ball = space
        .add_body(Body::new(Real::ONE, Real::ONE).expect("ball"))
        .expect("ball");
    let mut a = Recorder::new(&space, dt());
    let mut b = Recorder::new(&space, dt());
    for f in 0..20 {
        let inputs = if f % 4 == 0 {
            vec![Input::Force {
                body: ball,
                force: Vect::from_ints(f, 1),
            }]
        } else {
            Vec::new()
        };
        apply_inputs(&mut space, &inputs).expect("applies");
        space.step(dt()).expect("steps");
        a.record_frame(&space, &inputs).expect("records");
        b.record(&space, &inputs).expect("records");
    }
    let (a, b) = (a.finish(), b.finish());
    assert_eq!(a, b);
    // The step function may take the list as a slice or as the vector.
    let step = |s: &mut Space, inputs: &[Input]| -> Result<(), SpaceError> {
        apply_inputs(s, inputs)?;
        s.step(dt())
    };
    assert_eq!(
        a.verify_with(&mut Space::new(), step)
            .expect("verifies")
            .frames,
        20
    );
    let step = |s: &mut Space, inputs: &Vec<Input>| -> Result<(), SpaceError> {
        apply_inputs(s, inputs)?;
        s.step(dt())
    };
    assert_eq!(
        b.verify_with(&mut Space::new(), step)
            .expect("verifies")
            .frames,
        20
    );
    assert_eq!(a.verify().expect("verifies").frames, 20);
}

#[test]
fn a_replay_read_as_another_input_type_does_not_verify() {
    let (replay, _) = record();
    let bytes = replay.to_bytes();
    // The bytes do not name their input type: read as physics inputs they
    // fail to decode or to verify, never panic.
    let as_inputs = <Replay>::from_bytes(&bytes).and_then(|r| r.verify());
    assert!(as_inputs.is_err());
}

/// An input whose encoding fails.
#[derive(Clone, Debug, PartialEq, Deserialize)]
struct Unencodable;

impl Serialize for Unencodable {
    fn serialize<S: serde::Serializer>(&self, _: S) -> Result<S::Ok, S::Error> {
        Err(serde::ser::Error::custom("not today"))
    }
}

/// An input whose encoding is not a function of its value (as a
/// `HashMap`'s iteration order): it writes how often it was encoded.
#[derive(Clone, Debug, PartialEq, Deserialize)]
struct Drifting(u32);

static ENCODED: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);

impl Serialize for Drifting {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let n = ENCODED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        s.serialize_u32(n)
    }
}

#[test]
fn inputs_that_do_not_survive_their_encoding_are_refused_when_recorded() {
    let space = Space::new();
    let mut rec = Recorder::new(&space, dt());
    assert!(matches!(
        rec.record(&space, &Unencodable),
        Err(ReplayError::Encode(_))
    ));
    let mut rec = Recorder::new(&space, dt());
    assert!(matches!(
        rec.record(&space, &Drifting(0)),
        Err(ReplayError::Encode(_))
    ));
    assert_eq!(rec.frames(), 0, "nothing recorded");
}
