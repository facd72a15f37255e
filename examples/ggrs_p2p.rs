//! Two GGRS `P2PSession` peers in one process, talking UDP over
//! 127.0.0.1, each controlling one ball of the same physics game. Remote
//! inputs arrive late, so each peer predicts, rolls back and re-simulates;
//! at the end both must have saved the same checksum for every frame.
//! Exits non-zero if they differ (or on a desync event or a timeout).
//!
//! ```text
//! cargo run --release --example ggrs_p2p [frames]
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use tamias2d_scenes::ggrs_game;

use std::process::ExitCode;
use std::time::{Duration, Instant};

use ggrs_game::run_p2p;

/// Frames each scripted button mask is held (mispredicted on each change).
const HOLD: u64 = 4;

fn main() -> ExitCode {
    let frames: u64 = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 300,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("frames must be a whole number: {e}");
            return ExitCode::FAILURE;
        }
    };
    let t = Instant::now();
    let outcome = match run_p2p(frames, HOLD, Duration::from_secs(120)) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("p2p run failed: {e}");
            return ExitCode::FAILURE;
        }
    };
    for peer in 0..2 {
        println!(
            "peer {peer}: checksum at frame {frames} = {:#018x}; {} frames simulated, {} rollbacks",
            outcome.checksums[peer], outcome.advances[peer], outcome.loads[peer]
        );
    }
    println!("{:.2} s", t.elapsed().as_secs_f64());
    match outcome.first_mismatch {
        None if outcome.checksums[0] == outcome.checksums[1] => {
            println!("peers agree on every frame 0..={frames}");
            ExitCode::SUCCESS
        }
        mismatch => {
            eprintln!("peers differ (first differing frame: {mismatch:?})");
            ExitCode::FAILURE
        }
    }
}
