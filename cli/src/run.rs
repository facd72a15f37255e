//! The stepping commands: `demo` (the showcase with its picture and
//! animation), `run`, and `snapshot run`. They share one loop that times
//! every step (drawing is not timed) and hands frames to a sink.
use std::path::{Path, PathBuf};
use std::time::Instant;

use tamias2d::body::BodyType;
use tamias2d::space::Space;
use tamias2d_scenes::quality::Quality;
use tamias2d_scenes::ScriptedWorld;

use crate::progress::Progress;
use crate::render::{Apng, Canvas, View};
use crate::source::{self, Overrides};
use crate::{DemoArgs, RenderOpts, RunArgs};

/// Frames a run of `steps` draws at one every `every` steps: step 0, every
/// multiple of `every`, and the last step.
fn frame_count(steps: u32, every: u32) -> u32 {
    let every = every.max(1);
    steps / every + 1 + u32::from(steps % every != 0)
}

/// Whether the world after `step` of `steps` steps is drawn.
fn is_frame(step: u32, steps: u32, every: u32) -> bool {
    step % every.max(1) == 0 || step == steps
}

/// Per-step wall-clock times, in seconds.
pub struct Timing(Vec<f64>);

impl Timing {
    /// Median of the step times, in milliseconds.
    pub fn median_ms(&self) -> f64 {
        median(&self.0) * 1e3
    }

    /// Sum of the step times, in seconds.
    pub fn total_s(&self) -> f64 {
        self.0.iter().sum()
    }
}

/// Median of `xs` (mean of the middle two for an even count; 0 when empty).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match (v.get(n / 2), n % 2) {
        (None, _) => 0.0,
        (Some(m), 1) => *m,
        (Some(m), _) => (m + v.get(n / 2 - 1).copied().unwrap_or(*m)) / 2.0,
    }
}

/// Steps `sim` `steps` times under a progress bar; calls `frame(step,
/// space)` for step 0, every `every`-th step and the last one (if `every`
/// is given), and `after_step(space)` after every step (untimed).
fn step_loop(
    sim: &mut ScriptedWorld,
    steps: u32,
    label: &str,
    every: Option<u32>,
    mut frame: impl FnMut(u32, &Space) -> Result<(), String>,
    mut after_step: impl FnMut(&Space),
) -> Result<Timing, String> {
    let mut times = Vec::with_capacity(steps as usize);
    let mut bar = Progress::new(label, u64::from(steps));
    if every.is_some() {
        frame(0, &sim.space)?;
    }
    for step in 1..=steps {
        let t = Instant::now();
        sim.step()
            .map_err(|e| e.to_string())
            .map_err(|e| format!("step {step}: {e}"))?;
        times.push(t.elapsed().as_secs_f64());
        after_step(&sim.space);
        if let Some(k) = every {
            if is_frame(step, steps, k) {
                frame(step, &sim.space)?;
            }
        }
        bar.inc(1);
    }
    bar.finish();
    Ok(Timing(times))
}

/// Writes numbered PNG frames into a folder.
struct FrameDir {
    dir: PathBuf,
    canvas: Canvas,
    digits: usize,
    written: u32,
}

impl FrameDir {
    fn create(dir: &Path, view: View, steps: u32) -> Result<FrameDir, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(FrameDir {
            dir: dir.to_owned(),
            canvas: Canvas::new(view)?,
            digits: steps.to_string().len().max(5),
            written: 0,
        })
    }

    fn write(&mut self, step: u32, space: &Space) -> Result<(), String> {
        self.canvas.draw(space);
        let name = format!("step_{step:0width$}.png", width = self.digits);
        self.canvas.write_png(&self.dir.join(name))?;
        self.written += 1;
        Ok(())
    }
}

/// Bodies and dynamic bodies of a world.
fn body_counts(space: &Space) -> (usize, usize) {
    let all = space.bodies().count();
    let dynamic = space
        .bodies()
        .filter(|(_, b)| b.body_type() == BodyType::Dynamic)
        .count();
    (all, dynamic)
}

/// Runs `sim` for `steps`, with frames as `render` asks, and prints the
/// summary.
fn run_and_report(
    sim: &mut ScriptedWorld,
    steps: u32,
    label: &str,
    render: &RenderOpts,
) -> Result<(), String> {
    let (bodies, dynamic) = body_counts(&sim.space);
    let settings = sim.space.settings();
    println!(
        "{label}: {bodies} bodies ({dynamic} dynamic), {steps} steps of dt = {}, {} iterations",
        sim.dt, settings.iterations
    );
    // One view for every picture of the run, fitted to the first frame.
    let view = View::fit(&sim.space);
    let mut frames = match &render.render {
        Some(dir) => Some(FrameDir::create(dir, view, steps)?),
        None => None,
    };
    // About 60 frames per run unless told otherwise.
    let every = render.every.unwrap_or_else(|| steps.div_ceil(60).max(1));
    let mut quality = Quality::new();
    let timing = step_loop(
        sim,
        steps,
        label,
        frames.as_ref().map(|_| every),
        |step, space| frames.as_mut().map_or(Ok(()), |f| f.write(step, space)),
        |space| quality.measure(space),
    )?;
    println!(
        "time per step: median {:.3} ms, total {:.2} s",
        timing.median_ms(),
        timing.total_s()
    );
    if let Some(f) = &frames {
        println!(
            "wrote {} frames (one every {every} steps) to {}",
            f.written,
            f.dir.display()
        );
    }
    if let Some(file) = &render.picture {
        let mut canvas = Canvas::new(view)?;
        canvas.draw(&sim.space);
        canvas.write_png(file)?;
        println!(
            "wrote {} (step {steps}, {}x{})",
            file.display(),
            view.width,
            view.height
        );
    }
    if let Some(n) = tamias2d_scenes::bullets::tunnelled(sim) {
        println!("tunnelled: {n}");
    }
    println!("sleeping bodies: {}", sim.space.sleeping_bodies());
    for line in quality_lines(&quality) {
        println!("{line}");
    }
    println!("checksum: {:#018x}", sim.space.checksum());
    Ok(())
}

/// The run's quality lines: `max penetration: <m>` always,
/// `max joint error: <m>` for a world with measured joints (pivot, pin,
/// slide or groove), both the largest after any step, in metres, and
/// `max limit overrun: <rad>` for a world with rotary limits.
fn quality_lines(q: &Quality) -> Vec<String> {
    let mut lines = vec![format!(
        "max penetration: {:.6}",
        q.max_penetration.to_f64()
    )];
    if let Some(e) = q.max_joint_error {
        lines.push(format!("max joint error: {:.6}", e.to_f64()));
    }
    if let Some(e) = q.max_limit_overrun {
        lines.push(format!("max limit overrun: {:.6}", e.to_f64()));
    }
    lines
}

/// `tamias run`.
pub fn run(args: &RunArgs) -> Result<(), String> {
    let loaded = source::load(&args.scene, args.opts.overrides())?;
    let steps = args.steps.unwrap_or(loaded.steps);
    let mut sim = source::build(&loaded)?;
    let threads = args.threads.count();
    sim.space.set_threads(threads).map_err(|e| e.to_string())?;
    let kernels = args.threads.kernels.unwrap_or_default();
    sim.space.set_kernels(kernels);
    println!("threads: {threads}; kernels: {}", kernels.describe());
    let label = format!("scene {}", loaded.name);
    run_and_report(&mut sim, steps, &label, &args.render)
}

/// `tamias snapshot run`: a world loaded from `file`, `steps` more steps.
pub fn snapshot_run(
    file: &Path,
    steps: u32,
    overrides: Overrides,
    render: &RenderOpts,
) -> Result<(), String> {
    let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut sim = crate::files::load_world(&bytes, overrides.dt, &overrides.limits())
        .map_err(|e| format!("{}: {e}", file.display()))?;
    if let Some(n) = overrides.iterations {
        sim.space.set_iterations(n);
    }
    if overrides.colored_solver {
        let settings = tamias2d::space::Settings {
            colored_solver: true,
            ..*sim.space.settings()
        };
        sim.space
            .set_settings(settings)
            .map_err(|e| e.to_string())?;
    }
    println!("loaded {} at step {}", file.display(), sim.space.steps());
    run_and_report(&mut sim, steps, "snapshot", render)
}

/// `tamias` / `tamias demo`: the showcase, its summary, a picture of the
/// final frame, an animated PNG and the scene file, in `args.out`.
pub fn demo(args: &DemoArgs) -> Result<(), String> {
    let out = &args.out;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let desc = source::showcase();
    let steps = args.steps.unwrap_or(desc.steps);
    let every = args.every.max(1);
    let mut sim = source::build(&desc)?;
    let (bodies, dynamic) = body_counts(&sim.space);
    println!("showcase: {}", source::SHOWCASE_ABOUT);
    println!("output folder: {}", out.display());

    let view = View::fit(&sim.space);
    let mut canvas = Canvas::new(view)?;
    let frames = frame_count(steps, every);
    // Each frame stays up for `every` steps of 1/60 s: real time.
    let delay = (u16::try_from(every).unwrap_or(u16::MAX), 60);
    let anim_path = out.join("animation.png");
    let mut anim = Apng::create(&anim_path, &canvas, frames, delay)?;
    let timing = step_loop(
        &mut sim,
        steps,
        "showcase",
        Some(every),
        |_, space| {
            canvas.draw(space);
            anim.push(&canvas)
        },
        |_| {},
    )?;
    anim.finish()?;
    let final_path = out.join("final.png");
    canvas.draw(&sim.space);
    canvas.write_png(&final_path)?;
    let scene_path = out.join("showcase.json");
    let json = serde_json::to_string_pretty(&desc).map_err(|e| e.to_string())?;
    std::fs::write(&scene_path, json + "\n")
        .map_err(|e| format!("{}: {e}", scene_path.display()))?;

    println!("bodies: {bodies} ({dynamic} dynamic)");
    println!("steps: {steps} of dt = {}", sim.dt);
    println!(
        "time per step: median {:.3} ms (total {:.2} s)",
        timing.median_ms(),
        timing.total_s()
    );
    println!("checksum: {:#018x}", sim.space.checksum());
    println!(
        "wrote {} (final frame, {}x{})",
        final_path.display(),
        view.width,
        view.height
    );
    println!(
        "wrote {} (animated PNG: {frames} frames, one every {every} steps, real time)",
        anim_path.display()
    );
    println!(
        "wrote {} (run it again: tamias run {})",
        scene_path.display(),
        scene_path.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_count_matches_is_frame() {
        for steps in [0, 1, 7, 8, 9, 480] {
            for every in [1, 3, 4, 8, 1000] {
                let n = (0..=steps).filter(|&s| is_frame(s, steps, every)).count();
                assert_eq!(n as u32, frame_count(steps, every), "{steps} {every}");
            }
        }
    }

    #[test]
    fn quality_lines_print_joint_error_only_with_joints() {
        let mut q = Quality::new();
        q.max_penetration = tamias2d::math::Real::ratio(1, 8);
        assert_eq!(quality_lines(&q), ["max penetration: 0.125000"]);
        q.max_joint_error = Some(tamias2d::math::Real::ratio(1, 4));
        assert_eq!(
            quality_lines(&q),
            ["max penetration: 0.125000", "max joint error: 0.250000"]
        );
    }

    #[test]
    fn median_odd_even_empty() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
    }
}
