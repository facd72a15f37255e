//! Snapshots: the whole simulation state as bytes, and back.
//!
//! A lockstep or rollback game saves the world every frame (or keeps
//! in-memory copies), sends snapshots to late joiners, and compares
//! checksums to catch a desync the moment it happens. This module is the
//! byte form of [`WorldState`]; the in-memory rollback fast path needs no
//! bytes at all (see "Two ways to roll back" below).
//!
//! # API
//! * [`save`] / [`save_into`]: the state of a [`Space`] as bytes
//!   (`save_into` reuses the caller's buffer, so a per-frame save does not
//!   allocate once the buffer has grown).
//! * [`load`]: a fresh [`Space`] from bytes, after full validation.
//! * [`Space::load_snapshot`]: replaces a live world's state in place, after
//!   full validation, keeping its handlers, integrators and handle origin
//!   (pending post-step callbacks are discarded).
//!   On error the world is untouched (byte-identical).
//! * [`decode_state`]: the validated [`WorldState`] alone; [`header`]: the
//!   format version and checksum without decoding the body.
//! * [`checksum_parts`] and [`first_difference`]: what differs between two
//!   worlds, for desync reports.
//!
//! # Format (version [`FORMAT_VERSION`])
//! ```text
//! offset  size  content
//!      0     8  magic b"TAMIAS2D"
//!      8     4  format version, u32 little-endian
//!     12     8  checksum of the payload bytes (payload_checksum), u64 LE
//!     20     …  the WorldState, bincode 2 (serde), standard config with
//!               fixed-int encoding: little-endian on every target, every
//!               Real as its 8 raw bytes, lengths as u64, enum tags as u32
//! ```
//! The payload must end exactly at the end of the buffer. Its layout is
//! serde's form of [`WorldState`] field by field (settings, body arena,
//! shape arena, arbiters, stamp, current and previous `dt`, constraint
//! arena, dormant arbiters of sleeping islands); each arena is its slots
//! (generation, optional value), its free list and its length. A
//! constraint is its two body handles, `max_force`, `error_bias`,
//! `max_bias`, `collide_bodies` (one byte), its kind (a u32 tag, then
//! the kind's parameters and accumulated impulse) and its soft-step
//! `softness` (an option byte, then hertz and damping ratio).
//!
//! Bodies, shapes (and their geometry) and arbiters have a **compact
//! form** (since version 6; their `Serialize` impls give it to every
//! binary serializer, so any container encoding them with this
//! configuration gets it too): a tuple of a `u32` head, holding the
//! object's flags and small enums and a *presence mask* with one bit per
//! `Real` word, a few fixed integers, then only the words that are not
//! zero, raw; a body's or an arbiter's head may announce a *narrow mask*
//! (`u32`) of the present words whose raw value fits an `i32` (|x| < 0.5:
//! velocities, small angles, depths, impulses), written in 4 bytes, the
//! others in 8 (shape and geometry words always in 8):
//! ```text
//! body     head (mask of 19 words; type, explicit mass, sleep allowed,
//!          bullet, asleep, narrow), [narrow mask u32], [island root
//!          u32], words: mass, moment, cog,
//!          p, v, f, a, rot, w, t, v_bias, w_bias, idle time
//! shape    head (mask of 5 words; mass spec kind, sensor, filter and
//!          collision type stored), body handle, [filter 3×u32],
//!          [collision type u32], words: friction, elasticity, surface
//!          velocity, mass or density; then the geometry:
//!          head (kind, polygon count and form, mask), words: circle
//!          offset, radius | segment a, b, radius, tangents | polygon
//!          the used vertices, radius (a rectangle: l, b, r, t, radius;
//!          a centred one: r, t, radius)
//! arbiter  head (count, state, sensor, mask of 6 + 7 per contact words,
//!          narrow), [narrow mask u32], shapes, bodies (4 handles), warm-start id u32, stamp u64, a
//!          feature id u32 per contact, words: normal, restitution,
//!          friction, surface velocity, then r1, r2, dist, jn_acc, jt_acc
//!          per contact
//! ```
//! Not stored, because each is a pure function of what is: a body's
//! inverse mass and moment, a segment's normal, a polygon's normals and
//! unused vertex slots, an arbiter's contact slots past its count. Decoding
//! recomputes them exactly as the engine does (`recip` or 0; the
//! constructors' normals; zeros). The encoding is canonical: a word marked
//! present must not be zero, a body's or arbiter's word written in 8 bytes
//! must not fit 4, a narrow mask must not be empty or name an absent word,
//! head bits without a meaning must be clear, a
//! polygon has at most 8 vertices and an arbiter at most 2 contacts;
//! anything else is a [`SnapshotError::Decode`]. Human-readable
//! serializers (JSON) get every field instead, as a serde derive would
//! (tests and tools edit that form).
//!
//! Any change of the layout changes the bytes and must bump
//! [`FORMAT_VERSION`]; a test pins the empty world's bytes field by field
//! and the encoded size of each kind of object, so that the change cannot
//! go unnoticed.
//!
//! The header checksum covers the payload *bytes*: it catches corruption
//! that still decodes to a valid world (a flipped bit in a velocity) —
//! any one changed 8-byte word is always detected — at a small fraction of
//! the cost of [`Space::checksum`], which walks the state field by field.
//! It is not the world checksum (call [`Space::checksum`] for desync
//! checks), and no defence against a forger, which validation is.
//!
//! # What `load` checks
//! Nothing is trusted and nothing panics, whatever the bytes. In this
//! order, the first failure being reported: length, magic, version;
//! decoding (with a size limit, [`MAX_SNAPSHOT_BYTES`]; a forged length
//! prefix fails at the end of the data instead of allocating, see there);
//! trailing bytes; the payload checksum; then every invariant of
//! [`validate_state`]:
//! * settings in the ranges `Space::set_settings` enforces;
//! * step stamp and time steps consistent (`dt` 0 before the first step,
//!   positive after);
//! * both arenas: the free list names each empty slot exactly once and no
//!   live slot, and the length counts the live ones;
//! * bodies: mass and moment ≥ 0, inverse mass and moment exactly what the
//!   engine computes (`recip`, 0 for 0: true by construction for a decoded
//!   body, which does not store them), kinematic and static bodies
//!   massless, rotation of unit length within 2^-20;
//! * shapes: the body handle names a live body (generation included);
//!   radii ≥ 0; segment normals exactly those of the endpoints; polygons of
//!   3..=8 vertices, strictly convex and counter-clockwise, with exactly the
//!   normals the constructor computes (normals: by construction when
//!   decoded); mass and density ≥ 0; friction ≥ 0 and elasticity in
//!   [0, 1];
//! * arbiters: strictly increasing `(shape a, shape b)` slot order, both
//!   shapes live, the bodies those of the shapes (two different bodies, one
//!   of them dynamic), 1..=2 contacts with non-negative accumulated normal
//!   impulse and cleared slots past them (by construction when decoded),
//!   stamp in `1..=world stamp`, and a
//!   state that fits the stamp
//!   (`Cached` exactly when the pair did not touch in the last step, never
//!   `FirstCollision`, which only exists inside a step);
//! * constraints: the arena as above; two different live bodies (a
//!   constraint on a missing body is invalid); `max_force` and `max_bias`
//!   ≥ 0, `error_bias` in `[0, 1]`; the kind's parameters as its
//!   constructor checks them (lengths, stiffness and damping ≥ 0, a pin's
//!   distance > 0, a gear's ratio ≠ 0, nothing saturated).
//!
//! Only then is the state handed out. Errors are [`SnapshotError`]s that
//! say what is wrong.
//!
//! Validation accepts exactly what the API can produce that can step, no
//! less: a valid snapshot can still be expensive. Solver iterations are
//! capped at [`MAX_ITERATIONS`](crate::space::MAX_ITERATIONS), and then the
//! [`Limits`] bound what a valid world may ask of the receiver (bodies,
//! shapes, solver passes, candidate pairs, bytes): [`load`] and
//! [`decode_state`] apply [`Limits::UNTRUSTED`], [`load_with`] and
//! [`decode_state_with`] the caller's, [`Space::load_snapshot`] the
//! space's own ([`Space::set_limits`]).
//!
//! # Validation as a contract
//! [`validate_state`] is the one statement of what a world state is:
//! * **Every state the API produces passes it**, between any two calls: the
//!   `validate` feature runs it after every [`Space::step`] (the crate's
//!   tests enable it, see `Cargo.toml`), and the tests run
//!   [`Space::validate`] after their world edits.
//! * **Every state that passes it is safe to step**: loading checks nothing
//!   else, so a step must neither panic nor loop on any state it accepts
//!   (the snapshot fuzz target feeds it arbitrary bytes).
//! * **It covers every field**: the field ledger (`space/ledger.rs`)
//!   destructures each state type with no `..` and names, per field, the
//!   check above that covers it or why any value is fine; a new field does
//!   not compile until it is placed there. The desync tools are held to the
//!   same rule: [`first_difference`] destructures the structs it compares,
//!   and a test changes every leaf of a world's serde form and asserts that
//!   `==`, [`Space::checksum`], [`checksum_parts`] and [`first_difference`]
//!   all see the change.
//! * **Nothing outside the state is needed**: everything else a space holds
//!   is derived from the state or is scratch, and is rebuilt from it —
//!   world-space shape geometry and bounding boxes (`ShapeCache`), broadphase
//!   proxies and pairs, solver rows, the step-length constants (cleared when
//!   the settings or the state are replaced), the static tree (rebuilt
//!   after [`Space::restore_state`] and [`Space::from_state`]). Queries read
//!   the state only. So a validated state stepped in a fresh space and in
//!   the space it came from gives the same bits.
//!
//! # Frames and full snapshots
//! A rollback game saves every frame but never changes most of its world:
//! the level (static bodies and their shapes). A **frame**
//! ([`FrameState`](crate::space::FrameState), module [`frame`]) is the
//! world minus its level, which it names by a 64-bit digest; it restores
//! only into a world with the same level (an error otherwise, the world
//! untouched), and costs what the moving part of the world holds, whatever
//! the level's size. A **full snapshot** ([`save`]) is self-contained: for
//! files, late joiners, and rolling back across a change of the level.
//!
//! # Ways to roll back
//! * Frames in memory (fastest): [`Space::save_frame`] into a reused
//!   `FrameState` per frame, [`Space::restore_frame`] to roll back (no
//!   static tree rebuild, nothing of the level copied).
//! * Frame bytes (the network, a checksum-verified copy):
//!   [`save_frame_into`] per frame, [`Space::load_frame_snapshot`]
//!   (validated) to roll back.
//! * Whole states in memory: keep `space.state().clone()`
//!   (or `space.clone()`) per frame, and roll back with
//!   [`Space::restore_state`]. Clones share the handle origin of the
//!   original, so the game's handles keep working.
//! * Full snapshot bytes: [`save`] per frame, and [`Space::load_snapshot`]
//!   to roll back.
//!
//! # Handlers and integrators after loading
//! Closures are never part of a snapshot. [`Space::load_snapshot`] keeps the
//! live world's collision handlers and custom integrators (also those of
//! bodies removed since the save, which come back with them), and discards
//! post-step callbacks still pending (see [`Space::restore_state`]): a
//! rollback needs nothing re-attached. A space made by
//! [`load`] has none, so re-register them on it as when the world was first
//! built: collision handlers are keyed by collision type
//! (`space.add_collision_handler(a, b)`, `add_wildcard_handler(t)`), so one
//! registration per type pair covers every shape of those types, loaded or
//! not; custom integrators are keyed by body handle
//! (`space.set_velocity_update_func(h, …)`), so look the bodies up again
//! (their handles are in the snapshot, see below) and set them anew.
//!
//! # Handles after loading
//! A snapshot holds slot indices, generations and the arenas' free lists,
//! so a loaded world addresses the same objects by the same handles and
//! hands out the same handles for new objects as the saved one. Handles also
//! carry the *origin tag* of the space that made them (not state, not
//! serialized): handles from the saved world are rejected by a space made
//! with [`load`] (`SpaceError::ForeignHandle`), because it is a different
//! space. Use [`Space::load_snapshot`] on the game's own space to keep its
//! handles working, or, with [`load`], take handles from the loaded space:
//! every handle it hands out is its own (`bodies()`, `shapes()`, queries,
//! `Shape::body()`, `Arbiter::shapes()`/`bodies()`, handler contexts), or
//! build them with `Handle::from_raw_parts` (origin 0: accepted by every
//! space).
pub mod diff;
pub mod frame;
mod frame_codec;
mod wire;

use core::fmt;

use bincode::config::{Configuration, Fixint, Limit, LittleEndian};

pub use diff::{checksum_parts, first_difference, ChecksumParts, Difference, Subject};
pub use frame::{decode_frame, save_frame, save_frame_into, FRAME_FORMAT_VERSION, FRAME_MAGIC};

use crate::envelope::{self, EnvelopeError};
use crate::limits::{LimitError, Limits};
use crate::space::{validate_state, Space, WorldState};

/// First bytes of every snapshot.
pub const MAGIC: [u8; 8] = *b"TAMIAS2D";

/// Version of the byte layout; bumped whenever the serde layout of
/// [`WorldState`] (or anything in it) changes. Version 2: the settings end
/// with `substeps` (u32) and the solver switches `warm_starting`,
/// `friction`, `restitution`, `bias_impulses` (one byte each). Version 3:
/// `block_solver` (one byte) after `bias_impulses`. Version 4: the state
/// ends with the constraint arena (`constraints`). Version 5: a body ends
/// with its sleep record (`sleep`: idle time, optional island root, allowed)
/// and `bullet` (one byte, [`Body::set_bullet`](crate::body::Body::set_bullet));
/// the state ends with the dormant arbiters of sleeping islands. Version
/// 6: bodies, shapes (with their geometry) and arbiters in their compact
/// form (see "Format" in the module docs): a head of flags and a presence
/// mask, only the non-zero words (a body's or arbiter's in 4 bytes when
/// they fit); no inverse mass or moment, no normals,
/// no unused polygon vertices or contact slots (recomputed on decode).
/// Version 7: `colored_solver` (one byte) after `block_solver`. Version 8:
/// the settings end with `solver` (a u32 variant index, then for the soft
/// step its `substeps` and seven reals), a constraint with its `softness`
/// (an option: one byte, then two reals). Version 9: the soft step's
/// settings end with `contact_precision` (a u32 variant index).
pub const FORMAT_VERSION: u32 = 9;

/// Bytes before the bincode payload: magic, version, checksum (the frame
/// every Tamias file shares, see [`crate::envelope`]).
pub const HEADER_LEN: usize = envelope::HEADER_LEN;

/// Largest payload `load` decodes (1 GiB, about a million bodies): the
/// decoder's byte limit. Memory is bounded by the data actually present: a
/// length prefix only sizes the first allocation of a container, and serde
/// caps that at 1 MiB (`size_hint::cautious`), so a forged length of 2^60
/// fails with [`SnapshotError::Decode`] at the end of the input after
/// allocating at most 1 MiB.
pub const MAX_SNAPSHOT_BYTES: usize = 1 << 30;

/// The bincode configuration of the payload (see `docs/architecture.md`).
type Config = Configuration<LittleEndian, Fixint, Limit<MAX_SNAPSHOT_BYTES>>;

pub(crate) const CONFIG: Config = bincode::config::standard()
    .with_fixed_int_encoding()
    .with_limit::<MAX_SNAPSHOT_BYTES>();

/// Why bytes were not accepted as a snapshot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SnapshotError {
    /// Shorter than the header ([`HEADER_LEN`] bytes).
    TooShort,
    /// The first bytes are not [`MAGIC`].
    BadMagic,
    /// A format version this build does not read.
    UnsupportedVersion(u32),
    /// The payload does not decode as a world state (truncated, a bad enum
    /// tag or bool, a length past the end or over the limit).
    Decode(String),
    /// This many bytes follow the payload.
    TrailingBytes(usize),
    /// The payload bytes do not match the header's checksum: corrupted.
    ChecksumMismatch {
        /// Checksum in the header.
        stored: u64,
        /// Checksum of the payload as received.
        computed: u64,
    },
    /// The state decodes but breaks an invariant; names what is wrong.
    Invalid(String),
    /// Over one of the loading [`Limits`]; names the limit and the value.
    OverLimit(LimitError),
    /// A frame snapshot of another level: its level digest is not the
    /// world's (see [`Space::level_digest`]).
    LevelMismatch {
        /// Level digest stored in the frame.
        frame: u64,
        /// Level digest of the world it was loaded into.
        world: u64,
    },
}

impl fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SnapshotError::TooShort => {
                write!(f, "snapshot is shorter than its {HEADER_LEN}-byte header")
            }
            SnapshotError::BadMagic => f.write_str("not a tamias2d snapshot (bad magic bytes)"),
            SnapshotError::UnsupportedVersion(v) => write!(
                f,
                "snapshot format version {v} is not supported (this build reads {FORMAT_VERSION})"
            ),
            SnapshotError::Decode(e) => write!(f, "snapshot does not decode: {e}"),
            SnapshotError::TrailingBytes(n) => {
                write!(f, "{n} unexpected bytes after the snapshot")
            }
            SnapshotError::ChecksumMismatch { stored, computed } => write!(
                f,
                "snapshot is corrupted: header checksum {stored:#018x}, payload checksum {computed:#018x}"
            ),
            SnapshotError::Invalid(why) => write!(f, "invalid snapshot: {why}"),
            SnapshotError::OverLimit(e) => write!(f, "snapshot over a limit: {e}"),
            SnapshotError::LevelMismatch { frame, world } => write!(
                f,
                "frame snapshot of another level (level digest {frame:#018x}, this world's {world:#018x}): \
                 the static bodies or their shapes differ"
            ),
        }
    }
}

impl std::error::Error for SnapshotError {}

/// The header of a snapshot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// Format version.
    pub version: u32,
    /// [`payload_checksum`] of the bytes after the header.
    pub checksum: u64,
}

/// The state of `space` as bytes (see the module docs for the format).
///
/// Encoding a `WorldState` cannot fail (every field has a fixed serde shape
/// and the output is a `Vec`); were it ever to, the result is empty, which
/// [`load`] rejects as [`SnapshotError::TooShort`].
pub fn save(space: &Space) -> Vec<u8> {
    save_state(space.state())
}

/// [`save`] of a bare state (for states built or edited by hand; [`load`]
/// still validates them).
pub fn save_state(state: &WorldState) -> Vec<u8> {
    let mut out = Vec::with_capacity(size_hint(state));
    save_state_into(state, &mut out);
    out
}

/// [`save`] into `out`, replacing its contents and reusing its allocation;
/// returns the snapshot length. The per-frame form for rollback.
pub fn save_into(space: &Space, out: &mut Vec<u8>) -> usize {
    save_state_into(space.state(), out)
}

fn save_state_into(state: &WorldState, out: &mut Vec<u8>) -> usize {
    out.clear();
    envelope::begin(out, &MAGIC, FORMAT_VERSION);
    if bincode::serde::encode_into_std_write(state, out, CONFIG).is_err() {
        out.clear();
        return 0;
    }
    envelope::seal(out, 0, payload_checksum);
    out.len()
}

/// The header's checksum of the payload bytes: four independent lanes of a
/// multiply–xorshift step (its own, not [`WordHasher`](crate::checksum::WordHasher)'s)
/// over little-endian 64-bit words (independent lanes keep the multiplier
/// busy: several bytes per cycle), then the lanes, the length and the tail
/// bytes folded into one word, and SplitMix64's finaliser. For a fixed lane
/// each step is injective in the word, and for a fixed word a bijection of
/// the lane, so changing any one word always changes the result. Portable:
/// words are read little-endian.
pub fn payload_checksum(payload: &[u8]) -> u64 {
    const K: u64 = 0x9E37_79B9_7F4A_7C15;
    fn mix(s: u64, w: u64) -> u64 {
        let x = (s ^ w).wrapping_mul(K);
        x ^ (x >> 29)
    }
    fn word(bytes: &[u8]) -> u64 {
        let mut w = [0u8; 8];
        for (d, s) in w.iter_mut().zip(bytes) {
            *d = *s;
        }
        u64::from_le_bytes(w)
    }
    let mut lanes: [u64; 4] = [
        0x243F_6A88_85A3_08D3,
        0x1319_8A2E_0370_7344,
        0xA409_3822_299F_31D0,
        0x082E_FA98_EC4E_6C89,
    ];
    let blocks = payload.chunks_exact(32);
    let tail = blocks.remainder();
    for block in blocks {
        for (lane, w) in lanes.iter_mut().zip(block.chunks_exact(8)) {
            *lane = mix(*lane, word(w));
        }
    }
    let folded = lanes.iter().fold(payload.len() as u64, |h, &l| mix(h, l));
    let mut z = tail.chunks(8).fold(folded, |h, w| mix(h, word(w)));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A capacity guess for a first `save` (the largest encoded sizes of slots
/// and arbiters: every word non-zero), so the output grows at most once.
fn size_hint(state: &WorldState) -> usize {
    const BODY_SLOT: usize = 168;
    const SHAPE_SLOT: usize = 216;
    const ARBITER: usize = 216;
    const CONSTRAINT_SLOT: usize = 128;
    (HEADER_LEN + 128)
        .saturating_add(state.bodies.capacity_slots().saturating_mul(BODY_SLOT))
        .saturating_add(state.shapes.capacity_slots().saturating_mul(SHAPE_SLOT))
        .saturating_add(state.arbiters.len().saturating_mul(ARBITER))
        .saturating_add(
            state
                .constraints
                .capacity_slots()
                .saturating_mul(CONSTRAINT_SLOT),
        )
}

/// The header of `bytes`: checks length, magic and version only.
pub fn header(bytes: &[u8]) -> Result<Header, SnapshotError> {
    let frame = envelope::open(bytes, &MAGIC, FORMAT_VERSION).map_err(|e| match e {
        EnvelopeError::TooShort => SnapshotError::TooShort,
        EnvelopeError::BadMagic => SnapshotError::BadMagic,
        EnvelopeError::UnsupportedVersion(v) => SnapshotError::UnsupportedVersion(v),
    })?;
    Ok(Header {
        version: FORMAT_VERSION,
        checksum: frame.digest,
    })
}

/// The state in `bytes`, after every check of [`load`], under
/// [`Limits::UNTRUSTED`].
pub fn decode_state(bytes: &[u8]) -> Result<WorldState, SnapshotError> {
    decode_state_with(bytes, &Limits::UNTRUSTED)
}

/// [`decode_state`] under `limits` (see [`crate::limits`]): the byte count
/// first, then every check, then the state's counts, settings and
/// candidate pairs.
pub fn decode_state_with(bytes: &[u8], limits: &Limits) -> Result<WorldState, SnapshotError> {
    limits
        .check_bytes(bytes.len())
        .map_err(SnapshotError::OverLimit)?;
    let head = header(bytes)?;
    let payload = bytes.get(HEADER_LEN..).unwrap_or(&[]);
    let (state, read): (WorldState, usize) = bincode::serde::decode_from_slice(payload, CONFIG)
        .map_err(|e| SnapshotError::Decode(e.to_string()))?;
    let trailing = payload.len().saturating_sub(read);
    if trailing > 0 {
        return Err(SnapshotError::TrailingBytes(trailing));
    }
    let computed = payload_checksum(payload);
    if computed != head.checksum {
        return Err(SnapshotError::ChecksumMismatch {
            stored: head.checksum,
            computed,
        });
    }
    validate_state(&state).map_err(SnapshotError::Invalid)?;
    limits
        .check_state(&state)
        .map_err(SnapshotError::OverLimit)?;
    Ok(state)
}

/// A new space from a snapshot, after full validation (see the module docs),
/// under [`Limits::UNTRUSTED`]. The space has no handlers, callbacks or
/// custom integrators, and a new handle origin: re-attach handlers by
/// collision type.
pub fn load(bytes: &[u8]) -> Result<Space, SnapshotError> {
    load_with(bytes, &Limits::UNTRUSTED)
}

/// [`load`] under `limits`, which the new space keeps (for its step and
/// what it loads next).
pub fn load_with(bytes: &[u8], limits: &Limits) -> Result<Space, SnapshotError> {
    let mut space = Space::from_state(decode_state_with(bytes, limits)?);
    space.set_limits(*limits);
    Ok(space)
}

impl Space {
    /// Replaces this world's state by the snapshot's, after full
    /// validation; handlers, custom integrators and the handle origin stay,
    /// pending post-step callbacks are discarded (as with
    /// [`Space::restore_state`], which this calls). Under this space's
    /// [`Limits`] ([`Space::set_limits`]). On error nothing changes.
    pub fn load_snapshot(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let state = decode_state_with(bytes, &self.limits)?;
        self.restore_state(&state);
        Ok(())
    }
}
