//! The error measures: what each scene's result is compared with.
//!
//! Closed forms are the *continuous* answers (½gt², v = at, …), so the
//! integrator's own discretisation error is part of what is measured: it is
//! what a game gets, and what a smaller step buys back. Every function reads
//! the engine through [`Engine`], so both engines are measured the same way.
use super::{BodyState, Engine, Penetration};

/// Standard gravity of the SI accuracy scenes.
const G: f64 = 9.81;

/// One error measure of a scene.
#[derive(Clone, Copy, Debug)]
pub struct Measure {
    /// Short name for tables.
    pub name: &'static str,
    /// Unit (or "rel." for relative errors).
    pub unit: &'static str,
}

/// The measures of scene `name`, in the order [`errors`] returns them.
pub fn measures(name: &str) -> &'static [Measure] {
    macro_rules! m {
        ($name:expr, $unit:expr) => {
            Measure {
                name: $name,
                unit: $unit,
            }
        };
    }
    match name {
        "pyramid_20" | "pyramid_100" | "many_pyramids_4x4" | "many_pyramids_10x10" => &[
            m!("max box displacement", "m"),
            m!("max horizontal drift", "m"),
            m!("max box rotation", "rad"),
        ],
        "bowl_boxes_500" | "bowl_boxes_100" => &[
            m!("mean penetration", "units"),
            m!("max penetration", "units"),
        ],
        "free_fall" => &[m!("|y − (y0 − ½gt²)|", "m")],
        "constant_force" => &[m!("|x − (x0 + ½(F/m)t²)|", "m")],
        "projectile_45" | "projectile_60" => &[m!("|p − (p0 + v0·t + ½gt²)|", "m")],
        "spin" => &[m!("|φ − ½τt²/I|", "rad")],
        "elastic_pair" => &[
            m!("energy error", "rel."),
            m!("velocity exchange error", "m/s"),
        ],
        "newtons_cradle" => &[m!("energy error", "rel."), m!("|v_last − v0|", "m/s")],
        "incline_slide" => &[m!("acceleration error", "rel.")],
        "incline_stick" => &[m!("slip along the slope", "m")],
        "stack_10" => &[m!("top box |x| drift", "m")],
        "bullets" => &[m!("bullets beyond the wall", "of 32")],
        _ => &[],
    }
}

/// Seconds of simulated time each sweep run of `name` covers.
pub fn sweep_seconds(name: &str) -> f64 {
    match name {
        "pyramid_20" | "stack_10" | "projectile_45" | "projectile_60" | "spin" => 10.0,
        "bowl_boxes_500" | "bowl_boxes_100" => 8.0,
        "newtons_cradle" | "bullets" => 2.0,
        "incline_slide" | "incline_stick" => 3.0,
        _ => 4.0, // free_fall, constant_force, elastic_pair
    }
}

/// Seconds at the end of a run over which penetration is accumulated.
pub const PENETRATION_WINDOW: f64 = 2.0;

/// The errors of scene `name` after `t` seconds: `init` are the body
/// states at t = 0, `pen` the penetration accumulated over the last
/// [`PENETRATION_WINDOW`] seconds.
pub fn errors(
    name: &str,
    init: &[BodyState],
    engine: &dyn Engine,
    t: f64,
    pen: Penetration,
) -> Vec<f64> {
    let b = |i: usize| engine.body(i);
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    match name {
        "pyramid_20" | "pyramid_100" | "many_pyramids_4x4" | "many_pyramids_10x10" => {
            let d = drift(init, engine);
            vec![d.displacement, d.horizontal, d.rotation]
        }
        "bowl_boxes_500" | "bowl_boxes_100" => vec![pen.mean(), pen.max],
        "free_fall" => vec![(b(0).position[1] - (100.0 - 0.5 * G * t * t)).abs()],
        "constant_force" => vec![(b(0).position[0] - (20.0 + 0.5 * 10.0 * t * t)).abs()],
        "projectile_45" | "projectile_60" => {
            let (p0, v0, g) = if name == "projectile_45" {
                ([0.0, 0.0], [848.5, 848.5], -100.0)
            } else {
                ([50.0, 50.0], [150.0, 260.0], -40.0)
            };
            let exact = [p0[0] + v0[0] * t, p0[1] + v0[1] * t + 0.5 * g * t * t];
            vec![dist(b(0).position, exact)]
        }
        "spin" => {
            // Rapier reports angles in (−π, π]: compare modulo a turn.
            let inertia = 0.5 * (100.0f64 * 100.0 + 100.0 * 100.0) / 12.0;
            vec![wrap(b(0).angle - 0.5 * 100.0 * t * t / inertia).abs()]
        }
        "elastic_pair" => {
            let e = engine.kinetic_energy();
            let (va, vb) = (b(0).velocity, b(1).velocity);
            let dv = dist(va, [-1.0, 0.0]) + dist(vb, [3.0, 0.0]);
            vec![(e - 5.0).abs() / 5.0, dv]
        }
        "newtons_cradle" => {
            let e = engine.kinetic_energy();
            vec![(e - 2.0).abs() / 2.0, dist(b(4).velocity, [2.0, 0.0])]
        }
        "incline_slide" => {
            let theta = 30f64.to_radians();
            let expected = G * (theta.sin() - 0.2 * theta.cos());
            // Velocity down the slope; the box starts at rest, so a = v/t.
            let v = b(1).velocity;
            let down = -(v[0] * theta.cos() + v[1] * theta.sin());
            vec![(down / t - expected).abs() / expected]
        }
        "incline_stick" => {
            // Slip along the slope only: the displacement projected on the
            // slope's direction. The part normal to the slope is the box
            // settling into the contact (within the slop), not a slip.
            let theta = 30f64.to_radians();
            let (p, p0) = (b(1).position, init[1].position);
            let along = (p[0] - p0[0]) * theta.cos() + (p[1] - p0[1]) * theta.sin();
            vec![along.abs()]
        }
        "stack_10" => {
            let top = engine.body_count() - 1;
            vec![(b(top).position[0] - init[top].position[0]).abs()]
        }
        "bullets" => {
            // Ground, wall and 12 boxes, then the bullets; the wall is at x = 0.
            let beyond = (14..engine.body_count())
                .filter(|&i| b(i).position[0] > 0.0)
                .count();
            vec![beyond as f64]
        }
        _ => Vec::new(),
    }
}

/// `a` brought into [−π, π).
fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    (a + PI).rem_euclid(TAU) - PI
}

/// How far the dynamic bodies moved from where they started.
#[derive(Clone, Copy, Debug, Default)]
pub struct Drift {
    /// Largest displacement (m).
    pub displacement: f64,
    /// Largest horizontal displacement (m): creep, as opposed to the
    /// vertical settling of a pile under its weight.
    pub horizontal: f64,
    /// Largest rotation (rad).
    pub rotation: f64,
}

/// The [`Drift`] of the dynamic bodies since `init`.
pub fn drift(init: &[BodyState], engine: &dyn Engine) -> Drift {
    let mut out = Drift::default();
    for (i, s0) in init.iter().enumerate().filter(|(_, s)| s.dynamic) {
        let s = engine.body(i);
        let (dx, dy) = (
            s.position[0] - s0.position[0],
            s.position[1] - s0.position[1],
        );
        out.displacement = out.displacement.max(dx.hypot(dy));
        out.horizontal = out.horizontal.max(dx.abs());
        out.rotation = out.rotation.max(wrap(s.angle - s0.angle).abs());
    }
    out
}

/// Whether a dynamic body at `s` has left scene `name`'s container (fallen
/// through a wall or the ground).
pub fn escaped(name: &str, s: &BodyState) -> bool {
    let [x, y] = s.position;
    if !s.dynamic {
        return false;
    }
    if name.starts_with("bowl_") || name.starts_with("bouncy_") {
        x.hypot(y) > 250.0
    } else if name == "no_collide" {
        x.abs() > 335.0 || y.abs() > 255.0
    } else if name.starts_with("rain_") {
        y < 0.0 || x.abs() > 50.0
    } else if name.starts_with("tumbler_") {
        x.hypot(y - 10.0) > 14.2
    } else if name.starts_with("pyramid_") || name.starts_with("many_pyramids_") {
        y < -0.5
    } else {
        false
    }
}
