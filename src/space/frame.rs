//! The frame: what a step can change, saved and restored every frame of a
//! rollback game without touching the level.
//!
//! A [`FrameState`] is the [`WorldState`] minus the level (static bodies
//! and their shapes, see `space::level`), plus the level's digest: the
//! settings, every other body and shape slot (live or free) with the
//! arenas' free lists and lengths, the arbiters live and dormant, the
//! counters and the constraints. Constraints and arbiters may name level
//! objects by handle: handles are slot and generation, which the digest
//! covers.
//!
//! * [`Space::save_frame`] copies the frame into a reused `FrameState`
//!   (no allocation once its buffers have grown): the cost is the frame's,
//!   whatever the level's size.
//! * [`Space::restore_frame`] puts it back. It refuses, with
//!   [`SpaceError::LevelMismatch`], a frame whose level digest is not the
//!   world's: a frame of another level (or of this level before a change)
//!   would otherwise pair its contacts and joints with objects it never
//!   saw. The level, its static tree and its shapes' cached geometry stay
//!   as they are: nothing is rebuilt.
//! * [`Space::checksum`] hashes the frame and the level digest, so it too
//!   costs the frame's size; [`FrameState::checksum`] is the same value
//!   computed from a saved frame.
//! * Bytes: `snapshot::save_frame_into` / `Space::load_frame_snapshot`
//!   (validated), see `snapshot::frame`.
//!
//! **Rolling back across a level change.** Changing the level (adding,
//! removing, moving or reshaping a static body or a static body's shape)
//! changes its digest, so frames saved before the change no longer restore
//! (an error, the world untouched). A game that edits its level during play
//! either makes the edit part of its inputs and keeps full snapshots
//! (`Space::state` / `restore_state`, or `snapshot::save`) for the frames
//! around it, or undoes the edit before restoring an older frame: the digest
//! is a function of the level's contents, slots and generations, so the
//! level as it was gives the digest it had (a removed and re-added shape
//! has a new generation, hence another digest).
//!
//! The level is static bodies *as the state holds them*: a force, torque
//! or bias velocity set on a static body (the step clears them), or a
//! custom integrator on one, changes the level at the next step. A body
//! the game moves every frame belongs in the frame: make it kinematic.
use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::{Body, BodyType};
use crate::constraint::Constraint;
use crate::math::Vect;

use super::frame_state::FrameState;
use super::level::LevelIndex;
use super::{Space, SpaceError, WorldState};

impl Space {
    /// Whether a body handed out by `body_mut` as dynamic or kinematic is
    /// static now (see `space::level`): the static caches do not hold it.
    pub(crate) fn suspect_turned_static(&self) -> bool {
        self.caches.level_suspects.iter().any(|&(i, _)| {
            self.state
                .bodies
                .get_by_index(i)
                .is_some_and(|(_, b)| b.body_type() == BodyType::Static)
        })
    }

    /// Runs `f` on the level index, computing it first if the cache was
    /// dropped or a suspect body (see `space::level`) became static.
    pub(crate) fn with_level<R>(&self, f: impl FnOnce(&LevelIndex) -> R) -> R {
        let cached = self.caches.level.take();
        let suspects_changed = self.suspect_turned_static();
        let level = match cached {
            Some(level) if !suspects_changed => level,
            _ => LevelIndex::of(&self.state),
        };
        let out = f(&level);
        self.caches.level.set(Some(level));
        out
    }

    /// Drops the level cache (the level may have changed).
    pub(crate) fn forget_level(&mut self) {
        self.caches.level.set(None);
    }

    /// Settles the suspects of `body_mut` (start of a step): one that is
    /// static now was not when it was handed out, so the level changed
    /// (see [`flag_level_suspects`](Self::flag_level_suspects)); one that
    /// was dynamic and is not any more may leave arbiters without a dynamic
    /// body, which are dropped. The list is cleared.
    pub(crate) fn settle_level_suspects(&mut self) {
        if self.caches.level_suspects.is_empty() {
            return;
        }
        self.flag_level_suspects();
        let bodies = &self.state.bodies;
        let lost_dynamic = self.caches.level_suspects.iter().any(|&(i, was_dynamic)| {
            was_dynamic
                && bodies
                    .get_by_index(i)
                    .is_some_and(|(_, b)| b.body_type() != BodyType::Dynamic)
        });
        self.caches.level_suspects.clear();
        if lost_dynamic {
            self.drop_pairs_without_dynamic_body();
        }
    }

    /// The caches' part of settling the suspects, which changes no state
    /// (for the frame installs, which must leave the world untouched when
    /// they fail): a suspect that is static now drops the level cache and
    /// flags the statics (its shapes' cache entries and the static tree
    /// must be redone; the shape-cache stage walks the level's slots only when statics
    /// are clean). The list stays for the step's settling.
    fn flag_level_suspects(&mut self) {
        if self.suspect_turned_static() {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
    }

    /// Removes the arbiters (live and dormant) of which neither body is
    /// dynamic any more — left by a dynamic body replaced in place by a
    /// static or kinematic one through `body_mut` while it touched
    /// something: such a pair never collides, and a state holding one is
    /// invalid. Live touching pairs get their separate callbacks, as when
    /// a shape is removed.
    fn drop_pairs_without_dynamic_body(&mut self) {
        let bodies = &self.state.bodies;
        let keeps = |arb: &Arbiter| {
            bodies.get(arb.body_a).is_some_and(Body::is_dynamic)
                || bodies.get(arb.body_b).is_some_and(Body::is_dynamic)
        };
        let mut removed = Vec::new();
        self.state.arbiters.retain(|arb| {
            let keep = keeps(arb);
            if !keep && !arb.is_cached() {
                removed.push(arb.clone());
            }
            keep
        });
        self.state.dormant_arbiters.retain(keeps);
        for mut arb in removed {
            self.handlers.separate(
                &mut arb,
                &self.state.bodies,
                &self.state.shapes,
                &mut self.post_step,
            );
        }
    }

    /// Digest of the level: the static bodies and their shapes, with their
    /// slots and generations (see [`FrameState`]). Cached; recomputed after
    /// a change to the level.
    pub fn level_digest(&self) -> u64 {
        self.with_level(|l| l.digest)
    }

    /// Copies the frame (everything but the level) into `out`, reusing its
    /// buffers.
    pub fn save_frame(&self, out: &mut FrameState) {
        self.with_level(|level| {
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
            } = &self.state;
            out.level_digest = level.digest;
            out.settings.clone_from(settings);
            bodies.save_part(&level.body_runs, &mut out.bodies);
            shapes.save_part(&level.shape_runs, &mut out.shapes);
            out.arbiters.clone_from(arbiters);
            out.stamp = *stamp;
            out.steps = *steps;
            out.current_dt = *current_dt;
            out.prev_dt = *prev_dt;
            out.constraints.clone_from(constraints);
            out.dormant_arbiters.clone_from(dormant_arbiters);
        });
    }

    /// The level mismatch or tiling error of `frame` against this world's
    /// level, if any (the checks that make installing it exact).
    pub(crate) fn check_frame_fits(&self, frame: &FrameState) -> Result<(), SpaceError> {
        self.with_level(|level| {
            if frame.level_digest != level.digest {
                return Err(SpaceError::LevelMismatch {
                    frame: frame.level_digest,
                    world: level.digest,
                });
            }
            frame
                .bodies
                .check_against(&level.body_runs)
                .map_err(|e| SpaceError::FrameMismatch(format!("bodies: {e}")))?;
            frame
                .shapes
                .check_against(&level.shape_runs)
                .map_err(|e| SpaceError::FrameMismatch(format!("shapes: {e}")))
        })
    }

    /// Restores a frame saved by [`save_frame`](Self::save_frame) from this
    /// world or from one with the same level (a clone, a peer). The level
    /// and everything derived from it stay (no static tree rebuild).
    /// Callbacks as with [`restore_state`](Self::restore_state): handlers
    /// and integrators stay, pending post-step callbacks are discarded.
    ///
    /// Like `restore_state`, trusts the frame's contents (it came from
    /// `save_frame`); bytes from elsewhere go through
    /// `Space::load_frame_snapshot`, which validates them. Errors (the
    /// world untouched): [`SpaceError::LevelMismatch`] for a frame of
    /// another level; [`SpaceError::FrameMismatch`] for a frame whose slots
    /// do not fit around this level.
    pub fn restore_frame(&mut self, frame: &FrameState) -> Result<(), SpaceError> {
        self.flag_level_suspects();
        self.check_frame_fits(frame)?;
        let origin = self.origin;
        let Some(level) = self.caches.level.take() else {
            // `check_frame_fits` just cached it.
            return Err(SpaceError::FrameMismatch("level index missing".into()));
        };
        let state = &mut self.state;
        state.settings.clone_from(&frame.settings);
        state
            .bodies
            .restore_part(&level.body_runs, &frame.bodies, |_| {});
        state
            .shapes
            .restore_part(&level.shape_runs, &frame.shapes, |s| {
                s.body = s.body.with_origin(origin)
            });
        state.arbiters.clone_from(&frame.arbiters);
        state.stamp = frame.stamp;
        state.steps = frame.steps;
        state.current_dt = frame.current_dt;
        state.prev_dt = frame.prev_dt;
        state.constraints.clone_from(&frame.constraints);
        state.dormant_arbiters.clone_from(&frame.dormant_arbiters);
        adopt_shared(
            origin,
            &mut state.arbiters,
            &mut state.dormant_arbiters,
            &mut state.constraints,
        );
        self.after_frame_install(&level);
        self.caches.level.set(Some(level));
        Ok(())
    }

    /// Installs a decoded, untrusted frame: checks that it fits the level,
    /// swaps it in, validates the result (the level's own objects are
    /// trusted: they are this world's, unchanged), and swaps back on any
    /// error, leaving the world exactly as it was.
    /// Errors: [`SpaceError::LevelMismatch`], [`SpaceError::FrameMismatch`],
    /// or [`SpaceError::RejectedState`] naming the broken invariant.
    pub(crate) fn install_frame_validated(
        &mut self,
        frame: &mut FrameState,
        complete: &mut dyn FnMut(&mut Arbiter, Vect, Vect),
    ) -> Result<(), SpaceError> {
        self.flag_level_suspects();
        self.check_frame_fits(frame)?;
        if self.limits.same_settings && frame.settings != self.state.settings {
            return Err(SpaceError::FrameMismatch(
                "the frame's settings differ from this world's (Limits::same_settings)".into(),
            ));
        }
        let Some(level) = self.caches.level.take() else {
            return Err(SpaceError::FrameMismatch("level index missing".into()));
        };
        let bookkeeping = frame
            .bodies
            .check_bookkeeping(&level.body_runs)
            .map_err(|e| format!("bodies: {e}"))
            .and_then(|()| {
                frame
                    .shapes
                    .check_bookkeeping(&level.shape_runs)
                    .map_err(|e| format!("shapes: {e}"))
            });
        if let Err(e) = bookkeeping {
            self.caches.level.set(Some(level));
            return Err(SpaceError::RejectedState(e));
        }
        let origin = self.origin;
        for s in frame.shapes.values_mut() {
            s.body = s.body.with_origin(origin);
        }
        adopt_constraints(origin, &mut frame.constraints);
        swap_frame(&mut self.state, &level, frame);
        adopt_arbiters(&mut self.state, origin, complete);
        let checked = super::validate_state_trusting_level(&self.state, &level)
            .map_err(SpaceError::RejectedState)
            .and_then(|()| {
                // Counts and settings only: a frame's candidate pairs are
                // bounded by its first step (which stops at the limit), as
                // a broadphase here would add about 40% to every load.
                self.limits
                    .check_counts(&self.state)
                    .map_err(SpaceError::OverLimit)
            });
        if checked.is_err() {
            swap_frame(&mut self.state, &level, frame);
        }
        if let Err(e) = checked {
            self.caches.level.set(Some(level));
            return Err(e);
        }
        self.after_frame_install(&level);
        self.caches.level.set(Some(level));
        Ok(())
    }

    /// The caches a new frame invalidates; the level's stay.
    fn after_frame_install(&mut self, level: &LevelIndex) {
        self.post_step.clear();
        self.caches.broadphase.sleepers_dirty = true;
        self.caches.broadphase.sleeping_count = None;
        self.caches.body_shapes.refresh_frame(
            &self.state.shapes,
            &level.body_runs,
            &level.shape_runs,
        );
        self.caches.step.dt_constants = [None, None];
    }
}

/// Puts the origin tag on the handles of the frame's arbiters and
/// constraints (shapes are adopted as they are installed).
fn adopt_shared(
    origin: u32,
    arbiters: &mut [Arbiter],
    dormant: &mut [Arbiter],
    constraints: &mut Arena<Constraint>,
) {
    for arb in arbiters.iter_mut().chain(dormant) {
        adopt_arbiter(origin, arb);
    }
    adopt_constraints(origin, constraints);
}

/// Puts the origin tag on an arbiter's handles.
fn adopt_arbiter(origin: u32, arb: &mut Arbiter) {
    arb.shape_a = arb.shape_a.with_origin(origin);
    arb.shape_b = arb.shape_b.with_origin(origin);
    arb.body_a = arb.body_a.with_origin(origin);
    arb.body_b = arb.body_b.with_origin(origin);
}

/// Puts the origin tag on the handles of the constraints.
fn adopt_constraints(origin: u32, constraints: &mut Arena<Constraint>) {
    if constraints.origin() != origin {
        constraints.set_origin(origin);
        for (_, c) in constraints.iter_mut() {
            c.a = c.a.with_origin(origin);
            c.b = c.b.with_origin(origin);
        }
    }
}

/// Exchanges the frame part of `state` with `frame` (its own inverse).
fn swap_frame(state: &mut WorldState, level: &LevelIndex, frame: &mut FrameState) {
    use core::mem::swap;
    let FrameState {
        level_digest: _, // equal to the world's (checked)
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
    } = frame;
    swap(&mut state.settings, settings);
    state.bodies.swap_part(&level.body_runs, bodies);
    state.shapes.swap_part(&level.shape_runs, shapes);
    swap(&mut state.arbiters, arbiters);
    swap(&mut state.stamp, stamp);
    swap(&mut state.steps, steps);
    swap(&mut state.current_dt, current_dt);
    swap(&mut state.prev_dt, prev_dt);
    swap(&mut state.constraints, constraints);
    swap(&mut state.dormant_arbiters, dormant_arbiters);
}

/// Gives each arbiter of an installed frame the world's origin and the
/// bodies of its shapes (frame bytes do not carry them, see
/// `snapshot::frame_codec`), then lets `complete` rebuild what the bytes
/// hold relative to the bodies' positions. An arbiter whose shapes or
/// bodies are gone keeps what it has: validation names it.
fn adopt_arbiters(
    state: &mut WorldState,
    origin: u32,
    complete: &mut dyn FnMut(&mut Arbiter, Vect, Vect),
) {
    let (shapes, bodies) = (&state.shapes, &state.bodies);
    for a in state
        .arbiters
        .iter_mut()
        .chain(state.dormant_arbiters.iter_mut())
    {
        adopt_arbiter(origin, a);
        if let (Some(sa), Some(sb)) = (shapes.get(a.shape_a), shapes.get(a.shape_b)) {
            a.body_a = sa.body;
            a.body_b = sb.body;
            if let (Some(ba), Some(bb)) = (bodies.get(sa.body), bodies.get(sb.body)) {
                complete(a, ba.p, bb.p);
            }
        }
    }
}
