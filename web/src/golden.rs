//! The "same bits" proof: every golden scene of the registry, stepped in
//! the browser, against the checksum the native test suite commits.
//!
//! The native goldens are compiled in (they are constants of
//! [`tamias2d_scenes::REGISTRY`], the table `scenes/tests/golden.rs` checks
//! on every platform), so the page needs no file beside the `.wasm`. The
//! browser test (`tamias web --check`) does not trust the page's verdict: it
//! reads the checksums the page computed and compares them with the
//! registry itself.
use tamias2d_scenes::{Golden, REGISTRY};

/// The scenes with a native golden, in registry order.
pub fn scenes() -> impl Iterator<Item = (&'static str, Golden)> {
    REGISTRY
        .iter()
        .filter_map(|s| s.golden.map(|g| (s.name, g)))
}

/// Number of golden scenes.
pub fn count() -> usize {
    scenes().count()
}

/// One golden scene run here.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Registry name.
    pub name: &'static str,
    /// Steps taken from the built scene.
    pub steps: u32,
    /// The checksum this build computed after them.
    pub computed: u64,
    /// The native golden.
    pub golden: u64,
}

impl Outcome {
    /// The computed checksum equals the golden.
    pub fn agrees(&self) -> bool {
        self.computed == self.golden
    }

    /// One JSON object: `{"name":…,"steps":…,"computed":"0x…","golden":"0x…"}`
    /// (checksums as hex strings: JavaScript numbers hold 53 bits).
    pub fn to_json(&self) -> String {
        serde_json::json!({
            "name": self.name,
            "steps": self.steps,
            "computed": format!("{:#018x}", self.computed),
            "golden": format!("{:#018x}", self.golden),
        })
        .to_string()
    }
}

/// Builds golden scene `index` (registry order) and steps it to its
/// golden's step count. Errors name the scene and what failed.
pub fn run(index: usize) -> Result<Outcome, String> {
    let (name, golden) = scenes()
        .nth(index)
        .ok_or_else(|| format!("no golden scene {index} (there are {})", count()))?;
    let desc = tamias2d_scenes::builtin(name).ok_or_else(|| format!("{name}: not built in"))?;
    let mut world = desc.build().map_err(|e| format!("{name}: {e}"))?;
    world
        .step_n(golden.steps)
        .map_err(|e| format!("{name}: {e}"))?;
    Ok(Outcome {
        name,
        steps: golden.steps,
        computed: world.space.checksum(),
        golden: golden.checksum,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_golden_scene_agrees_natively() -> Result<(), String> {
        // The cheapest golden scenes (one or two bodies) run in a debug
        // test in milliseconds; all of them run in the browser test and in
        // scenes/tests/golden.rs.
        let cheap: Vec<usize> = scenes()
            .enumerate()
            .filter(|(_, (name, _))| tamias2d_scenes::find(name).is_some_and(|s| s.bodies <= 2))
            .map(|(i, _)| i)
            .take(3)
            .collect();
        assert!(!cheap.is_empty());
        for i in cheap {
            let outcome = run(i)?;
            assert!(outcome.agrees(), "{outcome:?}");
            assert!(outcome
                .to_json()
                .contains(&format!("{:#018x}", outcome.golden)));
        }
        Ok(())
    }

    #[test]
    fn an_unknown_index_is_an_error() {
        assert!(run(count()).is_err_and(|e| e.contains("no golden scene")));
    }
}
