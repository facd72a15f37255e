//! A dynamic body replaced in place through `body_mut` (`*body = …`) by a
//! static or kinematic one while it touches the ground used to leave its
//! arbiter to a pair that never collides: the next step's validation
//! failed ("pairs bodies that never collide"). The step now drops such
//! arbiters (with their separate callbacks), and a body turned static
//! joins the level (its shape becomes a static one).
use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::shape::Shape;
use tamias2d::space::Space;

fn resting_box() -> (Space, tamias2d::body::BodyHandle) {
    let mut w = Space::new();
    w.set_gravity(Vect::from_ints(0, -10));
    let ground = w.add_body(Body::new_static()).unwrap();
    w.add_shape(
        Shape::segment_shape_new(
            ground,
            Vect::from_ints(-5, 0),
            Vect::from_ints(5, 0),
            Real::ZERO,
        )
        .unwrap(),
    )
    .unwrap();
    let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
    b.set_position(Vect::new(Real::ZERO, Real::HALF));
    let h = w.add_body(b).unwrap();
    w.add_shape(Shape::box_shape_new(h, Real::ONE, Real::ONE, Real::ZERO).unwrap())
        .unwrap();
    for _ in 0..10 {
        w.step(Real::ratio(1, 60)).unwrap();
    }
    assert!(!w.arbiters().is_empty(), "the box touches the ground");
    (w, h)
}

#[test]
fn a_touching_body_replaced_by_a_static_or_kinematic_one_steps_on() {
    for kind in ["static", "kinematic"] {
        let (mut w, h) = resting_box();
        let digest = w.level_digest();
        let mut replacement = if kind == "static" {
            Body::new_static()
        } else {
            Body::new_kinematic()
        };
        replacement.set_position(Vect::new(Real::ZERO, Real::HALF));
        *w.body_mut(h).unwrap() = replacement;
        // The step drops the arbiter (validated after it in test builds).
        w.step(Real::ratio(1, 60))
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        w.validate().unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert!(w.arbiters().is_empty(), "{kind}: the pair never collides");
        assert_eq!(
            w.level_digest() != digest,
            kind == "static",
            "{kind}: the level changes exactly when the body became static"
        );
        // A ball dropped on the replacement lands on it (its shape is in
        // the broadphase as a static or kinematic shape).
        let mut ball = Body::new(Real::ONE, Real::ONE).unwrap();
        ball.set_position(Vect::from_ints(0, 3));
        let ball = w.add_body(ball).unwrap();
        w.add_shape(Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO).unwrap())
            .unwrap();
        for _ in 0..120 {
            w.step(Real::ratio(1, 60)).unwrap();
        }
        let y = w.body(ball).unwrap().position().y;
        assert!(
            y > Real::ONE + Real::ratio(1, 4),
            "{kind}: the ball fell through the replacement (y = {y})"
        );
    }
}
