//! The parallel step's figures for `docs/performance.md` ("The parallel
//! step"): `parallel_cost [--quality] [--soft] [--narrow] [--scalar] [--threads N]
//! [--samples N] [--quantile Q] [scene...]`.
//!
//! **Speed** (default): each scene (default `pyramid_100`,
//! `many_pyramids_10x10`, `bowl_boxes_1000`, `rain_4000`) with sleeping
//! off (as the side-by-side with Rapier), warmed up 120 steps, then timed
//! in samples of 10 steps, the four configurations (canonical or colored
//! solver, 1 or N threads, default N = 2) taking turns sample by sample so
//! that the machine's drift hits them alike. Prints the median ms per step
//! of each and the speed-ups, and checks that the thread counts agree bit
//! for bit (the checksums after the run).
//!
//! **Quality** (`--quality`): the colored solver against the canonical one
//! on the stacking scenes, what the side-by-side reports: the largest
//! displacement of a dynamic body after 10 s (`stack_10`: the top box's
//! sideways drift) and the deepest and mean penetration over the last
//! second. Deterministic: the same figures on every machine.
//! `--iterations N` runs every world at N solver iterations (a point of the
//! trade curve: what the colored order needs to match the canonical one).
//!
//! `--quantile Q` prints the Q-th percentile of the samples instead of the
//! median (`--quantile 10`: the runs the machine disturbed least, the
//! steadier figure for comparing two builds on a shared machine).
//!
//! `--soft` times the soft step instead (always in the colored order): 1
//! against N threads. `--narrow` times the soft step with the narrow
//! contact kernels. `--scalar` runs the scalar contact kernels on both
//! (by default the wide ones, where the processor has AVX2).
//!
//! Needs the `parallel` feature, which `perf/Cargo.toml` turns on:
//! `cargo run --release -p tamias2d-perf --bin parallel_cost` (from the
//! repository root).
use std::time::Instant;

use tamias2d::math::Real;
use tamias2d::space::SLEEP_NEVER;
use tamias2d_scenes::ScriptedWorld;

const DEFAULT_SCENES: [&str; 4] = [
    "pyramid_100",
    "many_pyramids_10x10",
    "bowl_boxes_1000",
    "rain_4000",
];
const QUALITY_SCENES: [&str; 4] = ["pyramid_20", "many_pyramids_4x4", "pyramid_100", "stack_10"];

/// `--quantile`: the percentile printed (50: the median).
static QUANTILE: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(50);

/// `--soft`: the soft step instead of the sequential solver.
static SOFT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `--narrow`: the soft step with the narrow contact kernels
/// (`ContactPrecision::Narrow`; implies `--soft`).
static NARROW: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `--scalar`: the scalar contact kernels (`Kernels::Scalar`) instead of
/// the default (`Kernels::Auto`: the wide ones where the processor has
/// AVX2 and the passes stay on one thread).
static SCALAR: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `--iterations`: the solver iterations of every world (0: the scene's).
static ITERATIONS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);

fn world(scene: &str, colored: bool, threads: usize) -> ScriptedWorld {
    let mut desc = tamias2d_scenes::builtin(scene).expect("a built-in scene");
    desc.settings.sleep_time_threshold = SLEEP_NEVER;
    let iterations = ITERATIONS.load(std::sync::atomic::Ordering::Relaxed);
    if iterations > 0 {
        desc.settings.iterations = iterations;
    }
    desc.settings.colored_solver = colored;
    if SOFT.load(std::sync::atomic::Ordering::Relaxed) {
        let mut soft = tamias2d::space::SoftStep::default();
        if NARROW.load(std::sync::atomic::Ordering::Relaxed) {
            soft.contact_precision = tamias2d::space::ContactPrecision::Narrow;
        }
        desc.settings.solver = tamias2d::space::Solver::Soft(soft).into();
    }
    let mut w = desc.build().expect("the scene builds");
    w.space.set_threads(threads).expect("the threads start");
    if SCALAR.load(std::sync::atomic::Ordering::Relaxed) {
        w.space.set_kernels(tamias2d::space::Kernels::Scalar);
    }
    w
}

/// The `--quantile` percentile of `v` (the median by default).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let q = QUANTILE.load(std::sync::atomic::Ordering::Relaxed).min(100);
    v.get((v.len() * q / 100).min(v.len().saturating_sub(1)))
        .copied()
        .unwrap_or(f64::NAN)
}

fn speed(scenes: &[String], threads: usize, samples: usize) {
    let soft = SOFT.load(std::sync::atomic::Ordering::Relaxed);
    let q = QUANTILE.load(std::sync::atomic::Ordering::Relaxed);
    let stat = if q == 50 {
        "median".to_owned()
    } else {
        format!("percentile {q} of the")
    };
    println!("threads: 1 and {threads}; sleeping off; {stat} ms per step of {samples} samples of 10 steps");
    // The soft step always solves in the colored order: one pair of
    // configurations.
    let configs: &[(bool, usize)] = if soft {
        println!("| scene | soft step, 1 thread | soft step, {threads} | speed-up |");
        println!("|---|---:|---:|---:|");
        &[(true, 1), (true, threads)]
    } else {
        println!(
            "| scene | canonical, 1 | canonical, {threads} | speed-up | colored, 1 | colored, {threads} | speed-up | colored {threads} / canonical 1 |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|---:|");
        &[(false, 1), (false, threads), (true, 1), (true, threads)]
    };
    for scene in scenes {
        let mut worlds: Vec<ScriptedWorld> =
            configs.iter().map(|&(c, t)| world(scene, c, t)).collect();
        for w in &mut worlds {
            w.step_n(120).expect("warm-up");
        }
        let mut times = vec![Vec::with_capacity(samples); configs.len()];
        for _ in 0..samples {
            for (w, t) in worlds.iter_mut().zip(&mut times) {
                let start = Instant::now();
                w.step_n(10).expect("a sample");
                t.push(start.elapsed().as_secs_f64() * 1e3 / 10.0);
            }
        }
        // Same configuration but the thread count: the same bits.
        let sums: Vec<u64> = worlds.iter().map(|w| w.space.checksum()).collect();
        for pair in sums.chunks(2) {
            assert_eq!(pair[0], pair[1], "{scene}: thread counts differ");
        }
        let m: Vec<f64> = times.iter_mut().map(|t| median(t)).collect();
        if soft {
            println!(
                "| `{scene}` | {:.2} | {:.2} | {:.2}× |",
                m[0],
                m[1],
                m[0] / m[1]
            );
            continue;
        }
        println!(
            "| `{scene}` | {:.2} | {:.2} | {:.2}× | {:.2} | {:.2} | {:.2}× | {:.2}× |",
            m[0],
            m[1],
            m[0] / m[1],
            m[2],
            m[3],
            m[2] / m[3],
            m[0] / m[3]
        );
    }
}

/// Largest displacement of a dynamic body from `start` (m), and for
/// `stack_10` the top box's |x| drift.
fn displacement(w: &ScriptedWorld, start: &[(f64, f64)]) -> f64 {
    let now: Vec<(f64, f64)> = positions(w);
    now.iter()
        .zip(start)
        .map(|(a, b)| (a.0 - b.0).hypot(a.1 - b.1))
        .fold(0.0, f64::max)
}

fn positions(w: &ScriptedWorld) -> Vec<(f64, f64)> {
    w.space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(_, b)| (b.position().x.to_f64(), b.position().y.to_f64()))
        .collect()
}

/// Deepest and mean overlap (positive numbers) of the touching contacts now.
fn penetration(w: &ScriptedWorld) -> (f64, f64, usize) {
    let mut deepest = 0.0f64;
    let (mut sum, mut n) = (0.0, 0usize);
    for arb in w.space.arbiters() {
        for c in arb.contacts() {
            let d = (-c.dist).max(Real::ZERO).to_f64();
            if d > 0.0 {
                deepest = deepest.max(d);
                sum += d;
                n += 1;
            }
        }
    }
    (deepest, sum, n)
}

fn quality(scenes: &[String]) {
    println!("sleeping off; after 10 s; penetration over the last second");
    println!("| scene | solver | max displacement (m) | penetration max / mean |");
    println!("|---|---|---:|---:|");
    for scene in scenes {
        for colored in [false, true] {
            let mut w = world(scene, colored, 1);
            let steps = (10.0 / w.dt.to_f64()).round() as u32;
            let start = positions(&w);
            let top_x = start.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map(|p| p.0);
            let (mut deepest, mut sum, mut n) = (0.0f64, 0.0, 0usize);
            for step in 0..steps {
                w.step().expect("a step");
                if step + 60 >= steps {
                    let (d, s, k) = penetration(&w);
                    deepest = deepest.max(d);
                    sum += s;
                    n += k;
                }
            }
            let moved = if scene == "stack_10" {
                let now = positions(&w);
                let top = now.iter().max_by(|a, b| a.1.total_cmp(&b.1)).map(|p| p.0);
                format!(
                    "top box x drift {:.3e}",
                    (top.unwrap_or(0.0) - top_x.unwrap_or(0.0)).abs()
                )
            } else {
                format!("{:.3e}", displacement(&w, &start))
            };
            println!(
                "| `{scene}` | {} | {moved} | {:.3e} / {:.3e} |",
                if colored { "colored" } else { "canonical" },
                deepest,
                sum / n.max(1) as f64
            );
        }
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut quality_mode, mut threads, mut samples) = (false, 2usize, 15usize);
    let mut scenes = Vec::new();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quality" => quality_mode = true,
            "--soft" => SOFT.store(true, std::sync::atomic::Ordering::Relaxed),
            "--narrow" => {
                SOFT.store(true, std::sync::atomic::Ordering::Relaxed);
                NARROW.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            "--scalar" => SCALAR.store(true, std::sync::atomic::Ordering::Relaxed),
            "--quantile" => QUANTILE.store(
                args.next().and_then(|n| n.parse().ok()).unwrap_or(50),
                std::sync::atomic::Ordering::Relaxed,
            ),
            "--threads" => threads = args.next().and_then(|n| n.parse().ok()).unwrap_or(2),
            "--samples" => samples = args.next().and_then(|n| n.parse().ok()).unwrap_or(15),
            "--iterations" => ITERATIONS.store(
                args.next().and_then(|n| n.parse().ok()).unwrap_or(0),
                std::sync::atomic::Ordering::Relaxed,
            ),
            _ => scenes.push(a),
        }
    }
    if !tamias2d::space::PARALLEL {
        eprintln!("warning: built without the `parallel` feature: one thread whatever the count");
    }
    if quality_mode {
        if scenes.is_empty() {
            scenes = QUALITY_SCENES.map(String::from).to_vec();
        }
        quality(&scenes);
    } else {
        if scenes.is_empty() {
            scenes = DEFAULT_SCENES.map(String::from).to_vec();
        }
        speed(&scenes, threads, samples.max(1));
    }
}
