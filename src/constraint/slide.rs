//! `SlideJoint` (Chipmunk `cpSlideJoint`): keeps the distance between two
//! anchors within `[min, max]`, like a rope (`min = 0`) or a telescoping
//! rod.
use serde::{Deserialize, Serialize};

use super::kernel::JointKernel;
use super::prep::Prep;
use super::{finite_vect, non_negative, ConstraintError};
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{apply_impulses, effective_mass, mult, normal_relative_velocity};
use crate::solver::{k_scalar_body, SolverBody};

/// The distance between `anchor_a` on a and `anchor_b` on b (body
/// coordinates) kept within `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SlideJoint {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    pub(crate) min: Real,
    pub(crate) max: Real,
    /// Accumulated impulse (≤ 0 along the violated direction; state).
    pub(crate) jn_acc: Real,
}

impl SlideJoint {
    /// Chipmunk `cpSlideJointNew`; `0 ≤ min ≤ max`.
    pub fn new(
        anchor_a: Vect,
        anchor_b: Vect,
        min: Real,
        max: Real,
    ) -> Result<SlideJoint, ConstraintError> {
        let j = SlideJoint {
            anchor_a,
            anchor_b,
            min,
            max,
            jn_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`SlideJoint::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        non_negative(self.min, "min")?;
        non_negative(self.max, "max")?;
        if self.max < self.min {
            return Err(ConstraintError::Negative("max - min"));
        }
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

    /// Smallest distance.
    pub fn min(&self) -> Real {
        self.min
    }

    /// Largest distance.
    pub fn max(&self) -> Real {
        self.max
    }
}

/// The solver row of a slide joint for one sub-step; `n = 0` when the
/// distance is within the limits (the row then does nothing).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlideRow {
    r1: Vect,
    r2: Vect,
    /// Along `Δ` when too long, against it when too short, 0 inside.
    n: Vect,
    n_mass: Real,
    bias: Real,
    pub(crate) jn_acc: Real,
}

impl SlideRow {
    /// As Chipmunk: the violated limit decides the direction and the error
    /// `pdist` (distance beyond the limit), the bias velocity is
    /// `−bias_coef·pdist/dt` capped at `max_bias`. Inside the limits the row
    /// is inactive and its accumulated impulse is dropped.
    pub(crate) fn new(j: &SlideJoint, p: &Prep<'_>) -> SlideRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let (dir, dist) = p.delta(r1, r2).normalize_with_length();
        let (n, pdist) = if dist > j.max {
            (dir, dist - j.max)
        } else if dist < j.min {
            (-dir, j.min - dist)
        } else {
            (Vect::ZERO, Real::ZERO)
        };
        let k = k_scalar_body(p.sa, r1, n) + k_scalar_body(p.sb, r2, n);
        SlideRow {
            r1,
            r2,
            n,
            n_mass: effective_mass(k),
            bias: p.bias(pdist),
            jn_acc: Real::ZERO,
        }
    }
}

impl JointKernel for SlideRow {
    type Impulse = Real;

    #[inline(always)]
    fn acc(&self) -> Real {
        self.jn_acc
    }

    #[inline(always)]
    fn set_acc(&mut self, acc: Real) {
        self.jn_acc = acc;
    }

    /// Inside the limits the row does nothing (and keeps a zero
    /// accumulator: the cached impulse is dropped).
    #[inline(always)]
    fn is_active(&self) -> bool {
        self.n != Vect::ZERO
    }

    /// The impulse `n·j` at the anchors.
    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        let p = mult(self.n, j, ar);
        apply_impulses(a, b, self.r1, self.r2, p, ar);
    }

    /// Like a pin joint's, but the accumulated impulse only pulls back
    /// towards the limit (clamped to `[−j_max, 0]`).
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
        *acc = ar.add(old, jn).clamp(-j_max, Real::ZERO);
        let d = ar.sub(*acc, old);
        self.apply(a, b, d, ar);
    }
}

#[cfg(test)]
impl SlideRow {
    /// A row from free values (the kernel tests); inactive when `n` is 0.
    pub(crate) fn from_raw(v: &[Real]) -> SlideRow {
        use crate::constraint::kernel::tests::{at, vect_at};
        SlideRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            n: vect_at(v, 4),
            n_mass: at(v, 6),
            bias: at(v, 7),
            jn_acc: Real::ZERO,
        }
    }
}
