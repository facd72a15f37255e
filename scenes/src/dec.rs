//! Decimal-string serde for [`Real`] in scene descriptions.
//!
//! Snapshots store a `Real` as its raw `i64` bits; scene files are meant to
//! be read and written by people and by other engines, so here a `Real` is a
//! decimal string: `"0.5"`, `"-9.81"`, `"0.0166666666"`. `fixed`'s `Display`
//! prints the shortest decimal that parses back to the same bits and its
//! `FromStr` rounds to nearest, so `Real → string → Real` is exact for every
//! value (the scene tests check this on random bit patterns). JSON integers
//! (`100`, `-3`) are accepted on input for convenience. JSON floats (`0.5`
//! without quotes) are **rejected**: they would go through `f64`, which
//! cannot hold most `Real`s and would make a scene file mean different
//! numbers to different readers.
//!
//! Use with `#[serde(with = "dec::real")]`, `dec::vect` (a `Vect` as
//! `["x", "y"]`) and `dec::vects` (a list of those).
use core::fmt;

use fixed::types::I32F32;
use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use tamias2d::math::{Real, Vect};

/// A `Real` that (de)serializes as a decimal string.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Dec(Real);

impl Serialize for Dec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(&self.0.to_fixed())
    }
}

struct DecVisitor;

impl DecVisitor {
    fn int<E: de::Error>(v: i128) -> Result<Dec, E> {
        i32::try_from(v)
            .map(|i| Dec(Real::from_int(i)))
            .map_err(|_| E::custom(format_args!("integer {v} is outside the Real range ±2^31")))
    }
}

impl Visitor<'_> for DecVisitor {
    type Value = Dec;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a decimal string such as \"0.5\" or an integer")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Dec, E> {
        I32F32::from_str(v)
            .map(|x| Dec(Real::from_fixed(x)))
            .map_err(|e| E::custom(format_args!("invalid real {v:?}: {e}")))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Dec, E> {
        DecVisitor::int(i128::from(v))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Dec, E> {
        DecVisitor::int(i128::from(v))
    }

    fn visit_i128<E: de::Error>(self, v: i128) -> Result<Dec, E> {
        DecVisitor::int(v)
    }

    fn visit_u128<E: de::Error>(self, v: u128) -> Result<Dec, E> {
        DecVisitor::int(i128::try_from(v).unwrap_or(i128::MAX))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Dec, E> {
        Err(E::custom(format_args!(
            "real {v} is a JSON float: write it as a decimal string (\"{v}\") so it is read exactly"
        )))
    }
}

impl<'de> Deserialize<'de> for Dec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Dec, D::Error> {
        d.deserialize_any(DecVisitor)
    }
}

/// A `Real` as a decimal string.
pub mod real {
    use super::*;

    /// Serializes as a decimal string.
    pub fn serialize<S: Serializer>(v: &Real, s: S) -> Result<S::Ok, S::Error> {
        Dec(*v).serialize(s)
    }

    /// Parses a decimal string or an integer.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Real, D::Error> {
        Dec::deserialize(d).map(|x| x.0)
    }
}

/// A `Vect` as `["x", "y"]`.
pub mod vect {
    use super::*;

    /// Serializes as a two-element array of decimal strings.
    pub fn serialize<S: Serializer>(v: &Vect, s: S) -> Result<S::Ok, S::Error> {
        [Dec(v.x), Dec(v.y)].serialize(s)
    }

    /// Parses a two-element array.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vect, D::Error> {
        <[Dec; 2]>::deserialize(d).map(|[x, y]| Vect::new(x.0, y.0))
    }
}

/// A list of `Vect`s as `[["x", "y"], …]`.
pub mod vects {
    use super::*;

    /// Serializes as an array of two-element arrays.
    pub fn serialize<S: Serializer>(v: &[Vect], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|p| [Dec(p.x), Dec(p.y)]))
    }

    /// Parses an array of two-element arrays.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vect>, D::Error> {
        let raw = Vec::<[Dec; 2]>::deserialize(d)?;
        Ok(raw.into_iter().map(|[x, y]| Vect::new(x.0, y.0)).collect())
    }
}

/// An optional `Real` as a decimal string (absent when `None`).
pub mod opt_real {
    use super::*;

    /// Serializes `Some` as a decimal string (use with
    /// `skip_serializing_if = "Option::is_none"`).
    pub fn serialize<S: Serializer>(v: &Option<Real>, s: S) -> Result<S::Ok, S::Error> {
        v.map(Dec).serialize(s)
    }

    /// Parses a decimal string or an integer.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Real>, D::Error> {
        Option::<Dec>::deserialize(d).map(|x| x.map(|x| x.0))
    }
}

/// An optional `Vect` as `["x", "y"]` (absent when `None`).
pub mod opt_vect {
    use super::*;

    /// Serializes `Some` as a two-element array of decimal strings.
    pub fn serialize<S: Serializer>(v: &Option<Vect>, s: S) -> Result<S::Ok, S::Error> {
        v.map(|v| [Dec(v.x), Dec(v.y)]).serialize(s)
    }

    /// Parses a two-element array.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vect>, D::Error> {
        Option::<[Dec; 2]>::deserialize(d).map(|x| x.map(|[x, y]| Vect::new(x.0, y.0)))
    }
}
