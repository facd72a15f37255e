//! The adapter under GGRS's sessions: a SyncTest agrees with a straight
//! run, two P2P peers agree on every confirmed frame, a game that breaks
//! itself is caught, a state that does not load is an error.
mod common;

use common::{buttons, straight, Game, Sabotage};
use tamias2d::space::SpaceError;
use tamias2d_ggrs::ggrs::{GameStateCell, GgrsError, GgrsRequest, InputStatus};
use tamias2d_ggrs::{
    fulfil, run_loopback, run_synctest, Error, GgrsConfig, Loopback, RollbackGame, SpaceState,
    Tally,
};

#[test]
fn synctest_at_check_distance_7_for_600_frames_agrees_with_a_straight_run() {
    let frames = 600;
    let mut game = Game::new();
    let tally = run_synctest(&mut game, 2, frames, 7, |p, f| buttons(p, f, 4))
        .expect("deterministic under rollback");
    // GGRS rolls back once the current frame exceeds the distance.
    assert_eq!(
        tally.loads,
        frames - 8,
        "a rollback on every frame from the 8th"
    );
    // 7 re-simulated frames per rollback on top of the first run.
    assert_eq!(tally.advances, frames + 7 * tally.loads);
    let (sums, reference) = straight(frames, 4, 0);
    assert_eq!(game.checksum(), sums[frames as usize]);
    assert_eq!(game.space.state(), reference.space.state());
    assert_eq!(game.charges, reference.charges);
    // The players did spend and regain charges: the extra state was live.
    let moved = game.space.body(game.players[0]).unwrap().position();
    assert_ne!(moved, tamias2d::Vect::from_ints(-6, 1));
}

#[test]
fn p2p_loopback_peers_agree_on_every_confirmed_frame() {
    let frames = 240;
    let setup = Loopback::new(frames);
    let mut games = [Game::new(), Game::new()];
    let outcome = run_loopback(&mut games, &setup, |p, f| buttons(p, f, 5)).expect("p2p run");
    assert_eq!(outcome.first_mismatch, None);
    let (sums, _) = straight(frames, 5, setup.options.input_delay as u64);
    for (f, &sum) in sums.iter().enumerate() {
        assert_eq!(outcome.checksums(f as u64), [Some(sum); 2], "frame {f}");
    }
    // Remote inputs arrived late: the peers predicted, and rolled back.
    let [a, b] = &outcome.tallies;
    assert!(a.loads + b.loads > 0, "{a:?} {b:?}");
}

#[test]
fn synctest_catches_state_left_out_of_the_save() {
    let mut game = Game::new();
    game.sabotage = Sabotage::ForgetCharges;
    match run_synctest(&mut game, 2, 120, 7, |p, f| buttons(p, f, 4)) {
        Err(Error::Ggrs(GgrsError::MismatchedChecksum { .. })) => {}
        other => panic!("expected a checksum mismatch, got {other:?}"),
    }
}

#[test]
fn a_state_that_does_not_load_is_an_error() {
    let mut game = Game::new();
    game.sabotage = Sabotage::ForeignFrame;
    match run_synctest(&mut game, 2, 30, 7, |p, f| buttons(p, f, 4)) {
        Err(Error::Load { frame, source }) => {
            assert!(frame >= 0);
            let e = source
                .downcast_ref::<SpaceError>()
                .expect("the engine's error");
            assert!(matches!(e, SpaceError::LevelMismatch { .. }), "{e:?}");
        }
        other => panic!("expected a load error, got {other:?}"),
    }
}

/// Requests GGRS would never send, served by hand: each is an error, and
/// the game is untouched.
#[test]
fn malformed_requests_are_errors_not_panics() {
    type Requests = Vec<GgrsRequest<GgrsConfig<Game>>>;
    let mut game = Game::new();
    game.step([common::RIGHT, 0]);
    let before = game.checksum();
    let mut tally = Tally::default();

    let empty: Requests = vec![GgrsRequest::LoadGameState {
        cell: GameStateCell::default(),
        frame: 3,
    }];
    assert!(matches!(
        fulfil(&mut game, empty, &mut tally),
        Err(Error::NothingSaved(3))
    ));

    let no_frame: Requests = vec![GgrsRequest::SaveGameState {
        cell: GameStateCell::default(),
        frame: -1,
    }];
    assert!(matches!(
        fulfil(&mut game, no_frame, &mut tally),
        Err(Error::InvalidFrame(-1))
    ));

    // A frame of another level (one more static body).
    let cell = GameStateCell::default();
    let mut other = Game::new();
    other
        .space
        .add_body(tamias2d::body::Body::new_static())
        .unwrap();
    let mut foreign = SpaceState::default();
    foreign.save(&other.space, &other.charges);
    cell.save(0, Some(foreign), None);
    let load: Requests = vec![GgrsRequest::LoadGameState { cell, frame: 0 }];
    assert!(matches!(
        fulfil(&mut game, load, &mut tally),
        Err(Error::Load { frame: 0, .. })
    ));

    // Inputs for a player the game does not have: its advance fails.
    let mut lonely = Game::new();
    lonely.players = [lonely.players[0]; 2];
    lonely.space.remove_body(lonely.players[0]).unwrap();
    let advance: Requests = vec![GgrsRequest::AdvanceFrame {
        inputs: vec![(0, InputStatus::Confirmed); 2],
    }];
    assert!(matches!(
        fulfil(&mut lonely, advance, &mut tally),
        Err(Error::Advance { frame: None, .. })
    ));

    assert_eq!(game.checksum(), before, "the game is untouched");
    assert_eq!(tally, Tally::default(), "nothing was served");
}

/// A save into a cell that already holds an older frame overwrites it,
/// and the checksum GGRS keeps is the game's, widened.
#[test]
fn saves_reuse_the_cell_and_carry_the_checksum() {
    let mut game = Game::new();
    let mut tally = Tally::recording();
    let cell = GameStateCell::default();
    let save = |frame| -> Vec<GgrsRequest<GgrsConfig<Game>>> {
        vec![GgrsRequest::SaveGameState {
            cell: cell.clone(),
            frame,
        }]
    };
    fulfil(&mut game, save(0), &mut tally).unwrap();
    let first = game.checksum();
    for _ in 0..5 {
        game.step([common::JUMP, common::LEFT]);
    }
    fulfil(&mut game, save(5), &mut tally).unwrap();
    assert_ne!(game.checksum(), first);
    let saved = cell.load().expect("a state");
    let mut restored = Game::new();
    restored.load(&saved).unwrap();
    assert_eq!(restored.checksum(), game.checksum());
    assert_eq!(tally.checksum(0), Some(first));
    assert_eq!(tally.checksum(5), Some(game.checksum()));
    assert_eq!(tally.checksum(3), None, "frames never saved");
    assert_eq!(tally.saves, 2);
    // A rollback to frame 0 and a new save forgets the later frames.
    fulfil(&mut game, save(0), &mut tally).unwrap();
    assert_eq!(tally.checksum(5), None);
}
