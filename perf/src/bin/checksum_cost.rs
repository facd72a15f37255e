//! The cost of `Space::checksum` on a warmed scene, for
//! `docs/performance.md`'s checksum figure:
//! `checksum_cost <snapshot file> [scene] [warm-up steps] [calls]`.
//! If the file does not exist, builds the scene (default `bowl_boxes_500`),
//! steps it (default 300 steps, as `tamias bench --rollback`) and saves it
//! there; then loads it and prints the checksum, the median time per
//! checksum over 15 rounds of `calls` calls, and the state's size. Run it
//! once to write the file, then under
//! `valgrind --tool=callgrind --toggle-collect='tamias2d::space::Space::checksum'`
//! with `calls` 1: the count covers 16 checksums (the printed one and 15
//! rounds of one), not the load or the warm-up; divide by 16.
use std::hint::black_box;
use std::time::Instant;

use tamias2d::snapshot;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map_or("checksum_cost.snap", String::as_str);
    let scene = args.get(2).map_or("bowl_boxes_500", String::as_str);
    let warmup: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(300);
    let calls: u32 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1000);
    if std::fs::metadata(path).is_err() {
        let desc = tamias2d_scenes::builtin(scene).expect("a built-in scene");
        let mut world = desc.build().expect("the scene builds");
        world.step_n(warmup).expect("the warm-up steps");
        std::fs::write(path, snapshot::save(&world.space)).expect("the file is written");
    }
    let bytes = std::fs::read(path).expect("the file is read");
    let space = snapshot::load(&bytes).expect("a valid snapshot");
    let bodies = space.bodies().count();
    println!(
        "{path}: {bodies} bodies, {} shapes, {} arbiters",
        space.shapes().count(),
        space.arbiters().len()
    );
    println!("checksum: {:#018x}", space.checksum());
    let mut rounds = Vec::with_capacity(15);
    for _ in 0..15 {
        let t = Instant::now();
        for _ in 0..calls {
            black_box(black_box(&space).checksum());
        }
        rounds.push(t.elapsed().as_secs_f64() * 1e3 / f64::from(calls.max(1)));
    }
    rounds.sort_by(f64::total_cmp);
    let ms = rounds[rounds.len() / 2];
    println!(
        "checksum ms: {ms:.4} ({:.4} per 1000 bodies)",
        ms * 1000.0 / bodies.max(1) as f64
    );
}
