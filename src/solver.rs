//! The impulse half of the MIS Collision Solver (§10): relative velocities,
//! effective masses, and normal, friction and bias impulses.
//!
//! # Glossary
//! * `a`, `b`: the two bodies of a contact; the normal `n` points from a to b.
//! * `r1`, `r2`: contact point relative to a's and b's centre of gravity.
//! * `vr`: relative velocity of b with respect to a at the contact,
//!   `(v_b + ω_b × r2) − (v_a + ω_a × r1)`.
//! * `k`: effective inverse mass along a direction `d`,
//!   `k = m_a⁻¹ + m_b⁻¹ + I_a⁻¹ (r1 × d)² + I_b⁻¹ (r2 × d)²`; an impulse `j`
//!   along `d` changes `vr·d` by `k·j`, so `j = −Δ/k` cancels a velocity error
//!   `Δ`. `n_mass = 1/k(n)` and `t_mass = 1/k(t)` are computed once per step
//!   (pre-step): the iterations only multiply.
//! * `jn_acc`, `jt_acc`: accumulated normal and tangent (friction) impulses.
//!   Clamping the *accumulated* value (`jn_acc ≥ 0`, `|jt_acc| ≤ μ·jn_acc`)
//!   instead of each increment lets later iterations take back impulse, which
//!   is what makes sequential impulses converge (Catto, GDC 2006).
//! * `bias`: target separation velocity that removes penetration beyond the
//!   slop: `bias = −bias_coef · min(0, dist + slop) / dt`. It is applied as a
//!   *pseudo-velocity* (`v_bias`, `ω_bias`, `j_bias`) that moves positions in
//!   the next position update but adds no momentum, so resolving overlap does
//!   not make objects bounce.
//! * `bounce`: restitution target, `e · (vr·n)` at the start of the step, so
//!   the normal impulse drives `vr·n` to `−bounce`.
//!
//! Bodies are copied into a contiguous [`SolverBody`] array for the
//! iterations (inverse masses and velocities side by side); static and
//! kinematic bodies have zero inverse mass, so impulses leave them unchanged.
use core::fmt;

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
pub fn normal_relative_velocity(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect, n: Vect) -> Real {
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

/// MIS `k_scalar_body`: `m⁻¹ + I⁻¹ (r × n)²`.
#[inline(always)]
pub fn k_scalar_body(body: &SolverBody, r: Vect, n: Vect) -> Real {
    let rcn = r.cross(n);
    body.m_inv + body.i_inv * rcn * rcn
}

/// MIS `k_scalar`: the effective inverse mass of the pair along `n`;
/// [`UnsolvableCollision`] when it is zero.
#[inline]
pub fn k_scalar(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect, n: Vect) -> Result<Real, UnsolvableCollision> {
    let k = k_scalar_body(a, r1, n) + k_scalar_body(b, r2, n);
    if k.is_positive() {
        Ok(k)
    } else {
        Err(UnsolvableCollision)
    }
}

/// One contact's solver state (persistent parts are warm-started).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct ContactConstraint {
    /// Contact point relative to body a's centre of gravity.
    pub r1: Vect,
    /// Contact point relative to body b's centre of gravity.
    pub r2: Vect,
    /// Signed separation (negative when penetrating).
    pub dist: Real,
    /// Feature id: matches this contact with last step's for warm starting.
    pub id: u32,
    /// `1/k(n)`.
    pub n_mass: Real,
    /// `1/k(t)`.
    pub t_mass: Real,
    /// Target bias (pseudo-)velocity.
    pub bias: Real,
    /// Restitution target velocity.
    pub bounce: Real,
    /// Accumulated normal impulse (warm-started).
    pub jn_acc: Real,
    /// Accumulated friction impulse (warm-started).
    pub jt_acc: Real,
    /// Accumulated bias impulse (not warm-started).
    pub j_bias: Real,
}

/// Step-wide constants of the contact solver.
#[derive(Clone, Copy, Debug)]
pub struct ContactParams {
    /// `1/dt`.
    pub dt_inv: Real,
    /// Allowed overlap that is not corrected.
    pub slop: Real,
    /// Fraction of the remaining overlap corrected this step, `1 − bias^dt`.
    pub bias_coef: Real,
    /// Largest bias velocity (Chipmunk's arbiter `maxBias`, unbounded by default).
    pub max_bias: Real,
}

/// Pre-step for one contact: effective masses, bias and bounce. The only
/// divisions of the contact solver happen here.
pub fn pre_step(c: &mut ContactConstraint, a: &SolverBody, b: &SolverBody, n: Vect, e: Real, params: &ContactParams) {
    // A zero k (two infinite masses) gives mass 0: the contact applies no impulse.
    c.n_mass = k_scalar(a, b, c.r1, c.r2, n).map_or(Real::ZERO, Real::recip);
    c.t_mass = k_scalar(a, b, c.r1, c.r2, n.perp()).map_or(Real::ZERO, Real::recip);
    let overlap = (c.dist + params.slop).min(Real::ZERO);
    c.bias = (-params.bias_coef * overlap * params.dt_inv).min(params.max_bias);
    c.j_bias = Real::ZERO;
    c.bounce = normal_relative_velocity(a, b, c.r1, c.r2, n) * e;
}

/// Applies the cached (warm-start) impulse, scaled by `dt_coef = dt/prev_dt`.
pub fn warm_start(c: &ContactConstraint, a: &mut SolverBody, b: &mut SolverBody, n: Vect, dt_coef: Real) {
    let j = n.rotate(Vect::new(c.jn_acc, c.jt_acc)) * dt_coef;
    apply_impulses(a, b, c.r1, c.r2, j);
}

/// One iteration for one contact: bias, normal and friction impulses.
///
/// With `t = perp(n)`: normal `jn = −(bounce + vr·n)·n_mass`, accumulated and
/// clamped ≥ 0; friction `jt = −(vr·t + surface_vr·t)·t_mass`, accumulated
/// and clamped to `±μ·jn_acc`; bias `jb = (bias − vb·n)·n_mass` on the
/// pseudo-velocities, accumulated and clamped ≥ 0.
#[inline]
pub fn apply_contact_impulse(
    c: &mut ContactConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    n: Vect,
    friction: Real,
    surface_vr: Vect,
) {
    // Bias (position correction) on pseudo-velocities.
    let vb1 = a.v_bias + c.r1.perp() * a.w_bias;
    let vb2 = b.v_bias + c.r2.perp() * b.w_bias;
    let vbn = (vb2 - vb1).dot(n);
    let jbn = (c.bias - vbn) * c.n_mass;
    let jbn_old = c.j_bias;
    c.j_bias = (jbn_old + jbn).max(Real::ZERO);
    apply_bias_impulses(a, b, c.r1, c.r2, n * (c.j_bias - jbn_old));

    // Normal and friction on real velocities.
    let vr = relative_velocity(a, b, c.r1, c.r2) + surface_vr;
    let vrn = vr.dot(n);
    let vrt = vr.dot(n.perp());

    let jn = -(c.bounce + vrn) * c.n_mass;
    let jn_old = c.jn_acc;
    c.jn_acc = (jn_old + jn).max(Real::ZERO);

    let jt_max = friction * c.jn_acc;
    let jt = -vrt * c.t_mass;
    let jt_old = c.jt_acc;
    c.jt_acc = (jt_old + jt).clamp(-jt_max, jt_max);

    let j = n.rotate(Vect::new(c.jn_acc - jn_old, c.jt_acc - jt_old));
    apply_impulses(a, b, c.r1, c.r2, j);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(m_inv: i32, i_inv: i32) -> SolverBody {
        SolverBody { m_inv: Real::from_int(m_inv), i_inv: Real::from_int(i_inv), ..Default::default() }
    }

    #[test]
    fn k_scalar_sums_both_bodies_and_rejects_infinite_pairs() {
        let a = body(1, 1);
        let b = body(2, 0);
        let r = Vect::from_ints(0, 1);
        let n = Vect::X;
        // (r × n)² = 1 for a; b has no rotation.
        assert_eq!(k_scalar(&a, &b, r, r, n), Ok(Real::from_int(4)));
        assert_eq!(k_scalar(&body(0, 0), &body(0, 0), r, r, n), Err(UnsolvableCollision));
    }

    #[test]
    fn impulses_are_equal_and_opposite() {
        let mut a = body(1, 0);
        let mut b = body(1, 0);
        apply_impulses(&mut a, &mut b, Vect::ZERO, Vect::ZERO, Vect::from_ints(2, 0));
        assert_eq!(a.v, Vect::from_ints(-2, 0));
        assert_eq!(b.v, Vect::from_ints(2, 0));
        let vr = relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO);
        assert_eq!(vr, Vect::from_ints(4, 0));
        assert_eq!(normal_relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO, Vect::X), Real::from_int(4));
    }

    #[test]
    fn normal_impulse_stops_approach_without_pulling() {
        // Two unit masses approaching at 2 along the normal: one iteration stops them.
        let mut a = body(1, 0);
        let mut b = body(1, 0);
        a.v = Vect::from_ints(1, 0);
        b.v = Vect::from_ints(-1, 0);
        let params = ContactParams { dt_inv: Real::from_int(60), slop: Real::ZERO, bias_coef: Real::ZERO, max_bias: Real::MAX };
        let mut c = ContactConstraint::default();
        pre_step(&mut c, &a, &b, Vect::X, Real::ZERO, &params);
        apply_contact_impulse(&mut c, &mut a, &mut b, Vect::X, Real::ZERO, Vect::ZERO);
        assert_eq!(a.v, Vect::ZERO);
        assert_eq!(b.v, Vect::ZERO);
        assert_eq!(c.jn_acc, Real::ONE);
        // Separating: no impulse (accumulated impulse cannot go negative).
        a.v = Vect::from_ints(-1, 0);
        c.jn_acc = Real::ZERO;
        apply_contact_impulse(&mut c, &mut a, &mut b, Vect::X, Real::ZERO, Vect::ZERO);
        assert_eq!(c.jn_acc, Real::ZERO);
        assert_eq!(a.v, Vect::from_ints(-1, 0));
    }
}
