//! The time per step of the soft step's full and narrow contact kernels
//! (`ContactPrecision`), side by side: `narrow_cost [--samples N]
//! [--steps K] [SCENE ...]` (default `pyramid_20 many_pyramids_4x4
//! bowl_boxes_500 rain_1000`, 30 samples of 10 steps).
//!
//! Each scene runs on the soft step with sleeping off, one thread and the
//! fastest kernels of this processor (`Kernels::Auto`). Each precision
//! steps 120 steps to warm up and saves that state; then each sample
//! restores both states in turn and times `K` steps of each, so both see
//! the same moments of a noisy machine. Printed: the median time per step
//! of each, and the median of the per-sample ratios narrow ÷ full.
use std::time::Instant;

use tamias2d::space::{ContactPrecision, SLEEP_NEVER};
use tamias2d_scenes::{SoftStepDesc, SolverDesc};

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() {
    let mut samples = 30usize;
    let mut steps = 10u32;
    let mut scenes = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--samples" => samples = args.next().and_then(|s| s.parse().ok()).unwrap_or(30),
            "--steps" => steps = args.next().and_then(|s| s.parse().ok()).unwrap_or(10),
            _ => scenes.push(a),
        }
    }
    if scenes.is_empty() {
        scenes = [
            "pyramid_20",
            "many_pyramids_4x4",
            "bowl_boxes_500",
            "rain_1000",
        ]
        .map(String::from)
        .to_vec();
    }
    println!(
        "| scene | full ms/step | narrow ms/step | narrow ÷ full (median of {samples} samples) |"
    );
    println!("|---|---:|---:|---:|");
    for scene in &scenes {
        let mut desc = tamias2d_scenes::builtin(scene).expect("a built-in scene");
        desc.settings.sleep_time_threshold = SLEEP_NEVER;
        desc.settings.use_soft_step();
        let mut states = Vec::new();
        let mut dt = None;
        for precision in [ContactPrecision::Full, ContactPrecision::Narrow] {
            let mut d = desc.clone();
            if let SolverDesc::Soft(SoftStepDesc(soft)) = &mut d.settings.solver {
                soft.contact_precision = precision;
            }
            let mut world = d.build().expect("the scene builds");
            world.space.set_threads(1).expect("one thread");
            world.step_n(120).expect("the warm-up steps");
            dt = Some(world.dt);
            states.push(tamias2d::snapshot::save(&world.space));
        }
        let dt = dt.expect("a time step");
        let mut times = [Vec::new(), Vec::new()];
        let mut ratios = Vec::new();
        for _ in 0..samples {
            let mut per = [0.0f64; 2];
            for (k, state) in states.iter().enumerate() {
                let mut space = tamias2d::snapshot::load(state).expect("the saved state");
                space.set_threads(1).expect("one thread");
                let t = Instant::now();
                for _ in 0..steps {
                    space.step(dt).expect("a step");
                }
                per[k] = t.elapsed().as_secs_f64() * 1e3 / f64::from(steps);
                times[k].push(per[k]);
            }
            ratios.push(per[1] / per[0]);
        }
        let [full, narrow] = &mut times;
        println!(
            "| {scene} | {:.3} | {:.3} | {:.2} |",
            median(full),
            median(narrow),
            median(&mut ratios)
        );
    }
}
