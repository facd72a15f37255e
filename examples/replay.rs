//! Records a run of `bowl_boxes_100` that the example drives itself (its
//! own step function: inputs, then the step), with a kick now and then;
//! writes it to a file, reads it back and verifies it frame by frame by
//! re-running that step function; then tampers with one input and shows
//! the report (the input log names the frame; with the log re-digested,
//! the checksums name the frame and the first body).
//!
//! ```text
//! cargo run --release --example replay [path]
//! ```
#![allow(clippy::float_arithmetic)] // timing report only

use std::process::ExitCode;
use std::time::Instant;

use tamias2d::replay::{apply_inputs, Input, Recorder, Replay, ReplayError};
use tamias2d::space::{Space, SpaceError};
use tamias2d::{Real, Vect};

/// Frames recorded.
const FRAMES: u32 = 300;
/// Body digests every this many frames (names the diverging body).
const DIGEST_EVERY: u32 = 1;

/// The time step.
fn dt() -> Real {
    Real::ratio(1, 60)
}

/// The game's world: the standard scene's space (it has no script).
fn world() -> Result<Space, String> {
    let desc = tamias2d_scenes::builtin("bowl_boxes_100").ok_or("no bowl_boxes_100")?;
    Ok(desc.build().map_err(|e| e.to_string())?.space)
}

/// The game's step function: its inputs, then one step.
fn step(space: &mut Space, inputs: &[Input]) -> Result<(), SpaceError> {
    apply_inputs(space, inputs)?;
    space.step(dt())
}

fn record() -> Result<Replay, String> {
    let mut space = world()?;
    let mut rec = Recorder::new(&space, dt()).with_body_digests(DIGEST_EVERY);
    let boxes: Vec<_> = space.bodies().skip(1).map(|(h, _)| h).collect();
    for frame in 0..FRAMES {
        let mut inputs = Vec::new();
        if frame % 20 == 10 {
            // Kick one box upwards, off its centre so that it spins.
            let i = (frame / 20) as usize % boxes.len().max(1);
            if let Some(&h) = boxes.get(i) {
                let at = space.body(h).map(|b| b.center()).unwrap_or_default();
                inputs.push(Input::Impulse {
                    body: h,
                    impulse: Vect::from_ints(0, 150),
                    point: at + Vect::from_ints(2, 0),
                });
            }
        }
        step(&mut space, &inputs).map_err(|e| e.to_string())?;
        rec.record_frame(&space, &inputs)
            .map_err(|e| e.to_string())?;
    }
    Ok(rec.finish())
}

fn run() -> Result<(), String> {
    let path = std::env::args()
        .nth(1)
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("tamias2d-example.replay"));
    let t = Instant::now();
    let replay = record()?;
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
        .verify_with(&mut world()?, step)
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
    impulse.y += Real::DELTA;
    println!("tampered: frame {frame}, impulse on body {body:?} changed by 2^-32");
    match tampered.verify_with(&mut world()?, step) {
        Err(e @ ReplayError::InputMismatch { .. }) => {
            println!("verification of the tampered replay: {e}");
        }
        other => return Err(format!("tampering went unnoticed: {other:?}")),
    }
    // A game that really sent that input: the log digests are recomputed
    // (re-recorded), and the checksums catch the changed world.
    let empty = Space::new();
    let mut rerecorded = Recorder::new(&empty, dt());
    for f in &tampered.frames {
        rerecorded
            .record_frame(&empty, &f.inputs)
            .map_err(|e| e.to_string())?;
    }
    let digests = rerecorded.finish();
    for (f, d) in tampered.frames.iter_mut().zip(&digests.frames) {
        f.input_digest = d.input_digest;
    }
    tampered.input_digest = digests.input_digest;
    match tampered.verify_with(&mut world()?, step) {
        Err(e @ ReplayError::Diverged { .. }) => {
            println!("with the input log re-digested: {e}");
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
