//! Sessions: a SyncTest run ([`run_synctest`]), a P2P session
//! ([`p2p_session`]) and two P2P peers in one process ([`run_loopback`]).
use core::fmt::Debug;
use core::hash::Hash;
use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use ggrs::{
    DesyncDetection, GgrsError, GgrsEvent, NonBlockingSocket, P2PSession, PlayerHandle, PlayerType,
    SessionBuilder, SessionState, SyncTestSession, UdpNonBlockingSocket,
};

use crate::game::{GgrsConfig, RollbackGame};
use crate::request::{fulfil, Error, Tally};

/// A [`SyncTestSession`] for `players` local players that rolls back and
/// re-simulates the last `check_distance` frames on every frame.
pub fn synctest_session<G: RollbackGame + 'static>(
    players: usize,
    check_distance: usize,
) -> Result<SyncTestSession<GgrsConfig<G>>, Error> {
    Ok(SessionBuilder::<GgrsConfig<G>>::new()
        .with_num_players(players)?
        // The window must hold the frames re-simulated plus the current one.
        .with_max_prediction_window(check_distance.saturating_add(1))
        .with_check_distance(check_distance)
        .start_synctest_session()?)
}

/// Runs `game` for `frames` frames in a SyncTest: after each frame GGRS
/// loads the state of `check_distance` frames ago, re-simulates them and
/// compares their checksums with the first run's. `input(player, frame)`
/// is each player's input (a pure function of its arguments, as the
/// re-simulations replay what the first run recorded anyway).
///
/// A checksum mismatch is `Err(Error::Ggrs(GgrsError::MismatchedChecksum
/// { .. }))`: state outside [`RollbackGame::State`] fed the simulation.
pub fn run_synctest<G, F>(
    game: &mut G,
    players: usize,
    frames: u64,
    check_distance: usize,
    mut input: F,
) -> Result<Tally, Error>
where
    G: RollbackGame + 'static,
    F: FnMut(PlayerHandle, u64) -> G::Input,
{
    let mut session = synctest_session::<G>(players, check_distance)?;
    let mut tally = Tally::default();
    for frame in 0..frames {
        for player in 0..players {
            session.add_local_input(player, input(player, frame))?;
        }
        let requests = session.advance_frame()?;
        fulfil(game, requests, &mut tally)?;
    }
    Ok(tally)
}

/// How a P2P session runs: GGRS's settings, with desync detection on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct P2pOptions {
    /// Frames a local input waits before it applies: each frame of delay
    /// hides one frame of latency from rollbacks.
    pub input_delay: usize,
    /// Frames a peer may run ahead of the inputs it has (8 in GGRS).
    pub max_prediction: usize,
    /// Peers exchange a confirmed frame's checksum every this many frames
    /// (`None`: never): a difference is a `DesyncDetected` event.
    pub desync_interval: Option<u32>,
    /// Silence after which a peer counts as disconnected.
    pub disconnect_timeout: Duration,
    /// Silence after which GGRS reports a network interruption.
    pub disconnect_notify_delay: Duration,
}

impl Default for P2pOptions {
    /// Input delay 1, prediction 8, a checksum exchange every 10 frames,
    /// GGRS's disconnection times (2 s, reported after 0.5 s).
    fn default() -> P2pOptions {
        P2pOptions {
            input_delay: 1,
            max_prediction: 8,
            desync_interval: Some(10),
            disconnect_timeout: Duration::from_millis(2000),
            disconnect_notify_delay: Duration::from_millis(500),
        }
    }
}

/// A [`P2PSession`] over `socket`. `players[h]` is player handle `h`:
/// [`PlayerType::Local`] for the players on this machine,
/// [`PlayerType::Remote`] with a peer's address for the others;
/// [`PlayerType::Spectator`] entries are not players (they take the
/// handles after the players', in order). The session still has to
/// synchronize: poll it ([`P2PSession::poll_remote_clients`]) until its
/// state is [`SessionState::Running`].
pub fn p2p_session<G, A, S>(
    players: &[PlayerType<A>],
    socket: S,
    options: &P2pOptions,
) -> Result<P2PSession<GgrsConfig<G, A>>, Error>
where
    G: RollbackGame + 'static,
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
    S: NonBlockingSocket<A> + 'static,
{
    let count = players
        .iter()
        .filter(|p| !matches!(p, PlayerType::Spectator(_)))
        .count();
    let desync = match options.desync_interval {
        Some(interval) => DesyncDetection::On { interval },
        None => DesyncDetection::Off,
    };
    let mut builder = SessionBuilder::<GgrsConfig<G, A>>::new()
        .with_num_players(count)?
        .with_input_delay(options.input_delay)
        .with_max_prediction_window(options.max_prediction)
        .with_desync_detection_mode(desync)
        .with_disconnect_timeout(options.disconnect_timeout)
        .with_disconnect_notify_delay(options.disconnect_notify_delay);
    let (mut player, mut spectator) = (0usize, count);
    for kind in players {
        let handle = if matches!(kind, PlayerType::Spectator(_)) {
            &mut spectator
        } else {
            &mut player
        };
        builder = builder.add_player(kind.clone(), *handle)?;
        *handle = handle.saturating_add(1);
    }
    Ok(builder.start_p2p_session(socket)?)
}

/// Two P2P peers in one process ([`run_loopback`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loopback {
    /// Frames both peers must confirm; their checksums of frames
    /// `0..=frames` are compared.
    pub frames: u64,
    /// The whole run's limit, synchronization included.
    pub timeout: Duration,
    /// The sessions' settings.
    pub options: P2pOptions,
    /// Seed of the frames each peer advances per turn (1 to 4).
    pub seed: u64,
}

impl Loopback {
    /// `frames` frames in at most 60 s, [`P2pOptions::default`] but with
    /// disconnection after 60 s of silence: a busy test machine may pause
    /// a peer that long, and a peer dropped for it would run on "no input".
    pub fn new(frames: u64) -> Loopback {
        Loopback {
            frames,
            timeout: Duration::from_secs(60),
            options: P2pOptions {
                disconnect_timeout: Duration::from_secs(60),
                disconnect_notify_delay: Duration::from_secs(30),
                ..P2pOptions::default()
            },
            seed: 0xB0057,
        }
    }
}

/// What the two peers of [`run_loopback`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoopbackOutcome {
    /// Frames compared: `0..=frames`.
    pub frames: u64,
    /// Each peer's tally, with the checksum of every frame it saved.
    pub tallies: [Tally; 2],
    /// The first frame in `0..=frames` whose checksums differ between the
    /// peers (or that one of them did not save).
    pub first_mismatch: Option<u64>,
}

impl LoopbackOutcome {
    /// Each peer's checksum of `frame`.
    pub fn checksums(&self, frame: u64) -> [Option<u64>; 2] {
        let [a, b] = &self.tallies;
        [a.checksum(frame), b.checksum(frame)]
    }
}

/// Frames past [`Loopback::frames`] that both peers confirm before the
/// run stops, so that frame `frames` was saved from confirmed inputs.
const CONFIRM_MARGIN: u64 = 10;

/// Runs `games[0]` and `games[1]` (the same game in the same state) as
/// two P2P peers talking UDP over 127.0.0.1, peer `i` playing player `i`
/// with `input(i, frame)`, until both have confirmed
/// [`Loopback::frames`] frames (plus a margin). Each peer advances a
/// varying number of frames per turn, so each runs ahead of the other's
/// inputs now and then, predicts wrong and rolls back.
///
/// Errors: a `DesyncDetected` or `Disconnected` event, a timeout, a
/// socket or GGRS error, a failed load or advance. Peers that merely end
/// with different checksums are no error: see
/// [`LoopbackOutcome::first_mismatch`].
pub fn run_loopback<G, F>(
    games: &mut [G; 2],
    setup: &Loopback,
    mut input: F,
) -> Result<LoopbackOutcome, Error>
where
    G: RollbackGame + 'static,
    F: FnMut(PlayerHandle, u64) -> G::Input,
{
    let deadline = Instant::now()
        .checked_add(setup.timeout)
        .ok_or(Error::Timeout { frames: [0, 0] })?;
    let ports = [free_port()?, free_port()?];
    let addr = |port: u16| SocketAddr::from(([127, 0, 0, 1], port));
    let mut sessions = Vec::with_capacity(2);
    for (me, (&mine, &theirs)) in ports.iter().zip(ports.iter().rev()).enumerate() {
        let socket = UdpNonBlockingSocket::bind_to_port(mine)?;
        let remote = PlayerType::Remote(addr(theirs));
        let players = if me == 0 {
            [PlayerType::Local, remote]
        } else {
            [remote, PlayerType::Local]
        };
        sessions.push(p2p_session::<G, _, _>(&players, socket, &setup.options)?);
    }
    let frames_now = |sessions: &[P2PSession<GgrsConfig<G>>]| {
        let mut at = [0; 2];
        for (slot, s) in at.iter_mut().zip(sessions) {
            *slot = s.current_frame();
        }
        at
    };

    while sessions
        .iter()
        .any(|s| s.current_state() != SessionState::Running)
    {
        for s in &mut sessions {
            s.poll_remote_clients();
            s.events().for_each(drop);
        }
        if Instant::now() > deadline {
            return Err(Error::Timeout {
                frames: frames_now(&sessions),
            });
        }
        std::thread::sleep(Duration::from_millis(1));
    }

    let target = i32::try_from(setup.frames.saturating_add(CONFIRM_MARGIN))
        .map_err(|_| Error::InvalidFrame(i32::MAX))?;
    let mut tallies = [Tally::recording(), Tally::recording()];
    let mut bursts = setup.seed;
    // One more round after both confirmed the target serves any rollback
    // the last inputs received call for.
    let mut extra_rounds = 1u32;
    loop {
        if sessions.iter().all(|s| s.confirmed_frame() >= target) {
            if extra_rounds == 0 {
                break;
            }
            extra_rounds = extra_rounds.saturating_sub(1);
        }
        for (me, ((session, game), tally)) in sessions
            .iter_mut()
            .zip(games.iter_mut())
            .zip(tallies.iter_mut())
            .enumerate()
        {
            let burst = next_random(&mut bursts) % 4;
            for _ in 0..=burst {
                session.poll_remote_clients();
                for event in session.events() {
                    match event {
                        GgrsEvent::DesyncDetected {
                            frame,
                            local_checksum,
                            remote_checksum,
                            ..
                        } => {
                            return Err(Error::Desync {
                                peer: me,
                                frame,
                                local: local_checksum,
                                remote: remote_checksum,
                            })
                        }
                        GgrsEvent::Disconnected { .. } => {
                            return Err(Error::Disconnected { peer: me })
                        }
                        _ => {}
                    }
                }
                let frame = u64::try_from(session.current_frame()).unwrap_or(0);
                session.add_local_input(me, input(me, frame))?;
                match session.advance_frame() {
                    Ok(requests) => fulfil(game, requests, tally)?,
                    // Too far ahead of the other peer: its turn.
                    Err(GgrsError::PredictionThreshold) => break,
                    Err(e) => return Err(Error::Ggrs(e)),
                }
            }
        }
        if Instant::now() > deadline {
            return Err(Error::Timeout {
                frames: frames_now(&sessions),
            });
        }
    }
    let [a, b] = &tallies;
    let first_mismatch = a.first_difference(b, setup.frames);
    Ok(LoopbackOutcome {
        frames: setup.frames,
        tallies,
        first_mismatch,
    })
}

/// A UDP port free on this machine now: bound to port 0, read, released.
fn free_port() -> std::io::Result<u16> {
    let probe = UdpSocket::bind(("127.0.0.1", 0))?;
    Ok(probe.local_addr()?.port())
}

/// SplitMix64: the next of a deterministic sequence of 64-bit values.
fn next_random(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
