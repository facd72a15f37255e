//! Records a run of `bowl_boxes_100` with a kick now and then, writes it
//! to a file, reads it back and verifies it frame by frame; then tampers
//! with one input and shows the divergence report (frame and first body).
//!
//! ```text
//! cargo run --release --example replay [path]
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use std::process::ExitCode;
use std::time::Instant;

use tamias2d::replay::{Input, Recorder, Replay, ReplayError, Start};
use tamias2d::Vect;

/// Frames recorded.
const FRAMES: u32 = 300;
/// Body digests every this many frames (names the diverging body).
const DIGEST_EVERY: u32 = 1;

fn record() -> Result<Replay, ReplayError> {
    let start = Start::builtin("bowl_boxes_100")
        .ok_or(ReplayError::UnknownScene("bowl_boxes_100".into()))?;
    let mut rec = Recorder::new(start)?.with_body_digests(DIGEST_EVERY);
    let boxes: Vec<_> = rec.space().bodies().skip(1).map(|(h, _)| h).collect();
    for frame in 0..FRAMES {
        let mut inputs = Vec::new();
        if frame % 20 == 10 {
            // Kick one box upwards, off its centre so that it spins.
            let i = (frame / 20) as usize % boxes.len().max(1);
            if let Some(&h) = boxes.get(i) {
                let at = rec.space().body(h).map(|b| b.center()).unwrap_or_default();
                inputs.push(Input::Impulse {
                    body: h,
                    impulse: Vect::from_ints(0, 150),
                    point: at + Vect::from_ints(2, 0),
                });
            }
        }
        rec.record_frame(&inputs)?;
    }
    Ok(rec.finish())
}

fn run() -> Result<(), String> {
    let path = std::env::args()
        .nth(1)
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("tamias2d-example.replay"));
    let t = Instant::now();
    let replay = record().map_err(|e| e.to_string())?;
    println!(
        "recorded {FRAMES} frames in {:.2} s",
        t.elapsed().as_secs_f64()
    );
    replay.write_file(&path).map_err(|e| e.to_string())?;
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    println!("wrote {} ({size} bytes)", path.display());

    let back = Replay::read_file(&path).map_err(|e| e.to_string())?;
    let t = Instant::now();
    let report = back
        .verify()
        .map_err(|e| format!("verification failed: {e}"))?;
    println!(
        "verified {} frames in {:.2} s, final checksum {:#018x}",
        report.frames,
        t.elapsed().as_secs_f64(),
        report.final_checksum
    );

    // Tamper: strengthen the first kick by one unit of the last place.
    let mut tampered = back;
    let kicked = tampered
        .frames
        .iter_mut()
        .enumerate()
        .find_map(|(f, frame)| frame.inputs.first_mut().map(|i| (f, i)));
    let Some((frame, Input::Impulse { body, impulse, .. })) = kicked else {
        return Err("no kick recorded".into());
    };
    impulse.y += tamias2d::Real::DELTA;
    println!("tampered: frame {frame}, impulse on body {body:?} changed by 2^-32");
    match tampered.verify() {
        Err(e @ ReplayError::Diverged { .. }) => {
            println!("verification of the tampered replay: {e}");
            Ok(())
        }
        other => Err(format!("tampering went unnoticed: {other:?}")),
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
