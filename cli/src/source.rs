//! Where a scene comes from (a built-in name, the showcase, or a JSON scene
//! file), the command-line overrides of its settings, and the running world
//! the commands step (a [`ScriptedWorld`]).
use std::path::Path;
use tamias2d::limits::Limits;

use fixed::types::I32F32;
use tamias2d::real;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{self as scenes, BodyDesc, BodyKind, SceneDesc, ScriptedWorld, ShapeDesc};

/// `auto`, `scalar`, `wide` or `portable` (`--kernels`).
pub fn parse_kernels(s: &str) -> Result<tamias2d::space::Kernels, String> {
    use tamias2d::space::Kernels;
    match s {
        "auto" => Ok(Kernels::Auto),
        "scalar" => Ok(Kernels::Scalar),
        "wide" => Ok(Kernels::Wide),
        "portable" => Ok(Kernels::Portable),
        _ => Err(format!(
            "{s:?}: the kernels are auto, scalar, wide or portable"
        )),
    }
}

/// Name of the CLI's own scene, what `tamias` with no arguments runs.
pub const SHOWCASE: &str = "showcase";
/// One-line description of the showcase for `tamias list`.
pub const SHOWCASE_ABOUT: &str = "pyramid_20 hit by a heavy ball (what `tamias` alone runs)";

/// The showcase: `pyramid_20` and a heavy ball (radius 1.25 m, density 10,
/// about 49 kg against the boxes' 1 kg) thrown at the pyramid's left flank
/// at 20 m/s. Built from exact literals like the built-in scenes, so it is
/// the same bits everywhere. 480 steps (8 s): the hit, the collapse, and
/// the debris coming to rest.
pub fn showcase() -> SceneDesc {
    // pyramid_20 is a listed scene: builtin() cannot return None for it.
    let mut desc =
        scenes::builtin("pyramid_20").unwrap_or_else(|| SceneDesc::new("", Real::ONE, 0));
    SHOWCASE.clone_into(&mut desc.name);
    desc.steps = 480;
    let ball = BodyDesc::new(BodyKind::Dynamic, Vect::new(real!(-19), real!(5.5)))
        .labeled("ball")
        .moving(Vect::new(real!(20), real!(2)))
        .with_shape(
            ShapeDesc::circle(real!(1.25))
                .material(real!(0.6), Real::ZERO)
                .density(real!(10)),
        );
    desc.bodies.push(ball);
    desc
}

/// Overrides from the command line.
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    /// `--dt`.
    pub dt: Option<Real>,
    /// `--iterations`.
    pub iterations: Option<u32>,
    /// `--colored-solver`.
    pub colored_solver: bool,
    /// `--solver`.
    pub solver: Option<SolverChoice>,
    /// `--no-sleep`.
    pub no_sleep: bool,
    /// `--trusted`: files load without the untrusted-input limits.
    pub trusted: bool,
}

impl Overrides {
    /// The limits files load under: [`Limits::UNTRUSTED`] unless
    /// `--trusted`.
    pub fn limits(&self) -> Limits {
        if self.trusted {
            Limits::TRUSTED
        } else {
            Limits::UNTRUSTED
        }
    }
}

/// `--solver`'s values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SolverChoice {
    /// Sequential impulses (the MIS's solver).
    Sequential,
    /// The soft step.
    Soft,
    /// The soft step with the narrow contact kernels
    /// (`ContactPrecision::Narrow`).
    SoftNarrow,
}

impl SolverChoice {
    /// Switches `settings` to this solver: the soft step scaled to the
    /// scene's length unit with one whole-pipeline sub-step
    /// (`SettingsDesc::use_soft_step`), or sequential impulses.
    pub fn apply(self, settings: &mut scenes::SettingsDesc) {
        match self {
            SolverChoice::Sequential => settings.solver = scenes::SolverDesc::Sequential,
            SolverChoice::Soft => settings.use_soft_step(),
            SolverChoice::SoftNarrow => settings.use_narrow_soft_step(),
        }
    }
}

/// Every core of this machine (1 if the system will not say).
pub fn all_cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// The scene `arg` names: a built-in scene, `showcase`, or a JSON file
/// (anything else that exists as a file, or ends in `.json`).
pub fn load(arg: &str, overrides: Overrides) -> Result<SceneDesc, String> {
    let mut desc = if let Some(desc) = scenes::builtin(arg) {
        desc
    } else if arg == SHOWCASE {
        showcase()
    } else if Path::new(arg).is_file() || arg.ends_with(".json") {
        let desc = read_scene_file(Path::new(arg), &overrides.limits())?;
        // A file may come from anywhere: the world it builds is held to
        // the same limits as a snapshot.
        let world = build(&desc)?;
        overrides
            .limits()
            .check_state(world.space.state())
            .map_err(|e| format!("{arg}: {e} (pass --trusted to lift the limits)"))?;
        desc
    } else {
        return Err(format!(
            "unknown scene {arg:?}: not a built-in scene nor a file (`tamias list` shows the scenes)"
        ));
    };
    if let Some(dt) = overrides.dt {
        desc.dt = dt;
    }
    desc.settings.colored_solver |= overrides.colored_solver;
    if let Some(choice) = overrides.solver {
        choice.apply(&mut desc.settings);
    }
    if overrides.no_sleep {
        desc.settings.sleep_time_threshold = tamias2d::space::SLEEP_NEVER;
    }
    if let Some(n) = overrides.iterations {
        desc.settings.iterations = n;
    }
    Ok(desc)
}

/// A scene description from a JSON file. serde_json's errors carry the line
/// and column.
pub fn read_scene_file(path: &Path, limits: &Limits) -> Result<SceneDesc, String> {
    let len = std::fs::metadata(path)
        .map_err(|e| format!("{}: {e}", path.display()))?
        .len();
    limits
        .check_bytes(usize::try_from(len).unwrap_or(usize::MAX))
        .map_err(|e| {
            format!(
                "{}: {e} (pass --trusted to lift the limits)",
                path.display()
            )
        })?;
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: invalid scene file: {e}", path.display()))
}

/// Parses a time step: an exact decimal (`0.01`, `0.0166666666`), rounded
/// to the nearest I32F32 by `fixed`, or a ratio of integers (`1/60`, the
/// built-in scenes' step, bit for bit). Never goes through a float. Must be
/// > 0.
pub fn parse_dt(s: &str) -> Result<Real, String> {
    let dt = match s.split_once('/') {
        Some((num, den)) => {
            let num: i32 = num.trim().parse().map_err(|_| ratio_error(s))?;
            let den: i32 = den.trim().parse().map_err(|_| ratio_error(s))?;
            if den <= 0 {
                return Err(ratio_error(s));
            }
            Real::ratio(num, den)
        }
        None => I32F32::from_str(s.trim())
            .map(Real::from_fixed)
            .map_err(|e| format!("not a decimal number ({e}); write e.g. 0.01 or 1/60"))?,
    };
    if dt.is_positive() {
        Ok(dt)
    } else {
        Err("the time step must be > 0".to_owned())
    }
}

fn ratio_error(s: &str) -> String {
    format!("{s:?} is not a ratio of integers with a positive denominator, e.g. 1/60")
}

/// Builds `desc` into the world a command steps (a plain snapshot loads as
/// a [`ScriptedWorld`] with an empty script, so every command steps one
/// kind of world).
pub fn build(desc: &SceneDesc) -> Result<ScriptedWorld, String> {
    desc.build()
        .map_err(|e| format!("scene {:?}: {e}", desc.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_dt_ratio_matches_builtin_step() {
        let builtin = scenes::builtin("pyramid_20").unwrap().dt;
        assert_eq!(parse_dt("1/60").unwrap(), builtin);
        assert_eq!(parse_dt(&builtin.to_string()).unwrap(), builtin);
    }

    #[test]
    fn parse_dt_decimal_is_exact() {
        assert_eq!(parse_dt("0.5").unwrap(), Real::HALF);
        assert_eq!(parse_dt("0.015625").unwrap(), Real::ratio(1, 64));
        // `fixed` also reads exponents, exactly.
        assert_eq!(parse_dt("1e-3").unwrap(), parse_dt("0.001").unwrap());
    }

    #[test]
    fn parse_dt_rejects_bad_input() {
        for bad in ["0", "-0.1", "abc", "1/0", "1/-60", "x/60", ""] {
            assert!(parse_dt(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn showcase_builds_with_ball() {
        let scene = showcase().build().unwrap();
        assert_eq!(scene.space.bodies().count(), 212);
        assert!(scene.body("ball").is_some());
    }
}
