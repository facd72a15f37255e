//! A minimal rollback loop without any networking library: player 0's
//! inputs are local, player 1's arrive `LATENCY` frames late. Each frame the
//! game saves its state, predicts the remote input (repeat the last one
//! received) and steps; when a late input shows a wrong prediction, it
//! restores the state of that frame and re-simulates up to the present.
//! The result must equal a straight run with all inputs known in time.
//!
//! Four ways to save and restore are compared: the frame (everything but
//! the static level, which is named by its digest) in memory
//! (`save_frame` / `restore_frame`) and as bytes
//! (`snapshot::save_frame_into` / `Space::load_frame_snapshot`, which
//! validates what it loads), and the whole world in memory (a clone of the
//! `WorldState`, `restore_state`) and as bytes (`snapshot::save_into` /
//! `Space::load_snapshot`).
//!
//! ```text
//! cargo run --release --example rollback
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use tamias2d_scenes::ggrs_game;

use std::process::ExitCode;
use std::time::{Duration, Instant};

use ggrs_game::{run_straight, scripted_buttons, Game};
use tamias2d::snapshot;
use tamias2d::space::{FrameState, WorldState};

/// Frames simulated.
const FRAMES: u64 = 600;
/// Frames a remote input takes to arrive.
const LATENCY: u64 = 5;
/// Frames each scripted button mask is held.
const HOLD: u64 = 6;
/// Saved frames kept: the oldest one a late input can need, and the present.
const RING: usize = LATENCY as usize + 1;

/// How frames are saved.
enum Saves {
    /// `space.save_frame` per frame (buffers reused).
    Frames(Vec<FrameState>),
    /// Frame snapshot bytes per frame (buffers reused).
    FrameBytes(Vec<Vec<u8>>),
    /// `space.state().clone()` per frame.
    Memory(Vec<WorldState>),
    /// Snapshot bytes per frame (buffers reused).
    Bytes(Vec<Vec<u8>>),
}

impl Saves {
    fn save(&mut self, game: &Game, frame: u64) {
        let slot = (frame % RING as u64) as usize;
        match self {
            Saves::Frames(frames) => game.space.save_frame(&mut frames[slot]),
            Saves::FrameBytes(buffers) => {
                snapshot::save_frame_into(&game.space, &mut buffers[slot]);
            }
            Saves::Memory(states) => states[slot].clone_from(game.space.state()),
            Saves::Bytes(buffers) => {
                snapshot::save_into(&game.space, &mut buffers[slot]);
            }
        }
    }

    fn load(&self, game: &mut Game, frame: u64) {
        let slot = (frame % RING as u64) as usize;
        match self {
            Saves::Frames(frames) => game
                .space
                .restore_frame(&frames[slot])
                .expect("a frame of this level"),
            Saves::FrameBytes(buffers) => game
                .space
                .load_frame_snapshot(&buffers[slot])
                .expect("our own frame"),
            Saves::Memory(states) => game.space.restore_state(&states[slot]),
            Saves::Bytes(buffers) => game
                .space
                .load_snapshot(&buffers[slot])
                .expect("our own snapshot"),
        }
        assert_eq!(game.frame(), frame, "restored the saved frame");
    }
}

/// Counters of one run.
struct Stats {
    rollbacks: u32,
    resimulated: u64,
    in_rollbacks: Duration,
    total: Duration,
}

/// Runs the game with late remote inputs and rollbacks; returns the final
/// checksum and counters.
fn run(mut saves: Saves) -> (u64, Stats) {
    let mut game = Game::new();
    let local = |frame: u64| scripted_buttons(0, frame, HOLD);
    let remote_truth = |frame: u64| scripted_buttons(1, frame, HOLD);
    // Remote inputs used per frame (received or predicted), and received.
    let mut used: Vec<u8> = Vec::new();
    let mut received: Vec<u8> = Vec::new();
    let mut stats = Stats {
        rollbacks: 0,
        resimulated: 0,
        in_rollbacks: Duration::ZERO,
        total: Duration::ZERO,
    };
    let start = Instant::now();
    // `FRAMES + LATENCY` turns: the last ones only deliver late inputs.
    for now in 0..FRAMES + LATENCY {
        if let Some(late) = now.checked_sub(LATENCY) {
            // The remote input of frame `late` arrives.
            received.push(remote_truth(late));
            if used.get(late as usize) != received.last() {
                let t = Instant::now();
                saves.load(&mut game, late);
                for f in late..game_end(now) {
                    let remote = predict(&received, f);
                    used[f as usize] = remote;
                    saves.save(&game, f);
                    game.advance(&[local(f), remote]);
                }
                stats.rollbacks += 1;
                stats.resimulated += game_end(now) - late;
                stats.in_rollbacks += t.elapsed();
            }
        }
        if now < FRAMES {
            let remote = predict(&received, now);
            used.push(remote);
            saves.save(&game, now);
            game.advance(&[local(now), remote]);
        }
    }
    stats.total = start.elapsed();
    assert_eq!(game.frame(), FRAMES);
    (game.space.checksum(), stats)
}

/// Frames simulated before turn `now` (the game runs one frame per turn
/// until `FRAMES`).
fn game_end(now: u64) -> u64 {
    now.min(FRAMES)
}

/// The remote input for frame `f`: received, or else the last one received
/// (repeat-last prediction), or none.
fn predict(received: &[u8], f: u64) -> u8 {
    received
        .get(f as usize)
        .or(received.last())
        .copied()
        .unwrap_or(0)
}

fn main() -> ExitCode {
    let straight = run_straight(FRAMES, HOLD, 0).space.checksum();
    println!("straight run: {FRAMES} frames, checksum {straight:#018x}");
    let mut ok = true;
    let runs = [
        (
            "in-memory frames",
            Saves::Frames(vec![FrameState::default(); RING]),
        ),
        (
            "frame snapshot bytes",
            Saves::FrameBytes(vec![Vec::new(); RING]),
        ),
        (
            "in-memory state clones",
            Saves::Memory(vec![WorldState::default(); RING]),
        ),
        ("snapshot bytes", Saves::Bytes(vec![Vec::new(); RING])),
    ];
    for (name, saves) in runs {
        let (checksum, s) = run(saves);
        let per_frame = s.in_rollbacks.as_secs_f64() * 1e3 / s.resimulated.max(1) as f64;
        println!(
            "{name}: checksum {checksum:#018x}; {} rollbacks re-simulated {} frames \
             ({per_frame:.3} ms per re-simulated frame incl. restore); total {:.2} s",
            s.rollbacks,
            s.resimulated,
            s.total.as_secs_f64(),
        );
        ok &= checksum == straight;
    }
    if ok {
        println!("rollback runs equal the straight run");
        ExitCode::SUCCESS
    } else {
        eprintln!("a rollback run differs from the straight run");
        ExitCode::FAILURE
    }
}
