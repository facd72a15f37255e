//! The level figure of the rollback budget: one box on a flat static
//! level of 30,000 unit segments against the same box on a level of 10,
//! after 30 steps (it rests). Prints, for each, the median time of a step
//! (the box awake: each sample starts from the same saved frame), of
//! `snapshot::save_frame_into` and of `Space::checksum`, and their ratios
//! (`docs/performance.md`, "Rollback budget"):
//! `cargo run --release -p tamias2d-perf --bin level_ratio [big segments] [small segments]`.
//! The `tamias bench --rollback` scenes `level_30000` and `level_300` differ
//! from these in more than their size (ten movers, and terrain of another
//! phase under them), so their ratios answer a different question.
use std::hint::black_box;
use std::time::Instant;

use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::snapshot;
use tamias2d::space::{FrameState, Space};

/// `segments` unit segments in a row on one static body, a 1×1 box resting
/// on them after 30 steps.
fn level_world(segments: i32) -> Space {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = w.add_body(Body::new_static()).expect("the level body");
    for i in 0..segments {
        let x = i - segments / 2;
        let seg = Shape::segment_shape_new(
            ground,
            Vect::from_ints(x, 0),
            Vect::from_ints(x + 1, 0),
            Real::ZERO,
        )
        .expect("a segment");
        w.add_shape(seg).expect("the segment is added");
    }
    let b = w
        .add_body(Body::new(Real::ONE, Real::ONE).expect("a box body"))
        .expect("the box body is added");
    w.body_mut(b)
        .expect("the box")
        .set_position(Vect::new(Real::ZERO, Real::HALF));
    let shape = Shape::box_shape_new(b, Real::ONE, Real::ONE, Real::ZERO)
        .expect("a box")
        .with_material(Real::ONE, Real::ZERO)
        .expect("a material");
    w.add_shape(shape).expect("the box is added");
    for _ in 0..30 {
        w.step(dt()).expect("a step");
    }
    w
}

fn dt() -> Real {
    Real::ONE / Real::from_int(60)
}

/// Median µs per call over 21 samples of `calls` calls each.
fn median_us(calls: u32, mut op: impl FnMut()) -> f64 {
    let mut samples: Vec<f64> = (0..21)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..calls {
                op();
            }
            t.elapsed().as_secs_f64() * 1e6 / f64::from(calls.max(1))
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// Step, save and checksum µs of one box on a level of `segments`.
fn figures(segments: i32) -> [f64; 3] {
    let mut w = level_world(segments);
    println!(
        "{segments} segments: {} arbiters, restore and 8 steps timed",
        w.arbiters().len()
    );
    let mut frame = FrameState::default();
    w.save_frame(&mut frame);
    // A step from the same frame each time: 8 steps per restore, the
    // restore's own cost taken off.
    let restore = median_us(2000, || w.restore_frame(&frame).expect("restores"));
    let step = median_us(200, || {
        w.restore_frame(&frame).expect("restores");
        for _ in 0..8 {
            w.step(dt()).expect("a step");
        }
    });
    let step = (step - restore) / 8.0;
    w.restore_frame(&frame).expect("restores");
    let mut buf = Vec::new();
    let save = median_us(2000, || {
        black_box(snapshot::save_frame_into(black_box(&w), &mut buf));
    });
    let checksum = median_us(2000, || {
        black_box(black_box(&w).checksum());
    });
    [step, save, checksum]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let big: i32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(30_000);
    let small: i32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let (b, s) = (figures(big), figures(small));
    for (k, what) in ["step", "save", "checksum"].iter().enumerate() {
        println!(
            "{what} µs: {:.3} on {big} segments, {:.3} on {small}: {:.2}×",
            b[k],
            s[k],
            b[k] / s[k]
        );
    }
}
