//! `DampedSpring` (Chipmunk `cpDampedSpring`): a spring with a damper
//! between two anchors, solved implicitly in the solver iterations.
//!
//! # Why implicit, and how
//! Chipmunk applies the spring force explicitly (once per step, from the
//! current stretch) and only the damping implicitly. An explicit stiffness
//! gains energy and diverges once `ω·dt > 2` (`ω = √(k/m)`): a spring of
//! `k = 10⁵ N/m` on 1 kg explodes at 1/60 s. Here both parts are implicit
//! (backward Euler, the soft-constraint form of Catto's "Soft Constraints",
//! GDC 2011), so a spring of any stiffness is stable at any `dt`.
//!
//! With stretch `C = |Δ| − rest_length`, stiffness `k` and damping `c`, the
//! impulse `λ` of the step must satisfy `λ = −dt·(k·(C + dt·v) + c·v)`,
//! where `v` is the stretch rate after the impulse. Rearranged:
//! `v + γ·λ + β = 0` with `γ = 1/(dt·(c + dt·k))` and `β = k·C/(c + dt·k)`;
//! the iterations solve it like a contact row with effective inverse mass
//! `k_eff + γ`: `Δλ = −(v + β + γ·λ_acc)/(k_eff + γ)`. The price of implicit
//! integration is numerical damping: an undamped spring's amplitude shrinks
//! by `1/√(1 + (ω·dt)²)` per step and its period grows by the factor
//! `ω·dt / atan(ω·dt)` (0.4 % at `ω·dt = 0.1`). `error_bias` and `max_bias`
//! are not used (the spring is its own error correction, as in Chipmunk);
//! `max_force` caps the spring force.
use serde::{Deserialize, Serialize};

use super::axis::apply_along;
use super::error::{finite_vect, non_negative, set_checked, ConstraintError};
use super::kernel::{accumulate, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{effective_mass, neg, normal_relative_velocity};
use crate::solver::softness::Softness;
use crate::solver::{k_scalar_body, SolverBody};

/// A spring of natural length `rest_length`, stiffness `stiffness` (N/m)
/// and damping `damping` (N·s/m) between two anchors (body coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct DampedSpring {
    pub(crate) anchor_a: Vect,
    pub(crate) anchor_b: Vect,
    pub(crate) rest_length: Real,
    pub(crate) stiffness: Real,
    pub(crate) damping: Real,
    /// Accumulated impulse along the spring, positive pushing the anchors
    /// apart (state: the next step's warm start).
    pub(crate) j_acc: Real,
}

impl DampedSpring {
    /// Chipmunk `cpDampedSpringNew`. `rest_length`, `stiffness` and
    /// `damping` must be ≥ 0.
    pub fn new(
        anchor_a: Vect,
        anchor_b: Vect,
        rest_length: Real,
        stiffness: Real,
        damping: Real,
    ) -> Result<DampedSpring, ConstraintError> {
        let j = DampedSpring {
            anchor_a,
            anchor_b,
            rest_length,
            stiffness,
            damping,
            j_acc: Real::ZERO,
        };
        j.validate()?;
        Ok(j)
    }

    /// The parameter checks of [`DampedSpring::new`].
    pub fn validate(&self) -> Result<(), ConstraintError> {
        finite_vect(self.anchor_a, "anchor_a")?;
        finite_vect(self.anchor_b, "anchor_b")?;
        non_negative(self.rest_length, "rest_length")?;
        non_negative(self.stiffness, "stiffness")?;
        non_negative(self.damping, "damping")?;
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

    /// Natural length.
    pub fn rest_length(&self) -> Real {
        self.rest_length
    }

    /// Stiffness (N/m).
    pub fn stiffness(&self) -> Real {
        self.stiffness
    }

    /// Damping (N·s/m).
    pub fn damping(&self) -> Real {
        self.damping
    }

    /// Chipmunk `cpDampedSpringSetAnchorA` (body a's coordinates).
    pub fn set_anchor_a(&mut self, anchor_a: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_a = anchor_a, DampedSpring::validate)
    }

    /// Chipmunk `cpDampedSpringSetAnchorB` (body b's coordinates).
    pub fn set_anchor_b(&mut self, anchor_b: Vect) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.anchor_b = anchor_b, DampedSpring::validate)
    }

    /// Chipmunk `cpDampedSpringSetRestLength` (≥ 0).
    pub fn set_rest_length(&mut self, rest_length: Real) -> Result<(), ConstraintError> {
        set_checked(
            self,
            |j| j.rest_length = rest_length,
            DampedSpring::validate,
        )
    }

    /// Chipmunk `cpDampedSpringSetStiffness` (≥ 0).
    pub fn set_stiffness(&mut self, stiffness: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.stiffness = stiffness, DampedSpring::validate)
    }

    /// Chipmunk `cpDampedSpringSetDamping` (≥ 0).
    pub fn set_damping(&mut self, damping: Real) -> Result<(), ConstraintError> {
        set_checked(self, |j| j.damping = damping, DampedSpring::validate)
    }
}

/// The solver row of a spring for one sub-step (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpringRow {
    r1: Vect,
    r2: Vect,
    n: Vect,
    /// `1/(k_eff + γ)`.
    soft_mass: Real,
    /// `γ = 1/(dt·(c + dt·k))`.
    gamma: Real,
    /// `β = k·C/(c + dt·k)`.
    beta: Real,
}

impl SpringRow {
    /// `γ`, `β` and the soft effective mass. A spring with `c + dt·k = 0`
    /// (no stiffness, no damping) applies nothing: its soft mass is 0. `Δ`
    /// comes from the difference of the bodies' centres (exact: translation
    /// changes no bit).
    pub(crate) fn new(j: &DampedSpring, p: &Prep<'_>) -> SpringRow {
        let (r1, r2) = p.arms(j.anchor_a, j.anchor_b);
        let (n, dist) = p.delta(r1, r2).normalize_with_length();
        let denom = j.damping + p.dt * j.stiffness;
        if !denom.is_positive() {
            return SpringRow {
                r1,
                r2,
                n,
                soft_mass: Real::ZERO,
                gamma: Real::ZERO,
                beta: Real::ZERO,
            };
        }
        let gamma = (p.dt * denom).recip();
        let beta = (dist - j.rest_length).mul_div(j.stiffness, denom);
        let k = k_scalar_body(p.sa, r1, n) + k_scalar_body(p.sb, r2, n);
        SpringRow {
            r1,
            r2,
            n,
            soft_mass: effective_mass(k + gamma),
            gamma,
            beta,
        }
    }
}

impl JointKernel for SpringRow {
    type Impulse = Real;

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        apply_along(a, b, self.r1, self.r2, self.n, j, ar);
    }

    /// `Δλ = −(v + β + γ·λ)·soft_mass`, accumulated impulse clamped to
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
        let vrn = normal_relative_velocity(a, b, self.r1, self.r2, self.n, ar);
        let v_beta = ar.add(vrn, self.beta);
        let soft = ar.mul(self.gamma, *acc);
        let err = ar.add(v_beta, soft);
        let j = ar.mul(err, self.soft_mass);
        let j = neg(j, ar);
        let d = accumulate(acc, j, -j_max, j_max, ar);
        self.apply(a, b, d, ar);
    }
}

#[cfg(test)]
impl SpringRow {
    /// A row from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> SpringRow {
        use crate::constraint::kernel::tests::{at, vect_at};
        SpringRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            n: vect_at(v, 4),
            soft_mass: at(v, 6),
            gamma: at(v, 7),
            beta: at(v, 8),
        }
    }
}
