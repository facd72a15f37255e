#![allow(clippy::float_arithmetic)]
//! Property tests and error sweeps of `tamias2d::math::trig` against an `f64`
//! oracle evaluated at the exact input values.
//!
//! Measured maxima (quoted in the module docs of `src/math/trig.rs`):
//! `cargo test --release --test geometry -- --nocapture math_trig::max_error`.
//! Timing: `cargo test --release --test geometry -- --ignored --nocapture math_trig::timing`.

use proptest::prelude::*;
use tamias2d::math::trig::{atan2, cos, sin, sin_cos};
use tamias2d::Real;

/// One ulp of `Real` (2^-32).
const ULP: f64 = 1.0 / 4_294_967_296.0;
/// Bound on the `sin`/`cos` error (ulp); the contract target is 2 ulp.
const SIN_COS_BOUND: f64 = 0.501;
/// Bound on the `atan2` error (ulp) against the oracle clamped to
/// `[-Real::PI, Real::PI]`; the contract target is 4 ulp.
const ATAN2_BOUND: f64 = 0.501;
/// Bound on the `atan2` error against the unclamped oracle: `Real::PI` is π
/// truncated, 0.522 ulp below π.
const ATAN2_BOUND_UNCLAMPED: f64 = 0.53;
/// π/2 in Q94, only used to generate inputs close to multiples of π/2.
const FRAC_PI_2_Q94: i128 = 31_112_826_664_028_885_653_815_243_078;
/// The largest k with k·π/2 ≤ 2^31.
const K_MAX: i64 = 1_367_130_551;

/// `(sin, cos)` of the exact value `bits · 2^-32`. Values with more than 53
/// significant bits are split into two exactly representable parts and
/// recombined with the addition formulas (libm reduces huge arguments
/// correctly, so `sin(hi)` is accurate for every `hi`).
fn oracle_sin_cos(bits: i64) -> (f64, f64) {
    let lo = bits & 0x7ff;
    let hi = (bits - lo) as f64 * ULP;
    let lo = lo as f64 * ULP;
    let (sh, ch) = hi.sin_cos();
    let (sl, cl) = lo.sin_cos();
    (sh * cl + ch * sl, ch * cl - sh * sl)
}

/// `atan2` of the values (relative input error ≤ 2^-53: ≤ 2^-21 ulp of angle).
fn oracle_atan2(y: Real, x: Real) -> f64 {
    y.to_f64().atan2(x.to_f64())
}

fn err_ulp(got: Real, want: f64) -> f64 {
    (got.to_f64() - want).abs() / ULP
}

/// `sin² + cos² − 1` exactly, in ulp.
fn norm_err_ulp(s: Real, c: Real) -> f64 {
    let (s, c) = (i128::from(s.to_bits()), i128::from(c.to_bits()));
    (s * s + c * c - (1i128 << 64)) as f64 / 4_294_967_296.0 / 4_294_967_296.0 / ULP
}

/// The `Real` bits nearest to `k·π/2` (for hard reduction cases).
fn near_multiple_of_frac_pi_2(k: i64) -> i64 {
    ((i128::from(k) * FRAC_PI_2_Q94 + (1 << 61)) >> 62) as i64
}

/// Errors of `atan2(y, x)`: against the oracle clamped to ±`Real::PI` and
/// against the raw oracle.
fn atan2_errs(y: Real, x: Real) -> (f64, f64) {
    let got = atan2(y, x);
    let want = oracle_atan2(y, x);
    let pi = Real::PI.to_f64();
    (err_ulp(got, want.clamp(-pi, pi)), err_ulp(got, want))
}

/// `a − b` wrapped into (−π, π], in ulp.
fn angle_diff_ulp(a: Real, b: Real) -> f64 {
    let tau = std::f64::consts::TAU;
    let mut d = a.to_f64() - b.to_f64();
    if d > std::f64::consts::PI {
        d -= tau;
    } else if d <= -std::f64::consts::PI {
        d += tau;
    }
    d.abs() / ULP
}

fn check_sin_cos(bits: i64) -> Result<(), TestCaseError> {
    let a = Real::from_bits(bits);
    let (s, c) = sin_cos(a);
    let (ws, wc) = oracle_sin_cos(bits);
    prop_assert!(
        err_ulp(s, ws) <= SIN_COS_BOUND,
        "sin({a:?}) = {s:?}, want {ws}"
    );
    prop_assert!(
        err_ulp(c, wc) <= SIN_COS_BOUND,
        "cos({a:?}) = {c:?}, want {wc}"
    );
    prop_assert!(norm_err_ulp(s, c).abs() <= 2.0, "sin²+cos² of {a:?}");
    prop_assert_eq!(sin(a), s);
    prop_assert_eq!(cos(a), c);
    if bits != i64::MIN {
        let (sn, cn) = sin_cos(-a);
        prop_assert_eq!(sn, -s);
        prop_assert_eq!(cn, c);
    }
    Ok(())
}

fn check_atan2(y: Real, x: Real) -> Result<(), TestCaseError> {
    let got = atan2(y, x);
    prop_assert!(
        got >= -Real::PI && got <= Real::PI,
        "atan2({y:?}, {x:?}) = {got:?}"
    );
    let (e, e_raw) = atan2_errs(y, x);
    let want = oracle_atan2(y, x);
    prop_assert!(
        e <= ATAN2_BOUND,
        "atan2({y:?}, {x:?}) = {got:?}, want {want}"
    );
    prop_assert!(e_raw <= ATAN2_BOUND_UNCLAMPED, "atan2({y:?}, {x:?})");
    // Odd in y (y = 0 is excluded: atan2(0, x < 0) = π, our zero has no sign).
    if y.to_bits() != i64::MIN && y != Real::ZERO {
        prop_assert_eq!(atan2(-y, x), -got);
    }
    Ok(())
}

/// Any `Real` whose magnitude is spread over all scales (not only ~2^31).
fn any_scale() -> impl Strategy<Value = Real> {
    (any::<i64>(), 0u32..64).prop_map(|(b, s)| Real::from_bits(b >> s))
}

/// Edge values.
fn special() -> impl Strategy<Value = Real> {
    prop::sample::select(vec![
        Real::ZERO,
        Real::DELTA,
        -Real::DELTA,
        Real::ONE,
        -Real::ONE,
        Real::MAX,
        Real::MIN,
        Real::from_bits(i64::MIN + 1),
        Real::from_bits(2),
        Real::from_bits(1 << 40),
    ])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    #[test]
    fn sin_cos_any_bits(bits in any::<i64>()) {
        check_sin_cos(bits)?;
    }

    #[test]
    fn sin_cos_small_angles(bits in -(40i64 << 32)..(40i64 << 32)) {
        check_sin_cos(bits)?;
    }

    #[test]
    fn sin_cos_any_scale(a in any_scale()) {
        check_sin_cos(a.to_bits())?;
    }

    #[test]
    fn sin_cos_near_multiples_of_frac_pi_2(k in -K_MAX..=K_MAX, off in -1000i64..=1000) {
        let b = near_multiple_of_frac_pi_2(k).saturating_add(off);
        check_sin_cos(b)?;
    }

    #[test]
    fn atan2_any_bits(y in any::<i64>(), x in any::<i64>()) {
        check_atan2(Real::from_bits(y), Real::from_bits(x))?;
    }

    #[test]
    fn atan2_mixed_magnitudes(y in any_scale(), x in any_scale()) {
        check_atan2(y, x)?;
    }

    #[test]
    fn atan2_with_special_values(y in special(), x in any_scale(), swap in any::<bool>()) {
        let (y, x) = if swap { (x, y) } else { (y, x) };
        check_atan2(y, x)?;
    }

    #[test]
    fn atan2_of_special_pairs(y in special(), x in special()) {
        check_atan2(y, x)?;
    }

    #[test]
    fn atan2_inverts_sin_cos(bits in -Real::PI.to_bits()..=Real::PI.to_bits()) {
        let a = Real::from_bits(bits);
        let (s, c) = sin_cos(a);
        let back = atan2(s, c);
        prop_assert!(angle_diff_ulp(back, a) <= 2.0, "atan2(sin, cos)({a:?}) = {back:?}");
    }

    #[test]
    fn atan2_is_scale_invariant_on_exact_scalings(
        y in -(1i64 << 40)..(1i64 << 40),
        x in -(1i64 << 40)..(1i64 << 40),
        k in 0u32..23,
    ) {
        // Multiplying both components by 2^k is exact here; the angle is the same.
        let a = atan2(Real::from_bits(y), Real::from_bits(x));
        let b = atan2(Real::from_bits(y << k), Real::from_bits(x << k));
        prop_assert_eq!(a, b);
    }
}

/// Deterministic pseudo-random numbers for the sweeps.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn next_i64(&mut self) -> i64 {
        self.next() as i64
    }
}

#[derive(Default)]
struct Max {
    err: f64,
    at: String,
}

impl Max {
    fn see(&mut self, err: f64, at: impl FnOnce() -> String) {
        if err > self.err {
            self.err = err;
            self.at = at();
        }
    }
}

/// Dense sweeps plus random inputs over the whole range; prints the maximum
/// errors quoted in the module docs of `trig.rs`.
#[test]
fn max_error() {
    // Fewer points in debug builds; the documented numbers use --release.
    // TRIG_SWEEP_N overrides the count.
    let default_n: i64 = if cfg!(debug_assertions) {
        50_000
    } else {
        2_000_000
    };
    let n = std::env::var("TRIG_SWEEP_N")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_n)
        .max(64);
    let mut rng = SplitMix64(0x7a31_a52d);
    let (mut e_sin, mut e_cos, mut e_norm) = (Max::default(), Max::default(), Max::default());
    let mut sc = |bits: i64| {
        let a = Real::from_bits(bits);
        let (s, c) = sin_cos(a);
        let (ws, wc) = oracle_sin_cos(bits);
        e_sin.see(err_ulp(s, ws), || format!("{a:?} (bits {bits})"));
        e_cos.see(err_ulp(c, wc), || format!("{a:?} (bits {bits})"));
        e_norm.see(norm_err_ulp(s, c).abs(), || format!("{a:?} (bits {bits})"));
    };
    // Dense over [-2π, 2π] (odd stride: all low-bit patterns occur).
    let span = 2 * Real::TAU.to_bits();
    let stride = (span / n) | 1;
    let mut b = -Real::TAU.to_bits();
    while b <= Real::TAU.to_bits() {
        sc(b);
        b += stride;
    }
    for _ in 0..n {
        // Whole i64 range, and every magnitude.
        sc(rng.next_i64());
        let s = (rng.next() % 64) as u32;
        sc(rng.next_i64() >> s);
    }
    for _ in 0..n / 4 {
        // Near multiples of π/2 up to 2^31 rad (hardest for range reduction).
        let k = (rng.next() % K_MAX as u64) as i64;
        let off = (rng.next() % 201) as i64 - 100;
        sc(near_multiple_of_frac_pi_2(k) + off);
        sc(-near_multiple_of_frac_pi_2(k) + off);
    }

    let (mut e_atan, mut e_atan_raw, mut e_back) = (Max::default(), Max::default(), Max::default());
    let mut at2 = |y: Real, x: Real| {
        let (e, e_raw) = atan2_errs(y, x);
        e_atan.see(e, || format!("atan2({y:?}, {x:?})"));
        e_atan_raw.see(e_raw, || format!("atan2({y:?}, {x:?})"));
    };
    // Dense around circles of radius 2^-31 .. 2^30.
    let per_circle = n / 64;
    for e in -31..=30 {
        let radius = 2f64.powi(e);
        for i in 0..per_circle {
            let th =
                (i as f64 + 0.5) / per_circle as f64 * std::f64::consts::TAU - std::f64::consts::PI;
            let y = Real::from_f64(radius * th.sin()).unwrap();
            let x = Real::from_f64(radius * th.cos()).unwrap();
            at2(y, x);
        }
    }
    for _ in 0..n {
        at2(
            Real::from_bits(rng.next_i64()),
            Real::from_bits(rng.next_i64()),
        );
        let (sy, sx) = ((rng.next() % 64) as u32, (rng.next() % 64) as u32);
        at2(
            Real::from_bits(rng.next_i64() >> sy),
            Real::from_bits(rng.next_i64() >> sx),
        );
    }
    let edges = [
        0,
        1,
        -1,
        2,
        -2,
        1 << 32,
        -(1 << 32),
        i64::MAX,
        i64::MIN,
        i64::MIN + 1,
        i64::MAX - 1,
    ];
    for &y in &edges {
        for &x in &edges {
            at2(Real::from_bits(y), Real::from_bits(x));
        }
    }
    // Round trip atan2(sin a, cos a) = a on [-π, π].
    let stride = (2 * Real::PI.to_bits() / n) | 1;
    let mut b = -Real::PI.to_bits();
    while b <= Real::PI.to_bits() {
        let a = Real::from_bits(b);
        let (s, c) = sin_cos(a);
        e_back.see(angle_diff_ulp(atan2(s, c), a), || format!("{a:?}"));
        b += stride;
    }

    println!("max error over the sweep (ulp = 2^-32), {n} points per category:");
    println!("  sin          {:.9} at {}", e_sin.err, e_sin.at);
    println!("  cos          {:.9} at {}", e_cos.err, e_cos.at);
    println!("  sin²+cos²−1  {:.9} at {}", e_norm.err, e_norm.at);
    println!(
        "  atan2        {:.9} at {} (vs oracle clamped to ±Real::PI)",
        e_atan.err, e_atan.at
    );
    println!(
        "  atan2 raw    {:.9} at {} (vs unclamped oracle)",
        e_atan_raw.err, e_atan_raw.at
    );
    println!(
        "  atan2∘sin_cos round trip {:.9} at {}",
        e_back.err, e_back.at
    );

    assert!(e_sin.err <= SIN_COS_BOUND && e_cos.err <= SIN_COS_BOUND);
    assert!(e_norm.err <= 2.0);
    assert!(e_atan.err <= ATAN2_BOUND && e_atan_raw.err <= ATAN2_BOUND_UNCLAMPED);
    assert!(e_back.err <= 2.0);
}

/// Rough cost per call (release build recommended).
#[test]
#[ignore]
fn timing() {
    use std::hint::black_box;
    use std::time::Instant;
    let mut rng = SplitMix64(42);
    let small: Vec<Real> = (0..1024)
        .map(|_| Real::from_bits(rng.next_i64() >> 28))
        .collect();
    let huge: Vec<Real> = (0..1024).map(|_| Real::from_bits(rng.next_i64())).collect();
    let pairs: Vec<(Real, Real)> = (0..1024)
        .map(|_| {
            (
                Real::from_bits(rng.next_i64() >> 20),
                Real::from_bits(rng.next_i64() >> 20),
            )
        })
        .collect();
    let rounds = 10_000;
    let calls = (rounds * 1024) as f64;

    for (name, inputs) in [
        ("sin_cos (|a| < 2^3)", &small),
        ("sin_cos (any bits)", &huge),
    ] {
        let t = Instant::now();
        let mut acc = 0i64;
        for _ in 0..rounds {
            for &a in inputs.iter() {
                let (s, c) = sin_cos(black_box(a));
                acc = acc.wrapping_add(s.to_bits() ^ c.to_bits());
            }
        }
        black_box(acc);
        println!(
            "{name}: {:.1} ns/call",
            t.elapsed().as_nanos() as f64 / calls
        );
    }
    let t = Instant::now();
    let mut acc = 0i64;
    for _ in 0..rounds {
        for &(y, x) in pairs.iter() {
            acc = acc.wrapping_add(atan2(black_box(y), black_box(x)).to_bits());
        }
    }
    black_box(acc);
    println!(
        "atan2: {:.1} ns/call",
        t.elapsed().as_nanos() as f64 / calls
    );
}
