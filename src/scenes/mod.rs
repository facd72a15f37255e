//! Built-in scenes (BENCH_SCENES.md), shared by tests, benches, examples and
//! the CLI.
//!
//! A scene is first **data**, a [`SceneDesc`]: settings, time step, bodies
//! with their shapes and materials, and scripted events (forces re-applied
//! every step, bodies spawned at a given step, `begin` counters). It
//! serializes with serde, every `Real` as an exact decimal string, so the
//! same bodies can be dumped to JSON and fed to other engines.
//! [`SceneDesc::build`] turns it into a running [`Scene`] (a
//! [`Space`](crate::space::Space) plus the scripted events), validating
//! everything and returning a [`SceneError`] instead of panicking.
//!
//! Each built-in scene is a **pure function of its parameters**: built from
//! integers, exact literals and our own `Real` routines (`sin_cos`, the mass
//! helpers) and, where randomness is needed, [`SplitMix64`](rng::SplitMix64)
//! seeded with 45073. No float is involved, so a scene is the same bits on
//! every platform.
//!
//! ```
//! use tamias2d::scenes;
//! let desc = scenes::builtin("pyramid_20").expect("listed scene");
//! let mut scene = desc.build().expect("valid scene");
//! scene.step().expect("step");
//! assert_eq!(scene.space.bodies().count(), 211);
//! ```
pub mod accuracy;
mod build;
pub mod dec;
pub mod desc;
pub mod rng;
pub mod stacking;
pub mod terrain;

pub use build::{BodyPath, Scene, SceneError};
pub use desc::{
    BodyDesc, BodyKind, CounterDesc, ForceDesc, GeometryDesc, MassDesc, Neighbors, SceneDesc,
    SettingsDesc, ShapeDesc, ShapeMassDesc, SpawnDesc,
};

use crate::real;

/// Every built-in scene: registry name and a one-line description.
const LIST: &[(&str, &str)] = &[
    (
        "bowl_circles_100",
        "A: 100 circles (r 5) dropped into a 48-segment bowl",
    ),
    (
        "bowl_circles_500",
        "A: 500 circles (r 5) dropped into a 48-segment bowl",
    ),
    (
        "bowl_circles_1000",
        "A: 1000 circles (r 5) dropped into a 48-segment bowl",
    ),
    (
        "bowl_boxes_100",
        "A: 100 rounded 10x10 boxes dropped into the bowl",
    ),
    (
        "bowl_boxes_500",
        "A: 500 rounded 10x10 boxes dropped into the bowl",
    ),
    (
        "bowl_boxes_1000",
        "A: 1000 rounded 10x10 boxes dropped into the bowl",
    ),
    (
        "bowl_hexagons_100",
        "A: 100 rounded hexagons dropped into the bowl",
    ),
    (
        "bowl_hexagons_500",
        "A: 500 rounded hexagons dropped into the bowl",
    ),
    (
        "bowl_hexagons_1000",
        "A: 1000 rounded hexagons dropped into the bowl",
    ),
    (
        "bouncy_circles_500",
        "A: 500 elastic circles bouncing in the bowl, no gravity",
    ),
    (
        "no_collide",
        "A: 28 movers threading 825 static circles; must never touch each other",
    ),
    ("pyramid_20", "B: pyramid of 210 unit boxes"),
    (
        "pyramid_100",
        "B: pyramid of 5050 unit boxes (Box2D large_pyramid)",
    ),
    ("many_pyramids_4x4", "B: 4x4 grid of 55-box pyramids"),
    ("many_pyramids_10x10", "B: 10x10 grid of 55-box pyramids"),
    (
        "rain_1000",
        "B: 1000 circles raining in rows of 50 onto a 100 m ground",
    ),
    (
        "rain_4000",
        "B: 4000 circles raining in rows of 50 onto a 100 m ground",
    ),
    (
        "tumbler_500",
        "B: 500 boxes in a spinning kinematic tumbler",
    ),
    (
        "tumbler_2000",
        "B: 2000 boxes in a spinning kinematic tumbler",
    ),
    ("free_fall", "C: a ball falling from rest under gravity"),
    (
        "constant_force",
        "C: constant force (100, 0) on a 10 kg ball (SRS TC2)",
    ),
    (
        "projectile_45",
        "C: projectile launched at 45 degrees (SRS TC6)",
    ),
    (
        "projectile_60",
        "C: projectile launched at 60 degrees (SRS TC7)",
    ),
    (
        "spin",
        "C: torque 100 on a 100x100 box of mass 0.5 (SRS TC8/TC9)",
    ),
    (
        "elastic_pair",
        "C: equal balls head-on with e = 1 exchange velocities",
    ),
    (
        "newtons_cradle",
        "C: 5 nearly touching elastic balls; the last leaves with the first's speed",
    ),
    (
        "incline_slide",
        "C: box on a 30 degree slope, mu 0.2 < tan 30: slides",
    ),
    (
        "incline_stick",
        "C: box on a 30 degree slope, mu 0.8 > tan 30: stays",
    ),
    (
        "stack_10",
        "C: 10 stacked unit boxes; the top box must not drift",
    ),
];

/// Every built-in scene as `(name, one-line description)`, in section order.
pub fn list() -> &'static [(&'static str, &'static str)] {
    LIST
}

/// The built-in scene called `name` (see [`list`]), or `None`. The
/// description's `name` is the registry name.
pub fn builtin(name: &str) -> Option<SceneDesc> {
    let mut desc = match name {
        "bowl_circles_100" => terrain::bowl_circles(100),
        "bowl_circles_500" => terrain::bowl_circles(500),
        "bowl_circles_1000" => terrain::bowl_circles(1000),
        "bowl_boxes_100" => terrain::bowl_boxes(100),
        "bowl_boxes_500" => terrain::bowl_boxes(500),
        "bowl_boxes_1000" => terrain::bowl_boxes(1000),
        "bowl_hexagons_100" => terrain::bowl_hexagons(100),
        "bowl_hexagons_500" => terrain::bowl_hexagons(500),
        "bowl_hexagons_1000" => terrain::bowl_hexagons(1000),
        "bouncy_circles_500" => terrain::bouncy_circles(500),
        "no_collide" => terrain::no_collide(),
        "pyramid_20" => stacking::pyramid(20),
        "pyramid_100" => stacking::pyramid(100),
        "many_pyramids_4x4" => stacking::many_pyramids(4, 4),
        "many_pyramids_10x10" => stacking::many_pyramids(10, 10),
        "rain_1000" => stacking::rain(1000),
        "rain_4000" => stacking::rain(4000),
        "tumbler_500" => stacking::tumbler(500),
        "tumbler_2000" => stacking::tumbler(2000),
        "free_fall" => accuracy::free_fall(),
        "constant_force" => accuracy::constant_force(),
        "projectile_45" => accuracy::projectile(45)?,
        "projectile_60" => accuracy::projectile(60)?,
        "spin" => accuracy::spin(),
        "elastic_pair" => accuracy::elastic_pair(),
        "newtons_cradle" => accuracy::newtons_cradle(),
        "incline_slide" => accuracy::incline(30, real!(0.2)),
        "incline_stick" => accuracy::incline(30, real!(0.8)),
        "stack_10" => accuracy::stack(10),
        _ => return None,
    };
    name.clone_into(&mut desc.name);
    Some(desc)
}
