//! Section C of scenes/README.md: accuracy scenes with closed-form answers
//!, in SI units, 1/60 s steps, Chipmunk's
//! default iterations, slop and bias.
//!
//! # The discrete closed form
//! A step integrates positions with the previous velocities, then
//! velocities (Chipmunk's order; see `space/step.rs`). Under a constant
//! acceleration `a` (gravity plus `F/m`, re-applied every step), after `N`
//! steps of `dt` (`t = N·dt`):
//!
//! ```text
//! v_N = v_0 + a·t
//! p_N = p_0 + v_0·t + ½·a·t²·(1 − 1/N)      (= ½·a·dt²·N(N − 1))
//! ```
//!
//! so the position lags the continuous `½·a·t²` by exactly `½·a·dt·t`. The
//! same holds for angles under a constant torque (`α = τ/I`). Accuracy tests
//! compare with this form within a few ulp per step of rounding, and with
//! the continuous form within `½·|a|·dt·t`. Every body that a test looks at
//! has a label ([`ScriptedWorld::body`](crate::ScriptedWorld::body)).
//!
//! Bodies without a collision partner still get a shape (a circle or box of
//! the stated size) so the scene can be drawn and fed to other engines; their
//! mass and moment are explicit, so the shapes are massless.
use super::desc::{BodyDesc, ForceDesc, SceneDesc, SettingsDesc, ShapeDesc};
use super::stacking;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::mass::{moment_for_box, moment_for_circle};

/// Standard gravity used by the SI accuracy scenes.
pub const G: Real = real!(9.81);

fn scene(name: &str, gravity: Vect, steps: u32) -> SceneDesc {
    SceneDesc {
        settings: SettingsDesc::with_gravity(gravity, 10),
        ..SceneDesc::new(name, Real::ratio(1, 60), steps)
    }
}

/// A dynamic circle of `radius` and `mass` (disc moment) at `p`, moving at `v`.
fn ball(p: Vect, v: Vect, radius: Real, mass: Real) -> BodyDesc {
    let moment = moment_for_circle(mass, Real::ZERO, radius, Vect::ZERO);
    BodyDesc::dynamic(p, mass, moment)
        .moving(v)
        .with_shape(ShapeDesc::circle(radius))
}

/// The body with every shape made frictionless and perfectly elastic.
fn elastic(mut body: BodyDesc) -> BodyDesc {
    body.shapes = body
        .shapes
        .into_iter()
        .map(|s| s.material(Real::ZERO, Real::ONE))
        .collect();
    body
}

/// `free_fall`: a ball (radius 0.5, mass 1, labelled `ball`) released at
/// rest at (0, 100) under g = (0, −9.81); 240 steps (4 s, a 78.5 m drop).
/// Compare `p(t)`, `v(t)` with the discrete form of the module docs, and
/// with `½gt²` within `½·g·dt·t`.
pub fn free_fall() -> SceneDesc {
    let mut desc = scene("free_fall", Vect::new(Real::ZERO, -G), 240);
    let b = ball(Vect::from_ints(0, 100), Vect::ZERO, Real::HALF, Real::ONE);
    desc.bodies.push(b.labeled("ball"));
    desc
}

/// `constant_force`: a ball (radius 1, mass 10, labelled
/// `ball`) at rest at (20, 20), no gravity, force F = (100, 0) applied before
/// every step; 240 steps (4 s, the span of TC2's table). Expect
/// `p(t) = p0 + ½(F/m)t²` up to the discrete lag: x(4 s) = 100 − 1/3 m.
pub fn constant_force() -> SceneDesc {
    let mut desc = scene("constant_force", Vect::ZERO, 240);
    let b = ball(
        Vect::from_ints(20, 20),
        Vect::ZERO,
        Real::ONE,
        Real::from_int(10),
    );
    desc.bodies.push(b.labeled("ball"));
    desc.forces.push(ForceDesc {
        body: 0,
        force: Vect::from_ints(100, 0),
        torque: Real::ZERO,
    });
    desc
}

/// `projectile_45` / `projectile_60`: a ball (radius
/// 1, labelled `ball`) launched under gravity; 600 steps (10 s, past the apex
/// of both). `None` for other angles.
///
/// Inputs, exact decimals (see `scenes/README.md`):
/// * 45°: p0 = (0, 0), v0 = (848.5, 848.5) (≈ 1200·(cos 45°, sin 45°); equal
///   components make the angle exactly 45°), m = 10, g = (0, −100).
/// * 60°: p0 = (50, 50), v0 = (150, 260) (≈ 300 m/s at 60.02°), m = 1000,
///   g = (0, −40).
///
/// Expect `x(t) = x0 + vx·t` exactly up to rounding, and `y(t)` the
/// discrete form of the module docs.
pub fn projectile(angle_deg: u32) -> Option<SceneDesc> {
    let (p0, v0, mass, g) = match angle_deg {
        45 => (Vect::ZERO, Vect::new(real!(848.5), real!(848.5)), 10, -100),
        60 => (
            Vect::from_ints(50, 50),
            Vect::from_ints(150, 260),
            1000,
            -40,
        ),
        _ => return None,
    };
    let mut desc = scene(
        &format!("projectile_{angle_deg}"),
        Vect::from_ints(0, g),
        600,
    );
    desc.bodies
        .push(ball(p0, v0, Real::ONE, Real::from_int(mass)).labeled("ball"));
    Some(desc)
}

/// `spin`: a 100 × 100 box (labelled `box`) of mass 0.5
/// and moment `0.5·(100² + 100²)/12 = 833.33…`, at rest at the origin, no
/// gravity, torque τ = 100 applied before every step; 600 steps (10 s).
/// Expect `ω(t) = τt/I` and `φ(t) = ½τt²/I` up to the discrete lag
/// (ω(10 s) = 1.2 rad/s, φ(10 s) ≈ 6 rad).
pub fn spin() -> SceneDesc {
    let mut desc = scene("spin", Vect::ZERO, 600);
    let (mass, side) = (Real::HALF, Real::from_int(100));
    let body = BodyDesc::dynamic(Vect::ZERO, mass, moment_for_box(mass, side, side))
        .with_shape(ShapeDesc::box_shape(side, side, Real::ZERO));
    desc.bodies.push(body.labeled("box"));
    desc.forces.push(ForceDesc {
        body: 0,
        force: Vect::ZERO,
        torque: Real::from_int(100),
    });
    desc
}

/// `elastic_pair`: two balls of radius 1 and mass 1 (labelled `a` and `b`),
/// elasticity 1, friction 0, no gravity, head-on along the x axis: `a` at
/// (−5, 0) moving at (3, 0), `b` at (5, 0) moving at (−1, 0). They meet
/// after 2 s; 240 steps (4 s). Expect the velocities exchanged
/// (`a`: (−1, 0), `b`: (3, 0)), momentum 2 and kinetic energy 5 conserved.
/// Unequal speeds make an exchange distinguishable from a pass-through.
pub fn elastic_pair() -> SceneDesc {
    let mut desc = scene("elastic_pair", Vect::ZERO, 240);
    let a = ball(
        Vect::from_ints(-5, 0),
        Vect::from_ints(3, 0),
        Real::ONE,
        Real::ONE,
    );
    let b = ball(
        Vect::from_ints(5, 0),
        Vect::from_ints(-1, 0),
        Real::ONE,
        Real::ONE,
    );
    desc.bodies.push(elastic(a).labeled("a"));
    desc.bodies.push(elastic(b).labeled("b"));
    desc
}

/// Gap between neighbouring balls of [`newtons_cradle`] (m).
const CRADLE_GAP: Real = real!(0.01);

/// `newtons_cradle`: 5 balls of radius 1 and mass 1 (labelled `ball0` …
/// `ball4`), elasticity 1, friction 0, no gravity, in a row along the x axis
/// with centres 2.01 m apart; `ball0` moves at (2, 0), the others are at
/// rest. 120 steps (2 s). Expect `ball4` to leave at (2, 0) and the others
/// at rest, with momentum and energy conserved.
///
/// Decision: the balls are *nearly* touching, 1 cm apart, not touching as
/// scenes/README.md says. Our circle test counts exactly touching circles as
/// colliding (distance ≤ r₁ + r₂), so with touching balls all four contacts
/// are solved together and a sequential-impulse solver hands the striker's
/// momentum to the whole row at once (measured: the striker bounced back at
/// −1.18 m/s and the other four left together at 0.80 m/s, momentum
/// conserved, energy not). With gaps smaller than one step's travel
/// (2/60 m), each pair collides on its own step and the velocity is passed
/// down the row, as in a real cradle.
pub fn newtons_cradle() -> SceneDesc {
    let mut desc = scene("newtons_cradle", Vect::ZERO, 120);
    let pitch = Real::TWO + CRADLE_GAP;
    for i in 0..5 {
        let v = if i == 0 {
            Vect::from_ints(2, 0)
        } else {
            Vect::ZERO
        };
        let p = Vect::new(pitch * Real::from_int(i), Real::ZERO);
        let b = ball(p, v, Real::ONE, Real::ONE);
        desc.bodies.push(elastic(b).labeled(&format!("ball{i}")));
    }
    desc
}

/// `incline_{theta_deg}_{mu}`: a unit box (mass 1, moment 1/6, labelled
/// `box`) resting on a static slope at `theta_deg` degrees with friction
/// `mu`, under g = (0, −9.81); 180 steps (3 s).
///
/// Decisions on the construction: θ = π·theta_deg/180 in `Real` and its
/// sine and cosine from [`Real::sin_cos`]. The slope is one static segment
/// (labelled `slope`, radius 0, friction 1, elasticity 0) from the origin
/// to `100·(cos θ, sin θ)`; the box is rotated by θ with its bottom face on
/// the slope, centred 80 m up it (`80·(cos θ, sin θ) + 0.5·(−sin θ, cos θ)`),
/// at rest. Contacts multiply the two frictions, so the slope's 1 makes the
/// pair's friction exactly `mu`. Expect, along the slope, an acceleration of
/// `g(sin θ − μ cos θ)` down it when `μ < tan θ`, and no motion when
/// `μ > tan θ`. The registry has `incline_slide` (30°, μ = 0.2) and
/// `incline_stick` (30°, μ = 0.8); tan 30° ≈ 0.577.
pub fn incline(theta_deg: i32, mu: Real) -> SceneDesc {
    let mut desc = scene(
        &format!("incline_{theta_deg}_{mu}"),
        Vect::new(Real::ZERO, -G),
        180,
    );
    let theta = Real::PI.mul_div(Real::from_int(theta_deg), Real::from_int(180));
    let (s, c) = theta.sin_cos();
    let (along, normal) = (Vect::new(c, s), Vect::new(-s, c));
    let slope = ShapeDesc::segment(Vect::ZERO, along.mult(Real::from_int(100)), Real::ZERO)
        .material(Real::ONE, Real::ZERO);
    desc.bodies
        .push(BodyDesc::static_body().labeled("slope").with_shape(slope));
    let position = along.mult(Real::from_int(80)) + normal.mult(Real::HALF);
    let shape = ShapeDesc::box_shape(Real::ONE, Real::ONE, Real::ZERO).material(mu, Real::ZERO);
    let mut block = BodyDesc::dynamic(
        position,
        Real::ONE,
        moment_for_box(Real::ONE, Real::ONE, Real::ONE),
    )
    .labeled("box")
    .with_shape(shape);
    block.angle = theta;
    desc.bodies.push(block);
    desc
}

/// `stack_{n}`: `n` unit boxes stacked at x = 0 (box `i` centred at
/// y = 0.5 + i) on a static ground segment from (−5, 0) to (5, 0), with the
/// section B materials (friction 0.6, density 1, elasticity 0) and gravity
/// (0, −10); 600 steps (10 s). The top box is labelled `top`: its drift from
/// x = 0 after 10 s is the measured quantity. `n + 1` bodies.
pub fn stack(n: u32) -> SceneDesc {
    let mut desc = stacking::scene(format!("stack_{n}"));
    desc.steps = 600;
    let five = Real::from_int(5);
    let ground = BodyDesc::static_body()
        .labeled("ground")
        .with_shape(stacking::ground_segment(-five, five, Real::ZERO));
    desc.bodies.push(ground);
    for i in 0..n {
        let y = Real::from_int(i32::try_from(i).unwrap_or(i32::MAX)) + Real::HALF;
        desc.bodies
            .push(stacking::box_body(Vect::new(Real::ZERO, y), Real::ONE));
    }
    if n > 0 {
        if let Some(top) = desc.bodies.last_mut() {
            top.label = Some("top".to_owned());
        }
    }
    desc
}

/// `sleep_wake`: two columns of five unit boxes, 20 m apart on one ground
/// (labels `left_top`, `right_top`), and two resting 200 kg balls 1.5 m
/// outside them (`player_left`, `player_right`: the GGRS game's players),
/// fall asleep (about 1 s: the default
/// 0.5 s of rest after they settle); at step 180 a 1 kg ball (label `ball`)
/// appears 4 m above the left column, falls onto it and wakes that island
/// only, which settles and falls asleep again. 480 steps. The scene of the
/// sleep tests and of the GGRS SyncTest across sleep and wake.
pub fn sleep_wake() -> SceneDesc {
    let mut desc = stacking::scene("sleep_wake".to_owned());
    desc.steps = 480;
    let twenty = Real::from_int(20);
    let ground = BodyDesc::static_body()
        .labeled("ground")
        .with_shape(stacking::ground_segment(-twenty, twenty, Real::ZERO));
    desc.bodies.push(ground);
    // The first two dynamic bodies are the players of the GGRS game
    // (`Game::with_scene`): 200 kg balls (heavy enough that the game's
    // jump impulses do not lift them off for good) 1.5 m beside the
    // columns, at rest in a plain run; pushed by the scripted buttons they
    // roll into the columns, which then wake and fall asleep again.
    for (x, side) in [(-12, "left"), (12, "right")] {
        let player = ball(
            Vect::new(Real::from_int(x), Real::HALF),
            Vect::ZERO,
            Real::HALF,
            Real::from_int(200),
        )
        .labeled(&format!("player_{side}"));
        desc.bodies.push(player);
    }
    for (x, side) in [(-10, "left"), (10, "right")] {
        for i in 0..5 {
            let p = Vect::new(Real::from_int(x), Real::from_int(i) + Real::HALF);
            let mut b = stacking::box_body(p, Real::ONE);
            if i == 4 {
                b.label = Some(format!("{side}_top"));
            }
            desc.bodies.push(b);
        }
    }
    let ball = ball(
        Vect::from_ints(-10, 9),
        Vect::ZERO,
        Real::lit("0.3"),
        Real::ONE,
    )
    .labeled("ball");
    desc.spawns.push(super::desc::SpawnDesc {
        at_step: 180,
        bodies: vec![ball],
    });
    desc
}
