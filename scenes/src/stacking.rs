//! Section B of scenes/README.md: stacking scenes of the Box2D benchmark
//! class, in SI units.
//!
//! Settings: gravity (0, −10), 1/60 s, Chipmunk's default iterations (10),
//! slop (0.1) and bias; every shape has friction 0.6 and elasticity 0, and
//! dynamic shapes density 1 (mass and moment summed from the shapes). Our
//! contacts multiply the two frictions (Chipmunk), so box–box and box–ground
//! pairs have friction 0.36; Box2D's `sqrt(f₁f₂)` gives 0.6. Default run:
//! 1000 steps.
use super::desc::{
    BodyDesc, BodyKind, GeometryDesc, Neighbors, SceneDesc, SettingsDesc, ShapeDesc, SpawnDesc,
};
use super::rng::{SplitMix64, SEED};
use tamias2d::math::{Real, Vect};
use tamias2d::real;

/// Friction of every shape in section B.
const FRICTION: Real = real!(0.6);
/// Density of every dynamic shape in section B.
const DENSITY: Real = Real::ONE;

pub(super) fn scene(name: String) -> SceneDesc {
    SceneDesc {
        settings: SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10),
        ..SceneDesc::new(&name, Real::ratio(1, 60), 1000)
    }
}

/// `k / 2` exactly (saturating far outside any scene's range).
fn halves(k: i64) -> Real {
    Real::from_bits(k.saturating_mul(1 << 31))
}

/// A dynamic box of `side` with density 1 and friction 0.6.
pub(super) fn box_body(position: Vect, side: Real) -> BodyDesc {
    let shape = ShapeDesc::box_shape(side, side, Real::ZERO)
        .material(FRICTION, Real::ZERO)
        .density(DENSITY);
    BodyDesc::new(BodyKind::Dynamic, position).with_shape(shape)
}

/// A static segment from `(x0, y)` to `(x1, y)` with friction 0.6.
pub(super) fn ground_segment(x0: Real, x1: Real, y: Real) -> ShapeDesc {
    ShapeDesc::segment(Vect::new(x0, y), Vect::new(x1, y), Real::ZERO)
        .material(FRICTION, Real::ZERO)
}

/// The boxes of a pyramid with `base` boxes of side 1 whose base is centred
/// on `(cx, y0)`: row `i` holds `base − i` boxes, box `j` centred at
/// `x = cx + (2j − (base − 1 − i))·0.5`, `y = y0 + 0.5 + i`. Bottom row
/// first, left to right.
// base < 2^32 and 0 ≤ j < base − i ≤ base: every i64 term is below 2^34.
#[allow(clippy::arithmetic_side_effects)]
pub(crate) fn pyramid_boxes(base: u32, cx: Real, y0: Real, out: &mut Vec<BodyDesc>) {
    let base = i64::from(base);
    for i in 0..base {
        for j in 0..base - i {
            let x = cx + halves(2 * j - (base - 1 - i));
            let y = y0 + halves(2 * i + 1);
            out.push(box_body(Vect::new(x, y), Real::ONE));
        }
    }
}

/// `pyramid_{n}`: a static ground segment at y = 0 from x = −n to n (twice
/// the base), and a pyramid of `n(n+1)/2` unit boxes centred on x = 0, each
/// box touching its neighbours. The top box is labelled `top`.
/// `n(n+1)/2 + 1` bodies (`pyramid_100`: 5,051).
pub fn pyramid(n: u32) -> SceneDesc {
    let mut desc = scene(format!("pyramid_{n}"));
    // n < 2^32: the product is below 2^33, never saturates.
    let half_width = halves(i64::from(n).saturating_mul(2));
    let ground = BodyDesc::static_body()
        .labeled("ground")
        .with_shape(ground_segment(-half_width, half_width, Real::ZERO));
    desc.bodies.push(ground);
    pyramid_boxes(n, Real::ZERO, Real::ZERO, &mut desc.bodies);
    if n > 0 {
        if let Some(top) = desc.bodies.last_mut() {
            top.label = Some("top".to_owned());
        }
    }
    desc
}

/// Base of each pyramid of [`many_pyramids`].
const SMALL_BASE: u32 = 10;
/// Distance between neighbouring pyramids, in both directions (m).
const PYRAMID_SPACING: i64 = 12;

/// `many_pyramids_{nx}x{ny}`: `nx × ny` pyramids of base 10 (55 boxes each),
/// 12 m apart in x and in y, all on one static ground body.
///
/// Decisions: "a grid on one ground" is read as Box2D's `many_pyramids`:
/// the ground body holds one segment per grid row, at y = 12·row, from
/// x = −6(nx + 1) to 6(nx + 1) (7 m beyond the outer boxes); pyramid `(col, row)` has its base
/// centred at x = 12·col − 6·(nx − 1), so the grid is centred on x = 0. A
/// pyramid is 10 m tall, leaving 2 m below the next row's ground.
/// `55·nx·ny + 1` bodies.
// nx, ny < 2^32 and s = 12: every i64 term is below 24·2^32 < 2^37.
#[allow(clippy::arithmetic_side_effects)]
pub fn many_pyramids(nx: u32, ny: u32) -> SceneDesc {
    let mut desc = scene(format!("many_pyramids_{nx}x{ny}"));
    let s = PYRAMID_SPACING;
    let half_span = halves(s * (i64::from(nx) + 1));
    let mut ground = BodyDesc::static_body().labeled("ground");
    for row in 0..i64::from(ny) {
        ground = ground.with_shape(ground_segment(-half_span, half_span, halves(2 * s * row)));
    }
    desc.bodies.push(ground);
    for row in 0..i64::from(ny) {
        for col in 0..i64::from(nx) {
            let cx = halves(2 * s * col - s * (i64::from(nx) - 1));
            pyramid_boxes(SMALL_BASE, cx, halves(2 * s * row), &mut desc.bodies);
        }
    }
    desc
}

/// Circles released per row of [`rain`].
pub const RAIN_ROW: u32 = 50;
/// Steps between two rows of [`rain`].
pub const RAIN_INTERVAL: u32 = 10;

/// Rounding radius of the rain container's segments (m): thick enough that
/// no circle tunnels through (see [`rain`]).
const RAIN_WALL_RADIUS: Real = Real::ONE;
/// Height at which rain rows are released (m).
const RAIN_HEIGHT: i32 = 30;
/// Height of the rain container's walls (m).
const RAIN_WALL_HEIGHT: i32 = 35;

/// `rain_{n}`: circles of radius uniform in [0.25, 0.5) released in rows of
/// 50 every 10 steps above a ground 100 m wide, until `n` circles exist.
///
/// Decisions where scenes/README.md is silent:
/// * ground: one static body with 10 segments of 10 m, chained with
///   neighbours (smooth: no catching on seams; the end segments use their
///   straight continuation), plus two walls, so the pile (≈ 22 m deep for
///   4000 circles) stays on the ground instead of pouring off the ends;
/// * the segments are capsules of radius 1 whose surfaces are the box
///   x ∈ [−50, 50], y ≥ 0 (cores at y = −1 and x = ±51; walls up to
///   y = 35). A circle dropped from 30 m hits the ground at ≈ 26 m/s, 0.44 m
///   per step, more than the smallest radius: with zero-radius segments,
///   circles tunnelled through the ground (measured: 2 of `rain_1000`). A
///   circle's centre would have to move 1.25 m in a step to cross a core;
/// * row `k` appears after `10k` steps (row 0 when the scene is built), as
///   [`SpawnDesc`]s, so the description lists every circle;
/// * circle `j` of a row is at x = −49 + 2j + jitter, jitter uniform in
///   [−0.25, 0.25), y = 30, with velocity (0, −10): released from rest, a
///   row falls only 0.14 m in 10 steps and the next row would overlap it;
///   at 10 m/s it has cleared the 1 m of a diameter. PRNG draws per circle:
///   radius, then jitter;
/// * circles: density 1, friction 0.6, elasticity 0.
///
/// `n + 1` bodies once all rows are out (51 right after building).
pub fn rain(n: u32) -> SceneDesc {
    let mut desc = scene(format!("rain_{n}"));
    desc.bodies.push(rain_container());
    let mut rng = SplitMix64::new(SEED);
    let (quarter, half) = (real!(0.25), Real::HALF);
    let mut released = 0u32;
    let mut row = 0u32;
    while released < n {
        // released < n (loop condition): never saturates.
        let count = RAIN_ROW.min(n.saturating_sub(released));
        let mut bodies = Vec::with_capacity(count as usize);
        for j in 0..count {
            let radius = rng.range(quarter, half);
            let jitter = rng.range(-quarter, quarter);
            // j < RAIN_ROW: the product never saturates.
            let x = Real::from_int(-49) + halves(i64::from(j).saturating_mul(4)) + jitter;
            let shape = ShapeDesc::circle(radius)
                .material(FRICTION, Real::ZERO)
                .density(DENSITY);
            let body = BodyDesc::new(BodyKind::Dynamic, Vect::new(x, Real::from_int(RAIN_HEIGHT)))
                .moving(Vect::from_ints(0, -10))
                .with_shape(shape);
            bodies.push(body);
        }
        desc.spawns.push(SpawnDesc {
            at_step: row.saturating_mul(RAIN_INTERVAL),
            bodies,
        });
        // released + count ≤ n, and row ≤ n / RAIN_ROW + 1: never saturate.
        released = released.saturating_add(count);
        row = row.saturating_add(1);
    }
    desc
}

/// The static ground and walls of [`rain`].
// Small literals only: k in −1..=11 and side = ±1, every term below 100.
#[allow(clippy::arithmetic_side_effects)]
fn rain_container() -> BodyDesc {
    let r = RAIN_WALL_RADIUS;
    let seg_x = |k: i32| Real::from_int(-50 + 10 * k);
    let at = |k: i32| Vect::new(seg_x(k), -r);
    let mut ground = BodyDesc::static_body().labeled("ground");
    for k in 0..10 {
        let geometry = GeometryDesc::Segment {
            a: at(k),
            b: at(k + 1),
            radius: r,
            neighbors: Some(Neighbors {
                prev: at(k - 1),
                next: at(k + 2),
            }),
        };
        ground = ground.with_shape(ShapeDesc::new(geometry).material(FRICTION, Real::ZERO));
    }
    for side in [-1, 1] {
        let x = Real::from_int(50 * side) + r * Real::from_int(side);
        let (a, b) = (
            Vect::new(x, -r),
            Vect::new(x, Real::from_int(RAIN_WALL_HEIGHT)),
        );
        ground = ground.with_shape(ShapeDesc::segment(a, b, r).material(FRICTION, Real::ZERO));
    }
    ground
}

/// Angular velocity of the tumbler (rad/s).
const TUMBLER_SPIN: Real = real!(0.25);
/// Largest box side of [`tumbler`] (scenes/README.md).
const TUMBLER_BOX: Real = Real::HALF;
/// Room the grid of boxes may use inside the tumbler: the 19 m interior less
/// 0.5 m at each side.
const TUMBLER_ROOM: Real = Real::from_int(18);

/// Side of the boxes of [`tumbler`] and the side of their square grid.
pub fn tumbler_box_side(n: u32) -> (Real, u32) {
    let mut k = n.isqrt();
    if k.saturating_mul(k) < n {
        // k = ⌊√n⌋ < 2^16: never saturates.
        k = k.saturating_add(1);
    }
    let extent = |side: Real| {
        // (k − 1) pitches of 1.25·side plus one box.
        Real::from_int(i32::try_from(k.saturating_sub(1)).unwrap_or(i32::MAX)) * side * real!(1.25)
            + side
    };
    let mut side = TUMBLER_BOX;
    while side.is_positive() && extent(side) > TUMBLER_ROOM {
        side *= Real::HALF;
    }
    (side, k)
}

/// `tumbler_{n}`: a kinematic hollow square spinning at 0.25 rad/s about
/// (0, 10), filled with `n` boxes (density 1, friction 0.6).
///
/// Decisions where scenes/README.md is silent or cannot be met:
/// * walls as in Box2D's tumbler: four 1 m thick boxes on one kinematic body
///   (labelled `tumbler`) centred 10 m from its centre (20 m wide measured
///   at the wall centres, 19 m inside), friction 0.6;
/// * fill: the boxes start at rest in a square grid of `k = ⌈√n⌉` columns,
///   pitch 1.25 × side, centred on the tumbler, filled row by row from the
///   bottom (the last row may be partial), and fall inside it;
/// * box side: 0.5 m as scenes/README.md says **while the grid fits** (up to
///   n = 841). 2000 boxes of 0.5 m cover 500 m², more than the 361 m²
///   interior, so the side is halved until the grid fits: `tumbler_2000` uses
///   0.25 m boxes (Box2D's tumbler size). See [`tumbler_box_side`].
///
/// `n + 1` bodies; no ground.
pub fn tumbler(n: u32) -> SceneDesc {
    let mut desc = scene(format!("tumbler_{n}"));
    let center = Vect::from_ints(0, 10);
    let mut tumbler = BodyDesc::new(BodyKind::Kinematic, center).labeled("tumbler");
    tumbler.angular_velocity = TUMBLER_SPIN;
    let walls = [
        ((1, 20), (10, 0)),
        ((1, 20), (-10, 0)),
        ((20, 1), (0, 10)),
        ((20, 1), (0, -10)),
    ];
    for ((w, h), (x, y)) in walls {
        let wall = ShapeDesc::box_at(
            Real::from_int(w),
            Real::from_int(h),
            Real::ZERO,
            Vect::from_ints(x, y),
        );
        tumbler = tumbler.with_shape(wall.material(FRICTION, Real::ZERO));
    }
    desc.bodies.push(tumbler);
    let (side, k) = tumbler_box_side(n);
    let half_pitch = side * real!(0.625);
    let k = i64::from(k);
    // 0 ≤ i < k ≤ 2^16: 2i − (k − 1) is below 2^17 in magnitude.
    #[allow(clippy::arithmetic_side_effects)]
    let offset = |i: i64| half_pitch * Real::from_bits((2 * i - (k - 1)).saturating_mul(1 << 32));
    // Row by row from the bottom, `k` per row, `n` in all (k² ≥ n).
    let cells = (0..k).flat_map(|row| (0..k).map(move |col| (row, col)));
    for (row, col) in cells.take(n as usize) {
        let p = center + Vect::new(offset(col), offset(row));
        desc.bodies.push(box_body(p, side));
    }
    desc
}
