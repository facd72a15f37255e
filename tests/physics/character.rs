//! The kinematic character mover (`tamias2d::character`), feature by
//! feature, each on a small world built for it, and the platformer level
//! of `examples/character.rs`.
//!
//! The character is the level's capsule (a 0.8 m core, radius 0.3 m: 1.4 m
//! tall) with the default settings (45° walkable, 0.3 m steps and snapping,
//! 0.01 m skin). Bounds come from the settings: standing, the gap to the
//! ground is at most one skin (the casts stop the skin's width short) and
//! never negative; a walk of `n` frames at `v` covers at most `n·v·dt`.
#![allow(clippy::float_arithmetic)]

use tamias2d::body::{Body, BodyHandle};
use tamias2d::character::{
    solve_planes, Character, CharacterConfig, CharacterError, MoveReport, Plane,
};
use tamias2d::shape::mass::moment_for_box;
use tamias2d::shape::{Chain, ChainKind, Geometry, Segment, Shape, ShapeFilter};
use tamias2d::space::Space;
use tamias2d::{real, Real, Vect};
use tamias2d_scenes::character_level::{inside_solid, script, CharacterGame, RunStats, FRAMES};

const DT: Real = real!(0.0166666666666666666);
const G: Real = real!(10);
const WALK: Real = real!(4);

fn capsule() -> Geometry {
    Geometry::Segment(Segment::new(
        Vect::new(Real::ZERO, real!(-0.4)),
        Vect::new(Real::ZERO, real!(0.4)),
        real!(0.3),
    ))
}

fn config() -> CharacterConfig {
    CharacterConfig::new(capsule()).unwrap()
}

fn v(x: f64, y: f64) -> Vect {
    Vect::from_f64(x, y).unwrap()
}

/// A world of one static chain through `points`.
fn terrain(points: &[Vect]) -> Space {
    let mut space = Space::new();
    space.set_gravity(Vect::new(Real::ZERO, -G));
    let ground = space.add_body(Body::new_static()).unwrap();
    let chain = Chain::new(points, ChainKind::Open).unwrap();
    space.add_chain(ground, &chain).unwrap();
    space
}

/// A walker: the game's velocity, gravity and the stick.
struct Walker {
    c: Character,
    vel: Vect,
    config: CharacterConfig,
}

impl Walker {
    fn at(x: f64, y: f64) -> Walker {
        Walker {
            c: Character::new(v(x, y)),
            vel: Vect::ZERO,
            config: config(),
        }
    }

    /// One frame: step the world, then move with `walk` (−1, 0, 1).
    fn frame(&mut self, space: &mut Space, walk: i32, jump: bool) -> MoveReport {
        space.step(DT).unwrap();
        let standing = self.c.ground.is_some();
        self.vel.x = WALK * Real::from_int(walk);
        self.vel.y = if standing && jump {
            real!(6)
        } else if standing {
            -G * DT
        } else {
            self.vel.y - G * DT
        };
        let r = self.c.move_by(space, &self.config, self.vel * DT, DT);
        self.vel = r.clip_velocity(self.vel);
        r
    }

    fn x(&self) -> f64 {
        self.c.position.x.to_f64()
    }
    fn y(&self) -> f64 {
        self.c.position.y.to_f64()
    }
}

/// Feet (bottom of the capsule) height.
fn feet(w: &Walker) -> f64 {
    w.y() - 0.7
}

#[test]
fn settles_and_walks_on_flat_ground_one_skin_above_it() {
    let mut space = terrain(&[v(-50.0, 0.0), v(50.0, 0.0)]);
    let mut w = Walker::at(0.0, 1.5);
    for _ in 0..60 {
        w.frame(&mut space, 0, false);
    }
    assert!(w.c.ground.is_some(), "standing after a 0.8 m fall");
    for _ in 0..120 {
        let r = w.frame(&mut space, 1, false);
        assert!(r.grounded);
        let gap = r.ground_gap.unwrap().to_f64();
        assert!((0.0..=0.0100001).contains(&gap), "gap {gap}");
        assert!(!r.hit_wall && !r.blocked_by_slope && !r.stepped);
    }
    // 120 frames at 4 m/s: exactly 8 m less rounding.
    assert!((w.x() - 8.0).abs() < 1e-6, "x {}", w.x());
    assert!(feet(&w) > 0.0 && feet(&w) <= 0.0100001, "feet {}", feet(&w));
}

#[test]
fn climbs_a_walkable_slope_and_is_stopped_by_a_steep_one() {
    // Flat, a 30° slope 4 m long, flat, a 60° slope.
    let h30 = 4.0 * (30f64).to_radians().tan();
    let mut space = terrain(&[
        v(-10.0, 0.0),
        v(2.0, 0.0),
        v(6.0, h30),
        v(9.0, h30),
        v(11.0, h30 + 2.0 * (60f64).to_radians().tan()),
        v(20.0, h30 + 2.0 * (60f64).to_radians().tan()),
    ]);
    let mut w = Walker::at(0.0, 0.71);
    let mut on_slope_grounded = 0;
    let mut blocked = 0;
    for _ in 0..300 {
        let r = w.frame(&mut space, 1, false);
        if (2.5..5.5).contains(&w.x()) && r.grounded {
            on_slope_grounded += 1;
        }
        blocked += u32::from(r.blocked_by_slope);
    }
    // Every frame on the 30° slope stands on it (45 frames at 4 m/s·cos).
    assert!(on_slope_grounded >= 40, "{on_slope_grounded}");
    // It stops at the foot of the 60° slope: the capsule's radius from it.
    assert!(blocked > 100, "blocked {blocked} frames");
    assert!(w.x() < 9.0 + 0.3, "x {}", w.x());
    assert!(
        feet(&w) < h30 + 0.05,
        "climbed the steep slope: feet {}",
        feet(&w)
    );
}

#[test]
fn steps_up_a_low_step_but_not_a_high_one() {
    for (step, climbs) in [(0.25, true), (0.45, false)] {
        let mut space = terrain(&[v(-10.0, 0.0), v(3.0, 0.0), v(3.0, step), v(20.0, step)]);
        let mut w = Walker::at(0.0, 0.71);
        let mut stepped = false;
        for _ in 0..90 {
            stepped |= w.frame(&mut space, 1, false).stepped;
        }
        assert_eq!(stepped, climbs, "step {step}");
        if climbs {
            assert!(w.x() > 5.0, "step {step}: x {}", w.x());
            assert!((feet(&w) - step).abs() < 0.011, "feet {}", feet(&w));
        } else {
            assert!(w.x() < 3.0 - 0.3 + 0.011, "step {step}: x {}", w.x());
        }
    }
}

#[test]
fn snaps_to_the_ground_walking_down_a_slope() {
    let h = 4.0 * (30f64).to_radians().tan();
    let points = [v(-10.0, h), v(2.0, h), v(6.0, 0.0), v(20.0, 0.0)];
    for (snap, stays) in [(0.3, true), (0.0, false)] {
        let mut space = terrain(&points);
        let mut w = Walker::at(0.0, h + 0.71);
        w.config = w
            .config
            .with_snap_distance(Real::from_f64(snap).unwrap())
            .unwrap();
        for _ in 0..10 {
            w.frame(&mut space, 0, false);
        }
        let mut airborne = 0;
        for _ in 0..60 {
            let r = w.frame(&mut space, 1, false);
            if (2.5..5.5).contains(&w.x()) && !r.grounded {
                airborne += 1;
            }
        }
        assert_eq!(
            airborne == 0,
            stays,
            "snap {snap}: {airborne} frames off the slope"
        );
    }
}

/// A kinematic slab 2 m × 0.2 m whose top is at `y`.
fn slab(space: &mut Space, x: f64, y: f64) -> BodyHandle {
    let mut b = Body::new_kinematic();
    b.set_position(v(x, y - 0.1));
    let h = space.add_body(b).unwrap();
    space
        .add_shape(Shape::box_shape_new(h, real!(2), real!(0.2), Real::ZERO).unwrap())
        .unwrap();
    h
}

#[test]
fn rides_a_moving_platform() {
    let mut space = terrain(&[v(-20.0, -5.0), v(20.0, -5.0)]);
    let platform = slab(&mut space, 0.0, 1.0);
    let mut w = Walker::at(0.0, 1.71);
    for _ in 0..10 {
        w.frame(&mut space, 0, false);
    }
    // Up at 1 m/s for 1 s, then sideways at 2 m/s for 0.5 s.
    space.body_mut(platform).unwrap().set_velocity(v(0.0, 1.0));
    let (x0, y0) = (w.x(), w.y());
    for _ in 0..60 {
        let r = w.frame(&mut space, 0, false);
        assert_eq!(r.carried_by, Some(platform));
        assert!(r.grounded);
    }
    assert!((w.y() - y0 - 1.0).abs() < 0.011, "rose {}", w.y() - y0);
    space.body_mut(platform).unwrap().set_velocity(v(2.0, 0.0));
    for _ in 0..30 {
        assert!(w.frame(&mut space, 0, false).grounded);
    }
    assert!((w.x() - x0 - 1.0).abs() < 0.011, "moved {}", w.x() - x0);
}

#[test]
fn turns_with_a_rotating_platform() {
    let mut space = terrain(&[v(-20.0, -5.0), v(20.0, -5.0)]);
    let platform = slab(&mut space, 0.0, 1.0);
    let mut w = Walker::at(0.7, 1.71);
    for _ in 0..10 {
        w.frame(&mut space, 0, false);
    }
    let pivot = space.body(platform).unwrap().position();
    let d0 = w.c.position - pivot;
    let (r0, angle0) = (d0.length().to_f64(), d0.y.to_f64().atan2(d0.x.to_f64()));
    // 0.3 rad/s for 1 s: 0.3 rad, under the 45° walkable limit.
    space
        .body_mut(platform)
        .unwrap()
        .set_angular_velocity(real!(0.3));
    for _ in 0..60 {
        let r = w.frame(&mut space, 0, false);
        assert!(r.grounded, "fell off at {}", w.x());
    }
    let d = w.c.position - pivot;
    let (r1, angle) = (d.length().to_f64(), d.y.to_f64().atan2(d.x.to_f64()));
    assert!((r1 - r0).abs() < 0.02, "radius {r0} → {r1}");
    // Turned with the platform (the character stays upright, so its
    // centre turns about the pivot by the platform's angle).
    assert!(
        (angle - angle0 - 0.3).abs() < 0.05,
        "turned {}",
        angle - angle0
    );
}

#[test]
fn one_way_platforms_block_only_from_above() {
    const ONE_WAY: u32 = 0b10;
    let mut space = terrain(&[v(-20.0, 0.0), v(20.0, 0.0)]);
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut s = Shape::segment_shape_new(ground, v(-2.0, 1.5), v(2.0, 1.5), real!(0.05)).unwrap();
    s.filter = ShapeFilter {
        categories: ONE_WAY,
        ..ShapeFilter::ALL
    };
    let plat = space.add_shape(s).unwrap();
    let mut w = Walker::at(0.0, 0.71);
    w.config = w.config.with_one_way_categories(ONE_WAY);
    for _ in 0..5 {
        w.frame(&mut space, 0, false);
    }
    // Jump up through it (the head passes it), land on it.
    let mut max_y = 0.0f64;
    for f in 0..90 {
        w.frame(&mut space, 0, f == 0);
        max_y = max_y.max(w.y());
    }
    assert!(max_y > 1.5 + 0.7, "passed up through: top {max_y}");
    let ground_shape = w.c.ground.map(|g| g.shape);
    assert_eq!(ground_shape, Some(plat), "landed on the platform");
    assert!((feet(&w) - 1.55).abs() < 0.011, "feet {}", feet(&w));
    // Without the one-way rule the same jump hits it from below.
    let mut w2 = Walker::at(0.0, 0.71);
    for f in 0..60 {
        let r = w2.frame(&mut space, 0, f == 5);
        assert!(w2.y() < 1.5 - 0.05 - 0.7 + 0.011 + 0.0001 || r.grounded);
    }
}

#[test]
fn pushes_a_crate_with_a_bounded_force() {
    for (force, moves) in [(60.0, true), (0.0, false)] {
        let mut space = terrain(&[v(-20.0, 0.0), v(20.0, 0.0)]);
        let m = real!(2);
        let mut b = Body::new(m, moment_for_box(m, real!(0.6), real!(0.6))).unwrap();
        b.set_position(v(2.0, 0.3));
        let crate_ = space.add_body(b).unwrap();
        space
            .add_shape(
                Shape::box_shape_new(crate_, real!(0.6), real!(0.6), Real::ZERO)
                    .unwrap()
                    .with_material(real!(0.5), Real::ZERO)
                    .unwrap(),
            )
            .unwrap();
        let mut w = Walker::at(0.0, 0.71);
        w.config = w
            .config
            .with_push_force(Real::from_f64(force).unwrap())
            .unwrap();
        let mut pushed = 0;
        let mut prev = space.body(crate_).unwrap().velocity();
        for _ in 0..120 {
            let r = w.frame(&mut space, 1, false);
            pushed += r.pushed;
            let now = space.body(crate_).unwrap().velocity();
            // One frame's push changes the crate's speed by at most F·dt/m
            // (friction only takes speed away).
            let dv = (now.x - prev.x).to_f64();
            assert!(dv <= force / 60.0 / 2.0 + 1e-6, "dv {dv}");
            prev = now;
        }
        let cx = space.body(crate_).unwrap().position().x.to_f64();
        assert_eq!(pushed > 0, moves, "force {force}");
        assert_eq!(cx > 2.5, moves, "force {force}: crate at {cx}");
        // The character never ends inside the crate.
        assert!(w.x() < cx - 0.3 - 0.3 + 0.011, "x {} crate {cx}", w.x());
    }
}

#[test]
fn reports_walls_and_ceilings_and_clips_the_velocity() {
    // A wall at x = 3 and a ceiling at y = 2.
    let mut space = terrain(&[v(-10.0, 2.0), v(-10.0, 0.0), v(3.0, 0.0), v(3.0, 5.0)]);
    let ground = space.add_body(Body::new_static()).unwrap();
    space
        .add_shape(
            Shape::segment_shape_new(ground, v(-10.0, 2.0), v(3.0, 2.0), Real::ZERO).unwrap(),
        )
        .unwrap();
    let mut w = Walker::at(0.0, 0.71);
    let (mut wall, mut ceiling) = (false, false);
    for f in 0..90 {
        let r = w.frame(&mut space, 1, f == 10);
        wall |= r.hit_wall;
        ceiling |= r.hit_ceiling;
        if r.hit_ceiling {
            assert!(w.vel.y <= Real::ZERO, "clipped at the ceiling");
        }
        if r.hit_wall {
            assert!(w.vel.x <= Real::ZERO, "clipped at the wall");
        }
    }
    assert!(wall && ceiling);
    assert!(
        w.x() <= 3.0 - 0.3 && w.x() > 3.0 - 0.3 - 0.011,
        "x {}",
        w.x()
    );
    assert!(w.y() + 0.7 <= 2.0, "head {}", w.y() + 0.7);
}

#[test]
fn is_pushed_out_of_a_shape_that_moved_into_it() {
    let mut space = terrain(&[v(-20.0, 0.0), v(20.0, 0.0)]);
    let mut w = Walker::at(0.0, 0.71);
    for _ in 0..5 {
        w.frame(&mut space, 0, false);
    }
    // A kinematic block appears overlapping the character by 0.1 m.
    let mut b = Body::new_kinematic();
    b.set_position(v(0.8 - 0.1, 1.0));
    let h = space.add_body(b).unwrap();
    space
        .add_shape(Shape::box_shape_new(h, real!(1), real!(1), Real::ZERO).unwrap())
        .unwrap();
    let r = w.frame(&mut space, 0, false);
    assert!(r.depenetration.to_f64() > 0.09, "{:?}", r.depenetration);
    assert!(w.x() <= -0.1 + 1e-6, "x {}", w.x());
}

#[test]
fn settings_out_of_range_are_errors() {
    let c = config();
    assert_eq!(
        c.with_max_slope(real!(1.6)).err(),
        Some(CharacterError::OutOfRange("max slope must be in [0, π/2)"))
    );
    assert!(c.with_max_slope(real!(-0.1)).is_err());
    assert!(c.with_step_height(real!(-0.1)).is_err());
    assert!(c.with_snap_distance(real!(-0.1)).is_err());
    assert!(c.with_skin(Real::ZERO).is_err());
    assert!(c.with_push_force(real!(-1)).is_err());
    assert!(c.with_max_slides(0).is_err());
    assert!(c.with_max_slides(17).is_err());
    assert!(c.with_up(Vect::ZERO).is_err());
    let up = c.with_up(v(0.0, 2.0)).unwrap().up();
    assert_eq!(up, Vect::new(Real::ZERO, Real::ONE));
    let e = CharacterError::OutOfRange("skin must be positive");
    assert_eq!(
        e.to_string(),
        "character setting out of range: skin must be positive"
    );
}

#[test]
fn the_plane_solver_clears_a_squeeze_as_well_as_it_can() {
    // Floor and ceiling 1 m apart squeezing by 0.2 m each: the pushes
    // settle between them (no plane is pulled), never diverge.
    let mut p = [
        Plane {
            normal: v(0.0, 1.0),
            separation: real!(-0.2),
        },
        Plane {
            normal: v(0.0, -1.0),
            separation: real!(-0.2),
        },
    ];
    let d = solve_planes(&mut p, Real::ZERO);
    assert!(d.length() <= real!(0.2), "{d:?}");
}

/// The level of `examples/character.rs`: no frame below the terrain or
/// inside a solid shape, every state seen, and a restore at frame 900 ends
/// with the checksum of the straight run.
#[test]
fn the_platformer_level_runs_clean_and_restores_exactly() {
    let mut game = CharacterGame::new().unwrap();
    let mut stats = RunStats::default();
    let mut saved = None;
    for f in 0..FRAMES {
        if f == FRAMES / 2 {
            saved = Some(game.save());
        }
        game.step(&[script(f)]).unwrap();
        stats.observe(&game);
    }
    assert_eq!(stats.frames, FRAMES);
    assert_eq!(stats.fell_through, 0);
    assert_eq!(stats.stuck, 0);
    // One skin along the surface's normal: skin / cos(slope) measured
    // straight down, at most skin / cos 45° on walkable ground.
    let bound = game.config.skin() * real!(1.4142136);
    assert!(stats.max_ground_gap <= bound, "{:?}", stats.max_ground_gap);
    for (k, seen) in stats.seen.iter().enumerate() {
        assert!(
            *seen > 0,
            "state {} never seen",
            tamias2d_scenes::character_level::STATES[k]
        );
    }
    let mut again = CharacterGame::new().unwrap();
    again.restore(saved.as_ref().unwrap()).unwrap();
    for f in FRAMES / 2..FRAMES {
        again.step(&[script(f)]).unwrap();
    }
    assert_eq!(again.checksum(), game.checksum());
    // A save in the middle of a frame's worth of state round-trips as
    // bytes too (the game's frame is serde data).
    let bytes = bincode::serde::encode_to_vec(game.save(), bincode::config::standard()).unwrap();
    assert!(!bytes.is_empty());
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

    /// Any sequence of moves, short or far (up to 40 m in one move, or
    /// beyond the level), on the level's still geometry: the character
    /// never ends a move inside a solid shape (deeper than the casts'
    /// tolerance) and never below the terrain.
    #[test]
    fn no_move_ends_inside_the_level(
        start in -13.0f64..27.0,
        moves in proptest::collection::vec((-40.0f64..40.0, -40.0f64..40.0), 1..40),
    ) {
        let mut game = CharacterGame::new().unwrap();
        let x = Real::from_f64(start).unwrap();
        let floor = tamias2d_scenes::character_level::floor_height(x).unwrap();
        let mut c = Character::new(Vect::new(x, floor + real!(2)));
        // Clear of the platforms and crates at the start.
        proptest::prop_assume!(!inside_solid(&game, &c, Real::ZERO));
        // The terrain is a line, not solid ground: a character that
        // leaves the level's box (over the end walls) may come back in
        // under its floor. The floor is checked until then.
        let mut in_level = true;
        for (dx, dy) in moves {
            let before = c.position;
            c.move_by(&mut game.space, &game.config, v(dx, dy), DT);
            proptest::prop_assert!(
                !inside_solid(&game, &c, real!(0.0001)),
                "inside at {:?}", c.position
            );
            let p = c.position;
            in_level &= p.x > real!(-14) && p.x < real!(28) && p.y < real!(12);
            if let (true, Some(h)) = (in_level, tamias2d_scenes::character_level::floor_height(p.x)) {
                proptest::prop_assert!(
                    p.y - real!(0.7) >= h - real!(0.0001),
                    "below the floor: {:?} → {:?}", before, p
                );
            }
        }
    }
}

#[test]
fn extreme_moves_are_defined() {
    let mut game = CharacterGame::new().unwrap();
    let mut c = Character::new(v(0.0, 0.72));
    for d in [
        Vect::ZERO,
        Vect::new(Real::MAX, Real::MAX),
        Vect::new(Real::MIN, Real::ZERO),
        Vect::new(Real::ZERO, Real::MIN),
        Vect::new(Real::DELTA, -Real::DELTA),
    ] {
        let r = c.move_by(&mut game.space, &game.config, d, DT);
        assert!(
            !inside_solid(&game, &c, real!(0.0001)),
            "{d:?} → {:?}",
            c.position
        );
        let _ = r.clip_velocity(d);
    }
}
