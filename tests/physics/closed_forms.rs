//! Accuracy against closed forms:
//! free fall, constant force, projectiles, spin, elastic collisions, Newton's
//! cradle and the incline, each on its built-in scene.
//!
//! Two kinds of expected value, both derived from physics, never copied from
//! a run:
//! * the **discrete closed form of our integrator** (semi-implicit Euler,
//!   positions first with the previous velocity: `p += v·dt`, then
//!   `v += a·dt`), evaluated in `Real` with the same operations the step
//!   does, so the comparison is exact (bit for bit);
//! * the **continuous closed form** (`v = v0 + a·t`, `p = p0 + v0·t + ½·a·t²`)
//!   in `f64`, within a stated bound: the integrator lags it by exactly
//!   `½·a·dt·t` in position, plus rounding of at most ½ ulp per rounded
//!   operation, summed over the steps.
//!
//! Floats appear only in these comparisons, never in a scene.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::Body;
use tamias2d::real;
use tamias2d::shape::mass::moment_for_box;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{self as scenes, ScriptedWorld};

/// One ulp of `Real` (2^-32) as an `f64`.
const ULP: f64 = 1.0 / 4_294_967_296.0;
/// The time step of every accuracy scene (scenes/README.md), 1/60 s (the
/// `f64` rounding, 10^-18 s, is negligible against the bounds below).
const DT: f64 = 1.0 / 60.0;

fn build(name: &str) -> ScriptedWorld {
    scenes::builtin(name)
        .unwrap_or_else(|| panic!("{name} is a listed scene"))
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn body<'a>(scene: &'a ScriptedWorld, label: &str) -> &'a Body {
    scene
        .body(label)
        .and_then(|h| scene.space.body(h))
        .unwrap_or_else(|| panic!("no body labelled {label}"))
}

fn step(scene: &mut ScriptedWorld) {
    scene.step().unwrap_or_else(|e| panic!("step: {e}"));
}

fn f(v: Vect) -> (f64, f64) {
    v.to_f64()
}

// ---------------------------------------------------------------------------
// Constant acceleration: free_fall, constant_force, projectile_45/60.
// ---------------------------------------------------------------------------

/// A constant-acceleration scene: the inputs of `scenes/README.md` as exact decimals (for the
/// continuous form) and as the `Real`s the scene is built from (for the
/// discrete form).
struct Ballistic {
    name: &'static str,
    /// Steps to check (the scene's documented run).
    steps: u32,
    p0: (f64, f64),
    v0: (f64, f64),
    /// Continuous acceleration `g + F/m`.
    a: (f64, f64),
    /// Gravity, force and mass as the `Real` inputs the scene is built from.
    gravity: Vect,
    force: Vect,
    mass: Real,
    /// Bound (ulps) on the representation error of the decimal inputs:
    /// `p0`, `v0` and `g` are decimal literals rounded to nearest, ≤ ½ ulp.
    input_err: f64,
}

impl Ballistic {
    /// The per-step velocity increment exactly as the integrator computes it:
    /// `(g + F·(1/m))·dt`, each product rounded to nearest (`Body::set_mass`
    /// stores `1/m` rounded; `update_velocity` multiplies by `dt` once).
    fn dv(&self, dt: Real) -> Vect {
        let m_inv = Real::ONE / self.mass;
        (self.gravity + self.force * m_inv) * dt
    }

    /// Bound (ulps) on `|dv − a/60|` per component. `dt = round(1/60)` is
    /// within ½ ulp; `1/m` within ½ ulp, so `F·(1/m)` within `½|F| + ½`; `g`
    /// within ½ ulp; the product by `dt` adds ½ ulp of rounding and carries
    /// `|a|·½` from the error of `dt`. Second-order cross terms are below
    /// 2^-25 ulp; one extra ulp covers them.
    fn dv_err(&self) -> (f64, f64) {
        let (fx, fy) = f(self.force);
        let one = |force: f64, a: f64| {
            let err_a = self.input_err + 0.5 * force.abs() + 0.5;
            0.5 + 0.5 * a.abs() + err_a * DT + 1.0
        };
        (one(fx, self.a.0), one(fy, self.a.1))
    }
}

/// Steps the scene and checks, after every step `n` (t = n·dt):
/// * exactly: `v_n = v0 + n·dv` and `p_n = p0 + Σ_{k<n} round(v_k·dt)` (the
///   integrator's own operations, replayed in `Real`);
/// * `|v_n − (v0 + a·t)| ≤ e_v(n)`, with `e_v(n) = input_err + n·dv_err`;
/// * `|p_n − (p0 + v0·t + ½·a·t² − ½·a·dt·t)| ≤ e_p(n)`: the discrete closed
///   form `p0 + v0·t + ½·a·dt²·n(n − 1)`, with `e_p(n)` the sum over the
///   steps of ½ ulp (rounding of `v_k·dt`) + `|v_k|·½ ulp` (error of `dt`)
///   + `e_v(k)·dt`;
/// * `|p_n − (p0 + v0·t + ½·a·t²)| ≤ ½·|a|·dt·t + e_p(n)`, and the position
///   lags the continuous one (never leads it).
fn check_ballistic(case: &Ballistic) {
    let mut scene = build(case.name);
    let dt = scene.dt;
    assert_eq!(dt, Real::ratio(1, 60), "{}: dt", case.name);
    let start = body(&scene, "ball").clone();
    // The scene is built from the inputs stated in `case`.
    assert_eq!(
        scene.space.gravity(),
        case.gravity,
        "{}: gravity",
        case.name
    );
    assert_eq!(start.mass(), case.mass, "{}: mass", case.name);
    assert_eq!(
        f(start.position()),
        case.p0,
        "{}: start position",
        case.name
    );
    assert_eq!(
        f(start.velocity()),
        case.v0,
        "{}: start velocity",
        case.name
    );
    let dv = case.dv(dt);
    let (ex, ey) = case.dv_err();
    let (mut p, mut v) = (start.position(), start.velocity());
    let mut err_p = (case.input_err, case.input_err);
    let mut worst = (0f64, 0f64);
    for n in 1..=case.steps {
        // Bound for this step's position increment, from v_{n-1}.
        let t_prev = f64::from(n - 1) * DT;
        let v_prev = (case.v0.0 + case.a.0 * t_prev, case.v0.1 + case.a.1 * t_prev);
        let ev_prev = (
            case.input_err + f64::from(n - 1) * ex,
            case.input_err + f64::from(n - 1) * ey,
        );
        err_p.0 += 0.5 + 0.5 * v_prev.0.abs() + ev_prev.0 * DT;
        err_p.1 += 0.5 + 0.5 * v_prev.1.abs() + ev_prev.1 * DT;
        // The integrator's operations, replayed: positions first.
        p += v * dt;
        v += dv;
        step(&mut scene);
        let b = body(&scene, "ball");
        assert_eq!(
            b.velocity(),
            v,
            "{} after {n} steps: v is not v0 + n·dv exactly",
            case.name
        );
        assert_eq!(
            b.position(),
            p,
            "{} after {n} steps: p is not p0 + Σ round(v_k·dt) exactly",
            case.name
        );
        let t = f64::from(n) * DT;
        let (vx, vy) = f(b.velocity());
        let (px, py) = f(b.position());
        let ev = (
            (case.input_err + f64::from(n) * ex) * ULP,
            (case.input_err + f64::from(n) * ey) * ULP,
        );
        let cont_v = (case.v0.0 + case.a.0 * t, case.v0.1 + case.a.1 * t);
        assert!(
            (vx - cont_v.0).abs() <= ev.0 && (vy - cont_v.1).abs() <= ev.1,
            "{} after {n} steps: v = ({vx}, {vy}), a·t gives {cont_v:?} ± {ev:?}",
            case.name
        );
        let cont = |p0: f64, v0: f64, a: f64| p0 + v0 * t + 0.5 * a * t * t;
        let lag = |a: f64| 0.5 * a * DT * t;
        let c = (
            cont(case.p0.0, case.v0.0, case.a.0),
            cont(case.p0.1, case.v0.1, case.a.1),
        );
        let disc = (c.0 - lag(case.a.0), c.1 - lag(case.a.1));
        let ep = (err_p.0 * ULP, err_p.1 * ULP);
        assert!(
            (px - disc.0).abs() <= ep.0 && (py - disc.1).abs() <= ep.1,
            "{} after {n} steps: p = ({px}, {py}), discrete closed form {disc:?} ± {ep:?}",
            case.name
        );
        for (pi, ci, ai, ei) in [(px, c.0, case.a.0, ep.0), (py, c.1, case.a.1, ep.1)] {
            let bound = 0.5 * ai.abs() * DT * t + ei;
            assert!(
                (pi - ci).abs() <= bound,
                "{} after {n} steps: |p − ½at²| = {} > ½·|a|·dt·t + rounding = {bound}",
                case.name,
                (pi - ci).abs()
            );
            // The lag has the sign of −a: the body is behind the parabola.
            assert!(
                (pi - ci) * ai <= ei * ai.abs(),
                "{} after {n} steps: position leads ½at² ({pi} vs {ci})",
                case.name
            );
        }
        worst.0 = worst.0.max((px - disc.0).abs().max((py - disc.1).abs()));
        worst.1 = worst
            .1
            .max((vx - cont_v.0).abs().max((vy - cont_v.1).abs()));
    }
    println!(
        "{}: after {} steps max |p − discrete closed form| = {:.3e} m ({:.1} ulp, bound {:.0} ulp), \
         max |v − (v0 + a·t)| = {:.3e} m/s",
        case.name,
        case.steps,
        worst.0,
        worst.0 / ULP,
        err_p.0.max(err_p.1),
        worst.1
    );
}

#[test]
fn free_fall_matches_discrete_and_continuous_closed_forms() {
    // Released at rest at (0, 100) under g = (0, −9.81); 240 steps (4 s).
    // After 4 s: v = −39.24 m/s, drop ½gt² = 78.48 m less the lag
    // ½·g·dt·t = 0.327 m.
    check_ballistic(&Ballistic {
        name: "free_fall",
        steps: 240,
        p0: (0.0, 100.0),
        v0: (0.0, 0.0),
        a: (0.0, -9.81),
        gravity: Vect::new(Real::ZERO, -real!(9.81)),
        force: Vect::ZERO,
        mass: Real::ONE,
        input_err: 0.5,
    });
    // The documented end point, stated independently: y(4 s) = 100 −
    // ½·9.81·(16 − 4/60) = 21.847 m.
    let mut s = build("free_fall");
    s.step_n(240).unwrap_or_else(|e| panic!("{e}"));
    let y = body(&s, "ball").position().y.to_f64();
    assert!(
        (y - (100.0 - 0.5 * 9.81 * (16.0 - 4.0 / 60.0))).abs() < 1e-6,
        "{y}"
    );
}

#[test]
fn constant_force_matches_discrete_and_continuous_closed_forms() {
    // F = (100, 0) on m = 10 from rest at (20, 20), no gravity:
    // a = (10, 0). x(4 s) = 20 + 80 − ½·10·dt·4 = 100 − 1/3 m; y stays 20.
    check_ballistic(&Ballistic {
        name: "constant_force",
        steps: 240,
        p0: (20.0, 20.0),
        v0: (0.0, 0.0),
        a: (10.0, 0.0),
        gravity: Vect::ZERO,
        force: Vect::from_ints(100, 0),
        mass: Real::from_int(10),
        input_err: 0.5,
    });
    let mut s = build("constant_force");
    s.step_n(240).unwrap_or_else(|e| panic!("{e}"));
    let b = body(&s, "ball");
    assert!(
        (b.position().x.to_f64() - (100.0 - 1.0 / 3.0)).abs() < 1e-6,
        "{:?}",
        b.position()
    );
    assert_eq!(b.position().y, Real::from_int(20), "no force along y");
}

#[test]
fn projectile_45_matches_closed_forms_in_2d() {
    // p0 = 0, v0 = (848.5, 848.5), g = (0, −100), 600 steps (10 s):
    // x = 848.5·t exactly up to rounding (no acceleration along x), y lags
    // the parabola by ½·g·dt·t.
    check_ballistic(&Ballistic {
        name: "projectile_45",
        steps: 600,
        p0: (0.0, 0.0),
        v0: (848.5, 848.5),
        a: (0.0, -100.0),
        gravity: Vect::from_ints(0, -100),
        force: Vect::ZERO,
        mass: Real::from_int(10),
        input_err: 0.0,
    });
}

#[test]
fn projectile_60_matches_closed_forms_in_2d() {
    // p0 = (50, 50), v0 = (150, 260), g = (0, −40), 600 steps.
    check_ballistic(&Ballistic {
        name: "projectile_60",
        steps: 600,
        p0: (50.0, 50.0),
        v0: (150.0, 260.0),
        a: (0.0, -40.0),
        gravity: Vect::from_ints(0, -40),
        force: Vect::ZERO,
        mass: Real::from_int(1000),
        input_err: 0.0,
    });
}

#[test]
fn projectile_horizontal_velocity_is_exactly_constant() {
    // No force along x: every step adds round(0·dt) = 0, so v_x never
    // changes by a single bit, and x_n = x0 + n·round(v_x·dt) exactly.
    for (name, x0, vx) in [
        ("projectile_45", Real::ZERO, real!(848.5)),
        ("projectile_60", Real::from_int(50), Real::from_int(150)),
    ] {
        let mut s = build(name);
        let dx = vx * s.dt;
        for n in 1..=600i64 {
            step(&mut s);
            let b = body(&s, "ball");
            assert_eq!(b.velocity().x, vx, "{name} after {n} steps");
            assert_eq!(
                b.position().x,
                x0 + Real::from_bits(dx.to_bits() * n),
                "{name} after {n} steps"
            );
        }
    }
}

// ---------------------------------------------------------------------------
// Spin: constant torque.
// ---------------------------------------------------------------------------

#[test]
fn spin_matches_discrete_and_continuous_closed_forms() {
    // τ = 100 on a 100 × 100 box of mass 0.5, I = 2500/3, no
    // gravity: α = τ/I = 0.12 rad/s² exactly. ω(t) = 0.12·t and
    // φ(t) = 0.06·t² − ½·α·dt·t (discrete lag). 600 steps (10 s):
    // ω = 1.2 rad/s, φ = 6 − 0.01 rad.
    let mut s = build("spin");
    let dt = s.dt;
    let (mass, side, tau) = (Real::HALF, Real::from_int(100), Real::from_int(100));
    let moment = moment_for_box(mass, side, side);
    // The moment helper is exact up to its final rounding: ≤ ½ ulp (1 allowed).
    assert!(
        (moment.to_f64() - 2500.0 / 3.0).abs() <= ULP,
        "moment {moment}"
    );
    assert_eq!(body(&s, "box").moment(), moment);
    // The integrator: ω += (τ·(1/I))·dt, φ += round(ω·dt), each rounded.
    let dw = (tau * (Real::ONE / moment)) * dt;
    // Error of dw vs α/60 (ulps): 1/I within ½ ulp (plus 1 ulp of I, ×1/I²,
    // negligible), times τ = 100 → 50 ulp, +½ for the product; times dt:
    // +½ rounding, +α·½ from the error of dt. One ulp for cross terms.
    let alpha = 0.12;
    let err_dw = 0.5 + 0.5 * alpha + (50.0 + 0.5) * DT + 1.0;
    let (mut w, mut phi) = (Real::ZERO, Real::ZERO);
    let mut err_phi = 0.0;
    let mut worst_rot = 0f64;
    for n in 1..=600u32 {
        let w_prev = alpha * f64::from(n - 1) * DT;
        err_phi += 0.5 + 0.5 * w_prev + f64::from(n - 1) * err_dw * DT;
        phi += w * dt;
        w += dw;
        step(&mut s);
        let b = body(&s, "box");
        assert_eq!(b.angular_velocity(), w, "after {n} steps: ω = n·dw exactly");
        assert_eq!(
            b.angle(),
            phi,
            "after {n} steps: φ = Σ round(ω_k·dt) exactly"
        );
        let t = f64::from(n) * DT;
        let ew = f64::from(n) * err_dw * ULP;
        assert!(
            (b.angular_velocity().to_f64() - alpha * t).abs() <= ew,
            "after {n} steps: ω = {} vs τt/I = {} ± {ew}",
            b.angular_velocity(),
            alpha * t
        );
        let continuous = 0.5 * alpha * t * t;
        let lag = 0.5 * alpha * DT * t;
        let a = b.angle().to_f64();
        assert!(
            (a - (continuous - lag)).abs() <= err_phi * ULP,
            "after {n} steps: φ = {a} vs ½αt² − ½α·dt·t = {} ± {}",
            continuous - lag,
            err_phi * ULP
        );
        assert!((a - continuous).abs() <= lag + err_phi * ULP);
        // rotation() is advanced by composing small exact rotations, not
        // recomputed from the angle: each step rounds the complex product
        // (½ ulp per component), the small-angle series (< 1 ulp) and, when
        // |rot|² drifts by 2^-24, a renormalisation. Allow 4 ulp per step.
        let rot = b.rotation();
        let err = (rot.c.to_f64() - a.cos())
            .abs()
            .max((rot.s.to_f64() - a.sin()).abs());
        worst_rot = worst_rot.max(err);
        assert!(
            err <= 4.0 * f64::from(n) * ULP,
            "after {n} steps: rotation {rot:?} vs (cos φ, sin φ) at φ = {a}: {err}"
        );
    }
    let b = body(&s, "box");
    assert!((b.angular_velocity().to_f64() - 1.2).abs() < 1e-6);
    assert!((b.angle().to_f64() - (6.0 - 0.01)).abs() < 1e-6);
    assert_eq!(b.position(), Vect::ZERO, "a pure torque does not translate");
    println!(
        "spin: after 600 steps ω = {}, φ = {}, max |rotation − (cos φ, sin φ)| = {:.3e} ({:.1} ulp)",
        b.angular_velocity(),
        b.angle(),
        worst_rot,
        worst_rot / ULP
    );
}

// ---------------------------------------------------------------------------
// Elastic collisions.
// ---------------------------------------------------------------------------

/// Sum of `½mv² + ½Iω²` over the labelled bodies, as `f64`.
fn kinetic_energy(scene: &ScriptedWorld, labels: &[&str]) -> f64 {
    labels
        .iter()
        .map(|l| body(scene, l).kinetic_energy().to_f64())
        .sum()
}

/// Sum of `m·v` over the labelled bodies, in `Real` (exact sums).
fn momentum(scene: &ScriptedWorld, labels: &[&str]) -> Vect {
    labels.iter().fold(Vect::ZERO, |acc, l| {
        let b = body(scene, l);
        acc + b.velocity() * b.mass()
    })
}

/// Bound on the velocity error of an elastic exchange between unit masses
/// on the x axis. In exact arithmetic the solver exchanges the velocities
/// exactly: the centres are on the x axis, so `n = (1, 0)` and `r × j = 0`;
/// `n_mass = ½`; the first iteration applies `j = −(e·vrn + vrn)·½ = −vrn`
/// and every later one 0. All of these are exact in I32F32 here; allow 4 ulp
/// per collision for a normal that is not exactly (1, 0) after
/// normalisation.
const EXCHANGE_ULPS: i64 = 4;

#[test]
fn elastic_pair_exchanges_velocities_and_conserves_momentum_and_energy() {
    // a at (−5, 0) moving at 3, b at (5, 0) moving at −1, radius 1, m = 1,
    // e = 1: they close 8 m at 4 m/s and touch at t = 2 s. Afterwards
    // v_a = −1, v_b = 3; momentum 2 and energy ½(9 + 1) = 5 throughout.
    let labels = ["a", "b"];
    let mut s = build("elastic_pair");
    let p0 = momentum(&s, &labels);
    assert_eq!(p0, Vect::from_ints(2, 0));
    let e0 = kinetic_energy(&s, &labels);
    assert_eq!(e0, 5.0);
    let tol = Real::from_bits(EXCHANGE_ULPS);
    let mut collided_at = None;
    for n in 1..=240u32 {
        step(&mut s);
        let (a, b) = (body(&s, "a"), body(&s, "b"));
        let gap = (b.position() - a.position()).length().to_f64() - 2.0;
        if collided_at.is_none() {
            if a.velocity() == Vect::from_ints(3, 0) {
                // Before the collision nothing may change by a single bit,
                // and the pair must not be overlapping by more than one
                // step's closing travel (4/60 m) without having collided.
                assert_eq!(b.velocity(), Vect::from_ints(-1, 0), "step {n}");
                assert!(gap > -4.0 * DT, "step {n}: overlap {gap} without impulse");
                continue;
            }
            collided_at = Some(n);
            // In exact arithmetic the balls touch (gap 0, which counts as a
            // contact) after exactly 120 steps; with dt rounded the gap then
            // is a few ulp either side of 0, so the collision is step 120
            // or 121, never earlier (no ghost contact) or later (no
            // tunnelling: 121 steps overlap by 4/60 m).
            assert!((120..=121).contains(&n), "collided at step {n}");
        }
        for (x, want) in [(a, -1), (b, 3)] {
            let d = x.velocity() - Vect::from_ints(want, 0);
            assert!(
                d.x.abs() <= tol && d.y.abs() <= tol,
                "step {n}: velocity {:?}, want ({want}, 0) ± {EXCHANGE_ULPS} ulp",
                x.velocity()
            );
            assert!(x.angular_velocity().abs() <= tol, "step {n}: spin");
        }
        // Equal and opposite impulses on equal masses round identically
        // ((−x)·y = −(x·y) exactly): momentum is conserved to the bit;
        // allow 2 ulp.
        let dp = momentum(&s, &labels) - p0;
        assert!(
            dp.x.abs() <= Real::from_bits(2) && dp.y.abs() <= Real::from_bits(2),
            "step {n}: momentum changed by {dp:?}"
        );
        // |ΔE| ≤ Σ|v|·|Δv| + the rounding of kinetic_energy() (4 ulp per body).
        let de = (kinetic_energy(&s, &labels) - e0).abs();
        let bound = (3.0 + 1.0) * EXCHANGE_ULPS as f64 * ULP + 8.0 * ULP;
        assert!(de <= bound, "step {n}: energy changed by {de} > {bound}");
    }
    assert!(collided_at.is_some(), "the balls never collided");
    let (a, b) = (body(&s, "a"), body(&s, "b"));
    println!(
        "elastic_pair: collided at step {:?}; final v_a = {:?}, v_b = {:?}, Δp = {:?}, ΔE = {:e}",
        collided_at,
        a.velocity(),
        b.velocity(),
        momentum(&s, &labels) - p0,
        kinetic_energy(&s, &labels) - e0
    );
    // Separating at 4 m/s ever since: after 240 steps the gap is 4·(4 − t_c).
    assert!(b.position().x > a.position().x + Real::from_int(2));
}

#[test]
fn newtons_cradle_last_ball_leaves_with_the_first_ones_speed() {
    // Five unit balls 1 cm apart, ball0 at 2 m/s, e = 1, no friction or
    // gravity. Equal-mass elastic collisions exchange velocities, so the
    // velocity is passed down the row: ball4 leaves at (2, 0), balls 0–3
    // end at rest; momentum 2 and energy 2 are conserved. Four exchanges,
    // each exact up to EXCHANGE_ULPS (see there).
    let labels = ["ball0", "ball1", "ball2", "ball3", "ball4"];
    let mut s = build("newtons_cradle");
    let p0 = momentum(&s, &labels);
    let e0 = kinetic_energy(&s, &labels);
    assert_eq!(p0, Vect::from_ints(2, 0));
    assert_eq!(e0, 2.0);
    let tol = Real::from_bits(4 * EXCHANGE_ULPS);
    for n in 1..=120u32 {
        step(&mut s);
        let dp = momentum(&s, &labels) - p0;
        assert!(
            dp.x.abs() <= Real::from_bits(2 * 4) && dp.y.abs() <= Real::from_bits(2 * 4),
            "step {n}: momentum changed by {dp:?}"
        );
        let de = (kinetic_energy(&s, &labels) - e0).abs();
        let bound = 2.0 * 4.0 * EXCHANGE_ULPS as f64 * ULP + 4.0 * 5.0 * ULP;
        assert!(de <= bound, "step {n}: energy changed by {de}");
    }
    for (i, l) in labels.iter().enumerate() {
        let b = body(&s, l);
        let want = if i == 4 {
            Vect::from_ints(2, 0)
        } else {
            Vect::ZERO
        };
        let d = b.velocity() - want;
        assert!(
            d.x.abs() <= tol && d.y.abs() <= tol && b.angular_velocity().abs() <= tol,
            "{l}: velocity {:?} (ω {}), want {want:?} ± {} ulp",
            b.velocity(),
            b.angular_velocity(),
            tol.to_bits()
        );
    }
    // The row stays in order and ball4 has moved away from ball3.
    for w in labels.windows(2) {
        let (l, r) = (body(&s, w[0]), body(&s, w[1]));
        assert!(r.position().x > l.position().x, "{} passed {}", w[0], w[1]);
    }
    let gap = (body(&s, "ball4").position().x - body(&s, "ball3").position().x).to_f64();
    assert!(gap > 2.0 + 1.0, "ball4 is only {gap} m from ball3");
    println!(
        "newtons_cradle: final velocities {:?}",
        labels
            .iter()
            .map(|l| body(&s, l).velocity().x.to_f64())
            .collect::<Vec<_>>()
    );
}

// ---------------------------------------------------------------------------
// Incline.
// ---------------------------------------------------------------------------

/// Unit vector up the 30° slope and its normal, in `f64`.
fn slope_axes() -> ((f64, f64), (f64, f64)) {
    let (s, c) = (0.5f64, 3f64.sqrt() / 2.0);
    ((c, s), (-s, c))
}

fn dot(a: (f64, f64), b: (f64, f64)) -> f64 {
    a.0 * b.0 + a.1 * b.1
}

#[test]
fn incline_slides_with_coulomb_acceleration() {
    // θ = 30°, μ = 0.2 < tan θ: a = g(sin θ − μ cos θ) = 3.20586 m/s² down
    // the slope. The velocity along the slope is measured once the box is
    // sliding (from step 30 to step 180, 2.5 s) so a start-up transient
    // cannot hide in the fit.
    //
    // Bound: in steady sliding the friction impulse is clamped exactly to
    // μ·jn and jn converges to m·g·cos θ·dt (warm-started from the last
    // step, so the iterations start at the answer); what remains is
    // rounding: the slope direction comes from sin_cos of a rounded θ (a few
    // ulp), and each step rounds v and the impulses (a few ulp of velocity
    // per step). 150 steps × 64 ulp/step over Δv ≈ 8 m/s is a relative
    // error below 10^-8; we allow 10^-6 relative on the acceleration.
    let g = 9.81;
    let (sin, cos) = (0.5, 3f64.sqrt() / 2.0);
    let mu = 0.2;
    let a_expected = g * (sin - mu * cos);
    let (up, normal) = slope_axes();
    let mut s = build("incline_slide");
    let mut v_at = Vec::new();
    for _ in 1..=180u32 {
        step(&mut s);
        v_at.push(dot(f(body(&s, "box").velocity()), up));
    }
    let (n1, n2) = (30usize, 180usize);
    let a_measured = -(v_at[n2 - 1] - v_at[n1 - 1]) / ((n2 - n1) as f64 * DT);
    let rel = (a_measured - a_expected).abs() / a_expected;
    println!(
        "incline_slide: a = {a_measured:.9} m/s² vs g(sin θ − μ cos θ) = {a_expected:.9} \
         (relative error {rel:.2e})"
    );
    assert!(rel <= 1e-6, "a = {a_measured}, want {a_expected}");
    // v(t) = −a·t from the first step on (no stick phase): after 3 s.
    let v_end = v_at[179];
    assert!(
        (v_end + a_expected * 3.0).abs() <= 1e-6 * a_expected * 3.0 + 1e-6,
        "v(3 s) = {v_end}"
    );
    // The box stays on the slope: its centre stays 0.5 m above the
    // surface, less at most the slop (contacts are not corrected within it).
    let b = body(&s, "box");
    let height = dot(f(b.position()), normal);
    assert!(
        (0.5 - 0.1..=0.5 + 1e-6).contains(&height),
        "height above the slope {height}"
    );
}

#[test]
fn incline_sliding_box_stays_flat_on_the_slope() {
    // The same slide, checked at every step: the slope pushes back with
    // m·g·cos θ > 0 throughout, so the box never leaves it, never tips and
    // never bounces. Its velocity along the normal and its angular velocity
    // are zero up to rounding (a few ulp of the 0.16 m/s per-step gravity
    // increment not cancelled); 10^-6 is thousands of ulp. A box that loses
    // one of its two contacts for a step (a corner lifted by an ulp) is
    // kicked into a visible rotation and drop, which this rejects.
    let (up, normal) = slope_axes();
    let mut s = build("incline_slide");
    for n in 1..=180u32 {
        step(&mut s);
        let b = body(&s, "box");
        let v = f(b.velocity());
        let vn = dot(v, normal);
        let contacts: usize = s.space.arbiters().iter().map(|a| a.contacts().len()).sum();
        assert!(
            vn.abs() <= 1e-6,
            "step {n}: velocity along the slope normal {vn} (along the slope {}, {contacts} contacts)",
            dot(v, up)
        );
        assert!(
            b.angular_velocity().to_f64().abs() <= 1e-6,
            "step {n}: the box tips: ω = {} ({contacts} contacts)",
            b.angular_velocity()
        );
    }
}

#[test]
fn incline_sticks_when_friction_exceeds_tan_theta() {
    // θ = 30°, μ = 0.8 > tan θ = 0.577: static friction holds and the box
    // stays put. Bound on the slip along the slope: even if friction failed
    // completely during one whole step (the first contact step has no warm
    // start), the box would gain g·sin θ·dt and move g·sin θ·dt² = 1.36 mm
    // the next step; we allow that one step of unopposed sliding and no
    // more over 3 s. Along the normal the box may sink by at most the slop
    // (0.1 m, overlap within it is not corrected). At the end it is at rest
    // to within a few ulp per step of gravity not cancelled: 2^-20 m/s.
    let g = 9.81;
    let (up, normal) = slope_axes();
    let slip_bound = g * 0.5 * DT * DT;
    let mut s = build("incline_stick");
    let start = f(body(&s, "box").position());
    let mut worst_slip = 0f64;
    for n in 1..=180u32 {
        step(&mut s);
        let p = f(body(&s, "box").position());
        let d = (p.0 - start.0, p.1 - start.1);
        let slip = dot(d, up).abs();
        worst_slip = worst_slip.max(slip);
        assert!(slip <= slip_bound, "step {n}: slipped {slip} m");
        let sink = -dot(d, normal);
        assert!(
            (-1e-6..=0.1).contains(&sink),
            "step {n}: moved {sink} m into the slope"
        );
    }
    let b = body(&s, "box");
    // It stays flat on the slope within the slop: tilting by δ lifts one
    // corner and sinks the other by δ·side/2 each, and sinking beyond the
    // slop is corrected, so |δ| ≤ 2·slop/side = 0.2 rad; we ask for half.
    let tilt = b.angle().to_f64() - std::f64::consts::FRAC_PI_6;
    assert!(tilt.abs() <= 0.1, "tilted by {tilt} rad");
    let (vx, vy) = f(b.velocity());
    let rest = 1.0 / 1_048_576.0;
    assert!(
        vx.abs() <= rest && vy.abs() <= rest && b.angular_velocity().to_f64().abs() <= rest,
        "not at rest: v = {:?}, ω = {}",
        b.velocity(),
        b.angular_velocity()
    );
    println!(
        "incline_stick: max slip along the slope {worst_slip:.3e} m (bound {slip_bound:.3e}), \
         final v = ({vx:e}, {vy:e}), tilt {tilt:e} rad"
    );
}
