//! The little two-player game shared by the GGRS and rollback examples and
//! by `tests/determinism/ggrs.rs` (feature `ggrs`): `bowl_boxes_100` (100 boxes dropped into a bowl) plus
//! two player balls, each driven by a `u8` button mask.
//!
//! Buttons decode deterministically into [`replay::Input`]s
//! ([`decode_buttons`]): left and right push with a force for one step,
//! jump is an impulse at the centre of gravity, spin is a torque. The game
//! state for rollback is the world's [`FrameState`] alone (the in-memory
//! fast path: `save_frame` to save, `restore_frame` to load; the static
//! bowl is the level, never copied); the frame number is the space's step
//! stamp.
#![allow(
    dead_code, // each example uses a part
    clippy::float_arithmetic,
    clippy::arithmetic_side_effects,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

use std::net::SocketAddr;
use std::time::{Duration, Instant};

use crate::{self as scenes, rng::SplitMix64, BodyDesc, BodyKind, ShapeDesc};
use ggrs::{
    DesyncDetection, GgrsError, GgrsEvent, GgrsRequest, InputStatus, PlayerType, PredictRepeatLast,
    SessionState, UdpNonBlockingSocket,
};
use tamias2d::body::BodyHandle;
use tamias2d::replay::{self, Input};
use tamias2d::space::{FrameState, Space};
use tamias2d::{real, Real, Vect};

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

/// The GGRS configuration: `u8` button masks, the world state as the saved
/// state, UDP socket addresses.
pub struct GgrsConfig;

impl ggrs::Config for GgrsConfig {
    type Input = u8;
    type InputPredictor = PredictRepeatLast;
    type State = FrameState;
    type Address = SocketAddr;
}

/// The world, its time step and the two player bodies.
pub struct Game {
    /// The world.
    pub space: Space,
    /// Time step of every frame.
    pub dt: Real,
    /// Player 0's and player 1's ball.
    pub players: [BodyHandle; 2],
    /// `checksums[f]`: checksum of the state saved for frame `f` (the last
    /// save wins: a re-simulation overwrites its frames).
    pub checksums: Vec<u64>,
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
            checksums: Vec::new(),
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
            checksums: Vec::new(),
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
        replay::apply_inputs(&mut self.space, &inputs).expect("players exist");
        self.space.step(self.dt).expect("step");
        self.advances += 1;
    }

    /// Serves GGRS requests in order: save = the frame plus its checksum
    /// (widened to u128), load = restore the frame, advance = inputs + step.
    pub fn fulfil(&mut self, requests: Vec<GgrsRequest<GgrsConfig>>) {
        for request in requests {
            match request {
                GgrsRequest::SaveGameState { cell, frame } => {
                    assert_eq!(u64::try_from(frame).ok(), Some(self.frame()), "save frame");
                    let checksum = self.space.checksum();
                    let f = usize::try_from(frame).expect("frame ≥ 0");
                    self.checksums.truncate(f);
                    self.checksums.push(checksum);
                    let mut state = FrameState::default();
                    self.space.save_frame(&mut state);
                    cell.save(frame, Some(state), Some(u128::from(checksum)));
                }
                GgrsRequest::LoadGameState { cell, frame } => {
                    let state = cell.load().expect("a saved state");
                    self.space
                        .restore_frame(&state)
                        .expect("a frame of this level");
                    assert_eq!(u64::try_from(frame).ok(), Some(self.frame()), "load frame");
                    self.loads += 1;
                }
                GgrsRequest::AdvanceFrame { inputs } => {
                    let buttons: Vec<u8> = inputs
                        .iter()
                        .map(|&(mask, status)| match status {
                            InputStatus::Disconnected => 0,
                            InputStatus::Confirmed | InputStatus::Predicted => mask,
                        })
                        .collect();
                    self.advance(&buttons);
                }
            }
        }
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

/// Runs a GGRS [`SyncTestSession`](ggrs::SyncTestSession): every frame is
/// simulated, then the last `check_distance` frames are rolled back and
/// re-simulated and their checksums compared with the first run's. Both
/// players' inputs are [`scripted_buttons`] held `hold` frames. Returns the
/// game after `frames` frames, or GGRS's error (a checksum mismatch means
/// the simulation is not deterministic under rollback).
pub fn run_synctest(
    game: &mut Game,
    frames: u64,
    check_distance: usize,
    hold: u64,
) -> Result<(), GgrsError> {
    let mut session = ggrs::SessionBuilder::<GgrsConfig>::new()
        .with_num_players(2)?
        .with_max_prediction_window(check_distance + 1)
        .with_check_distance(check_distance)
        .start_synctest_session()?;
    for frame in 0..frames {
        for player in 0..2 {
            session.add_local_input(player, scripted_buttons(player, frame, hold))?;
        }
        let requests = session.advance_frame()?;
        game.fulfil(requests);
    }
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
    pub first_mismatch: Option<usize>,
    /// Rollbacks each peer served.
    pub loads: [u64; 2],
    /// Frames each peer simulated, re-simulations included.
    pub advances: [u64; 2],
}

/// A UDP port free on this machine right now (bind to port 0, read the
/// port, release it).
fn free_port() -> std::io::Result<u16> {
    let probe = std::net::UdpSocket::bind(("127.0.0.1", 0))?;
    Ok(probe.local_addr()?.port())
}

/// Two [`P2PSession`](ggrs::P2PSession) peers in this process, talking UDP
/// over 127.0.0.1, each with one local player (peer `i` plays player `i`,
/// buttons [`scripted_buttons`] held `hold` frames), run until both have
/// confirmed `frames` frames plus a margin. Desync detection is on (every
/// 10 frames): a `DesyncDetected` event is an error, as is a timeout.
pub fn run_p2p(frames: u64, hold: u64, timeout: Duration) -> Result<P2pOutcome, String> {
    let err = |e: GgrsError| e.to_string();
    let ports = [
        free_port().map_err(|e| e.to_string())?,
        free_port().map_err(|e| e.to_string())?,
    ];
    let addr = |port: u16| SocketAddr::from(([127, 0, 0, 1], port));
    let mut sessions = Vec::new();
    for (me, &port) in ports.iter().enumerate() {
        let other = 1 - me;
        let socket = UdpNonBlockingSocket::bind_to_port(port).map_err(|e| e.to_string())?;
        let session = ggrs::SessionBuilder::<GgrsConfig>::new()
            .with_num_players(2)
            .map_err(err)?
            .with_input_delay(P2P_INPUT_DELAY as usize)
            .with_desync_detection_mode(DesyncDetection::On { interval: 10 })
            // A loaded test machine may pause this process for a while; a
            // peer must not be dropped for that (its inputs would then be
            // "disconnected" zeros and the run would differ from the
            // reference).
            .with_disconnect_timeout(Duration::from_secs(60))
            .with_disconnect_notify_delay(Duration::from_secs(30))
            .add_player(PlayerType::Local, me)
            .map_err(err)?
            .add_player(PlayerType::Remote(addr(ports[other])), other)
            .map_err(err)?
            .start_p2p_session(socket)
            .map_err(err)?;
        sessions.push(session);
    }
    let deadline = Instant::now() + timeout;
    while sessions
        .iter()
        .any(|s| s.current_state() != SessionState::Running)
    {
        for s in &mut sessions {
            s.poll_remote_clients();
            s.events().for_each(drop);
        }
        if Instant::now() > deadline {
            return Err("peers did not synchronize in time".into());
        }
        std::thread::sleep(Duration::from_millis(1));
    }

    let mut games = [Game::new(), Game::new()];
    let mut bursts = SplitMix64::new(0xB0057);
    let target = i32::try_from(frames + 10).map_err(|e| e.to_string())?;
    // One extra round after both confirmed the target serves any rollback
    // the last received inputs call for.
    let mut extra_rounds = 1;
    loop {
        let done = sessions.iter().all(|s| s.confirmed_frame() >= target);
        if done {
            if extra_rounds == 0 {
                break;
            }
            extra_rounds -= 1;
        }
        for (me, (session, game)) in sessions.iter_mut().zip(&mut games).enumerate() {
            // Each peer advances a varying number of frames per turn, so
            // each runs ahead of the other's inputs now and then, predicts
            // wrong and rolls back.
            let burst = 1 + bursts.next_u64() % 4;
            for _ in 0..burst {
                session.poll_remote_clients();
                for event in session.events() {
                    match event {
                        GgrsEvent::DesyncDetected {
                            frame,
                            local_checksum,
                            remote_checksum,
                            ..
                        } => {
                            return Err(format!(
                                "peer {me}: desync at frame {frame}: \
                                 {local_checksum:#x} vs {remote_checksum:#x}"
                            ))
                        }
                        GgrsEvent::Disconnected { addr } => {
                            return Err(format!("peer {me}: {addr} disconnected"))
                        }
                        _ => {}
                    }
                }
                let frame = u64::try_from(session.current_frame()).unwrap_or(0);
                session
                    .add_local_input(me, scripted_buttons(me, frame, hold))
                    .map_err(err)?;
                match session.advance_frame() {
                    Ok(requests) => game.fulfil(requests),
                    Err(GgrsError::PredictionThreshold) => break,
                    Err(e) => return Err(format!("peer {me}: {e}")),
                }
            }
        }
        if Instant::now() > deadline {
            return Err(format!(
                "timed out at frames {} / {}",
                sessions[0].current_frame(),
                sessions[1].current_frame()
            ));
        }
    }
    let n = usize::try_from(frames).map_err(|e| e.to_string())?;
    let [a, b] = &games;
    let first_mismatch = (0..=n).find(|&f| a.checksums.get(f) != b.checksums.get(f));
    let at = |g: &Game| g.checksums.get(n).copied().unwrap_or(0);
    Ok(P2pOutcome {
        frames,
        checksums: [at(a), at(b)],
        first_mismatch,
        loads: [a.loads, b.loads],
        advances: [a.advances, b.advances],
    })
}
