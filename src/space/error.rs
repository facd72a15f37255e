//! [`SpaceError`](super::SpaceError): what a space operation refuses, and why. Every error
//! leaves the space unchanged.
use core::fmt;

use crate::body::{BodyError, BodyHandle};
use crate::constraint::{ConstraintError, ConstraintHandle};
use crate::limits::LimitError;
use crate::shape::{ShapeError, ShapeHandle};

/// Errors of space operations. Each leaves the space unchanged.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SpaceError {
    /// The body handle is stale or from another space.
    StaleBody(BodyHandle),
    /// The shape handle is stale or from another space.
    StaleShape(ShapeHandle),
    /// The constraint handle is stale or from another space.
    StaleConstraint(ConstraintHandle),
    /// A constraint's parameters are invalid.
    Constraint(ConstraintError),
    /// A body invariant is violated.
    Body(BodyError),
    /// A shape is invalid.
    Shape(ShapeError),
    /// `dt` was negative.
    NegativeTimeStep,
    /// A setting is out of its range.
    InvalidSetting(&'static str),
    /// An arena is full (2^32 − 1 objects).
    Full,
    /// The operation is not allowed while the step runs (use a post-step callback).
    Locked,
    /// The handle was made by another space.
    ForeignHandle,
    /// A step left the world breaking an invariant of [`validate_state`](super::validate_state)
    /// (named in the message): an engine bug. Only returned by builds with
    /// the `validate` feature, which checks the state after every step
    /// (see [`VALIDATES_STEPS`](super::VALIDATES_STEPS)).
    InvalidState(String),
    /// Over one of the space's [`Limits`](crate::limits::Limits): a loaded state or frame (nothing
    /// changed), or a step whose broadphase found more candidate pairs
    /// than `max_pairs` (the step stopped after moving the bodies, before
    /// any contact: the world is valid but between two frames; restore a
    /// saved one).
    OverLimit(LimitError),
    /// A state given to [`Space::try_from_state`](super::Space::try_from_state) or
    /// [`Space::try_restore_state`](super::Space::try_restore_state) breaks an invariant of
    /// [`validate_state`](super::validate_state) (named in the message); nothing changed.
    RejectedState(String),
    /// [`Space::step`](super::Space::step) refused: this dynamic body has no mass (no explicit
    /// mass, and no shape with a mass or density), so no contact could stop
    /// it. Give it a mass (`Body::new`, `Body::set_mass`) or a shape a
    /// density (`Shape::set_density`). The first such body in slot order.
    MasslessDynamicBody(BodyHandle),
    /// A sleep request the rules refuse (see [`Space::sleep_body`](super::Space::sleep_body)).
    Sleep(&'static str),
    /// A frame ([`FrameState`](super::FrameState)) of another level: its level digest is not
    /// the world's (the static bodies or their shapes differ, see
    /// [`Space::level_digest`](super::Space::level_digest)).
    LevelMismatch {
        /// Level digest stored in the frame.
        frame: u64,
        /// Level digest of this world.
        world: u64,
    },
    /// A frame whose slots do not fit around this world's level (named in
    /// the message): not saved from a world with this level.
    FrameMismatch(String),
}

impl fmt::Display for SpaceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SpaceError::StaleBody(h) => {
                write!(f, "body handle {h:?} is stale or from another space")
            }
            SpaceError::StaleShape(h) => {
                write!(f, "shape handle {h:?} is stale or from another space")
            }
            SpaceError::StaleConstraint(h) => {
                write!(f, "constraint handle {h:?} is stale or from another space")
            }
            SpaceError::Constraint(e) => write!(f, "{e}"),
            SpaceError::Body(e) => write!(f, "{e}"),
            SpaceError::Shape(e) => write!(f, "{e}"),
            SpaceError::NegativeTimeStep => f.write_str("time step must not be negative"),
            SpaceError::InvalidSetting(why) => write!(f, "invalid setting: {why}"),
            SpaceError::Full => f.write_str("too many objects in the space"),
            SpaceError::Locked => {
                f.write_str("space is locked during the step; use a post-step callback")
            }
            SpaceError::ForeignHandle => f.write_str("handle belongs to another space"),
            SpaceError::InvalidState(why) => write!(f, "the step broke an invariant: {why}"),
            SpaceError::RejectedState(why) => write!(f, "invalid world state: {why}"),
            SpaceError::OverLimit(e) => write!(f, "over a limit of the space (Space::set_limits): {e}"),
            SpaceError::MasslessDynamicBody(h) => write!(
                f,
                "dynamic body {h:?} has no mass: give it a mass or a shape with mass or density"
            ),
            SpaceError::Sleep(why) => write!(f, "cannot sleep: {why}"),
            SpaceError::LevelMismatch { frame, world } => write!(
                f,
                "the frame belongs to another level (level digest {frame:#018x}, this world's {world:#018x}): \
                 the static bodies or their shapes changed since it was saved"
            ),
            SpaceError::FrameMismatch(why) => {
                write!(f, "the frame does not fit this world's level: {why}")
            }
        }
    }
}

impl std::error::Error for SpaceError {}

impl From<BodyError> for SpaceError {
    fn from(e: BodyError) -> Self {
        SpaceError::Body(e)
    }
}

impl From<ConstraintError> for SpaceError {
    fn from(e: ConstraintError) -> Self {
        SpaceError::Constraint(e)
    }
}

impl From<ShapeError> for SpaceError {
    fn from(e: ShapeError) -> Self {
        SpaceError::Shape(e)
    }
}
