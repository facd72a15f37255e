//! The worst step a peer's bytes can cause under `Limits::UNTRUSTED`,
//! through each loading path, beside a normal step of the largest world
//! the limits admit (`docs/architecture.md`, "Untrusted input"):
//! `cargo run --release -p tamias2d-perf --bin untrusted_worst_step`.
//!
//! * normal: a lattice of touching circles (radius 0.5, 1 m apart) on a
//!   floor, as many as `max_bodies` admits, default settings;
//! * forged, refused at load: settings of 1,024 iterations × 64 sub-steps;
//!   3,000 circles within 7 mm of each other (4.5 million candidate pairs);
//! * forged, admitted: the lattice at the largest solver passes the limits
//!   admit, as iterations and as sub-steps (each sub-step collides again);
//!   a pile of circles all overlapping, as many as `max_pairs` admits, at
//!   those passes; the lattice with velocities that bring every circle to
//!   one point in one step (the step stops at the pair limit).
//!
//! Each is loaded as a full snapshot (`Space::load_snapshot`), as a frame
//! (`Space::load_frame_snapshot`, around the floor as the level) and as the
//! start of a one-frame replay (`Replay::verify_on`), then stepped once; the
//! time is the median of 5 samples of load + step.
use std::time::Instant;

use tamias2d::body::{Body, BodyHandle};
use tamias2d::limits::Limits;
use tamias2d::math::{Real, Vect};
use tamias2d::replay::{Recorder, Replay};
use tamias2d::shape::Shape;
use tamias2d::snapshot::{self, SnapshotError};
use tamias2d::space::{Settings, Space};
use tamias2d::Transform;

fn dt() -> Real {
    Real::ratio(1, 60)
}

/// A floor and `n` circles placed by `at(i)`, each moving by `vel(i)`.
fn world(n: u32, at: impl Fn(u32) -> Vect, vel: impl Fn(u32) -> Vect) -> Space {
    world_of(n, at, vel, |b| {
        Shape::circle_shape_new(b, Real::HALF, Vect::ZERO).expect("a circle")
    })
}

/// An octagon of diameter about 1 m (8 vertices: the costliest polygon).
fn octagon(b: BodyHandle) -> Shape {
    let pts: Vec<Vect> = [
        (2, 1),
        (1, 2),
        (-1, 2),
        (-2, 1),
        (-2, -1),
        (-1, -2),
        (1, -2),
        (2, -1),
    ]
    .iter()
    .map(|&(x, y)| Vect::new(Real::ratio(x, 4), Real::ratio(y, 4)))
    .collect();
    Shape::poly_shape_new(b, &pts, &Transform::IDENTITY, Real::ZERO).expect("an octagon")
}

/// [`world`] with the shape `shape` makes for each body.
fn world_of(
    n: u32,
    at: impl Fn(u32) -> Vect,
    vel: impl Fn(u32) -> Vect,
    shape: impl Fn(BodyHandle) -> Shape,
) -> Space {
    let mut w = Space::new();
    w.set_limits(Limits::TRUSTED);
    w.set_gravity(Vect::from_ints(0, -10));
    let floor = w.add_body(Body::new_static()).expect("floor body");
    let seg = Shape::segment_shape_new(
        floor,
        Vect::from_ints(-1000, 0),
        Vect::from_ints(1000, 0),
        Real::ZERO,
    )
    .expect("floor");
    w.add_shape(seg).expect("floor added");
    for i in 0..n {
        let b = w
            .add_body(Body::new(Real::ONE, Real::ONE).expect("a body"))
            .expect("body added");
        let body = w.body_mut(b).expect("the body");
        body.set_position(at(i));
        body.set_velocity(vel(i));
        w.add_shape(shape(b)).expect("shape added");
    }
    w
}

/// Touching circles in rows of 128, resting on the floor.
fn lattice_at(i: u32) -> Vect {
    let (col, row) = (i % 128, i / 128);
    Vect::new(
        Real::from_int(col as i32 - 64),
        Real::from_int(row as i32) + Real::HALF,
    )
}

fn with_passes(mut w: Space, iterations: u32, substeps: u32) -> Space {
    let settings = Settings {
        iterations,
        substeps,
        ..*w.settings()
    };
    w.set_settings(settings).expect("settings in range");
    w
}

fn median_ms(mut op: impl FnMut()) -> f64 {
    let mut samples: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            op();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[2]
}

/// Load through each path under the untrusted limits, then one step:
/// (path, ms, outcome).
fn attack(forged: &Space) -> Vec<(&'static str, f64, String)> {
    let snap = snapshot::save(forged);
    let frame = snapshot::save_frame(forged);
    let replay: Replay = {
        let mut rec = Recorder::new(forged, dt());
        // Recorded under the limits too (a forged step that the limits
        // stop is not run to its end here either).
        let mut copy = forged.clone();
        copy.set_limits(Limits::UNTRUSTED);
        let _ = copy.step(dt());
        rec.record_frame(&copy, &[]).expect("a frame");
        rec.finish()
    };
    let replay_bytes = replay.to_bytes();
    // The receiver: the same level (the floor), untrusted limits.
    let receiver = || {
        let mut w = world(0, lattice_at, |_| Vect::ZERO);
        w.set_limits(Limits::UNTRUSTED);
        w
    };
    type Load<'a> = Box<dyn Fn(&mut Space) -> Result<(), SnapshotError> + 'a>;
    let loads: [(&'static str, Load); 2] = [
        ("snapshot", Box::new(|w: &mut Space| w.load_snapshot(&snap))),
        (
            "frame",
            Box::new(|w: &mut Space| w.load_frame_snapshot(&frame)),
        ),
    ];
    let mut out = Vec::new();
    let mut outcome = String::new();
    for (path, load) in &loads {
        let ms = median_ms(|| {
            let mut w = receiver();
            outcome = match load(&mut w) {
                Err(e) => format!("refused: {e}"),
                Ok(()) => match w.step(dt()) {
                    Ok(()) => "stepped".into(),
                    Err(e) => format!("step refused: {e}"),
                },
            };
        });
        out.push((*path, ms, outcome.clone()));
    }
    let ms = median_ms(|| {
        let mut w = receiver();
        outcome = match Replay::from_bytes(&replay_bytes).and_then(|r| r.verify_on(&mut w)) {
            Err(e) => format!("refused: {e}"),
            Ok(r) => format!("verified {} frame", r.frames),
        };
    });
    out.push(("replay", ms, outcome));
    out
}

fn main() {
    let limits = Limits::UNTRUSTED;
    let n = u32::try_from(limits.max_bodies).unwrap_or(u32::MAX) - 1;
    let mut normal = world(n, lattice_at, |_| Vect::ZERO);
    limits
        .check_state(normal.state())
        .expect("the limits admit the normal world");
    normal.step(dt()).expect("first step");
    let normal_ms = median_ms(|| {
        let mut w = normal.clone();
        w.step(dt()).expect("a step");
    });
    println!("limits: {limits:?}");
    println!("normal step, {n} circles in a lattice: {normal_ms:.1} ms");

    let passes = u32::try_from(limits.max_solver_passes).unwrap_or(u32::MAX);
    let substeps = u32::try_from(limits.max_substeps).unwrap_or(u32::MAX);
    let per_substep = passes / substeps;
    // Pile: k circles on one spot, k(k-1)/2 pairs within max_pairs.
    let mut k = 2u32;
    while u64::from(k + 1) * u64::from(k) / 2 <= limits.max_pairs {
        k += 1;
    }
    let spot = |_| Vect::from_ints(0, 5);
    let centre_in_one_step = |i: u32| {
        let p = lattice_at(i);
        (Vect::from_ints(0, 5) - p) * Real::from_int(60)
    };
    let cases: Vec<(String, Space)> = vec![
        (
            "settings 1,024 iterations x 64 sub-steps".into(),
            with_passes(world(n, lattice_at, |_| Vect::ZERO), 1024, 64),
        ),
        (
            "3,000 circles within 7 mm".into(),
            world(
                3000,
                |i| {
                    Vect::new(
                        Real::from_bits(i64::from(i % 55) << 19),
                        Real::from_int(5) + Real::from_bits(i64::from(i / 55) << 19),
                    )
                },
                |_| Vect::ZERO,
            ),
        ),
        (
            format!("lattice at {passes} iterations (the limit)"),
            with_passes(world(n, lattice_at, |_| Vect::ZERO), passes, 1),
        ),
        (
            format!("{k} circles on one spot at {passes} iterations"),
            with_passes(world(k, spot, |_| Vect::ZERO), passes, 1),
        ),
        (
            format!("lattice at {substeps} sub-steps of {per_substep} iterations"),
            with_passes(world(n, lattice_at, |_| Vect::ZERO), per_substep, substeps),
        ),
        (
            format!("{k} circles on one spot at {substeps} sub-steps of {per_substep} iterations"),
            with_passes(world(k, spot, |_| Vect::ZERO), per_substep, substeps),
        ),
        (
            format!("{k} octagons on one spot at {substeps} sub-steps of {per_substep} iterations"),
            with_passes(
                world_of(k, spot, |_| Vect::ZERO, octagon),
                per_substep,
                substeps,
            ),
        ),
        (
            "lattice converging on one point in one step".into(),
            world(n, lattice_at, centre_in_one_step),
        ),
    ];
    let mut worst = 0.0f64;
    for (name, forged) in &cases {
        println!("{name}:");
        for (path, ms, outcome) in attack(forged) {
            worst = worst.max(ms);
            println!(
                "  {path:8} {ms:9.1} ms  {:5.2}x normal  {outcome}",
                ms / normal_ms
            );
        }
    }
    println!(
        "worst: {worst:.1} ms = {:.2}x a normal step of the largest world",
        worst / normal_ms
    );
}
