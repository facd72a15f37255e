//! Replays: record a run a game drives (start, `dt`, the game's inputs,
//! per-frame checksums, a digest of the input log) and verify it frame by
//! frame by re-running the game's own step.
//!
//! A lockstep or rollback game is a pure function of its start and its
//! inputs. A [`Replay`] stores exactly that, plus the checksum of the world
//! after every frame, so that re-running it proves (or disproves) that this
//! build, on this machine, computes the same bits as the one that recorded
//! it. Optionally it also stores a digest of every body on every `K`-th
//! frame, so a divergence names the first body that differs.
//!
//! The game owns its world and drives it: it attaches its collision
//! handlers, sensors and one-way platforms, applies its inputs and steps;
//! the [`Recorder`] only looks at the world after each frame. To verify, the
//! game builds its world again (handlers included) and hands it to
//! [`Replay::verify_with`] together with its own step function; the replay
//! rolls that world back to the recorded start (in place, so the handlers
//! stay) and re-runs every frame through that function.
//!
//! ```
//! use tamias2d::body::Body;
//! use tamias2d::replay::{apply_inputs, Input, Recorder, Replay};
//! use tamias2d::shape::Shape;
//! use tamias2d::space::Space;
//! use tamias2d::{Real, Vect};
//!
//! // The game's world and its step function.
//! let mut space = Space::new();
//! let ball = space.add_body(Body::new(Real::ONE, Real::ONE)?)?;
//! space.add_shape(Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)?)?;
//! let dt = Real::ratio(1, 60);
//! let game_step = |space: &mut Space, inputs: &[Input]| {
//!     apply_inputs(space, inputs)?;
//!     space.step(dt)
//! };
//!
//! let mut rec = Recorder::new(&space, dt).with_body_digests(1);
//! for frame in 0..30 {
//!     let push = Input::Force { body: ball, force: Vect::from_ints(0, 5) };
//!     let inputs = if frame == 10 { vec![push] } else { vec![] };
//!     game_step(&mut space, &inputs)?;
//!     rec.record_frame(&space, &inputs)?;
//! }
//! let bytes = rec.finish().to_bytes();
//!
//! // Elsewhere: the game builds its world again and re-runs its step.
//! let mut again = Space::new();
//! let report = Replay::from_bytes(&bytes)?.verify_with(&mut again, game_step)?;
//! assert_eq!(report.frames, 30);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # A game's own inputs
//! A game's inputs are buttons and sticks, which its step function turns
//! into motor rates, impulses and spawns. The recorder and the replay carry
//! any input type `I` that serde encodes (`Serialize + DeserializeOwned`,
//! and `Clone`): [`Recorder::record`] takes `&I` each frame, and the step
//! function given to [`Replay::verify_with`] (or a [`Simulation<I>`]'s
//! `advance`) receives the same `&I` again. [`Input`] lists are one such
//! type, the default (`Recorder` is `Recorder<Vec<Input>>`, whose
//! [`record_frame`](Recorder::record_frame) takes `&[Input]`).
//!
//! ```
//! use serde::{Deserialize, Serialize};
//! use tamias2d::body::Body;
//! use tamias2d::constraint::{Constraint, SimpleMotor};
//! use tamias2d::replay::{Recorder, Replay, ReplayError};
//! use tamias2d::space::{Space, SpaceError};
//! use tamias2d::{Real, Vect};
//!
//! /// One player's buttons this frame.
//! #[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
//! struct Buttons(u8);
//! const LEFT: u8 = 1;
//! const RIGHT: u8 = 2;
//!
//! // A wheel driven by a motor; the buttons set the motor's rate.
//! let mut space = Space::new();
//! let ground = space.add_body(Body::new_static())?;
//! let wheel = space.add_body(Body::new(Real::ONE, Real::ONE)?)?;
//! let motor = space.add_constraint(Constraint::new(ground, wheel, SimpleMotor::new(Real::ZERO)?)?)?;
//! let dt = Real::ratio(1, 60);
//! let game_step = move |space: &mut Space, buttons: &Buttons| -> Result<(), SpaceError> {
//!     let rate = match buttons.0 & (LEFT | RIGHT) {
//!         LEFT => Real::from_int(-3),
//!         RIGHT => Real::from_int(3),
//!         _ => Real::ZERO,
//!     };
//!     space.modify_constraint(motor, |c| c.joint_mut::<SimpleMotor>()?.set_rate(rate))?;
//!     space.step(dt)
//! };
//!
//! let mut rec = Recorder::new(&space, dt);
//! for frame in 0..60u8 {
//!     let buttons = Buttons(if frame < 30 { RIGHT } else { LEFT });
//!     game_step(&mut space, &buttons)?;
//!     rec.record(&space, &buttons)?;
//! }
//! // The game's own space, rolled back to the start in place: the
//! // handles its step function holds (`motor`) stay valid.
//! let mut replay: Replay<Buttons> = Replay::from_bytes(&rec.finish().to_bytes())?;
//! assert_eq!(replay.verify_with(&mut space, game_step)?.frames, 60);
//!
//! // A button changed after recording is reported at its frame.
//! replay.frames[42].inputs = Buttons(RIGHT);
//! assert!(matches!(
//!     replay.verify_with(&mut space, game_step),
//!     Err(ReplayError::InputMismatch { frame: 42 })
//! ));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `Replay::from_bytes` returns a `Replay<I>` of the type the caller names
//! (or that the verification implies); `<Replay>::from_bytes(..)` is the
//! default [`Input`] lists when nothing else says.
//!
//! # Frames
//! Frame `f` (0-based) takes the world after `f` frames, runs the game's
//! step with `frames[f].inputs`, and records the checksum
//! ([`Space::checksum`]) of the result. [`Replay::verify`] re-runs a plain
//! space with the default step ([`apply_inputs`], then [`Space::step`] by the
//! replay's `dt`); [`Replay::verify_with`] with the game's step function on
//! the game's space; [`Replay::verify_on`] with any [`Simulation`] (a world
//! type that keeps state beside its space, such as a scripted scene, whose
//! start then holds that state too).
//!
//! # Inputs and the input log
//! [`Input`] is a small closed set of what a game does to bodies between
//! steps (impulse, force, torque, velocity, angular velocity). A body is
//! named by slot and generation only (a handle's origin tag is not
//! recorded), so the handles of the recording world work in the verifying
//! one. **An input naming a body that does not exist is an error**
//! ([`apply_inputs`] returns it before applying anything; the default step
//! reports it as [`ReplayError::Step`]).
//!
//! The recorder stores a frame's inputs as the file holds them: encoded
//! (the payload's encoding, below), then decoded back, so that handles lose
//! their origin tag and a replay verifies the same in memory and from
//! bytes. An input type whose encoding is not a function of its value (a
//! `HashMap`, iterated in a random order) is refused when recorded
//! ([`ReplayError::Encode`]).
//!
//! Every frame also stores the digest of the input log up to and including
//! it (a chain: the previous frame's digest and this frame's encoded
//! inputs), and the replay stores the digest of the whole log. Verification
//! checks the chain before re-running anything, so an input changed after
//! recording is reported at its frame ([`ReplayError::InputMismatch`]) even
//! when it does not change the world (a force on a static body, a velocity
//! set to the value it had, a button the game ignores). The digests detect
//! damage and careless edits, not a forger who recomputes them.
//!
//! # File format (version [`FORMAT_VERSION`])
//! ```text
//! offset  size  content
//!      0     8  magic b"TAMIASRP"
//!      8     4  format version, u32 little-endian
//!     12     8  digest of the payload bytes (checksum::checksum_of), u64 LE
//!     20     …  payload: bincode 2 (serde), standard config with fixed-int
//!               encoding, limit MAX_REPLAY_BYTES:
//!               (start, dt, initial checksum, input-log digest, frames)
//! ```
//! `start` is the start world's snapshot as its [`Simulation::save`] wrote it
//! ([`snapshot`] bytes for a plain [`Space`]). Each frame is its inputs
//! (the game's input type as serde encodes it; a length and the
//! [`Input`]s for the default lists), its input-log digest, its checksum
//! and optionally `(body handle, digest)` pairs in slot order. The bytes do
//! not name the input type: the game reads its replays with its own. The
//! payload must end exactly at the end of the bytes. Malformed bytes are
//! an error, never a panic: short or foreign header, unknown version, a
//! payload digest that does not match (corruption is reported as such, not
//! as a divergence), bytes that do not decode, trailing bytes.
//!
//! # What a divergence reports
//! The verification stops at the first frame whose checksum differs and
//! returns [`ReplayError::Diverged`] with the frame, both checksums and,
//! when that frame carries body digests, the first body (in slot order)
//! whose digest differs or that exists on one side only. A frame without
//! digests, or a difference outside the bodies (shapes, arbiters,
//! counters), gives `body: None`; [`crate::snapshot::first_difference`]
//! then tells more, given both worlds. Digests are only compared at the
//! diverging frame: they are a diagnosis, not a second check.
use crate::limits::{LimitError, Limits};
use core::borrow::Borrow;
use core::fmt;
use core::marker::PhantomData;
use std::path::Path;

use bincode::config::{Configuration, Fixint, Limit, LittleEndian};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::body::BodyHandle;
use crate::checksum::checksum_of;
use crate::envelope::{self, EnvelopeError};
use crate::math::{Real, Vect};
use crate::snapshot::{self, SnapshotError};
use crate::space::{Space, SpaceError};

/// First bytes of every replay.
pub const MAGIC: [u8; 8] = *b"TAMIASRP";

/// Version of the replay byte layout (bumped whenever it changes).
/// Version 3: the start is the world's snapshot (no scene start), with the
/// replay's `dt`; the input log is digested, per frame and as a whole.
/// Version 4: the same layout, but the checksums and digests it records
/// (and the header's digest) are those of the eight-lane
/// [`checksum`](crate::checksum) function, which replaced the single-lane
/// one: a version 3 replay would not verify, so it is refused by version.
/// Version 5: the same layout, but a frame's inputs are the game's own
/// input type, and the input log digests their encoded bytes (version 4
/// digested [`Input`] lists through `Hash`): a version 4 replay would
/// report an input mismatch at frame 0, so it is refused by version.
pub const FORMAT_VERSION: u32 = 5;

/// Bytes before the payload: magic, version, payload digest.
pub const HEADER_LEN: usize = envelope::HEADER_LEN;

/// Largest payload decoded (1 GiB): a forged length prefix fails instead of
/// making the decoder allocate.
pub const MAX_REPLAY_BYTES: usize = 1 << 30;

type Config = Configuration<LittleEndian, Fixint, Limit<MAX_REPLAY_BYTES>>;

const CONFIG: Config = bincode::config::standard()
    .with_fixed_int_encoding()
    .with_limit::<MAX_REPLAY_BYTES>();

/// An error of a game's step function or of a world's restore.
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

/// One thing a game does to a body before a step.
///
/// Applied in order, before the frame's step, through the [`Body`](crate::body::Body)
/// methods named below. Forces and torques act for that one step (the step
/// clears the accumulators); impulses and velocities change the velocity at
/// once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Input {
    /// `apply_impulse_at_world_point(impulse, point)`.
    Impulse {
        /// The body.
        body: BodyHandle,
        /// Impulse (mass × velocity).
        impulse: Vect,
        /// World point the impulse acts at (the centre of gravity for no spin).
        point: Vect,
    },
    /// `apply_force(force)`: a force at the centre of gravity for one step.
    Force {
        /// The body.
        body: BodyHandle,
        /// Force.
        force: Vect,
    },
    /// `apply_torque(torque)` for one step.
    Torque {
        /// The body.
        body: BodyHandle,
        /// Torque.
        torque: Real,
    },
    /// `set_velocity(velocity)`.
    Velocity {
        /// The body.
        body: BodyHandle,
        /// New linear velocity.
        velocity: Vect,
    },
    /// `set_angular_velocity(w)`.
    AngularVelocity {
        /// The body.
        body: BodyHandle,
        /// New angular velocity (rad/s, counter-clockwise).
        w: Real,
    },
}

impl Input {
    /// The body the input acts on.
    pub fn body(&self) -> BodyHandle {
        match *self {
            Input::Impulse { body, .. }
            | Input::Force { body, .. }
            | Input::Torque { body, .. }
            | Input::Velocity { body, .. }
            | Input::AngularVelocity { body, .. } => body,
        }
    }
}

/// Applies `inputs` to `space` in order. Every body is checked first: if
/// one is missing (stale, or from another space) nothing is applied and the
/// error names it.
pub fn apply_inputs(space: &mut Space, inputs: &[Input]) -> Result<(), SpaceError> {
    if let Some(missing) = inputs.iter().find(|i| space.body(i.body()).is_none()) {
        return Err(SpaceError::StaleBody(missing.body()));
    }
    for input in inputs {
        let Some(b) = space.body_mut(input.body()) else {
            continue; // unreachable: checked above
        };
        // Every field named (no `..`): a field added to an input does not
        // compile until it is applied.
        match *input {
            Input::Impulse {
                body: _,
                impulse,
                point,
            } => b.apply_impulse_at_world_point(impulse, point),
            Input::Force { body: _, force } => b.apply_force(force),
            Input::Torque { body: _, torque } => b.apply_torque(torque),
            Input::Velocity { body: _, velocity } => b.set_velocity(velocity),
            Input::AngularVelocity { body: _, w } => b.set_angular_velocity(w),
        }
    }
    Ok(())
}

/// A world a replay can record and re-run: the engine's [`Space`] plus
/// whatever the game keeps beside it that affects future steps, stepped
/// with inputs of type `I` (by default a list of [`Input`]s; a game's own
/// input type, e.g. a button mask, for a game that decodes its inputs
/// itself).
///
/// [`Space`] itself is one (its step is the default: [`apply_inputs`], then
/// [`Space::step`]); a game with state beside its space (a script, a
/// spawner, a score that changes forces) implements it for its own world
/// type, so that the replay's start holds that state too.
pub trait Simulation<I: ?Sized = [Input]> {
    /// The world's space (its checksum is what each frame records).
    fn space(&self) -> &Space;
    /// The world's snapshot: the replay's start. For a plain space,
    /// [`snapshot::save`] bytes.
    fn save(&self) -> Vec<u8>;
    /// Rolls the world back to `start` (bytes from [`Simulation::save`]),
    /// keeping what the game attached (handlers, callbacks). On error the
    /// world may be left as it was; nothing is stepped.
    fn restore(&mut self, start: &[u8]) -> Result<(), BoxError>;
    /// One frame: the inputs, then the step by `dt`.
    fn advance(&mut self, dt: Real, inputs: &I) -> Result<(), BoxError>;
}

impl Simulation for Space {
    fn space(&self) -> &Space {
        self
    }

    fn save(&self) -> Vec<u8> {
        snapshot::save(self)
    }

    fn restore(&mut self, start: &[u8]) -> Result<(), BoxError> {
        self.load_snapshot(start).map_err(BoxError::from)
    }

    fn advance(&mut self, dt: Real, inputs: &[Input]) -> Result<(), BoxError> {
        apply_inputs(self, inputs)?;
        self.step(dt).map_err(BoxError::from)
    }
}

/// A space driven by the game's own step function, which takes inputs of
/// type `I` (what [`Replay::verify_with`] re-runs).
struct GameStep<'a, F, I: ?Sized> {
    space: &'a mut Space,
    step: F,
    input: PhantomData<fn(&I)>,
}

impl<F, E, I: ?Sized> Simulation<I> for GameStep<'_, F, I>
where
    F: FnMut(&mut Space, &I) -> Result<(), E>,
    E: Into<BoxError>,
{
    fn space(&self) -> &Space {
        self.space
    }

    fn save(&self) -> Vec<u8> {
        snapshot::save(self.space)
    }

    fn restore(&mut self, start: &[u8]) -> Result<(), BoxError> {
        self.space.load_snapshot(start).map_err(BoxError::from)
    }

    fn advance(&mut self, _dt: Real, inputs: &I) -> Result<(), BoxError> {
        (self.step)(self.space, inputs).map_err(Into::into)
    }
}

/// A frame's inputs as the file holds them (the payload's encoding).
fn encode_input<I: Serialize + ?Sized>(input: &I) -> Result<Vec<u8>, ReplayError> {
    bincode::serde::encode_to_vec(input, CONFIG).map_err(|e| ReplayError::Encode(e.to_string()))
}

/// The input-log digest after a frame whose inputs encode to `encoded`,
/// given the digest before it (`0` before the first frame).
fn chain_digest(previous: u64, encoded: &[u8]) -> u64 {
    checksum_of(&(previous, encoded))
}

/// Digest of every body, in slot order: the body entries of
/// [`snapshot::checksum_parts`].
fn body_digests(space: &Space) -> Vec<(BodyHandle, u64)> {
    space
        .bodies()
        .map(|(h, b)| {
            (
                BodyHandle::from_raw_parts(h.index(), h.generation()),
                checksum_of(b),
            )
        })
        .collect()
}

/// The first body (slot order) whose digest differs or that one list lacks.
fn first_body_mismatch(
    expected: &[(BodyHandle, u64)],
    actual: &[(BodyHandle, u64)],
) -> Option<BodyHandle> {
    let (mut e, mut a) = (expected.iter().peekable(), actual.iter().peekable());
    loop {
        match (e.peek(), a.peek()) {
            (None, None) => return None,
            (Some((h, _)), None) | (None, Some((h, _))) => return Some(*h),
            (Some((he, de)), Some((ha, da))) => {
                if he.index() != ha.index() {
                    return Some(if he.index() < ha.index() { *he } else { *ha });
                }
                if he != ha || de != da {
                    return Some(*he);
                }
                e.next();
                a.next();
            }
        }
    }
}

/// One recorded frame, with the game's inputs of type `I` (by default a
/// list of [`Input`]s).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Frame<I = Vec<Input>> {
    /// The frame's inputs, given to the step before it (for [`Input`]
    /// lists: applied in order).
    pub inputs: I,
    /// Digest of the input log up to and including this frame.
    pub input_digest: u64,
    /// [`Space::checksum`] after the step.
    pub checksum: u64,
    /// `(body, digest)` of every body after the step, in slot order, on
    /// frames where the recorder took them.
    pub bodies: Option<Vec<(BodyHandle, u64)>>,
}

/// A recorded run with the game's inputs of type `I` (by default a list of
/// [`Input`]s per frame): plain data, editable (tests tamper with it),
/// checked when verified.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Replay<I = Vec<Input>> {
    /// The start world's snapshot ([`Simulation::save`]).
    pub start: Vec<u8>,
    /// Time step of every frame.
    pub dt: Real,
    /// [`Space::checksum`] of the start, before any frame.
    pub initial_checksum: u64,
    /// Digest of the whole input log (the last frame's
    /// [`Frame::input_digest`], `0` for no frame).
    pub input_digest: u64,
    /// The frames, in order.
    pub frames: Vec<Frame<I>>,
}

/// What a successful verification covered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VerifyReport {
    /// Frames re-run, all checksums equal.
    pub frames: u32,
    /// Checksum after the last frame (the initial one for an empty replay).
    pub final_checksum: u64,
}

/// Why a replay could not be recorded, read or verified.
#[derive(Debug)]
pub enum ReplayError {
    /// Reading or writing a replay file failed.
    Io(std::io::Error),
    /// Shorter than the header ([`HEADER_LEN`] bytes).
    TooShort,
    /// The first bytes are not [`MAGIC`].
    BadMagic,
    /// A format version this build does not read.
    UnsupportedVersion(u32),
    /// The payload's digest is not the one in the header: the bytes were
    /// damaged (truncated, flipped) after writing.
    Corrupt {
        /// Digest in the header.
        stored: u64,
        /// Digest of the payload as read.
        computed: u64,
    },
    /// The payload does not decode (or has trailing bytes).
    Decode(String),
    /// A frame's inputs do not encode, or do not come back the same from
    /// their encoding (a type whose encoding is not a function of its
    /// value, such as a `HashMap`, cannot be digested): the message says
    /// why.
    Encode(String),
    /// `dt` is not positive.
    TimeStep,
    /// The start does not restore (for a plain space: the snapshot does not
    /// load).
    Start(BoxError),
    /// The start restores to another world than recorded.
    StartMismatch {
        /// Recorded checksum.
        expected: u64,
        /// Checksum of the world restored now.
        actual: u64,
    },
    /// The inputs of `frame` are not the ones recorded: the input log's
    /// digest differs from that frame on (the first such frame).
    InputMismatch {
        /// First frame whose input-log digest differs.
        frame: u32,
    },
    /// The frames' inputs all match their digests but the whole log's
    /// digest does not (frames removed or added at the end).
    InputLog {
        /// Recorded digest of the whole log.
        expected: u64,
        /// Digest of the frames present.
        actual: u64,
    },
    /// The step of `frame` failed (for the default step: an input names a
    /// missing body, [`SpaceError::StaleBody`], or the space rejected the
    /// step).
    Step {
        /// The frame.
        frame: u32,
        /// Why.
        error: BoxError,
    },
    /// Frame `frame` ends in a different world than recorded.
    Diverged {
        /// First frame whose checksum differs.
        frame: u32,
        /// First body (slot order) whose digest differs, if the frame has
        /// body digests and a body differs.
        body: Option<BodyHandle>,
        /// Recorded checksum.
        expected: u64,
        /// Checksum computed now.
        actual: u64,
    },
    /// More than `u32::MAX - 1` frames.
    TooManyFrames,
    /// Over one of the [`Limits`] (bytes or frames; the start's own limits
    /// are those of the world it restores into, see [`Replay::verify_on`]).
    OverLimit(LimitError),
}

impl fmt::Display for ReplayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReplayError::Io(e) => write!(f, "replay file: {e}"),
            ReplayError::TooShort => {
                write!(f, "replay is shorter than its {HEADER_LEN}-byte header")
            }
            ReplayError::BadMagic => f.write_str("not a tamias2d replay (bad magic bytes)"),
            ReplayError::UnsupportedVersion(v) => write!(
                f,
                "replay format version {v} is not supported (this build reads {FORMAT_VERSION})"
            ),
            ReplayError::Corrupt { stored, computed } => write!(
                f,
                "replay is corrupted: header digest {stored:#018x}, payload digest {computed:#018x}"
            ),
            ReplayError::Decode(e) => write!(f, "replay does not decode: {e}"),
            ReplayError::Encode(e) => write!(f, "replay inputs do not encode: {e}"),
            ReplayError::TimeStep => f.write_str("replay time step must be > 0"),
            ReplayError::Start(e) => write!(f, "start: {e}"),
            ReplayError::StartMismatch { expected, actual } => write!(
                f,
                "start differs: recorded checksum {expected:#018x}, restored {actual:#018x}"
            ),
            ReplayError::InputMismatch { frame } => {
                write!(
                    f,
                    "frame {frame}: inputs differ from the recorded input log"
                )
            }
            ReplayError::InputLog { expected, actual } => write!(
                f,
                "input log differs (frames removed or added): recorded digest {expected:#018x}, \
                 got {actual:#018x}"
            ),
            ReplayError::Step { frame, error } => write!(f, "frame {frame}: {error}"),
            ReplayError::Diverged {
                frame,
                body,
                expected,
                actual,
            } => {
                write!(
                    f,
                    "diverged at frame {frame}: recorded checksum {expected:#018x}, got {actual:#018x}"
                )?;
                match body {
                    Some(h) => write!(f, "; first differing body {h:?}"),
                    None => Ok(()),
                }
            }
            ReplayError::TooManyFrames => f.write_str("a replay holds at most 2^32 - 1 frames"),
            ReplayError::OverLimit(e) => write!(f, "replay over a limit: {e}"),
        }
    }
}

impl std::error::Error for ReplayError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ReplayError::Io(e) => Some(e),
            ReplayError::Start(e) | ReplayError::Step { error: e, .. } => Some(&**e),
            _ => None,
        }
    }
}

impl From<SnapshotError> for ReplayError {
    fn from(e: SnapshotError) -> ReplayError {
        ReplayError::Start(Box::new(e))
    }
}

/// Records a run the game drives: takes the start world's snapshot, then,
/// after each frame the game stepped, its inputs (of type `I`: by default a
/// list of [`Input`]s, [`Recorder::record_frame`]; a game's own type,
/// [`Recorder::record`]) and the world's checksum.
#[derive(Debug)]
pub struct Recorder<I = Vec<Input>> {
    replay: Replay<I>,
    digest_every: u32,
}

impl<I> Recorder<I> {
    /// Starts a recording of `world` as it is now, to be stepped by `dt`
    /// every frame. Body digests are off; see [`Recorder::with_body_digests`].
    /// The input type `I` follows from what is recorded (or is named:
    /// `Recorder::<Buttons>::new`).
    pub fn new<W: Simulation<B> + ?Sized, B: ?Sized>(world: &W, dt: Real) -> Recorder<I> {
        Recorder {
            replay: Replay {
                start: world.save(),
                dt,
                initial_checksum: world.space().checksum(),
                input_digest: 0,
                frames: Vec::new(),
            },
            digest_every: 0,
        }
    }

    /// Records body digests on frames `0, every, 2·every, …` (`0`: never,
    /// `1`: every frame). Costs one hash per body per such frame and 16
    /// bytes per body in the file.
    pub fn with_body_digests(mut self, every: u32) -> Recorder<I> {
        self.digest_every = every;
        self
    }

    /// Frames recorded so far.
    pub fn frames(&self) -> u32 {
        u32::try_from(self.replay.frames.len()).unwrap_or(u32::MAX)
    }

    /// The recorded replay.
    pub fn finish(self) -> Replay<I> {
        self.replay
    }
}

impl<I: Serialize + DeserializeOwned> Recorder<I> {
    /// Records one frame: `inputs` are the game's inputs of the frame (any
    /// serde type: a button mask, sticks, a list of events, one entry per
    /// player), `world` the world after the game's step. Returns the
    /// frame's checksum.
    ///
    /// The inputs are stored as a file holds them: encoded, digested into
    /// the input log, and decoded back (so a handle loses its origin tag
    /// and the replay verifies on another space, in memory as from bytes).
    /// An input whose encoding does not come back the same is refused
    /// ([`ReplayError::Encode`]) here rather than reported as tampered at
    /// verification.
    pub fn record<W: Simulation<B> + ?Sized, B: ?Sized>(
        &mut self,
        world: &W,
        inputs: &I,
    ) -> Result<u64, ReplayError> {
        let frame =
            u32::try_from(self.replay.frames.len()).map_err(|_| ReplayError::TooManyFrames)?;
        if frame == u32::MAX {
            return Err(ReplayError::TooManyFrames);
        }
        let encoded = encode_input(inputs)?;
        let (stored, read): (I, usize) = bincode::serde::decode_from_slice(&encoded, CONFIG)
            .map_err(|e| ReplayError::Encode(format!("does not decode back: {e}")))?;
        if read != encoded.len() || encode_input(&stored)? != encoded {
            return Err(ReplayError::Encode(
                "the decoded inputs encode differently".to_string(),
            ));
        }
        let input_digest = chain_digest(self.replay.input_digest, &encoded);
        let space = world.space();
        let checksum = space.checksum();
        // `digest_every == 0` (no digests) has no remainder: `None`.
        let digests = frame.checked_rem(self.digest_every) == Some(0);
        self.replay.input_digest = input_digest;
        self.replay.frames.push(Frame {
            inputs: stored,
            input_digest,
            checksum,
            bodies: digests.then(|| body_digests(space)),
        });
        Ok(checksum)
    }
}

impl Recorder {
    /// Records one frame of physics [`Input`]s: `inputs` are what the game
    /// applied, `world` the world after the game's step. Returns the
    /// frame's checksum. [`Recorder::record`] with the list.
    pub fn record_frame<W: Simulation<B> + ?Sized, B: ?Sized>(
        &mut self,
        world: &W,
        inputs: &[Input],
    ) -> Result<u64, ReplayError> {
        self.record(world, &inputs.to_vec())
    }
}

impl<I: Serialize> Replay<I> {
    /// The first frame whose inputs do not match the recorded input log, or
    /// a whole-log mismatch (see [`ReplayError::InputMismatch`] and
    /// [`ReplayError::InputLog`]). Runs nothing.
    pub fn check_inputs(&self) -> Result<(), ReplayError> {
        let mut digest = 0;
        for (frame, recorded) in self.frames.iter().enumerate() {
            let frame = u32::try_from(frame).map_err(|_| ReplayError::TooManyFrames)?;
            // An input that no longer encodes was changed after recording.
            let encoded =
                encode_input(&recorded.inputs).map_err(|_| ReplayError::InputMismatch { frame })?;
            digest = chain_digest(digest, &encoded);
            if digest != recorded.input_digest {
                return Err(ReplayError::InputMismatch { frame });
            }
        }
        if digest != self.input_digest {
            return Err(ReplayError::InputLog {
                expected: self.input_digest,
                actual: digest,
            });
        }
        Ok(())
    }

    /// Verifies by re-running the game's own step on the game's space:
    /// `space` (with the game's handlers attached) is rolled back to the
    /// start in place ([`Space::load_snapshot`]: handlers stay), then
    /// `step(space, inputs)` runs every frame. The step function takes the
    /// frame's inputs by reference, `&I` (for the default [`Input`] lists
    /// also `&[Input]`).
    pub fn verify_with<B, F, E>(
        &self,
        space: &mut Space,
        step: F,
    ) -> Result<VerifyReport, ReplayError>
    where
        B: ?Sized + ToOwned<Owned = I>,
        I: Borrow<B>,
        F: FnMut(&mut Space, &B) -> Result<(), E>,
        E: Into<BoxError>,
    {
        self.verify_on(&mut GameStep {
            space,
            step,
            input: PhantomData,
        })
    }

    /// Verifies on any [`Simulation`] of the replay's input type (`&I`, or
    /// `&[Input]` for the default lists): checks the frame count against
    /// the world's [`Limits`] and the input log, restores `world` to the
    /// start (for a plain space: [`Space::load_snapshot`], under the same
    /// limits), checks its checksum, then advances it frame by frame (each
    /// step bounded by those limits) and checks every frame's checksum; the
    /// first difference is the error.
    pub fn verify_on<W, B>(&self, world: &mut W) -> Result<VerifyReport, ReplayError>
    where
        W: Simulation<B> + ?Sized,
        B: ?Sized + ToOwned<Owned = I>,
        I: Borrow<B>,
    {
        if !self.dt.is_positive() {
            return Err(ReplayError::TimeStep);
        }
        world
            .space()
            .limits()
            .check_replay_frames(self.frames.len())
            .map_err(ReplayError::OverLimit)?;
        self.check_inputs()?;
        world.restore(&self.start).map_err(ReplayError::Start)?;
        let actual = world.space().checksum();
        if actual != self.initial_checksum {
            return Err(ReplayError::StartMismatch {
                expected: self.initial_checksum,
                actual,
            });
        }
        let mut last = actual;
        let mut count = 0u32;
        for (frame, recorded) in self.frames.iter().enumerate() {
            let frame = u32::try_from(frame).map_err(|_| ReplayError::TooManyFrames)?;
            world
                .advance(self.dt, recorded.inputs.borrow())
                .map_err(|error| ReplayError::Step { frame, error })?;
            let space = world.space();
            let actual = space.checksum();
            if actual != recorded.checksum {
                let body = recorded
                    .bodies
                    .as_deref()
                    .and_then(|expected| first_body_mismatch(expected, &body_digests(space)));
                return Err(ReplayError::Diverged {
                    frame,
                    body,
                    expected: recorded.checksum,
                    actual,
                });
            }
            last = actual;
            count = frame.saturating_add(1);
        }
        Ok(VerifyReport {
            frames: count,
            final_checksum: last,
        })
    }

    /// The replay as bytes (see the module docs for the format).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        envelope::begin(&mut out, &MAGIC, FORMAT_VERSION);
        // Encoding plain serde data into a Vec cannot fail; were it to, the
        // payload is left empty and `from_bytes` rejects it as undecodable.
        if bincode::serde::encode_into_std_write(self, &mut out, CONFIG).is_err() {
            out.truncate(HEADER_LEN);
        }
        envelope::seal(&mut out, 0, checksum_of);
        out
    }

    /// Writes [`Replay::to_bytes`] to a file.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), ReplayError> {
        std::fs::write(path, self.to_bytes()).map_err(ReplayError::Io)
    }
}

impl Replay {
    /// Verifies on a new plain [`Space`] with the default step
    /// ([`apply_inputs`], then [`Space::step`] by `dt`): for runs whose step
    /// is exactly that (no handlers, no state beside the space).
    pub fn verify(&self) -> Result<VerifyReport, ReplayError> {
        self.verify_on(&mut Space::new())
    }
}

impl<I: DeserializeOwned> Replay<I> {
    /// A replay from bytes, under [`Limits::UNTRUSTED`]. Checks the header,
    /// the payload digest and the encoding; the content itself is checked
    /// by the verification. The input type is the caller's: the bytes do
    /// not name it (a replay decoded as another type than it was recorded
    /// with fails to decode, or fails its verification). Where nothing
    /// else names it, `<Replay>::from_bytes(bytes)` reads the default
    /// [`Input`] lists.
    pub fn from_bytes(bytes: &[u8]) -> Result<Replay<I>, ReplayError> {
        Replay::from_bytes_with(bytes, &Limits::UNTRUSTED)
    }

    /// [`Replay::from_bytes`] under `limits`: its bytes, its frame count
    /// and its start snapshot's bytes.
    pub fn from_bytes_with(bytes: &[u8], limits: &Limits) -> Result<Replay<I>, ReplayError> {
        limits
            .check_bytes(bytes.len())
            .map_err(ReplayError::OverLimit)?;
        let frame = envelope::open(bytes, &MAGIC, FORMAT_VERSION).map_err(|e| match e {
            EnvelopeError::TooShort => ReplayError::TooShort,
            EnvelopeError::BadMagic => ReplayError::BadMagic,
            EnvelopeError::UnsupportedVersion(v) => ReplayError::UnsupportedVersion(v),
        })?;
        let (stored, payload) = (frame.digest, frame.payload);
        let computed = checksum_of(payload);
        if stored != computed {
            return Err(ReplayError::Corrupt { stored, computed });
        }
        let (replay, read): (Replay<I>, usize) = bincode::serde::decode_from_slice(payload, CONFIG)
            .map_err(|e| ReplayError::Decode(e.to_string()))?;
        let trailing = payload.len().saturating_sub(read);
        if trailing > 0 {
            return Err(ReplayError::Decode(format!(
                "{trailing} bytes after the payload"
            )));
        }
        limits
            .check_replay_frames(replay.frames.len())
            .map_err(ReplayError::OverLimit)?;
        Ok(replay)
    }

    /// Reads a file written by [`Replay::write_file`].
    pub fn read_file(path: impl AsRef<Path>) -> Result<Replay<I>, ReplayError> {
        let bytes = std::fs::read(path).map_err(ReplayError::Io)?;
        Replay::from_bytes(&bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_mismatch_names_the_first_slot_that_differs() {
        let h = |i| BodyHandle::from_raw_parts(i, 0);
        let a = [(h(0), 1), (h(1), 2), (h(3), 3)];
        assert_eq!(first_body_mismatch(&a, &a), None);
        assert_eq!(
            first_body_mismatch(&a, &[(h(0), 1), (h(1), 9), (h(3), 4)]),
            Some(h(1))
        );
        assert_eq!(first_body_mismatch(&a, &[(h(0), 1), (h(2), 2)]), Some(h(1)));
        assert_eq!(first_body_mismatch(&a, &a[..2]), Some(h(3)));
    }
}
