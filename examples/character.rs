//! The character mover on a platformer level: a capsule walks, jumps
//! through a one-way platform and lands on it, pushes two crates, climbs a
//! 30° slope and a step, is stopped by a 60° slope, rides an elevator and
//! a see-saw. 1,800 scripted frames (30 s at 60 Hz); then the same run
//! again, restored from a frame saved at frame 900, must end with the same
//! checksum.
//!
//! ```text
//! cargo run --release --example character
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use std::process::ExitCode;
use std::time::Instant;

use tamias2d_scenes::character_level::{script, CharacterGame, RunStats, FRAMES, STATES};

fn main() -> Result<ExitCode, Box<dyn std::error::Error>> {
    let mut game = CharacterGame::new()?;
    let mut stats = RunStats::default();
    let mut saved = None;
    let start = Instant::now();
    for f in 0..FRAMES {
        if f == FRAMES / 2 {
            saved = Some(game.save());
        }
        game.step(&[script(f)])?;
        stats.observe(&game);
    }
    let per_frame_us = start.elapsed().as_secs_f64() * 1e6 / FRAMES as f64;
    println!(
        "character: frames {}, fell through {}, stuck {}, max ground gap {:.4}",
        stats.frames,
        stats.fell_through,
        stats.stuck,
        stats.max_ground_gap.to_f64()
    );
    for (k, name) in STATES.iter().enumerate() {
        println!(
            "  {name:<20} {:>5} frames, entered {:>3} times",
            stats.seen[k], stats.entered[k]
        );
    }
    println!("time: {per_frame_us:.1} us per frame (the world's step and the move, this build)");
    let straight = game.checksum();
    let mut again = CharacterGame::new()?;
    again.restore(saved.as_ref().ok_or("frame 900 saved")?)?;
    for f in FRAMES / 2..FRAMES {
        again.step(&[script(f)])?;
    }
    let restored = again.checksum();
    println!("checksum: {straight:#018x} straight, {restored:#018x} restored from frame 900");
    let ok = straight == restored && stats.fell_through == 0 && stats.stuck == 0;
    Ok(if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
