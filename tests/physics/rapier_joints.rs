//! The joint scenes as Rapier worlds (the performance report's converter,
//! `tamias2d_scenes::bench`): every kind with a Rapier counterpart is
//! mapped, the anchors are resolved the way the Tamias2D build resolves
//! them, and the signs of motors and springs turn the bodies the way ours
//! do.
#![allow(
    clippy::float_arithmetic,
    clippy::unwrap_used,
    clippy::indexing_slicing
)]

use tamias2d_scenes::bench::joints::{self, JointError};
use tamias2d_scenes::bench::{self as common, Engine, RapierRun, TamiasRun};
use tamias2d_scenes::JointType;

fn both(name: &str) -> (TamiasRun, RapierRun, Vec<joints::Resolved>) {
    let config = common::scene_config(name);
    let desc = common::scene_with(name, config);
    let resolved = joints::resolve(&desc);
    (
        TamiasRun::new(&desc, config),
        RapierRun::new(&desc, config, common::length_unit(name)),
        resolved,
    )
}

#[test]
fn every_joint_scene_is_mapped_but_gears_and_ratchets() {
    for name in common::joint_scenes() {
        let (tamias, rapier, resolved) = both(name);
        let expected: Vec<JointType> = resolved
            .iter()
            .map(|j| j.kind)
            .filter(|k| matches!(k, JointType::Gear | JointType::Ratchet))
            .collect();
        assert_eq!(rapier.left_out, expected, "{name}");
        assert!(rapier.joints > 0, "{name}: no Rapier joint");
        // The anchors are where the Tamias2D build put them: no joint is
        // open at the start, in either engine.
        for (engine, e) in [("Tamias2D", &tamias as &dyn Engine), ("Rapier", &rapier)] {
            let err = joints::error(&resolved, e);
            assert!(
                err.position < 1e-6,
                "{name} {engine}: open by {}",
                err.position
            );
            assert!(
                err.angle < 1e-6,
                "{name} {engine}: past a limit by {}",
                err.angle
            );
        }
    }
}

#[test]
fn gear_train_and_ratchet_are_the_scenes_with_left_out_joints() {
    let left: Vec<&str> = common::joint_scenes()
        .into_iter()
        .filter(|n| !both(n).1.left_out.is_empty())
        .collect();
    assert_eq!(left, ["gear_train", "ratchet"]);
}

/// Steps both engines `steps` times; returns them and the joint error over
/// the run.
fn run(name: &str, steps: u32) -> (TamiasRun, RapierRun, JointError, JointError) {
    let (mut t, mut r, resolved) = both(name);
    let (mut et, mut er) = (JointError::default(), JointError::default());
    for _ in 0..steps {
        t.step();
        r.step();
        et.merge(joints::error(&resolved, &t));
        er.merge(joints::error(&resolved, &r));
    }
    (t, r, et, er)
}

#[test]
fn motors_turn_the_same_way_in_both_engines() {
    // Windmill: rate 1.5 turns the rotor clockwise at 1.5 rad/s.
    let (t, r, _, er) = run("windmill", 60);
    for (engine, w) in [
        ("Tamias2D", t.body(1).angular_velocity),
        ("Rapier", r.body(1).angular_velocity),
    ] {
        assert!((w + 1.5).abs() < 0.05, "{engine}: rotor at {w} rad/s");
    }
    assert!(er.position < 1e-3, "Rapier pivot open by {}", er.position);
    // Car: the motors drive it forward (to the right) along its grooves.
    let (t, r, _, er) = run("car", 120);
    for (engine, x) in [
        ("Tamias2D", t.body(1).position[0]),
        ("Rapier", r.body(1).position[0]),
    ] {
        assert!(x > 2.0, "{engine}: chassis at x = {x} after 2 s");
    }
    assert!(er.position < 1e-2, "Rapier groove open by {}", er.position);
}

#[test]
fn springs_and_pins_hold_in_rapier() {
    // spring_mass: the rotary spring pulls the wheel from 1 rad back
    // through 0 (it rings at about 2 rad/s: a quarter period is 0.79 s),
    // the damped spring hangs the mass near y = -1.1.
    let (_, r, _, _) = run("spring_mass", 60);
    let wheel = r.body(2).angle;
    assert!(wheel < 0.0, "Rapier wheel at {wheel} rad after 1 s");
    let (_, r, _, _) = run("spring_mass", 600);
    let y = r.body(1).position[1];
    assert!((y + 1.1).abs() < 0.05, "Rapier mass at y = {y} after 10 s");
    // pendulum: the pin keeps the bob 1 m from the pivot.
    let (_, _, _, er) = run("pendulum", 120);
    assert!(er.position < 1e-3, "Rapier pin off by {}", er.position);
    assert!(er.has_position && !er.has_angle);
}
