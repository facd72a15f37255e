//! Costs that must not grow with the world (issue "rollback budget",
//! `docs/performance.md`, "Rollback budget"):
//!
//! * `ray_cast/N`: one `segment_query_first` (a 10 m ray) among N static
//!   segments spread at a constant density (one per 4 m²): the shapes near
//!   the ray set the cost, not N (queries go through the static tree, which
//!   the first step builds).
//! * `build/N`: building N dynamic bodies, each with a circle of density 1
//!   (so `add_shape` sums the body's mass from its shapes): linear in N
//!   (per-body shape lists; no scan of the world per added shape).
//!
//! ```sh
//! cargo bench --bench world_scale
//! ```
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tamias2d::body::Body;
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::space::Space;
use tamias2d::{Real, Vect};

/// A deterministic generator for the segments' places.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: i64) -> i64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) % n.max(1) as u64) as i64
    }
}

/// `n` unit segments at random places in a square of side 2·√n metres
/// centred on the origin (one per 4 m², whatever `n`).
fn level(n: usize) -> Space {
    let mut space = Space::new();
    let ground = space
        .add_body(Body::new_static())
        .unwrap_or_else(|e| panic!("{e}"));
    let half = ((n as f64).sqrt()) as i64; // side 2·half metres
    let mut rng = Lcg(0x5EED);
    let sixteenths = |v: i64| Real::ratio(v as i32, 16);
    for _ in 0..n {
        let x = rng.below(2 * half * 16) - half * 16;
        let y = rng.below(2 * half * 16) - half * 16;
        let a = Vect::new(sixteenths(x), sixteenths(y));
        let b = a + Vect::new(Real::ONE, sixteenths(rng.below(33) - 16));
        let seg =
            Shape::segment_shape_new(ground, a, b, Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
        space.add_shape(seg).unwrap_or_else(|e| panic!("{e}"));
    }
    space
}

fn ray_cast(c: &mut Criterion) {
    let mut group = c.benchmark_group("ray_cast");
    for n in [200usize, 2_000, 20_000] {
        let mut space = level(n);
        // The first step builds the static tree (queries read it, and scan
        // every shape before any step has built it).
        space
            .step(Real::ratio(1, 60))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(space.queries_use_broadphase());
        let (a, b) = (Vect::from_ints(-5, 1), Vect::from_ints(5, -1));
        let hit = space.segment_query_first(a, b, Real::ZERO, ShapeFilter::ALL);
        eprintln!("ray_cast/{n}: hit {}", hit.is_some());
        group.bench_function(BenchmarkId::from_parameter(n), |bench| {
            bench.iter(|| {
                black_box(&space).segment_query_first(
                    black_box(a),
                    black_box(b),
                    Real::ZERO,
                    ShapeFilter::ALL,
                )
            })
        });
    }
    group.finish();
}

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("build");
    group.sample_size(10);
    for n in [40_000usize, 1_000_000] {
        group.bench_function(BenchmarkId::from_parameter(n), |bench| {
            bench.iter(|| {
                let mut space = Space::new();
                for i in 0..n {
                    let mut body =
                        Body::new(Real::ZERO, Real::ZERO).unwrap_or_else(|e| panic!("{e}"));
                    body.set_position(Vect::from_ints((i % 1000) as i32, (i / 1000) as i32));
                    let h = space.add_body(body).unwrap_or_else(|e| panic!("{e}"));
                    let mut shape = Shape::circle_shape_new(h, Real::HALF, Vect::ZERO)
                        .unwrap_or_else(|e| panic!("{e}"));
                    shape
                        .set_density(Real::ONE)
                        .unwrap_or_else(|e| panic!("{e}"));
                    space.add_shape(shape).unwrap_or_else(|e| panic!("{e}"));
                }
                space
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_millis(500));
    targets = ray_cast, build
}
criterion_main!(benches);
