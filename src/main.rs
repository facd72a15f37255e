//! `tamias`: runs a built-in scene and prints what happened.
//!
//! ```text
//! tamias                    # the showcase: pyramid_20 for 600 steps
//! tamias list               # the built-in scenes
//! tamias run <scene> [steps]
//! ```
//! The full CLI (scene files, rendering, snapshots, replays, benches) is
//! tracked separately; this binary stays dependency-free meanwhile.
#![allow(clippy::float_arithmetic)] // timing and reports only, never simulation state

use std::process::ExitCode;
use std::time::Instant;

use tamias2d::body::BodyType;
use tamias2d::scenes;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        None => run("pyramid_20", Some(600)),
        Some("list") => {
            for (name, about) in scenes::list() {
                println!("{name:<22} {about}");
            }
            Ok(())
        }
        Some("run") => match args.get(1) {
            Some(name) => match args.get(2).map(|s| s.parse::<u32>()) {
                None => run(name, None),
                Some(Ok(n)) => run(name, Some(n)),
                Some(Err(_)) => Err(format!("steps must be a whole number, got {:?}", args[2])),
            },
            None => Err("usage: tamias run <scene> [steps]".to_string()),
        },
        Some(other) => Err(format!(
            "unknown command {other:?}; try `tamias list` or `tamias run <scene>`"
        )),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(name: &str, steps: Option<u32>) -> Result<(), String> {
    let desc = scenes::builtin(name)
        .ok_or_else(|| format!("unknown scene {name:?}; `tamias list` shows them"))?;
    let mut scene = desc.build().map_err(|e| e.to_string())?;
    let steps = steps.unwrap_or(scene.steps);
    let start_positions: Vec<_> = scene
        .space
        .bodies()
        .map(|(h, b)| (h, b.position(), b.body_type()))
        .collect();
    let dynamic = start_positions
        .iter()
        .filter(|(_, _, t)| *t == BodyType::Dynamic)
        .count();
    println!(
        "scene {name}: {} bodies ({dynamic} dynamic), {steps} steps of dt = {}",
        start_positions.len(),
        scene.dt
    );

    let mut times = Vec::with_capacity(steps as usize);
    for _ in 0..steps {
        let t = Instant::now();
        scene.step().map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let median = times.get(times.len() / 2).copied().unwrap_or(0.0);
    let total: f64 = times.iter().sum();

    let mut max_move = 0.0f64;
    for (h, p0, _) in &start_positions {
        if let Some(b) = scene.space.body(*h) {
            let (x, y) = (b.position() - *p0).to_f64();
            max_move = max_move.max((x * x + y * y).sqrt());
        }
    }
    println!(
        "time per step: median {:.3} ms, total {:.2} s",
        median * 1e3,
        total
    );
    println!(
        "arbiters: {}, largest body displacement: {max_move:.4}",
        scene.space.arbiters().len()
    );
    println!("checksum: {:#018x}", scene.space.checksum());
    Ok(())
}
