//! The "same bits" proof: every golden check of the scenes crate (each
//! golden scene on the canonical solver, the colored one and the soft step
//! on both kernel forms), stepped in the browser, against the checksum the
//! native test suite commits.
//!
//! The native goldens are compiled in (they are constants of
//! [`tamias2d_scenes::REGISTRY`] and [`tamias2d_scenes::goldens`], the
//! tables `scenes/tests/golden.rs` checks on every platform), so the page
//! needs no file beside the `.wasm`. The browser test (`tamias web
//! --check`) does not trust the page's verdict: it reads the checksums the
//! page computed and compares them with the tables itself.
use tamias2d_scenes::goldens::{self, Check};

/// Every golden check, in [`goldens::checks`]'s order: each scene with a
/// native golden on the canonical solver, the colored one, and the soft
/// step on the scalar and the wide kernels.
pub fn checks() -> Vec<Check> {
    goldens::checks()
}

/// Number of golden checks.
pub fn count() -> usize {
    checks().len()
}

/// One golden check run here.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The check's label ([`Check::label`]: the scene, then the solver).
    pub name: String,
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

/// Runs golden check `index` ([`checks`] order). Errors name the check and
/// what failed.
pub fn run(index: usize) -> Result<Outcome, String> {
    let all = checks();
    let check = all
        .get(index)
        .ok_or_else(|| format!("no golden check {index} (there are {})", all.len()))?;
    Ok(Outcome {
        name: check.label(),
        steps: check.steps,
        computed: check.run()?,
        golden: check.checksum,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_golden_scene_agrees_natively() -> Result<(), String> {
        // The checks of the cheapest golden scenes (one or two bodies)
        // run in a debug test in milliseconds; all of them run in the
        // browser test and in scenes/tests/golden.rs.
        let cheap: Vec<usize> = checks()
            .iter()
            .enumerate()
            .filter(|(_, c)| tamias2d_scenes::find(c.scene).is_some_and(|s| s.bodies <= 2))
            .map(|(i, _)| i)
            .take(8)
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
        assert!(run(count()).is_err_and(|e| e.contains("no golden check")));
    }
}
