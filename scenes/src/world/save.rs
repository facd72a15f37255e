//! A scripted world as bytes: the engine snapshot and the script beside it.
//!
//! ```text
//! offset  size  content
//!      0     8  magic b"TAMIASSW"
//!      8     4  format version (FORMAT_VERSION), u32 little-endian
//!     12     8  checksum_of the bytes after the header, u64 LE
//!     20     8  length n of the engine snapshot, u64 LE
//!     28     n  the engine snapshot (tamias2d::snapshot format)
//!   28+n     …  the script, JSON (every real an exact decimal string)
//! ```
//! The script holds the time step, the default step count, the steps taken,
//! the body handles in creation order and their labels, the scripted forces,
//! every spawn (those that have happened too, so an in-place rollback to an
//! earlier step spawns them again) with the index of the next one, and each
//! `begin` counter with its count. Loading checks the header and digest, the
//! snapshot (fully validated by the engine), the script's syntax, that every
//! force names a body of the world, that the spawn cursor is in range, and
//! every future spawn's bodies (built into a scratch space); any failure is
//! a [`LoadError`], never a panic.
use core::fmt;
use std::collections::BTreeMap;
use std::sync::atomic::Ordering;
use tamias2d::limits::Limits;

use serde::{Deserialize, Serialize};
use tamias2d::body::BodyHandle;
use tamias2d::checksum::checksum_of;
use tamias2d::envelope::{self, EnvelopeError};
use tamias2d::math::{Real, Vect};
use tamias2d::replay::{apply_inputs, BoxError, Input, Simulation};
use tamias2d::shape::CollisionType;
use tamias2d::snapshot::{self, SnapshotError};
use tamias2d::space::Space;

use super::{add_body, BodyPath, ScriptedWorld};
use crate::dec;
use crate::desc::SpawnDesc;

/// First bytes of a saved scripted world.
pub const MAGIC: [u8; 8] = *b"TAMIASSW";

/// Version of the layout (bumped whenever it changes). Version 2: the same
/// layout, with the header's digest by the eight-lane
/// [`checksum_of`](tamias2d::checksum::checksum_of), which replaced the
/// single-lane one (a version 1 file would fail its digest, so it is
/// refused by version instead).
pub const FORMAT_VERSION: u32 = 2;

/// Bytes before the payload: magic, version, payload digest (the engine's
/// shared file frame, [`tamias2d::envelope`]).
pub const HEADER_LEN: usize = envelope::HEADER_LEN;

/// Why saved bytes do not load as a scripted world.
#[derive(Debug)]
pub enum LoadError {
    /// Shorter than the header and snapshot length.
    TooShort,
    /// The first bytes are not scripted-world magic `TAMIASSW` (a bare engine snapshot starts
    /// with its own magic: load it with `tamias2d::snapshot`).
    BadMagic,
    /// A format version this build does not read.
    UnsupportedVersion(u32),
    /// The payload's digest is not the one in the header.
    Corrupt {
        /// Digest in the header.
        stored: u64,
        /// Digest of the payload as read.
        computed: u64,
    },
    /// The engine snapshot does not load.
    Snapshot(SnapshotError),
    /// The script does not parse.
    Script(String),
    /// The script does not fit the world (a force on a missing body, a
    /// spawn cursor out of range, an invalid spawned body …).
    Invalid(String),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::TooShort => f.write_str("scripted world: shorter than its header"),
            LoadError::BadMagic => f.write_str("not a saved scripted world (bad magic bytes)"),
            LoadError::UnsupportedVersion(v) => write!(
                f,
                "scripted world format version {v} is not supported (this build reads {FORMAT_VERSION})"
            ),
            LoadError::Corrupt { stored, computed } => write!(
                f,
                "scripted world is corrupted: header digest {stored:#018x}, payload digest {computed:#018x}"
            ),
            LoadError::Snapshot(e) => write!(f, "scripted world: {e}"),
            LoadError::Script(e) => write!(f, "scripted world: script does not parse: {e}"),
            LoadError::Invalid(e) => write!(f, "scripted world: {e}"),
        }
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            LoadError::Snapshot(e) => Some(e),
            _ => None,
        }
    }
}

/// A body handle as saved: slot and generation.
type RawHandle = (u32, u32);

fn raw(h: BodyHandle) -> RawHandle {
    (h.index(), h.generation())
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ForceWire {
    body: RawHandle,
    #[serde(with = "dec::vect")]
    force: Vect,
    #[serde(with = "dec::real")]
    torque: Real,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CounterWire {
    type_a: CollisionType,
    type_b: CollisionType,
    count: u64,
}

/// The script as saved.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScriptWire {
    #[serde(with = "dec::real")]
    dt: Real,
    steps: u32,
    steps_taken: u64,
    bodies: Vec<RawHandle>,
    labels: BTreeMap<String, RawHandle>,
    initial_bodies: usize,
    forces: Vec<ForceWire>,
    spawns: Vec<SpawnDesc>,
    next_spawn: usize,
    counters: Vec<CounterWire>,
}

impl ScriptedWorld {
    /// The world and its script as bytes (see the module docs of
    /// `world::save` for the layout).
    pub fn save(&self) -> Vec<u8> {
        let script = ScriptWire {
            dt: self.dt,
            steps: self.steps,
            steps_taken: self.steps_taken,
            bodies: self.bodies.iter().copied().map(raw).collect(),
            labels: self
                .labels
                .iter()
                .map(|(l, &h)| (l.clone(), raw(h)))
                .collect(),
            initial_bodies: self.initial_bodies,
            forces: self
                .forces
                .iter()
                .map(|&(h, force, torque)| ForceWire {
                    body: raw(h),
                    force,
                    torque,
                })
                .collect(),
            spawns: self.spawns.clone(),
            next_spawn: self.next_spawn,
            counters: self
                .counters
                .iter()
                .map(|c| CounterWire {
                    type_a: c.types.0,
                    type_b: c.types.1,
                    count: c.count.load(Ordering::Relaxed),
                })
                .collect(),
        };
        let snapshot = snapshot::save(&self.space);
        // Plain data with string keys: serializing to a Vec cannot fail;
        // were it to, the script is left empty and `load` rejects it.
        let script = serde_json::to_vec(&script).unwrap_or_default();
        let mut out = Vec::with_capacity(
            HEADER_LEN
                .saturating_add(8)
                .saturating_add(snapshot.len())
                .saturating_add(script.len()),
        );
        envelope::begin(&mut out, &MAGIC, FORMAT_VERSION);
        out.extend_from_slice(
            &u64::try_from(snapshot.len())
                .unwrap_or(u64::MAX)
                .to_le_bytes(),
        );
        out.extend_from_slice(&snapshot);
        out.extend_from_slice(&script);
        envelope::seal(&mut out, 0, checksum_of);
        out
    }

    /// A world from [`ScriptedWorld::save`] bytes, continuing exactly where
    /// the saved one was (script included).
    pub fn load(bytes: &[u8]) -> Result<ScriptedWorld, LoadError> {
        ScriptedWorld::load_with(bytes, &Limits::UNTRUSTED)
    }

    /// [`ScriptedWorld::load`] under `limits` (see `tamias2d::limits`),
    /// which the world's space keeps for its step and later loads.
    pub fn load_with(bytes: &[u8], limits: &Limits) -> Result<ScriptedWorld, LoadError> {
        let mut world = ScriptedWorld::empty();
        world.space.set_limits(*limits);
        world.load_in_place(bytes)?;
        Ok(world)
    }

    /// Replaces this world's state and script by the saved ones, in place:
    /// handlers the game attached to the space stay (as with
    /// [`Space::load_snapshot`]); the `begin` counters take the saved
    /// counts. On error nothing changes.
    pub fn load_in_place(&mut self, bytes: &[u8]) -> Result<(), LoadError> {
        let frame = envelope::open(bytes, &MAGIC, FORMAT_VERSION).map_err(|e| match e {
            EnvelopeError::TooShort => LoadError::TooShort,
            EnvelopeError::BadMagic => LoadError::BadMagic,
            EnvelopeError::UnsupportedVersion(v) => LoadError::UnsupportedVersion(v),
        })?;
        let (stored, payload) = (frame.digest, frame.payload);
        let computed = checksum_of(payload);
        if stored != computed {
            return Err(LoadError::Corrupt { stored, computed });
        }
        let len = payload
            .get(0..8)
            .and_then(|b| b.try_into().ok())
            .map(u64::from_le_bytes)
            .ok_or(LoadError::TooShort)?;
        let rest = payload.get(8..).unwrap_or(&[]);
        let split = usize::try_from(len)
            .ok()
            .filter(|&n| n <= rest.len())
            .ok_or(LoadError::TooShort)?;
        let (snap, script) = rest.split_at(split);
        let script: ScriptWire =
            serde_json::from_slice(script).map_err(|e| LoadError::Script(e.to_string()))?;
        let state =
            snapshot::decode_state_with(snap, self.space.limits()).map_err(LoadError::Snapshot)?;
        // Checked against a scratch world first, so that an error leaves
        // `self` untouched.
        let scratch = Space::from_state(state.clone());
        check_script(&scratch, &script)?;
        self.space.restore_state(&state);
        let live: BTreeMap<RawHandle, BodyHandle> =
            self.space.bodies().map(|(h, _)| (raw(h), h)).collect();
        // A live body gets the space's own (tagged) handle; a removed one
        // stays an untagged handle that resolves to nothing.
        let tag = |h: RawHandle| {
            live.get(&h)
                .copied()
                .unwrap_or_else(|| BodyHandle::from_raw_parts(h.0, h.1))
        };
        self.dt = script.dt;
        self.steps = script.steps;
        self.steps_taken = script.steps_taken;
        self.bodies = script.bodies.iter().map(|&h| tag(h)).collect();
        self.labels = script
            .labels
            .iter()
            .map(|(l, &h)| (l.clone(), tag(h)))
            .collect();
        self.initial_bodies = script.initial_bodies;
        self.forces = script
            .forces
            .iter()
            .map(|f| (tag(f.body), f.force, f.torque))
            .collect();
        self.spawns = script.spawns;
        self.next_spawn = script.next_spawn;
        for c in &script.counters {
            self.add_counter(c.type_a, c.type_b);
            if let Some(counter) = self
                .counters
                .iter()
                .find(|k| k.types == (c.type_a, c.type_b) || k.types == (c.type_b, c.type_a))
            {
                counter.count.store(c.count, Ordering::Relaxed);
            }
        }
        Ok(())
    }

    /// Whether `bytes` start like a saved scripted world (its magic); a
    /// bare engine snapshot does not.
    pub fn is_saved(bytes: &[u8]) -> bool {
        bytes.get(0..8) == Some(&MAGIC[..])
    }

    /// A world with nothing in it and no script (what [`ScriptedWorld::load`]
    /// fills in).
    fn empty() -> ScriptedWorld {
        ScriptedWorld {
            space: Space::new(),
            dt: Real::ONE,
            steps: 0,
            bodies: Vec::new(),
            labels: BTreeMap::new(),
            forces: Vec::new(),
            spawns: Vec::new(),
            next_spawn: 0,
            initial_bodies: 0,
            counters: Vec::new(),
            steps_taken: 0,
        }
    }
}

/// Checks the script against the world it was saved with.
fn check_script(space: &Space, script: &ScriptWire) -> Result<(), LoadError> {
    if !script.dt.is_positive() {
        return Err(LoadError::Invalid("time step must be > 0".to_owned()));
    }
    for (i, f) in script.forces.iter().enumerate() {
        let h = BodyHandle::from_raw_parts(f.body.0, f.body.1);
        if space.body(h).is_none() {
            return Err(LoadError::Invalid(format!(
                "forces[{i}] names body {:?}, which the world does not have",
                f.body
            )));
        }
    }
    if script.next_spawn > script.spawns.len() {
        return Err(LoadError::Invalid(format!(
            "next spawn {} of {} spawns",
            script.next_spawn,
            script.spawns.len()
        )));
    }
    if script.initial_bodies > script.bodies.len() {
        return Err(LoadError::Invalid(format!(
            "{} initial bodies of {} bodies",
            script.initial_bodies,
            script.bodies.len()
        )));
    }
    if script
        .spawns
        .windows(2)
        .any(|w| matches!(w, [a, b] if a.at_step > b.at_step))
    {
        return Err(LoadError::Invalid(
            "spawns are not in step order".to_owned(),
        ));
    }
    for (s, spawn) in script.spawns.iter().enumerate() {
        let mut scratch = Space::new();
        for (i, body) in spawn.bodies.iter().enumerate() {
            add_body(&mut scratch, body, BodyPath::Spawn { spawn: s, index: i })
                .map_err(|e| LoadError::Invalid(e.to_string()))?;
        }
    }
    Ok(())
}

/// A scripted world's frame: the inputs, then [`ScriptedWorld::step`]
/// (scripted forces, the step by `dt`, due spawns). Its start is
/// [`ScriptedWorld::save`], so a replay of a scene holds its script.
impl Simulation for ScriptedWorld {
    fn space(&self) -> &Space {
        &self.space
    }

    fn save(&self) -> Vec<u8> {
        ScriptedWorld::save(self)
    }

    fn restore(&mut self, start: &[u8]) -> Result<(), BoxError> {
        self.load_in_place(start).map_err(BoxError::from)
    }

    fn advance(&mut self, dt: Real, inputs: &[Input]) -> Result<(), BoxError> {
        apply_inputs(&mut self.space, inputs)?;
        self.step_by(dt).map_err(BoxError::from)
    }
}
