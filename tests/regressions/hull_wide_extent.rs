//! Regression (found by `fuzz/poly_points`): `convex_hull` of three points
//! spanning more than 2^31 returned four vertices, one of them twice.
//! Cause: `orientation` saturated coordinate differences to `i64`, so side
//! tests of far-apart points disagreed with each other. Fix: exact
//! orientation on 65-bit differences with a 256-bit product.
use tamias2d::math::{Real, Transform, Vect};
use tamias2d::shape::hull::{convex_hull, orientation};
use tamias2d::shape::{Poly, ShapeError};

fn v(x: i64, y: i64) -> Vect {
    Vect::new(Real::from_bits(x), Real::from_bits(y))
}

#[test]
fn hull_of_far_apart_points_is_a_subset_without_duplicates() {
    let pts = [
        v(-7143389, -1),
        v(i64::MAX, -1060856955009),
        v(-233092170121217, 65535),
    ];
    let hull = convex_hull(&pts, Real::ZERO);
    assert_eq!(hull.len(), 3, "{hull:?}");
    for p in &hull {
        assert!(pts.contains(p));
    }
    // Counter-clockwise.
    assert!(orientation(hull[0], hull[1], hull[2]) > 0);
    // A polygon that wide is outside the Real range: an error, not a panic.
    assert_eq!(
        Poly::from_points(&pts, &Transform::IDENTITY, Real::ZERO).unwrap_err(),
        ShapeError::OutOfRange("transformed vertex")
    );
}

#[test]
fn orientation_is_exact_at_the_extremes() {
    let (lo, hi) = (Real::MIN, Real::MAX);
    let (a, b, c) = (Vect::new(lo, lo), Vect::new(hi, lo), Vect::new(hi, hi));
    assert!(orientation(a, b, c) > 0);
    assert!(orientation(a, c, b) < 0);
    assert_eq!(orientation(a, b, Vect::new(Real::ZERO, lo)), 0);
    assert_eq!(
        orientation(Vect::ZERO, Vect::from_ints(1, 0), Vect::from_ints(0, 1)),
        1i128 << 64
    );
}
