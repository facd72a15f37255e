//! GGRS rollback netcode for [Tamias2D](tamias2d) games.
//!
//! A Tamias2D world is one value that saves and restores exactly
//! ([`Space::save_frame`](tamias2d::space::Space::save_frame),
//! [`Space::restore_frame`](tamias2d::space::Space::restore_frame)) and
//! checksums the same on every platform
//! ([`Space::checksum`](tamias2d::space::Space::checksum)): everything
//! [GGRS](ggrs) asks of a game state. This crate holds the glue:
//!
//! - [`RollbackGame`]: what a game implements (its input type, its saved
//!   state, save, load, advance, checksum);
//! - [`GgrsConfig`]: the [`ggrs::Config`] built from it;
//! - [`fulfil`]: serves a session's requests, with errors as values
//!   ([`Error`]) and counts in a [`Tally`];
//! - [`run_synctest`], [`p2p_session`] and [`run_loopback`] (two P2P peers
//!   in one process, compared frame by frame);
//! - [`SpaceState`]: the saved state of a game with state beyond its space
//!   (a space alone saves as its [`FrameState`](tamias2d::space::FrameState)).
//!
//! # A two-player game
//!
//! Two balls on a floor, each player's input a button mask. The whole
//! game state is the space, so the saved state is its
//! [`FrameState`](tamias2d::space::FrameState), and the checksum is the
//! space's. The SyncTest rolls back and re-simulates the last 7 frames on
//! every frame and fails on any checksum difference; the game then ends
//! where a run without GGRS ends.
//!
//! ```
//! use tamias2d::body::{Body, BodyHandle};
//! use tamias2d::math::{Real, Vect};
//! use tamias2d::replay::BoxError;
//! use tamias2d::shape::Shape;
//! use tamias2d::space::{FrameState, Space};
//! use tamias2d_ggrs::ggrs::InputStatus;
//! use tamias2d_ggrs::{run_synctest, RollbackGame};
//!
//! const LEFT: u8 = 1;
//! const RIGHT: u8 = 2;
//! const JUMP: u8 = 4;
//!
//! struct Game {
//!     space: Space,
//!     players: [BodyHandle; 2],
//! }
//!
//! impl Game {
//!     fn new() -> Result<Game, BoxError> {
//!         let mut space = Space::new();
//!         space.set_gravity(Vect::from_ints(0, -10));
//!         let ground = space.add_body(Body::new_static())?;
//!         let (a, b) = (Vect::from_ints(-20, 0), Vect::from_ints(20, 0));
//!         space.add_shape(Shape::segment_shape_new(ground, a, b, Real::ZERO)?)?;
//!         let mut ball = |x: i32| -> Result<BodyHandle, BoxError> {
//!             let mut body = Body::new(Real::ONE, Real::ONE)?;
//!             body.set_position(Vect::from_ints(x, 1));
//!             let body = space.add_body(body)?;
//!             space.add_shape(Shape::circle_shape_new(body, Real::HALF, Vect::ZERO)?)?;
//!             Ok(body)
//!         };
//!         let players = [ball(-2)?, ball(2)?];
//!         Ok(Game { space, players })
//!     }
//! }
//!
//! impl RollbackGame for Game {
//!     type Input = u8;
//!     type State = FrameState;
//!
//!     fn save_into(&self, state: &mut FrameState) {
//!         self.space.save_frame(state);
//!     }
//!
//!     fn load(&mut self, state: &FrameState) -> Result<(), BoxError> {
//!         Ok(self.space.restore_frame(state)?)
//!     }
//!
//!     fn advance(&mut self, inputs: &[(u8, InputStatus)]) -> Result<(), BoxError> {
//!         for (&player, &(buttons, _status)) in self.players.iter().zip(inputs) {
//!             let body = self.space.body_mut(player).ok_or("no such player")?;
//!             let push = i32::from(buttons & RIGHT != 0) - i32::from(buttons & LEFT != 0);
//!             body.apply_force(Vect::from_ints(10 * push, 0));
//!             if buttons & JUMP != 0 {
//!                 let center = body.center();
//!                 body.apply_impulse_at_world_point(Vect::from_ints(0, 1), center);
//!             }
//!         }
//!         Ok(self.space.step(Real::ratio(1, 60))?)
//!     }
//!
//!     fn checksum(&self) -> u64 {
//!         self.space.checksum()
//!     }
//! }
//!
//! // Each player's buttons: a pattern that changes every 5 frames.
//! let buttons = |player: usize, frame: u64| [RIGHT, LEFT | JUMP, 0, LEFT][(frame / 5 + player as u64) as usize % 4];
//!
//! let mut game = Game::new()?;
//! let tally = run_synctest(&mut game, 2, 120, 7, buttons)?;
//! assert!(tally.loads >= 110, "rolled back on every frame");
//!
//! let mut straight = Game::new()?;
//! for frame in 0..120 {
//!     let inputs = [0, 1].map(|p| (buttons(p, frame), InputStatus::Confirmed));
//!     straight.advance(&inputs)?;
//! }
//! assert_eq!(game.space.checksum(), straight.space.checksum());
//! # Ok::<(), BoxError>(())
//! ```
//!
//! Over the network the same game runs in a [`P2PSession`](ggrs::P2PSession)
//! from [`p2p_session`]: each machine adds its local players' inputs, calls
//! `advance_frame` and hands the requests to [`fulfil`];
//! `examples/two_player_p2p.rs` runs two peers over UDP.
//!
//! # State beyond the space
//!
//! A game that keeps state of its own (scores, timers, character
//! controllers) saves it with the space: [`SpaceState<T>`] holds both, its
//! [`save`](SpaceState::save) and [`restore`](SpaceState::restore) move
//! both, and [`SpaceState::checksum`] folds `T` into the space's checksum.
//! A value left out of the state is a desync: [`run_synctest`] finds it.
#![forbid(unsafe_code)]
// As the engine (see its `src/lib.rs`): no floats, no reachable panic, no
// unchecked arithmetic or indexing in library code.
#![cfg_attr(not(test), deny(clippy::float_arithmetic))]
#![cfg_attr(
    not(test),
    deny(
        clippy::arithmetic_side_effects,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]
#![warn(missing_docs)]

mod game;
mod request;
mod session;

/// The GGRS this crate is built on: use its types from here so that they
/// are the same version.
pub use ggrs;

pub use game::{GgrsConfig, RollbackGame, SpaceState};
pub use request::{fulfil, Error, Tally};
pub use session::{
    p2p_session, run_loopback, run_synctest, synctest_session, Loopback, LoopbackOutcome,
    P2pOptions,
};
pub use tamias2d::replay::BoxError;
