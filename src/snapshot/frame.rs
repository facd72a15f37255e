//! Frame snapshots: the per-frame state of a world ([`FrameState`]) as
//! bytes, for rollback through the network or a byte buffer.
//!
//! A frame snapshot holds what a step can change and names the level
//! (static bodies and their shapes) by its digest, so its size and its
//! save and load costs are those of the moving part of the world, however
//! big the level (see `space::frame`). It loads only into a world with the
//! same level ([`Space::load_frame_snapshot`]); a full snapshot
//! ([`save`](super::save)) is still the self-contained file for disk, late
//! joiners and the CLI.
//!
//! # Format (version [`FRAME_FORMAT_VERSION`])
//! ```text
//! offset  size  content
//!      0     8  magic b"TAMIASFR"
//!      8     4  frame format version, u32 little-endian
//!     12     8  payload_checksum of the payload bytes, u64 LE
//!     20     …  the payload: level digest, counters, settings and
//!               constraints (bincode), the body and shape slots outside
//!               the level, the arbiters — written by hand, each object a
//!               head and its words in as few bytes as their values need
//!               (see `snapshot::frame_codec` and `snapshot::wire`)
//! ```
//! The objects carry what their full-snapshot form carries, less the
//! arbiters' bodies (those of their shapes, filled in on load).
//!
//! # What loading checks
//! Length, magic, version, decoding (size limit
//! [`MAX_SNAPSHOT_BYTES`](super::MAX_SNAPSHOT_BYTES)), trailing bytes, the
//! payload checksum; then the level digest against the world's
//! ([`SnapshotError::LevelMismatch`]); that the frame's slots and the
//! level's tile the arenas exactly; and, with the frame installed, every
//! invariant of [`validate_state`](crate::space::validate_state) except the
//! level objects' own (they are the world's, unchanged and valid). On any
//! error the world is restored to exactly what it was.
use super::{frame_codec, payload_checksum, SnapshotError};
use crate::envelope::{self, EnvelopeError};
use crate::space::{FrameState, Space, SpaceError};

/// First bytes of every frame snapshot.
pub const FRAME_MAGIC: [u8; 8] = *b"TAMIASFR";

/// Version of the frame byte layout. Frames appeared in version 5 and
/// used the full snapshots' serde form through version 6; version 7 is the
/// hand-written coding of `snapshot::frame_codec`, versioned on its own
/// from then on. Version 8: the settings gained `colored_solver`.
/// Version 9: the settings end with `solver` (see the full snapshots'
/// version 8). Version 10: the soft step's settings end with
/// `contact_precision` (see the full snapshots' version 9).
pub const FRAME_FORMAT_VERSION: u32 = 10;

/// The frame of `space` as bytes into `out` (cleared first, its allocation
/// reused); returns the length. Cost: the frame's objects, not the level's.
/// Encoding cannot fail (fixed serde shapes into a `Vec`); were it ever to,
/// `out` is left empty, which loading rejects.
pub fn save_frame_into(space: &Space, out: &mut Vec<u8>) -> usize {
    out.clear();
    envelope::begin(out, &FRAME_MAGIC, FRAME_FORMAT_VERSION);
    if !frame_codec::encode(space, out) {
        out.clear();
        return 0;
    }
    envelope::seal(out, 0, payload_checksum);
    out.len()
}

/// [`save_frame_into`] a new buffer.
pub fn save_frame(space: &Space) -> Vec<u8> {
    let mut out = Vec::new();
    save_frame_into(space, &mut out);
    out
}

/// The payload of frame bytes after the byte-level checks (header,
/// payload checksum).
fn open_frame(bytes: &[u8]) -> Result<&[u8], SnapshotError> {
    let frame = envelope::open(bytes, &FRAME_MAGIC, FRAME_FORMAT_VERSION).map_err(|e| match e {
        EnvelopeError::TooShort => SnapshotError::TooShort,
        EnvelopeError::BadMagic => SnapshotError::BadMagic,
        EnvelopeError::UnsupportedVersion(v) => SnapshotError::UnsupportedVersion(v),
    })?;
    let computed = payload_checksum(frame.payload);
    if computed != frame.digest {
        return Err(SnapshotError::ChecksumMismatch {
            stored: frame.digest,
            computed,
        });
    }
    Ok(frame.payload)
}

/// The [`FrameState`] in `bytes`, a frame of `world`'s level, exactly as
/// [`Space::save_frame`] made it: loaded into a copy of `world` (every
/// check of [`Space::load_frame_snapshot`]) and saved from there. For tools
/// and tests; a game loads frames with [`Space::load_frame_snapshot`],
/// which costs no copy of the world.
pub fn decode_frame(bytes: &[u8], world: &Space) -> Result<FrameState, SnapshotError> {
    let mut copy = world.clone();
    copy.load_frame_snapshot(bytes)?;
    let mut frame = FrameState::default();
    copy.save_frame(&mut frame);
    Ok(frame)
}

impl Space {
    /// Replaces this world's frame by the one in `bytes` (a
    /// [`save_frame_into`] of a world with the same level), after every
    /// check listed in the module docs; keeps the level (nothing rebuilt),
    /// handlers and integrators, and discards pending post-step callbacks.
    /// On error nothing changes.
    pub fn load_frame_snapshot(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        self.limits
            .check_bytes(bytes.len())
            .map_err(SnapshotError::OverLimit)?;
        let payload = open_frame(bytes)?;
        // Decoded into the world's spare frame: its buffers are reused.
        let mut frame = core::mem::take(&mut self.caches.spare_frame);
        let result = frame_codec::decode_into(payload, &mut frame)
            .map_err(|e| SnapshotError::Decode(e.to_string()))
            .and_then(|()| {
                self.install_frame_validated(&mut frame, &mut frame_codec::complete_arbiter)
                    .map_err(|e| match e {
                        SpaceError::LevelMismatch { frame, world } => {
                            SnapshotError::LevelMismatch { frame, world }
                        }
                        SpaceError::OverLimit(e) => SnapshotError::OverLimit(e),
                        SpaceError::InvalidState(why)
                        | SpaceError::RejectedState(why)
                        | SpaceError::FrameMismatch(why) => SnapshotError::Invalid(why),
                        other => SnapshotError::Invalid(other.to_string()),
                    })
            });
        self.caches.spare_frame = frame;
        result
    }
}
