//! `PivotJoint` (Chipmunk `cpPivotJoint`): holds one anchor on each body
//! at the same point, like a pin through both (a hinge).
use serde::{Deserialize, Serialize};

use super::error::{finite_vect, set_checked, ConstraintError};
use super::kernel::{soften_vect, JointKernel};
use super::point::{clamp_len, KInv};
use super::prep::Prep;
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{add, apply_impulses, sub};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// Anchors `anchor_a` on body a and `anchor_b` on body b (body
/// coordinates) kept at one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PivotJoint {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    /// Accumulated impulse (state: the next step's warm start).
    pub(crate) j_acc: Vect,
}

impl PivotJoint {
    /// Chipmunk `cpPivotJointNew2`: from two anchors. `cpPivotJointNew`,
    /// from one world point, is [`Space::pivot_joint`](crate::space::Space::pivot_joint).
    pub fn new(anchor_a: Vect, anchor_b: Vect) -> Result<PivotJoint, ConstraintError> {
        let j = PivotJoint {
            anchor_a,
            anchor_b,
            j_acc: Vect::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`PivotJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
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

    /// Chipmunk `cpPivotJointSetAnchorA` (body a's coordinates).
    pub fn set_anchor_a(&mut self, anchor_a: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_a = anchor_a, PivotJoint::validate)
    }

    /// Chipmunk `cpPivotJointSetAnchorB` (body b's coordinates).
    pub fn set_anchor_b(&mut self, anchor_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_b = anchor_b, PivotJoint::validate)
    }
}

/// The solver row of a pivot joint for one sub-step: a 2-D point
/// constraint solved as one block.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PivotRow {
    r1: Vect,
    r2: Vect,
    k: KInv,
    bias: Vect,
}

impl PivotRow {
    /// Anchors in world orientation, the inverse of the 2×2 effective-mass
    /// matrix ([`KInv`]) and the bias velocity `−bias_coef·Δ/dt` (length
    /// capped at `max_bias`).
    pub(crate) fn new(j: &PivotJoint, p: &Prep<'_>) -> PivotRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let k = KInv::new(p.sa, p.sb, r1, r2);
        let delta = p.delta(r1, r2);
        let bias = clamp_len(delta * (-p.bias_rate()), p.max_bias);
        PivotRow { r1, r2, k, bias }
    }
}

impl JointKernel for PivotRow {
    type Impulse = Vect;

    #[inline(always)]
    fn relax(&mut self) {
        self.bias = Vect::ZERO;
    }

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Vect, ar: &mut A) {
        apply_impulses(a, b, self.r1, self.r2, j, ar);
    }

    /// `j = K⁻¹ (bias − vr)`, accumulated impulse clamped to length `j_max`
    /// (the clamp's length is computed by the saturating `Vect::clamp`, the
    /// same in both modes, and only for a finite `max_force`).
    #[inline(always)]
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Vect,
        j_max: Real,
        soft: Softness,
        ar: &mut A,
    ) {
        let j = self.k.point_impulse(a, b, self.r1, self.r2, self.bias, ar);
        let j = soften_vect(j, *acc, soft, ar);
        let old = *acc;
        *acc = clamp_len(add(old, j, ar), j_max);
        let d = sub(*acc, old, ar);
        apply_impulses(a, b, self.r1, self.r2, d, ar);
    }
}

#[cfg(test)]
impl PivotRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> PivotRow {
        use crate::constraint::kernel::tests::vect_at;
        PivotRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            k: KInv::from_raw(v.get(4..).unwrap_or_default()),
            bias: vect_at(v, 7),
        }
    }
}
