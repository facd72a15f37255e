//! Golden checksums: every standard scene with a golden in the registry
//! ([`REGISTRY`]), stepped that many steps, must reach that committed
//! [`Space::checksum`](tamias2d::space::Space::checksum) value.
//!
//! This is the cross-platform determinism check. The same test runs on
//! x86_64 (debug and release), native i686, aarch64 under qemu-user,
//! wasm32-wasip1 under node's WASI, and s390x (big-endian) and i686 under
//! Miri (`scripts/cross-platform.sh` runs them all). A platform passes only
//! if it reproduces these exact 64-bit values, so passing everywhere proves
//! the engine steps bit-identically everywhere.
//!
//! Besides the registry's goldens (the default, canonical solver) it
//! checks [`goldens::COLORED`], [`goldens::SOFT`] and [`goldens::NARROW`]
//! (in `scenes/src/goldens.rs`), the same scenes with the colored solver
//! (`Settings::colored_solver`), on the soft step and on the soft step
//! with the narrow contact kernels, natively; the demo page computes
//! every table in the browser. With `TAMIAS_GOLDEN_THREADS=N`
//! every world steps on N threads: the script's `i686-parallel` and
//! `aarch64-parallel` platforms build the engine with its `parallel`
//! feature and run this test on 3 threads (the same values: no bit depends
//! on the thread count).
//!
//! This file uses nothing but `tamias2d_scenes` (and through it `tamias2d`)
//! and `std`: the script builds it alone, and this crate has no
//! dev-dependencies, so keep it that way.
//!
//! # Changing a golden
//! A golden moves only when the numerics change (solver, collision,
//! integration, rounding, scene construction, or what the checksum hashes).
//! **Such a change is deliberate, and the commit message must say so** and
//! why ("numeric change: … ; goldens regenerated"). Never regenerate the
//! goldens to make a failure go away without knowing which change moved
//! them: an unexplained move is a determinism bug.
//!
//! Regenerate (then paste the printed values into the `golden(…)` and Miri
//! `golden(…)` fields of `scenes/src/registry.rs`):
//! ```text
//! cargo test -p tamias2d-scenes --release --test golden -- --ignored --nocapture print_goldens
//! ```
//! or set `TAMIAS_PRINT_GOLDENS=1` on a normal run, which prints the values
//! before checking them (and prints the colored-solver and soft-step
//! tables, to paste into [`goldens::COLORED`] and [`goldens::SOFT`]). The Miri values are computed natively too: they
//! are the same scenes at fewer steps, so the values are
//! platform-independent by the same promise.
//!
//! # Finding the first differing step
//! If a platform disagrees, `TAMIAS_GOLDEN_TRACE=<scene>` (or `all`) prints
//! that scene's checksum after every step (`trace <scene> <step>
//! <checksum>`, step 0 = as built); diff the traces of two platforms to find
//! the first step that differs:
//! ```text
//! TAMIAS_GOLDEN_TRACE=pyramid_20 cargo test -p tamias2d-scenes --test golden -- --nocapture \
//!     golden_checksums | grep '^trace' > x86_64.txt
//! ```
//! (add `--target …` and the platform's runner as `scripts/cross-platform.sh`
//! does; under Miri forward the variable with
//! `MIRIFLAGS=-Zmiri-env-forward=TAMIAS_GOLDEN_TRACE`).
//!
//! # Scenes and sizes
//! The smallest size of each scene family, at step counts that keep the
//! debug run short (under ~30 s on the CI machine) while still colliding,
//! stacking, spawning and spinning. Larger sizes run the same code on more
//! bodies and carry no golden (`SceneInfo::covered_by` names the size that
//! does); a scene registered without either fails
//! [`every_registered_scene_has_a_golden`]. Under Miri (~1000× slower) only
//! the Miri goldens run: small contact scenes for a few steps.
use tamias2d_scenes::goldens;
use tamias2d_scenes::{Golden, Kernels, SettingsDesc, REGISTRY};

/// `(scene, golden)` this build checks: the Miri table under Miri, the
/// native one otherwise.
fn goldens() -> Vec<(&'static str, Golden)> {
    REGISTRY
        .iter()
        .filter_map(|s| {
            let g = if cfg!(miri) { s.miri_golden } else { s.golden };
            g.map(|g| (s.name, g))
        })
        .collect()
}

/// Builds `name` (with the colored solver if `colored`) and steps it
/// `steps` times; returns the checksum. Prints every step's checksum when
/// `TAMIAS_GOLDEN_TRACE` names the scene.
fn checksum_after(name: &str, steps: u32) -> u64 {
    checksum_with(name, steps, false)
}

fn checksum_with(name: &str, steps: u32, colored: bool) -> u64 {
    checksum_of(name, steps, Kernels::Auto, |s| s.colored_solver = colored)
}

/// [`checksum_with`] after `adjust` changed the scene's settings, on
/// `kernels` (`Space::set_kernels`).
fn checksum_of(
    name: &str,
    steps: u32,
    kernels: Kernels,
    adjust: impl FnOnce(&mut SettingsDesc),
) -> u64 {
    let trace = std::env::var("TAMIAS_GOLDEN_TRACE").is_ok_and(|t| t == name || t == "all");
    let mut desc = tamias2d_scenes::builtin(name)
        .unwrap_or_else(|| panic!("{name} is not a registered scene"));
    adjust(&mut desc.settings);
    let mut world = desc.build().unwrap_or_else(|e| panic!("{name}: {e}"));
    // The cross-platform script's *-parallel platforms: the same goldens
    // on several threads (any count gives the bits of one).
    let threads = std::env::var("TAMIAS_GOLDEN_THREADS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(1);
    world
        .space
        .set_threads(threads)
        .unwrap_or_else(|e| panic!("{name}: {threads} threads: {e}"));
    // Every step split, however small the scene.
    world.space.set_parallel_threshold(0);
    world.space.set_kernels(kernels);
    if trace {
        println!("trace {name} 0 {:#018x}", world.space.checksum());
    }
    for n in 1..=steps {
        world
            .step()
            .unwrap_or_else(|e| panic!("{name}, step {n}: {e}"));
        if trace {
            println!("trace {name} {n} {:#018x}", world.space.checksum());
        }
    }
    world.space.checksum()
}

/// Prints the current checksums of `table`'s scenes and steps.
fn print_table(what: &str, table: &[(&str, Golden)]) {
    println!("{what}:");
    for &(name, g) in table {
        let t = std::time::Instant::now();
        let sum = checksum_after(name, g.steps);
        println!(
            "    {name}: golden({}, {sum:#018x}), // {:?}",
            g.steps,
            t.elapsed()
        );
    }
}

#[test]
fn golden_checksums_match_the_committed_values() {
    let table = goldens();
    if std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
        print_table(
            if cfg!(miri) {
                "Miri goldens"
            } else {
                "goldens"
            },
            &table,
        );
    }
    assert!(!table.is_empty(), "no golden to check");
    let mut wrong = Vec::new();
    for &(name, g) in &table {
        let got = checksum_after(name, g.steps);
        if got != g.checksum {
            wrong.push(format!(
                "{name} after {} steps: got {got:#018x}, golden {:#018x}",
                g.steps, g.checksum
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} goldens differ on this platform/build:\n  {}\n\
         If the numerics changed on purpose, regenerate (see scenes/tests/golden.rs) and say so \
         in the commit message; if not, this is a determinism bug.",
        wrong.len(),
        table.len(),
        wrong.join("\n  ")
    );
}

#[test]
fn colored_solver_goldens_match_the_committed_values() {
    if cfg!(miri) {
        return;
    }
    let native: Vec<(&str, Golden)> = goldens();
    let mut wrong = Vec::new();
    for &(name, g) in &native {
        let got = checksum_with(name, g.steps, true);
        if std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
            println!("    (\"{name}\", {got:#018x}),");
        }
        match goldens::COLORED.iter().find(|(n, _)| *n == name) {
            Some(&(_, want)) if want == got => {}
            Some(&(_, want)) => wrong.push(format!(
                "{name} after {} steps: got {got:#018x}, golden {want:#018x}",
                g.steps
            )),
            None => wrong.push(format!("{name}: no colored golden (got {got:#018x})")),
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} colored-solver goldens differ on this platform/build:\n  {}\n\
         Regenerate with TAMIAS_PRINT_GOLDENS=1 (see the module docs) only for a deliberate change.",
        wrong.len(),
        native.len(),
        wrong.join("\n  ")
    );
}

#[test]
fn soft_step_goldens_match_the_committed_values() {
    if cfg!(miri) {
        return;
    }
    let native: Vec<(&str, Golden)> = goldens();
    let mut wrong = Vec::new();
    // Every compiled form of the contact passes: the scalar kernels, the
    // wide ones as this processor runs them (AVX2 where it has it), and
    // the wide ones compiled for the build's instruction set. Unoptimised,
    // the wide kernels run about 60 times slower than the scalar ones: a
    // debug build runs them on a few short scenes instead
    // (`wide_kernels_in_a_debug_build`).
    let mut forms = kernel_forms();
    if cfg!(debug_assertions) {
        forms.retain(|&k| k == Kernels::Scalar);
    }
    for kernels in forms {
        for &(name, g) in &native {
            let got = checksum_of(name, g.steps, kernels, SettingsDesc::use_soft_step);
            if kernels == Kernels::Scalar && std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
                println!("    (\"{name}\", {got:#018x}),");
            }
            let how = kernels.describe();
            match goldens::SOFT.iter().find(|(n, _)| *n == name) {
                Some(&(_, want)) if want == got => {}
                Some(&(_, want)) => wrong.push(format!(
                    "{name} after {} steps ({how} kernels): got {got:#018x}, golden {want:#018x}",
                    g.steps
                )),
                None => wrong.push(format!("{name}: no soft-step golden (got {got:#018x})")),
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} soft-step goldens differ on this platform/build:\n  {}\n\
         Regenerate with TAMIAS_PRINT_GOLDENS=1 (see the module docs) only for a deliberate change.",
        wrong.len(),
        native.len(),
        wrong.join("\n  ")
    );
}

/// The golden steps in debug builds of the narrow table: a few contact
/// scenes (the narrow passes always run in lanes, which unoptimised run
/// about 60 times slower than optimised; the release tests run the whole
/// table on every kernel form).
const NARROW_IN_DEBUG: [&str; 3] = ["pyramid_20", "bowl_circles_100", "incline_slide"];

#[test]
fn narrow_contact_goldens_match_the_committed_values() {
    if cfg!(miri) {
        return;
    }
    let mut native: Vec<(&str, Golden)> = goldens();
    // The narrow passes run the portable lanes where the kernels are
    // scalar: the portable lanes, and AVX2 where the processor has it.
    let mut forms = kernel_forms();
    forms.retain(|&k| k != Kernels::Scalar);
    if cfg!(debug_assertions) {
        native.retain(|(name, _)| NARROW_IN_DEBUG.contains(name));
        forms.retain(|&k| k == Kernels::Portable);
    }
    let mut wrong = Vec::new();
    for kernels in forms {
        for &(name, g) in &native {
            let got = checksum_of(name, g.steps, kernels, SettingsDesc::use_narrow_soft_step);
            if kernels == Kernels::Portable && std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
                println!("    (\"{name}\", {got:#018x}),");
            }
            let how = kernels.describe();
            match goldens::NARROW.iter().find(|(n, _)| *n == name) {
                Some(&(_, want)) if want == got => {}
                Some(&(_, want)) => wrong.push(format!(
                    "{name} after {} steps ({how} kernels): got {got:#018x}, golden {want:#018x}",
                    g.steps
                )),
                None => wrong.push(format!("{name}: no narrow golden (got {got:#018x})")),
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} narrow-contact goldens differ on this platform/build:\n  {}\n\
         Regenerate with TAMIAS_PRINT_GOLDENS=1 (see the module docs) only for a deliberate change.",
        wrong.len(),
        native.len(),
        wrong.join("\n  ")
    );
}

/// A narrow-contact golden small enough for Miri (big-endian s390x in CI):
/// `stack_10` on the narrow soft step after 10 steps, and after 2 under
/// Miri (the narrow passes' portable lanes, unoptimised and interpreted,
/// are its slowest code), on every platform and build.
const NARROW_SMALL: [(u32, u64); 2] = [(10, 0x06f39273009ab059), (2, 0x3e70249c5c62fc33)];

#[test]
fn narrow_contacts_small_golden_matches_the_committed_value() {
    let runs = if cfg!(miri) {
        &NARROW_SMALL[1..]
    } else {
        &NARROW_SMALL[..]
    };
    for &(steps, want) in runs {
        let got = checksum_of(
            "stack_10",
            steps,
            Kernels::Auto,
            SettingsDesc::use_narrow_soft_step,
        );
        if std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
            println!("stack_10 narrow after {steps} steps: {got:#018x}");
        }
        assert_eq!(
            got, want,
            "stack_10 on the narrow soft step after {steps} steps: got {got:#018x}, \
             golden {want:#018x}"
        );
    }
}

/// The compiled forms of the soft step's contact passes this processor
/// has: those of every build ([`goldens::KERNEL_FORMS`]: the scalar
/// kernels and the wide ones for the build's instruction set) and the wide
/// ones as it runs them (AVX2 where it has it).
fn kernel_forms() -> Vec<Kernels> {
    let mut forms = goldens::KERNEL_FORMS.to_vec();
    if Kernels::Wide.describe() != Kernels::Portable.describe() {
        forms.insert(1, Kernels::Wide);
    }
    forms
}

/// The wide kernels in an unoptimised build (with its overflow checks):
/// the scalar kernels' bits on short runs of a stack (manifolds of two
/// points) and of circles in a bowl (of one point). The full golden
/// matrix runs in optimised builds.
#[test]
fn wide_kernels_in_a_debug_build() {
    if cfg!(miri) || !cfg!(debug_assertions) {
        return;
    }
    for (name, steps) in [("pyramid_20", 8), ("bowl_circles_100", 12)] {
        let scalar = checksum_of(name, steps, Kernels::Scalar, SettingsDesc::use_soft_step);
        for kernels in kernel_forms() {
            let got = checksum_of(name, steps, kernels, SettingsDesc::use_soft_step);
            assert_eq!(
                got,
                scalar,
                "{name} after {steps} steps: {} kernels differ from the scalar ones",
                kernels.describe()
            );
        }
    }
}

#[test]
fn every_registered_scene_has_a_golden() {
    for s in REGISTRY {
        match s.covered_by {
            None => assert!(s.golden.is_some(), "{}: give it a golden", s.name),
            Some(small) => assert!(
                REGISTRY
                    .iter()
                    .any(|t| t.name == small && t.golden.is_some()),
                "{}: covered by {small}, which has no golden",
                s.name
            ),
        }
    }
    assert!(
        REGISTRY.iter().any(|s| s.miri_golden.is_some()),
        "no Miri golden"
    );
}

/// Prints both tables with the current values, for a deliberate
/// regeneration:
/// `cargo test -p tamias2d-scenes --release --test golden -- --ignored --nocapture print_goldens`.
#[test]
#[ignore = "prints the goldens for a deliberate regeneration"]
fn print_goldens() {
    let native: Vec<_> = REGISTRY
        .iter()
        .filter_map(|s| s.golden.map(|g| (s.name, g)))
        .collect();
    let miri: Vec<_> = REGISTRY
        .iter()
        .filter_map(|s| s.miri_golden.map(|g| (s.name, g)))
        .collect();
    print_table("goldens", &native);
    print_table("Miri goldens", &miri);
}

/// The character mover's golden: the platformer level of
/// `examples/character.rs` (`tamias2d_scenes::character_level`) with its
/// scripted player, the game's checksum (space, character, velocity) after
/// [`CHARACTER_FRAMES`] frames (fewer under Miri). The mover's casts,
/// slides, steps and platform rides give the same bits everywhere.
const CHARACTER_GOLDEN: u64 = 0x10281c7afcddefb4;
/// The same after [`CHARACTER_MIRI_FRAMES`].
const CHARACTER_MIRI_GOLDEN: u64 = 0xffb94ed81562ce0d;
/// Frames of the native run: the whole script.
const CHARACTER_FRAMES: u64 = tamias2d_scenes::character_level::FRAMES;
/// Frames of the Miri run: the landing and standing (casts every frame;
/// Miri runs about 1,000 times slower, and this keeps it to seconds).
const CHARACTER_MIRI_FRAMES: u64 = 20;

#[test]
fn character_level_golden_matches_the_committed_value() {
    use tamias2d_scenes::character_level::{script, CharacterGame};
    let (frames, want) = if cfg!(miri) {
        (CHARACTER_MIRI_FRAMES, CHARACTER_MIRI_GOLDEN)
    } else {
        (CHARACTER_FRAMES, CHARACTER_GOLDEN)
    };
    let mut game = CharacterGame::new().expect("the level builds");
    for f in 0..frames {
        game.step(&[script(f)]).expect("a frame");
        if f + 1 == CHARACTER_MIRI_FRAMES && std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
            println!(
                "character level after {} frames: {:#018x}",
                f + 1,
                game.checksum()
            );
        }
    }
    let got = game.checksum();
    if std::env::var_os("TAMIAS_PRINT_GOLDENS").is_some() {
        println!("character level after {frames} frames: {got:#018x}");
    }
    assert_eq!(
        got, want,
        "character level after {frames} frames: got {got:#018x}, golden {want:#018x}"
    );
}
