//! `GrooveJoint` (Chipmunk `cpGrooveJoint`): a pivot on body b that slides
//! along a groove (a segment) on body a, like a wheel on a suspension rail
//! or a piston.
use serde::{Deserialize, Serialize};

use super::error::{finite_vect, set_checked, ConstraintError};
use super::kernel::{soften_vect, JointKernel};
use super::point::{clamp_len, KInv};
use super::prep::Prep;
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{add, apply_impulses, sub};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// The groove from `groove_a` to `groove_b` on body a and the pivot
/// `anchor_b` on body b (body coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct GrooveJoint {
    pub(crate) groove_a: Vect,
    pub(crate) groove_b: Vect,
    pub(crate) anchor_b: Vect,
    /// Accumulated impulse (state).
    pub(crate) j_acc: Vect,
}

impl GrooveJoint {
    /// Chipmunk `cpGrooveJointNew`; the groove's ends must differ.
    pub fn new(
        groove_a: Vect,
        groove_b: Vect,
        anchor_b: Vect,
    ) -> Result<GrooveJoint, ConstraintError> {
        let j = GrooveJoint {
            groove_a,
            groove_b,
            anchor_b,
            j_acc: Vect::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`GrooveJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.groove_a, "groove_a")?;
        finite_vect(self.groove_b, "groove_b")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        if self.groove_a == self.groove_b {
            return Err(ConstraintError::NotPositive("groove length"));
        }
        Ok(())
    }

    /// Start of the groove (body a's coordinates).
    pub fn groove_a(&self) -> Vect {
        self.groove_a
    }

    /// End of the groove (body a's coordinates).
    pub fn groove_b(&self) -> Vect {
        self.groove_b
    }

    /// The pivot on body b (body coordinates).
    pub fn anchor_b(&self) -> Vect {
        self.anchor_b
    }

    /// Chipmunk `cpGrooveJointSetGrooveA` (body a's coordinates; the ends
    /// must differ).
    pub fn set_groove_a(&mut self, groove_a: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.groove_a = groove_a, GrooveJoint::validate)
    }

    /// Chipmunk `cpGrooveJointSetGrooveB` (body a's coordinates; the ends
    /// must differ).
    pub fn set_groove_b(&mut self, groove_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.groove_b = groove_b, GrooveJoint::validate)
    }

    /// Both ends of the groove at once (they must differ): moves a groove
    /// onto its own old end in one call.
    pub fn set_groove(&mut self, groove_a: Vect, groove_b: Vect) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| {
                j.groove_a = groove_a;
                j.groove_b = groove_b;
            },
            GrooveJoint::validate,
        )
    }

    /// Chipmunk `cpGrooveJointSetAnchorB` (body b's coordinates).
    pub fn set_anchor_b(&mut self, anchor_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_b = anchor_b, GrooveJoint::validate)
    }
}

/// The solver row of a groove joint for one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GrooveRow {
    r1: Vect,
    r2: Vect,
    /// The groove's normal in world orientation.
    n: Vect,
    /// 1 at the groove's start, −1 at its end, 0 in between.
    clamp: i8,
    k: KInv,
    bias: Vect,
}

impl GrooveRow {
    /// As Chipmunk: the pivot's projection on the groove (clamped to its
    /// ends) is the point on a; from there it is a pivot joint, except
    /// that the impulse along the groove is dropped unless the pivot is
    /// pushed past an end. Everything is computed relative to a's centre
    /// (Chipmunk uses world coordinates): the same point, and exact under
    /// translation.
    pub(crate) fn new(j: &GrooveJoint, p: &Prep<'_>) -> GrooveRow {
        // Both ends of the groove are on body a (Chipmunk transforms both
        // by a's transform): `arms` would turn the second by body b.
        let (ta, r2) = p.arms(j.groove_a, j.anchor_b);
        let (tb, _) = p.arms(j.groove_b, j.anchor_b);
        // Chipmunk's groove normal: the left perpendicular of the
        // direction from groove_a to groove_b.
        let n = (tb - ta).normalize().perp();
        let d = ta.dot(n);
        // The pivot relative to a's centre.
        let pivot = (p.body_b.p - p.body_a.p) + r2;
        let td = pivot.cross(n);
        let (clamp, r1) = if td <= ta.cross(n) {
            (1, ta)
        } else if td >= tb.cross(n) {
            (-1, tb)
        } else {
            (0, n.perp() * (-td) + n * d)
        };
        let k = KInv::new(p.sa, p.sb, r1, r2);
        let delta = pivot - r1;
        let bias = clamp_len(delta * (-p.bias_rate()), p.max_bias);
        GrooveRow {
            r1,
            r2,
            n,
            clamp,
            k,
            bias,
        }
    }
}

impl JointKernel for GrooveRow {
    type Impulse = Vect;

    #[inline(always)]
    fn relax(&mut self) {
        self.bias = Vect::ZERO;
    }

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Vect, ar: &mut A) {
        apply_impulses(a, b, self.r1, self.r2, j, ar);
    }

    /// The pivot impulse, constrained to the groove's normal unless it
    /// pushes against the clamped end, accumulated impulse clamped to
    /// length `j_max`. The end test, the projection and the length clamp
    /// are the saturating `Vect` functions (the same in both modes).
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
        let sum = add(old, j, ar);
        let against_end = match self.clamp {
            1 => sum.cross(self.n).is_positive(),
            -1 => sum.cross(self.n).is_negative(),
            _ => false,
        };
        let sum = if against_end {
            sum
        } else {
            sum.project(self.n)
        };
        *acc = clamp_len(sum, j_max);
        let d = sub(*acc, old, ar);
        apply_impulses(a, b, self.r1, self.r2, d, ar);
    }
}

#[cfg(test)]
impl GrooveRow {
    /// A row from free values (the kernel tests); the clamp side from the
    /// sign of `v[14]`.
    pub(crate) fn from_raw(v: &[Real]) -> GrooveRow {
        use crate::constraint::kernel::tests::{at, vect_at};
        let side = at(v, 14);
        GrooveRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            n: vect_at(v, 12),
            clamp: if side.is_positive() {
                1
            } else if side.is_negative() {
                -1
            } else {
                0
            },
            k: KInv::from_raw(v.get(4..).unwrap_or_default()),
            bias: vect_at(v, 7),
        }
    }
}
