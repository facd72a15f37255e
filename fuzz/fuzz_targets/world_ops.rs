//! Arbitrary operation scripts on a world (add/remove bodies (bullets
//! among them), shapes and joints of every kind, joint parameters, impulses, steps, queries,
//! sleeping and waking, sleep settings, clone/restore): never panics, and the world's invariants hold after
//! every operation (a dynamic body without mass, allowed while its shapes
//! are to come, is reported by validation as the one thing that cannot
//! step).
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::body::Body;
use tamias2d::constraint::{
    Constraint, DampedRotarySpring, DampedSpring, GearJoint, GrooveJoint, JointKind, PinJoint,
    PivotJoint, RatchetJoint, RotaryLimitJoint, SimpleMotor, SlideJoint,
};
use tamias2d::math::{Real, Vect, BB};
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::space::Space;

#[derive(Arbitrary, Debug)]
enum Op {
    AddBody {
        kind: u8,
        x: i32,
        y: i32,
        mass: u16,
    },
    AddCircle {
        body: u8,
        r: u16,
        x: i16,
        y: i16,
    },
    AddBox {
        body: u8,
        w: u16,
        h: u16,
    },
    AddSegment {
        body: u8,
        ax: i16,
        ay: i16,
        bx: i16,
        by: i16,
    },
    RemoveBody {
        body: u8,
    },
    RemoveShape {
        shape: u8,
    },
    Impulse {
        body: u8,
        x: i32,
        y: i32,
    },
    Step {
        dt: u16,
    },
    Query {
        x: i32,
        y: i32,
    },
    CloneRestore,
    /// Iterations, sub-steps and the solver switches (bit i of `flags`).
    Settings {
        iterations: u8,
        substeps: u8,
        flags: u8,
    },
    /// A joint of kind `kind % 10` between two bodies (maybe the same
    /// one: an error), its parameters from `p` (any sign, zero included).
    AddJoint {
        kind: u8,
        a: u8,
        b: u8,
        p: [i16; 4],
    },
    RemoveJoint {
        joint: u8,
    },
    /// `sleep_body`, or `sleep_body_with_group` with `group` (errors when
    /// the rules refuse), or `activate_body`.
    Sleep {
        body: u8,
        group: u8,
        how: u8,
    },
    /// Sleep thresholds (any value: negative ones are errors) and a body's
    /// permission to sleep.
    SleepSettings {
        time: i16,
        idle: i16,
        body: u8,
        allowed: bool,
    },
    /// `max_force`, `max_bias`, `error_bias` (any sign: errors) and
    /// `collide_bodies` of a joint.
    JointParams {
        joint: u8,
        force: i32,
        bias: i32,
        error_bias: i32,
        collide: bool,
    },
}

/// A joint kind from fuzz input; constructor errors are fine.
fn joint_kind(kind: u8, p: [i16; 4]) -> Option<JointKind> {
    let r = |i: usize| real(i32::from(p[i % 4]), 24);
    let v = |i: usize| Vect::new(r(i), r(i + 1));
    Some(match kind % 10 {
        0 => PinJoint::new(v(0), v(2), r(1)).ok()?.into(),
        1 => SlideJoint::new(v(0), v(2), r(1), r(3)).ok()?.into(),
        2 => PivotJoint::new(v(0), v(2)).ok()?.into(),
        3 => GrooveJoint::new(v(0), v(1), v(2)).ok()?.into(),
        4 => DampedSpring::new(v(0), v(2), r(1), r(2), r(3)).ok()?.into(),
        5 => DampedRotarySpring::new(r(0), r(1), r(2)).ok()?.into(),
        6 => RotaryLimitJoint::new(r(0), r(1)).ok()?.into(),
        7 => RatchetJoint::new(r(0), r(1)).ok()?.into(),
        8 => GearJoint::new(r(0), r(1)).ok()?.into(),
        _ => SimpleMotor::new(r(0)).ok()?.into(),
    })
}

fn real(v: i32, shift: u32) -> Real {
    Real::from_bits(i64::from(v) << shift)
}

fuzz_target!(|ops: Vec<Op>| {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    for op in ops.iter().take(64) {
        let bodies: Vec<_> = space.bodies().map(|(h, _)| h).collect();
        let shapes: Vec<_> = space.shapes().map(|(h, _)| h).collect();
        let joints: Vec<_> = space.constraints().map(|(h, _)| h).collect();
        let pick_joint = |i: u8| joints.get(usize::from(i) % joints.len().max(1)).copied();
        let pick_body = |i: u8| bodies.get(usize::from(i) % bodies.len().max(1)).copied();
        match op {
            Op::AddBody { kind, x, y, mass } => {
                let mut b = match kind % 3 {
                    0 => Body::new(
                        Real::from_int(i32::from(*mass)),
                        Real::from_int(i32::from(*mass)),
                    )
                    .unwrap_or_else(|_| Body::new_static()),
                    1 => Body::new_kinematic(),
                    _ => Body::new_static(),
                };
                b.set_position(Vect::new(real(*x, 16), real(*y, 16)));
                // Bit 7: a bullet (continuous collision; kept but inert on
                // kinematic and static bodies).
                b.set_bullet(kind & 0x80 != 0);
                let _ = space.add_body(b);
            }
            Op::AddCircle { body, r, x, y } => {
                if let Some(b) = pick_body(*body) {
                    if let Ok(s) = Shape::circle_shape_new(
                        b,
                        real(i32::from(*r), 20),
                        Vect::new(real(i32::from(*x), 20), real(i32::from(*y), 20)),
                    ) {
                        let _ = space.add_shape(s);
                    }
                }
            }
            Op::AddBox { body, w, h } => {
                if let Some(b) = pick_body(*body) {
                    if let Ok(mut s) = Shape::box_shape_new(
                        b,
                        real(i32::from(*w), 20),
                        real(i32::from(*h), 20),
                        Real::ZERO,
                    ) {
                        let _ = s.set_density(Real::ONE);
                        let _ = space.add_shape(s);
                    }
                }
            }
            Op::AddSegment {
                body,
                ax,
                ay,
                bx,
                by,
            } => {
                if let Some(b) = pick_body(*body) {
                    let a = Vect::new(real(i32::from(*ax), 24), real(i32::from(*ay), 24));
                    let c = Vect::new(real(i32::from(*bx), 24), real(i32::from(*by), 24));
                    if let Ok(s) = Shape::segment_shape_new(b, a, c, Real::ZERO) {
                        let _ = space.add_shape(s);
                    }
                }
            }
            Op::RemoveBody { body } => {
                if let Some(b) = pick_body(*body) {
                    let _ = space.remove_body(b);
                }
            }
            Op::RemoveShape { shape } => {
                if let Some(s) = shapes.get(usize::from(*shape) % shapes.len().max(1)) {
                    let _ = space.remove_shape(*s);
                }
            }
            Op::Impulse { body, x, y } => {
                if let Some(b) = pick_body(*body).and_then(|b| space.body_mut(b)) {
                    let p = b.position();
                    b.apply_impulse_at_world_point(Vect::new(real(*x, 8), real(*y, 8)), p);
                }
            }
            Op::Step { dt } => {
                let _ = space.step(Real::from_bits(i64::from(*dt) << 12));
            }
            Op::Query { x, y } => {
                let p = Vect::new(real(*x, 16), real(*y, 16));
                let _ = space.point_query(p, Real::from_int(5), ShapeFilter::ALL);
                let _ = space.segment_query(Vect::ZERO, p, Real::ONE, ShapeFilter::ALL);
                let _ = space.bb_query(BB::for_circle(p, Real::from_int(3)), ShapeFilter::ALL);
            }
            Op::Settings {
                iterations,
                substeps,
                flags,
            } => {
                let mut s = *space.settings();
                s.iterations = u32::from(*iterations % 32);
                // Up to 5: out-of-range values must be rejected, not panic.
                s.substeps = u32::from(*substeps % 6);
                s.warm_starting = flags & 1 != 0;
                s.friction = flags & 2 != 0;
                s.restitution = flags & 4 != 0;
                s.bias_impulses = flags & 8 != 0;
                let _ = space.set_settings(s);
            }
            Op::AddJoint { kind, a, b, p } => {
                if let (Some(a), Some(b), Some(k)) =
                    (pick_body(*a), pick_body(*b), joint_kind(*kind, *p))
                {
                    if let Ok(c) = Constraint::new(a, b, k) {
                        let _ = space.add_constraint(c);
                    }
                }
            }
            Op::RemoveJoint { joint } => {
                if let Some(j) = pick_joint(*joint) {
                    let _ = space.remove_constraint(j);
                }
            }
            Op::JointParams {
                joint,
                force,
                bias,
                error_bias,
                collide,
            } => {
                if let Some(c) = pick_joint(*joint).and_then(|j| space.constraint_mut(j)) {
                    let _ = c.set_max_force(real(*force, 8));
                    let _ = c.set_max_bias(real(*bias, 8));
                    let _ = c.set_error_bias(real(*error_bias, 0));
                    c.set_collide_bodies(*collide);
                }
            }
            Op::Sleep { body, group, how } => {
                if let (Some(b), Some(g)) = (pick_body(*body), pick_body(*group)) {
                    let _ = match how % 3 {
                        0 => space.sleep_body(b),
                        1 => space.sleep_body_with_group(b, g),
                        _ => space.activate_body(b),
                    };
                }
            }
            Op::SleepSettings {
                time,
                idle,
                body,
                allowed,
            } => {
                let mut s = *space.settings();
                s.sleep_time_threshold = real(i32::from(*time), 24);
                s.idle_speed_threshold = real(i32::from(*idle), 24);
                let _ = space.set_settings(s);
                if let Some(b) = pick_body(*body).and_then(|b| space.body_mut(b)) {
                    b.set_sleep_allowed(*allowed);
                }
            }
            Op::CloneRestore => {
                let copy = space.clone();
                space.restore_state(copy.state());
                assert_eq!(copy.checksum(), space.checksum());
            }
        }
        check_invariants(&space, op);
    }
});

/// The world's invariants after `op`. A dynamic body without mass (the
/// API allows one while its shapes are still to come) is the one thing a
/// world may hold that does not validate, and the error must say so; every
/// other invariant is checked on a copy where such bodies get a mass.
fn check_invariants(space: &Space, op: &Op) {
    let massless: Vec<_> = space
        .bodies()
        .filter(|(_, b)| !b.can_step())
        .map(|(h, _)| h)
        .collect();
    if massless.is_empty() {
        if let Err(e) = space.validate() {
            panic!("invariant broken after {op:?}: {e}");
        }
        return;
    }
    let why = space
        .validate()
        .expect_err("a world that cannot step validated");
    assert!(why.contains("without mass"), "after {op:?}: {why}");
    let mut probe = space.clone();
    for h in massless {
        if let Some(b) = probe.body_mut(h) {
            b.set_mass(Real::ONE).expect("a dynamic body takes a mass");
        }
    }
    if let Err(e) = probe.validate() {
        panic!("invariant broken after {op:?}: {e}");
    }
}
