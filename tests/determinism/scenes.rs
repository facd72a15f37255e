//! Determinism and rollback: every built-in scene (smallest size of each
//! family, CI-friendly step counts) stepped in two worlds built the same way
//! gives identical states and checksums after every step, and valid states;
//! a world rebuilt from a snapshot (`Space::from_state`) or rolled back in
//! place (`Space::restore_state`) continues exactly as the original; and a
//! restored world hands out the same handles as the original.
//!
//! Exact equality (`==` on the whole `WorldState`, and the checksum) is the
//! only acceptable outcome here: a lockstep engine has no tolerance.
use tamias2d::body::{Body, BodyHandle, BodyType};
use tamias2d::shape::Shape;
use tamias2d::space::{Space, WorldState};
use tamias2d::{Real, Vect};
use tamias2d_scenes::{self as scenes, SceneInfo, ScriptedWorld, Section};

fn build(name: &str) -> ScriptedWorld {
    scenes::builtin(name)
        .unwrap_or_else(|| panic!("{name} is a listed scene"))
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn step(scene: &mut ScriptedWorld, name: &str) {
    scene.step().unwrap_or_else(|e| panic!("{name}: {e}"));
}

/// Steps to run a checked scene: its golden's step count (long enough to
/// collide, stack and, for rain, spawn several rows), capped at 300 for the
/// many-body sections A and B, which are slow in debug builds with a
/// validation after every step.
fn steps_for(info: &SceneInfo) -> u32 {
    let steps = info.golden.map_or(300, |g| g.steps);
    if info.section == Section::Accuracy {
        steps
    } else {
        steps.min(300)
    }
}

/// Builds the scene twice and steps both worlds `steps` times; after build
/// and after every step their states must be equal (`==`), their checksums
/// equal, and the state valid.
fn lockstep(name: &str, steps: u32) {
    let mut a = build(name);
    let mut b = build(name);
    assert!(
        a.space.state() == b.space.state(),
        "{name}: built differently"
    );
    assert_eq!(
        a.space.checksum(),
        b.space.checksum(),
        "{name}: build checksum"
    );
    let mut checksums = std::collections::BTreeSet::new();
    for n in 1..=steps {
        step(&mut a, name);
        step(&mut b, name);
        assert!(
            a.space.state() == b.space.state(),
            "{name}: states differ after {n} steps"
        );
        let sum = a.space.checksum();
        assert_eq!(
            sum,
            b.space.checksum(),
            "{name}: checksums differ after {n} steps"
        );
        checksums.insert(sum);
        a.space
            .validate()
            .unwrap_or_else(|e| panic!("{name} after {n} steps: {e}"));
    }
    // The checksum sees the motion: a scene where something moves changes
    // state (and so, barring a 2^-64 collision, checksum) every step.
    assert_eq!(a.space.steps(), u64::from(steps), "{name}: steps");
    assert_eq!(
        checksums.len(),
        steps as usize,
        "{name}: the checksum repeated (the stamp alone changes every step)"
    );
}

/// Checks every registered scene of `section` that stands for itself (the
/// larger sizes run the same code on more bodies: their smallest size,
/// `covered_by`, is checked instead).
fn check_section(section: Section) {
    let mut checked = 0;
    for info in scenes::REGISTRY {
        if info.section != section || info.covered_by.is_some() {
            continue;
        }
        let t = std::time::Instant::now();
        let steps = steps_for(info);
        lockstep(info.name, steps);
        checked += 1;
        println!(
            "{}: {steps} steps in lockstep, {:?}",
            info.name,
            t.elapsed()
        );
    }
    assert!(checked > 0, "no scene in section {section:?}");
}

#[test]
fn section_a_terrain_scenes_step_in_lockstep() {
    check_section(Section::Terrain);
}

#[test]
fn section_b_stacking_scenes_step_in_lockstep() {
    check_section(Section::Stacking);
}

#[test]
fn section_c_accuracy_scenes_step_in_lockstep() {
    check_section(Section::Accuracy);
}

#[test]
fn section_d_joint_scenes_step_in_lockstep() {
    check_section(Section::Joints);
}

#[test]
fn section_e_level_scenes_step_in_lockstep() {
    check_section(Section::Level);
}

/// Steps both scenes `steps` times and requires equal states after each.
fn continue_in_lockstep(a: &mut ScriptedWorld, b: &mut ScriptedWorld, steps: u32, what: &str) {
    for n in 1..=steps {
        step(a, what);
        step(b, what);
        assert!(
            a.space.state() == b.space.state(),
            "{what}: states differ {n} steps after the snapshot"
        );
        assert_eq!(a.space.checksum(), b.space.checksum(), "{what}: step {n}");
    }
}

#[test]
fn world_rebuilt_from_a_snapshot_continues_identically() {
    // Scenes with static terrain (the static index is rebuilt), warm-started
    // contacts, a kinematic body and a scripted torque. The copy is made
    // mid-run, with arbiters and cached impulses live; from then on both
    // worlds are driven at the Space level: the scripted forces are applied
    // to both before every step, through handles stripped of their origin
    // tag (a `Space::from_state` world has a new origin, so the handles
    // `ScriptedWorld` keeps from the original world are foreign to it).
    for (name, k, m) in [
        ("bowl_boxes_100", 60, 60),
        ("tumbler_500", 40, 40),
        ("spin", 100, 100),
        ("incline_slide", 30, 60),
    ] {
        let desc = scenes::builtin(name).unwrap_or_else(|| panic!("{name}"));
        assert!(
            desc.spawns.is_empty(),
            "{name}: spawns need the ScriptedWorld"
        );
        let mut a = build(name);
        let dt = a.dt;
        a.step_n(k).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            !a.space.arbiters().is_empty() || name == "spin",
            "{name}: no contacts at the snapshot"
        );
        let forces: Vec<(BodyHandle, Vect, Real)> = desc
            .forces
            .iter()
            .map(|f| {
                let h = a.bodies()[f.body as usize];
                (
                    BodyHandle::from_raw_parts(h.index(), h.generation()),
                    f.force,
                    f.torque,
                )
            })
            .collect();
        let snapshot: WorldState = a.space.state().clone();
        let mut b = Space::from_state(snapshot.clone());
        assert!(b.state() == &snapshot);
        b.validate()
            .unwrap_or_else(|e| panic!("{name}: restored state invalid: {e}"));
        for n in 1..=m {
            for space in [&mut a.space, &mut b] {
                for &(h, force, torque) in &forces {
                    let body = space
                        .body_mut(h)
                        .unwrap_or_else(|| panic!("{name}: scripted body {h:?} missing"));
                    body.apply_force(force);
                    body.apply_torque(torque);
                }
                space.step(dt).unwrap_or_else(|e| panic!("{name}: {e}"));
            }
            assert!(
                a.space.state() == b.state(),
                "{name}: states differ {n} steps after from_state"
            );
            assert_eq!(a.space.checksum(), b.checksum(), "{name}: step {n}");
        }
    }
}

#[test]
fn rain_rebuilt_from_a_snapshot_keeps_spawning_identically() {
    // Spawns are scripted by the ScriptedWorld: swap a rebuilt space into a second
    // scene that has taken the same number of steps (so its spawn script is
    // at the same point), and let both scenes spawn the next rows. rain has
    // no scripted forces, so no ScriptedWorld-held handle is needed after the swap.
    let name = "rain_1000";
    let desc = scenes::builtin(name).unwrap_or_else(|| panic!("{name}"));
    assert!(desc.forces.is_empty());
    let mut a = build(name);
    let mut b = build(name);
    a.step_n(110).unwrap_or_else(|e| panic!("{e}"));
    b.step_n(110).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !a.space.arbiters().is_empty(),
        "no contacts at the snapshot"
    );
    b.space = Space::from_state(a.space.state().clone());
    let before = a.space.bodies().count();
    continue_in_lockstep(&mut a, &mut b, 30, "rain_1000 (from_state)");
    assert!(
        a.space.bodies().count() > before,
        "no row spawned after the snapshot"
    );
}

#[test]
fn snapshot_survives_a_json_round_trip() {
    // The state is plain serde data: a snapshot written to JSON and read
    // back is the same state and continues identically.
    let name = "bowl_hexagons_100";
    let mut a = build(name);
    let mut b = build(name);
    a.step_n(40).unwrap_or_else(|e| panic!("{e}"));
    b.step_n(40).unwrap_or_else(|e| panic!("{e}"));
    let json = serde_json::to_string(a.space.state()).unwrap_or_else(|e| panic!("{e}"));
    let back: WorldState = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}"));
    assert!(&back == a.space.state());
    b.space = Space::from_state(back);
    continue_in_lockstep(&mut a, &mut b, 40, "json snapshot");
}

/// Makes the world diverge from its snapshot in every way a game might:
/// removes a static shape (the terrain the bodies rest on, if any) and a
/// dynamic body, adds a dynamic body and a static shape (both change the
/// static index and reuse freed slots), kicks the dynamic bodies and steps
/// on.
fn diverge(space: &mut Space, dt: Real) {
    let terrain = space
        .shapes()
        .find(|(_, s)| {
            space
                .body(s.body())
                .is_some_and(|b| b.body_type() == BodyType::Static)
        })
        .map(|(h, _)| h);
    if let Some(h) = terrain {
        space.remove_shape(h).unwrap_or_else(|e| panic!("{e}"));
    }
    let victim = space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .nth(3)
        .unwrap_or_else(|| panic!("a dynamic body"));
    space.remove_body(victim).unwrap_or_else(|e| panic!("{e}"));
    let extra = space
        .add_body(Body::new(Real::ONE, Real::ONE).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let circle =
        Shape::circle_shape_new(extra, Real::HALF, Vect::ZERO).unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(circle).unwrap_or_else(|e| panic!("{e}"));
    let ground = space
        .bodies()
        .find(|(_, b)| !b.is_dynamic())
        .map(|(h, _)| h)
        .unwrap_or_else(|| panic!("a static or kinematic body"));
    let wall = Shape::segment_shape_new(
        ground,
        Vect::from_ints(-3, 0),
        Vect::from_ints(3, 4),
        Real::ONE,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    space.add_shape(wall).unwrap_or_else(|e| panic!("{e}"));
    let handles: Vec<BodyHandle> = space.bodies().map(|(h, _)| h).collect();
    for h in handles {
        if let Some(b) = space.body_mut(h) {
            if b.is_dynamic() {
                b.set_velocity(b.velocity() + Vect::from_ints(3, 7));
            }
        }
    }
    for _ in 0..20 {
        space.step(dt).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn restore_state_in_place_replays_identically() {
    // World a diverges after the snapshot, then rolls back in place (keeping
    // its handlers and its now stale caches); world b never diverged. From
    // then on both must step identically. Scenes without scripted forces or
    // spawns, so the space alone is the whole simulation.
    for (name, k, m) in [
        ("bowl_boxes_100", 60, 60),
        ("tumbler_500", 40, 40),
        ("pyramid_20", 5, 20),
    ] {
        let mut a = build(name);
        let mut b = build(name);
        let dt = a.dt;
        a.step_n(k).unwrap_or_else(|e| panic!("{name}: {e}"));
        b.step_n(k).unwrap_or_else(|e| panic!("{name}: {e}"));
        let snapshot = a.space.state().clone();
        diverge(&mut a.space, dt);
        assert!(
            a.space.state() != &snapshot,
            "{name}: diverge changed nothing"
        );
        a.space.restore_state(&snapshot);
        assert!(a.space.state() == b.space.state(), "{name}: restore");
        assert_eq!(a.space.checksum(), b.space.checksum());
        for n in 1..=m {
            a.space.step(dt).unwrap_or_else(|e| panic!("{e}"));
            b.space.step(dt).unwrap_or_else(|e| panic!("{e}"));
            assert!(
                a.space.state() == b.space.state(),
                "{name}: states differ {n} steps after restore_state"
            );
            assert_eq!(a.space.checksum(), b.space.checksum());
        }
        a.space.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn adding_a_body_after_a_restore_yields_the_same_handle_in_every_world() {
    // Three worlds at the same state: `a` rolled back in place after
    // diverging, `b` rebuilt from the snapshot, `c` that never diverged.
    // A body removed before the snapshot leaves a free slot; the divergent
    // branch of `a` refilled it (and removed another body). The free lists
    // are part of the state, so all three hand out the same handle, and it
    // reuses the freed slot with a new generation.
    let name = "bowl_circles_100";
    let mut a = build(name);
    let dt = a.dt;
    a.step_n(30).unwrap_or_else(|e| panic!("{e}"));
    let removed = a
        .space
        .bodies()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .nth(10)
        .unwrap_or_else(|| panic!("a dynamic body"));
    a.space
        .remove_body(removed)
        .unwrap_or_else(|e| panic!("{e}"));
    a.step_n(5).unwrap_or_else(|e| panic!("{e}"));
    let snapshot = a.space.state().clone();
    let mut c = Space::from_state(snapshot.clone());
    diverge(&mut a.space, dt);
    a.space.restore_state(&snapshot);
    let mut b = Space::from_state(snapshot.clone());

    let new_body = || {
        let mut body = Body::new(Real::TWO, Real::ONE).unwrap_or_else(|e| panic!("{e}"));
        body.set_position(Vect::from_ints(0, 50));
        body
    };
    let ha = a
        .space
        .add_body(new_body())
        .unwrap_or_else(|e| panic!("{e}"));
    let hb = b.add_body(new_body()).unwrap_or_else(|e| panic!("{e}"));
    let hc = c.add_body(new_body()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ha, hb, "restore_state vs from_state");
    assert_eq!(ha, hc, "restored vs never diverged");
    assert_eq!(ha.index(), removed.index(), "the freed slot is reused");
    assert_ne!(ha, removed, "a stale handle must not alias the new body");
    assert!(a.space.body(removed).is_none());

    let shape =
        |h| Shape::circle_shape_new(h, Real::ONE, Vect::ZERO).unwrap_or_else(|e| panic!("{e}"));
    let sa = a
        .space
        .add_shape(shape(ha))
        .unwrap_or_else(|e| panic!("{e}"));
    let sb = b.add_shape(shape(hb)).unwrap_or_else(|e| panic!("{e}"));
    let sc = c.add_shape(shape(hc)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sa, sb);
    assert_eq!(sa, sc);

    for n in 1..=30 {
        for s in [&mut a.space, &mut b, &mut c] {
            s.step(dt).unwrap_or_else(|e| panic!("{e}"));
        }
        assert!(a.space.state() == b.state(), "a vs b after {n} steps");
        assert!(a.space.state() == c.state(), "a vs c after {n} steps");
    }
}

/// The wide kernels keep their batches' memory from step to step: a
/// world that switches between the narrow and the full-precision soft
/// step, and between kernel forms, gives after every run of steps the
/// bits of a new world that loads the same frame at each switch (whose
/// batches are new).
#[test]
fn switching_contact_kernels_between_steps_gives_a_fresh_world_s_bits() {
    use tamias2d::space::{ContactPrecision, Kernels, Settings, Solver};
    let set = |world: &mut ScriptedWorld, precision: ContactPrecision, kernels: Kernels| {
        let mut soft = scenes::soft_step_for(world.space.settings().gravity);
        soft.contact_precision = precision;
        let settings = Settings {
            solver: Solver::Soft(soft),
            ..*world.space.settings()
        };
        world.space.set_settings(settings).expect("valid settings");
        world.space.set_kernels(kernels);
    };
    let (narrow, full) = (ContactPrecision::Narrow, ContactPrecision::Full);
    let runs = [
        (narrow, Kernels::Auto, 12),
        (full, Kernels::Wide, 6),
        (narrow, Kernels::Portable, 6),
        (full, Kernels::Scalar, 3),
        (narrow, Kernels::Wide, 6),
    ];
    let mut world = build("pyramid_20");
    for (k, &(precision, kernels, steps)) in runs.iter().enumerate() {
        let frame = tamias2d::snapshot::save_frame(&world.space);
        let mut fresh = build("pyramid_20");
        fresh
            .space
            .load_frame_snapshot(&frame)
            .expect("the frame loads");
        for w in [&mut world, &mut fresh] {
            set(w, precision, kernels);
            w.step_n(steps).expect("steps");
        }
        assert_eq!(world.space.checksum(), fresh.space.checksum(), "run {k}");
    }
}
