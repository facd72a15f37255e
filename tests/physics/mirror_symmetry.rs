//! Mirror symmetry of the contact solver: a scene reflected in the y axis
//! (x → −x) must evolve as the exact reflection of the original, bit for bit,
//! and a scene that is its own mirror (a centred stack) must keep every body
//! exactly on the axis.
//!
//! Why it can hold exactly: every operation of `Real` is symmetric under
//! negation (products round to nearest with ties away from zero, sums are
//! exact), reflection negates x components, cross products and angles, and
//! leaves y components and effective masses unchanged. What used to break it
//! is the *order* of the two contacts of a box face: the sequential-impulse
//! solver solved the left contact before the right one in one scene and the
//! right before the left in its mirror. The block solver
//! (`Settings::block_solver`) solves both contacts of a face together, in
//! formulas symmetric in the two contacts, so the order no longer matters.
//!
//! What does not hold, and why: across *different* arbiters the solver is
//! still Gauss–Seidel in a canonical order (the arbiters' order), and a
//! mirror does not map that order to itself when it swaps bodies (a pyramid:
//! the left box's contact with its neighbour is solved before the right
//! one's in both scenes). A pyramid and its mirror therefore agree only up
//! to the iteration's convergence, not bit for bit; the tests below use
//! scenes where the reflection maps every arbiter to itself.
use tamias2d::body::BodyHandle;
use tamias2d::real;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{
    self as scenes, BodyDesc, BodyKind, GeometryDesc, SceneDesc, ScriptedWorld, SettingsDesc,
    ShapeDesc,
};

fn mirror_v(v: Vect) -> Vect {
    Vect::new(-v.x, v.y)
}

/// The reflection of `desc` in the y axis. Boxes and circles are their own
/// mirror images about their centres, so only offsets, positions, angles and
/// velocities change sign.
fn mirror(desc: &SceneDesc) -> SceneDesc {
    let mut m = desc.clone();
    m.name = format!("{}_mirrored", desc.name);
    m.settings.gravity = mirror_v(m.settings.gravity);
    for b in &mut m.bodies {
        b.position = mirror_v(b.position);
        b.angle = -b.angle;
        b.velocity = mirror_v(b.velocity);
        b.angular_velocity = -b.angular_velocity;
        for s in &mut b.shapes {
            s.surface_velocity = mirror_v(s.surface_velocity);
            match &mut s.geometry {
                GeometryDesc::Circle { offset, .. } | GeometryDesc::Box { offset, .. } => {
                    *offset = mirror_v(*offset)
                }
                GeometryDesc::Segment { a, b, .. } => {
                    *a = mirror_v(*a);
                    *b = mirror_v(*b);
                }
                GeometryDesc::Poly { .. } | GeometryDesc::RawPoly { .. } => {
                    panic!("mirror: polygons other than boxes are not used here")
                }
            }
        }
    }
    m
}

fn build(desc: &SceneDesc) -> ScriptedWorld {
    desc.build()
        .unwrap_or_else(|e| panic!("{}: {e}", desc.name))
}

fn handles(w: &ScriptedWorld) -> Vec<BodyHandle> {
    w.space.bodies().map(|(h, _)| h).collect()
}

/// Steps `desc` and its mirror side by side and asserts after every step
/// that every body of the mirror is the exact reflection of the original.
fn assert_mirrors(desc: &SceneDesc, steps: u32) {
    let mut a = build(desc);
    let mut b = build(&mirror(desc));
    let (ha, hb) = (handles(&a), handles(&b));
    assert_eq!(ha.len(), hb.len());
    for n in 1..=steps {
        a.step().unwrap_or_else(|e| panic!("step: {e}"));
        b.step().unwrap_or_else(|e| panic!("step: {e}"));
        for (i, (&x, &y)) in ha.iter().zip(&hb).enumerate() {
            let (Some(p), Some(q)) = (a.space.body(x), b.space.body(y)) else {
                panic!("body {i} is gone");
            };
            let same = q.position() == mirror_v(p.position())
                && q.angle() == -p.angle()
                && q.velocity() == mirror_v(p.velocity())
                && q.angular_velocity() == -p.angular_velocity();
            assert!(
                same,
                "{}: step {n}, body {i}: {:?} {:?} {:?} {:?} is not the mirror of {:?} {:?} {:?} {:?}",
                desc.name,
                q.position(),
                q.angle(),
                q.velocity(),
                q.angular_velocity(),
                p.position(),
                p.angle(),
                p.velocity(),
                p.angular_velocity()
            );
        }
    }
}

/// Ground segment from (−5, 0) to (5, 0), gravity (0, −10), 10 iterations,
/// Chipmunk's slop 0.1 (the standard scenes' settings), friction 0.6.
fn ground(name: &str) -> SceneDesc {
    let mut desc = SceneDesc {
        settings: SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10),
        ..SceneDesc::new(name, Real::ratio(1, 60), 600)
    };
    let five = Real::from_int(5);
    desc.bodies.push(
        BodyDesc::static_body().with_shape(
            ShapeDesc::segment(
                Vect::new(-five, Real::ZERO),
                Vect::new(five, Real::ZERO),
                Real::ZERO,
            )
            .material(real!(0.6), Real::ZERO),
        ),
    );
    desc
}

fn unit_box(position: Vect, angle: Real, velocity: Vect, w: Real) -> BodyDesc {
    let mut b = BodyDesc::new(BodyKind::Dynamic, position).with_shape(
        ShapeDesc::box_shape(Real::ONE, Real::ONE, Real::ZERO)
            .material(real!(0.6), Real::ZERO)
            .density(Real::ONE),
    );
    b.angle = angle;
    b.velocity = velocity;
    b.angular_velocity = w;
    b
}

#[test]
fn a_tumbling_box_on_the_ground_mirrors_for_600_steps() {
    // Thrown sideways with a spin, it lands on a corner, slides, tips over
    // and comes to rest on a face: every contact case of a box face.
    let mut desc = ground("box_on_ground");
    desc.bodies.push(unit_box(
        Vect::new(real!(-1.25), real!(1.5)),
        real!(0.3),
        Vect::new(real!(2.5), Real::ZERO),
        real!(1.5),
    ));
    assert_mirrors(&desc, 600);
}

#[test]
fn a_ball_rolling_off_a_box_mirrors_for_600_steps() {
    let mut desc = ground("ball_on_box");
    desc.bodies.push(unit_box(
        Vect::new(Real::ZERO, Real::HALF),
        Real::ZERO,
        Vect::ZERO,
        Real::ZERO,
    ));
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::new(real!(0.2), real!(1.5))).with_shape(
            ShapeDesc::circle(real!(0.25))
                .material(real!(0.6), Real::ZERO)
                .density(Real::ONE),
        ),
    );
    assert_mirrors(&desc, 600);
}

/// Five boxes, each shifted 0.1 m right of the one below, on the ground.
fn offset_stack(block_solver: bool) -> SceneDesc {
    let mut desc = ground("offset_stack");
    desc.settings.block_solver = block_solver;
    for i in 0..5 {
        let x = Real::ratio(i, 10);
        let y = Real::from_int(i) + Real::HALF;
        desc.bodies.push(unit_box(
            Vect::new(x, y),
            Real::ZERO,
            Vect::ZERO,
            Real::ZERO,
        ));
    }
    desc
}

/// The largest distance between a body of the mirror and the reflection of
/// its original over `steps` steps.
fn mirror_gap(desc: &SceneDesc, steps: u32) -> f64 {
    let mut a = build(desc);
    let mut b = build(&mirror(desc));
    let (ha, hb) = (handles(&a), handles(&b));
    let mut worst = 0f64;
    for _ in 0..steps {
        a.step().unwrap_or_else(|e| panic!("step: {e}"));
        b.step().unwrap_or_else(|e| panic!("step: {e}"));
        for (&x, &y) in ha.iter().zip(&hb) {
            let (Some(p), Some(q)) = (a.space.body(x), b.space.body(y)) else {
                panic!("a body is gone");
            };
            worst = worst.max((q.position() - mirror_v(p.position())).length().to_f64());
        }
    }
    worst
}

#[test]
fn an_offset_stack_mirrors_to_rounding_for_600_steps() {
    // Asymmetric: it leans right, its mirror leans left. Not bit-exact, and
    // why: the narrowphase computes a pair relative to an anchor vertex of
    // the pair's first polygon in a canonical order (that is what makes it
    // exactly translation invariant and swap-exact), and both the order and
    // the anchor are chosen by coordinates, so the mirror computes the same
    // clip points from another anchor and rounds one of them 1 ulp
    // differently (found at step 2). The solver then carries that 1 ulp
    // along. Measured: the mirror stays within 1.6e-9 m (7 ulp) of the
    // reflection for 600 steps; the bound 1e-8 m (43 ulp) leaves room for
    // other rounding paths, far below the sequential solver's gap (printed).
    let gap = mirror_gap(&offset_stack(true), 600);
    let sequential = mirror_gap(&offset_stack(false), 600);
    println!("offset stack, largest distance from the mirror image: block {gap:e} m, sequential {sequential:e} m");
    assert!(gap <= 1e-8, "block solver: the mirror is {gap} m off");
    assert!(
        sequential > gap,
        "the sequential solver should not be more symmetric"
    );
}

#[test]
fn stack_10_is_its_own_mirror_and_stays_on_the_axis() {
    // stack_10 is symmetric about x = 0, so its mirror is itself and every
    // box must keep x = 0, angle 0, v_x = 0 and ω = 0 exactly: this is the
    // goal "top box drift ≤ 1 mm", with the bound 0.
    let desc = scenes::builtin("stack_10").unwrap_or_else(|| panic!("listed"));
    let mut w = build(&desc);
    for n in 1..=desc.steps {
        w.step().unwrap_or_else(|e| panic!("step: {e}"));
        for (h, b) in w.space.bodies() {
            assert!(
                b.position().x.is_zero()
                    && b.angle().is_zero()
                    && b.velocity().x.is_zero()
                    && b.angular_velocity().is_zero(),
                "step {n}: body {h:?} left the axis: p {:?}, angle {:?}, v {:?}, w {:?}",
                b.position(),
                b.angle(),
                b.velocity(),
                b.angular_velocity()
            );
        }
    }
    assert_mirrors(&desc, 60);
}
