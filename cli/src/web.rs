//! `tamias web`: builds the engine for the browser and serves the demo page
//! (`web/static/`); `--check` is the browser test.
//!
//! - **Build.** `cargo build --profile web --target wasm32-unknown-unknown
//!   -p tamias2d-web` in this source tree (after `rustup target add`, a
//!   no-op once installed), twice: the scalar module, and the `simd128`
//!   one (`-C target-feature=+simd128`, in `target/wasm-simd128/`), which
//!   the page loads where the browser has 128-bit SIMD. The page and the
//!   glue are served from `web/static/` as they are on disk, so editing
//!   them needs no rebuild.
//! - **Serve.** A small HTTP/1.1 server on 127.0.0.1 (one thread per
//!   connection, `Connection: close`): the static files, the `.wasm`, and
//!   `POST /report`, where the page in `?check` mode posts its results.
//! - **Check.** Starts headless Chromium on `/?check`, waits for the report,
//!   and fails unless every golden check's checksum computed in the browser
//!   (each golden scene on the canonical solver, the colored one and the
//!   soft step on both kernel forms, the narrow soft step on the portable
//!   lanes: `tamias2d_scenes::goldens::checks`), in both modules,
//!   equals the native golden (compared here, not trusted from the page)
//!   and the lockstep peers agreed on every confirmed frame.
//!   It prints the browser's frame time of `pyramid_20` and
//!   `bowl_boxes_500` on sequential impulses, on the soft step and on the
//!   soft step with the narrow contact kernels (mean
//!   over the first 300 steps from the build), in both modules, beside
//!   this native build's, measured the same way in this process (an
//!   optimised `tamias` only).
//!   `--screenshot PNG` also saves a picture of the page after the test.
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use clap::Args;
use tamias2d_scenes::goldens;

/// `tamias web` arguments.
#[derive(Args)]
pub struct WebArgs {
    /// Port on 127.0.0.1 to serve the page on.
    #[arg(long, value_name = "P", default_value_t = 8080)]
    port: u16,
    /// The browser test: run the page in headless Chromium, compare every
    /// golden checksum it computes with the native one, print frame times,
    /// exit (status 1 on any difference).
    #[arg(long)]
    check: bool,
    /// With --check: also save a screenshot of the page after the test.
    #[arg(long, value_name = "PNG", requires = "check")]
    screenshot: Option<PathBuf>,
    /// The Chromium executable.
    #[arg(long, value_name = "PATH", default_value = "chromium")]
    chromium: String,
    /// Seconds to wait for the page's report.
    #[arg(long, value_name = "S", default_value_t = 300)]
    timeout: u64,
}

/// The source tree this binary was built from (the page lives in it).
fn root() -> PathBuf {
    let cli = Path::new(env!("CARGO_MANIFEST_DIR"));
    cli.parent().unwrap_or(cli).to_path_buf()
}

/// The files of `web/static/` the server hands out, with their types.
const STATIC: &[(&str, &str)] = &[
    ("index.html", "text/html; charset=utf-8"),
    ("app.js", "text/javascript; charset=utf-8"),
    ("tamias.js", "text/javascript; charset=utf-8"),
    ("golden-worker.js", "text/javascript; charset=utf-8"),
    ("style.css", "text/css; charset=utf-8"),
];

/// `tamias web`.
pub fn web(args: &WebArgs) -> Result<(), String> {
    let wasm = build_wasm()?;
    let port = if args.check { 0 } else { args.port };
    let listener = TcpListener::bind(("127.0.0.1", port))
        .map_err(|e| format!("cannot listen on 127.0.0.1:{port}: {e}"))?;
    let addr = listener.local_addr().map_err(|e| e.to_string())?;
    let (reports, report) = mpsc::channel();
    let files = Files {
        dir: root().join("web").join("static"),
        wasm,
    };
    std::thread::spawn(move || serve(&listener, &files, &reports));
    let url = format!("http://{addr}/");
    if !args.check {
        println!("serving the Tamias2D page at {url} (Ctrl-C to stop)");
        // The server thread runs until the process is stopped.
        loop {
            std::thread::park();
        }
    }
    println!("browser test: {url}?check in headless Chromium");
    let profile = std::env::temp_dir().join(format!("tamias-chromium-{}", std::process::id()));
    let mut browser = Browser(chromium(args, &profile, &[&format!("{url}?check")])?);
    let got = report.recv_timeout(Duration::from_secs(args.timeout));
    browser.stop();
    let body = got.map_err(|_| {
        format!(
            "no report from the page within {} s (is `{}` a working Chromium?)",
            args.timeout, args.chromium
        )
    })?;
    let verdict = judge(&body);
    frame_times(&body)?;
    if let Some(png) = &args.screenshot {
        screenshot(args, &profile, &format!("{url}?check"), png)?;
    }
    let _ = std::fs::remove_dir_all(&profile);
    verdict
}

/// The two builds of the module the page chooses between.
struct Modules {
    /// Built for the wasm baseline: runs in any engine.
    scalar: PathBuf,
    /// Built with 128-bit SIMD (`simd128`), which every current browser
    /// has: the lane kernels run two 64-bit lanes an instruction.
    simd128: PathBuf,
}

/// Builds both modules; returns their paths.
fn build_wasm() -> Result<Modules, String> {
    let root = root();
    const TARGET: &str = "wasm32-unknown-unknown";
    // A no-op when installed; a clear error if rustup is missing.
    let rustup = Command::new("rustup")
        .args(["target", "add", TARGET])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !rustup.is_ok_and(|s| s.success()) {
        eprintln!("note: `rustup target add {TARGET}` failed; trying the build anyway");
    }
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    // The SIMD build has a target directory of its own: the two builds
    // differ only in compiler flags, which cargo does not keep apart.
    let simd_target = target.join("wasm-simd128");
    let scalar = build_module(&root, &target, None)?;
    let simd128 = build_module(&root, &simd_target, Some("+simd128"))?;
    Ok(Modules { scalar, simd128 })
}

/// `cargo build --profile web --target wasm32-unknown-unknown -p
/// tamias2d-web` into `target`, with the target `feature` on top of the
/// caller's `RUSTFLAGS` if given; returns the module's path.
fn build_module(root: &Path, target: &Path, feature: Option<&str>) -> Result<PathBuf, String> {
    const TARGET: &str = "wasm32-unknown-unknown";
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let what = feature.map_or(String::new(), |f| format!(" with {f}"));
    println!(
        "building the wasm module{what} (cargo build --profile web --target {TARGET} -p tamias2d-web)"
    );
    let mut command = Command::new(cargo);
    command.current_dir(root).args([
        "build",
        "--profile",
        "web",
        "--target",
        TARGET,
        "-p",
        "tamias2d-web",
        "--target-dir",
    ]);
    command.arg(target);
    if let Some(feature) = feature {
        let mut flags: Vec<String> = std::env::var("RUSTFLAGS")
            .unwrap_or_default()
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        flags.push(format!("-Ctarget-feature={feature}"));
        command.env("CARGO_ENCODED_RUSTFLAGS", flags.join("\u{1f}"));
    }
    let status = command
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("the wasm build{what} failed ({status})"));
    }
    let wasm = target.join(TARGET).join("web").join("tamias2d_web.wasm");
    if wasm.is_file() {
        Ok(wasm)
    } else {
        Err(format!("the build did not produce {}", wasm.display()))
    }
}

/// What the server hands out.
struct Files {
    dir: PathBuf,
    wasm: Modules,
}

/// Accepts connections until the process ends; each on its own thread, so
/// a browser's idle pre-connection cannot hold up the others.
fn serve(listener: &TcpListener, files: &Files, reports: &mpsc::Sender<String>) {
    std::thread::scope(|scope| {
        for stream in listener.incoming().flatten() {
            let reports = reports.clone();
            scope.spawn(move || {
                // A broken connection is the browser's business: nothing to report.
                let _ = answer(stream, files, &reports);
            });
        }
    });
}

/// Largest request body accepted (the report is a few kilobytes).
const MAX_BODY: usize = 1 << 20;

fn answer(stream: TcpStream, files: &Files, reports: &mpsc::Sender<String>) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut parts = line.split_whitespace();
    let (method, path) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let mut length = 0usize;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header)? == 0 || header.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = header.split_once(':') {
            if name.eq_ignore_ascii_case("content-length") {
                length = value.trim().parse().unwrap_or(0);
            }
        }
    }
    let path = path.split('?').next().unwrap_or("");
    let mut out = stream;
    match (method, path) {
        ("POST", "/report") if length <= MAX_BODY => {
            let mut body = vec![0; length];
            reader.read_exact(&mut body)?;
            let _ = reports.send(String::from_utf8_lossy(&body).into_owned());
            respond(&mut out, "200 OK", "text/plain", b"ok")
        }
        ("GET", "/tamias2d_web.wasm" | "/tamias2d_web_simd128.wasm") => {
            let wasm = if path.contains("simd128") {
                &files.wasm.simd128
            } else {
                &files.wasm.scalar
            };
            match std::fs::read(wasm) {
                Ok(bytes) => respond(&mut out, "200 OK", "application/wasm", &bytes),
                Err(_) => respond(&mut out, "404 Not Found", "text/plain", b"not built"),
            }
        }
        ("GET", path) => {
            let name = match path.trim_start_matches('/') {
                "" => "index.html",
                name => name,
            };
            let file = STATIC.iter().find(|(n, _)| *n == name);
            match file.and_then(|(n, ty)| Some((std::fs::read(files.dir.join(n)).ok()?, ty))) {
                Some((bytes, ty)) => respond(&mut out, "200 OK", ty, &bytes),
                None => respond(&mut out, "404 Not Found", "text/plain", b"not found"),
            }
        }
        _ => respond(&mut out, "400 Bad Request", "text/plain", b"bad request"),
    }
}

fn respond(out: &mut TcpStream, status: &str, ty: &str, body: &[u8]) -> std::io::Result<()> {
    write!(
        out,
        "HTTP/1.1 {status}\r\nContent-Type: {ty}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    out.write_all(body)?;
    out.flush()
}

/// A running Chromium, killed when dropped.
struct Browser(Child);

impl Browser {
    fn stop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Starts headless Chromium with `extra` arguments. The flags keep it off
/// the network (this machine's is closed) and out of the user's profile.
fn chromium(args: &WebArgs, profile: &Path, extra: &[&str]) -> Result<Child, String> {
    Command::new(&args.chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--window-size=1600,1500",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start `{}`: {e} (install Debian's `chromium` package, or pass --chromium PATH)",
                args.chromium
            )
        })
}

/// A screenshot of the page, the test run again and then a few seconds of
/// play (Chromium's virtual time: the page's timers and frames run, the
/// picture is taken when the budget is spent).
fn screenshot(args: &WebArgs, profile: &Path, url: &str, png: &Path) -> Result<(), String> {
    let shot = format!("--screenshot={}", png.display());
    let mut child = chromium(args, profile, &["--virtual-time-budget=3000", &shot, url])?;
    let deadline = Instant::now() + Duration::from_secs(args.timeout);
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(100)),
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                return Err("the screenshot did not finish in time".into());
            }
        }
    }
    if png.is_file() {
        println!("screenshot: {}", png.display());
        Ok(())
    } else {
        Err(format!("Chromium wrote no screenshot at {}", png.display()))
    }
}

/// Reads the page's report, compares it with the registry and prints the
/// table (the other build's differences only).
fn judge(body: &str) -> Result<(), String> {
    let report: serde_json::Value =
        serde_json::from_str(body).map_err(|e| format!("the page's report is not JSON: {e}"))?;
    let module = report["module"].as_str().unwrap_or("?");
    compare_goldens(module, &report["goldens"], true)?;
    let fallback = &report["fallback"];
    if !fallback.is_null() {
        let other = fallback["module"].as_str().unwrap_or("?");
        compare_goldens(other, &fallback["goldens"], false)?;
    }
    let lock = &report["lockstep"];
    let (agreed, confirmed) = (lock["agreed"].as_u64(), lock["confirmed"].as_u64());
    println!(
        "lockstep: {} frames, {} rollbacks, confirmed frames agreeing {}/{}",
        lock["frames"],
        lock["rollbacks"],
        agreed.unwrap_or(0),
        confirmed.unwrap_or(0)
    );
    if agreed.is_none() || agreed != confirmed || confirmed == Some(0) {
        return Err("the lockstep peers did not agree on every confirmed frame".into());
    }
    let ui = &report["ui"];
    println!(
        "pointer: press on a body grabs it {}, release lets go {}, press on empty space drops one {}",
        ui["grabbed"], ui["released"], ui["dropped"]
    );
    for step in ["grabbed", "released", "dropped"] {
        if ui[step] != serde_json::Value::Bool(true) {
            return Err(format!("the page's pointer handling failed: not {step}"));
        }
    }
    Ok(())
}

/// Compares one build's golden outcomes (`got`, the report's array) with
/// the registry; prints every row (`all`) or only the differing ones, then
/// the count.
fn compare_goldens(module: &str, got: &serde_json::Value, all: bool) -> Result<(), String> {
    let got = got.as_array().cloned().unwrap_or_default();
    let expected = goldens::checks();
    let mut same = 0;
    for check in &expected {
        let name = check.label();
        let row = got
            .iter()
            .find(|o| o["name"].as_str() == Some(name.as_str()));
        let computed = row
            .and_then(|o| o["computed"].as_str())
            .unwrap_or("missing");
        let steps = row.and_then(|o| o["steps"].as_u64());
        let native = format!("{:#018x}", check.checksum);
        let ok = computed == native && steps == Some(u64::from(check.steps));
        same += usize::from(ok);
        if all || !ok {
            println!(
                "{name:<36} {:>4} steps  browser {computed:<18}  native {native}  {}",
                check.steps,
                if ok { "same" } else { "DIFFERENT" }
            );
        }
    }
    println!("same bits (wasm {module}): {same}/{}", expected.len());
    if same == expected.len() {
        Ok(())
    } else {
        Err(format!(
            "the browser's {module} build computed different bits for {} of {} golden checks",
            expected.len() - same,
            expected.len()
        ))
    }
}

/// Prints the page's frame times beside this build's (an unoptimised
/// build, such as the one CI's debug tests leave for its browser stage,
/// prints the page's alone: its own steps would be no fair comparison).
fn frame_times(body: &str) -> Result<(), String> {
    let report: serde_json::Value = serde_json::from_str(body).unwrap_or_default();
    let module = report["module"].as_str().unwrap_or("?");
    let other = report["fallback"]["module"].as_str().unwrap_or("?");
    for name in ["pyramid_20", "bowl_boxes_500"] {
        for solver in [PageSolver::Sequential, PageSolver::Soft, PageSolver::Narrow] {
            let key = format!("{name}{}", solver.suffix());
            let browser = report["timings"][&key].as_f64();
            let fallback = report["fallback"]["timings"][&key]
                .as_f64()
                .map_or(String::new(), |t| format!(" (wasm {other} {t:.3})"));
            let Some(b) = browser else {
                println!("frame time {key}: browser missing");
                continue;
            };
            if cfg!(debug_assertions) {
                println!(
                    "frame time {key}: browser wasm {module} {b:.3} ms/step{fallback} (native not \
                     timed: this `tamias` is an unoptimised build)"
                );
                continue;
            }
            let native = native_frame_time(name, solver)?;
            println!(
                "frame time {key}: browser wasm {module} {b:.3} ms/step{fallback}, native \
                 {native:.3} ms/step, ratio {:.2}",
                b / native
            );
        }
    }
    println!("browser: {}", report["userAgent"].as_str().unwrap_or("?"));
    Ok(())
}

/// The page's solver switch, as its frame times name them.
#[derive(Clone, Copy)]
enum PageSolver {
    /// Sequential impulses, the scene's own settings.
    Sequential,
    /// The soft step scaled to the scene's gravity.
    Soft,
    /// That soft step on the narrow contact kernels.
    Narrow,
}

impl PageSolver {
    /// The suffix of the page's timing key.
    fn suffix(self) -> &'static str {
        match self {
            PageSolver::Sequential => "",
            PageSolver::Soft => " soft",
            PageSolver::Narrow => " soft narrow",
        }
    }
}

/// This build's mean ms per step of `name` over its first 300 steps from
/// the build, on `solver` (set as the page's solver switch sets it),
/// measured as the page does.
fn native_frame_time(name: &str, solver: PageSolver) -> Result<f64, String> {
    let desc = tamias2d_scenes::builtin(name).ok_or_else(|| format!("no scene {name}"))?;
    let mut world = desc.build().map_err(|e| format!("{name}: {e}"))?;
    if let PageSolver::Soft | PageSolver::Narrow = solver {
        let space = &mut world.space;
        let mut soft = tamias2d_scenes::soft_step_for(space.settings().gravity);
        if let PageSolver::Narrow = solver {
            soft.contact_precision = tamias2d::space::ContactPrecision::Narrow;
        }
        let settings = tamias2d::space::Settings {
            solver: tamias2d::space::Solver::Soft(soft),
            ..*space.settings()
        };
        space.set_settings(settings).map_err(|e| e.to_string())?;
    }
    let t0 = Instant::now();
    world.step_n(300).map_err(|e| format!("{name}: {e}"))?;
    Ok(t0.elapsed().as_secs_f64() * 1e3 / 300.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report as the page posts it, with every golden as `checksum`
    /// returns it for each scene.
    fn report(checksum: impl Fn(&str, u64) -> u64, agreed: u64) -> String {
        let goldens: Vec<_> = goldens::checks()
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.label(),
                    "steps": c.steps,
                    "computed": format!("{:#018x}", checksum(&c.label(), c.checksum)),
                    "golden": format!("{:#018x}", c.checksum),
                })
            })
            .collect();
        let timings = serde_json::json!({ "pyramid_20": 1.0, "bowl_boxes_500": 2.0 });
        serde_json::json!({
            "module": "simd128",
            "goldens": goldens.clone(),
            "fallback": { "module": "scalar", "goldens": goldens, "timings": timings.clone() },
            "timings": timings,
            "lockstep": { "frames": 300, "confirmed": 295, "agreed": agreed, "rollbacks": 4 },
            "userAgent": "test",
            "ui": { "grabbed": true, "released": true, "dropped": true },
        })
        .to_string()
    }

    #[test]
    fn the_judge_passes_only_the_native_bits() {
        assert_eq!(judge(&report(|_, c| c, 295)), Ok(()));
        // One scene one bit off: fails, whatever the page's own "golden" says.
        let off = report(|name, c| if name == "pendulum" { c ^ 1 } else { c }, 295);
        assert!(judge(&off).is_err_and(|e| e.contains("1 of")));
        // And one of the soft step's.
        let off = report(
            |name, c| {
                if name == "pendulum soft portable" {
                    c ^ 1
                } else {
                    c
                }
            },
            295,
        );
        assert!(judge(&off).is_err_and(|e| e.contains("1 of")));
        // A lockstep frame that disagreed.
        assert!(judge(&report(|_, c| c, 294)).is_err_and(|e| e.contains("lockstep")));
        // A scene missing from the report.
        let mut partial: serde_json::Value = serde_json::from_str(&report(|_, c| c, 295)).unwrap();
        partial["goldens"].as_array_mut().unwrap().pop();
        assert!(judge(&partial.to_string()).is_err());
        assert!(judge("not json").is_err());
        // The other build one bit off, or its outcomes missing.
        let mut other: serde_json::Value = serde_json::from_str(&report(|_, c| c, 295)).unwrap();
        let first = &mut other["fallback"]["goldens"][0]["computed"];
        *first = serde_json::Value::String("0x0000000000000000".into());
        assert!(judge(&other.to_string()).is_err_and(|e| e.contains("scalar build")));
        other["fallback"]["goldens"] = serde_json::Value::Array(Vec::new());
        assert!(judge(&other.to_string()).is_err_and(|e| e.contains("scalar build")));
        // The page's pointer wiring failed.
        let mut clumsy: serde_json::Value = serde_json::from_str(&report(|_, c| c, 295)).unwrap();
        clumsy["ui"]["dropped"] = serde_json::Value::Bool(false);
        assert!(judge(&clumsy.to_string()).is_err_and(|e| e.contains("dropped")));
    }

    /// One request to a live server; the response's status line and body.
    fn request(addr: std::net::SocketAddr, text: &str) -> (String, String) {
        let mut s = TcpStream::connect(addr).unwrap();
        s.write_all(text.as_bytes()).unwrap();
        let mut out = String::new();
        s.read_to_string(&mut out).unwrap();
        let status = out.lines().next().unwrap_or("").to_owned();
        let body = out.split_once("\r\n\r\n").map_or("", |(_, b)| b).to_owned();
        (status, body)
    }

    #[test]
    fn the_server_serves_the_page_and_takes_the_report() {
        let listener = TcpListener::bind(("127.0.0.1", 0)).unwrap();
        let addr = listener.local_addr().unwrap();
        let (reports, report) = mpsc::channel();
        let files = Files {
            dir: root().join("web").join("static"),
            wasm: Modules {
                scalar: root().join("no-such.wasm"),
                simd128: root().join("no-such-simd128.wasm"),
            },
        };
        std::thread::spawn(move || serve(&listener, &files, &reports));
        let (status, body) = request(addr, "GET / HTTP/1.1\r\nHost: x\r\n\r\n");
        assert_eq!(status, "HTTP/1.1 200 OK");
        assert!(body.contains("Same bits"));
        let (status, _) = request(addr, "GET /tamias.js?v=1 HTTP/1.1\r\n\r\n");
        assert_eq!(status, "HTTP/1.1 200 OK");
        // Only the listed files: nothing else of the tree.
        let (status, _) = request(addr, "GET /../Cargo.toml HTTP/1.1\r\n\r\n");
        assert_eq!(status, "HTTP/1.1 404 Not Found");
        let (status, _) = request(addr, "GET /tamias2d_web.wasm HTTP/1.1\r\n\r\n");
        assert_eq!(status, "HTTP/1.1 404 Not Found");
        let (status, _) = request(addr, "BREW /pot HTTP/1.1\r\n\r\n");
        assert_eq!(status, "HTTP/1.1 400 Bad Request");
        let (status, _) = request(
            addr,
            "POST /report HTTP/1.1\r\nContent-Length: 7\r\n\r\n{\"a\":1}",
        );
        assert_eq!(status, "HTTP/1.1 200 OK");
        assert_eq!(
            report.recv_timeout(Duration::from_secs(5)).as_deref(),
            Ok("{\"a\":1}")
        );
    }
}
