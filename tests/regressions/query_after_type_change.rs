//! Regression: queries missed a body made static in place.
//!
//! Symptom: replacing a dynamic (or kinematic) body by a static one through
//! `body_mut` (`*space.body_mut(h).unwrap() = Body::new_static()`, the way
//! `space::level` documents) left its shapes invisible to point, box, ray
//! and shape queries until the next step. Cause: between steps, queries
//! take the static shapes from the static tree (built at the last step)
//! and the other bodies' shapes from their lists; a body that became
//! static since is in neither. Now a query that sees such a body scans
//! every shape, as it does when the static tree is stale.
//!
//! The class: every body type changed into every other one through
//! `body_mut`, each followed by every space query, before any step and
//! after one.
use tamias2d::body::{Body, BodyHandle, BodyType};
use tamias2d::math::{Real, Vect, BB};
use tamias2d::shape::{Geometry, Shape, ShapeFilter};
use tamias2d::space::{ShapeHandle, Space};

fn body_of(t: BodyType) -> Body {
    match t {
        BodyType::Dynamic => Body::new(Real::ONE, Real::ONE).unwrap(),
        BodyType::Kinematic => Body::new_kinematic(),
        BodyType::Static => Body::new_static(),
    }
}

/// A world with a floor and one 1 × 1 box of body type `t` at (5, 5),
/// stepped once so that the static tree and the body lists are built.
fn world(t: BodyType) -> (Space, BodyHandle, ShapeHandle) {
    let mut space = Space::new();
    let floor = space.add_body(Body::new_static()).unwrap();
    space
        .add_shape(
            Shape::segment_shape_new(
                floor,
                Vect::from_ints(-10, 0),
                Vect::from_ints(10, 0),
                Real::ZERO,
            )
            .unwrap(),
        )
        .unwrap();
    let b = space.add_body(body_of(t)).unwrap();
    space
        .body_mut(b)
        .unwrap()
        .set_position(Vect::from_ints(5, 5));
    let s = space
        .add_shape(Shape::box_shape_new(b, Real::ONE, Real::ONE, Real::ZERO).unwrap())
        .unwrap();
    space.step(Real::ratio(1, 60)).unwrap();
    (space, b, s)
}

/// Every space query finds the box at (5, 5) (its body at `at`).
fn every_query_finds(space: &Space, s: ShapeHandle, at: Vect, what: &str) {
    let all = ShapeFilter::ALL;
    let hit = |hs: Vec<ShapeHandle>| hs.contains(&s);
    assert!(
        hit(space
            .point_query(at, Real::ZERO, all)
            .into_iter()
            .map(|(h, _)| h)
            .collect()),
        "{what}: point query"
    );
    assert!(
        space
            .point_query_nearest(at, Real::ONE, all)
            .is_some_and(|(h, _)| h == s),
        "{what}: nearest point query"
    );
    assert!(
        hit(space.bb_query(BB::for_point(at), all)),
        "{what}: box query"
    );
    let (above, below) = (at + Vect::from_ints(0, 3), at - Vect::from_ints(0, 3));
    assert!(
        hit(space
            .segment_query(above, below, Real::ZERO, all)
            .into_iter()
            .map(|(h, _)| h)
            .collect()),
        "{what}: ray query"
    );
    assert!(
        space
            .segment_query_first(above, below, Real::ZERO, all)
            .is_some_and(|(h, _)| h == s),
        "{what}: first hit"
    );
    let probe = Geometry::Circle(tamias2d::shape::Circle::new(Real::HALF, at));
    assert!(
        hit(space
            .shape_query(&probe, all)
            .into_iter()
            .map(|(h, _)| h)
            .collect()),
        "{what}: shape query"
    );
}

#[test]
fn a_body_replaced_in_place_is_seen_by_every_query_at_once() {
    let types = [BodyType::Dynamic, BodyType::Kinematic, BodyType::Static];
    for from in types {
        for to in types {
            let (mut space, b, s) = world(from);
            let at = Vect::from_ints(3, 4);
            {
                let body = space.body_mut(b).unwrap();
                *body = body_of(to);
                body.set_position(at);
            }
            let what = format!("{from:?} -> {to:?}");
            every_query_finds(&space, s, at, &format!("{what}, before a step"));
            if to == BodyType::Dynamic {
                // Keep it in place for the check after the step.
                space.set_gravity(Vect::ZERO);
            }
            space.step(Real::ratio(1, 60)).unwrap();
            let at = space.body(b).unwrap().position();
            every_query_finds(&space, s, at, &format!("{what}, after a step"));
        }
    }
}
