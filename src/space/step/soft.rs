//! The soft step (`Solver::Soft`, Box2D v3's scheme in fixed point): the
//! stages of [`Stage::SOFT_STEP`](super::Stage::SOFT_STEP).
//!
//! Once per step: shape caches, broadphase and narrowphase at the current
//! poses, then the contacts' rows (anchors and separation at the collide,
//! effective masses, restitution's approach speed). Then, in each of
//! [`SoftStep::substeps`] sub-steps of `h`: integrate velocities (gravity,
//! damping, forces), the joints' rows from the current poses, warm start,
//! one soft solve (contacts whose separation is re-estimated from the
//! bodies' motion, then joints), integrate positions, one relax pass
//! without bias. After the sub-steps: restitution, the store, bullets
//! swept to their time of impact, post-solve handlers and sleep.
//!
//! Handlers and callbacks run once per step: begin, pre-solve and separate
//! in the narrowphase, post-solve after the restitution, the joints'
//! pre-solve callbacks before the first sub-step and post-solve after the
//! last, post-step callbacks at the end. The joints' rows are rebuilt every
//! sub-step from the poses, so their error is re-measured every time.
//!
//! The soft coefficients come from the first sub-step's length (sub-steps
//! differ by at most one ulp) and the settings, once per step.
use crate::body::BodyHandle;
use crate::math::{Real, Vect};
use crate::solver::soft_contact::{SoftContactParams, SoftPass, StoreImpulses};
use crate::solver::softness::Softness;

use super::super::{ContactPrecision, SoftStep, Space, SpaceError};
use super::sub_step_dts;

/// The fewest manifolds the soft passes split between threads.
const SPLIT_MIN_MANIFOLDS: usize = 64;

/// The soft step's coefficients of one step.
struct SoftCoefficients {
    contacts: SoftContactParams,
    joints: Softness,
}

impl SoftCoefficients {
    /// From the settings and the sub-step length `h`: contact and joint
    /// frequencies capped at a quarter of the sub-step rate (stiffer than
    /// that, the implicit spring of one sub-step overshoots), contacts with
    /// a body that does not move at twice the contact frequency.
    fn new(soft: &SoftStep, h: Real, friction: bool, restitution: bool) -> Self {
        let h_inv = h.recip();
        let quarter = h_inv * Real::lit("0.25");
        let contact_hz = soft.contact_hertz.min(quarter);
        let joint_hz = soft.joint_hertz.min(quarter);
        let zeta = soft.contact_damping_ratio;
        SoftCoefficients {
            contacts: SoftContactParams {
                contact: Softness::new(contact_hz, zeta, h),
                fixed: Softness::new(contact_hz + contact_hz, zeta, h),
                h_inv,
                slop: soft.slop,
                push_out: soft.push_out_speed,
                restitution_threshold: soft.restitution_threshold,
                friction,
                restitution,
                narrow: soft.contact_precision == ContactPrecision::Narrow,
            },
            joints: Softness::new(joint_hz, soft.joint_damping_ratio, h),
        }
    }
}

impl Space {
    /// One soft step of `dt > 0` (a sub-step of [`Space::step`] when
    /// `Settings::substeps` > 1). An error only when the broadphase finds
    /// more candidate pairs than the limits allow: nothing moved then.
    pub(super) fn soft_step(&mut self, dt: Real, soft: SoftStep) -> Result<(), SpaceError> {
        self.locked = true;
        // 2^64 steps never happen: never saturates.
        self.state.stamp = self.state.stamp.saturating_add(1);
        self.state.prev_dt = self.state.current_dt;
        self.state.current_dt = dt;
        let settings = &self.state.settings;
        let substeps = soft.substeps.max(1);
        let h = sub_step_dts(dt, substeps).next().unwrap_or(dt);
        let coef = SoftCoefficients::new(&soft, h, settings.friction, settings.restitution);
        let warm_starting = settings.warm_starting;

        let threads = self.caches.threads.clone();
        let active = threads.awake(|| {
            self.record_sweep_starts(); // Bullets: the start poses
            self.update_shape_caches(); // ShapeCaches
            self.update_constraint_filter(); // JointFilter
            if !self.find_pairs() {
                return None; // Broadphase: over the pair limit
            }
            while self.wake_touched_islands() {
                self.update_shape_caches(); // Wake
                if !self.find_pairs() {
                    return None;
                }
            }
            let active = self.collide_pairs(); // Narrowphase
            self.load_solver_bodies(); // SolverBodies
            let rows = self.caches.soft_contacts.prepare(
                &mut self.caches.solver,
                &self.state.arbiters,
                &self.state.bodies,
                &active,
                &coef.contacts,
            ); // Prepare: contacts
            self.caches.step.stats.solver_contacts = rows;
            Some(active)
        });
        let Some(active) = active else {
            self.locked = false;
            return Err(self.over_pair_limit());
        };
        self.run_constraint_callbacks(super::super::constraints::Phase::PreSolve);
        let mut forces = core::mem::take(&mut self.caches.step.soft_forces);
        forces.clear();
        if substeps > 1 {
            forces.extend(
                self.state
                    .bodies
                    .iter()
                    .filter(|(_, b)| b.f != Vect::ZERO || !b.t.is_zero())
                    .map(|(h, b)| (h, b.f, b.t)),
            );
        }
        let first_coef = self.warm_start_coef();
        // With threads, the impulse store walks every arbiter in pieces the
        // threads share; without handlers (nothing between it and the
        // post-solve stage reads what a settle changes), that walk also
        // settles them, instead of a walk of its own on this thread.
        let store = StoreImpulses {
            split: threads.parallel(),
            settle: (threads.parallel() && self.handlers.is_empty()).then_some(self.state.stamp),
        };
        let settled = threads.awake(|| {
            self.caches.soft_contacts.use_wide(
                self.caches.kernels.wide(),
                coef.contacts.narrow,
                &self.caches.solver.graph,
                &self.caches.solver.bodies,
            );
            let shared = self.keeps_bodies_shared(SPLIT_MIN_MANIFOLDS);
            if shared {
                let soft = &mut self.caches.soft_contacts;
                soft.share_bodies(&self.caches.solver.bodies);
            }
            for (i, h_i) in sub_step_dts(dt, substeps).enumerate() {
                let warm = warm_starting.then_some(first_coef);
                if shared {
                    self.shared_sub_step(h_i, i, &coef.contacts, &forces, warm);
                } else {
                    self.soft_sub_step(h_i, i, &coef, &forces, warm);
                }
            }
            if shared {
                let soft = &self.caches.soft_contacts;
                soft.unshare_bodies(&mut self.caches.solver.bodies);
            }
            // With the threads still awake: the narrow batches' write-back
            // (the restitution's first act) and the velocities' store split
            // between them.
            let (soft, bodies) = (
                &mut self.caches.soft_contacts,
                &mut self.caches.solver.bodies,
            );
            soft.restitution(bodies, &coef.contacts); // Restitution
            let settled = soft.store_impulses(&mut self.state.arbiters, store); // Store
            self.caches.solver.store_velocities(&mut self.state.bodies);
            settled
        });
        self.caches.step.soft_forces = forces;
        self.run_constraint_callbacks(super::super::constraints::Phase::PostSolve);
        if !self.caches.ccd.bullets.is_empty() {
            self.update_shape_caches();
            self.sweep_bullets(); // Bullets
        }
        self.count_saturated_bodies(); // Diagnostics
        self.post_solve(&active, settled); // PostSolve
        self.update_sleep(dt, &active); // Sleep
        self.caches.arbiters.active = active;
        self.locked = false;
        self.run_post_step_callbacks(); // PostStepCallbacks
        Ok(())
    }

    /// Passes over the soft contacts, in order: with threads, each color
    /// split between them; on one, in place in the same order (the same
    /// bits).
    fn soft_contact_passes(&mut self, params: &SoftContactParams, passes: &[SoftPass]) {
        let solver = &mut self.caches.solver;
        let soft = &mut self.caches.soft_contacts;
        // A few manifolds are not worth sharing the bodies for (any split
        // gives the same bits).
        if self.caches.threads.parallel() && soft.manifolds() >= SPLIT_MIN_MANIFOLDS {
            soft.solve_split(&mut solver.bodies, &solver.graph, params, passes);
            return;
        }
        for &pass in passes {
            match pass {
                SoftPass::WarmStart(warm) => soft.warm_start(&mut solver.bodies, warm),
                SoftPass::Solve { use_bias } => soft.solve(&mut solver.bodies, params, use_bias),
            }
        }
    }

    /// The forces and torques set before the step, added again for a
    /// sub-step after the first (integrating the velocities clears them).
    pub(super) fn add_forces_again(&mut self, forces: &[(BodyHandle, Vect, Real)]) {
        for &(b, f, t) in forces {
            if let Some(body) = self.state.bodies.get_mut(b) {
                body.f += f;
                body.t += t;
            }
        }
    }

    /// Sub-step `i` of length `h`: velocities, the joints' rows, the warm
    /// start (the first sub-step's scaled by `min(dt / prev_dt, 1)`),
    /// solve, positions, relax.
    fn soft_sub_step(
        &mut self,
        h: Real,
        i: usize,
        coef: &SoftCoefficients,
        forces: &[(BodyHandle, Vect, Real)],
        warm: Option<Real>,
    ) {
        if i > 0 {
            // The solver bodies hold the velocities; the forces act in
            // every sub-step.
            self.caches.solver.store_velocities(&mut self.state.bodies);
            self.add_forces_again(forces);
        }
        let ctx = self.step_context(h);
        self.integrate_velocities(&ctx); // IntegrateVelocities
        self.prepare_constraint_rows(ctx.dt, ctx.dt_inv, Some(coef.joints)); // Prepare: joints
        let warm = warm.map(|c| if i == 0 { c } else { Real::ONE });
        let (warm_start, solve) = (
            SoftPass::WarmStart(warm),
            SoftPass::Solve { use_bias: true },
        );
        match warm {
            // The joints' warm start comes between the contacts' and the
            // solve.
            Some(c) if !self.caches.constraints.is_empty() => {
                self.soft_contact_passes(&coef.contacts, &[warm_start]); // WarmStart
                self.caches
                    .constraints
                    .warm_start(&mut self.caches.solver.bodies, c);
                self.soft_contact_passes(&coef.contacts, &[solve]); // Solve
            }
            _ => self.soft_contact_passes(&coef.contacts, &[warm_start, solve]), // WarmStart, Solve
        }
        self.caches
            .constraints
            .iterate(&mut self.caches.solver.bodies);
        self.caches.solver.store_velocities(&mut self.state.bodies);
        self.integrate_positions(h); // IntegratePositions
        self.caches.soft_contacts.track_motion(&self.state.bodies);
        self.soft_contact_passes(&coef.contacts, &[SoftPass::Solve { use_bias: false }]); // Relax
        self.caches.constraints.relax();
        self.caches
            .constraints
            .iterate(&mut self.caches.solver.bodies);
        self.caches.constraints.store(&mut self.state.constraints);
    }
}
