//! `tamias`: runs, renders, snapshots, replays and benchmarks Tamias2D
//! scenes. See `tamias --help`, and the README's "The `tamias` command".
//!
//! A separate workspace member so that the CLI's dependencies (argument
//! parser, rasteriser, PNG encoder, JSON) never burden the library's users.
//!
//! Every command exits with status 0 on success; on bad input it prints one
//! line, `error: …`, on stderr and exits with 1 (2 for command-line usage
//! errors, as clap does).
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use tamias2d::Real;

mod bench;
mod files;
mod progress;
mod render;
mod rollback;
mod run;
mod source;
mod web;

use source::Overrides;

/// Where `tamias` alone writes its pictures.
const DEFAULT_OUT: &str = "tamias-out";
/// Steps between two frames of the showcase animation (15 frames a second
/// of simulated time at the showcase's 1/60 s step).
const DEFAULT_EVERY: u32 = 4;

/// Deterministic 2D physics (I32F32 fixed point): run, render, snapshot,
/// replay and benchmark scenes. Without a command, runs the showcase
/// (`tamias demo`).
#[derive(Parser)]
#[command(name = "tamias", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// The showcase: pyramid_20 hit by a heavy ball; writes a picture and an
    /// animation (what `tamias` alone runs).
    Demo(DemoArgs),
    /// The built-in scenes, one line each.
    List,
    /// Runs a scene headless: prints timing and the final checksum (and, for
    /// the `bullets` scene, `tunnelled: N`, the bullets beyond the wall).
    Run(RunArgs),
    /// Scene files.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Save a world after N steps; continue from the file.
    #[command(subcommand)]
    Snapshot(SnapshotCommand),
    /// Record a run's per-frame checksums; verify them.
    #[command(subcommand)]
    Replay(ReplayCommand),
    /// Times the benchmark scenes: median ms per step over ≥ 10 samples
    /// (`--rollback`: the rollback budget, snapshot and rollback figures).
    Bench(bench::BenchArgs),
    /// The demo page: builds the engine for the browser (wasm32) and serves
    /// it on localhost (`--check`: the headless-Chromium test that the
    /// browser computes the native goldens' bits).
    Web(web::WebArgs),
}

#[derive(Args)]
struct DemoArgs {
    /// Folder for the picture, the animation and the scene file.
    #[arg(long, value_name = "DIR", default_value = DEFAULT_OUT)]
    out: PathBuf,
    /// Steps to simulate [default: the showcase's 480].
    #[arg(long, value_name = "N")]
    steps: Option<u32>,
    /// Steps between two animation frames.
    #[arg(long, value_name = "K", default_value_t = DEFAULT_EVERY, value_parser = clap::value_parser!(u32).range(1..))]
    every: u32,
}

/// Settings a command line may override.
#[derive(Args, Clone, Copy)]
struct SceneOpts {
    /// Time step: an exact decimal (0.01) or a ratio (1/60); no float is involved.
    #[arg(long, value_name = "X", value_parser = source::parse_dt)]
    dt: Option<Real>,
    /// Solver iterations per step.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    iterations: Option<u32>,
    /// Solve the contacts color by color (`Settings::colored_solver`):
    /// the order the threads can share; changes the results.
    #[arg(long)]
    colored_solver: bool,
    /// The solver: `sequential` (the MIS's sequential impulses) or `soft`
    /// (the soft step at its defaults, its speeds and slop scaled to the
    /// scene's length unit, and one whole-pipeline sub-step: it sub-steps
    /// itself) [default: the scene's].
    #[arg(long, value_name = "KIND")]
    solver: Option<source::SolverChoice>,
    /// Sleeping off (`Settings::sleep_time_threshold = SLEEP_NEVER`): every
    /// body steps every step, for timing the awake step.
    #[arg(long)]
    no_sleep: bool,
    /// Load a scene file without the limits for untrusted input (bytes,
    /// bodies, shapes, solver passes, candidate pairs).
    #[arg(long)]
    trusted: bool,
}

impl SceneOpts {
    fn overrides(self) -> Overrides {
        Overrides {
            dt: self.dt,
            iterations: self.iterations,
            colored_solver: self.colored_solver,
            solver: self.solver,
            no_sleep: self.no_sleep,
            trusted: self.trusted,
        }
    }
}

/// Threads and kernels for the step: any choice gives the same results.
#[derive(Args, Clone, Copy)]
struct ThreadOpts {
    /// Threads the step may use [default: all cores]; the results are the
    /// same with any count.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    threads: Option<u32>,
    /// The soft step's contact kernels: `auto` (the fastest measured),
    /// `scalar`, `wide` (in lanes, compiled for AVX2 where the processor
    /// has it) or `portable` (in lanes, for the build's instruction set)
    /// [default: auto]; the same results with any.
    #[arg(long, value_name = "KIND", value_parser = source::parse_kernels)]
    kernels: Option<tamias2d::space::Kernels>,
}

impl ThreadOpts {
    /// The count asked for, or every core.
    fn count(self) -> usize {
        self.threads.map_or_else(source::all_cores, |n| n as usize)
    }
}

/// Where and how often to write frames.
#[derive(Args, Clone)]
struct RenderOpts {
    /// Write PNG frames (`step_NNNNN.png`) into DIR.
    #[arg(long, value_name = "DIR")]
    render: Option<PathBuf>,
    /// Steps between two frames [default: about 60 frames per run].
    #[arg(long, value_name = "K", requires = "render", value_parser = clap::value_parser!(u32).range(1..))]
    every: Option<u32>,
    /// Write a PNG of the last step to FILE.
    #[arg(long, value_name = "FILE")]
    picture: Option<PathBuf>,
}

#[derive(Args)]
struct RunArgs {
    /// A built-in scene name (`tamias list`), `showcase`, or a scene JSON file.
    scene: String,
    /// Steps to run [default: the scene's own].
    #[arg(long, value_name = "N")]
    steps: Option<u32>,
    #[command(flatten)]
    opts: SceneOpts,
    #[command(flatten)]
    threads: ThreadOpts,
    #[command(flatten)]
    render: RenderOpts,
}

#[derive(Subcommand)]
enum SceneCommand {
    /// Writes a scene as JSON (every real an exact decimal string), loadable by `run`.
    Dump {
        /// A built-in scene name, `showcase`, or a scene JSON file.
        scene: String,
        /// Output file [default: standard output].
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
    },
}

#[derive(Subcommand)]
enum SnapshotCommand {
    /// Runs a scene N steps and saves the world.
    Save {
        /// A built-in scene name, `showcase`, or a scene JSON file.
        scene: String,
        /// Steps before saving.
        #[arg(long, value_name = "N")]
        steps: u32,
        /// Snapshot file to write.
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        #[command(flatten)]
        opts: SceneOpts,
    },
    /// Loads a snapshot and runs M more steps: the checksum equals an
    /// uninterrupted run of N + M steps.
    Run {
        /// Snapshot file.
        file: PathBuf,
        /// Steps to run.
        #[arg(long, value_name = "M")]
        steps: u32,
        /// Time step [default: the last step's, stored in the snapshot].
        #[arg(long, value_name = "X", value_parser = source::parse_dt)]
        dt: Option<Real>,
        /// Solver iterations per step [default: the snapshot's].
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
        iterations: Option<u32>,
        /// Load and step without the limits for untrusted input (the
        /// default limits bound the bytes, the world and each step's work).
        #[arg(long)]
        trusted: bool,
        #[command(flatten)]
        render: RenderOpts,
    },
}

#[derive(Subcommand)]
enum ReplayCommand {
    /// Runs a scene N steps, recording every frame's checksum.
    Record {
        /// A built-in scene name, `showcase`, or a scene JSON file.
        scene: String,
        /// Frames (steps) to record.
        #[arg(long, value_name = "N")]
        steps: u32,
        /// Replay file to write.
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        /// Also store a digest of every body every K frames, so that a
        /// divergence names the first differing body (0: never).
        #[arg(long, value_name = "K", default_value_t = 1)]
        digests_every: u32,
        #[command(flatten)]
        opts: SceneOpts,
    },
    /// Re-runs a replay: `replay ok (N frames)`, or the first diverging
    /// frame and body.
    Verify {
        /// Replay file.
        file: PathBuf,
        /// Verify without the limits for untrusted input (bytes, frames,
        /// the start world, each step's work).
        #[arg(long)]
        trusted: bool,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return clap_exit(&e),
    };
    let result = match cli.command {
        None => run::demo(&DemoArgs {
            out: PathBuf::from(DEFAULT_OUT),
            steps: None,
            every: DEFAULT_EVERY,
        }),
        Some(Command::Demo(args)) => run::demo(&args),
        Some(Command::List) => {
            list();
            Ok(())
        }
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Scene(SceneCommand::Dump { scene, output })) => {
            files::scene_dump(&scene, output.as_deref())
        }
        Some(Command::Snapshot(SnapshotCommand::Save {
            scene,
            steps,
            output,
            opts,
        })) => files::snapshot_save(&scene, steps, &output, opts.overrides()),
        Some(Command::Snapshot(SnapshotCommand::Run {
            file,
            steps,
            dt,
            iterations,
            trusted,
            render,
        })) => run::snapshot_run(
            &file,
            steps,
            Overrides {
                dt,
                iterations,
                colored_solver: false,
                solver: None,
                no_sleep: false,
                trusted,
            },
            &render,
        ),
        Some(Command::Replay(ReplayCommand::Record {
            scene,
            steps,
            output,
            digests_every,
            opts,
        })) => files::replay_record(&scene, steps, &output, digests_every, opts.overrides()),
        Some(Command::Replay(ReplayCommand::Verify { file, trusted })) => {
            files::replay_verify(&file, trusted)
        }
        Some(Command::Bench(args)) => bench::bench(&args),
        Some(Command::Web(args)) => web::web(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// `tamias list`.
fn list() {
    for s in tamias2d_scenes::REGISTRY {
        println!("{:<22} {}: {}", s.name, s.section.letter(), s.about);
    }
    println!("{:<22} {}", source::SHOWCASE, source::SHOWCASE_ABOUT);
}

/// Help and version go to stdout with status 0; a usage error is reduced to
/// its first line (clap's tips and usage block follow it) plus a pointer to
/// `--help`, with status 2.
fn clap_exit(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            ExitCode::SUCCESS
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            // `tamias scene` alone: clap would print the whole help.
            let text = e.render().to_string();
            let usage = usage_line(&text).unwrap_or("tamias <COMMAND>");
            eprintln!(
                "error: a subcommand is missing; usage: {usage} (see `{} --help`)",
                command_of(usage)
            );
            ExitCode::from(2)
        }
        _ => {
            let text = e.render().to_string();
            let cmd = usage_line(&text).map_or("tamias", command_of);
            eprintln!("error: {} (see `{cmd} --help`)", first_paragraph(&text));
            ExitCode::from(2)
        }
    }
}

/// The `Usage: …` line of a clap message, without the prefix.
fn usage_line(text: &str) -> Option<&str> {
    text.lines().find_map(|l| l.strip_prefix("Usage: "))
}

/// The command path of a usage line: `tamias run --dt <X> <SCENE>` gives
/// `tamias run`.
fn command_of(usage: &str) -> &str {
    let end = [usage.find(" ["), usage.find(" <"), usage.find(" -")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(usage.len());
    usage.get(..end).unwrap_or(usage)
}

/// The first line of a clap error without its `error: ` prefix; a line
/// ending in `:` takes the indented lines that follow it ("the following
/// required arguments were not provided: --output `<FILE>`").
fn first_paragraph(text: &str) -> String {
    let mut lines = text.lines().skip_while(|l| l.trim().is_empty());
    let first = lines.next().unwrap_or("error: bad command line");
    let mut out = first.strip_prefix("error: ").unwrap_or(first).to_owned();
    if out.ends_with(':') {
        let items: Vec<&str> = lines
            .take_while(|l| l.starts_with(' ') && !l.trim().is_empty())
            .map(str::trim)
            .collect();
        out = format!("{} {}", out, items.join(", "));
    }
    out
}

/// Error messages are one line (some library messages could carry a newline).
fn one_line(s: &str) -> String {
    s.split('\n')
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
