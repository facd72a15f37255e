//! Desync diagnosis: per-object checksums and the first difference between
//! two worlds.
//!
//! When a peer reports a checksum that differs from ours, the game needs to
//! know *what* differs. Two tools, from cheap to thorough:
//! * [`checksum_parts`]: one digest per body, shape and constraint (by
//!   handle) and one for each of settings, arenas, arbiters and counters. Small enough
//!   to send over the network (it is serde data);
//!   [`ChecksumParts::first_mismatch`] names the first part that differs.
//! * [`first_difference`]: with both worlds at hand (a replay, or a
//!   snapshot from the peer), the first differing field and both values.
//!
//! Both walk the state in canonical order (settings, bodies by slot, shapes
//! by slot, arbiters, counters), so the first difference is the same on
//! every peer. Digests use [`checksum_of`], the hash behind
//! [`Space::checksum`].
use core::fmt;

use serde::{Deserialize, Serialize};

use crate::arbiter::Arbiter;
use crate::arena::{Arena, Handle};
use crate::body::{Body, BodyHandle};
use crate::checksum::checksum_of;
use crate::constraint::{Constraint, ConstraintHandle};
use crate::shape::Shape;
use crate::space::{Settings, ShapeHandle, Space, WorldState};

/// Digests of the parts of a world (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChecksumParts {
    /// Settings.
    pub settings: u64,
    /// Each live body, in slot order.
    pub bodies: Vec<(BodyHandle, u64)>,
    /// The whole body arena (bodies, free-slot generations, free list).
    pub body_arena: u64,
    /// Each live shape, in slot order.
    pub shapes: Vec<(ShapeHandle, u64)>,
    /// The whole shape arena.
    pub shape_arena: u64,
    /// All arbiters, in canonical order.
    pub arbiters: u64,
    /// Each live constraint, in slot order.
    pub constraints: Vec<(ConstraintHandle, u64)>,
    /// The whole constraint arena.
    pub constraint_arena: u64,
    /// Step stamp, current and previous `dt`.
    pub counters: u64,
}

/// What a difference is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Subject {
    /// The settings.
    Settings,
    /// A body (the handle of world a's body, or b's if a has none there).
    Body(BodyHandle),
    /// The body arena outside the live bodies: free list or generations of
    /// free slots.
    BodyArena,
    /// A shape.
    Shape(ShapeHandle),
    /// The shape arena outside the live shapes.
    ShapeArena,
    /// The arbiter at this position of the canonical list.
    Arbiter(usize),
    /// The arbiter list as a whole (its length, or its digest).
    Arbiters,
    /// The dormant arbiter (of a sleeping island) at this position.
    DormantArbiter(usize),
    /// The dormant arbiter list as a whole.
    DormantArbiters,
    /// A constraint.
    Constraint(ConstraintHandle),
    /// The constraint arena outside the live constraints.
    ConstraintArena,
    /// Step stamp or time steps.
    Counters,
}

impl fmt::Display for Subject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Subject::Settings => f.write_str("settings"),
            Subject::Body(h) => write!(f, "body {h:?}"),
            Subject::BodyArena => f.write_str("body arena"),
            Subject::Shape(h) => write!(f, "shape {h:?}"),
            Subject::ShapeArena => f.write_str("shape arena"),
            Subject::Arbiter(i) => write!(f, "arbiter [{i}]"),
            Subject::Arbiters => f.write_str("arbiters"),
            Subject::DormantArbiter(i) => write!(f, "dormant arbiter [{i}]"),
            Subject::DormantArbiters => f.write_str("dormant arbiters"),
            Subject::Constraint(h) => write!(f, "constraint {h:?}"),
            Subject::ConstraintArena => f.write_str("constraint arena"),
            Subject::Counters => f.write_str("counters"),
        }
    }
}

/// The first difference between two worlds: what, which field, and the two
/// values (`Debug` forms; `a` is the first world).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Difference {
    /// The object or part.
    pub subject: Subject,
    /// The field (`"v"`, `"geometry"`, `"stamp"`, …) or what differs about
    /// the object (`"presence"`, `"generation"`, `"free list"`).
    pub field: &'static str,
    /// The value in world a.
    pub a: String,
    /// The value in world b.
    pub b: String,
}

impl fmt::Display for Difference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} differs (a: {}, b: {})",
            self.subject, self.field, self.a, self.b
        )
    }
}

/// Digests of `space`'s parts (see [`ChecksumParts`]).
pub fn checksum_parts(space: &Space) -> ChecksumParts {
    let s = space.state();
    ChecksumParts {
        settings: checksum_of(&s.settings),
        bodies: s.bodies.iter().map(|(h, b)| (h, checksum_of(b))).collect(),
        body_arena: checksum_of(&s.bodies),
        shapes: s.shapes.iter().map(|(h, x)| (h, checksum_of(x))).collect(),
        shape_arena: checksum_of(&s.shapes),
        arbiters: checksum_of(&s.arbiters),
        constraints: s
            .constraints
            .iter()
            .map(|(h, c)| (h, checksum_of(c)))
            .collect(),
        constraint_arena: checksum_of(&s.constraints),
        counters: checksum_of(&counters(s)),
    }
}

fn counters(s: &WorldState) -> (u64, u64, crate::Real, crate::Real) {
    (s.stamp, s.steps, s.current_dt, s.prev_dt)
}

impl ChecksumParts {
    /// The first part that differs, in canonical order (settings, bodies,
    /// body arena, shapes, shape arena, arbiters, constraints, constraint
    /// arena, counters); `None` if all digests agree.
    pub fn first_mismatch(&self, other: &ChecksumParts) -> Option<Subject> {
        if self.settings != other.settings {
            return Some(Subject::Settings);
        }
        if let Some(h) = first_entry_mismatch(&self.bodies, &other.bodies) {
            return Some(Subject::Body(h));
        }
        if self.body_arena != other.body_arena {
            return Some(Subject::BodyArena);
        }
        if let Some(h) = first_entry_mismatch(&self.shapes, &other.shapes) {
            return Some(Subject::Shape(h));
        }
        if self.shape_arena != other.shape_arena {
            return Some(Subject::ShapeArena);
        }
        if self.arbiters != other.arbiters {
            return Some(Subject::Arbiters);
        }
        if let Some(h) = first_entry_mismatch(&self.constraints, &other.constraints) {
            return Some(Subject::Constraint(h));
        }
        if self.constraint_arena != other.constraint_arena {
            return Some(Subject::ConstraintArena);
        }
        (self.counters != other.counters).then_some(Subject::Counters)
    }
}

/// The first handle (in slot order) whose digest differs or that only one
/// list has.
fn first_entry_mismatch<T>(a: &[(Handle<T>, u64)], b: &[(Handle<T>, u64)]) -> Option<Handle<T>> {
    let (mut i, mut j) = (a.iter().peekable(), b.iter().peekable());
    loop {
        match (i.peek(), j.peek()) {
            (None, None) => return None,
            (Some((h, _)), None) | (None, Some((h, _))) => return Some(*h),
            (Some((ha, da)), Some((hb, db))) => {
                if ha.index() != hb.index() {
                    return Some(if ha.index() < hb.index() { *ha } else { *hb });
                }
                if ha != hb || da != db {
                    return Some(*ha);
                }
                i.next();
                j.next();
            }
        }
    }
}

/// Compares the fields of two values of struct `$ty` in the order given;
/// returns the first differing one as `(name, a, b)` in `Debug` form.
///
/// The list is checked against the struct by the compiler: the macro first
/// destructures `a` with exactly the listed fields and no `..`, so a field
/// added to the struct (or one left out of the list) is a compile error
/// here, and `first_difference` can never miss a field. Nested values
/// (`Vect`, `Geometry`, `Material`, contact arrays) are compared whole by
/// their derived `PartialEq`, which covers all their fields. The form with
/// `_` instead of a type compares a subset of a struct whose completeness
/// is checked by a destructuring elsewhere.
macro_rules! first_field {
    ($ty:ident; $a:expr, $b:expr; $($field:ident),+ $(,)?) => {{
        let $ty { $($field: _),+ } = $a;
        first_field!(_; $a, $b; $($field),+)
    }};
    (_; $a:expr, $b:expr; $($field:ident),+ $(,)?) => {{
        let (a, b) = ($a, $b);
        None$(.or_else(|| {
            (a.$field != b.$field).then(|| {
                (stringify!($field), format!("{:?}", a.$field), format!("{:?}", b.$field))
            })
        }))+
    }};
}

/// The first difference between worlds `a` and `b`, in canonical order:
/// settings, bodies (slot by slot: presence, generation, then each field),
/// the body arena's free list, shapes likewise, arbiters (one by one, then
/// the count), constraints like bodies, counters. `None` if the states are
/// equal.
pub fn first_difference(a: &Space, b: &Space) -> Option<Difference> {
    let (sa, sb) = (a.state(), b.state());
    // Every part of the state, named so that a new one is a compile error
    // until it is compared below: settings, the two arenas, the arbiters
    // (`arbiter_difference`) and the counters.
    let WorldState {
        settings,
        bodies,
        shapes,
        arbiters: _,
        stamp: _,
        steps: _,
        current_dt: _,
        prev_dt: _,
        constraints,
        dormant_arbiters: _,
    } = sa;
    let diff = |subject, (field, a, b): (&'static str, String, String)| Difference {
        subject,
        field,
        a,
        b,
    };
    let found = first_field!(Settings; settings, &sb.settings;
        iterations, gravity, damping, collision_slop, collision_bias, collision_persistence,
        substeps, warm_starting, friction, restitution, bias_impulses, block_solver,
        colored_solver,
        sleep_time_threshold, idle_speed_threshold, solver)
    .map(|f| diff(Subject::Settings, f));
    found
        .or_else(|| first_slot_difference(bodies, &sb.bodies, Subject::Body, body_fields))
        .or_else(|| arena_rest(bodies, &sb.bodies, Subject::BodyArena))
        .or_else(|| first_slot_difference(shapes, &sb.shapes, Subject::Shape, shape_fields))
        .or_else(|| arena_rest(shapes, &sb.shapes, Subject::ShapeArena))
        .or_else(|| {
            arbiter_list_difference(
                &sa.arbiters,
                &sb.arbiters,
                Subject::Arbiter,
                Subject::Arbiters,
            )
        })
        .or_else(|| {
            arbiter_list_difference(
                &sa.dormant_arbiters,
                &sb.dormant_arbiters,
                Subject::DormantArbiter,
                Subject::DormantArbiters,
            )
        })
        .or_else(|| {
            first_slot_difference(
                constraints,
                &sb.constraints,
                Subject::Constraint,
                constraint_fields,
            )
        })
        .or_else(|| arena_rest(constraints, &sb.constraints, Subject::ConstraintArena))
        .or_else(|| {
            first_field!(_; sa, sb; stamp, steps, current_dt, prev_dt)
                .map(|f| diff(Subject::Counters, f))
        })
}

fn body_fields(a: &Body, b: &Body) -> Option<(&'static str, String, String)> {
    first_field!(Body; a, b; body_type, mass, mass_inv, moment, moment_inv, explicit_mass, cog,
        p, v, f, a, rot, w, t, v_bias, w_bias, sleep, bullet)
}

fn constraint_fields(a: &Constraint, b: &Constraint) -> Option<(&'static str, String, String)> {
    first_field!(Constraint; a, b; a, b, max_force, error_bias, max_bias, collide_bodies, kind, softness)
}

fn shape_fields(a: &Shape, b: &Shape) -> Option<(&'static str, String, String)> {
    first_field!(Shape; a, b; body, geometry, material, filter, collision_type, sensor, mass_spec)
}

type FieldDiff = (&'static str, String, String);

/// Slot by slot over two arenas: a slot live in one world only, a live
/// slot with another generation, or the first differing field.
fn first_slot_difference<T>(
    a: &Arena<T>,
    b: &Arena<T>,
    subject: fn(Handle<T>) -> Subject,
    fields: impl Fn(&T, &T) -> Option<FieldDiff>,
) -> Option<Difference> {
    let slots = a.capacity_slots().max(b.capacity_slots());
    let show = |x: Option<Handle<T>>| x.map_or_else(|| "none".to_owned(), |h| format!("{h:?}"));
    (0..slots).find_map(|i| {
        let i = u32::try_from(i).ok()?;
        let (x, y) = (a.get_by_index(i), b.get_by_index(i));
        let (handle, field) = match (x, y) {
            (None, None) => return None,
            (Some((hx, vx)), Some((hy, vy))) if hx == hy => {
                let (field, va, vb) = fields(vx, vy)?;
                return Some(Difference {
                    subject: subject(hx),
                    field,
                    a: va,
                    b: vb,
                });
            }
            (Some((hx, _)), Some(_)) => (hx, "generation"),
            (Some((h, _)), None) | (None, Some((h, _))) => (h, "presence"),
        };
        Some(Difference {
            subject: subject(handle),
            field,
            a: show(x.map(|(h, _)| h)),
            b: show(y.map(|(h, _)| h)),
        })
    })
}

/// Live objects equal, arenas not: the free list or a free slot's
/// generation differs (the public arena API shows neither, so the digests
/// are reported).
fn arena_rest<T: core::hash::Hash>(
    a: &Arena<T>,
    b: &Arena<T>,
    subject: Subject,
) -> Option<Difference> {
    let (da, db) = (checksum_of(a), checksum_of(b));
    (da != db).then(|| Difference {
        subject,
        field: if a.capacity_slots() == b.capacity_slots() {
            "free list or free-slot generations"
        } else {
            "slot count"
        },
        a: format!("digest {da:#018x}, {} slots", a.capacity_slots()),
        b: format!("digest {db:#018x}, {} slots", b.capacity_slots()),
    })
}

fn arbiter_list_difference(
    la: &[Arbiter],
    lb: &[Arbiter],
    at: fn(usize) -> Subject,
    whole: Subject,
) -> Option<Difference> {
    let found = la.iter().zip(lb).enumerate().find_map(|(i, (x, y))| {
        first_field!(Arbiter; x, y; shape_a, shape_b, body_a, body_b, normal, count, contacts,
                restitution, friction, surface_velocity, warm_start_id, stamp, state, sensor)
        .map(|(field, a, b)| Difference {
            subject: at(i),
            field,
            a,
            b,
        })
    });
    found.or_else(|| {
        (la.len() != lb.len()).then(|| Difference {
            subject: whole,
            field: "count",
            a: la.len().to_string(),
            b: lb.len().to_string(),
        })
    })
}
