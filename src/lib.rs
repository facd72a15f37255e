//! Tamias2D: a deterministic 2D rigid-body physics engine in I32F32 fixed point.
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]
#![cfg_attr(not(test), deny(clippy::float_arithmetic))]

pub mod arbiter;
pub mod arena;
pub mod body;
pub mod broadphase;
pub mod checksum;
pub mod collision;
#[cfg(feature = "debug-draw")]
pub mod debug_draw;
pub mod math;
pub mod replay;
pub mod scenes;
pub mod shape;
pub mod snapshot;
pub mod solver;
pub mod space;

pub use math::{Real, RealError, Rot, Transform, Vect, BB};
