//! The MIS Space module (§8): the world that owns bodies, shapes and
//! arbiters, and steps them.
//!
//! A [`Space`] is two things:
//! * [`WorldState`]: everything that affects future steps — settings, the
//!   body and shape arenas (with their free lists), the arbiters with their
//!   cached impulses, the step counter and time steps. It is plain data
//!   (`Clone`, serde), which is what snapshots and rollback copy.
//! * Things that are *not* state: per-step caches (world-space geometry,
//!   broadphase buffers), collision handlers and post-step callbacks
//!   (closures cannot be serialized; a game re-attaches them by collision
//!   type after loading a snapshot).
mod body_shapes;
mod caches;
mod cast;
mod ccd;
mod constraints;
mod error;
mod frame;
mod frame_state;
pub mod handlers;
mod islands;
mod ledger;
mod level;
pub mod query;
mod settings;
mod sleep;
mod state;
mod state_limits;
mod step;
mod validate;
mod world;

use crate::limits::Limits;
use core::fmt;

pub use crate::solver::Kernels;
pub use crate::threads::DEFAULT_PARALLEL_THRESHOLD;
pub use cast::ShapeCast;
pub use ccd::MAX_TOI_ITERATIONS;
pub use frame_state::FrameState;
pub use settings::{
    ContactPrecision, Settings, SoftStep, Solver, CHIPMUNK_COLLISION_SLOP, DEFAULT_COLLISION_BIAS,
    DEFAULT_COLLISION_SLOP, DEFAULT_IDLE_SPEED_THRESHOLD, DEFAULT_SLEEP_TIME_THRESHOLD,
    MAX_ITERATIONS, MAX_SOFT_PARAMETER, MAX_SUBSTEPS, SLEEP_NEVER,
};
pub use step::{sub_step_dts, Stage};
pub(crate) use world::Integrators;
pub use world::{ArbiterContext, CollisionHandler, PostStepFn, Space};
pub use world::{ConstraintContext, ConstraintFn};
pub use world::{PositionUpdateFn, VelocityUpdateFn};

use crate::arbiter::Arbiter;
use crate::arena::Handle;
use crate::body::{Body, BodyHandle, BodyType};
use crate::broadphase::BroadphaseCache;
use crate::math::{Real, Vect};
use crate::shape::{CollisionType, Shape, ShapeError};

pub use crate::collision::{ShapeCastInfo, StartContact};
pub use crate::shape::ShapeHandle;
pub(crate) use caches::Caches;
pub use error::SpaceError;
pub use state::WorldState;
pub use step::StepStats;
pub use validate::validate_state;
pub(crate) use validate::validate_state_trusting_level;

/// Source of origin tags: process-local, never part of the simulation.
static NEXT_ORIGIN: core::sync::atomic::AtomicU32 = core::sync::atomic::AtomicU32::new(1);

fn new_origin() -> u32 {
    // Wrapping to 0 would only turn the check off for that space.
    NEXT_ORIGIN.fetch_add(1, core::sync::atomic::Ordering::Relaxed)
}

impl Default for Space {
    fn default() -> Self {
        Space::new()
    }
}

impl fmt::Debug for Space {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Space")
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

impl Clone for Space {
    /// Clones the simulation state; handlers and post-step callbacks are not
    /// cloned (closures), the clone has none.
    fn clone(&self) -> Space {
        let mut space = Space::with_origin(self.state.clone(), self.origin);
        // Not state: the same threads and kernels (neither changes a bit)
        // and limits.
        space.caches.threads = self.caches.threads.clone();
        space.caches.kernels = self.caches.kernels;
        space.limits = self.limits;
        space
    }
}

impl Space {
    /// MIS `spaceInit`: an empty space with Chipmunk's default settings.
    pub fn new() -> Space {
        Space::from_state(WorldState::default())
    }

    /// A space from a state (handlers empty; caches rebuilt on the next step),
    /// with a new handle origin: the handles it hands out, including those
    /// stored in the state (a shape's body, an arbiter's shapes and bodies),
    /// are its own. Not checked: for a state from an untrusted source use
    /// [`Space::try_from_state`].
    pub fn from_state(state: WorldState) -> Space {
        Space::with_origin(state, new_origin())
    }

    /// [`Space::from_state`] for a state from an untrusted source: the
    /// state is checked first ([`validate_state`], the same rule as snapshot
    /// loading), and an invalid one is an error naming what is wrong. A
    /// state that passes can step.
    pub fn try_from_state(state: WorldState) -> Result<Space, SpaceError> {
        validate_state(&state).map_err(SpaceError::RejectedState)?;
        Ok(Space::from_state(state))
    }

    /// A space from a state whose handles get the origin tag `origin`.
    fn with_origin(mut state: WorldState, origin: u32) -> Space {
        adopt_handles(&mut state, origin);
        Space {
            state,
            caches: Caches {
                broadphase: BroadphaseCache::dirty(),
                ..Caches::default()
            },
            handlers: world::HandlerTable::default(),
            post_step: Vec::new(),
            integrators: Integrators::default(),
            joint_callbacks: world::JointCallbacks::default(),
            locked: false,
            limits: Limits::default(),
            origin,
        }
    }

    /// The simulation state (for snapshots and checksums).
    pub fn state(&self) -> &WorldState {
        &self.state
    }

    /// Replaces the simulation state in place (rollback). The handles in the
    /// state become this space's (the state may come from another space).
    /// Not checked (a rollback restores the game's own saves): for a state
    /// from an untrusted source use [`Space::try_restore_state`].
    ///
    /// Callbacks, which are not state: collision handlers (keyed by
    /// collision type) stay; custom integrators (keyed by body handle) and
    /// constraint pre/post-solve callbacks (keyed by constraint handle)
    /// stay, including those of bodies and constraints removed since the
    /// save, which come back with them; post-step callbacks still pending are discarded —
    /// they were queued in the frames the rollback abandons (queue them from
    /// handlers or before the step they belong to, never across a save).
    pub fn restore_state(&mut self, state: &WorldState) {
        self.post_step.clear();
        self.state.clone_from(state);
        adopt_handles(&mut self.state, self.origin);
        self.caches.broadphase.statics_dirty = true;
        self.forget_level();
        self.caches.broadphase.sleepers_dirty = true;
        self.caches.broadphase.sleeping_count = None;
        self.caches.body_shapes.invalidate();
        self.caches.step.dt_constants = [None, None];
    }

    /// [`Space::restore_state`] for a state from an untrusted source: checked
    /// first ([`validate_state`]); an invalid state is an error and leaves
    /// this world untouched. A state that passes can step.
    pub fn try_restore_state(&mut self, state: &WorldState) -> Result<(), SpaceError> {
        validate_state(state).map_err(SpaceError::RejectedState)?;
        self.restore_state(state);
        Ok(())
    }

    /// The limits this space applies to what it loads and to its step's
    /// candidate pairs ([`Limits::UNTRUSTED`] unless set).
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// Sets the limits (see [`crate::limits`]): [`Limits::TRUSTED`] lifts
    /// them all. Configuration, not state: kept by restores and loads, not
    /// saved, copied by `clone`.
    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
    }

    /// Lets the step use `n` threads (0 counts as 1, more than 256 is an
    /// error; the default is 1).
    /// Nothing a step computes depends on it: any count gives the bits of
    /// one thread. Without the `parallel` cargo feature the count is kept
    /// and the step runs on the calling thread. With it, a step with
    /// enough work ([`set_parallel_threshold`](Self::set_parallel_threshold))
    /// splits its stages between the threads: the body stages, the
    /// broadphase, the narrowphase and the arbiters' merge, the prepare,
    /// and the contact passes color by color (the colored orders: the soft
    /// step, or [`Settings::colored_solver`]; the canonical order is one
    /// sequence, solved on one thread). An error (and no change) if the
    /// operating system will not start the threads.
    pub fn set_threads(&mut self, n: usize) -> Result<(), SpaceError> {
        let threads = crate::threads::Threads::new(n).map_err(SpaceError::InvalidSetting)?;
        self.caches.threads = threads.with_threshold_of(&self.caches.threads);
        Ok(())
    }

    /// The thread count of [`set_threads`](Self::set_threads).
    pub fn threads(&self) -> usize {
        self.caches.threads.count()
    }

    /// The least work a step shares between threads (with more than one,
    /// [`set_threads`](Self::set_threads)): a step runs on the calling
    /// thread alone when the step before had fewer contact points plus
    /// joints plus bodies than `work`. The default,
    /// [`DEFAULT_PARALLEL_THRESHOLD`],
    /// is where two threads stopped paying on a 2-core machine
    /// (`docs/performance.md`, "The parallel step"); 0 shares every step
    /// (the tests use it to split small scenes). Nothing a step computes
    /// depends on it. Configuration, like the thread count: kept by
    /// restores and loads, not saved, copied by `clone`.
    pub fn set_parallel_threshold(&mut self, work: u32) {
        self.caches.threads.set_threshold(work);
    }

    /// The threshold of [`set_parallel_threshold`](Self::set_parallel_threshold).
    pub fn parallel_threshold(&self) -> u32 {
        self.caches.threads.threshold()
    }

    /// Chooses the compiled form of the soft step's contact passes
    /// ([`Kernels`]; the default is [`Kernels::Auto`]). Nothing a step
    /// computes depends on it: every choice gives the same bits. With
    /// threads, each color's batches of the wide kernels are split between
    /// them. Configuration, not state: kept by restores and loads, not
    /// saved, copied by `clone`.
    pub fn set_kernels(&mut self, kernels: Kernels) {
        self.caches.kernels = kernels;
    }

    /// The kernels of [`set_kernels`](Self::set_kernels).
    pub fn kernels(&self) -> Kernels {
        self.caches.kernels
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.state.settings
    }

    /// Replaces the settings after checking them.
    /// Changed settings wake every sleeping body (new gravity, thresholds
    /// or solver switches concern them too); the same settings wake none.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), SpaceError> {
        settings.validate()?;
        if settings != self.state.settings {
            self.wake_all();
        }
        self.state.settings = settings;
        self.caches.step.dt_constants = [None, None];
        Ok(())
    }

    /// MIS `spaceSetGravity`.
    /// A new gravity wakes every sleeping body.
    pub fn set_gravity(&mut self, gravity: Vect) {
        if gravity != self.state.settings.gravity {
            self.wake_all();
        }
        self.state.settings.gravity = gravity;
        self.caches.step.dt_constants = [None, None];
    }

    /// Gravity.
    pub fn gravity(&self) -> Vect {
        self.state.settings.gravity
    }

    /// Sets the number of solver iterations.
    /// Values above [`MAX_ITERATIONS`] are clamped to it.
    pub fn set_iterations(&mut self, iterations: u32) {
        self.state.settings.iterations = iterations.min(MAX_ITERATIONS);
    }

    /// Number of steps taken (MIS `stamp`), counting each sub-step of a
    /// step with [`Settings::substeps`] > 1.
    pub fn stamp(&self) -> u64 {
        self.state.stamp
    }

    /// Number of [`Space::step`] calls that advanced time (`dt > 0`),
    /// whatever the sub-step count.
    pub fn steps(&self) -> u64 {
        self.state.steps
    }

    /// `dt` of the last step (of its last sub-step with
    /// [`Settings::substeps`] > 1).
    pub fn current_time_step(&self) -> Real {
        self.state.current_dt
    }

    /// Counters of the last step (broadphase pairs, contacts, iteration-cap
    /// hits); of its last sub-step with [`Settings::substeps`] > 1.
    pub fn last_step_stats(&self) -> StepStats {
        self.caches.step.stats
    }

    /// True while the step runs (handlers see a locked space).
    pub fn is_locked(&self) -> bool {
        self.locked
    }

    /// MIS `spaceAddBody`: adds a body and returns its handle.
    pub fn add_body(&mut self, body: Body) -> Result<BodyHandle, SpaceError> {
        self.check_unlocked()?;
        body.validate()?;
        let is_static = body.body_type() == BodyType::Static;
        let h = self
            .state
            .bodies
            .insert(body)
            .map_err(|_| SpaceError::Full)?;
        if is_static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
        // A new body starts with the default integration, even under a
        // handle a rollback re-issued (integrators outlive their bodies).
        self.integrators.velocity.remove(&h);
        self.integrators.position.remove(&h);
        Ok(h.with_origin(self.origin))
    }

    /// Removes a body, its shapes and their arbiters (separate handlers run
    /// for touching pairs), and the constraints on it. Returns the body.
    ///
    /// Chipmunk requires the game to remove a body's constraints first; a
    /// constraint left naming a removed body would be a world state that
    /// `validate_state` rejects (and a snapshot could not be loaded), so
    /// here removing the body removes them, in slot order. Their handles
    /// become stale.
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<Body, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        let is_static = match self.state.bodies.get(h) {
            Some(b) => b.body_type() == BodyType::Static,
            None => return Err(SpaceError::StaleBody(h)),
        };
        self.wake_touching(h);
        self.remove_constraints_of(h);
        // The body's shapes in slot order, found without a scan.
        let owned: Vec<ShapeHandle> = self
            .caches
            .body_shapes
            .of(&self.state.shapes, h)
            .into_iter()
            .filter_map(|i| self.state.shapes.get_by_index(i))
            .filter(|(_, s)| s.body == h)
            .map(|(sh, _)| sh)
            .collect();
        for sh in owned {
            self.remove_shape(sh)?;
        }
        if is_static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
        // The body's custom integrators stay, keyed by its handle: a
        // rollback to a state where it exists brings them back with it
        // (`prune_integrators` frees them).
        self.state.bodies.remove(h).ok_or(SpaceError::StaleBody(h))
    }

    /// Adds a shape to the body it names; recomputes the body's mass from its
    /// shapes unless the mass was set explicitly. Errors on an invalid
    /// material ([`Material::validate`](crate::shape::Material::validate)).
    pub fn add_shape(&mut self, shape: Shape) -> Result<ShapeHandle, SpaceError> {
        self.check_unlocked()?;
        shape.material.validate()?;
        let bh = shape.body;
        self.check_origin(bh)?;
        let body_type = self
            .state
            .bodies
            .get(bh)
            .ok_or(SpaceError::StaleBody(bh))?
            .body_type();
        self.wake_touching(bh);
        // Stored handles carry the space's origin (the caller's may be 0).
        let shape = Shape {
            body: bh.with_origin(self.origin),
            ..shape
        };
        let h = self
            .state
            .shapes
            .insert(shape)
            .map_err(|_| SpaceError::Full)?;
        // Only static bodies' shapes are in the static tree.
        if body_type == BodyType::Static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
        self.caches
            .body_shapes
            .insert(&self.state.shapes, bh, h.index());
        self.update_mass_from_shapes(bh);
        if body_type != BodyType::Dynamic {
            // A new piece of level (or of a kinematic body) may overlap a
            // sleeping pile, which no moving shape would wake.
            let bb = self
                .state
                .shapes
                .get(h)
                .zip(self.state.bodies.get(bh))
                .map(|(s, b)| s.geometry.to_world(b.position(), b.rotation()).bb());
            self.wake_overlapping(bb.as_slice());
        }
        Ok(h.with_origin(self.origin))
    }

    /// Adds the segments of `chain` to `body` (smooth terrain: each segment
    /// has its neighbours set, see [`Chain`](crate::shape::Chain)); returns
    /// their handles in chain order. All or nothing: on an error no segment
    /// stays in the space.
    pub fn add_chain(
        &mut self,
        body: BodyHandle,
        chain: &crate::shape::Chain,
    ) -> Result<Vec<ShapeHandle>, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(body)?;
        if !self.state.bodies.contains(body) {
            return Err(SpaceError::StaleBody(body));
        }
        let mut added = Vec::new();
        for shape in chain.shapes(body) {
            match self.add_shape(shape) {
                Ok(h) => added.push(h),
                Err(e) => {
                    for h in added.into_iter().rev() {
                        // Just added, unlocked, of this space: cannot fail.
                        let _ = self.remove_shape(h);
                    }
                    return Err(e);
                }
            }
        }
        Ok(added)
    }

    /// Removes a shape and its arbiters (separate handlers run for pairs that
    /// were touching).
    pub fn remove_shape(&mut self, h: ShapeHandle) -> Result<Shape, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        let Some(owner) = self.state.shapes.get(h).map(|s| s.body) else {
            return Err(SpaceError::StaleShape(h));
        };
        self.wake_touching(owner);
        let mut removed = Vec::new();
        self.state.arbiters.retain(|arb| {
            let hit = arb.shape_a == h || arb.shape_b == h;
            if hit {
                removed.push(arb.clone());
            }
            !hit
        });
        for mut arb in removed {
            if !arb.is_cached() {
                self.handlers.separate(
                    &mut arb,
                    &self.state.bodies,
                    &self.state.shapes,
                    &mut self.post_step,
                );
            }
        }
        let shape = self
            .state
            .shapes
            .remove(h)
            .ok_or(SpaceError::StaleShape(h))?;
        self.mark_statics_if_static(shape.body);
        self.caches
            .body_shapes
            .remove(&self.state.shapes, shape.body, h.index());
        self.update_mass_from_shapes(shape.body);
        Ok(shape)
    }

    /// A body.
    pub fn body(&self, h: BodyHandle) -> Option<&Body> {
        self.check_origin(h).ok()?;
        self.state.bodies.get(h)
    }

    /// A body, mutably. Moving a static body this way is noticed: the static
    /// index is rebuilt on the next step (if its shapes' boxes changed).
    ///
    /// Asking for it wakes the body's island and the islands resting on it
    /// (whatever is then changed: Chipmunk's setters wake the body too).
    /// A static or kinematic body moved this way does not know what it
    /// will touch: call [`activate_body`](Self::activate_body) on it
    /// afterwards to wake the islands at its new place.
    pub fn body_mut(&mut self, h: BodyHandle) -> Option<&mut Body> {
        self.check_origin(h).ok()?;
        let body_type = self.state.bodies.get(h)?.body_type();
        self.wake_touching(h);
        // Kinematic bodies' shapes are swept each step, not in the tree.
        if body_type == BodyType::Static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        } else {
            // The game may replace it by a static body (see `space::level`).
            let suspect = (h.index(), body_type == BodyType::Dynamic);
            if !self.caches.level_suspects.contains(&suspect) {
                self.caches.level_suspects.push(suspect);
            }
        }
        self.state.bodies.get_mut(h)
    }

    /// A shape.
    pub fn shape(&self, h: ShapeHandle) -> Option<&Shape> {
        self.check_origin(h).ok()?;
        self.state.shapes.get(h)
    }

    /// Changes a shape through `f` (material, filter, geometry setters),
    /// then refreshes the owning body's mass. Errors from `f`, or a material
    /// left invalid by `f`, leave the shape unchanged. For a change that
    /// cannot fail (a public field), [`Space::update_shape`] takes a closure
    /// without the `Result`.
    pub fn modify_shape<R>(
        &mut self,
        h: ShapeHandle,
        f: impl FnOnce(&mut Shape) -> Result<R, ShapeError>,
    ) -> Result<R, SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        let shape = self
            .state
            .shapes
            .get_mut(h)
            .ok_or(SpaceError::StaleShape(h))?;
        let mut copy = shape.clone();
        let out = f(&mut copy)?;
        copy.material.validate()?;
        let body = copy.body;
        if !self.state.bodies.contains(body) {
            return Err(SpaceError::StaleBody(body));
        }
        let old_body = shape.body;
        self.wake_touching(old_body);
        self.wake_touching(body);
        let Some(shape) = self.state.shapes.get_mut(h) else {
            return Err(SpaceError::StaleShape(h));
        };
        if copy.body != shape.body {
            // Only the crate can move a shape to another body.
            self.caches.body_shapes.invalidate();
        }
        *shape = copy;
        self.mark_statics_if_static(body);
        self.update_mass_from_shapes(body);
        if self.state.bodies.get(body).is_some_and(|b| !b.is_dynamic()) {
            let bb = self
                .state
                .shapes
                .get(h)
                .zip(self.state.bodies.get(body))
                .map(|(s, b)| s.geometry.to_world(b.position(), b.rotation()).bb());
            self.wake_overlapping(bb.as_slice());
        }
        Ok(out)
    }

    /// [`Space::modify_shape`] for a change that cannot fail by itself
    /// (the public fields: `material`, `filter`, `sensor`,
    /// `collision_type`): `f` returns its value, not a `Result`.
    ///
    /// ```
    /// # use tamias2d::body::Body;
    /// # use tamias2d::shape::Shape;
    /// # use tamias2d::space::Space;
    /// # use tamias2d::{Real, Vect};
    /// # let mut space = Space::new();
    /// # let ground = space.add_body(Body::new_static())?;
    /// # let floor = space.add_shape(Shape::segment_shape_new(ground, Vect::from_ints(-5, 0), Vect::from_ints(5, 0), Real::ZERO)?)?;
    /// space.update_shape(floor, |s| s.material.friction = Real::HALF)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// It still fails as `modify_shape` does: a stale or foreign handle, a
    /// locked space, or a material `f` left invalid (then the shape is
    /// unchanged).
    pub fn update_shape<R>(
        &mut self,
        h: ShapeHandle,
        f: impl FnOnce(&mut Shape) -> R,
    ) -> Result<R, SpaceError> {
        self.modify_shape(h, |s| Ok(f(s)))
    }

    /// MIS `spaceGetBodies`: the bodies in canonical (slot) order.
    pub fn bodies(&self) -> impl Iterator<Item = (BodyHandle, &Body)> {
        let origin = self.origin;
        self.state
            .bodies
            .iter()
            .map(move |(h, b)| (h.with_origin(origin), b))
    }

    /// The shapes in canonical (slot) order.
    pub fn shapes(&self) -> impl Iterator<Item = (ShapeHandle, &Shape)> {
        let origin = self.origin;
        self.state
            .shapes
            .iter()
            .map(move |(h, s)| (h.with_origin(origin), s))
    }

    /// The shapes of one body, in slot order (none for a handle of another
    /// space).
    pub fn body_shapes(&self, h: BodyHandle) -> impl Iterator<Item = (ShapeHandle, &Shape)> {
        let own = self.check_origin(h).is_ok();
        self.state
            .shapes
            .iter()
            .filter(move |(_, s)| own && s.body == h)
    }

    /// The arbiters in canonical order (touching and cached pairs).
    pub fn arbiters(&self) -> &[Arbiter] {
        &self.state.arbiters
    }

    /// MIS `spaceAddCollisionHandler`: the handler for shapes of types
    /// `(a, b)`, created empty ("do nothing") if needed. Callbacks see the
    /// arbiter with shape a of type `a`.
    pub fn add_collision_handler(
        &mut self,
        a: CollisionType,
        b: CollisionType,
    ) -> &mut CollisionHandler {
        self.handlers.pair_mut(a, b)
    }

    /// Chipmunk `cpSpaceAddWildcardHandler`: called for every pair that has
    /// a shape of type `t` and no exact pair handler.
    pub fn add_wildcard_handler(&mut self, t: CollisionType) -> &mut CollisionHandler {
        self.handlers.wildcard_mut(t)
    }

    /// Replaces the default velocity integration of one body (MIS "kinematic
    /// functions set to default ones"; `None` restores the default). Like
    /// handlers, these closures are not part of snapshots; they outlive
    /// `remove_body` so that a rollback restores them with the body (see
    /// [`Space::restore_state`], [`Space::prune_integrators`]), and a body
    /// newly added under the same handle starts without them.
    pub fn set_velocity_update_func(
        &mut self,
        h: BodyHandle,
        f: Option<VelocityUpdateFn>,
    ) -> Result<(), SpaceError> {
        self.check_origin(h)?;
        if !self.state.bodies.contains(h) {
            return Err(SpaceError::StaleBody(h));
        }
        match f {
            Some(f) => self.integrators.velocity.insert(h, f),
            None => self.integrators.velocity.remove(&h),
        };
        Ok(())
    }

    /// Replaces the default position integration of one body (`None`
    /// restores the default).
    pub fn set_position_update_func(
        &mut self,
        h: BodyHandle,
        f: Option<PositionUpdateFn>,
    ) -> Result<(), SpaceError> {
        self.check_origin(h)?;
        if !self.state.bodies.contains(h) {
            return Err(SpaceError::StaleBody(h));
        }
        match f {
            Some(f) => self.integrators.position.insert(h, f),
            None => self.integrators.position.remove(&h),
        };
        Ok(())
    }

    /// Drops the custom integrators of bodies not in the current state.
    /// Integrators survive `remove_body` so that a rollback to a state where
    /// the body exists brings them back; call this once the removals are
    /// older than the oldest state the game may still restore (e.g. on a
    /// confirmed frame), to free their closures.
    pub fn prune_integrators(&mut self) {
        let bodies = &self.state.bodies;
        self.integrators.velocity.retain(|h, _| bodies.contains(*h));
        self.integrators.position.retain(|h, _| bodies.contains(*h));
    }

    /// Chipmunk `cpSpaceAddPostStepCallback`: runs `f` after the current (or
    /// next) step, once per `key`; returns false if `key` is already queued.
    pub fn add_post_step_callback(&mut self, key: u64, f: PostStepFn) -> bool {
        handlers::queue_post_step(&mut self.post_step, key, f)
    }

    /// Rejects a handle made by another space (tag 0: origin unknown, accepted).
    fn check_origin<T>(&self, h: Handle<T>) -> Result<(), SpaceError> {
        if h.origin() == 0 || h.origin() == self.origin {
            Ok(())
        } else {
            Err(SpaceError::ForeignHandle)
        }
    }

    /// Flags the static tree for a rebuild check if `body` is static (the
    /// tree holds only static bodies' shapes; the next step compares their
    /// boxes with those the tree was built from).
    fn mark_statics_if_static(&mut self, body: BodyHandle) {
        if self
            .state
            .bodies
            .get(body)
            .is_some_and(|b| b.body_type() == BodyType::Static)
        {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
    }

    /// How many times this space built its static tree (not state; for
    /// tests and diagnostics: a step rebuilds it only when the static
    /// shapes' boxes changed).
    #[doc(hidden)]
    pub fn static_tree_builds(&self) -> u64 {
        self.caches.broadphase.static_builds
    }

    fn check_unlocked(&self) -> Result<(), SpaceError> {
        if self.locked {
            Err(SpaceError::Locked)
        } else {
            Ok(())
        }
    }

    /// Sums mass, centre of gravity and moment from the body's shapes
    /// (Chipmunk `cpBodyAccumulateMassFromShapes`), for dynamic bodies whose
    /// mass was not set explicitly.
    fn update_mass_from_shapes(&mut self, bh: BodyHandle) {
        let Some(body) = self.state.bodies.get(bh) else {
            return;
        };
        if body.body_type() != BodyType::Dynamic || body.explicit_mass {
            return;
        }
        let mut mass = Real::ZERO;
        let mut cog = Vect::ZERO;
        let mut moment = Real::ZERO;
        // The body's shapes in slot order (as a scan of every shape would
        // visit them): the summation order, hence the bits, of the result.
        self.caches
            .body_shapes
            .for_each(&self.state.shapes, bh, |s| {
                let info = s.mass_info();
                if !info.mass.is_positive() {
                    return;
                }
                let total = mass + info.mass;
                // Shift the running centre to the combined one (parallel axis).
                let new_cog = cog.lerp(info.cog, info.mass / total);
                moment = moment
                    + mass * (cog - new_cog).length_sq()
                    + info.mass * (info.moment_per_mass + (info.cog - new_cog).length_sq());
                cog = new_cog;
                mass = total;
            });
        if let Some(body) = self.state.bodies.get_mut(bh) {
            body.set_mass_properties(mass, moment, cog);
        }
    }

    /// A portable 64-bit checksum of the whole simulation state (see
    /// [`checksum`](crate::checksum)); equal states give equal checksums on
    /// every platform.
    ///
    /// The static level enters as its digest ([`Space::level_digest`],
    /// cached), so the cost is that of the frame ([`FrameState`]): a big
    /// static level does not slow the per-frame checksum.
    pub fn checksum(&self) -> u64 {
        self.with_level(|level| frame_state::world_checksum(&self.state, level))
    }

    /// Checks the space's invariants: arenas, shape→body links, arbiter
    /// order and references. Run by tests after every operation, and by
    /// snapshot loading.
    pub fn validate(&self) -> Result<(), String> {
        validate_state(&self.state)
    }
}

/// True in unoptimised builds (`debug_assertions`) with the `validate`
/// feature: [`Space::step`] then runs [`validate_state`] after every step
/// and returns [`SpaceError::InvalidState`] if the world breaks an
/// invariant (Box2D's validation builds). The crate's own test suite
/// enables the feature. The default build never validates, and optimised
/// builds ignore the feature (timing runs measure the engine alone); the
/// check only reads the state, so it changes no bit either way.
pub const VALIDATES_STEPS: bool = cfg!(all(feature = "validate", debug_assertions));

/// Whether this build has the `parallel` feature: [`Space::set_threads`]
/// then splits the step between threads (always with the bits of one).
pub const PARALLEL: bool = cfg!(feature = "parallel");

impl Space {
    /// The check [`Space::step`] ends with: when [`VALIDATES_STEPS`], every
    /// invariant of [`validate_state`]; otherwise nothing.
    #[inline(always)]
    pub(crate) fn check_step_invariants(&self) -> Result<(), SpaceError> {
        #[cfg(all(feature = "validate", debug_assertions))]
        {
            validate_state(&self.state).map_err(SpaceError::InvalidState)?;
            // The cached level must be the state's (a missed change to the
            // level would let a stale frame restore).
            let cached = self.caches.level.take();
            let fresh = level::LevelIndex::of(&self.state);
            let stale = cached.as_ref().is_some_and(|c| *c != fresh);
            self.caches.level.set(cached);
            if stale && self.caches.level_suspects.is_empty() {
                return Err(SpaceError::InvalidState(
                    "the cached level index is not the state's".into(),
                ));
            }
            // The shape-cache stage skips the level's slots while statics are clean: each
            // must hold its static entry.
            if !self.caches.broadphase.statics_dirty {
                for i in fresh.shape_runs.iter().flat_map(|&(a, b)| a..b) {
                    let ok = self
                        .caches
                        .shapes
                        .get(i as usize)
                        .is_some_and(|e| e.as_ref().is_some_and(|e| e.is_static));
                    if !ok {
                        return Err(SpaceError::InvalidState(format!(
                            "level shape slot {i} has no static cache entry"
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Puts the origin tag `origin` on a state's arenas (so every handle they
/// make carries it) and on the handles stored in it: each shape's body and
/// each arbiter's shapes and bodies. Nothing to do for a state that already
/// has it (a state saved from this space or one of its clones: the tags are
/// set whenever a handle is stored, see `add_shape` and the narrowphase).
fn adopt_handles(state: &mut WorldState, origin: u32) {
    if state.bodies.origin() == origin
        && state.shapes.origin() == origin
        && state.constraints.origin() == origin
    {
        return;
    }
    state.bodies.set_origin(origin);
    state.shapes.set_origin(origin);
    state.constraints.set_origin(origin);
    for (_, c) in state.constraints.iter_mut() {
        c.a = c.a.with_origin(origin);
        c.b = c.b.with_origin(origin);
    }
    for (_, shape) in state.shapes.iter_mut() {
        shape.body = shape.body.with_origin(origin);
    }
    for arb in state.arbiters.iter_mut().chain(&mut state.dormant_arbiters) {
        arb.shape_a = arb.shape_a.with_origin(origin);
        arb.shape_b = arb.shape_b.with_origin(origin);
        arb.body_a = arb.body_a.with_origin(origin);
        arb.body_b = arb.body_b.with_origin(origin);
    }
}

#[cfg(test)]
mod step_validation_tests {
    use super::*;

    /// A dynamic ball resting on a static box, after a few steps (so the
    /// state has an arbiter).
    fn resting() -> Result<Space, SpaceError> {
        let mut w = Space::new();
        w.set_gravity(Vect::new(Real::ZERO, Real::from_int(-10)));
        let ground = w.add_body(Body::new_static())?;
        w.add_shape(Shape::box_shape_new(
            ground,
            Real::from_int(10),
            Real::ONE,
            Real::ZERO,
        )?)?;
        let mut ball = Body::new(Real::ONE, Real::ONE)?;
        ball.set_position(Vect::new(Real::ZERO, Real::ONE));
        let ball = w.add_body(ball)?;
        w.add_shape(Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)?)?;
        for _ in 0..10 {
            w.step(Real::ONE / Real::from_int(60))?;
        }
        Ok(w)
    }

    #[test]
    fn the_step_check_reports_a_broken_invariant_only_in_validation_builds() {
        let mut w = resting().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(w.arbiters().len(), 1);
        assert_eq!(w.check_step_invariants(), Ok(()));
        // Break one invariant a step must keep: the cached inverse mass.
        let (_, ball) = w
            .state
            .bodies
            .iter_mut()
            .find(|(_, b)| b.is_dynamic())
            .unwrap_or_else(|| panic!("the ball"));
        ball.mass_inv = Real::TWO;
        let found = w.check_step_invariants();
        if VALIDATES_STEPS {
            let Err(SpaceError::InvalidState(why)) = found else {
                panic!("not reported: {found:?}");
            };
            assert!(why.contains("inverse mass does not match mass"), "{why}");
        } else {
            assert_eq!(found, Ok(()));
        }
    }

    #[test]
    fn data_past_an_arbiters_contact_count_is_invalid() {
        let mut w = resting().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(validate_state(&w.state), Ok(()));
        let arb = w
            .state
            .arbiters
            .first_mut()
            .unwrap_or_else(|| panic!("the ball touches the ground"));
        assert_eq!(arb.count(), 1, "a circle on a box: one contact");
        if let Some(unused) = arb.contacts.get_mut(1) {
            unused.jt_acc = Real::ONE;
        }
        let found = validate_state(&w.state);
        let Err(why) = found else {
            panic!("not reported");
        };
        assert!(why.contains("past its contact count"), "{why}");
    }
}
