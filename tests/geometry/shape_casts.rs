#![allow(clippy::float_arithmetic)]
//! Shape casts (`tamias2d::collision::shape_cast`, `Space::shape_cast` and
//! its kin) against a fine-stepped reference.
//!
//! The reference moves the cast shape along its path in steps of 1/4096 of
//! the translation and asks the narrow phase (`shapes_collide`) at every
//! step whether the two shapes overlap, deeper than `REF_DEPTH` (2^-20 m:
//! the narrow phase's own distances are rounded by a few hundred ulp at
//! most here). For every cast:
//! * **no miss:** if the reference finds an overlap, the cast hits, at a
//!   fraction no later than the reference's first overlapping step plus
//!   one step;
//! * **never deep:** at the cast's fraction, unless it is 0 (a start in
//!   overlap), the shapes overlap by at most
//!   `CAST_TOLERANCE + 2^-26·|translation|` (the documented bound);
//! * **a real contact:** at the cast's fraction the shapes are within
//!   `NEAR` (2^-16 m) of touching, and the hit point is within `NEAR` of
//!   the target's surface, the normal a unit vector.
//!
//! Every pair of kinds (cast: circle, capsule, box, rounded polygon,
//! sharp segment; target: the same) over a fan of paths, then a proptest of
//! random shapes and paths; then the space-level casts: filters, sensors,
//! ignored bodies, order, the broadphase against a full scan, a thin wall
//! hit at speed, a zero translation, a start in overlap.
use proptest::prelude::*;
use tamias2d::body::Body;
use tamias2d::collision::{
    separation, shape_cast, shapes_collide, ShapeCastInfo, StartContact, CAST_TOLERANCE,
};
use tamias2d::shape::query::point_query;
use tamias2d::shape::{Circle, Geometry, Poly, Segment, Shape, ShapeFilter};
use tamias2d::space::{ShapeCast, Space, SpaceError};
use tamias2d::{Real, Rot, Vect};

/// Reference steps per path.
const STEPS: i32 = 4096;

fn r(x: f64) -> Real {
    Real::from_f64(x).expect("test value in range")
}

fn v(x: f64, y: f64) -> Vect {
    Vect::new(r(x), r(y))
}

/// Depth of overlap the reference counts (2^-20 m).
fn ref_depth() -> Real {
    Real::from_bits(1 << 12)
}

/// How near to touching a reported hit must be (2^-16 m).
fn near() -> Real {
    Real::from_bits(1 << 16)
}

/// The overlap the casts may leave: `CAST_TOLERANCE + 2^-26·|δ|`.
fn allowed_depth(d: Vect) -> Real {
    CAST_TOLERANCE + Real::from_bits(d.length().to_bits() >> 26)
}

/// `g` moved by `offset` (as the cast moves its shape: exact additions).
fn moved(g: &Geometry, offset: Vect) -> Geometry {
    g.to_world(offset, Rot::IDENTITY)
}

/// The deepest contact of the narrow phase (positive: overlap depth), or
/// `None` when it reports no contact.
fn depth(a: &Geometry, b: &Geometry) -> Option<Real> {
    let set = shapes_collide(a, b);
    set.points.iter().take(set.count).map(|p| -p.distance).max()
}

/// The first reference step at which `a` moved along `d` overlaps `b`
/// deeper than `REF_DEPTH`, if any (steps whose boxes do not meet are
/// skipped: they cannot overlap).
fn reference_first_overlap(a: &Geometry, d: Vect, b: &Geometry) -> Option<i32> {
    let bb = b.bb();
    (0..=STEPS).find(|&k| {
        let at = moved(a, d * Real::ratio(k, STEPS));
        at.bb().intersects(&bb) && depth(&at, b).is_some_and(|x| x > ref_depth())
    })
}

#[derive(Default, Debug)]
struct Tally {
    casts: u32,
    hits: u32,
    reference_overlaps: u32,
    misses: u32,
    /// The deepest overlap at a reported fraction above 0, in ulp (2^-32 m).
    worst_depth_ulp: i64,
    /// The widest gap at a reported fraction (a hit reported early), in ulp.
    worst_gap_ulp: i64,
}

/// One cast checked against the reference (see the module docs); panics
/// with the case on a failure.
fn check(a: &Geometry, d: Vect, b: &Geometry, tally: &mut Tally) -> Option<ShapeCastInfo> {
    let hit = shape_cast(a, d, b, StartContact::Hit);
    let first = reference_first_overlap(a, d, b);
    tally.casts += 1;
    tally.hits += u32::from(hit.is_some());
    tally.reference_overlaps += u32::from(first.is_some());
    if let Some(k) = first {
        let Some(h) = hit else {
            tally.misses += 1;
            panic!("missed: reference overlap at step {k}\n a {a:?}\n d {d:?}\n b {b:?}");
        };
        let limit = Real::ratio(k + 1, STEPS);
        assert!(
            h.fraction <= limit,
            "late: fraction {:?} > step {k} + 1\n a {a:?}\n d {d:?}\n b {b:?}",
            h.fraction
        );
    }
    if let Some(h) = hit {
        assert!(h.fraction >= Real::ZERO && h.fraction <= Real::ONE);
        let at = moved(a, d * h.fraction);
        // (At fraction 0 the shapes may overlap as deep as they start.)
        if let Some(x) = depth(&at, b).filter(|_| h.fraction.is_positive()) {
            tally.worst_depth_ulp = tally.worst_depth_ulp.max(x.to_bits());
            assert!(
                x <= allowed_depth(d),
                "deep: {x:?} at fraction {:?}\n a {a:?}\n d {d:?}\n b {b:?}",
                h.fraction
            );
        }
        let gap = separation(&at, b).0;
        tally.worst_gap_ulp = tally.worst_gap_ulp.max(gap.to_bits());
        assert!(
            gap <= near(),
            "early: gap {gap:?} at fraction {:?}\n a {a:?}\n d {d:?}\n b {b:?}",
            h.fraction
        );
        let off = point_query(b, h.point).distance.abs();
        assert!(
            off <= near(),
            "point {:?} off the surface by {off:?}",
            h.point
        );
        let unit = (h.normal.length() - Real::ONE).abs();
        assert!(unit <= Real::from_bits(16), "normal {:?}", h.normal);
    }
    hit
}

/// The kinds, each built around the origin and turned by `angle`.
fn kinds(angle: f64) -> Vec<(&'static str, Geometry)> {
    let rot = Rot::from_angle(r(angle));
    let poly = |pts: &[(f64, f64)], radius: f64| {
        let vs: Vec<Vect> = pts.iter().map(|&(x, y)| v(x, y)).collect();
        Geometry::Poly(Poly::from_ccw(&vs, r(radius)).expect("convex")).to_world(Vect::ZERO, rot)
    };
    vec![
        ("circle", Geometry::Circle(Circle::new(r(0.5), Vect::ZERO))),
        (
            "capsule",
            Geometry::Segment(Segment::new(v(-0.6, 0.0), v(0.6, 0.0), r(0.3)))
                .to_world(Vect::ZERO, rot),
        ),
        (
            "box",
            poly(&[(0.5, -0.3), (0.5, 0.3), (-0.5, 0.3), (-0.5, -0.3)], 0.0),
        ),
        (
            "rounded polygon",
            poly(
                &[
                    (0.4, -0.3),
                    (0.5, 0.2),
                    (0.0, 0.5),
                    (-0.5, 0.2),
                    (-0.3, -0.4),
                ],
                0.15,
            ),
        ),
        (
            "segment",
            Geometry::Segment(Segment::new(v(-1.5, 0.0), v(1.5, 0.0), Real::ZERO))
                .to_world(Vect::ZERO, rot),
        ),
    ]
}

#[test]
fn every_pair_of_kinds_against_the_reference() {
    let mut total = Tally::default();
    for (ai, (a_name, _)) in kinds(0.0).iter().enumerate() {
        for (bi, (b_name, _)) in kinds(0.0).iter().enumerate() {
            let mut tally = Tally::default();
            // A fan of paths: 12 starts around the target, each aimed at it
            // with an offset that makes some hit, some graze, some miss.
            for i in 0..12 {
                let t = i as f64 * std::f64::consts::FRAC_PI_6 + 0.1;
                let a = kinds(0.37 * i as f64)[ai].1;
                let b = kinds(-0.21 * i as f64 + 0.3)[bi].1;
                let start = v(4.0 * t.cos(), 4.0 * t.sin());
                let side = v(-t.sin(), t.cos());
                let offset = (i % 5) as f64 * 0.35 - 0.7;
                let length = 3.0 + (i % 4) as f64 * 2.0;
                let aim = -start + side * r(offset);
                let d = aim.normalize() * r(length);
                check(&moved(&a, start), d, &b, &mut tally);
            }
            assert_eq!(tally.misses, 0, "{a_name} at {b_name}: {tally:?}");
            assert!(tally.hits > 0, "{a_name} at {b_name}: {tally:?}");
            total.casts += tally.casts;
            total.hits += tally.hits;
            total.reference_overlaps += tally.reference_overlaps;
            total.worst_depth_ulp = total.worst_depth_ulp.max(tally.worst_depth_ulp);
            total.worst_gap_ulp = total.worst_gap_ulp.max(tally.worst_gap_ulp);
        }
    }
    println!("every pair: {total:?}");
}

#[test]
fn many_random_casts_against_the_reference() {
    // A deterministic sweep of the proptest's space (the proptest below
    // shrinks a failure; this one counts): every kind against every kind.
    let mut rng = 0x5eed_u64;
    let mut next = |lo: f64, hi: f64| {
        rng = rng
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((rng >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut tally = Tally::default();
    for i in 0..2000 {
        let a = kinds(next(-3.2, 3.2))[i % 5].1;
        let b = kinds(next(-3.2, 3.2))[(i / 5) % 5].1;
        let start = v(next(-8.0, 8.0), next(-8.0, 8.0));
        let aim = v(next(-2.0, 2.0), next(-2.0, 2.0));
        let d = (aim - start).normalize() * r(next(0.0, 20.0));
        check(&moved(&a, start), d, &b, &mut tally);
    }
    assert_eq!(tally.misses, 0);
    println!("random casts: {tally:?}");
}

#[test]
fn touching_counts_and_one_ulp_apart_does_not() {
    // A box sliding along the top of another (zero depth all the way), and
    // the same path one ulp higher.
    let square = |at: Vect| {
        let h = Real::HALF;
        let vs = [
            at + Vect::new(h, -h),
            at + Vect::new(h, h),
            at + Vect::new(-h, h),
            at + Vect::new(-h, -h),
        ];
        Geometry::Poly(Poly::from_ccw(&vs, Real::ZERO).unwrap())
    };
    let b = square(Vect::ZERO);
    let d = v(10.0, 0.0);
    // The corners meet at 0.4; the normal is the face the path enters
    // through (the side: flush corners are where a mover keeps a skin).
    let hit = shape_cast(&square(v(-5.0, 1.0)), d, &b, StartContact::Hit);
    assert_eq!(
        hit.map(|h| (h.fraction, h.normal)),
        Some((r(0.4), -Vect::X))
    );
    let above = Vect::new(r(-5.0), Real::ONE + Real::DELTA);
    assert_eq!(shape_cast(&square(above), d, &b, StartContact::Hit), None);
    // Corner to corner, exactly: a touch; a ulp off: a miss. Moving along
    // the diagonal from (−5, −7), the moving box's top-left corner runs on
    // the line x − y = 1 through the other's bottom-right corner
    // (0.5, −0.5), reached at 0.6.
    let diagonal = v(10.0, 10.0);
    let hit = shape_cast(&square(v(-5.0, -7.0)), diagonal, &b, StartContact::Hit);
    assert_eq!(hit.map(|h| h.fraction), Some(r(0.6)));
    let off = Vect::new(r(-5.0) + Real::DELTA, r(-7.0));
    let miss = shape_cast(&square(off), diagonal, &b, StartContact::Hit);
    assert_eq!(miss, None, "{miss:?}");
    // Resting on it and sliding along: a hit at 0 only for `Hit`.
    let resting = square(v(0.25, 1.0));
    let slide = v(3.0, 0.0);
    let hit = shape_cast(&resting, slide, &b, StartContact::Hit);
    assert_eq!(
        hit.map(|h| (h.fraction, h.normal)),
        Some((Real::ZERO, Vect::Y))
    );
    assert_eq!(
        shape_cast(&resting, slide, &b, StartContact::HitIfApproaching),
        None
    );
}

#[test]
fn casts_at_the_edges_of_the_range_answer_without_panicking() {
    let edges = [Real::MIN, -Real::ONE, Real::ZERO, Real::MAX];
    for (_, g) in kinds(0.4) {
        for &x in &edges {
            for &y in &edges {
                let far = moved(&g, Vect::new(x, y));
                for d in [Vect::new(Real::MAX, Real::MIN), Vect::new(x, y), Vect::ZERO] {
                    for (_, b) in kinds(-0.2) {
                        let _ = shape_cast(&far, d, &b, StartContact::Hit);
                        let _ = shape_cast(&b, d, &far, StartContact::HitIfApproaching);
                    }
                }
            }
        }
    }
    let mut space = busy_world(3);
    space.step(Real::ratio(1, 60)).unwrap();
    let cast = ShapeCast::new(
        kinds(0.0)[2].1,
        Vect::new(Real::MIN, Real::MIN),
        Rot::IDENTITY,
        Vect::new(Real::MAX, Real::MAX),
    );
    let _ = space.shape_cast_all(&cast, ShapeFilter::ALL);
}

/// Random shapes: any kind, 0.1 … 3 m, turned anyhow.
fn any_shape() -> impl Strategy<Value = Geometry> {
    (
        0usize..5,
        0.1f64..3.0,
        0.2f64..1.0,
        -3.2f64..3.2,
        0.0f64..0.3,
        prop::collection::vec(0.0f64..1.0, 3..=8),
    )
        .prop_map(|(kind, size, aspect, angle, round, gaps)| {
            let rot = Rot::from_angle(r(angle));
            let h = 0.5 * size;
            let g = match kind {
                0 => Geometry::Circle(Circle::new(r(h), Vect::ZERO)),
                1 => Geometry::Segment(Segment::new(v(-h, 0.0), v(h, 0.0), r(h * aspect * 0.5))),
                2 => Geometry::Segment(Segment::new(v(-h, 0.0), v(h, 0.0), Real::ZERO)),
                _ => {
                    // Sorted angles on an ellipse: a convex polygon.
                    let total: f64 = gaps.iter().map(|g| g + 0.2).sum();
                    let mut ang = 0.0;
                    let mut vs = Vec::new();
                    for g in &gaps {
                        ang += (g + 0.2) / total * std::f64::consts::TAU;
                        vs.push(v(h * ang.cos(), h * aspect * ang.sin()));
                    }
                    let radius = if kind == 3 { 0.0 } else { round * h };
                    match Poly::from_ccw(&vs, r(radius)) {
                        Ok(p) => Geometry::Poly(p),
                        Err(_) => Geometry::Circle(Circle::new(r(h), Vect::ZERO)),
                    }
                }
            };
            g.to_world(Vect::ZERO, rot)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_casts_never_miss_and_never_go_deep(
        a in any_shape(),
        b in any_shape(),
        start in (-8.0f64..8.0, -8.0f64..8.0),
        aim in (-2.0f64..2.0, -2.0f64..2.0),
        length in 0.0f64..20.0,
    ) {
        let start = v(start.0, start.1);
        let dir = (v(aim.0, aim.1) - start).normalize();
        let d = dir * r(length);
        let mut tally = Tally::default();
        check(&moved(&a, start), d, &b, &mut tally);
        prop_assert_eq!(tally.misses, 0);
    }

    #[test]
    fn casts_are_the_same_anywhere(
        a in any_shape(),
        b in any_shape(),
        start in (-8.0f64..8.0, -8.0f64..8.0),
        length in 0.0f64..20.0,
        shift in (-1.0e6f64..1.0e6, -1.0e6f64..1.0e6),
    ) {
        let start = v(start.0, start.1);
        let d = (-start).normalize() * r(length);
        let shift = v(shift.0, shift.1);
        let here = shape_cast(&moved(&a, start), d, &b, StartContact::Hit);
        let there = shape_cast(&moved(&a, start + shift), d, &moved(&b, shift), StartContact::Hit);
        // Fraction and normal bit for bit; the point shifted exactly.
        prop_assert_eq!(here.map(|h| (h.fraction, h.normal, h.point + shift)),
            there.map(|h| (h.fraction, h.normal, h.point)));
    }
}

#[test]
fn a_fast_long_cast_does_not_pass_a_thin_wall() {
    // A sharp segment wall (no thickness) and small shapes crossing it at
    // 1,000 m per cast, at every angle of a fan.
    let wall = Geometry::Segment(Segment::new(v(0.0, -2.0), v(0.0, 2.0), Real::ZERO));
    let mut tally = Tally::default();
    for (name, small) in kinds(0.3) {
        for i in 0..9 {
            let y = -1.8 + 0.45 * i as f64;
            let start = v(-500.0, y * 0.5);
            let d = v(1000.0, y * 0.5);
            let hit = shape_cast(&moved(&small, start), d, &wall, StartContact::Hit);
            let hit = hit.unwrap_or_else(|| panic!("{name} passed the wall on path {i}"));
            // Stopped at the wall, not past it.
            let at = moved(&small, start + d * hit.fraction);
            assert!(separation(&at, &wall).0 >= -allowed_depth(d), "{name} {i}");
            assert!(hit.normal.x < Real::ZERO, "{name} {i}: {:?}", hit.normal);
            tally.casts += 1;
        }
    }
    // A point-like circle exactly through the wall's end point still hits.
    let dot = Geometry::Circle(Circle::new(Real::ZERO, v(-5.0, 2.0)));
    let hit = shape_cast(&dot, v(10.0, 0.0), &wall, StartContact::Hit);
    let hit = hit.expect("a ray through the wall's end point touches it");
    assert!((hit.fraction.to_f64() - 0.5).abs() < 1e-6, "{hit:?}");
    // One ulp past the end: a miss.
    let past = Geometry::Circle(Circle::new(
        Real::ZERO,
        Vect::new(r(-5.0), r(2.0) + Real::DELTA),
    ));
    assert_eq!(
        shape_cast(&past, v(10.0, 0.0), &wall, StartContact::Hit),
        None
    );
    assert_eq!(tally.casts, 45);
}

#[test]
fn a_zero_translation_is_an_overlap_test() {
    for (a_name, a) in kinds(0.2) {
        for (b_name, b) in kinds(-0.4) {
            for (x, touching) in [(0.3, true), (5.0, false)] {
                let at = moved(&a, v(x, 0.1));
                let hit = shape_cast(&at, Vect::ZERO, &b, StartContact::Hit);
                assert_eq!(hit.is_some(), touching, "{a_name} on {b_name} at {x}");
                if let Some(h) = hit {
                    assert_eq!(h.fraction, Real::ZERO);
                }
                // A zero translation never goes deeper.
                let h = shape_cast(&at, Vect::ZERO, &b, StartContact::HitIfApproaching);
                assert_eq!(h, None);
            }
        }
    }
}

#[test]
fn a_start_in_overlap_hits_at_zero_with_the_penetration_normal() {
    // A unit box sunk 0.25 m into a floor box whose top is at y = 0.
    let floor = Geometry::Poly(
        Poly::from_ccw(
            &[v(5.0, -1.0), v(5.0, 0.0), v(-5.0, 0.0), v(-5.0, -1.0)],
            Real::ZERO,
        )
        .unwrap(),
    );
    let square = Geometry::Poly(
        Poly::from_ccw(
            &[v(0.5, -0.75), v(0.5, 0.25), v(-0.5, 0.25), v(-0.5, -0.75)],
            Real::ZERO,
        )
        .unwrap(),
    );
    let hit = shape_cast(&square, v(3.0, 0.0), &floor, StartContact::Hit).unwrap();
    assert_eq!((hit.fraction, hit.normal), (Real::ZERO, Vect::Y));
    // Leaving (up) or sliding (sideways): no hit when only approaching counts.
    for d in [v(3.0, 0.0), v(0.0, 2.0), v(1.0, 1.0)] {
        assert_eq!(
            shape_cast(&square, d, &floor, StartContact::HitIfApproaching),
            None
        );
    }
    // Going deeper: hit at 0.
    let down = shape_cast(
        &square,
        v(1.0, -0.1),
        &floor,
        StartContact::HitIfApproaching,
    );
    assert_eq!(
        down.map(|h| (h.fraction, h.normal)),
        Some((Real::ZERO, Vect::Y))
    );
}

// ---- The space-level casts ----

struct World {
    space: Space,
    ground: tamias2d::body::BodyHandle,
    wall: tamias2d::space::ShapeHandle,
    near_box: tamias2d::space::ShapeHandle,
    sensor: tamias2d::space::ShapeHandle,
    filtered: tamias2d::space::ShapeHandle,
    mover: tamias2d::body::BodyHandle,
    mover_capsule: tamias2d::space::ShapeHandle,
}

/// A ground body with a wall at x = 10 and a box at x = 5, a sensor at
/// x = 3, a shape in category 2 at x = 7; a kinematic "character" body at
/// the origin with a capsule and a second shape of its own just ahead.
fn world() -> World {
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    let wall = space
        .add_shape(
            Shape::segment_shape_new(ground, v(10.0, -5.0), v(10.0, 5.0), Real::ZERO).unwrap(),
        )
        .unwrap();
    let near_box = space
        .add_shape(
            Shape::box_shape_new2(
                ground,
                tamias2d::BB::new(r(5.0), r(-1.0), r(6.0), r(1.0)),
                Real::ZERO,
            )
            .unwrap(),
        )
        .unwrap();
    let mut s = Shape::circle_shape_new(ground, r(0.5), v(3.0, 0.0)).unwrap();
    s.sensor = true;
    let sensor = space.add_shape(s).unwrap();
    let mut f = Shape::circle_shape_new(ground, r(0.5), v(7.0, 3.0)).unwrap();
    f.filter = ShapeFilter {
        group: 0,
        categories: 2,
        mask: u32::MAX,
    };
    let filtered = space.add_shape(f).unwrap();
    let mut body = Body::new_kinematic();
    body.set_position(v(0.0, 0.0));
    let mover = space.add_body(body).unwrap();
    let mover_capsule = space
        .add_shape(Shape::capsule(mover, v(0.0, -0.5), v(0.0, 0.5), r(0.4)).unwrap())
        .unwrap();
    space
        .add_shape(Shape::circle_shape_new(mover, r(0.3), v(1.2, 0.0)).unwrap())
        .unwrap();
    World {
        space,
        ground,
        wall,
        near_box,
        sensor,
        filtered,
        mover,
        mover_capsule,
    }
}

fn capsule_cast(from: Vect, d: Vect) -> ShapeCast {
    let g = Geometry::Segment(Segment::new(v(0.0, -0.5), v(0.0, 0.5), r(0.4)));
    ShapeCast::new(g, from, Rot::IDENTITY, d)
}

#[test]
fn the_first_hit_skips_sensors_and_the_ignored_body() {
    let w = world();
    let cast = capsule_cast(v(0.0, 0.0), v(20.0, 0.0));
    // Without ignoring the mover's body, its own circle (just ahead) and
    // capsule (at the start) are hit at once.
    let (h, hit) = w.space.shape_cast(&cast, ShapeFilter::ALL).unwrap();
    assert_eq!((h, hit.fraction), (w.mover_capsule, Real::ZERO));
    // Ignoring it: the sensor at x = 3 is skipped, the box at x = 5 is hit
    // with the capsule's front (x + 0.4) on its face.
    let (h, hit) = w
        .space
        .shape_cast(&cast.ignoring_body(w.mover), ShapeFilter::ALL)
        .unwrap();
    assert_eq!(h, w.near_box);
    assert_eq!(hit.normal, -Vect::X);
    assert!((hit.fraction.to_f64() - 4.6 / 20.0).abs() < 1e-9, "{hit:?}");
    assert!((hit.point.x.to_f64() - 5.0).abs() < 1e-9, "{hit:?}");
    // The same from the body's shape.
    let from = w
        .space
        .shape_cast_from(w.mover_capsule, v(20.0, 0.0), ShapeFilter::ALL)
        .unwrap();
    assert_eq!(from, Some((h, hit)));
    assert_eq!(
        w.space
            .shape_cast_of(w.mover_capsule, v(20.0, 0.0))
            .unwrap(),
        cast.ignoring_body(w.mover)
    );
}

#[test]
fn all_hits_are_sorted_with_sensors_and_filters_honoured() {
    let w = world();
    let cast = capsule_cast(v(0.0, 2.5), v(20.0, 0.0)).ignoring_body(w.mover);
    // At y = 2.5 the capsule (reaching y ∈ [1.6, 3.4]) passes over the
    // box and the sensor, meets the filtered circle at (7, 3) and the wall.
    let all = w.space.shape_cast_all(&cast, ShapeFilter::ALL);
    let order: Vec<_> = all.iter().map(|(h, _)| *h).collect();
    assert_eq!(order, vec![w.filtered, w.wall]);
    // A filter that rejects category 2.
    let only_1 = ShapeFilter {
        group: 0,
        categories: 1,
        mask: 1,
    };
    let all = w.space.shape_cast_all(&cast, only_1);
    assert_eq!(
        all.iter().map(|(h, _)| *h).collect::<Vec<_>>(),
        vec![w.wall]
    );
    // Low, through everything: the sensor is among all hits, not first.
    let low = capsule_cast(v(0.0, 0.0), v(20.0, 0.0)).ignoring_body(w.mover);
    let all = w.space.shape_cast_all(&low, ShapeFilter::ALL);
    let order: Vec<_> = all.iter().map(|(h, _)| *h).collect();
    assert_eq!(order, vec![w.sensor, w.near_box, w.wall]);
    assert!(all.windows(2).all(|p| p[0].1.fraction <= p[1].1.fraction));
    assert_eq!(
        w.space.shape_cast(&low, ShapeFilter::ALL).map(|(h, _)| h),
        Some(w.near_box)
    );
    // Errors of the cast from a shape.
    let mut other = w.space.clone();
    other.remove_shape(w.mover_capsule).unwrap();
    assert_eq!(
        other.shape_cast_from(w.mover_capsule, v(1.0, 0.0), ShapeFilter::ALL),
        Err(SpaceError::StaleShape(w.mover_capsule))
    );
    let _ = w.ground;
}

#[test]
fn equal_fractions_are_in_handle_order() {
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    let shapes: Vec<_> = (0..4)
        .map(|_| {
            space
                .add_shape(Shape::box_shape_new(ground, r(1.0), r(4.0), Real::ZERO).unwrap())
                .unwrap()
        })
        .collect();
    // Free a slot and refill it, so handle order is not insertion order.
    space.remove_shape(shapes[1]).unwrap();
    let again = space
        .add_shape(Shape::box_shape_new(ground, r(1.0), r(4.0), Real::ZERO).unwrap())
        .unwrap();
    let cast = capsule_cast(v(-10.0, 0.0), v(20.0, 0.0));
    let all = space.shape_cast_all(&cast, ShapeFilter::ALL);
    let mut want = vec![shapes[0], shapes[2], shapes[3], again];
    want.sort();
    assert_eq!(all.iter().map(|(h, _)| *h).collect::<Vec<_>>(), want);
    assert!(all.windows(2).all(|p| p[0].1 == p[1].1));
    assert_eq!(
        space.shape_cast(&cast, ShapeFilter::ALL).map(|(h, _)| h),
        want.first().copied()
    );
}

/// A world of many static and moving shapes (the broadphase test's kind).
fn busy_world(seed: u64) -> Space {
    let mut rng = seed;
    let mut next = |n: i32| {
        rng = rng
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((rng >> 33) % (n.max(1) as u64)) as i32
    };
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    for i in 0..300 {
        let p = Vect::new(
            Real::ratio(next(1280) - 640, 16),
            Real::ratio(next(1280) - 640, 16),
        );
        let body = if i % 3 == 0 {
            let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
            b.set_position(p);
            space.add_body(b).unwrap()
        } else {
            ground
        };
        let at = if body == ground { p } else { Vect::ZERO };
        let mut s = match next(4) {
            0 => Shape::circle_shape_new(body, Real::ratio(next(30) + 2, 16), at).unwrap(),
            1 => Shape::segment_shape_new(body, at, at + v(1.5, 0.7), Real::ratio(next(4), 16))
                .unwrap(),
            2 => Shape::capsule(body, at, at + v(0.0, 1.0), r(0.3)).unwrap(),
            _ => Shape::box_shape_new2(
                body,
                tamias2d::BB::new(at.x, at.y, at.x + r(1.5), at.y + r(0.5)),
                r(0.05),
            )
            .unwrap(),
        };
        s.sensor = next(10) == 0;
        space.add_shape(s).unwrap();
    }
    space
}

#[test]
fn the_broadphase_gives_the_full_scan_s_answers() {
    let mut space = busy_world(7);
    let dt = Real::ratio(1, 60);
    space.step(dt).unwrap();
    assert!(space.queries_use_broadphase());
    let oracle = space.clone();
    assert!(!oracle.queries_use_broadphase());
    let mut hits = 0;
    for i in 0..60 {
        let f = i as f64;
        let from = v((f * 7.3) % 80.0 - 40.0, (f * 3.1) % 80.0 - 40.0);
        let d = v((f * 1.7).cos() * 30.0, (f * 1.7).sin() * 30.0);
        let shapes = kinds(f * 0.3);
        let g = &shapes[i % shapes.len()].1;
        let cast = ShapeCast::new(*g, from, Rot::from_angle(r(f * 0.1)), d);
        let all = space.shape_cast_all(&cast, ShapeFilter::ALL);
        assert_eq!(all, oracle.shape_cast_all(&cast, ShapeFilter::ALL));
        let first = space.shape_cast(&cast, ShapeFilter::ALL);
        assert_eq!(first, oracle.shape_cast(&cast, ShapeFilter::ALL));
        // The first hit is the first of all hits that is not a sensor.
        let solid = all.iter().find(|(h, _)| !space.shape(*h).unwrap().sensor);
        assert_eq!(first.as_ref(), solid);
        hits += all.len();
    }
    assert!(hits > 60, "casts hit things ({hits})");
}

/// Cost of the casts on scenes of `scenes/` (release: `cargo test
/// --release --test geometry shape_casts::cast_cost -- --ignored
/// --nocapture`): `pyramid_20` after 60 steps (210 boxes, all moving
/// shapes: every query looks at each), casts falling from above the
/// pyramid through half its height; `no_collide` (825 static circles in the
/// static tree, 28 moving ones), casts of 30 m from points of its field.
/// Beside them the thick ray (`segment_query_first` with the shape's
/// radius) on the same paths, and one pair cast alone.
#[test]
#[ignore]
fn cast_cost() {
    use std::hint::black_box;
    use std::time::Instant;
    const N: u32 = 2000;
    let median = |op: &mut dyn FnMut()| {
        let mut runs: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                op();
                t.elapsed().as_nanos() as f64 / f64::from(N)
            })
            .collect();
        runs.sort_by(f64::total_cmp);
        runs[2]
    };
    for scene in ["pyramid_20", "no_collide"] {
        let mut world = tamias2d_scenes::builtin(scene)
            .expect("a registered scene")
            .build()
            .expect("a valid scene");
        for _ in 0..60 {
            world.step().unwrap();
        }
        let space = &world.space;
        // The pyramid's box (the ground, wider than 50 m, left out).
        let bb = space
            .shapes()
            .filter_map(|(_, s)| {
                let b = space.body(s.body())?;
                Some(s.geometry().to_world(b.position(), b.rotation()).bb())
            })
            .filter(|bb| bb.r - bb.l < r(50.0))
            .reduce(|a, b| a.merge(&b))
            .expect("shapes");
        let (w, h) = ((bb.r - bb.l).to_f64(), (bb.t - bb.b).to_f64());
        let (left, bottom, top) = (bb.l.to_f64(), bb.b.to_f64(), bb.t.to_f64());
        let path = |i: u32| {
            let f = f64::from(i);
            if scene == "pyramid_20" {
                let from = v(left + (f * 0.37) % w, top + 2.0 + (f * 0.11) % 2.0);
                (from, v((f * 0.05).sin() * 3.0, -0.5 * h - 2.0))
            } else {
                let from = v(left + (f * 7.37) % w, bottom + (f * 3.11) % h);
                (from, v((f * 0.7).cos() * 30.0, (f * 0.7).sin() * 30.0))
            }
        };
        for (name, g) in &kinds(0.0)[..4] {
            let mut hits = 0u32;
            let mut all_hits = 0usize;
            for i in 0..N {
                let (from, d) = path(i);
                let cast = ShapeCast::new(*g, from, Rot::IDENTITY, d);
                hits += u32::from(space.shape_cast(&cast, ShapeFilter::ALL).is_some());
                all_hits += space.shape_cast_all(&cast, ShapeFilter::ALL).len();
            }
            let cast_ns = median(&mut || {
                for i in 0..N {
                    let (from, d) = path(i);
                    let cast = ShapeCast::new(*g, from, Rot::IDENTITY, d);
                    black_box(space.shape_cast(&cast, ShapeFilter::ALL));
                }
            });
            let ray_ns = median(&mut || {
                for i in 0..N {
                    let (from, d) = path(i);
                    black_box(space.segment_query_first(
                        from,
                        from + d,
                        g.radius(),
                        ShapeFilter::ALL,
                    ));
                }
            });
            // One pair: the cast shape against a box it hits, alone.
            let target = kinds(0.3)[2].1;
            let start = moved(g, v(-3.0, 0.2));
            let pair_ns = median(&mut || {
                for _ in 0..N {
                    black_box(shape_cast(
                        black_box(&start),
                        v(6.0, 0.0),
                        &target,
                        StartContact::Hit,
                    ));
                }
            });
            println!(
                "{scene} {name}: shape_cast {cast_ns:.0} ns (first hit on {hits} of {N}, \
                 {:.1} hits per cast), thick ray {ray_ns:.0} ns; one pair {pair_ns:.0} ns",
                all_hits as f64 / f64::from(N)
            );
        }
    }
}
