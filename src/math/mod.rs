//! Deterministic fixed-point math: the scalar [`Real`], vectors, rotations,
//! affine transforms and bounding boxes.
pub mod real;
pub mod trig;

pub use real::{Real, RealError};
