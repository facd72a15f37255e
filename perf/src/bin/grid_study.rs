//! The narrow lane grid's quality study: the soft step's error measures on
//! the standard contact scenes, to compare between the default build and
//! the study builds (`grid-study-constants`, `-reads`, `-fine`, `grid-study`), whose soft
//! contact passes round what a 32-bit lane kernel would hold to its grid
//! (`docs/numerics.md`, "The narrow lane grid").
//!
//! ```text
//! scripts/grid-study.sh                      # the five builds side by side (about 12 min)
//! cargo run --release -p tamias2d-perf --bin grid_study [--features grid-study|grid-study-fine|grid-study-reads|grid-study-constants] [-- SCENE…]
//! cargo run --release -p tamias2d-perf --bin grid_study -- --narrow [SCENE…]
//! ```
//! `--narrow` measures the narrow contact kernels themselves
//! (`ContactPrecision::Narrow`, in the default build).
//! Each scene runs from its start at 1/60 s on the soft step at its
//! defaults (4 sub-steps), sleeping off, for the sweep's simulated time
//! (`perf_report`'s measures), [`RUNS`] times with the step nudged; output
//! is one tab-separated line per measure: scene, measure, and the median,
//! least and largest value of the runs. Besides the scene's own measures,
//! every scene reports its deepest contact overlap over the whole run, and
//! the first run's final checksum (which says whether the bits moved).
#![allow(clippy::float_arithmetic)] // measurement and reports only

use tamias2d::math::Real;
use tamias2d_scenes::bench::{self as common, measures};
use tamias2d_scenes::SolverDesc;

use common::{Config, Engine, Penetration, TamiasRun};

/// The soft step's contact scenes of the standard set.
const SCENES: &[&str] = &[
    "stack_10",
    "pyramid_20",
    "many_pyramids_4x4",
    "pyramid_100",
    "bowl_boxes_500",
    "rain_1000",
    "tumbler_500",
    "incline_slide",
    "incline_stick",
    "newtons_cradle",
    "elastic_pair",
];

/// Runs of each scene: the step length nudged by 0, 1, …, `RUNS − 1` ulps.
/// A pile is chaotic: any change of its bits, however small, moves its
/// measures by some percent. The nudged runs show that spread at a change
/// far below the grid's (2^-32 of a second against 2^-16 of a velocity), so
/// a difference between the builds counts only where their ranges part.
const RUNS: u32 = 5;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let narrow = args.iter().any(|a| a == "--narrow");
    args.retain(|a| a != "--narrow");
    let scenes: Vec<&str> = if args.is_empty() {
        SCENES.to_vec()
    } else {
        args.iter().map(String::as_str).collect()
    };
    for name in scenes {
        let runs: Vec<Run> = (0..RUNS).map(|k| run(name, k, narrow)).collect();
        let Some(first) = runs.first() else {
            continue;
        };
        for (m, label) in first.labels.iter().enumerate() {
            let mut values: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.values.get(m).copied())
                .collect();
            values.sort_by(f64::total_cmp);
            let at = |i: usize| values.get(i).copied().unwrap_or(f64::NAN);
            println!(
                "{name}\t{label}\t{:.3e}\t{:.3e}\t{:.3e}",
                at(values.len() / 2),
                at(0),
                at(values.len().saturating_sub(1))
            );
        }
        println!("{name}\tchecksum\t{:016x}\t\t", first.checksum);
    }
}

/// One run's measures.
struct Run {
    labels: Vec<String>,
    values: Vec<f64>,
    checksum: u64,
}

/// Scene `name` with its step nudged by `nudge` ulps (and with the narrow
/// contact kernels if `narrow`): its measures, its deepest overlap and the
/// final checksum.
fn run(name: &str, nudge: u32, narrow: bool) -> Run {
    let config = Config {
        iterations: 10,
        substeps: 1,
        rate: 60,
    };
    let mut desc = common::scene_with(name, config);
    desc.settings.solver = SolverDesc::SOFT;
    if narrow {
        if let SolverDesc::Soft(tamias2d_scenes::SoftStepDesc(soft)) = &mut desc.settings.solver {
            soft.contact_precision = tamias2d::space::ContactPrecision::Narrow;
        }
    }
    desc.dt = Real::from_bits(desc.dt.to_bits() + i64::from(nudge));
    let mut engine = TamiasRun::new(&desc, config);
    let seconds = measures::sweep_seconds(name);
    let steps = config.steps_for(seconds);
    let window = steps.saturating_sub(config.steps_for(measures::PENETRATION_WINDOW));
    let init = engine.states();
    let (mut pen, mut deepest) = (Penetration::default(), 0.0f64);
    for k in 1..=steps {
        engine.step();
        let p = engine.penetration();
        deepest = deepest.max(p.max);
        if k > window {
            pen.merge(p);
        }
    }
    let mut labels: Vec<String> = measures::measures(name)
        .iter()
        .map(|m| format!("{} ({}) after {seconds} s", m.name, m.unit))
        .collect();
    let mut values = measures::errors(name, &init, &engine, seconds, pen);
    labels.push("deepest overlap over the run".into());
    values.push(deepest);
    Run {
        labels,
        values,
        checksum: engine.scene.space.checksum(),
    }
}
