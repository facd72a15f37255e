//! Contacts as data: which shape pairs touch, which began, which ended.
//!
//! Computed after every step from the space's arbiters (in their canonical
//! order) and kept in [`Physics`], so they roll back with the world and
//! game logic may read them. The [`ContactStarted`] and [`ContactEnded`]
//! messages carry the same contacts for presentation (sounds, particles):
//! like every Bevy message they are not rolled back, so a re-simulated
//! frame sends its messages again.
use bevy_ecs::entity::{EntityMapper, MapEntities};
use bevy_ecs::prelude::*;
use tamias2d::arbiter::ArbiterState;
use tamias2d::body::BodyHandle;
use tamias2d::shape::ShapeHandle;

use crate::physics::Physics;

/// Two shapes touching (or a sensor overlapping a shape).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contact {
    /// The two shapes, in the arbiter's canonical order.
    pub shapes: (ShapeHandle, ShapeHandle),
    /// Their bodies, in the same order.
    pub bodies: (BodyHandle, BodyHandle),
    /// The bodies' entities (`None` for a body added without one).
    pub entities: (Option<Entity>, Option<Entity>),
    /// Whether either shape is a sensor (no collision, a report only).
    pub sensor: bool,
}

impl MapEntities for Contact {
    fn map_entities<E: EntityMapper>(&mut self, mapper: &mut E) {
        for entity in [&mut self.entities.0, &mut self.entities.1]
            .into_iter()
            .flatten()
        {
            *entity = mapper.get_mapped(*entity);
        }
    }
}

/// A contact that began in the last step.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactStarted(pub Contact);

/// A contact that ended in the last step.
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactEnded(pub Contact);

/// Recomputes the touching pairs after a step, and what began and ended.
pub(crate) fn update_contacts(physics: &mut Physics) {
    let space = physics.space();
    let mut now: Vec<Contact> = space
        .arbiters()
        .iter()
        .filter(|arb| arb.state() != ArbiterState::Cached)
        .map(|arb| {
            let shapes = arb.shapes();
            let bodies = arb.bodies();
            let sensor = [shapes.0, shapes.1]
                .iter()
                .any(|&h| space.shape(h).is_some_and(|s| s.sensor));
            Contact {
                shapes,
                bodies,
                entities: (physics.entity_of(bodies.0), physics.entity_of(bodies.1)),
                sensor,
            }
        })
        .collect();
    now.sort_by_key(|c| c.shapes);
    let before = std::mem::take(&mut physics.touching);
    physics.started = difference(&now, &before);
    physics.ended = difference(&before, &now);
    physics.touching = now;
}

/// The contacts of sorted `a` whose shape pair is not in sorted `b`.
fn difference(a: &[Contact], b: &[Contact]) -> Vec<Contact> {
    a.iter()
        .filter(|c| b.binary_search_by_key(&c.shapes, |d| d.shapes).is_err())
        .copied()
        .collect()
}
