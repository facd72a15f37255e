//! Box2D v3's benchmark scenes (its `shared/benchmarks.c`, the release
//! sizes that `benchmark/main.c` runs), rebuilt number for number in SI
//! units: `box2d_large_pyramid`, `box2d_many_pyramids`, `box2d_tumbler`,
//! `box2d_smash` and `box2d_spinner` (section B) and `box2d_joint_grid`
//! (section D).
//!
//! Every number is Box2D's, built from integers, exact decimal literals and
//! the engine's own `Real` routines (`sin_cos`, `Real::PI`); where Box2D
//! accumulates a float position (`x += 0.4`), the position is computed
//! from the integer index with one rounding instead.
//!
//! Settings shared by all of them: gravity (0, −10) (`b2DefaultWorldDef`),
//! a step of 1/60 s (`benchmark/main.c`), Box2D's linear slop of 0.005 m as
//! the collision slop (the engine's default; the Chipmunk-mirror scenes
//! keep 0.1), the engine's ten iterations of one step, and Box2D's shape
//! defaults (`b2DefaultShapeDef`): friction 0.6, density 1, no bounce.
//! Scenes where Box2D calls `b2World_EnableSleeping(false)` run with
//! sleeping off; the others sleep as the engine does by default.
//!
//! What the engines do differently, and these scenes therefore do not
//! reproduce: Box2D's runner takes 4 sub-steps of its soft-step solver per
//! 1/60 s step (these scenes run the engine's own solver settings, as the
//! rest of section B does); a pair's friction is `√(f₁f₂)` in Box2D and
//! `f₁f₂` here, and its restitution `max(e₁, e₂)` in Box2D and `e₁e₂`
//! here (the shapes carry Box2D's per-shape values); Box2D's capsules are
//! segments with a rounding radius here (the same shape); Box2D's chain
//! loops are one-sided, these segments with neighbours are two-sided; and a
//! body cannot start asleep here (Box2D's smash starts its grid asleep).
use super::desc::{
    BodyDesc, BodyKind, GeometryDesc, Neighbors, SceneDesc, SettingsDesc, ShapeDesc,
};
use super::joints::{ConstraintDesc, JointType};
use super::stacking;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::ShapeFilter;
use tamias2d::space::{DEFAULT_COLLISION_SLOP, SLEEP_NEVER};

/// Box2D's default shape friction (`b2DefaultShapeDef`).
const FRICTION: Real = real!(0.6);

/// A scene with the settings of the module docs; `sleeping` false turns
/// sleeping off (`b2World_EnableSleeping(worldId, false)`).
fn scene(name: &str, steps: u32, sleeping: bool) -> SceneDesc {
    let mut settings = SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10);
    settings.collision_slop = DEFAULT_COLLISION_SLOP;
    if !sleeping {
        settings.sleep_time_threshold = SLEEP_NEVER;
    }
    SceneDesc {
        settings,
        ..SceneDesc::new(name, Real::ratio(1, 60), steps)
    }
}

/// `num / den` in one rounding (`i64` arguments, clamped into `i32`).
fn ratio(num: i64, den: i32) -> Real {
    Real::ratio(
        i32::try_from(num).unwrap_or(if num < 0 { i32::MIN } else { i32::MAX }),
        den,
    )
}

/// `box2d_large_pyramid` (`CreateLargePyramid`, 500 steps): a static
/// ground body at (0, −1) holding a 200 × 2 m box (`b2MakeBox(100, 1)`:
/// its top at y = 0), and a pyramid of `base` rows of unit boxes
/// (`b2MakeSquare(0.5)`, density 1, friction 0.6), row `i` holding
/// `base − i` boxes at y = i + 0.5, centred on x = 0 and touching. These
/// are the boxes of [`stacking::pyramid`]; only the ground differs (a box
/// instead of a segment). Sleeping off. `base(base+1)/2 + 1` bodies
/// (5,051 for Box2D's 100).
pub fn large_pyramid(base: u32) -> SceneDesc {
    let mut desc = scene("box2d_large_pyramid", 500, false);
    let ground = BodyDesc::new(BodyKind::Static, Vect::from_ints(0, -1))
        .labeled("ground")
        .with_shape(
            ShapeDesc::box_shape(Real::from_int(200), Real::TWO, Real::ZERO)
                .material(FRICTION, Real::ZERO),
        );
    desc.bodies.push(ground);
    stacking::pyramid_boxes(base, Real::ZERO, Real::ZERO, &mut desc.bodies);
    desc
}

/// `box2d_many_pyramids` (`CreateManyPyramids`, 200 steps): `rows ×
/// columns` pyramids of base 10 (55 unit boxes each, density 1, friction
/// 0.6). One static ground body holds one segment per row of pyramids, at
/// y = 11·row (`groundDeltaY = 2·0.5·(10 + 1)`), from x = −5.5·columns to
/// 5.5·columns (`groundWidth = 2·0.5·columns·11`). The base row of pyramid
/// `(row, column)` starts at x = −5.5·columns + 11·column + 1
/// (`CreateSmallPyramid`'s `centerX`, which is its leftmost box, not its
/// centre) and stands on its row's segment. Sleeping off.
/// `55·rows·columns + 1` bodies (22,001 for Box2D's 20 × 20).
// rows, columns ≤ 2^16 (asserted by the callers' sizes): every i64 term is
// below 2^24.
#[allow(clippy::arithmetic_side_effects)]
pub fn many_pyramids(rows: u32, columns: u32) -> SceneDesc {
    let mut desc = scene("box2d_many_pyramids", 200, false);
    let (rows, columns) = (
        i64::from(rows.min(1 << 16)),
        i64::from(columns.min(1 << 16)),
    );
    let half_width = ratio(11 * columns, 2);
    let mut ground = BodyDesc::static_body().labeled("ground");
    for row in 0..rows {
        let y = ratio(11 * row, 1);
        ground = ground.with_shape(
            ShapeDesc::segment(
                Vect::new(-half_width, y),
                Vect::new(half_width, y),
                Real::ZERO,
            )
            .material(FRICTION, Real::ZERO),
        );
    }
    desc.bodies.push(ground);
    for row in 0..rows {
        for column in 0..columns {
            // The leftmost box at −5.5·columns + 11·column + 1, so the
            // base of 10 is centred 4.5 m to its right.
            let cx = ratio(22 * column - 11 * columns + 11, 2);
            stacking::pyramid_boxes(10, cx, ratio(11 * row, 1), &mut desc.bodies);
        }
    }
    desc
}

/// `box2d_tumbler` (`CreateTumbler`, 750 steps): a shapeless static body
/// (labelled `ground`) and a dynamic hollow square (labelled `tumbler`) at
/// (0, 10) made of four boxes of density 50 and friction 0.6: 1 × 20 m at
/// (±10, 0) and 20 × 1 m at (0, ±10) (`b2MakeOffsetBox(0.5, 10, …)` and
/// `(10, 0.5, …)`), 4,000 kg. A revolute joint at (0, 10) is a pivot joint
/// plus a simple motor turning the tumbler counter-clockwise at
/// 25°/s = 5π/36 rad/s (`motorSpeed = (π/180)·25`) with at most 10⁸ N·m
/// (`maxMotorTorque = 1e8`). Inside, a `grid × grid` square of 0.25 m
/// boxes (`b2MakeBox(0.125, 0.125)`, density 1, friction 0.6), 0.4 m
/// apart, from (−0.2·grid, 10 − 0.2·grid) (row by row from the bottom).
/// Sleeping as the engine's default. `grid² + 2` bodies (2,027 for
/// Box2D's 45).
// grid ≤ 2^16: every i64 term is below 2^18.
#[allow(clippy::arithmetic_side_effects)]
pub fn tumbler(grid: u32) -> SceneDesc {
    let mut desc = scene("box2d_tumbler", 750, true);
    desc.bodies.push(BodyDesc::static_body().labeled("ground"));
    let wall = |w: i32, h: i32, x: i32, y: i32| {
        ShapeDesc::box_at(
            Real::from_int(w),
            Real::from_int(h),
            Real::ZERO,
            Vect::from_ints(x, y),
        )
        .material(FRICTION, Real::ZERO)
        .density(Real::from_int(50))
    };
    let tumbler = BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(0, 10))
        .labeled("tumbler")
        .with_shape(wall(1, 20, 10, 0))
        .with_shape(wall(1, 20, -10, 0))
        .with_shape(wall(20, 1, 0, 10))
        .with_shape(wall(20, 1, 0, -10));
    desc.bodies.push(tumbler);
    let mut pivot = ConstraintDesc::new(JointType::Pivot, 0, 1);
    pivot.anchor_a = Some(Vect::from_ints(0, 10));
    pivot.anchor_b = Some(Vect::ZERO);
    pivot.collide_bodies = Some(false);
    desc.constraints.push(pivot);
    // Box2D's motor speed is ω_b − ω_a; Chipmunk's rate is its opposite.
    let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
    motor.rate = Some(-Real::PI.mul_div(Real::from_int(5), Real::from_int(36)));
    motor.max_force = Some(Real::from_int(100_000_000));
    motor.collide_bodies = Some(false);
    desc.constraints.push(motor);
    let g = i64::from(grid.min(1 << 16));
    for i in 0..g {
        let y = Real::from_int(10) + ratio(2 * i - g, 5);
        for j in 0..g {
            let x = ratio(2 * j - g, 5);
            desc.bodies.push(
                BodyDesc::new(BodyKind::Dynamic, Vect::new(x, y)).with_shape(
                    ShapeDesc::box_shape(real!(0.25), real!(0.25), Real::ZERO)
                        .material(FRICTION, Real::ZERO)
                        .density(Real::ONE),
                ),
            );
        }
    }
    desc
}

/// `box2d_smash` (`CreateSmash`, 300 steps): no gravity; an 8 × 8 m box
/// (`b2MakeBox(4, 4)`, density 8, friction 0.6, labelled `smasher`) at
/// (−20, 0) moving at (40, 0) m/s hits a block of `columns × rows` 0.4 m
/// boxes (`b2MakeSquare(0.2)`, density 1, friction 0.6), touching edge to
/// edge, box `(i, j)` at x = 30 + 0.4·i, y = 0.4·(j − rows/2). Box2D starts
/// the block asleep (`isAwake = false`); here it starts awake, at rest.
/// `columns·rows + 1` bodies (9,601 for Box2D's 120 × 80).
// columns, rows ≤ 2^16: every i64 term is below 2^18.
#[allow(clippy::arithmetic_side_effects)]
pub fn smash(columns: u32, rows: u32) -> SceneDesc {
    let mut desc = scene("box2d_smash", 300, true);
    desc.settings.gravity = Vect::ZERO;
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(-20, 0))
            .moving(Vect::from_ints(40, 0))
            .labeled("smasher")
            .with_shape(
                ShapeDesc::box_shape(Real::from_int(8), Real::from_int(8), Real::ZERO)
                    .material(FRICTION, Real::ZERO)
                    .density(Real::from_int(8)),
            ),
    );
    let (columns, rows) = (
        i64::from(columns.min(1 << 16)),
        i64::from(rows.min(1 << 16)),
    );
    for i in 0..columns {
        let x = Real::from_int(30) + ratio(2 * i, 5);
        for j in 0..rows {
            let y = ratio(2 * j - rows, 5);
            desc.bodies.push(
                BodyDesc::new(BodyKind::Dynamic, Vect::new(x, y)).with_shape(
                    ShapeDesc::box_shape(real!(0.4), real!(0.4), Real::ZERO)
                        .material(FRICTION, Real::ZERO)
                        .density(Real::ONE),
                ),
            );
        }
    }
    desc
}

/// Vertices of the spinner's loop (`SPINNER_POINT_COUNT`).
const SPINNER_POINTS: i32 = 360;

/// `box2d_spinner` (`CreateSpinner`, 500 steps): a static body (labelled
/// `ground`) holding a closed loop of 360 segments (radius 0, friction
/// 0.1, each with its neighbours, as Box2D's chain loop): vertex `i` at
/// (40·cos θᵢ, 32 + 40·sin θᵢ) with θᵢ = −2π·i/360, clockwise. A dynamic
/// bar (labelled `spinner`: a 0.8 × 40 m box rounded by 0.2 m,
/// `b2MakeRoundedBox(0.4, 20, 0.2)`, density 1, friction 0) at (0, 12)
/// turns on a revolute joint there (a pivot joint and a simple motor at
/// +5 rad/s, counter-clockwise, torque unbounded as Box2D's `FLT_MAX`).
/// `count` bodies (density 0.25, friction 0.1, elasticity 0.1) start on a
/// grid 0.5 m apart, 92 to a row from x = −23 (x < 23) and from y = 2 up,
/// overlapping at first as in Box2D; body `i` is, by `i mod 3`, a capsule
/// (Box2D's `b2Capsule` from (−0.25, 0) to (0.25, 0), radius 0.25: here a
/// segment with that rounding radius), a circle of radius 0.35, or a
/// 0.7 m square (`b2MakeSquare(0.35)`). `count + 2` bodies (6,078 for
/// Box2D's 2 · 3038).
// count ≤ 2^24: every i64 term is below 2^25.
#[allow(clippy::arithmetic_side_effects)]
pub fn spinner(count: u32) -> SceneDesc {
    let mut desc = scene("box2d_spinner", 500, true);
    let radius = Real::from_int(40);
    let vertex = |i: i32| {
        let angle = Real::TAU.mul_div(
            Real::from_int(-i.rem_euclid(SPINNER_POINTS)),
            Real::from_int(SPINNER_POINTS),
        );
        let (s, c) = angle.sin_cos();
        Vect::new(c * radius, s * radius + Real::from_int(32))
    };
    let mut ground = BodyDesc::static_body().labeled("ground");
    for i in 0..SPINNER_POINTS {
        let geometry = GeometryDesc::Segment {
            a: vertex(i),
            b: vertex(i + 1),
            radius: Real::ZERO,
            neighbors: Some(Neighbors {
                prev: vertex(i - 1),
                next: vertex(i + 2),
            }),
        };
        ground = ground.with_shape(ShapeDesc::new(geometry).material(real!(0.1), Real::ZERO));
    }
    desc.bodies.push(ground);
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(0, 12))
            .labeled("spinner")
            .with_shape(
                ShapeDesc::box_shape(real!(0.8), Real::from_int(40), real!(0.2))
                    .material(Real::ZERO, Real::ZERO)
                    .density(Real::ONE),
            ),
    );
    let mut pivot = ConstraintDesc::new(JointType::Pivot, 0, 1);
    pivot.pivot = Some(Vect::from_ints(0, 12));
    pivot.collide_bodies = Some(false);
    desc.constraints.push(pivot);
    let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
    motor.rate = Some(Real::from_int(-5));
    motor.collide_bodies = Some(false);
    desc.constraints.push(motor);
    let quarter = real!(0.25);
    for i in 0..i64::from(count.min(1 << 24)) {
        let (column, row) = (i % 92, i / 92);
        let at = Vect::new(ratio(column - 46, 2), ratio(row + 4, 2));
        let shape = match i % 3 {
            0 => ShapeDesc::segment(
                Vect::new(-quarter, Real::ZERO),
                Vect::new(quarter, Real::ZERO),
                quarter,
            ),
            1 => ShapeDesc::circle(real!(0.35)),
            _ => ShapeDesc::box_shape(real!(0.7), real!(0.7), Real::ZERO),
        };
        desc.bodies.push(
            BodyDesc::new(BodyKind::Dynamic, at)
                .with_shape(shape.material(real!(0.1), real!(0.1)).density(quarter)),
        );
    }
    desc
}

/// `box2d_joint_grid` (`CreateJointGrid`, 500 steps): an `n × n` grid of
/// circles of radius 0.4 (density 1), body `(k, i)` at (k, −i), column by
/// column (`k` outer, `i` inner); the top bodies of the middle seven
/// columns (`n/2 − 3 ≤ k ≤ n/2 + 3`, `i = 0`) are static, the rest
/// dynamic. Each body is joined by a revolute joint (a pivot joint) to the
/// one above it (anchors (0, −0.5) on the upper, (0, 0.5) on the lower) and
/// to the one on its left (anchors (0.5, 0) on the left, (−0.5, 0) on the
/// right), as Box2D creates them, except the six joints between two static
/// bodies, which hold nothing. The circles are in category 2 and collide
/// only with other categories (Box2D's `categoryBits = 2`,
/// `maskBits = ~2`): none, so the grid hangs without contacts. Sleeping
/// off. `n²` bodies and `2n(n − 1) − 6` joints (10,000 and 19,794 for
/// Box2D's 100).
// n ≤ 2^15: every i64 term is below 2^31.
#[allow(clippy::arithmetic_side_effects)]
pub fn joint_grid(n: u32) -> SceneDesc {
    let mut desc = scene("box2d_joint_grid", 500, false);
    let n = i64::from(n.min(1 << 15));
    let filter = ShapeFilter {
        group: 0,
        categories: 2,
        mask: !2,
    };
    let is_static = |k: i64, i: i64| i == 0 && k >= n / 2 - 3 && k <= n / 2 + 3;
    let index = |k: i64, i: i64| u32::try_from(k * n + i).unwrap_or(u32::MAX);
    let half = Real::HALF;
    for k in 0..n {
        for i in 0..n {
            let at = Vect::new(ratio(k, 1), ratio(-i, 1));
            let mut shape = ShapeDesc::circle(real!(0.4)).material(FRICTION, Real::ZERO);
            shape.filter = filter;
            let body = if is_static(k, i) {
                BodyDesc::new(BodyKind::Static, at).with_shape(shape)
            } else {
                BodyDesc::new(BodyKind::Dynamic, at).with_shape(shape.density(Real::ONE))
            };
            desc.bodies.push(body);
            let mut join = |other: (i64, i64), anchor_a: Vect| {
                if is_static(other.0, other.1) && is_static(k, i) {
                    return;
                }
                let mut c =
                    ConstraintDesc::new(JointType::Pivot, index(other.0, other.1), index(k, i));
                c.anchor_a = Some(anchor_a);
                c.anchor_b = Some(-anchor_a);
                c.collide_bodies = Some(false);
                desc.constraints.push(c);
            };
            if i > 0 {
                join((k, i - 1), Vect::new(Real::ZERO, -half));
            }
            if k > 0 {
                join((k - 1, i), Vect::new(half, Real::ZERO));
            }
        }
    }
    desc
}
