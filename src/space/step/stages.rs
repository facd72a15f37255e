//! The stages of a sub-step, named once: the code's comments, the docs and
//! the tests use these names, in this order, rather than numbers.

/// A stage of a sub-step. [`Stage::ALL`] lists them in the order
/// [`Space::step`](crate::space::Space::step) runs them; a stage that a
/// world does not need is skipped (bullets without a bullet, wake and
/// sleep with sleeping off, the warm start with warm starting off).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// `p += (v + v_bias)·dt` and the same for the angle (or the body's
    /// custom position integrator), with the last solve's velocities.
    IntegratePositions,
    /// World-space geometry and bounding box of every shape that moved.
    ShapeCaches,
    /// Each bullet swept from its pose before the step to its new one
    /// against static and kinematic shapes, and put back at the time of
    /// impact.
    Bullets,
    /// Which body pairs joints keep from colliding (`collide_bodies`).
    JointFilter,
    /// Candidate pairs whose boxes overlap, in canonical pair order.
    Broadphase,
    /// A moving shape touching a sleeping one wakes its island (then
    /// shape caches and broadphase again).
    Wake,
    /// Every candidate pair filtered and collided; arbiters matched by
    /// feature id, begin and pre-solve handlers run; arbiters of pairs that
    /// stopped touching retired.
    Narrowphase,
    /// Velocities and inverse masses into the solver's contiguous array.
    SolverBodies,
    /// The solve order, and the contacts' and joints' rows: effective
    /// masses, bias and bounce (every division of the solver).
    Prepare,
    /// Gravity, damping and forces (or the body's custom velocity
    /// integrator).
    IntegrateVelocities,
    /// Last step's accumulated impulses re-applied, scaled by
    /// `min(dt / prev_dt, 1)`.
    WarmStart,
    /// `iterations` Gauss–Seidel passes over the contacts, then the joints
    /// (the soft step: one pass of soft rows, with bias).
    Solve,
    /// The soft step only: one pass over the contacts and joints without
    /// bias, after the positions moved, taking back the velocity the bias
    /// added.
    Relax,
    /// The soft step only, after its sub-steps: contacts that approached
    /// faster than the restitution threshold bounce.
    Restitution,
    /// Accumulated impulses into the arbiters and joints, velocities into
    /// the bodies.
    Store,
    /// Counts of bodies whose position or velocity saturated.
    Diagnostics,
    /// Post-solve handlers; first contacts become normal.
    PostSolve,
    /// Idle times, islands, and islands that fall asleep.
    Sleep,
    /// Post-step callbacks, in the order queued (the space unlocked).
    PostStepCallbacks,
}

impl Stage {
    /// Every stage of the sequential solver, in the order a sub-step runs
    /// them (the soft step's order is [`SOFT_STEP`](Self::SOFT_STEP)).
    pub const ALL: [Stage; 17] = [
        Stage::IntegratePositions,
        Stage::ShapeCaches,
        Stage::Bullets,
        Stage::JointFilter,
        Stage::Broadphase,
        Stage::Wake,
        Stage::Narrowphase,
        Stage::SolverBodies,
        Stage::Prepare,
        Stage::IntegrateVelocities,
        Stage::WarmStart,
        Stage::Solve,
        Stage::Store,
        Stage::Diagnostics,
        Stage::PostSolve,
        Stage::Sleep,
        Stage::PostStepCallbacks,
    ];

    /// The soft step's stages in run order: the first seven once per step,
    /// integrate velocities … relax in every one of its sub-steps, the rest
    /// once at the end.
    pub const SOFT_STEP: [Stage; 19] = [
        Stage::ShapeCaches,
        Stage::JointFilter,
        Stage::Broadphase,
        Stage::Wake,
        Stage::Narrowphase,
        Stage::SolverBodies,
        Stage::Prepare,
        Stage::IntegrateVelocities,
        Stage::WarmStart,
        Stage::Solve,
        Stage::IntegratePositions,
        Stage::Relax,
        Stage::Restitution,
        Stage::Store,
        Stage::Bullets,
        Stage::Diagnostics,
        Stage::PostSolve,
        Stage::Sleep,
        Stage::PostStepCallbacks,
    ];

    /// The stage's name in the docs: "integrate positions", "shape
    /// caches", ….
    pub const fn name(self) -> &'static str {
        match self {
            Stage::IntegratePositions => "integrate positions",
            Stage::ShapeCaches => "shape caches",
            Stage::Bullets => "bullets",
            Stage::JointFilter => "joint filter",
            Stage::Broadphase => "broadphase",
            Stage::Wake => "wake",
            Stage::Narrowphase => "narrowphase",
            Stage::SolverBodies => "solver bodies",
            Stage::Prepare => "prepare",
            Stage::IntegrateVelocities => "integrate velocities",
            Stage::WarmStart => "warm start",
            Stage::Solve => "solve",
            Stage::Relax => "relax",
            Stage::Restitution => "restitution",
            Stage::Store => "store",
            Stage::Diagnostics => "diagnostics",
            Stage::PostSolve => "post-solve",
            Stage::Sleep => "sleep",
            Stage::PostStepCallbacks => "post-step callbacks",
        }
    }
}
