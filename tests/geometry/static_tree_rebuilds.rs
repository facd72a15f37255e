//! The static tree is rebuilt only when the static shapes' boxes change:
//! not on kinematic moves, not on edits of moving shapes, not on a restore
//! of the same level. Skipping a rebuild changes no bit.

use tamias2d::body::Body;
use tamias2d::shape::Shape;
use tamias2d::space::Space;
use tamias2d::{Real, Vect};

fn v(x: i32, y: i32) -> Vect {
    Vect::new(Real::from_int(x), Real::from_int(y))
}

/// A level of static segments, a kinematic platform, a few falling boxes.
fn world() -> (
    Space,
    tamias2d::body::BodyHandle,
    tamias2d::body::BodyHandle,
) {
    let mut space = Space::new();
    space.set_gravity(v(0, -10));
    let ground = space.add_body(Body::new_static()).unwrap();
    for i in -50..50 {
        let s = Shape::segment_shape_new(ground, v(i, 0), v(i + 1, 0), Real::ratio(1, 10)).unwrap();
        space.add_shape(s).unwrap();
    }
    let mut k = Body::new_kinematic();
    k.set_position(v(0, 3));
    let platform = space.add_body(k).unwrap();
    let s =
        Shape::box_shape_new(platform, Real::from_int(4), Real::ratio(1, 2), Real::ZERO).unwrap();
    space.add_shape(s).unwrap();
    for i in 0..4 {
        let mut b = Body::new(Real::ZERO, Real::ZERO).unwrap();
        b.set_position(v(i * 2 - 4, 6 + i));
        let bh = space.add_body(b).unwrap();
        let mut s = Shape::box_shape_new(bh, Real::ONE, Real::ONE, Real::ZERO).unwrap();
        s.set_density(Real::ONE).unwrap();
        space.add_shape(s).unwrap();
    }
    (space, ground, platform)
}

#[test]
fn kinematic_moves_and_same_level_restores_do_not_rebuild() {
    let (mut space, ground, platform) = world();
    let dt = Real::ratio(1, 60);
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 1);
    let saved = space.state().clone();
    for i in 0..30 {
        let body = space.body_mut(platform).unwrap();
        body.set_velocity(v(1, 0));
        body.set_position(v(i % 5, 3));
        space.step(dt).unwrap();
    }
    assert_eq!(space.static_tree_builds(), 1, "kinematic moves");
    for _ in 0..5 {
        space.restore_state(&saved);
        space.step(dt).unwrap();
        space.step(dt).unwrap();
    }
    assert_eq!(space.static_tree_builds(), 1, "restores of the same level");
    // Touching a static body without moving it: no rebuild either.
    let _ = space.body_mut(ground).unwrap();
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 1, "static body left in place");
    // Moving it, adding or removing a static shape: rebuilds.
    space.body_mut(ground).unwrap().set_position(v(0, -1));
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 2, "static body moved");
    let s = Shape::segment_shape_new(ground, v(60, 0), v(61, 0), Real::ZERO).unwrap();
    let sh = space.add_shape(s).unwrap();
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 3, "static shape added");
    space.remove_shape(sh).unwrap();
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 4, "static shape removed");
    // A restore to the level as saved (ground back at its old place).
    space.restore_state(&saved);
    space.step(dt).unwrap();
    assert_eq!(space.static_tree_builds(), 5, "restore of another level");
}

/// The same run with the tree kept (one space) and rebuilt every step (a
/// fresh clone each step, whose caches start empty): the same bits.
#[test]
fn keeping_the_tree_changes_no_bit() {
    let (mut kept, ground, platform) = world();
    let mut rebuilt = kept.clone();
    let dt = Real::ratio(1, 60);
    let mut saved = None;
    for step in 0..240 {
        for space in [&mut kept, &mut rebuilt] {
            if step % 3 == 0 {
                space
                    .body_mut(platform)
                    .unwrap()
                    .set_velocity(v(step % 7 - 3, 0));
            }
            if step == 100 {
                space.body_mut(ground).unwrap().set_position(v(0, -1));
            }
        }
        if step % 40 == 10 {
            saved = Some(kept.state().clone());
        }
        if step % 40 == 30 {
            if let Some(s) = &saved {
                kept.restore_state(s);
                rebuilt.restore_state(s);
            }
        }
        kept.step(dt).unwrap();
        rebuilt.step(dt).unwrap();
        assert_eq!(kept.checksum(), rebuilt.checksum(), "step {step}");
        assert_eq!(rebuilt.static_tree_builds(), 1, "a fresh clone builds");
        rebuilt = rebuilt.clone();
    }
    // Built at the start, at the move of step 100 and at the restores
    // that cross it (steps 110 and 150 restore a level saved before it).
    assert!(
        kept.static_tree_builds() <= 4,
        "{}",
        kept.static_tree_builds()
    );
}
