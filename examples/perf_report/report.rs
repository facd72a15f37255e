//! Markdown tables, CSV files and plots from the measurements, written into
//! the marked sections of `performance.md`.
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::measures;
use crate::plot;
use crate::side::SideRow;
use crate::sweep::{Kind, Series};

/// Everything one run measured.
pub struct Report {
    out: PathBuf,
    quick: bool,
    /// Sections A and B, both engines.
    pub side: Vec<SideRow>,
    /// Section C at default settings, both engines.
    pub accuracy: Vec<SideRow>,
    /// Trade sweeps per scene.
    pub sweeps: Vec<(String, Vec<Series>)>,
    /// Wall time of the whole run (s).
    pub elapsed: f64,
}

/// `x` with 3 significant digits, in plain or scientific notation.
pub fn sig(x: f64) -> String {
    if x == 0.0 {
        "0".to_owned()
    } else if !x.is_finite() {
        format!("{x}")
    } else if x.abs() >= 0.01 && x.abs() < 10_000.0 {
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

fn command_output(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The resolved version of `package` in `Cargo.lock`.
fn locked_version(package: &str) -> Option<String> {
    let lock = fs::read_to_string("Cargo.lock").ok()?;
    let mut lines = lock.lines();
    while let Some(l) = lines.next() {
        if l.trim() == format!("name = \"{package}\"") {
            let v = lines.next()?.trim();
            return Some(
                v.trim_start_matches("version = ")
                    .trim_matches('"')
                    .to_owned(),
            );
        }
    }
    None
}

impl Report {
    /// An empty report writing under `out`.
    pub fn new(out: &Path, quick: bool) -> Report {
        Report {
            out: out.to_owned(),
            quick,
            side: Vec::new(),
            accuracy: Vec::new(),
            sweeps: Vec::new(),
            elapsed: 0.0,
        }
    }

    fn machine(&self) -> String {
        let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
        let model = command_output("lscpu", &[])
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("Model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_owned())
            })
            .unwrap_or_else(|| "unknown".to_owned());
        let rustc = command_output("rustc", &["-V"]).unwrap_or_else(|| "unknown".to_owned());
        let date = command_output("date", &["-u", "+%Y-%m-%d"]).unwrap_or_default();
        let rapier = locked_version("rapier2d").unwrap_or_else(|| "?".to_owned());
        let mut s = String::new();
        let _ = writeln!(s, "| | |\n|---|---|");
        let _ = writeln!(s, "| date | {date} |");
        let _ = writeln!(s, "| `nproc` | {cores} |");
        let _ = writeln!(s, "| `lscpu` model | {model} |");
        let _ = writeln!(s, "| rustc | {rustc} |");
        let _ = writeln!(
            s,
            "| engines | Tamias2D {} (I32F32); rapier2d {rapier} (f32, `enhanced-determinism`) |",
            env!("CARGO_PKG_VERSION")
        );
        let _ = writeln!(
            s,
            "| run | `perf_report{}`, {:.0} s in all |",
            if self.quick { " --quick" } else { "" },
            self.elapsed
        );
        s
    }

    fn side_table(&self) -> String {
        let mut s = String::from(
            "| scene | bodies | steps timed | Tamias2D ms/step | Rapier ms/step | Tamias2D / Rapier |\n\
             |---|---:|---:|---:|---:|---:|\n",
        );
        for r in &self.side {
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {:.3} | {:.3} | **{:.2}** |",
                r.name,
                r.bodies,
                r.tamias.timed_steps,
                r.tamias.median_step * 1e3,
                r.rapier.median_step * 1e3,
                r.ratio()
            );
        }
        s
    }

    fn quality_table(&self) -> String {
        let mut s = String::from(
            "| scene | penetration max / mean, Tamias2D | penetration max / mean, Rapier | \
             other, Tamias2D | other, Rapier |\n|---|---:|---:|---|---|\n",
        );
        for r in &self.side {
            let other = |e: &crate::side::EngineResult| {
                let mut parts = Vec::new();
                if let Some(d) = e.drift {
                    parts.push(format!(
                        "at 10 s: moved ≤ {} m (sideways ≤ {} m), turned ≤ {} rad",
                        sig(d.displacement),
                        sig(d.horizontal),
                        sig(d.rotation)
                    ));
                }
                if let Some(k) = e.energy_drift {
                    parts.push(format!("energy {:+.1}%", k * 100.0));
                }
                parts.push(format!("escaped {}", e.escaped));
                parts.join("; ")
            };
            let pen = |e: &crate::side::EngineResult| {
                format!("{} / {}", sig(e.pen.max), sig(e.pen.mean()))
            };
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | {} |",
                r.name,
                pen(&r.tamias),
                pen(&r.rapier),
                other(&r.tamias),
                other(&r.rapier)
            );
        }
        s
    }

    fn accuracy_table(&self) -> String {
        let mut s = String::from(
            "| scene | after | measure | Tamias2D | Rapier |\n|---|---|---|---:|---:|\n",
        );
        for r in &self.accuracy {
            for (i, m) in measures::measures(&r.name).iter().enumerate() {
                let get =
                    |e: &crate::side::EngineResult| e.errors.get(i).map_or("-".into(), |v| sig(*v));
                let _ = writeln!(
                    s,
                    "| `{}` | {} steps of 1/60 s | {} ({}) | {} | {} |",
                    r.name,
                    r.steps,
                    m.name.replace('|', "\\|"),
                    m.unit,
                    get(&r.tamias),
                    get(&r.rapier)
                );
            }
        }
        s
    }

    /// One compact table per scene (first error measure, with the cost) and
    /// its plot.
    fn trade_section(&self) -> Result<String, Box<dyn std::error::Error>> {
        let images = self.out.join("images");
        fs::create_dir_all(&images)?;
        let mut s = String::new();
        for (name, series) in &self.sweeps {
            let ms = measures::measures(name);
            let Some(m0) = ms.first() else { continue };
            let file = format!("perf_{name}.svg");
            let y_label = format!("{} ({}, log)", m0.name, m0.unit);
            let title = format!(
                "{name}: cost vs {} after {} s",
                m0.name,
                measures::sweep_seconds(name)
            );
            plot::trade(&images.join(&file), &title, &y_label, series, 0)?;
            let _ = writeln!(
                s,
                "#### `{name}` — {} ({}) after {} s\n\n![{name} trade curve](images/{file})\n",
                m0.name,
                m0.unit,
                measures::sweep_seconds(name)
            );
            let iters: Vec<u32> = series
                .iter()
                .flat_map(|x| x.points.iter().map(|p| p.config.iterations))
                .fold(Vec::new(), |mut v, i| {
                    if !v.contains(&i) {
                        v.push(i);
                    }
                    v
                });
            let _ = write!(s, "| error @ ms per simulated s |");
            for i in &iters {
                let _ = write!(s, " {i} it |");
            }
            let _ = write!(s, "\n|---|");
            for _ in &iters {
                let _ = write!(s, "---:|");
            }
            s.push('\n');
            for x in series {
                let _ = write!(s, "| {} |", x.label);
                for i in &iters {
                    match x.points.iter().find(|p| p.config.iterations == *i) {
                        Some(p) => {
                            let e = p.errors.first().copied().unwrap_or(0.0);
                            let _ = write!(s, " {} @ {} |", sig(e), sig(p.cost_ms));
                        }
                        None => s.push_str(" |"),
                    }
                }
                s.push('\n');
            }
            s.push('\n');
        }
        Ok(s)
    }

    fn write_csv(&self) -> std::io::Result<()> {
        let data = self.out.join("data");
        fs::create_dir_all(&data)?;
        let mut side = String::from(
            "scene,engine,median_step_ms,timed_steps,pen_max,pen_mean,pen_pairs,drift_m,drift_sideways_m,drift_rad,energy_drift,escaped,errors\n",
        );
        for r in self.side.iter().chain(&self.accuracy) {
            for (engine, e) in [("tamias2d", &r.tamias), ("rapier", &r.rapier)] {
                let (d, h, a) = e.drift.map_or(Default::default(), |d| {
                    (
                        d.displacement.to_string(),
                        d.horizontal.to_string(),
                        d.rotation.to_string(),
                    )
                });
                let errors: Vec<String> = e.errors.iter().map(f64::to_string).collect();
                let _ = writeln!(
                    side,
                    "{},{engine},{},{},{},{},{},{d},{h},{a},{},{},{}",
                    r.name,
                    e.median_step * 1e3,
                    e.timed_steps,
                    e.pen.max,
                    e.pen.mean(),
                    e.pen.pairs,
                    e.energy_drift.map_or(String::new(), |k| k.to_string()),
                    e.escaped,
                    errors.join(";")
                );
            }
        }
        if !self.side.is_empty() || !self.accuracy.is_empty() {
            fs::write(data.join("perf_side.csv"), side)?;
        }
        let mut sw =
            String::from("scene,series,engine,iterations,substeps,rate,cost_ms_per_s,errors\n");
        for (name, series) in &self.sweeps {
            for x in series {
                for p in &x.points {
                    let errors: Vec<String> = p.errors.iter().map(f64::to_string).collect();
                    let _ = writeln!(
                        sw,
                        "{name},{},{},{},{},{},{},{}",
                        x.label,
                        if x.kind == Kind::Rapier {
                            "rapier"
                        } else {
                            "tamias2d"
                        },
                        p.config.iterations,
                        p.config.substeps,
                        p.config.rate,
                        p.cost_ms,
                        errors.join(";")
                    );
                }
            }
        }
        if !self.sweeps.is_empty() {
            fs::write(data.join("perf_sweep.csv"), sw)?;
        }
        Ok(())
    }

    /// Writes plots, CSV files and the marked sections of `performance.md`;
    /// returns the markdown file's path.
    pub fn write(&self, side: bool, sweep: bool) -> Result<PathBuf, Box<dyn std::error::Error>> {
        fs::create_dir_all(&self.out)?;
        self.write_csv()?;
        let mut sections = vec![("machine", self.machine())];
        if side {
            sections.push(("side_by_side", self.side_table()));
            sections.push(("quality", self.quality_table()));
            sections.push(("accuracy", self.accuracy_table()));
            if !self.side.is_empty() {
                let images = self.out.join("images");
                fs::create_dir_all(&images)?;
                let rows: Vec<(String, f64)> = self
                    .side
                    .iter()
                    .map(|r| (r.name.clone(), r.ratio()))
                    .collect();
                plot::ratios(&images.join("perf_ratio.svg"), &rows)?;
            }
        }
        if sweep {
            sections.push(("trade", self.trade_section()?));
        }
        let path = self.out.join("performance.md");
        let mut doc = fs::read_to_string(&path).unwrap_or_default();
        for (key, body) in sections {
            doc = replace_section(&doc, key, &body);
        }
        fs::write(&path, doc)?;
        Ok(path)
    }
}

/// `doc` with the text between the markers of section `key` replaced by
/// `body`; the section is appended if the markers are missing.
fn replace_section(doc: &str, key: &str, body: &str) -> String {
    let begin = format!("<!-- BEGIN perf_report:{key} -->");
    let end = format!("<!-- END perf_report:{key} -->");
    let block = format!("{begin}\n{body}{end}");
    match (doc.find(&begin), doc.find(&end)) {
        (Some(b), Some(e)) if e > b => {
            format!("{}{block}{}", &doc[..b], &doc[e + end.len()..])
        }
        _ => format!("{doc}\n{block}\n"),
    }
}
