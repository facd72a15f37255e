//! Section A of scenes/README.md: terrain scenes of the Chipmunk benchmark
//! class, in pixel-like units.
//!
//! Settings: gravity (0, −100), 10 solver iterations, collision slop 0.5,
//! Chipmunk's default bias, 1/60 s steps, 1000 steps. Everything is built
//! from integers, exact literals, [`Real::sin_cos`] and the seeded
//! [`SplitMix64`]; positions are drawn in body order (one rejection-sampled
//! disk point per body, then its velocity where the scene has one).
use super::desc::{BodyDesc, CounterDesc, SceneDesc, SettingsDesc, ShapeDesc};
use super::rng::{SplitMix64, SEED};
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::mass::{moment_for_box, moment_for_circle, moment_for_poly};

/// Vertices of the bowl loop.
const BOWL_VERTS: i32 = 48;
/// Friction of every terrain body in section A.
const FRICTION: Real = real!(0.9);
/// Radius of the spawn disk of the bowl scenes.
const SPAWN_RADIUS: i32 = 180;

/// Section A settings: gravity (0, −100), 10 iterations, slop 0.5.
fn settings(gravity: Vect) -> SettingsDesc {
    SettingsDesc {
        collision_slop: real!(0.5),
        ..SettingsDesc::with_gravity(gravity, 10)
    }
}

fn scene(name: String, gravity: Vect) -> SceneDesc {
    SceneDesc {
        settings: settings(gravity),
        ..SceneDesc::new(&name, Real::ratio(1, 60), 1000)
    }
}

/// `radius·(cos θ, sin θ)` for `θ = τ·num/den`, computed in `Real` (one
/// rounding for the angle, our deterministic `sin_cos`, one rounding per
/// product).
fn polar(radius: Real, num: i32, den: i32) -> Vect {
    let angle = Real::TAU.mul_div(Real::from_int(num), Real::from_int(den));
    let (s, c) = angle.sin_cos();
    Vect::new(c, s).mult(radius)
}

/// The bowl: one static body holding a closed loop of 48 segments (radius
/// 0); vertex `i` is at angle `2π·i/48` and radius `240 − 8·(i mod 3)`.
///
/// Decisions where scenes/README.md is silent: the segments have **no
/// neighbours** (Chipmunk's benchmark terrain has none; a closed jagged loop
/// has concave and convex joints, and neighbour filtering is meant for smooth
/// chains), and the terrain material is `(friction, elasticity)` as given.
// i in 0..BOWL_VERTS (48): `240 − 8·(i mod 3)` and `i + 1` are small.
#[allow(clippy::arithmetic_side_effects)]
pub fn bowl_terrain(friction: Real, elasticity: Real) -> BodyDesc {
    let vert = |i: i32| polar(Real::from_int(240 - 8 * (i % 3)), i, BOWL_VERTS);
    let mut ground = BodyDesc::static_body().labeled("ground");
    for i in 0..BOWL_VERTS {
        let (a, b) = (vert(i), vert((i + 1) % BOWL_VERTS));
        ground =
            ground.with_shape(ShapeDesc::segment(a, b, Real::ZERO).material(friction, elasticity));
    }
    ground
}

/// A bowl scene: the terrain (friction 1, so a contact's friction — the
/// product of the two shapes' — is the bodies' 0.9) and `n` bodies made by
/// `body`, each at a point drawn uniformly in the disk of radius 180.
fn bowl_scene(name: String, n: u32, body: impl Fn(Vect) -> BodyDesc) -> SceneDesc {
    let mut desc = scene(name, Vect::from_ints(0, -100));
    desc.bodies.push(bowl_terrain(Real::ONE, Real::ZERO));
    let mut rng = SplitMix64::new(SEED);
    for _ in 0..n {
        desc.bodies
            .push(body(rng.in_disk(Real::from_int(SPAWN_RADIUS))));
    }
    desc
}

/// `bowl_circles_{n}`: `n` circles of radius 5, mass 1, moment of a solid
/// disc (12.5), friction 0.9, elasticity 0, dropped into the bowl (spawn
/// points may overlap, as in Chipmunk's benchmark). `n + 1` bodies.
pub fn bowl_circles(n: u32) -> SceneDesc {
    let r = Real::from_int(5);
    let moment = moment_for_circle(Real::ONE, Real::ZERO, r, Vect::ZERO);
    bowl_scene(format!("bowl_circles_{n}"), n, |p| {
        BodyDesc::dynamic(p, Real::ONE, moment)
            .with_shape(ShapeDesc::circle(r).material(FRICTION, Real::ZERO))
    })
}

/// `bowl_boxes_{n}`: `n` 10×10 boxes made as an 8×8 box with rounding radius
/// 1, mass 1, moment of a 10×10 box (16.67), friction 0.9, elasticity 0.
/// `n + 1` bodies.
pub fn bowl_boxes(n: u32) -> SceneDesc {
    let moment = moment_for_box(Real::ONE, Real::from_int(10), Real::from_int(10));
    bowl_scene(format!("bowl_boxes_{n}"), n, |p| {
        let shape = ShapeDesc::box_shape(Real::from_int(8), Real::from_int(8), Real::ONE);
        BodyDesc::dynamic(p, Real::ONE, moment).with_shape(shape.material(FRICTION, Real::ZERO))
    })
}

/// The hexagon of the hexagon scenes: `4·(cos θk, sin θk)`, `θk = −2πk/6`
/// (clockwise, as in Chipmunk's benchmark; the shape keeps the convex hull,
/// which is counter-clockwise).
// k in 0..6: the negation is exact.
#[allow(clippy::arithmetic_side_effects)]
pub fn hexagon_verts() -> Vec<Vect> {
    (0..6).map(|k| polar(Real::from_int(4), -k, 6)).collect()
}

/// `bowl_hexagons_{n}`: `n` hexagons ([`hexagon_verts`]) with rounding radius
/// 1, mass 25, friction 0.9, elasticity 0. The moment is that of the core
/// polygon (`moment_for_poly` with radius 0, ≈ 166.7), as Chipmunk's
/// benchmark computes it. `n + 1` bodies.
pub fn bowl_hexagons(n: u32) -> SceneDesc {
    let verts = hexagon_verts();
    let mass = Real::from_int(25);
    let moment = moment_for_poly(mass, &verts, Vect::ZERO, Real::ZERO);
    bowl_scene(format!("bowl_hexagons_{n}"), n, |p| {
        let shape = ShapeDesc::poly(verts.clone(), Real::ONE);
        BodyDesc::dynamic(p, mass, moment).with_shape(shape.material(FRICTION, Real::ZERO))
    })
}

/// `bouncy_circles_{n}` (scenes/README.md lists `bouncy_circles_500`): no
/// gravity; the bowl terrain and circles (radius 5, mass 1, disc moment) all
/// with elasticity 1 and friction 0; each circle at a point uniform in the
/// disk of radius 130, then a velocity uniform in the disk of radius 50 (drawn
/// in that order per circle). `n + 1` bodies.
pub fn bouncy_circles(n: u32) -> SceneDesc {
    let mut desc = scene(format!("bouncy_circles_{n}"), Vect::ZERO);
    desc.bodies.push(bowl_terrain(Real::ZERO, Real::ONE));
    let r = Real::from_int(5);
    let moment = moment_for_circle(Real::ONE, Real::ZERO, r, Vect::ZERO);
    let mut rng = SplitMix64::new(SEED);
    for _ in 0..n {
        let p = rng.in_disk(Real::from_int(130));
        let v = rng.in_disk(Real::from_int(50));
        let shape = ShapeDesc::circle(r).material(Real::ZERO, Real::ONE);
        desc.bodies.push(
            BodyDesc::dynamic(p, Real::ONE, moment)
                .moving(v)
                .with_shape(shape),
        );
    }
    desc
}

/// Collision type of the moving circles of [`no_collide`].
pub const NO_COLLIDE_TYPE: u32 = 2;

/// `no_collide`: a broadphase test with no gravity. One static body holds 825
/// circles of radius 4.5 on a 20-unit grid (x = −320…320, y = −240…240) and 4
/// boundary segments at x = ±334.5, y = ±254.5 (elasticity 1). 12 circles
/// (radius 4.5, mass 7, disc moment, elasticity 1, collision type 2) start at
/// (−320, y), y = −230…210 step 40, moving at (100, 0); 16 more at (x, −240),
/// x = −290…310 step 40, moving at (0, 100). They run between the grid rows
/// and columns and never touch each other.
///
/// Decisions: the description carries a `begin` counter on the type pair
/// (2, 2) ([`ScriptedWorld::begin_count`](crate::ScriptedWorld::begin_count)); it counts and
/// accepts (Chipmunk's benchmark aborts instead), and must stay 0. Friction
/// is 0 everywhere (Chipmunk's default). 29 bodies, 857 shapes.
pub fn no_collide() -> SceneDesc {
    let mut desc = scene("no_collide".to_owned(), Vect::ZERO);
    let radius = real!(4.5);
    let (wx, wy) = (real!(334.5), real!(254.5));
    let corners = [
        Vect::new(-wx, -wy),
        Vect::new(wx, -wy),
        Vect::new(wx, wy),
        Vect::new(-wx, wy),
    ];
    let mut ground = BodyDesc::static_body().labeled("ground");
    for (i, a) in corners.iter().enumerate() {
        let b = corners
            .get(next_index(i, corners.len()))
            .copied()
            .unwrap_or(*a);
        ground = ground
            .with_shape(ShapeDesc::segment(*a, b, Real::ZERO).material(Real::ZERO, Real::ONE));
    }
    for x in (-320..=320).step_by(20) {
        for y in (-240..=240).step_by(20) {
            ground = ground.with_shape(ShapeDesc::circle_at(radius, Vect::from_ints(x, y)));
        }
    }
    desc.bodies.push(ground);
    let mass = Real::from_int(7);
    let moment = moment_for_circle(mass, Real::ZERO, radius, Vect::ZERO);
    let mover = |p: Vect, v: Vect| {
        let shape = ShapeDesc::circle(radius)
            .material(Real::ZERO, Real::ONE)
            .collision_type(NO_COLLIDE_TYPE);
        BodyDesc::dynamic(p, mass, moment)
            .moving(v)
            .with_shape(shape)
    };
    for y in (-230..=210).step_by(40) {
        desc.bodies
            .push(mover(Vect::from_ints(-320, y), Vect::from_ints(100, 0)));
    }
    for x in (-290..=310).step_by(40) {
        desc.bodies
            .push(mover(Vect::from_ints(x, -240), Vect::from_ints(0, 100)));
    }
    desc.begin_counters.push(CounterDesc {
        type_a: NO_COLLIDE_TYPE,
        type_b: NO_COLLIDE_TYPE,
    });
    desc
}

/// The index after `i` around a closed polygon of `n` vertices: `i + 1`, or
/// 0 after the last.
fn next_index(i: usize, n: usize) -> usize {
    match i.checked_add(1) {
        Some(j) if j < n => j,
        _ => 0,
    }
}

/// Segments per static body of a [`level`] (a level built in pieces, as a
/// game's level of tiles or rooms is).
pub const LEVEL_PIECE: u32 = 100;
/// Moving bodies of a [`level`] scene.
pub const LEVEL_MOVERS: i32 = 10;

/// `level_{n}` (registered: `level_300`, `level_30000`): a large static
/// level with a few bodies moving on it, the shape of a rollback game's
/// world (what the rollback budget measures: the level never moves, the
/// movers are the per-frame state).
///
/// An open chain of `n` segments (radius 0, friction 1, elasticity 0, no
/// neighbours) in static bodies of [`LEVEL_PIECE`] (100) consecutive
/// segments each (the last may hold fewer): vertex `i` (0 ≤ i ≤ n) at
/// `x = 4·i − 2·n`, `y = |(i mod 24) − 12| + (i mod 3)`, a bumpy ground of
/// 12-unit hills every 96 units with a 2-unit jag, `4·n` units long,
/// centred on x = 0. Ten bodies (mass 1, friction 0.9, elasticity 0),
/// body `k` at `(60·k − 270, 40)` moving at `(40 + 10·k, 0)`: even `k` a
/// circle of radius 5 (disc moment), odd `k` a 10×10 box made as an 8×8
/// box with rounding radius 1 (moment of a 10×10 box). They land within a
/// second and roll and tumble over the hills. Section A settings; `⌈n/100⌉`
/// static bodies and 10 dynamic ones; everything from integers. `None` for
/// `n` = 0 or above 1,000,000.
// n ≤ 1,000,000 and k < 10: every product and sum is small.
#[allow(clippy::arithmetic_side_effects)]
pub fn level(n: u32) -> Option<SceneDesc> {
    if n == 0 || n > 1_000_000 {
        return None;
    }
    let mut desc = scene(format!("level_{n}"), Vect::from_ints(0, -100));
    let half = 2 * n as i32;
    let vert = |i: i32| Vect::from_ints(4 * i - half, ((i % 24) - 12).abs() + i % 3);
    let mut piece = BodyDesc::static_body().labeled("level");
    for i in 0..n as i32 {
        let shape = ShapeDesc::segment(vert(i), vert(i + 1), Real::ZERO);
        piece = piece.with_shape(shape.material(Real::ONE, Real::ZERO));
        if piece.shapes.len() == LEVEL_PIECE as usize {
            desc.bodies.push(piece);
            piece = BodyDesc::static_body();
        }
    }
    if !piece.shapes.is_empty() {
        desc.bodies.push(piece);
    }
    let r = Real::from_int(5);
    let disc = moment_for_circle(Real::ONE, Real::ZERO, r, Vect::ZERO);
    let square = moment_for_box(Real::ONE, Real::from_int(10), Real::from_int(10));
    for k in 0..LEVEL_MOVERS {
        let p = Vect::from_ints(60 * k - 270, 40);
        let (shape, moment) = if k % 2 == 0 {
            (ShapeDesc::circle(r), disc)
        } else {
            let b = ShapeDesc::box_shape(Real::from_int(8), Real::from_int(8), Real::ONE);
            (b, square)
        };
        desc.bodies.push(
            BodyDesc::dynamic(p, Real::ONE, moment)
                .moving(Vect::from_ints(40 + 10 * k, 0))
                .with_shape(shape.material(FRICTION, Real::ZERO)),
        );
    }
    Some(desc)
}
