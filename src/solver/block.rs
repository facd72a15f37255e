//! The block solver: the two contacts of a two-point manifold (a box face on
//! a face) solved together instead of one after the other.
//!
//! Why: the sequential-impulse iteration solves contact 1, then contact 2
//! with the velocities contact 1 left. The first contact of a face always
//! gets more than its share, so a symmetric stack leans, drifts sideways
//! (`stack_10`'s top box moved 2.25 cm in 10 s) and a scene and its mirror
//! image evolve differently. Solving both contacts at once removes the order:
//!
//! * **normal and bias rows**: the exact 2×2 linear complementarity problem
//!   (Box2D v2's block solver, Catto): find accumulated impulses `x ≥ 0`
//!   with post-impulse errors `e = w + K (x − x_old) ≥ 0` and `xᵢ eᵢ = 0`,
//!   by trying the four cases (both push, only 1, only 2, neither) in a fixed
//!   order. `K` is the 2×2 effective inverse mass of the two contacts along
//!   the normal, inverted once per step in the pre-step, so an iteration has
//!   no division.
//! * **friction**: both contacts of a face lie on one line parallel to the
//!   tangent, so their tangent rows are (almost) the same row — the 2×2
//!   tangent matrix is singular and a block solve is meaningless. The face
//!   gets one friction row at the pair of contacts, half of its impulse on
//!   each, clamped to `μ·(jn₁ + jn₂)`. Both rows keep half of the total.
//!
//! Every formula is symmetric in the two contacts (sums are exact in fixed
//! point, `a·b + c·d` is rounded once), and every operation is symmetric
//! under negation, so a reflected scene evolves as the exact reflection.
//!
//! When `K` is ill-conditioned (the two contacts almost at the same lever
//! arm: a corner on a corner), the block is not used and the two rows are
//! solved sequentially as before; the condition guard is Box2D's
//! `k_max² < 1000·det K`, evaluated exactly in 128-bit integers.
use super::kernel::{effective_mass, load_pair, neg, store_pair};
use super::{move_bodies, ContactConstraint, SolverBody, Velocity};
use crate::math::exact::int::wide_mul;
use crate::math::exact::predicates::saturate_to_real;
use crate::math::{below_2_62, Bounded, FixedArith, Real, Saturating, Unsaturated, Vect};

/// Largest accepted condition estimate `k_max² / det K` (Box2D v2's value):
/// beyond it the 2×2 inverse amplifies rounding more than the block gains.
const MAX_CONDITION: i128 = 1000;

/// The 2×2 effective inverse mass `K` of two contacts along the normal,
/// and its inverse.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NormalBlock {
    /// `K = [[k11, k12], [k12, k22]]`; `k11`, `k22` are the rows' own `k`
    /// (their `n_mass` is `1/k`).
    pub k11: Real,
    pub k12: Real,
    pub k22: Real,
    /// `K⁻¹ = [[inv11, inv12], [inv12, inv22]]`.
    pub inv11: Real,
    pub inv12: Real,
    pub inv22: Real,
}

/// What the block solver needs beyond the two rows, built once per step in
/// the pre-step ([`ManifoldBlock::new`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ManifoldBlock {
    /// Normal (and bias) coupling.
    pub normal: NormalBlock,
    /// Face friction: `2·perp(n)`, the linear part of the summed tangent
    /// velocity `vt₁ + vt₂`.
    pub t2: Vect,
    /// `r1 × t` and `r2 × t` summed over the two contacts, per body.
    pub st_a: Real,
    pub st_b: Real,
    /// Angular velocity change per unit face-friction impulse
    /// (`I⁻¹·(rt₁ + rt₂)/2`: half the impulse at each contact).
    pub kt_a: Real,
    pub kt_b: Real,
    /// `1 / (d(vt₁ + vt₂)/dJ)` for a face impulse `J`.
    pub t_mass: Real,
    /// Both rows are [`bounded`](ContactConstraint::bounded) and so are
    /// the block's own constants of the iteration's dot products (`t2`,
    /// `st_a`, `st_b`, `kt_a`, `kt_b`): the iteration may run in
    /// [`Bounded`] arithmetic ([`check_range`](Self::check_range)). Set
    /// only by the pre-step and `check_range`.
    pub(crate) bounded: bool,
}

impl ManifoldBlock {
    /// The block of rows `c1`, `c2` (one manifold: same bodies, same
    /// normal), or `None` when `K` is singular or ill-conditioned.
    ///
    /// On the solver's fast path, as the rows' pre-step
    /// ([`ContactConstraint::prepare`]): the rounded arithmetic runs in
    /// [`Unsaturated`] arithmetic, recomputed in saturating [`Real`]
    /// arithmetic only if the overflow flag is raised; the exact integer
    /// part (the determinant, the condition guard and the divisions) comes
    /// after, on the chosen terms, and is the same in both modes.
    pub fn new(
        c1: &ContactConstraint,
        c2: &ContactConstraint,
        bodies: &[SolverBody],
        friction: bool,
    ) -> Option<ManifoldBlock> {
        let zero = SolverBody::default();
        let a = bodies.get(c1.a as usize).unwrap_or(&zero);
        let b = bodies.get(c1.b as usize).unwrap_or(&zero);
        let mut fast = Unsaturated::new();
        let mut terms = block_terms(c1, c2, a, b, friction, &mut fast);
        if fast.overflowed() {
            terms = block_terms_saturating(c1, c2, a, b, friction);
        }
        let mut block = terms.finish(a.i_inv, b.i_inv, friction)?;
        block.check_range(c1, c2);
        Some(block)
    }

    /// Sets [`bounded`](Self::bounded) from the rows' flags and the
    /// block's constants.
    #[inline(always)]
    pub fn check_range(&mut self, c1: &ContactConstraint, c2: &ContactConstraint) {
        self.bounded = c1.bounded
            && c2.bounded
            && below_2_62(&[
                self.t2.x, self.t2.y, self.st_a, self.st_b, self.kt_a, self.kt_b,
            ]);
    }
}

/// The rounded arithmetic of a block ([`block_terms`]): `K`, and the face
/// friction's direction, lever arms and `k`.
#[derive(Clone, Copy)]
struct BlockTerms {
    k11: Real,
    k12: Real,
    k22: Real,
    t2: Vect,
    st_a: Real,
    st_b: Real,
    /// `d(vt₁ + vt₂)/dJ`, whose reciprocal is the block's `t_mass`.
    kc: Real,
}

/// The block's terms in the arithmetic `ar`: the same operations, in the
/// same order of rounding, as the saturating code they replaced. The
/// friction terms are computed whether or not the block is then accepted
/// (a refused block is rare: a corner on a corner).
#[inline(always)]
fn block_terms<A: FixedArith>(
    c1: &ContactConstraint,
    c2: &ContactConstraint,
    a: &SolverBody,
    b: &SolverBody,
    friction: bool,
    ar: &mut A,
) -> BlockTerms {
    let m = ar.add(c1.m_inv_a, c1.m_inv_b);
    // The same expression (and roundings) as `k_scalar`, whose
    // reciprocal is each row's `n_mass`.
    let k_row = |c: &ContactConstraint, ar: &mut A| {
        let ta = ar.mul(c.kn_a, c.rn_a);
        let sa = ar.add(c.m_inv_a, ta);
        let tb = ar.mul(c.kn_b, c.rn_b);
        let sb = ar.add(c.m_inv_b, tb);
        ar.add(sa, sb)
    };
    let k11 = k_row(c1, ar);
    let k22 = k_row(c2, ar);
    // Products of lever arms first: symmetric in the two contacts.
    let pa = ar.mul(c1.rn_a, c2.rn_a);
    let pb = ar.mul(c1.rn_b, c2.rn_b);
    let coupling = ar.mul_add2(a.i_inv, pa, b.i_inv, pb);
    let mut terms = BlockTerms {
        k11,
        k12: ar.add(m, coupling),
        k22,
        t2: Vect::ZERO,
        st_a: Real::ZERO,
        st_b: Real::ZERO,
        kc: Real::ZERO,
    };
    if friction {
        // 2·perp(n), perp(n) = (−n.y, n.x); doubling is `x + x`.
        let tx = neg(c1.n.y, ar);
        terms.t2 = Vect::new(ar.add(tx, tx), ar.add(c1.n.x, c1.n.x));
        let st_a = ar.add(c1.rt_a, c2.rt_a);
        let st_b = ar.add(c1.rt_b, c2.rt_b);
        let sq_a = ar.mul(st_a, st_a);
        let sq_b = ar.mul(st_b, st_b);
        let angular = ar.mul_add2(a.i_inv, sq_a, b.i_inv, sq_b);
        let half = ar.mul(angular, Real::HALF);
        let m2 = ar.add(m, m);
        terms.kc = ar.add(m2, half);
        terms.st_a = st_a;
        terms.st_b = st_b;
    }
    terms
}

/// The reference path of [`ManifoldBlock::new`]'s arithmetic, out of line.
#[cold]
#[inline(never)]
fn block_terms_saturating(
    c1: &ContactConstraint,
    c2: &ContactConstraint,
    a: &SolverBody,
    b: &SolverBody,
    friction: bool,
) -> BlockTerms {
    block_terms(c1, c2, a, b, friction, &mut Saturating)
}

impl BlockTerms {
    /// The exact integer part: the condition guard, `K⁻¹` and the face
    /// friction's angular terms and effective mass.
    #[inline(always)]
    fn finish(self, i_inv_a: Real, i_inv_b: Real, friction: bool) -> Option<ManifoldBlock> {
        let BlockTerms { k11, k12, k22, .. } = self;
        if !k11.is_positive() || !k22.is_positive() {
            return None;
        }
        // det K in units of 2^-64: both products are ≥ 0 and ≤ 2^126, so
        // the difference cannot overflow.
        let det = wide_mul(k11.to_bits(), k22.to_bits())
            .checked_sub(wide_mul(k12.to_bits(), k12.to_bits()))?;
        let kmax = k11.max(k22).to_bits();
        if det <= 0 || wide_mul(kmax, kmax) >= det.saturating_mul(MAX_CONDITION) {
            return None;
        }
        let normal = NormalBlock {
            k11,
            k12,
            k22,
            inv11: ratio_by_det(k22, det),
            inv12: ratio_by_det(-k12, det),
            inv22: ratio_by_det(k11, det),
        };
        let mut block = ManifoldBlock {
            normal,
            ..ManifoldBlock::default()
        };
        if friction {
            block.t2 = self.t2;
            block.st_a = self.st_a;
            block.st_b = self.st_b;
            block.kt_a = half_product(i_inv_a, self.st_a);
            block.kt_b = half_product(i_inv_b, self.st_b);
            block.t_mass = effective_mass(self.kc);
        }
        Some(block)
    }
}

/// `num / det` for `det > 0` in units of 2^-64 (an entry of `K⁻¹`),
/// rounded to nearest (ties away from zero) and saturated: one native
/// 128-bit division (`|num|·2^64 ≤ 2^127`) and a multiplication for the
/// remainder, the same bits as the 256-bit `ratio_round` it replaced.
#[inline(always)]
fn ratio_by_det(num: Real, det: i128) -> Real {
    let Ok(d) = u128::try_from(det) else {
        return Real::ZERO;
    };
    let n = u128::from(num.to_bits().unsigned_abs()) << 64;
    let q = n.checked_div(d).unwrap_or(0);
    // q·d ≤ n: exact; d > r, so `d − r` does not wrap either.
    let r = n.wrapping_sub(q.wrapping_mul(d));
    let q = q.wrapping_add(u128::from(r >= d.wrapping_sub(r)));
    let max = u128::from(i64::MAX.unsigned_abs());
    let bits = match (num.is_negative(), u64::try_from(q)) {
        // −2^63 is the one negative magnitude beyond `i64::MAX`.
        (true, Ok(m)) if u128::from(m) <= max.wrapping_add(1) => 0i64.wrapping_sub_unsigned(m),
        (true, _) => i64::MIN,
        (false, Ok(m)) if u128::from(m) <= max => m as i64,
        (false, _) => i64::MAX,
    };
    Real::from_bits(bits)
}

/// `i_inv·s/2` rounded to nearest (ties away from zero), saturated: the
/// angular velocity per unit face impulse, half of it at each contact.
/// One rounding of the exact product (`|i_inv·s| ≤ 2^126`).
#[inline(always)]
fn half_product(i_inv: Real, s: Real) -> Real {
    let p = wide_mul(i_inv.to_bits(), s.to_bits());
    // |p| ≤ 2^126: adding 2^32 cannot overflow; the quotient is ≤ 2^93.
    let q = (p.unsigned_abs().wrapping_add(1 << 32) >> 33) as i128;
    saturate_to_real(if p < 0 { q.wrapping_neg() } else { q })
}

/// One block iteration of rows `c1`, `c2` (the two-contact
/// [`ContactConstraint::solve_with`]): fast path first, the saturating
/// reference only if the overflow flag is raised, so the result is always
/// the saturating one. The rows' and the block's constants are
/// range-checked first (their fields are public and may have changed since
/// the pre-step).
#[inline]
pub fn solve_with<const FRICTION: bool, const BIAS: bool>(
    c1: &mut ContactConstraint,
    c2: &mut ContactConstraint,
    block: &ManifoldBlock,
    bodies: &mut [SolverBody],
) {
    c1.check_range();
    c2.check_range();
    let mut checked = *block;
    checked.check_range(c1, c2);
    solve_prepared::<FRICTION, BIAS>(c1, c2, &checked, bodies, (c1.a, c1.b));
}

/// [`solve_with`] trusting the range flags the pre-step set: the space's
/// step, whose rows and blocks nothing changes before the iterations.
/// Bodies `a` and `b` are `bodies[ends.0]` and `bodies[ends.1]` (see
/// [`ContactConstraint::solve_prepared`]).
#[inline]
pub(crate) fn solve_prepared<const FRICTION: bool, const BIAS: bool>(
    c1: &mut ContactConstraint,
    c2: &mut ContactConstraint,
    block: &ManifoldBlock,
    bodies: &mut [SolverBody],
    ends: (u32, u32),
) {
    if !block.bounded {
        solve_saturating::<FRICTION, BIAS>(c1, c2, block, bodies, ends);
        return;
    }
    let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
        return;
    };
    let mut acc = [
        [c1.jb_acc, c1.jn_acc, c1.jt_acc],
        [c2.jb_acc, c2.jn_acc, c2.jt_acc],
    ];
    let mut fast = Bounded(Unsaturated::new());
    iterate::<_, FRICTION, BIAS>(c1, c2, block, &mut a, &mut b, &mut acc, &mut fast);
    if fast.0.overflowed() {
        // The inputs are still in `bodies` and the rows: no copies kept.
        solve_saturating::<FRICTION, BIAS>(c1, c2, block, bodies, ends);
        return;
    }
    [c1.jb_acc, c1.jn_acc, c1.jt_acc] = acc[0];
    [c2.jb_acc, c2.jn_acc, c2.jt_acc] = acc[1];
    store_pair(bodies, ends.0, a, ends.1, b);
}

/// The reference path of [`solve_with`], out of line.
#[cold]
#[inline(never)]
pub(super) fn solve_saturating<const FRICTION: bool, const BIAS: bool>(
    c1: &mut ContactConstraint,
    c2: &mut ContactConstraint,
    block: &ManifoldBlock,
    bodies: &mut [SolverBody],
    ends: (u32, u32),
) {
    let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
        return;
    };
    let mut acc = [
        [c1.jb_acc, c1.jn_acc, c1.jt_acc],
        [c2.jb_acc, c2.jn_acc, c2.jt_acc],
    ];
    iterate::<_, FRICTION, BIAS>(c1, c2, block, &mut a, &mut b, &mut acc, &mut Saturating);
    [c1.jb_acc, c1.jn_acc, c1.jt_acc] = acc[0];
    [c2.jb_acc, c2.jn_acc, c2.jt_acc] = acc[1];
    store_pair(bodies, ends.0, a, ends.1, b);
}

/// The velocity error of a row along the normal: `n·dv + ω_b (r2 × n) −
/// ω_a (r1 × n)`, one rounding.
#[inline(always)]
fn normal_velocity<A: FixedArith>(
    c: &ContactConstraint,
    dv: Vect,
    wa: Real,
    wb: Real,
    ar: &mut A,
) -> Real {
    let neg_rn_a = ar.neg_const(c.rn_a);
    ar.dot4_bounded([dv.x, dv.y, wb, wa], [c.n.x, c.n.y, c.rn_b, neg_rn_a])
}

/// One iteration on body copies and accumulators `acc[i] = [jb, jn, jt]` of
/// row `i`, in the arithmetic `ar`: bias block, normal block, face friction,
/// each from the velocities before this iteration's impulses (as the
/// sequential rows do), then one combined impulse per velocity.
#[inline(always)]
fn iterate<A: FixedArith, const FRICTION: bool, const BIAS: bool>(
    c1: &ContactConstraint,
    c2: &ContactConstraint,
    block: &ManifoldBlock,
    a: &mut SolverBody,
    b: &mut SolverBody,
    acc: &mut [[Real; 3]; 2],
    ar: &mut A,
) {
    let k = &block.normal;
    let masses = [c1.n_mass, c2.n_mass];
    // As in a row: with no bias velocity on either body and neither a
    // target nor an impulse on either contact, the bias block is an exact
    // no-op (the complementarity problem of zeros returns zeros).
    let bias_idle = || {
        c1.bias_target.is_zero()
            && c2.bias_target.is_zero()
            && acc[0][0].is_zero()
            && acc[1][0].is_zero()
            && a.bias_is_zero()
            && b.bias_is_zero()
    };
    if BIAS && !bias_idle() {
        let dvb = Vect::new(
            ar.sub(b.v_bias.x, a.v_bias.x),
            ar.sub(b.v_bias.y, a.v_bias.y),
        );
        let v1 = normal_velocity(c1, dvb, a.w_bias, b.w_bias, ar);
        let v2 = normal_velocity(c2, dvb, a.w_bias, b.w_bias, ar);
        let w = [ar.sub(v1, c1.bias_target), ar.sub(v2, c2.bias_target)];
        let old = [acc[0][0], acc[1][0]];
        let x = complementarity(k, masses, w, old, ar);
        [acc[0][0], acc[1][0]] = x;
        let d = [ar.sub(x[0], old[0]), ar.sub(x[1], old[1])];
        apply_normals(c1, c2, a, b, d, ar, Velocity::Bias);
    }

    let dv = Vect::new(ar.sub(b.v.x, a.v.x), ar.sub(b.v.y, a.v.y));
    let v1 = normal_velocity(c1, dv, a.w, b.w, ar);
    let v2 = normal_velocity(c2, dv, a.w, b.w, ar);
    let w = [ar.add(c1.bounce, v1), ar.add(c2.bounce, v2)];
    let old = [acc[0][1], acc[1][1]];
    let x = complementarity(k, masses, w, old, ar);
    [acc[0][1], acc[1][1]] = x;
    let d = [ar.sub(x[0], old[0]), ar.sub(x[1], old[1])];

    if FRICTION {
        // vt₁ + vt₂ (+ the surface velocity of both), one rounding.
        let neg_st_a = ar.neg_const(block.st_a);
        let vt = ar.dot4_bounded(
            [dv.x, dv.y, b.w, a.w],
            [block.t2.x, block.t2.y, block.st_b, neg_st_a],
        );
        let surface = ar.add(c1.surface_t, c2.surface_t);
        let vt = ar.add(vt, surface);
        let total = ar.add(acc[0][2], acc[1][2]);
        let jn = ar.add(x[0], x[1]);
        let jt_max = ar.mul(c1.friction, jn);
        let djt = ar.mul(vt, block.t_mass);
        let new_total = ar.sub(total, djt);
        let new_total = new_total.clamp(-jt_max, jt_max);
        let jt = ar.sub(new_total, total);
        let half = ar.mul(new_total, Real::HALF);
        acc[0][2] = half;
        acc[1][2] = half;
        let n = c1.n;
        let dn = ar.add(d[0], d[1]);
        // P = n·(d₁ + d₂) + perp(n)·J, perp(n) = (−n.y, n.x).
        let p = Vect::new(ar.mul_sub2(n.x, dn, n.y, jt), ar.mul_add2(n.y, dn, n.x, jt));
        let dwa = ar.dot4_bounded(
            [c1.kn_a, c2.kn_a, block.kt_a, Real::ZERO],
            [d[0], d[1], jt, Real::ZERO],
        );
        let dwb = ar.dot4_bounded(
            [c1.kn_b, c2.kn_b, block.kt_b, Real::ZERO],
            [d[0], d[1], jt, Real::ZERO],
        );
        move_bodies(
            a,
            b,
            p,
            dwa,
            dwb,
            c1.m_inv_a,
            c1.m_inv_b,
            ar,
            Velocity::Real,
        );
    } else {
        apply_normals(c1, c2, a, b, d, ar, Velocity::Real);
    }
}

/// Applies normal impulses `d[i]` at both rows as one impulse (exact sum of
/// the linear parts, one rounding per angular part).
#[inline(always)]
fn apply_normals<A: FixedArith>(
    c1: &ContactConstraint,
    c2: &ContactConstraint,
    a: &mut SolverBody,
    b: &mut SolverBody,
    d: [Real; 2],
    ar: &mut A,
    which: Velocity,
) {
    let n = c1.n;
    let dn = ar.add(d[0], d[1]);
    let p = Vect::new(ar.mul(n.x, dn), ar.mul(n.y, dn));
    let dwa = ar.mul_add2(c1.kn_a, d[0], c2.kn_a, d[1]);
    let dwb = ar.mul_add2(c1.kn_b, d[0], c2.kn_b, d[1]);
    move_bodies(a, b, p, dwa, dwb, c1.m_inv_a, c1.m_inv_b, ar, which);
}

/// The 2×2 complementarity problem of two rows: new accumulated impulses
/// `x ≥ 0` such that the errors after the impulse, `e = w + K (x − old)`,
/// are `≥ 0`, and `eᵢ = 0` wherever `xᵢ > 0`. `masses` are `1/k11`, `1/k22`.
/// Cases in a fixed order: both contacts push, only the first, only the
/// second, neither. In exact arithmetic exactly one case holds (`K` is
/// positive definite); if rounding rejects all four, one sequential pass
/// over the two rows decides.
#[inline(always)]
fn complementarity<A: FixedArith>(
    k: &NormalBlock,
    masses: [Real; 2],
    w: [Real; 2],
    old: [Real; 2],
    ar: &mut A,
) -> [Real; 2] {
    // Both push: e = 0, x = old − K⁻¹ w.
    let d1 = ar.mul_add2(k.inv11, w[0], k.inv12, w[1]);
    let d2 = ar.mul_add2(k.inv12, w[0], k.inv22, w[1]);
    let (x1, x2) = (ar.sub(old[0], d1), ar.sub(old[1], d2));
    if !x1.is_negative() && !x2.is_negative() {
        return [x1, x2];
    }
    // Only the first: x2 = 0, e1 = 0, e2 ≥ 0.
    let coupled = ar.mul(k.k12, old[1]);
    let e1 = ar.sub(w[0], coupled);
    let d1 = ar.mul(e1, masses[0]);
    let x1 = ar.sub(old[0], d1);
    if !x1.is_negative() {
        let dx1 = ar.sub(x1, old[0]);
        let de2 = ar.mul_sub2(k.k12, dx1, k.k22, old[1]);
        let e2 = ar.add(w[1], de2);
        if !e2.is_negative() {
            return [x1, Real::ZERO];
        }
    }
    // Only the second: x1 = 0, e2 = 0, e1 ≥ 0.
    let coupled = ar.mul(k.k12, old[0]);
    let e2 = ar.sub(w[1], coupled);
    let d2 = ar.mul(e2, masses[1]);
    let x2 = ar.sub(old[1], d2);
    if !x2.is_negative() {
        let dx2 = ar.sub(x2, old[1]);
        let de1 = ar.mul_sub2(k.k12, dx2, k.k11, old[0]);
        let e1 = ar.add(w[0], de1);
        if !e1.is_negative() {
            return [Real::ZERO, x2];
        }
    }
    // Neither: x = 0, e = w − K·old ≥ 0.
    let de1 = ar.mul_add2(k.k11, old[0], k.k12, old[1]);
    let de2 = ar.mul_add2(k.k12, old[0], k.k22, old[1]);
    let (e1, e2) = (ar.sub(w[0], de1), ar.sub(w[1], de2));
    if !e1.is_negative() && !e2.is_negative() {
        return [Real::ZERO, Real::ZERO];
    }
    // Rounding rejected all four (a contact at the edge between two cases):
    // one sequential pass, as the rows would do on their own. Keeping the
    // old impulses instead (Box2D's choice) let a warm-started impulse that
    // should vanish survive a step and pop a stack.
    let d1 = ar.mul(w[0], masses[0]);
    let x1 = ar.sub(old[0], d1).max(Real::ZERO);
    let dx1 = ar.sub(x1, old[0]);
    let coupled = ar.mul(k.k12, dx1);
    let e2 = ar.add(w[1], coupled);
    let d2 = ar.mul(e2, masses[1]);
    [x1, ar.sub(old[1], d2).max(Real::ZERO)]
}

#[cfg(test)]
mod tests {
    //! The block's pre-step against the one it replaced, kept here verbatim
    //! as the oracle (saturating operators, 256-bit divisions).
    use super::*;
    use crate::math::exact::int::I256;
    use crate::solver::kernel::tests::{any_real, moderate};
    use proptest::prelude::*;

    /// `ManifoldBlock::new` as it was.
    fn new_reference(
        c1: &ContactConstraint,
        c2: &ContactConstraint,
        bodies: &[SolverBody],
        friction: bool,
    ) -> Option<ManifoldBlock> {
        let zero = SolverBody::default();
        let a = bodies.get(c1.a as usize).unwrap_or(&zero);
        let b = bodies.get(c1.b as usize).unwrap_or(&zero);
        let m = c1.m_inv_a + c1.m_inv_b;
        let k_row =
            |c: &ContactConstraint| (c.m_inv_a + c.kn_a * c.rn_a) + (c.m_inv_b + c.kn_b * c.rn_b);
        let (k11, k22) = (k_row(c1), k_row(c2));
        let k12 = m + Real::mul_add2(a.i_inv, c1.rn_a * c2.rn_a, b.i_inv, c1.rn_b * c2.rn_b);
        if !k11.is_positive() || !k22.is_positive() {
            return None;
        }
        let det = wide_mul(k11.to_bits(), k22.to_bits())
            .checked_sub(wide_mul(k12.to_bits(), k12.to_bits()))?;
        let kmax = k11.max(k22).to_bits();
        if det <= 0 || wide_mul(kmax, kmax) >= det.saturating_mul(MAX_CONDITION) {
            return None;
        }
        let normal = NormalBlock {
            k11,
            k12,
            k22,
            inv11: ratio_reference(k22, det),
            inv12: ratio_reference(-k12, det),
            inv22: ratio_reference(k11, det),
        };
        let mut block = ManifoldBlock {
            normal,
            ..ManifoldBlock::default()
        };
        if friction {
            let t = c1.n.perp();
            let (st_a, st_b) = (c1.rt_a + c2.rt_a, c1.rt_b + c2.rt_b);
            let kc = m.mul_pow2(1)
                + Real::mul_add2(a.i_inv, st_a.square(), b.i_inv, st_b.square()) * Real::HALF;
            block.t2 = Vect::new(t.x.mul_pow2(1), t.y.mul_pow2(1));
            block.st_a = st_a;
            block.st_b = st_b;
            block.kt_a = half_reference(a.i_inv, st_a);
            block.kt_b = half_reference(b.i_inv, st_b);
            block.t_mass = if kc.is_positive() {
                kc.recip()
            } else {
                Real::ZERO
            };
        }
        // The range flag (newer than this oracle) is a function of the fields.
        block.check_range(c1, c2);
        Some(block)
    }

    fn ratio_reference(num: Real, det: i128) -> Real {
        let scaled = I256::from_i128(i128::from(num.to_bits())).shl(64);
        saturate_to_real(scaled.ratio_round(I256::from_i128(det)))
    }

    fn half_reference(i_inv: Real, s: Real) -> Real {
        saturate_to_real(I256::from_i128(wide_mul(i_inv.to_bits(), s.to_bits())).round_shr(33))
    }

    /// A row from free values (the fields the block reads).
    fn row(v: &[Real], n: Vect) -> ContactConstraint {
        let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
        ContactConstraint {
            a: 0,
            b: 1,
            n,
            rn_a: r(0),
            rn_b: r(1),
            rt_a: r(2),
            rt_b: r(3),
            kn_a: r(4),
            kn_b: r(5),
            m_inv_a: r(6).abs(),
            m_inv_b: r(7).abs(),
            ..ContactConstraint::default()
        }
    }

    fn body(m_inv: Real, i_inv: Real) -> SolverBody {
        SolverBody {
            m_inv: m_inv.abs(),
            i_inv: i_inv.abs(),
            ..SolverBody::default()
        }
    }

    /// `new` against the reference, with and without friction; returns
    /// whether the arithmetic stayed on the fast path.
    fn check(
        c1: &ContactConstraint,
        c2: &ContactConstraint,
        bodies: &[SolverBody; 2],
    ) -> Result<bool, TestCaseError> {
        let mut fast = true;
        for friction in [true, false] {
            let want = new_reference(c1, c2, bodies, friction);
            prop_assert_eq!(ManifoldBlock::new(c1, c2, bodies, friction), want);
            let mut u = Unsaturated::new();
            let _ = block_terms(c1, c2, &bodies[0], &bodies[1], friction, &mut u);
            fast &= !u.overflowed();
        }
        Ok(fast)
    }

    /// Raw values of a wide determinant: small, around 2^64, up to 2^126.
    fn any_det() -> impl Strategy<Value = i128> {
        prop_oneof![
            1i128..1000,
            (any::<u64>(), 0u32..63).prop_map(|(v, s)| i128::from(v >> s).max(1)),
            (any::<i64>(), 0u32..62).prop_map(|(v, s)| (i128::from(v.unsigned_abs()) << s).max(1)),
            Just(1i128 << 64),
            Just(i128::MAX),
        ]
    }

    #[test]
    fn exact_divisions_match_the_wide_ones_at_the_edges() {
        let nums = [
            Real::MIN,
            -Real::MAX,
            -Real::ONE,
            -Real::DELTA,
            Real::ZERO,
            Real::DELTA,
            Real::ONE,
            Real::MAX,
        ];
        let dets = [
            1,
            2,
            3,
            (1i128 << 64) - 1,
            1 << 64,
            (1 << 64) + 1,
            1 << 126,
            i128::MAX,
        ];
        for num in nums {
            for det in dets {
                assert_eq!(
                    ratio_by_det(num, det),
                    ratio_reference(num, det),
                    "{num:?} / {det}"
                );
            }
            for s in nums {
                assert_eq!(half_product(num.abs(), s), half_reference(num.abs(), s));
                assert_eq!(half_product(num, s), half_reference(num, s));
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        #[test]
        fn exact_divisions_match_the_wide_ones(
            num in any_real(), s in any_real(), det in any_det(),
        ) {
            prop_assert_eq!(ratio_by_det(num, det), ratio_reference(num, det));
            prop_assert_eq!(half_product(num, s), half_reference(num, s));
        }

        /// The fast block pre-step is bit-identical to the saturating one
        /// on any input, extremes and ties included.
        #[test]
        fn fast_block_pre_step_equals_the_saturating_one(
            v1 in proptest::collection::vec(any_real(), 8),
            v2 in proptest::collection::vec(any_real(), 8),
            (nx, ny) in (any_real(), any_real()),
            bv in proptest::array::uniform4(any_real()),
        ) {
            let n = Vect::new(nx, ny);
            let bodies = [body(bv[0], bv[1]), body(bv[2], bv[3])];
            check(&row(&v1, n), &row(&v2, n), &bodies)?;
        }

        /// The same on rows the pre-step builds from moderate bodies and
        /// lever arms (within ±16; blocks accepted or refused), where it
        /// must stay on the fast path.
        #[test]
        fn fast_block_pre_step_stays_fast_in_range(
            r in proptest::array::uniform8(moderate()),
            (nx, ny) in (moderate(), moderate()),
            bv in proptest::array::uniform4(moderate()),
        ) {
            let bodies = [body(bv[0], bv[1]), body(bv[2], bv[3])];
            let pair = super::super::PairParams {
                a: 0,
                b: 1,
                n: Vect::new(nx, ny),
                e: Real::ZERO,
                friction: Real::HALF,
                surface_vr: Vect::ZERO,
            };
            let params = super::super::ContactParams {
                dt_inv: Real::from_int(60),
                slop: Real::ZERO,
                bias_coef: Real::ZERO,
                max_bias: Real::MAX,
                switches: super::super::SolverSwitches::ALL,
            };
            let point = |i: usize| crate::arbiter::ManifoldPoint {
                r1: Vect::new(r[i], r[i + 1]),
                r2: Vect::new(r[i + 2], r[i + 3]),
                ..crate::arbiter::ManifoldPoint::default()
            };
            let c1 = ContactConstraint::new(&point(0), &bodies, &pair, &params);
            let c2 = ContactConstraint::new(&point(4), &bodies, &pair, &params);
            prop_assert!(check(&c1, &c2, &bodies)?, "an in-range case left the fast path");
        }
    }
}
