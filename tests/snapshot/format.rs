//! The byte format: pinned layout and sizes, header, buffer reuse, error
//! messages.
use super::*;

#[test]
fn format_layout_is_pinned() {
    // A change here means the byte layout changed: bump FORMAT_VERSION and
    // update the pins (and say so in the commit message).
    let empty = save(&Space::new());
    assert_eq!(&empty[..8], &MAGIC);
    assert_eq!(&empty[8..12], &FORMAT_VERSION.to_le_bytes());
    let sum = snapshot::payload_checksum(&empty[HEADER_LEN..]);
    assert_eq!(&empty[12..20], &sum.to_le_bytes());
    assert_eq!(FORMAT_VERSION, 9);
    // The empty world, field by field (little-endian, fixed-width ints,
    // every Real as its raw i64, lengths as u64, enum tags as u32).
    let expected = [
        "0a000000",         // settings.iterations: 10
        "0000000000000000", // gravity.x
        "0000000000000000", // gravity.y
        "0000000001000000", // damping: 1.0 = 2^32
        "14ae470100000000", // collision_slop: 0.005 (the default, a value, not layout)
        "d3c4750000000000", // collision_bias: 0.9^60
        "03000000",         // collision_persistence: 3
        "01000000",         // substeps: 1
        "01",               // warm_starting: true
        "01",               // friction: true
        "01",               // restitution: true
        "01",               // bias_impulses: true
        "01",               // block_solver: true
        "00",               // colored_solver: false
        "0000008000000000", // sleep_time_threshold: 0.5
        "cdcccc0c00000000", // idle_speed_threshold: 0.05 (rounded)
        "00000000",         // solver: Sequential (variant 0)
        "0000000000000000", // bodies.slots: length 0
        "0000000000000000", // bodies.free: length 0
        "00000000",         // bodies.len: 0
        "0000000000000000", // shapes.slots
        "0000000000000000", // shapes.free
        "00000000",         // shapes.len
        "0000000000000000", // arbiters: length 0
        "0000000000000000", // stamp
        "0000000000000000", // steps
        "0000000000000000", // current_dt
        "0000000000000000", // prev_dt
        "0000000000000000", // constraints.slots
        "0000000000000000", // constraints.free
        "00000000",         // constraints.len
        "0000000000000000", // dormant_arbiters: length 0
    ]
    .concat();
    assert_eq!(hex(&empty[HEADER_LEN..]), expected);
    // Encoded sizes per object: layout only (fixed-width encoding makes
    // them independent of the values).
    let mut w = Space::new();
    let mut sizes = vec![save(&w).len()];
    let mut grow = |w: &Space| {
        sizes.push(save(w).len());
    };
    let b = ok(w.add_body(Body::new_static()));
    grow(&w);
    ok(w.add_shape(ok(Shape::circle_shape_new(b, Real::ONE, Vect::ZERO))));
    grow(&w);
    ok(w.add_shape(ok(Shape::segment_shape_new(
        b,
        Vect::ZERO,
        Vect::from_ints(1, 0),
        Real::ZERO,
    ))));
    grow(&w);
    ok(w.add_shape(ok(Shape::box_shape_new(
        b,
        Real::ONE,
        Real::ONE,
        Real::ZERO,
    ))));
    grow(&w);
    ok(w.remove_body(b));
    grow(&w);
    let per_object: Vec<usize> = sizes.windows(2).map(|p| p[1].wrapping_sub(p[0])).collect();
    // Format 6 stores only the non-zero words of an object, so a size is
    // that of these objects. A slot is its generation (4) and option tag
    // (1) before the value. The static body at the origin: its head (4)
    // and one word (rot.c = 1; no inverse mass or moment, ever). A shape:
    // head (4), body handle (8), no material word (all zero), then its
    // geometry's head (4) and words: the unit circle its radius; the
    // segment (0,0)–(1,0) only b.x (no normal, ever); the 1 × 1 box, a
    // centred rectangle, r and t (no normals, no unused vertex slots).
    // Removing the body and its 3 shapes leaves 4 empty slots (5 bytes
    // each) and 4 free-list entries (u32).
    assert_eq!(
        per_object[..4],
        [5 + 4 + 8, 5 + 16 + 8, 5 + 16 + 8, 5 + 16 + 16]
    );
    let removed = [17, 29, 29, 37].iter().map(|n| n - 5 - 4).sum::<usize>();
    assert_eq!(per_object[4], 0usize.wrapping_sub(removed));
    // The arbiters of a stepped world: head (4), the narrow mask (4) when
    // some word fits 4 bytes, 4 handles (32), warm-start id (4), stamp (8),
    // a feature id (4) per contact, then the non-zero words, 4 or 8 bytes
    // each (normal, restitution, friction and surface velocity, 7 per
    // contact: r1, r2, dist, jn_acc, jt_acc).
    let stepped = small_world();
    let mut state = stepped.state().clone();
    let all = std::mem::take(&mut state.arbiters);
    let empty = snapshot::save_state(&state).len();
    let sizes: Vec<(usize, usize)> = all
        .iter()
        .map(|a| {
            state.arbiters = vec![a.clone()];
            (a.count(), snapshot::save_state(&state).len() - empty)
        })
        .collect();
    assert_eq!(sizes, ARBITER_SIZES, "bytes per arbiter (contacts, bytes)");
    // The largest forms: every word non-zero and 8 bytes wide (and the body
    // asleep, the filter and collision type not the defaults, an 8-vertex
    // polygon, two contacts).
    assert_eq!(
        largest_sizes(&stepped),
        [
            5 + 4 + 4 + 19 * 8,
            5 + 4 + 8 + 12 + 4 + 5 * 8 + 4 + 17 * 8,
            4 + 32 + 4 + 8 + 2 * 4 + 20 * 8
        ]
    );
    // A constraint slot: generation (4), option tag (1), bodies (2 × 8),
    // max_force, error_bias, max_bias (3 × 8), collide_bodies (1), the kind
    // tag (4) and the kind: a pin joint's two anchors, distance and
    // accumulated impulse (6 × 8), then the softness (1: `None`).
    let mut w = small_world();
    let bodies: Vec<_> = w.bodies().map(|(h, _)| h).collect();
    // Adding a joint to the ground wakes what sleeps on it (4 bytes less
    // per woken body): wake it first, so only the joint is measured.
    ok(w.activate_body(bodies[0]));
    let before = save(&w).len();
    let pin = ok(PinJoint::new(Vect::ZERO, Vect::ZERO, Real::ONE));
    ok(w.add_constraint(ok(Constraint::new(bodies[0], bodies[1], pin))));
    assert_eq!(save(&w).len() - before, 4 + 1 + 16 + 24 + 1 + 4 + 48 + 1);
}

/// `(contacts, bytes)` of each arbiter of `small_world`.
const ARBITER_SIZES: &[(usize, usize)] = &[(1, 100), (2, 132)];

/// Encoded sizes (slot included for the body and the shape) of a body, a
/// shape and an arbiter of `w` with every number set to a non-zero value
/// (through the human-readable form, which has every field).
fn largest_sizes(w: &Space) -> [usize; 3] {
    // Every number becomes 2^40 (a `Real` of 256 that needs 8 bytes), but
    // integer fields narrower than 64 bits become 1; handles keep naming
    // their objects and counts are set below.
    fn ones(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Number(_) | serde_json::Value::Null => {
                *v = serde_json::json!(1i64 << 40)
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(ones),
            serde_json::Value::Object(o) => {
                for (k, v) in o.iter_mut() {
                    match k.as_str() {
                        "body" | "shape_a" | "shape_b" | "body_a" | "body_b" | "count" => {}
                        "island" | "feature_id" | "warm_start_id" | "group" | "categories"
                        | "mask" | "collision_type" => *v = serde_json::json!(1),
                        _ => ones(v),
                    }
                }
            }
            serde_json::Value::Bool(_) | serde_json::Value::String(_) => {}
        }
    }
    let base = WorldState::default();
    let empty = snapshot::save_state(&base).len();
    let mut json = ok(serde_json::to_value(w.state()));
    let one = |arena: &str,
               pick: &dyn Fn(&serde_json::Value) -> bool,
               edit: &dyn Fn(&mut serde_json::Value)| {
        let mut slot = json[arena]["slots"]
            .as_array()
            .and_then(|s| {
                s.iter()
                    .find(|s| !s["value"].is_null() && pick(&s["value"]))
            })
            .cloned()
            .unwrap_or_else(|| panic!("no such {arena} slot"));
        ones(&mut slot["value"]);
        edit(&mut slot["value"]);
        let mut state = ok(serde_json::to_value(&base));
        state[arena]["slots"] = serde_json::json!([slot]);
        state[arena]["len"] = serde_json::json!(1);
        let state: WorldState = ok(serde_json::from_value(state));
        snapshot::save_state(&state).len() - empty
    };
    let body = one("bodies", &|b| b["body_type"] == "Dynamic", &|_| {});
    let shape = one("shapes", &|s| s["geometry"].get("Poly").is_some(), &|s| {
        s["geometry"]["Poly"]["count"] = serde_json::json!(8);
    });
    let mut arbiter = json["arbiters"][0].clone();
    ones(&mut arbiter);
    arbiter["count"] = serde_json::json!(2);
    json = ok(serde_json::to_value(&base));
    json["arbiters"] = serde_json::json!([arbiter]);
    let state: WorldState = ok(serde_json::from_value(json));
    [body, shape, snapshot::save_state(&state).len() - empty]
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn header_carries_version_and_payload_checksum() {
    let bytes = save(&small_world());
    let h = ok(snapshot::header(&bytes));
    assert_eq!(h.version, FORMAT_VERSION);
    assert_eq!(h.checksum, snapshot::payload_checksum(&bytes[HEADER_LEN..]));
}

#[test]
fn payload_checksum_is_pinned() {
    // Portable: the same values on every target (little-endian words).
    let ramp: Vec<u8> = (0..=100u8).collect();
    let sums = [0, 1, 7, 8, 31, 32, 33, 101].map(|n| snapshot::payload_checksum(&ramp[..n]));
    assert_eq!(
        sums,
        [
            12947730245408373148,
            14436479948233033896,
            12207078565629506267,
            18319719879261837459,
            15647855223621101133,
            12391200441337584545,
            7315989894677512464,
            12340533633619164456,
        ]
    );
    assert_eq!(
        sums.iter().collect::<std::collections::BTreeSet<_>>().len(),
        8
    );
}

#[test]
fn save_into_reuses_the_buffer_and_matches_save() {
    let mut scene = build("stack_10");
    let mut buf = Vec::new();
    let mut capacity = 0;
    for _ in 0..5 {
        ok(scene.step());
        let n = snapshot::save_into(&scene.space, &mut buf);
        assert_eq!(n, buf.len());
        assert!(buf == save(&scene.space));
        if capacity > 0 {
            assert_eq!(buf.capacity(), capacity, "no reallocation at the same size");
        }
        capacity = buf.capacity();
    }
}

#[test]
fn errors_display_what_is_wrong() {
    let all = [
        SnapshotError::TooShort,
        SnapshotError::BadMagic,
        SnapshotError::UnsupportedVersion(9),
        SnapshotError::Decode("unexpected end".into()),
        SnapshotError::TrailingBytes(3),
        SnapshotError::ChecksumMismatch {
            stored: 1,
            computed: 2,
        },
        SnapshotError::Invalid("body #1v0: mass must be ≥ 0".into()),
    ];
    for e in all {
        let shown = e.to_string();
        let boxed: Box<dyn std::error::Error> = Box::new(e);
        assert_eq!(boxed.to_string(), shown);
        assert!(shown.len() > 10, "{shown}");
    }
    assert!(SnapshotError::UnsupportedVersion(9)
        .to_string()
        .contains('9'));
    assert!(SnapshotError::TrailingBytes(3).to_string().contains('3'));
}

/// The committed seeds of the `snapshot_load` fuzz target are snapshots of
/// the current format (a stale seed is rejected at the version check and
/// fuzzes nothing). `TAMIAS_WRITE_FUZZ_SEEDS=1 cargo test --test snapshot
/// fuzz_seeds` rewrites them: three small scenes mid-run, one with
/// sub-steps and switches off so the settings vary too.
#[test]
fn fuzz_seeds_are_current_snapshots() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/snapshot_load");
    let seeds: [(&str, &str, u32); 3] = [
        ("seed0", "free_fall", 10),
        ("seed1", "stack_10", 30),
        ("seed2", "newtons_cradle", 5),
    ];
    for (file, scene, steps) in seeds {
        let path = dir.join(file);
        if std::env::var_os("TAMIAS_WRITE_FUZZ_SEEDS").is_some() {
            let mut s = build(scene);
            if file == "seed2" {
                let mut settings = *s.space.settings();
                settings.substeps = 2;
                settings.friction = false;
                settings.warm_starting = false;
                ok(s.space.set_settings(settings));
            }
            ok(s.step_n(steps));
            ok(std::fs::write(&path, save(&s.space)));
        }
        let bytes = ok(std::fs::read(&path));
        if let Err(e) = snapshot::load(&bytes) {
            panic!("{file}: {e} (regenerate: TAMIAS_WRITE_FUZZ_SEEDS=1)");
        }
    }
}

/// The `frame_load` fuzz target's world (`fuzz/frame_world.snap`, a full
/// snapshot of `small_world`) and its seeds (`fuzz/seeds/frame_load/`:
/// frames of that world after 0, 1 and 20 more steps, and after a body was
/// added) are current: the world loads and every seed loads into it.
/// `TAMIAS_WRITE_FUZZ_SEEDS=1 cargo test --test snapshot fuzz_seeds`
/// rewrites them.
#[test]
fn frame_fuzz_seeds_are_current_frames() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let world_path = root.join("frame_world.snap");
    let dir = root.join("seeds/frame_load");
    if std::env::var_os("TAMIAS_WRITE_FUZZ_SEEDS").is_some() {
        let w = small_world();
        ok(std::fs::write(&world_path, save(&w)));
        ok(std::fs::create_dir_all(&dir));
        let mut v = w.clone();
        for (file, steps) in [("seed0", 0), ("seed1", 1), ("seed2", 20)] {
            for _ in 0..steps {
                ok(v.step(dt()));
            }
            ok(std::fs::write(dir.join(file), snapshot::save_frame(&v)));
            v = w.clone();
        }
        let extra = ok(v.add_body(ok(Body::new(Real::ONE, Real::ONE))));
        ok(v.add_shape(ok(Shape::circle_shape_new(extra, Real::HALF, Vect::ZERO))));
        ok(std::fs::write(dir.join("seed3"), snapshot::save_frame(&v)));
    }
    let world = ok(snapshot::load(&ok(std::fs::read(&world_path))));
    for file in ["seed0", "seed1", "seed2", "seed3"] {
        let bytes = ok(std::fs::read(dir.join(file)));
        let mut w = world.clone();
        if let Err(e) = w.load_frame_snapshot(&bytes) {
            panic!("{file}: {e} (regenerate: TAMIAS_WRITE_FUZZ_SEEDS=1)");
        }
    }
}

#[test]
fn frame_layout_is_pinned() {
    // The empty world's frame (format 9, hand-written): header, level
    // digest, stamp, steps and the two dts (5 × 8), then the settings and
    // the constraint arena each as a byte count and their bincode bytes
    // (as in a full snapshot), then the empty body and shape parts (four
    // zero words each: two length bytes) and the two empty arbiter lists
    // (a u32 count each).
    let full = save(&Space::new());
    let frame = snapshot::save_frame(&Space::new());
    assert_eq!(&frame[..8], b"TAMIASFR");
    assert_eq!(&frame[8..12], &FRAME_FORMAT_VERSION.to_le_bytes());
    assert_eq!(FRAME_FORMAT_VERSION, 10);
    assert_eq!(
        &frame[HEADER_LEN..HEADER_LEN + 8],
        &Space::new().level_digest().to_le_bytes()
    );
    // Full payload: settings, body arena (3 × 8: slots, free, len as u64 +
    // u64 + u32 = 20 bytes), shape arena (20), arbiters (8), stamp, steps,
    // dts (32), constraints (20), dormant (8).
    let settings_len = full.len() - HEADER_LEN - (20 + 20 + 8 + 32 + 20 + 8);
    let at = HEADER_LEN + 40;
    assert_eq!(
        &frame[at..at + 4],
        &(settings_len as u32).to_le_bytes(),
        "settings byte count"
    );
    assert_eq!(
        &frame[at + 4..at + 4 + settings_len],
        &full[HEADER_LEN..HEADER_LEN + settings_len],
        "settings encoded as in a full snapshot"
    );
    let at = at + 4 + settings_len;
    assert_eq!(&frame[at..at + 4], &20u32.to_le_bytes(), "constraints");
    assert_eq!(
        &frame[at + 24..],
        &[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        "two empty parts, two empty lists"
    );
}
