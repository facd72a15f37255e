//! Two peers of a rollback game, side by side (GGRS-style prediction and
//! rollback, without the network).
//!
//! The same scene runs twice. Each frame may carry one input: "drop a ball
//! at (x, y)" (twice the size of the scene's first body, to be seen). Peer A sees every input on its own frame. Peer B receives it
//! `delay` frames late, so it predicts "no input"; when a late input
//! arrives it restores the frame the input belonged to (an in-memory
//! [`FrameState`], as a GGRS game does), replays the frames since with the
//! input in place, and carries on. A frame is *confirmed* once B has every
//! input up to it: `delay` frames back. The promise on show: B's checksum
//! of every confirmed frame equals A's, however many rollbacks it took.
//!
//! State `S_k` is the world after `k` frames; frame `k` applies input `I_k`
//! to `S_k` and steps: `S_{k+1} = step(apply(S_k, I_k))`.
//!
//! The scene's own script (scheduled forces, spawns) is not part of the
//! game, as in `tamias2d_scenes::ggrs_game`: inputs are the only events.
use tamias2d::space::{FrameState, Space};
use tamias2d::{Real, Vect};

use crate::play::{DropKind, Dropper};

/// One peer's world and its recent checksums.
#[derive(Debug)]
struct Peer {
    space: Space,
    /// Checksum of `S_k` at `k % ring`, for the last `ring` frames.
    checksums: Vec<u64>,
}

impl Peer {
    /// `S_k`'s checksum, if still in the ring.
    fn checksum_of(&self, k: u64) -> Option<u64> {
        self.checksums.get(slot(k, self.checksums.len())).copied()
    }

    fn record(&mut self, k: u64) {
        let ring = self.checksums.len();
        let c = self.space.checksum();
        if let Some(entry) = self.checksums.get_mut(slot(k, ring)) {
            *entry = c;
        }
    }
}

/// `k mod ring` as an index (`ring` ≥ 1 here; 0 only for an empty ring,
/// which then has no slot).
fn slot(k: u64, ring: usize) -> usize {
    let ring = u64::try_from(ring).unwrap_or(u64::MAX).max(1);
    usize::try_from(k.checked_rem(ring).unwrap_or(0)).unwrap_or(usize::MAX)
}

/// Frame `k` of a peer: the input, then one step.
fn simulate(
    space: &mut Space,
    dropper: &Dropper,
    dt: Real,
    input: Option<Vect>,
) -> Result<(), String> {
    if let Some(at) = input {
        dropper.drop(space, DropKind::Ball, at)?;
    }
    space.step(dt).map_err(|e| e.to_string())
}

/// The two peers.
#[derive(Debug)]
pub struct Lockstep {
    a: Peer,
    b: Peer,
    dt: Real,
    dropper: Dropper,
    delay: u32,
    /// Frames both peers have advanced (`S_frame` is current).
    frame: u64,
    /// Every input so far: `I_k` at `k` (what A applied).
    inputs: Vec<Option<Vect>>,
    /// B's saved `S_k`, at `k % (delay + 1)`: the frames a late input can
    /// still send it back to.
    saves: Vec<FrameState>,
    /// Confirmed frames compared so far, and how many agreed.
    pub confirmed: u64,
    /// See [`Lockstep::confirmed`].
    pub agreed: u64,
    /// Rollbacks B made.
    pub rollbacks: u64,
    /// Frames B replayed in its last rollback.
    pub last_replay: u32,
}

/// At most this many frames of input delay (a ring of saves per frame).
pub const MAX_DELAY: u32 = 30;

impl Lockstep {
    /// Scene `name` on both peers, B receiving inputs `delay` frames late
    /// (at most [`MAX_DELAY`]).
    pub fn new(name: &str, delay: u32) -> Result<Lockstep, String> {
        if delay > MAX_DELAY {
            return Err(format!("delay {delay} is above {MAX_DELAY} frames"));
        }
        let desc = tamias2d_scenes::builtin(name).ok_or_else(|| format!("no scene {name:?}"))?;
        let build = || desc.build().map_err(|e| format!("{name}: {e}"));
        let (wa, wb) = (build()?, build()?);
        let ring = usize::try_from(delay).unwrap_or(0).saturating_add(2);
        let peer = |space: Space| {
            let mut p = Peer {
                space,
                checksums: vec![0; ring],
            };
            p.record(0);
            p
        };
        let saves = (0..ring.saturating_sub(1))
            .map(|_| FrameState::default())
            .collect();
        Ok(Lockstep {
            dropper: Dropper::of(&wa.space).scaled(2),
            dt: wa.dt,
            a: peer(wa.space),
            b: peer(wb.space),
            delay,
            frame: 0,
            inputs: Vec::new(),
            saves,
            confirmed: 0,
            agreed: 0,
            rollbacks: 0,
            last_replay: 0,
        })
    }

    /// Frames advanced.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// The input delay in frames.
    pub fn delay(&self) -> u32 {
        self.delay
    }

    /// Peer A (`false`) or B (`true`).
    pub fn space(&self, b: bool) -> &Space {
        if b {
            &self.b.space
        } else {
            &self.a.space
        }
    }

    /// One frame on both peers with this frame's input; returns the frames
    /// B replayed (0 if it did not roll back). Peer A's part and B's part
    /// are [`Lockstep::advance_a`] and [`Lockstep::advance_b`], for a page
    /// that times them apart.
    pub fn advance(&mut self, input: Option<Vect>) -> Result<u32, String> {
        self.advance_a(input)?;
        self.advance_b()
    }

    /// Peer A's frame: it applies `input` at once.
    pub fn advance_a(&mut self, input: Option<Vect>) -> Result<(), String> {
        if self.inputs.len() as u64 != self.frame {
            return Err("peer A is a frame ahead: advance peer B first".into());
        }
        simulate(&mut self.a.space, &self.dropper, self.dt, input)?;
        self.inputs.push(input);
        self.a.record(self.frame.saturating_add(1));
        Ok(())
    }

    /// Peer B's frame: receives the input of `delay` frames ago, rolls back
    /// and replays if it was not the "no input" B predicted, steps, then
    /// compares the newly confirmed frame with A's.
    pub fn advance_b(&mut self) -> Result<u32, String> {
        let f = self.frame;
        if self.inputs.len() as u64 != f.saturating_add(1) {
            return Err("advance peer A first".into());
        }
        let known_upto = f.checked_sub(u64::from(self.delay));
        let mut replayed: u32 = 0;
        if let Some(k) = known_upto {
            if self.input(k).is_some() && self.delay > 0 {
                // Mispredicted: back to S_k, replay k..f with what is known.
                let save = self
                    .saves
                    .get(slot(k, self.saves.len()))
                    .ok_or("no save for the rollback")?;
                self.b
                    .space
                    .restore_frame(save)
                    .map_err(|e| e.to_string())?;
                for j in k..f {
                    self.b_frame(j)?;
                    replayed = replayed.saturating_add(1);
                }
                self.rollbacks = self.rollbacks.saturating_add(1);
                self.last_replay = replayed;
            }
        }
        self.b_frame(f)?;
        self.frame = f.saturating_add(1);
        // S_{f+1-delay} is now final on B: every input before it is known.
        if let Some(c) = self.frame.checked_sub(u64::from(self.delay)) {
            self.confirmed = self.confirmed.saturating_add(1);
            let (a, b) = (self.a.checksum_of(c), self.b.checksum_of(c));
            if a.is_some() && a == b {
                self.agreed = self.agreed.saturating_add(1);
            }
        }
        Ok(replayed)
    }

    /// B's frame `j` (saving `S_j` first), with `I_j` if B has received it
    /// and "no input" otherwise.
    fn b_frame(&mut self, j: u64) -> Result<(), String> {
        let ring = self.saves.len();
        if let Some(save) = self.saves.get_mut(slot(j, ring)) {
            self.b.space.save_frame(save);
        }
        let input = if self.known_to_b(j) {
            self.input(j)
        } else {
            None
        };
        simulate(&mut self.b.space, &self.dropper, self.dt, input)?;
        self.b.record(j.saturating_add(1));
        Ok(())
    }

    /// B has received `I_j` by the current frame.
    fn known_to_b(&self, j: u64) -> bool {
        j.saturating_add(u64::from(self.delay)) <= self.frame
    }

    fn input(&self, k: u64) -> Option<Vect> {
        usize::try_from(k)
            .ok()
            .and_then(|k| self.inputs.get(k).copied())
            .flatten()
    }

    /// The last confirmed frame and both peers' checksums of it.
    pub fn confirmed_frame(&self) -> Option<(u64, u64, u64)> {
        let c = self.frame.checked_sub(u64::from(self.delay))?;
        Some((c, self.a.checksum_of(c)?, self.b.checksum_of(c)?))
    }

    /// Both peers' checksums of the current frame (B's is a prediction
    /// while an input may still be in flight).
    pub fn current(&self) -> (u64, u64) {
        let f = self.frame;
        (
            self.a.checksum_of(f).unwrap_or(0),
            self.b.checksum_of(f).unwrap_or(0),
        )
    }

    /// Status for the page, one JSON object (checksums as hex strings).
    pub fn status_json(&self) -> String {
        let hex = |c: u64| format!("{c:#018x}");
        let (a_now, b_now) = self.current();
        let confirmed = self.confirmed_frame();
        serde_json::json!({
            "frame": self.frame,
            "delay": self.delay,
            "confirmed_frame": confirmed.map(|(c, _, _)| c),
            "confirmed_a": confirmed.map(|(_, a, _)| hex(a)),
            "confirmed_b": confirmed.map(|(_, _, b)| hex(b)),
            "a_now": hex(a_now),
            "b_now": hex(b_now),
            "confirmed": self.confirmed,
            "agreed": self.agreed,
            "rollbacks": self.rollbacks,
            "last_replay": self.last_replay,
        })
        .to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inputs every `every` frames, at x cycling over a few columns.
    fn input(frame: u64, every: u64) -> Option<Vect> {
        (frame % every == every - 1).then(|| {
            let col = i32::try_from(frame / every % 5).unwrap_or(0);
            Vect::from_ints(-20 + 10 * col, 60)
        })
    }

    #[test]
    fn the_late_peer_rolls_back_and_agrees_on_every_confirmed_frame() -> Result<(), String> {
        let mut game = Lockstep::new("pyramid_20", 4)?;
        for f in 0..60 {
            game.advance(input(f, 7))?;
        }
        assert_eq!(game.frame(), 60);
        // 8 inputs arrived late, each one a rollback of 4 frames.
        assert_eq!(game.rollbacks, 8);
        assert_eq!(game.last_replay, 4);
        assert_eq!(game.confirmed, 57);
        assert_eq!(game.agreed, game.confirmed);
        // The confirmed frame is `delay` back, and both peers see it alike.
        let (c, a, b) = game.confirmed_frame().ok_or("confirmed")?;
        assert_eq!((c, a), (56, b));
        // And the same world as one peer that never predicted.
        let mut straight = Lockstep::new("pyramid_20", 0)?;
        for f in 0..60 {
            assert_eq!(straight.advance(input(f, 7))?, 0);
        }
        assert_eq!(straight.current().0, game.current().0);
        Ok(())
    }

    #[test]
    fn a_prediction_is_visible_until_the_input_arrives() -> Result<(), String> {
        let mut game = Lockstep::new("pyramid_20", 5)?;
        game.advance(Some(Vect::from_ints(0, 60)))?;
        // A dropped a ball; B has not heard of it.
        let (a, b) = game.current();
        assert_ne!(a, b);
        assert_eq!(
            game.space(false).bodies().count(),
            game.space(true).bodies().count() + 1
        );
        for _ in 0..5 {
            game.advance(None)?;
        }
        assert_eq!(game.rollbacks, 1);
        let (a, b) = game.current();
        assert_eq!(a, b);
        Ok(())
    }

    #[test]
    fn bad_calls_are_errors() {
        assert!(Lockstep::new("pyramid_20", MAX_DELAY + 1).is_err());
        assert!(Lockstep::new("no_such_scene", 2).is_err());
        if let Ok(mut game) = Lockstep::new("pyramid_20", 2) {
            assert!(game.advance_b().is_err());
            assert!(game.advance_a(None).is_ok());
            assert!(game.advance_a(None).is_err());
        }
    }
}
