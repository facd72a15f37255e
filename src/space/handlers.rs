//! Collision handlers (MIS `spaceAddCollisionHandler`,
//! `collisionHandlerDoNothing`) and post-step callbacks.
//!
//! Handlers are closures, so they live beside the simulation state, not in
//! it: snapshots do not hold them, and a game re-registers them by collision
//! type after loading (they are keyed by type, not by object, for exactly
//! that reason).
//!
//! Dispatch for a pair of shapes with types `(ta, tb)`:
//! 1. an exact handler for `(ta, tb)` or `(tb, ta)` (the context is swapped
//!    so the handler's shape a always has its `type_a`);
//! 2. otherwise the wildcard handlers of `ta` and of `tb`; `begin` and
//!    `pre_solve` accept the pair only if both accept (Chipmunk's default
//!    handler).
//!
//! Handlers run in arbiter order (canonical), so they are deterministic too.
use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::{Body, BodyHandle};
use crate::collision::{ContactPoint, ContactPointSet, MAX_CONTACTS_PER_ARBITER};
use crate::math::Vect;
use crate::shape::{CollisionType, Shape, WILDCARD_COLLISION_TYPE};

use super::world::HandlerTable;
pub use super::world::{ArbiterContext, CollisionHandler, FilterFn, NotifyFn, PostStepFn};
use super::ShapeHandle;

/// MIS `collisionHandlerDoNothing`: wildcard types, no callbacks (accept all).
pub fn collision_handler_do_nothing() -> CollisionHandler {
    CollisionHandler {
        type_a: WILDCARD_COLLISION_TYPE,
        type_b: WILDCARD_COLLISION_TYPE,
        begin: None,
        pre_solve: None,
        post_solve: None,
        separate: None,
    }
}

impl ArbiterContext<'_> {
    /// True if the handler's shape a is the arbiter's shape b.
    pub fn swapped(&self) -> bool {
        self.swapped
    }

    /// The two shapes in the handler's order (a has the handler's `type_a`).
    pub fn shapes(&self) -> (ShapeHandle, ShapeHandle) {
        let (a, b) = self.arbiter.shapes();
        if self.swapped {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// The two bodies in the handler's order: those of
    /// [`shapes`](Self::shapes), in the same order (Chipmunk
    /// `cpArbiterGetBodies`). `self.arbiter.bodies()` is in the arbiter's
    /// canonical order, like `self.arbiter.shapes()`.
    pub fn bodies(&self) -> (BodyHandle, BodyHandle) {
        let (a, b) = self.arbiter.bodies();
        if self.swapped {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// The contact normal in the handler's order (from its shape a to b).
    pub fn normal(&self) -> Vect {
        if self.swapped {
            -self.arbiter.normal()
        } else {
            self.arbiter.normal()
        }
    }

    /// Contact points in world coordinates, in the handler's order
    /// (Chipmunk `cpArbiterGetContactPointSet`).
    pub fn contact_point_set(&self) -> ContactPointSet {
        let arb = &*self.arbiter;
        let pa = self.bodies.get(arb.body_a).map_or(Vect::ZERO, Body::center);
        let pb = self.bodies.get(arb.body_b).map_or(Vect::ZERO, Body::center);
        let mut set = ContactPointSet {
            count: arb.count(),
            normal: self.normal(),
            points: [ContactPoint::default(); MAX_CONTACTS_PER_ARBITER],
        };
        for (slot, c) in set.points.iter_mut().zip(arb.contacts()) {
            let (a, b) = (pa + c.r1, pb + c.r2);
            *slot = if self.swapped {
                ContactPoint {
                    point_a: b,
                    point_b: a,
                    distance: c.dist,
                }
            } else {
                ContactPoint {
                    point_a: a,
                    point_b: b,
                    distance: c.dist,
                }
            };
        }
        set
    }

    /// Queues a post-step callback (the way to add or remove objects from a
    /// handler); false if `key` is already queued.
    pub fn add_post_step_callback(&mut self, key: u64, f: PostStepFn) -> bool {
        queue_post_step(self.post_step, key, f)
    }
}

/// Queues `f` under `key` unless the key is already queued.
pub(crate) fn queue_post_step(queue: &mut Vec<(u64, PostStepFn)>, key: u64, f: PostStepFn) -> bool {
    if queue.iter().any(|(k, _)| *k == key) {
        return false;
    }
    queue.push((key, f));
    true
}

/// Which callback to run.
#[derive(Clone, Copy)]
enum Event {
    Begin,
    PreSolve,
    PostSolve,
    Separate,
}

impl HandlerTable {
    pub(crate) fn pair_mut(&mut self, a: CollisionType, b: CollisionType) -> &mut CollisionHandler {
        self.pairs
            .entry((a, b))
            .or_insert_with(|| CollisionHandler {
                type_a: a,
                type_b: b,
                ..collision_handler_do_nothing()
            })
    }

    pub(crate) fn wildcard_mut(&mut self, t: CollisionType) -> &mut CollisionHandler {
        self.wildcards.entry(t).or_insert_with(|| CollisionHandler {
            type_a: t,
            ..collision_handler_do_nothing()
        })
    }

    /// True if no handler is registered (the step skips dispatch entirely).
    pub(crate) fn is_empty(&self) -> bool {
        self.pairs.is_empty() && self.wildcards.is_empty()
    }

    fn dispatch(
        &mut self,
        event: Event,
        arbiter: &mut Arbiter,
        bodies: &Arena<Body>,
        shapes: &Arena<Shape>,
        post_step: &mut Vec<(u64, PostStepFn)>,
    ) -> bool {
        if self.is_empty() {
            return true;
        }
        let ta = shapes.get(arbiter.shape_a).map_or(0, |s| s.collision_type);
        let tb = shapes.get(arbiter.shape_b).map_or(0, |s| s.collision_type);
        let mut ctx = ArbiterContext {
            arbiter,
            bodies,
            shapes,
            post_step,
            swapped: false,
        };
        if let Some(h) = self.pairs.get_mut(&(ta, tb)) {
            return run(h, event, &mut ctx);
        }
        if let Some(h) = self.pairs.get_mut(&(tb, ta)) {
            ctx.swapped = true;
            return run(h, event, &mut ctx);
        }
        let mut accept = true;
        if let Some(h) = self.wildcards.get_mut(&ta) {
            accept &= run(h, event, &mut ctx);
        }
        if let Some(h) = self.wildcards.get_mut(&tb) {
            ctx.swapped = true;
            accept &= run(h, event, &mut ctx);
        }
        accept
    }

    pub(crate) fn begin(
        &mut self,
        arb: &mut Arbiter,
        bodies: &Arena<Body>,
        shapes: &Arena<Shape>,
        q: &mut Vec<(u64, PostStepFn)>,
    ) -> bool {
        self.dispatch(Event::Begin, arb, bodies, shapes, q)
    }

    pub(crate) fn pre_solve(
        &mut self,
        arb: &mut Arbiter,
        bodies: &Arena<Body>,
        shapes: &Arena<Shape>,
        q: &mut Vec<(u64, PostStepFn)>,
    ) -> bool {
        self.dispatch(Event::PreSolve, arb, bodies, shapes, q)
    }

    pub(crate) fn post_solve(
        &mut self,
        arb: &mut Arbiter,
        bodies: &Arena<Body>,
        shapes: &Arena<Shape>,
        q: &mut Vec<(u64, PostStepFn)>,
    ) {
        self.dispatch(Event::PostSolve, arb, bodies, shapes, q);
    }

    pub(crate) fn separate(
        &mut self,
        arb: &mut Arbiter,
        bodies: &Arena<Body>,
        shapes: &Arena<Shape>,
        q: &mut Vec<(u64, PostStepFn)>,
    ) {
        self.dispatch(Event::Separate, arb, bodies, shapes, q);
    }
}

fn run(h: &mut CollisionHandler, event: Event, ctx: &mut ArbiterContext<'_>) -> bool {
    match event {
        Event::Begin => h.begin.as_mut().is_none_or(|f| f(ctx)),
        Event::PreSolve => h.pre_solve.as_mut().is_none_or(|f| f(ctx)),
        Event::PostSolve => {
            if let Some(f) = h.post_solve.as_mut() {
                f(ctx);
            }
            true
        }
        Event::Separate => {
            if let Some(f) = h.separate.as_mut() {
                f(ctx);
            }
            true
        }
    }
}
