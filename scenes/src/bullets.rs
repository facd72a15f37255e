//! The `bullets` scene (section C): continuous collision against a thin
//! wall, and how many bullets got through it ([`tunnelled`]).
//!
//! A gun fires [`BULLETS`] circles of radius 0.05 m (density 1) at 300 m/s
//! along +x, one every [`FIRE_INTERVAL`] steps of 1/60 s, into a static
//! wall 0.1 m thick and 4 m tall standing on the ground at x = 0 (labelled
//! `wall`); twelve 0.5 m boxes stand in three columns behind it. At 300 m/s
//! a bullet moves 5 m per step, 33 times its own size plus the wall's, so
//! without continuous collision it is found on the far side of the wall as
//! often as not. The gun steps back by 5/32 m after each shot, so the 32
//! bullets reach the wall at 32 evenly spread points of one step's travel
//! (every phase a shot can have), at eight heights between 0.5 and 2.25 m.
//! Bullets do not collide with each other ([`BULLET_GROUP`]).
//!
//! Every bullet is a [bullet](tamias2d::body::Body::set_bullet), so none
//! passes the wall (`tamias run bullets` prints `tunnelled: 0`). The same
//! scene with the flags cleared ([`without_bullets`]) tunnels 31 of the 32
//! at one sub-step and none at 64 sub-steps (for 64 times the cost; the
//! comparison is in `docs/tuning.md`).
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::ShapeFilter;

use crate::desc::{BodyDesc, BodyKind, SceneDesc, SettingsDesc, ShapeDesc, SpawnDesc};
use crate::ScriptedWorld;

/// Number of bullets fired.
pub const BULLETS: u32 = 32;

/// Steps between two shots.
pub const FIRE_INTERVAL: u32 = 2;

/// Speed of a bullet, m/s.
pub const MUZZLE_SPEED: i32 = 300;

/// The bullets' filter group: bullets pass through each other, so each
/// one meets the wall alone (a bullet knocked off a pile at the wall's
/// foot could otherwise fly over the wall and count as tunnelled).
pub const BULLET_GROUP: u32 = 1;

/// The label of bullet `i` (`bullet_0` … `bullet_31`).
pub fn bullet_label(i: u32) -> String {
    format!("bullet_{i}")
}

/// The `bullets` scene: 120 steps of 1/60 s, the last shot at step 62.
pub fn bullets() -> SceneDesc {
    let mut desc = SceneDesc {
        settings: SettingsDesc::with_gravity(Vect::new(Real::ZERO, -real!(9.81)), 10),
        ..SceneDesc::new("bullets", Real::ratio(1, 60), 120)
    };
    let ground = BodyDesc::static_body()
        .with_shape(
            ShapeDesc::segment(Vect::from_ints(-20, 0), Vect::from_ints(20, 0), Real::ZERO)
                .material(real!(0.7), Real::ZERO),
        )
        .labeled("ground");
    desc.bodies.push(ground);
    let wall = BodyDesc::new(BodyKind::Static, Vect::from_ints(0, 2))
        .with_shape(
            ShapeDesc::box_shape(Real::ratio(1, 10), Real::from_int(4), Real::ZERO)
                .material(real!(0.7), Real::ZERO),
        )
        .labeled("wall");
    desc.bodies.push(wall);
    for column in 0..3i32 {
        for row in 0..4 {
            let at = Vect::new(
                Real::TWO + Real::ratio(column.saturating_mul(6), 10),
                Real::ratio(1, 4) + Real::ratio(row, 2),
            );
            let b = BodyDesc::new(BodyKind::Dynamic, at).with_shape(
                ShapeDesc::box_shape(Real::HALF, Real::HALF, Real::ZERO)
                    .material(real!(0.7), Real::ZERO)
                    .density(Real::ONE),
            );
            desc.bodies.push(b);
        }
    }
    for i in 0..BULLETS {
        // i < 32: the products are small.
        let step_back = Real::from_int(5) * Real::ratio(i as i32, 32);
        let height = Real::HALF + Real::ratio((i % 8) as i32, 4);
        let at = Vect::new(-Real::from_int(10) - step_back, height);
        let mut shape = ShapeDesc::circle(Real::ratio(1, 20))
            .material(real!(0.7), Real::ZERO)
            .density(Real::ONE);
        shape.filter = ShapeFilter {
            group: BULLET_GROUP,
            ..ShapeFilter::ALL
        };
        let b = BodyDesc::new(BodyKind::Dynamic, at)
            .moving(Vect::from_ints(MUZZLE_SPEED, 0))
            .with_shape(shape)
            .labeled(&bullet_label(i))
            .bullet();
        desc.spawns.push(SpawnDesc {
            at_step: i.saturating_mul(FIRE_INTERVAL),
            bodies: vec![b],
        });
    }
    desc
}

/// `desc` with every body's bullet flag cleared.
pub fn without_bullets(mut desc: SceneDesc) -> SceneDesc {
    let bodies = desc
        .bodies
        .iter_mut()
        .chain(desc.spawns.iter_mut().flat_map(|s| s.bodies.iter_mut()));
    for b in bodies {
        b.bullet = false;
    }
    desc
}

/// For a world with a body labelled `wall` and bodies labelled
/// `bullet_0`, `bullet_1`, …: how many of those bullets (fired so far) are
/// beyond the wall (centre at a larger x than the wall's). `None` for a
/// world without a `wall`.
pub fn tunnelled(world: &ScriptedWorld) -> Option<usize> {
    let wall = world.space.body(world.body("wall")?)?.position().x;
    let beyond = (0..u32::MAX)
        .map_while(|i| {
            let h = world.body(&bullet_label(i))?;
            Some(world.space.body(h).map(|b| b.position().x > wall))
        })
        .filter(|&past| past == Some(true))
        .count();
    Some(beyond)
}
