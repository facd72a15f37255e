//! The cost of one contact solver iteration, for `docs/performance.md`'s
//! per-unit figures: `solver_cost [scene] [warm-up steps] [steps] [factor]`.
//!
//! Builds the scene (default `pyramid_20`) with sleeping off, steps the
//! warm-up (default 300), then from that state runs `steps` steps (default
//! 100) twice — at the scene's iterations and at `factor` (default 2) times as many — timing each
//! step, and prints the contacts per step and the median extra time per
//! extra iteration, per contact. Each extra iteration is the whole per-
//! contact kernel (rows and blocks, warm start excluded), so the difference
//! isolates it from the rest of the step. Instructions: run it under
//! `valgrind --tool=callgrind` with factor 2 and with factor 1; the
//! difference of the totals is `steps × base iterations` extra iterations.
use std::time::Instant;

use tamias2d::space::SLEEP_NEVER;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = args.get(1).map_or("pyramid_20", String::as_str);
    let warmup: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let steps: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(100);
    let factor: u32 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(2);
    let mut desc = tamias2d_scenes::builtin(scene).expect("a built-in scene");
    desc.settings.sleep_time_threshold = SLEEP_NEVER;
    let base_iterations = desc.settings.iterations;
    let mut world = desc.build().expect("the scene builds");
    world.step_n(warmup).expect("the warm-up steps");
    let start = tamias2d::snapshot::save(&world.space);

    let mut per_step = Vec::new();
    let mut contacts = 0usize;
    let more = base_iterations.saturating_mul(factor);
    for iterations in [base_iterations, more] {
        let mut space = tamias2d::snapshot::load(&start).expect("the saved state");
        space.set_iterations(iterations);
        let mut times = Vec::with_capacity(steps as usize);
        contacts = 0;
        for _ in 0..steps {
            let t = Instant::now();
            space.step(world.dt).expect("a step");
            times.push(t.elapsed().as_secs_f64() * 1e6);
            contacts += space.arbiters().iter().map(|a| a.count()).sum::<usize>();
        }
        times.sort_by(f64::total_cmp);
        per_step.push(times[times.len() / 2]);
    }
    let contacts = contacts as f64 / f64::from(steps.max(1));
    let extra = f64::from(more.saturating_sub(base_iterations).max(1));
    let per_iteration_us = (per_step[1] - per_step[0]) / extra;
    println!("scene: {scene} (warm-up {warmup}, {steps} steps, sleeping off)");
    println!("contacts per step: {contacts:.0}");
    println!(
        "step us at {} / {} iterations: {:.1} / {:.1}",
        base_iterations, more, per_step[0], per_step[1]
    );
    println!(
        "ns per contact per iteration: {:.1}",
        per_iteration_us * 1e3 / contacts.max(1.0)
    );
}
