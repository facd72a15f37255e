#![allow(clippy::float_arithmetic)]
//! Shapes: convex hull, polygon construction, mass helpers and the MIS error
//! cases, as property tests against independent oracles.
//!
//! Oracles and bounds:
//! * orientation is recomputed here on i128 from the raw bits (exact), so
//!   hull convexity and containment are checked **exactly** (0 ulp) for
//!   `tolerance = 0`, and within `tolerance + 2^-30` otherwise;
//! * polygon normals are unit within `2^-32 + 1/len_raw` (`Vect::normalize`
//!   rounds each component to nearest and takes the floor of the length in
//!   raw units) and point outward within `4·2^-32·|vⱼ − vᵢ|`;
//! * area, centroid and centroid-relative moment are **bit-identical** under
//!   translation; against an f64 oracle (Chipmunk's formulas, relative to a
//!   vertex to avoid cancellation) they agree within the bounds stated in
//!   `tamias2d::shape::mass`, plus f64 rounding slack.
use proptest::prelude::*;
use tamias2d::arena::Handle;
use tamias2d::body::BodyHandle;
use tamias2d::shape::hull::convex_hull;
use tamias2d::shape::mass::{
    area_for_capsule, area_for_poly, area_for_segment, centroid_for_poly, moment_for_box,
    moment_for_capsule, moment_for_circle, moment_for_poly, moment_for_segment, shape_mass_info,
};
use tamias2d::shape::{Geometry, MassSpec, Poly, Shape, ShapeError, MAX_POLY_VERTICES};
use tamias2d::{Real, Transform, Vect, BB};

const ULP: f64 = 1.0 / 4_294_967_296.0;

fn body() -> BodyHandle {
    Handle::from_raw_parts(0, 0)
}

fn v(x: i32, y: i32) -> Vect {
    Vect::from_ints(x, y)
}

/// Exact `(b − a) × (c − a)` on raw bits (test-side oracle, independent of
/// the library's `orientation`).
fn orient(a: Vect, b: Vect, c: Vect) -> i128 {
    let d = |p: Real, q: Real| i128::from(p.to_bits()) - i128::from(q.to_bits());
    d(b.x, a.x) * d(c.y, a.y) - d(b.y, a.y) * d(c.x, a.x)
}

fn f(v: Vect) -> (f64, f64) {
    v.to_f64()
}

/// A coordinate: either a small integer (so duplicates and collinear points
/// are common) or any value with full fractional bits in `±2^bits`.
fn coord(bits: u32) -> impl Strategy<Value = Real> {
    let lim = 1i64 << (bits + 32);
    prop_oneof![
        (-8i32..=8).prop_map(Real::from_int),
        (-lim..lim).prop_map(Real::from_bits),
    ]
}

fn point(bits: u32) -> impl Strategy<Value = Vect> {
    (coord(bits), coord(bits)).prop_map(|(x, y)| Vect::new(x, y))
}

fn points(bits: u32, max: usize) -> impl Strategy<Value = Vec<Vect>> {
    prop::collection::vec(point(bits), 0..max)
}

/// Convex polygons of 3..=8 vertices: hulls of random points.
fn convex_poly(bits: u32) -> impl Strategy<Value = Vec<Vect>> {
    prop::collection::vec(point(bits), 3..24)
        .prop_map(|p| convex_hull(&p, Real::ZERO))
        .prop_filter("needs area and at most 8 vertices", |h| {
            (3..=MAX_POLY_VERTICES).contains(&h.len())
        })
}

fn edges(h: &[Vect]) -> impl Iterator<Item = (Vect, Vect)> + '_ {
    h.iter()
        .zip(h.iter().cycle().skip(1))
        .take(h.len())
        .map(|(a, b)| (*a, *b))
}

/// Checks that `h` is strictly convex and counter-clockwise: every vertex not
/// on an edge lies strictly left of it.
fn assert_strictly_convex_ccw(h: &[Vect]) -> Result<(), TestCaseError> {
    for (a, b) in edges(h) {
        for p in h {
            if *p != a && *p != b {
                prop_assert!(
                    orient(a, b, *p) > 0,
                    "{p:?} not left of {a:?}→{b:?} in {h:?}"
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2_000))]

    /// Hull with tolerance 0: convex, counter-clockwise, starts at the
    /// smallest (x, y), made of input points, containing every input point
    /// exactly.
    #[test]
    fn hull_zero_tolerance_is_convex_ccw_and_contains_all(pts in points(20, 40)) {
        let h = convex_hull(&pts, Real::ZERO);
        let Some(min) = pts.iter().min_by_key(|p| (p.x, p.y)).copied() else {
            prop_assert!(h.is_empty());
            return Ok(());
        };
        prop_assert_eq!(h.first().copied(), Some(min));
        prop_assert!(h.iter().all(|p| pts.contains(p)));
        match h.len() {
            0 => prop_assert!(false, "empty hull of non-empty input"),
            1 => prop_assert!(pts.iter().all(|p| *p == min)),
            2 => {
                let (a, b) = (min, h.get(1).copied().unwrap_or(min));
                prop_assert!(pts.iter().all(|p| orient(a, b, *p) == 0));
            }
            _ => {
                assert_strictly_convex_ccw(&h)?;
                for (a, b) in edges(&h) {
                    for p in &pts {
                        prop_assert!(orient(a, b, *p) >= 0, "{p:?} outside {a:?}→{b:?}");
                    }
                }
            }
        }
    }

    /// With a tolerance, the hull is still strictly convex and every dropped
    /// point lies within `tolerance` (+ 2^-30 slack) outside each edge line.
    #[test]
    fn hull_with_tolerance_is_convex_and_within_tolerance(
        pts in points(6, 40),
        tol_raw in 0i64..(1i64 << 32),
    ) {
        let tol = Real::from_bits(tol_raw);
        let h = convex_hull(&pts, tol);
        if h.len() >= 3 {
            assert_strictly_convex_ccw(&h)?;
            for (a, b) in edges(&h) {
                let len = (f(b).0 - f(a).0).hypot(f(b).1 - f(a).1);
                for p in &pts {
                    let dist = orient(a, b, *p) as f64 * ULP * ULP / len;
                    prop_assert!(dist >= -(tol.to_f64() + 4.0 * ULP), "{p:?} {dist} outside {a:?}→{b:?}");
                }
            }
        }
    }

    /// The hull of a hull is itself, and the hull does not depend on the
    /// order of the input points.
    #[test]
    fn hull_idempotent_and_order_independent(pts in points(20, 40), rot in 0usize..40) {
        let h = convex_hull(&pts, Real::ZERO);
        prop_assert_eq!(&convex_hull(&h, Real::ZERO), &h);
        let mut shuffled = pts.clone();
        shuffled.reverse();
        if !shuffled.is_empty() {
            let k = rot % shuffled.len();
            shuffled.rotate_left(k);
        }
        prop_assert_eq!(convex_hull(&shuffled, Real::ZERO), h);
    }

    /// `Poly::from_points` errors exactly when the hull is degenerate or too
    /// big; otherwise it holds the hull with unit outward normals.
    #[test]
    fn poly_from_points_errors_or_has_unit_outward_normals(
        pts in points(8, 16),
        t in (coord(8), coord(8)),
        scale in 1i32..4,
    ) {
        let transform = Transform {
            tx: t.0,
            ty: t.1,
            ..Transform::scale(Real::from_int(scale), Real::ONE)
        };
        let placed: Vec<Vect> = pts.iter().map(|p| transform.point(*p)).collect();
        let hull = convex_hull(&placed, Real::ZERO);
        match Poly::from_points(&pts, &transform, Real::ZERO) {
            Err(ShapeError::DegeneratePolygon) => prop_assert!(hull.len() < 3),
            Err(ShapeError::TooManyVertices(n)) => {
                prop_assert_eq!(n, hull.len());
                prop_assert!(n > MAX_POLY_VERTICES);
            }
            Err(e) => prop_assert!(false, "unexpected error {e:?}"),
            Ok(poly) => {
                prop_assert_eq!(poly.verts(), hull.as_slice());
                for (i, (a, b)) in edges(poly.verts()).enumerate() {
                    let n = poly.normal(i);
                    let (nx, ny) = f(n);
                    let len_raw = (f(b).0 - f(a).0).hypot(f(b).1 - f(a).1) / ULP;
                    let unit_err = (nx.hypot(ny) - 1.0).abs();
                    prop_assert!(unit_err <= ULP + 1.0 / len_raw + 1e-15, "|n| − 1 = {unit_err:e}");
                    for p in poly.verts() {
                        let (dx, dy) = (f(*p).0 - f(a).0, f(*p).1 - f(a).1);
                        let dot = nx * dx + ny * dy;
                        prop_assert!(dot <= 4.0 * ULP * dx.hypot(dy), "normal {i} not outward: {dot:e}");
                    }
                }
            }
        }
    }

    /// Area, centroid and centroid-relative moment are bit-identical under
    /// translation; the moment about an offset origin is unchanged when the
    /// offset compensates the translation.
    #[test]
    fn poly_mass_helpers_translation_invariant(
        poly in convex_poly(10),
        t in point(20),
        r_raw in 0i64..(4i64 << 32),
        m in 1i32..100,
    ) {
        let r = Real::from_bits(r_raw);
        let m = Real::from_int(m);
        let moved: Vec<Vect> = poly.iter().map(|p| *p + t).collect();
        prop_assert_eq!(area_for_poly(&moved, Real::ZERO), area_for_poly(&poly, Real::ZERO));
        prop_assert_eq!(area_for_poly(&moved, r), area_for_poly(&poly, r));
        let c = centroid_for_poly(&poly);
        let cm = centroid_for_poly(&moved);
        prop_assert_eq!(cm, c + t);
        prop_assert_eq!(
            moment_for_poly(m, &moved, -cm, r),
            moment_for_poly(m, &poly, -c, r)
        );
        let offset = v(3, -2);
        prop_assert_eq!(
            moment_for_poly(m, &moved, offset - t, r),
            moment_for_poly(m, &poly, offset, r)
        );
    }

    /// Area, centroid and moment agree with Chipmunk's formulas in f64.
    #[test]
    fn poly_mass_helpers_match_f64_oracle(
        poly in convex_poly(6),
        r_raw in 0i64..(2i64 << 32),
        m_raw in (1i64 << 28)..(64i64 << 32),
    ) {
        let (r, m) = (Real::from_bits(r_raw), Real::from_bits(m_raw));
        let (rf, mf) = (r.to_f64(), m.to_f64());
        let n = poly.len() as f64;
        let o = f(poly.first().copied().unwrap_or(Vect::ZERO));
        let rel: Vec<(f64, f64)> = poly.iter().map(|p| (f(*p).0 - o.0, f(*p).1 - o.1)).collect();
        let rel_edges = || rel.iter().zip(rel.iter().cycle().skip(1)).take(rel.len());
        let cross = |a: &(f64, f64), b: &(f64, f64)| a.0 * b.1 - a.1 * b.0;
        let twice_area: f64 = rel_edges().map(|(a, b)| cross(a, b)).sum();
        let perimeter: f64 = rel_edges().map(|(a, b)| (b.0 - a.0).hypot(b.1 - a.1)).sum();
        let slack = 2e-11;

        // Area: ½ ulp without radius; 1 + |r|(n + 1 + |r|/2) ulp with it.
        let area0 = twice_area / 2.0;
        prop_assert!((area_for_poly(&poly, Real::ZERO).to_f64() - area0).abs() <= 0.5 * ULP + slack);
        let area_r = area0 + rf * (core::f64::consts::PI * rf + perimeter);
        let bound = (1.0 + rf * (n + 1.0 + rf / 2.0)) * ULP + slack;
        prop_assert!((area_for_poly(&poly, r).to_f64() - area_r).abs() <= bound);

        // Centroid: ½ ulp per component.
        let (sx, sy) = rel_edges().fold((0.0, 0.0), |(sx, sy), (a, b)| {
            let c = cross(a, b);
            (sx + (a.0 + b.0) * c, sy + (a.1 + b.1) * c)
        });
        let (gx, gy) = (o.0 + sx / (3.0 * twice_area), o.1 + sy / (3.0 * twice_area));
        let c = centroid_for_poly(&poly);
        prop_assert!((c.x.to_f64() - gx).abs() <= 0.5 * ULP + slack);
        prop_assert!((c.y.to_f64() - gy).abs() <= 0.5 * ULP + slack);

        // Moment about the centroid: ½ ulp + |m|·2^-33 ulp.
        let about: Vec<(f64, f64)> = poly.iter().map(|p| (f(*p).0 - gx, f(*p).1 - gy)).collect();
        let (s1, s2) = about
            .iter()
            .zip(about.iter().cycle().skip(1))
            .take(about.len())
            .fold((0.0, 0.0), |(s1, s2), (a, b)| {
                let c = cross(a, b);
                let d = a.0 * a.0 + a.1 * a.1 + a.0 * b.0 + a.1 * b.1 + b.0 * b.0 + b.1 * b.1;
                (s1 + c * d, s2 + c)
            });
        let moment = mf * s1 / (6.0 * s2);
        let got = moment_for_poly(m, &poly, -c, r).to_f64();
        prop_assert!((got - moment).abs() <= (0.5 + mf * 0.5 * ULP) * ULP + 1e-11 * mf, "{got} vs {moment}");
    }

    /// Collinear points never make a polygon.
    #[test]
    fn collinear_points_are_degenerate(
        base in point(8),
        dir in (-4i32..=4, -4i32..=4),
        ks in prop::collection::vec(-10i32..=10, 0..12),
    ) {
        let d = v(dir.0, dir.1);
        let pts: Vec<Vect> = ks.iter().map(|k| base + d.mult(Real::from_int(*k))).collect();
        prop_assert_eq!(
            Shape::poly_shape_new(body(), &pts, &Transform::IDENTITY, Real::ZERO),
            Err(ShapeError::DegeneratePolygon)
        );
        prop_assert!(convex_hull(&pts, Real::ZERO).len() <= 2);
    }

    /// Any index at or past the count is IndexOutOfBounds.
    #[test]
    fn poly_vert_index_out_of_bounds(poly in convex_poly(6), extra in 0usize..100) {
        let shape = Shape::poly_shape_new_raw(body(), &poly, Real::ZERO);
        prop_assert!(shape.is_ok());
        if let Ok(s) = shape {
            let count = poly.len();
            prop_assert_eq!(s.poly_count(), Ok(count));
            for (i, p) in poly.iter().enumerate() {
                prop_assert_eq!(s.poly_vert(i), Ok(*p));
            }
            prop_assert_eq!(
                s.poly_vert(count + extra),
                Err(ShapeError::IndexOutOfBounds { index: count + extra, count })
            );
        }
    }
}

#[test]
fn kind_mismatch_errors_follow_the_mis() {
    let circle = Shape::circle_shape_new(body(), Real::ONE, Vect::ZERO).unwrap();
    let segment = Shape::segment_shape_new(body(), v(0, 0), v(1, 0), Real::ZERO).unwrap();
    let boxed = Shape::box_shape_new(body(), Real::ONE, Real::ONE, Real::ZERO).unwrap();
    assert_eq!(boxed.circle_radius(), Err(ShapeError::NotCircleShape));
    assert_eq!(boxed.circle_offset(), Err(ShapeError::NotCircleShape));
    assert_eq!(segment.circle_radius(), Err(ShapeError::NotCircleShape));
    for s in [&circle, &segment] {
        assert_eq!(s.poly_count(), Err(ShapeError::NotPolyShape));
        assert_eq!(s.poly_vert(0), Err(ShapeError::NotPolyShape));
        assert_eq!(s.poly_radius(), Err(ShapeError::NotPolyShape));
    }
    let mut c = circle.clone();
    assert_eq!(c.set_poly_radius(Real::ONE), Err(ShapeError::NotPolyShape));
    assert_eq!(
        c.set_poly_verts(&[v(0, 0), v(1, 0), v(0, 1)], &Transform::IDENTITY),
        Err(ShapeError::NotPolyShape)
    );
    assert_eq!(
        c.set_poly_verts_raw(&[v(0, 0), v(1, 0), v(0, 1)]),
        Err(ShapeError::NotPolyShape)
    );
    assert_eq!(c, circle);
}

#[test]
fn negative_radius_and_bad_vertices_are_errors() {
    let neg = -Real::DELTA;
    let tri = [v(0, 0), v(1, 0), v(0, 1)];
    let e = Err(ShapeError::Negative("radius"));
    assert_eq!(Shape::circle_shape_new(body(), neg, Vect::ZERO), e);
    assert_eq!(
        Shape::poly_shape_new(body(), &tri, &Transform::IDENTITY, neg),
        e
    );
    assert_eq!(Shape::poly_shape_new_raw(body(), &tri, neg), e);
    assert_eq!(Shape::box_shape_new(body(), Real::ONE, Real::ONE, neg), e);
    let bb = BB::new(Real::ZERO, Real::ZERO, Real::ONE, Real::ONE);
    assert_eq!(Shape::box_shape_new2(body(), bb, neg), e);
    let mut s = Shape::poly_shape_new_raw(body(), &tri, Real::ZERO).unwrap();
    assert_eq!(s.set_poly_radius(neg), Err(ShapeError::Negative("radius")));
    assert_eq!(
        Shape::box_shape_new(body(), -Real::ONE, Real::ONE, Real::ZERO),
        Err(ShapeError::Negative("box size"))
    );
    // Clockwise raw vertices are not convex-CCW; collinear ones are degenerate.
    assert_eq!(
        Shape::poly_shape_new_raw(body(), &[v(0, 0), v(0, 1), v(1, 0)], Real::ZERO),
        Err(ShapeError::NotConvex)
    );
    assert_eq!(
        Shape::poly_shape_new_raw(body(), &[v(0, 0), v(1, 1), v(2, 2)], Real::ZERO),
        Err(ShapeError::DegeneratePolygon)
    );
    assert_eq!(
        Shape::poly_shape_new(
            body(),
            &[v(0, 0), v(0, 0), v(0, 0)],
            &Transform::IDENTITY,
            Real::ZERO
        ),
        Err(ShapeError::DegeneratePolygon)
    );
}

#[test]
fn unit_box_mass_info_is_chipmunk_values() {
    let mut s = Shape::box_shape_new(body(), Real::ONE, Real::ONE, Real::ZERO).unwrap();
    s.set_density(Real::ONE).unwrap();
    let info = s.mass_info();
    assert_eq!(info.area, Real::ONE);
    assert_eq!(info.mass, Real::ONE);
    assert_eq!(info.cog, Vect::ZERO);
    assert_eq!(info.moment_per_mass, Real::ratio(1, 6));
    assert_eq!(
        info.moment_per_mass,
        moment_for_box(Real::ONE, Real::ONE, Real::ONE)
    );
    let geometry = Geometry::Poly(Poly::new_box(Real::ONE, Real::ONE, Real::ZERO).unwrap());
    assert_eq!(
        shape_mass_info(&geometry, MassSpec::Mass(Real::TWO)).mass,
        Real::TWO
    );
}

/// The capsule's exact moment in `f64`: the rectangle plus two half discs,
/// each carried to the centre (parallel axes), then to the origin.
fn capsule_moment_f64(m: f64, a: (f64, f64), b: (f64, f64), r: f64) -> f64 {
    let len = (b.0 - a.0).hypot(b.1 - a.1);
    let pi = std::f64::consts::PI;
    let rect = 2.0 * r * len;
    let disc = pi * r * r;
    let about_centre = rect * (len * len + 4.0 * r * r) / 12.0
        + disc * (r * r / 2.0 + len * len / 4.0)
        + 4.0 / 3.0 * r.powi(3) * len;
    let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
    m * (about_centre / (rect + disc) + mid.0 * mid.0 + mid.1 * mid.1)
}

#[test]
fn capsule_is_a_rounded_segment_with_exact_mass_helpers() {
    let (a, b, r) = (v(-1, 2), v(3, 2), Real::HALF);
    let capsule = Shape::capsule(body(), a, b, r).unwrap();
    assert_eq!(capsule, Shape::segment_shape_new(body(), a, b, r).unwrap());
    assert_eq!(
        Shape::capsule(body(), a, b, -Real::ONE),
        Err(ShapeError::Negative("radius"))
    );
    assert_eq!(area_for_capsule(a, b, r), area_for_segment(a, b, r));
    let mut dense = capsule.clone();
    dense.set_density(Real::ONE).unwrap();
    assert_eq!(dense.mass_info().area, area_for_capsule(a, b, r));
    // The limits: no radius is a rod (Chipmunk's segment moment agrees),
    // no length a disc (the circle's moment agrees).
    let m = Real::from_int(3);
    assert_eq!(
        moment_for_capsule(m, a, b, Real::ZERO),
        moment_for_segment(m, a, b, Real::ZERO)
    );
    let c = v(2, -1);
    let disc = moment_for_capsule(m, c, c, r);
    let want = moment_for_circle(m, Real::ZERO, r, c);
    assert!(
        (disc.to_bits() - want.to_bits()).abs() <= 2,
        "{disc:?} {want:?}"
    );
    // Below Chipmunk's box approximation, and on the f64 formula.
    assert!(moment_for_capsule(m, a, b, r) < moment_for_segment(m, a, b, r));
    for (a, b, r, m) in [
        ((0.0, 0.0), (2.0, 0.0), 0.5, 1.0),
        ((-1.0, 2.0), (3.0, 2.0), 0.5, 3.0),
        ((0.25, -0.5), (0.25, 0.5), 0.4, 70.0),
        ((10.0, 10.0), (13.0, 14.0), 1.5, 0.125),
        ((0.0, 0.0), (0.001, 0.0), 0.002, 0.01),
    ] {
        let got = moment_for_capsule(
            Real::from_f64(m).unwrap(),
            Vect::from_f64(a.0, a.1).unwrap(),
            Vect::from_f64(b.0, b.1).unwrap(),
            Real::from_f64(r).unwrap(),
        )
        .to_f64();
        let want = capsule_moment_f64(m, a, b, r);
        assert!(
            (got - want).abs() <= 8.0 * ULP * (1.0 + want.abs()),
            "{a:?} {b:?} {r} {m}: {got} vs {want}"
        );
    }
}
