//! `RotaryLimitJoint` (Chipmunk `cpRotaryLimitJoint`): keeps the relative
//! angle `θ_b − θ_a` within `[min, max]` (an elbow, a door stop).
use serde::{Deserialize, Serialize};

use super::solve::{inv_or_zero, Prep};
use super::{finite, ConstraintError};
use crate::math::Real;
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
    pub(crate) j_acc: Real,
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
            i_sum: inv_or_zero(p.sa.i_inv + p.sb.i_inv),
            bias: p.bias(pdist),
            j_acc: Real::ZERO,
        }
    }

    /// Applies `acc` (last step's impulse, already scaled) and keeps it;
    /// nothing when inactive.
    pub(crate) fn warm_start(&mut self, a: &mut SolverBody, b: &mut SolverBody, acc: Real) {
        if self.sign == 0 {
            return;
        }
        self.j_acc = acc;
        apply_angular(a, b, acc);
    }

    /// One iteration: drive `ω_b − ω_a` to `−bias` (Chipmunk's sign: the
    /// bias is `−bias_coef·pdist/dt`), the accumulated impulse only pushing
    /// back into the limits and at most `j_max`.
    pub(crate) fn apply_impulse(&mut self, a: &mut SolverBody, b: &mut SolverBody, j_max: Real) {
        if self.sign == 0 {
            return;
        }
        let wr = b.w - a.w;
        let j = -((self.bias + wr) * self.i_sum);
        let old = self.j_acc;
        self.j_acc = if self.sign > 0 {
            (old + j).clamp(Real::ZERO, j_max)
        } else {
            (old + j).clamp(-j_max, Real::ZERO)
        };
        apply_angular(a, b, self.j_acc - old);
    }
}

/// Angular impulse `−j` on a, `+j` on b.
pub(crate) fn apply_angular(a: &mut SolverBody, b: &mut SolverBody, j: Real) {
    a.w -= j * a.i_inv;
    b.w += j * b.i_inv;
}
