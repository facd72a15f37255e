//! Polygon construction from arbitrary points (any bits, any count): never
//! panics; an accepted polygon is convex, counter-clockwise, and accepted
//! again as a raw polygon.
#![no_main]
use libfuzzer_sys::fuzz_target;
use tamias2d::math::{Real, Transform, Vect};
use tamias2d::shape::hull::convex_hull;
use tamias2d::shape::Poly;

fuzz_target!(|input: (Vec<(i64, i64)>, i64, i64)| {
    let (points, radius, tol) = input;
    let pts: Vec<Vect> = points
        .iter()
        .take(64)
        .map(|&(x, y)| Vect::new(Real::from_bits(x), Real::from_bits(y)))
        .collect();
    let hull = convex_hull(&pts, Real::from_bits(tol));
    assert!(hull.len() <= pts.len());
    if let Ok(p) = Poly::from_points(&pts, &Transform::IDENTITY, Real::from_bits(radius)) {
        assert!(p.count() >= 3);
        // A built polygon is valid input for the raw constructor.
        assert!(Poly::from_ccw(p.verts(), p.radius()).is_ok());
    }
    let _ = Poly::from_ccw(&pts, Real::from_bits(radius));
});
