//! `SlideJoint` (Chipmunk `cpSlideJoint`): keeps the distance between two
//! anchors within `[min, max]`, like a rope (`min = 0`) or a telescoping
//! rod.
use serde::{Deserialize, Serialize};

use super::solve::{inv_or_zero, Prep};
use super::{finite_vect, non_negative, ConstraintError};
use crate::math::{Real, Vect};
use crate::solver::{apply_impulses, k_scalar_body, normal_relative_velocity, SolverBody};

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
            n_mass: inv_or_zero(k),
            bias: p.bias(pdist),
            jn_acc: Real::ZERO,
        }
    }

    /// Applies `acc` (last step's impulse, already scaled) and keeps it;
    /// nothing when inactive.
    pub(crate) fn warm_start(&mut self, a: &mut SolverBody, b: &mut SolverBody, acc: Real) {
        if self.n == Vect::ZERO {
            return;
        }
        self.jn_acc = acc;
        apply_impulses(a, b, self.r1, self.r2, self.n * acc);
    }

    /// One iteration: like a pin joint's, but the accumulated impulse only
    /// pulls back towards the limit (clamped to `[−j_max, 0]`).
    pub(crate) fn apply_impulse(&mut self, a: &mut SolverBody, b: &mut SolverBody, j_max: Real) {
        if self.n == Vect::ZERO {
            return;
        }
        let vrn = normal_relative_velocity(a, b, self.r1, self.r2, self.n);
        let jn = (self.bias - vrn) * self.n_mass;
        let old = self.jn_acc;
        self.jn_acc = (old + jn).clamp(-j_max, Real::ZERO);
        apply_impulses(a, b, self.r1, self.r2, self.n * (self.jn_acc - old));
    }
}
