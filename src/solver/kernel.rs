//! The fast-path arithmetic the contact rows and the joint rows share:
//! impulses, relative velocities and the copy-out/copy-in of a body pair,
//! each generic over the arithmetic [`FixedArith`] (the wide
//! [`Unsaturated`](crate::math::Unsaturated) first, the saturating
//! [`Saturating`](crate::math::Saturating) reference when it overflows).
//!
//! Each function repeats the saturating code it replaced operation for
//! operation (same products, same roundings, same order:
//! [`relative_velocity`] is [`super::relative_velocity`], and so on), which
//! is what keeps the goldens. The joints' driver over these is
//! `constraint::kernel`.
use super::body::SolverBody;
use crate::math::{FixedArith, Real, Vect};

/// Copies out two distinct solver bodies (`None` if equal or out of range).
/// A joint row's bodies always differ (its pre-step skips `a == b`), so
/// the test only ever refuses a contact's.
#[inline(always)]
pub(crate) fn load_pair(bodies: &[SolverBody], a: u32, b: u32) -> Option<(SolverBody, SolverBody)> {
    if a == b {
        return None;
    }
    Some((*bodies.get(a as usize)?, *bodies.get(b as usize)?))
}

/// Writes the copies back, a then b.
#[inline(always)]
pub(crate) fn store_pair(
    bodies: &mut [SolverBody],
    ia: u32,
    a: SolverBody,
    ib: u32,
    b: SolverBody,
) {
    if let Some(slot) = bodies.get_mut(ia as usize) {
        *slot = a;
    }
    if let Some(slot) = bodies.get_mut(ib as usize) {
        *slot = b;
    }
}

/// `1/k` for `k > 0`, else 0: the effective mass of a direction (0 when
/// both bodies have infinite mass along it, so the row applies nothing).
/// The one reciprocal of the contact and joint pre-steps (the joints'
/// former `inv_or_zero`, `k > 0 ? k.recip() : 0`, computed these bits on
/// every input: `solver::pre_step_tests` checks it against that formula).
///
/// The same bits as [`Real::recip`] (round to nearest, ties away from
/// zero, saturated) with one 64-bit division instead of a 128-bit one:
/// `2^64 + ⌊k/2⌋ = q·k + (r + 1 + ⌊k/2⌋)` with `q, r` the quotient and
/// remainder of `(2^64 − 1) / k`, and the last term is below `2k`, so the
/// rounded quotient is `q` or `q + 1`.
#[inline(always)]
pub(crate) fn effective_mass(k: Real) -> Real {
    let Ok(d) = u64::try_from(k.to_bits()) else {
        return Real::ZERO;
    };
    // 1/k ≥ 2^63 ulps for k ≤ 2 ulps: saturated (and 0 for k = 0).
    if d <= 2 {
        return if d == 0 { Real::ZERO } else { Real::MAX };
    }
    let q = u64::MAX.checked_div(d).unwrap_or(0);
    let r = u64::MAX.checked_rem(d).unwrap_or(0);
    // r < d ≤ 2^63 − 1: the sum stays below 2^64; q < 2^63 (d ≥ 3), so
    // q + 1 is a valid `i64`.
    let rest = r.wrapping_add(1).wrapping_add(d >> 1);
    let q = q.wrapping_add(u64::from(rest >= d));
    Real::from_bits(q as i64)
}

/// `−x` (saturating: `0 − x`, which is `Real`'s `−x` on every input, and
/// raises the flag on `−Real::MIN`).
#[inline(always)]
pub(crate) fn neg<A: FixedArith>(x: Real, ar: &mut A) -> Real {
    ar.sub(Real::ZERO, x)
}

/// `v·s` (`Vect::mult`).
#[inline(always)]
pub(crate) fn mult<A: FixedArith>(v: Vect, s: Real, ar: &mut A) -> Vect {
    Vect::new(ar.mul(v.x, s), ar.mul(v.y, s))
}

/// `u + v`.
#[inline(always)]
pub(crate) fn add<A: FixedArith>(u: Vect, v: Vect, ar: &mut A) -> Vect {
    Vect::new(ar.add(u.x, v.x), ar.add(u.y, v.y))
}

/// `u − v`.
#[inline(always)]
pub(crate) fn sub<A: FixedArith>(u: Vect, v: Vect, ar: &mut A) -> Vect {
    Vect::new(ar.sub(u.x, v.x), ar.sub(u.y, v.y))
}

/// `solver::relative_velocity`: `(v_b + perp(r2)·ω_b) − (v_a + perp(r1)·ω_a)`.
#[inline(always)]
pub(crate) fn relative_velocity<A: FixedArith>(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    ar: &mut A,
) -> Vect {
    let va = point_velocity(a, r1, ar);
    let vb = point_velocity(b, r2, ar);
    sub(vb, va, ar)
}

/// `v + perp(r)·ω`, with `perp(r) = (−r.y, r.x)`.
#[inline(always)]
pub(crate) fn point_velocity<A: FixedArith>(body: &SolverBody, r: Vect, ar: &mut A) -> Vect {
    let perp = Vect::new(neg(r.y, ar), r.x);
    let spin = mult(perp, body.w, ar);
    add(body.v, spin, ar)
}

/// `solver::normal_relative_velocity`: `relative_velocity · n`.
#[inline(always)]
pub(crate) fn normal_relative_velocity<A: FixedArith>(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
    ar: &mut A,
) -> Real {
    let vr = relative_velocity(a, b, r1, r2, ar);
    ar.mul_add2(vr.x, n.x, vr.y, n.y)
}

/// `solver::apply_impulse`: `v += j·m⁻¹`, `ω += I⁻¹ (r × j)`.
#[inline(always)]
fn apply_impulse<A: FixedArith>(body: &mut SolverBody, j: Vect, r: Vect, ar: &mut A) {
    let dv = mult(j, body.m_inv, ar);
    body.v = add(body.v, dv, ar);
    let torque = ar.mul_sub2(r.x, j.y, r.y, j.x);
    let dw = ar.mul(body.i_inv, torque);
    body.w = ar.add(body.w, dw);
}

/// `solver::apply_impulses`: `−j` on `a` at `r1`, `+j` on `b` at `r2`.
#[inline(always)]
pub(crate) fn apply_impulses<A: FixedArith>(
    a: &mut SolverBody,
    b: &mut SolverBody,
    r1: Vect,
    r2: Vect,
    j: Vect,
    ar: &mut A,
) {
    let minus_j = Vect::new(neg(j.x, ar), neg(j.y, ar));
    apply_impulse(a, minus_j, r1, ar);
    apply_impulse(b, j, r2, ar);
}

/// Angular impulse `−j` on a, `+j` on b: `ω_a −= j·I_a⁻¹`, `ω_b += j·I_b⁻¹`.
#[inline(always)]
pub(crate) fn apply_angular<A: FixedArith>(
    a: &mut SolverBody,
    b: &mut SolverBody,
    j: Real,
    ar: &mut A,
) {
    let dwa = ar.mul(j, a.i_inv);
    a.w = ar.sub(a.w, dwa);
    let dwb = ar.mul(j, b.i_inv);
    b.w = ar.add(b.w, dwb);
}

/// MIS `k_scalar_body`: `m⁻¹ + I⁻¹ (r × n)²`.
#[inline(always)]
pub fn k_scalar_body(body: &SolverBody, r: Vect, n: Vect) -> Real {
    let rcn = r.cross(n);
    body.m_inv + body.i_inv * rcn * rcn
}

#[cfg(test)]
pub(crate) mod tests {
    //! Value strategies the fast-path tests share (contacts and joints).
    use crate::math::Real;
    use proptest::prelude::*;

    /// Raw values over the whole range: small (ordinary scenes), large
    /// (near saturation), ties and the extremes.
    pub(crate) fn any_real() -> impl Strategy<Value = Real> {
        prop_oneof![
            (-(1i64 << 40)..(1i64 << 40)).prop_map(Real::from_bits),
            // Tiny raw values times multiples of ½: rounding ties.
            (-64i64..64).prop_map(Real::from_bits),
            (-8i64..8).prop_map(|k| Real::from_bits(k << 31)),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| Real::from_bits(v >> s)),
            Just(Real::MAX),
            Just(Real::MIN),
        ]
    }

    /// Raw values within ±16, ties among them: no kernel operation on
    /// these can leave the range.
    pub(crate) fn moderate() -> impl Strategy<Value = Real> {
        prop_oneof![
            (-(1i64 << 36)..(1i64 << 36)).prop_map(Real::from_bits),
            (-64i64..64).prop_map(Real::from_bits),
            (-8i64..8).prop_map(|k| Real::from_bits(k << 31)),
        ]
    }
}
