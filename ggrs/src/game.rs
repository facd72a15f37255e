//! What a game implements ([`RollbackGame`]), the GGRS configuration built
//! from it ([`GgrsConfig`]) and the saved state of a game with state beyond
//! its space ([`SpaceState`]).
use core::fmt::Debug;
use core::hash::Hash;
use core::marker::PhantomData;
use std::net::SocketAddr;

use ggrs::{InputStatus, PredictRepeatLast};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use tamias2d::replay::BoxError;
use tamias2d::space::{FrameState, Space, SpaceError};

/// A game GGRS can save, load and advance: the world it simulates, the
/// input of one player for one frame, and the state a rollback restores.
///
/// Everything that affects a future frame must be in [`State`](Self::State)
/// and in [`checksum`](Self::checksum); anything else is a desync waiting
/// to happen (a SyncTest finds it: [`run_synctest`](crate::run_synctest)).
pub trait RollbackGame {
    /// One player's input for one frame: the only thing peers send each
    /// other. Its `Default` is "no input" (GGRS gives it for a
    /// disconnected player). The bounds are GGRS's, with `Send + Sync` so
    /// the crate builds whether or not GGRS's `sync-send` feature is on.
    type Input: Copy + PartialEq + Default + Serialize + DeserializeOwned + Send + Sync + 'static;

    /// A saved frame: [`FrameState`] for a game that is its space alone,
    /// [`SpaceState<T>`] for a space plus the game's own `T`, or any type
    /// of the game's. `Default` makes the first save of each GGRS slot;
    /// later saves reuse the slot's previous state (see
    /// [`save_into`](Self::save_into)).
    type State: Clone + Default + Send + Sync + 'static;

    /// Writes the current frame into `state`, which holds an older frame
    /// (or the default): overwrite all of it, reusing its buffers, as
    /// [`Space::save_frame`] does.
    fn save_into(&self, state: &mut Self::State);

    /// Rolls the game back to a saved frame. An error ends the session's
    /// request loop ([`fulfil`](crate::fulfil) returns it).
    fn load(&mut self, state: &Self::State) -> Result<(), BoxError>;

    /// One frame: every player's input (in player-handle order) with its
    /// status, then the step. Predicted inputs are advanced like confirmed
    /// ones: GGRS rolls back and re-simulates when a prediction was wrong.
    fn advance(&mut self, inputs: &[(Self::Input, InputStatus)]) -> Result<(), BoxError>;

    /// A checksum of everything [`State`](Self::State) holds: what GGRS
    /// compares between a SyncTest's runs and between peers.
    /// [`Space::checksum`] for the space alone; with state beyond it, fold
    /// that in ([`SpaceState::checksum`]).
    fn checksum(&self) -> u64;
}

/// The [`ggrs::Config`] of a [`RollbackGame`]: its input and state, GGRS's
/// repeat-the-last-input prediction, and `A` as the peers' address type
/// (UDP socket addresses unless the game brings its own transport).
pub struct GgrsConfig<G, A = SocketAddr>(PhantomData<fn() -> (G, A)>);

impl<G, A> ggrs::Config for GgrsConfig<G, A>
where
    G: RollbackGame + 'static,
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    type Input = G::Input;
    type InputPredictor = PredictRepeatLast;
    type State = G::State;
    type Address = A;
}

/// A saved frame of a game whose state is a [`Space`] plus a value of its
/// own (`T`: scores, timers, character controllers, a spawn counter): the
/// space's [`FrameState`] (the world minus its static level) and a copy of
/// `T`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SpaceState<T> {
    /// The space's frame.
    pub frame: FrameState,
    /// The game's own state.
    pub extra: T,
}

impl<T: Clone + Hash> SpaceState<T> {
    /// Saves `space` and `extra` into this state, reusing its buffers.
    pub fn save(&mut self, space: &Space, extra: &T) {
        space.save_frame(&mut self.frame);
        self.extra.clone_from(extra);
    }

    /// Restores the saved frame into `space` and the saved value into
    /// `extra`. On an error (a frame of another level) neither changes.
    pub fn restore(&self, space: &mut Space, extra: &mut T) -> Result<(), SpaceError> {
        space.restore_frame(&self.frame)?;
        extra.clone_from(&self.extra);
        Ok(())
    }

    /// The checksum of a game made of `space` and `extra`: the space's
    /// checksum with `extra` hashed after it (the engine's portable hash,
    /// so peers on any platform agree).
    pub fn checksum(space: &Space, extra: &T) -> u64 {
        tamias2d::checksum::checksum_of(&(space.checksum(), extra))
    }
}
