//! Shared code of the Tamias2D-versus-Rapier benches and of the performance
//! report (`benches/`, `perf/src/bin/perf_report`), behind the feature `bench`
//! (it pulls in Rapier). Not part of the fixtures proper: measurement
//! helpers that the engine's benches and report share.
//!
//! * [`rapier_world`] turns a [`SceneDesc`] into a Rapier world with the same
//!   bodies, shapes, materials, gravity, time step and iteration count, and
//!   replays the description's scripted forces and spawns the same way
//!   [`ScriptedWorld::step`](crate::ScriptedWorld::step) does.
//! * [`measure`] reads what both engines deliver in one common form: body
//!   states in creation order and penetration of touching pairs.
//! * [`measures`] are the scenes' error measures against closed forms and
//!   conservation laws (the report's accuracy tables and trade curves, and
//!   the narrow-grid study).
//!
//! Floats are fine here: this is measurement code, never simulation state.
#![allow(
    dead_code, // each bench or example uses a different part of it
    clippy::float_arithmetic,
    clippy::arithmetic_side_effects,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod joints;
pub mod measure;
pub mod measures;
pub mod rapier_world;

use crate::{self as scenes, SceneDesc, Section};
use tamias2d::math::Real;
use tamias2d::space::{DEFAULT_IDLE_SPEED_THRESHOLD, DEFAULT_SLEEP_TIME_THRESHOLD};

#[allow(unused_imports)]
pub use joints::JointError;
#[allow(unused_imports)] // each user takes a different part
pub use measure::{BodyState, Engine, Penetration, TamiasRun};
#[allow(unused_imports)]
pub use rapier_world::{RapierRun, RapierSleep, JOINT_MAPPING};

/// Sections A and B (terrain, stacking), the sizes that stand for their
/// family: the quick set.
pub fn ci_scenes() -> Vec<&'static str> {
    scenes::REGISTRY
        .iter()
        .filter(|s| s.is_quick_bench())
        .map(|s| s.name)
        .collect()
}

/// Sections A and B, the larger sizes.
pub fn full_scenes() -> Vec<&'static str> {
    scenes::REGISTRY
        .iter()
        .filter(|s| s.is_performance() && s.covered_by.is_some())
        .map(|s| s.name)
        .collect()
}

/// Section C (closed-form answers).
pub fn accuracy_scenes() -> Vec<&'static str> {
    scenes::registry::section(Section::Accuracy)
        .map(|s| s.name)
        .collect()
}

/// Section D (joints), compared with Rapier's joints at each scene's own
/// settings ([`scene_config`]).
///
/// Box2D's own benchmark scenes (`box2d_*`) are left out: they are
/// compared with Box2D (`tools/box2d-side-by-side`), and the joint grid's
/// collision categories have no Rapier mapping here.
pub fn joint_scenes() -> Vec<&'static str> {
    scenes::registry::section(Section::Joints)
        .map(|s| s.name)
        .filter(|n| !n.starts_with("box2d_"))
        .collect()
}

/// The solver settings scene `name` is defined with (its iterations,
/// sub-steps and step rate): the joint scenes are compared at these, not at
/// [`Config::DEFAULT`], because their sub-steps are part of the scene.
pub fn scene_config(name: &str) -> Config {
    let desc = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
    Config {
        iterations: desc.settings.iterations,
        substeps: desc.settings.substeps.max(1),
        rate: (1.0 / desc.dt.to_f64()).round() as u32,
    }
}

/// Solver settings of one run: what the trade-off sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Solver iterations per (sub-)step (Rapier: `num_solver_iterations`).
    pub iterations: u32,
    /// Sub-steps per step (`Settings::substeps` for Tamias2D: the whole
    /// pipeline, collision detection included, on `dt / substeps`; Rapier
    /// is stepped `substeps` times by `dt / substeps`).
    pub substeps: u32,
    /// The step is `1 / rate` s.
    pub rate: u32,
}

impl Config {
    /// The benchmark default: 10 iterations, no sub-steps, 60 Hz.
    pub const DEFAULT: Config = Config {
        iterations: 10,
        substeps: 1,
        rate: 60,
    };

    /// The step in seconds.
    pub fn dt(&self) -> f64 {
        1.0 / f64::from(self.rate)
    }

    /// Steps of this config that cover `seconds` of simulated time.
    pub fn steps_for(&self, seconds: f64) -> u32 {
        (seconds * f64::from(self.rate)).round() as u32
    }

    /// Short label, e.g. `10 it, 1/60 s` or `10 it, 1/60 s ÷ 2`.
    pub fn label(&self) -> String {
        if self.substeps > 1 {
            format!(
                "{} it, 1/{} s ÷ {}",
                self.iterations, self.rate, self.substeps
            )
        } else {
            format!("{} it, 1/{} s", self.iterations, self.rate)
        }
    }
}

/// The registry scene `name` with its step, iterations and sub-steps
/// (`Settings::substeps`) replaced by `config`. Panics on unknown names: the
/// lists above come from the registry.
pub fn scene_with(name: &str, config: Config) -> SceneDesc {
    let mut desc = scenes::builtin(name).unwrap_or_else(|| panic!("scene {name} is listed"));
    let den = i32::try_from(config.rate).unwrap_or(i32::MAX);
    desc.dt = Real::ratio(1, den);
    desc.settings.iterations = config.iterations;
    desc.settings.substeps = config.substeps.max(1);
    // Sleeping off, as in the Rapier world (`can_sleep(false)`): the
    // side-by-side compares the work of awake bodies.
    desc.settings.sleep_time_threshold = tamias2d::space::SLEEP_NEVER;
    desc
}

/// Sleeping as the sleeping table of the report sets it in both engines:
/// the engine's default idle speed, 0.05 m/s, scaled by the scene's
/// [`length_unit`] (so 0.5 units/s in the pixel-unit scenes of section A,
/// as their collision slop is scaled), and the default 0.5 s sleep time.
/// Returns `(idle_speed_threshold, sleep_time_threshold)`.
pub fn sleep_settings(name: &str) -> (Real, Real) {
    let unit = Real::from_int(length_unit(name) as i32);
    (
        DEFAULT_IDLE_SPEED_THRESHOLD.mul_const(unit),
        DEFAULT_SLEEP_TIME_THRESHOLD,
    )
}

/// [`sleep_settings`] for the Rapier world ([`RapierSleep`] maps them).
pub fn rapier_sleep(name: &str) -> RapierSleep {
    let (idle, time) = sleep_settings(name);
    RapierSleep {
        idle_speed: idle.to_f32(),
        time: time.to_f32(),
    }
}

/// [`scene_with`] with sleeping on as [`sleep_settings`] says (instead of
/// off).
pub fn scene_sleeping(name: &str, config: Config) -> SceneDesc {
    let mut desc = scene_with(name, config);
    let (idle, time) = sleep_settings(name);
    desc.settings.idle_speed_threshold = idle;
    desc.settings.sleep_time_threshold = time;
    desc
}

/// Length scale Rapier should be told about (`IntegrationParameters::length_unit`):
/// section A is in pixel-like units with 10-unit bodies and gravity 100
/// (10 units per metre), everything else is SI.
pub fn length_unit(name: &str) -> f32 {
    if name.starts_with("bowl_") || name.starts_with("bouncy_") || name == "no_collide" {
        10.0
    } else {
        1.0
    }
}

/// Steps to run before timing starts, so that piles have formed and warm
/// starting is in effect (rain: until every row has been released).
pub fn warmup_steps(name: &str) -> u32 {
    if let Some(n) = name.strip_prefix("rain_") {
        let n: u32 = n.parse().unwrap_or(1000);
        let rows = n.div_ceil(scenes::stacking::RAIN_ROW);
        rows * scenes::stacking::RAIN_INTERVAL
    } else {
        300
    }
}

/// Median of `xs` (sorted in place); 0 for an empty slice.
pub fn median(xs: &mut [f64]) -> f64 {
    if xs.is_empty() {
        return 0.0;
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}
