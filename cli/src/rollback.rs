//! `tamias bench --rollback`: the rollback budget of a scene, one line per
//! figure (`docs/performance.md`, "Rollback budget").
//!
//! A rollback game at 60 Hz re-simulates up to 8 frames inside one frame:
//! it loads the confirmed frame's snapshot, then steps, saves and
//! checksums each of the 8 frames again. For each scene, built and warmed
//! up as defined (sleeping on, so a settled pile may be asleep: the count
//! is printed), this prints the median over the samples of:
//!
//! * `snapshot bytes`: the frame snapshot (`snapshot::save_frame`: what a
//!   step can change, the static level named by its digest) of the warm
//!   world, and its bodies;
//! * `save`: `snapshot::save_frame_into` a reused buffer; `load`:
//!   `Space::load_frame_snapshot` (decoding and validating) into a live
//!   world; `checksum`: `Space::checksum`; each also per 1,000 bodies;
//!   then the full, self-contained snapshot's size, save and load
//!   (`snapshot::save_into`, `Space::load_snapshot`) for comparison;
//! * `step ms`: one step as defined, then one step of the same scene
//!   built with sleeping off and warmed up the same way;
//! * `rollback 8 frames ms`: `load_frame_snapshot` + 8 × (step +
//!   `save_frame_into` + `checksum`), always from the same confirmed frame;
//!   the in-memory form: `restore_frame` + 8 × (step + `save_frame` into a
//!   ring of 8 + `checksum`); the same through full snapshots
//!   (`load_snapshot`, `save_into`); and `restore_frame` + 8 steps alone
//!   (the part of a rollback that is stepping: a step right after a
//!   restore may cost more than `step ms`, which continues a running
//!   world).
//!
//! Wall-clock time of one process (`benches/snapshot.rs` measures the same
//! figures under criterion).
use std::time::Instant;

use tamias2d::body::BodyType;
use tamias2d::snapshot;
use tamias2d::space::{FrameState, Space, SLEEP_NEVER};
use tamias2d::Real;
use tamias2d_scenes as scenes;

use crate::run::median;
use crate::source;

/// The scenes of `tamias bench --rollback` without `--scene`.
/// `level_300` is there to compare with `level_30000`: the same 10 movers
/// on a level 100 times smaller.
pub const DEFAULT_SCENES: &[&str] = &["bowl_boxes_500", "pyramid_100", "level_300", "level_30000"];

/// Frames re-simulated by one rollback.
const FRAMES: usize = 8;

/// A sample is at least this long (fast operations are repeated).
const MIN_SAMPLE_S: f64 = 1e-3;

/// Warm-up steps of `name` unless `--warmup` says otherwise: a bowl pile
/// 300 steps (5 s: landed, contacts in place), a pyramid 120 (stacked from
/// the start), anything else 60 (a level's movers have landed).
pub fn default_warmup(name: &str) -> u32 {
    if name.starts_with("bowl_") {
        300
    } else if name.starts_with("pyramid_") {
        120
    } else {
        60
    }
}

/// `tamias bench --rollback`.
pub fn rollback(
    names: &[String],
    warmup: Option<u32>,
    samples: u32,
    solver: Option<source::SolverChoice>,
    kernels: tamias2d::space::Kernels,
) -> Result<(), String> {
    let names: Vec<String> = if names.is_empty() {
        DEFAULT_SCENES.iter().map(|s| (*s).to_owned()).collect()
    } else {
        names.to_vec()
    };
    let mut descs = Vec::with_capacity(names.len());
    for name in &names {
        let mut desc = scenes::builtin(name)
            .ok_or_else(|| format!("unknown scene {name:?} (`tamias list` shows the scenes)"))?;
        if let Some(solver) = solver {
            solver.apply(&mut desc.settings);
        }
        descs.push(desc);
    }
    if cfg!(debug_assertions) {
        eprintln!(
            "note: a debug build; `cargo run --release -- bench --rollback` gives meaningful numbers"
        );
    }
    println!(
        "rollback budget: {} scenes{}, {} kernels, medians of {samples} samples; \
         rollback = load + {FRAMES} x (step + save + checksum)",
        descs.len(),
        match solver {
            Some(source::SolverChoice::Soft) => ", soft step",
            Some(source::SolverChoice::SoftNarrow) => ", soft step, narrow contacts",
            Some(source::SolverChoice::Sequential) => ", sequential impulses",
            None => "",
        },
        kernels.describe()
    );
    for desc in &descs {
        let steps = warmup.unwrap_or_else(|| default_warmup(&desc.name));
        measure(desc, steps, samples, kernels).map_err(|e| format!("scene {}: {e}", desc.name))?;
    }
    Ok(())
}

/// Builds `desc`, steps it `warmup` times and returns the world and its dt.
fn warm(
    desc: &scenes::SceneDesc,
    warmup: u32,
    kernels: tamias2d::space::Kernels,
) -> Result<(Space, Real), String> {
    let mut sim = source::build(desc)?;
    sim.space.set_kernels(kernels);
    for _ in 0..warmup {
        sim.step().map_err(|e| e.to_string())?;
    }
    Ok((sim.space, sim.dt))
}

/// Median ms of `op` over `samples` samples, each repeating `op` until it
/// lasts [`MIN_SAMPLE_S`] (the repeat count is set by a first call).
fn median_ms(samples: u32, mut op: impl FnMut() -> Result<(), String>) -> Result<f64, String> {
    let t = Instant::now();
    op()?;
    let once = t.elapsed().as_secs_f64().max(1e-9);
    let reps = (MIN_SAMPLE_S / once).ceil().clamp(1.0, 100_000.0) as u32;
    let mut per_op = Vec::with_capacity(samples as usize);
    for _ in 0..samples {
        let t = Instant::now();
        for _ in 0..reps {
            op()?;
        }
        per_op.push(t.elapsed().as_secs_f64() * 1e3 / f64::from(reps));
    }
    Ok(median(&per_op))
}

/// Measures and prints one scene.
fn measure(
    desc: &scenes::SceneDesc,
    warmup: u32,
    samples: u32,
    kernels: tamias2d::space::Kernels,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (space, dt) = warm(desc, warmup, kernels)?;
    let bodies = space.bodies().count();
    let moving = space
        .bodies()
        .filter(|(_, b)| b.body_type() != BodyType::Static)
        .count();
    let asleep = space.sleeping_bodies();
    let per_k = |ms: f64| ms * 1000.0 / bodies.max(1) as f64;
    println!(
        "{} (warm-up {warmup} steps): {bodies} bodies ({moving} moving, {asleep} asleep), \
         {} shapes, {} arbiters",
        desc.name,
        space.shapes().count(),
        space.arbiters().len()
    );

    // The per-frame path of a rollback game: frame snapshots (the level
    // named by its digest, see `tamias2d::space::FrameState`).
    let confirmed = snapshot::save_frame(&space);
    let full = snapshot::save(&space);
    let mut buf = Vec::new();
    let save = median_ms(samples, || {
        snapshot::save_frame_into(&space, &mut buf);
        Ok(())
    })?;
    let mut live = space.clone();
    let load = median_ms(samples, || {
        live.load_frame_snapshot(&confirmed).map_err(|e| err(&e))
    })?;
    let checksum = median_ms(samples, || {
        std::hint::black_box(space.checksum());
        Ok(())
    })?;
    let full_save = median_ms(samples, || {
        snapshot::save_into(&space, &mut buf);
        Ok(())
    })?;
    let full_load = median_ms(samples, || live.load_snapshot(&full).map_err(|e| err(&e)))?;

    let mut stepper = space.clone();
    let step = median_ms(samples, || stepper.step(dt).map_err(|e| err(&e)))?;
    let (asleep_after, steps_timed) = (
        stepper.sleeping_bodies(),
        stepper.steps().saturating_sub(space.steps()),
    );
    let mut off = desc.clone();
    off.settings.sleep_time_threshold = SLEEP_NEVER;
    let (mut awake, _) = warm(&off, warmup, kernels)?;
    let step_off = median_ms(samples, || awake.step(dt).map_err(|e| err(&e)))?;

    let mut frames: Vec<Vec<u8>> = vec![Vec::new(); FRAMES];
    let rollback = median_ms(samples, || {
        live.load_frame_snapshot(&confirmed).map_err(|e| err(&e))?;
        for frame in &mut frames {
            live.step(dt).map_err(|e| err(&e))?;
            snapshot::save_frame_into(&live, frame);
            std::hint::black_box(live.checksum());
        }
        Ok(())
    })?;
    let mut saved = FrameState::default();
    space.save_frame(&mut saved);
    let mut ring = vec![saved.clone(); FRAMES];
    let in_memory = median_ms(samples, || {
        live.restore_frame(&saved).map_err(|e| err(&e))?;
        for frame in &mut ring {
            live.step(dt).map_err(|e| err(&e))?;
            live.save_frame(frame);
            std::hint::black_box(live.checksum());
        }
        Ok(())
    })?;
    let full_rollback = median_ms(samples, || {
        live.load_snapshot(&full).map_err(|e| err(&e))?;
        for frame in &mut frames {
            live.step(dt).map_err(|e| err(&e))?;
            snapshot::save_into(&live, frame);
            std::hint::black_box(live.checksum());
        }
        Ok(())
    })?;

    let steps_only = median_ms(samples, || {
        live.restore_frame(&saved).map_err(|e| err(&e))?;
        for _ in 0..FRAMES {
            live.step(dt).map_err(|e| err(&e))?;
        }
        Ok(())
    })?;

    println!("  snapshot bytes: {} ({bodies} bodies)", confirmed.len());
    println!(
        "  snapshot bytes per moving body: {:.0}",
        confirmed.len() as f64 / moving.max(1) as f64
    );
    println!("  save ms per 1000 bodies: {:.3}", per_k(save));
    println!("  load ms per 1000 bodies: {:.3}", per_k(load));
    println!("  checksum ms per 1000 bodies: {:.3}", per_k(checksum));
    println!("  save / load / checksum ms: {save:.4} / {load:.4} / {checksum:.4}");
    println!("  full snapshot bytes: {}", full.len());
    println!("  full snapshot save / load ms: {full_save:.3} / {full_load:.3}");
    println!(
        "  step ms: {step:.3} (asleep: {asleep} of {bodies} bodies at the start, \
         {asleep_after} after the {steps_timed} steps timed)"
    );
    println!("  step ms, sleeping off: {step_off:.3}");
    println!("  rollback {FRAMES} frames ms: {rollback:.3}");
    println!("  rollback {FRAMES} frames in memory ms: {in_memory:.3}");
    println!("  rollback {FRAMES} frames, full snapshots ms: {full_rollback:.3}");
    println!("  restore + {FRAMES} steps ms: {steps_only:.3}");
    Ok(())
}
