//! Regression: a negative friction set through the public `material` field
//! was accepted by `Space::add_shape`, `Space::modify_shape` and snapshot
//! validation, and a sliding box sped up from 1 to 6 m/s (friction pushed
//! it forward). Likewise an elasticity above 1 (energy gain at every bounce)
//! or below 0. Cause: only `Shape::with_material` checked the material; the
//! field is public, and neither the space nor `validate_state` looked at it.
//! Fix: `Material::validate` (friction ≥ 0, elasticity in [0, 1], any
//! surface velocity), run by `add_shape`, `modify_shape`, `with_material`
//! and `validate_state` (so `snapshot::load` and `load_snapshot`).
use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::{Material, Shape, ShapeError};
use tamias2d::snapshot::{self, SnapshotError};
use tamias2d::space::{Space, SpaceError};

fn world() -> (Space, Shape) {
    let mut space = Space::new();
    let body = space
        .add_body(Body::new(real!(1), real!(1)).unwrap())
        .unwrap();
    let shape = Shape::circle_shape_new(body, real!(1), Vect::ZERO).unwrap();
    (space, shape)
}

fn bad_materials() -> Vec<(Material, ShapeError)> {
    let ok = Material::default();
    vec![
        (
            Material {
                friction: real!(-0.5),
                ..ok
            },
            ShapeError::Negative("friction"),
        ),
        (
            Material {
                friction: Real::from_bits(-1),
                ..ok
            },
            ShapeError::Negative("friction"),
        ),
        (
            Material {
                elasticity: real!(-0.1),
                ..ok
            },
            ShapeError::Negative("elasticity"),
        ),
        (
            Material {
                elasticity: Real::ONE + Real::from_bits(1),
                ..ok
            },
            ShapeError::AboveOne("elasticity"),
        ),
    ]
}

#[test]
fn add_shape_rejects_bad_materials() {
    for (m, err) in bad_materials() {
        let (mut space, mut shape) = world();
        shape.material = m;
        let before = space.checksum();
        assert_eq!(space.add_shape(shape), Err(SpaceError::Shape(err)));
        assert_eq!(space.checksum(), before, "space changed by a failed add");
        assert_eq!(space.shapes().count(), 0);
    }
}

#[test]
fn modify_shape_rejects_bad_materials() {
    for (m, err) in bad_materials() {
        let (mut space, shape) = world();
        let h = space.add_shape(shape).unwrap();
        let before = space.checksum();
        assert_eq!(
            space.modify_shape(h, |s| {
                s.material = m;
                Ok(())
            }),
            Err(SpaceError::Shape(err))
        );
        assert_eq!(space.checksum(), before, "shape changed by a failed modify");
    }
}

#[test]
fn with_material_rejects_elasticity_above_one() {
    let (_, shape) = world();
    assert_eq!(
        shape.clone().with_material(real!(0.5), real!(1.5)),
        Err(ShapeError::AboveOne("elasticity"))
    );
    assert!(shape.with_material(real!(0.5), Real::ONE).is_ok());
}

#[test]
fn snapshot_load_rejects_bad_materials() {
    for (m, _) in bad_materials() {
        let (mut space, shape) = world();
        let h = space.add_shape(shape).unwrap();
        let mut state = space.state().clone();
        state.shapes.get_mut(h).unwrap().material = m;
        let bytes = snapshot::save_state(&state);
        match snapshot::load(&bytes) {
            Err(SnapshotError::Invalid(why)) => assert!(
                why.contains("elasticity") || why.contains("friction"),
                "{why}"
            ),
            other => panic!("forged material accepted: {other:?}"),
        }
        let before = space.checksum();
        assert!(space.load_snapshot(&bytes).is_err());
        assert_eq!(space.checksum(), before);
    }
}

#[test]
fn boundary_materials_are_accepted() {
    let (mut space, mut shape) = world();
    shape.material = Material {
        friction: Real::MAX,
        elasticity: Real::ONE,
        surface_velocity: Vect::new(Real::MIN, Real::MAX),
    };
    let h = space.add_shape(shape).unwrap();
    space
        .modify_shape(h, |s| {
            s.material = Material::default();
            Ok(())
        })
        .unwrap();
    assert!(snapshot::load(&snapshot::save(&space)).is_ok());
}

/// The symptom: a box sliding on ground with a (now rejected) negative
/// friction sped up. With valid friction it slows down.
#[test]
fn sliding_box_never_speeds_up() {
    let mut space = Space::new();
    space.set_gravity(Vect::new(Real::ZERO, real!(-10)));
    let ground = space.add_body(Body::new_static()).unwrap();
    let seg = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-100, 0),
        Vect::from_ints(100, 0),
        Real::ZERO,
    )
    .unwrap();
    let mut seg = seg;
    seg.material.friction = Real::ONE;
    space.add_shape(seg).unwrap();
    let b = space
        .add_body(Body::new(real!(1), real!(1)).unwrap())
        .unwrap();
    space
        .body_mut(b)
        .unwrap()
        .set_position(Vect::new(Real::ZERO, real!(0.5)));
    space
        .body_mut(b)
        .unwrap()
        .set_velocity(Vect::from_ints(1, 0));
    let mut boxed = Shape::box_shape_new(b, Real::ONE, Real::ONE, Real::ZERO).unwrap();
    boxed.material.friction = real!(-1);
    assert!(space.add_shape(boxed.clone()).is_err());
    boxed.material.friction = real!(0.5);
    space.add_shape(boxed).unwrap();
    for _ in 0..60 {
        space.step(real!(1) / real!(60)).unwrap();
    }
    assert!(space.body(b).unwrap().velocity().x < Real::ONE);
}
