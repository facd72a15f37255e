//! The commands that write or read files: `scene dump`, `snapshot save`,
//! `replay record` and `replay verify`.
use std::path::Path;

use tamias2d::replay::{Recorder, Replay, ReplayError, Start};
use tamias2d::snapshot;

use crate::progress::Progress;
use crate::source::{self, Overrides, Sim};

/// `tamias scene dump`: the scene as pretty JSON, to `output` or stdout.
pub fn scene_dump(scene: &str, output: Option<&Path>) -> Result<(), String> {
    let desc = source::load(scene, Overrides::default())?.desc;
    let json = serde_json::to_string_pretty(&desc).map_err(|e| e.to_string())? + "\n";
    match output {
        Some(path) => {
            std::fs::write(path, json).map_err(|e| format!("{}: {e}", path.display()))?;
            println!(
                "wrote {} ({} bodies, {} shapes)",
                path.display(),
                desc.total_bodies(),
                desc.total_shapes()
            );
        }
        None => print!("{json}"),
    }
    Ok(())
}

/// `tamias snapshot save`: `steps` steps of the scene, then the world's
/// bytes in `output`.
pub fn snapshot_save(
    scene: &str,
    steps: u32,
    output: &Path,
    overrides: Overrides,
) -> Result<(), String> {
    let desc = source::load(scene, overrides)?.desc;
    if !desc.forces.is_empty() || !desc.spawns.is_empty() {
        // A snapshot is the world (DESIGN §4.3); the scene's script lives in
        // its description, so a loaded snapshot runs without it. (Begin
        // counters only count and accept, so losing them changes nothing.)
        eprintln!(
            "warning: scene {:?} scripts forces or spawns; a snapshot holds only the world, so \
             `snapshot run` continues without them and its checksum will not match an \
             uninterrupted `run`",
            desc.name
        );
    }
    let mut sim = Sim::build(&desc)?;
    let mut bar = Progress::new(&format!("scene {}", desc.name), u64::from(steps));
    for step in 1..=steps {
        sim.step().map_err(|e| format!("step {step}: {e}"))?;
        bar.inc(1);
    }
    bar.finish();
    let bytes = snapshot::save(sim.space());
    std::fs::write(output, &bytes).map_err(|e| format!("{}: {e}", output.display()))?;
    println!(
        "wrote {} ({} bytes): {} after {steps} steps",
        output.display(),
        bytes.len(),
        desc.name
    );
    println!("checksum: {:#018x}", sim.space().checksum());
    Ok(())
}

/// `tamias replay record`: `steps` frames without inputs, each frame's
/// checksum, and body digests every `digests_every` frames.
pub fn replay_record(
    scene: &str,
    steps: u32,
    output: &Path,
    digests_every: u32,
    overrides: Overrides,
) -> Result<(), String> {
    let loaded = source::load(scene, overrides)?;
    let name = loaded.desc.name.clone();
    // A built-in scene is recorded by name (small files); anything else as
    // its whole description.
    let start = match loaded.builtin {
        Some(builtin) => Start::Builtin {
            name: builtin,
            dt: loaded.desc.dt,
        },
        None => Start::Scene(Box::new(loaded.desc)),
    };
    let mut rec = Recorder::new(start).map_err(|e| e.to_string())?;
    if digests_every > 0 {
        rec = rec.with_body_digests(digests_every);
    }
    let mut bar = Progress::new(&format!("recording {name}"), u64::from(steps));
    let mut last = rec.space().checksum();
    for _ in 0..steps {
        last = rec.record_frame(&[]).map_err(|e| e.to_string())?;
        bar.inc(1);
    }
    bar.finish();
    let replay = rec.finish();
    replay
        .write_file(output)
        .map_err(|e| format!("{}: {e}", output.display()))?;
    let size = std::fs::metadata(output).map(|m| m.len()).unwrap_or(0);
    println!(
        "recorded {steps} frames of {name} to {} ({size} bytes)",
        output.display()
    );
    println!("checksum: {last:#018x}");
    Ok(())
}

/// `tamias replay verify`: re-runs the replay; `replay ok (N frames)`, or an
/// error naming the first diverging frame and body.
pub fn replay_verify(file: &Path) -> Result<(), String> {
    let replay = Replay::read_file(file).map_err(|e| match e {
        // The library's I/O message already says "replay file: …".
        ReplayError::Io(io) => format!("{}: {io}", file.display()),
        e => format!("{}: {e}", file.display()),
    })?;
    let report = replay
        .verify()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    println!("replay ok ({} frames)", report.frames);
    println!("checksum: {:#018x}", report.final_checksum);
    Ok(())
}
