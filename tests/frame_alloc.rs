//! A rollback loop on frames allocates nothing once its buffers have grown:
//! `save_frame` into a reused `FrameState`, `restore_frame`, `checksum` and
//! `step` (a GGRS-style game keeps a ring of frames and never allocates
//! per frame). Counted by `allocation-counter` (its global allocator is
//! in this test binary only); checked in release test builds (debug test builds validate every
//! step, which allocates).
use tamias2d::space::FrameState;

#[test]
fn a_frame_rollback_loop_allocates_nothing_once_warm() {
    if tamias2d::space::VALIDATES_STEPS {
        // Debug test builds validate the world after every step, which
        // allocates; `cargo test --release` (CI runs it) checks this.
        eprintln!("skipped: steps are validated in this build");
        return;
    }
    for name in ["level_300", "bowl_boxes_100", "car"] {
        let mut w = tamias2d_scenes::builtin(name)
            .unwrap_or_else(|| panic!("{name}"))
            .build()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for _ in 0..60 {
            w.space.step(w.dt).unwrap_or_else(|e| panic!("{e}"));
        }
        let mut confirmed = FrameState::default();
        w.space.save_frame(&mut confirmed);
        let mut ring = vec![FrameState::default(); 8];
        let mut rollback = |space: &mut tamias2d::space::Space| {
            space
                .restore_frame(&confirmed)
                .unwrap_or_else(|e| panic!("{e}"));
            for frame in &mut ring {
                space.step(w.dt).unwrap_or_else(|e| panic!("{e}"));
                space.save_frame(frame);
                std::hint::black_box(space.checksum());
            }
        };
        // Two rollbacks grow every buffer; the third must not allocate.
        rollback(&mut w.space);
        rollback(&mut w.space);
        let info = allocation_counter::measure(|| rollback(&mut w.space));
        assert_eq!(
            info.count_total, 0,
            "{name}: {} allocations in one 8-frame rollback",
            info.count_total
        );
    }
}
