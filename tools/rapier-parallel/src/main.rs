//! Rapier2D 0.36 built with `enhanced-determinism` and `parallel`, stepping
//! the same worlds as the performance report's side-by-side (sleeping off)
//! in rayon pools of 1 and 2 threads: median ms per step of 15 samples of
//! 10 steps after 120 steps of warm-up, and whether the two thread counts
//! end in the same body states (`bits`: 300 steps, every body's position,
//! angle and velocities compared).
use std::time::Instant;

use tamias2d_scenes::bench::{self as common, Config, Engine, RapierRun};

const SCENES: [&str; 4] = [
    "pyramid_100",
    "many_pyramids_10x10",
    "bowl_boxes_1000",
    "rain_4000",
];

fn run(name: &str) -> RapierRun {
    let desc = common::scene_with(name, Config::DEFAULT);
    RapierRun::new(&desc, Config::DEFAULT, common::length_unit(name))
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}

fn same_bits() {
    for name in ["pyramid_100", "bowl_boxes_1000"] {
        let states: Vec<Vec<String>> = [1, 2]
            .map(|threads| {
                pool(threads).install(|| {
                    let mut r = run(name);
                    for _ in 0..300 {
                        r.step();
                    }
                    (0..r.body_count())
                        .map(|i| format!("{:?}", r.body(i)))
                        .collect()
                })
            })
            .to_vec();
        let differ = states[0]
            .iter()
            .zip(&states[1])
            .filter(|(a, b)| a != b)
            .count();
        println!(
            "{name}: bodies whose state differs between 1 and 2 threads after 300 steps: {differ} of {}",
            states[0].len()
        );
    }
}

fn main() {
    if std::env::args().nth(1).as_deref() == Some("bits") {
        same_bits();
        return;
    }
    println!("| scene | Rapier, 1 thread | Rapier, 2 threads | speed-up |");
    println!("|---|---:|---:|---:|");
    for name in SCENES {
        let medians: Vec<f64> = [1, 2]
            .map(|threads| {
                pool(threads).install(|| {
                    let mut r = run(name);
                    for _ in 0..120 {
                        r.step();
                    }
                    let mut t: Vec<f64> = (0..15)
                        .map(|_| {
                            let s = Instant::now();
                            for _ in 0..10 {
                                r.step();
                            }
                            s.elapsed().as_secs_f64() * 1e3 / 10.0
                        })
                        .collect();
                    t.sort_by(f64::total_cmp);
                    t[t.len() / 2]
                })
            })
            .to_vec();
        println!(
            "| `{name}` | {:.2} | {:.2} | {:.2}× |",
            medians[0],
            medians[1],
            medians[0] / medians[1]
        );
    }
}
