//! Tamias2D beside Rapier on one scene: time per step and what it delivers.
//!
//! Both engines run the scene's default number of steps (1000 for sections
//! A and B) **in lockstep**: step k of one, then step k of the other
//! (alternating which goes first), so that the load of a shared machine hits
//! both alike. Every step is timed; the median is taken over the steps after
//! the warm-up (300 steps, or until the rain is all out). Quality is read
//! between steps, outside the timed code, every 4th step of the second half
//! of the run.
//!
//! The joint scenes (section D, [`run_joints`]) run at their own settings
//! (iterations and sub-steps as the scene defines them), are timed after a
//! one-second warm-up (they move throughout), and also measure the joint
//! error ([`common::joints`]) of both engines after every step, outside the
//! timed code.
use std::time::Instant;

use crate::common::joints::{self, JointError, Resolved};
use crate::common::{self, Config, Engine, Penetration, RapierRun, TamiasRun};
use crate::measures;

/// What one engine did on one scene.
#[derive(Clone, Debug, Default)]
pub struct EngineResult {
    /// Median time per step over the timing window (s).
    pub median_step: f64,
    /// Number of steps in the timing window.
    pub timed_steps: usize,
    /// Penetration over the second half of the run.
    pub pen: Penetration,
    /// Drift after 10 s (pyramids).
    pub drift: Option<measures::Drift>,
    /// Relative kinetic energy change over the run (elastic scenes).
    pub energy_drift: Option<f64>,
    /// Dynamic bodies outside the container at the end.
    pub escaped: usize,
    /// Scene-specific errors at the end ([`measures::errors`]).
    pub errors: Vec<f64>,
    /// Joint error over the whole run (joint scenes).
    pub joint: JointError,
    /// Joints the engine simulates.
    pub joints: usize,
}

/// One scene of the side-by-side table.
#[derive(Clone, Debug)]
pub struct SideRow {
    /// Scene name.
    pub name: String,
    /// Bodies at the end (static ones included).
    pub bodies: usize,
    /// Steps run.
    pub steps: u32,
    /// Tamias2D.
    pub tamias: EngineResult,
    /// Rapier.
    pub rapier: EngineResult,
    /// Solver settings both engines ran at.
    pub config: Config,
    /// Kinds of the scene's constraints that Rapier has no counterpart for
    /// (left out of its world).
    pub left_out: Vec<String>,
}

impl SideRow {
    /// Tamias2D time over Rapier time.
    pub fn ratio(&self) -> f64 {
        self.tamias.median_step / self.rapier.median_step
    }
}

/// Runs scene `name` on both engines at the benchmark's default settings
/// (see the module docs).
pub fn run(name: &str) -> SideRow {
    run_with(name, Config::DEFAULT)
}

/// Runs joint scene `name` on both engines at its own settings, with the
/// joint error (see the module docs).
pub fn run_joints(name: &str) -> SideRow {
    run_with(name, common::scene_config(name))
}

/// Runs scene `name` with Tamias2D on the narrow soft step (four
/// sub-steps of its own, one pipeline step) and Rapier at four iterations,
/// which are its sub-steps: both engines at four soft sub-steps.
pub fn run_soft_narrow(name: &str) -> SideRow {
    let config = Config {
        iterations: 4,
        ..Config::DEFAULT
    };
    let mut desc = common::scene_with(name, config);
    desc.settings.use_narrow_soft_step();
    run_desc(name, desc, config)
}

fn run_with(name: &str, config: Config) -> SideRow {
    run_desc(name, common::scene_with(name, config), config)
}

fn run_desc(name: &str, desc: tamias2d_scenes::SceneDesc, config: Config) -> SideRow {
    let resolved: Vec<Resolved> = joints::resolve(&desc);
    let steps = desc.steps;
    // The joint scenes move throughout (falls, swings, a drive): their
    // warm-up is one second, enough for warm starting to be in effect.
    let warmup = if resolved.is_empty() {
        common::warmup_steps(name)
    } else {
        config.steps_for(1.0)
    }
    .min(steps.saturating_sub(100));
    let mut tamias = TamiasRun::new(&desc, config);
    let mut rapier = RapierRun::new(&desc, config, common::length_unit(name));
    let (rapier_joints, left_out) = (
        rapier.joints,
        rapier
            .left_out
            .iter()
            .map(|k| format!("{k:?}"))
            .collect::<Vec<_>>(),
    );
    let mut engines: [(&mut dyn Engine, Acc); 2] =
        [(&mut tamias, Acc::default()), (&mut rapier, Acc::default())];
    // Each engine's initial states are read from that engine (Rapier's are
    // the description rounded to f32).
    for (e, acc) in engines.iter_mut() {
        acc.init = e.states();
        acc.energy0 = e.kinetic_energy();
    }
    let drift_step = config.steps_for(10.0);
    for k in 1..=steps {
        let order: [usize; 2] = if k % 2 == 0 { [0, 1] } else { [1, 0] };
        for i in order {
            let (e, acc) = &mut engines[i];
            let start = Instant::now();
            e.step();
            let dt = start.elapsed().as_secs_f64();
            if k > warmup {
                acc.times.push(dt);
            }
        }
        for (e, acc) in engines.iter_mut() {
            if k > steps / 2 && k % 4 == 0 {
                acc.pen.merge(e.penetration());
            }
            if k == drift_step && name.contains("pyramid") {
                acc.drift = Some(measures::drift(&acc.init, &**e));
            }
            if !resolved.is_empty() {
                acc.joint.merge(joints::error(&resolved, &**e));
            }
        }
    }
    let t = steps as f64 * config.dt();
    let [(t_engine, t_acc), (r_engine, r_acc)] = engines;
    let mut tamias = t_acc.finish(name, &*t_engine, t);
    let mut rapier = r_acc.finish(name, &*r_engine, t);
    tamias.joints = desc.constraints.len();
    rapier.joints = rapier_joints;
    SideRow {
        name: name.to_owned(),
        bodies: t_engine.body_count(),
        steps,
        tamias,
        rapier,
        config,
        left_out,
    }
}

/// What is accumulated for one engine during a side-by-side run.
#[derive(Default)]
struct Acc {
    init: Vec<common::BodyState>,
    energy0: f64,
    times: Vec<f64>,
    pen: Penetration,
    drift: Option<measures::Drift>,
    joint: JointError,
}

impl Acc {
    fn finish(mut self, name: &str, e: &dyn Engine, t: f64) -> EngineResult {
        let energy_drift = (name.starts_with("bouncy_") && self.energy0 > 0.0)
            .then(|| (e.kinetic_energy() - self.energy0) / self.energy0);
        let escaped = (0..e.body_count())
            .filter(|&i| measures::escaped(name, &e.body(i)))
            .count();
        let errors = measures::errors(name, &self.init, e, t, self.pen);
        EngineResult {
            median_step: common::median(&mut self.times),
            timed_steps: self.times.len(),
            pen: self.pen,
            drift: self.drift,
            energy_drift,
            escaped,
            errors,
            joint: self.joint,
            joints: 0,
        }
    }
}
