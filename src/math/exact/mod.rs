//! Exact integer arithmetic: everything the engine computes on more bits
//! than a [`Real`](super::Real) holds, in one module with two layers.
//!
//! * [`int`], below `Real`: [`wide_mul`], the exact `i64 × i64 → i128`
//!   product behind `Real`'s own multiplication, and [`I256`] for exact sums
//!   of products of `i128`s (mass integrals, kinetic energy, the hull's
//!   orientation far from the origin); the caller rounds once at the end.
//! * [`predicates`], above `Real` and `Vect`: raw sums, differences and squares of
//!   `Real` bits on `i128` ([`raw_sum`], [`raw_diff`], [`raw_sq`]), the exact
//!   vector predicates ([`dot`], [`cross`], [`len_sq`]) and the precise
//!   [`normalize`] of the collision code. Every decision GJK and EPA take
//!   (which vertex is the support point, which side of an edge the origin is
//!   on, whether a new point makes progress) is a sign of a dot or cross
//!   product. Computed on the raw `i64` bits of the operands, a product fits
//!   an `i128` exactly, so these decisions are *exact*: no rounding can make
//!   the algorithms cycle, and the same inputs take the same branch on every
//!   platform. Only the final outputs (points, normal, distance) are rounded,
//!   once each.
//!
//! The two layers keep the module graph free of circles: `Real` and `Vect`
//! use `int`, and `predicates` uses them.
//!
//! Units: a raw product of two `Real`s is in units of 2^-64.
//!
//! Every operation here is exact for the stated operand ranges; the
//! `saturating_*` calls never saturate on raw `Real` bits (each says why)
//! and only give a defined result instead of a panic or a wrap if a future
//! caller breaks the stated bound; the vector predicates' sums saturate only
//! for operands near `Real::MIN`/`MAX`, far outside the envelope.
pub(crate) mod int;
pub(crate) mod predicates;

pub(crate) use int::{wide_mul, I256};
pub(crate) use predicates::{
    cross, dot, dot_unit, len_sq, normalize, raw_diff, raw_sq, raw_sum, saturate_to_real,
    scale_by_ratio, unit_or, unit_ratio,
};
