//! The little two-player game shared by the GGRS and rollback examples and
//! by `tests/determinism/ggrs.rs` (feature `ggrs`): `bowl_boxes_100` (100
//! boxes dropped into a bowl) plus two player balls, each driven by a `u8`
//! button mask.
//!
//! Buttons decode deterministically into [`replay::Input`]s
//! ([`decode_buttons`]): left and right push with a force for one step,
//! jump is an impulse at the centre of gravity, spin is a torque. The game
//! is a [`RollbackGame`] whose state is the world's [`FrameState`] alone
//! (`save_frame` to save, `restore_frame` to load; the static bowl is the
//! level, never copied); the frame number is the space's step count. The
//! sessions are `tamias2d-ggrs`'s: [`run_synctest`] and [`run_p2p`] only
//! fix the players, the scripted buttons and the reference run.
#![allow(
    dead_code, // each example uses a part
    clippy::float_arithmetic,
    clippy::arithmetic_side_effects,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

use std::time::Duration;

use crate::{self as scenes, rng::SplitMix64, BodyDesc, BodyKind, ShapeDesc};
use tamias2d::body::BodyHandle;
use tamias2d::replay::{self, BoxError, Input};
use tamias2d::space::{FrameState, Space, SpaceError};
use tamias2d::{real, Real, Vect};
use tamias2d_ggrs::ggrs::InputStatus;
use tamias2d_ggrs::{Error, Loopback, RollbackGame};

/// Push left.
pub const LEFT: u8 = 1 << 0;
/// Push right.
pub const RIGHT: u8 = 1 << 1;
/// Jump (upward impulse).
pub const JUMP: u8 = 1 << 2;
/// Spin (counter-clockwise torque).
pub const SPIN: u8 = 1 << 3;

/// Horizontal force of left/right: the ~4 kg ball gains ~6 units/s per frame.
const PUSH: Real = real!(1500);
/// Upward impulse of a jump.
const JUMP_IMPULSE: Real = real!(60);
/// Torque of a spin.
const SPIN_TORQUE: Real = real!(4000);

/// The GGRS configuration: `u8` button masks, the world's frame as the
/// saved state, UDP socket addresses.
pub type GgrsConfig = tamias2d_ggrs::GgrsConfig<Game>;

/// The world, its time step and the two player bodies.
pub struct Game {
    /// The world.
    pub space: Space,
    /// Time step of every frame.
    pub dt: Real,
    /// Player 0's and player 1's ball.
    pub players: [BodyHandle; 2],
    /// Frames simulated, re-simulations included.
    pub advances: u64,
    /// Rollbacks (load requests) served.
    pub loads: u64,
    /// Test hook: when set, the 100th simulated frame (re-simulations
    /// count) nudges player 0: state outside the snapshot feeds the
    /// simulation, the classic desync, to show that the checks catch it.
    pub sabotage: bool,
}

impl Default for Game {
    fn default() -> Game {
        Game::new()
    }
}

impl Game {
    /// `bowl_boxes_100` with two balls of radius 8 (about 4 kg) near the
    /// bottom of the bowl, labelled `p0` and `p1`.
    pub fn new() -> Game {
        let mut desc = scenes::builtin("bowl_boxes_100").expect("listed scene");
        for (label, x) in [("p0", -60), ("p1", 60)] {
            let ball = ShapeDesc::circle(real!(8))
                .density(real!(0.02))
                .material(real!(0.9), Real::ZERO);
            let body = BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(x, -200)).labeled(label);
            desc.bodies.push(body.with_shape(ball));
        }
        let scene = desc.build().expect("valid scene");
        let players = [
            scene.body("p0").expect("labelled"),
            scene.body("p1").expect("labelled"),
        ];
        Game {
            dt: scene.dt,
            space: scene.space,
            players,
            advances: 0,
            loads: 0,
            sabotage: false,
        }
    }

    /// Any built-in scene as a two-player game: the players are its first
    /// two dynamic bodies (their buttons push and spin them), the scene's
    /// own script (scheduled forces, spawns) is not part of the game.
    /// `None` if the scene is unknown, does not build or has fewer than two
    /// dynamic bodies.
    pub fn with_scene(name: &str) -> Option<Game> {
        let scene = scenes::builtin(name)?.build().ok()?;
        let dynamic: Vec<BodyHandle> = scene
            .space
            .bodies()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .take(2)
            .collect();
        let players = [*dynamic.first()?, *dynamic.get(1)?];
        Some(Game {
            dt: scene.dt,
            space: scene.space,
            players,
            advances: 0,
            loads: 0,
            sabotage: false,
        })
    }

    /// Frames advanced since the start: `Space::steps` (one per `step`
    /// call), not the sub-step `stamp`, which runs ahead of the frame count
    /// once the settings use sub-steps.
    pub fn frame(&self) -> u64 {
        self.space.steps()
    }

    /// One frame: every player's buttons, then one step.
    pub fn advance(&mut self, buttons: &[u8]) {
        self.try_advance(buttons).expect("step");
    }

    /// [`Game::advance`], with the step's error as a value.
    pub fn try_advance(&mut self, buttons: &[u8]) -> Result<(), SpaceError> {
        let mut inputs = Vec::new();
        for (&player, &mask) in self.players.iter().zip(buttons) {
            inputs.extend(decode_buttons(&self.space, player, mask));
        }
        if self.sabotage && self.advances == 100 {
            inputs.push(Input::Torque {
                body: self.players[0],
                torque: Real::ONE,
            });
        }
        replay::apply_inputs(&mut self.space, &inputs)?;
        self.space.step(self.dt)?;
        self.advances += 1;
        Ok(())
    }
}

/// The game under GGRS: the saved state is the space's frame; a
/// disconnected player's buttons count as none.
impl RollbackGame for Game {
    type Input = u8;
    type State = FrameState;

    fn save_into(&self, state: &mut FrameState) {
        self.space.save_frame(state);
    }

    fn load(&mut self, state: &FrameState) -> Result<(), BoxError> {
        self.space.restore_frame(state)?;
        self.loads += 1;
        Ok(())
    }

    fn advance(&mut self, inputs: &[(u8, InputStatus)]) -> Result<(), BoxError> {
        let buttons: Vec<u8> = inputs
            .iter()
            .map(|&(mask, status)| match status {
                InputStatus::Disconnected => 0,
                InputStatus::Confirmed | InputStatus::Predicted => mask,
            })
            .collect();
        Ok(self.try_advance(&buttons)?)
    }

    fn checksum(&self) -> u64 {
        self.space.checksum()
    }
}

/// The inputs a button mask stands for, in a fixed order (left, right,
/// jump, spin); none for a missing body.
pub fn decode_buttons(space: &Space, player: BodyHandle, mask: u8) -> Vec<Input> {
    let Some(body) = space.body(player) else {
        return Vec::new();
    };
    let mut inputs = Vec::new();
    let mut push = Real::ZERO;
    if mask & LEFT != 0 {
        push -= PUSH;
    }
    if mask & RIGHT != 0 {
        push += PUSH;
    }
    if push != Real::ZERO {
        inputs.push(Input::Force {
            body: player,
            force: Vect::new(push, Real::ZERO),
        });
    }
    if mask & JUMP != 0 {
        inputs.push(Input::Impulse {
            body: player,
            impulse: Vect::new(Real::ZERO, JUMP_IMPULSE),
            point: body.center(),
        });
    }
    if mask & SPIN != 0 {
        inputs.push(Input::Torque {
            body: player,
            torque: SPIN_TORQUE,
        });
    }
    inputs
}

/// A player's buttons at `frame` in the scripted runs: a pseudo-random mask
/// held for `hold` frames (a deterministic function of player and frame).
pub fn scripted_buttons(player: usize, frame: u64, hold: u64) -> u8 {
    let block = frame / hold.max(1);
    let mut rng = SplitMix64::new(0x5EED ^ ((player as u64) << 32) ^ block);
    (rng.next_u64() & 0x0F) as u8
}

/// Runs a GGRS [`SyncTestSession`](tamias2d_ggrs::ggrs::SyncTestSession)
/// ([`tamias2d_ggrs::run_synctest`]): every frame is simulated, then the
/// last `check_distance` frames are rolled back and re-simulated and their
/// checksums compared with the first run's. Both players' inputs are
/// [`scripted_buttons`] held `hold` frames. Returns the game after
/// `frames` frames, or the error (a checksum mismatch means the
/// simulation is not deterministic under rollback).
pub fn run_synctest(
    game: &mut Game,
    frames: u64,
    check_distance: usize,
    hold: u64,
) -> Result<(), Error> {
    tamias2d_ggrs::run_synctest(game, 2, frames, check_distance, |player, frame| {
        scripted_buttons(player, frame, hold)
    })?;
    Ok(())
}

/// The reference run without GGRS: frame `f` gets the buttons scripted for
/// frame `f − delay` (none before `delay`), as a session with that input
/// delay applies them (0 for [`run_synctest`], [`P2P_INPUT_DELAY`] for
/// [`run_p2p`]).
pub fn run_straight(frames: u64, hold: u64, delay: u64) -> Game {
    run_straight_on(Game::new(), frames, hold, delay)
}

/// [`run_straight`] on a given game (e.g. [`Game::with_scene`]).
pub fn run_straight_on(mut game: Game, frames: u64, hold: u64, delay: u64) -> Game {
    for frame in 0..frames {
        let buttons = |player| match frame.checked_sub(delay) {
            Some(f) => scripted_buttons(player, f, hold),
            None => 0,
        };
        game.advance(&[buttons(0), buttons(1)]);
    }
    game
}

/// Input delay of the P2P sessions (frames).
pub const P2P_INPUT_DELAY: u64 = 1;

/// What two peers ended with.
#[derive(Debug)]
pub struct P2pOutcome {
    /// Frames compared (`0..=frames`).
    pub frames: u64,
    /// Each peer's checksum of frame `frames`.
    pub checksums: [u64; 2],
    /// First frame whose saved checksums differ between the peers.
    pub first_mismatch: Option<u64>,
    /// Rollbacks each peer served.
    pub loads: [u64; 2],
    /// Frames each peer simulated, re-simulations included.
    pub advances: [u64; 2],
}

/// Two [`P2PSession`](tamias2d_ggrs::ggrs::P2PSession) peers in this
/// process ([`tamias2d_ggrs::run_loopback`]), talking UDP over 127.0.0.1,
/// each with one local player (peer `i` plays player `i`, buttons
/// [`scripted_buttons`] held `hold` frames, input delay
/// [`P2P_INPUT_DELAY`]), run until both have confirmed `frames` frames
/// plus a margin. Desync detection is on (every 10 frames): a
/// `DesyncDetected` event is an error, as is a timeout.
pub fn run_p2p(frames: u64, hold: u64, timeout: Duration) -> Result<P2pOutcome, Error> {
    let mut setup = Loopback::new(frames);
    setup.timeout = timeout;
    setup.options.input_delay = P2P_INPUT_DELAY as usize;
    let mut games = [Game::new(), Game::new()];
    let outcome = tamias2d_ggrs::run_loopback(&mut games, &setup, |player, frame| {
        scripted_buttons(player, frame, hold)
    })?;
    let [a, b] = outcome.checksums(frames).map(|c| c.unwrap_or(0));
    let [ta, tb] = &outcome.tallies;
    Ok(P2pOutcome {
        frames,
        checksums: [a, b],
        first_mismatch: outcome.first_mismatch,
        loads: [ta.loads, tb.loads],
        advances: [ta.advances, tb.advances],
    })
}
