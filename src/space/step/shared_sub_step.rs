//! The soft step's sub-step with the solver bodies shared between threads
//! from the first sub-step to the last.
//!
//! The contact passes split between threads run on the shared copy of the
//! solver bodies (`solver::sweep::SharedBody`). Copied in and out around
//! each group of passes, that was two copies of every body per group, two
//! groups a sub-step, each a hand-over to the threads. When nothing
//! between the passes reads the solver bodies in place (no joint, no
//! custom integrator), the bodies are shared once per step instead, and
//! the body stages read and write the shared copy directly, fused where
//! they follow one another: store the velocities, integrate the velocities
//! (one pass over the bodies); store the velocities, integrate the
//! positions, track the motion (another). Every body is worked on alone,
//! so the fused stages give the bits of the stages one after the other.
use core::sync::atomic::{AtomicBool, Ordering::Relaxed};

use crate::body::{Body, BodyHandle, BodyType};
use crate::math::{Real, Vect};
use crate::solver::contact_solver::store_velocity;
use crate::solver::soft_contact::{Motion, SoftContactParams, SoftPass};
use crate::solver::sweep::SharedBody;

use super::super::Space;
use super::positions::BODY_PIECE;
use super::StepContext;

impl Space {
    /// Whether this step's sub-steps keep the solver bodies shared between
    /// threads throughout: the contact passes split (threads, and at
    /// least `split_min` manifolds), and no joint or custom integrator
    /// reads or writes the solver bodies in place between them.
    ///
    /// The joints are the space's, not the joint rows: those are built in
    /// the first sub-step, so before it they are the step before's (none
    /// on a first step, after a load, or when a joint's bodies wake up),
    /// and the shared sub-steps, which have no joint stages, would skip
    /// the joints of this step.
    pub(super) fn keeps_bodies_shared(&self, split_min: usize) -> bool {
        self.caches.threads.parallel()
            && self.caches.soft_contacts.manifolds() >= split_min
            && self.state.constraints.is_empty()
            && self.integrators.velocity.is_empty()
            && self.integrators.position.is_empty()
    }

    /// Sub-step `i` of length `h` on the shared bodies
    /// ([`keeps_bodies_shared`](Self::keeps_bodies_shared)): the stages of
    /// `soft_sub_step` without the joints', in the same order.
    pub(super) fn shared_sub_step(
        &mut self,
        h: Real,
        i: usize,
        contacts: &SoftContactParams,
        forces: &[(BodyHandle, Vect, Real)],
        warm: Option<Real>,
    ) {
        if i > 0 {
            // Only the force and torque accumulators change: before the
            // velocities' store (fused below) as after it.
            self.add_forces_again(forces);
        }
        let ctx = self.step_context(h);
        self.integrate_shared_velocities(&ctx, i > 0); // IntegrateVelocities
        let warm = warm.map(|c| if i == 0 { c } else { Real::ONE });
        let passes = [
            SoftPass::WarmStart(warm),
            SoftPass::Solve { use_bias: true },
        ];
        self.shared_contact_passes(contacts, &passes); // WarmStart, Solve
        self.move_shared_bodies(h); // IntegratePositions
        let relax = [SoftPass::Solve { use_bias: false }];
        self.shared_contact_passes(contacts, &relax); // Relax
    }

    /// Contact `passes` on the shared bodies.
    fn shared_contact_passes(&mut self, contacts: &SoftContactParams, passes: &[SoftPass]) {
        let graph = &self.caches.solver.graph;
        self.caches
            .soft_contacts
            .solve_shared(graph, contacts, passes);
    }

    /// [`Stage::IntegrateVelocities`](super::Stage::IntegrateVelocities)
    /// on the shared bodies, after the velocities' store from them when
    /// `store_first` (every sub-step but the first): the bodies' new
    /// velocities into the shared copy.
    fn integrate_shared_velocities(&mut self, ctx: &StepContext, store_first: bool) {
        let g = self.state.settings.gravity;
        let (damping, dt) = (ctx.damping, ctx.dt);
        let g_dt = g * dt;
        let level_touched = AtomicBool::new(false);
        let shared = self.caches.soft_contacts.shared_bodies();
        self.state.bodies.zip_values_mut_split(
            shared,
            BODY_PIECE,
            &|body: &mut Body, s: &SharedBody| {
                if store_first {
                    store_velocity(body, &s.load());
                }
                if body.is_sleeping() {
                    return;
                }
                if body.body_type() == BodyType::Static
                    && (body.f != Vect::ZERO || !body.t.is_zero())
                {
                    level_touched.store(true, Relaxed);
                }
                body.update_velocity_by(g, g_dt, damping, dt);
                let (v, w) = (body.velocity(), body.angular_velocity());
                s.set_velocity_bits([v.x.to_bits(), v.y.to_bits(), w.to_bits()]);
            },
        );
        if level_touched.into_inner() {
            self.forget_level();
        }
    }

    /// The velocities' store from the shared bodies,
    /// [`Stage::IntegratePositions`](super::Stage::IntegratePositions) and
    /// the contacts' motion tracking, in one pass over the bodies.
    fn move_shared_bodies(&mut self, h: Real) {
        let level_touched = AtomicBool::new(false);
        let (shared, motion) = self.caches.soft_contacts.shared_bodies_and_motion();
        self.state.bodies.zip_values_mut2_split(
            shared,
            motion,
            BODY_PIECE,
            &|body: &mut Body, s: &SharedBody, m: &mut Motion| {
                store_velocity(body, &s.load());
                if body.is_sleeping() {
                    return;
                }
                if body.body_type() == BodyType::Static
                    && (body.v_bias != Vect::ZERO || !body.w_bias.is_zero())
                {
                    level_touched.store(true, Relaxed);
                }
                body.update_position(h);
                m.track(body);
            },
        );
        if level_touched.into_inner() {
            self.forget_level();
        }
    }
}
