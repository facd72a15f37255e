//! The platformer level of the character mover (`examples/character.rs`
//! and its tests): chain terrain with a walkable 30° slope, a step and an
//! unwalkable 60° slope, a one-way platform, two crates to push, an
//! elevator (a moving kinematic platform) and a see-saw (a turning one),
//! and a capsule character driven by a scripted stick and jump button.
//!
//! ```text
//!   wall                                                        ______ wall
//!    |      see-saw  elevator     one-way          step _____/ 60°
//!    |       ____     ____         ____            ___|
//!    |____________________________________ crates /  30°
//!   x: -14   -10.5     -6          2–6      9 10 12–16 19   22–24   28
//! ```
//!
//! A frame is: the scripted platform velocities, [`Space::step`], then the
//! character's move by its velocity (gravity and stick added, the move's
//! report clipping it). The game's state is the space, the [`Character`],
//! its velocity and the frame number ([`CharacterGame::save`]); its
//! checksum folds the characters and velocities into the space's. The
//! level takes any number of players (the GGRS test runs two).
use serde::{Deserialize, Serialize};
use tamias2d::body::{Body, BodyHandle};
use tamias2d::character::{Character, CharacterConfig, MoveReport};
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::shape::mass::moment_for_box;
use tamias2d::shape::{Chain, ChainKind, Geometry, Segment, Shape, ShapeFilter};
use tamias2d::space::{FrameState, Space, SpaceError};

/// Frames of the scripted run.
pub const FRAMES: u64 = 1800;
/// The time step.
pub const DT: Real = real!(0.0166666666666666666);
/// Gravity along −y.
const GRAVITY: Real = real!(10);
/// Walking speed.
const WALK: Real = real!(4);
/// Jump speed.
const JUMP: Real = real!(6.5);
/// The one-way platforms' category.
pub const ONE_WAY: u32 = 0b10;

/// The stick and button of a frame: walk −1, 0 or +1; jump.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Buttons {
    /// −1 left, +1 right, 0 still.
    pub walk: i8,
    /// Jump (taken only while standing).
    pub jump: bool,
}

/// The scripted input of frame `f`: to the right, a jump through the
/// one-way platform onto it, a push at the crates and a jump over them, up
/// the slope and the step to the steep slope, which stops it; back to the
/// left down the slope, a jump, onto the elevator for a ride up, off it,
/// and a jump onto the see-saw for a ride back and forth.
pub fn script(f: u64) -> Buttons {
    let (walk, jump) = match f {
        0..60 => (0, false),
        60..84 => (1, false),
        84..86 => (1, true),
        86..235 => (1, false),
        235..237 => (1, true),
        237..440 => (1, false),
        440..460 => (0, false),
        460..700 => (-1, false),
        700..702 => (-1, true),
        702..800 => (-1, false),
        800..1000 => (0, false),
        1000..1085 => (-1, false),
        1085..1180 => (0, false),
        1180..1200 => (-1, false),
        1200..1240 => (0, false),
        1240..1242 => (-1, true),
        1242..1275 => (-1, false),
        1275..1500 => (0, false),
        1500..1600 => (1, false),
        _ => (0, false),
    };
    Buttons { walk, jump }
}

/// A player: the character and its velocity (the game's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Player {
    /// The character.
    pub character: Character,
    /// Its velocity.
    pub velocity: Vect,
}

/// The world and its players.
pub struct CharacterGame {
    /// The world.
    pub space: Space,
    /// The characters' mover settings.
    pub config: CharacterConfig,
    /// The players.
    pub players: Vec<Player>,
    /// Frames run.
    pub frame: u64,
    /// The elevator (kinematic, moves up and down).
    pub elevator: BodyHandle,
    /// The see-saw (kinematic, turns back and forth).
    pub seesaw: BodyHandle,
    /// The crates.
    pub crates: Vec<BodyHandle>,
    /// Each player's last move.
    pub last: Vec<MoveReport>,
}

/// A saved frame of the game.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct SavedFrame {
    frame: u64,
    space: FrameState,
    players: Vec<Player>,
}

fn v(x: Real, y: Real) -> Vect {
    Vect::new(x, y)
}

impl CharacterGame {
    /// The level with one player standing at x = 0.
    pub fn new() -> Result<CharacterGame, Box<dyn std::error::Error>> {
        CharacterGame::with_players(&[Real::ZERO])
    }

    /// The level with a player standing at each of these x positions.
    pub fn with_players(xs: &[Real]) -> Result<CharacterGame, Box<dyn std::error::Error>> {
        let mut space = Space::new();
        space.set_gravity(v(Real::ZERO, -GRAVITY));
        let ground = space.add_body(Body::new_static())?;
        let rise30 = real!(2.3094010767585); // 4·tan 30°
        let rise60 = real!(3.4641016151377); // 2·tan 60°
        let step = real!(0.25);
        let points = [
            v(real!(-14), real!(8)),
            v(real!(-14), Real::ZERO),
            v(real!(12), Real::ZERO),
            v(real!(16), rise30),
            v(real!(19), rise30),
            v(real!(19), rise30 + step),
            v(real!(22), rise30 + step),
            v(real!(24), rise30 + step + rise60),
            v(real!(28), rise30 + step + rise60),
            v(real!(28), real!(12)),
        ];
        let chain = Chain::new(&points, ChainKind::Open)?.with_material(real!(0.8), Real::ZERO)?;
        space.add_chain(ground, &chain)?;
        // The one-way platform.
        let one_way = Shape::segment_shape_new(
            ground,
            v(real!(2), real!(1.6)),
            v(real!(6), real!(1.6)),
            real!(0.05),
        )?;
        let one_way_handle = space.add_shape(one_way)?;
        space.modify_shape(one_way_handle, |s| {
            s.filter = ShapeFilter {
                categories: ONE_WAY,
                ..ShapeFilter::ALL
            };
            Ok(())
        })?;
        // Crates.
        let mut crates = Vec::new();
        for x in [real!(9), real!(10.2)] {
            let (m, side) = (real!(2), real!(0.6));
            let mut b = Body::new(m, moment_for_box(m, side, side))?;
            b.set_position(v(x, real!(0.3)));
            let h = space.add_body(b)?;
            let s = Shape::box_shape_new(h, side, side, Real::ZERO)?;
            space.add_shape(s.with_material(real!(0.5), Real::ZERO)?)?;
            crates.push(h);
        }
        // The elevator: a 2 m × 0.2 m kinematic slab resting on the floor.
        let mut e = Body::new_kinematic();
        e.set_position(v(real!(-6), real!(0.1)));
        let elevator = space.add_body(e)?;
        space.add_shape(
            Shape::box_shape_new(elevator, real!(2), real!(0.2), Real::ZERO)?
                .with_material(real!(0.8), Real::ZERO)?,
        )?;
        // The see-saw: a 4 m bar turning about its middle.
        let mut s = Body::new_kinematic();
        s.set_position(v(real!(-10.5), real!(0.6)));
        let seesaw = space.add_body(s)?;
        space.add_shape(
            Shape::box_shape_new(seesaw, real!(4), real!(0.2), Real::ZERO)?
                .with_material(real!(0.8), Real::ZERO)?,
        )?;
        let capsule = Geometry::Segment(Segment::new(
            v(Real::ZERO, real!(-0.4)),
            v(Real::ZERO, real!(0.4)),
            real!(0.3),
        ));
        let config = CharacterConfig::new(capsule)?
            .with_push_force(real!(60))?
            .with_one_way_categories(ONE_WAY);
        let players = xs
            .iter()
            .map(|&x| Player {
                character: Character::new(v(x, real!(0.72))),
                velocity: Vect::ZERO,
            })
            .collect();
        Ok(CharacterGame {
            space,
            config,
            players,
            frame: 0,
            elevator,
            seesaw,
            crates,
            last: vec![MoveReport::default(); xs.len()],
        })
    }

    /// One frame with each player's buttons (missing ones: none).
    pub fn step(&mut self, buttons: &[Buttons]) -> Result<(), SpaceError> {
        self.drive_platforms();
        self.space.step(DT)?;
        for (i, player) in self.players.iter_mut().enumerate() {
            let b = buttons.get(i).copied().unwrap_or_default();
            let standing = player.character.ground.is_some();
            let mut vel = player.velocity;
            vel.x = WALK * Real::from_int(i32::from(b.walk));
            // Standing, the ground holds the character: only gravity's
            // pull this frame (the move slides it along the ground).
            vel.y = if standing && b.jump {
                JUMP
            } else if standing {
                -GRAVITY * DT
            } else {
                vel.y - GRAVITY * DT
            };
            let report = player
                .character
                .move_by(&mut self.space, &self.config, vel * DT, DT);
            player.velocity = report.clip_velocity(vel);
            if let Some(slot) = self.last.get_mut(i) {
                *slot = report;
            }
        }
        self.frame = self.frame.saturating_add(1);
        Ok(())
    }

    /// The platforms' velocities for this frame: the elevator rises for
    /// 3 s and comes down for 3 s at 1 m/s; the see-saw turns at 0.3 rad/s
    /// one way for 1.5 s and back for 1.5 s (±0.45 rad, under the 45°
    /// walkable limit).
    fn drive_platforms(&mut self) {
        let up = (self.frame % 360) < 180;
        if let Some(e) = self.space.body_mut(self.elevator) {
            e.set_velocity(v(Real::ZERO, if up { Real::ONE } else { -Real::ONE }));
        }
        let phase = (self.frame.saturating_add(45)) % 180 < 90;
        if let Some(s) = self.space.body_mut(self.seesaw) {
            s.set_angular_velocity(if phase { real!(0.3) } else { real!(-0.3) });
        }
    }

    /// The game's checksum: the space's with the character and its
    /// velocity folded in.
    pub fn checksum(&self) -> u64 {
        let c = self
            .players
            .iter()
            .fold(self.space.checksum(), |c, p| p.character.fold_checksum(c));
        let velocities: Vec<Vect> = self.players.iter().map(|p| p.velocity).collect();
        tamias2d::checksum::checksum_of(&(c, velocities, self.frame))
    }

    /// This frame of the game.
    pub fn save(&self) -> SavedFrame {
        let mut space = FrameState::default();
        self.space.save_frame(&mut space);
        SavedFrame {
            frame: self.frame,
            space,
            players: self.players.clone(),
        }
    }

    /// Back to a saved frame of this level.
    pub fn restore(&mut self, saved: &SavedFrame) -> Result<(), SpaceError> {
        self.space.restore_frame(&saved.space)?;
        self.frame = saved.frame;
        self.players.clone_from(&saved.players);
        Ok(())
    }
}

/// The game under GGRS (feature `ggrs`): each player's input is its
/// [`Buttons`], the saved state a [`SavedFrame`] (the space's frame, the
/// players and the frame number), the checksum [`CharacterGame::checksum`].
#[cfg(feature = "ggrs")]
impl tamias2d_ggrs::RollbackGame for CharacterGame {
    type Input = Buttons;
    type State = SavedFrame;

    fn save_into(&self, state: &mut SavedFrame) {
        self.space.save_frame(&mut state.space);
        state.frame = self.frame;
        state.players.clone_from(&self.players);
    }

    fn load(&mut self, state: &SavedFrame) -> Result<(), tamias2d::replay::BoxError> {
        Ok(self.restore(state)?)
    }

    fn advance(
        &mut self,
        inputs: &[(Buttons, tamias2d_ggrs::ggrs::InputStatus)],
    ) -> Result<(), tamias2d::replay::BoxError> {
        let buttons: Vec<Buttons> = inputs.iter().map(|&(b, _)| b).collect();
        Ok(self.step(&buttons)?)
    }

    fn checksum(&self) -> u64 {
        CharacterGame::checksum(self)
    }
}

/// The height of the terrain chain under `x` (the floor a character may
/// never end below), `None` outside the level.
pub fn floor_height(x: Real) -> Option<Real> {
    let rise30 = real!(2.3094010767585);
    let top = rise30 + real!(0.25);
    let h = if x < real!(-14) || x > real!(28) {
        return None;
    } else if x <= real!(12) {
        Real::ZERO
    } else if x <= real!(16) {
        (x - real!(12)) * rise30 / real!(4)
    } else if x < real!(19) {
        rise30
    } else if x <= real!(22) {
        top
    } else if x <= real!(24) {
        top + (x - real!(22)) * real!(1.7320508075689)
    } else {
        top + real!(3.4641016151377)
    };
    Some(h)
}

/// True if `c` overlaps a solid shape of the level (not a sensor, not
/// one-way) by more than `depth`.
pub fn inside_solid(game: &CharacterGame, c: &Character, depth: Real) -> bool {
    let world = c.world_shape(&game.config);
    game.space
        .shape_query(&world, ShapeFilter::ALL)
        .iter()
        .any(|(h, set)| {
            let solid = game
                .space
                .shape(*h)
                .is_some_and(|s| !s.sensor && !game.config.is_one_way(s));
            solid
                && set
                    .points
                    .iter()
                    .take(set.count)
                    .any(|p| p.distance < -depth)
        })
}

/// The states a run counts, in the order of [`RunStats::seen`].
pub const STATES: [&str; 8] = [
    "grounded",
    "airborne",
    "on elevator",
    "on see-saw",
    "on one-way platform",
    "blocked by slope",
    "stepped",
    "pushing",
];

/// What a run of the level saw (player 0).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunStats {
    /// Frames observed.
    pub frames: u64,
    /// Frames that ended with the character below the terrain.
    pub fell_through: u64,
    /// Frames that ended with the character inside a solid shape (deeper
    /// than two skins).
    pub stuck: u64,
    /// The largest gap to the ground of a standing frame.
    pub max_ground_gap: Real,
    /// Frames in each of [`STATES`].
    pub seen: [u64; 8],
    /// Times each of [`STATES`] was entered.
    pub entered: [u64; 8],
    /// The states of the last frame.
    last: [bool; 8],
}

impl RunStats {
    /// Counts the frame the game just ran.
    pub fn observe(&mut self, game: &CharacterGame) {
        let (Some(player), Some(report)) = (game.players.first(), game.last.first()) else {
            return;
        };
        self.frames = self.frames.saturating_add(1);
        let c = &player.character;
        let bottom = c.position.y - real!(0.7);
        let below = floor_height(c.position.x).is_none_or(|h| bottom < h - real!(0.05));
        self.fell_through = self.fell_through.saturating_add(u64::from(below));
        let inside = inside_solid(game, c, game.config.skin() + game.config.skin());
        self.stuck = self.stuck.saturating_add(u64::from(inside));
        if let Some(gap) = report.ground_gap {
            self.max_ground_gap = self.max_ground_gap.max(gap);
        }
        let ground_body = c.ground.map(|g| g.body);
        let on_one_way = c.ground.is_some_and(|g| {
            game.space
                .shape(g.shape)
                .is_some_and(|s| game.config.is_one_way(s))
        });
        let now = [
            report.grounded,
            !report.grounded,
            ground_body == Some(game.elevator),
            ground_body == Some(game.seesaw),
            on_one_way,
            report.blocked_by_slope,
            report.stepped,
            report.pushed > 0,
        ];
        for (k, &state) in now.iter().enumerate() {
            if let (Some(seen), Some(entered), Some(&was)) = (
                self.seen.get_mut(k),
                self.entered.get_mut(k),
                self.last.get(k),
            ) {
                *seen = seen.saturating_add(u64::from(state));
                *entered = entered.saturating_add(u64::from(state && !was));
            }
        }
        self.last = now;
    }
}
