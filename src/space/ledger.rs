//! The field ledger of [`validate_state`](super::validate_state): for every
//! field of every type in a [`WorldState`], the check that covers it, or why
//! it needs none.
//!
//! Each entry destructures its type with no `..`, so a field added to any
//! state type is a compile error here until someone decides how snapshot
//! loading (and the `validate` feature's check after every step) treats it.
//! The entries are never run: they are non-capturing closures in constants,
//! checked by the compiler and free at run time. "Any value" means the API
//! can produce every value of the field (validation accepts exactly what the
//! API can produce) and the step is safe with each of them (saturating
//! arithmetic, see `docs/numerics.md`).
//!
//! "Derived" marks a field that snapshots (format 6) do not store: a pure
//! function of stored fields, recomputed on decode exactly as the engine
//! computes it (see the `Serialize` impl of its type). Validation still
//! checks it, with the same strictness, for states that never went through
//! bytes (`Space::validate`, the `validate` feature's check after every
//! step, a state deserialized from a human-readable form, which carries
//! every field); for a decoded state the check holds by construction.
//!
//! Arena internals (slots, free list, length) are placed by
//! [`Arena::validate`](crate::arena::Arena::validate), which destructures
//! its own type the same way.
use super::{Settings, WorldState};
use crate::arbiter::{Arbiter, ArbiterState, ManifoldPoint};
use crate::body::{Body, BodyType};
use crate::constraint::{
    Constraint, DampedRotarySpring, DampedSpring, GearJoint, GrooveJoint, JointKind, PinJoint,
    PivotJoint, RatchetJoint, RotaryLimitJoint, SimpleMotor, SlideJoint,
};
use crate::shape::{Circle, Geometry, MassSpec, Material, Poly, Segment, Shape, ShapeFilter};

const _WORLD: fn(&WorldState) = |s| {
    let WorldState {
        settings: _,    // Settings::validate, see _SETTINGS
        bodies: _,      // Arena::validate, then each body (_BODY)
        shapes: _,      // Arena::validate, then each shape (_SHAPE)
        arbiters: _,    // canonical order, live shapes, their bodies (one dynamic), _ARBITER
        stamp: _,       // validate_counters: 0 exactly when no dt was taken
        steps: _,       // validate_counters: steps ≤ stamp
        current_dt: _,  // validate_counters: 0 before the first step, positive after
        prev_dt: _,     // validate_counters: 0 before the second step, positive after
        constraints: _, // Arena::validate, then each constraint (_CONSTRAINT)
        dormant_arbiters: _, // sleep::validate_sleep: sorted, not live, between sleeping
                        // bodies, age < stamp, then _ARBITER as of that age
    } = s;
};

const _CONSTRAINT: fn(&Constraint) = |c| {
    let Constraint {
        a: _,              // names a live body (generation included); not b
        b: _,              // names a live body
        max_force: _,      // ≥ 0 (Real::MAX: unbounded)
        error_bias: _,     // in [0, 1]
        max_bias: _,       // ≥ 0 (Real::MAX: unbounded)
        collide_bodies: _, // any value
        kind: _,           // see _JOINT_KIND
        softness: _,       // hertz and damping ratio in [0, 10⁶]
    } = c;
};

const _JOINT_KIND: fn(&JointKind) = |k| match k {
    JointKind::Pin(PinJoint {
        anchor_a: _, // not saturated
        anchor_b: _, // not saturated
        dist: _,     // > 0, not saturated
        jn_acc: _,   // any value (clamped by max_force·dt of its step, which may differ)
    }) => {}
    JointKind::Pivot(PivotJoint {
        anchor_a: _, // not saturated
        anchor_b: _, // not saturated
        j_acc: _,    // any value
    }) => {}
    JointKind::DampedSpring(DampedSpring {
        anchor_a: _,    // not saturated
        anchor_b: _,    // not saturated
        rest_length: _, // ≥ 0, not saturated
        stiffness: _,   // ≥ 0, not saturated
        damping: _,     // ≥ 0, not saturated
        j_acc: _,       // any value
    }) => {}
    JointKind::SimpleMotor(SimpleMotor {
        rate: _,  // not saturated
        j_acc: _, // any value
    }) => {}
    JointKind::Gear(GearJoint {
        phase: _, // not saturated
        ratio: _, // not zero, not saturated
        j_acc: _, // any value
    }) => {}
    JointKind::Slide(SlideJoint {
        anchor_a: _, // not saturated
        anchor_b: _, // not saturated
        min: _,      // ≥ 0, not saturated
        max: _,      // ≥ min, not saturated
        jn_acc: _,   // any value
    }) => {}
    JointKind::RotaryLimit(RotaryLimitJoint {
        min: _,   // not saturated
        max: _,   // ≥ min, not saturated
        j_acc: _, // any value
    }) => {}
    JointKind::DampedRotarySpring(DampedRotarySpring {
        rest_angle: _, // not saturated
        stiffness: _,  // ≥ 0, not saturated
        damping: _,    // ≥ 0, not saturated
        j_acc: _,      // any value
    }) => {}
    JointKind::Groove(GrooveJoint {
        groove_a: _, // not saturated; differs from groove_b
        groove_b: _, // not saturated
        anchor_b: _, // not saturated
        j_acc: _,    // any value
    }) => {}
    JointKind::Ratchet(RatchetJoint {
        angle: _,   // any value (the step sets it from the bodies' angles)
        phase: _,   // not saturated
        ratchet: _, // not zero, not saturated
        j_acc: _,   // any value
    }) => {}
};

const _SETTINGS: fn(&Settings) = |s| {
    let Settings {
        iterations: _,            // ≤ MAX_ITERATIONS (a step's work)
        gravity: _,               // any value
        damping: _,               // ≥ 0
        collision_slop: _,        // ≥ 0
        collision_bias: _,        // in [0, 1]
        collision_persistence: _, // any value (bounds how long arbiters stay)
        substeps: _,              // 1..=MAX_SUBSTEPS
        warm_starting: _,         // any value
        friction: _,              // any value
        restitution: _,           // any value
        bias_impulses: _,         // any value
        block_solver: _,          // any value
        colored_solver: _,        // any value
        sleep_time_threshold: _,  // ≥ 0 (SLEEP_NEVER: off)
        idle_speed_threshold: _,  // ≥ 0
        solver: _,                // soft: SoftStep::validate's ranges
    } = s;
};

const _BODY: fn(&Body) = |b| {
    let Body {
        body_type: _, // any; decides the mass checks below
        mass: _,      // ≥ 0; 0 unless dynamic
        mass_inv: _,  // derived: the engine's inverse of mass (0 for 0); 0 unless dynamic;
        // positive for a dynamic body (Body::can_step, the step's precondition)
        moment: _,        // ≥ 0; 0 unless dynamic
        moment_inv: _,    // derived: the engine's inverse of moment; 0 unless dynamic
        explicit_mass: _, // false unless dynamic; for a dynamic body any value (the
        // mass is not cross-checked against the shapes' mass specifications)
        cog: _,    // any value
        p: _,      // any value (saturation is reported by StepStats, not invalid)
        v: _,      // any value
        f: _,      // any value
        a: _,      // any value
        rot: _,    // unit length within 2^-20
        w: _,      // any value
        t: _,      // any value
        v_bias: _, // any value (the last solve's pseudo-velocity, used by the next step)
        w_bias: _, // any value
        sleep: _,  // see _SLEEP
        bullet: _, // any value (no effect on kinematic and static bodies)
    } = b;
    match b.body_type {
        BodyType::Dynamic | BodyType::Kinematic | BodyType::Static => {}
    }
};

const _SLEEP: fn(&crate::body::SleepState) = |s| {
    let crate::body::SleepState {
        idle_time: _, // ≥ 0
        island: _,    // Some only for a dynamic body that may sleep, with zero velocities,
        // bias velocities, force and torque; the root is a sleeping body whose root is itself
        allowed: _, // any value
    } = s;
};

const _SHAPE: fn(&Shape) = |s| {
    let Shape {
        body: _,           // names a live body (generation included)
        geometry: _,       // Geometry::validate, see _GEOMETRY
        material: _,       // any value, see _MATERIAL
        filter: _,         // any value, see _FILTER
        collision_type: _, // any value
        sensor: _,         // any value
        mass_spec: _,      // see _MASS_SPEC
    } = s;
};

const _MATERIAL: fn(&Material) = |m| {
    let Material {
        friction: _,         // any value (the field is public)
        elasticity: _,       // any value (the field is public)
        surface_velocity: _, // any value
    } = m;
};

const _FILTER: fn(&ShapeFilter) = |f| {
    let ShapeFilter {
        group: _,      // any value
        categories: _, // any value
        mask: _,       // any value
    } = f;
};

const _MASS_SPEC: fn(&MassSpec) = |m| match m {
    MassSpec::None => {}
    MassSpec::Mass(_) | MassSpec::Density(_) => {} // ≥ 0
};

const _GEOMETRY: fn(&Geometry) = |g| match g {
    Geometry::Circle(Circle {
        offset: _, // any value
        radius: _, // ≥ 0
    }) => {}
    Geometry::Segment(Segment {
        a: _,         // any value
        b: _,         // any value
        normal: _,    // derived: exactly what Segment::new computes from a and b
        radius: _,    // ≥ 0
        a_tangent: _, // any value (zero: no neighbour)
        b_tangent: _, // any value
    }) => {}
    Geometry::Poly(Poly {
        count: _,   // 3..=MAX_POLY_VERTICES
        verts: _,   // strictly convex, counter-clockwise; zero past count (derived)
        normals: _, // derived: exactly what Poly::from_ccw computes; zero past count
        radius: _,  // ≥ 0
    }) => {}
};

const _ARBITER: fn(&Arbiter) = |a| {
    let Arbiter {
        shape_a: _,          // live; slot index below shape_b's; canonical order in the list
        shape_b: _,          // live
        body_a: _,           // shape_a's body; not body_b; one of the two dynamic
        body_b: _,           // shape_b's body
        normal: _,           // any value
        count: _,            // 1..=MAX_CONTACTS_PER_ARBITER
        contacts: _,         // see _CONTACT; past count the default (derived)
        restitution: _,      // any value (handlers may set it)
        friction: _,         // any value (handlers may set it)
        surface_velocity: _, // any value (handlers may set it)
        warm_start_id: _, // any value (a warm-start hint; one naming no vertices means a cold start)
        stamp: _,         // 1..=world stamp
        state: _,         // see below
        sensor: _,        // any value
    } = a;
    match a.state {
        ArbiterState::FirstCollision => {} // never between steps
        ArbiterState::Normal | ArbiterState::Ignore => {} // touched in the last sub-step
        ArbiterState::Cached => {}         // not touched in the last sub-step
    }
};

const _CONTACT: fn(&ManifoldPoint) = |c| {
    let ManifoldPoint {
        r1: _,         // any value
        r2: _,         // any value
        dist: _,       // any value
        feature_id: _, // any value (matched by equality only)
        jn_acc: _,     // ≥ 0 (the solver clamps the accumulated normal impulse)
        jt_acc: _,     // any value
    } = c;
};
