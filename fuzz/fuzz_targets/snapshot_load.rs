//! Snapshot bytes from anywhere: `load` returns an error or a world that
//! validates, and stepping that world never panics and keeps it valid.
#![no_main]
use libfuzzer_sys::fuzz_target;
use tamias2d::math::Real;
use tamias2d::snapshot;

fuzz_target!(|bytes: &[u8]| {
    let Ok(mut space) = snapshot::load(bytes) else {
        return;
    };
    if let Err(e) = space.validate() {
        panic!("load accepted an invalid world: {e}");
    }
    // Bound the work a forged world can ask for (body count, iterations,
    // sub-steps).
    let s = space.settings();
    if space.bodies().count() > 64 || s.iterations > 50 || s.substeps > 4 {
        return;
    }
    for _ in 0..3 {
        let _ = space.step(Real::ratio(1, 60));
        if let Err(e) = space.validate() {
            panic!("stepping broke a loaded world: {e}");
        }
    }
});
