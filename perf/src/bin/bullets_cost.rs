//! The `bullets` scene three ways, for `docs/tuning.md`: without the
//! bullet flags at 1 sub-step (tunnels), without them at 64 sub-steps (the
//! brute-force fix) and with them at 1 sub-step (continuous collision).
//! Prints, per variant, the median wall-clock time per step over `RUNS`
//! runs of the scene's 120 steps and the bullets beyond the wall.
//!
//! ```text
//! cargo run --release -p tamias2d-perf --bin bullets_cost
//! ```
use std::time::Instant;

use tamias2d_scenes::bullets::{tunnelled, without_bullets};
use tamias2d_scenes::SceneDesc;

/// Runs of the whole scene per variant.
const RUNS: usize = 5;

fn main() {
    let scene = tamias2d_scenes::builtin("bullets").expect("registered scene");
    let plain = without_bullets(scene.clone());
    let mut fine = plain.clone();
    fine.settings.substeps = 64;
    let variants: [(&str, &SceneDesc); 3] = [
        ("no bullets, 1 sub-step", &plain),
        ("no bullets, 64 sub-steps", &fine),
        ("bullets, 1 sub-step", &scene),
    ];
    println!("| variant | median ms/step | total ms (120 steps) | tunnelled (of 32) | checksum |");
    println!("|---|---|---|---|---|");
    for (name, desc) in variants {
        let mut times = Vec::new();
        let mut totals = Vec::new();
        let mut last = None;
        for _ in 0..RUNS {
            let mut w = desc.build().expect("valid scene");
            let start = Instant::now();
            for _ in 0..desc.steps {
                let t = Instant::now();
                w.step().expect("step");
                times.push(t.elapsed().as_secs_f64());
            }
            totals.push(start.elapsed().as_secs_f64());
            last = Some(w);
        }
        let w = last.expect("at least one run");
        println!(
            "| {name} | {:.4} | {:.2} | {} | {:#018x} |",
            median(&mut times) * 1e3,
            median(&mut totals) * 1e3,
            tunnelled(&w).unwrap_or(0),
            w.space.checksum()
        );
    }
}

fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs.get(xs.len() / 2).copied().unwrap_or(0.0)
}
