//! End-to-end tests of the `tamias` binary: every command, its output, the
//! files it writes, and one-line errors with a non-zero status on bad input.
//! Small scenes and few steps keep the whole file to a few seconds.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use tamias2d::replay::Recorder;

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli-tests")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn tamias_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tamias"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run tamias")
}

fn tamias(args: &[&str]) -> Output {
    tamias_in(Path::new(env!("CARGO_TARGET_TMPDIR")), args)
}

/// Runs `args`, asserts success, returns stdout.
fn ok(args: &[&str]) -> String {
    let out = tamias(args);
    check_ok(args, &out)
}

fn check_ok(args: &[&str], out: &Output) -> String {
    assert!(
        out.status.success(),
        "tamias {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).expect("utf-8 stdout")
}

/// Runs `args`, asserts a non-zero status and a single `error: …` line on
/// stderr containing `expect`; returns that line.
fn fails(args: &[&str], expect: &str) -> String {
    let out = tamias(args);
    assert!(!out.status.success(), "tamias {args:?} succeeded");
    let err = String::from_utf8(out.stderr).expect("utf-8 stderr");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "tamias {args:?}: not one line: {err:?}");
    let line = lines[0];
    assert!(line.starts_with("error: "), "tamias {args:?}: {line:?}");
    assert!(
        line.contains(expect),
        "tamias {args:?}: {line:?} lacks {expect:?}"
    );
    line.to_owned()
}

/// The value of the `checksum: 0x…` line.
fn checksum(stdout: &str) -> u64 {
    let hex = stdout
        .lines()
        .find_map(|l| l.strip_prefix("checksum: 0x"))
        .unwrap_or_else(|| panic!("no checksum line in {stdout:?}"));
    assert_eq!(hex.len(), 16, "{hex}");
    u64::from_str_radix(hex, 16).expect("hex checksum")
}

fn path(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn is_png(file: &Path) -> bool {
    let bytes = std::fs::read(file).unwrap_or_default();
    bytes.len() > 1000 && bytes.starts_with(b"\x89PNG\r\n\x1a\n")
}

/// Decodes every frame of an animated PNG; returns the frame count.
fn apng_frames(file: &Path) -> u32 {
    let bytes = std::fs::read(file).expect("animation file");
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("a PNG");
    let frames = reader
        .info()
        .animation_control
        .expect("an animated PNG")
        .num_frames;
    let mut buf = vec![0; reader.output_buffer_size().expect("frame size")];
    for i in 0..frames {
        reader
            .next_frame(&mut buf)
            .unwrap_or_else(|e| panic!("frame {i}: {e}"));
    }
    frames
}

#[test]
fn list_names_every_builtin_scene_and_the_showcase() {
    let out = ok(&["list"]);
    for name in tamias2d_scenes::REGISTRY.iter().map(|s| s.name) {
        assert!(
            out.lines()
                .any(|l| l.split_whitespace().next() == Some(name)),
            "{name} missing"
        );
    }
    assert!(out.lines().any(|l| l.starts_with("showcase ")));
    assert_eq!(out.lines().count(), tamias2d_scenes::REGISTRY.len() + 1);
}

#[test]
fn run_prints_timing_and_the_library_checksum() {
    let out = ok(&["run", "stack_10", "--steps", "20"]);
    assert!(out.contains("time per step: median"), "{out}");
    let mut scene = tamias2d_scenes::builtin("stack_10")
        .unwrap()
        .build()
        .unwrap();
    scene.step_n(20).unwrap();
    assert_eq!(checksum(&out), scene.space.checksum());
}

/// The value of the `<key>: <metres>` line, if any.
fn metres(stdout: &str, key: &str) -> Option<f64> {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(": "))
        .map(|v| v.parse().unwrap_or_else(|e| panic!("{key}: {v:?}: {e}")))
}

#[test]
fn run_prints_the_largest_penetration_and_joint_error() {
    let stack = ok(&["run", "stack_10", "--steps", "20"]);
    let pen = metres(&stack, "max penetration").expect("a max penetration line");
    assert!(pen > 0.0 && pen < 0.2, "{stack}");
    assert_eq!(metres(&stack, "max joint error"), None, "{stack}");
    let chain = ok(&["run", "hanging_chain_20_100", "--steps", "20"]);
    let err = metres(&chain, "max joint error").expect("a max joint error line");
    assert!((0.0..0.5).contains(&err), "{chain}");
    assert_eq!(metres(&chain, "max penetration"), Some(0.0), "{chain}");
}

#[test]
fn run_bullets_prints_tunnelled_zero() {
    let out = ok(&["run", "bullets"]);
    assert!(out.lines().any(|l| l == "tunnelled: 0"), "{out}");
    let other = ok(&["run", "stack_10", "--steps", "2"]);
    assert!(!other.contains("tunnelled"), "{other}");
}

#[test]
fn run_dt_is_exact_and_iterations_matter() {
    let default = checksum(&ok(&["run", "stack_10", "--steps", "20"]));
    // The built-in step is 1/60; its decimal form is the same bits.
    assert_eq!(
        checksum(&ok(&["run", "stack_10", "--steps", "20", "--dt", "1/60"])),
        default
    );
    assert_eq!(
        checksum(&ok(&[
            "run",
            "stack_10",
            "--steps",
            "20",
            "--dt",
            "0.0166666666"
        ])),
        default
    );
    assert_ne!(
        checksum(&ok(&["run", "stack_10", "--steps", "20", "--dt", "0.01"])),
        default
    );
    assert_ne!(
        checksum(&ok(&[
            "run",
            "stack_10",
            "--steps",
            "20",
            "--iterations",
            "3"
        ])),
        default
    );
}

#[test]
fn run_render_writes_png_frames() {
    let dir = scratch("run_render");
    let out = ok(&[
        "run",
        "stack_10",
        "--steps",
        "10",
        "--render",
        path(&dir),
        "--every",
        "4",
        "--picture",
        path(&dir.join("last.png")),
    ]);
    assert!(out.contains("wrote 4 frames"), "{out}");
    assert!(is_png(&dir.join("last.png")));
    // The last frame and the picture are the same image.
    assert_eq!(
        std::fs::read(dir.join("step_00010.png")).unwrap(),
        std::fs::read(dir.join("last.png")).unwrap()
    );
    for step in [0, 4, 8, 10] {
        let f = dir.join(format!("step_{step:05}.png"));
        assert!(is_png(&f), "{} missing or not a PNG", f.display());
    }
}

#[test]
fn run_bad_input_is_one_line_errors() {
    fails(&["run", "no_such_scene"], "unknown scene \"no_such_scene\"");
    fails(&["run", "missing.json"], "missing.json");
    fails(&["run", "stack_10", "--stepz", "5"], "--stepz");
    fails(&["run", "stack_10", "--steps", "many"], "--steps");
    fails(&["run", "stack_10", "--dt", "0"], "must be > 0");
    fails(&["run", "stack_10", "--dt", "fast"], "not a decimal");
    fails(&["run", "stack_10", "--iterations", "0"], "--iterations");
    fails(&["run", "stack_10", "--every", "3"], "--render");
    fails(&["run"], "<SCENE>");
    fails(&["frobnicate"], "frobnicate");
    fails(&["scene"], "subcommand");
}

#[test]
fn help_and_version_succeed() {
    let help = ok(&["--help"]);
    for cmd in [
        "demo", "list", "run", "scene", "snapshot", "replay", "bench",
    ] {
        assert!(help.contains(cmd), "{cmd} not in help");
    }
    assert!(ok(&["--version"]).starts_with("tamias "));
    assert!(ok(&["run", "--help"]).contains("--render"));
}

#[test]
fn scene_dump_is_json_that_run_loads_to_the_same_checksum() {
    let stdout = ok(&["scene", "dump", "stack_10"]);
    let desc: tamias2d_scenes::SceneDesc = serde_json::from_str(&stdout).expect("valid JSON");
    assert_eq!(desc, tamias2d_scenes::builtin("stack_10").unwrap());

    let dir = scratch("scene_dump");
    let file = dir.join("stack.json");
    ok(&["scene", "dump", "stack_10", "-o", path(&file)]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), stdout);
    assert_eq!(
        checksum(&ok(&["run", path(&file), "--steps", "20"])),
        checksum(&ok(&["run", "stack_10", "--steps", "20"]))
    );
}

#[test]
fn scene_file_errors_name_line_column_or_body() {
    let dir = scratch("scene_errors");
    let syntax = dir.join("syntax.json");
    std::fs::write(&syntax, "{\n  \"name\": \"x\",\n  \"dt\": \"0.01\",,\n}\n").unwrap();
    fails(&["run", path(&syntax)], "line 3 column");

    let float = dir.join("float.json");
    std::fs::write(
        &float,
        "{\"name\": \"x\", \"dt\": 0.01, \"steps\": 1, \"bodies\": []}",
    )
    .unwrap();
    fails(&["run", path(&float)], "line 1 column");

    let physics = dir.join("physics.json");
    std::fs::write(
        &physics,
        r#"{"name": "x", "dt": "0.01", "steps": 1, "bodies": [
            {"kind": "dynamic", "shapes": [{"geometry": {"kind": "circle", "radius": "-1"}, "mass": {"density": "1"}}]}
        ]}"#,
    )
    .unwrap();
    fails(&["run", path(&physics)], "bodies[0].shapes[0]");
    fails(&["scene", "dump", path(&syntax)], "line 3 column");
}

#[test]
fn snapshot_continues_exactly_where_the_run_stopped() {
    let dir = scratch("snapshot");
    // no_collide counts `begin` callbacks: counting changes nothing, so its
    // snapshot continues exactly too (and without a warning).
    for scene in ["stack_10", "newtons_cradle", "no_collide"] {
        let file = dir.join(format!("{scene}.snap"));
        let args = [
            "snapshot",
            "save",
            scene,
            "--steps",
            "15",
            "-o",
            path(&file),
        ];
        let out = tamias(&args);
        assert!(out.stderr.is_empty(), "{scene}: {:?}", out.stderr);
        let saved = check_ok(&args, &out);
        assert_eq!(
            checksum(&saved),
            checksum(&ok(&["run", scene, "--steps", "15"]))
        );
        let continued = ok(&["snapshot", "run", path(&file), "--steps", "10"]);
        let uninterrupted = ok(&["run", scene, "--steps", "25"]);
        assert_eq!(checksum(&continued), checksum(&uninterrupted), "{scene}");
    }
}

#[test]
fn snapshot_bad_files_are_one_line_errors() {
    let dir = scratch("snapshot_bad");
    let good = dir.join("good.snap");
    ok(&[
        "snapshot",
        "save",
        "stack_10",
        "--steps",
        "5",
        "-o",
        path(&good),
    ]);
    let bytes = std::fs::read(&good).unwrap();
    let truncated = dir.join("truncated.snap");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    fails(
        &["snapshot", "run", path(&truncated), "--steps", "5"],
        "corrupted",
    );
    let short = dir.join("short.snap");
    std::fs::write(&short, &bytes[..10]).unwrap();
    fails(
        &["snapshot", "run", path(&short), "--steps", "5"],
        "shorter",
    );
    let foreign = dir.join("foreign.snap");
    std::fs::write(&foreign, b"{\"name\": \"not a snapshot at all\"}").unwrap();
    fails(
        &["snapshot", "run", path(&foreign), "--steps", "5"],
        "bad magic",
    );
    fails(
        &["snapshot", "run", "nowhere.snap", "--steps", "5"],
        "nowhere.snap",
    );
    fails(&["snapshot", "run", path(&good)], "--steps");
    fails(
        &["snapshot", "save", "stack_10", "--steps", "5"],
        "--output",
    );
}

#[test]
fn scripted_scenes_snapshot_with_their_script_and_continue_exactly() {
    // The script is state: scripted forces (constant_force), a scripted
    // torque (spin) and bodies spawned by step (rain_1000, whose rows keep
    // spawning after the save) continue exactly, without a warning.
    let dir = scratch("snapshot_scripted");
    for scene in ["constant_force", "spin", "rain_1000"] {
        let file = dir.join(format!("{scene}.snap"));
        let args = [
            "snapshot",
            "save",
            scene,
            "--steps",
            "100",
            "-o",
            path(&file),
        ];
        let out = tamias(&args);
        check_ok(&args, &out);
        assert!(
            out.stderr.is_empty(),
            "{scene}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let args = ["snapshot", "run", path(&file), "--steps", "100"];
        let out = tamias(&args);
        let continued = check_ok(&args, &out);
        assert!(
            out.stderr.is_empty(),
            "{scene}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let straight = ok(&["run", scene, "--steps", "200"]);
        assert_eq!(
            checksum(&continued),
            checksum(&straight),
            "{scene}: save at 100 + run 100 differs from a straight run of 200"
        );
    }
}

#[test]
fn replay_records_and_verifies() {
    let dir = scratch("replay");
    let file = dir.join("stack.replay");
    let rec = ok(&[
        "replay",
        "record",
        "stack_10",
        "--steps",
        "20",
        "-o",
        path(&file),
    ]);
    let out = ok(&["replay", "verify", path(&file)]);
    assert!(out.lines().any(|l| l == "replay ok (20 frames)"), "{out}");
    assert_eq!(checksum(&out), checksum(&rec));
    assert_eq!(
        checksum(&rec),
        checksum(&ok(&["run", "stack_10", "--steps", "20"]))
    );

    // A scene file is recorded whole, overrides included.
    let json = dir.join("stack.json");
    ok(&["scene", "dump", "stack_10", "-o", path(&json)]);
    let file2 = dir.join("json.replay");
    ok(&[
        "replay",
        "record",
        path(&json),
        "--steps",
        "8",
        "--iterations",
        "4",
        "-o",
        path(&file2),
    ]);
    assert!(ok(&["replay", "verify", path(&file2)]).contains("replay ok (8 frames)"));
}

#[test]
fn replay_verify_names_the_diverging_frame_and_body() {
    let dir = scratch("replay_diverged");
    let mut world = tamias2d_scenes::builtin("stack_10")
        .unwrap()
        .build()
        .unwrap();
    let mut rec = Recorder::new(&world, world.dt).with_body_digests(1);
    for _ in 0..12 {
        world.step().unwrap();
        rec.record_frame(&world, &[]).unwrap();
    }
    let mut replay = rec.finish();
    // As if another build had computed frame 7 differently for body #3.
    let frame = &mut replay.frames[7];
    frame.checksum ^= 1;
    let bodies = frame.bodies.as_mut().expect("digests");
    bodies[3].1 ^= 1;
    let body = bodies[3].0;
    let file = dir.join("diverged.replay");
    replay.write_file(&file).unwrap();
    let line = fails(&["replay", "verify", path(&file)], "diverged at frame 7");
    assert!(line.contains(&format!("{body:?}")), "{line}");

    let bytes = std::fs::read(&file).unwrap();
    let truncated = dir.join("truncated.replay");
    std::fs::write(&truncated, &bytes[..bytes.len() - 9]).unwrap();
    fails(&["replay", "verify", path(&truncated)], "corrupted");
    fails(&["replay", "verify", "nowhere.replay"], "nowhere.replay");
}

#[test]
fn bench_prints_a_table() {
    let out = ok(&[
        "bench",
        "--quick",
        "--scene",
        "stack_10",
        "--scene",
        "elastic_pair",
        "--warmup",
        "5",
    ]);
    assert!(out.contains("median ms/step"), "{out}");
    let row = out
        .lines()
        .find(|l| l.starts_with("stack_10 "))
        .expect("a stack_10 row");
    let cols: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(cols.len(), 5, "{row}");
    assert_eq!(cols[1], "11");
    let median: f64 = cols[2].parse().expect("a number");
    assert!(median > 0.0);
    assert!(out.lines().any(|l| l.starts_with("elastic_pair ")));
    fails(&["bench", "--scene", "nope"], "unknown scene \"nope\"");
    fails(&["bench", "--samples", "3"], "--samples");
}

#[test]
fn bench_rollback_prints_one_line_per_figure() {
    let out = ok(&[
        "bench",
        "--rollback",
        "--scene",
        "stack_10",
        "--warmup",
        "5",
        "--samples",
        "10",
    ]);
    // A figure's value: the number after `name: `.
    let figure = |name: &str| -> f64 {
        let line = out
            .lines()
            .find_map(|l| l.trim().strip_prefix(name))
            .unwrap_or_else(|| panic!("no {name:?} line in {out}"));
        let value = line.split_whitespace().next().expect("a value");
        value.parse().unwrap_or_else(|_| panic!("{name}{line}"))
    };
    assert!(figure("snapshot bytes: ") > 0.0);
    // The frame snapshot leaves the static ground out: smaller than the full one.
    assert!(figure("full snapshot bytes: ") > figure("snapshot bytes: "));
    assert!(out.contains("(11 bodies)"), "{out}");
    for name in [
        "save ms per 1000 bodies: ",
        "load ms per 1000 bodies: ",
        "checksum ms per 1000 bodies: ",
        "step ms: ",
        "step ms, sleeping off: ",
        "rollback 8 frames ms: ",
        "rollback 8 frames in memory ms: ",
        "rollback 8 frames, full snapshots ms: ",
        "restore + 8 steps ms: ",
    ] {
        // A time, printed to 3 decimals: a release build steps stack_10
        // faster than 0.0005 ms, so only its presence and form are checked
        // (timings are benches' business, not tests').
        let v = figure(name);
        assert!(v.is_finite() && v >= 0.0, "{name}{v}");
    }
    assert!(
        out.contains("stack_10 (warm-up 5 steps): 11 bodies (10 moving, 0 asleep)"),
        "{out}"
    );
    fails(
        &["bench", "--rollback", "--scene", "nope"],
        "unknown scene \"nope\"",
    );
    fails(&["bench", "--rollback", "--quick"], "--quick");
}

#[test]
fn demo_writes_picture_animation_and_scene() {
    let dir = scratch("demo");
    let out = ok(&[
        "demo",
        "--steps",
        "24",
        "--every",
        "8",
        "--out",
        path(&dir.join("out")),
    ]);
    let out_dir = dir.join("out");
    assert!(is_png(&out_dir.join("final.png")));
    assert!(is_png(&out_dir.join("animation.png")));
    assert_eq!(apng_frames(&out_dir.join("animation.png")), 4);
    assert!(out.contains("4 frames"), "{out}");
    // The demo, `run showcase` and the scene file it wrote agree.
    let scene = out_dir.join("showcase.json");
    let sum = checksum(&out);
    assert_eq!(checksum(&ok(&["run", "showcase", "--steps", "24"])), sum);
    assert_eq!(checksum(&ok(&["run", path(&scene), "--steps", "24"])), sum);
}

/// What `cargo run --release` runs. The full showcase takes about 40 s
/// unoptimised, so this runs in release test runs (`.ci/run` has one); the
/// test above covers the same code with fewer steps.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "the full showcase is slow unoptimised; runs under `cargo test --release`"
)]
fn no_arguments_runs_the_showcase_into_tamias_out() {
    let dir = scratch("no_args");
    let out = tamias_in(&dir, &[]);
    let stdout = check_ok(&[], &out);
    for line in ["bodies: 212", "steps: 480", "time per step: median"] {
        assert!(stdout.contains(line), "{line} missing from {stdout}");
    }
    checksum(&stdout);
    assert!(stdout.contains("tamias-out"));
    assert!(is_png(&dir.join("tamias-out/final.png")));
    assert_eq!(apng_frames(&dir.join("tamias-out/animation.png")), 121);
}
