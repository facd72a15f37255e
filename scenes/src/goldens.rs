//! The golden tables of the colored solver and of the soft step, beside
//! the registry's own goldens (the canonical solver,
//! [`SceneInfo::golden`](crate::SceneInfo::golden)): the same scenes at the
//! same steps in another solver order, and their checksums.
//!
//! `scenes/tests/golden.rs` checks every table natively on every platform
//! but Miri (whose small table is the canonical solver's), and the demo page
//! computes every [`check`](checks) in the browser (`tamias web --check`
//! compares its results with these values). Like the registry's goldens,
//! a value here moves only with a deliberate numeric change, said in the
//! commit message (see the golden test's module docs).
use crate::{Kernels, ScriptedWorld, REGISTRY};

/// The checksums of the native golden scenes, at their golden step, with
/// the colored solver on (`Settings::colored_solver`, the order threads
/// share): the bits every platform and every thread count must give for
/// it (`tests/parallel.rs` checks the thread counts against this table).
pub const COLORED: &[(&str, u64)] = &[
    ("bowl_circles_100", 0x67aa7ebf7604b5f5),
    ("bowl_boxes_100", 0x4bc405bc897616aa),
    ("bowl_hexagons_100", 0x6148e48a5354337b),
    ("bouncy_circles_500", 0x5a4f32c4458129b9),
    ("no_collide", 0x028dfaa930556694),
    ("pyramid_20", 0x33ac3028c3f54ce5),
    ("many_pyramids_4x4", 0x583f004fb9459b72),
    ("rain_1000", 0xb502e9f1f260b79f),
    ("tumbler_500", 0x35ca775b264aa4a1),
    ("free_fall", 0x7f4bfcad9cc96c9d),
    ("constant_force", 0x800f2b806658b63a),
    ("projectile_45", 0xf4be14e2d76f5f06),
    ("projectile_60", 0x180b0ea93c0a989c),
    ("spin", 0x0124c9306443f234),
    ("elastic_pair", 0xcc963996db5f05b2),
    ("newtons_cradle", 0x56cfbbd59e85549b),
    ("incline_slide", 0x98c0eee6ba6517f3),
    ("incline_stick", 0x065f4704ff1d5be6),
    ("stack_10", 0x4459f08045fb1e26),
    ("sleep_wake", 0xb9a4de9824fab095),
    ("bullets", 0xc1cda3aefeced93f),
    ("pendulum", 0x3999466388625a7e),
    ("chain_100", 0x292334c880d18bc9),
    ("windmill", 0x5c4de02893ce0667),
    ("gear_train", 0x2ef6ce4ee457cfc9),
    ("spring_mass", 0xf76c8fde20738f27),
    ("ratchet", 0x2fb066a05085725a),
    ("rope_bridge", 0x66f41218b130fcbe),
    ("ragdolls_20", 0x163dd2f75fd93ff3),
    ("car", 0x5841eac8446eab12),
    ("level_300", 0x8b0da822909ee6a2),
];

/// The registry's golden scenes and steps on the soft step
/// ([`SettingsDesc::use_soft_step`](crate::SettingsDesc::use_soft_step): the
/// soft step's defaults scaled to each scene's length unit, one
/// whole-pipeline sub-step), on every compiled form of its contact passes.
pub const SOFT: &[(&str, u64)] = &[
    ("bowl_circles_100", 0x44201e4f9a8d7211),
    ("bowl_boxes_100", 0x0b894c7688b3cb16),
    ("bowl_hexagons_100", 0xfeacf2504981fd52),
    ("bouncy_circles_500", 0xfbe029c880a02dd6),
    ("no_collide", 0x3114c858fb2f0b6b),
    ("pyramid_20", 0x73672e5ad155d3d6),
    ("many_pyramids_4x4", 0x7c192a7374bfe179),
    ("rain_1000", 0x2a0a6c032d5763af),
    ("tumbler_500", 0x28bfd8d7aa813c0f),
    ("free_fall", 0x7890415929c3ad71),
    ("constant_force", 0xff3e3bee7c154c5a),
    ("projectile_45", 0x12af88276b73db57),
    ("projectile_60", 0xcc8bb5e24db71ccc),
    ("spin", 0x47a9d208dc7df6ce),
    ("elastic_pair", 0x0f01eedb2a0212e3),
    ("newtons_cradle", 0x5f4844efa2540a6c),
    ("incline_slide", 0x3ea4a2fdbd58ac9a),
    ("incline_stick", 0x309b9acd6bba4f98),
    ("stack_10", 0xfc6a7731c7082744),
    ("sleep_wake", 0x6f8cbd4b0f699161),
    ("bullets", 0x81342227aaa1b1ea),
    ("pendulum", 0x47d8ab65d2b14131),
    ("chain_100", 0xb171d24657e6cebe),
    ("windmill", 0x0daa7c752b35d2fd),
    ("gear_train", 0x7b7344e76ffbaded),
    ("spring_mass", 0x71c4c90bb91d5b29),
    ("ratchet", 0x106c7969ffbe1e5a),
    ("rope_bridge", 0x414ffbba0dddd25f),
    ("ragdolls_20", 0xfdb647ec0db76b77),
    ("car", 0x1584e9b130455780),
    ("level_300", 0x23a89d3218bea210),
];

/// The registry's golden scenes and steps on the soft step as in [`SOFT`],
/// with the narrow contact kernels (`ContactPrecision::Narrow`). The
/// narrow passes always run in lanes (portable ones where the kernels are
/// scalar), so [`checks`] checks them on the portable lanes and the
/// golden test adds the AVX2 ones where the processor has them.
pub const NARROW: &[(&str, u64)] = &[
    ("bowl_circles_100", 0x4af782d82b43b7b3),
    ("bowl_boxes_100", 0xff04d35cdcdbfca4),
    ("bowl_hexagons_100", 0x1ea0076204b7e931),
    ("bouncy_circles_500", 0xda0174297c20b491),
    ("no_collide", 0x07793edfbeb2a68c),
    ("pyramid_20", 0xe92497ae02e54bab),
    ("many_pyramids_4x4", 0xbfcfdc3633900d6c),
    ("rain_1000", 0xd35cc423e4ebee68),
    ("tumbler_500", 0xecfedf94bad91830),
    ("free_fall", 0x557f9c122e1e911b),
    ("constant_force", 0x98cc171c28f7b82e),
    ("projectile_45", 0x9b3c918f0f5ecdbd),
    ("projectile_60", 0x79d52a5d770c1efc),
    ("spin", 0xd53de22bb07e3447),
    ("elastic_pair", 0x6f3d944f00e23ac1),
    ("newtons_cradle", 0xccf366c5a9cca3bd),
    ("incline_slide", 0x15bbcae5adbf9af5),
    ("incline_stick", 0xb2cf27d62e78f530),
    ("stack_10", 0x0d3b91a9933afbe4),
    ("sleep_wake", 0x5091c63f950665e1),
    ("bullets", 0xcea42bccd477441a),
    ("pendulum", 0x0f3da75fd38bc12a),
    ("chain_100", 0x7fc68affed814a63),
    ("windmill", 0xdb47ec2658f98a53),
    ("gear_train", 0x798a3ff1cb6b3e99),
    ("spring_mass", 0xbc587b38aeb55dfa),
    ("ratchet", 0x1639f2b31ea360ce),
    ("rope_bridge", 0x2d118cf8b660ed16),
    ("ragdolls_20", 0xc4c6cbfd990061d8),
    ("car", 0x7dbe1a2e63c5567a),
    ("level_300", 0x7b739ff5af9e6fa6),
];

/// The compiled forms of the soft step's contact passes that every build
/// has: the scalar kernels and the wide ones compiled for the build's
/// instruction set. (The golden test adds the wide kernels as this
/// processor runs them, AVX2 where it has it.)
pub const KERNEL_FORMS: [Kernels; 2] = [Kernels::Scalar, Kernels::Portable];

/// The solver a golden check steps with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// The scene's own settings: the sequential solver's canonical order.
    Canonical,
    /// The sequential solver's colored order (`Settings::colored_solver`).
    Colored,
    /// The soft step, its contact passes on these kernels.
    Soft(Kernels),
    /// The soft step with the narrow contact kernels, on these kernels.
    Narrow(Kernels),
}

/// One golden check: a registered scene, built with [`solver`](Self::solver)
/// and stepped [`steps`](Self::steps) times, reaches
/// [`checksum`](Self::checksum) on every platform.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Check {
    /// Registry name.
    pub scene: &'static str,
    /// The solver it steps with.
    pub solver: Solver,
    /// Steps from the built scene (the registry golden's).
    pub steps: u32,
    /// The committed checksum after them.
    pub checksum: u64,
}

impl Check {
    /// The scene's name, then the solver where it is not the canonical
    /// one: `pyramid_20`, `pyramid_20 colored`, `pyramid_20 soft scalar`.
    pub fn label(&self) -> String {
        match self.solver {
            Solver::Canonical => self.scene.to_string(),
            Solver::Colored => format!("{} colored", self.scene),
            Solver::Soft(kernels) => format!("{} soft {}", self.scene, kernels.describe()),
            Solver::Narrow(kernels) => {
                format!("{} soft narrow {}", self.scene, kernels.describe())
            }
        }
    }

    /// The scene as built for this check, not yet stepped. Errors name the
    /// scene.
    pub fn build(&self) -> Result<ScriptedWorld, String> {
        let mut desc = crate::builtin(self.scene)
            .ok_or_else(|| format!("{}: not a registered scene", self.scene))?;
        match self.solver {
            Solver::Canonical => {}
            Solver::Colored => desc.settings.colored_solver = true,
            Solver::Soft(_) => desc.settings.use_soft_step(),
            Solver::Narrow(_) => desc.settings.use_narrow_soft_step(),
        }
        let mut world = desc.build().map_err(|e| format!("{}: {e}", self.scene))?;
        if let Solver::Soft(kernels) | Solver::Narrow(kernels) = self.solver {
            world.space.set_kernels(kernels);
        }
        Ok(world)
    }

    /// Builds the scene and steps it; the checksum it reaches (to compare
    /// with [`checksum`](Self::checksum)).
    pub fn run(&self) -> Result<u64, String> {
        let mut world = self.build()?;
        world
            .step_n(self.steps)
            .map_err(|e| format!("{}: {e}", self.label()))?;
        Ok(world.space.checksum())
    }
}

/// Every golden check, scene by scene in registry order: the registry's
/// golden, then the colored solver's and the soft step's on each of
/// [`KERNEL_FORMS`], and the narrow soft step's on the portable lanes (a
/// scene missing from a table has no check there; the
/// golden test fails on it).
pub fn checks() -> Vec<Check> {
    let table = |t: &[(&str, u64)], name: &str| t.iter().find(|(n, _)| *n == name).map(|e| e.1);
    let mut all = Vec::new();
    for info in REGISTRY {
        let Some(golden) = info.golden else { continue };
        let check = |solver, checksum| Check {
            scene: info.name,
            solver,
            steps: golden.steps,
            checksum,
        };
        all.push(check(Solver::Canonical, golden.checksum));
        if let Some(sum) = table(COLORED, info.name) {
            all.push(check(Solver::Colored, sum));
        }
        if let Some(sum) = table(SOFT, info.name) {
            for kernels in KERNEL_FORMS {
                all.push(check(Solver::Soft(kernels), sum));
            }
        }
        if let Some(sum) = table(NARROW, info.name) {
            // The narrow passes run the portable lanes where the kernels
            // are scalar: one check covers both.
            all.push(check(Solver::Narrow(Kernels::Portable), sum));
        }
    }
    all
}
