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
use crate::math::{FixedArith, Real, Saturating, Unsaturated};
use crate::solver::kernel::{load_pair, store_pair};
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
    /// `acc`, which is clamped by `j_max = max_force·dt`.
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Self::Impulse,
        j_max: Real,
        ar: &mut A,
    );
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
) {
    if !r.row.is_active() {
        return;
    }
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut acc = r.acc;
    let mut fast = Unsaturated::new();
    r.row.iterate(&mut a, &mut b, &mut acc, j_max, &mut fast);
    if fast.overflowed() {
        // The inputs are still in `bodies` and `r`: no copies kept.
        solve_saturating(r, bodies, ia, ib, j_max);
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
) {
    let Some((mut a, mut b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut acc = r.acc;
    r.row
        .iterate(&mut a, &mut b, &mut acc, j_max, &mut Saturating);
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
pub(crate) mod tests {
    //! Every kind's kernel: the fast path ([`solve`], [`warm_start`])
    //! against the saturating reference alone, on free inputs (the rows'
    //! fields need not be consistent: the fast path must match on any
    //! input), extremes and rounding ties included.
    use super::*;
    use crate::math::Vect;
    use crate::solver::kernel::tests::{any_real, moderate};
    use proptest::prelude::*;
    use proptest::test_runner::TestCaseError;

    /// The free values a row is built from (`v[i]`, zero past the end).
    pub(crate) fn at(v: &[Real], i: usize) -> Real {
        v.get(i).copied().unwrap_or(Real::ZERO)
    }

    /// The free vector `(v[i], v[i + 1])`.
    pub(crate) fn vect_at(v: &[Real], i: usize) -> Vect {
        Vect::new(at(v, i), at(v, i.saturating_add(1)))
    }

    fn solver_body(v: [Real; 8]) -> SolverBody {
        SolverBody {
            v: Vect::new(v[0], v[1]),
            w: v[2],
            v_bias: Vect::new(v[3], v[4]),
            w_bias: v[5],
            m_inv: v[6].abs(),
            i_inv: v[7].abs(),
        }
    }

    /// [`solve`] and [`warm_start`] on row `k` against its saturating
    /// `iterate` and `apply`: the same bodies and accumulator, bit for bit.
    /// Returns whether both stayed on the fast path (no overflow).
    pub(crate) fn check<K>(
        k: K,
        acc: K::Impulse,
        a: SolverBody,
        b: SolverBody,
        j_max: Real,
    ) -> Result<bool, TestCaseError>
    where
        K: JointKernel + Copy,
        K::Impulse: PartialEq + core::fmt::Debug,
    {
        // The iteration.
        let mut fast = Accumulated { row: k, acc };
        let mut bodies = [a, b];
        solve(&mut fast, &mut bodies, 0, 1, j_max);
        let (mut ra, mut rb, mut racc) = (a, b, acc);
        if k.is_active() {
            k.iterate(&mut ra, &mut rb, &mut racc, j_max, &mut Saturating);
        }
        prop_assert_eq!(bodies, [ra, rb]);
        prop_assert_eq!(fast.acc, racc);

        // The warm start.
        let mut fast = Accumulated::new(k);
        let before = fast.acc;
        let mut bodies = [a, b];
        warm_start(&mut fast, &mut bodies, 0, 1, acc);
        let (mut ra, mut rb) = (a, b);
        if k.is_active() {
            k.apply(&mut ra, &mut rb, acc, &mut Saturating);
            prop_assert_eq!(fast.acc, acc);
        } else {
            prop_assert_eq!(fast.acc, before);
        }
        prop_assert_eq!(bodies, [ra, rb]);

        // Whether the fast path was enough.
        let (mut fa, mut fb, mut facc) = (a, b, acc);
        let mut u = Unsaturated::new();
        if k.is_active() {
            k.iterate(&mut fa, &mut fb, &mut facc, j_max, &mut u);
            k.apply(&mut fa, &mut fb, acc, &mut u);
        }
        Ok(!u.overflowed())
    }

    /// The inputs of one case: the row's free values, two bodies, an
    /// accumulator (as a vector; scalar rows take `x`) and `j_max`.
    pub(crate) type Case = (Vec<Real>, [Real; 8], [Real; 8], Vect, Real);

    pub(crate) fn any_case() -> impl Strategy<Value = Case> {
        (
            proptest::collection::vec(any_real(), 16),
            proptest::array::uniform8(any_real()),
            proptest::array::uniform8(any_real()),
            (any_real(), any_real()).prop_map(|(x, y)| Vect::new(x, y)),
            prop_oneof![any_real().prop_map(Real::abs), Just(Real::MAX)],
        )
    }

    /// Runs [`check`] on every kind's row built from the case's values;
    /// returns whether every kind stayed on the fast path.
    pub(crate) fn check_all_kinds(case: &Case) -> Result<bool, TestCaseError> {
        let (v, av, bv, acc, j_max) = case;
        let (a, b, j_max) = (solver_body(*av), solver_body(*bv), *j_max);
        use crate::constraint::{
            axis::{PinRow, SlideRow},
            damped_rotary_spring::RotarySpringRow,
            damped_spring::SpringRow,
            gear::GearRow,
            groove::GrooveRow,
            pivot::PivotRow,
            rotary_limit::AngularLimitRow,
            simple_motor::MotorRow,
        };
        let fast = [
            check(PinRow::from_raw(v), acc.x, a, b, j_max)?,
            check(PivotRow::from_raw(v), *acc, a, b, j_max)?,
            check(SpringRow::from_raw(v), acc.x, a, b, j_max)?,
            check(MotorRow::from_raw(v), acc.x, a, b, j_max)?,
            check(GearRow::from_raw(v), acc.x, a, b, j_max)?,
            check(SlideRow::from_raw(v), acc.x, a, b, j_max)?,
            check(AngularLimitRow::from_raw(v), acc.x, a, b, j_max)?,
            check(RotarySpringRow::from_raw(v), acc.x, a, b, j_max)?,
            check(GrooveRow::from_raw(v), *acc, a, b, j_max)?,
        ];
        Ok(fast.iter().all(|&f| f))
    }

    #[test]
    fn inactive_rows_are_skipped_and_keep_a_zero_accumulator() {
        use crate::constraint::{axis::SlideRow, rotary_limit::AngularLimitRow};
        // A slide joint inside its limits (n = 0) and a rotary limit inside
        // its range (sign 0), with free values elsewhere.
        let mut v = vec![Real::ONE; 16];
        let body = SolverBody {
            v: Vect::new(Real::ONE, -Real::ONE),
            w: Real::HALF,
            m_inv: Real::ONE,
            i_inv: Real::ONE,
            ..SolverBody::default()
        };
        v[4] = Real::ZERO;
        v[5] = Real::ZERO;
        let slide = SlideRow::from_raw(&v);
        v[0] = Real::ZERO;
        let limit = AngularLimitRow::from_raw(&v);
        assert!(!slide.is_active() && !limit.is_active());
        for acc in [Real::ONE, Real::MIN, Real::MAX] {
            let (mut s, mut l) = (Accumulated::new(slide), Accumulated::new(limit));
            let mut bodies = [body, SolverBody::default()];
            warm_start(&mut s, &mut bodies, 0, 1, acc);
            warm_start(&mut l, &mut bodies, 0, 1, acc);
            solve(&mut s, &mut bodies, 0, 1, Real::MAX);
            solve(&mut l, &mut bodies, 0, 1, Real::MAX);
            assert_eq!(bodies, [body, SolverBody::default()]);
            assert_eq!((s.acc, l.acc), (Real::ZERO, Real::ZERO));
            let case = (
                v.clone(),
                [acc; 8],
                [acc; 8],
                Vect::new(acc, acc),
                Real::MAX,
            );
            assert!(check_all_kinds(&case).is_ok());
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Every joint kernel's fast path is bit-identical to its
        /// saturating reference on any input, extremes and ties included.
        #[test]
        fn fast_joint_kernels_equal_the_saturating_ones(case in any_case()) {
            check_all_kinds(&case)?;
        }

        /// The same on moderate inputs (within ±16, `j_max` finite or
        /// unbounded), where every kernel must stay on the fast path: the
        /// first test alone could pass with a fallback that always runs.
        #[test]
        fn fast_joint_kernels_equal_the_saturating_ones_in_range(
            v in proptest::collection::vec(moderate(), 16),
            av in proptest::array::uniform8(moderate()),
            bv in proptest::array::uniform8(moderate()),
            (ax, ay) in (moderate(), moderate()),
            j_max in prop_oneof![moderate().prop_map(Real::abs), Just(Real::MAX)],
        ) {
            let fast = check_all_kinds(&(v, av, bv, Vect::new(ax, ay), j_max))?;
            prop_assert!(fast, "an in-range case left the fast path");
        }
    }
}
