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
//!     20     …  the FrameState, bincode 2 (serde), the configuration of
//!               full snapshots: level digest (u64), settings, the body
//!               and shape arena parts (slot count u32, then each slot
//!               outside the level as (index u32, slot), free list, length
//!               u32), arbiters, stamp, steps, current and previous dt,
//!               constraint arena, dormant arbiters
//! ```
//! Objects are encoded exactly as in a full snapshot (their serde form).
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
use super::{payload_checksum, SnapshotError, CONFIG};
use crate::framing::{self, FrameError};
use crate::space::{FrameState, Space, SpaceError};

/// First bytes of every frame snapshot.
pub const FRAME_MAGIC: [u8; 8] = *b"TAMIASFR";

/// Version of the frame byte layout: that of full snapshots
/// ([`FORMAT_VERSION`](super::FORMAT_VERSION)), since frames encode the
/// same objects; a change of [`FrameState`]'s own layout bumps both.
/// (Frames first appeared in version 5.)
pub const FRAME_FORMAT_VERSION: u32 = super::FORMAT_VERSION;

/// The frame of `space` as bytes into `out` (cleared first, its allocation
/// reused); returns the length. Cost: the frame's objects, not the level's.
/// Encoding cannot fail (fixed serde shapes into a `Vec`); were it ever to,
/// `out` is left empty, which loading rejects.
pub fn save_frame_into(space: &Space, out: &mut Vec<u8>) -> usize {
    out.clear();
    framing::begin(out, &FRAME_MAGIC, FRAME_FORMAT_VERSION);
    let encoded = space.with_frame_view(|view| {
        bincode::serde::encode_into_std_write(view, &mut *out, CONFIG).is_ok()
    });
    if !encoded {
        out.clear();
        return 0;
    }
    framing::seal(out, 0, payload_checksum);
    out.len()
}

/// [`save_frame_into`] a new buffer.
pub fn save_frame(space: &Space) -> Vec<u8> {
    let mut out = Vec::new();
    save_frame_into(space, &mut out);
    out
}

/// The [`FrameState`] in `bytes` after the byte-level checks (header,
/// decoding, trailing bytes, payload checksum), not yet checked against a
/// level.
pub fn decode_frame(bytes: &[u8]) -> Result<FrameState, SnapshotError> {
    let frame = framing::open(bytes, &FRAME_MAGIC, FRAME_FORMAT_VERSION).map_err(|e| match e {
        FrameError::TooShort => SnapshotError::TooShort,
        FrameError::BadMagic => SnapshotError::BadMagic,
        FrameError::UnsupportedVersion(v) => SnapshotError::UnsupportedVersion(v),
    })?;
    let (state, read): (FrameState, usize) =
        bincode::serde::decode_from_slice(frame.payload, CONFIG)
            .map_err(|e| SnapshotError::Decode(e.to_string()))?;
    let trailing = frame.payload.len().saturating_sub(read);
    if trailing > 0 {
        return Err(SnapshotError::TrailingBytes(trailing));
    }
    let computed = payload_checksum(frame.payload);
    if computed != frame.digest {
        return Err(SnapshotError::ChecksumMismatch {
            stored: frame.digest,
            computed,
        });
    }
    Ok(state)
}

impl Space {
    /// Replaces this world's frame by the one in `bytes` (a
    /// [`save_frame_into`] of a world with the same level), after every
    /// check listed in the module docs; keeps the level (nothing rebuilt),
    /// handlers and integrators, and discards pending post-step callbacks.
    /// On error nothing changes.
    pub fn load_frame_snapshot(&mut self, bytes: &[u8]) -> Result<(), SnapshotError> {
        let frame = decode_frame(bytes)?;
        self.install_frame_validated(frame).map_err(|e| match e {
            SpaceError::LevelMismatch { frame, world } => {
                SnapshotError::LevelMismatch { frame, world }
            }
            SpaceError::InvalidState(why) | SpaceError::FrameMismatch(why) => {
                SnapshotError::Invalid(why)
            }
            other => SnapshotError::Invalid(other.to_string()),
        })
    }
}
