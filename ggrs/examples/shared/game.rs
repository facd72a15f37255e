//! The examples' game: two balls on a hill of crates, each player's input
//! a button mask. Jumping spends the player's energy, which refills one
//! unit a frame: game state beyond the space, saved with it in a
//! [`SpaceState`].
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

/// Energy a jump costs; each player holds at most this.
const JUMP_COST: u32 = 40;

/// The game's own state: each player's energy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Energy(pub [u32; 2]);

pub struct Game {
    pub space: Space,
    pub players: [BodyHandle; 2],
    pub energy: Energy,
}

impl Game {
    pub fn new() -> Result<Game, BoxError> {
        let mut space = Space::new();
        space.set_gravity(Vect::from_ints(0, -10));
        let ground = space.add_body(Body::new_static())?;
        for (a, b) in [((-15, 4), (0, 0)), ((0, 0), (15, 4))] {
            let (a, b) = (Vect::from_ints(a.0, a.1), Vect::from_ints(b.0, b.1));
            space.add_shape(Shape::segment_shape_new(ground, a, b, Real::ZERO)?)?;
        }
        for row in 0..4 {
            for col in 0..(4 - row) {
                let mut body = Body::new(Real::ONE, Real::ratio(1, 6))?;
                body.set_position(Vect::new(
                    Real::from_int(col - 2) + Real::ratio(row, 2),
                    Real::from_int(row + 1),
                ));
                let body = space.add_body(body)?;
                space.add_shape(Shape::box_shape_new(
                    body,
                    Real::ONE,
                    Real::ONE,
                    Real::ZERO,
                )?)?;
            }
        }
        let mut ball = |x: i32| -> Result<BodyHandle, BoxError> {
            let mut body = Body::new(Real::from_int(2), Real::ONE)?;
            body.set_position(Vect::from_ints(x, 4));
            let body = space.add_body(body)?;
            space.add_shape(Shape::circle_shape_new(body, Real::HALF, Vect::ZERO)?)?;
            Ok(body)
        };
        let players = [ball(-10)?, ball(10)?];
        Ok(Game {
            space,
            players,
            energy: Energy([JUMP_COST; 2]),
        })
    }
}

impl RollbackGame for Game {
    type Input = u8;
    type State = SpaceState<Energy>;

    fn save_into(&self, state: &mut SpaceState<Energy>) {
        state.save(&self.space, &self.energy);
    }

    fn load(&mut self, state: &SpaceState<Energy>) -> Result<(), BoxError> {
        Ok(state.restore(&mut self.space, &mut self.energy)?)
    }

    fn advance(&mut self, inputs: &[(u8, InputStatus)]) -> Result<(), BoxError> {
        let players = self.players.iter().zip(&mut self.energy.0);
        for ((&player, energy), &(buttons, _)) in players.zip(inputs) {
            let body = self.space.body_mut(player).ok_or("no such player")?;
            let push = i32::from(buttons & RIGHT != 0) - i32::from(buttons & LEFT != 0);
            body.apply_force(Vect::from_ints(30 * push, 0));
            if buttons & JUMP != 0 && *energy >= JUMP_COST {
                *energy -= JUMP_COST;
                let center = body.center();
                body.apply_impulse_at_world_point(Vect::from_ints(0, 12), center);
            }
            *energy = (*energy + 1).min(JUMP_COST);
        }
        Ok(self.space.step(Real::ratio(1, 60))?)
    }

    fn checksum(&self) -> u64 {
        SpaceState::checksum(&self.space, &self.energy)
    }
}

/// Player `player`'s buttons at `frame`: a scripted pattern, each mask
/// held 6 frames (a real game reads its controller here).
pub fn buttons(player: usize, frame: u64) -> u8 {
    const PATTERN: [u8; 5] = [RIGHT, RIGHT | JUMP, 0, LEFT, LEFT | JUMP];
    let step = (frame / 6).wrapping_add(player as u64 * 2);
    PATTERN[(step % PATTERN.len() as u64) as usize]
}
