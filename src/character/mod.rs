//! A kinematic character mover: moves a shape (a capsule is best) through a
//! space by a desired translation, sliding along what it meets, the way a
//! platformer or a fighting game moves its characters.
//!
//! The character is not a body of the space: bodies do not push it, and it
//! does not take part in the step. It is plain data ([`Character`]: its
//! position and what it stood on) that the game keeps beside its space,
//! moves once per frame with [`Character::move_by`], and saves, restores
//! and checksums with its frame ([`Character::fold_checksum`]). Every
//! operation is `Real` (I32F32) arithmetic on the space's shapes, so a move
//! gives the same bits on every platform and after any restore, like the
//! step.
//!
//! # One move
//! 1. **Carried.** If the character stood on a moving or turning body at
//!    the end of its last move, it first follows that body: its position,
//!    kept in the body's own frame, is put back into the world (so a
//!    turning platform carries it round exactly), swept against everything
//!    but that body.
//! 2. **Pushed out.** Shapes that moved into it since (a crate, a platform)
//!    are resolved: the overlaps become planes and a small plane solver
//!    finds the least translation that clears them all.
//! 3. **Collide and slide.** The desired translation is cast
//!    ([`Space::shape_cast_all`]); at the first hit the character stops
//!    [`skin`](CharacterConfig::with_skin) short of the surface, and the
//!    rest of the translation is projected onto the surface and cast again,
//!    up to [`max_slides`](CharacterConfig::with_max_slides) times.
//!    * A surface whose normal is within the **walkable slope** of `up` is
//!      ground. A steeper one facing up blocks: a translation that was not
//!      going up is not turned into a climb (the surface acts as a wall and
//!      [`MoveReport::blocked_by_slope`] is set).
//!    * A wall met while standing is tried as a **step**: up by
//!      [`step_height`](CharacterConfig::with_step_height), forward, and
//!      down again, kept only if it lands on walkable ground.
//!    * A dynamic body met is **pushed** with an impulse of at most
//!      [`push_force`](CharacterConfig::with_push_force) · `dt` (its own
//!      mass times the approach speed if that is less), at the contact.
//!    * Shapes whose categories are **one-way** block only from above: a
//!      walkable surface met moving down, never from below or the side.
//! 4. **Snapped.** A character that stood on ground and is not moving up
//!    follows the ground down by up to
//!    [`snap_distance`](CharacterConfig::with_snap_distance) (down a slope or a step)
//!    instead of leaving it.
//! 5. **Ground.** A short cast down says whether it stands, on what, and
//!    how far above it ([`MoveReport::ground_gap`], about the skin).
//!
//! Velocity is the game's: it adds gravity and input to its own velocity,
//! asks for `velocity · dt`, and clips what the move reports with
//! [`MoveReport::clip_velocity`] (no speed builds up against a wall or a
//! floor).
use serde::{Deserialize, Serialize};

use crate::body::{BodyHandle, BodyType};
use crate::checksum::checksum_of;
use crate::collision::shapes_collide;
use crate::math::{Real, Rot, Vect};
use crate::shape::{Geometry, Shape, ShapeFilter, ShapeHandle};
use crate::space::{ShapeCast, Space, StartContact};

mod planes;

pub use planes::{solve_planes, Plane};

/// Why a [`CharacterConfig`] setting was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CharacterError {
    /// The setting named is outside its range (the message says which).
    OutOfRange(&'static str),
}

impl core::fmt::Display for CharacterError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CharacterError::OutOfRange(what) => write!(f, "character setting out of range: {what}"),
        }
    }
}

impl std::error::Error for CharacterError {}

/// The least upward component of a surface normal for a surface too
/// steep to walk to count as a slope (about 11.5°); below it, a wall.
const SLOPE_MIN: Real = Real::from_bits(858_993_459);

/// The longest translation of one move: the casts are exact while the
/// shapes and the path lie within 2^30 m of each other, so a longer
/// translation is shortened to this (2^24 m, its direction kept).
pub const MAX_MOVE: Real = Real::from_int(1 << 24);

/// `v` shortened to at most `max` (its direction kept).
fn clamp_length(v: Vect, max: Real) -> Vect {
    let (dir, len) = v.normalize_with_length();
    if len > max {
        dir * max
    } else {
        v
    }
}

/// How far below the character, in skins, ground counts as under it.
const PROBE_SKINS: Real = Real::from_int(2);

/// Most slides of one move ([`CharacterConfig::with_max_slides`]).
pub const MAX_SLIDES: u32 = 16;

/// How a character moves: its shape and the rules of the ground. Built
/// once per kind of character; every setter checks its range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CharacterConfig {
    shape: Geometry,
    up: Vect,
    walkable: Real,
    step_height: Real,
    snap_distance: Real,
    skin: Real,
    push_force: Real,
    one_way: u32,
    filter: ShapeFilter,
    max_slides: u32,
}

impl CharacterConfig {
    /// A character of `shape` (relative to the character's position; a
    /// capsule, `Geometry::Segment` with a radius, slides most smoothly),
    /// with defaults for a character about 1–2 m tall in metres: up is
    /// `+y`, slopes up to 45° are walkable, steps up to 0.3 m, snapping
    /// down 0.3 m, a skin of 0.01 m, no pushing, no one-way categories,
    /// every shape seen, 4 slides.
    pub fn new(shape: Geometry) -> Result<CharacterConfig, CharacterError> {
        shape
            .validate()
            .map_err(|_| CharacterError::OutOfRange("shape"))?;
        Ok(CharacterConfig {
            shape,
            up: Vect::new(Real::ZERO, Real::ONE),
            // cos 45°.
            walkable: Real::from_bits(3_037_000_500),
            step_height: Real::ratio(3, 10),
            snap_distance: Real::ratio(3, 10),
            skin: Real::ratio(1, 100),
            push_force: Real::ZERO,
            one_way: 0,
            filter: ShapeFilter::ALL,
            max_slides: 4,
        })
    }

    /// The direction of up (normalised; not zero).
    pub fn with_up(mut self, up: Vect) -> Result<CharacterConfig, CharacterError> {
        let n = up.normalize();
        if n == Vect::ZERO {
            return Err(CharacterError::OutOfRange("up must not be zero"));
        }
        self.up = n;
        Ok(self)
    }

    /// The steepest walkable slope, in radians, in `[0, π/2)`.
    pub fn with_max_slope(mut self, angle: Real) -> Result<CharacterConfig, CharacterError> {
        if angle.is_negative() || angle >= Real::FRAC_PI_2 {
            return Err(CharacterError::OutOfRange("max slope must be in [0, π/2)"));
        }
        self.walkable = crate::math::trig::cos(angle);
        Ok(self)
    }

    /// The highest step climbed without jumping (≥ 0).
    pub fn with_step_height(mut self, h: Real) -> Result<CharacterConfig, CharacterError> {
        self.step_height = non_negative(h, "step height must not be negative")?;
        Ok(self)
    }

    /// How far the character follows the ground down (≥ 0).
    pub fn with_snap_distance(mut self, d: Real) -> Result<CharacterConfig, CharacterError> {
        self.snap_distance = non_negative(d, "snap distance must not be negative")?;
        Ok(self)
    }

    /// The gap kept between the character and what it touches (> 0): the
    /// casts start apart, so sliding along a surface never starts in it.
    pub fn with_skin(mut self, skin: Real) -> Result<CharacterConfig, CharacterError> {
        if !skin.is_positive() {
            return Err(CharacterError::OutOfRange("skin must be positive"));
        }
        self.skin = skin;
        Ok(self)
    }

    /// The largest force the character pushes dynamic bodies with (≥ 0;
    /// 0: it does not push them, they only block it).
    pub fn with_push_force(mut self, f: Real) -> Result<CharacterConfig, CharacterError> {
        self.push_force = non_negative(f, "push force must not be negative")?;
        Ok(self)
    }

    /// Shapes whose filter categories all lie in `categories` are one-way
    /// platforms (a shape keeps every category by default, so only shapes
    /// given these categories alone are one-way). 0: none.
    pub fn with_one_way_categories(mut self, categories: u32) -> CharacterConfig {
        self.one_way = categories;
        self
    }

    /// What the character collides with (a shape its filter rejects is
    /// passed through).
    pub fn with_filter(mut self, filter: ShapeFilter) -> CharacterConfig {
        self.filter = filter;
        self
    }

    /// Slides per move, 1 to [`MAX_SLIDES`].
    pub fn with_max_slides(mut self, n: u32) -> Result<CharacterConfig, CharacterError> {
        if !(1..=MAX_SLIDES).contains(&n) {
            return Err(CharacterError::OutOfRange("max slides must be 1 to 16"));
        }
        self.max_slides = n;
        Ok(self)
    }

    /// The character's shape, relative to its position.
    pub fn shape(&self) -> &Geometry {
        &self.shape
    }

    /// The unit up direction.
    pub fn up(&self) -> Vect {
        self.up
    }

    /// The skin.
    pub fn skin(&self) -> Real {
        self.skin
    }

    /// True if `shape` is a one-way platform for this character: its
    /// categories are not empty and all lie in the one-way categories.
    pub fn is_one_way(&self, shape: &Shape) -> bool {
        let c = shape.filter.categories;
        self.one_way != 0 && c != 0 && c & !self.one_way == 0
    }

    /// True if a surface of unit normal `n` is walkable ground.
    pub fn is_walkable(&self, n: Vect) -> bool {
        n.dot(self.up) >= self.walkable
    }
}

fn non_negative(v: Real, what: &'static str) -> Result<Real, CharacterError> {
    if v.is_negative() {
        Err(CharacterError::OutOfRange(what))
    } else {
        Ok(v)
    }
}

/// What a character stands on, kept between moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Ground {
    /// The shape under the character.
    pub shape: ShapeHandle,
    /// Its body.
    pub body: BodyHandle,
    /// Its surface normal there (unit, out of the ground).
    pub normal: Vect,
    /// The character's position in the body's frame: where the body
    /// carries it.
    pub anchor: Vect,
}

/// A character's state: plain data the game keeps with its frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Character {
    /// Where the character is (its shape's origin).
    pub position: Vect,
    /// What it stood on at the end of its last move.
    pub ground: Option<Ground>,
}

/// What one move did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveReport {
    /// The whole translation of the move (carried, pushed out, slid,
    /// stepped and snapped).
    pub translation: Vect,
    /// Carried by this body (a moving or turning one it stood on).
    pub carried_by: Option<BodyHandle>,
    /// Standing on walkable ground at the end.
    pub grounded: bool,
    /// The gap between the character and the ground, when standing.
    pub ground_gap: Option<Real>,
    /// Stopped by ground too steep to walk.
    pub blocked_by_slope: bool,
    /// Met a surface facing down.
    pub hit_ceiling: bool,
    /// Met a wall.
    pub hit_wall: bool,
    /// Climbed a step.
    pub stepped: bool,
    /// Followed the ground down.
    pub snapped: bool,
    /// Pushed out of overlapping shapes by this much.
    pub depenetration: Real,
    /// Dynamic bodies pushed.
    pub pushed: u32,
    /// The surfaces met (unit normals out of them), for
    /// [`clip_velocity`](Self::clip_velocity).
    normals: [Vect; MAX_SLIDES as usize],
    normal_count: u32,
}

impl MoveReport {
    /// `v` without its components into the surfaces the move met: the
    /// game's velocity after the move, so that speed does not build up
    /// against a floor, a wall or a ceiling.
    pub fn clip_velocity(&self, v: Vect) -> Vect {
        self.normals()
            .iter()
            .fold(v, |v, &n| v - n * v.dot(n).min(Real::ZERO))
    }

    /// The unit normals of the surfaces met, in the order met.
    pub fn normals(&self) -> &[Vect] {
        self.normals
            .get(..self.normal_count as usize)
            .unwrap_or(&[])
    }

    fn met(&mut self, n: Vect) {
        if let Some(slot) = self.normals.get_mut(self.normal_count as usize) {
            *slot = n;
            self.normal_count = self.normal_count.saturating_add(1);
        }
    }
}

/// The first surface a cast meets.
#[derive(Clone, Copy, Debug)]
struct Hit {
    shape: ShapeHandle,
    body: BodyHandle,
    fraction: Real,
    /// Unit normal out of the surface, toward the character.
    normal: Vect,
    point: Vect,
}

impl Character {
    /// A character at `position`, standing on nothing yet.
    pub fn new(position: Vect) -> Character {
        Character {
            position,
            ground: None,
        }
    }

    /// The character's shape where it is.
    pub fn world_shape(&self, config: &CharacterConfig) -> Geometry {
        config.shape.to_world(self.position, Rot::IDENTITY)
    }

    /// `space_checksum` (the frame's [`Space::checksum`]) with this
    /// character folded in: the one number a rollback game compares.
    pub fn fold_checksum(&self, space_checksum: u64) -> u64 {
        checksum_of(&(space_checksum, self))
    }

    /// Moves the character by `desired` (see the module docs for the
    /// order of a move). `dt` is the frame's time step, for the pushes'
    /// impulses. Pushes wake the bodies pushed; nothing else in the space
    /// changes.
    pub fn move_by(
        &mut self,
        space: &mut Space,
        config: &CharacterConfig,
        desired: Vect,
        dt: Real,
    ) -> MoveReport {
        let start = self.position;
        let mut report = MoveReport::default();
        let was_grounded = self.ground.is_some();
        let mut pushes = Pushes::default();

        // 1. Carried by the body stood on.
        if let Some(g) = self.ground {
            let carrier = space
                .body(g.body)
                .filter(|b| b.body_type() != BodyType::Static)
                .map(|b| b.local_to_world(g.anchor));
            if let Some(target) = carrier {
                report.carried_by = Some(g.body);
                let carry = target - self.position;
                self.slide(
                    space,
                    config,
                    carry,
                    Some(g.body),
                    false,
                    &mut report,
                    None,
                    dt,
                );
            }
        }

        // 2. Out of whatever moved into it.
        report.depenetration = self.depenetrate(space, config);

        // 3. Collide and slide.
        self.slide(
            space,
            config,
            desired,
            None,
            was_grounded,
            &mut report,
            Some(&mut pushes),
            dt,
        );
        pushes.apply(space);
        report.pushed = pushes.count;

        // 4. Snap to the ground.
        let going_up = desired.dot(config.up).is_positive();
        // Down a slope or off a step the ground falls away: follow it
        // while it is within the snap distance, back to one skin above it.
        // A character that lands within the ground probe settles the same
        // way.
        let probe = self.probe_ground(space, config);
        let floating = probe.is_none_or(|(_, gap)| gap > config.skin);
        let reach = if was_grounded {
            config.snap_distance.max(PROBE_SKINS * config.skin)
        } else if probe.is_some() {
            PROBE_SKINS * config.skin
        } else {
            Real::ZERO
        };
        if !going_up && floating && reach.is_positive() {
            let down = -config.up * reach;
            if let Some(hit) = self.first_hit(space, config, down, None, true) {
                if config.is_walkable(hit.normal) {
                    self.advance_to(down, &hit);
                    report.snapped = probe.is_none();
                }
            }
        }

        // 5. The ground.
        self.ground = None;
        if let Some((hit, gap)) = self.probe_ground(space, config) {
            report.grounded = true;
            report.ground_gap = Some(gap);
            let anchor = space
                .body(hit.body)
                .map_or(self.position, |b| b.world_to_local(self.position));
            self.ground = Some(Ground {
                shape: hit.shape,
                body: hit.body,
                normal: hit.normal,
                anchor,
            });
        }
        report.translation = self.position - start;
        report
    }

    /// Collide and slide by `delta`; `exclude`: a body not collided with
    /// (the carrier); `standing`: steps may be tried; `pushes`: dynamic
    /// bodies met are recorded to be pushed.
    #[allow(clippy::too_many_arguments)]
    fn slide(
        &mut self,
        space: &Space,
        config: &CharacterConfig,
        delta: Vect,
        exclude: Option<BodyHandle>,
        standing: bool,
        report: &mut MoveReport,
        mut pushes: Option<&mut Pushes>,
        dt: Real,
    ) {
        let up = config.up;
        let delta = clamp_length(delta, MAX_MOVE);
        let climbing_asked = delta.dot(up).is_positive();
        let mut remaining = delta;
        for _ in 0..config.max_slides {
            if remaining == Vect::ZERO {
                break;
            }
            let Some(hit) = self.first_hit(space, config, remaining, exclude, true) else {
                self.position += remaining;
                return;
            };
            let t = self.advance_to(remaining, &hit);
            remaining = remaining * (Real::ONE - t);
            let n = hit.normal;
            report.met(n);
            let facing_up = n.dot(up);
            let walkable = config.is_walkable(n);
            if let Some(p) = pushes.as_deref_mut() {
                p.record(space, config, &hit, remaining, dt);
            }
            if !walkable && facing_up <= -config.walkable {
                report.hit_ceiling = true;
            } else if !walkable {
                report.hit_wall = true;
                if standing && config.step_height.is_positive() {
                    if let Some(rest) = self.try_step(space, config, remaining, exclude) {
                        report.stepped = true;
                        remaining = rest;
                        continue;
                    }
                }
            }
            // On walkable ground the pull down is held by the ground, not
            // turned into a slide down the slope.
            if walkable {
                remaining = remaining - up * remaining.dot(up).min(Real::ZERO);
            }
            let mut slid = remaining - n * remaining.dot(n).min(Real::ZERO);
            // A steep slope facing up does not turn a walk into a climb.
            if !walkable && facing_up.is_positive() && !climbing_asked && slid.dot(up).is_positive()
            {
                let flat = (n - up * facing_up).normalize();
                slid = remaining - flat * remaining.dot(flat).min(Real::ZERO);
                // Near-vertical faces (a crate's side) are walls, not slopes.
                report.blocked_by_slope |= facing_up >= SLOPE_MIN;
            }
            remaining = slid;
        }
    }

    /// Moves to the hit of a cast of the shape grown by the skin: the
    /// skin's width short of the surface. Returns the fraction of `delta`
    /// moved.
    fn advance_to(&mut self, delta: Vect, hit: &Hit) -> Real {
        let t = hit.fraction.clamp(Real::ZERO, Real::ONE);
        self.position += delta * t;
        t
    }

    /// A step over the wall just met: up, forward by the rest of the
    /// translation's part across `up`, and down onto walkable ground.
    /// Returns the translation left (the part along `up`), or `None` (and
    /// the character unmoved) if the step does not land on walkable ground
    /// higher than it started by at most the step height.
    fn try_step(
        &mut self,
        space: &Space,
        config: &CharacterConfig,
        remaining: Vect,
        exclude: Option<BodyHandle>,
    ) -> Option<Vect> {
        let up = config.up;
        let along_up = up * remaining.dot(up);
        let across = remaining - along_up;
        let (dir, len) = across.normalize_with_length();
        if len <= config.skin {
            return None;
        }
        // A round foot stands on the step's edge only once its centre is
        // within `radius · sin(max slope)` of it: go at least that far.
        let sin_max = (Real::ONE - config.walkable * config.walkable).sqrt();
        let foot = config.shape.radius();
        let least = foot * (Real::ONE - sin_max) + config.skin + config.skin;
        let across = dir * len.max(least);
        let start = self.position;
        let rise = up * config.step_height;
        if let Some(hit) = self.first_hit(space, config, rise, exclude, true) {
            self.advance_to(rise, &hit);
        } else {
            self.position += rise;
        }
        let lifted = self.position;
        if let Some(hit) = self.first_hit(space, config, across, exclude, true) {
            self.advance_to(across, &hit);
        } else {
            self.position += across;
        }
        let forward = self.position - lifted;
        // Stepping needs real progress across, and walkable ground below.
        let drop = up * -((lifted - start).dot(up) + config.skin + config.skin);
        let landed = self
            .first_hit(space, config, drop, exclude, true)
            .filter(|hit| forward.length() >= least.min(len) && config.is_walkable(hit.normal));
        match landed {
            Some(hit) => {
                self.advance_to(drop, &hit);
                Some(along_up)
            }
            None => {
                self.position = start;
                None
            }
        }
    }

    /// The ground under the character, within two skins, if walkable: the
    /// hit and the gap to it.
    fn probe_ground(&self, space: &Space, config: &CharacterConfig) -> Option<(Hit, Real)> {
        let reach = PROBE_SKINS * config.skin;
        let down = -config.up * reach;
        let hit = self.first_hit(space, config, down, None, false)?;
        config
            .is_walkable(hit.normal)
            .then(|| (hit, hit.fraction * reach))
    }

    /// Pushes the character out of the shapes it overlaps (one-way shapes
    /// and sensors excepted) by the least translation the plane solver
    /// finds, a few rounds; returns how far it moved.
    fn depenetrate(&mut self, space: &Space, config: &CharacterConfig) -> Real {
        const ROUNDS: u32 = 4;
        let start = self.position;
        for _ in 0..ROUNDS {
            let world = self.world_shape(config);
            let mut planes: Vec<Plane> = Vec::new();
            for (h, set) in space.shape_query(&world, config.filter) {
                let Some(shape) = space.shape(h) else {
                    continue;
                };
                if shape.sensor || config.is_one_way(shape) {
                    continue;
                }
                let deepest = set
                    .points
                    .iter()
                    .take(set.count)
                    .map(|p| p.distance)
                    .min()
                    .unwrap_or(Real::ZERO);
                if deepest.is_negative() {
                    planes.push(Plane {
                        normal: -set.normal,
                        separation: deepest,
                    });
                }
            }
            if planes.is_empty() {
                break;
            }
            let delta = solve_planes(&mut planes, config.skin);
            if delta == Vect::ZERO {
                break;
            }
            self.position += delta;
        }
        (self.position - start).length()
    }

    /// The first surface a cast of the character by `delta` meets that
    /// blocks it: approached (not moved away from), not a sensor, not of
    /// `exclude`, and for a one-way shape a walkable surface met moving
    /// down from outside it.
    fn first_hit(
        &self,
        space: &Space,
        config: &CharacterConfig,
        delta: Vect,
        exclude: Option<BodyHandle>,
        inflated: bool,
    ) -> Option<Hit> {
        if delta == Vect::ZERO {
            return None;
        }
        let shape = if inflated {
            inflate(&config.shape, config.skin)
        } else {
            config.shape
        };
        let mut cast = ShapeCast::new(shape, self.position, Rot::IDENTITY, delta)
            .with_start(StartContact::HitIfApproaching);
        if let Some(body) = exclude {
            cast = cast.ignoring_body(body);
        }
        for (h, info) in space.shape_cast_all(&cast, config.filter) {
            let Some(shape) = space.shape(h) else {
                continue;
            };
            if shape.sensor || !delta.dot(info.normal).is_negative() {
                continue;
            }
            if config.is_one_way(shape)
                && !self.blocked_by_one_way(space, config, shape, delta, info.normal)
            {
                continue;
            }
            return Some(Hit {
                shape: h,
                body: shape.body(),
                fraction: info.fraction,
                normal: info.normal,
                point: info.point,
            });
        }
        None
    }

    /// A one-way shape blocks a move only from above: a walkable surface
    /// met moving down, with the character (its own shape, not grown by
    /// the skin) not inside it where the move starts.
    fn blocked_by_one_way(
        &self,
        space: &Space,
        config: &CharacterConfig,
        shape: &Shape,
        delta: Vect,
        normal: Vect,
    ) -> bool {
        if !config.is_walkable(normal) || !delta.dot(config.up).is_negative() {
            return false;
        }
        let Some(body) = space.body(shape.body()) else {
            return false;
        };
        let theirs = shape.geometry().to_world(body.position(), body.rotation());
        let set = shapes_collide(&self.world_shape(config), &theirs);
        set.points
            .iter()
            .take(set.count)
            .all(|p| !p.distance.is_negative())
    }
}

/// The impulses a move gives dynamic bodies, at most `push_force · dt` per
/// body, applied after the slides.
#[derive(Default)]
struct Pushes {
    /// (body, impulse, point), in the order met.
    list: Vec<(BodyHandle, Vect, Vect)>,
    count: u32,
}

impl Pushes {
    fn record(
        &mut self,
        space: &Space,
        config: &CharacterConfig,
        hit: &Hit,
        remaining: Vect,
        dt: Real,
    ) {
        if !config.push_force.is_positive() || !dt.is_positive() {
            return;
        }
        let Some(body) = space.body(hit.body) else {
            return;
        };
        if body.body_type() != BodyType::Dynamic {
            return;
        }
        let cap = config.push_force * dt;
        let already = self
            .list
            .iter()
            .filter(|(b, _, _)| *b == hit.body)
            .fold(Real::ZERO, |acc, (_, j, _)| acc + j.length());
        let speed = -remaining.dot(hit.normal) / dt;
        let j = (body.mass() * speed).min(cap - already);
        if j.is_positive() {
            self.list.push((hit.body, -hit.normal * j, hit.point));
        }
    }

    fn apply(&mut self, space: &mut Space) {
        let mut seen: Vec<BodyHandle> = Vec::new();
        for &(h, impulse, point) in &self.list {
            if let Some(body) = space.body_mut(h) {
                body.apply_impulse_at_world_point(impulse, point);
                if !seen.contains(&h) {
                    seen.push(h);
                }
            }
        }
        self.count = seen.len() as u32;
    }
}

/// `g` grown by `r` all round (its rounding radius).
fn inflate(g: &Geometry, r: Real) -> Geometry {
    let mut g = *g;
    match &mut g {
        Geometry::Circle(c) => c.radius += r,
        Geometry::Segment(s) => s.radius += r,
        Geometry::Poly(p) => p.radius += r,
    }
    g
}
