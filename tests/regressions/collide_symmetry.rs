#![allow(clippy::float_arithmetic)]
//! Regressions for the swap symmetry and warm-start invariance of the narrow
//! phase: `collide(b, a, swap(id))` must be the exact mirror of
//! `collide(a, b, id)`, and the warm-start id must not change the answer.
//!
//! The fuzz inputs were found by the `collide_pair` fuzz target (their bytes
//! are regression seeds in `fuzz/seeds/collide_pair/regression-*`); the
//! shapes are built here exactly as that target builds them. The first two
//! were found when the harness compared `collide(a, b, id)` with
//! `collide(b, a, 0)`. They were one bug, not an argument-order asymmetry
//! (with the same, swapped, id both orders were already exact mirrors): when
//! GJK ended on an edge of the Minkowski difference whose line passes exactly
//! through the origin, past the edge's end, `closest_points_new` took the
//! exact-zero side test for "touching" and reported distance 0 between shapes
//! that are apart. Whether GJK ends on such an edge depends on where it
//! starts, i.e. on the warm-start id (or, for the staircase below, on the
//! cold start too).
use tamias2d::collision::{collide, poly_to_poly_gjk, CollisionInfo};
use tamias2d::math::{Real, Rot, Vect};
use tamias2d::shape::{Circle, Geometry, Poly, Segment};
use tamias2d::Transform;

fn r(bits: i64) -> Real {
    Real::from_bits(bits)
}

/// A fuzz-target `Poly { pts, r }` input: points in units of 2^-16.
fn fuzz_poly(pts: &[(i32, i32)], rad: i64) -> Geometry {
    let v: Vec<Vect> = pts
        .iter()
        .take(16)
        .map(|&(x, y)| {
            Vect::new(
                Real::from_bits(i64::from(x) << 16),
                Real::from_bits(i64::from(y) << 16),
            )
        })
        .collect();
    Geometry::Poly(Poly::from_points(&v, &Transform::IDENTITY, r(rad).abs()).expect("valid hull"))
}

/// Places a geometry as the fuzz target does: `to_world` at `(x, y)` (raw
/// bits), rotated by the angle with raw bits `angle`.
fn placed(g: Geometry, x: i64, y: i64, angle: i64) -> Geometry {
    g.to_world(Vect::new(r(x), r(y)), Rot::from_angle(r(angle)))
}

fn swap_id(id: u32) -> u32 {
    ((id & 0x00FF_00FF) << 8) | ((id >> 8) & 0x00FF_00FF)
}

fn without_id(mut info: CollisionInfo) -> CollisionInfo {
    info.warm_start_id = 0;
    info
}

/// Asserts that `collide(b, a, swap(id))` is the exact mirror of
/// `collide(a, b, id)`, for `id` and for a cold start.
fn assert_mirror(a: &Geometry, b: &Geometry, id: u32) {
    for id in [0, id] {
        let ab = collide(a, b, id);
        let ba = collide(b, a, swap_id(id));
        assert_eq!(ab.count, ba.count, "id {id:#x}: {ab:?}\n{ba:?}");
        assert_eq!(ab.normal, -ba.normal, "id {id:#x}");
        assert_eq!(ab.warm_start_id, swap_id(ba.warm_start_id), "id {id:#x}");
        for (x, y) in ab.contacts().iter().zip(ba.contacts()) {
            assert_eq!(
                (x.point_a, x.point_b, x.distance, x.feature_id),
                (
                    y.point_b,
                    y.point_a,
                    y.distance,
                    y.feature_id.rotate_left(16)
                ),
                "id {id:#x}"
            );
        }
    }
}

/// [`assert_mirror`], and the warm-started answer equals the cold one (all
/// but the returned warm-start id). Returns the cold answer.
fn assert_mirror_and_warm_invariant(a: &Geometry, b: &Geometry, id: u32) -> CollisionInfo {
    assert_mirror(a, b, id);
    let cold = collide(a, b, 0);
    assert_eq!(
        without_id(collide(a, b, id)),
        without_id(cold),
        "id {id:#x} vs cold"
    );
    cold
}

/// Fuzz finding 1 (`segment-segment-asymmetry`): two zero-radius segments,
/// 255 ulp and 1 ulp long, 65,536 apart, both lying on the x axis' line
/// through the origin of the Minkowski difference. The answer is no contact;
/// before the fix a cold start said "touching at distance 0" (in both orders)
/// and the fuzz input's warm-start id 1 said "apart".
#[test]
fn tiny_segments_65536_apart_do_not_touch() {
    let a = placed(
        Geometry::Segment(Segment::new(Vect::new(r(255), r(0)), Vect::ZERO, r(0))),
        1 << 48,
        0,
        -(1 << 56),
    );
    let b = Geometry::Segment(Segment::new(Vect::new(r(1), r(0)), Vect::ZERO, r(0)));
    let info = assert_mirror_and_warm_invariant(&a, &b, 1);
    assert_eq!(info.count, 0, "{info:?}");
}

/// Fuzz finding 2 (`sliver-circle-asymmetry`): a sliver triangle whose long
/// edge points (along y = x) at a zero-radius circle 2.16·10⁻⁵ from its
/// corner. No contact (the gap is above `CONTACT_TOLERANCE`); before the fix
/// the fuzz input's warm-start id `0x0100_0000` started GJK on that long
/// edge and reported a contact at distance 0.
#[test]
fn sliver_triangle_corner_near_point_circle() {
    let m = -1_111_638_595;
    let mut pts = vec![(m, m), (m, m), (m, m), (m, -256)];
    pts.extend([(-1, -1); 17]);
    pts.extend([
        (-1, 1_532_755_967),
        (1_532_722_011, 1_532_713_819),
        (1_532_713_819, -197),
        (23551, 0),
    ]);
    let a = placed(fuzz_poly(&pts, 0), 0, 0, 0);
    let b = placed(
        Geometry::Circle(Circle::new(r(0), Vect::ZERO)),
        0,
        0,
        390_842_023_936,
    );
    let info = assert_mirror_and_warm_invariant(&a, &b, 1 << 24);
    assert_eq!(info.count, 0, "{info:?}");
}

fn rect(l: i32, b: i32, r: i32, t: i32, radius: Real) -> Geometry {
    let v = [
        Vect::from_ints(r, b),
        Vect::from_ints(r, t),
        Vect::from_ints(l, t),
        Vect::from_ints(l, b),
    ];
    Geometry::Poly(Poly::from_ccw(&v, radius).expect("convex"))
}

/// Every warm-start id that names vertices of the pair.
fn all_vertex_ids(na: u32, nb: u32) -> impl Iterator<Item = u32> {
    let pairs = move || (0..na).flat_map(move |i| (0..nb).map(move |j| (i << 8) | j));
    pairs().flat_map(move |hi| pairs().map(move |lo| (hi << 16) | lo))
}

/// The same bug in plain geometry: a staircase of two unit boxes one unit
/// apart horizontally, the top of one on the line of the bottom of the other.
/// The Minkowski difference's bottom edge lies on a line through the origin,
/// so a GJK that ends on it must still report the corner distance (1), from
/// every warm start, in both orders.
#[test]
fn staircase_boxes_are_one_apart_from_every_warm_start() {
    for radius in [Real::ZERO, Real::from_bits(1 << 30)] {
        let a = rect(0, 0, 1, 1, radius);
        let b = rect(2, 1, 3, 2, radius);
        for id in all_vertex_ids(4, 4) {
            let info = assert_mirror_and_warm_invariant(&a, &b, id);
            assert_eq!(info.count, 0, "radius {radius:?} id {id:#x}: {info:?}");
        }
    }
    // Rounded enough to touch at the corners: one contact, along the diagonal.
    let a = rect(0, 0, 1, 1, Real::ONE);
    let b = rect(2, 1, 3, 2, Real::ONE);
    for id in all_vertex_ids(4, 4) {
        let info = assert_mirror_and_warm_invariant(&a, &b, id);
        assert_eq!(info.count, 1, "id {id:#x}: {info:?}");
    }
}

/// Segments on one line with a gap: the degenerate (collinear) Minkowski
/// difference has every edge on a line through the origin.
#[test]
fn collinear_segments_with_a_gap() {
    let a = Geometry::Segment(Segment::new(Vect::ZERO, Vect::from_ints(1, 0), Real::ZERO));
    let b = Geometry::Segment(Segment::new(
        Vect::from_ints(3, 0),
        Vect::from_ints(5, 0),
        Real::ZERO,
    ));
    for id in all_vertex_ids(2, 2) {
        let info = assert_mirror_and_warm_invariant(&a, &b, id);
        assert_eq!(info.count, 0, "id {id:#x}: {info:?}");
    }
    let touching = Geometry::Segment(Segment::new(
        Vect::from_ints(1, 0),
        Vect::from_ints(5, 0),
        Real::ZERO,
    ));
    for id in all_vertex_ids(2, 2) {
        let info = assert_mirror_and_warm_invariant(&a, &touching, id);
        assert_eq!(info.count, 1, "id {id:#x}: {info:?}");
        assert_eq!(info.contacts()[0].distance, Real::ZERO);
    }
}

/// Not a bug, the documented limit of warm-start invariance of GJK/EPA: a
/// 2×2 box centred in a 4×2 one is equally deep (2) pushed up or down. EPA
/// (`poly_to_poly_gjk`) reports the face its starting triangle leads to, so
/// some warm-start ids give `−y` where the cold start gives `+y`; every answer
/// has the same depth and is an exact mirror of the swapped call.
/// `collide` takes the separating-axis path for two polygons, which does not
/// read the warm-start id and breaks the tie by a fixed rule (A's face, lowest
/// edge index): `+y` for every id.
#[test]
fn equally_deep_faces_may_depend_on_the_warm_start_but_not_the_depth() {
    let a = rect(-1, -1, 1, 1, Real::ZERO);
    let b = rect(-2, -1, 2, 1, Real::ZERO);
    let (Geometry::Poly(pa), Geometry::Poly(pb)) = (&a, &b) else {
        panic!("rect builds polygons");
    };
    let cold = collide(&a, &b, 0);
    assert_eq!((cold.count, cold.normal), (2, Vect::Y));
    let mut flipped = 0;
    for id in all_vertex_ids(4, 4) {
        let warm = collide(&a, &b, id);
        let ba = collide(&b, &a, swap_id(id));
        assert_eq!(warm.normal, -ba.normal, "id {id:#x}");
        assert_eq!(warm.count, 2, "id {id:#x}");
        for c in warm.contacts() {
            assert_eq!(c.distance, -Real::TWO, "id {id:#x}");
        }
        assert_eq!(warm.normal, Vect::Y, "id {id:#x}");
        let mut gjk = CollisionInfo::new(id);
        poly_to_poly_gjk(pa, pb, &mut gjk);
        assert_eq!(gjk.count, 2, "id {id:#x}");
        for c in gjk.contacts() {
            assert_eq!(c.distance, -Real::TWO, "id {id:#x}");
        }
        assert!(
            gjk.normal == Vect::Y || gjk.normal == -Vect::Y,
            "id {id:#x}"
        );
        flipped += usize::from(gjk.normal != cold.normal);
    }
    assert!(
        flipped > 0,
        "the GJK/EPA tie is resolved by the start (else tighten the docs)"
    );
}

/// Fuzz finding 3 (`near-tie-segment-poly`, after the first fix): a long,
/// almost flat segment (tilted by 2.3·10⁻¹⁰ rad) sunk into a polygon whose
/// top edge is exactly flat. The two faces of the Minkowski difference meet
/// at the deepest point and their depths differ by ~10⁻⁵ ulp. With EPA's
/// edges ranked by a rounded closest point the two tied, and the cold start
/// reported the segment's face (normal x = −1 ulp), the fuzz input's warm
/// start `0x100` the polygon's (x = 0). Ranked by their true distances (to
/// 2^-61 relative) both starts agree, bit for bit.
#[test]
fn near_tie_segment_poly_faces_ranked_exactly() {
    let pts = [
        (-1, -1),
        (-1, -1_650_614_785),
        (-1_650_614_883, -1_650_614_883),
        (-1_650_614_883, -1_650_628_963),
        (-6_447_715, -1),
        (-268_435_457, -1),
        (-1, -1),
        (-1, -13_500_417),
        (-1, -1_073_741_825),
        (-1, -1),
        (-1, -1),
    ];
    let a = placed(
        Geometry::Segment(Segment::new(
            Vect::new(r(-1_234_077_248_126_721), r(-1)),
            Vect::new(r(-1), r(-1)),
            r(-1).abs(),
        )),
        -1,
        -1,
        -1,
    );
    let b = placed(fuzz_poly(&pts, -16_318_464), -1, 4_294_967_295, 0);
    let cold = assert_mirror_and_warm_invariant(&a, &b, 0x100);
    assert_eq!(cold.count, 2);
    assert_eq!(cold.normal, Vect::new(-Real::DELTA, -Real::ONE));
}

/// Fuzz finding 4 (`epa-long-edges-point`, after the fix): a zero-radius
/// circle 5.7·10⁻⁷ inside the corner of a polygon with edges ~2·10⁴ long.
/// The depth is the distance to the nearer edge, 4.529·10⁻⁷. The cold start
/// reported the other edge (5.632·10⁻⁷, 475 ulp deeper): EPA ranked its hull
/// edges by `|p|²` of the closest point `p` computed through the rounded edge
/// parameter `t`, and on an edge 2·10⁴ long one ulp of `t` moves `p` by
/// 5·10⁻⁶, far more than the depths being compared.
#[test]
fn epa_ranks_long_edges_by_their_true_distance() {
    let pts = [
        (-1_111_638_595, -1_514_291_779),
        (-1_111_687_168, -1),
        (-1, -1),
        (-1, -1_674_281_473),
        (33_550_474, -16_766_975),
        (0, 0),
    ];
    let a = placed(fuzz_poly(&pts, 0), 0, 0, 21_110_623_253_299_200);
    let b = placed(
        Geometry::Circle(Circle::new(r(0), Vect::new(r(0), r(512)))),
        2048,
        0,
        72_057_594_037_928_027,
    );
    assert_mirror(&a, &b, 1024);
    let depth = |info: &CollisionInfo| info.contacts().iter().map(|c| c.distance).min();
    let (cold, warm) = (collide(&a, &b, 0), collide(&a, &b, 1024));
    let (c, w) = (
        depth(&cold).expect("overlap"),
        depth(&warm).expect("overlap"),
    );
    // The true depth, from the exact geometry, to 1e-10.
    assert!((c.to_f64() + 4.529e-7).abs() < 1e-10, "cold {c:?}");
    assert!((w.to_f64() + 4.529e-7).abs() < 1e-10, "warm {w:?}");
}

/// Fuzz finding (30-minute `collide_pair` run): two collinear, overlapping,
/// zero-radius segments (255 ulp and 0.0117 long, both from the origin along
/// +x). Their Minkowski difference has no area, GJK ends at distance 0 with
/// whatever normal its start leads to, and the clipped depth was 0 along ±y
/// for one warm-start id but −255 ulp along x from the cold start. Collinear
/// cores now take the first segment's own normal: depth 0 for every start.
#[test]
fn collinear_overlapping_segments_agree_for_every_warm_start() {
    let a = Geometry::Segment(Segment::new(Vect::new(r(255), r(0)), Vect::ZERO, r(0)));
    let b = Geometry::Segment(Segment::new(
        Vect::new(r(50_400_000), r(0)),
        Vect::ZERO,
        r(0),
    ));
    let cold = collide(&a, &b, 0);
    assert!(cold.count > 0, "the segments overlap");
    for c in cold.contacts() {
        assert_eq!(c.distance, Real::ZERO);
    }
    for id in (0..=0xFFFF_u32)
        .step_by(0x101)
        .chain([0x1_0000, 0x100, 0x0101_0000])
    {
        let warm = collide(&a, &b, id);
        assert_eq!(without_id(warm), without_id(cold), "id {id:#x}");
        assert_mirror(&a, &b, id);
    }
}
