//! A cheap, portable 64-bit checksum of the simulation state, for desync
//! detection every frame.
//!
//! The state types derive `Hash`; [`WordHasher`] consumes the integers that
//! `Hash` feeds it **as integer values**, one 64-bit word at a time (never as
//! bytes in memory order, never with `usize` width), so the digest is the
//! same on 32- and 64-bit, little- and big-endian targets. The mixing is a
//! multiply–xorshift in the style of FxHash/SplitMix: not cryptographic, but
//! every bit of every word reaches the result.
//!
//! Caveat for state types: `Hash` for slices of primitive integers
//! (`[u32]`, `[i64]`) writes native-endian *bytes*; state types hash such
//! slices element by element instead (see `Arena`'s `Hash`).
//!
//! Coverage: the checksum sees every field of the state because every state
//! type derives `Hash`, except `Arena`, `Handle` and `WorldState`, whose
//! hand-written impls destructure the type with no `..` (a new field does
//! not compile until it is hashed or, like a handle's origin tag, said not
//! to be state). `WorldState`'s impl is the derive's, except that a
//! constraint arena that never had a slot adds nothing: a world without
//! joints hashes exactly as before joints existed, so the goldens of
//! joint-free scenes did not move when constraints became state.
//! `tests/mirrors.rs` changes every leaf of a world in turn and checks that
//! the checksum changes.
use core::hash::{Hash, Hasher};

/// Number of lanes (independent multiply chains).
const LANES: usize = 8;

/// The multiplier of the lane step (2^64 / φ, odd).
const K: u64 = 0x9E37_79B9_7F4A_7C15;

/// One step of a lane: injective in the word for a fixed lane, a
/// bijection of the lane for a fixed word.
#[inline(always)]
fn mix(lane: u64, w: u64) -> u64 {
    // Multiplication modulo 2^64 is the mix itself: `wrapping_mul` here
    // (and in `finish`) is the intended semantics, not an overflow.
    (lane ^ w).wrapping_mul(K).rotate_left(29)
}

/// Deterministic word-at-a-time hasher with independent lanes (see the
/// module docs).
#[derive(Clone, Copy, Debug)]
pub struct WordHasher {
    /// `lanes[0]` takes the next word; the lanes then rotate.
    lanes: [u64; LANES],
}

impl Default for WordHasher {
    fn default() -> Self {
        // π's fraction bits (as the snapshot's payload checksum): any
        // distinct seeds work.
        WordHasher {
            lanes: [
                0x243F_6A88_85A3_08D3,
                0x1319_8A2E_0370_7344,
                0xA409_3822_299F_31D0,
                0x082E_FA98_EC4E_6C89,
                0x4528_21E6_38D0_1377,
                0xBE54_66CF_34E9_0C6C,
                0xC0AC_29B7_C97C_50DD,
                0x3F84_D5B5_B547_0917,
            ],
        }
    }
}

impl WordHasher {
    /// Mixes `w` into the first lane and rotates the lanes, so word `k` of
    /// the stream goes to lane `k mod LANES`. The rotation is free once the
    /// lanes are in registers (the compiler renames them).
    #[inline(always)]
    fn word(&mut self, w: u64) {
        let [a, b, c, d, e, f, g, i] = self.lanes;
        self.lanes = [b, c, d, e, f, g, i, mix(a, w)];
    }
}

impl Hasher for WordHasher {
    fn finish(&self) -> u64 {
        // The lanes folded into one word (each fold step is a bijection of
        // the lane folded in), then SplitMix64's finaliser.
        let [a, b, c, d, e, f, g, i] = self.lanes;
        let mut z = mix(mix(mix(mix(mix(mix(mix(a, b), c), d), e), f), g), i);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn write(&mut self, bytes: &[u8]) {
        // Only strings reach this path; bytes are order-defined already.
        for chunk in bytes.chunks(8) {
            let mut w = [0u8; 8];
            for (d, s) in w.iter_mut().zip(chunk) {
                *d = *s;
            }
            self.word(u64::from_le_bytes(w));
        }
        self.word(bytes.len() as u64);
    }
    fn write_u8(&mut self, v: u8) {
        self.word(u64::from(v));
    }
    fn write_u16(&mut self, v: u16) {
        self.word(u64::from(v));
    }
    fn write_u32(&mut self, v: u32) {
        self.word(u64::from(v));
    }
    fn write_u64(&mut self, v: u64) {
        self.word(v);
    }
    fn write_u128(&mut self, v: u128) {
        self.word(v as u64);
        self.word((v >> 64) as u64);
    }
    fn write_usize(&mut self, v: usize) {
        self.word(v as u64);
    }
    fn write_i8(&mut self, v: i8) {
        self.word(v as i64 as u64);
    }
    fn write_i16(&mut self, v: i16) {
        self.word(v as i64 as u64);
    }
    fn write_i32(&mut self, v: i32) {
        self.word(v as i64 as u64);
    }
    fn write_i64(&mut self, v: i64) {
        self.word(v as u64);
    }
    fn write_i128(&mut self, v: i128) {
        self.write_u128(v as u128);
    }
    fn write_isize(&mut self, v: isize) {
        self.word(v as i64 as u64);
    }
}

/// The checksum of any `Hash` value under [`WordHasher`].
pub fn checksum_of<T: Hash + ?Sized>(value: &T) -> u64 {
    let mut h = WordHasher::default();
    value.hash(&mut h);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usize_and_u64_hash_alike_so_32_and_64_bit_agree() {
        let mut a = WordHasher::default();
        a.write_usize(7);
        let mut b = WordHasher::default();
        b.write_u64(7);
        assert_eq!(a.finish(), b.finish());
    }

    #[test]
    fn order_and_value_change_the_digest() {
        assert_ne!(checksum_of(&(1i64, 2i64)), checksum_of(&(2i64, 1i64)));
        assert_ne!(checksum_of(&1i64), checksum_of(&2i64));
    }
}
