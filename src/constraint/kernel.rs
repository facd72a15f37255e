//! The joints' per-iteration arithmetic on the solver's fast path, as the
//! contacts' (`solver::ContactConstraint::solve_with`).
//!
//! Each kind's row implements [`JointKernel`]: its warm-start impulse
//! ([`apply`](JointKernel::apply)) and its iteration
//! ([`iterate`](JointKernel::iterate)) are written once, generic over the
//! arithmetic [`FixedArith`]. [`solve`] and [`warm_start`] run them first in
//! [`Unsaturated`] arithmetic (plain wide integer operations and one sticky
//! overflow flag) on copies of the two bodies and the accumulated impulse;
//! only if the flag is raised do they discard the copies and rerun the same
//! code in [`Saturating`] arithmetic (`Real`'s operators, the reference).
//! Wrapping and saturating arithmetic agree on every in-range result, so
//! the outcome is the saturating one bit for bit, and ordinary scenes pay
//! for no per-operation saturation checks.
//!
//! The kernels are built from the solver's fast-path arithmetic
//! (`solver::kernel`), which repeats the saturating code it replaced
//! operation for operation, which is what keeps the goldens. Operations that are not hot (a vector's length for the
//! `max_force` clamp, a projection, a sign test) call the saturating `Real`
//! and `Vect` functions directly: they are the same function in both modes,
//! so they need no flag.
use crate::math::{FixedArith, Real, Saturating, Unsaturated, Vect};
use crate::solver::kernel::{load_pair, store_pair};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// A joint row's impulse arithmetic, generic over the arithmetic mode.
/// The accumulated impulse is not the row's: [`Accumulated`] holds it
/// beside the row, and [`solve`] and [`warm_start`] pass it in.
pub(crate) trait JointKernel {
    /// The accumulated impulse: a scalar along the row's direction, or a
    /// vector for point constraints (zero by default).
    type Impulse: Copy + Default;

    /// False for a row that does nothing this sub-step (a limit not
    /// reached): it is neither warm started nor iterated.
    #[inline(always)]
    fn is_active(&self) -> bool {
        true
    }

    /// Applies the impulse `j` to body copies `a` (−) and `b` (+): the
    /// warm start.
    fn apply<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        j: Self::Impulse,
        ar: &mut A,
    );

    /// One iteration on body copies `a`, `b` and the accumulated impulse
    /// `acc`, which is clamped by `j_max = max_force·dt`. A row with a
    /// position bias applies `soft` to its impulse ([`soften`]); the
    /// sequential solver passes [`Softness::RIGID`], which changes no bit.
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Self::Impulse,
        j_max: Real,
        soft: Softness,
        ar: &mut A,
    );

    /// Drops the row's position bias (the soft step's relax pass); rows
    /// without one do nothing.
    #[inline(always)]
    fn relax(&mut self) {}
}

/// The soft impulse of a row whose rigid impulse is `j` and whose
/// accumulated impulse is `acc`: `mass_scale·j − impulse_scale·acc`
/// (module `solver::softness`); `j` itself, untouched, for a rigid row.
#[inline(always)]
pub(crate) fn soften<A: FixedArith>(j: Real, acc: Real, soft: Softness, ar: &mut A) -> Real {
    if soft.is_rigid() {
        return j;
    }
    let scaled = ar.mul(j, soft.mass_scale);
    let back = ar.mul(soft.impulse_scale, acc);
    ar.sub(scaled, back)
}

/// [`soften`] of a point constraint's impulse, component by component.
#[inline(always)]
pub(crate) fn soften_vect<A: FixedArith>(j: Vect, acc: Vect, soft: Softness, ar: &mut A) -> Vect {
    if soft.is_rigid() {
        return j;
    }
    Vect::new(soften(j.x, acc.x, soft, ar), soften(j.y, acc.y, soft, ar))
}

/// A row and its accumulated impulse for one sub-step: zero when built,
/// last step's impulse after the warm start, then what the iterations
/// accumulate (stored back into the constraint after the step).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Accumulated<K: JointKernel> {
    pub(crate) row: K,
    pub(crate) acc: K::Impulse,
}

impl<K: JointKernel> Accumulated<K> {
    /// The row with a zero accumulator.
    #[inline(always)]
    pub(crate) fn new(row: K) -> Self {
        Accumulated {
            row,
            acc: K::Impulse::default(),
        }
    }
}

/// The accumulate-clamp step of a scalar row: adds the impulse `j` to the
/// accumulated impulse `acc`, clamps the sum to `[lo, hi]` and returns the
/// change of `acc`, the impulse to apply.
#[inline(always)]
pub(crate) fn accumulate<A: FixedArith>(
    acc: &mut Real,
    j: Real,
    lo: Real,
    hi: Real,
    ar: &mut A,
) -> Real {
    let old = *acc;
    *acc = ar.add(old, j).clamp(lo, hi);
    ar.sub(*acc, old)
}

/// One iteration of row `r` on solver bodies `ia`, `ib`: fast path first,
/// the saturating reference only if something overflowed.
#[inline(always)]
pub(crate) fn solve<K: JointKernel>(
    r: &mut Accumulated<K>,
    bodies: &mut [SolverBody],
    ia: u32,
    ib: u32,
    j_max: Real,
    soft: Softness,
) {
    if !r.row.is_active() {
        return;
    }
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut acc = r.acc;
    let mut fast = Unsaturated::new();
    r.row
        .iterate(&mut a, &mut b, &mut acc, j_max, soft, &mut fast);
    if fast.overflowed() {
        // The inputs are still in `bodies` and `r`: no copies kept.
        solve_saturating(r, bodies, ia, ib, j_max, soft);
        return;
    }
    r.acc = acc;
    store_pair(bodies, ia, a, ib, b);
}

/// The reference path of [`solve`], out of line: it runs only when
/// something saturates.
#[cold]
#[inline(never)]
fn solve_saturating<K: JointKernel>(
    r: &mut Accumulated<K>,
    bodies: &mut [SolverBody],
    ia: u32,
    ib: u32,
    j_max: Real,
    soft: Softness,
) {
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut acc = r.acc;
    r.row
        .iterate(&mut a, &mut b, &mut acc, j_max, soft, &mut Saturating);
    r.acc = acc;
    store_pair(bodies, ia, a, ib, b);
}

/// The warm start of row `r`: `acc` (last step's impulse, already scaled)
/// becomes the accumulator and is applied to solver bodies `ia`, `ib`, fast
/// path first as in [`solve`]. An inactive row keeps its zero accumulator.
#[inline(always)]
pub(crate) fn warm_start<K: JointKernel>(
    r: &mut Accumulated<K>,
    bodies: &mut [SolverBody],
    ia: u32,
    ib: u32,
    acc: K::Impulse,
) {
    if !r.row.is_active() {
        return;
    }
    r.acc = acc;
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut fast = Unsaturated::new();
    r.row.apply(&mut a, &mut b, acc, &mut fast);
    if fast.overflowed() {
        // The inputs are still in `bodies`: no copies kept.
        apply_saturating(&r.row, bodies, ia, ib, acc);
        return;
    }
    store_pair(bodies, ia, a, ib, b);
}

/// The reference path of [`warm_start`].
#[cold]
#[inline(never)]
fn apply_saturating<K: JointKernel>(
    k: &K,
    bodies: &mut [SolverBody],
    ia: u32,
    ib: u32,
    acc: K::Impulse,
) {
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    k.apply(&mut a, &mut b, acc, &mut Saturating);
    store_pair(bodies, ia, a, ib, b);
}

#[cfg(test)]
pub(crate) mod tests;
