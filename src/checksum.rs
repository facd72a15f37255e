//! A cheap, portable 64-bit checksum of the simulation state, for desync
//! detection every frame.
//!
//! **Portable.** [`WordHasher`] consumes the integers that `Hash` feeds it
//! **as integer values**, one 64-bit word per `write_*` call (never as bytes
//! in memory order, never with `usize` width; bytes given to `write` are
//! read as little-endian words), and mixes them with wrapping
//! multiplication, xor and rotation only, so the digest is the same on 32-
//! and 64-bit, little- and big-endian targets, in debug and release builds.
//!
//! **Lanes.** Word `k` of the stream goes to lane `k mod 8` of eight
//! independent lanes. A lane step is `lane = rotl((lane ^ w) · K, 29)`
//! (`K` = 2^64/φ, odd): injective in the word for a fixed lane, a bijection
//! of the lane for a fixed word, so a change of any one word changes its
//! lane's final value; `finish` folds the eight lanes into one word (each
//! fold step a bijection of the lane folded in) and applies SplitMix64's
//! finaliser, so the change reaches every bit of the result. One lane alone
//! would be a serial chain, every word waiting for the multiply of the word
//! before it (about 5 cycles); eight chains let the processor overlap eight
//! multiplies, and a word costs about three instructions (xor with the
//! loaded word, multiply, rotate). The lanes rotate by one position per
//! word (`[b, c, …, h, mix(a, w)]`), which is free once the hasher sits in
//! registers: the compiler renames them. The hot `Hash` impls are inlined
//! into the arena and slice loops for that. Not cryptographic: a desync
//! detector, not a defence against crafted states.
//!
//! **Words per object.** The hot state types hand-write `Hash` (`Body`,
//! `Shape`, `Geometry`, `Poly`, `Arbiter`, `Handle` and the arena slots):
//! small fields are packed into one word (a handle's index and generation;
//! a body's type, flags and sleeping island; an arbiter's contact count,
//! state, sensor flag and warm-start id; a shape's filter and collision
//! type, its sensor flag, mass kind, geometry kind and vertex count), every
//! number is one word, and a polygon's normals, which follow from its
//! vertices in every valid state, are folded by exclusive or into one
//! word. Fixed-size arrays (a polygon's vertex slots, an arbiter's contact
//! slots) are hashed whole, with no branch on their count: the slots past
//! the count are zero in every valid state.
//!
//! Caveat for state types: `Hash` for slices of primitive integers
//! (`[u32]`, `[i64]`) writes native-endian *bytes*; state types hash such
//! slices element by element instead (see `Arena`'s `Hash`).
//!
//! Coverage: the checksum sees every field of the state. The types that
//! derive `Hash` hash every field; every hand-written impl destructures its
//! type with no `..` (a new field does not compile until it is hashed or,
//! like a handle's origin tag, said not to be state). `Space::checksum`
//! walks the frame (`space/frame.rs`: every slot outside the static level,
//! each slot as its index then generation and occupancy in one word, see
//! `arena::hash_part`) after the level's digest, itself a hash of the level
//! objects under this hasher; a constraint arena that never had a slot adds
//! nothing. `tests/determinism/desync_coverage.rs` changes every leaf of a world in turn
//! (unused vertex and contact slots and normals included) and checks that
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
    #[inline]
    fn finish(&self) -> u64 {
        // The lanes folded into one word (each fold step is a bijection of
        // the lane folded in), then SplitMix64's finaliser.
        let [a, b, c, d, e, f, g, i] = self.lanes;
        let mut z = mix(mix(mix(mix(mix(mix(mix(a, b), c), d), e), f), g), i);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        // Byte strings (strings, file payloads): little-endian words, the
        // last one zero-padded, then the length.
        let words = bytes.chunks_exact(8);
        let tail = words.remainder();
        for w in words {
            let mut le = [0u8; 8];
            le.copy_from_slice(w);
            self.word(u64::from_le_bytes(le));
        }
        if !tail.is_empty() {
            let mut le = [0u8; 8];
            for (d, s) in le.iter_mut().zip(tail) {
                *d = *s;
            }
            self.word(u64::from_le_bytes(le));
        }
        self.word(bytes.len() as u64);
    }
    #[inline]
    fn write_u8(&mut self, v: u8) {
        self.word(u64::from(v));
    }
    #[inline]
    fn write_u16(&mut self, v: u16) {
        self.word(u64::from(v));
    }
    #[inline]
    fn write_u32(&mut self, v: u32) {
        self.word(u64::from(v));
    }
    #[inline]
    fn write_u64(&mut self, v: u64) {
        self.word(v);
    }
    #[inline]
    fn write_u128(&mut self, v: u128) {
        self.word(v as u64);
        self.word((v >> 64) as u64);
    }
    #[inline]
    fn write_usize(&mut self, v: usize) {
        self.word(v as u64);
    }
    #[inline]
    fn write_i8(&mut self, v: i8) {
        self.word(v as i64 as u64);
    }
    #[inline]
    fn write_i16(&mut self, v: i16) {
        self.word(v as i64 as u64);
    }
    #[inline]
    fn write_i32(&mut self, v: i32) {
        self.word(v as i64 as u64);
    }
    #[inline]
    fn write_i64(&mut self, v: i64) {
        self.word(v as u64);
    }
    #[inline]
    fn write_i128(&mut self, v: i128) {
        self.write_u128(v as u128);
    }
    #[inline]
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

    const KNOWN_EMPTY: u64 = 0x73f5_7d69_f50d_33eb;
    const KNOWN_TUPLE: u64 = 0x2b68_2dbc_867b_164d;

    #[test]
    fn usize_and_u64_hash_alike_so_32_and_64_bit_agree() {
        let mut a = WordHasher::default();
        a.write_usize(7);
        let mut b = WordHasher::default();
        b.write_u64(7);
        assert_eq!(a.finish(), b.finish());
    }

    #[test]
    fn a_change_of_any_one_word_in_any_lane_changes_the_digest() {
        // 20 words: every lane gets two or three, the last ones partly.
        let words: Vec<u64> = (0..20u64).map(|i| i.wrapping_mul(K) ^ 0x5555).collect();
        let digest = |ws: &[u64]| {
            let mut h = WordHasher::default();
            for &w in ws {
                h.write_u64(w);
            }
            h.finish()
        };
        let base = digest(&words);
        for k in 0..words.len() {
            for bit in [0, 1, 31, 32, 62, 63] {
                let mut changed = words.clone();
                changed[k] ^= 1 << bit;
                assert_ne!(digest(&changed), base, "word {k}, bit {bit}");
            }
        }
        // Where a word falls (its lane) matters, and so does the length.
        assert_ne!(digest(&words[1..]), digest(&words[..19]));
        assert_ne!(digest(&[0; 8]), digest(&[0; 16]));
    }

    #[test]
    fn bytes_are_little_endian_words_then_the_length() {
        let mut a = WordHasher::default();
        a.write(&[1, 0, 0, 0, 0, 0, 0, 0, 2, 3]);
        let mut b = WordHasher::default();
        b.write_u64(1);
        b.write_u64(0x0302);
        b.write_u64(10);
        assert_eq!(a.finish(), b.finish());
    }

    #[test]
    fn known_answers() {
        // Pinned: the function is part of the format of every recorded
        // checksum (replays, goldens); a change must be deliberate. Only
        // integer values and wrapping arithmetic: the same on every target.
        assert_eq!(WordHasher::default().finish(), KNOWN_EMPTY);
        assert_eq!(checksum_of(&(1u8, -2i32, 3u64, "tamias")), KNOWN_TUPLE);
    }

    #[test]
    fn order_and_value_change_the_digest() {
        assert_ne!(checksum_of(&(1i64, 2i64)), checksum_of(&(2i64, 1i64)));
        assert_ne!(checksum_of(&1i64), checksum_of(&2i64));
    }
}
