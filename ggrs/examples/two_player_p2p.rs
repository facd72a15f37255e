//! The same two-player game between two GGRS P2P peers in one process,
//! talking UDP over 127.0.0.1: remote inputs arrive late, each peer
//! predicts, rolls back and re-simulates, and both must save the same
//! checksum for every confirmed frame.
//!
//! ```text
//! cargo run --release -p tamias2d-ggrs --example two_player_p2p [frames]
//! ```
#[path = "shared/game.rs"]
mod game;

use std::process::ExitCode;

use game::{buttons, Game};
use tamias2d_ggrs::{run_loopback, BoxError, Loopback};

fn run(frames: u64) -> Result<bool, BoxError> {
    let mut games = [Game::new()?, Game::new()?];
    let outcome = run_loopback(&mut games, &Loopback::new(frames), buttons)?;
    for (peer, tally) in outcome.tallies.iter().enumerate() {
        println!(
            "peer {peer}: checksum at frame {frames} {:#018x}; {} frames simulated, {} rollbacks",
            tally.checksum(frames).unwrap_or(0),
            tally.advances,
            tally.loads
        );
    }
    match outcome.first_mismatch {
        None => println!("the peers agree on every frame 0..={frames}"),
        Some(f) => eprintln!("the peers differ from frame {f} on"),
    }
    Ok(outcome.first_mismatch.is_none())
}

fn main() -> ExitCode {
    let frames = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 300,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("frames must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    match run(frames) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
