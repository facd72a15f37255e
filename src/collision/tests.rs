//! Unit tests of the narrow phase entry: the circle and polygon kernels
//! against the general path, swap and translation exactness, degenerate
//! inputs.
use super::canonical::flat;
use super::*;
use crate::real;
use crate::shape::Segment;

fn boxed(w: i32, h: i32, at: Vect) -> Geometry {
    let p = Poly::new_box(Real::from_int(w), Real::from_int(h), Real::ZERO)
        .unwrap_or_else(|_| Poly::from_ccw_unchecked(&[Vect::ZERO, Vect::X, Vect::Y], Real::ZERO));
    Geometry::Poly(moved_poly(&p, -at))
}

#[test]
fn circle_fast_path_is_the_general_path() {
    let big = Real::MAX - Real::ONE;
    let at = |x: Real, y: Real| Vect::new(x, y);
    let centres = [
        at(Real::ZERO, Real::ZERO),
        at(real!(0.3), real!(1.7)),
        at(real!(0.3), real!(-0.2)),
        at(real!(1.1), real!(1.7)),
        at(big, big),
        at(-big, big),
        at(Real::MIN, Real::MAX),
        at(Real::from_bits(1), Real::ZERO),
    ];
    let radii = [Real::ZERO, Real::HALF, Real::ONE, real!(1.25)];
    for &ca in &centres {
        for &cb in &centres {
            for &ra in &radii {
                for &rb in &radii {
                    let a = Circle::new(ra, ca);
                    let b = Circle::new(rb, cb);
                    for id in [0, 7] {
                        let (ga, gb) = (Geometry::Circle(a), Geometry::Circle(b));
                        let fast = collide_circles(&a, &b, id);
                        let general = collide_general(&ga, &gb, id);
                        assert_eq!(fast, general, "{a:?} {b:?} {id}");
                    }
                }
            }
        }
    }
}

/// A raw coordinate: anywhere, near a few values (so ties and touching
/// pairs are common), or at the range's ends.
fn raw_coord() -> impl proptest::strategy::Strategy<Value = i64> {
    use proptest::prelude::*;
    prop_oneof![
        any::<i64>(),
        (-3i64..=3, -(1i64 << 34)..(1i64 << 34)).prop_map(|(k, d)| (k << 32) + d),
        (-3i64..=3).prop_map(|k| k << 31),
        Just(i64::MAX),
        Just(i64::MIN),
        Just(i64::MIN + 1),
    ]
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]
    #[test]
    fn circle_kernel_is_the_general_path(
        (ax, ay, bx, by) in (raw_coord(), raw_coord(), raw_coord(), raw_coord()),
        (ra, rb) in (0i64..(3 << 32), 0i64..(3 << 32)),
        same in 0u8..4,
        id: u32,
    ) {
        let a = Circle::new(Real::from_bits(ra), Vect::new(Real::from_bits(ax), Real::from_bits(ay)));
        // Ties: the same centre, the same x, or the same circle.
        let b_centre = match same {
            0 => a.offset,
            1 => Vect::new(a.offset.x, Real::from_bits(by)),
            _ => Vect::new(Real::from_bits(bx), Real::from_bits(by)),
        };
        let rb = if same == 0 && rb % 2 == 0 { ra } else { rb };
        let b = Circle::new(Real::from_bits(rb), b_centre);
        let (ga, gb) = (Geometry::Circle(a), Geometry::Circle(b));
        proptest::prop_assert_eq!(collide_circles(&a, &b, id), collide_general(&ga, &gb, id));
        proptest::prop_assert_eq!(collide_circles(&b, &a, id), collide_general(&gb, &ga, id));
    }
}

/// The order `compare_polys` had as an iterator chain.
fn compare_polys_chained(x: &Poly, y: &Poly) -> Ordering {
    flat(x.verts())
        .chain(flat(x.normals()))
        .chain([x.radius()])
        .cmp(flat(y.verts()).chain(flat(y.normals())).chain([y.radius()]))
}

/// A convex polygon of 3, 4 or 8 vertices (sizes from `size`), moved by
/// `at` with saturating adds.
fn poly_at(kind: u8, size: i64, at: Vect, radius: Real) -> Poly {
    let s = Real::from_bits(size);
    let h = Real::from_bits(size / 2 + 1);
    let local: Vec<Vect> = match kind % 3 {
        0 => vec![
            Vect::ZERO,
            Vect::new(s, Real::ZERO),
            Vect::new(Real::ZERO, s),
        ],
        1 => vec![
            Vect::new(s, -h),
            Vect::new(s, h),
            Vect::new(-s, h),
            Vect::new(-s, -h),
        ],
        _ => (0..8)
            .map(|k| Vect::for_angle(Real::PI * real!(0.25) * Real::from_int(k)).mult(s))
            .collect(),
    };
    let p = Poly::from_ccw_unchecked(&local, radius);
    moved_poly(&p, -at)
}

#[test]
fn compare_polys_is_the_chained_order() {
    let at = |x: i64, y: i64| Vect::new(Real::from_bits(x), Real::from_bits(y));
    let mut polys = Vec::new();
    for kind in 0..3 {
        for size in [1i64 << 32, 3 << 31] {
            for pos in [at(0, 0), at(0, 1), at(1, 0), at(i64::MAX, i64::MIN)] {
                for radius in [Real::ZERO, Real::HALF] {
                    polys.push(poly_at(kind, size, pos, radius));
                }
            }
        }
    }
    for x in &polys {
        for y in &polys {
            assert_eq!(
                compare_polys(x, y),
                compare_polys_chained(x, y),
                "{x:?} {y:?}"
            );
        }
    }
}

#[test]
fn poly_fast_path_is_the_general_path() {
    let at = |x: i64, y: i64| Vect::new(Real::from_bits(x), Real::from_bits(y));
    let positions = [
        at(0, 0),
        at(3 << 31, 1 << 30),
        at(1 << 32, 0),
        at(0, 5 << 30),
        at(i64::MAX - (1 << 33), 0),
        at(i64::MIN, i64::MAX),
        at((1 << 61) - (1 << 34), -(1 << 61)),
        at(1 << 61, 0),
    ];
    for ka in 0..3 {
        for kb in 0..3 {
            for &pa in &positions {
                for &pb in &positions {
                    let a = poly_at(ka, 1 << 32, pa, Real::ZERO);
                    let b = poly_at(kb, 3 << 31, pb, real!(0.125));
                    for id in [0, 0x0102_0300] {
                        let (ga, gb) = (Geometry::Poly(a), Geometry::Poly(b));
                        assert_eq!(collide_polys(&a, &b, id), collide_general(&ga, &gb, id));
                        assert_eq!(collide_polys(&b, &a, id), collide_general(&gb, &ga, id));
                    }
                }
            }
        }
    }
}

/// The polygon fast path's range test: exactly the coordinates in
/// `[−2^61, 2^61)`, and inside it no move by another vertex saturates.
#[test]
fn half_range_test_is_its_bounds() {
    const H: i64 = 1 << 61;
    let tri = |x: i64, y: i64| {
        let p = Vect::new(Real::from_bits(x), Real::from_bits(y));
        Poly::from_ccw_unchecked(&[p, p + Vect::X, p + Vect::Y], Real::ZERO)
    };
    for (x, inside) in [
        (-H, true),
        (H - (1 << 33), true),
        (H, false),
        (-H - 1, false),
        (i64::MIN, false),
        (i64::MAX, false),
    ] {
        for y in [0, x] {
            assert_eq!(within_half_range(&tri(x, y)), inside, "{x} {y}");
            assert_eq!(within_half_range(&tri(y, x)), inside, "{y} {x}");
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(5_000))]
    /// Where the range test holds for both polygons, no vertex moved by
    /// either's vertex saturates or lands on `MIN` or `MAX`.
    #[test]
    fn half_range_implies_unsaturated_moves(
        coords in proptest::collection::vec(
            proptest::prop_oneof![-(1i64 << 61)..(1i64 << 61), (1i64 << 61) - 64..(1i64 << 61), -(1i64 << 61)..-(1i64 << 61) + 64],
            8,
        ),
    ) {
        let p = |k: usize| Vect::new(Real::from_bits(coords[k]), Real::from_bits(coords[k + 1]));
        let (a, b) = (
            Poly::from_ccw_unchecked(&[p(0), p(2)], Real::ZERO),
            Poly::from_ccw_unchecked(&[p(4), p(6)], Real::ZERO),
        );
        proptest::prop_assert!(within_half_range(&a) && within_half_range(&b));
        for v in a.verts().iter().chain(b.verts()) {
            for w in a.verts().iter().chain(b.verts()) {
                let moved = *v - *w;
                proptest::prop_assert!(!moved.x.is_saturated() && !moved.y.is_saturated());
            }
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(5_000))]
    #[test]
    fn poly_kernel_is_the_general_path(
        (ka, kb) in (0u8..3, 0u8..3),
        (sa, sb) in ((1i64 << 28)..(5i64 << 32), (1i64 << 28)..(5i64 << 32)),
        (ax, ay, bx, by) in (raw_coord(), raw_coord(), raw_coord(), raw_coord()),
        (ra, rb) in (0i64..(1 << 31), 0i64..(1 << 31)),
        same in 0u8..4,
        id: u32,
    ) {
        let a = poly_at(ka, sa, Vect::new(Real::from_bits(ax), Real::from_bits(ay)), Real::from_bits(ra));
        // Ties: the same polygon, or the same first vertex.
        let b = match same {
            0 => a,
            1 => poly_at(kb, sb, Vect::new(Real::from_bits(ax), Real::from_bits(ay)), Real::from_bits(rb)),
            _ => poly_at(kb, sb, Vect::new(Real::from_bits(bx), Real::from_bits(by)), Real::from_bits(rb)),
        };
        let (ga, gb) = (Geometry::Poly(a), Geometry::Poly(b));
        proptest::prop_assert_eq!(collide_polys(&a, &b, id), collide_general(&ga, &gb, id));
        proptest::prop_assert_eq!(collide_polys(&b, &a, id), collide_general(&gb, &ga, id));
    }
}

#[test]
fn swapped_kinds_mirror_exactly() {
    let ball = Geometry::Circle(Circle::new(Real::ONE, Vect::new(real!(0.3), real!(1.7))));
    let crate_box = boxed(2, 2, Vect::ZERO);
    let ab = collide(&ball, &crate_box, 0);
    let ba = collide(&crate_box, &ball, 0);
    assert_eq!(ab.count, 1);
    assert_eq!(ab.normal, -ba.normal);
    assert_eq!(ab.contacts()[0].point_a, ba.contacts()[0].point_b);
    assert_eq!(ab.contacts()[0].distance, ba.contacts()[0].distance);
}

#[test]
fn same_kind_swap_mirrors_exactly_with_ids() {
    let a = boxed(2, 2, Vect::ZERO);
    let b = boxed(2, 2, Vect::new(real!(0.5), real!(1.8)));
    let ab = collide(&a, &b, 0);
    let ba = collide(&b, &a, 0);
    assert_eq!(ab.count, 2);
    assert_eq!(ab.normal, -ba.normal);
    for (x, y) in ab.contacts().iter().zip(ba.contacts()) {
        assert_eq!(
            (x.point_a, x.point_b, x.distance),
            (y.point_b, y.point_a, y.distance)
        );
        assert_eq!(x.feature_id, y.feature_id.rotate_left(16));
    }
    assert_eq!(ab.warm_start_id, swap_id_shapes(ba.warm_start_id));
    // Warm-started calls agree with cold ones, in both orders.
    assert_eq!(collide(&a, &b, ab.warm_start_id), ab);
    assert_eq!(collide(&b, &a, ba.warm_start_id), ba);
}

#[test]
fn translation_moves_points_exactly() {
    let a = boxed(2, 2, Vect::ZERO);
    let b = Geometry::Segment(Segment::new(
        Vect::new(real!(-0.5), real!(0.9)),
        Vect::new(real!(2.5), real!(1.3)),
        real!(0.1),
    ));
    let shift = Vect::new(Real::from_int(1 << 29), Real::from_int(-(1 << 29)));
    let far_a = collide(&a, &b, 0);
    let ta = boxed(2, 2, shift);
    let tb = Geometry::Segment(Segment::new(
        Vect::new(real!(-0.5), real!(0.9)) + shift,
        Vect::new(real!(2.5), real!(1.3)) + shift,
        real!(0.1),
    ));
    let far_b = collide(&ta, &tb, 0);
    assert!(far_a.count > 0);
    assert_eq!(far_a.normal, far_b.normal);
    for (x, y) in far_a.contacts().iter().zip(far_b.contacts()) {
        assert_eq!(x.point_a + shift, y.point_a);
        assert_eq!(x.point_b + shift, y.point_b);
        assert_eq!((x.distance, x.feature_id), (y.distance, y.feature_id));
    }
}

#[test]
fn degenerate_inputs_do_not_panic() {
    let dot = Geometry::Circle(Circle::new(Real::ZERO, Vect::ZERO));
    let info = collide(&dot, &dot, 0);
    assert_eq!((info.count, info.normal), (1, Vect::X));
    let point_seg = Geometry::Segment(Segment::new(Vect::ZERO, Vect::ZERO, Real::ZERO));
    let _ = collide(&point_seg, &point_seg, 0);
    let _ = collide(&point_seg, &dot, 0);
    let _ = collide(&point_seg, &boxed(1, 1, Vect::ZERO), 0);
    let max = Vect::new(Real::MAX, Real::MAX);
    let min = Vect::new(Real::MIN, Real::MIN);
    let far = Geometry::Segment(Segment::new(min, max, Real::MAX));
    let _ = collide(&far, &boxed(1, 1, max), 0);
    let _ = collide(&boxed(1, 1, min), &boxed(1, 1, max), 0xFFFF_FFFF);
    let info = collide(
        &Geometry::Circle(Circle::new(Real::ONE, min)),
        &Geometry::Circle(Circle::new(Real::ONE, max)),
        0,
    );
    assert_eq!(info.count, 0);
    let empty = Geometry::Poly(Poly::from_ccw_unchecked(&[], Real::ZERO));
    assert_eq!(collide(&empty, &boxed(1, 1, Vect::ZERO), 0).count, 0);
    assert_eq!(shapes_collide(&empty, &dot).count, 0);
}

#[test]
fn shapes_collide_matches_collide() {
    let a = boxed(2, 2, Vect::ZERO);
    let b = Geometry::Circle(Circle::new(Real::ONE, Vect::new(real!(1.5), Real::ZERO)));
    let set = shapes_collide(&a, &b);
    let info = collide(&a, &b, 0);
    assert_eq!((set.count, set.normal), (info.count, info.normal));
    assert_eq!(set.points[0].distance, info.contacts[0].distance);
    assert_eq!(set.normal, Vect::X);
}
