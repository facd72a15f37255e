//! Regression: `docs/numerics.md` promised `ShapeError::OutOfRange` for
//! shapes spanning 2^31 m or more, but only polygon *vertices* were
//! checked: a circle of radius 2^30 + 1 m, a segment from `Real::MIN` to
//! `Real::MAX` and a rounding radius of `Real::MAX` were accepted. Cause:
//! the check lived in the polygon constructors and ignored the rounding
//! radius. Fix: one rule for every shape kind, checked by every constructor
//! and setter and by snapshot validation — the shape's local bounding box,
//! rounding radius included, lies in the `Real` range and spans less than
//! 2^31 m on each axis (so the difference of any two of its points, and the
//! sum of two shapes' radii, fit a `Real`).
use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Transform, Vect, BB};
use tamias2d::shape::{Shape, ShapeError};
use tamias2d::snapshot::{self, SnapshotError};
use tamias2d::space::Space;

const EXTENT: ShapeError = ShapeError::OutOfRange("shape extent");

fn h() -> BodyHandle {
    BodyHandle::from_raw_parts(0, 0)
}

/// 2^30 m, the largest radius whose diameter is not below 2^31 m.
fn half_range() -> Real {
    Real::from_bits(1 << 62)
}

#[test]
fn circle_radius_boundary() {
    let inside = half_range() - Real::DELTA;
    assert!(Shape::circle_shape_new(h(), inside, Vect::ZERO).is_ok());
    assert_eq!(
        Shape::circle_shape_new(h(), half_range(), Vect::ZERO).unwrap_err(),
        EXTENT
    );
    assert_eq!(
        Shape::circle_shape_new(h(), half_range() + Real::ONE, Vect::ZERO).unwrap_err(),
        EXTENT
    );
    // A small circle whose box leaves the range in body coordinates.
    assert!(
        Shape::circle_shape_new(h(), Real::ONE, Vect::new(Real::MAX - Real::ONE, Real::ZERO))
            .is_ok()
    );
    assert_eq!(
        Shape::circle_shape_new(
            h(),
            Real::ONE,
            Vect::new(Real::MAX - Real::HALF, Real::ZERO)
        )
        .unwrap_err(),
        EXTENT
    );
    // Setters keep the rule and leave the shape unchanged on error.
    let mut c = Shape::circle_shape_new(h(), Real::ONE, Vect::ZERO).unwrap();
    assert_eq!(c.set_circle_radius(half_range()), Err(EXTENT));
    assert_eq!(
        c.set_circle_offset(Vect::new(Real::MIN, Real::ZERO)),
        Err(EXTENT)
    );
    assert_eq!(c.circle_radius(), Ok(Real::ONE));
    assert_eq!(c.circle_offset(), Ok(Vect::ZERO));
}

#[test]
fn segment_boundary() {
    // 2^31 − 2 ulp long (the envelope test's longest ground): accepted.
    let inside = half_range() - Real::DELTA;
    let ok = Shape::segment_shape_new(
        h(),
        Vect::new(-inside, Real::ZERO),
        Vect::new(inside, Real::ZERO),
        Real::ZERO,
    );
    assert!(ok.is_ok());
    // One ulp longer on one side: 2^31 − 1 ulp, still below 2^31: accepted.
    let a = Vect::new(-half_range(), Real::ZERO);
    assert!(Shape::segment_shape_new(h(), a, Vect::new(inside, Real::ZERO), Real::ZERO).is_ok());
    // 2^31 exactly: rejected.
    assert_eq!(
        Shape::segment_shape_new(h(), a, Vect::new(half_range(), Real::ZERO), Real::ZERO)
            .unwrap_err(),
        EXTENT
    );
    assert_eq!(
        Shape::segment_shape_new(
            h(),
            Vect::new(Real::MIN, Real::MIN),
            Vect::new(Real::MAX, Real::MAX),
            Real::ZERO
        )
        .unwrap_err(),
        EXTENT
    );
    // The rounding radius counts: 2 ulp more span on the accepted segment.
    assert_eq!(
        Shape::segment_shape_new(
            h(),
            Vect::new(-inside, Real::ZERO),
            Vect::new(inside, Real::ZERO),
            Real::DELTA
        )
        .unwrap_err(),
        EXTENT
    );
    let mut s =
        Shape::segment_shape_new(h(), Vect::ZERO, Vect::from_ints(1, 0), Real::ZERO).unwrap();
    assert_eq!(s.set_segment_radius(Real::MAX), Err(EXTENT));
    assert_eq!(
        s.set_segment_endpoints(
            Vect::new(Real::MIN, Real::ZERO),
            Vect::new(Real::MAX, Real::ZERO)
        ),
        Err(EXTENT)
    );
    assert_eq!(s.segment().unwrap().radius, Real::ZERO);
    assert_eq!(s.segment().unwrap().b, Vect::from_ints(1, 0));
}

#[test]
fn polygon_rounding_radius_counts() {
    let unit = Shape::box_shape_new(h(), Real::ONE, Real::ONE, Real::ZERO).unwrap();
    // Half-width 0.5 plus radius r: span 1 + 2r < 2^31 ⇔ r < 2^30 − 0.5.
    let r_in = half_range() - Real::HALF - Real::DELTA;
    assert!(Shape::box_shape_new(h(), Real::ONE, Real::ONE, r_in).is_ok());
    assert_eq!(
        Shape::box_shape_new(h(), Real::ONE, Real::ONE, r_in + Real::DELTA).unwrap_err(),
        EXTENT
    );
    assert_eq!(
        Shape::box_shape_new(h(), Real::ONE, Real::ONE, Real::MAX).unwrap_err(),
        EXTENT
    );
    assert_eq!(
        Shape::box_shape_new2(
            h(),
            BB::new(Real::ZERO, Real::ZERO, Real::ONE, Real::ONE),
            Real::MAX
        )
        .unwrap_err(),
        EXTENT
    );
    let pts = [Vect::ZERO, Vect::from_ints(1, 0), Vect::from_ints(0, 1)];
    assert_eq!(
        Shape::poly_shape_new(h(), &pts, &Transform::IDENTITY, Real::MAX).unwrap_err(),
        EXTENT
    );
    assert_eq!(
        Shape::poly_shape_new_raw(h(), &pts, Real::MAX).unwrap_err(),
        EXTENT
    );
    let mut p = unit.clone();
    assert_eq!(p.set_poly_radius(Real::MAX), Err(EXTENT));
    assert_eq!(p, unit);
}

#[test]
fn snapshot_load_rejects_oversized_geometry() {
    // Only a forger can make such geometry (every setter checks): write a
    // distinctive radius, then replace its bytes with 2^30 m.
    let marker = Real::from_bits(0x1234_5678_9ABC);
    let mut space = Space::new();
    let b = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap())
        .unwrap();
    space
        .add_shape(Shape::circle_shape_new(b, marker, Vect::ZERO).unwrap())
        .unwrap();
    let bytes = snapshot::save(&space);
    assert!(snapshot::load(&bytes).is_ok());
    let needle = marker.to_bits().to_le_bytes();
    let at = bytes.windows(8).position(|w| w == needle).unwrap();
    assert_eq!(bytes.windows(8).filter(|w| *w == needle).count(), 1);
    let mut forged = bytes.clone();
    forged[at..at + 8].copy_from_slice(&half_range().to_bits().to_le_bytes());
    // The header checksum covers the payload bytes: recompute it.
    let sum = snapshot::payload_checksum(&forged[snapshot::HEADER_LEN..]);
    forged[12..20].copy_from_slice(&sum.to_le_bytes());
    match snapshot::load(&forged) {
        Err(SnapshotError::Invalid(why)) => assert!(why.contains("extent"), "{why}"),
        other => panic!("forged radius accepted: {:?}", other.map(|s| s.checksum())),
    }
    // Just inside loads.
    let mut inside = bytes.clone();
    inside[at..at + 8].copy_from_slice(&(half_range() - Real::DELTA).to_bits().to_le_bytes());
    let sum = snapshot::payload_checksum(&inside[snapshot::HEADER_LEN..]);
    inside[12..20].copy_from_slice(&sum.to_le_bytes());
    assert!(snapshot::load(&inside).is_ok());
}
