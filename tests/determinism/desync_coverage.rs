//! Exhaustive mirrors: every field of the world state is seen by the
//! desync tools.
//!
//! The state is walked generically through its serde form (JSON here), so a
//! field added to any state type, at any depth, is covered without editing
//! this test: each leaf (number, bool, enum variant) of a small world with
//! every shape kind, arbiters and free slots is changed in turn, and the
//! changed world must
//! * differ under `==` (the snapshot's derived `PartialEq` sees the field),
//! * have another [`Space::checksum`] (the `Hash` impls see it),
//! * be reported by [`first_difference`], under the subject the field
//!   belongs to and, for a field of a settings, body, shape or arbiter
//!   struct, under that field's name (the hand-kept field lists of
//!   `snapshot::diff` are complete and correctly named), and
//! * be reported by [`ChecksumParts::first_mismatch`].
//!
//! (The field lists of `first_difference` are also checked by the compiler:
//! they destructure each struct with no `..`.)
use serde_json::Value;
use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{
    Constraint, DampedRotarySpring, DampedSpring, GearJoint, GrooveJoint, JointKind, PinJoint,
    PivotJoint, RatchetJoint, RotaryLimitJoint, SimpleMotor, SlideJoint,
};
use tamias2d::shape::Shape;
use tamias2d::snapshot::{checksum_parts, first_difference, Subject};
use tamias2d::space::{Space, WorldState};
use tamias2d::{Real, Transform, Vect};

fn ok<T, E: std::fmt::Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

/// Bodies resting on a ground segment: a circle, a box, a hexagon and a
/// capsule (so arbiters with one and two contacts exist), one body removed
/// (a free slot), one constraint of each kind (one removed: a free
/// constraint slot), non-default settings, after 60 steps.
fn world() -> Space {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = ok(w.add_body(Body::new_static()));
    let seg = ok(Shape::segment_shape_new(
        ground,
        Vect::from_ints(-40, 0),
        Vect::from_ints(40, 0),
        Real::HALF,
    ));
    ok(w.add_shape(ok(seg.with_material(Real::ONE, Real::HALF))));
    let hexagon: Vec<Vect> = [(2, 0), (1, 2), (-1, 2), (-2, 0), (-1, -2), (1, -2)]
        .iter()
        .map(|&(x, y)| Vect::from_ints(x, y) * Real::HALF)
        .collect();
    for (i, kind) in (0..5).enumerate() {
        let mut b = ok(Body::new(Real::ZERO, Real::ZERO));
        b.set_position(Vect::from_ints(i32::try_from(i).unwrap_or(0) * 4 - 8, 2));
        let h = ok(w.add_body(b));
        let mut shape = ok(match kind {
            0 | 4 => Shape::circle_shape_new(h, Real::ONE, Vect::ZERO),
            1 => Shape::box_shape_new(h, Real::TWO, Real::ONE, Real::ZERO),
            2 => Shape::poly_shape_new(h, &hexagon, &Transform::IDENTITY, Real::ZERO),
            _ => Shape::segment_shape_new(
                h,
                Vect::from_ints(-1, 0),
                Vect::from_ints(1, 0),
                Real::HALF,
            ),
        });
        ok(shape.set_density(Real::ONE));
        shape.collision_type = 7;
        ok(w.add_shape(shape));
        if kind == 4 {
            ok(w.remove_body(h));
        }
    }
    let dynamic: Vec<_> = w
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .collect();
    let (b0, b1, b2, b3) = (dynamic[0], dynamic[1], dynamic[2], dynamic[3]);
    let half = Vect::new(Real::HALF, Real::ZERO);
    let quarter = Real::HALF * Real::HALF;
    let kinds: [(BodyHandle, BodyHandle, JointKind); 11] = [
        (
            b0,
            b1,
            ok(PinJoint::new(half, -half, Real::from_int(3))).into(),
        ),
        (b1, b2, ok(PivotJoint::new(half, -half)).into()),
        (
            b2,
            b3,
            ok(DampedSpring::new(
                Vect::ZERO,
                Vect::ZERO,
                Real::TWO,
                Real::from_int(50),
                Real::ONE,
            ))
            .into(),
        ),
        (ground, b3, ok(SimpleMotor::new(Real::HALF)).into()),
        (b0, b3, ok(GearJoint::new(Real::ZERO, Real::TWO)).into()),
        (b0, b2, ok(SimpleMotor::new(Real::ONE)).into()),
        (
            b1,
            b3,
            ok(SlideJoint::new(half, -half, Real::ONE, Real::from_int(3))).into(),
        ),
        (b2, b0, ok(RotaryLimitJoint::new(-quarter, quarter)).into()),
        (
            b3,
            b1,
            ok(DampedRotarySpring::new(
                quarter,
                Real::from_int(20),
                Real::HALF,
            ))
            .into(),
        ),
        (
            ground,
            b2,
            ok(GrooveJoint::new(
                Vect::from_ints(0, -5),
                Vect::from_ints(0, 5),
                Vect::ZERO,
            ))
            .into(),
        ),
        (
            ground,
            b1,
            ok(RatchetJoint::new(quarter, Real::HALF)).into(),
        ),
    ];
    let mut handles = Vec::new();
    for (a, b, kind) in kinds {
        let mut c = ok(Constraint::new(a, b, kind));
        ok(c.set_max_force(Real::from_int(1000)));
        c.set_collide_bodies(a == ground);
        handles.push(ok(w.add_constraint(c)));
    }
    ok(w.remove_constraint(handles[5]));
    for _ in 0..60 {
        ok(w.step(Real::ONE / Real::from_int(60)));
    }
    assert!(
        w.arbiters().len() >= 3,
        "the bodies rest on the ground: {:?}",
        w.bodies().map(|(_, b)| b.position()).collect::<Vec<_>>()
    );
    ok(w.validate());
    w
}

/// A step of a path into the JSON tree.
#[derive(Clone, Debug)]
enum Key {
    Field(String),
    Index(usize),
}

/// Every leaf of `v` (numbers, bools, strings) with its path; `null` (an
/// empty arena slot) has no field below it and is skipped.
fn leaves(v: &Value, path: &mut Vec<Key>, out: &mut Vec<Vec<Key>>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                path.push(Key::Field(k.clone()));
                leaves(x, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Key::Index(i));
                leaves(x, path, out);
                path.pop();
            }
        }
        Value::Null => {}
        Value::Bool(_) | Value::Number(_) | Value::String(_) => out.push(path.clone()),
    }
}

fn at<'a>(v: &'a mut Value, path: &[Key]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match k {
        Key::Field(f) => &mut v[f.as_str()],
        Key::Index(i) => &mut v[*i],
    })
}

/// Unit variants of the state's enums (`BodyType`, `ArbiterState`): a
/// string leaf is changed to another one that decodes, or to one of
/// [`DATA_VARIANTS`] (`MassSpec::None` becomes `Mass(ε)` or `Density(ε)`).
const VARIANTS: &[&str] = &[
    "Dynamic",
    "Kinematic",
    "Static",
    "FirstCollision",
    "Normal",
    "Ignore",
    "Cached",
];

/// Variants with one number (`MassSpec`).
const DATA_VARIANTS: &[&str] = &["Mass", "Density"];

/// The candidate replacements of a leaf, each different from it.
fn changes(leaf: &Value) -> Vec<Value> {
    match leaf {
        Value::Bool(b) => vec![Value::Bool(!b)],
        Value::Number(n) => {
            let changed = if let Some(u) = n.as_u64() {
                if u > 0 {
                    Value::from(u - 1)
                } else {
                    Value::from(1u64)
                }
            } else {
                Value::from(n.as_i64().unwrap_or(0) + 1)
            };
            vec![changed]
        }
        // The solver: the sequential one is a unit variant, the soft step
        // carries its parameters.
        Value::String(s) if s == "Sequential" => {
            vec![serde_json::to_value(tamias2d::space::Solver::SOFT).unwrap_or(Value::Null)]
        }
        Value::String(s) => VARIANTS
            .iter()
            .filter(|v| **v != s.as_str())
            .map(|v| Value::from(*v))
            .chain(DATA_VARIANTS.iter().map(|v| serde_json::json!({ *v: 1 })))
            .collect(),
        Value::Null | Value::Array(_) | Value::Object(_) => vec![],
    }
}

/// The subject kind and field name `first_difference` must report for a
/// change at `path`, given whether the slot it is in (if any) is live.
/// `None` as field: any field name (arena bookkeeping).
fn expected(path: &[Key], live: bool) -> (&'static str, Option<String>) {
    let name = |i: usize| match path.get(i) {
        Some(Key::Field(f)) => Some(f.clone()),
        _ => None,
    };
    let top = name(0).unwrap_or_default();
    match top.as_str() {
        "settings" => ("settings", name(1)),
        "arbiters" => ("arbiter", name(2)),
        "dormant_arbiters" => ("dormant arbiter", name(2)),
        "bodies" | "shapes" | "constraints" => {
            let (object, arena) = match top.as_str() {
                "bodies" => ("body", "body arena"),
                "shapes" => ("shape", "shape arena"),
                _ => ("constraint", "constraint arena"),
            };
            match (name(1).as_deref(), live) {
                (Some("slots"), true) if name(3).as_deref() == Some("generation") => {
                    (object, Some("generation".into()))
                }
                (Some("slots"), true) => (object, name(4)),
                _ => (arena, None),
            }
        }
        _ => ("counters", Some(top)),
    }
}

fn kind(s: Subject) -> &'static str {
    match s {
        Subject::Settings => "settings",
        Subject::Body(_) => "body",
        Subject::BodyArena => "body arena",
        Subject::Shape(_) => "shape",
        Subject::ShapeArena => "shape arena",
        Subject::Arbiter(_) => "arbiter",
        Subject::Arbiters => "arbiters",
        Subject::DormantArbiter(_) => "dormant arbiter",
        Subject::DormantArbiters => "dormant arbiters",
        Subject::Constraint(_) => "constraint",
        Subject::ConstraintArena => "constraint arena",
        Subject::Counters => "counters",
    }
}

/// Whether the arena slot `path` is in holds an object.
fn slot_is_live(json: &Value, path: &[Key]) -> bool {
    match path {
        [Key::Field(_), Key::Field(slots), Key::Index(i), ..] if slots == "slots" => {
            let arena = match &path[0] {
                Key::Field(f) => f.as_str(),
                Key::Index(_) => "",
            };
            !json[arena]["slots"][*i]["value"].is_null()
        }
        _ => false,
    }
}

#[test]
fn every_leaf_of_the_state_is_seen_by_eq_checksum_parts_and_first_difference() {
    let base = world();
    let json = serde_json::to_value(base.state()).unwrap_or(Value::Null);
    let mut paths = Vec::new();
    leaves(&json, &mut Vec::new(), &mut paths);
    let mut seen_tops = std::collections::BTreeSet::new();
    let mut kinds = std::collections::BTreeSet::new();
    for path in &paths {
        let mut changed = json.clone();
        let original = at(&mut changed, path).clone();
        // The first change that still decodes (numbers and bools always do;
        // a variant name must belong to the leaf's enum).
        let state = changes(&original).into_iter().find_map(|c| {
            *at(&mut changed, path) = c;
            serde_json::from_value::<WorldState>(changed.clone()).ok()
        });
        let Some(state) = state else {
            panic!("no change of the leaf {path:?} = {original} decodes");
        };
        let where_ = format!("leaf {path:?} (was {original})");
        assert_ne!(&state, base.state(), "{where_}: == does not see it");
        let other = Space::from_state(state);
        assert_ne!(
            other.checksum(),
            base.checksum(),
            "{where_}: the checksum does not see it"
        );
        let found = first_difference(&base, &other)
            .unwrap_or_else(|| panic!("{where_}: first_difference reports no difference"));
        let (subject, field) = expected(path, slot_is_live(&json, path));
        assert_eq!(
            kind(found.subject),
            subject,
            "{where_}: reported as {found}"
        );
        if let Some(field) = field {
            assert_eq!(found.field, field, "{where_}: reported as {found}");
        }
        let mismatch = checksum_parts(&base)
            .first_mismatch(&checksum_parts(&other))
            .unwrap_or_else(|| panic!("{where_}: the checksum parts all agree"));
        let parts_subject = if subject == "arbiter" {
            "arbiters"
        } else {
            subject
        };
        assert_eq!(
            kind(mismatch),
            parts_subject,
            "{where_}: parts report {mismatch}"
        );
        if let Some(Key::Field(f)) = path.first() {
            seen_tops.insert(f.clone());
        }
        kinds.insert(subject);
    }
    // Every part of the state had leaves to change.
    let tops: Vec<&str> = seen_tops.iter().map(String::as_str).collect();
    assert_eq!(
        tops,
        [
            "arbiters",
            "bodies",
            "constraints",
            "current_dt",
            "prev_dt",
            "settings",
            "shapes",
            "stamp",
            "steps"
        ]
    );
    // Every kind of subject was reported at least once.
    assert_eq!(
        kinds.into_iter().collect::<Vec<_>>(),
        [
            "arbiter",
            "body",
            "body arena",
            "constraint",
            "constraint arena",
            "counters",
            "settings",
            "shape",
            "shape arena"
        ]
    );
}
