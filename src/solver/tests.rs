//! Tests of the contact rows, the reference routines and the kernel.
use super::*;
use crate::real;

fn body(m_inv: i32, i_inv: i32) -> SolverBody {
    SolverBody {
        m_inv: Real::from_int(m_inv),
        i_inv: Real::from_int(i_inv),
        ..Default::default()
    }
}

#[test]
fn k_scalar_sums_both_bodies_and_rejects_infinite_pairs() {
    let a = body(1, 1);
    let b = body(2, 0);
    let r = Vect::from_ints(0, 1);
    let n = Vect::X;
    // (r × n)² = 1 for a; b has no rotation.
    assert_eq!(k_scalar(&a, &b, r, r, n), Ok(Real::from_int(4)));
    assert_eq!(
        k_scalar(&body(0, 0), &body(0, 0), r, r, n),
        Err(UnsolvableCollision)
    );
}

#[test]
fn impulses_are_equal_and_opposite() {
    let mut a = body(1, 0);
    let mut b = body(1, 0);
    apply_impulses(
        &mut a,
        &mut b,
        Vect::ZERO,
        Vect::ZERO,
        Vect::from_ints(2, 0),
    );
    assert_eq!(a.v, Vect::from_ints(-2, 0));
    assert_eq!(b.v, Vect::from_ints(2, 0));
    let vr = relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO);
    assert_eq!(vr, Vect::from_ints(4, 0));
    assert_eq!(
        normal_relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO, Vect::X),
        Real::from_int(4)
    );
}

#[test]
fn normal_impulse_stops_approach_without_pulling() {
    // Two unit masses approaching at 2 along the normal: one iteration stops them.
    let mut bodies = [body(1, 0), body(1, 0)];
    bodies[0].v = Vect::from_ints(1, 0);
    bodies[1].v = Vect::from_ints(-1, 0);
    let params = ContactParams {
        dt_inv: Real::from_int(60),
        slop: Real::ZERO,
        bias_coef: Real::ZERO,
        max_bias: Real::MAX,
        switches: SolverSwitches::ALL,
    };
    let pair = PairParams {
        a: 0,
        b: 1,
        n: Vect::X,
        e: Real::ZERO,
        friction: Real::ZERO,
        surface_vr: Vect::ZERO,
    };
    let mut c = ContactConstraint::new(&ManifoldPoint::default(), &bodies, &pair, &params);
    c.solve(&mut bodies);
    assert_eq!(bodies[0].v, Vect::ZERO);
    assert_eq!(bodies[1].v, Vect::ZERO);
    assert_eq!(c.jn_acc, Real::ONE);
    // Separating: no impulse (accumulated impulse cannot go negative).
    bodies[0].v = Vect::from_ints(-1, 0);
    c.jn_acc = Real::ZERO;
    c.solve(&mut bodies);
    assert_eq!(c.jn_acc, Real::ZERO);
    assert_eq!(bodies[0].v, Vect::from_ints(-1, 0));
}

#[test]
fn friction_is_bounded_by_the_normal_impulse() {
    // Body b slides along +x on a static a, pressed down by 1 unit of normal impulse.
    let mut bodies = [body(0, 0), body(1, 0)];
    bodies[1].v = Vect::new(Real::from_int(5), -Real::ONE);
    let params = ContactParams {
        dt_inv: Real::from_int(60),
        slop: Real::ZERO,
        bias_coef: Real::ZERO,
        max_bias: Real::MAX,
        switches: SolverSwitches::ALL,
    };
    let pair = PairParams {
        a: 0,
        b: 1,
        n: Vect::Y,
        e: Real::ZERO,
        friction: Real::HALF,
        surface_vr: Vect::ZERO,
    };
    let mut c = ContactConstraint::new(&ManifoldPoint::default(), &bodies, &pair, &params);
    c.solve(&mut bodies);
    assert_eq!(c.jn_acc, Real::ONE);
    assert_eq!(c.jt_acc.abs(), Real::HALF);
    assert_eq!(bodies[1].v, Vect::new(real!(4.5), Real::ZERO));
}

/// Raw values over the whole range: small (ordinary scenes), large
/// (near saturation) and the extremes.
fn any_real() -> impl proptest::strategy::Strategy<Value = Real> {
    use proptest::prelude::*;
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

fn contact(v: &[Real]) -> ContactConstraint {
    let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
    let mut c = ContactConstraint {
        a: 0,
        b: 1,
        n: Vect::new(r(0), r(1)),
        rn_a: r(2),
        rn_b: r(3),
        rt_a: r(4),
        rt_b: r(5),
        kn_a: r(6),
        kn_b: r(7),
        kt_a: r(8),
        kt_b: r(9),
        m_inv_a: r(10),
        m_inv_b: r(11),
        n_mass: r(12),
        t_mass: r(13),
        bias_target: r(14),
        bounce: r(15),
        friction: r(16).abs(),
        surface_t: r(17),
        jn_acc: r(18).abs(),
        jt_acc: r(19),
        jb_acc: r(20).abs(),
        ..ContactConstraint::default()
    };
    c.check_range();
    c
}

/// Any value below `2^62` raw in magnitude, the largest included: the
/// constants [`Bounded`] arithmetic accepts.
fn bounded_real() -> impl proptest::strategy::Strategy<Value = Real> {
    use proptest::prelude::*;
    prop_oneof![
        any_real().prop_map(|r| Real::from_bits(r.to_bits() % (1 << 62))),
        Just(Real::from_bits((1 << 62) - 1)),
        Just(Real::from_bits(1 - (1 << 62))),
    ]
}

/// `solve_with` (fast path, fallback on overflow) against the
/// saturating reference alone, for one feature combination.
fn check_fast_path<const F: bool, const B: bool>(
    c: ContactConstraint,
    a: SolverBody,
    b: SolverBody,
) -> Result<(), proptest::test_runner::TestCaseError> {
    let mut fast = c;
    let mut bodies = [a, b];
    fast.solve_with::<F, B>(&mut bodies);
    let mut reference = c;
    let mut ref_bodies = [a, b];
    reference.solve_saturating::<F, B>(&mut ref_bodies, (reference.a, reference.b));
    proptest::prop_assert_eq!(bodies, ref_bodies);
    proptest::prop_assert_eq!(
        [fast.jb_acc, fast.jn_acc, fast.jt_acc],
        [reference.jb_acc, reference.jn_acc, reference.jt_acc]
    );
    Ok(())
}

/// The same for the warm start.
fn check_fast_warm_start<const F: bool>(
    c: ContactConstraint,
    a: SolverBody,
    b: SolverBody,
    dt_coef: Real,
) -> Result<(), proptest::test_runner::TestCaseError> {
    let mut c = c;
    c.scale_cached_impulses::<F>(dt_coef);
    let mut bodies = [a, b];
    c.warm_start_with::<F>(&mut bodies, (c.a, c.b));
    let mut ref_bodies = [a, b];
    c.warm_start_saturating::<F>(&mut ref_bodies, (c.a, c.b));
    proptest::prop_assert_eq!(bodies, ref_bodies);
    Ok(())
}

/// A block of two rows from raw values (the matrix entries are free:
/// the fast path must match the reference on any input).
fn manifold_block(v: &[Real]) -> block::ManifoldBlock {
    let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
    block::ManifoldBlock {
        normal: block::NormalBlock {
            k11: r(0),
            k12: r(1),
            k22: r(2),
            inv11: r(3),
            inv12: r(4),
            inv22: r(5),
        },
        t2: Vect::new(r(6), r(7)),
        st_a: r(8),
        st_b: r(9),
        kt_a: r(10),
        kt_b: r(11),
        t_mass: r(12),
        bounded: false, // set by `check_fast_block` from the rows
    }
}

/// `block::solve_with` against the saturating reference alone.
fn check_fast_block<const F: bool, const B: bool>(
    c1: ContactConstraint,
    c2: ContactConstraint,
    blk: &block::ManifoldBlock,
    a: SolverBody,
    b: SolverBody,
) -> Result<(), proptest::test_runner::TestCaseError> {
    let mut blk = *blk;
    blk.check_range(&c1, &c2);
    let blk = &blk;
    let (mut f1, mut f2) = (c1, c2);
    let mut bodies = [a, b];
    block::solve_with::<F, B>(&mut f1, &mut f2, blk, &mut bodies);
    let (mut r1, mut r2) = (c1, c2);
    let mut ref_bodies = [a, b];
    let ends = (r1.a, r1.b);
    block::solve_saturating::<F, B>(&mut r1, &mut r2, blk, &mut ref_bodies, ends);
    proptest::prop_assert_eq!(bodies, ref_bodies);
    proptest::prop_assert_eq!(
        [f1.jb_acc, f1.jn_acc, f1.jt_acc],
        [r1.jb_acc, r1.jn_acc, r1.jt_acc]
    );
    proptest::prop_assert_eq!(
        [f2.jb_acc, f2.jn_acc, f2.jt_acc],
        [r2.jb_acc, r2.jn_acc, r2.jt_acc]
    );
    Ok(())
}

/// A realistic two-contact face: box of half-size `h` on another body,
/// contacts at `±x` along the face, normal `n`, both rows built by the
/// pre-step from the same bodies.
fn face_rows(
    bodies: &[SolverBody; 2],
    n: Vect,
    x: Real,
    h: Real,
    dist: [Real; 2],
) -> (ContactConstraint, ContactConstraint) {
    let t = n.perp();
    let params = ContactParams {
        dt_inv: Real::from_int(60),
        slop: Real::ZERO,
        bias_coef: Real::ratio(1, 10),
        max_bias: Real::MAX,
        switches: SolverSwitches::ALL,
    };
    let pair = PairParams {
        a: 0,
        b: 1,
        n,
        e: Real::ZERO,
        friction: Real::HALF,
        surface_vr: Vect::ZERO,
    };
    let row = |side: Real, d: Real| {
        let r1 = t * (side * x) + n * h;
        let r2 = t * (side * x) - n * h;
        let p = ManifoldPoint {
            r1,
            r2,
            dist: d,
            ..ManifoldPoint::default()
        };
        ContactConstraint::new(&p, bodies, &pair, &params)
    };
    (row(Real::ONE, dist[0]), row(-Real::ONE, dist[1]))
}

#[test]
fn block_is_symmetric_in_its_two_contacts() {
    // Swapping the rows of a block swaps the impulses and leaves the
    // bodies' velocities exactly the same: the order of the contacts
    // in the manifold does not matter (what makes mirrors exact).
    let body = |vx: i32, vy: i32, w: i32| SolverBody {
        v: Vect::new(Real::ratio(vx, 7), Real::ratio(vy, 3)),
        w: Real::ratio(w, 11),
        v_bias: Vect::ZERO,
        w_bias: Real::ZERO,
        m_inv: Real::ONE,
        i_inv: Real::from_int(6),
    };
    for (vx, vy, w) in [(1, -5, 3), (-2, -1, -7), (0, -9, 0), (3, 2, 5)] {
        let bodies = [body(0, 0, 0), body(vx, vy, w)];
        let n = Vect::new(Real::ratio(3, 5), Real::ratio(4, 5));
        let (c1, c2) = face_rows(
            &bodies,
            n,
            Real::HALF,
            Real::HALF,
            [real!(-0.02), real!(-0.01)],
        );
        let blk = block::ManifoldBlock::new(&c1, &c2, &bodies, true)
            .unwrap_or_else(|| panic!("well conditioned"));
        let blk_swapped = block::ManifoldBlock::new(&c2, &c1, &bodies, true)
            .unwrap_or_else(|| panic!("well conditioned"));
        let (mut x1, mut x2, mut bx) = (c1, c2, bodies);
        let (mut y1, mut y2, mut by) = (c1, c2, bodies);
        for _ in 0..10 {
            block::solve_with::<true, true>(&mut x1, &mut x2, &blk, &mut bx);
            block::solve_with::<true, true>(&mut y2, &mut y1, &blk_swapped, &mut by);
        }
        assert_eq!(bx, by);
        assert_eq!((x1.jn_acc, x2.jn_acc), (y1.jn_acc, y2.jn_acc));
        assert_eq!((x1.jb_acc, x2.jb_acc), (y1.jb_acc, y2.jb_acc));
        assert_eq!((x1.jt_acc, x2.jt_acc), (y1.jt_acc, y2.jt_acc));
        // And the answer is a complementarity solution: both pushing
        // contacts end at zero normal velocity error (to rounding).
        let vn = |c: &ContactConstraint| {
            let dv = bx[1].v - bx[0].v;
            dv.dot(c.n) + bx[1].w * c.rn_b - bx[0].w * c.rn_a
        };
        for c in [&x1, &x2] {
            assert!(!c.jn_acc.is_negative());
            if c.jn_acc.is_positive() {
                assert!(vn(c).abs() <= Real::from_bits(64), "{:?}", vn(c));
            } else {
                assert!(!(vn(c) + Real::from_bits(64)).is_negative());
            }
        }
    }
}

#[test]
fn nearly_coincident_contacts_are_not_a_block() {
    // Two contacts at the same lever arm make K singular: the condition
    // guard refuses the block and the rows are solved sequentially.
    let b = SolverBody {
        m_inv: Real::ONE,
        i_inv: Real::from_int(6),
        ..SolverBody::default()
    };
    let bodies = [SolverBody::default(), b];
    let (c1, c2) = face_rows(
        &bodies,
        Vect::Y,
        Real::from_bits(3),
        Real::HALF,
        [Real::ZERO; 2],
    );
    assert!(block::ManifoldBlock::new(&c1, &c2, &bodies, true).is_none());
    let (c1, c2) = face_rows(&bodies, Vect::Y, Real::HALF, Real::HALF, [Real::ZERO; 2]);
    assert!(block::ManifoldBlock::new(&c1, &c2, &bodies, true).is_some());
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
    /// The block kernel's fast path is bit-identical to its saturating
    /// reference on any input, extremes and ties included.
    #[test]
    fn fast_block_iteration_equals_the_saturating_one(
        c1v in proptest::collection::vec(any_real(), 21),
        c2v in proptest::collection::vec(any_real(), 21),
        kv in proptest::collection::vec(any_real(), 13),
        av in proptest::array::uniform8(any_real()),
        bv in proptest::array::uniform8(any_real()),
    ) {
        let (c1, mut c2) = (contact(&c1v), contact(&c2v));
        c2.n = c1.n;
        c2.check_range();
        let blk = manifold_block(&kv);
        let (a, b) = (solver_body(av), solver_body(bv));
        check_fast_block::<true, true>(c1, c2, &blk, a, b)?;
        check_fast_block::<true, false>(c1, c2, &blk, a, b)?;
        check_fast_block::<false, true>(c1, c2, &blk, a, b)?;
        check_fast_block::<false, false>(c1, c2, &blk, a, b)?;
    }

    /// The same on blocks the pre-step builds from bounded, realistic
    /// inputs (where the fast path is taken, not only the fallback).
    #[test]
    fn fast_block_equals_the_saturating_one_on_built_blocks(
        vx in -1000i32..1000, vy in -1000i32..1000, w in -1000i32..1000,
        nx in -100i32..100, x in 1i32..100, h in 1i32..100,
        d1 in -100i32..10, d2 in -100i32..10, jn in 0i32..1000,
    ) {
        let len = Vect::new(Real::from_int(nx), Real::from_int(100)).length();
        let n = Vect::new(Real::from_int(nx) / len, Real::from_int(100) / len);
        let body = SolverBody {
            v: Vect::new(Real::ratio(vx, 100), Real::ratio(vy, 100)),
            w: Real::ratio(w, 100),
            m_inv: Real::ONE,
            i_inv: Real::from_int(6),
            ..SolverBody::default()
        };
        let bodies = [SolverBody { m_inv: Real::HALF, i_inv: Real::from_int(3), ..SolverBody::default() }, body];
        let (mut c1, mut c2) = face_rows(
            &bodies, n, Real::ratio(x, 100), Real::ratio(h, 100),
            [Real::ratio(d1, 1000), Real::ratio(d2, 1000)],
        );
        c1.jn_acc = Real::ratio(jn, 1000);
        c2.jn_acc = Real::ratio(jn, 700);
        // Realistic rows take the `Bounded` fast path: the range check
        // is not so strict that the fast path is never used.
        proptest::prop_assert!(c1.is_bounded() && c2.is_bounded());
        if let Some(blk) = block::ManifoldBlock::new(&c1, &c2, &bodies, true) {
            proptest::prop_assert!(blk.bounded);
            check_fast_block::<true, true>(c1, c2, &blk, bodies[0], bodies[1])?;
            check_fast_block::<false, false>(c1, c2, &blk, bodies[0], bodies[1])?;
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
    /// The unsaturated fast path is bit-identical to the saturating
    /// iteration on any input, extremes included.
    #[test]
    fn fast_iteration_equals_the_saturating_one(
        cv in proptest::collection::vec(any_real(), 21),
        av in proptest::array::uniform8(any_real()),
        bv in proptest::array::uniform8(any_real()),
        dt_coef in any_real(),
    ) {
        let (c, a, b) = (contact(&cv), solver_body(av), solver_body(bv));
        check_fast_warm_start::<true>(c, a, b, dt_coef)?;
        check_fast_warm_start::<false>(c, a, b, dt_coef)?;
        check_fast_path::<true, true>(c, a, b)?;
        check_fast_path::<true, false>(c, a, b)?;
        check_fast_path::<false, true>(c, a, b)?;
        check_fast_path::<false, false>(c, a, b)?;
    }

    /// The same with every constant of the dot products accepted by
    /// `below_2_62` (up to its edge) and free velocities and impulses:
    /// the `Bounded` kernel runs, and matches the reference on any
    /// input. A missing overflow case in its unflagged sums or
    /// negations fails here.
    #[test]
    fn bounded_iteration_equals_the_saturating_one(
        kv in proptest::collection::vec(bounded_real(), 10),
        cv in proptest::collection::vec(any_real(), 21),
        bk in proptest::collection::vec(bounded_real(), 6),
        av in proptest::array::uniform8(any_real()),
        bv in proptest::array::uniform8(any_real()),
    ) {
        let mut v = cv.clone();
        v[..10].copy_from_slice(&kv);
        let c1 = contact(&v);
        proptest::prop_assert!(c1.bounded);
        let mut c2 = contact(&cv);
        c2.n = c1.n;
        c2.rn_a = kv[3];
        c2.rn_b = kv[2];
        c2.kn_a = kv[7];
        c2.kn_b = kv[6];
        c2.check_range();
        let (a, b) = (solver_body(av), solver_body(bv));
        check_fast_path::<true, true>(c1, a, b)?;
        check_fast_path::<false, false>(c1, a, b)?;
        let mut k = cv[..13].to_vec();
        k[6..12].copy_from_slice(&bk);
        let blk = manifold_block(&k);
        check_fast_block::<true, true>(c1, c2, &blk, a, b)?;
        check_fast_block::<true, false>(c1, c2, &blk, a, b)?;
        check_fast_block::<false, true>(c1, c2, &blk, a, b)?;
    }
}
