//! [`WorldState`](super::WorldState): everything that affects future steps, and nothing
//! else. Plain data (`Clone`, `Eq`, `Hash`, serde): what a snapshot
//! serializes, what the checksum hashes, what a rollback copies.
use core::hash::{Hash, Hasher};

use serde::{Deserialize, Serialize};

use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::Body;
use crate::constraint::Constraint;
use crate::math::Real;
use crate::shape::Shape;

use super::settings::Settings;

/// Everything that affects future steps: what a snapshot holds.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct WorldState {
    /// Settings.
    pub settings: Settings,
    /// Bodies.
    pub bodies: Arena<Body>,
    /// Shapes.
    pub shapes: Arena<Shape>,
    /// Arbiters, sorted by `(shape_a, shape_b)` slot index.
    pub arbiters: Vec<Arbiter>,
    /// Number of sub-steps taken (MIS `stamp`: arbiters count in it).
    pub stamp: u64,
    /// Number of [`Space::step`](super::Space::step) calls with `dt > 0` (each is `substeps`
    /// sub-steps; scenes schedule spawns by it).
    pub steps: u64,
    /// `dt` of the last (sub-)step (0 before the first).
    pub current_dt: Real,
    /// `dt` of the (sub-)step before (scales warm starting).
    pub prev_dt: Real,
    /// Constraints (joints), in slot order (the order they are solved in).
    pub constraints: Arena<Constraint>,
    /// Arbiters of sleeping islands, sorted by pair key like `arbiters`
    /// (no pair in both): kept with their contacts and impulses while the
    /// island sleeps; their `stamp` holds their age (see `space::sleep`).
    pub dormant_arbiters: Vec<Arbiter>,
}

/// The derive's hash (each field in declaration order), except that a
/// constraint arena that never held a constraint (no slots) adds nothing:
/// a world without joints has the checksum it had before constraints
/// existed, so the committed goldens of joint-free scenes stay valid. An
/// arena with slots (live or freed) is hashed whole, after the counters.
impl Hash for WorldState {
    fn hash<H: Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let WorldState {
            settings,
            bodies,
            shapes,
            arbiters,
            stamp,
            steps,
            current_dt,
            prev_dt,
            constraints,
            dormant_arbiters,
        } = self;
        settings.hash(h);
        bodies.hash(h);
        shapes.hash(h);
        hash_tail(
            h,
            (arbiters, *stamp, *steps, *current_dt, *prev_dt),
            constraints,
            dormant_arbiters,
        );
    }
}

/// The fields after the arenas, hashed alike by the state's `Hash`, a
/// frame's checksum and a world's checksum: one order, written once.
pub(super) fn hash_tail<H: Hasher>(
    h: &mut H,
    (arbiters, stamp, steps, current_dt, prev_dt): (&Vec<Arbiter>, u64, u64, Real, Real),
    constraints: &Arena<Constraint>,
    dormant_arbiters: &Vec<Arbiter>,
) {
    arbiters.hash(h);
    stamp.hash(h);
    steps.hash(h);
    current_dt.hash(h);
    prev_dt.hash(h);
    // A world that never had a constraint slot hashes none (as before
    // joints existed).
    if constraints.capacity_slots() > 0 {
        constraints.hash(h);
    }
    dormant_arbiters.hash(h);
}
