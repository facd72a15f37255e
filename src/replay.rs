//! Replays: record a run (start, inputs, per-frame checksums) and verify it
//! frame by frame.
//!
//! A lockstep or rollback game is a pure function of its start and its
//! inputs. A [`Replay`] stores exactly that, plus the checksum of the world
//! after every frame, so that re-running it proves (or disproves) that this
//! build, on this machine, computes the same bits as the one that recorded
//! it. Optionally it also stores a digest of every body on every `K`-th
//! frame, so a divergence names the first body that differs.
//!
//! ```
//! use tamias2d::replay::{Input, Recorder, Replay, Start};
//! use tamias2d::Vect;
//!
//! let start = Start::builtin("elastic_pair").expect("listed scene");
//! let mut rec = Recorder::new(start)?.with_body_digests(1);
//! let ball = rec.body("b").expect("labelled body");
//! for frame in 0..30 {
//!     let push = Input::Force { body: ball, force: Vect::from_ints(0, 5) };
//!     let inputs = if frame == 10 { vec![push] } else { vec![] };
//!     rec.record_frame(&inputs)?;
//! }
//! let bytes = rec.finish().to_bytes();
//! let report = Replay::from_bytes(&bytes)?.verify()?;
//! assert_eq!(report.frames, 30);
//! # Ok::<(), tamias2d::replay::ReplayError>(())
//! ```
//!
//! # Frames
//! Frame `f` (0-based) takes the world after `f` steps, applies
//! `frames[f].inputs` in order, steps once and records the checksum
//! ([`Space::checksum`]) of the result. A scene start steps with
//! [`Scene::step`] (its scripted forces and spawns run, as in a plain run of
//! the scene); a snapshot start steps the space by the replay's `dt`.
//!
//! # Inputs
//! [`Input`] is a small closed set of what a game does to bodies between
//! steps (impulse, force, torque, velocity, angular velocity). A body is
//! named by slot and generation only (a handle's origin tag is not
//! recorded), so the handles of the recording world work in the verifying
//! one. **An input naming a body that does not exist is an error**
//! ([`ReplayError::MissingBody`]), both when recording (the frame is then
//! not recorded and the world is unchanged: all inputs are checked before
//! any is applied) and when verifying. Silently ignoring it would let a
//! game bug (an input for a removed body) hide in a replay that still
//! "verifies".
//!
//! # File format (version [`FORMAT_VERSION`])
//! ```text
//! offset  size  content
//!      0     8  magic b"TAMIASRP"
//!      8     4  format version, u32 little-endian
//!     12     8  digest of the payload bytes (checksum::checksum_of), u64 LE
//!     20     …  payload: bincode 2 (serde), standard config with fixed-int
//!               encoding, limit MAX_REPLAY_BYTES:
//!               (start, initial checksum, frames)
//! ```
//! `start` is one of: a built-in scene name with its `dt`; a whole
//! [`SceneDesc`] (in a bincode-friendly mirror, every `Real` as raw bits);
//! or snapshot bytes ([`crate::snapshot`] format) with a `dt`. Each frame is
//! its inputs, its checksum and optionally `(body handle, digest)` pairs in
//! slot order. The payload must end exactly at the end of the bytes.
//! Malformed bytes are an error, never a panic: short or foreign header,
//! unknown version, a payload digest that does not match (corruption is
//! reported as such, not as a divergence), bytes that do not decode,
//! trailing bytes.
//!
//! # What a divergence reports
//! [`Replay::verify`] stops at the first frame whose checksum differs and
//! returns [`ReplayError::Diverged`] with the frame, both checksums and,
//! when that frame carries body digests, the first body (in slot order)
//! whose digest differs or that exists on one side only. A frame without
//! digests, or a difference outside the bodies (shapes, arbiters,
//! counters), gives `body: None`; [`crate::snapshot::first_difference`]
//! then tells more, given both worlds. Digests are only compared at the
//! diverging frame: they are a diagnosis, not a second check.
use core::fmt;
use std::path::Path;

use bincode::config::{Configuration, Fixint, Limit, LittleEndian};
use serde::{Deserialize, Serialize};

use crate::body::BodyHandle;
use crate::checksum::checksum_of;
use crate::math::{Real, Vect};
use crate::scenes::{self, Scene, SceneDesc, SceneError};
use crate::snapshot::{self, SnapshotError};
use crate::space::{Space, SpaceError};

mod desc_wire;

use desc_wire::WireScene;

/// First bytes of every replay.
pub const MAGIC: [u8; 8] = *b"TAMIASRP";

/// Version of the replay byte layout (bumped whenever it changes).
/// Version 2: the scene settings gained `substeps` and the solver switches,
/// and embedded snapshots are snapshot format 2.
pub const FORMAT_VERSION: u32 = 2;

/// Bytes before the payload: magic, version, payload digest.
pub const HEADER_LEN: usize = 20;

/// Largest payload decoded (1 GiB): a forged length prefix fails instead of
/// making the decoder allocate.
pub const MAX_REPLAY_BYTES: usize = 1 << 30;

type Config = Configuration<LittleEndian, Fixint, Limit<MAX_REPLAY_BYTES>>;

const CONFIG: Config = bincode::config::standard()
    .with_fixed_int_encoding()
    .with_limit::<MAX_REPLAY_BYTES>();

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

    /// The same input with the body handle reduced to slot and generation
    /// (the form replays store; accepted by every space).
    fn portable(self) -> Input {
        let raw = |h: BodyHandle| BodyHandle::from_raw_parts(h.index(), h.generation());
        match self {
            Input::Impulse {
                body,
                impulse,
                point,
            } => Input::Impulse {
                body: raw(body),
                impulse,
                point,
            },
            Input::Force { body, force } => Input::Force {
                body: raw(body),
                force,
            },
            Input::Torque { body, torque } => Input::Torque {
                body: raw(body),
                torque,
            },
            Input::Velocity { body, velocity } => Input::Velocity {
                body: raw(body),
                velocity,
            },
            Input::AngularVelocity { body, w } => Input::AngularVelocity { body: raw(body), w },
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

/// Where a replay starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Start {
    /// A built-in scene ([`scenes::builtin`]) stepped by `dt` (recorded, so a
    /// later change of the scene's default step does not break old replays).
    Builtin {
        /// Registry name.
        name: String,
        /// Time step.
        dt: Real,
    },
    /// A scene description, stepped by its own `dt`.
    Scene(Box<SceneDesc>),
    /// A snapshot ([`snapshot::save`] bytes), stepped by `dt`.
    Snapshot {
        /// The snapshot.
        bytes: Vec<u8>,
        /// Time step.
        dt: Real,
    },
}

impl Start {
    /// The built-in scene `name` with its own time step, or `None` if there
    /// is no such scene.
    pub fn builtin(name: &str) -> Option<Start> {
        let desc = scenes::builtin(name)?;
        Some(Start::Builtin {
            name: name.to_owned(),
            dt: desc.dt,
        })
    }

    /// The time step of every frame.
    pub fn dt(&self) -> Real {
        match self {
            Start::Builtin { dt, .. } | Start::Snapshot { dt, .. } => *dt,
            Start::Scene(desc) => desc.dt,
        }
    }

    /// The world at frame 0.
    fn build(&self) -> Result<Sim, ReplayError> {
        let scene = |desc: &SceneDesc, dt: Real| -> Result<Sim, ReplayError> {
            let mut scene = desc.build().map_err(ReplayError::Scene)?;
            scene.dt = dt;
            Ok(Sim::Scene(scene))
        };
        if !self.dt().is_positive() {
            return Err(ReplayError::Scene(SceneError::TimeStep));
        }
        match self {
            Start::Builtin { name, dt } => {
                let desc =
                    scenes::builtin(name).ok_or_else(|| ReplayError::UnknownScene(name.clone()))?;
                scene(&desc, *dt)
            }
            Start::Scene(desc) => scene(desc, desc.dt),
            Start::Snapshot { bytes, dt } => {
                let space = snapshot::load(bytes).map_err(ReplayError::Snapshot)?;
                Ok(Sim::Space { space, dt: *dt })
            }
        }
    }
}

/// The running world of a recording or a verification.
enum Sim {
    Scene(Scene),
    Space { space: Space, dt: Real },
}

impl Sim {
    fn space(&self) -> &Space {
        match self {
            Sim::Scene(scene) => &scene.space,
            Sim::Space { space, .. } => space,
        }
    }

    /// One frame: inputs, then the step. `frame` only labels errors.
    fn advance(&mut self, frame: u32, inputs: &[Input]) -> Result<(), ReplayError> {
        let space = match self {
            Sim::Scene(scene) => &mut scene.space,
            Sim::Space { space, .. } => space,
        };
        apply_inputs(space, inputs).map_err(|e| match e {
            SpaceError::StaleBody(body) => ReplayError::MissingBody { frame, body },
            other => ReplayError::Step {
                frame,
                error: SceneError::Step(other),
            },
        })?;
        let stepped = match self {
            Sim::Scene(scene) => scene.step(),
            Sim::Space { space, dt } => space.step(*dt).map_err(SceneError::Step),
        };
        stepped.map_err(|error| ReplayError::Step { frame, error })
    }
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

/// One recorded frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Frame {
    /// Inputs applied before the step, in order.
    pub inputs: Vec<Input>,
    /// [`Space::checksum`] after the step.
    pub checksum: u64,
    /// `(body, digest)` of every body after the step, in slot order, on
    /// frames where the recorder took them.
    pub bodies: Option<Vec<(BodyHandle, u64)>>,
}

/// A recorded run: plain data, editable (tests tamper with it), checked
/// when verified.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Replay {
    /// Where the run starts.
    pub start: Start,
    /// [`Space::checksum`] of the start, before any frame.
    pub initial_checksum: u64,
    /// The frames, in order.
    pub frames: Vec<Frame>,
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
    /// The start names a built-in scene that does not exist.
    UnknownScene(String),
    /// The start scene does not build, or its `dt` is not positive.
    Scene(SceneError),
    /// The start snapshot does not load.
    Snapshot(SnapshotError),
    /// The start does not build to the recorded world.
    StartMismatch {
        /// Recorded checksum.
        expected: u64,
        /// Checksum of the world built now.
        actual: u64,
    },
    /// An input of `frame` names a body the world does not have.
    MissingBody {
        /// Frame of the input.
        frame: u32,
        /// The body named.
        body: BodyHandle,
    },
    /// The step of `frame` failed.
    Step {
        /// The frame.
        frame: u32,
        /// Why.
        error: SceneError,
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
    /// More than `u32::MAX` frames.
    TooManyFrames,
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
            ReplayError::UnknownScene(name) => write!(f, "unknown built-in scene {name:?}"),
            ReplayError::Scene(e) => write!(f, "start scene: {e}"),
            ReplayError::Snapshot(e) => write!(f, "start snapshot: {e}"),
            ReplayError::StartMismatch { expected, actual } => write!(
                f,
                "start differs: recorded checksum {expected:#018x}, built {actual:#018x}"
            ),
            ReplayError::MissingBody { frame, body } => {
                write!(f, "frame {frame}: input names missing body {body:?}")
            }
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
        }
    }
}

impl std::error::Error for ReplayError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ReplayError::Io(e) => Some(e),
            ReplayError::Scene(e) | ReplayError::Step { error: e, .. } => Some(e),
            ReplayError::Snapshot(e) => Some(e),
            _ => None,
        }
    }
}

/// Records a run: owns the world, applies each frame's inputs, steps, and
/// keeps inputs and checksums.
pub struct Recorder {
    sim: Sim,
    replay: Replay,
    digest_every: u32,
}

impl fmt::Debug for Recorder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Recorder")
            .field("frames", &self.replay.frames.len())
            .field("digest_every", &self.digest_every)
            .finish_non_exhaustive()
    }
}

impl Recorder {
    /// Builds the start world (errors as [`Replay::verify`] would report
    /// them). Body digests are off; see [`Recorder::with_body_digests`].
    pub fn new(start: Start) -> Result<Recorder, ReplayError> {
        let sim = start.build()?;
        let initial_checksum = sim.space().checksum();
        Ok(Recorder {
            sim,
            replay: Replay {
                start,
                initial_checksum,
                frames: Vec::new(),
            },
            digest_every: 0,
        })
    }

    /// Records body digests on frames `0, every, 2·every, …` (`0`: never,
    /// `1`: every frame). Costs one hash per body per such frame and 16
    /// bytes per body in the file.
    pub fn with_body_digests(mut self, every: u32) -> Recorder {
        self.digest_every = every;
        self
    }

    /// The world as it is now (after [`frames`](Recorder::frames) frames).
    pub fn space(&self) -> &Space {
        self.sim.space()
    }

    /// The handle of the start scene's body labelled `label` (`None` for a
    /// snapshot start or an unknown label).
    pub fn body(&self, label: &str) -> Option<BodyHandle> {
        match &self.sim {
            Sim::Scene(scene) => scene.body(label),
            Sim::Space { .. } => None,
        }
    }

    /// Frames recorded so far.
    pub fn frames(&self) -> u32 {
        u32::try_from(self.replay.frames.len()).unwrap_or(u32::MAX)
    }

    /// Applies `inputs`, steps, records the frame and returns its checksum.
    /// On error nothing is recorded; a [`ReplayError::MissingBody`] also
    /// leaves the world untouched.
    pub fn record_frame(&mut self, inputs: &[Input]) -> Result<u64, ReplayError> {
        let frame =
            u32::try_from(self.replay.frames.len()).map_err(|_| ReplayError::TooManyFrames)?;
        if frame == u32::MAX {
            return Err(ReplayError::TooManyFrames);
        }
        let inputs: Vec<Input> = inputs.iter().map(|i| i.portable()).collect();
        self.sim.advance(frame, &inputs)?;
        let space = self.sim.space();
        let checksum = space.checksum();
        // `digest_every == 0` (no digests) has no remainder: `None`.
        let digests = frame.checked_rem(self.digest_every) == Some(0);
        self.replay.frames.push(Frame {
            inputs,
            checksum,
            bodies: digests.then(|| body_digests(space)),
        });
        Ok(checksum)
    }

    /// The recorded replay.
    pub fn finish(self) -> Replay {
        self.replay
    }
}

/// The start as stored: scene descriptions in their bincode mirror.
#[derive(Serialize, Deserialize)]
enum WireStart {
    Builtin { name: String, dt: Real },
    Scene(WireScene),
    Snapshot { bytes: Vec<u8>, dt: Real },
}

impl Replay {
    /// Re-runs the replay from its start and checks the start and every
    /// frame's checksum; the first difference is the error.
    pub fn verify(&self) -> Result<VerifyReport, ReplayError> {
        let mut sim = self.start.build()?;
        let actual = sim.space().checksum();
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
            sim.advance(frame, &recorded.inputs)?;
            let actual = sim.space().checksum();
            if actual != recorded.checksum {
                let body = recorded
                    .bodies
                    .as_deref()
                    .and_then(|expected| first_body_mismatch(expected, &body_digests(sim.space())));
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
        let start = match &self.start {
            Start::Builtin { name, dt } => WireStart::Builtin {
                name: name.clone(),
                dt: *dt,
            },
            Start::Scene(desc) => WireStart::Scene(WireScene::from(&**desc)),
            Start::Snapshot { bytes, dt } => WireStart::Snapshot {
                bytes: bytes.clone(),
                dt: *dt,
            },
        };
        let mut out = Vec::new();
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&[0; 8]); // payload digest, filled in below
        let payload = (&start, self.initial_checksum, &self.frames);
        // Encoding plain serde data into a Vec cannot fail; were it to, the
        // payload is left empty and `from_bytes` rejects it as undecodable.
        if bincode::serde::encode_into_std_write(payload, &mut out, CONFIG).is_err() {
            out.truncate(HEADER_LEN);
        }
        let digest = checksum_of(out.get(HEADER_LEN..).unwrap_or(&[]));
        if let Some(slot) = out.get_mut(12..HEADER_LEN) {
            slot.copy_from_slice(&digest.to_le_bytes());
        }
        out
    }

    /// A replay from bytes. Checks the header, the payload digest and the
    /// encoding; the content itself is checked by [`Replay::verify`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Replay, ReplayError> {
        let (Some(magic), Some(version), Some(stored), Some(payload)) = (
            bytes.get(0..8),
            bytes.get(8..12),
            bytes.get(12..HEADER_LEN),
            bytes.get(HEADER_LEN..),
        ) else {
            return Err(ReplayError::TooShort);
        };
        if magic != MAGIC {
            return Err(ReplayError::BadMagic);
        }
        let version = u32::from_le_bytes(version.try_into().unwrap_or([0; 4]));
        if version != FORMAT_VERSION {
            return Err(ReplayError::UnsupportedVersion(version));
        }
        let stored = u64::from_le_bytes(stored.try_into().unwrap_or([0; 8]));
        let computed = checksum_of(payload);
        if stored != computed {
            return Err(ReplayError::Corrupt { stored, computed });
        }
        let ((start, initial_checksum, frames), read): ((WireStart, u64, Vec<Frame>), usize) =
            bincode::serde::decode_from_slice(payload, CONFIG)
                .map_err(|e| ReplayError::Decode(e.to_string()))?;
        let trailing = payload.len().saturating_sub(read);
        if trailing > 0 {
            return Err(ReplayError::Decode(format!(
                "{trailing} bytes after the payload"
            )));
        }
        let start = match start {
            WireStart::Builtin { name, dt } => Start::Builtin { name, dt },
            WireStart::Scene(w) => Start::Scene(Box::new(SceneDesc::from(w))),
            WireStart::Snapshot { bytes, dt } => Start::Snapshot { bytes, dt },
        };
        Ok(Replay {
            start,
            initial_checksum,
            frames,
        })
    }

    /// Writes [`Replay::to_bytes`] to a file.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), ReplayError> {
        std::fs::write(path, self.to_bytes()).map_err(ReplayError::Io)
    }

    /// Reads a file written by [`Replay::write_file`].
    pub fn read_file(path: impl AsRef<Path>) -> Result<Replay, ReplayError> {
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
