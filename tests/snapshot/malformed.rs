//! Malformed input: truncations, bit flips, forged payloads, wrong
//! headers and structurally valid but inconsistent states. Every one is a
//! specific error, nothing panics, and a failed `load_snapshot` leaves the
//! live world byte-identical.
use super::*;
use tamias2d::limits::Limits;

/// `load` fails with an error `is_expected` accepts; `load_snapshot` fails
/// the same way and leaves a live world byte-identical.
fn expect_error(bytes: &[u8], what: &str, is_expected: impl Fn(&SnapshotError) -> bool) {
    let e = match snapshot::load(bytes) {
        Ok(_) => panic!("{what}: accepted"),
        Err(e) => e,
    };
    assert!(is_expected(&e), "{what}: unexpected error {e:?}");
    let mut live = live_world();
    let before = save(&live);
    assert_eq!(live.load_snapshot(bytes), Err(e), "{what}: load_snapshot");
    assert!(save(&live) == before, "{what}: live world changed");
}

#[test]
fn empty_buffer_and_short_headers_are_too_short() {
    for n in 0..HEADER_LEN {
        let bytes = small_snapshot().get(..n).unwrap_or(&[]);
        expect_error(bytes, "short", |e| *e == SnapshotError::TooShort);
    }
}

#[test]
fn every_truncation_is_an_error() {
    let bytes = small_snapshot();
    let mut live = live_world();
    let before = save(&live);
    for n in 0..bytes.len() {
        let prefix = bytes.get(..n).unwrap_or(&[]);
        let e = snapshot::load(prefix).err();
        match e {
            Some(SnapshotError::TooShort) => assert!(n < HEADER_LEN, "prefix {n}"),
            Some(SnapshotError::Decode(_)) => assert!(n >= HEADER_LEN, "prefix {n}"),
            other => panic!("prefix {n}: {other:?}"),
        }
        assert!(live.load_snapshot(prefix).is_err());
    }
    assert!(save(&live) == before, "live world changed");
    assert!(snapshot::load(bytes).is_ok());
}

#[test]
fn wrong_magic_version_and_trailing_bytes_are_named() {
    let good = small_snapshot();
    let mut bad = good.to_vec();
    bad[0] ^= 0x20;
    expect_error(&bad, "magic", |e| *e == SnapshotError::BadMagic);
    let mut bad = good.to_vec();
    bad[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    expect_error(&bad, "version", |e| {
        *e == SnapshotError::UnsupportedVersion(FORMAT_VERSION + 1)
    });
    let mut bad = good.to_vec();
    bad.extend_from_slice(&[0, 1, 2]);
    expect_error(&bad, "trailing", |e| *e == SnapshotError::TrailingBytes(3));
    let mut bad = good.to_vec();
    bad[12] ^= 1;
    expect_error(&bad, "checksum", |e| {
        matches!(e, SnapshotError::ChecksumMismatch { .. })
    });
    let not_ours = b"PNG\x0d\x0a\x1a\x0a and twenty more bytes".to_vec();
    expect_error(&not_ours, "foreign file", |e| *e == SnapshotError::BadMagic);
}

#[test]
fn a_forged_length_prefix_fails_without_allocating() {
    // The first length in the payload is the body arena's slot count, after
    // the settings (u32 + 2×8 + 3×8 + u32 + u32 + 5×bool + 2×8 = 73 bytes).
    let at = HEADER_LEN + 73;
    for len in [1u64 << 62, 1 << 40, 1 << 27, u64::MAX] {
        let mut bad = small_snapshot().to_vec();
        bad[at..at + 8].copy_from_slice(&len.to_le_bytes());
        expect_error(&bad, "forged length", |e| {
            matches!(e, SnapshotError::Decode(_))
        });
    }
}

#[test]
fn every_single_bit_flip_is_an_error() {
    // A small snapshot, every bit: the header fields give their own
    // errors; in the payload a flip breaks decoding, the layout (trailing
    // bytes), the checksum or an invariant.
    let good = small_snapshot();
    let mut bad = good.to_vec();
    for i in 0..good.len() {
        for bit in 0..8 {
            bad[i] ^= 1 << bit;
            let e = snapshot::load(&bad).err();
            let fits = matches!(
                (i, &e),
                (0..8, Some(SnapshotError::BadMagic))
                    | (8..12, Some(SnapshotError::UnsupportedVersion(_)))
                    | (12..20, Some(SnapshotError::ChecksumMismatch { .. }))
                    | (20.., Some(_))
            );
            assert!(fits, "byte {i} bit {bit}: {e:?}");
            bad[i] ^= 1 << bit;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Several flipped bits anywhere: always an error, never a panic.
    #[test]
    fn random_bit_flips_are_errors(
        flips in prop::collection::vec((any::<prop::sample::Index>(), 0u8..8), 1..6)
    ) {
        let good = small_snapshot();
        let mut bad = good.to_vec();
        for (i, bit) in &flips {
            bad[i.index(good.len())] ^= 1 << bit;
        }
        prop_assume!(bad != good);
        prop_assert!(snapshot::load(&bad).is_err());
    }

    /// Bytes overwritten in the payload and the header checksum fixed up,
    /// as a forger would: whatever decodes must either be rejected with a
    /// reason or be a valid world that steps without panicking and stays
    /// valid.
    #[test]
    fn forged_payloads_are_rejected_or_valid(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4)
    ) {
        let good = small_snapshot();
        let mut bad = good.to_vec();
        let payload_len = good.len() - HEADER_LEN;
        for (i, v) in &edits {
            bad[HEADER_LEN + i.index(payload_len)] = *v;
        }
        let sum = snapshot::payload_checksum(&bad[HEADER_LEN..]);
        bad[12..20].copy_from_slice(&sum.to_le_bytes());
        match snapshot::load(&bad) {
            Ok(mut w) => {
                prop_assert!(w.validate().is_ok());
                // What loads can step (a dynamic body without mass does not
                // validate), and within the untrusted limits a step is
                // bounded (a forged iteration count is refused at load).
                let passes = u64::from(w.settings().iterations * w.settings().substeps);
                prop_assert!(passes <= Limits::UNTRUSTED.max_solver_passes);
                for _ in 0..3 {
                    if let Err(e) = w.step(dt()) {
                        return Err(TestCaseError::fail(format!("step: {e}")));
                    }
                }
                if let Err(e) = w.validate() {
                    return Err(TestCaseError::fail(format!("valid world stepped into: {e}")));
                }
            }
            Err(SnapshotError::Invalid(why)) => prop_assert!(!why.is_empty()),
            Err(SnapshotError::Decode(_) | SnapshotError::TrailingBytes(_)) => {}
            // Valid but over the untrusted limits (an iteration count or
            // a sub-step count forged upwards): refused by name.
            Err(SnapshotError::OverLimit(e)) => prop_assert!(!e.limit.is_empty()),
            Err(e) => return Err(TestCaseError::fail(format!("unexpected {e:?}"))),
        }
    }
}

/// Snapshot of `state` after `edit` on its JSON form (fields of the state
/// types are private; serde shows them all).
fn tampered(state: &WorldState, edit: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    let mut json = ok(serde_json::to_value(state));
    edit(&mut json);
    let back: WorldState = ok(serde_json::from_value(json));
    snapshot::save_state(&back)
}

/// Indices of the first live body slot of each type, and a live shape slot
/// of each geometry kind, in the JSON form.
fn live_slot(
    json: &serde_json::Value,
    arena: &str,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> usize {
    json[arena]["slots"]
        .as_array()
        .and_then(|slots| {
            slots
                .iter()
                .position(|s| !s["value"].is_null() && pred(&s["value"]))
        })
        .unwrap_or_else(|| panic!("no such slot in {arena}"))
}

fn bump(v: &mut serde_json::Value, by: i64) {
    *v = serde_json::json!(v.as_i64().unwrap_or(0).wrapping_add(by));
}

const ONE: i64 = 1 << 32;

#[test]
fn inconsistent_snapshots_are_invalid_and_say_why() {
    let world = small_world();
    let state = world.state();
    assert!(snapshot::save_state(state) == save(&world));
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let dynamic = |j: &serde_json::Value| j["body_type"] == "Dynamic";
    let is_static = |j: &serde_json::Value| j["body_type"] == "Static";
    let poly = |j: &serde_json::Value| j["geometry"].get("Poly").is_some();
    let circle = |j: &serde_json::Value| j["geometry"].get("Circle").is_some();
    let segment = |j: &serde_json::Value| j["geometry"].get("Segment").is_some();
    let body = move |j: &mut serde_json::Value, f: &dyn Fn(&mut serde_json::Value)| {
        let i = live_slot(j, "bodies", dynamic);
        f(&mut j["bodies"]["slots"][i]["value"]);
    };
    let shape = |j: &mut serde_json::Value,
                 kind: &dyn Fn(&serde_json::Value) -> bool,
                 f: &dyn Fn(&mut serde_json::Value)| {
        let i = live_slot(j, "shapes", kind);
        f(&mut j["shapes"]["slots"][i]["value"]);
    };
    let cases: Vec<(&str, &str, Edit)> = vec![
        (
            "dangling body handle",
            "names missing body",
            Box::new(move |j| {
                shape(j, &circle, &|s| bump(&mut s["body"]["generation"], 1));
            }),
        ),
        (
            "shape body past the arena",
            "names missing body",
            Box::new(move |j| {
                shape(j, &poly, &|s| s["body"]["index"] = serde_json::json!(999));
            }),
        ),
        (
            "free list names a live slot",
            "free list names live slot",
            Box::new(|j| {
                if let Some(f) = j["bodies"]["free"].as_array_mut() {
                    f.push(serde_json::json!(0));
                }
            }),
        ),
        (
            "free list past the end",
            "past the end",
            Box::new(|j| {
                j["shapes"]["free"][0] = serde_json::json!(77);
            }),
        ),
        (
            "arena length",
            "arena length",
            Box::new(|j| bump(&mut j["bodies"]["len"], 1)),
        ),
        (
            "non-unit rotation",
            "rotation",
            Box::new(move |j| {
                body(j, &|b| b["rot"]["c"] = serde_json::json!(2 * ONE));
            }),
        ),
        (
            "negative mass",
            "mass must be ≥ 0",
            Box::new(move |j| {
                body(j, &|b| b["mass"] = serde_json::json!(-ONE));
            }),
        ),
        (
            "negative moment",
            "moment must be ≥ 0",
            Box::new(move |j| {
                body(j, &|b| b["moment"] = serde_json::json!(-ONE));
            }),
        ),
        (
            "static body with mass",
            "static body with a mass",
            Box::new(move |j| {
                let i = live_slot(j, "bodies", is_static);
                j["bodies"]["slots"][i]["value"]["mass"] = serde_json::json!(ONE);
            }),
        ),
        (
            "polygon of 2 vertices",
            "polygon has 2 vertices",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    s["geometry"]["Poly"]["count"] = serde_json::json!(2)
                });
            }),
        ),
        (
            "clockwise polygon",
            "not convex",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    let p = &mut s["geometry"]["Poly"];
                    let n = usize::try_from(p["count"].as_u64().unwrap_or(0)).unwrap_or(0);
                    if let Some(v) = p["verts"].as_array_mut() {
                        v[..n].reverse();
                    }
                });
            }),
        ),
        (
            "negative circle radius",
            "negative radius",
            Box::new(move |j| {
                shape(j, &circle, &|s| {
                    s["geometry"]["Circle"]["radius"] = serde_json::json!(-1)
                });
            }),
        ),
        (
            "negative density",
            "negative mass or density",
            Box::new(move |j| {
                shape(j, &circle, &|s| {
                    s["mass_spec"] = serde_json::json!({"Density": -ONE})
                });
            }),
        ),
        (
            "settings",
            "collision bias",
            Box::new(|j| {
                j["settings"]["collision_bias"] = serde_json::json!(2 * ONE);
            }),
        ),
        (
            "stamp without dt",
            "stamp 0",
            Box::new(|j| j["stamp"] = serde_json::json!(0)),
        ),
        (
            "more steps than sub-steps",
            "sub-steps",
            Box::new(|j| bump(&mut j["steps"], 1_000_000)),
        ),
        (
            "negative dt",
            "current dt",
            Box::new(|j| j["current_dt"] = serde_json::json!(-1)),
        ),
        (
            "arbiter stamp in the future",
            "outside 1..=",
            Box::new(|j| {
                bump(&mut j["arbiters"][0]["stamp"], 1);
            }),
        ),
        (
            "arbiter order",
            "canonical order",
            Box::new(|j| {
                if let Some(a) = j["arbiters"].as_array_mut() {
                    a.swap(0, 1);
                }
            }),
        ),
        (
            "arbiter with no contacts",
            "0 contacts",
            Box::new(|j| {
                j["arbiters"][0]["count"] = serde_json::json!(0);
            }),
        ),
        (
            "arbiter state",
            "FirstCollision",
            Box::new(|j| {
                j["arbiters"][0]["state"] = serde_json::json!("FirstCollision");
            }),
        ),
        (
            "cached arbiter that touched",
            "Cached",
            Box::new(|j| {
                j["arbiters"][0]["state"] = serde_json::json!("Cached");
            }),
        ),
        (
            "arbiter body",
            "bodies do not match",
            Box::new(|j| {
                let b = j["arbiters"][0]["body_b"].clone();
                j["arbiters"][0]["body_a"] = b;
            }),
        ),
        (
            "arbiter shape generation",
            "missing shape",
            Box::new(|j| {
                bump(&mut j["arbiters"][0]["shape_b"]["generation"], 1);
            }),
        ),
        (
            "negative normal impulse",
            "normal impulse",
            Box::new(|j| {
                j["arbiters"][0]["contacts"][0]["jn_acc"] = serde_json::json!(-1);
            }),
        ),
    ];
    for (what, expected, edit) in cases {
        let bytes = tampered(state, |j| edit(j));
        expect_error(
            &bytes,
            what,
            |e| matches!(e, SnapshotError::Invalid(why) if why.contains(expected)),
        );
    }
    // Format 6 stores no derived field and nothing past a count: such a
    // field edited in the state never reaches the bytes, and the loaded
    // state has it recomputed (or cleared), equal to the untouched one.
    // (Validation still checks these fields in memory: `Space::validate`,
    // and the crate's unit tests.)
    let with_one_contact = |j: &serde_json::Value| {
        j["arbiters"]
            .as_array()
            .and_then(|a| a.iter().position(|a| a["count"] == 1))
            .unwrap_or_else(|| panic!("an arbiter with one contact"))
    };
    let not_stored: Vec<(&str, Edit)> = vec![
        (
            "inverse mass",
            Box::new(move |j| body(j, &|b| bump(&mut b["mass_inv"], 1))),
        ),
        (
            "inverse moment",
            Box::new(move |j| body(j, &|b| bump(&mut b["moment_inv"], -1))),
        ),
        (
            "static body's inverse mass",
            Box::new(move |j| {
                let i = live_slot(j, "bodies", is_static);
                j["bodies"]["slots"][i]["value"]["mass_inv"] = serde_json::json!(ONE);
            }),
        ),
        (
            "polygon normal",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    bump(&mut s["geometry"]["Poly"]["normals"][1]["x"], 1)
                });
            }),
        ),
        (
            "polygon unused entry",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    bump(&mut s["geometry"]["Poly"]["verts"][7]["y"], 1)
                });
            }),
        ),
        (
            "segment normal",
            Box::new(move |j| {
                shape(j, &segment, &|s| {
                    bump(&mut s["geometry"]["Segment"]["normal"]["y"], -1)
                });
            }),
        ),
        (
            "arbiter contact past the count",
            Box::new(move |j| {
                let i = with_one_contact(j);
                j["arbiters"][i]["contacts"][1]["jt_acc"] = serde_json::json!(ONE);
            }),
        ),
    ];
    for (what, edit) in not_stored {
        let mut json = ok(serde_json::to_value(state));
        edit(&mut json);
        let edited: WorldState = ok(serde_json::from_value(json));
        assert!(edited != *state, "{what}: the edit changed nothing");
        let loaded = snapshot::decode_state(&snapshot::save_state(&edited))
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(loaded == *state, "{what}: the edit survived a save");
    }
    // Counts the compact form cannot hold do not decode.
    let undecodable: Vec<(&str, &str, Edit)> = vec![
        (
            "polygon of 9 vertices",
            "unknown kind, count or form",
            Box::new(move |j| {
                shape(j, &poly, &|s| {
                    s["geometry"]["Poly"]["count"] = serde_json::json!(9)
                });
            }),
        ),
        (
            "arbiter with 3 contacts",
            "too many contacts",
            Box::new(|j| {
                j["arbiters"][0]["count"] = serde_json::json!(3);
            }),
        ),
    ];
    for (what, expected, edit) in undecodable {
        let bytes = tampered(state, |j| edit(j));
        expect_error(
            &bytes,
            what,
            |e| matches!(e, SnapshotError::Decode(why) if why.contains(expected)),
        );
    }
}

#[test]
fn an_arbiter_naming_a_removed_shape_is_invalid() {
    let world = small_world();
    let mut state = world.state().clone();
    let (sa, _) = world.arbiters()[0].shapes();
    assert!(state.shapes.remove(sa).is_some());
    expect_error(
        &snapshot::save_state(&state),
        "removed shape",
        |e| matches!(e, SnapshotError::Invalid(why) if why.contains("missing shape")),
    );
}
