//! The test game: a walled box with a pile of 16 crates and two player
//! balls. Each player's input is a button mask; a jump spends one of the
//! player's charges, which recharge every 30 frames: state beyond the
//! space, saved with it in a [`SpaceState`].
#![allow(dead_code)] // each test program uses a part

use serde::{Deserialize, Serialize};
use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Vect};
use tamias2d::replay::BoxError;
use tamias2d::shape::Shape;
use tamias2d::space::Space;
use tamias2d_ggrs::ggrs::InputStatus;
use tamias2d_ggrs::{RollbackGame, SpaceState};

pub const LEFT: u8 = 1;
pub const RIGHT: u8 = 2;
pub const JUMP: u8 = 4;

/// The game's own state: the frame number and each player's charges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Charges {
    pub frame: u64,
    pub left: [u32; 2],
}

/// How the game breaks itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sabotage {
    None,
    /// `load` restores the space but not the charges: state outside the
    /// saved state feeds the simulation.
    ForgetCharges,
    /// `save_into` saves a frame of another level, which `load` refuses.
    ForeignFrame,
}

pub struct Game {
    pub space: Space,
    pub players: [BodyHandle; 2],
    pub charges: Charges,
    pub sabotage: Sabotage,
}

fn ball(space: &mut Space, x: i32) -> BodyHandle {
    let mut body = Body::new(Real::ONE, Real::ONE).unwrap();
    body.set_position(Vect::from_ints(x, 1));
    let body = space.add_body(body).unwrap();
    space
        .add_shape(Shape::circle_shape_new(body, Real::HALF, Vect::ZERO).unwrap())
        .unwrap();
    body
}

impl Game {
    pub fn new() -> Game {
        let mut space = Space::new();
        space.set_gravity(Vect::from_ints(0, -10));
        let walls = space.add_body(Body::new_static()).unwrap();
        for (a, b) in [
            ((-10, 0), (10, 0)),
            ((-10, 0), (-10, 20)),
            ((10, 0), (10, 20)),
        ] {
            let (a, b) = (Vect::from_ints(a.0, a.1), Vect::from_ints(b.0, b.1));
            let wall = Shape::segment_shape_new(walls, a, b, Real::ZERO).unwrap();
            space.add_shape(wall).unwrap();
        }
        for i in 0..16 {
            let mut crate_ = Body::new(Real::ONE, Real::ONE).unwrap();
            crate_.set_position(Vect::new(
                Real::from_int(i % 4 - 2),
                Real::from_int(i / 4 + 1),
            ));
            let crate_ = space.add_body(crate_).unwrap();
            let shape = Shape::box_shape_new(crate_, Real::ONE, Real::ONE, Real::ZERO).unwrap();
            space.add_shape(shape).unwrap();
        }
        let players = [ball(&mut space, -6), ball(&mut space, 6)];
        Game {
            space,
            players,
            charges: Charges {
                frame: 0,
                left: [2, 2],
            },
            sabotage: Sabotage::None,
        }
    }

    /// One frame of buttons (for straight runs).
    pub fn step(&mut self, buttons: [u8; 2]) {
        let inputs = buttons.map(|b| (b, InputStatus::Confirmed));
        RollbackGame::advance(self, &inputs).unwrap();
    }
}

impl RollbackGame for Game {
    type Input = u8;
    type State = SpaceState<Charges>;

    fn save_into(&self, state: &mut SpaceState<Charges>) {
        if self.sabotage == Sabotage::ForeignFrame {
            let mut other = Game::new();
            other.space.add_body(Body::new_static()).unwrap();
            state.save(&other.space, &self.charges);
        } else {
            state.save(&self.space, &self.charges);
        }
    }

    fn load(&mut self, state: &SpaceState<Charges>) -> Result<(), BoxError> {
        if self.sabotage == Sabotage::ForgetCharges {
            let mut kept = self.charges;
            state.restore(&mut self.space, &mut kept)?;
        } else {
            state.restore(&mut self.space, &mut self.charges)?;
        }
        Ok(())
    }

    fn advance(&mut self, inputs: &[(u8, InputStatus)]) -> Result<(), BoxError> {
        for (i, (&player, &(buttons, _))) in self.players.iter().zip(inputs).enumerate() {
            let body = self.space.body_mut(player).ok_or("no player")?;
            let push = i32::from(buttons & RIGHT != 0) - i32::from(buttons & LEFT != 0);
            body.apply_force(Vect::from_ints(20 * push, 0));
            if buttons & JUMP != 0 && self.charges.left[i] > 0 {
                self.charges.left[i] -= 1;
                let center = body.center();
                body.apply_impulse_at_world_point(Vect::from_ints(0, 6), center);
            }
        }
        self.charges.frame += 1;
        if self.charges.frame.is_multiple_of(30) {
            self.charges.left = self.charges.left.map(|c| (c + 1).min(2));
        }
        Ok(self.space.step(Real::ratio(1, 60))?)
    }

    fn checksum(&self) -> u64 {
        SpaceState::checksum(&self.space, &self.charges)
    }
}

/// Player `player`'s buttons at `frame`: a pseudo-random mask held for
/// `hold` frames.
pub fn buttons(player: usize, frame: u64, hold: u64) -> u8 {
    let mut z = (frame / hold) ^ ((player as u64) << 40) ^ 0x5EED;
    z = z.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z ^= z >> 29;
    z = z.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    ((z >> 32) & 0b111) as u8
}

/// The straight run: frame `f` gets the buttons of frame `f − delay`
/// (none before), as a session with that input delay applies them.
/// Returns the checksum of every frame `0..=frames` and the game.
pub fn straight(frames: u64, hold: u64, delay: u64) -> (Vec<u64>, Game) {
    let mut game = Game::new();
    let mut sums = vec![game.checksum()];
    for f in 0..frames {
        let b = |p| f.checked_sub(delay).map_or(0, |g| buttons(p, g, hold));
        game.step([b(0), b(1)]);
        sums.push(game.checksum());
    }
    (sums, game)
}
