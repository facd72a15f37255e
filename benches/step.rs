//! Whole-step benchmarks on the standard scenes (BENCH_SCENES.md).
//!
//! Each scene is built, warmed up for a number of steps (so piles have
//! formed and warm starting is in effect), and then one `Scene::step` is
//! measured: the real code path, scripted events included. The broadphase
//! group also prints the candidate-pair count per body, which must stay
//! about constant as the body count grows (no quadratic broadphase).
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use tamias2d::scenes;

fn warmed(name: &str, warmup: u32) -> scenes::Scene {
    let desc = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
    let mut scene = desc
        .build()
        .unwrap_or_else(|e| panic!("scene {name} builds: {e}"));
    scene
        .step_n(warmup)
        .unwrap_or_else(|e| panic!("scene {name} steps: {e}"));
    scene
}

fn bench_scene(c: &mut Criterion, group: &str, name: &str, warmup: u32) {
    let mut scene = warmed(name, warmup);
    let stats = scene.space.last_step_stats();
    let bodies = scene.space.bodies().count();
    eprintln!(
        "{name}: {bodies} bodies, {} candidate pairs ({:.2} per body), {} touching, {} contacts",
        stats.candidate_pairs,
        stats.candidate_pairs as f64 / bodies as f64,
        stats.touching_pairs,
        stats.solver_contacts
    );
    c.benchmark_group(group).bench_function(name, |b| {
        b.iter(|| {
            scene.step().unwrap_or_else(|e| panic!("step: {e}"));
            black_box(&scene.space);
        })
    });
}

fn broadphase(c: &mut Criterion) {
    bench_scene(c, "broadphase", "no_collide", 100);
    for n in ["bowl_circles_100", "bowl_circles_500", "bowl_circles_1000"] {
        bench_scene(c, "broadphase", n, 300);
    }
}

fn stacking(c: &mut Criterion) {
    for n in ["pyramid_20", "bowl_boxes_500", "bowl_hexagons_500"] {
        bench_scene(c, "stacking", n, 300);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(4)).warm_up_time(Duration::from_secs(1));
    targets = broadphase, stacking
}
criterion_main!(benches);
