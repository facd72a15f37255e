//! The pre-step's fast path against the saturating pre-step it
//! replaced, kept here verbatim as the oracle: bit for bit on free
//! inputs (the fields need not be consistent), extremes and rounding
//! ties included, and on the fast path (no fallback) in range.
use super::kernel::tests::{any_real, moderate};
use super::*;
use proptest::prelude::*;

/// `ContactConstraint::new` as it was (saturating `Real` and `Vect`
/// operators, `Real::recip`).
fn new_reference(
    c: &ManifoldPoint,
    bodies: &[SolverBody],
    pair: &PairParams,
    params: &ContactParams,
) -> ContactConstraint {
    let zero = SolverBody::default();
    let a = bodies.get(pair.a as usize).unwrap_or(&zero);
    let b = bodies.get(pair.b as usize).unwrap_or(&zero);
    let f = params.switches;
    let n = pair.n;
    let (rn_a, rn_b) = (c.r1.cross(n), c.r2.cross(n));
    let n_mass = k_scalar(a, b, c.r1, c.r2, n).map_or(Real::ZERO, Real::recip);
    let mut sc = ContactConstraint {
        a: pair.a,
        b: pair.b,
        n,
        rn_a,
        rn_b,
        kn_a: a.i_inv * rn_a,
        kn_b: b.i_inv * rn_b,
        m_inv_a: a.m_inv,
        m_inv_b: b.m_inv,
        n_mass,
        ..ContactConstraint::default()
    };
    if f.friction {
        let t = n.perp();
        let (rt_a, rt_b) = (c.r1.cross(t), c.r2.cross(t));
        sc.rt_a = rt_a;
        sc.rt_b = rt_b;
        sc.kt_a = a.i_inv * rt_a;
        sc.kt_b = b.i_inv * rt_b;
        sc.t_mass = k_scalar(a, b, c.r1, c.r2, t).map_or(Real::ZERO, Real::recip);
        sc.friction = pair.friction;
        sc.surface_t = pair.surface_vr.dot(t);
    }
    if f.bias_impulses {
        let overlap = (c.dist + params.slop).min(Real::ZERO);
        sc.bias_target = (-params.bias_coef * overlap * params.dt_inv).min(params.max_bias);
    }
    if f.restitution {
        sc.bounce = normal_relative_velocity(a, b, c.r1, c.r2, n) * pair.e;
    }
    if f.warm_starting {
        sc.jn_acc = c.jn_acc;
        if f.friction {
            sc.jt_acc = c.jt_acc;
        }
    }
    // The range flag (newer than this oracle) is a function of the fields.
    sc.check_range();
    sc
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

/// One pre-step case from free values: the manifold point, the pair,
/// the step's parameters (`v` has 19 values), the feature switches.
fn case(v: &[Real], f: [bool; 4]) -> (ManifoldPoint, PairParams, ContactParams) {
    let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
    let point = ManifoldPoint {
        r1: Vect::new(r(0), r(1)),
        r2: Vect::new(r(2), r(3)),
        dist: r(4),
        feature_id: 0,
        jn_acc: r(5),
        jt_acc: r(6),
    };
    let pair = PairParams {
        a: 0,
        b: 1,
        n: Vect::new(r(7), r(8)),
        e: r(9),
        friction: r(10),
        surface_vr: Vect::new(r(11), r(12)),
    };
    let params = ContactParams {
        dt_inv: r(13),
        slop: r(14),
        bias_coef: r(15),
        max_bias: r(16),
        switches: SolverSwitches {
            warm_starting: f[0],
            friction: f[1],
            restitution: f[2],
            bias_impulses: f[3],
        },
    };
    (point, pair, params)
}

/// `new` and `prepare` against the reference; returns whether the
/// arithmetic stayed on the fast path.
fn check(v: &[Real], f: [bool; 4], av: [Real; 8], bv: [Real; 8]) -> Result<bool, TestCaseError> {
    let (point, pair, params) = case(v, f);
    let bodies = [solver_body(av), solver_body(bv)];
    let want = new_reference(&point, &bodies, &pair, &params);
    prop_assert_eq!(
        ContactConstraint::new(&point, &bodies, &pair, &params),
        want
    );
    // `prepare` is `new` with the tangent mass left to the caller.
    let (mut row, k_t) = ContactConstraint::prepare(&point, &bodies, &pair, &params);
    prop_assert_eq!(row.t_mass, Real::ZERO);
    row.t_mass = effective_mass(k_t);
    prop_assert_eq!(row, want);
    let mut u = Unsaturated::new();
    let _ = pre_step_terms(&point, &bodies[0], &bodies[1], &pair, &params, &mut u);
    Ok(!u.overflowed())
}

#[test]
fn effective_mass_is_the_rounded_reciprocal() {
    let edges = [
        i64::MIN,
        -1,
        0,
        1,
        2,
        3,
        4,
        5,
        7,
        1 << 31,
        (1 << 32) - 1,
        1 << 32,
        (1 << 32) + 1,
        3 << 31,
        i64::MAX - 1,
        i64::MAX,
    ];
    for bits in edges {
        let k = Real::from_bits(bits);
        let want = if k.is_positive() {
            k.recip()
        } else {
            Real::ZERO
        };
        assert_eq!(effective_mass(k), want, "{bits}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    #[test]
    fn effective_mass_equals_recip(k in any_real()) {
        let want = if k.is_positive() { k.recip() } else { Real::ZERO };
        prop_assert_eq!(effective_mass(k), want);
    }

    /// The fast pre-step is bit-identical to the saturating one on any
    /// input, extremes and ties included, every feature combination.
    #[test]
    fn fast_pre_step_equals_the_saturating_one(
        v in proptest::collection::vec(any_real(), 17),
        f in proptest::array::uniform4(any::<bool>()),
        av in proptest::array::uniform8(any_real()),
        bv in proptest::array::uniform8(any_real()),
    ) {
        check(&v, f, av, bv)?;
    }

    /// The same on moderate inputs (within ±16), where the pre-step
    /// must stay on the fast path: the first test alone could pass
    /// with a fallback that always runs.
    #[test]
    fn fast_pre_step_stays_fast_in_range(
        v in proptest::collection::vec(moderate(), 17),
        f in proptest::array::uniform4(any::<bool>()),
        av in proptest::array::uniform8(moderate()),
        bv in proptest::array::uniform8(moderate()),
    ) {
        prop_assert!(check(&v, f, av, bv)?, "an in-range case left the fast path");
    }
}
