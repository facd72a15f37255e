//! `SlideJoint` (Chipmunk `cpSlideJoint`): keeps the distance between two
//! anchors within `[min, max]`, like a rope (`min = 0`) or a telescoping
//! rod.
use serde::{Deserialize, Serialize};

use super::axis::SlideRow;
use super::error::{finite_vect, non_negative, set_checked, ConstraintError};
use super::prep::Prep;
use crate::math::{Real, Vect};

/// The distance between `anchor_a` on a and `anchor_b` on b (body
/// coordinates) kept within `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SlideJoint {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    pub(crate) min: Real,
    pub(crate) max: Real,
    /// Accumulated impulse (≤ 0 along the violated direction; state).
    pub(crate) jn_acc: Real,
}

impl SlideJoint {
    /// Chipmunk `cpSlideJointNew`; `0 ≤ min ≤ max`.
    pub fn new(
        anchor_a: Vect,
        anchor_b: Vect,
        min: Real,
        max: Real,
    ) -> Result<SlideJoint, ConstraintError> {
        let j = SlideJoint {
            anchor_a,
            anchor_b,
            min,
            max,
            jn_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`SlideJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        non_negative(self.min, "min")?;
        non_negative(self.max, "max")?;
        if self.max < self.min {
            return Err(ConstraintError::Negative("max - min"));
        }
        Ok(())
    }

    /// Anchor on body a (body coordinates).
    pub fn anchor_a(&self) -> Vect {
        self.anchor_a
    }

    /// Anchor on body b (body coordinates).
    pub fn anchor_b(&self) -> Vect {
        self.anchor_b
    }

    /// Smallest distance.
    pub fn min(&self) -> Real {
        self.min
    }

    /// Largest distance.
    pub fn max(&self) -> Real {
        self.max
    }

    /// Chipmunk `cpSlideJointSetAnchorA` (body a's coordinates).
    pub fn set_anchor_a(&mut self, anchor_a: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_a = anchor_a, SlideJoint::validate)
    }

    /// Chipmunk `cpSlideJointSetAnchorB` (body b's coordinates).
    pub fn set_anchor_b(&mut self, anchor_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_b = anchor_b, SlideJoint::validate)
    }

    /// Chipmunk `cpSlideJointSetMin` (`0 ≤ min ≤ max`).
    pub fn set_min(&mut self, min: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.min = min, SlideJoint::validate)
    }

    /// Chipmunk `cpSlideJointSetMax` (`min ≤ max`).
    pub fn set_max(&mut self, max: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.max = max, SlideJoint::validate)
    }

    /// Both limits at once (`0 ≤ min ≤ max`): moves the range past its old
    /// bounds in one call, where `set_min` then `set_max` would pass
    /// through an empty range.
    pub fn set_limits(&mut self, min: Real, max: Real) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| {
                j.min = min;
                j.max = max;
            },
            SlideJoint::validate,
        )
    }
}

impl SlideRow {
    /// As Chipmunk: the violated limit decides the direction and the error
    /// `pdist` (distance beyond the limit), the bias velocity is
    /// `−bias_coef·pdist/dt` capped at `max_bias`. Inside the limits the row
    /// is inactive (`n = 0`) and its accumulated impulse is dropped.
    pub(crate) fn new(j: &SlideJoint, p: &Prep<'_>) -> SlideRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let (dir, dist) = p.delta(r1, r2).normalize_with_length();
        let (n, pdist) = if dist > j.max {
            (dir, dist - j.max)
        } else if dist < j.min {
            (-dir, j.min - dist)
        } else {
            (Vect::ZERO, Real::ZERO)
        };
        SlideRow::along(p, r1, r2, n, pdist)
    }
}
