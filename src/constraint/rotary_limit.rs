//! `RotaryLimitJoint` (Chipmunk `cpRotaryLimitJoint`): keeps the relative
//! angle `θ_b − θ_a` within `[min, max]` (an elbow, a door stop).
use serde::{Deserialize, Serialize};

use super::error::{finite, set_checked, ConstraintError};
use super::kernel::{accumulate, soften, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real};
use crate::solver::kernel::{apply_angular, effective_mass, neg};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// `θ_b − θ_a` kept within `[min, max]` (radians; the angles count turns,
/// so limits beyond ±π are meaningful).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct RotaryLimitJoint {
    pub(crate) min: Real,
    pub(crate) max: Real,
    /// Accumulated angular impulse (state).
    pub(crate) j_acc: Real,
}

impl RotaryLimitJoint {
    /// The error Chipmunk's pre-step computes: limit minus relative angle
    /// (positive below `min`, negative above `max`, 0 inside).
    pub(crate) fn error(&self, p: &Prep<'_>) -> Real {
        let dist = p.body_b.a - p.body_a.a;
        if dist > self.max {
            self.max - dist
        } else if dist < self.min {
            self.min - dist
        } else {
            Real::ZERO
        }
    }

    /// Chipmunk `cpRotaryLimitJointNew`; `min ≤ max`.
    pub fn new(min: Real, max: Real) -> Result<RotaryLimitJoint, ConstraintError> {
        let j = RotaryLimitJoint {
            min,
            max,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`RotaryLimitJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite(self.min, "min")?;
        finite(self.max, "max")?;
        if self.max < self.min {
            return Err(ConstraintError::Negative("max - min"));
        }
        Ok(())
    }

    /// Smallest relative angle.
    pub fn min(&self) -> Real {
        self.min
    }

    /// Largest relative angle.
    pub fn max(&self) -> Real {
        self.max
    }

    /// Chipmunk `cpRotaryLimitJointSetMin` (`min ≤ max`).
    pub fn set_min(&mut self, min: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.min = min, RotaryLimitJoint::validate)
    }

    /// Chipmunk `cpRotaryLimitJointSetMax` (`min ≤ max`).
    pub fn set_max(&mut self, max: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.max = max, RotaryLimitJoint::validate)
    }

    /// Both limits at once (`min ≤ max`): moves the range past its old
    /// bounds in one call (a steering lock that turns with the wheel).
    pub fn set_limits(&mut self, min: Real, max: Real) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| {
                j.min = min;
                j.max = max;
            },
            RotaryLimitJoint::validate,
        )
    }
}

/// The solver row of an angular limit (rotary limit, ratchet) for one
/// sub-step. `sign` is 0 when no limit is violated (the row does nothing),
/// +1 when the relative angle is below its lower limit (the impulse may
/// only turn b forward relative to a), −1 when above its upper limit. A
/// ratchet is a one-sided limit whose error has the ratchet's sign, which
/// is also Chipmunk's clamp for it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AngularLimitRow {
    sign: i8,
    i_sum: Real,
    bias: Real,
}

impl AngularLimitRow {
    /// A row for the error `pdist` (limit minus relative angle: positive
    /// below the lower limit, negative above the upper one, 0 inside).
    /// Chipmunk marks the row inactive by a zero bias; here by the sign of
    /// the error, so that `error_bias = 1` or `max_bias = 0` (no position
    /// correction) still stop the motion at the limit.
    pub(crate) fn new(pdist: Real, p: &Prep<'_>) -> AngularLimitRow {
        AngularLimitRow {
            sign: if pdist.is_positive() {
                1
            } else if pdist.is_negative() {
                -1
            } else {
                0
            },
            i_sum: effective_mass(p.sa.i_inv + p.sb.i_inv),
            bias: p.bias(pdist),
        }
    }
}

impl JointKernel for AngularLimitRow {
    type Impulse = Real;

    /// No limit violated: the row does nothing (zero accumulator).
    #[inline(always)]
    fn is_active(&self) -> bool {
        self.sign != 0
    }

    #[inline(always)]
    fn relax(&mut self) {
        self.bias = Real::ZERO;
    }

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        apply_angular(a, b, j, ar);
    }

    /// Drive `ω_b − ω_a` to `−bias` (Chipmunk's sign: the bias is
    /// `−bias_coef·pdist/dt`), the accumulated impulse only pushing back
    /// into the limits and at most `j_max`.
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
        let wr = ar.sub(b.w, a.w);
        let err = ar.add(self.bias, wr);
        let j = ar.mul(err, self.i_sum);
        let j = soften(neg(j, ar), *acc, soft, ar);
        let (lo, hi) = if self.sign > 0 {
            (Real::ZERO, j_max)
        } else {
            (-j_max, Real::ZERO)
        };
        let d = accumulate(acc, j, lo, hi, ar);
        apply_angular(a, b, d, ar);
    }
}

#[cfg(test)]
impl AngularLimitRow {
    /// A row from free values (the kernel tests); the sign from `v[0]`'s.
    pub(crate) fn from_raw(v: &[Real]) -> AngularLimitRow {
        use crate::constraint::kernel::tests::at;
        let side = at(v, 0);
        AngularLimitRow {
            sign: if side.is_positive() {
                1
            } else if side.is_negative() {
                -1
            } else {
                0
            },
            i_sum: at(v, 1),
            bias: at(v, 2),
        }
    }
}
