//! The [`Space`] struct and the closures it owns. They are defined
//! together because they name each other: a space holds collision
//! handlers, constraint callbacks and post-step callbacks, and a post-step
//! callback (which handlers and constraint callbacks may queue) takes the
//! whole space. What the closures do is in `handlers.rs` and
//! `constraints.rs`; the space's operations are in the other files of
//! `space/`.
use std::collections::BTreeMap;

use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::{Body, BodyHandle};
use crate::constraint::{Constraint, ConstraintHandle};
use crate::limits::Limits;
use crate::math::{Real, Vect};
use crate::shape::{CollisionType, Shape};

use super::caches::Caches;
use super::state::WorldState;

/// The world: bodies, shapes, arbiters, settings and handlers.
pub struct Space {
    pub(crate) state: WorldState,
    pub(crate) caches: Caches,
    pub(crate) handlers: HandlerTable,
    pub(crate) post_step: Vec<(u64, PostStepFn)>,
    pub(crate) integrators: Integrators,
    /// Per-constraint pre-solve and post-solve callbacks (closures: not
    /// state), keyed by constraint handle like the integrators.
    pub(crate) joint_callbacks: JointCallbacks,
    pub(crate) locked: bool,
    /// What this space accepts from the bytes it loads, and the work of
    /// its step (see [`crate::limits`]): configuration, not state.
    pub(crate) limits: Limits,
    /// Tag put on the handles this space hands out (see [`Handle`]); shared
    /// by clones, so a game's handles keep working on its rollback copies.
    pub(crate) origin: u32,
}

/// Custom velocity integration (Chipmunk `cpBodySetVelocityUpdateFunc`):
/// called instead of [`Body::update_velocity`] with the gravity, the
/// per-step damping factor and `dt`. Must be deterministic (no floats, no
/// outside state that differs between peers).
pub type VelocityUpdateFn = Box<dyn FnMut(&mut Body, Vect, Real, Real) + Send + Sync>;

/// Custom position integration (Chipmunk `cpBodySetPositionUpdateFunc`):
/// called instead of [`Body::update_position`] with `dt`.
pub type PositionUpdateFn = Box<dyn FnMut(&mut Body, Real) + Send + Sync>;

/// Per-body custom integrators (closures: not simulation state).
#[derive(Default)]
pub(crate) struct Integrators {
    pub(crate) velocity: BTreeMap<BodyHandle, VelocityUpdateFn>,
    pub(crate) position: BTreeMap<BodyHandle, PositionUpdateFn>,
}

/// A callback that may reject the pair (`begin`, `pre_solve`).
pub type FilterFn = Box<dyn FnMut(&mut ArbiterContext<'_>) -> bool + Send + Sync>;
/// A callback that only observes (`post_solve`, `separate`).
pub type NotifyFn = Box<dyn FnMut(&mut ArbiterContext<'_>) + Send + Sync>;
/// A post-step callback: runs once after the step with the whole space.
pub type PostStepFn = Box<dyn FnOnce(&mut Space) + Send + Sync>;

/// The four callbacks of a collision type pair (Chipmunk `cpCollisionHandler`).
pub struct CollisionHandler {
    /// Collision type of shape a as the callbacks see it.
    pub type_a: CollisionType,
    /// Collision type of shape b.
    pub type_b: CollisionType,
    /// First step of contact; `false` ignores the pair until it separates.
    pub begin: Option<FilterFn>,
    /// Every touching step before solving; `false` skips solving this step.
    /// May change the arbiter's friction, restitution, surface velocity.
    pub pre_solve: Option<FilterFn>,
    /// After solving: sees the total impulse and energy.
    pub post_solve: Option<NotifyFn>,
    /// First step the shapes stop touching, or when one is removed.
    pub separate: Option<NotifyFn>,
}

/// What a handler sees: the arbiter (mutable: friction, restitution and
/// surface velocity may be changed in `pre_solve`), read access to bodies
/// and shapes, and the post-step queue.
pub struct ArbiterContext<'a> {
    /// The arbiter, in canonical order (see [`ArbiterContext::swapped`]).
    pub arbiter: &'a mut Arbiter,
    /// All bodies.
    pub bodies: &'a Arena<Body>,
    /// All shapes.
    pub shapes: &'a Arena<Shape>,
    pub(super) post_step: &'a mut Vec<(u64, PostStepFn)>,
    pub(super) swapped: bool,
}

/// The registered handlers (not simulation state).
#[derive(Default)]
pub(crate) struct HandlerTable {
    pub(super) pairs: BTreeMap<(CollisionType, CollisionType), CollisionHandler>,
    pub(super) wildcards: BTreeMap<CollisionType, CollisionHandler>,
}

/// A constraint's pre-solve or post-solve callback (Chipmunk
/// `cpConstraintPreSolveFunc` / `cpConstraintPostSolveFunc`). Not state:
/// never saved, hashed or cloned; it must be deterministic (no floats, no
/// outside state that differs between peers).
pub type ConstraintFn = Box<dyn FnMut(&mut ConstraintContext<'_>) + Send + Sync>;

/// What a constraint callback sees: its constraint (mutable: a pre-solve
/// callback may change parameters, e.g. a motor's rate, through the
/// validating setters), the bodies (read-only) and the post-step queue
/// (where structural changes go, e.g. removing a joint that broke).
pub struct ConstraintContext<'a> {
    /// The constraint's handle.
    pub handle: ConstraintHandle,
    /// The constraint.
    pub constraint: &'a mut Constraint,
    /// All bodies.
    pub bodies: &'a Arena<Body>,
    pub(super) post_step: &'a mut Vec<(u64, PostStepFn)>,
}

/// The pre-solve and post-solve callbacks of one constraint.
#[derive(Default)]
pub(crate) struct Callbacks {
    pub(super) pre_solve: Option<ConstraintFn>,
    pub(super) post_solve: Option<ConstraintFn>,
}

/// Callbacks by constraint handle (sorted: they run in slot order).
pub(crate) type JointCallbacks = BTreeMap<ConstraintHandle, Callbacks>;
