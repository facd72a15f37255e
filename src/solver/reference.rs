//! The MIS impulse routines, as the specification states them: plain
//! saturating arithmetic on [`SolverBody`] values, one call per formula.
//! They are the reference the engine's rows are checked against (the
//! tests compare the fast kernels of `solver::kernel` and the contact rows
//! with them) and part of the public API for code that wants the formulas
//! themselves; the step does not call them.
use core::fmt;

use crate::math::{Real, Vect};

use super::body::SolverBody;
use super::kernel::k_scalar_body;

/// MIS UnsolvableCollision: both bodies have infinite mass along the
/// direction, so no impulse can change their relative velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsolvableCollision;

impl fmt::Display for UnsolvableCollision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("unsolvable collision: effective mass is infinite (k = 0)")
    }
}

impl std::error::Error for UnsolvableCollision {}

/// MIS `relative_velocity`: velocity of `b` at `r2` minus velocity of `a` at `r1`.
#[inline(always)]
pub fn relative_velocity(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect) -> Vect {
    let va = a.v + r1.perp() * a.w;
    let vb = b.v + r2.perp() * b.w;
    vb - va
}

/// MIS `normal_relative_velocity`: `relative_velocity · n`.
#[inline(always)]
pub fn normal_relative_velocity(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
) -> Real {
    relative_velocity(a, b, r1, r2).dot(n)
}

/// MIS `apply_impulse`: `v += j·m⁻¹`, `ω += I⁻¹ (r × j)`.
#[inline(always)]
pub fn apply_impulse(body: &mut SolverBody, j: Vect, r: Vect) {
    body.v += j * body.m_inv;
    body.w += body.i_inv * r.cross(j);
}

/// MIS `apply_impulses`: `−j` on `a` at `r1`, `+j` on `b` at `r2`.
#[inline(always)]
pub fn apply_impulses(a: &mut SolverBody, b: &mut SolverBody, r1: Vect, r2: Vect, j: Vect) {
    apply_impulse(a, -j, r1);
    apply_impulse(b, j, r2);
}

/// MIS `apply_bias_impulse`: like [`apply_impulse`] on the pseudo-velocities.
#[inline(always)]
pub fn apply_bias_impulse(body: &mut SolverBody, j: Vect, r: Vect) {
    body.v_bias += j * body.m_inv;
    body.w_bias += body.i_inv * r.cross(j);
}

/// MIS `apply_bias_impulses`: `−j` on `a` at `r1`, `+j` on `b` at `r2`.
#[inline(always)]
pub fn apply_bias_impulses(a: &mut SolverBody, b: &mut SolverBody, r1: Vect, r2: Vect, j: Vect) {
    apply_bias_impulse(a, -j, r1);
    apply_bias_impulse(b, j, r2);
}

/// MIS `k_scalar`: the effective inverse mass of the pair along `n`;
/// [`UnsolvableCollision`] when it is zero.
#[inline]
pub fn k_scalar(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
) -> Result<Real, UnsolvableCollision> {
    let k = k_scalar_body(a, r1, n) + k_scalar_body(b, r2, n);
    if k.is_positive() {
        Ok(k)
    } else {
        Err(UnsolvableCollision)
    }
}
