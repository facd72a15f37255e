//! Resting contact and stacking (scenes/README.md sections B and C):
//! `pyramid_20` stands for 10 s, `stack_10` does not drift or collapse, a
//! ball resting on the ground sits at its radius (less at most the slop),
//! and a box left on the ground for 10^4 steps neither creeps nor gains
//! energy.
//!
//! Bounds come from the contact model (Chipmunk's: overlap up to the
//! collision slop (0.1 m in the standard scenes, Chipmunk's value; the engine's default is 0.005 m), is not corrected; beyond it 10% per
//! 1/60 s step is) and from energy and symmetry arguments, stated at each
//! test. Floats appear only in comparisons, never in a scene.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::real;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{
    self as scenes, BodyDesc, BodyKind, SceneDesc, ScriptedWorld, SettingsDesc, ShapeDesc,
};

/// Chipmunk's default collision slop, which every stacking scene uses.
const SLOP: f64 = 0.1;

fn build(desc: &SceneDesc) -> ScriptedWorld {
    desc.build()
        .unwrap_or_else(|e| panic!("{}: {e}", desc.name))
}

fn builtin(name: &str) -> ScriptedWorld {
    build(&scenes::builtin(name).unwrap_or_else(|| panic!("{name} is a listed scene")))
}

fn get(scene: &ScriptedWorld, h: BodyHandle) -> &Body {
    scene
        .space
        .body(h)
        .unwrap_or_else(|| panic!("body {h:?} is gone"))
}

fn step(scene: &mut ScriptedWorld) {
    scene.step().unwrap_or_else(|e| panic!("step: {e}"));
}

/// Handle, start position and start angle of every dynamic body.
fn dynamic_starts(scene: &ScriptedWorld) -> Vec<(BodyHandle, Vect, Real)> {
    scene
        .space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, b)| (h, b.position(), b.angle()))
        .collect()
}

/// The energy the integrator conserves in free flight under gravity
/// (0, −10) at dt = 1/60, summed over the dynamic bodies:
/// `m·g·y + ½mv² + ½Iω² + ½·m·g·v_y·dt`. With `y' = y + v·dt` and
/// `v' = v − g·dt`: `g·(y' − y) = g·v·dt`, `½(v'² − v²) = −g·v·dt + ½g²dt²`,
/// `½·g·dt·(v' − v) = −½g²dt²`, which sum to 0.
fn integrator_energy(scene: &ScriptedWorld) -> f64 {
    scene
        .space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(_, b)| {
            let m = b.mass().to_f64();
            let (y, vy) = (b.center().y.to_f64(), b.velocity().y.to_f64());
            10.0 * m * y + b.kinetic_energy().to_f64() + 0.5 * m * 10.0 * vy / 60.0
        })
        .sum()
}

fn total_kinetic_energy(scene: &ScriptedWorld) -> f64 {
    scene
        .space
        .bodies()
        .map(|(_, b)| b.kinetic_energy().to_f64())
        .sum()
}

#[test]
fn pyramid_20_stands_for_ten_seconds() {
    // 210 unit boxes, 600 steps of 1/60 s. Acceptance (the Box2D benchmark
    // meaning of "stands"): after every step, every box is within 0.05 m
    // (5% of its side, half the slop) of where it started and has turned by
    // at most 0.05 rad. A pyramid that starts to slide apart or topple
    // leaves these bounds within a fraction of a second.
    let mut scene = builtin("pyramid_20");
    assert_eq!(scene.dt, Real::ratio(1, 60));
    let starts = dynamic_starts(&scene);
    assert_eq!(starts.len(), 210);
    let (mut max_d, mut max_a) = (0f64, 0f64);
    for n in 1..=600u32 {
        step(&mut scene);
        for &(h, p0, a0) in &starts {
            let b = get(&scene, h);
            let d = (b.position() - p0).length().to_f64();
            let a = (b.angle() - a0).abs().to_f64();
            max_d = max_d.max(d);
            max_a = max_a.max(a);
            assert!(
                d <= 0.05,
                "step {n}: box {h:?} moved {d} m from {p0:?} to {:?}",
                b.position()
            );
            assert!(a <= 0.05, "step {n}: box {h:?} turned by {a} rad");
        }
    }
    scene
        .space
        .validate()
        .unwrap_or_else(|e| panic!("invalid state: {e}"));
    println!(
        "pyramid_20 after 600 steps: max displacement {max_d:.4} m, max rotation {max_a:.4} rad, \
         kinetic energy {:.3e} J",
        total_kinetic_energy(&scene)
    );
}

#[test]
fn stack_10_top_box_stays_within_drift_bounds() {
    // 10 unit boxes stacked at x = 0 on the ground, 600 steps (10 s).
    //
    // Vertical: each of the 10 contacts (ground–box and 9 box–box) may
    // overlap up to the slop with no correction, so the stack may settle by
    // up to 10·slop: y_top ≥ 9.5 − 10·slop. A box can only rise by
    // pivoting on a corner, which lifts its centre by at most half a side ×
    // its tilt (≤ 0.05 rad, below), or by leaving its support, which would
    // need energy: y_top ≤ 9.5 + 0.5·0.05.
    //
    // Energy: the integrator (positions first, then v += g·dt) conserves
    // E* = Σ(m·g·y + ½mv² + ½Iω² + ½·m·g·v_y·dt) exactly in free flight
    // (the ½·m·g·v_y·dt term accounts for the velocity being half a step
    // ahead of the position); a resting contact that stops a body's
    // per-step fall leaves E* unchanged, and inelastic contacts can only
    // remove energy. The stack starts at rest with E* = 500 J; E* may never
    // exceed that (10^-6 J allowed for the f64 sums).
    //
    // Lateral: by symmetry the exact answer is x = 0, and with the block
    // solver (the default) it is exactly 0 at every step
    // (tests/physics/mirror_symmetry.rs). The sequential solver (`block_solver`
    // off) breaks the mirror symmetry (the two contacts of a face are
    // solved one after the other), and overlap within the slop is never
    // corrected, so the stack may sway; it still stands as long as each box
    // sits on the one below. The bounds below hold for both solvers. We require the top box to stay within a quarter
    // of a side (half the 0.5 m at which the top box would overhang its
    // support's edge) and every box to stay upright within 0.05 rad, as in
    // the pyramid, after every step. (Measured: the stack sways as a whole,
    // top amplitude up to 0.1 m, period ~2.5 s, slowly decaying; see the
    // printed values.)
    let mut scene = builtin("stack_10");
    let top = scene.body("top").unwrap_or_else(|| panic!("labelled"));
    let starts = dynamic_starts(&scene);
    assert_eq!(starts.len(), 10);
    let y0 = get(&scene, top).position().y.to_f64();
    assert_eq!(y0, 9.5);
    let e0 = integrator_energy(&scene);
    assert_eq!(e0, 500.0);
    let (mut max_x, mut min_y, mut max_a, mut max_e) = (0f64, y0, 0f64, f64::MIN);
    for n in 1..=600u32 {
        step(&mut scene);
        let p = get(&scene, top).position().to_f64();
        max_x = max_x.max(p.0.abs());
        min_y = min_y.min(p.1);
        assert!(
            p.1 >= y0 - 10.0 * SLOP && p.1 <= y0 + 0.5 * 0.05,
            "step {n}: top box at height {}",
            p.1
        );
        let e = integrator_energy(&scene);
        max_e = max_e.max(e);
        assert!(e <= e0 + 1e-6, "step {n}: energy grew from {e0} J to {e} J");
        assert!(
            p.0.abs() <= 0.25,
            "step {n}: top box drifted to x = {}",
            p.0
        );
        for &(h, _, a0) in &starts {
            let a = (get(&scene, h).angle() - a0).abs().to_f64();
            max_a = max_a.max(a);
            assert!(a <= 0.05, "step {n}: box {h:?} turned by {a} rad");
        }
    }
    let p = get(&scene, top).position().to_f64();
    println!(
        "stack_10 after 10 s: top at ({:.4}, {:.4}) (drift {:.4} m lateral, {:.4} m down); \
         over the run max |x_top| {max_x:.4} m, lowest y_top {min_y:.4}, max rotation {max_a:.4} rad, \
         max E* {max_e:.4} J (start {e0} J)",
        p.0,
        p.1,
        p.0.abs(),
        y0 - p.1
    );
}

/// A static ground segment from (−5, 0) to (5, 0) with the section B
/// material, and nothing else; gravity (0, −10), Chipmunk defaults.
fn ground_scene(name: &str) -> SceneDesc {
    let mut desc = SceneDesc {
        settings: SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10),
        ..SceneDesc::new(name, Real::ratio(1, 60), 600)
    };
    let five = Real::from_int(5);
    let ground = ShapeDesc::segment(
        Vect::new(-five, Real::ZERO),
        Vect::new(five, Real::ZERO),
        Real::ZERO,
    )
    .material(real!(0.6), Real::ZERO);
    desc.bodies
        .push(BodyDesc::static_body().labeled("ground").with_shape(ground));
    desc
}

#[test]
fn resting_ball_sits_at_its_radius_less_at_most_the_slop() {
    // A ball of radius 0.5 (density 1, friction 0.6, e = 0) on the ground,
    // either placed touching (centre at y = r) or dropped from 1 m above
    // that (it lands at √(2·10·1) ≈ 4.5 m/s and overlaps by at most one
    // step's travel, 0.075 m, which is within the slop). Once settled
    // (after 2 s) and until 10 s: r − slop ≤ y ≤ r (overlap is corrected
    // only beyond the slop, and a ball with e = 0 cannot float above the
    // ground), and it is at rest: |v| ≤ 2^-20 m/s (the contact cancels the
    // step's gravity up to rounding).
    let r = Real::HALF;
    for drop in [0, 1] {
        let mut desc = ground_scene("resting_ball");
        let start = Vect::new(Real::ZERO, r + Real::from_int(drop));
        let ball = ShapeDesc::circle(r)
            .material(real!(0.6), Real::ZERO)
            .density(Real::ONE);
        desc.bodies.push(
            BodyDesc::new(BodyKind::Dynamic, start)
                .labeled("ball")
                .with_shape(ball),
        );
        let mut scene = build(&desc);
        let h = scene.body("ball").unwrap_or_else(|| panic!("labelled"));
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for n in 1..=600u32 {
            step(&mut scene);
            let b = get(&scene, h);
            let (x, y) = b.position().to_f64();
            if n < 120 {
                continue;
            }
            lo = lo.min(y);
            hi = hi.max(y);
            assert!(
                (0.5 - SLOP..=0.5 + 1e-9).contains(&y),
                "drop {drop}, step {n}: centre at height {y}"
            );
            // Straight down onto flat ground: no horizontal force at all
            // (n = (0, 1), friction impulse 0); rounding only.
            assert!(x.abs() <= 1e-9, "drop {drop}, step {n}: drifted to x = {x}");
            let (vx, vy) = b.velocity().to_f64();
            let rest = 1.0 / 1_048_576.0;
            assert!(
                vx.abs() <= rest && vy.abs() <= rest,
                "drop {drop}, step {n}: v = ({vx}, {vy})"
            );
        }
        println!(
            "resting ball (dropped from {drop} m): height in [{lo:.6}, {hi:.6}] (radius 0.5, slop 0.1)"
        );
    }
}

#[test]
fn resting_box_neither_creeps_nor_gains_energy_over_ten_thousand_steps() {
    // A unit box (density 1, friction 0.6) placed touching the ground,
    // 10^4 steps (167 s). It settles within the first second (the contact
    // overlap, at most the slop, is then fixed); from step 600 on:
    // * no creep: on flat ground nothing pushes it sideways (friction
    //   impulses are 0 in exact arithmetic) and the normal impulse cancels
    //   gravity, so only rounding can move it: a few ulp per step,
    //   < 9400 × 4 ulp ≈ 9·10^-6 m over the run; we allow 2^-16 m (1.5·10^-5)
    //   of displacement and 2^-16 rad of rotation relative to step 600;
    // * no energy gain: the kinetic energy stays at rounding level, below
    //   ½·m·(2^-20 m/s)² ≈ 4.5·10^-13 J at every step (a velocity of a few
    //   ulp, nowhere near the g·dt = 0.17 m/s one uncancelled step of
    //   gravity would give), and the total energy m·g·y + KE never exceeds its
    //   value at step 600 by more than the same rounding allowance.
    let mut desc = ground_scene("resting_box");
    let boxy = ShapeDesc::box_shape(Real::ONE, Real::ONE, Real::ZERO)
        .material(real!(0.6), Real::ZERO)
        .density(Real::ONE);
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::new(Real::ZERO, Real::HALF))
            .labeled("box")
            .with_shape(boxy),
    );
    let mut scene = build(&desc);
    let h = scene.body("box").unwrap_or_else(|| panic!("labelled"));
    scene.step_n(600).unwrap_or_else(|e| panic!("{e}"));
    let settled = get(&scene, h).clone();
    let (x0, y0) = settled.position().to_f64();
    assert!(
        (0.5 - SLOP..=0.5 + 1e-9).contains(&y0),
        "settled at height {y0}"
    );
    assert!(x0.abs() <= 0.05, "slid to x = {x0} while settling");
    let energy =
        |b: &Body| 10.0 * b.mass().to_f64() * b.position().y.to_f64() + b.kinetic_energy().to_f64();
    let e0 = energy(&settled);
    let creep = 1.0 / 65_536.0;
    let ke_bound = 0.5 * (1.0f64 / 1_048_576.0).powi(2);
    let (mut max_d, mut max_ke) = (0f64, 0f64);
    for n in 601..=10_000u32 {
        step(&mut scene);
        let b = get(&scene, h);
        let d = (b.position() - settled.position()).length().to_f64();
        max_d = max_d.max(d);
        assert!(
            d <= creep,
            "step {n}: crept {d} m from the settled position"
        );
        let da = (b.angle() - settled.angle()).abs().to_f64();
        assert!(da <= creep, "step {n}: turned {da} rad");
        let ke = b.kinetic_energy().to_f64();
        max_ke = max_ke.max(ke);
        assert!(ke <= ke_bound, "step {n}: kinetic energy {ke} J");
        assert!(
            energy(b) <= e0 + 10.0 * creep + ke_bound,
            "step {n}: energy grew from {e0} to {}",
            energy(b)
        );
    }
    println!(
        "resting box: settled at ({x0:.6}, {y0:.6}); from step 600 to 10^4 max displacement \
         {max_d:.3e} m, max kinetic energy {max_ke:.3e} J"
    );
}
