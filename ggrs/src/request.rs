//! The request loop: [`fulfil`] serves what a GGRS session asks for, a
//! [`Tally`] counts it, [`Error`] says what went wrong.
use core::fmt;
use core::hash::Hash;
use std::fmt::Debug;

use ggrs::{Frame, GgrsError, GgrsRequest};
use tamias2d::replay::BoxError;

use crate::game::{GgrsConfig, RollbackGame};

/// What went wrong in a session or its request loop.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// GGRS refused a call, or a SyncTest's re-simulation disagreed with
    /// the first run ([`GgrsError::MismatchedChecksum`]: the game is not
    /// deterministic under rollback).
    Ggrs(GgrsError),
    /// A request named a frame below 0 (GGRS's "no frame"): saving it
    /// would make GGRS panic, so the loop stops instead.
    InvalidFrame(Frame),
    /// GGRS asked to load a frame that was never saved.
    NothingSaved(Frame),
    /// The game's [`load`](RollbackGame::load) failed.
    Load {
        /// The frame GGRS asked for.
        frame: Frame,
        /// The game's error.
        source: BoxError,
    },
    /// The game's [`advance`](RollbackGame::advance) failed.
    Advance {
        /// The frame being advanced from, when a save or load in the same
        /// request list named it.
        frame: Option<Frame>,
        /// The game's error.
        source: BoxError,
    },
    /// A socket could not be opened.
    Io(std::io::Error),
    /// A peer saw another peer's checksum differ from its own.
    Desync {
        /// The peer (in [`run_loopback`](crate::run_loopback), its index).
        peer: usize,
        /// The frame whose checksums differ.
        frame: Frame,
        /// This peer's checksum.
        local: u128,
        /// The other peer's.
        remote: u128,
    },
    /// A peer lost its connection to another.
    Disconnected {
        /// The peer that saw the disconnection.
        peer: usize,
    },
    /// The peers did not get there in the time given.
    Timeout {
        /// Each peer's current frame when time ran out.
        frames: [Frame; 2],
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Ggrs(e) => write!(f, "GGRS: {e}"),
            Error::InvalidFrame(frame) => write!(f, "request for invalid frame {frame}"),
            Error::NothingSaved(frame) => write!(f, "no state saved for frame {frame}"),
            Error::Load { frame, source } => write!(f, "loading frame {frame}: {source}"),
            Error::Advance {
                frame: Some(frame),
                source,
            } => write!(f, "advancing frame {frame}: {source}"),
            Error::Advance {
                frame: None,
                source,
            } => write!(f, "advancing a frame: {source}"),
            Error::Io(e) => write!(f, "socket: {e}"),
            Error::Desync {
                peer,
                frame,
                local,
                remote,
            } => write!(
                f,
                "peer {peer}: desync at frame {frame}: {local:#x} vs {remote:#x}"
            ),
            Error::Disconnected { peer } => write!(f, "peer {peer}: a peer disconnected"),
            Error::Timeout { frames } => write!(
                f,
                "timed out at frames {} and {}",
                frames.first().copied().unwrap_or_default(),
                frames.get(1).copied().unwrap_or_default()
            ),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Ggrs(e) => Some(e),
            Error::Load { source, .. } | Error::Advance { source, .. } => Some(source.as_ref()),
            Error::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<GgrsError> for Error {
    fn from(e: GgrsError) -> Error {
        Error::Ggrs(e)
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Error {
        Error::Io(e)
    }
}

/// What [`fulfil`] did, summed over calls: saves, loads (rollbacks) and
/// advances (frames simulated, re-simulations included); and, when made
/// by [`Tally::recording`], the checksum saved for each frame, which two
/// peers compare frame by frame.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Save requests served.
    pub saves: u64,
    /// Load requests served: rollbacks.
    pub loads: u64,
    /// Advance requests served: frames simulated, re-simulations included.
    pub advances: u64,
    /// `checksums[f]`: the checksum last saved for frame `f` (a rollback
    /// re-saves, and forgets the frames after it until they are saved
    /// again); `None` when not recording.
    checksums: Option<Vec<Option<u64>>>,
}

impl Tally {
    /// A tally that also keeps each frame's checksum (8 bytes a frame).
    pub fn recording() -> Tally {
        Tally {
            checksums: Some(Vec::new()),
            ..Tally::default()
        }
    }

    /// The checksum last saved for `frame`: `None` if not recording or
    /// not saved.
    pub fn checksum(&self, frame: u64) -> Option<u64> {
        let at = usize::try_from(frame).ok()?;
        self.checksums.as_ref()?.get(at).copied().flatten()
    }

    /// The first frame in `0..=last` whose recorded checksum differs
    /// between `self` and `other` (a frame one of them lacks differs).
    pub fn first_difference(&self, other: &Tally, last: u64) -> Option<u64> {
        (0..=last).find(|&f| self.checksum(f).is_none() || self.checksum(f) != other.checksum(f))
    }

    /// Records `checksum` as frame `frame`'s, dropping later frames.
    fn record(&mut self, frame: u64, checksum: u64) {
        let (Some(list), Ok(at)) = (self.checksums.as_mut(), usize::try_from(frame)) else {
            return;
        };
        list.truncate(at);
        list.resize(at, None);
        list.push(Some(checksum));
    }
}

/// Serves a session's requests in order, as GGRS requires: a save writes
/// the game's [`State`](RollbackGame::State) and its checksum (widened to
/// the `u128` GGRS keeps) into the request's cell, a load hands the cell's
/// state to [`RollbackGame::load`], an advance hands the inputs to
/// [`RollbackGame::advance`]. Stops at the first error, which leaves the
/// game mid-list: end the session then.
///
/// A save reuses the state the cell held (GGRS keeps one cell per frame of
/// its prediction window), so a game whose
/// [`save_into`](RollbackGame::save_into) reuses buffers allocates nothing
/// once every cell has been filled.
pub fn fulfil<G, A>(
    game: &mut G,
    requests: Vec<GgrsRequest<GgrsConfig<G, A>>>,
    tally: &mut Tally,
) -> Result<(), Error>
where
    G: RollbackGame + 'static,
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    // The frame the next advance starts from, once a request named it.
    let mut at: Option<Frame> = None;
    for request in requests {
        match request {
            GgrsRequest::SaveGameState { cell, frame } => {
                let number = u64::try_from(frame).map_err(|_| Error::InvalidFrame(frame))?;
                let mut state = cell
                    .data()
                    .map(|mut old| core::mem::take(old.as_mut_dangerous()))
                    .unwrap_or_default();
                game.save_into(&mut state);
                let checksum = game.checksum();
                cell.save(frame, Some(state), Some(u128::from(checksum)));
                tally.saves = tally.saves.saturating_add(1);
                tally.record(number, checksum);
                at = Some(frame);
            }
            GgrsRequest::LoadGameState { cell, frame } => {
                let state = cell.data().ok_or(Error::NothingSaved(frame))?;
                game.load(&state)
                    .map_err(|source| Error::Load { frame, source })?;
                tally.loads = tally.loads.saturating_add(1);
                at = Some(frame);
            }
            GgrsRequest::AdvanceFrame { inputs } => {
                game.advance(&inputs)
                    .map_err(|source| Error::Advance { frame: at, source })?;
                tally.advances = tally.advances.saturating_add(1);
                at = at.map(|f| f.saturating_add(1));
            }
        }
    }
    Ok(())
}
