//! Hello world: a ball dropped on the ground comes to rest.
use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::Shape;
use tamias2d::space::Space;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));
    let ground = space.add_body(Body::new_static())?;
    let seg = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-5, 0),
        Vect::from_ints(5, 0),
        Real::ZERO,
    )?;
    space.add_shape(seg.with_material(Real::ONE, Real::ZERO)?)?;
    let mut ball = Body::new(Real::ONE, real!(0.125))?;
    ball.set_position(Vect::from_ints(0, 2));
    let ball = space.add_body(ball)?;
    let circle = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)?;
    space.add_shape(circle.with_material(Real::ONE, Real::ZERO)?)?;
    let dt = Real::ratio(1, 60);
    for i in 0..120 {
        space.step(dt)?;
        if i % 10 == 0 {
            let b = space.body(ball).ok_or("ball")?;
            println!(
                "step {i:3}: y = {}  vy = {}",
                b.position().y,
                b.velocity().y
            );
        }
    }
    println!("checksum: {:#018x}", space.checksum());
    Ok(())
}
