//! `DampedRotarySpring` (Chipmunk `cpDampedRotarySpring`): an angular
//! spring with a damper, solved implicitly like
//! [`DampedSpring`](super::DampedSpring) (see there for the derivation and
//! its numerical damping).
use serde::{Deserialize, Serialize};

use super::error::{finite, non_negative, set_checked, ConstraintError};
use super::kernel::{accumulate, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real};
use crate::solver::kernel::{apply_angular, effective_mass};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// A torsion spring holding `θ_a − θ_b` at `rest_angle` (Chipmunk's sign),
/// with `stiffness` (N·m/rad) and `damping` (N·m·s/rad).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct DampedRotarySpring {
    pub(crate) rest_angle: Real,
    pub(crate) stiffness: Real,
    pub(crate) damping: Real,
    /// Accumulated angular impulse, Chipmunk's sign: positive turns b
    /// forward and a back (state).
    pub(crate) j_acc: Real,
}

impl DampedRotarySpring {
    /// Chipmunk `cpDampedRotarySpringNew`; `stiffness`, `damping` ≥ 0.
    pub fn new(
        rest_angle: Real,
        stiffness: Real,
        damping: Real,
    ) -> Result<DampedRotarySpring, ConstraintError> {
        let j = DampedRotarySpring {
            rest_angle,
            stiffness,
            damping,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`DampedRotarySpring::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite(self.rest_angle, "rest_angle")?;
        non_negative(self.stiffness, "stiffness")?;
        non_negative(self.damping, "damping")?;
        Ok(())
    }

    /// Rest angle of `θ_a − θ_b`.
    pub fn rest_angle(&self) -> Real {
        self.rest_angle
    }

    /// Stiffness (N·m/rad).
    pub fn stiffness(&self) -> Real {
        self.stiffness
    }

    /// Damping (N·m·s/rad).
    pub fn damping(&self) -> Real {
        self.damping
    }

    /// Chipmunk `cpDampedRotarySpringSetRestAngle`.
    pub fn set_rest_angle(&mut self, rest_angle: Real) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| j.rest_angle = rest_angle,
            DampedRotarySpring::validate,
        )
    }

    /// Chipmunk `cpDampedRotarySpringSetStiffness` (≥ 0).
    pub fn set_stiffness(&mut self, stiffness: Real) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| j.stiffness = stiffness,
            DampedRotarySpring::validate,
        )
    }

    /// Chipmunk `cpDampedRotarySpringSetDamping` (≥ 0).
    pub fn set_damping(&mut self, damping: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.damping = damping, DampedRotarySpring::validate)
    }
}

/// The solver row of a rotary spring for one sub-step: with
/// `E = θ_a − θ_b − rest_angle`, an impulse `j` (−j on a, +j on b) changes
/// `Ė = ω_a − ω_b` by `−j·(I_a⁻¹ + I_b⁻¹)`; backward Euler asks
/// `j = dt·(k·E' + c·Ė')` at the end of the step, i.e.
/// `−Ė + γ·j − β = 0` with `γ`, `β` as for the linear spring.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RotarySpringRow {
    soft_mass: Real,
    gamma: Real,
    beta: Real,
}

impl RotarySpringRow {
    pub(crate) fn new(j: &DampedRotarySpring, p: &Prep<'_>) -> RotarySpringRow {
        let denom = j.damping + p.dt * j.stiffness;
        if !denom.is_positive() {
            return RotarySpringRow {
                soft_mass: Real::ZERO,
                gamma: Real::ZERO,
                beta: Real::ZERO,
            };
        }
        let error = p.body_a.a - p.body_b.a - j.rest_angle;
        let gamma = (p.dt * denom).recip();
        RotarySpringRow {
            soft_mass: effective_mass(p.sa.i_inv + p.sb.i_inv + gamma),
            gamma,
            beta: error.mul_div(j.stiffness, denom),
        }
    }
}

impl JointKernel for RotarySpringRow {
    type Impulse = Real;

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        apply_angular(a, b, j, ar);
    }

    /// `Δj = (Ė + β − γ·j)·soft_mass`, accumulated impulse clamped to
    /// `±j_max`.
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
        let e_dot = ar.sub(a.w, b.w);
        let e_beta = ar.add(e_dot, self.beta);
        let soft = ar.mul(self.gamma, *acc);
        let err = ar.sub(e_beta, soft);
        let j = ar.mul(err, self.soft_mass);
        let d = accumulate(acc, j, -j_max, j_max, ar);
        apply_angular(a, b, d, ar);
    }
}

#[cfg(test)]
impl RotarySpringRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> RotarySpringRow {
        use crate::constraint::kernel::tests::at;
        RotarySpringRow {
            soft_mass: at(v, 0),
            gamma: at(v, 1),
            beta: at(v, 2),
        }
    }
}
