//! bevy_ggrs rollback, registered in one place.
//!
//! The world is one value: the [`Physics`] resource is saved and restored
//! as a whole (the space, its entity map and its contact lists together),
//! its checksum is the space's, and after a restore its entity references
//! follow the entities bevy_ggrs respawned. The components are rolled
//! back too, so an entity and its body come and go together; each of them
//! requires the `Rollback` marker.
//!
//! The space is saved as the engine's frame ([`FrameState`]: everything
//! that changes, the static level named by its digest) into buffers reused
//! from save to save, and restored in place: no allocation once the
//! prediction window is full, and the space keeps its caches (a clone
//! would rebuild them on the next step). A frame of another level (static
//! bodies added or removed within the window) is restored onto a copy of
//! the space taken when that level was first saved.
use bevy_app::App;
use bevy_ecs::lifecycle::Add;
use bevy_ecs::prelude::*;
use bevy_ecs::query::Allow;
use bevy_ggrs::{
    ComponentMapEntitiesPlugin, ConfirmedFrameCount, LoadWorld, LoadWorldSystems,
    ResourceMapEntitiesPlugin, RollbackApp, RollbackDespawned, RollbackFrameCount, SaveWorld,
    SaveWorldSystems,
};
use std::collections::{BTreeMap, BTreeSet};
use tamias2d::body::BodyHandle;
use tamias2d::math::Real;
use tamias2d::space::{FrameState, Space};

use crate::body::{Collider, RigidBody};
use crate::contacts::Contact;
use crate::joint::Joint;
use crate::physics::{Physics, PhysicsErrors, Removals};

pub(crate) fn register(app: &mut App) {
    app.init_resource::<PhysicsSnapshots>()
        .add_systems(SaveWorld, save_physics.in_set(SaveWorldSystems::Snapshot))
        .add_systems(LoadWorld, load_physics.in_set(LoadWorldSystems::Data))
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
        physics.pending.bodies.insert(handle);
    }
}

/// One saved frame of [`Physics`].
#[derive(Default)]
struct Snapshot {
    frame: FrameState,
    dt: Real,
    entities: BTreeMap<BodyHandle, Entity>,
    touching: Vec<Contact>,
    started: Vec<Contact>,
    ended: Vec<Contact>,
    pending: Removals,
}

/// Frames bevy_ggrs may roll back to: a safety cap on top of dropping
/// what is confirmed (a session never rolls back further than its
/// prediction window, 8 frames by default).
const MAX_FRAMES: usize = 128;

/// The saved frames of the physics, by frame number, and what restoring
/// them needs.
#[derive(Resource, Default)]
pub(crate) struct PhysicsSnapshots {
    frames: BTreeMap<i32, Snapshot>,
    /// Dropped snapshots, their buffers reused by the next saves.
    spare: Vec<Snapshot>,
    /// A space of each level the kept frames name, copied when that level
    /// was first saved.
    levels: BTreeMap<u64, Space>,
}

fn save_physics(
    mut snapshots: ResMut<PhysicsSnapshots>,
    physics: Res<Physics>,
    frame: Res<RollbackFrameCount>,
    confirmed: Option<Res<ConfirmedFrameCount>>,
) {
    let snapshots = &mut *snapshots;
    let now = frame.0;
    // A re-simulated frame overwrites its successors; a frame before the
    // confirmed one is never loaded again.
    let oldest = confirmed.map_or(i32::MIN, |c| c.0);
    let stale: Vec<i32> = snapshots
        .frames
        .keys()
        .copied()
        .filter(|&f| f >= now || f < oldest)
        .collect();
    for f in stale {
        if let Some(s) = snapshots.frames.remove(&f) {
            snapshots.spare.push(s);
        }
    }
    while snapshots.frames.len() >= MAX_FRAMES {
        match snapshots.frames.pop_first() {
            Some((_, s)) => snapshots.spare.push(s),
            None => break,
        }
    }
    let mut snap = snapshots.spare.pop().unwrap_or_default();
    physics.space.save_frame(&mut snap.frame);
    snap.dt = physics.dt;
    snap.entities.clone_from(&physics.entities);
    snap.touching.clone_from(&physics.touching);
    snap.started.clone_from(&physics.started);
    snap.ended.clone_from(&physics.ended);
    snap.pending.clone_from(&physics.pending);
    let level = snap.frame.level_digest();
    snapshots
        .levels
        .entry(level)
        .or_insert_with(|| physics.space.clone());
    snapshots.frames.insert(now, snap);
    let live = physics.space.level_digest();
    let named: BTreeSet<u64> = snapshots
        .frames
        .values()
        .map(|s| s.frame.level_digest())
        .collect();
    snapshots
        .levels
        .retain(|digest, _| *digest == live || named.contains(digest));
}

fn load_physics(
    snapshots: Res<PhysicsSnapshots>,
    mut physics: ResMut<Physics>,
    frame: Res<RollbackFrameCount>,
    mut errors: ResMut<PhysicsErrors>,
) {
    let Some(snap) = snapshots.frames.get(&frame.0) else {
        let e = format!("rollback: no physics snapshot of frame {}", frame.0);
        errors.errors.push((Entity::PLACEHOLDER, e));
        return;
    };
    let physics = &mut *physics;
    let level = snap.frame.level_digest();
    if physics.space.level_digest() != level {
        let Some(space) = snapshots.levels.get(&level) else {
            let e = format!("rollback: frame {} names a level no longer kept", frame.0);
            errors.errors.push((Entity::PLACEHOLDER, e));
            return;
        };
        physics.space = space.clone();
    }
    if let Err(e) = physics.space.restore_frame(&snap.frame) {
        let e = format!("rollback: frame {}: {e}", frame.0);
        errors.errors.push((Entity::PLACEHOLDER, e));
        return;
    }
    physics.dt = snap.dt;
    physics.entities.clone_from(&snap.entities);
    physics.bodies = physics.entities.iter().map(|(h, e)| (*e, *h)).collect();
    physics.touching.clone_from(&snap.touching);
    physics.started.clone_from(&snap.started);
    physics.ended.clone_from(&snap.ended);
    physics.pending.clone_from(&snap.pending);
}
