//! [`FrameState`]: the part of a world that changes from frame to frame
//! (everything but the level), what a rollback game saves every frame
//! (see `space::frame` for the save and restore), and the checksum walk a
//! frame and a live world share.
use core::hash::{Hash, Hasher};

use serde::{Deserialize, Serialize};

use crate::arbiter::Arbiter;
use crate::arena::{Arena, ArenaPart};
use crate::body::Body;
use crate::checksum::WordHasher;
use crate::constraint::Constraint;
use crate::math::Real;
use crate::shape::Shape;

use super::level::LevelIndex;
use super::settings::Settings;
use super::state::{hash_tail, WorldState};

/// The per-frame state of a world (see the module docs). Made by
/// [`Space::save_frame`](super::Space::save_frame); its fields are private: it is only ever a copy of
/// a world's frame.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FrameState {
    pub(crate) level_digest: u64,
    pub(crate) settings: Settings,
    pub(crate) bodies: ArenaPart<Body>,
    pub(crate) shapes: ArenaPart<Shape>,
    pub(crate) arbiters: Vec<Arbiter>,
    pub(crate) stamp: u64,
    pub(crate) steps: u64,
    pub(crate) current_dt: Real,
    pub(crate) prev_dt: Real,
    pub(crate) constraints: Arena<Constraint>,
    pub(crate) dormant_arbiters: Vec<Arbiter>,
}

impl FrameState {
    /// Digest of the level this frame belongs to.
    pub fn level_digest(&self) -> u64 {
        self.level_digest
    }

    /// Number of [`Space::step`](super::Space::step) calls of the world it was saved from.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Number of body slots held (every body slot of the world outside
    /// the level).
    pub fn body_slots(&self) -> usize {
        self.bodies.held()
    }

    /// [`Space::checksum`](super::Space::checksum) of the world this frame was saved from (equal
    /// by construction: one hashing sequence for both).
    pub fn checksum(&self) -> u64 {
        let mut h = WordHasher::default();
        let FrameState {
            level_digest,
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
        h.write_u64(*level_digest);
        settings.hash(&mut h);
        bodies.hash_into(&mut h);
        shapes.hash_into(&mut h);
        hash_tail(
            &mut h,
            (arbiters, *stamp, *steps, *current_dt, *prev_dt),
            constraints,
            dormant_arbiters,
        );
        h.finish()
    }
}

impl WorldState {
    /// [`Space::checksum`](super::Space::checksum) of a space holding this state (the level found
    /// and hashed on the way: for a live space, `Space::checksum` is
    /// cheaper, its level digest is cached).
    pub fn checksum(&self) -> u64 {
        world_checksum(self, &LevelIndex::of(self))
    }
}

/// The world's checksum: the frame walk of [`FrameState::checksum`] over the
/// live state.
pub(crate) fn world_checksum(state: &WorldState, level: &LevelIndex) -> u64 {
    let mut h = WordHasher::default();
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
    } = state;
    h.write_u64(level.digest);
    settings.hash(&mut h);
    bodies.hash_part(&level.body_runs, &mut h);
    shapes.hash_part(&level.shape_runs, &mut h);
    hash_tail(
        &mut h,
        (arbiters, *stamp, *steps, *current_dt, *prev_dt),
        constraints,
        dormant_arbiters,
    );
    h.finish()
}
