//! The plugin: resources, the fixed-step systems, the render write-out.
use bevy_app::{App, FixedUpdate, Plugin, PostUpdate};
use bevy_ecs::intern::Interned;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleLabel;

use crate::contacts::{update_contacts, ContactEnded, ContactStarted};
use crate::physics::{Physics, PhysicsErrors};
use crate::render::write_transforms;

/// The physics systems of the fixed schedule, in this order. Order the
/// game's systems that touch [`Physics`] against them (`.before(
/// PhysicsSystems::Step)` for forces and inputs): under bevy_ggrs an
/// unordered pair is a schedule error, so no order is left to chance.
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub enum PhysicsSystems {
    /// One step of the space by [`Physics::dt`], then the contact lists.
    Step,
    /// The contact messages of that step.
    Messages,
}

/// Adds [`Physics`] (unless the app already has one: insert your own to
/// choose gravity, settings and the time step), [`PhysicsErrors`], the
/// contact messages, the step in a fixed schedule and the `Transform`
/// write-out in `PostUpdate`.
pub struct TamiasPlugin {
    schedule: Interned<dyn ScheduleLabel>,
    #[cfg(feature = "ggrs")]
    rollback: bool,
}

impl Default for TamiasPlugin {
    /// Steps in `FixedUpdate`: one step of [`Physics::dt`] per fixed
    /// update, whatever Bevy's fixed clock says (set it to the same rate,
    /// `Time::<Fixed>::from_hz(60.0)`, for real time).
    fn default() -> TamiasPlugin {
        TamiasPlugin::in_schedule(FixedUpdate)
    }
}

impl TamiasPlugin {
    /// Steps in `schedule` instead.
    pub fn in_schedule(schedule: impl ScheduleLabel) -> TamiasPlugin {
        TamiasPlugin {
            schedule: schedule.intern(),
            #[cfg(feature = "ggrs")]
            rollback: false,
        }
    }

    /// Rollback with bevy_ggrs (feature `ggrs`): steps in `GgrsSchedule`
    /// and registers the resource, the components, their `Rollback`
    /// marker, the entity remapping and the checksum. Add bevy_ggrs'
    /// `GgrsPlugin` as usual; nothing else is registered by hand.
    #[cfg(feature = "ggrs")]
    pub fn rollback() -> TamiasPlugin {
        TamiasPlugin {
            schedule: bevy_ggrs::GgrsSchedule.intern(),
            rollback: true,
        }
    }
}

impl Plugin for TamiasPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Physics>()
            .init_resource::<PhysicsErrors>()
            .add_message::<ContactStarted>()
            .add_message::<ContactEnded>()
            .configure_sets(
                self.schedule,
                (PhysicsSystems::Step, PhysicsSystems::Messages).chain(),
            )
            .add_systems(self.schedule, step.in_set(PhysicsSystems::Step))
            .add_systems(
                self.schedule,
                send_contact_messages.in_set(PhysicsSystems::Messages),
            )
            .add_systems(PostUpdate, write_transforms);
        #[cfg(feature = "ggrs")]
        if self.rollback {
            crate::rollback::register(app);
        }
    }
}

/// One step; an error (the world's own validation) is reported, and the
/// world stays as it was before the step.
fn step(mut physics: ResMut<Physics>, mut errors: ResMut<PhysicsErrors>) {
    physics.flush_removals();
    let dt = physics.dt();
    if let Err(e) = physics.space_mut().step(dt) {
        errors
            .errors
            .push((Entity::PLACEHOLDER, format!("step: {e}")));
        return;
    }
    update_contacts(&mut physics);
}

fn send_contact_messages(
    physics: Res<Physics>,
    mut started: MessageWriter<ContactStarted>,
    mut ended: MessageWriter<ContactEnded>,
) {
    started.write_batch(
        physics
            .contacts_started()
            .iter()
            .copied()
            .map(ContactStarted),
    );
    ended.write_batch(physics.contacts_ended().iter().copied().map(ContactEnded));
}
