//! The level: the static bodies and their shapes, which a rollback game
//! builds once and never saves per frame.
//!
//! A step never changes a static body or its shapes (only the game does,
//! through the API, or a custom position integrator set on a static body),
//! so a frame snapshot ([`FrameState`](super::FrameState)) leaves them out
//! and names them by a 64-bit **level digest** instead. The level is found
//! from the state alone: a live body of type [`BodyType::Static`] and every
//! live shape attached to one. [`LevelIndex`] caches the digest and the slot
//! runs the level occupies in the body and shape arenas, so that saving,
//! restoring and hashing a frame walk the other slots only.
//!
//! The cache is dropped by every change that can touch the level (the
//! places that also flag the static tree for a check: adding, removing or
//! reshaping a static body's shape, adding or removing a static body,
//! `body_mut` on a static body, a custom integrator moving one, a full
//! `restore_state`) and recomputed on first use. `body_mut` on a non-static
//! body cannot know whether the game turns it into a static one, so it
//! only records the body as a suspect; the next use checks the suspects.
//! Under the `validate` feature every step checks that the cached digest
//! is that of the state (see `Space::check_step_invariants`).
use crate::arena::Arena;
use crate::body::{Body, BodyType};
use crate::checksum::WordHasher;
use crate::shape::Shape;
use core::hash::{Hash, Hasher};

use super::WorldState;

/// Where the level lives and what it is (a cache of the state).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct LevelIndex {
    /// Digest of every level object with its slot and generation.
    pub(crate) digest: u64,
    /// Body slots of the level, as sorted disjoint runs.
    pub(crate) body_runs: Vec<(u32, u32)>,
    /// Shape slots of the level, as sorted disjoint runs.
    pub(crate) shape_runs: Vec<(u32, u32)>,
}

fn is_static(b: &Body) -> bool {
    b.body_type() == BodyType::Static
}

/// The runs of consecutive slots for which `level` holds.
fn runs(slots: impl Iterator<Item = (u32, bool)>) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = Vec::new();
    for (i, level) in slots {
        if !level {
            continue;
        }
        match out.last_mut() {
            Some(run) if run.1 == i => run.1 = i.saturating_add(1),
            _ => out.push((i, i.saturating_add(1))),
        }
    }
    out
}

/// Hashes the slots of `runs` (index, generation, object), in order.
fn hash_runs<T: Hash>(arena: &Arena<T>, runs: &[(u32, u32)], h: &mut WordHasher) {
    h.write_u64(runs.len() as u64);
    for &(a, b) in runs {
        for i in a..b {
            h.write_u32(i);
            if let Some(slot) = arena.slot(i) {
                slot.hash(h);
            }
        }
    }
}

impl LevelIndex {
    /// The level of `state`: one pass over the slots, and a hash of the
    /// level's objects.
    pub(crate) fn of(state: &WorldState) -> LevelIndex {
        let bodies = &state.bodies;
        let body_runs = runs(
            bodies
                .raw_slots()
                .map(|(i, b)| (i, b.is_some_and(is_static))),
        );
        let shape_runs = runs(state.shapes.raw_slots().map(|(i, s)| {
            (
                i,
                s.is_some_and(|s: &Shape| bodies.get(s.body).is_some_and(is_static)),
            )
        }));
        let mut h = WordHasher::default();
        // A tag, so that a level digest never equals a frame checksum.
        h.write(b"tamias2d level");
        hash_runs(&state.bodies, &body_runs, &mut h);
        hash_runs(&state.shapes, &shape_runs, &mut h);
        LevelIndex {
            digest: h.finish(),
            body_runs,
            shape_runs,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::runs;

    #[test]
    fn runs_join_consecutive_slots() {
        let flags = [true, true, false, true, false, false, true, true, true];
        let got = runs(flags.iter().enumerate().map(|(i, f)| (i as u32, *f)));
        assert_eq!(got, vec![(0, 2), (3, 4), (6, 9)]);
        assert!(runs(core::iter::empty()).is_empty());
    }
}

/// The level index cache. A `Mutex` rather than a `Cell`, so that a `Space`
/// is `Sync` (a Bevy resource, a world shared with a query thread): it is
/// filled from `&self` paths (saving a frame), never contended, and a
/// poisoned lock still holds a valid `Option`.
#[derive(Default)]
pub(crate) struct LevelCache(std::sync::Mutex<Option<LevelIndex>>);

impl LevelCache {
    /// Takes the cached index out, leaving `None`.
    pub(crate) fn take(&self) -> Option<LevelIndex> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take()
    }

    /// Replaces the cached index.
    pub(crate) fn set(&self, level: Option<LevelIndex>) {
        *self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = level;
    }
}
