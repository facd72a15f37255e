//! The trade curve: cost per simulated second against error, over solver
//! iterations, step size and sub-steps.
//!
//! A series fixes the step size (and sub-steps) and varies the iteration
//! count; every point is one run of [`measures::sweep_seconds`] simulated
//! seconds from the scene's start. Cost is the wall time of the steps
//! (median step time × steps, measurement excluded) divided by the
//! simulated time.
use std::time::Instant;

use crate::common::{self, Config, Engine, Penetration, RapierRun, TamiasRun};
use crate::measures;

/// Which engine a series runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Tamias2D.
    Tamias,
    /// Rapier (its iterations are its sub-steps).
    Rapier,
}

/// One line of a trade plot.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Engine.
    pub kind: Kind,
    /// The points, in increasing iteration count.
    pub points: Vec<Point>,
}

/// One run.
#[derive(Clone, Debug)]
pub struct Point {
    /// Settings.
    pub config: Config,
    /// Milliseconds of wall time per simulated second.
    pub cost_ms: f64,
    /// The scene's errors ([`measures::errors`]).
    pub errors: Vec<f64>,
}

/// The series to run for a scene: per step size, Tamias2D over the
/// iteration counts; Rapier over the same counts at 1/60 s; with
/// `substeps`, Tamias2D at 1/60 s with `Settings::substeps` = 2 and 4 (2
/// only with `quick`). Heavy scenes get fewer iteration counts.
///
/// A step with `substeps = k` runs the whole pipeline k times on sub-steps
/// of `dt / k` (split exactly, see `tamias2d::space::sub_step_dts`), so its
/// series should lie on the `1/(60k)` s series: same error, same cost, up
/// to the one-ulp difference of the sub-step lengths and timing noise.
pub fn plan(name: &str, quick: bool, with_substeps: bool) -> Vec<(String, Kind, Vec<Config>)> {
    let heavy = name.starts_with("bowl_");
    let iterations: &[u32] = if quick {
        &[2, 10, 30]
    } else if heavy {
        &[1, 2, 4, 10, 30]
    } else {
        &[1, 2, 4, 8, 10, 16, 30]
    };
    let rates: &[u32] = if quick {
        &[30, 60, 120]
    } else {
        &[30, 60, 120, 240]
    };
    let substeps: &[u32] = match (with_substeps, quick) {
        (false, _) => &[],
        (true, true) => &[2],
        (true, false) => &[2, 4],
    };
    let series = |kind: Kind, rate: u32, sub: u32| {
        let configs = iterations
            .iter()
            .map(|&iterations| Config {
                iterations,
                substeps: sub,
                rate,
            })
            .collect::<Vec<_>>();
        let engine = match kind {
            Kind::Tamias => "Tamias2D",
            Kind::Rapier => "Rapier",
        };
        let label = if sub > 1 {
            format!("{engine} 1/{rate} s ÷ {sub}")
        } else {
            format!("{engine} 1/{rate} s")
        };
        (label, kind, configs)
    };
    let mut out: Vec<_> = rates.iter().map(|&r| series(Kind::Tamias, r, 1)).collect();
    out.extend(substeps.iter().map(|&s| series(Kind::Tamias, 60, s)));
    out.push(series(Kind::Rapier, 60, 1));
    out
}

/// Runs every series of [`plan`] on scene `name`.
pub fn run_scene(
    name: &str,
    quick: bool,
    with_substeps: bool,
    log: &mut dyn FnMut(&str),
) -> Vec<Series> {
    plan(name, quick, with_substeps)
        .into_iter()
        .map(|(label, kind, configs)| {
            let points = configs
                .iter()
                .map(|&c| {
                    let p = run_point(name, kind, c);
                    log(&format!(
                        "  {name:<16} {label:<22} {:>2} it: {:>9.2} ms/s  errors {:?}",
                        c.iterations, p.cost_ms, p.errors
                    ));
                    p
                })
                .collect();
            Series {
                label,
                kind,
                points,
            }
        })
        .collect()
}

/// One run of scene `name` on `kind` with `config`.
pub fn run_point(name: &str, kind: Kind, config: Config) -> Point {
    let desc = common::scene_with(name, config);
    let mut engine: Box<dyn Engine> = match kind {
        Kind::Tamias => Box::new(TamiasRun::new(&desc, config)),
        Kind::Rapier => Box::new(RapierRun::new(&desc, config, common::length_unit(name))),
    };
    let seconds = measures::sweep_seconds(name);
    let steps = config.steps_for(seconds);
    let window = steps.saturating_sub(config.steps_for(measures::PENETRATION_WINDOW));
    let wants_pen = name.starts_with("bowl_");
    let init = engine.states();
    let mut pen = Penetration::default();
    let mut times = Vec::with_capacity(steps as usize);
    for k in 1..=steps {
        let start = Instant::now();
        engine.step();
        times.push(start.elapsed().as_secs_f64());
        if wants_pen && k > window {
            pen.merge(engine.penetration());
        }
    }
    // Median step time × steps: robust against the preemptions of a shared
    // machine, which would dominate the sum for the one-body scenes.
    let cost = common::median(&mut times) * f64::from(steps) / seconds;
    Point {
        config,
        cost_ms: cost * 1e3,
        errors: measures::errors(name, &init, &*engine, seconds, pen),
    }
}
