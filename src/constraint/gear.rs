//! `GearJoint` (Chipmunk `cpGearJoint`): keeps the angles of two bodies in
//! a fixed ratio, like two meshed gears.
use serde::{Deserialize, Serialize};

use super::error::{finite, set_checked, ConstraintError};
use super::kernel::{accumulate, soften, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real};
use crate::solver::softness::Softness;
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

    /// Chipmunk `cpGearJointSetPhase`.
    pub fn set_phase(&mut self, phase: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.phase = phase, GearJoint::validate)
    }

    /// Chipmunk `cpGearJointSetRatio` (≠ 0; Chipmunk's cached inverse is
    /// recomputed every step here).
    pub fn set_ratio(&mut self, ratio: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.ratio = ratio, GearJoint::validate)
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
        }
    }
}

impl JointKernel for GearRow {
    type Impulse = Real;

    #[inline(always)]
    fn relax(&mut self) {
        self.bias = Real::ZERO;
    }

    /// `ω_a −= j·I_a⁻¹/ratio` (two roundings, in that order), `ω_b += j·I_b⁻¹`.
    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        let ja = ar.mul(j, a.i_inv);
        let dwa = ar.mul(ja, self.ratio_inv);
        a.w = ar.sub(a.w, dwa);
        let dwb = ar.mul(j, b.i_inv);
        b.w = ar.add(b.w, dwb);
    }

    /// Drive `ratio·ω_b − ω_a` to the bias, accumulated impulse clamped to
    /// `±j_max`.
    #[inline(always)]
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Real,
        j_max: Real,
        soft: Softness,
        ar: &mut A,
    ) {
        let wb = ar.mul(b.w, self.ratio);
        let wr = ar.sub(wb, a.w);
        let err = ar.sub(self.bias, wr);
        let j = soften(ar.mul(err, self.i_sum), *acc, soft, ar);
        let d = accumulate(acc, j, -j_max, j_max, ar);
        self.apply(a, b, d, ar);
    }
}

#[cfg(test)]
impl GearRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> GearRow {
        use crate::constraint::kernel::tests::at;
        GearRow {
            ratio: at(v, 0),
            ratio_inv: at(v, 1),
            i_sum: at(v, 2),
            bias: at(v, 3),
        }
    }
}
