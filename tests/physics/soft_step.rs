//! The soft step (`Solver::Soft`): hanging chains hold, joints' closed
//! forms, stacks stand.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::JointKind;
use tamias2d::space::{Settings, SoftStep, Solver, Space};
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

#[test]
fn hanging_chain_probe() {
    for (links, end) in [(20, 1), (20, 100), (100, 100)] {
        for solver in [Solver::Sequential, Solver::SOFT] {
            let (mut space, _) = hanging_chain(links, end, solver);
            let mut worst = 0.0f64;
            for step in 1..=600 {
                space.step(Real::ONE / Real::from_int(60)).unwrap();
                worst = worst.max(worst_gap(&space));
                if step % 200 == 0 {
                    println!("{links} links, {end} kg, {solver:?}: step {step} gap {:.5} worst {worst:.5}", worst_gap(&space));
                }
            }
        }
    }
}

#[test]
#[ignore]
fn hanging_chain_variants() {
    let d = SoftStep::DEFAULT;
    let variants = [
        ("default", d),
        ("8 substeps", SoftStep { substeps: 8, ..d }),
        (
            "joint zeta 1",
            SoftStep {
                joint_damping_ratio: Real::ONE,
                ..d
            },
        ),
        (
            "joint zeta 5",
            SoftStep {
                joint_damping_ratio: real!(5),
                ..d
            },
        ),
        (
            "joint zeta 0.5",
            SoftStep {
                joint_damping_ratio: real!(0.5),
                ..d
            },
        ),
        (
            "8 substeps 120 hz",
            SoftStep {
                substeps: 8,
                joint_hertz: real!(120),
                ..d
            },
        ),
        (
            "8 substeps 120 hz zeta 5",
            SoftStep {
                substeps: 8,
                joint_hertz: real!(120),
                joint_damping_ratio: real!(5),
                ..d
            },
        ),
        (
            "4 substeps 120 hz",
            SoftStep {
                joint_hertz: real!(120),
                ..d
            },
        ),
        (
            "4 substeps 120 hz zeta 5",
            SoftStep {
                joint_hertz: real!(120),
                joint_damping_ratio: real!(5),
                ..d
            },
        ),
        (
            "4 substeps 120 hz zeta 1",
            SoftStep {
                joint_hertz: real!(120),
                joint_damping_ratio: real!(1),
                ..d
            },
        ),
    ];
    for (links, end) in [(20, 100), (100, 100)] {
        for (name, v) in variants {
            let (mut space, _) = hanging_chain(links, end, Solver::Soft(v));
            let mut worst = 0.0f64;
            for _ in 1..=600 {
                space.step(Real::ONE / Real::from_int(60)).unwrap();
                worst = worst.max(worst_gap(&space));
            }
            println!(
                "{links}/{end} {name}: worst {worst:.5} end {:.5}",
                worst_gap(&space)
            );
        }
    }
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

#[test]
#[ignore]
fn stacking_probe() {
    use tamias2d_scenes::{builtin, SoftStepDesc, SolverDesc};
    let names = std::env::var("PROBE_SCENES").unwrap_or("stack_10,pyramid_20".into());
    let slop = std::env::var("PROBE_SLOP").unwrap_or("0.005".into());
    let soft = SoftStepDesc(SoftStep {
        slop: Real::from_f64(slop.parse().unwrap()).unwrap(),
        ..SoftStep::DEFAULT
    });
    for name in names.split(',') {
        for (label, solver, colored) in [
            ("sequential", SolverDesc::Sequential, false),
            ("sequential colored", SolverDesc::Sequential, true),
            ("soft", SolverDesc::Soft(soft), false),
            ("soft colored", SolverDesc::Soft(soft), true),
        ] {
            let mut desc = builtin(name).unwrap();
            desc.settings.solver = solver;
            desc.settings.colored_solver = colored;
            let mut w = desc.build().unwrap();
            let start: Vec<(f64, f64)> = w
                .space
                .bodies()
                .map(|(_, b)| (b.position().x.to_f64(), b.position().y.to_f64()))
                .collect();
            let mut pen = 0.0f64;
            let t0 = std::time::Instant::now();
            for _ in 0..desc.steps.min(600) {
                w.step().unwrap();
                pen = pen.max(max_penetration(&w.space));
            }
            let el = t0.elapsed().as_secs_f64();
            let mut side = 0.0f64;
            let mut drop = 0.0f64;
            for ((_, b), (x0, y0)) in w.space.bodies().zip(&start) {
                side = side.max((b.position().x.to_f64() - x0).abs());
                drop = drop.max(y0 - b.position().y.to_f64());
            }
            println!(
                "{name} {label}: sideways {side:.5} drop {drop:.5} max pen {pen:.5} time {el:.3}s"
            );
        }
    }
}
