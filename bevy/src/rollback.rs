//! bevy_ggrs rollback, registered in one place.
//!
//! The world is one value: the [`Physics`] resource is saved and restored
//! by clone (the space, its entity map and its contact lists together),
//! its checksum is the space's, and after a restore its entity references
//! follow the entities bevy_ggrs respawned. The components are rolled
//! back too, so an entity and its body come and go together; each of them
//! requires the `Rollback` marker.
use bevy_app::App;
use bevy_ecs::lifecycle::Add;
use bevy_ecs::prelude::*;
use bevy_ecs::query::Allow;
use bevy_ggrs::{
    ComponentMapEntitiesPlugin, LoadWorld, LoadWorldSystems, ResourceMapEntitiesPlugin,
    RollbackApp, RollbackDespawned,
};

use crate::body::{Collider, RigidBody};
use crate::joint::Joint;
use crate::physics::Physics;

pub(crate) fn register(app: &mut App) {
    app.rollback_resource_with_clone::<Physics>()
        .checksum_resource::<Physics>(Physics::checksum)
        .rollback_component_with_clone::<RigidBody>()
        .rollback_component_with_clone::<Collider>()
        .rollback_component_with_clone::<Joint>()
        .require_rollback::<RigidBody>()
        .require_rollback::<Joint>()
        .add_plugins(ResourceMapEntitiesPlugin::<Physics>::default())
        .add_plugins(ComponentMapEntitiesPlugin::<Joint>::default())
        .add_systems(
            LoadWorld,
            begin_restore.before(LoadWorldSystems::EntityResurrect),
        )
        .add_systems(LoadWorld, end_restore.after(LoadWorldSystems::Mapping))
        .add_observer(body_despawned_for_rollback);
}

fn begin_restore(mut physics: ResMut<Physics>) {
    physics.restoring = true;
}

fn end_restore(mut physics: ResMut<Physics>) {
    physics.restoring = false;
}

/// `despawn_rollback` hides an entity until its frame is confirmed instead
/// of despawning it: its body leaves the space now, as a despawn would.
fn body_despawned_for_rollback(
    add: On<Add, RollbackDespawned>,
    // `RollbackDespawned` disables the entity: queries skip it unless allowed.
    bodies: Query<&RigidBody, Allow<RollbackDespawned>>,
    mut physics: ResMut<Physics>,
) {
    if physics.restoring {
        return;
    }
    let entity = add.event_target();
    let Some(handle) = bodies.get(entity).ok().and_then(RigidBody::handle) else {
        return;
    };
    if physics.unlink(handle, entity) {
        let _ = physics.space_mut().remove_body(handle);
    }
}
