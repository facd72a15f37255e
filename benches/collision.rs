//! Collision micro-benchmarks: each pair function (polygon pairs through
//! both the separating-axis path and the GJK + EPA one), GJK and EPA alone,
//! and the full `collide` (ordering, translation to the origin, dispatch).
//!
//! Shapes are built from integers, exact literals and the crate's own
//! fixed-point trig (no floats). Run with `cargo bench --bench collision`;
//! criterion reports the time per call (the middle figure is the estimate).
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use tamias2d::collision::{
    circle_to_circle, circle_to_poly, circle_to_segment, collide, epa, gjk, poly_to_poly,
    poly_to_poly_gjk, segment_to_poly, segment_to_segment, support, CollisionInfo, SupportContext,
};
use tamias2d::shape::{Circle, Geometry, Poly, Segment};
use tamias2d::{real, Real, Vect};

fn rect(l: Real, b: Real, r: Real, t: Real, radius: Real) -> Poly {
    let v = [
        Vect::new(r, b),
        Vect::new(r, t),
        Vect::new(l, t),
        Vect::new(l, b),
    ];
    Poly::from_ccw(&v, radius).expect("valid box")
}

/// A regular octagon of circumradius `r` around `c`, turned by `turn` rad.
fn octagon(c: Vect, r: Real, turn: Real) -> Poly {
    let step = Real::PI * real!(0.25);
    let v: Vec<Vect> = (0..8)
        .map(|k| c + Vect::for_angle(turn + step * Real::from_int(k)).mult(r))
        .collect();
    Poly::from_ccw(&v, Real::ZERO).expect("valid octagon")
}

/// Runs a pair function once and checks the scenario is what it claims.
fn check(name: &str, want: usize, f: impl Fn(&mut CollisionInfo)) {
    let mut info = CollisionInfo::new(0);
    f(&mut info);
    assert_eq!(info.count, want, "{name}: {info:?}");
    assert!(!info.hit_iteration_cap, "{name}");
}

/// Benchmarks a polygon pair through `poly_to_poly` (separating axes) and
/// `poly_to_poly_gjk` (GJK + EPA, the path it replaced), cold started.
fn poly_pair(c: &mut Criterion, name: &str, want: usize, (a, b): (&Poly, &Poly)) {
    check(name, want, |i| poly_to_poly(a, b, i));
    check(name, want, |i| poly_to_poly_gjk(a, b, i));
    c.bench_function(&format!("poly_to_poly/{name}"), |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            poly_to_poly(black_box(a), black_box(b), &mut info);
            info
        })
    });
    c.bench_function(&format!("poly_to_poly_gjk/{name}"), |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            poly_to_poly_gjk(black_box(a), black_box(b), &mut info);
            info
        })
    });
}

fn pairs(c: &mut Criterion) {
    let ball = Circle::new(Real::ONE, Vect::ZERO);
    let ball2 = Circle::new(Real::ONE, Vect::new(real!(1.5), real!(0.25)));
    check("circle_to_circle", 1, |i| {
        circle_to_circle(&ball, &ball2, i)
    });
    c.bench_function("circle_to_circle", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            circle_to_circle(black_box(&ball), black_box(&ball2), &mut info);
            info
        })
    });

    let ground = Segment::new(Vect::from_ints(-10, 0), Vect::from_ints(10, 0), real!(0.1));
    let resting = Circle::new(Real::ONE, Vect::new(real!(2.5), real!(1.05)));
    check("circle_to_segment", 1, |i| {
        circle_to_segment(&resting, &ground, i)
    });
    c.bench_function("circle_to_segment", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            circle_to_segment(black_box(&resting), black_box(&ground), &mut info);
            info
        })
    });

    let plank = Segment::new(
        Vect::new(real!(-1.5), real!(0.15)),
        Vect::new(real!(1.5), real!(0.18)),
        real!(0.1),
    );
    check("segment_to_segment", 2, |i| {
        segment_to_segment(&ground, &plank, i)
    });
    c.bench_function("segment_to_segment", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            segment_to_segment(black_box(&ground), black_box(&plank), &mut info);
            info
        })
    });

    let crate_box = rect(-Real::ONE, -Real::ONE, Real::ONE, Real::ONE, Real::ZERO);
    let ball_on_box = Circle::new(Real::HALF, Vect::new(real!(0.3), real!(1.45)));
    check("circle_to_poly", 1, |i| {
        circle_to_poly(&ball_on_box, &crate_box, i)
    });
    c.bench_function("circle_to_poly", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            circle_to_poly(black_box(&ball_on_box), black_box(&crate_box), &mut info);
            info
        })
    });

    let sunk_box = rect(Real::ZERO, real!(0.05), Real::ONE, real!(1.05), Real::ZERO);
    check("segment_to_poly", 2, |i| {
        segment_to_poly(&ground, &sunk_box, i)
    });
    c.bench_function("segment_to_poly", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(0);
            segment_to_poly(black_box(&ground), black_box(&sunk_box), &mut info);
            info
        })
    });

    // Box resting on a box (cores overlap).
    let floor = rect(
        Real::from_int(-5),
        -Real::ONE,
        Real::from_int(5),
        Real::ZERO,
        Real::ZERO,
    );
    let top = rect(-Real::ONE, real!(-0.01), Real::ONE, real!(0.99), Real::ZERO);
    poly_pair(c, "box_on_box_overlap", 2, (&floor, &top));

    // Rounded boxes whose cores are apart (vertex–face through the radius).
    let r_floor = rect(
        Real::from_int(-5),
        -Real::ONE,
        Real::from_int(5),
        Real::ZERO,
        real!(0.05),
    );
    let r_top = rect(-Real::ONE, real!(0.09), Real::ONE, real!(1.09), real!(0.05));
    poly_pair(c, "rounded_boxes_core_apart", 2, (&r_floor, &r_top));

    // Two rotated boxes overlapping corner into face.
    let turned = |c: Vect, turn: Real, w: Real, h: Real| {
        let rot = Vect::for_angle(turn);
        let v: Vec<Vect> = [(1, -1), (1, 1), (-1, 1), (-1, -1)]
            .iter()
            .map(|&(x, y)| {
                let local = Vect::new(w * Real::from_int(x), h * Real::from_int(y));
                c + rot.rotate(local)
            })
            .collect();
        Poly::from_ccw(&v, Real::ZERO).expect("valid box")
    };
    let ra = turned(Vect::ZERO, real!(0.1), Real::ONE, Real::HALF);
    let rb = turned(
        Vect::new(real!(0.6), real!(0.8)),
        real!(0.7),
        real!(0.75),
        real!(0.4),
    );
    poly_pair(c, "rotated_boxes_overlap", 2, (&ra, &rb));

    // Two overlapping octagons, cold and warm started.
    let oa = octagon(Vect::ZERO, Real::ONE, Real::ZERO);
    let ob = octagon(Vect::new(real!(1.7), real!(0.4)), Real::ONE, real!(0.2));
    poly_pair(c, "octagons_overlap_cold", 2, (&oa, &ob));
    let mut first = CollisionInfo::new(0);
    poly_to_poly_gjk(&oa, &ob, &mut first);
    let warm_id = first.warm_start_id;
    c.bench_function("poly_to_poly/octagons_overlap_warm", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(black_box(warm_id));
            poly_to_poly(black_box(&oa), black_box(&ob), &mut info);
            info
        })
    });
    c.bench_function("poly_to_poly_gjk/octagons_overlap_warm", |bch| {
        bch.iter(|| {
            let mut info = CollisionInfo::new(black_box(warm_id));
            poly_to_poly_gjk(black_box(&oa), black_box(&ob), &mut info);
            info
        })
    });

    // The whole entry point on the pairs a pile is made of (what the step
    // calls per candidate pair): two touching circles, two circles whose
    // boxes overlap but which do not touch, and a box resting on a box.
    let gc1 = Geometry::Circle(Circle::new(Real::ONE, Vect::new(real!(10.25), real!(3.5))));
    let gc2 = Geometry::Circle(Circle::new(Real::ONE, Vect::new(real!(11.75), real!(4.0))));
    let gc3 = Geometry::Circle(Circle::new(Real::ONE, Vect::new(real!(11.75), real!(5.25))));
    assert_eq!(collide(&gc1, &gc2, 0).count, 1);
    assert_eq!(collide(&gc1, &gc3, 0).count, 0);
    c.bench_function("collide/circles_touching", |bch| {
        bch.iter(|| collide(black_box(&gc1), black_box(&gc2), 0))
    });
    c.bench_function("collide/circles_apart", |bch| {
        bch.iter(|| collide(black_box(&gc1), black_box(&gc3), 0))
    });
    let gfloor = Geometry::Poly(floor);
    let gtop = Geometry::Poly(top);
    assert_eq!(collide(&gfloor, &gtop, 0).count, 2);
    c.bench_function("collide/box_on_box", |bch| {
        bch.iter(|| collide(black_box(&gfloor), black_box(&gtop), 0))
    });

    // The whole entry point, far from the origin.
    let far = Vect::from_ints(100_000, -50_000);
    let ga = Geometry::Poly(octagon(far, Real::ONE, Real::ZERO));
    let gb = Geometry::Poly(octagon(
        far + Vect::new(real!(1.7), real!(0.4)),
        Real::ONE,
        real!(0.2),
    ));
    c.bench_function("collide/octagons_far_from_origin", |bch| {
        bch.iter(|| collide(black_box(&ga), black_box(&gb), 0))
    });
}

fn gjk_epa(c: &mut Criterion) {
    let a = octagon(Vect::ZERO, Real::ONE, Real::ZERO);
    let apart = octagon(Vect::new(real!(3.1), real!(1.3)), Real::ONE, real!(0.2));
    let ctx = SupportContext::new(&a, &apart);
    c.bench_function("gjk/octagons_apart_cold", |bch| {
        bch.iter(|| gjk(black_box(&ctx), black_box(0)))
    });
    let id = gjk(&ctx, 0).warm_start_id;
    c.bench_function("gjk/octagons_apart_warm", |bch| {
        bch.iter(|| gjk(black_box(&ctx), black_box(id)))
    });

    // EPA alone from a triangle of support points around the origin.
    let over = octagon(Vect::new(real!(0.3), real!(0.1)), Real::ONE, real!(0.2));
    let ctx = SupportContext::new(&a, &over);
    let v0 = support(&ctx, Vect::from_ints(2, 0));
    let v1 = support(&ctx, Vect::new(-Real::ONE, real!(1.732)));
    let v2 = support(&ctx, Vect::new(-Real::ONE, real!(-1.732)));
    c.bench_function("epa/octagons_overlap", |bch| {
        bch.iter(|| epa(black_box(&ctx), black_box(v0), black_box(v1), black_box(v2)))
    });
}

criterion_group!(benches, pairs, gjk_epa);
criterion_main!(benches);
