//! `PinJoint` (Chipmunk `cpPinJoint`): keeps the distance between two
//! anchor points fixed, like a massless rod with a pin at each end.
use serde::{Deserialize, Serialize};

use super::axis::PinRow;
use super::error::{finite, finite_vect, set_checked, ConstraintError};
use super::prep::Prep;
use crate::math::{Real, Vect};

/// A rod of length `dist` between `anchor_a` on body a and `anchor_b` on
/// body b (anchors in body coordinates, relative to the body's origin, as
/// Chipmunk's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PinJoint {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    pub(crate) dist: Real,
    /// Accumulated impulse along the rod (state: the next step's warm start).
    pub(crate) jn_acc: Real,
}

impl PinJoint {
    /// A pin joint of length `dist` (> 0: a zero-length pin has no
    /// direction; use a [`PivotJoint`](super::PivotJoint)). Chipmunk's
    /// `cpPinJointNew` measures `dist` from the bodies' current positions:
    /// [`Space::pin_joint`](crate::space::Space::pin_joint) does that.
    pub fn new(anchor_a: Vect, anchor_b: Vect, dist: Real) -> Result<PinJoint, ConstraintError> {
        let j = PinJoint {
            anchor_a,
            anchor_b,
            dist,
            jn_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`PinJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        if !self.dist.is_positive() {
            return Err(ConstraintError::NotPositive("dist"));
        }
        finite(self.dist, "dist")?;
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

    /// The kept distance.
    pub fn dist(&self) -> Real {
        self.dist
    }

    /// Chipmunk `cpPinJointSetAnchorA` (body a's coordinates).
    pub fn set_anchor_a(&mut self, anchor_a: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_a = anchor_a, PinJoint::validate)
    }

    /// Chipmunk `cpPinJointSetAnchorB` (body b's coordinates).
    pub fn set_anchor_b(&mut self, anchor_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_b = anchor_b, PinJoint::validate)
    }

    /// Chipmunk `cpPinJointSetDist` (> 0).
    pub fn set_dist(&mut self, dist: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.dist = dist, PinJoint::validate)
    }
}

impl PinRow {
    /// The row along the rod: anchors in world orientation, the unit
    /// vector from anchor a to anchor b, the effective mass and the bias
    /// velocity `−bias_coef·(|Δ| − dist)/dt`, capped at `max_bias`. `Δ` is
    /// computed from the difference of the bodies' centres, which is exact
    /// in fixed point: a translated joint gives the same bits.
    pub(crate) fn new(j: &PinJoint, p: &Prep<'_>) -> PinRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let (n, dist) = p.delta(r1, r2).normalize_with_length();
        PinRow::along(p, r1, r2, n, dist - j.dist)
    }
}
