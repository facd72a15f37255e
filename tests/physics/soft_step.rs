//! The soft step (`Solver::Soft`) at its defaults: hanging chains hold,
//! the joints' closed forms, stacks stand, any thread count and a snapshot
//! round trip give the same bits.
//!
//! Bounds: the chain's are Box2D v3's measured figures on the same chain
//! (3.1 cm worst, 1.7 cm steady at 100:1; 4.4 mm at 1:1) with a margin of
//! a millimetre or two, and the sequential solver's tearing on it shows the
//! test can fail. The closed forms' come from the integrator: symplectic
//! Euler on a sub-step `h` changes an oscillator's period by `(ωh)²/24`
//! (below 10⁻⁵ here) and the soft joint's compliance by less than its
//! stretch over the length; the period is read from zero crossings
//! interpolated between steps of 1/60 s over ≥ 10 s, a resolution better
//! than 0.1 %, so 0.5 % bounds the whole.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{Constraint, DampedSpring, GearJoint, JointKind, SimpleMotor};
use tamias2d::space::{Settings, Solver, Space};
use tamias2d::{real, Real, Vect};

/// A chain of `links` links of 0.5 m and 1 kg (moment 0.0217) hung down
/// from a static body by pivots at ±0.25 m, with an end mass of `end` kg
/// hung from the last link's lower end, at rest; gravity (0, −10).
fn hanging_chain(links: i32, end: i32, solver: Solver) -> (Space, Vec<BodyHandle>) {
    let mut space = Space::new();
    space
        .set_settings(Settings {
            gravity: Vect::from_ints(0, -10),
            solver,
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut prev = ground;
    let mut bodies = vec![];
    for i in 0..links {
        let mut b = Body::new(Real::ONE, real!(0.0217)).unwrap();
        b.set_position(Vect::new(
            Real::ZERO,
            real!(-0.25) - real!(0.5) * Real::from_int(i),
        ));
        let h = space.add_body(b).unwrap();
        let top = Vect::new(Real::ZERO, real!(-0.5) * Real::from_int(i));
        let c = space.pivot_joint(prev, h, top).unwrap();
        space.add_constraint(c).unwrap();
        bodies.push(h);
        prev = h;
    }
    let mass = Real::from_int(end);
    let mut b = Body::new(mass, mass * real!(0.03125)).unwrap();
    let y = real!(-0.5) * Real::from_int(links) - real!(0.25);
    b.set_position(Vect::new(Real::ZERO, y));
    let h = space.add_body(b).unwrap();
    let top = Vect::new(Real::ZERO, real!(-0.5) * Real::from_int(links));
    let c = space.pivot_joint(prev, h, top).unwrap();
    space.add_constraint(c).unwrap();
    bodies.push(h);
    (space, bodies)
}

/// The largest pivot gap (distance between the two world anchors).
fn worst_gap(space: &Space) -> f64 {
    let mut worst = 0.0f64;
    for (_, c) in space.constraints() {
        if let JointKind::Pivot(p) = c.kind() {
            let a = space.body(c.body_a()).unwrap().local_to_world(p.anchor_a());
            let b = space.body(c.body_b()).unwrap().local_to_world(p.anchor_b());
            worst = worst.max((b - a).length().to_f64());
        }
    }
    worst
}

/// The deepest overlap among the current contacts (0 if none).
fn max_penetration(space: &Space) -> f64 {
    space
        .arbiters()
        .iter()
        .flat_map(|a| a.contacts())
        .map(|c| -c.dist.to_f64())
        .fold(0.0, f64::max)
}

const DT_DEN: i32 = 60;

fn dt() -> Real {
    Real::ONE / Real::from_int(DT_DEN)
}

/// Steps `steps` times and returns the worst pivot gap over all steps and
/// over the last `tail` steps.
fn run_chain(space: &mut Space, steps: u32, tail: u32) -> (f64, f64) {
    let (mut worst, mut late) = (0.0f64, 0.0f64);
    for n in 1..=steps {
        space.step(dt()).unwrap();
        let g = worst_gap(space);
        worst = worst.max(g);
        if n > steps - tail {
            late = late.max(g);
        }
    }
    (worst, late)
}

#[test]
fn hanging_chain_holds_over_ten_thousand_steps() {
    // (end mass, worst bound, measured worst): the 100:1 chain opens as
    // far as Box2D's (its 3.1 cm), the 2 cm goal is missed there.
    for (end, bound) in [(1, 0.006), (10, 0.012), (100, 0.032)] {
        let (mut space, _) = hanging_chain(20, end, Solver::SOFT);
        let (worst, late) = run_chain(&mut space, 10_000, 1_000);
        println!("20 links, end {end} kg: worst gap {worst:.5} m, last 1000 steps {late:.5} m");
        assert!(worst < bound, "end {end}: worst gap {worst} ≥ {bound}");
        // Not growing: the last thousand steps stay within the worst of the
        // start (the load's first swing).
        assert!(late <= worst, "end {end}: gap grows");
    }
}

#[test]
fn hanging_chain_of_a_hundred_links_holds() {
    let (mut space, _) = hanging_chain(100, 100, Solver::SOFT);
    let (worst, late) = run_chain(&mut space, 2_000, 500);
    println!("100 links, end 100 kg: worst gap {worst:.5} m, last 500 steps {late:.5} m");
    assert!(worst < 0.055, "worst gap {worst}");
    assert!(late <= worst);
}

#[test]
fn sequential_solver_tears_the_same_chain() {
    // What the bounds above guard against: sequential impulses with a
    // velocity-level bias open the 100:1 chain by metres within 300 steps.
    let (mut space, _) = hanging_chain(20, 100, Solver::Sequential);
    let (worst, _) = run_chain(&mut space, 300, 1);
    assert!(worst > 1.0, "worst gap {worst}");
}

#[test]
fn kicked_chain_holds() {
    let (mut space, bodies) = hanging_chain(20, 100, Solver::SOFT);
    let end = *bodies.last().unwrap();
    space
        .body_mut(end)
        .unwrap()
        .set_velocity(Vect::from_ints(5, 0));
    let (worst, late) = run_chain(&mut space, 3_000, 500);
    println!("kicked: worst gap {worst:.5} m, last 500 steps {late:.5} m");
    assert!(worst < 0.06, "worst gap {worst}");
    assert!(late <= worst);
}

/// Zero crossings of `x(t)` (linear interpolation between steps), in seconds.
fn crossings(xs: &[f64]) -> Vec<f64> {
    let h = 1.0 / f64::from(DT_DEN);
    xs.windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * h)
        .collect()
}

/// The mean period from upward zero crossings.
fn period(xs: &[f64]) -> f64 {
    let c = crossings(xs);
    assert!(c.len() >= 4, "too few crossings: {}", c.len());
    (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
}

#[test]
fn pendulum_period_matches_the_closed_form() {
    // A 1 kg body with moment 0.01 on a pivot 1 m above its centre, started
    // 0.1 rad out: T = 2π·sqrt((I + mL²)/(m g L))·(1 + θ₀²/16).
    let mut space = Space::new();
    space
        .set_settings(Settings {
            gravity: Vect::from_ints(0, -10),
            solver: Solver::SOFT,
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut b = Body::new(Real::ONE, real!(0.01)).unwrap();
    let th = 0.1f64;
    b.set_position(Vect::new(
        Real::from_f64(th.sin()).unwrap(),
        Real::from_f64(-th.cos()).unwrap(),
    ));
    let bob = space.add_body(b).unwrap();
    let c = space.pivot_joint(ground, bob, Vect::ZERO).unwrap();
    space.add_constraint(c).unwrap();
    let xs: Vec<f64> = (0..1200)
        .map(|_| {
            space.step(dt()).unwrap();
            space.body(bob).unwrap().position().x.to_f64()
        })
        .collect();
    let want = 2.0 * std::f64::consts::PI * (1.01f64 / 10.0).sqrt() * (1.0 + th * th / 16.0);
    let got = period(&xs);
    println!("pendulum period {got:.5} s, closed form {want:.5} s");
    assert!((got / want - 1.0).abs() < 0.005, "period {got} vs {want}");
}

#[test]
fn spring_frequency_matches_the_closed_form() {
    // 2 kg on an undamped 200 N/m spring to a static body, no gravity,
    // 0.1 m out: T = 2π·sqrt(m/k).
    let mut space = Space::new();
    space
        .set_settings(Settings {
            solver: Solver::SOFT,
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut b = Body::new(Real::from_int(2), Real::ONE).unwrap();
    b.set_position(Vect::new(real!(1.1), Real::ZERO));
    let mass = space.add_body(b).unwrap();
    let spring = DampedSpring::new(
        Vect::ZERO,
        Vect::ZERO,
        Real::ONE,
        Real::from_int(200),
        Real::ZERO,
    )
    .unwrap();
    space
        .add_constraint(Constraint::new(ground, mass, spring).unwrap())
        .unwrap();
    let xs: Vec<f64> = (0..1200)
        .map(|_| {
            space.step(dt()).unwrap();
            space.body(mass).unwrap().position().x.to_f64() - 1.0
        })
        .collect();
    let want = 2.0 * std::f64::consts::PI * (2.0f64 / 200.0).sqrt();
    let got = period(&xs);
    println!("spring period {got:.5} s, closed form {want:.5} s");
    assert!((got / want - 1.0).abs() < 0.005, "period {got} vs {want}");
}

#[test]
fn gear_keeps_its_ratio() {
    // Wheel b geared to wheel a at ratio 2 (ω_b = ω_a / 2 in Chipmunk's
    // convention ratio·ω_b = ω_a), a driven by a motor at 3 rad/s.
    let mut space = Space::new();
    space
        .set_settings(Settings {
            solver: Solver::SOFT,
            ..Settings::default()
        })
        .unwrap();
    let ground = space.add_body(Body::new_static()).unwrap();
    let a = space
        .add_body(Body::new(Real::ONE, real!(0.5)).unwrap())
        .unwrap();
    let mut bb = Body::new(Real::ONE, real!(2)).unwrap();
    bb.set_position(Vect::from_ints(3, 0));
    let b = space.add_body(bb).unwrap();
    for h in [a, b] {
        let p = space.body(h).unwrap().position();
        let c = space.pivot_joint(ground, h, p).unwrap();
        space.add_constraint(c).unwrap();
    }
    let gear = GearJoint::new(Real::ZERO, Real::from_int(2)).unwrap();
    space
        .add_constraint(Constraint::new(a, b, gear).unwrap())
        .unwrap();
    let motor = SimpleMotor::new(Real::from_int(3)).unwrap();
    space
        .add_constraint(Constraint::new(ground, a, motor).unwrap())
        .unwrap();
    for _ in 0..300 {
        space.step(dt()).unwrap();
    }
    let wa = space.body(a).unwrap().angular_velocity().to_f64();
    let wb = space.body(b).unwrap().angular_velocity().to_f64();
    let (ta, tb) = (
        space.body(a).unwrap().angle().to_f64(),
        space.body(b).unwrap().angle().to_f64(),
    );
    println!("gear: ω_a {wa:.6}, ω_b {wb:.6}, θ_a {ta:.4}, θ_b {tb:.4}");
    assert!(
        (2.0 * wb - wa).abs() < 1e-3 * wa.abs(),
        "ω_a {wa}, ω_b {wb}"
    );
    // The angles too (the position bias re-measures them every sub-step).
    assert!((2.0 * tb - ta).abs() < 1e-3, "θ_a {ta}, θ_b {tb}");
}

/// Steps a built-in scene on the soft step; returns the largest sideways
/// and downward displacement of a body from its start and the deepest
/// overlap seen.
fn stack_run(name: &str, steps: u32) -> (f64, f64, f64) {
    let mut desc = tamias2d_scenes::builtin(name).unwrap();
    desc.settings.use_soft_step();
    let mut w = desc.build().unwrap();
    let start: Vec<Vect> = w.space.bodies().map(|(_, b)| b.position()).collect();
    let mut pen = 0.0f64;
    for _ in 0..steps {
        w.step().unwrap();
        pen = pen.max(max_penetration(&w.space));
    }
    let (mut side, mut drop) = (0.0f64, 0.0f64);
    for ((_, b), p0) in w.space.bodies().zip(&start) {
        side = side.max((b.position().x - p0.x).abs().to_f64());
        drop = drop.max((p0.y - b.position().y).to_f64());
    }
    (side, drop, pen)
}

#[test]
fn stacks_stand() {
    // stack_10: the goal's 1 mm sideways; pyramid_20: Box2D v3 at 4
    // sub-steps moves a box 3.6–3.7 mm sideways and overlaps 3.6 mm.
    let (side, drop, pen) = stack_run("stack_10", 600);
    println!("stack_10: sideways {side:.5} m, sag {drop:.5} m, overlap {pen:.5} m");
    assert!(side < 0.001, "stack_10 sideways {side}");
    assert!(
        drop < 0.04 && pen < 0.008,
        "stack_10 sag {drop}, overlap {pen}"
    );
    let (side, drop, pen) = stack_run("pyramid_20", 600);
    println!("pyramid_20: sideways {side:.5} m, sag {drop:.5} m, overlap {pen:.5} m");
    assert!(side < 0.005, "pyramid_20 sideways {side}");
    assert!(
        drop < 0.04 && pen < 0.006,
        "pyramid_20 sag {drop}, overlap {pen}"
    );
}

/// 120 steps (60 in a debug build, where every step is validated: CI runs
/// `tests/parallel.rs`, the full thread comparison, optimised).
#[test]
fn any_thread_count_and_a_snapshot_round_trip_give_the_same_bits() {
    let steps: u32 = if cfg!(debug_assertions) { 60 } else { 120 };
    let run = |threads: usize, split: Option<u32>| {
        let mut desc = tamias2d_scenes::builtin("many_pyramids_4x4").unwrap();
        desc.settings.use_soft_step();
        let mut w = desc.build().unwrap();
        w.space.set_threads(threads).unwrap();
        w.space.set_parallel_threshold(0);
        for n in 0..steps {
            if Some(n) == split {
                let bytes = tamias2d::snapshot::save(&w.space);
                let mut restored = tamias2d::snapshot::load(&bytes).unwrap();
                restored.set_threads(threads).unwrap();
                restored.set_parallel_threshold(0);
                w.space = restored;
            }
            w.space.step(dt()).unwrap();
        }
        w.space.checksum()
    };
    let one = run(1, None);
    for (threads, split) in [(2, None), (3, None), (1, Some(steps / 2)), (2, Some(37))] {
        assert_eq!(
            run(threads, split),
            one,
            "{threads} threads, split {split:?}"
        );
    }
}

#[test]
fn a_joint_keeps_its_own_stiffness() {
    use tamias2d::constraint::JointSoftness;
    let soften = |space: &mut Space, hertz: i32| {
        let handles: Vec<_> = space.constraints().map(|(h, _)| h).collect();
        for h in handles {
            let own = JointSoftness {
                hertz: Real::from_int(hertz),
                damping_ratio: Real::from_int(2),
            };
            space
                .constraint_mut(h)
                .unwrap()
                .set_softness(Some(own))
                .unwrap();
        }
    };
    // Softer joints (15 Hz) stretch the 100:1 chain more than the world's
    // 60 Hz; 60 Hz of their own is the world's default, bit for bit.
    let (mut world, _) = hanging_chain(20, 100, Solver::SOFT);
    let (mut soft15, _) = hanging_chain(20, 100, Solver::SOFT);
    let (mut own60, _) = hanging_chain(20, 100, Solver::SOFT);
    soften(&mut soft15, 15);
    soften(&mut own60, 60);
    let (w, _) = run_chain(&mut world, 300, 1);
    let (s, _) = run_chain(&mut soft15, 300, 1);
    run_chain(&mut own60, 300, 1);
    println!("world 60 Hz: {w:.5} m, own 15 Hz: {s:.5} m");
    assert!(s > 4.0 * w, "15 Hz {s} vs 60 Hz {w}");
    assert_eq!(own60.state().bodies, world.state().bodies);
    // The sequential solver ignores it.
    let (mut seq, _) = hanging_chain(5, 1, Solver::Sequential);
    let (mut seq_own, _) = hanging_chain(5, 1, Solver::Sequential);
    soften(&mut seq_own, 15);
    run_chain(&mut seq, 100, 1);
    run_chain(&mut seq_own, 100, 1);
    assert_eq!(seq.state().bodies, seq_own.state().bodies);
    // Out of range: refused.
    let bad = JointSoftness {
        hertz: Real::from_int(-1),
        damping_ratio: Real::ONE,
    };
    let h = world.constraints().next().unwrap().0;
    assert!(world
        .constraint_mut(h)
        .unwrap()
        .set_softness(Some(bad))
        .is_err());
}

/// `pyramid_100` (5,050 boxes) on both solvers, 600 steps: the soft step's
/// pyramid stands (its largest sideways move stays below the sequential
/// solver's). Slow in debug: run with `--release --ignored`.
#[test]
#[ignore = "5,050 boxes for 600 steps: run in release"]
fn pyramid_100_stands_on_the_soft_step() {
    let run = |soft: bool| {
        let mut desc = tamias2d_scenes::builtin("pyramid_100").unwrap();
        if soft {
            desc.settings.use_soft_step();
        }
        let mut w = desc.build().unwrap();
        let start: Vec<Vect> = w.space.bodies().map(|(_, b)| b.position()).collect();
        let mut pen = 0.0f64;
        for _ in 0..600 {
            w.step().unwrap();
            pen = pen.max(max_penetration(&w.space));
        }
        let side = w
            .space
            .bodies()
            .zip(&start)
            .map(|((_, b), p0)| (b.position().x - p0.x).abs().to_f64())
            .fold(0.0, f64::max);
        (side, pen)
    };
    let (seq_side, seq_pen) = run(false);
    let (soft_side, soft_pen) = run(true);
    println!("pyramid_100 sideways: sequential {seq_side:.4} m, soft {soft_side:.4} m");
    println!("pyramid_100 overlap: sequential {seq_pen:.4} m, soft {soft_pen:.4} m");
    assert!(
        soft_side < seq_side,
        "soft {soft_side} vs sequential {seq_side}"
    );
}
