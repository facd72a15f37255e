//! [`SolverBody`]: the per-body data every solver row reads and writes,
//! a leaf the kernel, the contact rows and the joints' rows share.
use crate::math::{Real, Vect};

/// The per-body data the iterations touch, stored contiguously.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverBody {
    /// Linear velocity.
    pub v: Vect,
    /// Angular velocity.
    pub w: Real,
    /// Linear pseudo-velocity from bias impulses.
    pub v_bias: Vect,
    /// Angular pseudo-velocity from bias impulses.
    pub w_bias: Real,
    /// Inverse mass (0 for infinite mass).
    pub m_inv: Real,
    /// Inverse moment (0 for infinite moment).
    pub i_inv: Real,
}

impl SolverBody {
    /// No bias velocity, linear or angular (bit test, no arithmetic).
    #[inline(always)]
    pub fn bias_is_zero(&self) -> bool {
        (self.v_bias.x.to_bits() | self.v_bias.y.to_bits() | self.w_bias.to_bits()) == 0
    }
}
