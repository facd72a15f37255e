//! Tamias2D: a deterministic 2D rigid-body physics engine in I32F32 fixed point.
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]
#![cfg_attr(not(test), deny(clippy::float_arithmetic))]
// No reachable panic in library code: every index is checked
// (`get`), every fallible conversion handled. Tests may unwrap. No plain
// integer arithmetic either (`arithmetic_side_effects`; `Real` and `Vect`
// operators saturate and are exempt in clippy.toml): wide helpers,
// saturating or checked operations that provably never saturate, or a local
// `allow` with a range proof.
#![cfg_attr(
    not(test),
    deny(
        clippy::arithmetic_side_effects,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

pub mod arbiter;
pub mod arena;
pub mod body;
pub mod character;
// Engine internals (not user API): public only for benches and the MIS
// conformance map, hidden from the documentation.
#[doc(hidden)]
pub mod broadphase;
pub mod checksum;
pub mod collision;
mod compact;
pub mod constraint;
#[cfg(feature = "debug-draw")]
pub mod debug_draw;
pub mod envelope;
/// The guide to using the library (`docs/guide.md`): every example in it is a
/// doctest.
#[doc = include_str!("../docs/guide.md")]
pub mod guide {}
pub mod limits;
pub mod math;
pub mod replay;
pub mod shape;
pub mod snapshot;
#[doc(hidden)]
pub mod solver;
pub mod space;
mod threads;

pub use math::{Real, RealError, Rot, Transform, Vect, BB};
