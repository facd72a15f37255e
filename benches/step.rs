//! Whole-step benchmarks on the standard scenes (scenes/README.md).
//!
//! * `broadphase`, `stacking`: each scene is built, warmed up for a number
//!   of steps (so piles have formed and warm starting is in effect), and
//!   then one `ScriptedWorld::step` is measured: the real code path, scripted events
//!   included. The broadphase group also prints the candidate-pair count per
//!   body, which must stay about constant as the body count grows (no
//!   quadratic broadphase).
//! * `switches`: what each solver switch of `Settings` saves ("pay only for
//!   what you use"). A stacking scene is warmed up with the default settings
//!   and its state kept; every measured step starts from that same state
//!   (restored untimed) with one switch off (`no_warm_starting`,
//!   `no_friction`, `no_restitution`, `no_bias`, `no_block_solver`), all
//!   off (`all_off`) or
//!   none (`all_on`), so every variant solves the very same contacts. The
//!   timed step includes the static-tree rebuild and `dt` constants that a
//!   restored state recomputes, the same for every variant. After
//!   criterion's output two tables give each variant's median time per
//!   step and its ratio to `all_on`: the median of criterion's samples
//!   (variants timed one after the other), and a lockstep measurement
//!   (400 rounds, each timing one step of every variant in rotated order,
//!   so that load on a shared machine hits every variant alike: the one to
//!   quote).
//!
//! ```text
//! cargo bench --bench step                       # everything
//! cargo bench --bench step -- switches           # the switch table only
//! cargo bench --bench step -- switches --quick   # shorter samples
//! cargo bench --bench step -- switches/lockstep   # the lockstep table alone
//! cargo bench --bench step -- sleeping           # sleeping: asleep vs awake
//! ```
//!
//! * `sleeping`: a settled `bowl_boxes_500` asleep against the same scene
//!   awake, steps 1,200–1,500 timed in lockstep (see `sleeping_lockstep`).
#![allow(clippy::float_arithmetic)] // timing report only

use tamias2d_scenes::bench as common;

use std::hint::black_box;
use std::time::{Duration, Instant};
use tamias2d_scenes::shared::Shared;

use common::median;
use criterion::Criterion;
use tamias2d::space::{Settings, WorldState};
use tamias2d_scenes as scenes;

/// The scene warmed up with sleeping off (these groups time the work of
/// awake bodies; the `sleeping` group times sleep).
fn warmed(name: &str, warmup: u32) -> scenes::ScriptedWorld {
    warmed_with(name, warmup, false)
}

fn warmed_with(name: &str, warmup: u32, sleeping: bool) -> scenes::ScriptedWorld {
    let mut desc = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
    if !sleeping {
        desc.settings.sleep_time_threshold = tamias2d::space::SLEEP_NEVER;
    }
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

/// `sleeping`: `bowl_boxes_500` settled (1,200 steps), once with sleeping
/// on (every body asleep by then) and once with it off (the same scene
/// awake); then steps 1,200–1,500 of each are timed in lockstep (each
/// round times one step of both, so machine load hits both alike). Prints
/// the medians and the ratio asleep / awake (issue 14's target: ≤ 5 %).
fn sleeping_lockstep() {
    let mut asleep = warmed_with("bowl_boxes_500", 1200, true);
    let mut awake = warmed_with("bowl_boxes_500", 1200, false);
    let sleeping_bodies = asleep.space.sleeping_bodies();
    let (mut t_asleep, mut t_awake) = (Vec::new(), Vec::new());
    for _ in 0..300 {
        for (scene, times) in [(&mut asleep, &mut t_asleep), (&mut awake, &mut t_awake)] {
            let t = Instant::now();
            scene.step().unwrap_or_else(|e| panic!("step: {e}"));
            times.push(t.elapsed().as_secs_f64() * 1e3);
            black_box(&scene.space);
        }
    }
    let (a, w) = (median(&mut t_asleep), median(&mut t_awake));
    println!(
        "sleeping (lockstep, steps 1200-1500 of bowl_boxes_500): asleep {a:.4} ms/step \
         ({sleeping_bodies} of 500 bodies asleep at step 1200, {} at 1500), awake {w:.4} ms/step, \
         ratio {:.2} %",
        asleep.space.sleeping_bodies(),
        100.0 * a / w
    );
}

/// A variant of the `switches` group: a name and the settings change.
type Variant = (&'static str, fn(&mut Settings));

/// The variants of the `switches` group.
const SWITCHES: &[Variant] = &[
    ("all_on", |_| {}),
    ("no_warm_starting", |s| s.warm_starting = false),
    ("no_friction", |s| s.friction = false),
    ("no_restitution", |s| s.restitution = false),
    ("no_bias", |s| s.bias_impulses = false),
    ("no_block_solver", |s| s.block_solver = false),
    ("all_off", |s| {
        s.warm_starting = false;
        s.friction = false;
        s.restitution = false;
        s.bias_impulses = false;
        s.block_solver = false;
    }),
];

/// Scenes of the `switches` group: the CI-sized pyramid and a 500-box pile.
const SWITCH_SCENES: &[&str] = &["pyramid_20", "bowl_boxes_500"];

/// One row of the switch table: scene, variant, median seconds per step.
type Row = (&'static str, &'static str, f64);

/// A warmed scene and the state every measured step of it starts from.
struct SwitchScene {
    name: &'static str,
    scene: scenes::ScriptedWorld,
    warm: WorldState,
}

/// Times one step from `s.warm` with `edit` applied to its settings;
/// returns the median of criterion's samples (seconds per step), `None`
/// when the command line filter left the variant out.
fn bench_switch(
    c: &mut Criterion,
    s: &mut SwitchScene,
    (variant, edit): Variant,
    sample_size: usize,
) -> Option<f64> {
    let mut start = s.warm.clone();
    edit(&mut start.settings);
    let dt = s.scene.dt;
    let space = &mut s.scene.space;
    let samples = Shared::new(Vec::new());
    let record = Shared::clone(&samples);
    c.benchmark_group("switches")
        .bench_function(format!("{}/{variant}", s.name), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    space.restore_state(&start);
                    let t = Instant::now();
                    space.step(dt).unwrap_or_else(|e| panic!("step: {e}"));
                    total += t.elapsed();
                    black_box(&*space);
                }
                record
                    .borrow_mut()
                    .push(total.as_secs_f64() / iters.max(1) as f64);
                total
            })
        });
    let mut all = samples.borrow().clone();
    if all.is_empty() {
        return None;
    }
    // Warm-up calls come first; the last `sample_size` calls are the samples.
    let first = all.len().saturating_sub(sample_size);
    Some(median(&mut all[first..]))
}

fn switches(c: &mut Criterion, sample_size: usize, test_mode: bool) -> Vec<Row> {
    let mut rows = Vec::new();
    for &name in SWITCH_SCENES {
        let scene = warmed(name, if test_mode { 1 } else { 300 });
        let warm = scene.space.state().clone();
        let mut s = SwitchScene { name, scene, warm };
        for &variant in SWITCHES {
            if let Some(t) = bench_switch(c, &mut s, variant, sample_size) {
                rows.push((name, variant.0, t));
            }
        }
    }
    rows
}

/// The switch variants timed in lockstep: `rounds` rounds, each timing one
/// step of every variant (from the same warmed state, in an order rotated
/// every round), so that a busy moment of a shared machine hits all
/// variants alike. Returns each variant's median.
fn switches_lockstep(rounds: usize) -> Vec<Row> {
    let mut rows = Vec::new();
    for &name in SWITCH_SCENES {
        let mut scene = warmed(name, 300);
        let starts: Vec<WorldState> = SWITCHES
            .iter()
            .map(|(_, edit)| {
                let mut s = scene.space.state().clone();
                edit(&mut s.settings);
                s
            })
            .collect();
        let n = starts.len();
        let mut times = vec![Vec::with_capacity(rounds); n];
        for r in 0..rounds {
            for j in 0..n {
                let v = (j + r) % n;
                scene.space.restore_state(&starts[v]);
                let t = Instant::now();
                scene
                    .space
                    .step(scene.dt)
                    .unwrap_or_else(|e| panic!("step: {e}"));
                times[v].push(t.elapsed().as_secs_f64());
                black_box(&scene.space);
            }
        }
        for ((variant, _), t) in SWITCHES.iter().zip(&mut times) {
            rows.push((name, *variant, median(t)));
        }
    }
    rows
}

/// True when the command line's filters (if any) select the switch group.
fn switches_selected() -> bool {
    group_selected("switches")
}

/// True when the command line's filters (if any) select `group`.
fn group_selected(group: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    filters.is_empty()
        || filters
            .iter()
            .any(|f| f.starts_with(group) || group.contains(f.as_str()))
}

fn print_switch_table(title: &str, rows: &[Row]) {
    if rows.is_empty() {
        return;
    }
    println!();
    println!("{title}");
    println!(
        "{:<16} {:<18} {:>10} {:>8}",
        "scene", "variant", "ms/step", "ratio"
    );
    for &(scene, variant, t) in rows {
        let base = rows
            .iter()
            .find(|r| r.0 == scene && r.1 == "all_on")
            .map(|r| r.2);
        let ratio = base
            .filter(|b| *b > 0.0)
            .map_or("-".to_owned(), |b| format!("{:.3}", t / b));
        println!("{scene:<16} {variant:<18} {:>10.4} {ratio:>8}", t * 1e3);
    }
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` does not (and
    // criterion then runs every benchmark once): keep that cheap and quiet.
    let benching = std::env::args().any(|a| a == "--bench");
    let test_mode = !benching || std::env::args().any(|a| a == "--test");
    let sample_size = 20;
    let mut c = Criterion::default()
        .sample_size(sample_size)
        .measurement_time(Duration::from_secs(4))
        .warm_up_time(Duration::from_secs(1))
        .configure_from_args();
    broadphase(&mut c);
    stacking(&mut c);
    let rows = switches(&mut c, sample_size, test_mode);
    c.final_summary();
    if !test_mode {
        print_switch_table(
            "switches (criterion): median ms per step from the same warmed state, ratio to all_on",
            &rows,
        );
        if group_selected("sleeping") {
            sleeping_lockstep();
        }
        if switches_selected() {
            let lockstep = switches_lockstep(400);
            print_switch_table(
                "switches (lockstep, 400 rounds): median ms per step, ratio to all_on",
                &lockstep,
            );
        }
    }
}
