//! Scripted worlds save and load with their script: a loaded world
//! continues exactly as the saved one (scripted forces, spawns by step,
//! `begin` counters), and damaged bytes are errors, never panics.
use tamias2d::checksum::checksum_of;
use tamias2d_scenes::{builtin, LoadError, ScriptedWorld};

fn build(name: &str) -> ScriptedWorld {
    builtin(name)
        .unwrap_or_else(|| panic!("{name}"))
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn a_loaded_world_continues_exactly_script_included() {
    // constant_force and spin script a force and a torque; rain_1000 spawns
    // a row every 10 steps (saved at 25: rows at 30, 40, … are still due).
    for (name, before, after) in [
        ("constant_force", 100, 100),
        ("spin", 37, 60),
        ("rain_1000", 25, 60),
    ] {
        let mut straight = build(name);
        let mut saved = build(name);
        saved.step_n(before).unwrap();
        let bytes = saved.save();
        let mut loaded = ScriptedWorld::load(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(loaded.space.checksum(), saved.space.checksum(), "{name}");
        assert_eq!(loaded.steps_taken(), u64::from(before));
        assert_eq!(loaded.save(), bytes, "{name}: save ∘ load is the identity");
        straight.step_n(before + after).unwrap();
        loaded.step_n(after).unwrap();
        assert!(
            loaded.space.state() == straight.space.state(),
            "{name}: the loaded world continued differently"
        );
        assert_eq!(loaded.bodies().len(), straight.bodies().len(), "{name}");
    }
}

#[test]
fn counters_and_labels_survive_and_handlers_stay_in_place() {
    let mut world = build("no_collide");
    world.step_n(30).unwrap();
    let bytes = world.save();
    let loaded = ScriptedWorld::load(&bytes).unwrap();
    assert_eq!(loaded.begin_count(2, 2), world.begin_count(2, 2));
    let mut cradle = build("newtons_cradle");
    let labels: Vec<_> = ["ball0", "ball4"].iter().map(|l| cradle.body(l)).collect();
    cradle.step_n(20).unwrap();
    let back = ScriptedWorld::load(&cradle.save()).unwrap();
    for (l, h) in ["ball0", "ball4"].iter().zip(labels) {
        let h = h.unwrap_or_else(|| panic!("{l}"));
        let b = back.body(l).unwrap_or_else(|| panic!("{l} after load"));
        assert_eq!((b.index(), b.generation()), (h.index(), h.generation()));
        assert!(
            back.space.body(b).is_some(),
            "{l} resolves in the loaded world"
        );
    }

    // In place: a handler the game attached stays attached.
    let mut game = build("stack_10");
    let touches = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let t = touches.clone();
    game.space.add_collision_handler(0, 0).begin = Some(Box::new(move |_| {
        t.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        true
    }));
    let start = build("stack_10").save();
    game.step_n(5).unwrap();
    game.load_in_place(&start).unwrap();
    assert_eq!(game.steps_taken(), 0);
    let before = touches.load(std::sync::atomic::Ordering::Relaxed);
    game.step_n(5).unwrap();
    assert!(touches.load(std::sync::atomic::Ordering::Relaxed) > before);
}

/// Replaces the payload and writes a matching digest, so that the checks
/// after the digest see the damage.
fn with_payload(bytes: &[u8], payload: &[u8]) -> Vec<u8> {
    let mut out = bytes[..20].to_vec();
    out[12..20].copy_from_slice(&checksum_of(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

#[test]
fn damaged_bytes_are_errors_never_panics() {
    let mut world = build("constant_force");
    world.step_n(10).unwrap();
    let bytes = world.save();
    for len in 0..bytes.len() {
        assert!(
            ScriptedWorld::load(&bytes[..len]).is_err(),
            "truncated to {len}"
        );
    }
    for i in 0..bytes.len() {
        let mut bad = bytes.clone();
        bad[i] ^= 0x04;
        assert!(ScriptedWorld::load(&bad).is_err(), "flip at {i}");
    }
    let mut bad = bytes.clone();
    bad[8] ^= 1;
    assert!(matches!(
        ScriptedWorld::load(&bad),
        Err(LoadError::UnsupportedVersion(_))
    ));
    assert!(matches!(
        ScriptedWorld::load(b"TAMIASSPxxxxxxxxxxxxxxxxxxxxx"),
        Err(LoadError::BadMagic)
    ));
    assert!(!ScriptedWorld::is_saved(&tamias2d::snapshot::save(
        &world.space
    )));

    // Valid digests over damaged content: the script and the references
    // are checked too.
    let payload = &bytes[20..];
    let text = String::from_utf8_lossy(payload).into_owned();
    let snap_len = u64::from_le_bytes(payload[..8].try_into().unwrap()) as usize;
    let script = std::str::from_utf8(&payload[8 + snap_len..]).unwrap();
    assert!(text.contains("\"forces\""));
    let cases = [
        (
            script.replace("\"forces\":[{\"body\":[0,0]", "\"forces\":[{\"body\":[9,0]"),
            "forces[0]",
        ),
        (
            script.replace("\"next_spawn\":0", "\"next_spawn\":5"),
            "next spawn",
        ),
        (script.replace("\"dt\":\"", "\"dt\":\"-"), "time step"),
        (script.replace("\"steps\"", "\"stepz\""), "parse"),
    ];
    for (damaged, expect) in cases {
        assert_ne!(damaged, script, "{expect}: the replacement matched nothing");
        let mut p = payload[..8 + snap_len].to_vec();
        p.extend_from_slice(damaged.as_bytes());
        let err = ScriptedWorld::load(&with_payload(&bytes, &p)).expect_err(expect);
        assert!(err.to_string().contains(expect), "{expect}: {err}");
    }
    // A snapshot length beyond the bytes.
    let mut p = payload.to_vec();
    p[..8].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(matches!(
        ScriptedWorld::load(&with_payload(&bytes, &p)),
        Err(LoadError::TooShort)
    ));
}
