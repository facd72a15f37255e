//! The commands that write or read files: `scene dump`, `snapshot save`,
//! `replay record` and `replay verify`.
use std::path::Path;

use tamias2d::limits::Limits;
use tamias2d::replay::{Recorder, Replay, ReplayError};
use tamias2d::snapshot;
use tamias2d::Real;
use tamias2d_scenes::ScriptedWorld;

use crate::progress::Progress;
use crate::source::{self, Overrides};

/// `tamias scene dump`: the scene as pretty JSON, to `output` or stdout.
pub fn scene_dump(scene: &str, output: Option<&Path>) -> Result<(), String> {
    let desc = source::load(scene, Overrides::default())?;
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
/// bytes with its script (scripted forces, spawns and counters: a
/// [`ScriptedWorld`] save) in `output`, so that `snapshot run` continues
/// exactly as an uninterrupted run.
pub fn snapshot_save(
    scene: &str,
    steps: u32,
    output: &Path,
    overrides: Overrides,
) -> Result<(), String> {
    let desc = source::load(scene, overrides)?;
    let mut sim = source::build(&desc)?;
    let mut bar = Progress::new(&format!("scene {}", desc.name), u64::from(steps));
    for step in 1..=steps {
        sim.step().map_err(|e| format!("step {step}: {e}"))?;
        bar.inc(1);
    }
    bar.finish();
    let bytes = sim.save();
    std::fs::write(output, &bytes).map_err(|e| format!("{}: {e}", output.display()))?;
    println!(
        "wrote {} ({} bytes): {} after {steps} steps",
        output.display(),
        bytes.len(),
        desc.name
    );
    println!("checksum: {:#018x}", sim.space.checksum());
    Ok(())
}

/// The world saved in `bytes`: a scripted world ([`ScriptedWorld::save`]),
/// or a bare engine snapshot (`tamias2d::snapshot`), which loads with an
/// empty script and steps by `dt` (its last step's, unless given).
pub fn load_world(
    bytes: &[u8],
    dt: Option<Real>,
    limits: &Limits,
) -> Result<ScriptedWorld, String> {
    if ScriptedWorld::is_saved(bytes) {
        let mut world = ScriptedWorld::load_with(bytes, limits).map_err(|e| e.to_string())?;
        if let Some(dt) = dt {
            world.dt = dt;
        }
        return Ok(world);
    }
    let space = snapshot::load_with(bytes, limits).map_err(|e| e.to_string())?;
    let dt = match dt {
        Some(dt) => dt,
        None if space.current_time_step().is_positive() => space.current_time_step(),
        None => {
            return Err(
                "saved before the first step, so it holds no time step; pass --dt".to_owned(),
            )
        }
    };
    Ok(ScriptedWorld::unscripted(space, dt))
}

/// `tamias replay record`: `steps` frames without inputs of the scene's
/// scripted world (its start and script saved in the replay), each frame's
/// checksum, and body digests every `digests_every` frames.
pub fn replay_record(
    scene: &str,
    steps: u32,
    output: &Path,
    digests_every: u32,
    overrides: Overrides,
) -> Result<(), String> {
    let desc = source::load(scene, overrides)?;
    let mut world = source::build(&desc)?;
    let mut rec = Recorder::new(&world, world.dt);
    if digests_every > 0 {
        rec = rec.with_body_digests(digests_every);
    }
    let mut bar = Progress::new(&format!("recording {}", desc.name), u64::from(steps));
    let mut last = world.space.checksum();
    for step in 1..=steps {
        world.step().map_err(|e| format!("step {step}: {e}"))?;
        last = rec.record_frame(&world, &[]).map_err(|e| e.to_string())?;
        bar.inc(1);
    }
    bar.finish();
    let replay = rec.finish();
    replay
        .write_file(output)
        .map_err(|e| format!("{}: {e}", output.display()))?;
    let size = std::fs::metadata(output).map(|m| m.len()).unwrap_or(0);
    println!(
        "recorded {steps} frames of {} to {} ({size} bytes)",
        desc.name,
        output.display()
    );
    println!("checksum: {last:#018x}");
    Ok(())
}

/// `tamias replay verify`: re-runs the replay (a scene's through its
/// scripted world, a bare snapshot start with the default step); `replay ok
/// (N frames)`, or an error naming the first frame whose inputs or
/// checksum differ (and the first differing body).
pub fn replay_verify(file: &Path, trusted: bool) -> Result<(), String> {
    let limits = if trusted {
        Limits::TRUSTED
    } else {
        Limits::UNTRUSTED
    };
    let at = |e: ReplayError| format!("{}: {e}", file.display());
    let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let replay = Replay::from_bytes_with(&bytes, &limits).map_err(at)?;
    // The start and every step are held to the same limits, through the
    // world's own (`Replay::verify_on`).
    let report = if ScriptedWorld::is_saved(&replay.start) {
        let mut world = ScriptedWorld::load_with(&replay.start, &limits)
            .map_err(|e| format!("{}: start: {e}", file.display()))?;
        replay.verify_on(&mut world)
    } else {
        let mut space = tamias2d::space::Space::new();
        space.set_limits(limits);
        replay.verify_on(&mut space)
    }
    .map_err(at)?;
    println!("replay ok ({} frames)", report.frames);
    println!("checksum: {:#018x}", report.final_checksum);
    Ok(())
}
