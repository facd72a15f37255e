//! What every joint kind's pre-step reads ([`Prep`]): the leaf the kinds
//! and the stages (module `solve`) share. Their effective masses take the
//! solver's reciprocal, `solver::kernel::effective_mass`.
use crate::body::Body;
use crate::math::{Real, Vect};
use crate::solver::SolverBody;

/// What a kind's pre-step reads: both bodies (state and solver copy) and
/// the sub-step's constants.
pub(crate) struct Prep<'a> {
    pub(crate) body_a: &'a Body,
    pub(crate) body_b: &'a Body,
    pub(crate) sa: &'a SolverBody,
    pub(crate) sb: &'a SolverBody,
    pub(crate) dt: Real,
    pub(crate) dt_inv: Real,
    /// `1 − error_bias^dt`.
    pub(crate) bias_coef: Real,
    pub(crate) max_bias: Real,
    /// The soft step's bias rate (1/s): the bias is `−rate·error`
    /// instead of Chipmunk's.
    pub(crate) soft_rate: Option<Real>,
}

impl Prep<'_> {
    /// The anchors relative to the centres of gravity, in world orientation
    /// (Chipmunk's `r1`, `r2`).
    pub(crate) fn arms(&self, anchor_a: Vect, anchor_b: Vect) -> (Vect, Vect) {
        (
            self.body_a.rot.apply(anchor_a - self.body_a.cog),
            self.body_b.rot.apply(anchor_b - self.body_b.cog),
        )
    }

    /// World anchor b minus world anchor a, from the difference of the
    /// centres (exact in fixed point, so independent of where the pair is).
    pub(crate) fn delta(&self, r1: Vect, r2: Vect) -> Vect {
        (self.body_b.p - self.body_a.p) + (r2 - r1)
    }

    /// Chipmunk's bias velocity for a position error `error`:
    /// `−bias_coef·error/dt`, clamped to `±max_bias`.
    pub(crate) fn bias(&self, error: Real) -> Real {
        let v = match self.soft_rate {
            Some(rate) => -(rate * error),
            None => -(self.bias_coef * error) * self.dt_inv,
        };
        v.clamp(-self.max_bias, self.max_bias)
    }

    /// The bias velocity per unit of position error: Chipmunk's
    /// `bias_coef/dt`, or the soft step's rate.
    pub(crate) fn bias_rate(&self) -> Real {
        match self.soft_rate {
            Some(rate) => rate,
            None => self.bias_coef * self.dt_inv,
        }
    }
}
