//! Golden checksums: every built-in scene, stepped a fixed number of steps,
//! must reach a committed [`Space::checksum`] value.
//!
//! This is the cross-platform determinism check. The same test runs on
//! x86_64 (debug and release), native i686, aarch64 under qemu-user,
//! wasm32-wasip1 under node's WASI, and s390x (big-endian) and i686 under
//! Miri (`scripts/cross-platform.sh` runs them all). A platform passes only
//! if it reproduces these exact 64-bit values, so passing everywhere proves
//! the engine steps bit-identically everywhere.
//!
//! This file uses nothing but `tamias2d` and `std`: the script builds it
//! alone, without the crate's dev-dependencies (some of which do not build
//! for wasm32 or under Miri for s390x), so keep it that way.
//!
//! # Changing a golden
//! A golden moves only when the numerics change (solver, collision,
//! integration, rounding, scene construction, or what the checksum hashes).
//! **Such a change is deliberate, and the commit message must say so** and
//! why ("numeric change: … ; goldens regenerated"). Never regenerate the
//! goldens to make a failure go away without knowing which change moved
//! them: an unexplained move is a determinism bug.
//!
//! Regenerate (then paste the printed tables over [`GOLDEN`] and
//! [`GOLDEN_MIRI`]):
//! ```text
//! cargo test --release --test golden -- --ignored --nocapture print_goldens
//! ```
//! or set `TAMIAS_PRINT_GOLDENS=1` on a normal run, which prints the table
//! before checking it. The Miri table is computed natively too: it holds
//! the same scenes at fewer steps, so the values are platform-independent by
//! the same promise.
//!
//! # Finding the first differing step
//! If a platform disagrees, `TAMIAS_GOLDEN_TRACE=<scene>` (or `all`) prints
//! that scene's checksum after every step (`trace <scene> <step>
//! <checksum>`, step 0 = as built); diff the traces of two platforms to find
//! the first step that differs:
//! ```text
//! TAMIAS_GOLDEN_TRACE=pyramid_20 cargo test --test golden -- --nocapture golden_checksums \
//!     | grep '^trace' > x86_64.txt
//! ```
//! (add `--target …` and the platform's runner as `scripts/cross-platform.sh`
//! does; under Miri forward the variable with
//! `MIRIFLAGS=-Zmiri-env-forward=TAMIAS_GOLDEN_TRACE`).
//!
//! # Scenes and sizes
//! The smallest size of each scene family, at step counts that keep the
//! debug run short (under ~30 s on the CI machine) while still colliding,
//! stacking, spawning and spinning. Larger sizes run the same code on more
//! bodies; they are listed in [`LARGER_SIZES`] so that a new scene added to
//! `scenes::list()` without a golden fails
//! [`every_listed_scene_has_a_golden`]. Under Miri (~1000× slower) only
//! [`GOLDEN_MIRI`] runs: a small contact scene for a few steps.
use tamias2d::scenes;

/// `(scene, steps, checksum after that many steps)`, checked natively in
/// debug and release. Regenerate deliberately only (see the module docs).
const GOLDEN: &[(&str, u32, u64)] = &[
    // A: terrain
    ("bowl_circles_100", 600, 0x92a2c7c437b7fa51),
    ("bowl_boxes_100", 600, 0x9c52ac251cd637c7),
    ("bowl_hexagons_100", 600, 0x4db21d74abd4b987),
    ("bouncy_circles_500", 60, 0x144bbca450533572),
    ("no_collide", 600, 0x6334df0c71ece427),
    // B: stacking
    ("pyramid_20", 120, 0x401628d12a8c45a3),
    ("many_pyramids_4x4", 20, 0x60f65afb437762b0),
    ("rain_1000", 200, 0x9920f32492d3fee1),
    ("tumbler_500", 120, 0x4b33dd5cb1f44d1e),
    // C: accuracy
    ("free_fall", 240, 0x0f7f77bf5f30df03),
    ("constant_force", 240, 0x80423f32342cd5d8),
    ("projectile_45", 600, 0x6dc4e95f88c17f95),
    ("projectile_60", 600, 0x7cbbd6b7d1d1cc67),
    ("spin", 600, 0xd1288aaadb4ec988),
    ("elastic_pair", 240, 0x60356187a9a44429),
    ("newtons_cradle", 120, 0xf5c2043a08b199c5),
    ("incline_slide", 180, 0x9ad314272f5e9fa3),
    ("incline_stick", 180, 0x709665bab3a026bc),
    ("stack_10", 600, 0x9bb17f88289a2141),
];

/// The subset checked under Miri: one small scene with contacts, friction
/// and warm starting, for a few steps.
const GOLDEN_MIRI: &[(&str, u32, u64)] = &[
    ("stack_10", 10, 0xd97f53985299c256),
    ("incline_slide", 10, 0x43bc327eb23d4dc9),
    ("elastic_pair", 10, 0xe9b6e229c6778f8d),
];

/// Larger sizes of a family, covered by their smallest size in [`GOLDEN`].
const LARGER_SIZES: &[&str] = &[
    "bowl_circles_500",
    "bowl_circles_1000",
    "bowl_boxes_500",
    "bowl_boxes_1000",
    "bowl_hexagons_500",
    "bowl_hexagons_1000",
    "pyramid_100",
    "many_pyramids_10x10",
    "rain_4000",
    "tumbler_2000",
];

/// The table this build checks.
fn goldens() -> &'static [(&'static str, u32, u64)] {
    if cfg!(miri) {
        GOLDEN_MIRI
    } else {
        GOLDEN
    }
}

/// Builds `name` and steps it `steps` times; returns the checksum. Prints
/// every step's checksum when `TAMIAS_GOLDEN_TRACE` names the scene.
fn checksum_after(name: &str, steps: u32) -> u64 {
    let trace = std::env::var("TAMIAS_GOLDEN_TRACE").is_ok_and(|t| t == name || t == "all");
    let mut scene = scenes::builtin(name)
        .unwrap_or_else(|| panic!("{name} is not a built-in scene"))
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    if trace {
        println!("trace {name} 0 {:#018x}", scene.space.checksum());
    }
    for n in 1..=steps {
        scene
            .step()
            .unwrap_or_else(|e| panic!("{name}, step {n}: {e}"));
        if trace {
            println!("trace {name} {n} {:#018x}", scene.space.checksum());
        }
    }
    scene.space.checksum()
}

/// Prints `table`'s scenes with their current checksums, as Rust source.
fn print_table(const_name: &str, table: &[(&str, u32, u64)]) {
    println!("const {const_name}: &[(&str, u32, u64)] = &[");
    for &(name, steps, _) in table {
        let t = std::time::Instant::now();
        let sum = checksum_after(name, steps);
        println!("    ({name:?}, {steps}, {sum:#018x}), // {:?}", t.elapsed());
    }
    println!("];");
}

#[test]
fn golden_checksums_match_the_committed_values() {
    if std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
        print_table(if cfg!(miri) { "GOLDEN_MIRI" } else { "GOLDEN" }, goldens());
    }
    let mut wrong = Vec::new();
    for &(name, steps, expected) in goldens() {
        let got = checksum_after(name, steps);
        if got != expected {
            wrong.push(format!(
                "{name} after {steps} steps: got {got:#018x}, golden {expected:#018x}"
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} goldens differ on this platform/build:\n  {}\n\
         If the numerics changed on purpose, regenerate (see tests/golden.rs) and say so \
         in the commit message; if not, this is a determinism bug.",
        wrong.len(),
        goldens().len(),
        wrong.join("\n  ")
    );
}

#[test]
#[cfg_attr(
    miri,
    ignore = "builds every scene description, including the large ones"
)]
fn every_listed_scene_has_a_golden() {
    for (name, _) in scenes::list() {
        assert!(
            GOLDEN.iter().any(|(g, _, _)| g == name) || LARGER_SIZES.contains(name),
            "{name}: add it to GOLDEN (or to LARGER_SIZES if a smaller size of it is there)"
        );
    }
    for &(name, _, _) in GOLDEN.iter().chain(GOLDEN_MIRI) {
        assert!(
            scenes::builtin(name).is_some(),
            "{name} has a golden but is no longer a built-in scene"
        );
    }
    for name in LARGER_SIZES {
        assert!(
            scenes::builtin(name).is_some(),
            "{name} is no longer a built-in scene"
        );
    }
}

/// Prints both tables with the current values, for a deliberate regeneration:
/// `cargo test --release --test golden -- --ignored --nocapture print_goldens`.
#[test]
#[ignore = "prints the goldens for a deliberate regeneration"]
fn print_goldens() {
    print_table("GOLDEN", GOLDEN);
    print_table("GOLDEN_MIRI", GOLDEN_MIRI);
}
