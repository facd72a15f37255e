//! Transforms written out for rendering: floats at the edge only.
//!
//! Runs in `PostUpdate`, after whatever fixed updates (and rollbacks) the
//! frame ran, so a `Transform` always shows the space's current state. It
//! is written, never read: nothing float flows back into the simulation.
use bevy_ecs::prelude::*;
use bevy_math::Quat;
use bevy_transform::components::Transform;

use crate::body::RigidBody;
use crate::physics::Physics;

/// Copies every built body's position and angle into its `Transform`
/// (x and y; z and scale are the game's).
pub(crate) fn write_transforms(
    physics: Res<Physics>,
    mut bodies: Query<(&RigidBody, &mut Transform)>,
) {
    for (rb, mut transform) in &mut bodies {
        let Some(body) = rb.handle().and_then(|h| physics.space().body(h)) else {
            continue;
        };
        let p = body.position();
        transform.translation.x = p.x.to_f32();
        transform.translation.y = p.y.to_f32();
        transform.rotation = Quat::from_rotation_z(body.angle().to_f32());
    }
}
