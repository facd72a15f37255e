//! `GearJoint` (Chipmunk `cpGearJoint`): keeps the angles of two bodies in
//! a fixed ratio, like two meshed gears.
use serde::{Deserialize, Serialize};

use super::solve::Prep;
use super::{finite, ConstraintError};
use crate::math::Real;
use crate::solver::SolverBody;

/// Keeps `ratio·θ_b − θ_a = phase` (Chipmunk's definition), so that
/// `ω_a = ratio·ω_b`. A negative ratio turns the bodies in opposite
/// directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct GearJoint {
    pub(crate) phase: Real,
    pub(crate) ratio: Real,
    /// Accumulated angular impulse (state: the next step's warm start).
    pub(crate) j_acc: Real,
}

impl GearJoint {
    /// Chipmunk `cpGearJointNew`; `ratio` must not be zero.
    pub fn new(phase: Real, ratio: Real) -> Result<GearJoint, ConstraintError> {
        let j = GearJoint {
            phase,
            ratio,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`GearJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite(self.phase, "phase")?;
        finite(self.ratio, "ratio")?;
        if self.ratio.is_zero() {
            return Err(ConstraintError::Zero("ratio"));
        }
        Ok(())
    }

    /// Angular offset (rad).
    pub fn phase(&self) -> Real {
        self.phase
    }

    /// Ratio `ω_a / ω_b`.
    pub fn ratio(&self) -> Real {
        self.ratio
    }
}

/// The solver row of a gear joint for one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GearRow {
    ratio: Real,
    ratio_inv: Real,
    /// `1/(I_a⁻¹/ratio + ratio·I_b⁻¹)` (Chipmunk's `iSum`).
    i_sum: Real,
    bias: Real,
    pub(crate) j_acc: Real,
}

impl GearRow {
    /// As Chipmunk: an impulse `j` turns a by `−j·I_a⁻¹/ratio` and b by
    /// `+j·I_b⁻¹`, which changes `ratio·ω_b − ω_a` by `j·(ratio·I_b⁻¹ +
    /// I_a⁻¹/ratio)`; the bias velocity is `−bias_coef·(ratio·θ_b − θ_a −
    /// phase)/dt`, capped at `max_bias`.
    pub(crate) fn new(j: &GearJoint, p: &Prep<'_>) -> GearRow {
        let ratio_inv = j.ratio.recip();
        let k = p.sa.i_inv * ratio_inv + j.ratio * p.sb.i_inv;
        let error = j.ratio * p.body_b.a - p.body_a.a - j.phase;
        GearRow {
            ratio: j.ratio,
            ratio_inv,
            // Negative for a negative ratio (then so is every impulse's
            // effect on `ratio·ω_b − ω_a`); 0 only if neither body can turn.
            i_sum: if k.is_zero() { Real::ZERO } else { k.recip() },
            bias: p.bias(error),
            j_acc: Real::ZERO,
        }
    }

    /// Applies `acc` (last step's impulse, already scaled) and keeps it.
    pub(crate) fn warm_start(&mut self, a: &mut SolverBody, b: &mut SolverBody, acc: Real) {
        self.j_acc = acc;
        self.apply(a, b, acc);
    }

    /// One iteration: drive `ratio·ω_b − ω_a` to the bias, accumulated
    /// impulse clamped to `±j_max`.
    pub(crate) fn apply_impulse(&mut self, a: &mut SolverBody, b: &mut SolverBody, j_max: Real) {
        let wr = b.w * self.ratio - a.w;
        let j = (self.bias - wr) * self.i_sum;
        let old = self.j_acc;
        self.j_acc = (old + j).clamp(-j_max, j_max);
        self.apply(a, b, self.j_acc - old);
    }

    fn apply(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real) {
        a.w -= j * a.i_inv * self.ratio_inv;
        b.w += j * b.i_inv;
    }
}
