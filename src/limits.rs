//! Limits for worlds from untrusted sources: how much a peer's snapshot,
//! frame or replay may ask of the receiver.
//!
//! A valid state can still be expensive: a snapshot whose settings ask for
//! 1,024 iterations of 64 sub-steps, or 3,000 circles piled within
//! millimetres of each other (4.5 million candidate pairs), takes seconds
//! per step. [`Limits`] bounds what a world may hold (bytes, bodies,
//! shapes, constraints, contact pairs), what its settings may ask
//! (sub-steps, and solver passes per step: iterations × sub-steps), how
//! long a replay may
//! run, and the work of one step (candidate pairs found by the
//! broadphase). Every loading path checks it before anything changes;
//! over-limit input is an error naming the limit and the value
//! ([`LimitError`]), never a silent cap that changes the simulation.
//! Full snapshots and replay starts are also checked for the candidate
//! pairs of the world as loaded; frames (the per-frame path of a rollback
//! game) only for counts and settings, their pairs being bounded by the
//! first step, which stops at the limit (a broadphase at every frame load
//! would add about 40% to it).
//!
//! Where it applies:
//! * a [`Space`](crate::space::Space) carries its limits
//!   ([`Space::set_limits`](crate::space::Space::set_limits)); they check
//!   what it loads ([`Space::load_snapshot`](crate::space::Space::load_snapshot),
//!   [`Space::load_frame_snapshot`](crate::space::Space::load_frame_snapshot),
//!   a replay's start) and bound its step's candidate pairs;
//! * the free functions take them explicitly
//!   ([`snapshot::load_with`](crate::snapshot::load_with),
//!   [`snapshot::decode_state_with`](crate::snapshot::decode_state_with),
//!   [`Replay::from_bytes_with`](crate::replay::Replay::from_bytes_with));
//!   their short forms use [`Limits::UNTRUSTED`].
//!
//! The default is [`Limits::UNTRUSTED`]; a game that trusts a source (its
//! own saves, a level file it ships) says so with [`Limits::TRUSTED`].
//! `docs/architecture.md` ("Untrusted input") states the threat model and
//! the measured worst step under the defaults.
use core::fmt;

/// What a world, its settings and its step may cost; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Bytes of a snapshot, frame or replay.
    pub max_bytes: u64,
    /// Bodies of a world (static ones included).
    pub max_bodies: u64,
    /// Shapes of a world (a level's static shapes included).
    pub max_shapes: u64,
    /// Constraints (joints) of a world.
    pub max_constraints: u64,
    /// Solver passes per step: `Settings::iterations × Settings::substeps`
    /// (on the soft step, `2 × SoftStep::substeps × Settings::substeps`).
    pub max_solver_passes: u64,
    /// Sub-steps per step (`Settings::substeps`): each one collides
    /// again, so it costs about a whole step.
    pub max_substeps: u64,
    /// Candidate pairs (overlapping bounding boxes with a body that moves)
    /// of a world as loaded (full snapshots and replay starts) and of each
    /// step's broadphase, and contact pairs (arbiters, live and dormant) a
    /// world holds. A step that finds more stops with
    /// `SpaceError::OverLimit` (see `Space::step`).
    pub max_pairs: u64,
    /// Frames of a replay.
    pub max_replay_frames: u64,
    /// A frame whose settings differ from the receiving world's is refused
    /// (peers of one game step with the same settings).
    pub same_settings: bool,
}

impl Limits {
    /// For bytes from a peer or a player: room for the largest standard
    /// scenes (`pyramid_100`'s 5,051 bodies, a 30,000-segment level) with
    /// a margin; a forged world within them steps within 10× a normal step
    /// of the largest world they admit (measured: `docs/architecture.md`).
    pub const UNTRUSTED: Limits = Limits {
        max_bytes: 64 << 20,
        max_bodies: 16_384,
        max_shapes: 65_536,
        max_constraints: 16_384,
        max_solver_passes: 48,
        max_substeps: 4,
        max_pairs: 65_536,
        max_replay_frames: 1 << 22,
        same_settings: false,
    };

    /// No limit: for the game's own saves and files it ships.
    pub const TRUSTED: Limits = Limits {
        max_bytes: u64::MAX,
        max_bodies: u64::MAX,
        max_shapes: u64::MAX,
        max_constraints: u64::MAX,
        max_solver_passes: u64::MAX,
        max_substeps: u64::MAX,
        max_pairs: u64::MAX,
        max_replay_frames: u64::MAX,
        same_settings: false,
    };

    /// `max_pairs` as a count the broadphase compares against.
    pub(crate) fn pair_budget(&self) -> usize {
        usize::try_from(self.max_pairs).unwrap_or(usize::MAX)
    }

    /// Checks a length of bytes.
    pub fn check_bytes(&self, len: usize) -> Result<(), LimitError> {
        check(
            "bytes",
            u64::try_from(len).unwrap_or(u64::MAX),
            self.max_bytes,
        )
    }

    /// Checks a replay's frame count.
    pub fn check_replay_frames(&self, frames: usize) -> Result<(), LimitError> {
        let n = u64::try_from(frames).unwrap_or(u64::MAX);
        check("replay frames", n, self.max_replay_frames)
    }
}

impl Default for Limits {
    /// [`Limits::UNTRUSTED`]: safe unless the source is known.
    fn default() -> Limits {
        Limits::UNTRUSTED
    }
}

/// `value` over `max`, as an error naming the limit.
pub(crate) fn check(limit: &'static str, value: u64, max: u64) -> Result<(), LimitError> {
    if value > max {
        Err(LimitError { limit, value, max })
    } else {
        Ok(())
    }
}

/// Input over one of the [`Limits`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LimitError {
    /// Which limit ("bodies", "solver passes (iterations x sub-steps)", …).
    pub limit: &'static str,
    /// The input's value (for candidate pairs: the first count over the
    /// limit, where counting stopped).
    pub value: u64,
    /// The limit.
    pub max: u64,
}

impl fmt::Display for LimitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.limit == "candidate pairs" {
            write!(f, "{}: more than the limit of {}", self.limit, self.max)
        } else {
            write!(
                f,
                "{}: {} over the limit of {}",
                self.limit, self.value, self.max
            )
        }
    }
}

impl std::error::Error for LimitError {}
