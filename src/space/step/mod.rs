//! One simulation step (MIS `spaceStep`): the driver and its stages.
//!
//! A sub-step runs the stages of [`Stage::ALL`] in that order, each a
//! function of its own file (or of the module that owns its data: the
//! contact solver's loops are `solver::contact_solver`'s, the joints'
//! `constraint::solve`'s, the bullets' sweep `space::ccd`'s, the wake and
//! sleep stages `space::sleep`'s). [`Space::step`] runs the sub-steps:
//! with [`Settings::substeps`](super::Settings::substeps) = n, all stages
//! n times on sub-steps of `dt` split exactly ([`sub_step_dts`]): bit for
//! bit the same as n calls with those lengths. On the sequential solver
//! collision runs in every sub-step because positions move in every one:
//! its contact model (Chipmunk's) does not track separation between
//! sub-steps. The soft step (`Solver::Soft`, module `soft`, the stages of
//! [`Stage::SOFT_STEP`]) does: it collides once per step and sub-steps only
//! its solver, as Box2D v3.
//!
//! The per-step constants and the solver switches are computed once per
//! sub-step into a [`StepContext`]: a switched-off part is not computed at
//! all (a separate monomorphised iteration routine, a skipped stage),
//! rather than tested for in the inner loop.
//!
//! Every loop runs in arena or arbiter order; nothing depends on a hash,
//! an address or a thread.
use core::mem;

use crate::body::{BodyHandle, BodyType};
use crate::limits::LimitError;
use crate::math::{Real, Vect};
use crate::solver::contact_solver::RowOrder;

use super::{Space, SpaceError};

mod arbiter_merge;
mod bullets;
mod context;
mod narrowphase;
mod pairs;
mod positions;
mod shape_caches;
mod shared_sub_step;
mod soft;
mod stages;

pub use context::StepStats;
pub(crate) use context::{StepCache, StepContext};
pub(crate) use shape_caches::ShapeCache;
pub use stages::Stage;

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

    /// What sharing this (sub-)step between threads would be worth, from
    /// the step before: its contact points, the joints and the bodies.
    fn parallel_work(&self) -> u32 {
        let bodies = u32::try_from(self.state.bodies.len()).unwrap_or(u32::MAX);
        let joints = u32::try_from(self.state.constraints.len()).unwrap_or(u32::MAX);
        self.caches
            .step
            .stats
            .solver_contacts
            .saturating_add(joints)
            .saturating_add(bodies)
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

    /// All stages, in [`Stage::ALL`]'s order, for one (sub-)step of
    /// `dt > 0`. An error only when the broadphase finds more candidate
    /// pairs than the space's limits allow: the sub-step then stops after
    /// [`Stage::Broadphase`] (bodies moved, no contact touched).
    fn sub_step(&mut self, dt: Real) -> Result<(), SpaceError> {
        let work = self.parallel_work();
        self.caches.threads.engage(work);
        if let super::Solver::Soft(soft) = self.state.settings.solver {
            return self.soft_step(dt, soft);
        }
        self.locked = true;
        // 2^64 sub-steps never happen: never saturates.
        self.state.stamp = self.state.stamp.saturating_add(1);
        self.state.prev_dt = self.state.current_dt;
        self.state.current_dt = dt;
        let ctx = self.step_context(dt);

        // The stages up to the solve hold the parallel ones: the threads
        // stay awake.
        let threads = self.caches.threads.clone();
        let active = threads.awake(|| {
            self.record_sweep_starts(); // Bullets: the start poses (ccd.rs)
            self.integrate_positions(dt); // IntegratePositions
            self.update_shape_caches(); // ShapeCaches
            self.sweep_bullets(); // Bullets: to their time of impact (ccd.rs)
            self.update_constraint_filter(); // JointFilter
            if !self.find_pairs() {
                return None; // Broadphase: over the pair limit
            }
            // Wake: a moving shape touching a sleeping one wakes its
            // island, whose shapes then move too: ShapeCaches and
            // Broadphase again (at most once per island woken, so it ends).
            while self.wake_touched_islands() {
                self.update_shape_caches();
                if !self.find_pairs() {
                    return None;
                }
            }
            let active = self.collide_pairs(); // Narrowphase
            self.load_solver_bodies(); // SolverBodies
            self.prepare_contacts(&active, &ctx); // Prepare
            self.pre_step_constraints(ctx.dt, ctx.dt_inv); // Prepare: joints
            self.integrate_velocities(&ctx); // IntegrateVelocities
            self.warm_start_and_solve(&ctx); // WarmStart, Solve
            Some(active)
        });
        let Some(active) = active else {
            self.locked = false;
            return Err(self.over_pair_limit());
        };
        self.caches
            .solver
            .store(&mut self.state.arbiters, &mut self.state.bodies); // Store
        self.store_constraint_impulses(); // Store: joints
        self.count_saturated_bodies(); // Diagnostics
        self.post_solve(&active, false); // PostSolve
        self.update_sleep(dt, &active); // Sleep
        self.caches.arbiters.active = active;

        self.locked = false;
        self.run_post_step_callbacks(); // PostStepCallbacks
        Ok(())
    }

    /// The error of a broadphase that found more candidate pairs than the
    /// limits allow.
    fn over_pair_limit(&self) -> SpaceError {
        let max = self.limits.max_pairs;
        SpaceError::OverLimit(LimitError {
            limit: "candidate pairs",
            value: max.saturating_add(1),
            max,
        })
    }

    /// The constants of a sub-step of `dt`: the per-`dt` ones recomputed
    /// only when `dt` or the settings change.
    fn step_context(&mut self, dt: Real) -> StepContext {
        let cache = &mut self.caches.step.dt_constants;
        StepContext::new(dt, &self.state.settings, cache)
    }

    /// [`Stage::ShapeCaches`], on the space's parts it reads and writes.
    fn update_shape_caches(&mut self) {
        shape_caches::update_shape_caches(
            &self.state,
            &mut self.caches.shapes,
            &mut self.caches.broadphase,
            &self.caches.level,
            &mut self.caches.step.cache_pieces,
        );
    }

    /// [`Stage::SolverBodies`]: velocities and inverse masses into the
    /// contiguous solver array (indexed by body slot).
    fn load_solver_bodies(&mut self) {
        let massless = self.caches.solver.load_bodies(&self.state.bodies);
        self.caches.step.stats.massless_dynamic_bodies = massless;
    }

    /// [`Stage::Prepare`] of the contacts: the solve order and one row per
    /// manifold point of each active arbiter.
    fn prepare_contacts(&mut self, active: &[u32], ctx: &StepContext) {
        let s = &self.state.settings;
        let order = RowOrder {
            colored: s.colored_solver,
            blocks: s.block_solver,
        };
        let rows = self
            .caches
            .solver
            .prepare(&self.state.arbiters, active, &ctx.contact, order);
        self.caches.step.stats.solver_contacts = rows;
    }

    /// [`Stage::WarmStart`] and [`Stage::Solve`]: the contacts' and the
    /// joints' rows. With threads and the colored order, color by color
    /// between the threads: the same bits.
    fn warm_start_and_solve(&mut self, ctx: &StepContext) {
        let split = self.caches.threads.parallel() && self.state.settings.colored_solver;
        let dt_coef = self.warm_start_coef();
        self.caches.solver.warm_start_and_solve(
            &mut self.caches.constraints,
            ctx.contact.switches,
            dt_coef,
            self.state.settings.iterations,
            split,
        );
    }

    /// [`Stage::IntegrateVelocities`]: gravity, damping and forces (or the
    /// body's custom velocity integrator); clears the force accumulators.
    /// The solver bodies get the new velocities.
    fn integrate_velocities(&mut self, ctx: &StepContext) {
        let g = self.state.settings.gravity;
        if self.integrators.velocity.is_empty() {
            // Without custom integrators, as `integrate_positions`: body by
            // body in pieces, halves in parallel where there are threads,
            // then the velocities into the solver bodies (the same bits, as
            // each body changes alone). The closures of custom integrators
            // run on the stepping thread, in slot order (below).
            let level_touched = core::sync::atomic::AtomicBool::new(false);
            let (damping, dt) = (ctx.damping, ctx.dt);
            let g_dt = g * dt;
            self.state.bodies.for_each_value_split(
                positions::BODY_PIECE,
                &|body: &mut crate::body::Body| {
                    if body.is_sleeping() {
                        return;
                    }
                    if body.body_type() == BodyType::Static
                        && (body.f != Vect::ZERO || !body.t.is_zero())
                    {
                        level_touched.store(true, core::sync::atomic::Ordering::Relaxed);
                    }
                    body.update_velocity_by(g, g_dt, damping, dt);
                },
            );
            self.state.bodies.zip_values_split(
                &mut self.caches.solver.bodies,
                positions::BODY_PIECE,
                &|body: &crate::body::Body, slot: &mut crate::solver::SolverBody| {
                    if !body.is_sleeping() {
                        slot.v = body.velocity();
                        slot.w = body.angular_velocity();
                    }
                },
            );
            if level_touched.into_inner() {
                self.forget_level();
            }
            return;
        }
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
                && (custom_fn.is_some() || body.f != Vect::ZERO || !body.t.is_zero());
            match custom_fn {
                Some(f) => f(body, g, ctx.damping, ctx.dt),
                None => body.update_velocity(g, ctx.damping, ctx.dt),
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

    /// `dt_coef = min(dt / prev_dt, 1)` of [`Stage::WarmStart`], 0
    /// after a step of no length.
    pub(super) fn warm_start_coef(&self) -> Real {
        let prev = self.state.prev_dt;
        if prev.is_zero() {
            Real::ZERO
        } else {
            (self.state.current_dt / prev).min(Real::ONE)
        }
    }

    /// [`Stage::Diagnostics`] ([`StepStats::saturated_bodies`](super::StepStats::saturated_bodies)): awake bodies whose
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

    /// [`Stage::PostSolve`]: post-solve handlers, then first contacts become
    /// normal (unless `settled`: the store did it already, with no handler
    /// to see the difference).
    fn post_solve(&mut self, active: &[u32], settled: bool) {
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
        if settled {
            return;
        }
        let stamp = self.state.stamp;
        for arb in self.state.arbiters.iter_mut() {
            arb.settle(stamp);
        }
    }

    /// [`Stage::PostStepCallbacks`]: post-step callbacks, in the order they were queued.
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
