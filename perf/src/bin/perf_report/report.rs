//! Markdown tables, CSV files and plots from the measurements, written into
//! the marked sections of `performance.md`.
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::measures;
use crate::plot;
use crate::side::SideRow;
use crate::sleep::{SleepRow, AWAKE, SETTLED};
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
    /// Section D beside Rapier's joints.
    pub joints: Vec<SideRow>,
    /// Wall time of the joint part (s).
    pub joints_elapsed: f64,
    /// 1-minute load average before and after the joint part.
    pub load_before: Option<f64>,
    /// See `load_before`.
    pub load_after: Option<f64>,
    /// Settling scenes with sleeping on in both engines.
    pub sleep: Vec<SleepRow>,
    /// Wall time of the sleeping part (s).
    pub sleep_elapsed: f64,
    /// 1-minute load average before and after the sleeping part.
    pub sleep_load_before: Option<f64>,
    /// See `sleep_load_before`.
    pub sleep_load_after: Option<f64>,
    /// Wall time of the whole run (s).
    pub elapsed: f64,
}

/// The 1-minute load average (`/proc/loadavg`), where there is one.
pub fn load_average() -> Option<f64> {
    fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
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

/// What the machine tables say about where a run happened.
struct Machine {
    date: String,
    cores: usize,
    model: String,
    rustc: String,
    engines: String,
}

impl Machine {
    fn read() -> Machine {
        let model = command_output("lscpu", &[])
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("Model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_owned())
            })
            .unwrap_or_else(|| "unknown".to_owned());
        let rapier = locked_version("rapier2d").unwrap_or_else(|| "?".to_owned());
        // This program is a crate of its own (tamias2d-perf): the engine's
        // version is the one locked, as Rapier's.
        let tamias = locked_version("tamias2d").unwrap_or_else(|| "?".to_owned());
        Machine {
            date: command_output("date", &["-u", "+%Y-%m-%d"]).unwrap_or_default(),
            cores: std::thread::available_parallelism().map_or(0, |n| n.get()),
            model,
            rustc: command_output("rustc", &["-V"]).unwrap_or_else(|| "unknown".to_owned()),
            engines: format!(
                "Tamias2D {tamias} (I32F32); rapier2d {rapier} (f32, `enhanced-determinism`)"
            ),
        }
    }
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
            joints: Vec::new(),
            joints_elapsed: 0.0,
            load_before: None,
            load_after: None,
            sleep: Vec::new(),
            sleep_elapsed: 0.0,
            sleep_load_before: None,
            sleep_load_after: None,
            elapsed: 0.0,
        }
    }

    fn machine(&self) -> String {
        let m = Machine::read();
        let mut s = String::new();
        let _ = writeln!(s, "| | |\n|---|---|");
        let _ = writeln!(s, "| date | {} |", m.date);
        let _ = writeln!(s, "| `nproc` | {} |", m.cores);
        let _ = writeln!(s, "| `lscpu` model | {} |", m.model);
        let _ = writeln!(s, "| rustc | {} |", m.rustc);
        let _ = writeln!(s, "| engines | {} |", m.engines);
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

    /// The joint section: its own machine note, the time and joint-error
    /// tables, and the mapping to Rapier's joints.
    fn joint_section(&self) -> String {
        let m = Machine::read();
        let mut s = String::new();
        let load = |l: Option<f64>| l.map_or("?".to_owned(), |x| format!("{x:.2}"));
        let busy = self
            .load_before
            .into_iter()
            .chain(self.load_after)
            .any(|l| l > 1.0);
        let _ = writeln!(
            s,
            "Measured {} on {} cores ({}), {}, {}; `{}`, joint part {:.0} s. \
             1-minute load average {} before, {} after{}.\n",
            m.date,
            m.cores,
            m.model,
            m.rustc,
            m.engines,
            std::iter::once("perf_report".to_owned())
                .chain(std::env::args().skip(1))
                .collect::<Vec<_>>()
                .join(" "),
            self.joints_elapsed,
            load(self.load_before),
            load(self.load_after),
            if busy {
                ": **measured while other builds ran**, so the times are noisy \
                 (the lockstep order spreads the noise over both engines alike)"
            } else {
                ""
            }
        );
        s.push_str(
            "Each scene runs at its own settings (iterations and sub-steps as the scene \
             defines them, 1/60 s steps), both engines in lockstep; the time is the \
             median step after a one-second warm-up. A dagger (†) marks a scene whose \
             Rapier world lacks joints Rapier has no counterpart for (see the mapping \
             below): its ratio is not like for like. Rapier's joint count is after an \
             angular limit or motor has gone onto the pair's revolute or pin-slot joint, \
             with the empty joints that stand in for left-out ones where those disabled \
             contacts.\n\n",
        );
        s.push_str(
            "| scene | bodies | joints (Tamias2D / Rapier) | settings | steps timed | \
             Tamias2D µs/step | Rapier µs/step | Tamias2D / Rapier |\n\
             |---|---:|---:|---|---:|---:|---:|---:|\n",
        );
        let dagger = |r: &SideRow| if r.left_out.is_empty() { "" } else { " †" };
        for r in &self.joints {
            let _ = writeln!(
                s,
                "| `{}`{} | {} | {} / {} | {} | {} | {} | {} | **{:.2}** |",
                r.name,
                dagger(r),
                r.bodies,
                r.tamias.joints,
                r.rapier.joints,
                r.config.label(),
                r.tamias.timed_steps,
                sig(r.tamias.median_step * 1e6),
                sig(r.rapier.median_step * 1e6),
                r.ratio()
            );
        }
        s.push_str(
            "\nJoint error, measured the same way for both engines from the bodies' \
             positions and angles after every step of the run: for pivots the distance \
             between the two world anchors, for pins the anchors' distance minus the pin's \
             length, for slides (ropes) the distance outside [min, max], for grooves the \
             distance of the anchor from the groove; the worst joint at the worst step \
             (max) and the worst joint averaged over the steps (mean). Rotary limits: how \
             far the relative angle went past its limit. Springs, motors, gears and \
             ratchets are not measured.\n\n\
             | scene | max, Tamias2D (m) | max, Rapier (m) | mean, Tamias2D (m) | \
             mean, Rapier (m) | rotary limit excess max, Tamias2D / Rapier (rad) | \
             left out of Rapier |\n|---|---:|---:|---:|---:|---:|---|\n",
        );
        for r in &self.joints {
            let (t, ra) = (&r.tamias.joint, &r.rapier.joint);
            let pos = |x: f64| if t.has_position { sig(x) } else { "-".into() };
            let angle = if t.has_angle {
                format!("{} / {}", sig(t.angle), sig(ra.angle))
            } else {
                "-".into()
            };
            let mut left: Vec<String> = Vec::new();
            for k in &r.left_out {
                let n = r.left_out.iter().filter(|x| *x == k).count();
                let item = format!("{n} × {k}");
                if !left.contains(&item) {
                    left.push(item);
                }
            }
            let _ = writeln!(
                s,
                "| `{}`{} | {} | {} | {} | {} | {} | {} |",
                r.name,
                dagger(r),
                pos(t.position),
                pos(ra.position),
                pos(t.position_mean()),
                pos(ra.position_mean()),
                angle,
                if left.is_empty() {
                    "-".to_owned()
                } else {
                    left.join(", ")
                }
            );
        }
        s.push_str(
            "\nThe mapping (Tamias2D's joints are Chipmunk's; Rapier 0.36's joints as built \
             by the side-by-side's converter):\n\n\
             | Tamias2D | Rapier 0.36 | note |\n|---|---|---|\n",
        );
        for (ours, theirs, note) in crate::common::JOINT_MAPPING {
            let _ = writeln!(s, "| {ours} | {theirs} | {note} |");
        }
        s.push_str(
            "\nThe hard joints keep Rapier's default joint softness (1 MHz, ζ = 1: rigid); \
             where Rapier only has a motor for a rigid Chipmunk constraint (a pin, a \
             simple motor), the motor gets that same stiffness. Chipmunk's \
             `error_bias` and `max_bias` have no Rapier counterpart; `max_force` is \
             mapped on motors. An angular limit or motor between two bodies that a \
             revolute or pin-slot joint already holds goes on that joint.\n",
        );
        s
    }

    /// The sleeping section: its own machine note, the table (awake and
    /// settled windows, bodies asleep, the saving against sleeping off) and
    /// the settings of each scene in both engines.
    fn sleep_section(&self) -> String {
        let m = Machine::read();
        let mut s = String::new();
        let load = |l: Option<f64>| l.map_or("?".to_owned(), |x| format!("{x:.2}"));
        let busy = self
            .sleep_load_before
            .into_iter()
            .chain(self.sleep_load_after)
            .any(|l| l > 1.0);
        let _ = writeln!(
            s,
            "Measured {} on {} cores ({}), {}, {}; `{}`, sleeping part {:.0} s. \
             1-minute load average {} before, {} after{}.\n",
            m.date,
            m.cores,
            m.model,
            m.rustc,
            m.engines,
            std::iter::once("perf_report".to_owned())
                .chain(std::env::args().skip(1))
                .collect::<Vec<_>>()
                .join(" "),
            self.sleep_elapsed,
            load(self.sleep_load_before),
            load(self.sleep_load_after),
            if busy {
                ": **measured while other builds ran**, so the times are noisy \
                 (the lockstep order spreads the noise over the three runs alike)"
            } else {
                ""
            }
        );
        let _ = writeln!(
            s,
            "| scene | dynamic bodies | steps {a0}–{a1}: Tamias2D µs/step | Rapier µs/step | \
             Tamias2D / Rapier | steps {s0}–{s1}: Tamias2D µs/step | Rapier µs/step | \
             Tamias2D / Rapier | asleep after step {s1}, Tamias2D / Rapier | \
             Tamias2D sleeping off, µs/step, steps {a0}–{a1} / {s0}–{s1} | \
             Tamias2D settled, on / off |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|",
            a0 = AWAKE.0,
            a1 = AWAKE.1,
            s0 = SETTLED.0,
            s1 = SETTLED.1
        );
        let asleep = |r: &crate::sleep::SleepRun| match r.all_asleep_from {
            Some(k) => format!("{} (all from step {k})", r.asleep),
            None => r.asleep.to_string(),
        };
        for r in &self.sleep {
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | **{:.2}** | {} | {} | **{:.2}** | {} / {} | {} / {} | \
                 {:.1} % |",
                r.name,
                r.dynamic,
                sig(r.tamias.awake * 1e6),
                sig(r.rapier.awake * 1e6),
                r.awake_ratio(),
                sig(r.tamias.settled * 1e6),
                sig(r.rapier.settled * 1e6),
                r.settled_ratio(),
                asleep(&r.tamias),
                asleep(&r.rapier),
                sig(r.tamias_off.awake * 1e6),
                sig(r.tamias_off.settled * 1e6),
                100.0 * r.tamias.settled / r.tamias_off.settled
            );
        }
        s.push_str(
            "\nThe settings of each scene (idle speed in the scene's length units per \
             second; Rapier's linear threshold is multiplied by its `length_unit`):\n\n\
             | scene | `length_unit` | Tamias2D `idle_speed_threshold` | Tamias2D \
             `sleep_time_threshold` (s) | Rapier `normalized_linear_threshold` | Rapier \
             `angular_threshold` (rad/s, idle / r_g per body) | Rapier `time_until_sleep` (s) |\n\
             |---|---:|---:|---:|---:|---:|---:|\n",
        );
        for r in &self.sleep {
            let (lo, hi) = r.rapier_angular;
            let angular = if (hi - lo).abs() <= 1e-6 * hi.abs() {
                sig(f64::from(lo))
            } else {
                format!("{}–{}", sig(f64::from(lo)), sig(f64::from(hi)))
            };
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {} | {} | {} | {} |",
                r.name,
                r.length_unit,
                sig(r.idle_speed),
                sig(r.sleep_time),
                sig(f64::from(r.rapier_linear)),
                angular,
                sig(r.sleep_time)
            );
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
        let mut joints = String::from(
            "scene,engine,iterations,substeps,joints,median_step_ms,timed_steps,\
             joint_error_max_m,joint_error_mean_m,rotary_limit_excess_rad,left_out\n",
        );
        for r in &self.joints {
            for (engine, e) in [("tamias2d", &r.tamias), ("rapier", &r.rapier)] {
                let _ = writeln!(
                    joints,
                    "{},{engine},{},{},{},{},{},{},{},{},{}",
                    r.name,
                    r.config.iterations,
                    r.config.substeps,
                    e.joints,
                    e.median_step * 1e3,
                    e.timed_steps,
                    e.joint.position,
                    e.joint.position_mean(),
                    e.joint.angle,
                    if engine == "rapier" {
                        r.left_out.join(";")
                    } else {
                        String::new()
                    }
                );
            }
        }
        if !self.joints.is_empty() {
            fs::write(data.join("perf_joints.csv"), joints)?;
        }
        let mut sleep = String::from(
            "scene,engine,sleeping,dynamic_bodies,awake_median_step_ms,settled_median_step_ms,\
             asleep_at_end,all_asleep_from_step,idle_speed,sleep_time,length_unit,\
             rapier_normalized_linear_threshold,rapier_angular_threshold_min,\
             rapier_angular_threshold_max\n",
        );
        for r in &self.sleep {
            for (engine, on, e) in [
                ("tamias2d", true, &r.tamias),
                ("rapier", true, &r.rapier),
                ("tamias2d", false, &r.tamias_off),
            ] {
                let _ = writeln!(
                    sleep,
                    "{},{engine},{},{},{},{},{},{},{},{},{},{},{},{}",
                    r.name,
                    if on { "on" } else { "off" },
                    r.dynamic,
                    e.awake * 1e3,
                    e.settled * 1e3,
                    e.asleep,
                    e.all_asleep_from.map_or(String::new(), |k| k.to_string()),
                    r.idle_speed,
                    r.sleep_time,
                    r.length_unit,
                    r.rapier_linear,
                    r.rapier_angular.0,
                    r.rapier_angular.1
                );
            }
        }
        if !self.sleep.is_empty() {
            fs::write(data.join("perf_sleeping.csv"), sleep)?;
        }
        Ok(())
    }

    /// Writes plots, CSV files and the marked sections of `performance.md`
    /// (the trade curves: of `tuning.md`); returns `performance.md`'s path.
    pub fn write(
        &self,
        side: bool,
        sweep: bool,
        joints: bool,
        sleep: bool,
    ) -> Result<PathBuf, Box<dyn std::error::Error>> {
        fs::create_dir_all(&self.out)?;
        self.write_csv()?;
        let mut sections = Vec::new();
        if side || sweep {
            sections.push(("machine", self.machine()));
        }
        if joints {
            sections.push(("joints", self.joint_section()));
        }
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
        if sleep {
            sections.push(("sleeping", self.sleep_section()));
        }
        if sweep {
            sections.push(("trade", self.trade_section()?));
        }
        // The trade curves belong to the settings guide (`tuning.md`), the
        // rest to `performance.md`.
        let path = self.out.join("performance.md");
        let tuning = self.out.join("tuning.md");
        let mut doc = fs::read_to_string(&path).unwrap_or_default();
        let mut tuning_doc = fs::read_to_string(&tuning).unwrap_or_default();
        for (key, body) in sections {
            if key == "trade" {
                tuning_doc = replace_section(&tuning_doc, key, &body);
            } else {
                doc = replace_section(&doc, key, &body);
            }
        }
        fs::write(&path, doc)?;
        if sweep {
            fs::write(&tuning, tuning_doc)?;
        }
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
