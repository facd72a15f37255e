//! A two-player game in a GGRS SyncTest: after every frame GGRS rolls back
//! 7 frames, re-simulates them and compares checksums; the game then ends
//! where a run without GGRS ends.
//!
//! ```text
//! cargo run --release -p tamias2d-ggrs --example two_player_synctest [frames]
//! ```
#[path = "shared/game.rs"]
mod game;

use std::process::ExitCode;

use game::{buttons, Game};
use tamias2d_ggrs::ggrs::InputStatus;
use tamias2d_ggrs::{run_synctest, BoxError, RollbackGame};

/// Frames re-simulated after every frame.
const CHECK_DISTANCE: usize = 7;

fn run(frames: u64) -> Result<bool, BoxError> {
    let mut game = Game::new()?;
    let tally = run_synctest(&mut game, 2, frames, CHECK_DISTANCE, buttons)?;
    println!(
        "sync test: {frames} frames, check distance {CHECK_DISTANCE}: {} frames simulated, {} rollbacks, every checksum agreed",
        tally.advances, tally.loads
    );
    let mut straight = Game::new()?;
    for frame in 0..frames {
        straight.advance(&[0, 1].map(|p| (buttons(p, frame), InputStatus::Confirmed)))?;
    }
    let (a, b) = (game.checksum(), straight.checksum());
    println!("checksum after frame {frames}: rollback {a:#018x}, straight {b:#018x}");
    println!("energy: {:?}", game.energy.0);
    Ok(a == b)
}

fn main() -> ExitCode {
    let frames = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 600,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("frames must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    match run(frames) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("the rolled-back run differs from the straight run");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
