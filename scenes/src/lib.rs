//! Tamias2D's fixtures: the scene description language, the standard scenes
//! (see `scenes/README.md`) with their one registry, and scripted worlds.
//! The engine (`tamias2d`) does not depend on this crate; its tests, benches
//! and examples, and the `tamias` CLI, do.
//!
//! A scene is first **data**, a [`SceneDesc`]: settings, time step, bodies
//! with their shapes and materials, and scripted events (forces re-applied
//! every step, bodies spawned at a given step, `begin` counters). It
//! serializes with serde, every `Real` as an exact decimal string, so the
//! same bodies can be dumped to JSON and fed to other engines.
//! [`SceneDesc::build`] turns it into a running [`ScriptedWorld`] (a
//! [`Space`](tamias2d::space::Space) plus its script: the scripted events and
//! how far they have run), validating everything and returning a
//! [`SceneError`] instead of panicking. A scripted world saves and loads
//! with its script ([`ScriptedWorld::save`], [`ScriptedWorld::load`]), and
//! is a [`Simulation`](tamias2d::replay::Simulation), so replays of a scene
//! re-run its script.
//!
//! [`REGISTRY`] lists every standard scene once, with its section, size,
//! default step count and golden checksum; every other list of scenes
//! (tests, benches, the CLI, the performance report) reads it.
//!
//! Each standard scene is a **pure function of its parameters**: built from
//! integers, exact literals and the engine's own `Real` routines (`sin_cos`,
//! the mass helpers) and, where randomness is needed,
//! [`SplitMix64`](rng::SplitMix64) seeded with 45073. No float is involved,
//! so a scene is the same bits on every platform.
//!
//! ```
//! let desc = tamias2d_scenes::builtin("pyramid_20").expect("registered scene");
//! let mut world = desc.build().expect("valid scene");
//! world.step().expect("step");
//! assert_eq!(world.space.bodies().count(), 211);
//! ```
#![forbid(unsafe_code)]
// The same rules as the engine's library code: no reachable panic, no
// unchecked integer arithmetic.
#![cfg_attr(
    not(test),
    deny(
        clippy::arithmetic_side_effects,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

pub mod accuracy;
#[cfg(feature = "bench")]
pub mod bench;
pub mod box2d;
pub mod bullets;
pub mod character_level;
pub mod dec;
pub mod desc;
#[cfg(feature = "ggrs")]
pub mod ggrs_game;
pub mod goldens;
pub mod joints;
pub mod quality;
pub mod registry;
pub mod rng;
pub mod shared;
pub mod stacking;
pub mod terrain;
mod world;

pub use desc::{
    soft_step_for, BodyDesc, BodyKind, ConstraintDesc, CounterDesc, ForceDesc, GeometryDesc,
    JointType, MassDesc, Neighbors, SceneDesc, SettingsDesc, ShapeDesc, ShapeMassDesc,
    SoftStepDesc, SolverDesc, SpawnDesc,
};
pub use registry::{builtin, find, Golden, SceneInfo, Section, REGISTRY};
/// The engine's kernel choice (`Space::set_kernels`), for the golden test,
/// which names nothing outside this crate.
pub use tamias2d::space::Kernels;
pub use world::{BodyPath, LoadError, SceneError, ScriptedWorld};
