//! The `bullets` scene: none of the 32 bullets passes the wall; with the
//! bullet flags cleared most do at one sub-step and none at 64; a saved and
//! loaded run continues exactly.
use tamias2d_scenes::bullets::{self, tunnelled, without_bullets};
use tamias2d_scenes::{builtin, ScriptedWorld};

fn run(desc: &tamias2d_scenes::SceneDesc) -> ScriptedWorld {
    let mut w = desc.build().unwrap_or_else(|e| panic!("{e}"));
    w.run().unwrap_or_else(|e| panic!("{e}"));
    w
}

fn scene() -> tamias2d_scenes::SceneDesc {
    builtin("bullets").unwrap_or_else(|| panic!("bullets is registered"))
}

#[test]
fn no_bullet_tunnels_and_all_were_fired() {
    let w = run(&scene());
    assert_eq!(tunnelled(&w), Some(0));
    let fired = (0..bullets::BULLETS)
        .filter(|&i| w.body(&bullets::bullet_label(i)).is_some())
        .count();
    assert_eq!(fired, bullets::BULLETS as usize);
    // Every bullet hit the wall and dropped to the ground in front of it.
    for i in 0..bullets::BULLETS {
        let h = w
            .body(&bullets::bullet_label(i))
            .unwrap_or_else(|| panic!("fired"));
        let p = w.space.body(h).map(|b| b.position()).unwrap_or_default();
        let (x, y) = p.to_f64();
        assert!(x > -1.0 && x < -0.09 && y < 0.1, "bullet {i} at {x}, {y}");
    }
}

#[test]
fn without_the_flags_they_tunnel_at_one_sub_step_not_at_64() {
    let plain = without_bullets(scene());
    let n = tunnelled(&run(&plain)).unwrap_or(0);
    assert!(n >= 28, "only {n} of 32 tunnelled without bullets");
    let mut fine = plain;
    fine.settings.substeps = 64;
    fine.steps = 70; // the last shot reaches the wall by step 66
    assert_eq!(tunnelled(&run(&fine)), Some(0));
}

#[test]
fn a_saved_run_continues_exactly() {
    let desc = scene();
    let mut straight = desc.build().unwrap_or_else(|e| panic!("{e}"));
    straight.step_n(9).unwrap_or_else(|e| panic!("{e}"));
    let bytes = straight.save();
    straight.step_n(40).unwrap_or_else(|e| panic!("{e}"));
    let mut loaded = ScriptedWorld::load(&bytes).unwrap_or_else(|e| panic!("{e}"));
    loaded.step_n(40).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.space.checksum(), straight.space.checksum());
    assert_eq!(tunnelled(&loaded), Some(0));
}
