//! The cost of one narrowphase call (`collide`, the entry the step uses for
//! every candidate pair) on a fixed pair, for `docs/performance.md`'s
//! per-unit figures: `pair_cost <circles|circles_apart|boxes> <calls>`
//! prints the median over 15 rounds of the time per call. Run under
//! `valgrind --tool=callgrind` at two call counts and difference the totals
//! for the instructions per call (see "Narrowphase and broadphase, per unit").
use std::hint::black_box;
use std::time::Instant;

use tamias2d::collision::collide;
use tamias2d::shape::{Circle, Geometry, Poly};
use tamias2d::{real, Real, Vect};

fn rect(l: Real, b: Real, r: Real, t: Real) -> Geometry {
    let v = [
        Vect::new(r, b),
        Vect::new(r, t),
        Vect::new(l, t),
        Vect::new(l, b),
    ];
    Geometry::Poly(Poly::from_ccw(&v, Real::ZERO).expect("valid box"))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let pair = args.get(1).map_or("circles", String::as_str);
    let calls: u32 = args
        .get(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let circle = |x, y| Geometry::Circle(Circle::new(Real::ONE, Vect::new(x, y)));
    let (a, b, contacts) = match pair {
        // Two unit circles overlapping by 0.42.
        "circles" => (
            circle(real!(10.25), real!(3.5)),
            circle(real!(11.75), real!(4.0)),
            1,
        ),
        // Boxes overlapping, circles apart: the broadphase's false positive.
        "circles_apart" => (
            circle(real!(10.25), real!(3.5)),
            circle(real!(11.75), real!(5.25)),
            0,
        ),
        // A 2 × 1 box resting 0.01 deep on a 10 × 1 one.
        "boxes" => (
            rect(
                Real::from_int(-5),
                -Real::ONE,
                Real::from_int(5),
                Real::ZERO,
            ),
            rect(-Real::ONE, real!(-0.01), Real::ONE, real!(0.99)),
            2,
        ),
        other => {
            eprintln!("unknown pair {other}: circles, circles_apart or boxes");
            std::process::exit(2);
        }
    };
    assert_eq!(collide(&a, &b, 0).count, contacts);
    let mut per_call = Vec::new();
    for _ in 0..15 {
        let start = Instant::now();
        for _ in 0..calls / 15 {
            black_box(collide(black_box(&a), black_box(&b), 0));
        }
        per_call.push(start.elapsed().as_secs_f64() * 1e9 / f64::from((calls / 15).max(1)));
    }
    per_call.sort_by(f64::total_cmp);
    println!(
        "{pair}: {:.1} ns per call (median of 15 rounds)",
        per_call[7]
    );
}
