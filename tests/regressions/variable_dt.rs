//! Regression: changing `dt` between steps blew up
//! inside the documented range (1/10,000–1/30 s, `docs/numerics.md`): the
//! 210-box pyramid of `pyramid_20` stepped with `dt` alternating 1/240 and
//! 1/30 s reached 3.8·10³ m/s, alternating 1/1000 and 1/30 s 1.8·10⁵ m/s.
//!
//! The pyramid is built here with the public API (the same bodies, shapes,
//! materials and settings as the built-in `pyramid_20`), so the test does
//! not depend on the scene registry. Every sequence of steps is checked
//! after every step against two bounds that follow from energy, not from a
//! measurement:
//!
//! * **Kinetic energy.** Contacts and friction only remove energy and the
//!   bias impulses move positions without adding momentum, so the kinetic
//!   energy of the boxes can come only from their fall. A box rests at its
//!   lowest on the ground, its centre ½ m up, less the overlap the solver
//!   leaves uncorrected (the collision slop); so the total kinetic energy
//!   is at most `Σ m·g·(y₀ − ½ + slop)` over the boxes, `y₀` each box's
//!   starting height (13,510 J for base 20 at slop 0.1 m).
//! * **Speed.** No box can move faster than one dropped from the top of the
//!   pyramid onto the ground, `sqrt(2·g·(y_top − ½ + slop))` (19.5 m/s),
//!   plus one step of gravity `g·dt_max` (0.33 m/s): the integrator moves a
//!   body with the velocity of the step before, so a falling body may carry
//!   one step's `g·dt` more than the exact fall gives.
//!
//! The rotation is part of the kinetic energy (`Body::kinetic_energy` sums
//! `½Iω²`), so a spinning box is caught by the first bound. A box that
//! fell off the 40 m ground would break both bounds, as it should: a
//! pyramid that stays bounded in energy does not lose boxes.
//!
//! The random sequences come from an integer generator (SplitMix64): the
//! test is deterministic and uses no floats in the simulation.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::space::Space;

/// Gravity (m/s², downwards), as in the stacking scenes.
const G: i32 = 10;
/// Base of the pyramid (`pyramid_20`).
const BASE: i32 = 20;
/// Friction of every shape (the stacking scenes' 0.6).
const FRICTION: Real = Real::lit("0.6");
/// The documented range of `dt`: 1/10,000 s to 1/30 s.
const DT_MIN_DEN: i32 = 10_000;
const DT_MAX_DEN: i32 = 30;

/// `pyramid_{base}` on the public API: a static ground segment from
/// x = −base to base at y = 0, and `base(base+1)/2` unit boxes of density 1,
/// row `i` holding `base − i` boxes centred at `x = (2j − (base − 1 − i))/2`,
/// `y = i + ½`. Gravity (0, −10), 10 iterations, default slop and bias.
fn pyramid(base: i32) -> Space {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -G));
    space.set_iterations(10);
    let ground = space.add_body(Body::new_static()).unwrap();
    let half = Real::from_int(base);
    let seg = Shape::segment_shape_new(
        ground,
        Vect::new(-half, Real::ZERO),
        Vect::new(half, Real::ZERO),
        Real::ZERO,
    )
    .unwrap()
    .with_material(FRICTION, Real::ZERO)
    .unwrap();
    space.add_shape(seg).unwrap();
    for i in 0..base {
        for j in 0..base - i {
            let mut body = Body::new(Real::ZERO, Real::ZERO).unwrap();
            // (2j − (base − 1 − i))/2 and i + ½, exactly.
            let x = Real::ratio(2 * j - (base - 1 - i), 2);
            let y = Real::ratio(2 * i + 1, 2);
            body.set_position(Vect::new(x, y));
            let h = space.add_body(body).unwrap();
            let mut shape = Shape::box_shape_new(h, Real::ONE, Real::ONE, Real::ZERO)
                .unwrap()
                .with_material(FRICTION, Real::ZERO)
                .unwrap();
            shape.set_density(Real::ONE).unwrap();
            space.add_shape(shape).unwrap();
        }
    }
    space
}

/// The bounds of the module comment for `space` as built, before any step.
struct Bounds {
    kinetic_energy: f64,
    speed: f64,
}

fn bounds(space: &Space, dt_max: Real) -> Bounds {
    let g = f64::from(G);
    let slop = space.settings().collision_slop.to_f64();
    let drops = space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(_, b)| (b.mass().to_f64(), b.center().y.to_f64() - 0.5 + slop));
    let (mut energy, mut top) = (0.0, 0.0f64);
    for (m, drop) in drops {
        energy += m * g * drop;
        top = top.max(drop);
    }
    Bounds {
        kinetic_energy: energy,
        speed: (2.0 * g * top).sqrt() + g * dt_max.to_f64(),
    }
}

/// The largest total kinetic energy and body speed seen after any step.
#[derive(Debug, Default, Clone, Copy)]
struct Peak {
    kinetic_energy: f64,
    speed: f64,
    kinetic_step: usize,
    speed_step: usize,
}

/// Steps a fresh pyramid through `dts` and checks the bounds on the
/// largest values seen after any step.
fn run(name: &str, dts: &[Real]) {
    let (peak, bound) = measure(name, dts);
    check(name, &peak, &bound);
}

/// Steps a fresh pyramid through `dts`; returns the peaks and the bounds.
fn measure(name: &str, dts: &[Real]) -> (Peak, Bounds) {
    let mut space = pyramid(BASE);
    let dt_max = dts.iter().copied().fold(Real::ZERO, Real::max);
    let bound = bounds(&space, dt_max);
    let mut peak = Peak::default();

    for (n, &dt) in dts.iter().enumerate() {
        space.step(dt).unwrap();
        let mut ke = 0.0;
        for (_, b) in space.bodies() {
            ke += b.kinetic_energy().to_f64();
            let speed = b.velocity().length().to_f64();
            if speed > peak.speed {
                (peak.speed, peak.speed_step) = (speed, n);
            }
        }
        if ke > peak.kinetic_energy {
            (peak.kinetic_energy, peak.kinetic_step) = (ke, n);
        }
    }
    println!(
        "{name}: {} steps, {:.3} s simulated: max KE {:.4e} J at step {} (bound {:.4e}), \
         max speed {:.4e} m/s at step {} (bound {:.4})",
        dts.len(),
        dts.iter().map(|d| d.to_f64()).sum::<f64>(),
        peak.kinetic_energy,
        peak.kinetic_step,
        bound.kinetic_energy,
        peak.speed,
        peak.speed_step,
        bound.speed,
    );
    (peak, bound)
}

fn check(name: &str, peak: &Peak, bound: &Bounds) {
    assert!(
        peak.kinetic_energy <= bound.kinetic_energy,
        "{name}: kinetic energy {:.4e} J at step {} exceeds the {:.4e} J the pyramid can release",
        peak.kinetic_energy,
        peak.kinetic_step,
        bound.kinetic_energy
    );
    assert!(
        peak.speed <= bound.speed,
        "{name}: speed {:.4e} m/s at step {} exceeds a fall from the top ({:.4} m/s)",
        peak.speed,
        peak.speed_step,
        bound.speed
    );
}

/// `n` steps alternating `1/a` and `1/b` seconds.
fn alternating(a: i32, b: i32, n: usize) -> Vec<Real> {
    let (da, db) = (Real::ratio(1, a), Real::ratio(1, b));
    (0..n).map(|i| if i % 2 == 0 { da } else { db }).collect()
}

/// SplitMix64, integers only.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `lo..=hi` (the modulo bias is irrelevant here).
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        let span = u64::try_from(hi - lo + 1).unwrap();
        lo + i64::try_from(self.next() % span).unwrap()
    }
}

/// Steps whose lengths are drawn until they add up to `seconds`: each one
/// either uniform in raw bits over the documented range (mostly long steps)
/// or `1/k` with `k` uniform in 30..=10,000 (mostly short steps), so that
/// neighbouring steps differ by ratios from 1 to 333 either way.
fn random(seed: u64, seconds: i32) -> Vec<Real> {
    let mut rng = SplitMix64(seed);
    let (lo, hi) = (
        Real::ratio(1, DT_MIN_DEN).to_bits(),
        Real::ratio(1, DT_MAX_DEN).to_bits(),
    );
    let total = Real::from_int(seconds);
    let (mut t, mut dts) = (Real::ZERO, Vec::new());
    while t < total {
        let dt = if rng.next() % 2 == 0 {
            Real::from_bits(rng.range(lo, hi))
        } else {
            let k = i32::try_from(rng.range(i64::from(DT_MAX_DEN), i64::from(DT_MIN_DEN))).unwrap();
            Real::ratio(1, k)
        };
        dts.push(dt);
        t += dt;
    }
    dts
}

/// The reference: at a constant 1/30 s (the longest documented step) the
/// same pyramid settles within the same bounds. Measured (unchanged by the
/// fix, which changes no bit at a constant `dt`): 20.7 J, 0.84 m/s, both
/// while the boxes settle in the first steps.
#[test]
fn constant_1_30_keeps_energy_bounded() {
    run("constant 1/30", &alternating(30, 30, 4 * 30));
}

#[test]
fn alternating_1_240_and_1_30_keeps_energy_bounded() {
    // 4 s of simulated time.
    run(
        "1/240 <-> 1/30",
        &alternating(240, 30, 2 * 4 * 30 * 240 / 270),
    );
}

#[test]
fn alternating_1_1000_and_1_30_keeps_energy_bounded() {
    // 4 s of simulated time.
    run(
        "1/1000 <-> 1/30",
        &alternating(1000, 30, 2 * 4 * 30 * 1000 / 1030),
    );
}

#[test]
fn alternating_the_ends_of_the_documented_range_keeps_energy_bounded() {
    // 1/10,000 and 1/30 s, 4 s of simulated time.
    run(
        "1/10000 <-> 1/30",
        &alternating(DT_MIN_DEN, DT_MAX_DEN, 2 * 4 * 30 * 10_000 / 10_030),
    );
}

#[test]
fn random_steps_across_the_documented_range_keep_energy_bounded() {
    // Every seed is measured (and printed) before any is checked.
    let runs: Vec<(String, Peak, Bounds)> = [1, 2, 3]
        .into_iter()
        .map(|seed| {
            let name = format!("random seed {seed}");
            let (peak, bound) = measure(&name, &random(seed, 4));
            (name, peak, bound)
        })
        .collect();
    for (name, peak, bound) in &runs {
        check(name, peak, bound);
    }
}
