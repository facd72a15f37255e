//! The word coding of frame snapshots: each integer in as few bytes as its
//! value needs.
//!
//! An object is a fixed list of signed 64-bit *words* (raw fixed-point
//! values, handles, counters) known from its kind. It is written as the
//! words' byte lengths, two 4-bit lengths per byte (low nibble first; the
//! high nibble of an odd count's last byte is 0), then each word's
//! shortest two's-complement little-endian form: 0 bytes for 0, 1 for
//! −128..=127, … 8 for the rest. A fixed-point value of magnitude 2^k
//! takes about (k + 33) / 8 bytes: a unit normal 5, a position below
//! 128 m 6, a small impulse 3.
//!
//! The coding is canonical: a length above 8, a word longer than its
//! shortest form or a non-zero padding nibble is an error, so one state has
//! one encoding. Writing appends to a `Vec<u8>` (its allocation reused);
//! reading borrows the bytes and never panics.

/// Bytes of the shortest two's-complement form of `v` (0 for 0).
#[inline(always)]
pub(crate) fn byte_len(v: i64) -> u32 {
    // The magnitude bits (a negative value's complement), then one more
    // for the sign; without a branch: 0 has no bits at all, −1 one.
    let magnitude = (v ^ v.wrapping_shr(63)) as u64;
    let bits = 64u32.wrapping_sub((magnitude.wrapping_shl(1) | u64::from(v != 0)).leading_zeros());
    bits.div_ceil(8)
}

/// Most words one object may have (an arbiter with two contacts: 28).
pub(crate) const MAX_WORDS: usize = 32;

/// Bytes of one object's coding at most (a head, the lengths, the
/// words), plus room for the last word's whole store.
const OBJECT_MAX: usize = 8 + MAX_WORDS / 2 + 8 * MAX_WORDS + 8;
/// The encoder's staging buffer: objects are built there and copied into
/// the output a few kilobytes at a time.
const STAGE: usize = 4 * 1024;

/// Appends to a byte buffer, through a staging buffer on the stack (the
/// fixed-position writes of one object cost no call and no capacity check;
/// the output grows by one copy per [`STAGE`] bytes). Call
/// [`finish`](Self::finish) at the end.
pub(crate) struct Enc<'a> {
    out: &'a mut Vec<u8>,
    stage: [u8; STAGE],
    at: usize,
}

impl<'a> Enc<'a> {
    pub(crate) fn new(out: &'a mut Vec<u8>) -> Enc<'a> {
        Enc {
            out,
            stage: [0; STAGE],
            at: 0,
        }
    }

    /// Moves the staged bytes into the output.
    #[inline]
    fn flush(&mut self) {
        self.out
            .extend_from_slice(self.stage.get(..self.at).unwrap_or(&[]));
        self.at = 0;
    }

    /// Makes room for one object.
    #[inline(always)]
    fn room(&mut self) {
        if self.at > STAGE.saturating_sub(OBJECT_MAX) {
            self.flush();
        }
    }

    /// Everything written so far, in the output (the whole buffer).
    pub(crate) fn buffer(&mut self) -> &mut Vec<u8> {
        self.flush();
        self.out
    }

    /// Ends the writing: everything is in the output.
    pub(crate) fn finish(&mut self) {
        self.flush();
    }

    #[inline(always)]
    fn bytes<const N: usize>(&mut self, b: [u8; N]) {
        self.room();
        if let Some(dst) = self.stage.get_mut(self.at..self.at.saturating_add(N)) {
            dst.copy_from_slice(&b);
            self.at = self.at.saturating_add(N);
        }
    }

    #[inline(always)]
    pub(crate) fn u8(&mut self, v: u8) {
        self.bytes(v.to_le_bytes());
    }

    #[inline(always)]
    pub(crate) fn u16(&mut self, v: u16) {
        self.bytes(v.to_le_bytes());
    }

    #[inline(always)]
    pub(crate) fn u32(&mut self, v: u32) {
        self.bytes(v.to_le_bytes());
    }

    #[inline(always)]
    pub(crate) fn u64(&mut self, v: u64) {
        self.bytes(v.to_le_bytes());
    }

    /// Starts an object of exactly `n` words (at most [`MAX_WORDS`]),
    /// written one by one with [`Obj::word`] and ended with
    /// [`Obj::finish`]: the same bytes as [`words`](Self::words), without
    /// gathering the words first.
    #[inline(always)]
    pub(crate) fn object(&mut self, n: usize) -> Obj<'_, 'a> {
        self.room();
        let n = n.min(MAX_WORDS);
        let lens_at = self.at;
        let n_lens = n.div_ceil(2);
        Obj {
            end: lens_at.saturating_add(n_lens),
            enc: self,
            lens_at,
            n_lens,
            lens_lo: 0,
            lens_hi: 0,
            shift: 0,
            // ≤ 4 · MAX_WORDS.
            limit: (n as u32).saturating_mul(4),
        }
    }

    /// Writes `words` (at most [`MAX_WORDS`]; more are not written, which
    /// the reader of a fixed list rejects) in the coding above.
    #[inline]
    pub(crate) fn words(&mut self, words: &[i64]) {
        let mut o = self.object(words.len());
        for &w in words {
            o.word(w);
        }
        o.finish();
    }
}

/// One object being written (see [`Enc::object`]).
pub(crate) struct Obj<'e, 'a> {
    enc: &'e mut Enc<'a>,
    lens_at: usize,
    n_lens: usize,
    end: usize,
    /// The lengths so far, a nibble each, low first: words 0–15, 16–31.
    lens_lo: u64,
    lens_hi: u64,
    /// 4 × the words written, and 4 × the words declared.
    shift: u32,
    limit: u32,
}

impl Obj<'_, '_> {
    /// The next word: stored whole (one 8-byte store) at the end, which
    /// then moves by its length.
    #[inline(always)]
    pub(crate) fn word(&mut self, w: i64) {
        // Past the declared count the word is dropped (the lengths have no
        // room for it); the writers here declare exactly what they write.
        if self.shift >= self.limit {
            return;
        }
        let len = byte_len(w);
        if let Some(dst) = self.enc.stage.get_mut(self.end..self.end.wrapping_add(8)) {
            dst.copy_from_slice(&w.to_le_bytes());
        }
        // ≤ STAGE: no overflow.
        self.end = self.end.wrapping_add(len as usize);
        if self.shift < 64 {
            self.lens_lo |= u64::from(len).wrapping_shl(self.shift);
        } else {
            self.lens_hi |= u64::from(len).wrapping_shl(self.shift);
        }
        self.shift = self.shift.wrapping_add(4);
    }

    /// The next word, a fixed-point value's raw bits.
    #[inline(always)]
    pub(crate) fn real(&mut self, r: crate::math::Real) {
        self.word(r.to_bits());
    }

    /// Ends the object: its lengths go in front of its words (a 16-byte
    /// read-modify-write that keeps the words' first bytes).
    #[inline(always)]
    pub(crate) fn finish(self) {
        let at = self.lens_at;
        if let Some(block) = self
            .enc
            .stage
            .get_mut(at..at.wrapping_add(16))
            .and_then(|b| <&mut [u8; 16]>::try_from(b).ok())
        {
            let old = u128::from_le_bytes(*block);
            // n_lens ≤ 16 bytes: the low n_lens bytes are the lengths'.
            let mask = match u32::try_from(self.n_lens.wrapping_mul(8)) {
                Ok(bits) if bits < 128 => 1u128.wrapping_shl(bits).wrapping_sub(1),
                _ => u128::MAX,
            };
            let lens = u128::from(self.lens_lo) | u128::from(self.lens_hi).wrapping_shl(64);
            *block = ((old & !mask) | (lens & mask)).to_le_bytes();
        }
        self.enc.at = self.end;
    }
}

/// Why bytes did not decode: what was wrong and where.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct WireError {
    pub(crate) what: &'static str,
    pub(crate) at: usize,
}

impl core::fmt::Display for WireError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{} at payload byte {}", self.what, self.at)
    }
}

/// Reads bytes in order.
pub(crate) struct Dec<'a> {
    bytes: &'a [u8],
    at: usize,
    /// A zero-padded copy of the last bytes, read by the objects that end
    /// too near the end for whole 8-byte loads.
    pad: [u8; PAD],
}

/// Bytes of the longest object coding plus an 8-byte load past it.
const PAD: usize = MAX_WORDS / 2 + 8 * MAX_WORDS + 8;

impl<'a> Dec<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Dec<'a> {
        Dec {
            bytes,
            at: 0,
            pad: [0; PAD],
        }
    }

    /// Starts reading an object of exactly `n` words (at most
    /// [`MAX_WORDS`]), read one by one with [`ObjR::word`] and ended with
    /// [`ObjR::finish`], which reports any coding error (a length above 8,
    /// a word longer than its shortest form, a padding nibble, the end of
    /// the bytes): the same checks as [`words`](Self::words).
    #[inline(always)]
    pub(crate) fn object(&mut self, n: usize) -> Result<ObjR<'_>, WireError> {
        if n > MAX_WORDS {
            return Err(self.error("too many words"));
        }
        let n_lens = n.div_ceil(2);
        let Dec { bytes, at, pad } = self;
        let rest = bytes.get(*at..).unwrap_or(&[]);
        // A whole `PAD` bytes from the object's start (the longest object
        // and an 8-byte load past it), or their zero-padded copy near the
        // end: a fixed-size window, so the word loads need no bounds tests.
        let src: &[u8; PAD] = match rest.first_chunk::<PAD>() {
            Some(window) => window,
            None => {
                *pad = [0; PAD];
                if let Some(head) = pad.get_mut(..rest.len()) {
                    head.copy_from_slice(rest);
                }
                pad
            }
        };
        let block = src
            .first_chunk::<16>()
            .map_or(0, |b| u128::from_le_bytes(*b));
        let mask = match u32::try_from(n_lens.saturating_mul(8)) {
            Ok(bits) if bits < 128 => 1u128.wrapping_shl(bits).wrapping_sub(1),
            _ => u128::MAX,
        };
        Ok(ObjR {
            available: rest.len(),
            src,
            start: at,
            lens: block & mask,
            at: n_lens,
            bad: false,
        })
    }

    /// An error at the current position.
    pub(crate) fn error(&self, what: &'static str) -> WireError {
        WireError { what, at: self.at }
    }

    /// Bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.at)
    }

    /// The next `n` bytes.
    #[inline(always)]
    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], WireError> {
        let end = self.at.saturating_add(n);
        match self.bytes.get(self.at..end) {
            Some(b) => {
                self.at = end;
                Ok(b)
            }
            None => Err(self.error("unexpected end of the bytes")),
        }
    }

    #[inline(always)]
    fn array<const N: usize>(&mut self) -> Result<[u8; N], WireError> {
        let b = self.take(N)?;
        <[u8; N]>::try_from(b).map_err(|_| self.error("unexpected end of the bytes"))
    }

    #[inline(always)]
    pub(crate) fn u8(&mut self) -> Result<u8, WireError> {
        Ok(u8::from_le_bytes(self.array()?))
    }

    #[inline(always)]
    pub(crate) fn u16(&mut self) -> Result<u16, WireError> {
        Ok(u16::from_le_bytes(self.array()?))
    }

    #[inline(always)]
    pub(crate) fn u32(&mut self) -> Result<u32, WireError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    #[inline(always)]
    pub(crate) fn u64(&mut self) -> Result<u64, WireError> {
        Ok(u64::from_le_bytes(self.array()?))
    }

    /// A count of items that each take at least `min_bytes`: more than the
    /// remaining bytes can hold is an error (before anything is reserved).
    pub(crate) fn count(&mut self, min_bytes: usize) -> Result<usize, WireError> {
        let n = self.u32()? as usize;
        if n.saturating_mul(min_bytes.max(1)) > self.remaining() {
            return Err(self.error("a count past the end of the bytes"));
        }
        Ok(n)
    }

    /// Fills `out` (at most [`MAX_WORDS`]) with the words the coding above
    /// holds next, checking that it is canonical.
    #[inline]
    pub(crate) fn words(&mut self, out: &mut [i64]) -> Result<(), WireError> {
        let mut o = self.object(out.len())?;
        for w in out.iter_mut() {
            *w = o.word();
        }
        o.finish()
    }
}

/// One object being read (see [`Dec::object`]).
pub(crate) struct ObjR<'d> {
    /// The bytes from the object's start (or their padded copy).
    src: &'d [u8; PAD],
    /// The reader's position, moved past the object by `finish`.
    start: &'d mut usize,
    /// The lengths not yet used, a nibble each, next lowest.
    lens: u128,
    /// Offset of the next word from the object's start.
    at: usize,
    /// Bytes from the object's start to the end of the bytes.
    available: usize,
    bad: bool,
}

impl ObjR<'_> {
    /// The next word (0 once the declared words are read).
    #[inline(always)]
    pub(crate) fn word(&mut self) -> i64 {
        let len = (self.lens & 15) as u8;
        self.lens = self.lens.wrapping_shr(4);
        let (v, wrong) = word_at(self.src, self.at, len);
        self.bad |= wrong;
        // ≤ 15 · MAX_WORDS past the start: no overflow.
        self.at = self.at.wrapping_add(usize::from(len));
        v
    }

    /// The next word, as a fixed-point value.
    #[inline(always)]
    pub(crate) fn real(&mut self) -> crate::math::Real {
        crate::math::Real::from_bits(self.word())
    }

    /// The next word as an unsigned 32-bit field (out of range: an error
    /// at [`finish`](Self::finish), 0 here).
    #[inline(always)]
    pub(crate) fn u32(&mut self) -> u32 {
        let w = self.word();
        match u32::try_from(w) {
            Ok(v) => v,
            Err(_) => {
                self.bad = true;
                0
            }
        }
    }

    /// Ends the object after its declared words: an error if any was
    /// malformed or out of range, or the padding nibble is not 0, or the
    /// object runs past the end of the bytes.
    #[inline(always)]
    pub(crate) fn finish(self) -> Result<(), WireError> {
        if self.bad || self.lens != 0 || self.at > self.available {
            return Err(WireError {
                what: "a malformed object (a word length above 8, a word longer than its shortest form, a field out of range, a padding length that is not 0, or the end of the bytes)",
                at: *self.start,
            });
        }
        *self.start = self.start.saturating_add(self.at);
        Ok(())
    }
}

/// The word of `len` bytes (≤ 8) at `at` in `bytes`, and whether it is
/// longer than its shortest form. `at` is at most `PAD − 16` while every
/// length so far was at most 8; past that the object is already malformed
/// (a length above 8 sets the error) and the load is clamped to the window.
#[inline(always)]
fn word_at(bytes: &[u8; PAD], at: usize, len: u8) -> (i64, bool) {
    let at = at.min(PAD - 8);
    let raw = bytes
        .get(at..at.wrapping_add(8))
        .and_then(|b| <[u8; 8]>::try_from(b).ok())
        .map_or(0, i64::from_le_bytes);
    if len == 0 {
        return (0, false);
    }
    if len > 8 {
        return (0, true);
    }
    // Sign-extend the low `len` bytes. Canonical: the value does not fit
    // one byte fewer (one byte: it is not 0).
    let shift = 64u32.wrapping_sub(u32::from(len).wrapping_mul(8));
    let v = raw.wrapping_shl(shift).wrapping_shr(shift);
    let narrower = shift.wrapping_add(8);
    let wrong = if len == 1 {
        v == 0
    } else {
        v.wrapping_shl(narrower).wrapping_shr(narrower) == v
    };
    (v, wrong)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_lengths_are_the_shortest_twos_complement() {
        let cases: [(i64, u32); 12] = [
            (0, 0),
            (1, 1),
            (-1, 1),
            (127, 1),
            (-128, 1),
            (128, 2),
            (-129, 2),
            (1 << 31, 5),
            (-(1 << 31), 4),
            (1 << 32, 5),
            (i64::MAX, 8),
            (i64::MIN, 8),
        ];
        for (v, n) in cases {
            assert_eq!(byte_len(v), n, "{v}");
        }
    }

    #[test]
    fn words_round_trip_and_non_canonical_forms_are_refused() {
        let words = [0, 5, -1, 1 << 40, i64::MIN, i64::MAX, -300];
        let mut buf = Vec::new();
        let mut e = Enc::new(&mut buf);
        e.words(&words);
        e.finish();
        // Lengths 0,1,1,6,8,8,2: four length bytes, 26 word bytes.
        assert_eq!(buf.len(), 4 + 26);
        let mut out = [0i64; 7];
        let mut d = Dec::new(&buf);
        d.words(&mut out).unwrap();
        assert_eq!(out, words);
        assert_eq!(d.remaining(), 0);
        // Truncated anywhere: an error, never a panic.
        for cut in 0..buf.len() {
            let mut out = [0i64; 7];
            assert!(Dec::new(&buf[..cut]).words(&mut out).is_err(), "{cut}");
        }
        // 5 written in 2 bytes; a length of 9; a padding nibble.
        // Each near the end of the bytes and far from it (the fast path).
        for bad in [vec![0x02u8, 5, 0], vec![0x09u8], vec![0x10u8]] {
            let mut one = [0i64; 1];
            assert!(Dec::new(&bad).words(&mut one).is_err(), "{bad:?}");
            let mut far = bad.clone();
            far.resize(300, 0);
            assert!(Dec::new(&far).words(&mut one).is_err(), "{bad:?}");
        }
        // Far from the end the fast path reads the same words.
        let mut far = buf.clone();
        far.resize(buf.len() + 300, 0xff);
        let mut d = Dec::new(&far);
        d.words(&mut out).unwrap();
        assert_eq!(out, words);
        assert_eq!(d.remaining(), 300);
    }
}
