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
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

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

    // Handlers report into a shared log; `step` says when. Callbacks are
    // `Send + Sync` (so is the `Space`): shared state is `Arc`ed.
    let step = Arc::new(AtomicU32::new(0));
    let log = Arc::new(Mutex::new(Vec::<String>::new()));
    let resting_impulse = Arc::new(Mutex::new(Vect::ZERO));

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
        if let Ok(mut log) = l.lock() {
            let at = s.load(Ordering::Relaxed);
            log.push(format!("step {at:3}: the ball {what} the platform"));
        }
        from_above
    }));
    let r = resting_impulse.clone();
    h.post_solve = Some(Box::new(move |ctx| {
        if let Ok(mut r) = r.lock() {
            *r = ctx.arbiter.total_impulse();
        }
    }));

    let (s, l) = (step.clone(), log.clone());
    space.add_collision_handler(BALL, COIN).begin = Some(Box::new(move |ctx| {
        let at = ctx.contact_point_set().points[0].point_a;
        if let Ok(mut log) = l.lock() {
            log.push(format!(
                "step {:3}: coin collected (contact at y = {:.2})",
                s.load(Ordering::Relaxed),
                at.y.to_f64()
            ));
        }
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
        step.store(i, Ordering::Relaxed);
        space.step(dt)?;
        for line in log.lock().map_err(|_| "log")?.drain(..) {
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
        resting_impulse
            .lock()
            .map_err(|_| "impulse")?
            .length()
            .to_f64(),
        weight_dt.to_f64()
    );
    println!("checksum: {:#018x}", space.checksum());
    Ok(())
}
