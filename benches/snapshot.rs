//! Snapshot benchmarks: byte snapshots (`save`, `load`, `load_snapshot`),
//! the in-memory path (`Space::clone`, `state().clone()`,
//! `restore_state`) and `checksum` on resting piles of about 100, 1,000
//! and 5,000 bodies, plus the rollback budget (`rollback`: the figures of
//! `tamias bench --rollback`, with an 8-frame rollback) of `bowl_boxes_500`,
//! `pyramid_100` and `level_30000`.
//!
//! Piles: `bowl_boxes_100` and `bowl_boxes_1000` after 600 steps (10 s:
//! dropped, landed and at rest), and `pyramid_100` (5,050 unit boxes,
//! Box2D's large pyramid, stacked from the start) after 120 steps. Before
//! measuring, each prints its snapshot size per body, arbiters per body and
//! largest body speed (a resting pile has small speeds), and the sizes of
//! the circle and hexagon piles for comparison.
//!
//! Targets (not enforced): ≤ 300 bytes per body in a resting
//! pile; per 1,000 bodies save ≤ 0.1 ms, load ≤ 0.2 ms, checksum ≤ 0.02 ms;
//! 8-frame rollback of the 500-box pile ≤ 4 ms.
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tamias2d::snapshot;
use tamias2d::space::{FrameState, Space, SLEEP_NEVER};
use tamias2d::Real;
use tamias2d_scenes as scenes;

/// A built-in scene stepped `warmup` times, with its time step.
fn resting(name: &str, warmup: u32) -> (Space, Real) {
    let desc = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
    let mut scene = desc
        .build()
        .unwrap_or_else(|e| panic!("scene {name} builds: {e}"));
    scene
        .step_n(warmup)
        .unwrap_or_else(|e| panic!("scene {name} steps: {e}"));
    (scene.space, scene.dt)
}

/// Prints size per body and how restful the pile is.
fn report(name: &str, space: &Space) {
    let bytes = snapshot::save(space).len();
    let bodies = space.bodies().count();
    let top_speed = space
        .bodies()
        .map(|(_, b)| b.velocity().length())
        .max()
        .unwrap_or(Real::ZERO);
    eprintln!(
        "{name}: {bodies} bodies, {} shapes, {} arbiters ({:.2} per body); \
         snapshot {bytes} bytes = {:.0} bytes per body; top speed {top_speed:.3}",
        space.shapes().count(),
        space.arbiters().len(),
        space.arbiters().len() as f64 / bodies as f64,
        bytes as f64 / bodies as f64,
    );
}

const PILES: &[(&str, u32)] = &[
    ("bowl_boxes_100", 600),
    ("bowl_boxes_1000", 600),
    ("pyramid_100", 120),
];

fn piles(c: &mut Criterion) {
    for name in ["bowl_circles_1000", "bowl_hexagons_1000"] {
        report(name, &resting(name, 600).0);
    }
    for &(name, warmup) in PILES {
        let (space, _) = resting(name, warmup);
        report(name, &space);
        let bodies = space.bodies().count();
        let bytes = snapshot::save(&space);
        let state = space.state().clone();
        let mut group = c.benchmark_group("snapshot");
        let id = |what: &str| BenchmarkId::new(what, format!("{name} ({bodies} bodies)"));

        let mut buf = Vec::new();
        group.bench_function(id("save_into"), |b| {
            b.iter(|| snapshot::save_into(black_box(&space), &mut buf))
        });
        group.bench_function(id("save"), |b| b.iter(|| snapshot::save(black_box(&space))));
        group.bench_function(id("load"), |b| {
            b.iter(|| snapshot::load(black_box(&bytes)).unwrap_or_else(|e| panic!("{e}")))
        });
        let mut live = space.clone();
        group.bench_function(id("load_snapshot"), |b| {
            b.iter(|| {
                live.load_snapshot(black_box(&bytes))
                    .unwrap_or_else(|e| panic!("{e}"))
            })
        });
        group.bench_function(id("space_clone"), |b| b.iter(|| black_box(&space).clone()));
        group.bench_function(id("state_clone"), |b| {
            b.iter(|| black_box(&space).state().clone())
        });
        group.bench_function(id("restore_state"), |b| {
            b.iter(|| live.restore_state(black_box(&state)))
        });
        group.bench_function(id("checksum"), |b| b.iter(|| black_box(&space).checksum()));
        group.bench_function(id("checksum_parts"), |b| {
            b.iter(|| snapshot::checksum_parts(black_box(&space)))
        });
        group.finish();
    }
}

/// The rollback budget (`tamias bench --rollback` prints the same figures,
/// `docs/performance.md`, "Rollback budget"): for `bowl_boxes_500` after
/// 300 steps, `pyramid_100` after 120 and `level_30000` (30,000 static
/// segments in 300 pieces, 10 movers) after 60 (and `level_300`, the same
/// movers on a level 100 times smaller), as defined (sleeping on):
/// `save_frame_into`, `load_frame_snapshot`, the full snapshot's
/// `save_into` and `load_snapshot`, `checksum`, one step, one step of the
/// same scene with sleeping off, and an 8-frame rollback: load the frame
/// snapshot of the confirmed frame, then re-simulate 8 frames, saving and
/// checksumming each (what a rollback netcode does when a late input
/// arrives); also its in-memory form (`restore_frame`, and `save_frame`
/// per frame into a ring), the same through full snapshots, and the 8
/// steps alone.
const ROLLBACK_SCENES: &[(&str, u32)] = &[
    ("bowl_boxes_500", 300),
    ("pyramid_100", 120),
    ("level_300", 60),
    ("level_30000", 60),
];

fn rollback(c: &mut Criterion) {
    for &(name, warmup) in ROLLBACK_SCENES {
        let (space, dt) = resting(name, warmup);
        report(name, &space);
        eprintln!("{name}: {} bodies asleep", space.sleeping_bodies());
        let bodies = space.bodies().count();
        let label = format!("{name} ({bodies} bodies)");
        let confirmed = snapshot::save_frame(&space);
        let full = snapshot::save(&space);
        let mut saved = FrameState::default();
        space.save_frame(&mut saved);
        let mut group = c.benchmark_group("rollback_budget");
        let id = |what: &str| BenchmarkId::new(what, &label);

        let mut buf = Vec::new();
        group.bench_function(id("save_frame_into"), |b| {
            b.iter(|| snapshot::save_frame_into(black_box(&space), &mut buf))
        });
        let mut live = space.clone();
        group.bench_function(id("load_frame_snapshot"), |b| {
            b.iter(|| {
                live.load_frame_snapshot(black_box(&confirmed))
                    .unwrap_or_else(|e| panic!("{e}"))
            })
        });
        group.bench_function(id("save_into_full"), |b| {
            b.iter(|| snapshot::save_into(black_box(&space), &mut buf))
        });
        group.bench_function(id("load_snapshot_full"), |b| {
            b.iter(|| {
                live.load_snapshot(black_box(&full))
                    .unwrap_or_else(|e| panic!("{e}"))
            })
        });
        group.bench_function(id("checksum"), |b| b.iter(|| black_box(&space).checksum()));

        let mut stepper = space.clone();
        group.bench_function(id("step"), |b| {
            b.iter(|| stepper.step(dt).unwrap_or_else(|e| panic!("{e}")))
        });
        let mut off = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
        off.settings.sleep_time_threshold = SLEEP_NEVER;
        let mut awake = off.build().unwrap_or_else(|e| panic!("{name}: {e}"));
        awake
            .step_n(warmup)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        group.bench_function(id("step_sleep_off"), |b| {
            b.iter(|| awake.space.step(dt).unwrap_or_else(|e| panic!("{e}")))
        });

        let mut frames: Vec<Vec<u8>> = vec![Vec::new(); 8];
        group.bench_function(id("rollback_8_frames"), |b| {
            b.iter(|| {
                live.load_frame_snapshot(black_box(&confirmed))
                    .unwrap_or_else(|e| panic!("{e}"));
                for frame in &mut frames {
                    live.step(dt).unwrap_or_else(|e| panic!("{e}"));
                    snapshot::save_frame_into(&live, frame);
                    black_box(live.checksum());
                }
            })
        });

        let mut ring: Vec<_> = vec![saved.clone(); 8];
        group.bench_function(id("rollback_8_frames_in_memory"), |b| {
            b.iter(|| {
                live.restore_frame(black_box(&saved))
                    .unwrap_or_else(|e| panic!("{e}"));
                for frame in &mut ring {
                    live.step(dt).unwrap_or_else(|e| panic!("{e}"));
                    live.save_frame(frame);
                    black_box(live.checksum());
                }
            })
        });

        group.bench_function(id("rollback_8_frames_full_snapshots"), |b| {
            b.iter(|| {
                live.load_snapshot(black_box(&full))
                    .unwrap_or_else(|e| panic!("{e}"));
                for frame in &mut frames {
                    live.step(dt).unwrap_or_else(|e| panic!("{e}"));
                    snapshot::save_into(&live, frame);
                    black_box(live.checksum());
                }
            })
        });

        group.bench_function(id("steps_only_8_frames"), |b| {
            b.iter(|| {
                live.restore_frame(black_box(&saved))
                    .unwrap_or_else(|e| panic!("{e}"));
                for _ in 0..8 {
                    live.step(dt).unwrap_or_else(|e| panic!("{e}"));
                }
            })
        });
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(500));
    targets = piles, rollback
}
criterion_main!(benches);
