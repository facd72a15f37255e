//! `RatchetJoint` (Chipmunk `cpRatchetJoint`): lets the relative angle
//! `θ_b − θ_a` advance freely in one direction and catches it on the last
//! tooth (every `ratchet` radians, offset by `phase`) in the other, like a
//! socket wrench.
use serde::{Deserialize, Serialize};

use super::error::{finite, set_checked, ConstraintError};
use super::prep::Prep;
use super::rotary_limit::AngularLimitRow;
use crate::math::Real;

/// A ratchet of tooth spacing `ratchet` (radians; its sign is the free
/// direction) and `phase`. `angle` is the tooth the ratchet last caught on:
/// state that the step advances.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct RatchetJoint {
    pub(crate) angle: Real,
    pub(crate) phase: Real,
    pub(crate) ratchet: Real,
    /// Accumulated angular impulse (state).
    pub(crate) j_acc: Real,
}

impl RatchetJoint {
    /// Chipmunk `cpRatchetJointNew`: starts at tooth angle 0 (Chipmunk
    /// starts at `b.a − a.a`'s tooth; the first step moves it there, as the
    /// relative angle is then on the free side). `ratchet` must not be 0.
    pub fn new(phase: Real, ratchet: Real) -> Result<RatchetJoint, ConstraintError> {
        let j = RatchetJoint {
            angle: Real::ZERO,
            phase,
            ratchet,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`RatchetJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite(self.phase, "phase")?;
        finite(self.ratchet, "ratchet")?;
        if self.ratchet.is_zero() {
            return Err(ConstraintError::Zero("ratchet"));
        }
        Ok(())
    }

    /// The tooth angle the ratchet holds (Chipmunk `angle`).
    pub fn angle(&self) -> Real {
        self.angle
    }

    /// Tooth offset.
    pub fn phase(&self) -> Real {
        self.phase
    }

    /// Tooth spacing; its sign is the free direction.
    pub fn ratchet(&self) -> Real {
        self.ratchet
    }

    /// Chipmunk `cpRatchetJointSetAngle`: the tooth the ratchet holds (the
    /// relative angle `θ_b − θ_a` it may not go back past). Not saturated.
    pub fn set_angle(&mut self, angle: Real) -> Result<(), ConstraintError> {
        finite(angle, "angle")?;
        set_checked(self, |j| j.angle = angle, RatchetJoint::validate)
    }

    /// Chipmunk `cpRatchetJointSetPhase`.
    pub fn set_phase(&mut self, phase: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.phase = phase, RatchetJoint::validate)
    }

    /// Chipmunk `cpRatchetJointSetRatchet` (≠ 0; its sign is the free
    /// direction).
    pub fn set_ratchet(&mut self, ratchet: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.ratchet = ratchet, RatchetJoint::validate)
    }

    /// Chipmunk's pre-step: behind the held tooth (in the free direction's
    /// opposite) the error is the distance back to it; otherwise the
    /// ratchet advances to the tooth at or behind the relative angle,
    /// `⌊(δ − phase)/ratchet⌋·ratchet + phase`, and the row is inactive.
    /// Returns the row and the tooth angle to store.
    pub(crate) fn row(&self, p: &Prep<'_>) -> (AngularLimitRow, Real) {
        let delta = p.body_b.a - p.body_a.a;
        let diff = self.angle - delta;
        let caught = (diff.is_positive() && self.ratchet.is_positive())
            || (diff.is_negative() && self.ratchet.is_negative());
        if caught {
            (AngularLimitRow::new(diff, p), self.angle)
        } else {
            let tooth = ((delta - self.phase) / self.ratchet).floor() * self.ratchet + self.phase;
            (AngularLimitRow::new(Real::ZERO, p), tooth)
        }
    }
}
