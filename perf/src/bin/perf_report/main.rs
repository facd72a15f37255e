//! Regenerates every table and plot of `docs/performance.md` and
//! `docs/tuning.md`: Tamias2D beside Rapier2D on the standard scenes (time
//! per step and the quality it buys), the accuracy scenes at default
//! settings, the joint scenes beside Rapier's joints (time per step and
//! joint error), settling scenes with sleeping on in both engines (awake and
//! settled time per step), and the speed/accuracy trade curves over solver
//! iterations, step size and sub-steps.
//!
//! ```text
//! cargo run --release -p tamias2d-perf --bin perf_report -- --out docs     # full run (5-9 min on 2 cores)
//! cargo run --release -p tamias2d-perf --bin perf_report -- --quick        # CI-sized scenes, short sweep (< 1 min)
//! cargo run --release -p tamias2d-perf --bin perf_report -- --out docs --only joints   # section D only (~1 min)
//! cargo run --release -p tamias2d-perf --bin perf_report -- --out docs --only sleep    # sleeping table only (~1 min)
//! ```
//! Run it from the repository root (it reads `Cargo.lock` there).
//! Options: `--out DIR` (default `target/perf_report`): the tables go into
//! `DIR/performance.md` (the trade curves into `DIR/tuning.md`) between its
//! `<!-- BEGIN perf_report:… -->` / `<!-- END … -->` markers (the file is
//! created with bare sections if it does not exist), plots into `DIR/images/perf_*.svg`, raw numbers into
//! `DIR/data/perf_*.csv`. `--quick` runs the CI-sized scenes and a shorter
//! sweep. `--skip-side`, `--skip-sweep` leave parts out; `--scenes a,b`
//! restricts both parts to the named scenes; `--skip-substeps` leaves the
//! sub-step series (`Settings::substeps` = 2 and 4) out of the sweep (see
//! `sweep::plan`). `--skip-joints` leaves the joint scenes out,
//! `--skip-sleep` the sleeping table; `--only side|joints|sleep|sweep` runs
//! that part alone (`side` is sections A–C) and rewrites only its sections
//! of `performance.md` (the machine table belongs to `side` and `sweep`;
//! the joint and sleeping sections carry their own). `--soft-narrow` runs
//! the side-by-side with Tamias2D on the narrow soft step (its own four
//! sub-steps) and Rapier at four iterations (its sub-steps), the setting
//! the Box2D comparison uses; its figures are printed (give it an `--out`
//! of its own: the generated tables are the default solver's).
#![allow(clippy::float_arithmetic)] // measurement and reports only

use tamias2d_scenes::bench as common;
use tamias2d_scenes::bench::measures;
mod plot;
mod report;
mod side;
mod sleep;
mod sweep;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Command line options.
pub struct Options {
    out: PathBuf,
    quick: bool,
    side: bool,
    sweep: bool,
    joints: bool,
    sleep: bool,
    scenes: Option<Vec<String>>,
    substeps: bool,
    soft_narrow: bool,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        out: PathBuf::from("target/perf_report"),
        quick: false,
        side: true,
        sweep: true,
        joints: true,
        sleep: true,
        scenes: None,
        substeps: true,
        soft_narrow: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--out" => o.out = args.next().ok_or("--out needs a directory")?.into(),
            "--quick" => o.quick = true,
            "--soft-narrow" => o.soft_narrow = true,
            "--skip-side" => o.side = false,
            "--skip-sweep" => o.sweep = false,
            "--skip-substeps" => o.substeps = false,
            "--skip-joints" => o.joints = false,
            "--skip-sleep" => o.sleep = false,
            "--only" => {
                let part = args
                    .next()
                    .ok_or("--only needs side, joints, sleep or sweep")?;
                o.side = part == "side";
                o.joints = part == "joints";
                o.sleep = part == "sleep";
                o.sweep = part == "sweep";
                if !(o.side || o.joints || o.sleep || o.sweep) {
                    return Err(format!(
                        "--only {part:?}: expected side, joints, sleep or sweep"
                    ));
                }
            }
            "--scenes" => {
                let list = args.next().ok_or("--scenes needs a list")?;
                o.scenes = Some(list.split(',').map(|s| s.trim().to_owned()).collect());
            }
            "-h" | "--help" => {
                return Err("usage: perf_report [--out DIR] [--quick] [--skip-side] \
                            [--skip-sweep] [--skip-substeps] [--skip-joints] \
                            [--skip-sleep] [--only side|joints|sleep|sweep] \
                            [--scenes a,b,…] [--soft-narrow]"
                    .to_owned())
            }
            other => return Err(format!("unknown argument {other:?} (try --help)")),
        }
    }
    Ok(o)
}

fn main() -> ExitCode {
    let opts = match parse_args() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    if cfg!(debug_assertions) {
        eprintln!("warning: debug build; timings are meaningless (use --release)");
    }
    let keep = |n: &&str| {
        opts.scenes
            .as_ref()
            .is_none_or(|s| s.iter().any(|x| x == n))
    };
    let started = Instant::now();
    let mut rep = report::Report::new(&opts.out, opts.quick);

    if opts.side {
        let mut scenes: Vec<&str> = common::ci_scenes();
        if !opts.quick {
            scenes.extend(common::full_scenes());
        }
        for name in scenes.into_iter().filter(keep) {
            let row = if opts.soft_narrow {
                side::run_soft_narrow(name)
            } else {
                side::run(name)
            };
            eprintln!(
                "[{:>5.0} s] {name:<20} Tamias2D {:>8.3} ms  Rapier {:>8.3} ms  ratio {:.2}",
                started.elapsed().as_secs_f64(),
                row.tamias.median_step * 1e3,
                row.rapier.median_step * 1e3,
                row.ratio()
            );
            rep.side.push(row);
        }
        for name in common::accuracy_scenes().into_iter().filter(keep) {
            let row = side::run(name);
            eprintln!(
                "[{:>5.0} s] {name:<20} errors Tamias2D {:?}  Rapier {:?}",
                started.elapsed().as_secs_f64(),
                row.tamias.errors,
                row.rapier.errors
            );
            rep.accuracy.push(row);
        }
    }
    if opts.joints {
        let t0 = started.elapsed().as_secs_f64();
        rep.load_before = report::load_average();
        for name in common::joint_scenes().into_iter().filter(keep) {
            let row = side::run_joints(name);
            eprintln!(
                "[{:>5.0} s] {name:<20} Tamias2D {:>8.3} ms  Rapier {:>8.3} ms  ratio {:.2}  \
                 joint error Tamias2D {:.2e} m  Rapier {:.2e} m",
                started.elapsed().as_secs_f64(),
                row.tamias.median_step * 1e3,
                row.rapier.median_step * 1e3,
                row.ratio(),
                row.tamias.joint.position,
                row.rapier.joint.position
            );
            rep.joints.push(row);
        }
        rep.load_after = report::load_average();
        rep.joints_elapsed = started.elapsed().as_secs_f64() - t0;
    }
    if opts.sleep {
        let t0 = started.elapsed().as_secs_f64();
        rep.sleep_load_before = report::load_average();
        let scenes = if opts.quick {
            vec!["pyramid_20", "bowl_boxes_100"]
        } else {
            vec![
                "pyramid_20",
                "bowl_boxes_500",
                "many_pyramids_4x4",
                "rain_1000",
            ]
        };
        for name in scenes.into_iter().filter(keep) {
            let row = sleep::run(name);
            eprintln!(
                "[{:>5.0} s] {name:<20} sleeping on, awake: Tamias2D {:>8.3} ms  Rapier {:>8.3} ms; \
                 settled: Tamias2D {:>8.4} ms  Rapier {:>8.4} ms (Tamias2D off {:.3} ms); \
                 asleep {} / {} of {}",
                started.elapsed().as_secs_f64(),
                row.tamias.awake * 1e3,
                row.rapier.awake * 1e3,
                row.tamias.settled * 1e3,
                row.rapier.settled * 1e3,
                row.tamias_off.settled * 1e3,
                row.tamias.asleep,
                row.rapier.asleep,
                row.dynamic
            );
            rep.sleep.push(row);
        }
        rep.sleep_load_after = report::load_average();
        rep.sleep_elapsed = started.elapsed().as_secs_f64() - t0;
    }
    if opts.sweep {
        let heavy = if opts.quick {
            "bowl_boxes_100"
        } else {
            "bowl_boxes_500"
        };
        let mut scenes = vec!["pyramid_20", heavy];
        scenes.extend(common::accuracy_scenes());
        for name in scenes.into_iter().filter(keep) {
            let t0 = started.elapsed().as_secs_f64();
            let mut log = |s: &str| eprintln!("{s}");
            let series = sweep::run_scene(name, opts.quick, opts.substeps, &mut log);
            eprintln!(
                "[{:>5.0} s] sweep {name} done in {:.0} s",
                started.elapsed().as_secs_f64(),
                started.elapsed().as_secs_f64() - t0
            );
            rep.sweeps.push((name.to_owned(), series));
        }
    }
    rep.elapsed = started.elapsed().as_secs_f64();
    match rep.write(opts.side, opts.sweep, opts.joints, opts.sleep) {
        Ok(path) => {
            eprintln!(
                "wrote {} in {:.0} s",
                path.display(),
                started.elapsed().as_secs_f64()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error writing the report: {e}");
            ExitCode::FAILURE
        }
    }
}
