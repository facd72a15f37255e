//! The compact binary form of the per-object state (format version 6).
//!
//! [`Body`](crate::body::Body), [`Shape`](crate::shape::Shape),
//! [`Geometry`](crate::shape::Geometry) and
//! [`Arbiter`](crate::arbiter::Arbiter) have hand-written serde impls with
//! two forms:
//! * for a **binary** serializer (`is_human_readable() == false`: bincode,
//!   so every snapshot, and any other container that encodes these types
//!   with the snapshot's configuration), a compact tuple: a 32-bit head of
//!   flags and a *presence mask*, a few fixed integers, then only the `Real`
//!   words that are not zero, as raw little-endian integers: 4 bytes when
//!   the raw value fits an `i32` (|x| < 0.5; bodies and arbiters, with a
//!   *narrow mask*), 8 otherwise. Fields that are a
//!   pure function of the stored ones (inverse mass and moment, polygon and
//!   segment normals, unused polygon vertices, contact slots past the count)
//!   are not written and are recomputed on decode, exactly as the engine
//!   computes them;
//! * for a **human-readable** one (JSON), the plain field-by-field form of
//!   a serde derive, derived fields included (tests and tools edit that
//!   form; validation checks the derived fields there as everywhere).
//!
//! The encoding is canonical: a word whose mask bit is set must not be
//! zero, a word written in 8 bytes must not fit 4 (where the type has a
//! narrow mask), and head bits with no meaning must be clear; the decoder rejects
//! anything else ([`SnapshotError::Decode`](crate::snapshot::SnapshotError::Decode)),
//! so one state has one encoding. Decoding never panics and allocates
//! nothing per object; what it builds is then validated like any state.
use core::marker::PhantomData;

use serde::de::{self, Deserialize, Deserializer, SeqAccess, Visitor};
use serde::ser::{SerializeTuple, Serializer};

use crate::math::Real;

/// `1 << i` for `i < 32`; 0 past the top (never asked for).
#[inline]
pub(crate) const fn bit(i: usize) -> u32 {
    match 1u32.checked_shl(i as u32) {
        Some(b) if i < 32 => b,
        _ => 0,
    }
}

/// The presence mask of `words`: bit `i` set when `words[i]` is not zero
/// (at most 32 words).
#[inline]
pub(crate) fn mask_of(words: &[Real]) -> u32 {
    words
        .iter()
        .enumerate()
        .fold(0, |m, (i, w)| if w.is_zero() { m } else { m | bit(i) })
}

/// Number of elements the `mask`ed words take.
#[inline]
pub(crate) fn count(mask: u32) -> usize {
    mask.count_ones() as usize
}

/// The narrow mask of `words` within `mask`: bit `i` set when word `i` is
/// present and its raw value fits an `i32` (written in 4 bytes).
#[inline]
pub(crate) fn narrow_of(words: &[Real], mask: u32) -> u32 {
    words.iter().enumerate().fold(0, |m, (i, w)| {
        if mask & bit(i) != 0 && i32::try_from(w.to_bits()).is_ok() {
            m | bit(i)
        } else {
            m
        }
    })
}

/// Writes the words of `words` whose bit is set in `mask`, in order: as an
/// `i32` when their bit is set in `narrow`, as an `i64` otherwise.
#[inline]
pub(crate) fn write_words<T: SerializeTuple>(
    t: &mut T,
    words: &[Real],
    mask: u32,
    narrow: u32,
) -> Result<(), T::Error> {
    for (i, w) in words.iter().enumerate() {
        if mask & bit(i) == 0 {
            continue;
        }
        let raw = w.to_bits();
        match i32::try_from(raw) {
            Ok(small) if narrow & bit(i) != 0 => t.serialize_element(&small)?,
            _ => t.serialize_element(&raw)?,
        }
    }
    Ok(())
}

/// A type with a compact binary form, read from a tuple's elements.
pub(crate) trait Compact: Sized {
    /// What the decoder expected, for error messages.
    const EXPECTING: &'static str;
    /// The most tuple elements the form can take.
    const MAX_ELEMENTS: usize;
    /// Reads the value from its elements (the head first).
    fn read<'de, A: SeqAccess<'de>>(r: &mut Reader<'de, A>) -> Result<Self, A::Error>;
}

/// The compact form of `T` from a binary deserializer.
pub(crate) fn deserialize<'de, T: Compact, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
    d.deserialize_tuple(T::MAX_ELEMENTS, Visit::<T>(PhantomData))
}

struct Visit<T>(PhantomData<fn() -> T>);

impl<'de, T: Compact> Visitor<'de> for Visit<T> {
    type Value = T;

    fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(T::EXPECTING)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<T, A::Error> {
        let mut r = Reader {
            seq,
            at: 0,
            expecting: T::EXPECTING,
            _de: PhantomData,
        };
        T::read(&mut r)
    }
}

/// The elements of one compact tuple, read in order.
pub(crate) struct Reader<'de, A> {
    seq: A,
    at: usize,
    expecting: &'static str,
    _de: PhantomData<&'de ()>,
}

impl<'de, A: SeqAccess<'de>> Reader<'de, A> {
    /// The next element.
    #[inline]
    pub(crate) fn next<T: Deserialize<'de>>(&mut self) -> Result<T, A::Error> {
        match self.seq.next_element()? {
            Some(v) => {
                self.at = self.at.saturating_add(1);
                Ok(v)
            }
            None => Err(de::Error::invalid_length(self.at, &self.expecting)),
        }
    }

    /// A decode error naming the type being read.
    pub(crate) fn error(&self, what: &str) -> A::Error {
        de::Error::custom(format_args!("{}: {what}", self.expecting))
    }

    /// Checks that `head` has no bit outside `allowed`.
    #[inline]
    pub(crate) fn check_head(&self, head: u32, allowed: u32) -> Result<(), A::Error> {
        if head & !allowed == 0 {
            Ok(())
        } else {
            Err(self.error("unknown bits set in the head"))
        }
    }

    /// Fills `out`: word `i` is read when bit `i` of `mask` is set, zero
    /// otherwise. With a narrow mask (`Some`: bodies, arbiters) a word is
    /// an `i32` when its bit is set there and an `i64` otherwise; without
    /// one (`None`: shapes, geometry) always an `i64`. Canonical form: a
    /// present word is not zero; with a narrow mask, a wide word does not
    /// fit an `i32` and the narrow mask has no bit outside `mask`.
    #[inline]
    pub(crate) fn words(
        &mut self,
        mask: u32,
        narrow: Option<u32>,
        out: &mut [Real],
    ) -> Result<(), A::Error> {
        let narrowing = narrow.is_some();
        let narrow = narrow.unwrap_or(0);
        if narrow & !mask != 0 {
            return Err(self.error("a narrow word that is not present"));
        }
        for (i, w) in out.iter_mut().enumerate() {
            *w = if mask & bit(i) == 0 {
                Real::ZERO
            } else if narrow & bit(i) != 0 {
                let raw: i32 = self.next()?;
                if raw == 0 {
                    return Err(self.error("a word marked present is zero"));
                }
                Real::from_bits(i64::from(raw))
            } else {
                let raw: i64 = self.next()?;
                if raw == 0 {
                    return Err(self.error("a word marked present is zero"));
                }
                if narrowing && i32::try_from(raw).is_ok() {
                    return Err(self.error("a wide word that fits 4 bytes"));
                }
                Real::from_bits(raw)
            };
        }
        Ok(())
    }
}

/// Starts the compact tuple of `len` elements.
#[inline]
pub(crate) fn tuple<S: Serializer>(s: S, len: usize) -> Result<S::SerializeTuple, S::Error> {
    s.serialize_tuple(len)
}

#[cfg(test)]
mod tests {
    use crate::body::Body;
    use crate::math::{Real, Vect, BB};
    use crate::shape::{Geometry, Poly, Segment};
    use crate::snapshot::CONFIG;

    fn encode<T: serde::Serialize>(v: &T) -> Vec<u8> {
        bincode::serde::encode_to_vec(v, CONFIG).unwrap()
    }

    fn decode<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Result<T, String> {
        match bincode::serde::decode_from_slice::<T, _>(bytes, CONFIG) {
            Ok((v, n)) if n == bytes.len() => Ok(v),
            Ok((_, n)) => Err(format!("{n} of {} bytes read", bytes.len())),
            Err(e) => Err(e.to_string()),
        }
    }

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    #[test]
    fn geometry_of_every_form_round_trips_with_its_derived_fields() {
        let pentagon = Poly::from_ccw(&[v(0, 0), v(2, 0), v(3, 1), v(1, 3), v(-1, 1)], Real::ONE);
        let cases = [
            (
                Geometry::Poly(Poly::new_box(v(3, 0).x, v(1, 0).x, Real::ZERO).unwrap()),
                4 + 16,
            ),
            (
                Geometry::Poly(
                    Poly::from_bb(
                        BB::new(v(1, 0).x, v(2, 0).x, v(4, 0).x, v(3, 0).x),
                        Real::ONE,
                    )
                    .unwrap(),
                ),
                4 + 5 * 8,
            ),
            // 11 words, three of them zero.
            (Geometry::Poly(pentagon.unwrap()), 4 + 8 * 8),
            (
                Geometry::Segment(
                    Segment::new(v(1, 2), v(-3, 4), Real::ONE).with_neighbors(v(0, 0), v(5, 5)),
                ),
                4 + 9 * 8,
            ),
        ];
        // Small words (they fit 4 bytes) are still written in 8: geometry
        // has no narrow mask.
        let quarter = Real::from_bits(1 << 30);
        let small = Geometry::Circle(crate::shape::Circle::new(
            quarter,
            Vect::new(-quarter, Real::from_bits(3)),
        ));
        let cases = cases.into_iter().chain([(small, 4 + 3 * 8)]);
        for (g, len) in cases {
            let bytes = encode(&g);
            assert_eq!(bytes.len(), len, "{g:?}");
            assert_eq!(decode::<Geometry>(&bytes), Ok(g));
            // The derived fields came back: the geometry is valid as stored.
            assert_eq!(g.validate(), Ok(()));
        }
    }

    #[test]
    fn non_canonical_bytes_do_not_decode() {
        // A static body at the origin: head, then rot.c (word 11).
        let body = Body::new_static();
        let bytes = encode(&body);
        assert_eq!(bytes.len(), 4 + 8);
        assert_eq!(decode::<Body>(&bytes), Ok(body));
        let head = u32::from_le_bytes(bytes[..4].try_into().unwrap());
        // Word 0 (mass) marked present but zero.
        let mut zero = (head | 1).to_le_bytes().to_vec();
        zero.extend_from_slice(&0i64.to_le_bytes());
        zero.extend_from_slice(&bytes[4..]);
        assert!(decode::<Body>(&zero).unwrap_err().contains("zero"));
        // A head bit without a meaning; body type 3.
        for bad in [head | 1 << 20, head | 3 << 24] {
            let mut b = bytes.clone();
            b[..4].copy_from_slice(&bad.to_le_bytes());
            assert!(decode::<Body>(&b).is_err(), "{bad:#x}");
        }
        // A rectangle written in the general form.
        let bx = Geometry::Poly(Poly::new_box(Real::ONE, Real::ONE, Real::ZERO).unwrap());
        let half = Real::HALF.to_bits();
        let mut general = (2u32 | 4 << 2 | 0xff << 8).to_le_bytes().to_vec();
        for w in [half, -half, half, half, -half, half, -half, -half] {
            general.extend_from_slice(&w.to_le_bytes());
        }
        assert!(decode::<Geometry>(&general).unwrap_err().contains("form"));
        assert_eq!(decode::<Geometry>(&encode(&bx)), Ok(bx));
        // Narrow words: a body at rest near the origin with a small spin.
        let mut moving = Body::new(Real::ONE, Real::ONE).unwrap();
        moving.set_velocity(Vect::new(Real::from_bits(-5), Real::from_bits(1 << 31)));
        moving.set_angular_velocity(Real::from_bits(i64::from(i32::MIN)));
        let bytes = encode(&moving);
        // head, narrow mask, mass, moment, rot.c (wide), v.x, w (narrow),
        // v.y (2^31: wide).
        assert_eq!(bytes.len(), 4 + 4 + 3 * 8 + 2 * 4 + 8);
        assert_eq!(decode::<Body>(&bytes), Ok(moving.clone()));
        // The same body with v.x written wide: not canonical.
        let head = u32::from_le_bytes(bytes[..4].try_into().unwrap());
        let narrow = u32::from_le_bytes(bytes[4..8].try_into().unwrap());
        let v_x = 1 << 6;
        assert_ne!(narrow & v_x, 0);
        let mut wide = bytes[..4].to_vec();
        wide.extend_from_slice(&(narrow & !v_x).to_le_bytes());
        wide.extend_from_slice(&bytes[8..24]); // mass, moment
        wide.extend_from_slice(&(-5i64).to_le_bytes());
        wide.extend_from_slice(&bytes[28..]); // v.y, rot.c, w
        assert!(
            decode::<Body>(&wide).unwrap_err().contains("fits"),
            "{head:#x}"
        );
        // A narrow bit for an absent word; an empty narrow mask.
        for bad in [narrow | 1 << 2, 0] {
            let mut b = bytes.clone();
            b[4..8].copy_from_slice(&bad.to_le_bytes());
            assert!(decode::<Body>(&b).is_err(), "{bad:#x}");
        }
        // A polygon of 9 vertices.
        let nine = (2u32 | 9 << 2).to_le_bytes();
        assert!(decode::<Geometry>(&nine).is_err());
    }
}
