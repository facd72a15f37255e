//! What the [`Limits`] check of a world: its settings, its counts and the
//! candidate pairs its first step would start from. Here, beside the state
//! it reads, so that the limits themselves (`crate::limits`) sit below
//! everything that carries them.
use crate::body::BodyType;
use crate::broadphase::{Proxy, StaticTree};
use crate::limits::{check, LimitError, Limits};

use super::{Settings, WorldState};

impl Limits {
    /// Checks settings' sub-steps and solver passes.
    pub fn check_settings(&self, settings: &Settings) -> Result<(), LimitError> {
        check("sub-steps", u64::from(settings.substeps), self.max_substeps)?;
        // The soft step's passes: a solve and a relax in each of its
        // sub-steps (its `iterations` setting does not apply).
        let per_step = match settings.solver {
            super::Solver::Sequential => u64::from(settings.iterations),
            super::Solver::Soft(soft) => u64::from(soft.substeps).saturating_mul(2),
        };
        let passes = per_step.saturating_mul(u64::from(settings.substeps));
        check(
            "solver passes (iterations x sub-steps)",
            passes,
            self.max_solver_passes,
        )
    }

    /// Checks what a world state holds and asks of every step: counts of
    /// bodies, shapes, constraints and contact pairs, and the settings.
    /// Cheap (no geometry): what a frame is checked for at load.
    pub fn check_counts(&self, state: &WorldState) -> Result<(), LimitError> {
        let count = |n: usize| u64::try_from(n).unwrap_or(u64::MAX);
        check("bodies", count(state.bodies.len()), self.max_bodies)?;
        check("shapes", count(state.shapes.len()), self.max_shapes)?;
        check(
            "constraints",
            count(state.constraints.len()),
            self.max_constraints,
        )?;
        let arbiters = state
            .arbiters
            .len()
            .saturating_add(state.dormant_arbiters.len());
        check("contact pairs (arbiters)", count(arbiters), self.max_pairs)?;
        self.check_settings(&state.settings)
    }

    /// [`check_counts`](Self::check_counts), then the candidate pairs the
    /// world's first step would start from (the boxes of its shapes as
    /// they are, every pair with a body that is not static). Counting
    /// stops at the limit, so the check costs at most a broadphase of the
    /// world: what a full snapshot and a replay's start are checked for.
    pub fn check_state(&self, state: &WorldState) -> Result<(), LimitError> {
        self.check_counts(state)?;
        if self.max_pairs == u64::MAX {
            return Ok(());
        }
        let (mut moving, mut statics) = (Vec::new(), Vec::new());
        for (h, shape) in state.shapes.iter() {
            let Some(body) = state.bodies.get(shape.body) else {
                continue;
            };
            let proxy = Proxy {
                index: h.index(),
                bb: shape
                    .geometry()
                    .to_world(body.position(), body.rotation())
                    .bb(),
            };
            if body.body_type() == BodyType::Static {
                statics.push(proxy);
            } else {
                moving.push(proxy);
            }
        }
        if pairs_within(&mut moving, &StaticTree::build(statics), self.max_pairs) {
            Ok(())
        } else {
            Err(LimitError {
                limit: "candidate pairs",
                value: self.max_pairs.saturating_add(1),
                max: self.max_pairs,
            })
        }
    }
}

/// Whether the boxes of `moving` overlap each other and the boxes of
/// `statics` in at most `limit` pairs: the step's broadphase count (a sweep
/// along x, the static tree), stopped as soon as it passes the limit.
fn pairs_within(moving: &mut [Proxy], statics: &StaticTree, limit: u64) -> bool {
    // The count does not depend on the order of equal left edges.
    moving.sort_unstable_by_key(|p| p.bb.l);
    let mut count = 0u64;
    let mut rest: &[Proxy] = moving;
    while let Some((a, later)) = rest.split_first() {
        rest = later;
        for b in later {
            if b.bb.l > a.bb.r {
                break;
            }
            if a.bb.b <= b.bb.t && b.bb.b <= a.bb.t {
                count = count.saturating_add(1);
            }
        }
        statics.query(&a.bb, |_| count = count.saturating_add(1));
        if count > limit {
            return false;
        }
    }
    true
}
