//! GGRS `SyncTestSession` on a two-player physics game: every frame is
//! simulated, then the last 7 frames are rolled back (restore of the saved
//! `FrameState`: the world minus its static level) and re-simulated, and GGRS compares the checksums of both
//! runs. Any difference is an error; the example also checks the final
//! state against a straight run without GGRS.
//!
//! ```text
//! cargo run --release --example ggrs_synctest [frames]
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use tamias2d_scenes::ggrs_game;

use std::process::ExitCode;
use std::time::Instant;

use ggrs_game::{run_straight, run_synctest, Game};

/// Frames re-simulated on every frame.
const CHECK_DISTANCE: usize = 7;
/// Frames each scripted button mask is held.
const HOLD: u64 = 3;

fn main() -> ExitCode {
    let frames: u64 = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 600,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("frames must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut game = Game::new();
    let t = Instant::now();
    if let Err(e) = run_synctest(&mut game, frames, CHECK_DISTANCE, HOLD) {
        eprintln!("sync test failed at frame {}: {e}", game.frame());
        return ExitCode::FAILURE;
    }
    let elapsed = t.elapsed();
    println!(
        "sync test: {frames} frames, check distance {CHECK_DISTANCE}: {} steps, {} rollbacks in {:.2} s ({:.3} ms per step incl. save/load)",
        game.advances,
        game.loads,
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * 1e3 / game.advances.max(1) as f64,
    );
    let straight = run_straight(frames, HOLD, 0);
    let (a, b) = (game.space.checksum(), straight.space.checksum());
    println!("checksum after frame {frames}: rollback {a:#018x}, straight {b:#018x}");
    if a == b {
        ExitCode::SUCCESS
    } else {
        eprintln!("the rolled-back run differs from the straight run");
        ExitCode::FAILURE
    }
}
