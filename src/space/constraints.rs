//! The constraints of a space (Chipmunk `cpSpaceAddConstraint` and
//! friends) and their part of the step (the joint-filter stage and prepare to store, see
//! [`crate::constraint`]).
use super::handlers::queue_post_step;
use super::world::{ConstraintContext, ConstraintFn, PostStepFn};
use super::{Space, SpaceError};
use crate::body::{Body, BodyHandle};
use crate::constraint::{Constraint, ConstraintError, ConstraintHandle, PinJoint, PivotJoint};
use crate::math::{Real, Vect};

impl ConstraintContext<'_> {
    /// A body of the constraint's space.
    pub fn body(&self, h: BodyHandle) -> Option<&Body> {
        self.bodies.get(h)
    }

    /// Chipmunk `cpSpaceAddPostStepCallback` from a callback: runs `f`
    /// after the step, once per `key`; false if `key` is already queued.
    pub fn add_post_step_callback(&mut self, key: u64, f: PostStepFn) -> bool {
        queue_post_step(self.post_step, key, f)
    }
}

/// Which callback to run.
#[derive(Clone, Copy)]
pub(super) enum Phase {
    PreSolve,
    PostSolve,
}

impl Space {
    /// Chipmunk `cpSpaceAddConstraint`: adds a constraint and returns its
    /// handle. Its two bodies must be different live bodies of this space;
    /// its parameters are checked again ([`Constraint::validate`]).
    pub fn add_constraint(&mut self, c: Constraint) -> Result<ConstraintHandle, SpaceError> {
        self.check_unlocked()?;
        c.validate()?;
        for body in [c.a, c.b] {
            self.check_origin(body)?;
            if !self.state.bodies.contains(body) {
                return Err(SpaceError::StaleBody(body));
            }
        }
        // A joint changes its bodies' islands: both wake.
        self.wake_touching(c.a);
        self.wake_touching(c.b);
        // Stored handles carry the space's origin (the caller's may be 0).
        let c = Constraint {
            a: c.a.with_origin(self.origin),
            b: c.b.with_origin(self.origin),
            ..c
        };
        let h = self
            .state
            .constraints
            .insert(c)
            .map_err(|_| SpaceError::Full)?;
        // A new constraint starts without callbacks, even under a handle a
        // rollback re-issued (callbacks outlive their constraints).
        self.joint_callbacks.remove(&h);
        Ok(h.with_origin(self.origin))
    }

    /// Chipmunk `cpConstraintSetPreSolveFunc`: `f` runs every sub-step
    /// before the constraint is prepared for the solver, in constraint slot
    /// order (`None` removes it). Like the custom integrators, callbacks
    /// are not state and outlive `remove_constraint`, so that a rollback to
    /// a state where the constraint exists brings them back (see
    /// [`Space::restore_state`], [`Space::prune_constraint_callbacks`]).
    pub fn set_constraint_pre_solve(
        &mut self,
        h: ConstraintHandle,
        f: Option<ConstraintFn>,
    ) -> Result<(), SpaceError> {
        self.check_origin(h)?;
        if !self.state.constraints.contains(h) {
            return Err(SpaceError::StaleConstraint(h));
        }
        self.joint_callbacks.entry(h).or_default().pre_solve = f;
        Ok(())
    }

    /// Chipmunk `cpConstraintSetPostSolveFunc`: `f` runs every sub-step
    /// after the solver (the constraint's [`impulse`](Constraint::impulse)
    /// is this sub-step's), in constraint slot order, before the contacts'
    /// post-solve handlers (`None` removes it). See
    /// [`Space::set_constraint_pre_solve`] for rollback.
    pub fn set_constraint_post_solve(
        &mut self,
        h: ConstraintHandle,
        f: Option<ConstraintFn>,
    ) -> Result<(), SpaceError> {
        self.check_origin(h)?;
        if !self.state.constraints.contains(h) {
            return Err(SpaceError::StaleConstraint(h));
        }
        self.joint_callbacks.entry(h).or_default().post_solve = f;
        Ok(())
    }

    /// Drops the callbacks of constraints not in the current state (see
    /// [`Space::prune_integrators`], the same for bodies).
    pub fn prune_constraint_callbacks(&mut self) {
        let constraints = &self.state.constraints;
        self.joint_callbacks.retain(|h, _| constraints.contains(*h));
    }

    /// Runs the `phase` callbacks of the live constraints, in slot order.
    pub(super) fn run_constraint_callbacks(&mut self, phase: Phase) {
        if self.joint_callbacks.is_empty() {
            return;
        }
        let origin = self.origin;
        for (h, cb) in self.joint_callbacks.iter_mut() {
            let f = match phase {
                Phase::PreSolve => cb.pre_solve.as_mut(),
                Phase::PostSolve => cb.post_solve.as_mut(),
            };
            let (Some(f), Some(constraint)) = (f, self.state.constraints.get_mut(*h)) else {
                continue;
            };
            // As in Chipmunk, a sleeping island's joints are not solved and
            // their callbacks do not run (keep a servo's bodies awake with
            // `Body::set_sleep_allowed(false)`, or wake them).
            let asleep = |b| self.state.bodies.get(b).is_some_and(Body::is_sleeping);
            if asleep(constraint.a) || asleep(constraint.b) {
                continue;
            }
            f(&mut ConstraintContext {
                handle: h.with_origin(origin),
                constraint,
                bodies: &self.state.bodies,
                post_step: &mut self.post_step,
            });
        }
    }

    /// Chipmunk `cpSpaceRemoveConstraint`: removes a constraint and returns
    /// it. (Removing one of its bodies removes it too, see
    /// [`Space::remove_body`].)
    pub fn remove_constraint(&mut self, h: ConstraintHandle) -> Result<Constraint, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        let (a, b) = self
            .state
            .constraints
            .get(h)
            .map(|c| (c.a, c.b))
            .ok_or(SpaceError::StaleConstraint(h))?;
        self.wake_touching(a);
        self.wake_touching(b);
        self.state
            .constraints
            .remove(h)
            .ok_or(SpaceError::StaleConstraint(h))
    }

    /// A constraint.
    pub fn constraint(&self, h: ConstraintHandle) -> Option<&Constraint> {
        self.check_origin(h).ok()?;
        self.state.constraints.get(h)
    }

    /// A constraint, mutably: its setters check their values, and its
    /// bodies cannot be changed. Asking for it wakes both bodies' islands
    /// (a motor's new rate must act; a static or kinematic body has none,
    /// and what rests on it stays asleep). [`Space::modify_constraint`]
    /// changes it through a closure, all or nothing.
    pub fn constraint_mut(&mut self, h: ConstraintHandle) -> Option<&mut Constraint> {
        self.check_origin(h).ok()?;
        let (a, b) = self.state.constraints.get(h).map(|c| (c.a, c.b))?;
        self.wake_jointed(a);
        self.wake_jointed(b);
        self.state.constraints.get_mut(h)
    }

    /// Changes a constraint through `f` (Chipmunk's `cp…Set…` routines, in
    /// place: `c.joint_mut::<SimpleMotor>()?.set_rate(r)`,
    /// `c.set_max_force(f)`, …), then wakes both bodies' islands as
    /// Chipmunk's setters do (`cpConstraintActivateBodies`). `f` works on a
    /// copy: an error from `f` (a refused value, a constraint of another
    /// kind), or a constraint `f` left invalid, leaves the constraint
    /// unchanged and wakes nothing. The accumulated impulse is kept unless
    /// `f` replaces the kind ([`Constraint::set_kind`]): the next step warm
    /// starts from it. See also [`Space::constraint_mut`] (the same
    /// access without the copy, waking on the call).
    pub fn modify_constraint<R>(
        &mut self,
        h: ConstraintHandle,
        f: impl FnOnce(&mut Constraint) -> Result<R, ConstraintError>,
    ) -> Result<R, SpaceError> {
        self.check_origin(h)?;
        let mut copy = *self
            .state
            .constraints
            .get(h)
            .ok_or(SpaceError::StaleConstraint(h))?;
        let out = f(&mut copy)?;
        copy.validate()?;
        let (a, b) = (copy.a, copy.b);
        self.wake_jointed(a);
        self.wake_jointed(b);
        let c = self
            .state
            .constraints
            .get_mut(h)
            .ok_or(SpaceError::StaleConstraint(h))?;
        *c = copy;
        Ok(out)
    }

    /// Wakes the island of a jointed body whose joint changed, if it is
    /// dynamic (Chipmunk's `cpBodyActivate` does nothing for the others): a
    /// static body's change would wake every pile resting on it, and a
    /// joint's change moves only its two bodies.
    fn wake_jointed(&mut self, h: BodyHandle) {
        if self.state.bodies.get(h).is_some_and(Body::is_dynamic) {
            self.wake_touching(h);
        }
    }

    /// The constraints in canonical (slot) order, which is the order the
    /// solver applies them in.
    pub fn constraints(&self) -> impl Iterator<Item = (ConstraintHandle, &Constraint)> {
        let origin = self.origin;
        self.state
            .constraints
            .iter()
            .map(move |(h, c)| (h.with_origin(origin), c))
    }

    /// Chipmunk `cpPinJointNew`: a pin joint whose distance is the current
    /// distance between the anchors (body coordinates). Errors if a body is
    /// not in the space, `a == b`, or the anchors coincide (a zero-length
    /// pin has no direction: use [`Space::pivot_joint`]). Add it with
    /// [`Space::add_constraint`].
    pub fn pin_joint(
        &self,
        a: BodyHandle,
        b: BodyHandle,
        anchor_a: Vect,
        anchor_b: Vect,
    ) -> Result<Constraint, SpaceError> {
        if a == b {
            return Err(ConstraintError::SameBody.into());
        }
        let (ba, bb) = (self.live_body(a)?, self.live_body(b)?);
        let dist = ba
            .local_to_world(anchor_a)
            .dist(bb.local_to_world(anchor_b));
        Ok(Constraint::new(
            a,
            b,
            PinJoint::new(anchor_a, anchor_b, dist)?,
        )?)
    }

    /// Chipmunk `cpPivotJointNew`: a pivot joint at the world point `pivot`
    /// (converted to each body's coordinates). Add it with
    /// [`Space::add_constraint`].
    pub fn pivot_joint(
        &self,
        a: BodyHandle,
        b: BodyHandle,
        pivot: Vect,
    ) -> Result<Constraint, SpaceError> {
        if a == b {
            return Err(ConstraintError::SameBody.into());
        }
        let (ba, bb) = (self.live_body(a)?, self.live_body(b)?);
        let kind = PivotJoint::new(ba.world_to_local(pivot), bb.world_to_local(pivot))?;
        Ok(Constraint::new(a, b, kind)?)
    }

    fn live_body(&self, h: BodyHandle) -> Result<&crate::body::Body, SpaceError> {
        self.check_origin(h)?;
        self.state.bodies.get(h).ok_or(SpaceError::StaleBody(h))
    }

    /// Removes the constraints on body `h` (see [`Space::remove_body`]).
    pub(super) fn remove_constraints_of(&mut self, h: BodyHandle) {
        let on_body: Vec<ConstraintHandle> = self
            .state
            .constraints
            .iter()
            .filter(|(_, c)| c.a == h || c.b == h)
            .map(|(ch, _)| ch)
            .collect();
        for ch in on_body {
            self.state.constraints.remove(ch);
        }
    }

    /// The joint-filter stage: the body pairs of constraints with
    /// `collide_bodies = false` (read by the narrowphase).
    pub(super) fn update_constraint_filter(&mut self) {
        self.caches
            .constraints
            .update_filter(&self.state.constraints);
    }

    /// The prepare stage, after the contacts: the pre-solve callbacks, then one
    /// solver row per constraint.
    pub(super) fn pre_step_constraints(&mut self, dt: Real, dt_inv: Real) {
        self.run_constraint_callbacks(Phase::PreSolve);
        self.prepare_constraint_rows(dt, dt_inv, None);
    }

    /// The joints' rows from the bodies' current poses, without the
    /// callbacks: with `soft`, the soft step's (every sub-step).
    pub(super) fn prepare_constraint_rows(
        &mut self,
        dt: Real,
        dt_inv: Real,
        soft: Option<crate::solver::softness::Softness>,
    ) {
        self.caches.constraints.pre_step(
            &self.state.constraints,
            &self.state.bodies,
            &self.caches.solver.bodies,
            dt,
            dt_inv,
            soft,
        );
    }

    /// The store stage, after the contacts: accumulated impulses into the state,
    /// then the post-solve callbacks (Chipmunk runs them right after the
    /// solver, before the arbiters' post-solve).
    pub(super) fn store_constraint_impulses(&mut self) {
        self.caches.constraints.store(&mut self.state.constraints);
        self.run_constraint_callbacks(Phase::PostSolve);
    }
}
