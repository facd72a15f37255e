//! The world as one resource.
use std::collections::BTreeMap;

use bevy_ecs::entity::{EntityMapper, MapEntities};
use bevy_ecs::prelude::*;
use std::collections::BTreeSet;
use tamias2d::body::BodyHandle;
use tamias2d::constraint::ConstraintHandle;
use tamias2d::math::Real;
use tamias2d::shape::ShapeHandle;
use tamias2d::space::Space;

use crate::contacts::Contact;

/// The simulation: the space, its time step, which entity owns which body,
/// and the contacts the last step started and ended.
///
/// One value: saving it saves the world, restoring it restores the world
/// exactly (what rollback does with it). Move bodies, apply forces and add
/// what has no component through [`space_mut`](Self::space_mut); look a
/// body up by its entity with [`body_of`](Self::body_of).
#[derive(Resource, Clone)]
pub struct Physics {
    pub(crate) space: Space,
    pub(crate) dt: Real,
    /// The entity of every body built from a [`RigidBody`](crate::RigidBody),
    /// in handle order (iteration is deterministic).
    pub(crate) entities: BTreeMap<BodyHandle, Entity>,
    /// The reverse of `entities`.
    pub(crate) bodies: BTreeMap<Entity, BodyHandle>,
    /// Shape pairs touching after the last step, sorted.
    pub(crate) touching: Vec<Contact>,
    pub(crate) started: Vec<Contact>,
    pub(crate) ended: Vec<Contact>,
    /// What removed components and despawned entities took out, removed
    /// from the space before the next step in handle order.
    pub(crate) pending: Removals,
    /// Set while bevy_ggrs restores a frame: the component hooks then leave
    /// the space alone, since the restored resource already holds it.
    pub(crate) restoring: bool,
}

impl Default for Physics {
    /// An empty space with gravity (0, −9.81) and a 1/60 s step.
    fn default() -> Physics {
        let mut space = Space::new();
        space.set_gravity(tamias2d::Vect::new(Real::ZERO, Real::ratio(-981, 100)));
        Physics::new(space, Real::ratio(1, 60))
    }
}

impl Physics {
    /// A resource around `space`, stepped by `dt` per fixed update.
    pub fn new(space: Space, dt: Real) -> Physics {
        Physics {
            space,
            dt,
            entities: BTreeMap::new(),
            bodies: BTreeMap::new(),
            touching: Vec::new(),
            started: Vec::new(),
            ended: Vec::new(),
            pending: Removals::default(),
            restoring: false,
        }
    }

    /// The space.
    pub fn space(&self) -> &Space {
        &self.space
    }

    /// The space, to move bodies, apply forces, change settings, or add
    /// bodies without entities.
    pub fn space_mut(&mut self) -> &mut Space {
        &mut self.space
    }

    /// The time step of one update.
    pub fn dt(&self) -> Real {
        self.dt
    }

    /// Sets the time step of one update.
    pub fn set_dt(&mut self, dt: Real) {
        self.dt = dt;
    }

    /// The body built for `entity`'s [`RigidBody`](crate::RigidBody).
    pub fn body_of(&self, entity: Entity) -> Option<BodyHandle> {
        self.bodies.get(&entity).copied()
    }

    /// The entity whose [`RigidBody`](crate::RigidBody) built `body`.
    pub fn entity_of(&self, body: BodyHandle) -> Option<Entity> {
        self.entities.get(&body).copied()
    }

    /// The entity owning `shape`'s body.
    pub fn entity_of_shape(&self, shape: ShapeHandle) -> Option<Entity> {
        self.entity_of(self.space.shape(shape)?.body())
    }

    /// Every (body, entity) pair, in handle order.
    pub fn entities(&self) -> impl Iterator<Item = (BodyHandle, Entity)> + '_ {
        self.entities.iter().map(|(h, e)| (*h, *e))
    }

    /// Contacts that began in the last step, in shape-handle order. Part of
    /// the resource, so rolled back with it: game logic may read it.
    pub fn contacts_started(&self) -> &[Contact] {
        &self.started
    }

    /// Contacts that ended in the last step, in shape-handle order.
    pub fn contacts_ended(&self) -> &[Contact] {
        &self.ended
    }

    /// Shape pairs touching after the last step, in shape-handle order.
    pub fn contacts(&self) -> &[Contact] {
        &self.touching
    }

    /// The checksum of the simulation: the space's, so that peers whose
    /// entity ids differ still agree. What rollback sessions compare.
    pub fn checksum(&self) -> u64 {
        self.space.checksum()
    }

    pub(crate) fn link(&mut self, body: BodyHandle, entity: Entity) {
        self.entities.insert(body, entity);
        self.bodies.insert(entity, body);
    }

    /// Removes what removed components and despawned entities took out:
    /// joints, then shapes, then bodies, each in handle order, so the
    /// space (its free lists, hence the next handles) does not depend on
    /// the order the game despawned them in, a query's order, which
    /// differs between peers. The step does it first; call it to see the
    /// space without them sooner. Stale handles (a joint that went with its
    /// body) are skipped.
    pub fn flush_removals(&mut self) {
        let pending = std::mem::take(&mut self.pending);
        for h in pending.constraints {
            let _ = self.space.remove_constraint(h);
        }
        for h in pending.shapes {
            let _ = self.space.remove_shape(h);
        }
        for h in pending.bodies {
            let _ = self.space.remove_body(h);
        }
    }

    /// Forgets `entity`'s body if `body` is still the one it owns.
    pub(crate) fn unlink(&mut self, body: BodyHandle, entity: Entity) -> bool {
        if self.entities.get(&body) != Some(&entity) {
            return false;
        }
        self.entities.remove(&body);
        self.bodies.remove(&entity);
        true
    }
}

/// Removals waiting for the next step, sorted by handle.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Removals {
    pub(crate) bodies: BTreeSet<BodyHandle>,
    pub(crate) shapes: BTreeSet<ShapeHandle>,
    pub(crate) constraints: BTreeSet<ConstraintHandle>,
}

impl MapEntities for Physics {
    /// After a rollback respawned entities under new ids: the map and the
    /// contact lists follow them.
    fn map_entities<E: EntityMapper>(&mut self, mapper: &mut E) {
        for entity in self.entities.values_mut() {
            *entity = mapper.get_mapped(*entity);
        }
        self.bodies = self.entities.iter().map(|(h, e)| (*e, *h)).collect();
        for list in [&mut self.touching, &mut self.started, &mut self.ended] {
            for contact in list.iter_mut() {
                contact.map_entities(mapper);
            }
        }
    }
}

/// What could not be built (a collider with a negative radius, a joint
/// naming an entity without a body…), newest last. Not part of the
/// simulation and not rolled back: a game drains it (`take`) or logs it.
#[derive(Resource, Clone, Debug, Default)]
pub struct PhysicsErrors {
    /// `(entity, what went wrong)`.
    pub errors: Vec<(Entity, String)>,
}

impl PhysicsErrors {
    /// Takes every error reported so far.
    pub fn take(&mut self) -> Vec<(Entity, String)> {
        std::mem::take(&mut self.errors)
    }
}
