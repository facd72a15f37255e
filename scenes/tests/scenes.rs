//! Standard scenes: every registered scene builds with the body count its
//! description in `scenes/README.md` implies, round-trips through JSON exactly, builds to the
//! same state twice, steps without error (small sizes, few steps: debug
//! builds stay fast), and bad descriptions are errors, never panics.
use serde::{Deserialize, Serialize};
use tamias2d::real;
use tamias2d::shape::ShapeError;
use tamias2d::space::SpaceError;
use tamias2d::{Real, Vect};
use tamias2d_scenes::rng::{SplitMix64, SEED};
use tamias2d_scenes::{
    self as scenes, accuracy, stacking, terrain, BodyDesc, BodyKind, BodyPath, ForceDesc,
    GeometryDesc, MassDesc, SceneDesc, SceneError, ShapeDesc,
};

/// `(initial bodies, bodies once every spawn is out)` as `scenes/README.md`
/// implies for each registry name.
fn expected_bodies(name: &str) -> (usize, usize) {
    let num = |s: &str| s.parse::<usize>().unwrap_or(0);
    let suffix = name.rsplit('_').next().unwrap_or("");
    let same = |n: usize| (n, n);
    match name {
        _ if name.starts_with("bowl_") => same(num(suffix) + 1),
        "bouncy_circles_500" => same(501),
        "no_collide" => same(1 + 12 + 16),
        _ if name.starts_with("pyramid_") => {
            let n = num(suffix);
            same(n * (n + 1) / 2 + 1)
        }
        _ if name.starts_with("many_pyramids_") => {
            let (nx, ny) = suffix.split_once('x').unwrap_or(("0", "0"));
            same(55 * num(nx) * num(ny) + 1)
        }
        _ if name.starts_with("rain_") => (1 + 50, num(suffix) + 1),
        _ if name.starts_with("tumbler_") => same(num(suffix) + 1),
        "elastic_pair" | "incline_slide" | "incline_stick" => same(2),
        "newtons_cradle" => same(5),
        "stack_10" => same(11),
        // the ground, 2 players and 10 boxes, then the ball at step 180.
        "sleep_wake" => (13, 14),
        // ground, wall and 12 boxes, then one bullet every 2 steps from step 0.
        "bullets" => (2 + 12 + 1, 2 + 12 + 32),
        "pendulum" => same(2),
        // post and rotor, then 2 of the 10 boxes at step 0.
        "windmill" => (2 + 2, 12),
        // the frame and 4 wheels.
        "gear_train" => same(5),
        // the ceiling, the mass and the wheel.
        "spring_mass" => same(3),
        // the frame, the crank, the rocker and the wheel.
        "ratchet" => same(4),
        // the cliffs and 12 planks, then 6 boxes at steps 120 and 180.
        "rope_bridge" => (13, 19),
        // the stairs and 6 bodies per ragdoll.
        _ if name.starts_with("ragdolls_") => same(6 * num(suffix) + 1),
        // the terrain, the chassis and 2 wheels.
        "car" => same(4),
        // the level in pieces of 100 segments, and 10 movers.
        _ if name.starts_with("level_") => same(num(suffix).div_ceil(100) + 10),
        _ if name.starts_with("chain_") => same(num(suffix) + 1),
        _ => same(1),
    }
}

#[test]
fn builtin_every_listed_scene_builds_with_documented_body_count() {
    assert_eq!(scenes::REGISTRY.len(), 42);
    for info in scenes::REGISTRY {
        let name = &info.name;
        assert!(!info.about.is_empty());
        let desc = scenes::builtin(name).unwrap_or_else(|| panic!("{name} is listed but unknown"));
        assert_eq!(desc.name, *name);
        let (initial, total) = expected_bodies(name);
        assert_eq!(
            desc.total_bodies(),
            total,
            "{name}: bodies in the description"
        );
        // A debug build of the 30,000-segment level costs about a minute (the
        // engine's `add_shape` to a static body scans every shape before the
        // first step: quadratic in the level's size). `level_300` is built
        // here in every build and `level_30000` in release (`cargo test
        // --release`, CI), by the same builder.
        if cfg!(debug_assertions) && desc.total_shapes() > 10_000 {
            continue;
        }
        let scene = desc.build().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            scene.space.bodies().count(),
            initial,
            "{name}: bodies after build"
        );
        assert_eq!(scene.bodies().len(), initial, "{name}: handles after build");
        assert_eq!(scene.dt, Real::ratio(1, 60), "{name}: dt");
    }
}

#[test]
fn builtin_names_are_unique_and_unknown_is_none() {
    let mut names: Vec<&str> = scenes::REGISTRY.iter().map(|s| s.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), scenes::REGISTRY.len());
    assert!(scenes::builtin("pyramid_21").is_none());
    assert!(scenes::builtin("").is_none());
}

#[test]
fn builtin_scenes_have_documented_settings_and_shapes() {
    let a = scenes::builtin("bowl_circles_100").unwrap_or_else(|| panic!("listed"));
    assert_eq!(a.settings.gravity, Vect::from_ints(0, -100));
    assert_eq!(a.settings.iterations, 10);
    assert_eq!(a.settings.collision_slop, real!(0.5));
    assert_eq!(a.steps, 1000);
    assert_eq!(a.bodies.first().map(|b| b.shapes.len()), Some(48));
    let nc = terrain::no_collide();
    assert_eq!(nc.total_shapes(), 4 + 825 + 28);
    assert_eq!(nc.settings.gravity, Vect::ZERO);
    let b = scenes::builtin("pyramid_20").unwrap_or_else(|| panic!("listed"));
    assert_eq!(b.settings.gravity, Vect::from_ints(0, -10));
    // The base row is centred on x = 0 and each box touches its neighbour.
    let xs: Vec<Real> = b
        .bodies
        .iter()
        .skip(1)
        .take(20)
        .map(|d| d.position.x)
        .collect();
    assert_eq!(xs.first().copied(), Some(real!(-9.5)));
    assert_eq!(xs.last().copied(), Some(real!(9.5)));
    assert!(xs.windows(2).all(|w| w[1] - w[0] == Real::ONE));
    let top = b.bodies.last().unwrap_or_else(|| panic!("boxes"));
    assert_eq!(top.position, Vect::new(Real::ZERO, real!(19.5)));
    assert_eq!(top.label.as_deref(), Some("top"));
}

#[test]
fn bowl_vertices_follow_the_documented_radii() {
    let ground = terrain::bowl_terrain(Real::ONE, Real::ZERO);
    for (i, s) in ground.shapes.iter().enumerate() {
        let GeometryDesc::Segment { a, .. } = s.geometry else {
            panic!("bowl shape {i} is not a segment")
        };
        // sin and cos are within ½ ulp, so the radius is within about r ulp.
        let r = Real::from_int(240 - 8 * (i as i32 % 3));
        assert!(
            (a.length() - r).abs() < Real::from_bits(512),
            "vertex {i}: {:?}",
            a.length()
        );
    }
    let hex = terrain::hexagon_verts();
    assert_eq!(hex.first().copied(), Some(Vect::from_ints(4, 0)));
    assert!(hex
        .iter()
        .all(|v| (v.length() - Real::from_int(4)).abs() < Real::from_bits(16)));
}

#[test]
fn tumbler_box_side_halves_only_when_the_grid_does_not_fit() {
    assert_eq!(stacking::tumbler_box_side(500), (Real::HALF, 23));
    assert_eq!(stacking::tumbler_box_side(841), (Real::HALF, 29));
    assert_eq!(stacking::tumbler_box_side(842).0, real!(0.25));
    assert_eq!(stacking::tumbler_box_side(2000), (real!(0.25), 45));
}

#[test]
fn rng_disk_samples_stay_inside_and_are_reproducible() {
    let mut a = SplitMix64::new(SEED);
    let mut b = SplitMix64::new(SEED);
    for _ in 0..1000 {
        let p = a.in_disk(Real::from_int(180));
        assert_eq!(p, b.in_disk(Real::from_int(180)));
        assert!(p.length() <= Real::from_int(180));
    }
}

fn to_json(desc: &SceneDesc) -> String {
    serde_json::to_string(desc).unwrap_or_else(|e| panic!("{}: {e}", desc.name))
}

fn from_json(json: &str) -> Result<SceneDesc, serde_json::Error> {
    serde_json::from_str(json)
}

#[test]
fn json_round_trip_is_exact_and_builds_identical_state() {
    for name in scenes::REGISTRY.iter().map(|s| s.name) {
        let desc = scenes::builtin(name).unwrap_or_else(|| panic!("listed"));
        let back = from_json(&to_json(&desc)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back, desc, "{name}: description changed through JSON");
        // Building the 4000–5500-body scenes (and the 30,000-segment level)
        // twice more would only cost debug time.
        if desc.total_bodies() <= 1100 && desc.total_shapes() <= 1100 {
            let (a, b) = (desc.build(), back.build());
            let (a, b) = (
                a.unwrap_or_else(|e| panic!("{e}")),
                b.unwrap_or_else(|e| panic!("{e}")),
            );
            assert!(
                a.space.state() == b.space.state(),
                "{name}: state differs after round trip"
            );
        }
    }
}

#[test]
fn json_reals_are_decimal_strings() {
    let json = to_json(&accuracy::constant_force());
    assert!(json.contains(r#""dt":"0.0166666666""#), "{json}");
    assert!(json.contains(r#""position":["20","20"]"#), "{json}");
    assert!(!json.contains("e-"), "no float notation: {json}");
}

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct OneReal(#[serde(with = "tamias2d_scenes::dec::real")] Real);

#[test]
fn decimal_reals_round_trip_every_bit_pattern() {
    let mut rng = SplitMix64::new(7);
    let mut values = vec![
        Real::MIN,
        Real::MAX,
        Real::DELTA,
        -Real::DELTA,
        Real::ZERO,
        Real::PI,
    ];
    values.extend((0..20_000).map(|i| Real::from_bits((rng.next_u64() as i64) >> (i % 48))));
    for v in values {
        let json = serde_json::to_string(&OneReal(v)).unwrap_or_default();
        let back: OneReal = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{json}: {e}"));
        assert_eq!(back.0, v, "{json}");
    }
}

#[test]
fn decimal_reals_accept_integers_and_reject_floats() {
    let int: OneReal = serde_json::from_str("-7").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(int.0, Real::from_int(-7));
    assert!(serde_json::from_str::<OneReal>("0.5").is_err());
    assert!(serde_json::from_str::<OneReal>("3000000000").is_err());
    assert!(serde_json::from_str::<OneReal>(r#""3000000000""#).is_err());
    assert!(serde_json::from_str::<OneReal>(r#""half""#).is_err());
}

const MINIMAL: &str = r#"{
  "name": "hand_written",
  "dt": "0.01",
  "steps": 10,
  "bodies": [
    { "kind": "static", "shapes": [
      { "geometry": { "kind": "segment", "a": [-10, 0], "b": ["10", "0"] }, "friction": "1" } ] },
    { "kind": "dynamic", "label": "ball", "position": [0, "0.5"],
      "shapes": [ { "geometry": { "kind": "circle", "radius": "0.5" }, "mass": { "density": 1 } } ] }
  ]
}"#;

#[test]
fn json_hand_written_minimal_scene_uses_defaults_and_runs() {
    let desc = from_json(MINIMAL).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(desc.settings, scenes::SettingsDesc::default());
    let mut scene = desc.build().unwrap_or_else(|e| panic!("{e}"));
    let ball = scene.body("ball").unwrap_or_else(|| panic!("labelled"));
    assert!(scene
        .space
        .body(ball)
        .is_some_and(|b| b.mass().is_positive()));
    scene.run().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.steps_taken(), 10);
}

#[test]
fn json_malformed_input_is_an_error() {
    let bad = [
        "",
        "{",
        "[]",
        r#"{"name": "x"}"#,
        &MINIMAL.replace(r#""dt": "0.01""#, r#""dt": 0.01"#),
        &MINIMAL.replace(r#""steps": 10"#, r#""steps": 10, "stpes": 3"#),
        &MINIMAL.replace(r#""kind": "circle""#, r#""kind": "ellipse""#),
        &MINIMAL.replace(r#""kind": "dynamic""#, r#""kind": "floating""#),
        &MINIMAL.replace(r#""radius": "0.5""#, r#""radius": "0.5.1""#),
        &MINIMAL.replace(r#""a": [-10, 0]"#, r#""a": [-10]"#),
    ];
    for json in bad {
        assert!(from_json(json).is_err(), "accepted: {json}");
    }
}

fn one_body(body: BodyDesc) -> SceneDesc {
    let mut desc = SceneDesc::new("bad", Real::ratio(1, 60), 1);
    desc.bodies.push(body);
    desc
}

fn ball_with(shape: ShapeDesc) -> BodyDesc {
    BodyDesc::dynamic(Vect::ZERO, Real::ONE, Real::ONE).with_shape(shape)
}

#[test]
fn build_invalid_values_are_errors_not_panics() {
    let shape_error = |desc: SceneDesc| match desc.build() {
        Err(SceneError::Shape {
            error: SpaceError::Shape(e),
            ..
        }) => e,
        other => panic!("expected a shape error, got {other:?}"),
    };
    let negative_radius = one_body(ball_with(ShapeDesc::circle(-Real::ONE)));
    assert_eq!(shape_error(negative_radius), ShapeError::Negative("radius"));
    let concave = vec![
        Vect::from_ints(0, 0),
        Vect::from_ints(2, 0),
        Vect::from_ints(1, 1),
        Vect::from_ints(2, 2),
        Vect::from_ints(0, 2),
    ];
    let raw = ShapeDesc::new(GeometryDesc::RawPoly {
        verts: concave.clone(),
        radius: Real::ZERO,
    });
    assert_eq!(shape_error(one_body(ball_with(raw))), ShapeError::NotConvex);
    // The same points as a hull-taking polygon are fine.
    assert!(one_body(ball_with(ShapeDesc::poly(concave, Real::ZERO)))
        .build()
        .is_ok());
    let friction = ShapeDesc::circle(Real::ONE).material(-Real::ONE, Real::ZERO);
    assert_eq!(
        shape_error(one_body(ball_with(friction))),
        ShapeError::Negative("friction")
    );
    let flat_box = ShapeDesc::box_at(-Real::ONE, Real::ONE, Real::ZERO, Vect::from_ints(1, 0));
    assert_eq!(
        shape_error(one_body(ball_with(flat_box))),
        ShapeError::Negative("box size")
    );
    let line = ShapeDesc::poly(
        vec![Vect::ZERO, Vect::from_ints(1, 1), Vect::from_ints(2, 2)],
        Real::ZERO,
    );
    assert_eq!(
        shape_error(one_body(ball_with(line))),
        ShapeError::DegeneratePolygon
    );
}

#[test]
fn build_invalid_bodies_and_scripts_are_errors() {
    let mut zero_dt = one_body(ball_with(ShapeDesc::circle(Real::ONE)));
    zero_dt.dt = Real::ZERO;
    assert_eq!(zero_dt.build().err(), Some(SceneError::TimeStep));

    let massless = one_body(
        BodyDesc::new(BodyKind::Dynamic, Vect::ZERO).with_shape(ShapeDesc::circle(Real::ONE)),
    );
    assert_eq!(
        massless.build().err(),
        Some(SceneError::Massless(BodyPath::Initial(0)))
    );

    let mut heavy_wall = BodyDesc::static_body();
    heavy_wall.mass = MassDesc::Explicit {
        mass: Real::ONE,
        moment: Real::ONE,
    };
    assert!(matches!(
        one_body(heavy_wall).build(),
        Err(SceneError::Body { .. })
    ));

    let zero_mass = BodyDesc::dynamic(Vect::ZERO, Real::ZERO, Real::ONE);
    assert!(matches!(
        one_body(zero_mass).build(),
        Err(SceneError::Body { .. })
    ));

    let mut force = accuracy::constant_force();
    force.forces.push(ForceDesc {
        body: 3,
        force: Vect::ZERO,
        torque: Real::ZERO,
    });
    assert_eq!(
        force.build().err(),
        Some(SceneError::ForceTarget { force: 1, body: 3 })
    );

    let mut twins = accuracy::elastic_pair();
    if let Some(b) = twins.bodies.get_mut(1) {
        b.label = Some("a".to_owned());
    }
    assert_eq!(
        twins.build().err(),
        Some(SceneError::DuplicateLabel("a".to_owned()))
    );

    let mut bad_spawn = stacking::rain(60);
    if let Some(body) = bad_spawn
        .spawns
        .get_mut(1)
        .and_then(|s| s.bodies.get_mut(3))
    {
        body.shapes = vec![ShapeDesc::circle(-Real::ONE)];
    }
    let err = bad_spawn.build().err();
    assert!(
        matches!(
            err,
            Some(SceneError::Shape {
                at: BodyPath::Spawn { spawn: 1, index: 3 },
                ..
            })
        ),
        "{err:?}"
    );

    let mut settings = accuracy::free_fall();
    settings.settings.collision_bias = Real::TWO;
    assert!(matches!(settings.build(), Err(SceneError::Settings(_))));
}

/// Small versions of every scene family, with a few steps each.
fn small_scenes() -> Vec<(SceneDesc, u32)> {
    vec![
        (terrain::bowl_circles(20), 10),
        (terrain::bowl_boxes(20), 10),
        (terrain::bowl_hexagons(20), 10),
        (terrain::bouncy_circles(20), 10),
        (terrain::no_collide(), 30),
        (stacking::pyramid(5), 10),
        (stacking::many_pyramids(2, 2), 5),
        (stacking::rain(120), 25),
        (stacking::tumbler(30), 10),
        (accuracy::free_fall(), 10),
        (accuracy::constant_force(), 10),
        (accuracy::projectile(45).unwrap_or_else(|| panic!("45")), 10),
        (accuracy::projectile(60).unwrap_or_else(|| panic!("60")), 10),
        (accuracy::spin(), 10),
        (accuracy::elastic_pair(), 10),
        (accuracy::newtons_cradle(), 10),
        (accuracy::incline(30, real!(0.2)), 10),
        (accuracy::stack(10), 10),
    ]
}

#[test]
fn small_scenes_step_without_error_and_deterministically() {
    for (desc, steps) in small_scenes() {
        let mut a = desc
            .build()
            .unwrap_or_else(|e| panic!("{}: {e}", desc.name));
        let mut b = desc
            .build()
            .unwrap_or_else(|e| panic!("{}: {e}", desc.name));
        assert!(
            a.space.state() == b.space.state(),
            "{}: built twice differently",
            desc.name
        );
        a.step_n(steps)
            .unwrap_or_else(|e| panic!("{}: {e}", desc.name));
        b.step_n(steps)
            .unwrap_or_else(|e| panic!("{}: {e}", desc.name));
        assert!(
            a.space.state() == b.space.state(),
            "{}: stepped twice differently",
            desc.name
        );
        assert_eq!(a.steps_taken(), u64::from(steps));
        a.space
            .validate()
            .unwrap_or_else(|e| panic!("{}: {e}", desc.name));
    }
}

#[test]
fn rain_releases_a_row_every_ten_steps_until_the_count() {
    let mut scene = stacking::rain(120)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let count = |s: &scenes::ScriptedWorld| s.space.bodies().count();
    assert_eq!(count(&scene), 51);
    scene.step_n(9).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(count(&scene), 51);
    scene.step().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(count(&scene), 101);
    scene.step_n(10).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(count(&scene), 121);
    scene.step_n(20).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(count(&scene), 121);
    assert_eq!(scene.bodies().len(), 121);
}

#[test]
fn no_collide_movers_never_begin_touching_each_other() {
    let mut scene = terrain::no_collide()
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.begin_count(2, 2), Some(0));
    assert_eq!(scene.begin_count(0, 2), None);
    scene.step_n(60).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.begin_count(2, 2), Some(0));
}

#[test]
fn tumbler_kinematic_body_spins_at_quarter_radian_per_second() {
    let mut scene = stacking::tumbler(4)
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    let h = scene.body("tumbler").unwrap_or_else(|| panic!("labelled"));
    scene.step_n(60).unwrap_or_else(|e| panic!("{e}"));
    let body = scene.space.body(h).unwrap_or_else(|| panic!("alive"));
    assert_eq!(body.angular_velocity(), real!(0.25));
    assert!(
        (body.angle() - real!(0.25)).abs() < Real::from_bits(1 << 12),
        "{:?}",
        body.angle()
    );
}

#[test]
fn scripted_force_and_torque_are_reapplied_every_step() {
    // 60 steps of a = F/m = 10 m/s² and α = τ/I = 0.12 rad/s²: v = 10 m/s and
    // ω = 0.12 rad/s after 1 s, up to the rounding of dt = 1/60.
    let tol = Real::from_bits(1 << 16);
    let mut push = accuracy::constant_force()
        .build()
        .unwrap_or_else(|e| panic!("{e}"));
    push.step_n(60).unwrap_or_else(|e| panic!("{e}"));
    let ball = push
        .body("ball")
        .and_then(|h| push.space.body(h))
        .unwrap_or_else(|| panic!("ball"));
    assert!(
        (ball.velocity().x - Real::from_int(10)).abs() < tol,
        "{:?}",
        ball.velocity()
    );
    let mut spin = accuracy::spin().build().unwrap_or_else(|e| panic!("{e}"));
    spin.step_n(60).unwrap_or_else(|e| panic!("{e}"));
    let b = spin
        .body("box")
        .and_then(|h| spin.space.body(h))
        .unwrap_or_else(|| panic!("box"));
    assert!(
        (b.angular_velocity() - real!(0.12)).abs() < tol,
        "{:?}",
        b.angular_velocity()
    );
}

#[test]
fn scene_restore_state_rolls_back_spawns_and_replays_identically() {
    // rain_1000 spawns a row every 10 steps: roll back across two spawns.
    let mut scene = scenes::builtin("rain_1000").unwrap().build().unwrap();
    scene.step_n(15).unwrap();
    let saved = scene.space.state().clone();
    let bodies_at_15 = scene.bodies().len();
    scene.step_n(25).unwrap();
    let straight = scene.space.state().clone();
    assert!(scene.bodies().len() > bodies_at_15);
    scene.restore_state(&saved);
    assert_eq!(scene.bodies().len(), bodies_at_15);
    assert_eq!(scene.steps_taken(), 15);
    scene.step_n(25).unwrap();
    assert_eq!(scene.space.state(), &straight);
}

#[test]
fn constraints_in_json_build_and_bad_ones_are_named_errors() {
    let scene = |constraints: &str| {
        format!(
            r#"{{"name": "j", "dt": "0.0166666667", "steps": 1, "bodies": [
                {{"kind": "static", "shapes": []}},
                {{"kind": "dynamic", "position": ["1", "0"],
                  "mass": {{"explicit": {{"mass": "1", "moment": "1"}}}}, "shapes": []}},
                {{"kind": "dynamic", "position": ["3", "0"],
                  "mass": {{"explicit": {{"mass": "1", "moment": "1"}}}}, "shapes": []}}],
              "constraints": [{constraints}]}}"#
        )
    };
    let good = scene(
        r#"{"type": "pin", "a": 0, "b": 1},
           {"type": "damped_spring", "a": 1, "b": 2, "anchor_a": ["0.5", "0"],
            "rest_length": "2", "stiffness": "100", "damping": "0.5"},
           {"type": "simple_motor", "a": 0, "b": 2, "rate": "2", "max_force": "10"}"#,
    );
    let desc = from_json(&good).unwrap_or_else(|e| panic!("{e}"));
    let mut world = desc.build().unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(world.space.constraints().count(), 3);
    world.step().unwrap_or_else(|e| panic!("{e}"));
    let back = from_json(&to_json(&desc)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back, desc);
    for (bad, why) in [
        (
            r#"{"type": "pin", "a": 0, "b": 7}"#,
            "body 7 does not exist",
        ),
        (r#"{"type": "gear", "a": 1, "b": 2}"#, "needs ratio"),
        (
            r#"{"type": "gear", "a": 1, "b": 2, "ratio": "1", "rate": "1"}"#,
            "rate is not",
        ),
        (r#"{"type": "pin", "a": 1, "b": 1}"#, "two different bodies"),
        (
            r#"{"type": "damped_spring", "a": 1, "b": 2, "rest_length": "1",
               "stiffness": "-1", "damping": "0"}"#,
            "stiffness is negative",
        ),
    ] {
        let desc = from_json(&scene(bad)).unwrap_or_else(|e| panic!("{e}"));
        match desc.build() {
            Err(e) => assert!(e.to_string().contains(why), "{bad}: {e}"),
            Ok(_) => panic!("{bad} accepted"),
        }
    }
    assert!(from_json(&scene(r#"{"type": "rope", "a": 0, "b": 1}"#)).is_err());
}
