//! Helpers shared by the extreme-scene tests (`tests/extremes/*.rs`) and by
//! the envelope report (`report.rs`, `envelope_report`): scene
//! transforms, a per-step watchdog, and the measurements whose results
//! `docs/numerics.md` quotes. The tests assert bounds on these
//! measurements; the report prints them.
//!
//! Scenes are built from integers and exact literals only; floats appear in
//! measurements (distances, speeds, energies), never in a scene.
#![allow(dead_code)] // each test file uses its own subset
#![allow(clippy::float_arithmetic)]

use tamias2d::body::BodyHandle;
use tamias2d::real;
use tamias2d::space::Space;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{
    self as scenes, BodyDesc, BodyKind, SceneDesc, SceneError, ScriptedWorld, SettingsDesc,
    ShapeDesc,
};

/// Chipmunk's default collision slop (m), used by every scene here unless
/// scaled.
pub const SLOP: Real = real!(0.1);
/// Friction of the stacking scenes (scenes/README.md section B).
pub const FRICTION: Real = real!(0.6);
/// `CONTACT_TOLERANCE` of the narrowphase (2^-20 m), as an `f64`.
pub const CONTACT_TOLERANCE: f64 = 1.0 / 1_048_576.0;

/// Builds a scene or fails the test with the scene's error.
pub fn build(desc: &SceneDesc) -> ScriptedWorld {
    desc.build()
        .unwrap_or_else(|e| panic!("{}: {e}", desc.name))
}

/// The integer `x` as a `Real` (exact for |x| < 2^31).
pub fn int(x: i64) -> Real {
    Real::from_bits(x.saturating_mul(1 << 32))
}

/// `(x, 0)` for an integer `x`.
pub fn x_vect(x: i64) -> Vect {
    Vect::new(int(x), Real::ZERO)
}

/// Length of `v` in metres, as an `f64` (for measurements only).
pub fn len(v: Vect) -> f64 {
    let (x, y) = v.to_f64();
    x.hypot(y)
}

/// The description with every body (initial and spawned) moved by `by`.
/// Shapes are in body coordinates, so this moves the whole scene exactly.
pub fn shifted(desc: &SceneDesc, by: Vect) -> SceneDesc {
    let mut out = desc.clone();
    let all = out
        .bodies
        .iter_mut()
        .chain(out.spawns.iter_mut().flat_map(|s| s.bodies.iter_mut()));
    for b in all {
        b.position += by;
    }
    out.name = format!("{} shifted by {by:?}", desc.name);
    out
}

// ---------------------------------------------------------------------------
// Watchdog: speed, per-step jumps, diagnostics.
// ---------------------------------------------------------------------------

/// Largest values seen over a run, checked after every step. A wrapped
/// coordinate would jump by about 2^32 m in one step and a sign flip by up
/// to 2^32 m, so `max_jump` catches both, as well as explosions.
#[derive(Clone, Debug, Default)]
pub struct Watch {
    prev: Vec<(BodyHandle, Vect)>,
    /// Steps observed.
    pub steps: u64,
    /// Largest linear speed of any body (m/s).
    pub max_speed: f64,
    /// Largest angular speed of any body (rad/s).
    pub max_spin: f64,
    /// Largest change of one body's position in one step (m).
    pub max_jump: f64,
    /// Largest `StepStats::saturated_bodies` of any step.
    pub saturated: u32,
    /// Sum of `StepStats::iteration_cap_hits` over the run.
    pub cap_hits: u64,
}

impl Watch {
    /// A watch that starts from the space's current positions.
    pub fn new(space: &Space) -> Watch {
        Watch {
            prev: positions(space),
            ..Watch::default()
        }
    }

    /// Records the step just taken.
    pub fn observe(&mut self, space: &Space) {
        self.steps += 1;
        let now = positions(space);
        for ((h0, p0), (h1, p1)) in self.prev.iter().zip(&now) {
            if h0 == h1 {
                self.max_jump = self.max_jump.max(len(*p1 - *p0));
            }
        }
        for (_, b) in space.bodies() {
            self.max_speed = self.max_speed.max(len(b.velocity()));
            self.max_spin = self.max_spin.max(b.angular_velocity().abs().to_f64());
        }
        let stats = space.last_step_stats();
        self.saturated = self.saturated.max(stats.saturated_bodies);
        self.cap_hits += u64::from(stats.iteration_cap_hits);
        self.prev = now;
    }

    /// Steps the scene `n` times, observing each step.
    pub fn run(scene: &mut ScriptedWorld, n: u32) -> Watch {
        let mut w = Watch::new(&scene.space);
        w.step(scene, n);
        w
    }

    /// Steps the scene `n` more times, observing each step.
    pub fn step(&mut self, scene: &mut ScriptedWorld, n: u32) {
        for _ in 0..n {
            scene
                .step()
                .unwrap_or_else(|e| panic!("step {}: {e}", self.steps + 1));
            self.observe(&scene.space);
        }
    }
}

/// Every body's origin position, in slot order.
pub fn positions(space: &Space) -> Vec<(BodyHandle, Vect)> {
    space.bodies().map(|(h, b)| (h, b.position())).collect()
}

/// Largest distance of any body from where it started (m).
pub fn worst_displacement(start: &[(BodyHandle, Vect)], space: &Space) -> f64 {
    start
        .iter()
        .filter_map(|(h, p)| space.body(*h).map(|b| len(b.position() - *p)))
        .fold(0.0, f64::max)
}

/// Steps `n` times and returns the largest displacement of any body from
/// its start seen after any step, with the watch of the run.
pub fn run_displacement(scene: &mut ScriptedWorld, n: u32) -> (f64, Watch) {
    let start = positions(&scene.space);
    let mut w = Watch::new(&scene.space);
    let mut worst = 0.0f64;
    for _ in 0..n {
        w.step(scene, 1);
        worst = worst.max(worst_displacement(&start, &scene.space));
    }
    (worst, w)
}

/// The deepest contact separation of the last step (0 if none; negative
/// means overlap).
pub fn deepest_contact(space: &Space) -> f64 {
    space
        .arbiters()
        .iter()
        .flat_map(|a| a.contacts().iter().map(|c| c.dist.to_f64()))
        .fold(0.0, f64::min)
}

// ---------------------------------------------------------------------------
// Translation.
// ---------------------------------------------------------------------------

/// Outcome of running a scene and its shifted copy side by side.
#[derive(Clone, Debug)]
pub struct ShiftOutcome {
    /// Bodies compared.
    pub bodies: usize,
    /// First step after which some body's state differed (after removing
    /// the shift), or `None` if every step matched bit for bit.
    pub first_mismatch: Option<u32>,
    /// Watch of the shifted run.
    pub watch: Watch,
}

/// Runs `desc` and `desc` shifted by `by` for `steps` steps and compares,
/// after every step, every body's origin and centre of gravity minus `by`,
/// velocity, angular velocity, angle and rotation, and every arbiter's
/// normal and contacts (relative offsets, separation, impulses), bit for bit.
pub fn compare_shifted(desc: &SceneDesc, by: Vect, steps: u32) -> ShiftOutcome {
    let mut a = build(desc);
    let mut b = build(&shifted(desc, by));
    let mut watch = Watch::new(&b.space);
    let mut first_mismatch = None;
    for i in 1..=steps {
        a.step()
            .unwrap_or_else(|e| panic!("reference step {i}: {e}"));
        b.step().unwrap_or_else(|e| panic!("shifted step {i}: {e}"));
        watch.observe(&b.space);
        if first_mismatch.is_none() && !same_up_to_shift(&a.space, &b.space, by) {
            first_mismatch = Some(i);
        }
    }
    ShiftOutcome {
        bodies: a.space.bodies().count(),
        first_mismatch,
        watch,
    }
}

fn same_up_to_shift(a: &Space, b: &Space, by: Vect) -> bool {
    let bodies_match = a.bodies().count() == b.bodies().count()
        && a.bodies().zip(b.bodies()).all(|((_, x), (_, y))| {
            x.position() == y.position() - by
                && x.center() == y.center() - by
                && x.velocity() == y.velocity()
                && x.angular_velocity() == y.angular_velocity()
                && x.angle() == y.angle()
                && x.rotation() == y.rotation()
        });
    let arbiters_match = a.arbiters().len() == b.arbiters().len()
        && a.arbiters()
            .iter()
            .zip(b.arbiters())
            .all(|(x, y)| x.normal() == y.normal() && x.contacts() == y.contacts());
    bodies_match && arbiters_match
}

// ---------------------------------------------------------------------------
// Stacks, scaling and mass ratios.
// ---------------------------------------------------------------------------

/// A dynamic square box of `side` with friction 0.6 and `density`.
pub fn box_body(position: Vect, side: Real, density: Real) -> BodyDesc {
    let shape = ShapeDesc::box_shape(side, side, Real::ZERO)
        .material(FRICTION, Real::ZERO)
        .density(density);
    BodyDesc::new(BodyKind::Dynamic, position).with_shape(shape)
}

/// `stack_{n}` (`scenes::accuracy::stack`) scaled by `k`: box sides, ground,
/// gravity and slop all multiplied by `k`, boxes of `density`, dt 1/60.
/// With `g·dt²/side` and `slop/side` unchanged the scene is *similar* to
/// `stack_{n}`: in exact arithmetic its positions are `k` times those of
/// the unit scene at every step, so any difference in box sizes comes from
/// rounding (and from the absolute contact tolerance, 2^-20 m).
pub fn scaled_stack(n: u32, k: Real, density: Real) -> SceneDesc {
    let mut d = SceneDesc::new(&format!("stack_{n} x{k}"), Real::ratio(1, 60), 600);
    d.settings = SettingsDesc::with_gravity(Vect::new(Real::ZERO, int(-10) * k), 10);
    d.settings.collision_slop = SLOP * k;
    let half = int(5) * k;
    let ground = ShapeDesc::segment(
        Vect::new(-half, Real::ZERO),
        Vect::new(half, Real::ZERO),
        Real::ZERO,
    )
    .material(FRICTION, Real::ZERO);
    d.bodies.push(BodyDesc::static_body().with_shape(ground));
    for i in 0..n {
        let y = (int(i64::from(i)) + Real::HALF) * k;
        d.bodies
            .push(box_body(Vect::new(Real::ZERO, y), k, density));
    }
    d
}

/// Runs the unit stack and the stack scaled by `k` side by side for `steps`
/// steps; returns the largest `|p_k / k − p_1|` over bodies and steps, in
/// box sizes, and the step where it occurred, with the block solver on or off. Errors if the scaled scene
/// cannot be built (e.g. a box too small to have a moment).
pub fn similarity_error(
    n: u32,
    k: Real,
    density: Real,
    steps: u32,
    block_solver: bool,
) -> Result<(f64, u32), SceneError> {
    // Sleeping off: the idle speed is absolute (m/s), so the two scales
    // would fall asleep at different steps; this compares the solver.
    let with_solver = |mut d: SceneDesc| {
        d.settings.block_solver = block_solver;
        d.settings.sleep_time_threshold = tamias2d::space::SLEEP_NEVER;
        d
    };
    let mut unit = build(&with_solver(scaled_stack(n, Real::ONE, Real::ONE)));
    let mut scaled = with_solver(scaled_stack(n, k, density)).build()?;
    let kf = k.to_f64();
    let (mut worst, mut at) = (0.0f64, 0);
    for i in 1..=steps {
        unit.step().unwrap_or_else(|e| panic!("unit step {i}: {e}"));
        scaled
            .step()
            .unwrap_or_else(|e| panic!("scaled step {i}: {e}"));
        for ((_, u), (_, s)) in unit.space.bodies().zip(scaled.space.bodies()) {
            let (ux, uy) = u.position().to_f64();
            let (sx, sy) = s.position().to_f64();
            let d = (sx / kf - ux).hypot(sy / kf - uy);
            if d > worst {
                (worst, at) = (d, i);
            }
        }
    }
    Ok((worst, at))
}

/// Two unit boxes on the `stack_0` ground: a box of density `bottom` with a
/// box of density `top` resting on it, `iterations` solver iterations.
pub fn mass_ratio_pair(bottom: i32, top: i32, iterations: u32) -> SceneDesc {
    let mut d = scenes::accuracy::stack(0);
    d.name = format!("density {bottom} under {top}, {iterations} iterations");
    d.settings.iterations = iterations;
    for (i, density) in [bottom, top].into_iter().enumerate() {
        let y = int(i as i64) + Real::HALF;
        d.bodies.push(box_body(
            Vect::new(Real::ZERO, y),
            Real::ONE,
            Real::from_int(density),
        ));
    }
    d
}

/// `stack_{n}` with another time step and iteration count.
pub fn stack_with_dt(n: u32, dt: Real, iterations: u32) -> SceneDesc {
    let mut d = scenes::accuracy::stack(n);
    d.dt = dt;
    d.settings.iterations = iterations;
    d
}

// ---------------------------------------------------------------------------
// Speed: tunnelling.
// ---------------------------------------------------------------------------

/// Radius of the tunnelling ball (m).
pub const BALL_RADIUS: Real = Real::HALF;

/// A ball of radius 0.5 at `(x0, 0)` moving at `(v, 0)` towards a static
/// wall at x = 0, no gravity, dt 1/60: a segment of radius 0 from (0, −10)
/// to (0, 10) (`thick == false`) or a 1 m × 20 m box centred on the origin.
pub fn tunnel_scene(v: Real, x0: Real, thick: bool) -> SceneDesc {
    let mut d = SceneDesc::new("tunnel", Real::ratio(1, 60), 0);
    d.settings = SettingsDesc::with_gravity(Vect::ZERO, 10);
    let wall = if thick {
        ShapeDesc::box_shape(Real::ONE, int(20), Real::ZERO)
    } else {
        ShapeDesc::segment(Vect::from_ints(0, -10), Vect::from_ints(0, 10), Real::ZERO)
    };
    d.bodies.push(BodyDesc::static_body().with_shape(wall));
    let ball = BodyDesc::new(BodyKind::Dynamic, Vect::new(x0, Real::ZERO))
        .moving(Vect::new(v, Real::ZERO))
        .with_shape(ShapeDesc::circle(BALL_RADIUS).density(Real::ONE));
    d.bodies.push(ball);
    d
}

/// True if the ball of [`tunnel_scene`] ends up beyond the wall, false if
/// it bounces back.
pub fn tunnels(v: Real, x0: Real, thick: bool) -> bool {
    let mut s = build(&tunnel_scene(v, x0, thick));
    let Some(&ball) = s.bodies().get(1) else {
        panic!("tunnel scene has a ball");
    };
    for _ in 0..10_000 {
        s.step().unwrap_or_else(|e| panic!("tunnel step: {e}"));
        let b = s.space.body(ball).unwrap_or_else(|| panic!("ball is gone"));
        if b.position().x > int(2) {
            return true;
        }
        if !b.velocity().x.is_positive() {
            return false;
        }
    }
    panic!("the ball neither passed nor bounced within 10^4 steps");
}

/// How many of `phases` evenly spaced start offsets let the ball through
/// when it travels `num/den` radii per step. Starting offsets cover one
/// step's travel, so every relative phase of the sampling is tried.
pub fn tunnel_count(num: i32, den: i32, thick: bool, phases: i32) -> i32 {
    let travel = BALL_RADIUS * Real::ratio(num, den);
    let v = travel * Real::from_int(60);
    (0..phases)
        .filter(|&k| {
            let x0 = int(-3) - travel * Real::ratio(k, phases);
            tunnels(v, x0, thick)
        })
        .count() as i32
}

// ---------------------------------------------------------------------------
// Many bodies at one point.
// ---------------------------------------------------------------------------

/// `n` unit-density bodies (circles of radius 0.5 or 1 m boxes) all at the
/// origin, at rest, no gravity, dt 1/60.
pub fn coincident(n: u32, boxes: bool) -> SceneDesc {
    let mut d = SceneDesc::new("coincident", Real::ratio(1, 60), 0);
    d.settings = SettingsDesc::with_gravity(Vect::ZERO, 10);
    for _ in 0..n {
        let shape = if boxes {
            ShapeDesc::box_shape(Real::ONE, Real::ONE, Real::ZERO)
        } else {
            ShapeDesc::circle(Real::HALF)
        };
        d.bodies.push(
            BodyDesc::new(BodyKind::Dynamic, Vect::ZERO).with_shape(shape.density(Real::ONE)),
        );
    }
    d
}

/// Runs a coincident scene for `steps` steps; returns the watch, the first
/// step after which no contact overlaps by more than the slop (plus the
/// contact tolerance), the deepest contact at the end, and the largest |x|
/// and |y| of any body at the end.
pub fn separate(scene: &mut ScriptedWorld, steps: u32) -> (Watch, Option<u32>, f64, f64, f64) {
    let mut w = Watch::new(&scene.space);
    let mut separated = None;
    let limit = -SLOP.to_f64() - CONTACT_TOLERANCE;
    for i in 1..=steps {
        w.step(scene, 1);
        if separated.is_none() && deepest_contact(&scene.space) >= limit {
            separated = Some(i);
        }
    }
    let (mut xmax, mut ymax) = (0.0f64, 0.0f64);
    for (_, b) in scene.space.bodies() {
        let (x, y) = b.position().to_f64();
        xmax = xmax.max(x.abs());
        ymax = ymax.max(y.abs());
    }
    (w, separated, deepest_contact(&scene.space), xmax, ymax)
}

// ---------------------------------------------------------------------------
// Diagnostics.
// ---------------------------------------------------------------------------

/// A ball of radius 0.5 at `p` moving at `v`, nothing else, no gravity.
pub fn lone_ball(p: Vect, v: Vect) -> ScriptedWorld {
    let mut d = SceneDesc::new("lone ball", Real::ratio(1, 60), 0);
    d.settings = SettingsDesc::with_gravity(Vect::ZERO, 10);
    d.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, p)
            .moving(v)
            .with_shape(ShapeDesc::circle(Real::HALF).density(Real::ONE)),
    );
    build(&d)
}

/// Steps `n` times; returns per step `(x, saturated_bodies)` of body 0.
pub fn trace_x(scene: &mut ScriptedWorld, n: u32) -> Vec<(Real, u32)> {
    let Some(&h) = scene.bodies().first() else {
        panic!("scene has a body");
    };
    (0..n)
        .map(|i| {
            scene.step().unwrap_or_else(|e| panic!("step {i}: {e}"));
            let x = scene.space.body(h).map_or(Real::ZERO, |b| b.position().x);
            (x, scene.space.last_step_stats().saturated_bodies)
        })
        .collect()
}
