//! `tamias bench`: the benchmark scenes (sections A and B of the registry,
//! `scenes/README.md`) as a table of milliseconds per step.
//!
//! Each scene is built and warmed up (piles form, warm starting takes
//! effect: the state the criterion benches in `benches/step.rs` measure),
//! then timed in samples of a few consecutive steps; the table gives the
//! median, fastest and slowest sample in ms per step. Wall-clock time of
//! one process: for comparisons between commits, use `cargo bench`.
use std::time::Instant;

use clap::Args;
use tamias2d_scenes as scenes;

use crate::progress::Progress;
use crate::rollback;
use crate::run::median;
use crate::source;

/// Warm-up steps and samples × steps per sample of the two modes.
const QUICK_PLAN: Plan = Plan {
    warmup: 100,
    samples: 10,
    steps_per_sample: 5,
};
const FULL_PLAN: Plan = Plan {
    warmup: 300,
    samples: 20,
    steps_per_sample: 10,
};

#[derive(Clone, Copy)]
struct Plan {
    warmup: u32,
    samples: u32,
    steps_per_sample: u32,
}

impl Plan {
    fn steps(&self) -> u64 {
        u64::from(self.warmup) + u64::from(self.samples) * u64::from(self.steps_per_sample)
    }
}

/// Options of `tamias bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Small scenes and short runs (under 30 s in release).
    #[arg(long, conflicts_with = "rollback")]
    quick: bool,
    /// The rollback budget instead of the step table: per scene, snapshot
    /// size, save, load and checksum per 1000 bodies, a step, and an
    /// 8-frame rollback (load + 8 x (step + save + checksum)), one line
    /// each [default scenes: bowl_boxes_500, pyramid_100, level_30000].
    #[arg(long)]
    rollback: bool,
    /// Only this scene (repeatable) [default: all section A and B scenes,
    /// or the quick set].
    #[arg(long = "scene", value_name = "NAME")]
    scenes: Vec<String>,
    /// Warm-up steps before timing [default: 300, quick 100; rollback:
    /// bowl scenes 300, pyramids 120, others 60].
    #[arg(long, value_name = "N")]
    warmup: Option<u32>,
    /// Timed samples [default: 20, quick 10; at least 10].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(10..))]
    samples: Option<u32>,
    /// Threads the step may use [default: all cores]; the results are the
    /// same with any count.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    threads: Option<u32>,
    /// Solve the contacts color by color (`Settings::colored_solver`), the
    /// order the threads can share.
    #[arg(long)]
    colored_solver: bool,
    /// The solver: `sequential` or `soft` (as `tamias run --solver`)
    /// [default: the scene's].
    #[arg(long, value_name = "KIND")]
    solver: Option<source::SolverChoice>,
    /// The soft step's contact kernels: `auto`, `scalar`, `wide` or
    /// `portable` (as `tamias run --kernels`) [default: auto].
    #[arg(long, value_name = "KIND", value_parser = source::parse_kernels)]
    kernels: Option<tamias2d::space::Kernels>,
}

/// One row of the table.
struct Row {
    name: String,
    bodies: usize,
    median: f64,
    min: f64,
    max: f64,
}

/// `tamias bench`.
pub fn bench(args: &BenchArgs) -> Result<(), String> {
    if args.rollback {
        return rollback::rollback(
            &args.scenes,
            args.warmup,
            args.samples.unwrap_or(20),
            args.solver,
            args.kernels.unwrap_or_default(),
        );
    }
    let base = if args.quick { QUICK_PLAN } else { FULL_PLAN };
    let plan = Plan {
        warmup: args.warmup.unwrap_or(base.warmup),
        samples: args.samples.unwrap_or(base.samples),
        ..base
    };
    let names: Vec<String> = if !args.scenes.is_empty() {
        args.scenes.clone()
    } else {
        // Sections A and B: the performance scenes (C is accuracy); quick:
        // the sizes that stand for their family.
        scenes::REGISTRY
            .iter()
            .filter(|s| s.is_performance())
            .filter(|s| !args.quick || s.is_quick_bench())
            .map(|s| s.name.to_owned())
            .collect()
    };
    let mut descs = Vec::with_capacity(names.len());
    for name in &names {
        let mut desc = scenes::builtin(name)
            .ok_or_else(|| format!("unknown scene {name:?} (`tamias list` shows the scenes)"))?;
        desc.settings.colored_solver |= args.colored_solver;
        if let Some(solver) = args.solver {
            solver.apply(&mut desc.settings);
        }
        descs.push(desc);
    }
    let threads = args.threads.map_or_else(source::all_cores, |n| n as usize);
    let kernels = args.kernels.unwrap_or_default();
    if cfg!(debug_assertions) {
        eprintln!("note: a debug build; `cargo run --release -- bench` gives meaningful numbers");
    }
    println!(
        "{} scenes; {threads} thread(s), {} kernels{}; warm-up {} steps, then {} samples of {} steps",
        descs.len(),
        kernels.describe(),
        match (args.colored_solver, args.solver) {
            (_, Some(source::SolverChoice::Soft)) => ", soft step",
            (_, Some(source::SolverChoice::SoftNarrow)) => ", soft step, narrow contacts",
            (true, _) => ", colored solver",
            _ => "",
        },
        plan.warmup,
        plan.samples,
        plan.steps_per_sample
    );
    let mut bar = Progress::new("bench", plan.steps() * descs.len() as u64);
    let mut rows = Vec::with_capacity(descs.len());
    for desc in &descs {
        bar.set_label(&format!("bench {}", desc.name));
        rows.push(measure(desc, plan, threads, kernels, &mut bar)?);
    }
    bar.finish();
    print_table(&rows);
    Ok(())
}

/// Warms `desc` up and times its samples.
fn measure(
    desc: &scenes::SceneDesc,
    plan: Plan,
    threads: usize,
    kernels: tamias2d::space::Kernels,
    bar: &mut Progress,
) -> Result<Row, String> {
    let mut sim = source::build(desc)?;
    let fail = |e: String| format!("scene {}: {e}", desc.name);
    sim.space
        .set_threads(threads)
        .map_err(|e| e.to_string())
        .map_err(fail)?;
    sim.space.set_kernels(kernels);
    for _ in 0..plan.warmup {
        sim.step().map_err(|e| e.to_string()).map_err(fail)?;
        bar.inc(1);
    }
    let mut per_step = Vec::with_capacity(plan.samples as usize);
    for _ in 0..plan.samples {
        let t = Instant::now();
        for _ in 0..plan.steps_per_sample {
            sim.step().map_err(|e| e.to_string()).map_err(fail)?;
        }
        per_step.push(t.elapsed().as_secs_f64() * 1e3 / f64::from(plan.steps_per_sample));
        bar.inc(u64::from(plan.steps_per_sample));
    }
    Ok(Row {
        name: desc.name.clone(),
        bodies: sim.space.bodies().count(),
        median: median(&per_step),
        min: per_step.iter().copied().fold(f64::INFINITY, f64::min),
        max: per_step.iter().copied().fold(0.0, f64::max),
    })
}

fn print_table(rows: &[Row]) {
    println!(
        "{:<22} {:>7} {:>15} {:>9} {:>9}",
        "scene", "bodies", "median ms/step", "min", "max"
    );
    for r in rows {
        println!(
            "{:<22} {:>7} {:>15.3} {:>9.3} {:>9.3}",
            r.name, r.bodies, r.median, r.min, r.max
        );
    }
}
