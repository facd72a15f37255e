//! [`ConstraintError`] and the parameter checks every joint's setters
//! share: a leaf below the joint files, which all use it.
use core::fmt;

use crate::math::{Real, Vect};

/// A parameter of a constraint is out of its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstraintError {
    /// The named parameter is negative where only values ≥ 0 mean something.
    Negative(&'static str),
    /// The named parameter must be positive (non-zero).
    NotPositive(&'static str),
    /// The named parameter must not be zero.
    Zero(&'static str),
    /// The named parameter is saturated (`Real::MIN` or `Real::MAX`), the
    /// fixed-point form of an infinity or an overflow.
    Saturated(&'static str),
    /// `error_bias` is outside `[0, 1]`.
    ErrorBiasRange,
    /// Both bodies are the same body.
    SameBody,
    /// The constraint is not of the kind asked for
    /// ([`Constraint::joint_mut`](super::Constraint::joint_mut)).
    WrongKind {
        /// The kind asked for ([`JointKind::name`](super::JointKind::name)).
        expected: &'static str,
        /// The constraint's kind.
        found: &'static str,
    },
}

impl fmt::Display for ConstraintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConstraintError::Negative(p) => write!(f, "constraint parameter {p} is negative"),
            ConstraintError::NotPositive(p) => {
                write!(f, "constraint parameter {p} must be positive")
            }
            ConstraintError::Zero(p) => write!(f, "constraint parameter {p} must not be zero"),
            ConstraintError::Saturated(p) => {
                write!(f, "constraint parameter {p} is saturated (infinite)")
            }
            ConstraintError::ErrorBiasRange => f.write_str("error_bias must be in [0, 1]"),
            ConstraintError::SameBody => f.write_str("a constraint joins two different bodies"),
            ConstraintError::WrongKind { expected, found } => {
                write!(f, "constraint is a {found} joint, not a {expected} joint")
            }
        }
    }
}

impl std::error::Error for ConstraintError {}

/// `Err(Saturated)` for a saturated value.
pub(crate) fn finite(v: Real, name: &'static str) -> Result<Real, ConstraintError> {
    if v.is_saturated() {
        Err(ConstraintError::Saturated(name))
    } else {
        Ok(v)
    }
}

/// A finite vector.
pub(crate) fn finite_vect(v: Vect, name: &'static str) -> Result<Vect, ConstraintError> {
    finite(v.x, name)?;
    finite(v.y, name)?;
    Ok(v)
}

/// A finite value ≥ 0.
pub(crate) fn non_negative(v: Real, name: &'static str) -> Result<Real, ConstraintError> {
    if v.is_negative() {
        return Err(ConstraintError::Negative(name));
    }
    finite(v, name)
}

/// The setters' pattern: `change` is made on a copy of `joint`, the copy
/// is checked by the kind's `validate` (the constructor's checks), and it
/// replaces `joint` only if valid: on an error `joint` is unchanged. The
/// accumulated impulse is not touched (the warm start is kept).
pub(crate) fn set_checked<T: Copy>(
    joint: &mut T,
    change: impl FnOnce(&mut T),
    validate: impl FnOnce(&T) -> Result<(), ConstraintError>,
) -> Result<(), ConstraintError> {
    let mut copy = *joint;
    change(&mut copy);
    validate(&copy)?;
    *joint = copy;
    Ok(())
}
