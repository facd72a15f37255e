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

/// The words of one object, gathered before writing.
pub(crate) struct Words {
    w: [i64; MAX_WORDS],
    n: usize,
}

impl Words {
    #[inline(always)]
    pub(crate) fn new() -> Words {
        Words {
            w: [0; MAX_WORDS],
            n: 0,
        }
    }

    /// Appends a word (past [`MAX_WORDS`] it is dropped: no object has
    /// that many).
    #[inline(always)]
    pub(crate) fn push(&mut self, v: i64) {
        if let Some(slot) = self.w.get_mut(self.n) {
            *slot = v;
            self.n = self.n.saturating_add(1);
        }
    }

    /// Appends fixed-point values as their raw words.
    #[inline(always)]
    pub(crate) fn reals(&mut self, v: &[crate::math::Real]) {
        for x in v {
            self.push(x.to_bits());
        }
    }

    #[inline(always)]
    pub(crate) fn as_slice(&self) -> &[i64] {
        self.w.get(..self.n).unwrap_or(&[])
    }
}

/// Bytes of one object's coding at most (a head, the lengths, the
/// words), plus room for the last word's whole store.
const OBJECT_MAX: usize = 8 + MAX_WORDS / 2 + 8 * MAX_WORDS + 8;
/// The encoder's staging buffer: objects are built there and copied into
/// the output a few kilobytes at a time.
const STAGE: usize = 16 * 1024;

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
    pub(crate) fn finish(mut self) {
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

    /// Writes `words` (at most [`MAX_WORDS`]; more are not written, which
    /// the reader of a fixed list rejects) in the coding above.
    #[inline]
    pub(crate) fn words(&mut self, words: &[i64]) {
        self.room();
        let words = words.get(..MAX_WORDS).unwrap_or(words);
        // Each word stored whole (one 8-byte store) at the current end and
        // the end moved by its length; the lengths packed in front after.
        let lens_at = self.at;
        let mut lens = [0u8; MAX_WORDS];
        let mut end = lens_at.saturating_add(words.len().div_ceil(2));
        for (l, &w) in lens.iter_mut().zip(words) {
            let len = byte_len(w);
            if let Some(dst) = self.stage.get_mut(end..end.saturating_add(8)) {
                dst.copy_from_slice(&w.to_le_bytes());
            }
            end = end.saturating_add(len as usize);
            // At most 8: a nibble.
            *l = len as u8;
        }
        for (dst, pair) in self
            .stage
            .iter_mut()
            .skip(lens_at)
            .zip(lens.chunks_exact(2).take(words.len().div_ceil(2)))
        {
            if let [lo, hi] = *pair {
                *dst = lo | hi.wrapping_shl(4);
            }
        }
        self.at = end;
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
}

impl<'a> Dec<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Dec<'a> {
        Dec { bytes, at: 0 }
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
        let n = out.len();
        if n > MAX_WORDS {
            return Err(self.error("too many words"));
        }
        let lens = self.take(n.div_ceil(2))?;
        if n % 2 == 1 && lens.last().is_some_and(|b| b >> 4 != 0) {
            return Err(self.error("a padding length that is not 0"));
        }
        let mut total = 0usize;
        for &b in lens {
            let (lo, hi) = (b & 15, b >> 4);
            if lo > 8 || hi > 8 {
                return Err(self.error("a word length above 8"));
            }
            total = total.saturating_add(usize::from(lo).saturating_add(usize::from(hi)));
        }
        let start = self.at;
        let body = self.take(total)?;
        // Each word read whole (one 8-byte load) where 8 bytes remain from
        // its start, byte by byte near the end of the bytes.
        let mut at = 0usize;
        for (i, w) in out.iter_mut().enumerate() {
            let byte = lens.get(i / 2).copied().unwrap_or(0);
            let len = u32::from(byte.wrapping_shr(4 * (i as u32 % 2)) & 15);
            if len == 0 {
                *w = 0;
                continue;
            }
            let raw = match self
                .bytes
                .get(start.saturating_add(at)..start.saturating_add(at).saturating_add(8))
                .and_then(|b| <[u8; 8]>::try_from(b).ok())
            {
                Some(b) => i64::from_le_bytes(b),
                None => {
                    let mut b = [0u8; 8];
                    for (d, s) in b.iter_mut().zip(body.get(at..).unwrap_or(&[])) {
                        *d = *s;
                    }
                    i64::from_le_bytes(b)
                }
            };
            // Sign-extend the low `len` bytes. Canonical: the value does not
            // fit one byte fewer (for one byte: it is not 0).
            let shift = 64u32.saturating_sub(len.saturating_mul(8));
            let v = raw.wrapping_shl(shift).wrapping_shr(shift);
            let narrower = shift.saturating_add(8);
            let fits_shorter = if len == 1 {
                v == 0
            } else {
                v.wrapping_shl(narrower).wrapping_shr(narrower) == v
            };
            if fits_shorter {
                return Err(WireError {
                    what: "a word longer than its shortest form",
                    at: start.saturating_add(at),
                });
            }
            *w = v;
            at = at.saturating_add(len as usize);
        }
        Ok(())
    }
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
        for bad in [vec![0x02u8, 5, 0], vec![0x09u8], vec![0x10u8]] {
            let mut one = [0i64; 1];
            assert!(Dec::new(&bad).words(&mut one).is_err(), "{bad:?}");
        }
    }
}
