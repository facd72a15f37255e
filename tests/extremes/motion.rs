//! Extreme scenes, part 3: speed, overlap and time. Tunnelling through thin
//! and thick walls (where it starts, and how often), 100 bodies spawned at
//! one point, tiny (1/10,000 s) and large (1/10 s) time steps, and a
//! resting stack left for 10^5 steps.
//!
//! Measured values (release build) are quoted at each test; the bounds
//! leave room for solver changes. The longest test,
//! `resting_stack_for_1e5_steps_*`, takes about 1 s in release builds and
//! 7–15 s in debug builds (depending on load), so it runs in both.
#![allow(clippy::float_arithmetic)]

use super::common::{
    build, coincident, positions, run_displacement, separate, stack_with_dt, tunnel_count,
    worst_displacement, Watch, SLOP,
};
use tamias2d::Real;
use tamias2d_scenes as scenes;

// ---------------------------------------------------------------------------
// Tunnelling. A ball of radius r = 0.5 m, dt = 1/60 s, travelling s radii
// per step (v = 30·s m/s), against a thin segment or a 1 m thick box, from
// 32 start offsets spread over one step's travel.
//
// The sampling argument: the ball is pushed back only if some step ends
// with its centre on the near side of the wall's middle while touching:
// within r of a thin segment (a window of r), within r + w of a wall of
// half-thickness w (a window of r + w). A centre that lands past the middle
// is pushed *through* (the contact normal flips). So nothing tunnels while
// v·dt ≤ window, and beyond it a fraction 1 − window/(v·dt) of the phases
// does.
// ---------------------------------------------------------------------------

const PHASES: i32 = 32;

/// `PHASES · (1 − window/travel)` for a travel of `num/den` radii and a
/// window of `window` radii, rounded to the nearest phase count.
fn predicted(num: i32, den: i32, window: i32) -> i32 {
    let frac = 1.0 - f64::from(window * den) / f64::from(num);
    (f64::from(PHASES) * frac.max(0.0)).round() as i32
}

#[test]
fn ball_never_tunnels_a_thin_segment_while_a_step_is_within_its_radius() {
    // v·dt = 0.5 r, 0.9 r, r (15, 27, 30 m/s): measured 0 of 32 pass.
    for (num, den) in [(1, 2), (9, 10), (1, 1)] {
        assert_eq!(
            tunnel_count(num, den, false, PHASES),
            0,
            "{num}/{den} r per step"
        );
    }
}

#[test]
fn thin_segment_tunnelling_beyond_the_radius_follows_the_sampling_argument() {
    // Measured passes of 32: 1.1 r → 3, 1.5 r → 10, 2 r → 16, 4 r → 24;
    // predicted 2.9, 10.7, 16, 24.
    for (num, den) in [(11, 10), (3, 2), (2, 1), (4, 1)] {
        let got = tunnel_count(num, den, false, PHASES);
        let want = predicted(num, den, 1);
        assert!(
            (got - want).abs() <= 1,
            "{num}/{den} r per step: {got} of {PHASES} passed, predicted {want}"
        );
    }
}

#[test]
fn thick_wall_stops_the_ball_until_a_step_exceeds_radius_plus_half_thickness() {
    // Window r + w = 2r (1 m): measured 0 passes up to 2 r per step (60
    // m/s), then 7 (2.5 r), 10 (3 r), 16 (4 r); predicted 0, 6.4, 10.7, 16.
    for (num, den) in [(3, 2), (2, 1), (5, 2), (3, 1), (4, 1)] {
        let got = tunnel_count(num, den, true, PHASES);
        let want = predicted(num, den, 2);
        assert!(
            (got - want).abs() <= 1,
            "{num}/{den} r per step: {got} of {PHASES} passed, predicted {want}"
        );
    }
}

// ---------------------------------------------------------------------------
// 100 bodies at exactly the same point, no gravity.
// ---------------------------------------------------------------------------

#[test]
fn hundred_boxes_at_one_point_separate_without_gaining_speed() {
    // Sequential contacts (`block_solver` off): overlap is removed by bias
    // impulses, which move positions but add no momentum, and the pairs
    // start at rest: measured speed 0 (exactly), spin 0, separated to the
    // slop after 501 steps, spread over ±9.4 m × ±4.2 m, largest single-step
    // move 0.86 m. The spread in y and the spin come only from the order of
    // the two contacts of each face; with the block solver see the next test.
    let mut desc = coincident(100, true);
    desc.settings.block_solver = false;
    let mut s = build(&desc);
    let (w, separated, deepest, xmax, ymax) = separate(&mut s, 600);
    assert!(w.max_speed < 1e-6 && w.max_spin < 1e-6, "{w:?}");
    assert_eq!(w.saturated, 0);
    assert_eq!(w.cap_hits, 0, "GJK/EPA hit their iteration caps");
    assert!(
        separated.is_some(),
        "still overlapping by {deepest} m after 600 steps"
    );
    assert!(xmax < 20.0 && ymax < 20.0, "spread to {xmax} × {ymax} m");
    assert!(
        w.max_jump < 2.0,
        "a box jumped {} m in one step",
        w.max_jump
    );
    s.space.validate().unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn hundred_boxes_at_one_point_spread_on_one_line_with_the_block_solver() {
    // Every pair of coincident axis-aligned boxes gets the same contact
    // normal (±x, the narrowphase's tie rule) and two contacts placed
    // symmetrically about the x axis. The block solver solves them in
    // formulas symmetric in the two contacts, so nothing can push a box off
    // the x axis or turn it: the boxes spread along one line, exactly.
    // That is the exact answer of the contact model for this input (the
    // sequential solver leaves the line only through its contact order),
    // and a line of 100 unit boxes needs ~100 m, so separation is slow:
    // measured deepest overlap 0.50 m after 600 steps, 0.14 m after 3,000,
    // speed 0, largest single-step move 0.94 m. Asserted: exactly on the
    // line, no speed, no jump of 2 m or more, and the overlap shrinking.
    let mut s = build(&coincident(100, true));
    let (w, _, deepest_300, _, ymax) = separate(&mut s, 300);
    assert_eq!(ymax, 0.0, "a box left the x axis");
    let (w2, _, deepest_600, xmax, ymax) = separate(&mut s, 300);
    assert_eq!(ymax, 0.0, "a box left the x axis");
    for w in [&w, &w2] {
        assert!(w.max_speed < 1e-6 && w.max_spin == 0.0, "{w:?}");
        assert_eq!(w.saturated, 0);
        assert!(
            w.max_jump < 2.0,
            "a box jumped {} m in one step",
            w.max_jump
        );
    }
    assert!(
        deepest_600 > deepest_300,
        "overlap did not shrink: {deepest_300} m after 300 steps, {deepest_600} m after 600"
    );
    assert!(xmax < 60.0, "spread to {xmax} m");
    s.space.validate().unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn hundred_circles_at_one_point_spread_along_a_line_without_gaining_speed() {
    // Coincident circles have no direction between them; the narrowphase
    // then uses the normal (1, 0) for every pair, so the circles spread
    // along the x axis only, a 1-D chain that sorts itself out slowly.
    // Measured after 600 steps: speed 0 (exactly), every y = 0, |x| ≤
    // 31.6 m, deepest overlap 0.51 m (0.14 m after 3000 steps).
    let mut s = build(&coincident(100, false));
    let (w, _, deepest, xmax, ymax) = separate(&mut s, 600);
    assert!(w.max_speed < 1e-6 && w.max_spin < 1e-6, "{w:?}");
    assert_eq!(w.saturated, 0);
    assert_eq!(ymax, 0.0, "circles left the x axis");
    // 100 circles of diameter 1 in a row span at most 99 m.
    assert!(xmax < 99.0, "spread to {xmax} m");
    assert!(
        deepest > -0.75,
        "deepest overlap {deepest} m after 600 steps"
    );
    assert!(
        w.max_jump < 2.0,
        "a circle jumped {} m in one step",
        w.max_jump
    );
}

// ---------------------------------------------------------------------------
// Time steps.
// ---------------------------------------------------------------------------

#[test]
fn stack_at_dt_1_over_10000_stands_still() {
    // stack_5 for 1 s at 10^4 steps per second: each step's fall into the
    // contacts is g·dt² = 10^-7 m. Measured worst displacement 3.9e-7 m,
    // speed 5.0e-4 m/s.
    let mut s = build(&stack_with_dt(5, Real::ratio(1, 10_000), 10));
    let (moved, w) = run_displacement(&mut s, 10_000);
    assert!(moved < 1e-5, "moved {moved} m");
    assert!(w.max_speed < 1e-2, "speed {}", w.max_speed);
    assert_eq!(w.saturated, 0);
}

#[test]
fn free_fall_at_dt_1_over_10000_matches_its_closed_form() {
    // free_fall (g = 9.81) for 1 s at 10^4 steps per second. The discrete
    // closed form with the *rounded* dt is what the integrator computes
    // up to ½ ulp per operation: y_N = y0 − g·dt²·N(N−1)/2, v_N = −g·dt·N.
    // Measured: 5.0e-7 m from that form; 6.7e-6 m from the form with the
    // *nominal* dt = 10^-4 s (which `Real` rounds by 6.3e-7 relative).
    let mut desc = scenes::accuracy::free_fall();
    let dt = Real::ratio(1, 10_000);
    desc.dt = dt;
    let mut s = build(&desc);
    let Some(ball) = s.body("ball") else {
        panic!("free_fall has a ball");
    };
    let n: u32 = 10_000;
    let w = Watch::run(&mut s, n);
    assert_eq!(w.saturated, 0);
    let b = s.space.body(ball).unwrap_or_else(|| panic!("ball is gone"));
    let (g, dtf, nf) = (9.81, dt.to_f64(), f64::from(n));
    let y_rounded_dt = 100.0 - g * dtf * dtf * nf * (nf - 1.0) / 2.0;
    let ulp = 1.0 / 4_294_967_296.0;
    // ½ ulp per multiplication and addition, two of each per step.
    let err = (b.position().y.to_f64() - y_rounded_dt).abs();
    assert!(err < 2.0 * nf * ulp, "y off the rounded-dt form by {err} m");
    let v_err = (b.velocity().y.to_f64() + g * dtf * nf).abs();
    assert!(v_err < nf * ulp, "v off by {v_err} m/s");
}

#[test]
fn box_and_short_stack_stand_at_dt_1_over_10() {
    // g·dt² = 0.1 m per step, as large as the slop. Measured worst
    // displacement: one box 0.100 m (it settles into the slop), stack_3
    // 0.223 m, speed ≤ 1.32 m/s.
    for n in [1, 3] {
        let mut s = build(&stack_with_dt(n, Real::ratio(1, 10), 10));
        let (moved, w) = run_displacement(&mut s, 200);
        assert!(moved < 0.35, "stack_{n} moved {moved} m");
        assert!(w.max_speed < 3.0, "stack_{n} speed {}", w.max_speed);
        assert_eq!(w.saturated, 0);
    }
}

#[test]
fn tall_stack_at_dt_1_over_10_topples_but_stays_bounded() {
    // Outside the envelope: stack_5 at 1/10 s topples (measured top box
    // 6.4 m from its start, speed ≤ 8.4 m/s; with 30 iterations it leans
    // 0.74 m, at 1/20 s it stands: 0.07 m). Nothing saturates or explodes.
    let mut s = build(&stack_with_dt(5, Real::ratio(1, 10), 10));
    let (moved, w) = run_displacement(&mut s, 600);
    assert_eq!(w.saturated, 0);
    assert!(w.max_speed < 20.0, "speed {}", w.max_speed);
    assert!(moved < 15.0, "moved {moved} m");
    let mut s = build(&stack_with_dt(5, Real::ratio(1, 20), 10));
    let (moved, _) = run_displacement(&mut s, 400);
    assert!(moved < 0.2, "stack_5 at 1/20 s moved {moved} m");
}

#[test]
fn resting_stack_for_1e5_steps_neither_creeps_nor_gains_energy() {
    // stack_3 settles within the first 10^4 steps (measured: top box at
    // (−2.9e-3, 2.4959) m). From then on, measured: every position bit for
    // bit the same at every 10^4-step sample, kinetic energy 0, speed ≤ 1
    // ulp (2.3e-10 m/s).
    let mut s = build(&scenes::accuracy::stack(3));
    let mut w = Watch::run(&mut s, 10_000);
    let settled = positions(&s.space);
    let mut creep = 0.0f64;
    let mut energy = 0.0f64;
    let mut speed = 0.0f64;
    for _ in 0..90 {
        let mut chunk = Watch::new(&s.space);
        chunk.step(&mut s, 1_000);
        speed = speed.max(chunk.max_speed);
        creep = creep.max(worst_displacement(&settled, &s.space));
        let ke: f64 = s
            .space
            .bodies()
            .map(|(_, b)| b.kinetic_energy().to_f64())
            .sum();
        energy = energy.max(ke);
        w.saturated = w.saturated.max(chunk.saturated);
    }
    assert_eq!(w.saturated, 0);
    assert!(creep < 1e-6, "crept {creep} m after settling");
    assert!(speed < 1e-6, "speed {speed} m/s after settling");
    assert!(energy < 1e-9, "kinetic energy {energy} J after settling");
    // Gravity never pushes a settled box into its neighbour by more than
    // the slop.
    assert!(super::common::deepest_contact(&s.space) > -SLOP.to_f64());
}
