//! Sleeping on in both engines: what a settling scene costs while it falls
//! and once it rests.
//!
//! Three runs of one scene go **in lockstep** (step k of each, the order
//! rotating from step to step): Tamias2D and Rapier with sleeping on, set
//! alike ([`common::sleep_settings`], [`common::RapierSleep`]), and
//! Tamias2D with sleeping off (the side-by-side's setting), so the saving
//! is measured on the same machine moments. Every step is timed; the
//! medians are taken over steps 1–300 (falling, awake) and 1201–1500
//! (settled). The bodies asleep are counted between steps, outside the
//! timed code.
use std::time::Instant;

use crate::common::{self, Config, Engine, RapierRun, TamiasRun};

/// Steps each run takes.
pub const STEPS: u32 = 1500;
/// The awake window: steps `AWAKE.0..=AWAKE.1`.
pub const AWAKE: (u32, u32) = (1, 300);
/// The settled window: steps `SETTLED.0..=SETTLED.1`.
pub const SETTLED: (u32, u32) = (1201, 1500);

/// One engine's run with sleeping on (or, for `tamias_off`, off).
#[derive(Clone, Debug, Default)]
pub struct SleepRun {
    /// Median time per step over [`AWAKE`] (s).
    pub awake: f64,
    /// Median time per step over [`SETTLED`] (s).
    pub settled: f64,
    /// Dynamic bodies asleep after the last step.
    pub asleep: usize,
    /// The step from which every dynamic body has stayed asleep to the
    /// end, if they all are at the end.
    pub all_asleep_from: Option<u32>,
}

/// One scene of the sleeping table.
#[derive(Clone, Debug)]
pub struct SleepRow {
    /// Scene name.
    pub name: String,
    /// Dynamic bodies after the last step.
    pub dynamic: usize,
    /// Rapier's `length_unit` for the scene.
    pub length_unit: f32,
    /// `idle_speed_threshold` of both (scene units per second).
    pub idle_speed: f64,
    /// `sleep_time_threshold` / `time_until_sleep` (s).
    pub sleep_time: f64,
    /// Rapier's `normalized_linear_threshold`.
    pub rapier_linear: f32,
    /// Smallest and largest Rapier `angular_threshold` of the dynamic
    /// bodies (rad/s).
    pub rapier_angular: (f32, f32),
    /// Tamias2D, sleeping on.
    pub tamias: SleepRun,
    /// Rapier, sleeping on.
    pub rapier: SleepRun,
    /// Tamias2D, sleeping off.
    pub tamias_off: SleepRun,
}

impl SleepRow {
    /// Tamias2D over Rapier in the awake window.
    pub fn awake_ratio(&self) -> f64 {
        self.tamias.awake / self.rapier.awake
    }

    /// Tamias2D over Rapier in the settled window.
    pub fn settled_ratio(&self) -> f64 {
        self.tamias.settled / self.rapier.settled
    }
}

/// Timings and sleep counts of one run.
#[derive(Default)]
struct Acc {
    awake: Vec<f64>,
    settled: Vec<f64>,
    all_asleep_from: Option<u32>,
}

/// Dynamic bodies of `e` now.
fn dynamic(e: &dyn Engine) -> usize {
    (0..e.body_count()).filter(|&i| e.body(i).dynamic).count()
}

/// Runs scene `name` with sleeping on in both engines and off in a second
/// Tamias2D world (see the module docs).
pub fn run(name: &str) -> SleepRow {
    let config = Config::DEFAULT;
    let on = common::scene_sleeping(name, config);
    let off = common::scene_with(name, config);
    let unit = common::length_unit(name);
    let sleep = common::rapier_sleep(name);
    let mut tamias = TamiasRun::new(&on, config);
    let mut rapier = RapierRun::with_sleep(&on, config, unit, Some(sleep));
    let mut tamias_off = TamiasRun::new(&off, config);
    let mut engines: [(&mut dyn Engine, Acc); 3] = [
        (&mut tamias, Acc::default()),
        (&mut rapier, Acc::default()),
        (&mut tamias_off, Acc::default()),
    ];
    for k in 1..=STEPS {
        for j in 0..3 {
            let (e, acc) = &mut engines[(k as usize + j) % 3];
            let start = Instant::now();
            e.step();
            let dt = start.elapsed().as_secs_f64();
            if (AWAKE.0..=AWAKE.1).contains(&k) {
                acc.awake.push(dt);
            } else if (SETTLED.0..=SETTLED.1).contains(&k) {
                acc.settled.push(dt);
            }
        }
        for (e, acc) in engines.iter_mut().take(2) {
            let n = dynamic(&**e);
            if n > 0 && e.sleeping_bodies() == n {
                acc.all_asleep_from.get_or_insert(k);
            } else {
                acc.all_asleep_from = None;
            }
        }
    }
    let [(t, t_acc), (r, r_acc), (o, o_acc)] = engines;
    let finish = |e: &dyn Engine, mut acc: Acc| SleepRun {
        awake: common::median(&mut acc.awake),
        settled: common::median(&mut acc.settled),
        asleep: e.sleeping_bodies(),
        all_asleep_from: acc.all_asleep_from,
    };
    let row_tamias = finish(&*t, t_acc);
    let row_rapier = finish(&*r, r_acc);
    let row_off = finish(&*o, o_acc);
    let dynamic_count = dynamic(&*t);
    let (rapier_linear, rapier_angular) = rapier_thresholds(&rapier);
    let (idle, time) = common::sleep_settings(name);
    SleepRow {
        name: name.to_owned(),
        dynamic: dynamic_count,
        length_unit: unit,
        idle_speed: idle.to_f64(),
        sleep_time: time.to_f64(),
        rapier_linear,
        rapier_angular,
        tamias: row_tamias,
        rapier: row_rapier,
        tamias_off: row_off,
    }
}

/// Rapier's linear threshold and the range of its angular thresholds over
/// the dynamic bodies.
fn rapier_thresholds(r: &RapierRun) -> (f32, (f32, f32)) {
    let mut linear = 0.0;
    let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
    for (_, rb) in r.world.bodies.iter().filter(|(_, rb)| rb.is_dynamic()) {
        let a = rb.activation();
        linear = a.normalized_linear_threshold;
        lo = lo.min(a.angular_threshold);
        hi = hi.max(a.angular_threshold);
    }
    (linear, (lo, hi))
}
