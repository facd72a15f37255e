//! The constraints of a space (Chipmunk `cpSpaceAddConstraint` and
//! friends) and their part of the step (stages 4 and 7–11, see
//! [`crate::constraint`]).
use super::{Space, SpaceError};
use crate::body::BodyHandle;
use crate::constraint::{Constraint, ConstraintError, ConstraintHandle, PinJoint, PivotJoint};
use crate::math::{Real, Vect};

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
        Ok(h.with_origin(self.origin))
    }

    /// Chipmunk `cpSpaceRemoveConstraint`: removes a constraint and returns
    /// it. (Removing one of its bodies removes it too, see
    /// [`Space::remove_body`].)
    pub fn remove_constraint(&mut self, h: ConstraintHandle) -> Result<Constraint, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
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
    /// bodies cannot be changed.
    pub fn constraint_mut(&mut self, h: ConstraintHandle) -> Option<&mut Constraint> {
        self.check_origin(h).ok()?;
        self.state.constraints.get_mut(h)
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

    /// Stage 4's filter: the body pairs of constraints with
    /// `collide_bodies = false` (read by the narrowphase).
    pub(super) fn update_constraint_filter(&mut self) {
        self.caches
            .constraints
            .update_filter(&self.state.constraints);
    }

    /// Stage 7, after the contacts: one solver row per constraint.
    pub(super) fn pre_step_constraints(&mut self, dt: Real, dt_inv: Real) {
        self.caches.constraints.pre_step(
            &self.state.constraints,
            &self.state.bodies,
            &self.caches.solver.bodies,
            dt,
            dt_inv,
        );
    }

    /// Stage 9, after the contacts: the constraints' warm start, scaled
    /// like the contacts' by `min(dt / prev_dt, 1)`.
    pub(super) fn warm_start_constraints(&mut self) {
        if self.caches.constraints.is_empty() {
            return;
        }
        let prev = self.state.prev_dt;
        let dt_coef = if prev.is_zero() {
            Real::ZERO
        } else {
            (self.state.current_dt / prev).min(Real::ONE)
        };
        self.caches
            .constraints
            .warm_start(&mut self.caches.solver.bodies, dt_coef);
    }

    /// Stage 11, after the contacts: accumulated impulses into the state.
    pub(super) fn store_constraint_impulses(&mut self) {
        self.caches.constraints.store(&mut self.state.constraints);
    }
}
