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
    // The iteration, rigid (the sequential solver) and soft (the soft
    // step's coefficients at its defaults).
    let soft = Softness::new(
        Real::from_int(60),
        Real::from_int(2),
        Real::ONE / Real::from_int(240),
    );
    for soft in [Softness::RIGID, soft] {
        let mut fast = Accumulated { row: k, acc };
        let mut bodies = [a, b];
        solve(&mut fast, &mut bodies, 0, 1, j_max, soft);
        let (mut ra, mut rb, mut racc) = (a, b, acc);
        if k.is_active() {
            k.iterate(&mut ra, &mut rb, &mut racc, j_max, soft, &mut Saturating);
        }
        prop_assert_eq!(bodies, [ra, rb]);
        prop_assert_eq!(fast.acc, racc);
    }

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
        k.iterate(&mut fa, &mut fb, &mut facc, j_max, Softness::RIGID, &mut u);
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
        solve(&mut s, &mut bodies, 0, 1, Real::MAX, Softness::RIGID);
        solve(&mut l, &mut bodies, 0, 1, Real::MAX, Softness::RIGID);
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
