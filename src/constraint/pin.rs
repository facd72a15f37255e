//! `PinJoint` (Chipmunk `cpPinJoint`): keeps the distance between two
//! anchor points fixed, like a massless rod with a pin at each end.
use serde::{Deserialize, Serialize};

use super::kernel::JointKernel;
use super::prep::Prep;
use super::{finite, finite_vect, ConstraintError};
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{apply_impulses, effective_mass, mult, normal_relative_velocity};
use crate::solver::{k_scalar_body, SolverBody};

/// A rod of length `dist` between `anchor_a` on body a and `anchor_b` on
/// body b (anchors in body coordinates, relative to the body's origin, as
/// Chipmunk's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PinJoint {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    pub(crate) dist: Real,
    /// Accumulated impulse along the rod (state: the next step's warm start).
    pub(crate) jn_acc: Real,
}

impl PinJoint {
    /// A pin joint of length `dist` (> 0: a zero-length pin has no
    /// direction; use a [`PivotJoint`](super::PivotJoint)). Chipmunk's
    /// `cpPinJointNew` measures `dist` from the bodies' current positions:
    /// [`Space::pin_joint`](crate::space::Space::pin_joint) does that.
    pub fn new(anchor_a: Vect, anchor_b: Vect, dist: Real) -> Result<PinJoint, ConstraintError> {
        let j = PinJoint {
            anchor_a,
            anchor_b,
            dist,
            jn_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`PinJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        if !self.dist.is_positive() {
            return Err(ConstraintError::NotPositive("dist"));
        }
        finite(self.dist, "dist")?;
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

    /// The kept distance.
    pub fn dist(&self) -> Real {
        self.dist
    }
}

/// The solver row of a pin joint for one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PinRow {
    r1: Vect,
    r2: Vect,
    /// Unit vector from anchor a to anchor b.
    n: Vect,
    /// `1/k` along `n`.
    n_mass: Real,
    bias: Real,
    pub(crate) jn_acc: Real,
}

impl PinRow {
    /// Anchors in world orientation, the direction, the effective mass and
    /// the bias velocity `−bias_coef·(|Δ| − dist)/dt`, capped at `max_bias`.
    /// `Δ` is computed from the difference of the bodies' centres, which is
    /// exact in fixed point: a translated joint gives the same bits.
    pub(crate) fn new(j: &PinJoint, p: &Prep<'_>) -> PinRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let (n, dist) = p.delta(r1, r2).normalize_with_length();
        let k = k_scalar_body(p.sa, r1, n) + k_scalar_body(p.sb, r2, n);
        PinRow {
            r1,
            r2,
            n,
            n_mass: effective_mass(k),
            bias: p.bias(dist - j.dist),
            jn_acc: Real::ZERO,
        }
    }
}

impl JointKernel for PinRow {
    type Impulse = Real;

    #[inline(always)]
    fn acc(&self) -> Real {
        self.jn_acc
    }

    #[inline(always)]
    fn set_acc(&mut self, acc: Real) {
        self.jn_acc = acc;
    }

    /// The impulse `n·j` at the anchors.
    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        let p = mult(self.n, j, ar);
        apply_impulses(a, b, self.r1, self.r2, p, ar);
    }

    /// Drive the relative velocity along `n` to the bias, accumulated
    /// impulse clamped to `±j_max`.
    #[inline(always)]
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Real,
        j_max: Real,
        ar: &mut A,
    ) {
        let vrn = normal_relative_velocity(a, b, self.r1, self.r2, self.n, ar);
        let err = ar.sub(self.bias, vrn);
        let jn = ar.mul(err, self.n_mass);
        let old = *acc;
        *acc = ar.add(old, jn).clamp(-j_max, j_max);
        let d = ar.sub(*acc, old);
        self.apply(a, b, d, ar);
    }
}

#[cfg(test)]
impl PinRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> PinRow {
        use crate::constraint::kernel::tests::{at, vect_at};
        PinRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            n: vect_at(v, 4),
            n_mass: at(v, 6),
            bias: at(v, 7),
            jn_acc: Real::ZERO,
        }
    }
}
