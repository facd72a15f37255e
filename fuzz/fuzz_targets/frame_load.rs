//! Frame snapshot bytes from anywhere, loaded into a live world
//! (`fuzz/frame_world.snap`, a full snapshot of the world the seeds are
//! frames of): `load_frame_snapshot` returns an error and leaves the world
//! byte-identical, or installs a frame and the world validates, keeps its
//! level, and steps without panicking. Each input is tried as it is and
//! with its header checksum fixed up (as a forger would), so that damaged
//! payloads reach the decoder instead of stopping at the checksum.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;
use tamias2d::math::Real;
use tamias2d::snapshot;
use tamias2d::space::{Space, WorldState};

/// The world's state (a `Space` is not `Sync`) and its full snapshot.
fn world() -> &'static (WorldState, Vec<u8>) {
    static WORLD: OnceLock<(WorldState, Vec<u8>)> = OnceLock::new();
    WORLD.get_or_init(|| {
        let bytes = include_bytes!("../frame_world.snap");
        let state = snapshot::decode_state(bytes).expect("the committed world loads");
        let saved = snapshot::save_state(&state);
        (state, saved)
    })
}

fuzz_target!(|bytes: &[u8]| {
    check(bytes);
    if bytes.len() >= snapshot::HEADER_LEN {
        let mut sealed = bytes.to_vec();
        let sum = snapshot::payload_checksum(&sealed[snapshot::HEADER_LEN..]);
        sealed[12..20].copy_from_slice(&sum.to_le_bytes());
        check(&sealed);
    }
});

fn check(bytes: &[u8]) {
    let (base, saved) = world();
    let mut space = Space::from_state(base.clone());
    let level = space.level_digest();
    if let Err(e) = space.load_frame_snapshot(bytes) {
        assert!(
            snapshot::save(&space) == *saved,
            "a refused frame changed the world: {e}"
        );
        return;
    }
    if let Err(e) = space.validate() {
        panic!("load_frame_snapshot accepted an invalid world: {e}");
    }
    assert_eq!(space.level_digest(), level, "a frame changed the level");
    let s = space.settings();
    if space.bodies().count() > 64 || s.iterations > 50 || s.substeps > 4 {
        return;
    }
    for _ in 0..3 {
        let _ = space.step(Real::ratio(1, 60));
        if let Err(e) = space.validate() {
            panic!("stepping broke a loaded frame: {e}");
        }
    }
}
