//! Rollback determinism through GGRS: a `SyncTestSession` re-simulates the
//! last 7 frames on every frame and compares checksums (a mismatch is an
//! error), and two `P2PSession` peers over loopback UDP must end with the
//! same checksums. The game is `tamias2d_scenes::ggrs_game` (bowl_boxes_100 with two
//! player balls); the sessions and the request loop are `tamias2d-ggrs`'s.
use tamias2d_ggrs::ggrs::GgrsError;
use tamias2d_scenes::ggrs_game;

use ggrs_game::{
    run_p2p, run_straight, run_straight_on, run_synctest, scripted_buttons, Game, P2P_INPUT_DELAY,
};

/// 600 frames at check distance 7 (8 steps of a 103-body scene per frame).
const SYNCTEST_FRAMES: u64 = 600;

/// The frames a SyncTest runs in this build: [`SYNCTEST_FRAMES`] when
/// optimised (CI runs these tests in release too), the first third in a
/// debug build, where every step is validated and an unoptimised step
/// costs about twenty times more (it still rolls back on every frame from
/// the eighth).
const FRAMES: u64 = if cfg!(debug_assertions) {
    SYNCTEST_FRAMES / 3
} else {
    SYNCTEST_FRAMES
};

#[test]
fn synctest_check_distance_7_agrees_with_a_straight_run() {
    let mut game = Game::new();
    run_synctest(&mut game, FRAMES, 7, 3).expect("deterministic under rollback");
    assert_eq!(game.frame(), FRAMES);
    assert!(game.loads >= FRAMES - 8, "rolled back every frame");
    let straight = run_straight(FRAMES, 3, 0);
    assert_eq!(game.space.checksum(), straight.space.checksum());
    assert_eq!(game.space.state(), straight.space.state());
}

/// The joint scenes under rollback: `ragdolls_20` (pivot and
/// rotary-limit joints, 2 sub-steps) and `car` (groove joints, damped
/// springs, motors), their first two dynamic bodies driven by the players,
/// [`FRAMES`] at check distance 7; the end state equals a straight run.
#[test]
fn synctest_on_the_joint_scenes_agrees_with_a_straight_run() {
    for name in ["ragdolls_20", "car"] {
        let mut game = Game::with_scene(name).unwrap_or_else(|| panic!("{name} is a game"));
        run_synctest(&mut game, FRAMES, 7, 3)
            .unwrap_or_else(|e| panic!("{name}: not deterministic under rollback: {e}"));
        assert_eq!(game.frame(), FRAMES, "{name}");
        assert!(game.loads >= FRAMES - 8, "{name}: rolled back every frame");
        let fresh = Game::with_scene(name).unwrap_or_else(|| panic!("{name} is a game"));
        let straight = run_straight_on(fresh, FRAMES, 3, 0);
        assert_eq!(game.space.checksum(), straight.space.checksum(), "{name}");
        assert_eq!(game.space.state(), straight.space.state(), "{name}");
        assert!(
            game.space.constraints().next().is_some(),
            "{name} has joints"
        );
    }
}

/// Sleeping under rollback: `sleep_wake`'s players are two
/// balls that the scripted buttons roll into the sleeping columns, which
/// wake, scatter and fall asleep again. 600 frames at check distance 7;
/// the end state equals a straight run, and the straight run did sleep and
/// wake (counted frame by frame).
#[test]
fn synctest_across_sleep_and_wake_agrees_with_a_straight_run() {
    let name = "sleep_wake";
    let mut game = Game::with_scene(name).expect("sleep_wake is a game");
    run_synctest(&mut game, SYNCTEST_FRAMES, 7, 3)
        .unwrap_or_else(|e| panic!("{name}: not deterministic under rollback: {e}"));
    let mut straight = Game::with_scene(name).expect("sleep_wake is a game");
    let (mut asleep_frames, mut wakes, mut last) = (0u64, 0u64, 0usize);
    for frame in 0..SYNCTEST_FRAMES {
        straight.advance(&[scripted_buttons(0, frame, 3), scripted_buttons(1, frame, 3)]);
        let now = straight.space.sleeping_bodies();
        asleep_frames += u64::from(now > 0);
        wakes += u64::from(now < last);
        last = now;
    }
    assert_eq!(game.space.checksum(), straight.space.checksum());
    assert_eq!(game.space.state(), straight.space.state());
    println!("sleep_wake: {asleep_frames} frames with sleeping bodies, {wakes} wake-ups");
    assert!(
        asleep_frames > 100 && wakes > 0,
        "{asleep_frames} frames asleep, {wakes} wakes"
    );
}

#[test]
fn synctest_catches_a_nondeterministic_game() {
    let mut game = Game::new();
    game.sabotage = true;
    match run_synctest(&mut game, 60, 7, 3) {
        Err(tamias2d_ggrs::Error::Ggrs(GgrsError::MismatchedChecksum { .. })) => {}
        other => panic!("expected a checksum mismatch, got {other:?}"),
    }
}

#[test]
fn p2p_two_peers_over_loopback_agree() {
    let outcome = run_p2p(300, 4, std::time::Duration::from_secs(60)).expect("p2p run");
    assert_eq!(outcome.first_mismatch, None, "{outcome:?}");
    assert_eq!(outcome.checksums[0], outcome.checksums[1]);
    let straight = run_straight(300, 4, P2P_INPUT_DELAY);
    assert_eq!(outcome.checksums[0], straight.space.checksum());
}

/// The soft step under rollback: `name` (`"bowl"`, the default game's
/// pile in a bowl, or a game scene) switched to `Solver::Soft` before its
/// first frame, [`FRAMES`] at check distance 7; the end state equals a
/// straight run on the soft step. One test per scene, so that two run side
/// by side.
fn synctest_on_the_soft_step(name: &str) {
    let frames = FRAMES;
    let soft = |mut game: Game| {
        let settings = tamias2d::space::Settings {
            solver: tamias2d::space::Solver::SOFT,
            ..*game.space.settings()
        };
        game.space.set_settings(settings).expect("valid settings");
        game
    };
    let make = || {
        if name == "bowl" {
            Game::new()
        } else {
            Game::with_scene(name).unwrap_or_else(|| panic!("{name} is a game"))
        }
    };
    let mut game = soft(make());
    run_synctest(&mut game, frames, 7, 3)
        .unwrap_or_else(|e| panic!("{name}: not deterministic under rollback: {e}"));
    assert_eq!(game.frame(), frames, "{name}");
    let straight = run_straight_on(soft(make()), frames, 3, 0);
    assert_eq!(game.space.checksum(), straight.space.checksum(), "{name}");
    assert_eq!(game.space.state(), straight.space.state(), "{name}");
    assert!(game.space.settings().solver.is_soft(), "{name}");
}

#[test]
fn synctest_on_the_soft_step_of_the_bowl_agrees_with_a_straight_run() {
    synctest_on_the_soft_step("bowl");
}

#[test]
fn synctest_on_the_soft_step_of_ragdolls_20_agrees_with_a_straight_run() {
    synctest_on_the_soft_step("ragdolls_20");
}

#[test]
fn synctest_on_the_soft_step_of_sleep_wake_agrees_with_a_straight_run() {
    synctest_on_the_soft_step("sleep_wake");
}

/// The character mover under rollback: two characters on the platformer
/// level of `examples/character.rs` (`tamias2d_scenes::character_level`),
/// driven by pseudo-random sticks and jumps held 10 frames, 600 frames at
/// check distance 7. The game state GGRS saves is the level's frame (the
/// space's frame, both characters and their velocities); the end equals a
/// straight run.
#[test]
fn synctest_of_a_two_character_game_agrees_with_a_straight_run() {
    use tamias2d::{real, Real};
    use tamias2d_scenes::character_level::{Buttons, CharacterGame};
    use tamias2d_scenes::rng::SplitMix64;

    fn mask(player: usize, frame: u64) -> u8 {
        let mut rng = SplitMix64::new(0xC4A2 ^ ((player as u64) << 32) ^ (frame / 10));
        (rng.next_u64() & 0b111) as u8
    }
    fn decode(m: u8) -> Buttons {
        Buttons {
            walk: i8::from(m & 0b10 != 0) - i8::from(m & 0b01 != 0),
            jump: m & 0b100 != 0,
        }
    }
    let xs = [Real::ZERO, real!(-3)];
    let mut game = CharacterGame::with_players(&xs).unwrap();
    let tally =
        tamias2d_ggrs::run_synctest(&mut game, 2, SYNCTEST_FRAMES, 7, |p, f| decode(mask(p, f)))
            .expect("deterministic under rollback");
    let loads = tally.loads;
    assert!(loads >= SYNCTEST_FRAMES - 8, "rolled back every frame");
    let mut straight = CharacterGame::with_players(&xs).unwrap();
    for frame in 0..SYNCTEST_FRAMES {
        straight
            .step(&[decode(mask(0, frame)), decode(mask(1, frame))])
            .unwrap();
    }
    assert_eq!(game.frame, SYNCTEST_FRAMES);
    assert_eq!(game.checksum(), straight.checksum());
    // Both characters moved.
    for (a, b) in game.players.iter().zip(&xs) {
        assert!((a.character.position.x - *b).abs() > real!(1));
    }
}
