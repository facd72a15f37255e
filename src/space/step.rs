//! One simulation step (MIS `spaceStep`), in the MIS/Chipmunk order:
//!
//! 1. integrate positions with last step's velocities (plus bias velocities);
//! 2. move shapes into world space and update their bounding boxes;
//!
//!    2b. bullets only: sweep each bullet from its pose before stage 1 to
//!    its new one against static and kinematic shapes, and put it back at
//!    the time of impact (`ccd.rs`);
//! 3. broadphase: candidate pairs in canonical order;
//! 4. narrowphase: filter, collide, match arbiters by feature id (warm start),
//!    run begin / pre-solve handlers;
//! 5. retire arbiters of pairs that stopped touching (separate handlers,
//!    expiry) — in the same merge pass as stage 4;
//! 6. load the solver bodies: velocities and inverse masses into one
//!    contiguous array;
//! 7. pre-step: effective masses, bias and bounce (all divisions here);
//! 8. integrate velocities (gravity, damping, forces);
//! 9. apply cached impulses (warm start), scaled by `min(dt / prev_dt, 1)`;
//! 10. solver iterations: bias, normal and friction impulses;
//! 11. store the solver results: velocities back into the bodies,
//!     accumulated impulses back into the arbiters' manifold points;
//! 12. diagnostics: count saturated bodies;
//! 13. post-solve handlers, first contacts become normal;
//! 14. post-step callbacks.
//!
//! With [`Settings::substeps`](super::Settings::substeps) = n, [`Space::step`]
//! runs stages 1–14 n times on sub-steps of `dt` split exactly (see
//! [`sub_step_dts`]): bit for bit the same as n calls with those lengths.
//! Collision runs in every sub-step because positions move in every one;
//! running it once per step and only the solver n times (Box2D v3's and
//! Rapier's choice) needs a contact model that tracks separation between
//! sub-steps, which ours (Chipmunk's) does not.
//!
//! The solver switches of the settings (warm starting, friction,
//! restitution, bias impulses) are read once per step: a switched-off part
//! is not computed at all (a separate monomorphised iteration routine, a
//! skipped stage), rather than tested for in the inner loop.
//!
//! Every loop runs in arena or arbiter order; nothing depends on a hash,
//! an address or a thread.
use core::mem;

use crate::arbiter::Arbiter;
use crate::body::{BodyHandle, BodyType};
use crate::broadphase::Proxy;
use crate::collision::collide;
use crate::math::{Real, Vect};
use crate::solver::block::ManifoldBlock;
use crate::solver::{
    effective_mass, sweep, ContactConstraint, ContactFeatures, ContactParams, PairParams,
    SolverBody, SolverScratch,
};

use crate::math::exp;

use super::{ShapeCache, Space, SpaceError, StepStats};

/// Per-`dt` constants: the only `pow`, reciprocal and such of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DtConstants {
    pub(crate) dt: Real,
    pub(crate) dt_inv: Real,
    /// `damping^dt`.
    pub(crate) damping: Real,
    /// `1 − collision_bias^dt`.
    pub(crate) bias_coef: Real,
}

/// The step driver's caches in the space (not simulation state).
#[derive(Default)]
pub(crate) struct StepCache {
    /// Constants of the last two distinct step lengths (cleared when
    /// settings change): two, because sub-steps of a step that `substeps`
    /// does not divide evenly differ by one ulp.
    pub(crate) dt_constants: [Option<DtConstants>; 2],
    /// Forces and torques set before a sub-stepped step, re-applied before
    /// each of its later sub-steps.
    pub(crate) frame_forces: Vec<(BodyHandle, Vect, Real)>,
    /// Counters of the last (sub-)step.
    pub(crate) stats: StepStats,
    /// With threads: the pieces of stage 2 and what each found (scratch,
    /// kept so that a warm step does not allocate).
    pub(crate) cache_pieces: Vec<CachePiece>,
}

/// The lengths of the `substeps` sub-steps of a step of `dt`, in order:
/// with `q = dt / substeps` and `r = dt mod substeps` on the raw bits, the
/// first `r` last `q + 1` ulp and the others `q`, so they sum to `dt`
/// exactly and differ by at most one ulp. Zero-length sub-steps (when `dt`
/// is shorter than `substeps` ulp) are left out; `substeps = 0` counts as 1;
/// a negative `dt` gives nothing.
///
/// ```
/// use tamias2d::math::Real;
/// use tamias2d::space::sub_step_dts;
/// let dts: Vec<Real> = sub_step_dts(Real::from_bits(10), 4).collect();
/// assert_eq!(dts, [3, 3, 2, 2].map(Real::from_bits));
/// ```
pub fn sub_step_dts(dt: Real, substeps: u32) -> impl Iterator<Item = Real> {
    let n = i64::from(substeps.max(1));
    let bits = dt.to_bits().max(0);
    // n ≥ 1 and bits ≥ 0: the checked division and remainder never fail
    // (the fallbacks are unreachable), and q + 1 ≤ bits whenever r > 0.
    let (q, r) = (
        bits.checked_div(n).unwrap_or(bits),
        bits.checked_rem(n).unwrap_or(0),
    );
    (0..n)
        .map(move |i| Real::from_bits(q.wrapping_add(i64::from(i < r))))
        .filter(|d| d.is_positive())
}

impl Space {
    /// MIS `spaceStep`: advances the world by `dt`, in
    /// [`Settings::substeps`](super::Settings::substeps) sub-steps. `dt == 0`
    /// does nothing; a negative `dt` is an error and changes nothing, and so
    /// is a dynamic body without mass ([`SpaceError::MasslessDynamicBody`]:
    /// it would fall through everything).
    ///
    /// `dt` may change from one call to the next anywhere in the documented
    /// range (1/10,000 to 1/30 s): warm starting scales the cached impulses
    /// by `min(dt / prev_dt, 1)`, so energy stays bounded (a shorter step
    /// after a longer one only starts the solver from less).
    pub fn step(&mut self, dt: Real) -> Result<(), SpaceError> {
        if dt.is_negative() {
            return Err(SpaceError::NegativeTimeStep);
        }
        if dt.is_zero() {
            return Ok(());
        }
        self.check_unlocked()?;
        self.settle_level_suspects();
        // A body's mass is summed from shapes added after it, so the first
        // point where a missing mass is known for sure is the step.
        if let Some((h, _)) = self.state.bodies.iter().find(|(_, b)| !b.can_step()) {
            return Err(SpaceError::MasslessDynamicBody(h.with_origin(self.origin)));
        }
        // 2^64 steps never happen: never saturates.
        self.state.steps = self.state.steps.saturating_add(1);
        let substeps = self.state.settings.substeps;
        if substeps <= 1 {
            self.sub_step(dt)?;
            return self.check_step_invariants();
        }
        // The split is fixed here: a post-step callback that changes the
        // settings affects the next step, not the rest of this one.
        let mut forces = mem::take(&mut self.caches.step.frame_forces);
        forces.clear();
        forces.extend(
            self.state
                .bodies
                .iter()
                .filter(|(_, b)| b.f != Vect::ZERO || !b.t.is_zero())
                .map(|(h, b)| (h, b.f, b.t)),
        );
        for (i, sub_dt) in sub_step_dts(dt, substeps).enumerate() {
            if i > 0 {
                self.reapply_forces(&forces);
            }
            if let Err(e) = self.sub_step(sub_dt) {
                self.caches.step.frame_forces = forces;
                return Err(e);
            }
        }
        self.caches.step.frame_forces = forces;
        self.check_step_invariants()
    }

    /// Adds the forces and torques the step started with to the bodies that
    /// still exist (velocity integration cleared them).
    fn reapply_forces(&mut self, forces: &[(BodyHandle, Vect, Real)]) {
        for &(h, f, t) in forces {
            if let Some(body) = self.state.bodies.get_mut(h) {
                body.f += f;
                body.t += t;
            }
        }
    }

    /// Stages 1–14 for one (sub-)step of `dt > 0`. An error only when
    /// the broadphase finds more candidate pairs than the space's limits
    /// allow: the sub-step then stops after stage 3 (bodies moved, no
    /// contact touched).
    fn sub_step(&mut self, dt: Real) -> Result<(), SpaceError> {
        self.locked = true;
        // 2^64 sub-steps never happen: never saturates.
        self.state.stamp = self.state.stamp.saturating_add(1);
        self.state.prev_dt = self.state.current_dt;
        self.state.current_dt = dt;
        let dtc = self.dt_constants(dt);
        let features = self.contact_features();

        // Stages 1-10 hold the parallel ones: the threads stay awake.
        let threads = self.caches.threads.clone();
        let active = threads.awake(|| {
            self.record_sweep_starts(); // 1: bullets' start poses (ccd.rs)
            self.integrate_positions(dt); // 1
            self.update_shape_caches(); // 2
            self.sweep_bullets(); // 2b: bullets to their time of impact (ccd.rs)
            self.update_constraint_filter(); // 4: collide_bodies = false
            if !self.find_pairs() {
                return None; // 3: over the pair limit
            }

            // 3b: a moving shape touching a sleeping one wakes its island,
            // whose shapes then move too: stages 2-3 again (at most once
            // per island woken, so it ends).
            while self.wake_touched_islands() {
                self.update_shape_caches();
                if !self.find_pairs() {
                    return None;
                }
            }
            let active = self.collide_pairs(); // 4, 5
            self.load_solver_bodies(); // 6
            self.pre_step(&active, &dtc, features); // 7
            self.pre_step_constraints(dtc.dt, dtc.dt_inv); // 7: after the contacts
            self.integrate_velocities(&dtc); // 8
            self.warm_start_and_solve(features); // 9, 10
            Some(active)
        });
        let Some(active) = active else {
            self.locked = false;
            let max = self.limits.max_pairs;
            return Err(SpaceError::OverLimit(crate::limits::LimitError {
                limit: "candidate pairs",
                value: max.saturating_add(1),
                max,
            }));
        };
        self.store_solver_results(); // 11
        self.store_constraint_impulses(); // 11
        self.count_saturated_bodies(); // 12
        self.post_solve(&active); // 13
        self.update_sleep(dt, &active); // 13b
        self.caches.arbiters.active = active;

        self.locked = false;
        self.run_post_step_callbacks(); // 14
        Ok(())
    }

    /// Per-`dt` constants, recomputed only when `dt` or the settings change.
    fn dt_constants(&mut self, dt: Real) -> DtConstants {
        let cached = self.caches.step.dt_constants;
        if let Some(c) = cached.iter().flatten().find(|c| c.dt == dt) {
            return *c;
        }
        let s = &self.state.settings;
        let c = DtConstants {
            dt,
            dt_inv: dt.recip(),
            damping: exp::pow(s.damping, dt),
            bias_coef: Real::ONE - exp::pow(s.collision_bias, dt),
        };
        self.caches.step.dt_constants = [Some(c), cached[0]];
        c
    }

    /// The solver switches of the settings.
    fn contact_features(&self) -> ContactFeatures {
        let s = &self.state.settings;
        ContactFeatures {
            warm_starting: s.warm_starting,
            friction: s.friction,
            restitution: s.restitution,
            bias_impulses: s.bias_impulses,
        }
    }

    /// Stage 1: `p += (v + v_bias)·dt` and the same for the angle.
    fn integrate_positions(&mut self, dt: Real) {
        if self.caches.threads.parallel() && self.integrators.position.is_empty() {
            // With threads and no custom integrator, body by body between
            // them: what the loop below does then, the same bits.
            let level_touched = core::sync::atomic::AtomicBool::new(false);
            self.state
                .bodies
                .for_each_value_split(BODY_PIECE, &|body: &mut crate::body::Body| {
                    if body.is_sleeping() {
                        return;
                    }
                    if body.body_type() == BodyType::Static
                        && (body.v_bias != crate::math::Vect::ZERO || !body.w_bias.is_zero())
                    {
                        level_touched.store(true, core::sync::atomic::Ordering::Relaxed);
                    }
                    body.update_position(dt);
                });
            if level_touched.into_inner() {
                self.forget_level();
            }
            return;
        }
        let custom = &mut self.integrators.position;
        let mut moved_static = false;
        let mut level_touched = false;
        let mut moved_by_hand = Vec::new();
        for (h, body) in self.state.bodies.iter_mut() {
            if body.is_sleeping() {
                continue;
            }
            match custom.get_mut(&h) {
                Some(f) => {
                    // A custom integrator may move even a static body: its
                    // shapes' cache entries and the static tree are redone.
                    moved_static |= body.body_type() == BodyType::Static;
                    if !body.is_dynamic() {
                        moved_by_hand.push(h);
                    }
                    f(body, dt)
                }
                None => {
                    // Clearing a static body's bias velocities (set through
                    // the API) changes the level (`space::level`).
                    level_touched |= body.body_type() == BodyType::Static
                        && (body.v_bias != crate::math::Vect::ZERO || !body.w_bias.is_zero());
                    body.update_position(dt)
                }
            }
        }
        if level_touched {
            self.forget_level();
        }
        if moved_static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
        // Sleeping piles do not see a static or kinematic body that an
        // integrator teleports (only velocities are noticed): wake them.
        for h in moved_by_hand {
            self.wake_for_moved(h);
        }
    }

    /// Stage 2: world-space geometry and bounding box of every shape of a
    /// non-static body; static shapes' entries are rewritten only when
    /// `statics_dirty` says statics changed (the API calls that can add,
    /// remove, move or reshape a static shape, `restore_state` and a new
    /// space set it), otherwise kept from the step that wrote them. A live
    /// slot whose body is static but whose entry was not written for a
    /// static body (a body replaced in place through `body_mut`) is written
    /// now and marks the statics dirty. Also lists the moving shapes' boxes,
    /// in slot order, for the sweep of stage 3.
    fn update_shape_caches(&mut self) {
        let caches = &mut self.caches.shapes;
        let bp = &mut self.caches.broadphase;
        let rewrite = Rewrite {
            statics: bp.statics_dirty,
            sleepers: bp.sleepers_dirty,
        };
        bp.sleepers.clear();
        let mut statics_changed = false;
        let bodies = &self.state.bodies;
        let shapes = &self.state.shapes;
        let slots = shapes.capacity_slots();
        caches.resize(slots, None);
        bp.proxies.clear();
        // While the statics are clean, every level slot holds its static
        // entry already: walk the other slots only, so a big level costs
        // nothing here (`space::level`; a change to the level flags the
        // statics, and the walk is then complete).
        let level = if rewrite.statics {
            None
        } else {
            Some(
                self.caches
                    .level
                    .take()
                    .unwrap_or_else(|| super::level::LevelIndex::of(&self.state)),
            )
        };
        let skip: &[(u32, u32)] = level.as_ref().map_or(&[], |l| &l.shape_runs);
        if self.caches.threads.parallel() {
            // With threads: the slots outside the level in pieces, each
            // listing its own boxes, joined in slot order as below.
            let pieces = &mut self.caches.step.cache_pieces;
            pieces.clear();
            for gap in crate::arena::gaps(skip, slots as u32) {
                let mut start = gap.start;
                while start < gap.end {
                    let end = start.saturating_add(SHAPE_PIECE).min(gap.end);
                    pieces.push(CachePiece {
                        slots: start..end,
                        ..CachePiece::default()
                    });
                    start = end;
                }
            }
            let view = (shapes, bodies, rewrite);
            update_caches_split(&view, caches, 0, pieces);
            for piece in pieces.iter() {
                bp.proxies.extend_from_slice(&piece.proxies);
                bp.sleepers.extend_from_slice(&piece.sleepers);
                statics_changed |= piece.statics_changed;
            }
        } else {
            for i in crate::arena::outside_runs(skip, slots as u32) {
                let Some(entry) = caches.get_mut(i as usize) else {
                    continue;
                };
                let written = update_cache_entry(entry, i, shapes, bodies, rewrite);
                statics_changed |= written.static_entry;
                match written.listed {
                    Listed::Neither => {}
                    Listed::Moving(p) => bp.proxies.push(p),
                    Listed::Sleeping(p) => bp.sleepers.push(p),
                }
            }
        }
        if statics_changed {
            bp.statics_dirty = true;
            // Also a body made static in place (`body_mut`): the level changed.
            self.caches.level.set(None);
        } else if let Some(level) = level {
            self.caches.level.set(Some(level));
        }
    }

    /// Stage 3: moving shapes are swept (their boxes listed by stage 2),
    /// static shapes come from the static tree (rebuilt only when statics
    /// changed). False, with no pairs, when there are more than the
    /// space's limits allow.
    fn find_pairs(&mut self) -> bool {
        self.update_static_tree();
        self.rebuild_sleeping_tree();
        let split = self.caches.threads.parallel();
        let budget = self.limits.pair_budget();
        let bp = &mut self.caches.broadphase;
        bp.sweep.find_pairs_with(
            &bp.proxies,
            &bp.static_tree,
            &bp.sleeping_tree,
            split,
            budget,
        )
    }

    /// The sleeping tree from this step's sleeping boxes, if they changed
    /// (bodies fell asleep or woke since the last build).
    fn rebuild_sleeping_tree(&mut self) {
        let bp = &mut self.caches.broadphase;
        if bp.sleepers_dirty {
            bp.sleeping_tree = crate::broadphase::StaticTree::build(bp.sleepers.clone());
            bp.sleepers_dirty = false;
        }
    }

    /// Stage 3's first half (also run by stage 2b when there are bullets):
    /// rebuilds the static tree from the static shapes' boxes if statics
    /// changed.
    pub(super) fn update_static_tree(&mut self) {
        if self.caches.broadphase.statics_dirty {
            let statics: Vec<Proxy> = self
                .caches
                .shapes
                .iter()
                .enumerate()
                .filter_map(|(i, c)| {
                    c.as_ref().filter(|c| c.is_static).map(|c| Proxy {
                        index: i as u32,
                        bb: c.bb,
                    })
                })
                .collect();
            self.caches.broadphase.set_statics(statics);
        }
    }

    /// Stages 4–5: narrowphase and arbiter matching. Old and new arbiters
    /// are both sorted by pair key, so matching is one merge pass; arbiters
    /// whose pair is not touching are retired on the way (separate handler,
    /// expiry). Returns the indices of the arbiters to solve this step.
    fn collide_pairs(&mut self) -> Vec<u32> {
        // Double-buffered: last step's list is drained into this step's,
        // and both allocations are kept for the next step.
        let mut old = mem::take(&mut self.state.arbiters);
        let mut arbiters = mem::take(&mut self.caches.arbiters.spare);
        arbiters.clear();
        let mut active = mem::take(&mut self.caches.arbiters.active);
        active.clear();
        let pairs = mem::take(&mut self.caches.broadphase.sweep.pairs);
        self.caches.step.stats = StepStats {
            candidate_pairs: pairs.len() as u32,
            ..StepStats::default()
        };
        // With threads, every pair's narrowphase first, in parallel; then
        // the same merge.
        let mut infos = mem::take(&mut self.caches.arbiters.infos);
        let ahead = self.caches.threads.parallel();
        if ahead {
            self.collide_ahead(&pairs, &old, &mut infos);
        }
        let mut old_iter = old.drain(..);
        for (k, &(ia, ib)) in pairs.iter().enumerate() {
            // Arbiters of pairs that the broadphase no longer reports.
            while let Some(arb) = take_if(&mut old_iter, |key| key < (ia, ib)) {
                self.retire(arb, &mut arbiters);
            }
            let existing = take_if(&mut old_iter, |key| key == (ia, ib));
            // By reference: an info is 150-odd bytes, a move is a memcpy.
            let computed;
            let info = if ahead {
                infos.get(k).and_then(Option::as_ref)
            } else {
                computed = self.narrowphase(ia, ib, existing.as_ref());
                computed.as_ref()
            };
            if let Some(mut arb) = self.collide_pair(ia, ib, info, existing, &mut arbiters) {
                if self.run_contact_handlers(&mut arb) {
                    active.push(arbiters.len() as u32);
                }
                arbiters.push(arb);
            }
        }
        for arb in old_iter {
            self.retire(arb, &mut arbiters);
        }
        self.caches.broadphase.sweep.pairs = pairs;
        self.caches.arbiters.infos = infos;
        self.state.arbiters = arbiters;
        self.caches.arbiters.spare = old;
        active
    }

    /// Stage 4 for every candidate pair at once, split between threads:
    /// `infos[k]` becomes pair `k`'s narrowphase answer, warm-started from
    /// its arbiter in `old` (last step's, in canonical order like `pairs`).
    fn collide_ahead(
        &self,
        pairs: &[(u32, u32)],
        old: &[Arbiter],
        infos: &mut Vec<Option<crate::collision::CollisionInfo>>,
    ) {
        infos.clear();
        infos.resize(pairs.len(), None);
        // The warm-start ids, by the merge the serial pass makes.
        let mut old_keys = old.iter().peekable();
        let ids: Vec<u32> = pairs
            .iter()
            .map(|&key| {
                while old_keys.next_if(|a| a.key() < key).is_some() {}
                old_keys
                    .peek()
                    .filter(|a| a.key() == key)
                    .map_or(0, |a| a.warm_start_id)
            })
            .collect();
        let view = NarrowView {
            shapes: &self.state.shapes,
            bodies: &self.state.bodies,
            caches: &self.caches.shapes,
            constraints: &self.caches.constraints,
        };
        collide_split(&view, pairs, &ids, infos);
    }

    /// Stage 4 for one candidate pair: the touched arbiter (the pair's
    /// `existing` one or a new one), given the narrowphase's `info`. A pair
    /// that does not touch retires its existing arbiter into `arbiters`
    /// (stage 5) and gives `None`.
    fn collide_pair(
        &mut self,
        ia: u32,
        ib: u32,
        info: Option<&crate::collision::CollisionInfo>,
        existing: Option<Arbiter>,
        arbiters: &mut Vec<Arbiter>,
    ) -> Option<Arbiter> {
        let Some(info) = info else {
            if let Some(arb) = existing {
                self.retire(arb, arbiters);
            }
            return None;
        };
        let stats = &mut self.caches.step.stats;
        stats.touching_pairs = stats.touching_pairs.saturating_add(1);
        stats.iteration_cap_hits = stats
            .iteration_cap_hits
            .saturating_add(u32::from(info.hit_iteration_cap));
        let (ha, sa) = self.state.shapes.get_by_index(ia)?;
        let (hb, sb) = self.state.shapes.get_by_index(ib)?;
        let body_a = self.state.bodies.get(sa.body)?;
        let body_b = self.state.bodies.get(sb.body)?;
        let mut arb = existing.unwrap_or_else(|| Arbiter::new(ha, sa, hb, sb));
        let centers = (body_a.center(), body_b.center());
        arb.touch(info, sa, sb, centers, self.state.stamp);
        Some(arb)
    }

    /// Stage 5 for one arbiter whose shapes did not touch this step: the
    /// separate handler runs once (it becomes `Cached`), and it is kept in
    /// `arbiters` until it has not touched for `collision_persistence` steps.
    fn retire(&mut self, mut arb: Arbiter, arbiters: &mut Vec<Arbiter>) {
        if !arb.is_cached() {
            self.handlers.separate(
                &mut arb,
                &self.state.bodies,
                &self.state.shapes,
                &mut self.post_step,
            );
            arb.cache();
        }
        let persistence = self.state.settings.collision_persistence;
        if !arb.is_expired(self.state.stamp, persistence) {
            arbiters.push(arb);
        }
    }

    /// Filters a candidate pair and collides it; `None` if rejected or not touching.
    fn narrowphase(
        &self,
        ia: u32,
        ib: u32,
        existing: Option<&Arbiter>,
    ) -> Option<crate::collision::CollisionInfo> {
        let view = NarrowView {
            shapes: &self.state.shapes,
            bodies: &self.state.bodies,
            caches: &self.caches.shapes,
            constraints: &self.caches.constraints,
        };
        view.collide(ia, ib, existing.map_or(0, |a| a.warm_start_id))
    }

    /// Begin and pre-solve handlers; true if the arbiter goes to the solver.
    fn run_contact_handlers(&mut self, arb: &mut Arbiter) -> bool {
        let (bodies, shapes, q) = (&self.state.bodies, &self.state.shapes, &mut self.post_step);
        if arb.is_first_contact() && !self.handlers.begin(arb, bodies, shapes, q) {
            arb.ignore();
        }
        if arb.is_ignored() {
            return false;
        }
        let accept = self.handlers.pre_solve(arb, bodies, shapes, q);
        accept && !arb.sensor
    }

    /// Stage 6: copies velocities and inverse masses into the contiguous
    /// solver array (indexed by body slot).
    fn load_solver_bodies(&mut self) {
        let sb = &mut self.caches.solver.bodies;
        sb.clear();
        sb.resize(self.state.bodies.capacity_slots(), SolverBody::default());
        let mut massless = 0u32;
        for (h, body) in self.state.bodies.iter() {
            if let Some(slot) = sb.get_mut(h.index() as usize) {
                // A sleeping body is solved as if static (it is never in
                // an active contact: stage 3b woke whatever touches it).
                let dynamic = body.body_type() == BodyType::Dynamic && !body.is_sleeping();
                massless = massless.saturating_add(u32::from(dynamic && !body.can_step()));
                *slot = SolverBody {
                    v: body.velocity(),
                    w: body.angular_velocity(),
                    v_bias: body.v_bias,
                    w_bias: body.w_bias,
                    m_inv: if dynamic { body.mass_inv() } else { Real::ZERO },
                    i_inv: if dynamic {
                        body.moment_inv()
                    } else {
                        Real::ZERO
                    },
                };
            }
        }
        self.caches.step.stats.massless_dynamic_bodies = massless;
    }

    /// Stage 7: effective masses, bias and bounce for every active contact,
    /// gathered into the contiguous solver array.
    fn pre_step(&mut self, active: &[u32], dtc: &DtConstants, features: ContactFeatures) {
        let s = &self.state.settings;
        let params = ContactParams {
            dt_inv: dtc.dt_inv,
            slop: s.collision_slop,
            bias_coef: dtc.bias_coef,
            max_bias: Real::MAX,
            features,
        };
        let threads = &self.caches.threads;
        let SolverScratch {
            bodies: solver_bodies,
            constraints: contact_constraints,
            blocks,
            graph,
            color_rows,
            manifold_rows,
            manifold_blocks,
            ..
        } = &mut self.caches.solver;
        let arbiters = &self.state.arbiters;
        if !s.colored_solver {
            graph.uncolored(active);
        } else {
            graph.color(active, solver_bodies.len(), |i| {
                let movable = |slot: u32| {
                    solver_bodies
                        .get(slot as usize)
                        .is_some_and(|b| !b.m_inv.is_zero() || !b.i_inv.is_zero())
                };
                arbiters.get(i as usize).map_or([(0, false); 2], |arb| {
                    let (a, b) = (arb.body_a.index(), arb.body_b.index());
                    [(a, movable(a)), (b, movable(b))]
                })
            });
        }
        let use_blocks = s.block_solver;
        let job = PrepareJob {
            arbiters,
            bodies: solver_bodies,
            params: &params,
            friction: features.friction,
        };
        if !threads.parallel() {
            contact_constraints.clear();
            blocks.clear();
            // One thread: rows and blocks appended in order, each written
            // once (the split below writes every row twice, placing first).
            for &i in graph.order() {
                let Some(arb) = arbiters.get(i as usize) else {
                    continue;
                };
                let pair = pair_params(arb);
                let block = use_blocks && arb.contacts().len() == 2;
                let mut k_t = [Real::ZERO; 2];
                for ((n, c), k) in arb.contacts().iter().enumerate().zip(&mut k_t) {
                    let row;
                    (row, *k) = prepare_row(&job, &pair, i, n, c, block);
                    contact_constraints.push(row);
                }
                if let (true, [.., c1, c2]) = (block, contact_constraints.as_mut_slice()) {
                    if let Some(b) = finish_block(&job, c1, c2, k_t) {
                        blocks.push(b);
                        // Its index + 1 (at most 2^32 blocks: rows are counted in u32).
                        c1.block = blocks.len() as u32;
                    }
                }
            }
            self.caches.step.stats.solver_contacts = contact_constraints.len() as u32;
            return;
        }
        // Where each manifold's rows and block go, in one pass over the
        // arbiters: the manifolds can then be prepared in any order, and
        // split between threads.
        manifold_rows.clear();
        manifold_blocks.clear();
        let (mut rows, mut block_count) = (0u32, 0u32);
        for &i in graph.order() {
            manifold_rows.push(rows);
            manifold_blocks.push(block_count);
            // At most MAX_CONTACTS_PER_ARBITER (2) rows per arbiter, and
            // rows are counted in u32 like the stats.
            let n = arbiters
                .get(i as usize)
                .map_or(0, |a| a.contacts().len() as u32);
            rows = rows.saturating_add(n);
            block_count = block_count.saturating_add(u32::from(use_blocks && n == 2));
        }
        manifold_rows.push(rows);
        manifold_blocks.push(block_count);
        // Every row is written below, and a block slot is read only by the
        // row that points at it once written: last step's contents stay
        // where the lists were long enough (no 200-byte default per row).
        contact_constraints.truncate(rows as usize);
        contact_constraints.resize(rows as usize, ContactConstraint::default());
        blocks.truncate(block_count as usize);
        blocks.resize(block_count as usize, ManifoldBlock::default());
        let order = graph.order();
        let parts = ManifoldParts {
            order,
            rows: manifold_rows,
            blocks: manifold_blocks,
        };
        prepare_split(&job, parts, contact_constraints, blocks);
        for (c, first_row) in color_rows.iter_mut().enumerate() {
            let first_manifold = graph.range(c).start;
            *first_row = manifold_rows.get(first_manifold).copied().unwrap_or(0);
        }
        self.caches.step.stats.solver_contacts = contact_constraints.len() as u32;
    }

    /// Stage 8: gravity, damping and forces; clears force accumulators.
    fn integrate_velocities(&mut self, dtc: &DtConstants) {
        let g = self.state.settings.gravity;
        let custom = &mut self.integrators.velocity;
        let mut level_touched = false;
        for (h, body) in self.state.bodies.iter_mut() {
            if body.is_sleeping() {
                continue;
            }
            // A static body is part of the level (`space::level`): a custom
            // integrator on it, or clearing a force or torque the game set
            // on it, changes the level.
            let custom_fn = custom.get_mut(&h);
            level_touched |= body.body_type() == BodyType::Static
                && (custom_fn.is_some() || body.f != crate::math::Vect::ZERO || !body.t.is_zero());
            match custom_fn {
                Some(f) => f(body, g, dtc.damping, dtc.dt),
                None => body.update_velocity(g, dtc.damping, dtc.dt),
            }
            if let Some(slot) = self.caches.solver.bodies.get_mut(h.index() as usize) {
                slot.v = body.velocity();
                slot.w = body.angular_velocity();
            }
        }
        if level_touched {
            self.forget_level();
        }
    }

    /// Stage 9: re-apply last step's accumulated impulses (only called with
    /// warm starting on), scaled by `dt_coef = min(dt / prev_dt, 1)`; the
    /// scaled impulses become the accumulators the iterations start from
    /// ([`ContactConstraint::warm_start`]).
    ///
    /// Why never more than 1: a contact's impulse is part force (a resting
    /// load, proportional to `dt`) and part impact (a velocity change,
    /// independent of `dt`). Scaling the impact part up by a long step
    /// after a short one pushes the bodies apart by many times the impulse
    /// that stopped them; the iterations can take it back only as far as
    /// they propagate through a stack in `iterations` passes, and
    /// `pyramid_20` alternating 1/1000 and 1/30 s reached 27 m/s even with
    /// consistent accumulators. A guess that is too small only costs
    /// convergence (the iterations add the rest, the bias corrects the
    /// overlap), so after a longer step the cached impulse is applied
    /// unscaled. A shorter step scales it down, as before. For a constant
    /// `dt` the ratio is exactly 1 and no bit changes.
    fn warm_start(&mut self, features: ContactFeatures) {
        let dt_coef = self.warm_start_coef();
        let SolverScratch {
            bodies: solver_bodies,
            constraints: contact_constraints,
            ..
        } = &mut self.caches.solver;
        if features.friction {
            for c in contact_constraints.iter_mut() {
                c.warm_start(solver_bodies, dt_coef);
            }
        } else {
            for c in contact_constraints.iter_mut() {
                c.warm_start_normal(solver_bodies, dt_coef);
            }
        }
    }

    /// `dt_coef = min(dt / prev_dt, 1)` of the warm start (stage 9), 0
    /// after a step of no length.
    pub(super) fn warm_start_coef(&self) -> Real {
        let prev = self.state.prev_dt;
        if prev.is_zero() {
            Real::ZERO
        } else {
            (self.state.current_dt / prev).min(Real::ONE)
        }
    }

    /// Stages 9 and 10: with warm starting on, the contacts' warm start
    /// then the constraints'; then the solver iterations, with the
    /// iteration routine of the switched-on features chosen once (see
    /// [`ContactConstraint::solve_with`]). With more than one thread
    /// ([`Space::set_threads`]) and the colored solver, both run color by
    /// color on bodies the threads share ([`solver::sweep`]): the same bits.
    fn warm_start_and_solve(&mut self, features: ContactFeatures) {
        let split = self.caches.threads.parallel() && self.state.settings.colored_solver;
        let n = self.state.settings.iterations;
        if split {
            let warm = features.warm_starting.then(|| self.warm_start_coef());
            match (features.friction, features.bias_impulses) {
                (true, true) => self.solve_split::<true, true>(n, warm),
                (true, false) => self.solve_split::<true, false>(n, warm),
                (false, true) => self.solve_split::<false, true>(n, warm),
                (false, false) => self.solve_split::<false, false>(n, warm),
            }
            return;
        }
        if features.warm_starting {
            self.warm_start(features);
            self.warm_start_constraints();
        }
        match (features.friction, features.bias_impulses) {
            (true, true) => self.iterate::<true, true>(n),
            (true, false) => self.iterate::<true, false>(n),
            (false, true) => self.iterate::<false, true>(n),
            (false, false) => self.iterate::<false, false>(n),
        }
    }

    /// `n` Gauss–Seidel passes in place over the active contacts in solve
    /// order (canonical, or color by color: see [`solver::graph`]), each
    /// followed by the constraints (joints) in canonical order.
    fn iterate<const FRICTION: bool, const BIAS: bool>(&mut self, n: u32) {
        let SolverScratch {
            bodies,
            constraints: rows,
            blocks,
            ..
        } = &mut self.caches.solver;
        let joints = &mut self.caches.constraints;
        for _ in 0..n {
            sweep::solve_rows::<FRICTION, BIAS>(rows, blocks, bodies);
            joints.iterate(bodies);
        }
    }

    /// Stages 9 (with `warm = Some(dt_coef)`) and 10 on threads: each color
    /// split between them on shared bodies, the overflow in order on one,
    /// the constraints (joints) on one with the bodies unshared. The order
    /// of [`iterate`](Self::iterate) and of the serial warm start exactly.
    fn solve_split<const FRICTION: bool, const BIAS: bool>(&mut self, n: u32, warm: Option<Real>) {
        let SolverScratch {
            bodies,
            constraints: rows,
            blocks,
            color_rows,
            manifold_rows,
            graph,
            shared,
            ..
        } = &mut self.caches.solver;
        let layout = sweep::ColorLayout {
            graph,
            color_rows,
            manifold_rows,
        };
        let joints = &mut self.caches.constraints;
        sweep::share(bodies, shared);
        if let Some(dt_coef) = warm {
            let kernel = |m: &mut [ContactConstraint], copy: &mut [SolverBody; 2]| {
                sweep::warm_start_copy::<FRICTION>(m, dt_coef, copy);
            };
            sweep::for_each_color(rows, layout, shared, &kernel);
            if !joints.is_empty() {
                sweep::unshare(shared, bodies);
                joints.warm_start(bodies, dt_coef);
                sweep::share(bodies, shared);
            }
        }
        let blocks = blocks.as_slice();
        let kernel = |m: &mut [ContactConstraint], copy: &mut [SolverBody; 2]| {
            sweep::solve_copy::<FRICTION, BIAS>(m, blocks, copy);
        };
        for _ in 0..n {
            sweep::for_each_color(rows, layout, shared, &kernel);
            if !joints.is_empty() {
                sweep::unshare(shared, bodies);
                joints.iterate(bodies);
                sweep::share(bodies, shared);
            }
        }
        sweep::unshare(shared, bodies);
    }

    /// Stage 11: copies solved velocities back into the bodies and
    /// accumulated impulses back into the arbiters' manifold points (for
    /// warm starting and handlers).
    fn store_solver_results(&mut self) {
        for c in &self.caches.solver.constraints {
            let contact = self
                .state
                .arbiters
                .get_mut(c.arbiter as usize)
                .and_then(|arb| arb.contacts.get_mut(c.slot as usize));
            if let Some(contact) = contact {
                contact.jn_acc = c.jn_acc;
                contact.jt_acc = c.jt_acc;
            }
        }
        for (h, body) in self.state.bodies.iter_mut() {
            if body.body_type() != BodyType::Dynamic || body.is_sleeping() {
                continue;
            }
            if let Some(s) = self.caches.solver.bodies.get(h.index() as usize) {
                body.v = s.v;
                body.w = s.w;
                body.v_bias = s.v_bias;
                body.w_bias = s.w_bias;
            }
        }
    }

    /// Stage 12, diagnostics ([`StepStats::saturated_bodies`]): awake bodies whose
    /// position, velocity or angular velocity saturated. Runs after the
    /// solver, so it sees this step's positions and final velocities; five
    /// comparisons per body, no arithmetic.
    fn count_saturated_bodies(&mut self) {
        let saturated = self
            .state
            .bodies
            .iter()
            .filter(|(_, b)| !b.is_sleeping())
            .filter(|(_, b)| b.p.is_saturated() || b.v.is_saturated() || b.w.is_saturated())
            .count();
        self.caches.step.stats.saturated_bodies = u32::try_from(saturated).unwrap_or(u32::MAX);
    }

    /// Stage 13: post-solve handlers, then first contacts become normal.
    fn post_solve(&mut self, active: &[u32]) {
        if !self.handlers.is_empty() {
            for &i in active {
                let Some(arb) = self.state.arbiters.get_mut(i as usize) else {
                    continue;
                };
                self.handlers.post_solve(
                    arb,
                    &self.state.bodies,
                    &self.state.shapes,
                    &mut self.post_step,
                );
            }
        }
        let stamp = self.state.stamp;
        for arb in self.state.arbiters.iter_mut() {
            arb.settle(stamp);
        }
    }

    /// Stage 14: post-step callbacks, in the order they were queued.
    fn run_post_step_callbacks(&mut self) {
        // Callbacks may queue more callbacks; those run after this step too.
        while !self.post_step.is_empty() {
            let queue = mem::take(&mut self.post_step);
            for (_, f) in queue {
                f(self);
            }
        }
    }
}

/// What the narrowphase of a pair reads: the space's parts threads may
/// share (the space itself holds callbacks, which they may not).
struct NarrowView<'a> {
    shapes: &'a crate::arena::Arena<crate::shape::Shape>,
    bodies: &'a crate::arena::Arena<crate::body::Body>,
    caches: &'a [Option<ShapeCache>],
    constraints: &'a crate::constraint::solve::ConstraintScratch,
}

impl NarrowView<'_> {
    /// Filters the candidate pair of shape slots `ia`, `ib` and collides
    /// it from warm-start id `ws`; `None` if rejected or not touching.
    #[inline]
    fn collide(&self, ia: u32, ib: u32, ws: u32) -> Option<crate::collision::CollisionInfo> {
        let (_, sa) = self.shapes.get_by_index(ia)?;
        let (_, sb) = self.shapes.get_by_index(ib)?;
        if sa.body == sb.body || sa.filter.rejects(&sb.filter) || (sa.sensor && sb.sensor) {
            return None;
        }
        if self.constraints.rejects(sa.body, sb.body) {
            return None;
        }
        let ba = self.bodies.get(sa.body)?;
        let bb = self.bodies.get(sb.body)?;
        // Two bodies that cannot move, or a sleeping body and one that
        // does not move it (stage 3b woke the islands a mover touches).
        let awake = |b: &crate::body::Body| b.is_dynamic() && !b.is_sleeping();
        if !awake(ba) && !awake(bb) {
            return None;
        }
        let ca = self.caches.get(ia as usize)?.as_ref()?;
        let cb = self.caches.get(ib as usize)?.as_ref()?;
        let info = collide(&ca.geometry, &cb.geometry, ws);
        (info.count > 0).then_some(info)
    }
}

/// Which cache entries stage 2 rewrites even if written before.
#[derive(Clone, Copy)]
struct Rewrite {
    /// Static shapes' (the statics changed).
    statics: bool,
    /// Sleeping shapes' (bodies fell asleep or woke).
    sleepers: bool,
}

/// What stage 2 did with a shape slot: whether it wrote a static
/// shape's entry (the statics changed), and the list its box goes to.
struct Written {
    static_entry: bool,
    listed: Listed,
}

/// The list a written entry's box goes to.
enum Listed {
    /// None: nothing written, the slot cleared, or a static shape.
    Neither,
    /// A moving shape's: the sweep's.
    Moving(Proxy),
    /// A sleeping shape's: the sleeping tree's.
    Sleeping(Proxy),
}

impl Written {
    const NOTHING: Written = Written {
        static_entry: false,
        listed: Listed::Neither,
    };
}

/// Stage 2 for shape slot `i` and its cache `entry`.
#[inline]
fn update_cache_entry(
    entry: &mut Option<ShapeCache>,
    i: u32,
    shapes: &crate::arena::Arena<crate::shape::Shape>,
    bodies: &crate::arena::Arena<crate::body::Body>,
    rewrite: Rewrite,
) -> Written {
    let Some((s, body)) = shapes
        .get_by_index(i)
        .and_then(|(_, s)| Some((s, bodies.get(s.body)?)))
    else {
        *entry = None;
        return Written::NOTHING;
    };
    let is_static = body.body_type() == BodyType::Static;
    if is_static && !rewrite.statics && entry.as_ref().is_some_and(|c| c.is_static) {
        return Written::NOTHING;
    }
    // A sleeping body has not moved since its entry was written
    // (anything that could move it wakes it and sets the flag).
    let sleeping = body.is_sleeping();
    if sleeping && !rewrite.sleepers && entry.as_ref().is_some_and(|c| !c.is_static) {
        return Written::NOTHING;
    }
    let (pos, rot) = (body.position(), body.rotation());
    // Written over last step's entry where there is one.
    let bb = match entry {
        Some(c) => {
            s.geometry.write_world_into(pos, rot, &mut c.geometry);
            c.bb = c.geometry.bb();
            c.is_static = is_static;
            c.bb
        }
        None => {
            let geometry = s.geometry.to_world(pos, rot);
            let bb = geometry.bb();
            *entry = Some(ShapeCache {
                geometry,
                bb,
                is_static,
            });
            bb
        }
    };
    let proxy = Proxy { index: i, bb };
    Written {
        static_entry: is_static,
        listed: if sleeping {
            Listed::Sleeping(proxy)
        } else if !is_static {
            Listed::Moving(proxy)
        } else {
            Listed::Neither
        },
    }
}

/// Shape slots per piece of the split stage 2 (a few µs of work).
const SHAPE_PIECE: usize = 256;

/// A piece of the split stage 2: its slots, and what it found.
#[derive(Clone, Debug, Default)]
pub(crate) struct CachePiece {
    slots: core::ops::Range<usize>,
    proxies: Vec<Proxy>,
    sleepers: Vec<Proxy>,
    statics_changed: bool,
}

/// Stage 2 for `pieces` (in slot order), whose slots lie in `caches`
/// from slot `base` on: halves in parallel, each piece writing its own
/// entries and lists.
fn update_caches_split(
    view: &(
        &crate::arena::Arena<crate::shape::Shape>,
        &crate::arena::Arena<crate::body::Body>,
        Rewrite,
    ),
    caches: &mut [Option<ShapeCache>],
    base: usize,
    pieces: &mut [CachePiece],
) {
    let (shapes, bodies, rewrite) = *view;
    if let [piece] = pieces {
        piece.proxies.clear();
        piece.sleepers.clear();
        piece.statics_changed = false;
        let range = piece.slots.start.wrapping_sub(base)..piece.slots.end.wrapping_sub(base);
        let Some(entries) = caches.get_mut(range) else {
            return;
        };
        for (k, entry) in entries.iter_mut().enumerate() {
            // Slots are counted in u32 (the arena's indices).
            let i = piece.slots.start.wrapping_add(k) as u32;
            let written = update_cache_entry(entry, i, shapes, bodies, rewrite);
            piece.statics_changed |= written.static_entry;
            match written.listed {
                Listed::Neither => {}
                Listed::Moving(p) => piece.proxies.push(p),
                Listed::Sleeping(p) => piece.sleepers.push(p),
            }
        }
        return;
    }
    if pieces.is_empty() {
        return;
    }
    let mid = pieces.len() / 2;
    let (left, right) = pieces.split_at_mut(mid);
    let cut = right.first().map_or(base, |p| p.slots.start);
    let Some((caches_l, caches_r)) = caches.split_at_mut_checked(cut.wrapping_sub(base)) else {
        return;
    };
    crate::threads::join(
        || update_caches_split(view, caches_l, base, left),
        || update_caches_split(view, caches_r, cut, right),
    );
}

/// Body slots per piece of the split position integration (a few µs).
const BODY_PIECE: usize = 256;

/// Pairs per piece of the split narrowphase (a few µs of work).
const PAIR_PIECE: usize = 64;

/// [`NarrowView::collide`] for every pair, halves in parallel down to
/// [`PAIR_PIECE`]s: each piece writes its own slots of `infos`.
fn collide_split(
    view: &NarrowView<'_>,
    pairs: &[(u32, u32)],
    ids: &[u32],
    infos: &mut [Option<crate::collision::CollisionInfo>],
) {
    if infos.len() <= PAIR_PIECE {
        for ((info, &(ia, ib)), &ws) in infos.iter_mut().zip(pairs).zip(ids) {
            *info = view.collide(ia, ib, ws);
        }
        return;
    }
    let mid = infos.len() / 2;
    let (left, right) = infos.split_at_mut(mid);
    let (pl, pr) = (
        pairs.get(..mid).unwrap_or(&[]),
        pairs.get(mid..).unwrap_or(&[]),
    );
    let (il, ir) = (ids.get(..mid).unwrap_or(&[]), ids.get(mid..).unwrap_or(&[]));
    crate::threads::join(
        || collide_split(view, pl, il, left),
        || collide_split(view, pr, ir, right),
    );
}

/// The next arbiter of `old` if its pair key satisfies `pred`.
/// `Drain::as_slice` peeks without moving: each kept arbiter is moved once
/// out of the old list and once into the new one (they are 240 bytes).
fn take_if(
    old: &mut std::vec::Drain<'_, Arbiter>,
    pred: impl FnOnce((u32, u32)) -> bool,
) -> Option<Arbiter> {
    if old.as_slice().first().is_some_and(|a| pred(a.key())) {
        old.next()
    } else {
        None
    }
}

/// What preparing a manifold reads.
struct PrepareJob<'a> {
    arbiters: &'a [Arbiter],
    bodies: &'a [SolverBody],
    params: &'a ContactParams,
    friction: bool,
}

/// A run of manifolds in solve order: their arbiters, and the first row
/// and first block slot of each (absolute, as in the scratch) and the end.
#[derive(Clone, Copy)]
struct ManifoldParts<'a> {
    order: &'a [u32],
    rows: &'a [u32],
    blocks: &'a [u32],
}

impl<'a> ManifoldParts<'a> {
    /// The manifolds `..mid` and `mid..`.
    fn split(self, mid: usize) -> (ManifoldParts<'a>, ManifoldParts<'a>) {
        let head = |v: &'a [u32]| v.get(..=mid).unwrap_or(&[]);
        let tail = |v: &'a [u32]| v.get(mid..).unwrap_or(&[]);
        (
            ManifoldParts {
                order: self.order.get(..mid).unwrap_or(&[]),
                rows: head(self.rows),
                blocks: head(self.blocks),
            },
            ManifoldParts {
                order: self.order.get(mid..).unwrap_or(&[]),
                rows: tail(self.rows),
                blocks: tail(self.blocks),
            },
        )
    }
}

/// Manifolds per piece of the split pre-step.
const PREPARE_PIECE: usize = 32;

/// Stage 7 for the manifolds of `parts`, whose rows are `rows` and whose
/// block slots are `blocks`: halves in parallel down to
/// [`PREPARE_PIECE`]s, each writing only its own rows and slots.
fn prepare_split(
    job: &PrepareJob<'_>,
    parts: ManifoldParts<'_>,
    rows: &mut [ContactConstraint],
    blocks: &mut [ManifoldBlock],
) {
    let n = parts.order.len();
    let row_base = parts.rows.first().copied().unwrap_or(0);
    let block_base = parts.blocks.first().copied().unwrap_or(0);
    if n <= PREPARE_PIECE {
        for (k, &i) in parts.order.iter().enumerate() {
            let at = |v: &[u32], k: usize| v.get(k).copied().unwrap_or(0);
            let (r0, r1) = (at(parts.rows, k), at(parts.rows, k.wrapping_add(1)));
            let (b0, b1) = (at(parts.blocks, k), at(parts.blocks, k.wrapping_add(1)));
            let range = r0.wrapping_sub(row_base) as usize..r1.wrapping_sub(row_base) as usize;
            let (Some(arb), Some(out)) = (job.arbiters.get(i as usize), rows.get_mut(range)) else {
                continue;
            };
            // A block slot (b1 = b0 + 1) and its index + 1 for the row.
            let slot = (b1 > b0)
                .then(|| blocks.get_mut(b0.wrapping_sub(block_base) as usize))
                .flatten()
                .map(|dst| (dst, b0.saturating_add(1)));
            prepare_manifold(job, i, arb, out, slot);
        }
        return;
    }
    let mid = n / 2;
    let (left, right) = parts.split(mid);
    let row_cut = left
        .rows
        .last()
        .copied()
        .unwrap_or(row_base)
        .wrapping_sub(row_base);
    let block_cut = left
        .blocks
        .last()
        .copied()
        .unwrap_or(block_base)
        .wrapping_sub(block_base);
    let (Some((rows_l, rows_r)), Some((blocks_l, blocks_r))) = (
        rows.split_at_mut_checked(row_cut as usize),
        blocks.split_at_mut_checked(block_cut as usize),
    ) else {
        return;
    };
    crate::threads::join(
        || prepare_split(job, left, rows_l, blocks_l),
        || prepare_split(job, right, rows_r, blocks_r),
    );
}

/// Stage 7 for arbiter `i` (`arb`): its rows into `out`, and with a block
/// `slot` (a two-contact manifold, block solver on) its block, if its
/// normal matrix is well conditioned ([`finish_block`]).
fn prepare_manifold(
    job: &PrepareJob<'_>,
    i: u32,
    arb: &Arbiter,
    out: &mut [ContactConstraint],
    slot: Option<(&mut ManifoldBlock, u32)>,
) {
    let pair = pair_params(arb);
    let block = slot.is_some();
    let mut k_t = [Real::ZERO; 2];
    let rows = arb.contacts().iter().enumerate().zip(out.iter_mut());
    for (((n, c), row), k) in rows.zip(&mut k_t) {
        (*row, *k) = prepare_row(job, &pair, i, n, c, block);
    }
    let (Some((dst, id)), [c1, c2]) = (slot, out) else {
        return;
    };
    if let Some(b) = finish_block(job, c1, c2, k_t) {
        *dst = b;
        c1.block = id;
    }
}

/// What the rows of arbiter `arb` share.
#[inline]
fn pair_params(arb: &Arbiter) -> PairParams {
    PairParams {
        a: arb.body_a.index(),
        b: arb.body_b.index(),
        n: arb.normal,
        e: arb.restitution,
        friction: arb.friction,
        surface_vr: arb.surface_velocity,
    }
}

/// Stage 7 for contact `n` (`c`) of arbiter `i`: its row, and `k(t)`. A
/// row of a `block` does not get its tangent effective mass (a division):
/// the block's face friction has its own ([`finish_block`]).
#[inline(always)]
fn prepare_row(
    job: &PrepareJob<'_>,
    pair: &PairParams,
    i: u32,
    n: usize,
    c: &crate::arbiter::ManifoldPoint,
    block: bool,
) -> (ContactConstraint, Real) {
    let (mut row, k) = ContactConstraint::prepare(c, job.bodies, pair, job.params);
    if !block {
        row.t_mass = effective_mass(k);
    }
    row.arbiter = i;
    // n < MAX_CONTACTS_PER_ARBITER.
    row.slot = n as u32;
    (row, k)
}

/// The block of a two-contact manifold's rows `c1`, `c2` if its normal
/// matrix is well conditioned ([`ManifoldBlock::new`]); otherwise the rows
/// are solved on their own and get their tangent effective masses from
/// `k_t`. The caller stores the block and points `c1` at it.
#[inline]
fn finish_block(
    job: &PrepareJob<'_>,
    c1: &mut ContactConstraint,
    c2: &mut ContactConstraint,
    k_t: [Real; 2],
) -> Option<ManifoldBlock> {
    let b = ManifoldBlock::new(c1, c2, job.bodies, job.friction);
    if b.is_none() {
        c1.t_mass = effective_mass(k_t[0]);
        c2.t_mass = effective_mass(k_t[1]);
    }
    b
}
