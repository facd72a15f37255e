//! Component hooks: where declarations become bodies, shapes and joints.
//!
//! Hooks run when a command inserts or removes a component, in command
//! order, which the game's systems fix. Building here (and not in a system
//! that iterates a query) is what makes the order bodies enter the space
//! the same on every peer.
//!
//! While a rollback restores a frame ([`Physics::restoring`]) the hooks do
//! nothing: the restored resource already holds the space of that frame,
//! and the components bevy_ggrs re-inserts carry their handles.
use bevy_ecs::lifecycle::HookContext;
use bevy_ecs::prelude::*;
use bevy_ecs::world::DeferredWorld;
use tamias2d::body::{BodyHandle, BodyType};
use tamias2d::constraint::Constraint;
use tamias2d::shape::ShapeHandle;

use crate::body::{Collider, RigidBody};
use crate::joint::Joint;
use crate::physics::{Physics, PhysicsErrors};

fn report(world: &mut DeferredWorld, entity: Entity, error: String) {
    if let Some(mut errors) = world.get_resource_mut::<PhysicsErrors>() {
        errors.errors.push((entity, error));
    }
}

/// The physics resource, unless absent or restoring.
fn live_physics<'w>(world: &'w mut DeferredWorld) -> Option<Mut<'w, Physics>> {
    world
        .get_resource_mut::<Physics>()
        .filter(|physics| !physics.restoring)
}

pub(crate) fn body_added(mut world: DeferredWorld, ctx: HookContext) {
    let entity = ctx.entity;
    let Some(decl) = world.get::<RigidBody>(entity).cloned() else {
        return;
    };
    if decl.handle.is_some() {
        return;
    }
    let collider = world
        .get::<Collider>(entity)
        .filter(|c| c.handles.is_empty())
        .cloned();
    let Some(mut physics) = live_physics(&mut world) else {
        if !world.contains_resource::<Physics>() {
            report(
                &mut world,
                entity,
                "RigidBody without a Physics resource: add TamiasPlugin".into(),
            );
        }
        return;
    };
    let built = build_body(&mut physics, entity, &decl, collider.as_ref());
    match built {
        Ok((body, shapes)) => {
            if let Some(mut rb) = world.get_mut::<RigidBody>(entity) {
                rb.handle = Some(body);
            }
            if let (Some(shapes), Some(mut c)) = (shapes, world.get_mut::<Collider>(entity)) {
                c.handles = shapes;
            }
        }
        Err(e) => report(&mut world, entity, e),
    }
}

/// Adds the body and its collider's shapes, all or nothing.
fn build_body(
    physics: &mut Physics,
    entity: Entity,
    decl: &RigidBody,
    collider: Option<&Collider>,
) -> Result<(BodyHandle, Option<Vec<ShapeHandle>>), String> {
    if decl.body_type == BodyType::Dynamic && decl.mass.is_none() && collider.is_none() {
        return Err(
            "a dynamic RigidBody needs a Collider (its density gives the mass) or with_mass".into(),
        );
    }
    let body = decl.to_body()?;
    let space = physics.space_mut();
    let handle = space.add_body(body).map_err(|e| e.to_string())?;
    let shapes = match collider {
        Some(c) => match add_shapes(physics, handle, c) {
            Ok(shapes) => Some(shapes),
            Err(e) => {
                let _ = physics.space_mut().remove_body(handle);
                return Err(e);
            }
        },
        None => None,
    };
    physics.link(handle, entity);
    Ok((handle, shapes))
}

/// Adds a collider's shapes to `body`, all or nothing.
fn add_shapes(
    physics: &mut Physics,
    body: BodyHandle,
    collider: &Collider,
) -> Result<Vec<ShapeHandle>, String> {
    let shapes = collider.to_shapes(body)?;
    let space = physics.space_mut();
    let mut handles = Vec::with_capacity(shapes.len());
    for shape in shapes {
        match space.add_shape(shape) {
            Ok(h) => handles.push(h),
            Err(e) => {
                for h in handles {
                    let _ = space.remove_shape(h);
                }
                return Err(e.to_string());
            }
        }
    }
    Ok(handles)
}

pub(crate) fn body_removed(mut world: DeferredWorld, ctx: HookContext) {
    let entity = ctx.entity;
    let Some(handle) = world.get::<RigidBody>(entity).and_then(RigidBody::handle) else {
        return;
    };
    if let Some(mut physics) = live_physics(&mut world) {
        // A body another entity owns now (a stale link) is left alone.
        if physics.unlink(handle, entity) {
            physics.pending.bodies.insert(handle);
        }
    }
}

pub(crate) fn collider_added(mut world: DeferredWorld, ctx: HookContext) {
    let entity = ctx.entity;
    let Some(collider) = world.get::<Collider>(entity).cloned() else {
        return;
    };
    if !collider.handles.is_empty() {
        return;
    }
    // Without a built body yet, the body's hook builds the collider with it.
    let Some(body) = world.get::<RigidBody>(entity).and_then(RigidBody::handle) else {
        return;
    };
    let Some(mut physics) = live_physics(&mut world) else {
        return;
    };
    let added = add_shapes(&mut physics, body, &collider);
    match added {
        Ok(handles) => {
            if let Some(mut c) = world.get_mut::<Collider>(entity) {
                c.handles = handles;
            }
        }
        Err(e) => report(&mut world, entity, e),
    }
}

pub(crate) fn collider_removed(mut world: DeferredWorld, ctx: HookContext) {
    let entity = ctx.entity;
    let Some(handles) = world.get::<Collider>(entity).map(|c| c.handles.clone()) else {
        return;
    };
    if let Some(mut physics) = live_physics(&mut world) {
        physics.pending.shapes.extend(handles);
    }
}

pub(crate) fn joint_added(mut world: DeferredWorld, ctx: HookContext) {
    let entity = ctx.entity;
    let Some(decl) = world.get::<Joint>(entity).cloned() else {
        return;
    };
    if decl.handle.is_some() {
        return;
    }
    let body = |world: &DeferredWorld, e: Entity| {
        world
            .get::<RigidBody>(e)
            .and_then(RigidBody::handle)
            .ok_or_else(|| format!("joint: entity {e} has no built RigidBody"))
    };
    let bodies = body(&world, decl.a).and_then(|a| Ok((a, body(&world, decl.b)?)));
    let Some(mut physics) = live_physics(&mut world) else {
        return;
    };
    let built = bodies.and_then(|(a, b)| {
        let mut c = Constraint::new(a, b, decl.kind).map_err(|e| format!("joint: {e}"))?;
        c.set_collide_bodies(decl.collide_bodies);
        c.set_softness(decl.softness)
            .map_err(|e| format!("joint: {e}"))?;
        physics
            .space_mut()
            .add_constraint(c)
            .map_err(|e| format!("joint: {e}"))
    });
    match built {
        Ok(handle) => {
            if let Some(mut j) = world.get_mut::<Joint>(entity) {
                j.handle = Some(handle);
            }
        }
        Err(e) => report(&mut world, entity, e),
    }
}

pub(crate) fn joint_removed(mut world: DeferredWorld, ctx: HookContext) {
    let Some(handle) = world.get::<Joint>(ctx.entity).and_then(Joint::handle) else {
        return;
    };
    if let Some(mut physics) = live_physics(&mut world) {
        physics.pending.constraints.insert(handle);
    }
}
