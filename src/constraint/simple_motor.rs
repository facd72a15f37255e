//! `SimpleMotor` (Chipmunk `cpSimpleMotor`): keeps the relative angular
//! velocity of two bodies constant, with a torque bounded by `max_force`.
use serde::{Deserialize, Serialize};

use super::error::{finite, set_checked, ConstraintError};
use super::kernel::{accumulate, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real};
use crate::solver::kernel::{apply_angular, effective_mass, neg};
use crate::solver::softness::Softness;
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

    /// Chipmunk `cpSimpleMotorSetRate`: a new rate (rad/s), checked as by
    /// [`SimpleMotor::new`]; the accumulated impulse (the warm start) is
    /// kept. On an error the motor is unchanged.
    pub fn set_rate(&mut self, rate: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.rate = rate, SimpleMotor::validate)
    }
}

/// The solver row of a motor for one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MotorRow {
    rate: Real,
    /// `1/(I_a⁻¹ + I_b⁻¹)`.
    i_sum: Real,
}

impl MotorRow {
    pub(crate) fn new(j: &SimpleMotor, p: &Prep<'_>) -> MotorRow {
        MotorRow {
            rate: j.rate,
            i_sum: effective_mass(p.sa.i_inv + p.sb.i_inv),
        }
    }
}

impl JointKernel for MotorRow {
    type Impulse = Real;

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        apply_angular(a, b, j, ar);
    }

    /// Cancel `ω_b − ω_a + rate`, accumulated impulse clamped to `±j_max`.
    #[inline(always)]
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Real,
        j_max: Real,
        _soft: Softness,
        ar: &mut A,
    ) {
        let dw = ar.sub(b.w, a.w);
        let wr = ar.add(dw, self.rate);
        let j = ar.mul(wr, self.i_sum);
        let j = neg(j, ar);
        let d = accumulate(acc, j, -j_max, j_max, ar);
        apply_angular(a, b, d, ar);
    }
}

#[cfg(test)]
impl MotorRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> MotorRow {
        use crate::constraint::kernel::tests::at;
        MotorRow {
            rate: at(v, 0),
            i_sum: at(v, 1),
        }
    }
}
