//! `PivotJoint` (Chipmunk `cpPivotJoint`): holds one anchor on each body
//! at the same point, like a pin through both (a hinge).
use serde::{Deserialize, Serialize};

use super::solve::Prep;
use super::{finite_vect, ConstraintError};
use crate::math::{Real, Vect};
use crate::solver::{apply_impulses, relative_velocity, SolverBody};

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
}

/// The solver row of a pivot joint for one sub-step: a 2-D point
/// constraint solved as one block.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PivotRow {
    r1: Vect,
    r2: Vect,
    k: KInv,
    bias: Vect,
    pub(crate) j_acc: Vect,
}

impl PivotRow {
    /// Anchors in world orientation, the inverse of the 2×2 effective-mass
    /// matrix ([`KInv`]) and the bias velocity `−bias_coef·Δ/dt` (length
    /// capped at `max_bias`).
    pub(crate) fn new(j: &PivotJoint, p: &Prep<'_>) -> PivotRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let k = KInv::new(p.sa, p.sb, r1, r2);
        let delta = p.delta(r1, r2);
        let bias = clamp_len(delta * (-(p.bias_coef * p.dt_inv)), p.max_bias);
        PivotRow {
            r1,
            r2,
            k,
            bias,
            j_acc: Vect::ZERO,
        }
    }
}

/// The inverse of the 2×2 effective-mass matrix of a point constraint
/// (Chipmunk's `k_tensor`), symmetric: `[[k11, k12], [k12, k22]]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KInv {
    k11: Real,
    k12: Real,
    k22: Real,
}

impl KInv {
    /// `K = (m_a⁻¹ + m_b⁻¹)·I + I_a⁻¹·[r1]ᵀ[r1] + I_b⁻¹·[r2]ᵀ[r2]` with
    /// `[r]ᵀ[r] = [[r_y², −r_x r_y], [−r_x r_y, r_x²]]` (an impulse `j` at `r`
    /// changes the point velocity by `m⁻¹ j + I⁻¹ (r × j) r⊥`). `K` is
    /// symmetric positive definite when a body can move, so `K⁻¹ =
    /// adj(K)/det K`; a determinant that is not positive (two immovable
    /// bodies, or rounding to 0) gives `K⁻¹ = 0`: no impulse. In fixed point
    /// `det` has the absolute resolution of `Real`, so for heavy bodies
    /// (inverse masses near 10⁻³) `K⁻¹` is accurate to about 10⁻⁴ relative;
    /// that only slows the iterations' convergence, not their fixed point.
    pub(crate) fn new(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect) -> KInv {
        let m_sum = a.m_inv + b.m_inv;
        let k11 = m_sum + a.i_inv * r1.y * r1.y + b.i_inv * r2.y * r2.y;
        let k12 = -(a.i_inv * r1.x * r1.y) - b.i_inv * r2.x * r2.y;
        let k22 = m_sum + a.i_inv * r1.x * r1.x + b.i_inv * r2.x * r2.x;
        let det = Real::mul_sub2(k11, k22, k12, k12);
        if det.is_positive() {
            KInv {
                k11: k22 / det,
                k12: -(k12 / det),
                k22: k11 / det,
            }
        } else {
            KInv {
                k11: Real::ZERO,
                k12: Real::ZERO,
                k22: Real::ZERO,
            }
        }
    }

    /// `K⁻¹·e`.
    pub(crate) fn apply(&self, e: Vect) -> Vect {
        Vect::new(
            Real::mul_add2(self.k11, e.x, self.k12, e.y),
            Real::mul_add2(self.k12, e.x, self.k22, e.y),
        )
    }
}

impl PivotRow {
    /// Applies `acc` (last step's impulse, already scaled) and keeps it.
    pub(crate) fn warm_start(&mut self, a: &mut SolverBody, b: &mut SolverBody, acc: Vect) {
        self.j_acc = acc;
        apply_impulses(a, b, self.r1, self.r2, acc);
    }

    /// One iteration: `j = K⁻¹ (bias − vr)`, accumulated impulse clamped to
    /// length `j_max`.
    pub(crate) fn apply_impulse(&mut self, a: &mut SolverBody, b: &mut SolverBody, j_max: Real) {
        let j = self
            .k
            .apply(self.bias - relative_velocity(a, b, self.r1, self.r2));
        let old = self.j_acc;
        self.j_acc = clamp_len(old + j, j_max);
        apply_impulses(a, b, self.r1, self.r2, self.j_acc - old);
    }
}

/// `v` shortened to length `max` if longer; `Real::MAX` (unbounded) skips
/// the square root (every length is at most `Real::MAX`: the same result).
pub(crate) fn clamp_len(v: Vect, max: Real) -> Vect {
    if max == Real::MAX {
        v
    } else {
        v.clamp(max)
    }
}
