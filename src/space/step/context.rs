//! What a sub-step computes once and every stage reads: the per-`dt`
//! constants, the solver switches and the contact solver's parameters
//! ([`StepContext`]); and the step driver's own caches ([`StepCache`]).
use crate::body::BodyHandle;
use crate::math::{exp, Real, Vect};
use crate::solver::{ContactParams, SolverSwitches};

use super::super::{Settings, StepStats};
use super::shape_caches::CachePiece;

/// The per-`dt` constants: the only `pow`, reciprocal and such of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DtConstants {
    pub(crate) dt: Real,
    pub(crate) dt_inv: Real,
    /// `damping^dt`.
    pub(crate) damping: Real,
    /// `1 − collision_bias^dt`.
    pub(crate) bias_coef: Real,
}

/// The constants and switches of one sub-step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepContext {
    /// The sub-step's length.
    pub(crate) dt: Real,
    /// `1/dt`.
    pub(crate) dt_inv: Real,
    /// `damping^dt`.
    pub(crate) damping: Real,
    /// The contact solver's constants, with the solver switches.
    pub(crate) contact: ContactParams,
}

impl StepContext {
    /// The context of a sub-step of `dt` under `settings`; the per-`dt`
    /// constants come from `cache` when it holds them for this `dt`.
    pub(crate) fn new(
        dt: Real,
        settings: &Settings,
        cache: &mut [Option<DtConstants>; 2],
    ) -> StepContext {
        let c = match cache.iter().flatten().find(|c| c.dt == dt) {
            Some(c) => *c,
            None => {
                let c = DtConstants {
                    dt,
                    dt_inv: dt.recip(),
                    damping: exp::pow(settings.damping, dt),
                    bias_coef: Real::ONE - exp::pow(settings.collision_bias, dt),
                };
                *cache = [Some(c), cache[0]];
                c
            }
        };
        let switches = SolverSwitches {
            warm_starting: settings.warm_starting,
            friction: settings.friction,
            restitution: settings.restitution,
            bias_impulses: settings.bias_impulses,
        };
        StepContext {
            dt: c.dt,
            dt_inv: c.dt_inv,
            damping: c.damping,
            contact: ContactParams {
                dt_inv: c.dt_inv,
                slop: settings.collision_slop,
                bias_coef: c.bias_coef,
                max_bias: Real::MAX,
                switches,
            },
        }
    }
}

/// The step driver's caches in the space (not simulation state).
#[derive(Default)]
pub(crate) struct StepCache {
    /// Constants of the last two distinct step lengths (cleared when
    /// settings change): two, because sub-steps of a step that `substeps`
    /// does not divide evenly differ by one ulp.
    pub(crate) dt_constants: [Option<DtConstants>; 2],
    /// Forces and torques set before a sub-stepped step, re-applied before
    /// each of its later sub-steps.
    pub(crate) frame_forces: Vec<(BodyHandle, Vect, Real)>,
    /// Counters of the last (sub-)step.
    pub(crate) stats: StepStats,
    /// With threads: the pieces of the shape-cache stage and what each
    /// found (scratch, kept so that a warm step does not allocate).
    pub(crate) cache_pieces: Vec<CachePiece>,
}
