//! Tamias2D in Bevy: deterministic fixed-point 2D physics as one resource.
//!
//! The whole simulation is one [`Physics`] resource holding a
//! [`tamias2d::space::Space`]. Bodies, colliders and joints are declared as
//! components ([`RigidBody`], [`Collider`], [`Joint`]); the plugin builds
//! them into the space the moment their components are inserted, steps the
//! space in a fixed schedule, writes `Transform`s out for rendering, and
//! reports contacts ([`ContactStarted`], [`ContactEnded`]). Queries (rays,
//! shape casts, points) go through the [`PhysicsQuery`] system parameter.
//!
//! With the `ggrs` feature, `TamiasPlugin::rollback()` steps in
//! `bevy_ggrs`'s `GgrsSchedule` and registers everything rollback needs:
//! the resource (saved and restored as one value, its entity map with it),
//! the components, the `Rollback` marker and the checksum GGRS compares.
//! Nothing is registered by hand.
//!
//! # Determinism, designed in
//! - **Order.** Bodies enter the space in the order their components are
//!   inserted (command order, which a game's systems fix), never in query
//!   order: Bevy's iteration order follows archetypes and entity ids, which
//!   differ between peers once rollbacks have respawned entities.
//! - **Removals in handle order.** Despawns often come from a query loop;
//!   the bodies, shapes and joints they take out leave the space at the
//!   next step, sorted by handle, so the free lists (and the next handles)
//!   are the same on every peer. Spawn in an order the game fixes.
//! - **No floats in.** Positions, velocities and sizes are fixed point
//!   ([`tamias2d::Real`], [`tamias2d::Vect`]); `Transform` is written, never
//!   read. Bevy's `Time` is not read either: each step advances by
//!   [`Physics::dt`].
//! - **Entities stay out of the simulation.** The entity ↔ body map lives in
//!   the resource for lookups and events; the checksum covers the space
//!   alone, so peers whose entity ids differ still agree.
//!
//! ```
//! use bevy_app::{App, Startup};
//! use bevy_ecs::prelude::*;
//! use tamias2d::{real, Real, Vect};
//! use tamias2d_bevy::prelude::*;
//!
//! fn setup(mut commands: Commands) {
//!     commands.spawn((
//!         RigidBody::fixed(),
//!         Collider::segment(Vect::from_ints(-10, 0), Vect::from_ints(10, 0), Real::ZERO),
//!     ));
//!     commands.spawn((
//!         RigidBody::dynamic().at(Vect::from_ints(0, 5)),
//!         Collider::circle(Real::HALF),
//!     ));
//! }
//!
//! let mut app = App::new();
//! app.add_plugins(TamiasPlugin::default()).add_systems(Startup, setup);
//! app.update();
//! // Step by hand here (a game steps in `FixedUpdate`).
//! for _ in 0..120 {
//!     app.world_mut().run_schedule(bevy_app::FixedUpdate);
//! }
//! let physics = app.world().resource::<Physics>();
//! let ball = physics.space().bodies().find(|(_, b)| b.is_dynamic()).unwrap().1;
//! assert!(ball.position().y < real!(0.6)); // resting on the ground
//! ```
#![forbid(unsafe_code)]
#![cfg_attr(not(test), deny(clippy::float_arithmetic))]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

mod body;
mod contacts;
mod hooks;
mod joint;
mod physics;
mod plugin;
mod query;
mod render;
#[cfg(feature = "ggrs")]
mod rollback;

pub use body::{Collider, ColliderShape, RigidBody};
pub use contacts::{Contact, ContactEnded, ContactStarted};
pub use joint::Joint;
pub use physics::{Physics, PhysicsErrors};
pub use plugin::{PhysicsSystems, TamiasPlugin};
pub use query::{CastHit, PhysicsQuery, PointHit, RayHit};

/// The bevy_ggrs this crate is built against (feature `ggrs`): use it, so
/// that the versions match.
#[cfg(feature = "ggrs")]
pub use bevy_ggrs;

/// What a game needs in scope: the components, the resource, the plugin
/// and the query parameter.
pub mod prelude {
    pub use crate::{
        CastHit, Collider, ColliderShape, Contact, ContactEnded, ContactStarted, Joint, Physics,
        PhysicsErrors, PhysicsQuery, PhysicsSystems, PointHit, RayHit, RigidBody, TamiasPlugin,
    };
}
