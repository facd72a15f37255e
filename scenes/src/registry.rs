//! The one list of standard scenes: every name, section, description, size,
//! default step count and golden checksum lives in [`REGISTRY`], and every
//! other list (tests, benches, the `tamias` CLI, the performance report, the
//! cross-platform check) is taken from it.
//!
//! # Goldens
//! A scene's [`Golden`] is the [`Space::checksum`](tamias2d::space::Space::checksum)
//! after that many steps of [`ScriptedWorld::step`](crate::ScriptedWorld::step)
//! from the built scene. `tests/golden.rs` of this crate checks them on every
//! platform (`scripts/cross-platform.sh`). The larger sizes of a family
//! carry no golden: they run the same code on more bodies, and
//! [`SceneInfo::covered_by`] names the smallest size that stands for them.
//! **A golden moves only with a deliberate numeric change**, stated in the
//! commit message (see `tests/golden.rs`).
use tamias2d::real;

use crate::desc::SceneDesc;
use crate::{accuracy, box2d, bullets, joints, stacking, terrain};

/// The groups (sections A to E) of standard scenes (see `scenes/README.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Section {
    /// A: bodies poured into static terrain (a segment bowl), and movers
    /// that must never touch.
    Terrain,
    /// B: stacking, piling and sustained contact (pyramids, rain, a tumbler,
    /// and Box2D's own benchmark scenes, `box2d_*`).
    Stacking,
    /// C: accuracy against closed-form answers (free fall, projectiles,
    /// elastic collisions, inclines).
    Accuracy,
    /// D: joints (constraints): a pendulum, a hanging chain, machines
    /// (windmill, gears, springs, a ratchet, a bridge, ragdolls, a car),
    /// Box2D's joint grid, and chains hanging at rest under end masses.
    Joints,
    /// E: large static levels with a few movers, the world of a rollback
    /// game (`tamias bench --rollback`); not in the speed tables of A and B.
    Level,
}

impl Section {
    /// The section's letter: `A` to `E`.
    pub fn letter(self) -> char {
        match self {
            Section::Terrain => 'A',
            Section::Stacking => 'B',
            Section::Accuracy => 'C',
            Section::Joints => 'D',
            Section::Level => 'E',
        }
    }

    /// The section's name: `terrain`, `stacking`, `accuracy`, `joints` or
    /// `level`.
    pub fn name(self) -> &'static str {
        match self {
            Section::Terrain => "terrain",
            Section::Stacking => "stacking",
            Section::Accuracy => "accuracy",
            Section::Joints => "joints",
            Section::Level => "level",
        }
    }
}

/// A committed checksum: [`Space::checksum`](tamias2d::space::Space::checksum)
/// after `steps` steps of the built scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Golden {
    /// Steps from the built scene.
    pub steps: u32,
    /// The checksum after them.
    pub checksum: u64,
}

/// One standard scene.
#[derive(Clone, Copy, Debug)]
pub struct SceneInfo {
    /// Registry name, e.g. `pyramid_20`.
    pub name: &'static str,
    /// Its section.
    pub section: Section,
    /// One line on what it is.
    pub about: &'static str,
    /// Bodies over the whole run (static terrain and spawned bodies included):
    /// [`SceneDesc::total_bodies`], checked by a test.
    pub bodies: u32,
    /// Steps of a default run ([`SceneDesc::steps`], checked by a test).
    pub steps: u32,
    /// The smaller size of the same family that stands for this one where
    /// debug-build time matters (goldens, lockstep tests); `None` for a
    /// scene that stands for itself.
    pub covered_by: Option<&'static str>,
    /// Golden checked natively (debug and release, every platform);
    /// `Some` exactly when `covered_by` is `None`.
    pub golden: Option<Golden>,
    /// Golden checked under Miri (a few steps of a few small scenes).
    pub miri_golden: Option<Golden>,
    /// Builds the description (`None` only if the scene's parameters are
    /// out of its builder's range, which a test rules out).
    build: fn() -> Option<SceneDesc>,
}

impl SceneInfo {
    /// The scene's description, named by its registry name.
    pub fn desc(&self) -> Option<SceneDesc> {
        let mut desc = (self.build)()?;
        self.name.clone_into(&mut desc.name);
        Some(desc)
    }

    /// A full-size scene (no smaller size stands for it) of sections A or
    /// B: the quick benchmark set.
    pub fn is_quick_bench(&self) -> bool {
        self.is_performance() && self.covered_by.is_none()
    }

    /// A scene of sections A or B, the performance scenes (compared with
    /// Rapier at the benchmark's default settings; the joint scenes of
    /// section D are compared at their own settings, apart).
    pub fn is_performance(&self) -> bool {
        matches!(self.section, Section::Terrain | Section::Stacking)
    }
}

const fn golden(steps: u32, checksum: u64) -> Option<Golden> {
    Some(Golden { steps, checksum })
}

macro_rules! scene {
    ($name:literal, $section:ident, $about:literal, bodies $bodies:literal, steps $steps:literal,
     $covered:expr, $golden:expr, $miri:expr, $build:expr) => {
        SceneInfo {
            name: $name,
            section: Section::$section,
            about: $about,
            bodies: $bodies,
            steps: $steps,
            covered_by: $covered,
            golden: $golden,
            miri_golden: $miri,
            build: $build,
        }
    };
}

/// Every standard scene, in section order (A to E), each family smallest
/// size first.
pub const REGISTRY: &[SceneInfo] = &[
    // A: terrain
    scene!("bowl_circles_100", Terrain, "100 circles (r 5) dropped into a 48-segment bowl",
        bodies 101, steps 1000, None, golden(600, 0x8315fc61d3a74458), None,
        || Some(terrain::bowl_circles(100))),
    scene!("bowl_circles_500", Terrain, "500 circles (r 5) dropped into a 48-segment bowl",
        bodies 501, steps 1000, Some("bowl_circles_100"), None, None,
        || Some(terrain::bowl_circles(500))),
    scene!("bowl_circles_1000", Terrain, "1000 circles (r 5) dropped into a 48-segment bowl",
        bodies 1001, steps 1000, Some("bowl_circles_100"), None, None,
        || Some(terrain::bowl_circles(1000))),
    scene!("bowl_boxes_100", Terrain, "100 rounded 10x10 boxes dropped into the bowl",
        bodies 101, steps 1000, None, golden(600, 0x570305a02d39fa7f), None,
        || Some(terrain::bowl_boxes(100))),
    scene!("bowl_boxes_500", Terrain, "500 rounded 10x10 boxes dropped into the bowl",
        bodies 501, steps 1000, Some("bowl_boxes_100"), None, None,
        || Some(terrain::bowl_boxes(500))),
    scene!("bowl_boxes_1000", Terrain, "1000 rounded 10x10 boxes dropped into the bowl",
        bodies 1001, steps 1000, Some("bowl_boxes_100"), None, None,
        || Some(terrain::bowl_boxes(1000))),
    scene!("bowl_hexagons_100", Terrain, "100 rounded hexagons dropped into the bowl",
        bodies 101, steps 1000, None, golden(600, 0xade6e48911bb256c), None,
        || Some(terrain::bowl_hexagons(100))),
    scene!("bowl_hexagons_500", Terrain, "500 rounded hexagons dropped into the bowl",
        bodies 501, steps 1000, Some("bowl_hexagons_100"), None, None,
        || Some(terrain::bowl_hexagons(500))),
    scene!("bowl_hexagons_1000", Terrain, "1000 rounded hexagons dropped into the bowl",
        bodies 1001, steps 1000, Some("bowl_hexagons_100"), None, None,
        || Some(terrain::bowl_hexagons(1000))),
    scene!("bouncy_circles_500", Terrain, "500 elastic circles bouncing in the bowl, no gravity",
        bodies 501, steps 1000, None, golden(60, 0x9f29d0eee442da84), None,
        || Some(terrain::bouncy_circles(500))),
    scene!("no_collide", Terrain, "28 movers threading 825 static circles; must never touch each other",
        bodies 29, steps 1000, None, golden(600, 0xa3c61e820e063063), None,
        || Some(terrain::no_collide())),
    // B: stacking
    scene!("pyramid_20", Stacking, "pyramid of 210 unit boxes",
        bodies 211, steps 1000, None, golden(120, 0x414c462831dbc717), None,
        || Some(stacking::pyramid(20))),
    scene!("pyramid_100", Stacking, "pyramid of 5050 unit boxes (Box2D large_pyramid)",
        bodies 5051, steps 1000, Some("pyramid_20"), None, None,
        || Some(stacking::pyramid(100))),
    scene!("many_pyramids_4x4", Stacking, "4x4 grid of 55-box pyramids",
        bodies 881, steps 1000, None, golden(20, 0x17650b42a4c1dbc7), None,
        || Some(stacking::many_pyramids(4, 4))),
    scene!("many_pyramids_10x10", Stacking, "10x10 grid of 55-box pyramids",
        bodies 5501, steps 1000, Some("many_pyramids_4x4"), None, None,
        || Some(stacking::many_pyramids(10, 10))),
    scene!("rain_1000", Stacking, "1000 circles raining in rows of 50 onto a 100 m ground",
        bodies 1001, steps 1000, None, golden(200, 0x346a2142d9d0f2b5), None,
        || Some(stacking::rain(1000))),
    scene!("rain_4000", Stacking, "4000 circles raining in rows of 50 onto a 100 m ground",
        bodies 4001, steps 1000, Some("rain_1000"), None, None,
        || Some(stacking::rain(4000))),
    scene!("tumbler_500", Stacking, "500 boxes in a spinning kinematic tumbler",
        bodies 501, steps 1000, None, golden(120, 0x86a12addf309fa93), None,
        || Some(stacking::tumbler(500))),
    scene!("tumbler_2000", Stacking, "2000 boxes in a spinning kinematic tumbler",
        bodies 2001, steps 1000, Some("tumbler_500"), None, None,
        || Some(stacking::tumbler(2000))),
    scene!("box2d_large_pyramid", Stacking, "Box2D's large_pyramid: 5050 unit boxes on a 200x2 m ground box, no sleeping",
        bodies 5051, steps 500, Some("pyramid_20"), None, None,
        || Some(box2d::large_pyramid(100))),
    scene!("box2d_many_pyramids", Stacking, "Box2D's many_pyramids: 20x20 pyramids of 55 unit boxes on 20 ground segments 11 m apart",
        bodies 22001, steps 200, Some("many_pyramids_4x4"), None, None,
        || Some(box2d::many_pyramids(20, 20))),
    scene!("box2d_tumbler", Stacking, "Box2D's tumbler: 2025 0.25 m boxes in a dynamic box of density 50 turned by a motor at 25 deg/s",
        bodies 2027, steps 750, Some("tumbler_500"), None, None,
        || Some(box2d::tumbler(45))),
    scene!("box2d_smash", Stacking, "Box2D's smash: an 8 m box at 40 m/s hits a block of 120x80 0.4 m boxes, no gravity",
        bodies 9601, steps 300, Some("pyramid_20"), None, None,
        || Some(box2d::smash(120, 80))),
    scene!("box2d_spinner", Stacking, "Box2D's spinner: a motor-driven 40 m bar stirs 6076 capsules (rounded segments), circles and boxes in a 360-segment loop",
        bodies 6078, steps 500, Some("tumbler_500"), None, None,
        || Some(box2d::spinner(6076))),
    // C: accuracy
    scene!("free_fall", Accuracy, "a ball falling from rest under gravity",
        bodies 1, steps 240, None, golden(240, 0x88b2255d0edea5d4), None,
        || Some(accuracy::free_fall())),
    scene!("constant_force", Accuracy, "constant force (100, 0) on a 10 kg ball",
        bodies 1, steps 240, None, golden(240, 0x1363bb2e5f889fde), None,
        || Some(accuracy::constant_force())),
    scene!("projectile_45", Accuracy, "projectile launched at 45 degrees",
        bodies 1, steps 600, None, golden(600, 0x9550ee66d4146366), None,
        || accuracy::projectile(45)),
    scene!("projectile_60", Accuracy, "projectile launched at 60 degrees",
        bodies 1, steps 600, None, golden(600, 0xe3a39fbbd9158a20), None,
        || accuracy::projectile(60)),
    scene!("spin", Accuracy, "torque 100 on a 100x100 box of mass 0.5",
        bodies 1, steps 600, None, golden(600, 0x509e40ebf5ae3b9e), None,
        || Some(accuracy::spin())),
    scene!("elastic_pair", Accuracy, "equal balls head-on with e = 1 exchange velocities",
        bodies 2, steps 240, None, golden(240, 0x529a027432b25c35),
        golden(10, 0x37f5ee50e89047e6),
        || Some(accuracy::elastic_pair())),
    scene!("newtons_cradle", Accuracy, "5 nearly touching elastic balls; the last leaves with the first's speed",
        bodies 5, steps 120, None, golden(120, 0xfbd2febabde221b3), None,
        || Some(accuracy::newtons_cradle())),
    scene!("incline_slide", Accuracy, "box on a 30 degree slope, mu 0.2 < tan 30: slides",
        bodies 2, steps 180, None, golden(180, 0x17790f085c6e6e21),
        golden(10, 0x8df1635f6c7142ec),
        || Some(accuracy::incline(30, real!(0.2)))),
    scene!("incline_stick", Accuracy, "box on a 30 degree slope, mu 0.8 > tan 30: stays",
        bodies 2, steps 180, None, golden(180, 0x7b7a3da195312d09), None,
        || Some(accuracy::incline(30, real!(0.8)))),
    scene!("stack_10", Accuracy, "10 stacked unit boxes; the top box must not drift",
        bodies 11, steps 600, None, golden(600, 0x2751592dcfc46d5e),
        golden(10, 0x78a2dde451835b46),
        || Some(accuracy::stack(10))),
    scene!("sleep_wake", Accuracy, "two 5-box columns fall asleep; a ball dropped at step 180 wakes only the left one",
        bodies 14, steps 480, None, golden(480, 0x789e3efbc6b3a598), None,
        || Some(accuracy::sleep_wake())),
    scene!("bullets", Accuracy, "a gun fires 32 bullets (r 0.05 m, 300 m/s) into a 0.1 m wall; none may pass",
        bodies 46, steps 120, None, golden(120, 0xfe0ce631758e83d1), None,
        || Some(bullets::bullets())),
    // D: joints
    scene!("pendulum", Joints, "a 1 kg bob on a 1 m pin joint, released at 37 degrees",
        bodies 2, steps 600, None, golden(600, 0x6ee0698483b38746), None,
        || Some(joints::pendulum())),
    scene!("chain_100", Joints, "100 links on pivot joints falling from horizontal, 100:1 end mass, 4 sub-steps",
        bodies 101, steps 600, None, golden(300, 0xac39c84e45f81787), None,
        || Some(joints::chain(100))),
    scene!("windmill", Joints, "a simple motor turns a 4-bladed rotor on a static post; 10 boxes dropped on it",
        bodies 12, steps 600, None, golden(600, 0x987720babe05d612), None,
        || Some(joints::windmill())),
    scene!("gear_train", Joints, "4 wheels meshed by gear joints (ratios -0.5, -2, -0.25), the first driven by a simple motor",
        bodies 5, steps 600, None, golden(600, 0xf74831dedb9ce20f), None,
        || Some(joints::gear_train())),
    scene!("spring_mass", Joints, "a 1 kg mass on a damped spring and a wheel on a damped rotary spring, ringing down",
        bodies 3, steps 600, None, golden(600, 0xcbd1c335eb6f1f4d), None,
        || Some(joints::spring_mass())),
    scene!("ratchet", Joints, "a motor-driven crank rocks a lever that ratchets a weighted wheel round; a pawl ratchet holds it",
        bodies 4, steps 600, None, golden(600, 0x8fb4ca76a10d6966), None,
        || Some(joints::ratchet())),
    scene!("rope_bridge", Joints, "12 planks on pivot joints hung from two cliffs by slide-joint ropes; 6 boxes dropped on it",
        bodies 19, steps 600, None, golden(600, 0xef9e02dc309159b6), None,
        || Some(joints::rope_bridge())),
    scene!("ragdolls_20", Joints, "20 six-part ragdolls (pivot + rotary limit joints) falling onto stairs",
        bodies 121, steps 600, None, golden(300, 0x11f5deb67d9b857a), None,
        || Some(joints::ragdolls(20))),
    scene!("car", Joints, "a chassis on groove joints and damped springs, wheels driven by simple motors over bumps",
        bodies 4, steps 600, None, golden(600, 0x5566180091f61f58), None,
        || Some(joints::car())),
    scene!("box2d_joint_grid", Joints, "Box2D's joint_grid: 100x100 circles joined by pivots to their neighbours, hung from 7 static ones",
        bodies 10000, steps 500, Some("chain_100"), None, None,
        || Some(box2d::joint_grid(100))),
    scene!("hanging_chain_20_1", Joints, "20 links (1 kg, 0.5 m) hanging at rest on pivots, 1 kg end mass",
        bodies 22, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(20, 1, false))),
    scene!("hanging_chain_20_10", Joints, "20 links (1 kg, 0.5 m) hanging at rest on pivots, 10 kg end mass",
        bodies 22, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(20, 10, false))),
    scene!("hanging_chain_20_100", Joints, "20 links (1 kg, 0.5 m) hanging at rest on pivots, 100 kg end mass",
        bodies 22, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(20, 100, false))),
    scene!("hanging_chain_100_1", Joints, "100 links (1 kg, 0.5 m) hanging at rest on pivots, 1 kg end mass",
        bodies 102, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(100, 1, false))),
    scene!("hanging_chain_100_10", Joints, "100 links (1 kg, 0.5 m) hanging at rest on pivots, 10 kg end mass",
        bodies 102, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(100, 10, false))),
    scene!("hanging_chain_100_100", Joints, "100 links (1 kg, 0.5 m) hanging at rest on pivots, 100 kg end mass",
        bodies 102, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(100, 100, false))),
    scene!("hanging_chain_20_100_kicked", Joints, "20 hanging links with a 100 kg end mass kicked sideways at 5 m/s",
        bodies 22, steps 600, Some("chain_100"), None, None,
        || Some(joints::hanging_chain(20, 100, true))),
    // E: level
    scene!("level_300", Level, "10 bodies rolling over a static level of 300 terrain segments",
        bodies 13, steps 1000, None, golden(60, 0x2a383b6afee24382), None,
        || terrain::level(300)),
    scene!("level_30000", Level, "10 bodies rolling over a static level of 30000 terrain segments",
        bodies 310, steps 1000, Some("level_300"), None, None,
        || terrain::level(30_000)),
];

/// The registry entry called `name`.
pub fn find(name: &str) -> Option<&'static SceneInfo> {
    REGISTRY.iter().find(|s| s.name == name)
}

/// The standard scene called `name` (see [`REGISTRY`]), or `None`. The
/// description's `name` is the registry name.
pub fn builtin(name: &str) -> Option<SceneDesc> {
    find(name)?.desc()
}

/// The registry's scenes of `section`, in order.
pub fn section(section: Section) -> impl Iterator<Item = &'static SceneInfo> {
    REGISTRY.iter().filter(move |s| s.section == section)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_sizes_cover_themselves() {
        for (i, s) in REGISTRY.iter().enumerate() {
            assert!(
                REGISTRY.iter().skip(i + 1).all(|t| t.name != s.name),
                "{} is registered twice",
                s.name
            );
            match s.covered_by {
                None => assert!(s.golden.is_some(), "{}: no golden", s.name),
                Some(small) => {
                    assert!(s.golden.is_none(), "{}: covered and golden", s.name);
                    let small = find(small).unwrap_or_else(|| panic!("{small} not registered"));
                    assert!(
                        small.covered_by.is_none(),
                        "{}: covered by a covered scene",
                        s.name
                    );
                    assert_eq!(
                        small.section, s.section,
                        "{}: covered across sections",
                        s.name
                    );
                }
            }
            if s.miri_golden.is_some() {
                assert!(s.golden.is_some(), "{}: Miri golden without golden", s.name);
            }
        }
        assert!(REGISTRY.windows(2).all(|w| w[0].section <= w[1].section));
    }

    #[test]
    #[cfg_attr(miri, ignore = "builds every description, the large ones too")]
    fn sizes_and_steps_are_the_descriptions() {
        for s in REGISTRY {
            let d = s
                .desc()
                .unwrap_or_else(|| panic!("{} does not describe", s.name));
            assert_eq!(d.name, s.name);
            assert_eq!(d.total_bodies(), s.bodies as usize, "{}: bodies", s.name);
            assert_eq!(d.steps, s.steps, "{}: steps", s.name);
        }
    }
}
