//! Extreme scenes, part 1: far from the origin. A stack and a pyramid
//! placed at x = 10^4, 10^6, ±2^30 and at the very edge of the range
//! (±(2^31 − 16)) must behave exactly like the same scene at the origin:
//! after every step, every body's position minus the shift, its velocity,
//! angle and rotation, and every contact are equal **bit for bit**.
//!
//! Why exact: positions are integers of 2^-32 m, so adding the shift is
//! exact; shapes move to world space by `position + rotation·local`
//! (the shift only enters the exact addition); the narrowphase subtracts
//! one shape's anchor before any product (`collision/mod.rs`, step 2), and
//! the solver works on `contact − centre` offsets. Nothing rounds a world
//! coordinate, so nothing depends on where the scene is. (An f32 engine
//! has a position step of 0.0625 m at 10^6 m and cannot even represent the
//! scene there; see `docs/numerics.md`.)
//!
//! Steps: 120 in debug builds, 600 (10 s) in release builds.

use super::common::{compare_shifted, int, x_vect};
use tamias2d::Vect;
use tamias2d_scenes::{self as scenes, SceneDesc};

/// Steps per comparison (debug builds are ~30x slower).
const STEPS: u32 = if cfg!(debug_assertions) { 120 } else { 600 };

/// Largest shift that keeps a scene spanning `margin` metres either side of
/// its origin inside the range.
fn edge(margin: i64) -> i64 {
    (1i64 << 31) - margin
}

fn assert_exact(desc: &SceneDesc, by: Vect) {
    let out = compare_shifted(desc, by, STEPS);
    assert_eq!(
        out.first_mismatch, None,
        "{} shifted by {by:?}: state differs from the origin run (first after step {:?})",
        desc.name, out.first_mismatch
    );
    // The shifted run itself stays inside the range and calm: no saturation,
    // no jump larger than a resting stack ever makes (a wrap would jump by
    // ~2^32 m).
    assert_eq!(out.watch.saturated, 0, "{}: saturated bodies", desc.name);
    assert!(
        out.watch.max_jump < 0.05,
        "{}: a body jumped {} m in one step",
        desc.name,
        out.watch.max_jump
    );
}

#[test]
fn stack_far_from_origin_equals_stack_at_origin_shifted_exactly() {
    let desc = scenes::accuracy::stack(5);
    for x in [10_000, 1_000_000, 1 << 30, -(1 << 30)] {
        assert_exact(&desc, x_vect(x));
    }
}

#[test]
fn pyramid_far_from_origin_equals_pyramid_at_origin_shifted_exactly() {
    let desc = scenes::stacking::pyramid(10);
    for x in [10_000, 1_000_000, 1 << 30, -(1 << 30)] {
        assert_exact(&desc, x_vect(x));
    }
}

#[test]
fn scenes_at_the_edge_of_the_range_are_still_exact() {
    // stack_5's ground spans ±5 m and pyramid_10's ±10 m: 16 m of margin
    // keeps every shape (and bounding box) below 2^31.
    let stack = scenes::accuracy::stack(5);
    let pyramid = scenes::stacking::pyramid(10);
    for desc in [&stack, &pyramid] {
        assert_exact(desc, x_vect(edge(16)));
        assert_exact(desc, x_vect(-edge(16)));
    }
}

#[test]
fn diagonal_shift_moves_both_axes_exactly() {
    // Gravity acts along y, so a y shift moves the direction that carries
    // the load; both axes at 2^30 at once.
    let by = Vect::new(int(1 << 30), int(-(1 << 30)));
    assert_exact(&scenes::accuracy::stack(5), by);
}
