//! Numbers for renderers. Symptom: only `Real` had
//! `to_f32`/`to_f64`, so a renderer converted `Vect`, `Rot` and `Transform`
//! component by component, and `Real::from_f64` did not say what is
//! deterministic about it. Fix: `to_f32` on `Vect` (`(x, y)`, like its
//! `to_f64`), `to_f32`/`to_f64` on `Rot` (`(cos, sin)`) and `Transform` (`[a, b, c, d, tx, ty]`, the order of
//! a canvas `setTransform`), output only; `from_f64` documented (same f64
//! bits → same `Real` everywhere, round to nearest, ties to even).
use tamias2d::math::{Real, Rot, Transform, Vect};
use tamias2d::real;

#[test]
fn vect_rot_and_transform_convert_componentwise() {
    let v = Vect::new(real!(1.5), real!(-2.25));
    assert_eq!(v.to_f32(), (1.5f32, -2.25));
    assert_eq!(v.to_f64(), (1.5f64, -2.25));

    assert_eq!(Rot::IDENTITY.to_f64(), (1.0, 0.0));
    let r = Rot::from_angle(real!(0.5));
    assert_eq!(r.to_f64(), (r.c.to_f64(), r.s.to_f64()));
    assert_eq!(r.to_f32(), (r.c.to_f32(), r.s.to_f32()));
    let (c, s) = r.to_f64();
    assert!((c - 0.5f64.cos()).abs() < 1e-9 && (s - 0.5f64.sin()).abs() < 1e-9);

    let t = Transform {
        a: real!(0.5),
        b: real!(0.25),
        c: real!(-0.25),
        d: real!(0.5),
        tx: real!(10),
        ty: real!(-3.75),
    };
    assert_eq!(t.to_f64(), [0.5, 0.25, -0.25, 0.5, 10.0, -3.75]);
    assert_eq!(t.to_f32(), [0.5f32, 0.25, -0.25, 0.5, 10.0, -3.75]);
    // The order is that of `x' = a·x + c·y + tx, y' = b·x + d·y + ty`.
    let p = Vect::new(real!(2), real!(4));
    let [a, b, c, d, tx, ty] = t.to_f64();
    let (x, y) = p.to_f64();
    assert_eq!(
        t.point(p).to_f64(),
        (a * x + c * y + tx, b * x + d * y + ty)
    );
}

#[test]
fn to_f64_is_exact_below_2_pow_21_and_nearest_above() {
    assert_eq!(Real::from_bits(1).to_f64(), 2f64.powi(-32));
    assert_eq!(Real::from_bits(-1).to_f64(), -(2f64.powi(-32)));
    assert_eq!(Real::MIN.to_f64(), -(2f64.powi(31)));
    // 2^31 − 2^-32 has 63 significant bits: rounds to 2^31.
    assert_eq!(Real::MAX.to_f64(), 2f64.powi(31));
    // Round trip through f64 is exact for |v| < 2^21 (53 bits).
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    for _ in 0..10_000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let bits = (x as i64) >> 11; // |bits| < 2^52: |v| < 2^20
        let r = Real::from_bits(bits);
        assert_eq!(Real::from_f64(r.to_f64()), Ok(r));
    }
}

#[test]
fn from_f64_rounds_to_nearest_ties_to_even_from_the_bits() {
    // Same f64 bits → same Real: 0.1 is 0x3FB999999999999A, which is
    // 429496729.6000000015 ulp: rounds to 429496730.
    assert_eq!(Real::from_f64(0.1).map(Real::to_bits), Ok(429_496_730));
    assert_eq!(
        Real::from_f64(f64::from_bits(0x3FB9_9999_9999_999A)),
        Real::from_f64(0.1)
    );
    // Half an ulp ties to even.
    assert_eq!(Real::from_f64(2f64.powi(-33)), Ok(Real::ZERO));
    assert_eq!(Real::from_f64(3.0 * 2f64.powi(-33)), Ok(Real::from_bits(2)));
    assert_eq!(Real::from_f64(5.0 * 2f64.powi(-33)), Ok(Real::from_bits(2)));
    assert!(Real::from_f64(f64::NAN).is_err());
    assert!(Real::from_f64(2f64.powi(31)).is_err());
}
