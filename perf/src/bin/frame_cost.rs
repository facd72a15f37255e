//! The cost of frame snapshots (`snapshot::save_frame_into` and
//! `Space::load_frame_snapshot`) on a warmed scene, for
//! `docs/performance.md`'s rollback figures:
//! `frame_cost <snapshot file> [scene] [warm-up steps] [calls] [save|load|both]`.
//! If the file does not exist, builds the scene (default `bowl_boxes_500`),
//! steps it (default 300 steps, as `tamias bench --rollback`) and saves a
//! full snapshot there; then loads it and prints the frame's size and the
//! median time per save and per load (and, by default, per in-memory
//! `Space::save_frame` and `Space::restore_frame`) over 15 rounds of
//! `calls` calls. Run
//! it once to write the file, then under `perf record` or
//! `valgrind --tool=callgrind` with the one operation to study.
use std::hint::black_box;
use std::time::Instant;

use tamias2d::body::BodyType;
use tamias2d::snapshot;

fn median_ms(calls: u32, mut op: impl FnMut()) -> f64 {
    let mut rounds = Vec::with_capacity(15);
    for _ in 0..15 {
        let t = Instant::now();
        for _ in 0..calls {
            op();
        }
        rounds.push(t.elapsed().as_secs_f64() * 1e3 / f64::from(calls.max(1)));
    }
    rounds.sort_by(f64::total_cmp);
    rounds[rounds.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map_or("frame_cost.snap", String::as_str);
    let scene = args.get(2).map_or("bowl_boxes_500", String::as_str);
    let warmup: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(300);
    let calls: u32 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(200);
    let which = args.get(5).map_or("both", String::as_str);
    if std::fs::metadata(path).is_err() {
        let desc = tamias2d_scenes::builtin(scene).expect("a built-in scene");
        let mut world = desc.build().expect("the scene builds");
        world.step_n(warmup).expect("the warm-up steps");
        std::fs::write(path, snapshot::save(&world.space)).expect("the file is written");
    }
    let bytes = std::fs::read(path).expect("the file is read");
    let mut space = snapshot::load(&bytes).expect("a valid snapshot");
    let bodies = space.bodies().count();
    let moving = space
        .bodies()
        .filter(|(_, b)| b.body_type() != BodyType::Static)
        .count();
    let frame = snapshot::save_frame(&space);
    println!(
        "{path}: {bodies} bodies ({moving} moving), {} shapes, {} arbiters",
        space.shapes().count(),
        space.arbiters().len()
    );
    println!(
        "frame bytes: {} ({:.0} per moving body)",
        frame.len(),
        frame.len() as f64 / moving.max(1) as f64
    );
    let per_k = |ms: f64| ms * 1000.0 / bodies.max(1) as f64;
    if which != "load" {
        let mut buf = Vec::new();
        let ms = median_ms(calls, || {
            black_box(snapshot::save_frame_into(black_box(&space), &mut buf));
        });
        println!("save ms: {ms:.4} ({:.4} per 1000 bodies)", per_k(ms));
    }
    if which == "both" {
        // The in-memory frame (a copy into reused buffers, no coding).
        let mut frame = tamias2d::space::FrameState::default();
        let ms = median_ms(calls, || {
            black_box(&space).save_frame(&mut frame);
        });
        println!(
            "in-memory save_frame ms: {ms:.4} ({:.4} per 1000 bodies)",
            per_k(ms)
        );
        let ms = median_ms(calls, || {
            space
                .restore_frame(black_box(&frame))
                .expect("the frame restores");
        });
        println!(
            "in-memory restore_frame ms: {ms:.4} ({:.4} per 1000 bodies)",
            per_k(ms)
        );
    }
    if which != "save" {
        let ms = median_ms(calls, || {
            space
                .load_frame_snapshot(black_box(&frame))
                .expect("the frame loads");
        });
        println!("load ms: {ms:.4} ({:.4} per 1000 bodies)", per_k(ms));
    }
}
