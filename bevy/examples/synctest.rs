//! A headless bevy_ggrs SyncTest of a small physics game: every frame, the
//! session rolls back `CHECK_DISTANCE` frames, re-simulates them and
//! compares checksums. Then the same inputs run straight, without a
//! rollback, and the two worlds must be the same bits.
//!
//! `cargo run -p tamias2d-bevy --example synctest` prints
//! `synctest: 600 frames, check distance 7, 0 mismatches`; `cargo test`
//! runs the same checks (this example is a test target too). With
//! `-- --pile N`, N boxes start piled on the floor: a heavier world, to
//! time the rolled-back run (`--release`).
mod common;

use bevy::prelude::*;
use common::{game_app, run_frames, Config, Counters, Pile, Sabotage, Score};
use tamias2d_bevy::bevy_ggrs::prelude::*;
use tamias2d_bevy::prelude::*;

const FRAMES: i32 = 600;
const CHECK_DISTANCE: usize = 7;

/// Mismatches the session reported (not rolled back).
#[derive(Resource, Default)]
struct Mismatches(u32);

/// The game under a two-player SyncTest session at `check_distance` (0:
/// no rollback, the straight run).
fn synctest_app(check_distance: usize) -> App {
    let session = SessionBuilder::<Config>::new()
        .with_num_players(2)
        .and_then(|b| {
            b.with_check_distance(check_distance)
                .add_player(PlayerType::Local, 0)
        })
        .and_then(|b| b.add_player(PlayerType::Local, 1))
        .and_then(|b| b.start_synctest_session())
        .expect("a valid session");
    let mut app = game_app(Session::SyncTest(session), vec![0, 1]);
    app.init_resource::<Mismatches>();
    app.world_mut()
        .add_observer(|_: On<SyncTestMismatch>, mut m: ResMut<Mismatches>| m.0 += 1);
    app
}

/// What a run ends with: the physics checksum, the score, and the run's
/// counters.
struct Outcome {
    checksum: u64,
    score: u32,
    bodies: usize,
    mismatches: u32,
    loads: u64,
    /// Wall time of the run.
    seconds: f64,
    /// What the plugin reported it could not do (none expected).
    errors: Vec<(Entity, String)>,
    /// Every live body entity maps to its body and back, and the map has
    /// no other entry: the entity map followed the respawned entities.
    map_consistent: bool,
}

fn run(check_distance: usize, sabotage: bool, pile: i32) -> Outcome {
    let mut app = synctest_app(check_distance);
    app.world_mut().resource_mut::<Sabotage>().on = sabotage;
    app.insert_resource(Pile(pile));
    let start = std::time::Instant::now();
    run_frames(&mut app, FRAMES);
    let seconds = start.elapsed().as_secs_f64();
    let mut live = app.world_mut().query::<(Entity, &RigidBody)>();
    let live: Vec<(Entity, Option<_>)> = live
        .iter(app.world())
        .map(|(e, rb)| (e, rb.handle()))
        .collect();
    let world = app.world();
    let physics = world.resource::<Physics>();
    let map_consistent = live.len() == physics.entities().count()
        && live.iter().all(|&(e, h)| {
            h.is_some()
                && physics.body_of(e) == h
                && h.and_then(|h| physics.entity_of(h)) == Some(e)
        });
    Outcome {
        checksum: physics.checksum(),
        score: world.resource::<Score>().0,
        bodies: physics.space().bodies().count(),
        mismatches: world.resource::<Mismatches>().0,
        loads: world.resource::<Counters>().loads,
        seconds,
        errors: world.resource::<PhysicsErrors>().errors.clone(),
        map_consistent,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let pile = match args.iter().position(|a| a == "--pile") {
        None => 0,
        Some(i) => match args.get(i + 1).map(|n| n.parse::<i32>()) {
            Some(Ok(n)) if (0..=2000).contains(&n) => n,
            _ => {
                eprintln!("--pile takes a number of boxes, 0 to 2000");
                std::process::exit(2);
            }
        },
    };
    let rolled = run(CHECK_DISTANCE, false, pile);
    let straight = run(0, false, pile);
    println!(
        "synctest: {FRAMES} frames, check distance {CHECK_DISTANCE}, {} mismatches",
        rolled.mismatches
    );
    println!(
        "  {} rollbacks; {} bodies, score {}; checksum {:#018x} rolled back, {:#018x} straight",
        rolled.loads, rolled.bodies, rolled.score, rolled.checksum, straight.checksum
    );
    let same = rolled.checksum == straight.checksum && rolled.score == straight.score;
    println!("  the same world as a straight run: {same}");
    if pile > 0 {
        println!(
            "  {pile} boxes piled: {:.2} s rolled back, {:.2} s straight",
            rolled.seconds, straight.seconds
        );
    }
    println!(
        "  entity map consistent after rollbacks: {}",
        rolled.map_consistent
    );
    for (entity, error) in rolled.errors.iter().chain(&straight.errors) {
        println!("  plugin error ({entity}): {error}");
    }
    let clean = rolled.errors.is_empty() && straight.errors.is_empty();
    if rolled.mismatches != 0 || !same || !rolled.map_consistent || !clean {
        std::process::exit(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synctest_at_check_distance_7_has_no_mismatch_and_ends_as_a_straight_run() {
        let rolled = run(CHECK_DISTANCE, false, 0);
        let straight = run(0, false, 0);
        assert_eq!(rolled.mismatches, 0);
        assert!(
            rolled.loads >= (FRAMES as u64) - 8,
            "rolled back every frame: {}",
            rolled.loads
        );
        assert_eq!(straight.loads, 0, "the straight run never rolls back");
        assert_eq!(rolled.checksum, straight.checksum);
        assert_eq!(rolled.score, straight.score);
        assert!(
            rolled.map_consistent,
            "the entity map lost track after rollbacks"
        );
        // The game did what it is for: crates came and went, players hit them.
        assert!(rolled.score > 0, "no player touched a crate");
        assert!(
            rolled.bodies > 5 && rolled.bodies < 5 + 24,
            "{} bodies",
            rolled.bodies
        );
    }

    #[test]
    fn a_desync_is_caught() {
        let sabotaged = run(CHECK_DISTANCE, true, 0);
        assert!(sabotaged.mismatches > 0, "the sabotage went unnoticed");
    }
}
