//! Deterministic fixed-point math: the scalar [`Real`], vectors, rotations,
//! affine transforms and bounding boxes.
pub mod bb;
pub(crate) mod exact;
pub mod exp;
pub(crate) mod lanes;
pub mod real;
pub mod rot;
pub mod transform;
pub mod trig;
pub mod unsaturated;
pub mod vect;

pub use bb::BB;
pub use real::{Real, RealError};
pub use rot::Rot;
pub use transform::Transform;
pub(crate) use unsaturated::{below_2_62, range_record, Bounded, Ranged, RANGED_INPUT};
pub use unsaturated::{FixedArith, Saturating, Unsaturated};
pub use vect::Vect;
