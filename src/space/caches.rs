//! What the step derives from the state and keeps between steps (never
//! serialized): [`Caches`], one struct per stage. The test of the boundary: two spaces with equal world
//! states produce the same bits whatever their caches held.
use crate::arbiter::ArbiterBuffers;
use crate::broadphase::BroadphaseCache;
use crate::constraint::solve::ConstraintScratch;
use crate::solver::contact_solver::ContactSolver;

use super::body_shapes::BodyShapes;
use super::ccd::CcdCache;
use super::frame_state::FrameState;
use super::islands::SleepScratch;

use super::step::{ShapeCache, StepCache};

/// Caches derived from the state, never serialized: one struct per stage,
/// each defined by the module of its stage.
#[derive(Default)]
pub(crate) struct Caches {
    /// The shape-cache stage: world-space geometry and box of each shape, indexed by shape
    /// slot (`None` for free slots); read by the broadphase and narrowphase stages.
    pub(crate) shapes: Vec<Option<ShapeCache>>,
    /// The broadphase stage (`crate::broadphase`).
    pub(crate) broadphase: BroadphaseCache,
    /// The narrowphase stage ([`crate::arbiter`]).
    pub(crate) arbiters: ArbiterBuffers,
    /// The solver stages, solver bodies to store (`crate::solver`).
    pub(crate) solver: ContactSolver,
    /// The soft step's contact rows and the bodies' motion
    /// (`crate::solver::soft_contact`).
    pub(crate) soft_contacts: crate::solver::soft_contact::SoftContacts,
    /// The joint filter, and the joints' part of prepare to store
    /// ([`crate::constraint`]).
    pub(crate) constraints: ConstraintScratch,
    /// The step driver's own (`space/step/`): `dt` constants, sub-step
    /// forces, counters.
    pub(crate) step: StepCache,
    /// Each body's shapes (not a stage: kept by the building operations).
    pub(crate) body_shapes: BodyShapes,
    /// The bullets stage's sweep (`space/ccd.rs`).
    pub(crate) ccd: CcdCache,
    /// The sleep stage's buffers (`space/sleep.rs`).
    pub(crate) sleep: SleepScratch,
    /// The level's digest and slot runs (`space/level.rs`), computed on
    /// first use; `None` after a change to the level.
    pub(crate) level: super::level::LevelCache,
    /// Body slots given out by `body_mut` while not static since the level
    /// was last settled (one may have been made static), each with whether
    /// it was dynamic then (one may have been made static or kinematic).
    pub(crate) level_suspects: Vec<(u32, bool)>,
    /// The frame `snapshot::Space::load_frame_snapshot` decodes into and
    /// swaps in (afterwards, the frame it replaced): its buffers are
    /// reused from load to load.
    pub(crate) spare_frame: FrameState,
    /// The threads the step may use ([`Space::set_threads`](super::Space::set_threads)).
    pub(crate) threads: crate::threads::Threads,
    /// The compiled form of the contact passes ([`Space::set_kernels`](super::Space::set_kernels)).
    pub(crate) kernels: crate::solver::Kernels,
}
