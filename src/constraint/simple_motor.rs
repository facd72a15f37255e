//! `SimpleMotor` (Chipmunk `cpSimpleMotor`): keeps the relative angular
//! velocity of two bodies constant, with a torque bounded by `max_force`.
use serde::{Deserialize, Serialize};

use super::solve::{inv_or_zero, Prep};
use super::{finite, ConstraintError};
use crate::math::Real;
use crate::solver::SolverBody;

/// A motor turning body b relative to body a. As in Chipmunk, it drives
/// `ω_b − ω_a` to `−rate` (Chipmunk's sign convention: a positive rate
/// turns b clockwise relative to a). Its torque is limited by the
/// constraint's `max_force` (unbounded by default: the rate is reached in
/// one step).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SimpleMotor {
    pub(crate) rate: Real,
    /// Accumulated angular impulse (state: the next step's warm start).
    pub(crate) j_acc: Real,
}

impl SimpleMotor {
    /// Chipmunk `cpSimpleMotorNew`; `rate` in rad/s.
    pub fn new(rate: Real) -> Result<SimpleMotor, ConstraintError> {
        let j = SimpleMotor {
            rate,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`SimpleMotor::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite(self.rate, "rate")?;
        Ok(())
    }

    /// The rate (rad/s).
    pub fn rate(&self) -> Real {
        self.rate
    }
}

/// The solver row of a motor for one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MotorRow {
    rate: Real,
    /// `1/(I_a⁻¹ + I_b⁻¹)`.
    i_sum: Real,
    pub(crate) j_acc: Real,
}

impl MotorRow {
    pub(crate) fn new(j: &SimpleMotor, p: &Prep<'_>) -> MotorRow {
        MotorRow {
            rate: j.rate,
            i_sum: inv_or_zero(p.sa.i_inv + p.sb.i_inv),
            j_acc: Real::ZERO,
        }
    }

    /// Applies `acc` (last step's impulse, already scaled) and keeps it.
    pub(crate) fn warm_start(&mut self, a: &mut SolverBody, b: &mut SolverBody, acc: Real) {
        self.j_acc = acc;
        apply_angular(a, b, acc);
    }

    /// One iteration: cancel `ω_b − ω_a + rate`, accumulated impulse clamped
    /// to `±j_max`.
    pub(crate) fn apply_impulse(&mut self, a: &mut SolverBody, b: &mut SolverBody, j_max: Real) {
        let wr = b.w - a.w + self.rate;
        let j = -(wr * self.i_sum);
        let old = self.j_acc;
        self.j_acc = (old + j).clamp(-j_max, j_max);
        apply_angular(a, b, self.j_acc - old);
    }
}

/// Angular impulse `−j` on a, `+j` on b.
fn apply_angular(a: &mut SolverBody, b: &mut SolverBody, j: Real) {
    a.w -= j * a.i_inv;
    b.w += j * b.i_inv;
}
