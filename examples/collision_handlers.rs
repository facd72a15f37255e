//! Collision handlers: a ball thrown up through a one-way platform picks up
//! a coin (a sensor), falls back and lands on the platform.
//!
//! * `begin` of (platform, ball) ignores the pair when the ball comes from
//!   below (Chipmunk's one-way platform): ignored pairs stay ignored until
//!   the shapes separate, so the ball passes through.
//! * `begin` of (ball, coin) removes the coin with a post-step callback
//!   (objects cannot be removed while the step is running).
//! * `post_solve` of (platform, ball) sees the impulse holding the ball up:
//!   at rest it is the ball's weight times the time step.
//!
//! ```text
//! cargo run --example collision_handlers
//! ```
use std::cell::{Cell, RefCell};
use std::rc::Rc;

use tamias2d::body::Body;
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::Shape;
use tamias2d::space::Space;

const BALL: u32 = 1;
const PLATFORM: u32 = 2;
const COIN: u32 = 3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut space = Space::new();
    space.set_gravity(Vect::from_ints(0, -10));

    // A static one-way platform at y = 4 and a coin above it at y = 6.
    let world = space.add_body(Body::new_static())?;
    let mut platform = Shape::segment_shape_new(
        world,
        Vect::from_ints(-3, 4),
        Vect::from_ints(3, 4),
        real!(0.1),
    )?
    .with_material(Real::ONE, Real::ZERO)?;
    platform.collision_type = PLATFORM;
    space.add_shape(platform)?;
    let mut coin_body = Body::new_kinematic();
    coin_body.set_position(Vect::from_ints(0, 6));
    let coin = space.add_body(coin_body)?;
    let mut coin_shape = Shape::circle_shape_new(coin, Real::HALF, Vect::ZERO)?;
    coin_shape.collision_type = COIN;
    coin_shape.sensor = true;
    space.add_shape(coin_shape)?;

    // A 1 kg ball of radius 0.5 thrown straight up at 12 m/s from y = 1.
    let mut ball_body = Body::new(Real::ONE, real!(0.125))?;
    ball_body.set_position(Vect::from_ints(0, 1));
    ball_body.set_velocity(Vect::from_ints(0, 12));
    let ball = space.add_body(ball_body)?;
    let mut ball_shape = Shape::circle_shape_new(ball, Real::HALF, Vect::ZERO)?
        .with_material(Real::ONE, Real::ZERO)?;
    ball_shape.collision_type = BALL;
    space.add_shape(ball_shape)?;

    // Handlers report into a shared log; `step` says when.
    let step = Rc::new(Cell::new(0u32));
    let log = Rc::new(RefCell::new(Vec::<String>::new()));
    let resting_impulse = Rc::new(Cell::new(Vect::ZERO));

    let (s, l) = (step.clone(), log.clone());
    let h = space.add_collision_handler(PLATFORM, BALL);
    h.begin = Some(Box::new(move |ctx| {
        // The normal points from the platform (the handler's a) to the ball.
        let from_above = ctx.normal().y.is_positive();
        let what = if from_above {
            "lands on"
        } else {
            "passes up through"
        };
        l.borrow_mut()
            .push(format!("step {:3}: the ball {what} the platform", s.get()));
        from_above
    }));
    let r = resting_impulse.clone();
    h.post_solve = Some(Box::new(move |ctx| r.set(ctx.arbiter.total_impulse())));

    let (s, l) = (step.clone(), log.clone());
    space.add_collision_handler(BALL, COIN).begin = Some(Box::new(move |ctx| {
        let at = ctx.contact_point_set().points[0].point_a;
        l.borrow_mut().push(format!(
            "step {:3}: coin collected (contact at y = {:.2})",
            s.get(),
            at.y.to_f64()
        ));
        ctx.add_post_step_callback(
            u64::from(COIN),
            Box::new(move |space: &mut Space| {
                let _ = space.remove_body(coin);
            }),
        );
        true
    }));

    let dt = Real::ratio(1, 60);
    for i in 1..=240 {
        step.set(i);
        space.step(dt)?;
        for line in log.borrow_mut().drain(..) {
            println!("{line}");
        }
    }

    let b = space.body(ball).ok_or("ball")?;
    println!(
        "after 4 s: ball at y = {:.3} (platform top 4.1 + radius 0.5 - collision slop 0.1), coin {}",
        b.position().y.to_f64(),
        if space.body(coin).is_some() {
            "still there"
        } else {
            "gone"
        }
    );
    let weight_dt = Real::from_int(10) * dt;
    println!(
        "impulse holding the ball: {:.4} N·s per step (m·g·dt = {:.4})",
        resting_impulse.get().length().to_f64(),
        weight_dt.to_f64()
    );
    println!("checksum: {:#018x}", space.checksum());
    Ok(())
}
