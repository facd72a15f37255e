//! One view of both engines: step, read body states, measure penetration.
//!
//! Penetration is measured **per touching pair** (the deepest point of the
//! pair), on the positions at the end of a step:
//! * Tamias2D: arbiters touching this step; a pair's depth is the largest
//!   `-dist` of its contacts. Our narrowphase runs after the positions are
//!   integrated, so these are the end-of-step positions.
//! * Rapier: pairs with an active contact; the depth is recomputed with
//!   parry's exact `contact` query on the colliders' current poses, not read
//!   from the manifold, because Rapier's contact recycling (on by default)
//!   leaves manifold `dist` values stale by up to
//!   `normalized_contact_recycle_distance` (0.05 length units), and because
//!   its manifolds are computed before the solver moves the bodies.
//!
//! Both counts leave out pairs that do not overlap (Rapier's speculative
//! contacts, our cached arbiters).
use crate::{SceneDesc, ScriptedWorld};
use tamias2d::arbiter::ArbiterState;
use tamias2d::body::BodyType;

use crate::bench::Config;

/// A body's state at one moment, engine-independent.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyState {
    /// Position of the body origin.
    pub position: [f64; 2],
    /// Angle (radians, counter-clockwise).
    pub angle: f64,
    /// Linear velocity.
    pub velocity: [f64; 2],
    /// Angular velocity.
    pub angular_velocity: f64,
    /// Kinetic energy ½mv² + ½Iω² (0 for static and kinematic bodies).
    pub energy: f64,
    /// True for dynamic bodies.
    pub dynamic: bool,
}

/// Penetration of the overlapping pairs at one moment, or accumulated over
/// several moments with [`Penetration::merge`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Penetration {
    /// Deepest overlap.
    pub max: f64,
    /// Sum of the pairs' overlaps.
    pub sum: f64,
    /// Number of overlapping pairs counted.
    pub pairs: u64,
}

impl Penetration {
    /// Counts one pair overlapping by `depth` (ignored when ≤ 0).
    pub fn add(&mut self, depth: f64) {
        if depth > 0.0 {
            self.max = self.max.max(depth);
            self.sum += depth;
            self.pairs += 1;
        }
    }

    /// Adds another measurement.
    pub fn merge(&mut self, other: Penetration) {
        self.max = self.max.max(other.max);
        self.sum += other.sum;
        self.pairs += other.pairs;
    }

    /// Mean overlap of the counted pairs (0 if none).
    pub fn mean(&self) -> f64 {
        if self.pairs == 0 {
            0.0
        } else {
            self.sum / self.pairs as f64
        }
    }
}

/// What the report needs from an engine.
pub trait Engine {
    /// Engine name for tables.
    fn name(&self) -> &'static str;
    /// One step of the scene (all of its sub-steps).
    fn step(&mut self);
    /// Number of bodies so far (initial and spawned), in creation order.
    fn body_count(&self) -> usize;
    /// State of body `index` in creation order (description order, then
    /// spawns in order).
    fn body(&self, index: usize) -> BodyState;
    /// Penetration of the pairs overlapping now.
    fn penetration(&self) -> Penetration;
    /// Dynamic bodies asleep now.
    fn sleeping_bodies(&self) -> usize;

    /// States of every body, in creation order.
    fn states(&self) -> Vec<BodyState> {
        (0..self.body_count()).map(|i| self.body(i)).collect()
    }

    /// Total kinetic energy of the dynamic bodies.
    fn kinetic_energy(&self) -> f64 {
        (0..self.body_count()).map(|i| self.body(i).energy).sum()
    }
}

/// A Tamias2D scene; one report step is one `ScriptedWorld::step` (sub-steps are
/// the library's, `Settings::substeps`).
pub struct TamiasRun {
    /// The scene (its `dt` is the whole step).
    pub scene: ScriptedWorld,
}

impl TamiasRun {
    /// Builds `desc`, which [`scene_with`](super::scene_with) made for
    /// `config` (its sub-steps are in `desc.settings.substeps`).
    pub fn new(desc: &SceneDesc, config: Config) -> TamiasRun {
        assert_eq!(desc.settings.substeps, config.substeps.max(1));
        let scene = desc
            .build()
            .unwrap_or_else(|e| panic!("scene {} builds: {e}", desc.name));
        TamiasRun { scene }
    }
}

impl Engine for TamiasRun {
    fn name(&self) -> &'static str {
        "Tamias2D"
    }

    fn step(&mut self) {
        self.scene
            .step()
            .unwrap_or_else(|e| panic!("tamias step: {e}"));
    }

    fn body_count(&self) -> usize {
        self.scene.bodies().len()
    }

    fn body(&self, index: usize) -> BodyState {
        let Some(b) = self
            .scene
            .bodies()
            .get(index)
            .and_then(|h| self.scene.space.body(*h))
        else {
            return BodyState::default();
        };
        let (px, py) = b.position().to_f64();
        let (vx, vy) = b.velocity().to_f64();
        BodyState {
            position: [px, py],
            angle: b.angle().to_f64(),
            velocity: [vx, vy],
            angular_velocity: b.angular_velocity().to_f64(),
            energy: b.kinetic_energy().to_f64(),
            dynamic: b.body_type() == BodyType::Dynamic,
        }
    }

    fn sleeping_bodies(&self) -> usize {
        self.scene.space.sleeping_bodies()
    }

    fn penetration(&self) -> Penetration {
        let space = &self.scene.space;
        let mut pen = Penetration::default();
        for arb in space.arbiters() {
            if matches!(arb.state(), ArbiterState::Cached | ArbiterState::Ignore) {
                continue;
            }
            let (sa, sb) = arb.shapes();
            let sensor = |h| space.shape(h).is_some_and(|s| s.sensor);
            if sensor(sa) || sensor(sb) {
                continue;
            }
            let depth = (0..arb.count())
                .filter_map(|i| arb.depth(i))
                .map(|d| d.to_f64())
                .fold(0.0, f64::max);
            pen.add(depth);
        }
        pen
    }
}
