//! The envelope every Tamias file shares (a header around the payload):
//! snapshots, replays and the fixtures crate's scripted worlds. (A rollback
//! *frame* is something else: `space::FrameState`.)
//!
//! ```text
//! offset  size  content
//!      0     8  magic: names the kind of file
//!      8     4  format version, u32 little-endian
//!     12     8  digest of the payload, u64 little-endian
//!     20     …  payload
//! ```
//! One routine writes the header and one reads it, so the three formats
//! cannot drift apart in how they reject short, foreign or newer files. Each
//! format keeps its own magic, version, digest function and error type
//! (a snapshot's digest is its fast payload checksum, checked after
//! decoding; the others use [`checksum_of`](crate::checksum::checksum_of)).

/// Bytes before the payload: magic, version, payload digest.
pub const HEADER_LEN: usize = 20;

/// Byte range of the digest in the header.
const DIGEST: core::ops::Range<usize> = 12..HEADER_LEN;

/// What is wrong with a header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvelopeError {
    /// Shorter than [`HEADER_LEN`] bytes.
    TooShort,
    /// The first 8 bytes are not the expected magic.
    BadMagic,
    /// The magic matches but the version is not the one this build reads.
    UnsupportedVersion(u32),
}

/// A file split at its header, after the magic and version were checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Envelope<'a> {
    /// The digest the writer stored (not yet compared with the payload).
    pub digest: u64,
    /// The bytes after the header.
    pub payload: &'a [u8],
}

/// Splits `bytes` at its header: checks the length, `magic` and `version`.
pub fn open<'a>(
    bytes: &'a [u8],
    magic: &[u8; 8],
    version: u32,
) -> Result<Envelope<'a>, EnvelopeError> {
    let (Some(found_magic), Some(found_version), Some(digest), Some(payload)) = (
        bytes.get(0..8),
        bytes.get(8..12),
        bytes.get(DIGEST),
        bytes.get(HEADER_LEN..),
    ) else {
        return Err(EnvelopeError::TooShort);
    };
    if found_magic != magic {
        return Err(EnvelopeError::BadMagic);
    }
    let found_version = u32::from_le_bytes(found_version.try_into().unwrap_or([0; 4]));
    if found_version != version {
        return Err(EnvelopeError::UnsupportedVersion(found_version));
    }
    let digest = u64::from_le_bytes(digest.try_into().unwrap_or([0; 8]));
    Ok(Envelope { digest, payload })
}

/// Appends a header with a zero digest to `out`; write the payload after
/// it, then call [`seal`].
pub fn begin(out: &mut Vec<u8>, magic: &[u8; 8], version: u32) {
    out.extend_from_slice(magic);
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&[0; 8]);
}

/// Fills in the digest of the envelope that starts at `out[start..]`: `digest`
/// of its payload. Returns the digest.
pub fn seal(out: &mut [u8], start: usize, digest: impl Fn(&[u8]) -> u64) -> u64 {
    let frame = out.get_mut(start..).unwrap_or(&mut []);
    let sum = digest(frame.get(HEADER_LEN..).unwrap_or(&[]));
    if let Some(slot) = frame.get_mut(DIGEST) {
        slot.copy_from_slice(&sum.to_le_bytes());
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::checksum::checksum_of;

    const MAGIC: [u8; 8] = *b"TESTFILE";

    fn framed(payload: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        begin(&mut out, &MAGIC, 3);
        out.extend_from_slice(payload);
        seal(&mut out, 0, checksum_of);
        out
    }

    #[test]
    fn open_returns_what_seal_wrote() {
        let bytes = framed(b"payload");
        let frame = open(&bytes, &MAGIC, 3).unwrap();
        assert_eq!(frame.payload, b"payload");
        assert_eq!(frame.digest, checksum_of(&b"payload"[..]));
    }

    #[test]
    fn open_rejects_short_foreign_and_newer_headers() {
        let bytes = framed(b"");
        assert_eq!(open(&bytes, &MAGIC, 3).unwrap().payload, b"");
        assert_eq!(open(&bytes[..19], &MAGIC, 3), Err(EnvelopeError::TooShort));
        assert_eq!(open(&bytes, b"OTHERFIL", 3), Err(EnvelopeError::BadMagic));
        assert_eq!(
            open(&bytes, &MAGIC, 4),
            Err(EnvelopeError::UnsupportedVersion(3))
        );
    }
}
