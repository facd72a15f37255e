//! The component that declares a joint between two bodies' entities.
use bevy_ecs::entity::{EntityMapper, MapEntities};
use bevy_ecs::prelude::*;
use tamias2d::constraint::{ConstraintHandle, JointKind, JointSoftness};

use crate::hooks;

/// A joint between the bodies of entities `a` and `b`, built into the space
/// when inserted (both bodies must be built by then: spawn them first),
/// removed with the component, or with either body.
///
/// It may sit on an entity of its own or on one of the two bodies' entities.
#[derive(Component, Clone, Debug, PartialEq)]
#[component(on_add = hooks::joint_added, on_remove = hooks::joint_removed)]
pub struct Joint {
    pub(crate) a: Entity,
    pub(crate) b: Entity,
    pub(crate) kind: JointKind,
    pub(crate) collide_bodies: bool,
    pub(crate) softness: Option<JointSoftness>,
    pub(crate) handle: Option<ConstraintHandle>,
}

impl Joint {
    /// A joint of `kind` (e.g. a `PivotJoint`) between `a`'s and `b`'s
    /// bodies. The bodies collide with each other unless
    /// [`with_collide_bodies`](Self::with_collide_bodies) says not.
    pub fn new(a: Entity, b: Entity, kind: impl Into<JointKind>) -> Joint {
        Joint {
            a,
            b,
            kind: kind.into(),
            collide_bodies: true,
            softness: None,
            handle: None,
        }
    }

    /// Whether the two bodies collide with each other.
    pub fn with_collide_bodies(mut self, collide: bool) -> Joint {
        self.collide_bodies = collide;
        self
    }

    /// The joint's own stiffness on the soft step (`None`: the world's).
    pub fn with_softness(mut self, softness: Option<JointSoftness>) -> Joint {
        self.softness = softness;
        self
    }

    /// The two entities.
    pub fn entities(&self) -> (Entity, Entity) {
        (self.a, self.b)
    }

    /// The constraint's handle in the space, once built.
    pub fn handle(&self) -> Option<ConstraintHandle> {
        self.handle
    }
}

impl MapEntities for Joint {
    fn map_entities<E: EntityMapper>(&mut self, mapper: &mut E) {
        self.a = mapper.get_mapped(self.a);
        self.b = mapper.get_mapped(self.b);
    }
}
