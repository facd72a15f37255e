//! The envelope report: every measured number of the "Safe envelope" and
//! "Comparison with f32 and f64 engines" sections of `docs/numerics.md`,
//! printed as the tables pasted there (release builds only, about 45 s; an
//! ignored test, since it prints rather than checks):
//!
//! ```text
//! cargo test --release --test extremes -- --nocapture envelope_report
//! ```
//!
//! The measurements are the ones the extreme-scene tests assert bounds on
//! (`diagnostics.rs`, `translation.rs`,
//! `scale.rs`, `motion.rs`; shared helpers in
//! `common.rs`). Everything except the timings is
//! deterministic, so a change in a pasted table means the engine's numbers
//! changed. The format limits and the position resolution are cheap and
//! follow from the format alone, so they are also checked here, on every
//! `cargo test`, against their formulas.
#![allow(clippy::float_arithmetic)]

use std::hint::black_box;
use std::time::Instant;

use super::common::{
    box_body, build, coincident, compare_shifted, int, lone_ball, mass_ratio_pair,
    run_displacement, separate, similarity_error, stack_with_dt, trace_x, tunnel_count,
    worst_displacement, x_vect, Watch, FRICTION,
};
use tamias2d::body::Body;
use tamias2d::real;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{self as scenes, BodyDesc, SceneDesc, SceneError, ShapeDesc};

/// One ulp of `Real` (2^-32) as an `f64`.
const ULP: f64 = 1.0 / 4_294_967_296.0;

// ---------------------------------------------------------------------------
// The envelope report (docs/numerics.md, "Safe envelope").
// ---------------------------------------------------------------------------

#[test]
#[ignore = "report (about 40 s): cargo test --release --test extremes -- --ignored --nocapture envelope_report"]
fn envelope_report() {
    report_format_limits();
    report_position_resolution();
    report_translation();
    report_relative_distance();
    report_mass_properties();
    report_similarity();
    report_mass_ratios();
    report_tunnelling();
    report_coincident();
    report_time_steps();
    report_long_rest();
    report_diagnostics();
    report_cost();
}

/// The largest value in `[lo, hi]` for which `ok` holds, assuming `ok` is
/// monotone (true, then false), to 2^-20 of a unit.
fn bisect(mut lo: f64, mut hi: f64, ok: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

fn r(v: f64) -> Real {
    Real::from_f64(v).unwrap_or_else(|e| panic!("{v}: {e}"))
}

/// Mass and moment of a dynamic square box of `side` at `density`, or the
/// scene error (massless).
fn box_mass(side: Real, density: Real) -> Result<(Real, Real), SceneError> {
    let mut d = SceneDesc::new("box", Real::ratio(1, 60), 0);
    d.bodies.push(box_body(Vect::ZERO, side, density));
    let s = d.build()?;
    let h = s.bodies()[0];
    Ok(s.space
        .body(h)
        .map_or((Real::ZERO, Real::ZERO), |b| (b.mass(), b.moment())))
}

/// The format limits of the envelope, computed with the engine's own
/// operations.
struct FormatLimits {
    /// Largest `x` with `x·x` unsaturated.
    square: f64,
    /// Largest speed for which `kinetic_energy()` of 1 kg is right to 10^-6.
    kinetic: f64,
    /// Per density: the side above which a square box's moment saturates,
    /// and the side below which its moment rounds to 0 (massless).
    boxes: Vec<(f64, f64, f64)>,
}

fn format_limits() -> FormatLimits {
    let square = bisect(1.0, 1e6, |x| !(r(x) * r(x)).is_saturated());
    let kinetic = bisect(1.0, 1e7, |v| {
        let mut b = Body::new(Real::ONE, Real::ONE).unwrap_or_else(|e| panic!("{e}"));
        b.set_velocity(Vect::new(r(v), Real::ZERO));
        let exact = 0.5 * r(v).to_f64() * r(v).to_f64();
        (b.kinetic_energy().to_f64() - exact).abs() <= 1e-6 * exact
    });
    let boxes = [1.0, 1000.0]
        .into_iter()
        .map(|density| {
            let big = bisect(1.0, 10_000.0, |s| {
                box_mass(r(s), r(density)).is_ok_and(|(_, i)| !i.is_saturated())
            });
            let small = bisect(1e-5, 1.0, |s| box_mass(r(s), r(density)).is_err());
            (density, big, small)
        })
        .collect();
    FormatLimits {
        square,
        kinetic,
        boxes,
    }
}

/// The limits are where the format says they are: I32F32 holds values
/// below 2^31 and rounds below half an ulp (2^-33) to 0, so `x·x` saturates
/// at x = 2^15.5, ½·m·v² (1 kg) at v = 2^16, and a square box's moment
/// ρ·s⁴/6 saturates at s = (6·2^31/ρ)^¼ and rounds to 0 below
/// s = (6·2^-33/ρ)^¼. Each measured limit must match its formula to 10^-4
/// relative, plus, for the tiny boxes, what rounding the moment per unit
/// mass s²/6 can move the threshold: an ulp of s²/6 is a relative error of
/// ulp·6/s² in the moment, so a quarter of that in the side.
#[test]
fn format_limits_follow_from_the_format() {
    let near_within = |measured: f64, formula: f64, rel: f64, what: &str| {
        assert!(
            (measured - formula).abs() <= rel * formula,
            "{what}: measured {measured}, formula {formula}"
        );
    };
    let near = |measured: f64, formula: f64, what: &str| {
        near_within(measured, formula, 1e-4, what);
    };
    let limits = format_limits();
    near(limits.square, 2f64.powf(15.5), "x·x");
    near(limits.kinetic, 2f64.powi(16), "kinetic energy");
    for &(density, big, small) in &limits.boxes {
        near(
            big,
            (6.0 * 2f64.powi(31) / density).powf(0.25),
            "moment saturates",
        );
        let formula = (6.0 * 2f64.powi(-33) / density).powf(0.25);
        let rounding = ULP * 6.0 / (formula * formula) / 4.0;
        near_within(small, formula, 1e-4 + rounding, "moment rounds to 0");
    }
}

fn report_format_limits() {
    println!("## Format limits (computed with the engine's own operations)\n");
    println!("| quantity | value |\n|---|---|");
    println!("| range | ±{} |", Real::MAX.to_f64().round());
    println!("| resolution (1 ulp) | {ULP:.3e} |");
    let limits = format_limits();
    println!("| largest x with x·x unsaturated | {:.2} |", limits.square);
    println!(
        "| f32 / f64: significant bits, smallest normal value | {} / {}, {:.1e} / {:.1e} |",
        f32::MANTISSA_DIGITS,
        f64::MANTISSA_DIGITS,
        f32::MIN_POSITIVE,
        f64::MIN_POSITIVE
    );
    println!(
        "| largest speed for which `kinetic_energy()` is right, 1 kg | {:.0} m/s |",
        limits.kinetic
    );
    for (density, big, small) in limits.boxes {
        println!("| square box at density {density}: moment saturates above side | {big:.1} m |");
        println!(
            "| square box at density {density}: massless (moment rounds to 0) below side | {small:.2e} m |"
        );
    }
    println!();
}

/// Distances from the origin of the position-resolution table.
const SLIDE_STARTS: [(f64, &str); 4] = [
    (1.0, "1"),
    (1e4, "10^4"),
    (1e6, "10^6"),
    (1_073_741_824.0, "2^30"),
];

/// How far 60 steps of `x += v·dt` (v = 1 m/s, dt = 1/60 s) move a point
/// starting at `x0`, in I32F32.
fn slide(x0: f64) -> Real {
    let (mut x, dt, v) = (r(x0), Real::ratio(1, 60), Real::ONE);
    for _ in 0..60 {
        x += v * dt;
    }
    x - r(x0)
}

/// Fixed point has one resolution everywhere: the slide moves a point by
/// exactly 60 times the rounded step, wherever it starts (float steps grow
/// with the distance from the origin).
#[test]
fn a_slide_moves_the_same_distance_at_every_distance_from_the_origin() {
    let step = Real::ratio(1, 60);
    let expected = Real::from_bits(step.to_bits() * 60);
    for (x0, label) in SLIDE_STARTS {
        assert_eq!(slide(x0), expected, "from {label}");
    }
}

fn report_position_resolution() {
    println!("## Position resolution and a 1 m/s slide (60 steps of x += v·dt)\n");
    println!(
        "| distance from origin (m) | I32F32 step | f64 step | f32 step | I32F32 moved | f64 moved | f32 moved |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (x0, label) in SLIDE_STARTS {
        let ulp32 = f64::from(f32::from_bits((x0 as f32).to_bits() + 1) - x0 as f32);
        let ulp64 = f64::from_bits(x0.to_bits() + 1) - x0;
        let (mut x64, mut x32) = (x0, x0 as f32);
        for _ in 0..60 {
            x64 += 1.0 / 60.0;
            x32 += 1.0f32 / 60.0;
        }
        println!(
            "| {label} | {ULP:.1e} | {ulp64:.1e} | {ulp32:.1e} | {:.9} | {:.9} | {:.9} |",
            slide(x0).to_f64(),
            x64 - x0,
            f64::from(x32) - x0
        );
    }
    println!();
}

fn report_translation() {
    println!("## Translation (600 steps; every body and contact compared after every step)\n");
    println!("| scene | shift | bodies | bit-identical | max jump (m) | saturated |");
    println!("|---|---|---|---|---|---|");
    let edge = (1i64 << 31) - 16;
    let shifts = [10_000, 1_000_000, 1 << 30, -(1 << 30), edge, -edge];
    for desc in [scenes::accuracy::stack(5), scenes::stacking::pyramid(10)] {
        for x in shifts {
            let out = compare_shifted(&desc, x_vect(x), 600);
            println!(
                "| {} | x + {x} | {} | {} | {:.4} | {} |",
                desc.name,
                out.bodies,
                match out.first_mismatch {
                    None => "yes".to_owned(),
                    Some(i) => format!("no (step {i})"),
                },
                out.watch.max_jump,
                out.watch.saturated
            );
        }
    }
    println!();
}

fn report_relative_distance() {
    println!("## Relative distance: a unit box resting 10 m from the end of a long ground segment, and on a static circle (300 steps)\n");
    println!("| ground | box displacement (m) |\n|---|---|");
    for half in [500i64, 50_000, 5_000_000, 1 << 30] {
        let mut d = scenes::accuracy::stack(0);
        let h = Real::from_bits((half << 32) - 1);
        d.bodies[0].shapes[0] = ShapeDesc::segment(
            Vect::new(-h, Real::ZERO),
            Vect::new(h, Real::ZERO),
            Real::ZERO,
        )
        .material(FRICTION, Real::ZERO);
        d.bodies.push(box_body(
            Vect::new(h - int(10), Real::HALF),
            Real::ONE,
            Real::ONE,
        ));
        let mut s = build(&d);
        let (moved, _) = run_displacement(&mut s, 300);
        println!("| segment {} m long | {moved:.7e} |", 2 * half);
    }
    for radius in [100i64, 10_000, 1_000_000] {
        let mut d = scenes::accuracy::stack(0);
        d.bodies[0].shapes[0] = ShapeDesc::circle(int(radius)).material(FRICTION, Real::ZERO);
        d.bodies.push(box_body(
            Vect::new(Real::ZERO, int(radius) + Real::HALF),
            Real::ONE,
            Real::ONE,
        ));
        let mut s = build(&d);
        let (moved, _) = run_displacement(&mut s, 300);
        println!("| circle of radius {radius} m | {moved:.7e} |");
    }
    println!();
}

fn report_mass_properties() {
    println!("## Mass properties of a square box (engine vs exact)\n");
    println!(
        "| side (m) | density | mass | rel. error of mass | moment | rel. error of moment | note |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (side, density) in [
        (0.001, 1.0),
        (0.001, 1000.0),
        (0.01, 1.0),
        (0.01, 1000.0),
        (0.1, 1.0),
        (1.0, 1.0),
        (10.0, 1.0),
        (100.0, 1.0),
        (300.0, 1.0),
        (400.0, 1.0),
        (100.0, 1000.0),
    ] {
        let (sr, dr) = (r(side), r(density));
        let (s, dn) = (sr.to_f64(), dr.to_f64());
        let m_exact = dn * s * s;
        let i_exact = m_exact * 2.0 * s * s / 12.0;
        match box_mass(sr, dr) {
            Ok((m, i)) => {
                let note = if i.is_saturated() {
                    "moment saturated"
                } else {
                    ""
                };
                println!(
                    "| {side} | {density} | {:.4e} | {:.1e} | {:.4e} | {:.1e} | {note} |",
                    m.to_f64(),
                    (m.to_f64() - m_exact).abs() / m_exact,
                    i.to_f64(),
                    (i.to_f64() - i_exact).abs() / i_exact
                );
            }
            Err(e) => println!("| {side} | {density} | | | | | error: {e} |"),
        }
    }
    println!("\n## Mass and inverse mass as `Real`\n");
    println!("| mass (kg) | rel. error of mass | rel. error of 1/mass |\n|---|---|---|");
    for m in [1e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6, 1e8, 1e9] {
        let mr = r(m);
        let inv = mr.recip().to_f64();
        println!(
            "| {m:.0e} | {:.1e} | {:.1e} |",
            (mr.to_f64() - m).abs() / m,
            (inv - 1.0 / m).abs() * m
        );
    }
    println!();
}

fn report_similarity() {
    println!("## Similar scenes: stack_5 with lengths, gravity and slop scaled by k, vs the unit stack (600 steps)\n");
    println!("| k | density | box mass | box moment | worst difference (box sizes) | at step |");
    println!("|---|---|---|---|---|---|");
    let k_values = [
        (Real::from_bits(4_294_967), "0.001"),
        (real!(0.01), "0.01"),
        (real!(0.1), "0.1"),
        (Real::HALF, "0.5"),
        (Real::TWO, "2"),
        (Real::from_int(10), "10"),
        (Real::from_int(100), "100"),
        (Real::from_int(1000), "1000"),
    ];
    for (k, label) in k_values {
        for density in [Real::ONE, (k * k).recip()] {
            let mass = box_mass(k, density);
            let (m, i) = mass.map_or((String::new(), String::new()), |(m, i)| {
                (format!("{:.3e}", m.to_f64()), format!("{:.3e}", i.to_f64()))
            });
            match similarity_error(5, k, density, 600, true) {
                Ok((err, at)) => println!(
                    "| {label} | {:.4e} | {m} | {i} | {err:.2e} | {at} |",
                    density.to_f64()
                ),
                Err(e) => println!("| {label} | {:.4e} | | | error: {e} | |", density.to_f64()),
            }
        }
    }
    // Why k > 1 differs: the first step where k = 2 leaves the unit stack,
    // and the unit scene's contacts with a positive separation just before.
    let (step, kept) = first_divergence_k2();
    println!(
        "\nk = 2 first differs after step {step}; unit-scene contacts kept at a positive separation just before (ulp): {kept:?} (tolerance {} ulp)",
        1 << 12
    );
    println!();
}

/// Runs the unit stack_5 and the k = 2 similar stack side by side; returns
/// the first step after which they differ by more than 10^-7 box sizes and
/// the positive contact separations (ulp) of the unit scene before it.
fn first_divergence_k2() -> (u32, Vec<i64>) {
    let mut unit = build(&super::common::scaled_stack(5, Real::ONE, Real::ONE));
    let mut two = build(&super::common::scaled_stack(5, Real::TWO, real!(0.25)));
    for i in 1..=600 {
        let kept: Vec<i64> = unit
            .space
            .arbiters()
            .iter()
            .flat_map(|a| a.contacts().iter().map(|c| c.dist.to_bits()))
            .filter(|&d| d > 0)
            .collect();
        unit.step().unwrap_or_else(|e| panic!("{e}"));
        two.step().unwrap_or_else(|e| panic!("{e}"));
        let differs = unit
            .space
            .bodies()
            .zip(two.space.bodies())
            .any(|((_, u), (_, t))| {
                let d = t.position().to_f64();
                let e = u.position().to_f64();
                (d.0 / 2.0 - e.0).abs().max((d.1 / 2.0 - e.1).abs()) > 1e-7
            });
        if differs {
            return (i, kept);
        }
    }
    (0, Vec::new())
}

/// A point (a circle of radius 0, 1 kg) starting `offset` m above y = 1
/// (offsets of k/32 of one step's travel),
/// falling at 1 m/s without gravity onto a ground segment of radius 0:
/// true if it ends below the segment.
fn point_passes_segment(offset: Real) -> bool {
    let mut d = scenes::accuracy::stack(0);
    d.settings.gravity = Vect::ZERO;
    let body = BodyDesc::dynamic(
        Vect::new(Real::ZERO, Real::ONE + offset),
        Real::ONE,
        Real::ONE,
    )
    .moving(Vect::from_ints(0, -1))
    .with_shape(ShapeDesc::circle(Real::ZERO));
    d.bodies.push(body);
    let mut s = build(&d);
    let h = s.bodies()[1];
    Watch::run(&mut s, 180);
    s.space
        .body(h)
        .is_some_and(|b| b.position().y.is_negative())
}

fn report_mass_ratios() {
    println!(
        "## Mass ratios: two unit boxes on the ground, worst displacement over 600 steps (m)\n"
    );
    println!("| lower : upper density | 10 iterations | 30 | 100 | 300 |\n|---|---|---|---|---|");
    let pairs = [
        (1, 10),
        (1, 100),
        (1, 300),
        (1, 1_000),
        (1, 1_000_000),
        (1_000, 1),
        (1_000_000, 1),
    ];
    for (lower, upper) in pairs {
        let cells: Vec<String> = [10, 30, 100, 300]
            .iter()
            .map(|&it| {
                let mut s = build(&mass_ratio_pair(lower, upper, it));
                let (moved, w) = run_displacement(&mut s, 600);
                let sat = if w.saturated > 0 { " (saturated)" } else { "" };
                format!("{moved:.4}{sat}")
            })
            .collect();
        println!("| {lower} : {upper} | {} |", cells.join(" | "));
    }
    println!();
}

fn report_tunnelling() {
    println!(
        "## Tunnelling: ball r = 0.5 m, dt = 1/60 s, 32 start phases; passes of 32 (predicted)\n"
    );
    println!("| travel per step | speed (m/s) | thin segment | 1 m thick box |\n|---|---|---|---|");
    for (num, den) in [
        (1, 2),
        (9, 10),
        (1, 1),
        (11, 10),
        (3, 2),
        (2, 1),
        (21, 10),
        (5, 2),
        (3, 1),
        (4, 1),
    ] {
        let s = f64::from(num) / f64::from(den);
        let pred = |window: f64| 32.0 * (1.0 - window / s).max(0.0);
        println!(
            "| {s:.1} r | {:.0} | {} ({:.1}) | {} ({:.1}) |",
            30.0 * s,
            tunnel_count(num, den, false, 32),
            pred(1.0),
            tunnel_count(num, den, true, 32),
            pred(2.0)
        );
    }
    // A point (circle of radius 0) falling at 1 m/s onto the thin segment.
    let passes = (0..32)
        .filter(|&k| point_passes_segment(Real::ratio(k, 32 * 60)))
        .count();
    println!("\nA point (circle of radius 0) at 1 m/s onto the thin segment (radius 0): passes {passes} of 32.");
    println!();
}

fn report_coincident() {
    println!("## 100 bodies spawned at one point, no gravity\n");
    println!("| bodies | steps | separated to the slop at step | deepest overlap (m) | max speed (m/s) | max jump (m) | extent in x, y (m) |");
    println!("|---|---|---|---|---|---|---|");
    for boxes in [true, false] {
        for steps in [600, 3_000, 20_000] {
            let mut s = build(&coincident(100, boxes));
            let (w, sep, deepest, xmax, ymax) = separate(&mut s, steps);
            println!(
                "| {} | {steps} | {} | {deepest:.4} | {:.1e} | {:.3} | {xmax:.2}, {ymax:.2} |",
                if boxes { "1 m boxes" } else { "r 0.5 circles" },
                sep.map_or("—".to_owned(), |i| i.to_string()),
                w.max_speed,
                w.max_jump
            );
        }
    }
    println!();
}

fn report_time_steps() {
    println!("## Time steps\n");
    println!("| dt (s) | rel. rounding of dt | stack_5, 10 s: worst displacement (m) | max speed (m/s) | same, 30 iterations (m) |");
    println!("|---|---|---|---|---|");
    for den in [10_000, 1_000, 60, 30, 20, 15, 10] {
        let dt = Real::ratio(1, den);
        let rel = (dt.to_f64() - 1.0 / f64::from(den)).abs() * f64::from(den);
        let steps = 10 * den as u32;
        let mut s = build(&stack_with_dt(5, dt, 10));
        let (moved, w) = run_displacement(&mut s, steps);
        let mut s30 = build(&stack_with_dt(5, dt, 30));
        let (moved30, _) = run_displacement(&mut s30, steps);
        println!(
            "| 1/{den} | {rel:.1e} | {moved:.3e} | {:.3} | {moved30:.3e} |",
            w.max_speed
        );
    }
    println!("\nFree fall (g = 9.81) for 1 s:\n");
    println!("| dt (s) | error vs discrete form, rounded dt (m) | error vs discrete form, nominal dt (m) | integrator lag ½·g·dt·t (m) |");
    println!("|---|---|---|---|");
    for den in [60u32, 1_000, 10_000] {
        let mut desc = scenes::accuracy::free_fall();
        let dt = Real::ratio(1, den as i32);
        desc.dt = dt;
        let mut s = build(&desc);
        let ball = s.body("ball").unwrap_or_else(|| panic!("ball"));
        Watch::run(&mut s, den);
        let y = s.space.body(ball).map_or(0.0, |b| b.position().y.to_f64());
        let n = f64::from(den);
        let form = |dt: f64| 100.0 - 9.81 * dt * dt * n * (n - 1.0) / 2.0;
        println!(
            "| 1/{den} | {:.1e} | {:.1e} | {:.1e} |",
            (y - form(dt.to_f64())).abs(),
            (y - form(1.0 / n)).abs(),
            0.5 * 9.81 / n
        );
    }
    println!(
        "\nCollision bias is per second (`bias^dt` per step). Smallest non-zero bias is 1 ulp:\n"
    );
    println!("| dt (s) | largest correction per step with bias ≥ 1 ulp | default 0.9^60 gives | bias 0 gives |\n|---|---|---|---|");
    for den in [60, 600, 10_000] {
        let dt = Real::ratio(1, den);
        let min_bias = Real::ONE - tamias2d::math::exp::pow(Real::DELTA, dt);
        let default =
            Real::ONE - tamias2d::math::exp::pow(tamias2d::space::DEFAULT_COLLISION_BIAS, dt);
        let zero = Real::ONE - tamias2d::math::exp::pow(Real::ZERO, dt);
        println!(
            "| 1/{den} | {:.4} | {:.4} | {:.4} |",
            min_bias.to_f64(),
            default.to_f64(),
            zero.to_f64()
        );
    }
    println!();
}

fn report_long_rest() {
    println!("## stack_3 at rest for 10^5 steps\n");
    let mut s = build(&scenes::accuracy::stack(3));
    let w0 = Watch::run(&mut s, 10_000);
    let settled = super::common::positions(&s.space);
    let mut creep = 0.0f64;
    let mut ke = 0.0f64;
    let mut w = Watch::new(&s.space);
    for _ in 0..90 {
        w.step(&mut s, 1_000);
        creep = creep.max(worst_displacement(&settled, &s.space));
        let e: f64 = s
            .space
            .bodies()
            .map(|(_, b)| b.kinetic_energy().to_f64())
            .sum();
        ke = ke.max(e);
    }
    println!("| quantity | value |\n|---|---|");
    println!(
        "| max speed, first 10^4 steps (settling) | {:.4} m/s |",
        w0.max_speed
    );
    println!("| max displacement from step 10^4 to 10^5 | {creep:.3e} m |");
    println!(
        "| max speed, steps 10^4 to 10^5 | {:.3e} m/s |",
        w.max_speed
    );
    println!("| max kinetic energy at 1000-step samples | {ke:.3e} J |");
    println!();
}

fn report_diagnostics() {
    println!("## Diagnostics: `StepStats::saturated_bodies`\n");
    let v = Real::from_bits(i64::MAX - 1);
    let mut s = lone_ball(Vect::ZERO, Vect::new(v, Real::ZERO));
    let trace = trace_x(&mut s, 70);
    let first = trace
        .iter()
        .position(|&(_, n)| n > 0)
        .map_or("never".to_owned(), |i| (i + 1).to_string());
    let last = trace.last().map_or(Real::ZERO, |t| t.0);
    println!(
        "- ball from the origin at (2^31 − 2 ulp) m/s: first counted at step {first}, x = {last}"
    );
    let mut s = lone_ball(
        Vect::new(int((1 << 31) - 10), Real::ZERO),
        Vect::from_ints(1000, 0),
    );
    let trace = trace_x(&mut s, 1);
    println!(
        "- ball 10 m from the edge at 1000 m/s: step 1 x = {}, counted {}",
        trace[0].0, trace[0].1
    );
    let mut s = build(&scenes::builtin("pyramid_100").unwrap_or_else(|| panic!("pyramid_100")));
    s.step_n(10).unwrap_or_else(|e| panic!("{e}"));
    let t = Instant::now();
    s.step_n(20).unwrap_or_else(|e| panic!("{e}"));
    let step = t.elapsed() / 20;
    let t = Instant::now();
    let mut n = 0;
    for _ in 0..100 {
        n += black_box(&s.space)
            .bodies()
            .filter(|(_, b)| {
                b.center().is_saturated()
                    || b.velocity().is_saturated()
                    || b.angular_velocity().is_saturated()
            })
            .count();
    }
    let count = t.elapsed() / 100;
    println!("- pyramid_100 (5051 bodies): one step {step:?}; the counting loop (public API) {count:?}; counted {n}");
    println!();
}

fn report_cost() {
    println!("## Cost of the arithmetic (this machine, release, ns per operation, indicative)\n");
    const N: usize = 4096;
    const REPS: usize = 2_000;
    let xs: Vec<f64> = (0..N).map(|i| 1.0 + (i as f64) * 0.37).collect();
    let rs: Vec<Real> = xs.iter().map(|&x| r(x)).collect();
    let fs: Vec<f32> = xs.iter().map(|&x| x as f32).collect();
    let time = |f: &dyn Fn() -> f64| {
        let t = Instant::now();
        black_box(f());
        t.elapsed().as_secs_f64() * 1e9 / (N * REPS) as f64
    };
    let real_mul = time(&|| {
        let mut acc = Real::ZERO;
        for _ in 0..REPS {
            for w in black_box(&rs).windows(2) {
                acc += w[0] * w[1];
            }
        }
        acc.to_f64()
    });
    let f64_mul = time(&|| {
        let mut acc = 0.0;
        for _ in 0..REPS {
            for w in black_box(&xs).windows(2) {
                acc += w[0] * w[1];
            }
        }
        acc
    });
    let f32_mul = time(&|| {
        let mut acc = 0.0f32;
        for _ in 0..REPS {
            for w in black_box(&fs).windows(2) {
                acc += w[0] * w[1];
            }
        }
        f64::from(acc)
    });
    let real_div = time(&|| {
        let mut acc = Real::ZERO;
        for _ in 0..REPS {
            for w in black_box(&rs).windows(2) {
                acc += w[0] / w[1];
            }
        }
        acc.to_f64()
    });
    let f64_div = time(&|| {
        let mut acc = 0.0;
        for _ in 0..REPS {
            for w in black_box(&xs).windows(2) {
                acc += w[0] / w[1];
            }
        }
        acc
    });
    let f32_div = time(&|| {
        let mut acc = 0.0f32;
        for _ in 0..REPS {
            for w in black_box(&fs).windows(2) {
                acc += w[0] / w[1];
            }
        }
        f64::from(acc)
    });
    let real_sqrt = time(&|| {
        let mut acc = Real::ZERO;
        for _ in 0..REPS {
            for x in black_box(&rs) {
                acc += x.sqrt();
            }
        }
        acc.to_f64()
    });
    let f64_sqrt = time(&|| {
        let mut acc = 0.0;
        for _ in 0..REPS {
            for x in black_box(&xs) {
                acc += x.sqrt();
            }
        }
        acc
    });
    let f32_sqrt = time(&|| {
        let mut acc = 0.0f32;
        for _ in 0..REPS {
            for x in black_box(&fs) {
                acc += x.sqrt();
            }
        }
        f64::from(acc)
    });
    println!("| operation (+ accumulate) | I32F32 | f64 | f32 |\n|---|---|---|---|");
    println!("| a·b | {real_mul:.2} | {f64_mul:.2} | {f32_mul:.2} |");
    println!("| a/b | {real_div:.2} | {f64_div:.2} | {f32_div:.2} |");
    println!("| sqrt | {real_sqrt:.2} | {f64_sqrt:.2} | {f32_sqrt:.2} |");
    println!();
}
