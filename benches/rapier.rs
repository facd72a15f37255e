//! Tamias2D beside Rapier2D on the standard scenes (scenes/README.md A and B).
//!
//! Both engines are built from the *same* [`SceneDesc`](tamias2d_scenes::SceneDesc)
//! (the converter is `common::rapier_world`): same bodies, shapes,
//! materials (product combine rule), gravity, `dt` and 10 solver iterations;
//! scripted forces and spawns replayed the same way. Each scene is warmed up
//! (300 steps, or until the rain has all been released), then criterion
//! times one step of each engine; the scene keeps evolving while it is
//! measured, identically for both.
//!
//! ```text
//! cargo bench --bench rapier                         # CI-sized and full-sized scenes
//! TAMIAS_BENCH_QUICK=1 cargo bench --bench rapier    # CI-sized only, short samples (< 2 min)
//! TAMIAS_BENCH_SCENES=pyramid_20,rain_1000 cargo bench --bench rapier
//! ```
//! After criterion's own output, a table gives per scene the median time
//! per step of each engine (median of criterion's samples, each sample's
//! time divided by its iteration count) and the ratio Tamias2D / Rapier.
//! The two medians of a row come from the same run: on a shared machine
//! compare ratios, not absolute times across runs.
#![allow(clippy::float_arithmetic)] // timing report only

use tamias2d_scenes::bench as common;

use std::hint::black_box;
use std::time::{Duration, Instant};
use tamias2d_scenes::shared::Shared;

use common::{Config, Engine, RapierRun, TamiasRun};
use criterion::Criterion;

/// Per-iteration times of the samples criterion asked for, in seconds.
type Samples = Shared<Vec<f64>>;

/// Times one step of `engine` with criterion and returns the median of its
/// samples (seconds per step).
fn bench_engine(
    c: &mut Criterion,
    scene: &str,
    engine: &mut dyn Engine,
    sample_size: usize,
) -> Option<f64> {
    let samples: Samples = Shared::new(Vec::new());
    let record = Shared::clone(&samples);
    let id = format!("{}/{}", scene, engine.name().to_lowercase());
    c.bench_function(&id, |b| {
        b.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                engine.step();
            }
            let elapsed = start.elapsed();
            black_box(&*engine);
            record
                .borrow_mut()
                .push(elapsed.as_secs_f64() / iters.max(1) as f64);
            elapsed
        });
    });
    let mut all = samples.borrow().clone();
    if all.is_empty() {
        return None; // filtered out by criterion's command line filter
    }
    // Warm-up calls come first; the last `sample_size` calls are the samples.
    let start = all.len().saturating_sub(sample_size);
    Some(common::median(&mut all[start..]))
}

fn main() {
    let quick = std::env::var("TAMIAS_BENCH_QUICK").is_ok_and(|v| v != "0" && !v.is_empty());
    let only: Option<Vec<String>> = std::env::var("TAMIAS_BENCH_SCENES")
        .ok()
        .map(|s| s.split(',').map(|n| n.trim().to_owned()).collect());
    // `cargo test --benches` runs bench binaries with `--test`: keep that cheap.
    let test_mode = std::env::args().any(|a| a == "--test");
    let sample_size = if quick { 10 } else { 20 };
    let mut c = Criterion::default()
        .sample_size(sample_size)
        .warm_up_time(Duration::from_millis(if quick { 200 } else { 1000 }))
        .measurement_time(Duration::from_millis(if quick { 600 } else { 3000 }))
        .configure_from_args();

    let mut names: Vec<&str> = common::ci_scenes();
    if !quick && !test_mode {
        names.extend(common::full_scenes());
    }
    if let Some(only) = &only {
        let known: Vec<&str> = common::ci_scenes()
            .into_iter()
            .chain(common::full_scenes())
            .collect();
        names = known
            .into_iter()
            .filter(|n| only.iter().any(|o| o == n))
            .collect();
    }

    let mut rows = Vec::new();
    for name in names {
        let desc = common::scene_with(name, Config::DEFAULT);
        let warmup = if test_mode {
            1
        } else {
            common::warmup_steps(name)
        };
        let mut tamias = TamiasRun::new(&desc, Config::DEFAULT);
        let mut rapier = RapierRun::new(&desc, Config::DEFAULT, common::length_unit(name));
        for _ in 0..warmup {
            tamias.step();
            rapier.step();
        }
        let t = bench_engine(&mut c, name, &mut tamias, sample_size);
        let r = bench_engine(&mut c, name, &mut rapier, sample_size);
        rows.push((name, t, r));
    }
    c.final_summary();

    if test_mode {
        return;
    }
    println!();
    println!("median time per step (ms), same run for both engines");
    println!(
        "{:<22} {:>10} {:>10} {:>16}",
        "scene", "Tamias2D", "Rapier", "Tamias2D/Rapier"
    );
    for (name, t, r) in rows {
        let ms = |x: Option<f64>| x.map_or("-".to_owned(), |s| format!("{:.3}", s * 1e3));
        let ratio = match (t, r) {
            (Some(t), Some(r)) if r > 0.0 => format!("{:.2}", t / r),
            _ => "-".to_owned(),
        };
        println!("{name:<22} {:>10} {:>10} {ratio:>16}", ms(t), ms(r));
    }
}
