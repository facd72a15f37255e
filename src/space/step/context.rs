//! What a sub-step computes once and every stage reads: the per-`dt`
//! constants, the solver switches and the contact solver's parameters
//! ([`StepContext`]); the step driver's own caches ([`StepCache`]) and the
//! counters of the last step ([`StepStats`]).
use crate::body::BodyHandle;
use crate::math::{exp, Real, Vect};
use crate::solver::{ContactParams, SolverSwitches};

use super::super::Settings;
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
    /// The same for the sub-steps of a soft step.
    pub(crate) soft_forces: Vec<(BodyHandle, Vect, Real)>,
    /// Counters of the last (sub-)step.
    pub(crate) stats: StepStats,
    /// With threads: the pieces of the shape-cache stage and what each
    /// found (scratch, kept so that a warm step does not allocate).
    pub(crate) cache_pieces: Vec<CachePiece>,
}

/// Counters of the last step, for diagnostics and benchmarks (not state).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Shape pairs whose bounding boxes overlap (broadphase output).
    pub candidate_pairs: u32,
    /// Pairs that touch (narrowphase found contacts).
    pub touching_pairs: u32,
    /// Contacts sent to the solver.
    pub solver_contacts: u32,
    /// Narrowphase calls where GJK or EPA stopped at its iteration cap
    /// (MIS WARN_GJK/WARN_EPA): the scene is outside the tested envelope.
    pub iteration_cap_hits: u32,
    /// Bodies that ended the step with a component of position, velocity
    /// or angular velocity at `Real::MIN` or `Real::MAX`: saturated, i.e.
    /// outside the representable range (see the safe envelope in
    /// `docs/numerics.md`). Zero for every scene inside the envelope.
    /// Sleeping bodies are not counted: they do not move, and were
    /// counted in the steps before they fell asleep.
    pub saturated_bodies: u32,
    /// Dynamic bodies with infinite mass (no explicit mass and no shape
    /// with mass or density): gravity moves them but no contact can stop
    /// them, so they fall through everything — almost always a missing
    /// density. [`Space::step`](crate::space::Space::step) refuses to start with one
    /// ([`SpaceError::MasslessDynamicBody`](crate::space::SpaceError::MasslessDynamicBody)), so this is 0 unless a
    /// post-step callback made one between two sub-steps of a step. Counted
    /// when the solver loads the bodies.
    pub massless_dynamic_bodies: u32,
}
