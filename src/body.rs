//! The MIS Rigid Body module (§6): mass, position, velocity, forces.
//!
//! Representation choices:
//! * `p` is the world position of the **centre of gravity** (Chipmunk's `p`),
//!   so the solver works at the centroid; [`Body::position`] is the body
//!   origin, `p − rot·cog`.
//! * Orientation is a unit complex number ([`Rot`]): rotating a vector is two
//!   multiply-adds and integration needs no trig in the common case. The
//!   continuous angle (which counts whole turns) is kept beside it for the MIS
//!   `angle` state variable; `rot` is what the simulation uses.
//! * Inverse mass and moment are cached: the solver multiplies, never divides.
//!
//! Invariants (MIS §6.4.2): mass, moment ≥ 0. A zero mass or moment on a
//! dynamic body means *infinite* (inverse 0), not illegal: `Body::new(m, 0)`
//! with `m > 0` is a body no impulse or torque turns (fixed rotation), and
//! `Body::new(0, 0)` takes its mass and moment from its shapes' mass or
//! density. Setters check the invariants and return
//! [`BodyError::IllegalBody`] instead of panicking. Fixed point has no NaN or
//! infinity, so "finite" holds by type.
use core::fmt;

use serde::{Deserialize, Serialize};

use crate::arena::Handle;
use crate::compact;
use crate::math::exact::{saturate_to_real, wide_mul, I256};
use crate::math::real::FRAC_BITS;
use crate::math::{FixedArith, Real, Rot, Saturating, Unsaturated, Vect};

/// Handle of a body in a [`Space`](crate::space::Space).
pub type BodyHandle = Handle<Body>;

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum BodyType {
    /// Moved by forces, gravity and collisions.
    Dynamic,
    /// Infinite mass, moved only by its velocity (set by the game).
    Kinematic,
    /// Never moves.
    Static,
}

/// Errors of body operations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BodyError {
    /// MIS IllegalBody: the operation would break an invariant of §6.4.2.
    IllegalBody(&'static str),
}

impl fmt::Display for BodyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BodyError::IllegalBody(why) => write!(f, "illegal body: {why}"),
        }
    }
}

impl std::error::Error for BodyError {}

/// A rigid body.
///
/// Serde: a binary serializer (snapshots) gets the compact form of
/// [`snapshot`](crate::snapshot) format version 6 (inverse mass and moment
/// not stored but recomputed, zero words left out); a human-readable one
/// every field (see `Body`'s `Serialize` impl).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Body {
    pub(crate) body_type: BodyType,
    pub(crate) mass: Real,
    pub(crate) mass_inv: Real,
    pub(crate) moment: Real,
    pub(crate) moment_inv: Real,
    /// True when mass and moment were set by the user; otherwise they are
    /// summed from the shapes' mass or density.
    pub(crate) explicit_mass: bool,
    /// Centre of gravity in body coordinates.
    pub(crate) cog: Vect,
    /// World position of the centre of gravity.
    pub(crate) p: Vect,
    pub(crate) v: Vect,
    pub(crate) f: Vect,
    /// Continuous angle (counts turns); `rot` is derived from it at set time
    /// and advanced alongside it during integration.
    pub(crate) a: Real,
    pub(crate) rot: Rot,
    pub(crate) w: Real,
    pub(crate) t: Real,
    /// Pseudo-velocities from bias impulses; cleared after each position update.
    pub(crate) v_bias: Vect,
    pub(crate) w_bias: Real,
    /// Sleeping: idle time, island, opt-out (see [`SleepState`]).
    pub(crate) sleep: SleepState,
    /// Continuous collision ([`Body::set_bullet`]): the step sweeps this
    /// body's shapes against static and kinematic shapes.
    pub(crate) bullet: bool,
}

/// The field-by-field serde form of [`Body`] (a derive's), used for
/// human-readable formats.
#[derive(Serialize, Deserialize)]
#[serde(remote = "Body", rename = "Body")]
struct BodyFields {
    body_type: BodyType,
    mass: Real,
    mass_inv: Real,
    moment: Real,
    moment_inv: Real,
    explicit_mass: bool,
    cog: Vect,
    p: Vect,
    v: Vect,
    f: Vect,
    a: Real,
    rot: Rot,
    w: Real,
    t: Real,
    v_bias: Vect,
    w_bias: Real,
    sleep: SleepState,
    bullet: bool,
}

/// Words of the compact form, in order (bit `i` of the presence mask is
/// word `i`): mass, moment, cog, p, v, f, a, rot (c, s), w, t, v_bias,
/// w_bias, idle time.
pub(crate) const BODY_WORDS: usize = 19;
/// Head bits above the presence mask: the body type (2 bits: dynamic,
/// kinematic, static), then one bit each.
const BODY_TYPE_SHIFT: u32 = 24;
const BODY_EXPLICIT_MASS: u32 = 1 << 26;
const BODY_SLEEP_ALLOWED: u32 = 1 << 27;
const BODY_BULLET: u32 = 1 << 28;
const BODY_ASLEEP: u32 = 1 << 29;
const BODY_NARROW: u32 = 1 << 30;
const BODY_HEAD: u32 = ((1 << BODY_WORDS) - 1)
    | (3 << BODY_TYPE_SHIFT)
    | BODY_EXPLICIT_MASS
    | BODY_SLEEP_ALLOWED
    | BODY_BULLET
    | BODY_ASLEEP
    | BODY_NARROW;

/// Binary (snapshot format 6): a tuple of
/// * a `u32` head: bits 0..19 the presence mask of the 19 words below,
///   bits 24–25 the body type (0 dynamic, 1 kinematic, 2 static), bit 26
///   `explicit_mass`, 27 sleep allowed, 28 `bullet`, 29 asleep, 30 "narrow
///   mask follows";
/// * the narrow mask (`u32`, not zero) when bit 30 is set: the present
///   words whose raw value fits an `i32`;
/// * the island root (`u32`) when asleep;
/// * the non-zero words, raw, as `i32` when narrow and `i64` otherwise:
///   mass, moment, cog (x, y), p, v, f, a, rot (c, s), w, t, v_bias,
///   w_bias, idle time.
///
/// Not stored: `mass_inv` and `moment_inv`, pure functions of the body
/// type, mass and moment, recomputed on decode: for a dynamic body `recip`,
/// 0 for 0 (`Body::set_mass_properties`, `Body::set_mass` and
/// `Body::set_moment`, the only writers, compute exactly that), for a
/// kinematic or static body 0 (set by its constructor, never written
/// again; validation demands it). Human-readable: every field, as a derive would.
impl Serialize for Body {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        if s.is_human_readable() {
            return BodyFields::serialize(self, s);
        }
        let words = self.compact_words();
        let mask = compact::mask_of(&words);
        let narrow = compact::narrow_of(&words, mask);
        let kind: u32 = match self.body_type {
            BodyType::Dynamic => 0,
            BodyType::Kinematic => 1,
            BodyType::Static => 2,
        };
        let flag = |on: bool, bit: u32| if on { bit } else { 0 };
        let head = mask
            | kind << BODY_TYPE_SHIFT
            | flag(self.explicit_mass, BODY_EXPLICIT_MASS)
            | flag(self.sleep.allowed, BODY_SLEEP_ALLOWED)
            | flag(self.bullet, BODY_BULLET)
            | flag(self.sleep.island.is_some(), BODY_ASLEEP)
            | flag(narrow != 0, BODY_NARROW);
        let island = usize::from(self.sleep.island.is_some());
        let mut t = compact::tuple(
            s,
            compact::count(mask)
                .saturating_add(island)
                .saturating_add(usize::from(narrow != 0))
                .saturating_add(1),
        )?;
        t.serialize_element(&head)?;
        if narrow != 0 {
            t.serialize_element(&narrow)?;
        }
        if let Some(root) = self.sleep.island {
            t.serialize_element(&root)?;
        }
        compact::write_words(&mut t, &words, mask, narrow)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for Body {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Body, D::Error> {
        if d.is_human_readable() {
            BodyFields::deserialize(d)
        } else {
            compact::deserialize(d)
        }
    }
}

impl compact::Compact for Body {
    const EXPECTING: &'static str = "a compact body";
    const MAX_ELEMENTS: usize = 3 + BODY_WORDS;

    fn read<'de, A: serde::de::SeqAccess<'de>>(
        r: &mut compact::Reader<'de, A>,
    ) -> Result<Body, A::Error> {
        let head: u32 = r.next()?;
        r.check_head(head, BODY_HEAD)?;
        let body_type = match (head >> BODY_TYPE_SHIFT) & 3 {
            0 => BodyType::Dynamic,
            1 => BodyType::Kinematic,
            2 => BodyType::Static,
            _ => return Err(r.error("unknown body type")),
        };
        let narrow = if head & BODY_NARROW != 0 {
            let n: u32 = r.next()?;
            if n == 0 {
                return Err(r.error("an empty narrow mask"));
            }
            n
        } else {
            0
        };
        let island = if head & BODY_ASLEEP != 0 {
            Some(r.next::<u32>()?)
        } else {
            None
        };
        let mut w = [Real::ZERO; BODY_WORDS];
        r.words(head & ((1 << BODY_WORDS) - 1), Some(narrow), &mut w)?;
        Ok(Body::from_compact(
            body_type,
            CompactFlags {
                explicit_mass: head & BODY_EXPLICIT_MASS != 0,
                sleep_allowed: head & BODY_SLEEP_ALLOWED != 0,
                bullet: head & BODY_BULLET != 0,
                island,
            },
            w,
        ))
    }
}

/// The flags of a body's compact forms (snapshots and frames).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CompactFlags {
    pub(crate) explicit_mass: bool,
    pub(crate) sleep_allowed: bool,
    pub(crate) bullet: bool,
    pub(crate) island: Option<u32>,
}

impl Body {
    /// The stored words of the compact forms, in order: mass, moment, cog,
    /// p, v, f, a, rot (c, s), w, t, v_bias, w_bias, idle time.
    #[inline]
    pub(crate) fn compact_words(&self) -> [Real; BODY_WORDS] {
        [
            self.mass,
            self.moment,
            self.cog.x,
            self.cog.y,
            self.p.x,
            self.p.y,
            self.v.x,
            self.v.y,
            self.f.x,
            self.f.y,
            self.a,
            self.rot.c,
            self.rot.s,
            self.w,
            self.t,
            self.v_bias.x,
            self.v_bias.y,
            self.w_bias,
            self.sleep.idle_time,
        ]
    }

    /// The flags of the compact forms.
    #[inline]
    pub(crate) fn compact_flags(&self) -> CompactFlags {
        CompactFlags {
            explicit_mass: self.explicit_mass,
            sleep_allowed: self.sleep.allowed,
            bullet: self.bullet,
            island: self.sleep.island,
        }
    }

    /// The body the compact forms describe, with the derived fields
    /// recomputed (see the `Serialize` impl).
    #[inline]
    pub(crate) fn from_compact(
        body_type: BodyType,
        flags: CompactFlags,
        w: [Real; BODY_WORDS],
    ) -> Body {
        Body::from_compact_reusing(body_type, flags, w, None)
    }

    /// [`from_compact`](Self::from_compact), the inverse mass and moment
    /// taken from `known` where it has the same type and mass (moment)
    /// instead of divided anew: they are a pure function of those (the
    /// frame decoder passes the body it writes over, which a valid state or
    /// this function made).
    #[inline]
    pub(crate) fn from_compact_reusing(
        body_type: BodyType,
        flags: CompactFlags,
        w: [Real; BODY_WORDS],
        known: Option<&Body>,
    ) -> Body {
        let [mass, moment, cog_x, cog_y, p_x, p_y, v_x, v_y, f_x, f_y, a, rot_c, rot_s, ang_v, torque, vb_x, vb_y, w_bias, idle_time] =
            w;
        // Derived, see the `Serialize` impl (a kinematic or static body
        // with a mass is left to validation to name).
        let dynamic = body_type == BodyType::Dynamic;
        let derive = |v: Real, known: Option<(Real, Real)>| match known {
            Some((kv, inv)) if kv == v => inv,
            _ if dynamic => inverse_or_zero(v),
            _ => Real::ZERO,
        };
        let known = known.filter(|k| k.body_type == body_type);
        Body {
            body_type,
            mass,
            mass_inv: derive(mass, known.map(|k| (k.mass, k.mass_inv))),
            moment,
            moment_inv: derive(moment, known.map(|k| (k.moment, k.moment_inv))),
            explicit_mass: flags.explicit_mass,
            cog: Vect::new(cog_x, cog_y),
            p: Vect::new(p_x, p_y),
            v: Vect::new(v_x, v_y),
            f: Vect::new(f_x, f_y),
            a,
            rot: Rot { c: rot_c, s: rot_s },
            w: ang_v,
            t: torque,
            v_bias: Vect::new(vb_x, vb_y),
            w_bias,
            sleep: SleepState {
                idle_time,
                island: flags.island,
                allowed: flags.sleep_allowed,
            },
            bullet: flags.bullet,
        }
    }
}

/// A body's part in sleeping (Chipmunk's `sleeping` record, Box2D's
/// `enableSleep`). The space's `sleep` stage updates it; a game reads it
/// with [`Body::is_sleeping`] and opts a body out with
/// [`Body::set_sleep_allowed`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SleepState {
    /// Seconds this body has been idle (slower than the space's idle
    /// speed) while awake; the island sleeps when all its bodies reach the
    /// sleep time threshold.
    pub(crate) idle_time: Real,
    /// `Some(root)` while asleep: the body slot index of its island's root
    /// (a sleeping body of the same island whose root is itself). Waking
    /// any body of an island wakes every body with the same root.
    pub(crate) island: Option<u32>,
    /// False: the body never falls asleep, nor does any island it is in
    /// (a player character). Default true.
    pub(crate) allowed: bool,
}

impl SleepState {
    /// Awake, never idle, allowed to sleep.
    pub(crate) const AWAKE: SleepState = SleepState {
        idle_time: Real::ZERO,
        island: None,
        allowed: true,
    };
}

/// Every field, the small ones packed into one word (type, flags and the
/// sleeping island), then the numbers in declaration order: the checksum
/// costs per word, and a body is hashed every frame.
impl core::hash::Hash for Body {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Body {
            body_type,
            mass,
            mass_inv,
            moment,
            moment_inv,
            explicit_mass,
            cog,
            p,
            v,
            f,
            a,
            rot,
            w,
            t,
            v_bias,
            w_bias,
            sleep:
                SleepState {
                    idle_time,
                    island,
                    allowed,
                },
            bullet,
        } = self;
        let kind: u64 = match body_type {
            BodyType::Dynamic => 0,
            BodyType::Kinematic => 1,
            BodyType::Static => 2,
        };
        let (asleep, root) = match island {
            Some(root) => (1u64, *root),
            None => (0, 0),
        };
        h.write_u64(
            kind | u64::from(*explicit_mass) << 2
                | u64::from(*bullet) << 3
                | u64::from(*allowed) << 4
                | asleep << 5
                | u64::from(root) << 32,
        );
        mass.hash(h);
        mass_inv.hash(h);
        moment.hash(h);
        moment_inv.hash(h);
        cog.hash(h);
        p.hash(h);
        v.hash(h);
        f.hash(h);
        a.hash(h);
        rot.hash(h);
        w.hash(h);
        t.hash(h);
        v_bias.hash(h);
        w_bias.hash(h);
        idle_time.hash(h);
    }
}

/// `|θ|` below which [`small_angle_rot`] uses its series (error < 1 ulp).
const SERIES_MAX_ANGLE: Real = Real::from_bits(1 << 30); // 0.25 rad

/// Rotation by a small angle without the general trig routine: the Taylor
/// series of cos to θ⁸ and sin to θ⁷ is below 1 ulp for |θ| ≤ 0.25.
fn small_angle_rot(theta: Real) -> Rot {
    if theta.abs() > SERIES_MAX_ANGLE {
        return Rot::from_angle(theta);
    }
    // Every product below has one factor of at most 1/4 (θ, θ² ≤ 1/16) and
    // the other at most 1 (θ, the coefficients, the Horner sums, which stay
    // in (0, 1]): raw products of at most 2^62, so `mul_small` gives the bits of
    // `*` in one 64-bit multiply.
    let t2 = theta.mul_small(theta);
    // Below about 2^-16.5 rad (a body at rest) θ² rounds to zero, and so
    // does every term after the first: cos 1, sin θ, exactly the series'
    // bits without its dozen products.
    if t2.is_zero() {
        return Rot {
            c: Real::ONE,
            s: theta,
        };
    }
    // Horner form; the coefficient constants are 1/k! rounded to nearest.
    const C2: Real = Real::from_bits(2_147_483_648); // 1/2
    const C4: Real = Real::from_bits(178_956_971); // 1/24
    const C6: Real = Real::from_bits(5_965_232); // 1/720
    const C8: Real = Real::from_bits(106_522); // 1/40320
    const S3: Real = Real::from_bits(715_827_883); // 1/6
    const S5: Real = Real::from_bits(35_791_394); // 1/120
    const S7: Real = Real::from_bits(852_176); // 1/5040
    let m = |a: Real, b: Real| a.mul_small(b);
    let c = Real::ONE - m(t2, C2 - m(t2, C4 - m(t2, C6 - m(t2, C8))));
    let s = m(theta, Real::ONE - m(t2, S3 - m(t2, S5 - m(t2, S7))));
    Rot { c, s }
}

/// Largest tolerated drift of `|rot|²` from 1 before renormalising (2^-24):
/// renormalising costs a square root, drift grows by about an ulp per step.
const ROT_DRIFT_LIMIT: Real = Real::from_bits(1 << 8);

impl Body {
    fn with_type(body_type: BodyType, mass: Real, moment: Real) -> Body {
        Body {
            body_type,
            mass,
            mass_inv: inverse_or_zero(mass),
            moment,
            moment_inv: inverse_or_zero(moment),
            explicit_mass: false,
            cog: Vect::ZERO,
            p: Vect::ZERO,
            v: Vect::ZERO,
            f: Vect::ZERO,
            a: Real::ZERO,
            rot: Rot::IDENTITY,
            w: Real::ZERO,
            t: Real::ZERO,
            v_bias: Vect::ZERO,
            w_bias: Real::ZERO,
            sleep: SleepState::AWAKE,
            bullet: false,
        }
    }

    /// MIS `bodyInit`: a dynamic body with the given mass and moment. Zero
    /// for both means "sum them from the shapes' mass or density" (Chipmunk).
    /// A positive mass with zero moment is **fixed rotation**: the moment is
    /// infinite, so the body never turns (Chipmunk's `cpBodySetMoment(INFINITY)`).
    pub fn new(mass: Real, moment: Real) -> Result<Body, BodyError> {
        check_non_negative(mass, "mass must be ≥ 0")?;
        check_non_negative(moment, "moment must be ≥ 0")?;
        let mut b = Body::with_type(BodyType::Dynamic, mass, moment);
        b.explicit_mass = mass.is_positive() || moment.is_positive();
        Ok(b)
    }

    /// A kinematic body (infinite mass, moved by its velocity only).
    pub fn new_kinematic() -> Body {
        Body::with_type(BodyType::Kinematic, Real::ZERO, Real::ZERO)
    }

    /// A static body (never moves).
    pub fn new_static() -> Body {
        Body::with_type(BodyType::Static, Real::ZERO, Real::ZERO)
    }

    /// The body type.
    pub fn body_type(&self) -> BodyType {
        self.body_type
    }

    /// True for dynamic bodies.
    pub fn is_dynamic(&self) -> bool {
        self.body_type == BodyType::Dynamic
    }

    /// Whether the step can move this body: false for a dynamic body
    /// without mass (an inverse mass of 0: no explicit mass and no shape
    /// with mass or density, or a mass too large for its inverse), which
    /// gravity would move and no contact could stop. The one rule behind
    /// both [`Space::step`](crate::space::Space::step)'s refusal
    /// (`SpaceError::MasslessDynamicBody`) and state validation, so that
    /// every state that validates can step.
    pub fn can_step(&self) -> bool {
        self.body_type != BodyType::Dynamic || !self.mass_inv.is_zero()
    }

    /// Mass (0 for kinematic and static bodies: their inverse mass is 0).
    pub fn mass(&self) -> Real {
        self.mass
    }

    /// Inverse mass (0 for infinite mass).
    pub fn mass_inv(&self) -> Real {
        self.mass_inv
    }

    /// Sets an explicit mass (Chipmunk `cpBodySetMass`). Dynamic bodies only;
    /// must be > 0.
    pub fn set_mass(&mut self, mass: Real) -> Result<(), BodyError> {
        if self.body_type != BodyType::Dynamic {
            return Err(BodyError::IllegalBody("only dynamic bodies have a mass"));
        }
        if !mass.is_positive() {
            return Err(BodyError::IllegalBody("mass must be > 0"));
        }
        self.mass = mass;
        self.mass_inv = mass.recip();
        self.explicit_mass = true;
        Ok(())
    }

    /// Moment of inertia about the centre of gravity.
    pub fn moment(&self) -> Real {
        self.moment
    }

    /// Inverse moment (0 for infinite moment).
    pub fn moment_inv(&self) -> Real {
        self.moment_inv
    }

    /// Sets an explicit moment of inertia (Chipmunk `cpBodySetMoment`).
    /// Dynamic bodies only; must be > 0 (for fixed rotation, create the body
    /// with [`Body::new`]`(mass, 0)`).
    pub fn set_moment(&mut self, moment: Real) -> Result<(), BodyError> {
        if self.body_type != BodyType::Dynamic {
            return Err(BodyError::IllegalBody("only dynamic bodies have a moment"));
        }
        if !moment.is_positive() {
            return Err(BodyError::IllegalBody("moment must be > 0"));
        }
        self.moment = moment;
        self.moment_inv = moment.recip();
        self.explicit_mass = true;
        Ok(())
    }

    /// Centre of gravity in body coordinates.
    pub fn center_of_gravity(&self) -> Vect {
        self.cog
    }

    /// Sets the centre of gravity, keeping the body origin in place.
    pub fn set_center_of_gravity(&mut self, cog: Vect) {
        let origin = self.position();
        self.cog = cog;
        self.set_position(origin);
    }

    /// MIS `set_pos` / Chipmunk `cpBodyGetPosition`: world position of the body origin.
    pub fn position(&self) -> Vect {
        // Most bodies keep their centre of gravity at the origin: `p` itself,
        // exactly what the rotation of a zero vector would give.
        if self.cog == Vect::ZERO {
            return self.p;
        }
        self.p - self.rot.apply(self.cog)
    }

    /// Moves the body origin to `pos`.
    pub fn set_position(&mut self, pos: Vect) {
        self.p = pos + self.rot.apply(self.cog);
    }

    /// World position of the centre of gravity.
    pub fn center(&self) -> Vect {
        self.p
    }

    /// Linear velocity of the centre of gravity.
    pub fn velocity(&self) -> Vect {
        self.v
    }

    /// Sets the linear velocity.
    pub fn set_velocity(&mut self, v: Vect) {
        self.v = v;
    }

    /// True if the body is a bullet (see [`Body::set_bullet`]).
    pub fn is_bullet(&self) -> bool {
        self.bullet
    }

    /// Marks the body as a bullet (Box2D's `isBullet`): continuous
    /// collision. In each (sub-)step the motion of a bullet that is dynamic
    /// is swept against the static and kinematic shapes it may hit, and the
    /// body is stopped at the time of impact, so it cannot pass through
    /// them however fast it moves (see `docs/numerics.md`, "Speeds and
    /// tunnelling"). Bullets are not swept against other dynamic bodies.
    /// The flag is state (snapshots, checksum); on kinematic and static
    /// bodies it is kept but has no effect. Costs one time-of-impact
    /// search per nearby shape and sub-step, so mark only small fast bodies.
    pub fn set_bullet(&mut self, bullet: bool) {
        self.bullet = bullet;
    }

    /// Accumulated force (cleared after each velocity update).
    pub fn force(&self) -> Vect {
        self.f
    }

    /// Replaces the accumulated force.
    pub fn set_force(&mut self, f: Vect) {
        self.f = f;
    }

    /// MIS `angle`: continuous rotation angle in radians (counts whole turns).
    pub fn angle(&self) -> Real {
        self.a
    }

    /// MIS `set_angle`: rotates the body about its centre of gravity.
    pub fn set_angle(&mut self, angle: Real) {
        self.a = angle;
        self.rot = Rot::from_angle(angle);
    }

    /// Orientation as a unit complex number.
    pub fn rotation(&self) -> Rot {
        self.rot
    }

    /// Angular velocity (rad/s, counter-clockwise positive).
    pub fn angular_velocity(&self) -> Real {
        self.w
    }

    /// Sets the angular velocity.
    pub fn set_angular_velocity(&mut self, w: Real) {
        self.w = w;
    }

    /// Accumulated torque (cleared after each velocity update).
    pub fn torque(&self) -> Real {
        self.t
    }

    /// Replaces the accumulated torque.
    pub fn set_torque(&mut self, t: Real) {
        self.t = t;
    }

    /// MIS `apply_force`: adds `force` at the centre of gravity.
    pub fn apply_force(&mut self, force: Vect) {
        self.f += force;
    }

    /// MIS `apply_torque`: adds `torque`.
    pub fn apply_torque(&mut self, torque: Real) {
        self.t += torque;
    }

    /// MIS `set_angular_accler`: sets the torque so that the angular
    /// acceleration of the next velocity update is `alpha` (τ = I·α).
    pub fn set_angular_acceleration(&mut self, alpha: Real) {
        self.t = self.moment * alpha;
    }

    /// Adds `force` applied at world point `point` (force and torque).
    pub fn apply_force_at_world_point(&mut self, force: Vect, point: Vect) {
        self.f += force;
        self.t += (point - self.p).cross(force);
    }

    /// Adds `force` (body coordinates) applied at body point `point`.
    pub fn apply_force_at_local_point(&mut self, force: Vect, point: Vect) {
        let wf = self.rot.apply(force);
        let wp = self.local_to_world(point);
        self.apply_force_at_world_point(wf, wp);
    }

    /// Applies an impulse at a world point: changes velocity at once.
    pub fn apply_impulse_at_world_point(&mut self, impulse: Vect, point: Vect) {
        let r = point - self.p;
        self.v += impulse * self.mass_inv;
        self.w += self.moment_inv * r.cross(impulse);
    }

    /// Applies an impulse (body coordinates) at a body point.
    pub fn apply_impulse_at_local_point(&mut self, impulse: Vect, point: Vect) {
        let wi = self.rot.apply(impulse);
        let wp = self.local_to_world(point);
        self.apply_impulse_at_world_point(wi, wp);
    }

    /// Velocity of the body at a world point.
    pub fn velocity_at_world_point(&self, point: Vect) -> Vect {
        let r = point - self.p;
        self.v + r.perp() * self.w
    }

    /// Velocity of the body at a body point.
    pub fn velocity_at_local_point(&self, point: Vect) -> Vect {
        self.velocity_at_world_point(self.local_to_world(point))
    }

    /// Body coordinates → world coordinates.
    pub fn local_to_world(&self, point: Vect) -> Vect {
        self.p + self.rot.apply(point - self.cog)
    }

    /// World coordinates → body coordinates.
    pub fn world_to_local(&self, point: Vect) -> Vect {
        self.rot.apply_inv(point - self.p) + self.cog
    }

    /// Kinetic energy ½mv² + ½Iω² (Chipmunk `cpBodyKineticEnergy`); 0 for
    /// infinite mass.
    ///
    /// Computed exactly on 256 bits and rounded once (to nearest, ½ ulp), so
    /// it is right at any speed: `v·v` is never formed as a `Real` (it would
    /// saturate above 46,341 m/s). Saturates at `Real::MAX` only when the
    /// energy itself exceeds the range.
    pub fn kinetic_energy(&self) -> Real {
        if self.body_type != BodyType::Dynamic {
            return Real::ZERO;
        }
        // Raw units: mass 2^-32 · squared speed 2^-64 = 2^-96, so the energy
        // in raw `Real` bits (2^-32) is (m·|v|² + I·ω²) / 2^65 with the ½.
        // Each product is below 2^63 · 2^126 = 2^189: the sum cannot wrap.
        let term = |k: Real, r: Real| {
            I256::mul_i128(i128::from(k.to_bits()), wide_mul(r.to_bits(), r.to_bits()))
        };
        let twice = term(self.mass, self.v.x)
            .add(term(self.mass, self.v.y))
            .add(term(self.moment, self.w));
        saturate_to_real(twice.round_shr(2 * FRAC_BITS + 1))
    }

    /// True while the body sleeps (its island rests: see `Space`'s sleeping
    /// settings). A sleeping body does not move and costs nothing in the
    /// step; the space wakes it when something touches or changes it.
    pub fn is_sleeping(&self) -> bool {
        self.sleep.island.is_some()
    }

    /// Seconds the body has been idle while awake (Chipmunk's idle time):
    /// its island falls asleep when every body in it reaches
    /// `Settings::sleep_time_threshold`.
    pub fn idle_time(&self) -> Real {
        self.sleep.idle_time
    }

    /// Whether the body may fall asleep (default true).
    pub fn is_sleep_allowed(&self) -> bool {
        self.sleep.allowed
    }

    /// Allows or forbids sleeping for this body (Box2D's `enableSleep`):
    /// a body that may not sleep keeps its whole island awake, e.g. a
    /// player character standing on a pile. Forbidding it resets the idle
    /// time. Changing it through `Space::body_mut` wakes the body first.
    pub fn set_sleep_allowed(&mut self, allowed: bool) {
        self.sleep.allowed = allowed;
        if !allowed {
            self.sleep.idle_time = Real::ZERO;
        }
    }

    /// True if `|v|² + (I/m)·ω² ≤ idle_speed²`, and the same for the bias
    /// velocities (Chipmunk's idle test: the
    /// kinetic energy per unit mass against that of the idle speed; the
    /// rotation counts at the radius of gyration, so no shape extent is
    /// needed). Exact: compared on 256 bits, never rounded or saturated.
    /// Non-dynamic bodies are idle.
    pub(crate) fn is_idle(&self, idle_speed: Real) -> bool {
        if self.body_type != BodyType::Dynamic {
            return true;
        }
        // A body of positive mass moving faster than `idle_speed` along an
        // axis has more than the limit's energy in that term alone (the
        // others are ≥ 0): not idle, the exact answer without the 256-bit
        // sums. Most moving bodies leave here.
        let fast = |v: Vect| v.x.abs() > idle_speed.abs() || v.y.abs() > idle_speed.abs();
        if self.mass.is_positive() && (fast(self.v) || fast(self.v_bias)) {
            return false;
        }
        let term = |k: Real, r: Real| {
            I256::mul_i128(i128::from(k.to_bits()), wide_mul(r.to_bits(), r.to_bits()))
        };
        let limit = term(self.mass, idle_speed);
        let below = |v: Vect, w: Real| {
            let energy = term(self.mass, v.x)
                .add(term(self.mass, v.y))
                .add(term(self.moment, w));
            let excess = energy.sub(limit);
            excess.is_negative() || excess.is_zero()
        };
        // The bias velocities count too: a body pushed out of an overlap
        // moves although its velocity is 0, and must not sleep overlapping.
        below(self.v, self.w) && below(self.v_bias, self.w_bias)
    }

    /// Puts the body to sleep in island `root`: velocities, bias
    /// velocities, force and torque become exactly 0 (a sleeping body
    /// holds no motion, so waking it starts from rest).
    pub(crate) fn fall_asleep(&mut self, root: u32) {
        self.sleep.island = Some(root);
        self.v = Vect::ZERO;
        self.w = Real::ZERO;
        self.v_bias = Vect::ZERO;
        self.w_bias = Real::ZERO;
        self.f = Vect::ZERO;
        self.t = Real::ZERO;
    }

    /// Wakes the body with its idle time reset (Chipmunk's activate).
    pub(crate) fn wake(&mut self) {
        self.sleep.island = None;
        self.sleep.idle_time = Real::ZERO;
    }

    /// Default velocity integration (Chipmunk `cpBodyUpdateVelocity`):
    /// `v ← v·damping + (g + f/m)·dt`, `ω ← ω·damping + τ/I·dt`, then the
    /// force and torque accumulators are cleared. `damping` is the per-step
    /// factor (the space precomputes `damping^dt`). Only dynamic bodies move.
    pub fn update_velocity(&mut self, gravity: Vect, damping: Real, dt: Real) {
        self.update_velocity_by(gravity, gravity * dt, damping, dt);
    }

    /// [`update_velocity`](Self::update_velocity) given `gravity_dt =
    /// gravity·dt`, the velocity change of every body without a force: the
    /// step computes it once for all bodies (the same product each time).
    pub(crate) fn update_velocity_by(
        &mut self,
        gravity: Vect,
        gravity_dt: Vect,
        damping: Real,
        dt: Real,
    ) {
        if self.body_type == BodyType::Dynamic {
            // Each shortcut skips a product whose result is known exactly
            // (`x·1 = x`, `0·x = 0`, `x + 0 = x`): the same bits, without
            // the multiplies of the usual body (no damping, no force).
            let damped = |x: Real| if damping == Real::ONE { x } else { x * damping };
            let v = Vect::new(damped(self.v.x), damped(self.v.y));
            self.v = if self.f == Vect::ZERO {
                // The acceleration is gravity: `v + g·dt`, or `v` without.
                if gravity == Vect::ZERO {
                    v
                } else {
                    v + gravity_dt
                }
            } else {
                let accel = gravity + self.f * self.mass_inv;
                if accel == Vect::ZERO {
                    v
                } else {
                    v + accel * dt
                }
            };
            let w = damped(self.w);
            self.w = if self.t.is_zero() {
                w
            } else {
                w + self.t * self.moment_inv * dt
            };
        }
        self.f = Vect::ZERO;
        self.t = Real::ZERO;
    }

    /// Default position integration (MIS `update`, Chipmunk
    /// `cpBodyUpdatePosition`): `p ← p + (v + v_bias)·dt`, angle likewise,
    /// then the bias velocities are cleared. Static bodies never move.
    pub fn update_position(&mut self, dt: Real) {
        if self.body_type != BodyType::Static {
            let mut fast = Unsaturated::new();
            let moved = self.moved(dt, &mut fast);
            (self.p, self.a, self.rot) = if fast.overflowed() {
                self.moved_saturating(dt)
            } else {
                moved
            };
        }
        self.v_bias = Vect::ZERO;
        self.w_bias = Real::ZERO;
    }

    /// The position, angle and rotation after `dt` at the velocities plus
    /// the bias velocities: `p + (v + v_bias)·dt`, and the rotation
    /// composed with the exact small-angle rotation of `(ω + ω_bias)·dt`,
    /// renormalised only when its rounding drift exceeds 2^-24. In the
    /// arithmetic `ar` ([`Unsaturated`] first: the saturating operators'
    /// bits unless it overflowed).
    #[inline(always)]
    fn moved<A: FixedArith>(&self, dt: Real, ar: &mut A) -> (Vect, Real, Rot) {
        let v = Vect::new(
            ar.add(self.v.x, self.v_bias.x),
            ar.add(self.v.y, self.v_bias.y),
        );
        let step = Vect::new(ar.mul(v.x, dt), ar.mul(v.y, dt));
        let p = Vect::new(ar.add(self.p.x, step.x), ar.add(self.p.y, step.y));
        let w = ar.add(self.w, self.w_bias);
        let dtheta = ar.mul(w, dt);
        if dtheta.is_zero() {
            return (p, self.a, self.rot);
        }
        // `small_angle_rot`, `abs` and `normalize` are the same functions
        // in both arithmetics.
        let q = small_angle_rot(dtheta);
        let (c, s) = (self.rot.c, self.rot.s);
        let rot = Rot {
            c: ar.mul_sub2(c, q.c, s, q.s),
            s: ar.mul_add2(c, q.s, s, q.c),
        };
        let len_sq = ar.mul_add2(rot.c, rot.c, rot.s, rot.s);
        let drift = ar.sub(len_sq, Real::ONE).abs();
        let rot = if drift > ROT_DRIFT_LIMIT {
            rot.normalize()
        } else {
            rot
        };
        (p, ar.add(self.a, dtheta), rot)
    }

    /// [`moved`](Self::moved) in the saturating operators, out of line (so
    /// that the fast path does not keep its products alive for it).
    #[cold]
    #[inline(never)]
    fn moved_saturating(&self, dt: Real) -> (Vect, Real, Rot) {
        self.moved(dt, &mut Saturating)
    }

    /// Sets mass properties summed from shapes (space-internal).
    pub(crate) fn set_mass_properties(&mut self, mass: Real, moment: Real, cog: Vect) {
        let origin = self.position();
        self.mass = mass;
        self.mass_inv = inverse_or_zero(mass);
        self.moment = moment;
        self.moment_inv = inverse_or_zero(moment);
        self.cog = cog;
        self.set_position(origin);
    }

    /// Checks the MIS §6.4.2 invariants for a body about to be simulated.
    pub fn validate(&self) -> Result<(), BodyError> {
        check_non_negative(self.mass, "mass must be ≥ 0")?;
        check_non_negative(self.moment, "moment must be ≥ 0")?;
        if self.body_type != BodyType::Dynamic
            && (!self.mass_inv.is_zero() || !self.moment_inv.is_zero())
        {
            return Err(BodyError::IllegalBody("non-dynamic body with finite mass"));
        }
        let len_sq = self.rot.as_vect().dot(self.rot.as_vect());
        if (len_sq - Real::ONE).abs() > Real::from_bits(1 << 12) {
            return Err(BodyError::IllegalBody(
                "rotation is not a unit complex number",
            ));
        }
        Ok(())
    }

    /// Checks the cached values a stored body (snapshot, restored state)
    /// could get wrong, beyond [`Body::validate`]: the inverse mass and
    /// moment are exactly what the engine computes from mass and moment
    /// (`recip`, or 0 for 0), and kinematic and static bodies have zero mass
    /// and moment and no explicit mass.
    pub(crate) fn validate_derived(&self) -> Result<(), BodyError> {
        self.validate()?;
        if self.body_type == BodyType::Dynamic {
            if self.mass_inv != inverse_or_zero(self.mass) {
                return Err(BodyError::IllegalBody("inverse mass does not match mass"));
            }
            if self.moment_inv != inverse_or_zero(self.moment) {
                return Err(BodyError::IllegalBody(
                    "inverse moment does not match moment",
                ));
            }
        } else if !self.mass.is_zero() || !self.moment.is_zero() || self.explicit_mass {
            return Err(BodyError::IllegalBody(
                "kinematic or static body with a mass or moment",
            ));
        }
        self.validate_sleep()
    }

    /// A stored body's sleep record: idle time ≥ 0; only a dynamic body
    /// that may sleep sleeps, and then it holds no motion (the space zeroes
    /// velocities, forces and bias velocities when an island falls asleep,
    /// and wakes a body before anything can set them). The island root is
    /// checked by the space, which sees the other bodies.
    fn validate_sleep(&self) -> Result<(), BodyError> {
        if self.sleep.idle_time.is_negative() {
            return Err(BodyError::IllegalBody("negative idle time"));
        }
        if self.sleep.island.is_none() {
            return Ok(());
        }
        if self.body_type != BodyType::Dynamic {
            return Err(BodyError::IllegalBody("a non-dynamic body is asleep"));
        }
        if !self.sleep.allowed {
            return Err(BodyError::IllegalBody(
                "a body that may not sleep is asleep",
            ));
        }
        let still = self.v == Vect::ZERO
            && self.w.is_zero()
            && self.v_bias == Vect::ZERO
            && self.w_bias.is_zero()
            && self.f == Vect::ZERO
            && self.t.is_zero();
        if !still {
            return Err(BodyError::IllegalBody(
                "a sleeping body has a velocity or force",
            ));
        }
        Ok(())
    }
}

fn inverse_or_zero(v: Real) -> Real {
    if v.is_positive() {
        v.recip()
    } else {
        Real::ZERO
    }
}

fn check_non_negative(v: Real, why: &'static str) -> Result<(), BodyError> {
    if v.is_negative() {
        Err(BodyError::IllegalBody(why))
    } else {
        Ok(())
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::real;

    /// A `Real` drawn from raw bits, extremes and small values alike.
    fn any_real() -> impl proptest::strategy::Strategy<Value = Real> {
        use proptest::prelude::*;
        prop_oneof![
            any::<i64>().prop_map(Real::from_bits),
            (-(1i64 << 40)..(1i64 << 40)).prop_map(Real::from_bits),
            Just(Real::ZERO),
            Just(Real::ONE),
            Just(Real::MAX),
            Just(Real::MIN),
        ]
    }

    /// [`small_angle_rot`]'s series in `Real`'s saturating operators: its
    /// one-multiply products must give these bits.
    fn small_angle_rot_reference(theta: Real) -> Rot {
        let t2 = theta * theta;
        let [c2, c4, c6, c8] =
            [2_147_483_648, 178_956_971, 5_965_232, 106_522].map(Real::from_bits);
        let [s3, s5, s7] = [715_827_883, 35_791_394, 852_176].map(Real::from_bits);
        let c = Real::ONE - t2 * (c2 - t2 * (c4 - t2 * (c6 - t2 * c8)));
        let s = theta * (Real::ONE - t2 * (s3 - t2 * (s5 - t2 * s7)));
        Rot { c, s }
    }

    #[test]
    fn small_angle_series_matches_saturating_products() {
        // Every angle of the series' window on a prime stride, and its edges.
        let edge = SERIES_MAX_ANGLE.to_bits();
        let swept = (-edge..=edge).step_by(104_729);
        let edges = [-edge, -edge + 1, -1, 0, 1, edge - 1, edge];
        for raw in swept.chain(edges) {
            let theta = Real::from_bits(raw);
            assert_eq!(
                small_angle_rot(theta),
                small_angle_rot_reference(theta),
                "θ raw {raw}"
            );
        }
    }

    #[test]
    fn angles_whose_square_rounds_to_zero_take_the_shortcut_exactly() {
        // Every seventh angle across the edge where θ² stops rounding to
        // zero (|θ| raw about 46,341), and the angles at the edge.
        for raw in (-70_000i64..=70_000)
            .step_by(7)
            .chain([-46_341, -46_340, 46_340, 46_341])
        {
            let theta = Real::from_bits(raw);
            assert_eq!(
                small_angle_rot(theta),
                small_angle_rot_reference(theta),
                "θ raw {raw}"
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]
        /// The position update's fast path gives the bits of the former
        /// formulas in `Real`'s saturating operators, on any input (and the
        /// fallback does too, where the fast path overflows).
        #[test]
        fn position_update_is_the_saturating_formulas(
            (px, py, vx, vy, bx) in (any_real(), any_real(), any_real(), any_real(), any_real()),
            (by, w, bw, a, dt) in (any_real(), any_real(), any_real(), any_real(), any_real()),
            turn in -(1i64 << 28)..(1i64 << 28),
        ) {
            let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
            (b.p, b.v, b.v_bias) = (Vect::new(px, py), Vect::new(vx, vy), Vect::new(bx, by));
            (b.w, b.w_bias, b.a) = (w, bw, a);
            b.rot = Rot::from_angle(Real::from_bits(turn.wrapping_mul(97)));
            let mut want = b.clone();
            want.p += (want.v + want.v_bias) * dt;
            let dtheta = (want.w + want.w_bias) * dt;
            if !dtheta.is_zero() {
                want.a += dtheta;
                want.rot = want.rot.compose(small_angle_rot(dtheta));
                let drift = (want.rot.as_vect().dot(want.rot.as_vect()) - Real::ONE).abs();
                if drift > ROT_DRIFT_LIMIT {
                    want.rot = want.rot.normalize();
                }
            }
            (want.v_bias, want.w_bias) = (Vect::ZERO, Real::ZERO);
            proptest::prop_assert_eq!(b.moved_saturating(dt), (want.p, want.a, want.rot));
            b.update_position(dt);
            proptest::prop_assert_eq!((b.p, b.a, b.rot, b.v_bias, b.w_bias), (want.p, want.a, want.rot, want.v_bias, want.w_bias));
        }

        /// The series' one-multiply products give the saturating products'
        /// bits at every angle of its window.
        #[test]
        fn small_angle_series_is_exact(raw in -(1i64 << 30)..=(1i64 << 30)) {
            let theta = Real::from_bits(raw);
            proptest::prop_assert_eq!(small_angle_rot(theta), small_angle_rot_reference(theta));
        }

        /// The integrator's shortcuts (no damping, no force, no
        /// acceleration) and the idle test's early "fast" exit give exactly
        /// the results of the full formulas.
        #[test]
        fn velocity_update_and_idle_test_shortcuts_are_exact(
            (m, i, vx, vy, w) in (any_real(), any_real(), any_real(), any_real(), any_real()),
            (bx, by, bw, fx, fy) in (any_real(), any_real(), any_real(), any_real(), any_real()),
            (t, gx, gy, damping, dt) in (any_real(), any_real(), any_real(), any_real(), any_real()),
            (pick, idle) in (0u8..8, any_real()),
        ) {
            let mut b = Body::new(m.abs().max(Real::DELTA), i.abs().max(Real::DELTA)).unwrap();
            let zero_or = |keep: bool, x: Real| if keep { x } else { Real::ZERO };
            b.v = Vect::new(vx, vy);
            b.w = w;
            b.v_bias = Vect::new(zero_or(pick & 1 == 0, bx), by);
            b.w_bias = bw;
            b.f = Vect::new(zero_or(pick & 2 == 0, fx), zero_or(pick & 2 == 0, fy));
            b.t = zero_or(pick & 4 == 0, t);
            let gravity = Vect::new(zero_or(pick & 2 == 0, gx), zero_or(pick & 4 == 0, gy));
            let damping = if pick & 1 == 0 { Real::ONE } else { damping };
            // The idle test in full: energy on 256 bits against the limit.
            let term = |k: Real, r: Real| {
                I256::mul_i128(i128::from(k.to_bits()), wide_mul(r.to_bits(), r.to_bits()))
            };
            let below = |v: Vect, w: Real| {
                let e = term(b.mass, v.x).add(term(b.mass, v.y)).add(term(b.moment, w));
                let x = e.sub(term(b.mass, idle));
                x.is_negative() || x.is_zero()
            };
            proptest::prop_assert_eq!(b.is_idle(idle), below(b.v, b.w) && below(b.v_bias, b.w_bias));
            let (v, w, f, t) = (b.v, b.w, b.f, b.t);
            b.update_velocity(gravity, damping, dt);
            proptest::prop_assert_eq!(b.v, v * damping + (gravity + f * b.mass_inv) * dt);
            proptest::prop_assert_eq!(b.w, w * damping + t * b.moment_inv * dt);
        }
    }

    #[test]
    fn small_angle_series_constants_are_nearest() {
        for (bits, k) in [
            (178_956_971i64, 24.0),
            (5_965_232, 720.0),
            (106_522, 40320.0),
        ] {
            assert!((bits as f64 - 4294967296.0 / k).abs() <= 0.5, "1/{k}");
        }
        for (bits, k) in [
            (715_827_883i64, 6.0),
            (35_791_394, 120.0),
            (852_176, 5040.0),
        ] {
            assert!((bits as f64 - 4294967296.0 / k).abs() <= 0.5, "1/{k}");
        }
    }

    #[test]
    fn new_rejects_negative_mass_and_moment() {
        assert!(Body::new(-Real::ONE, Real::ONE).is_err());
        assert!(Body::new(Real::ONE, -Real::ONE).is_err());
        let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
        assert!(b.set_mass(Real::ZERO).is_err());
        assert!(Body::new_static().set_mass(Real::ONE).is_err());
    }

    #[test]
    fn impulse_at_offset_spins_the_body() {
        let mut b = Body::new(Real::TWO, Real::from_int(4)).unwrap();
        b.apply_impulse_at_world_point(Vect::from_ints(0, 2), Vect::from_ints(1, 0));
        assert_eq!(b.velocity(), Vect::from_ints(0, 1));
        assert_eq!(b.angular_velocity(), real!(0.5));
        assert_eq!(
            b.velocity_at_world_point(Vect::from_ints(2, 0)),
            Vect::new(Real::ZERO, real!(2))
        );
    }

    #[test]
    fn local_world_round_trip_with_cog() {
        let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
        b.set_center_of_gravity(Vect::from_ints(1, 0));
        b.set_position(Vect::from_ints(5, 5));
        assert_eq!(b.position(), Vect::from_ints(5, 5));
        assert_eq!(b.center(), Vect::from_ints(6, 5));
        let p = Vect::from_ints(3, -2);
        assert_eq!(b.world_to_local(b.local_to_world(p)), p);
    }

    #[test]
    fn integrator_is_semi_implicit_euler() {
        let mut b = Body::new(Real::ONE, Real::ONE).unwrap();
        let g = Vect::from_ints(0, -10);
        let dt = real!(0.5);
        b.update_velocity(g, Real::ONE, dt);
        b.update_position(dt);
        assert_eq!(b.velocity(), Vect::from_ints(0, -5));
        assert_eq!(b.position(), Vect::new(Real::ZERO, real!(-2.5)));
    }

    #[test]
    fn kinetic_energy_counts_both_parts() {
        let mut b = Body::new(Real::TWO, Real::from_int(3)).unwrap();
        b.set_velocity(Vect::from_ints(3, 4));
        b.set_angular_velocity(Real::TWO);
        assert_eq!(b.kinetic_energy(), Real::from_int(25 + 6));
    }

    #[test]
    fn kinetic_energy_is_exact_at_any_speed() {
        // 2^-10 kg at |v| = 10^5 m/s (v·v would saturate above 46,341 m/s):
        // ½ · 2^-10 · 10^10 = 4,882,812.5 J exactly.
        let m = Real::from_bits(1 << 22);
        let mut b = Body::new(m, m).unwrap();
        b.set_velocity(Vect::from_ints(60_000, 80_000));
        assert_eq!(b.kinetic_energy(), Real::from_int(4_882_812) + Real::HALF);
        // Spin alone, just as fast.
        b.set_velocity(Vect::ZERO);
        b.set_angular_velocity(Real::from_int(-100_000));
        assert_eq!(b.kinetic_energy(), Real::from_int(4_882_812) + Real::HALF);
        // 1 ulp of mass at 2^30 m/s: 2^27 J.
        let mut b = Body::new(Real::from_bits(1), Real::ONE).unwrap();
        b.set_velocity(Vect::new(Real::ZERO, Real::from_int(-(1 << 30))));
        assert_eq!(b.kinetic_energy(), Real::from_int(1 << 27));
        // Energies beyond the range saturate; they never wrap or go negative.
        let mut b = Body::new(Real::ONE, Real::MAX).unwrap();
        b.set_velocity(Vect::from_ints(100_000, 0));
        assert_eq!(b.kinetic_energy(), Real::MAX);
        b.set_velocity(Vect::new(Real::MIN, Real::MIN));
        b.set_angular_velocity(Real::MIN);
        assert_eq!(b.kinetic_energy(), Real::MAX);
    }

    #[test]
    fn kinetic_energy_is_rounded_once() {
        // Exact reference on u128 where m·v² fits: (Σ k·r²) / 2^65, rounded
        // to nearest (ties up: the energy is not negative).
        let mut seed = 0x1234_5678_9ABC_DEF1u64;
        let mut next = |bits: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed >> (64 - bits)
        };
        for _ in 0..1000 {
            let (m, i) = (next(40).max(1), next(40).max(1));
            let (vx, vy, w) = (next(42) as i64, -(next(42) as i64), next(42) as i64);
            let mut b = Body::new(Real::from_bits(m as i64), Real::from_bits(i as i64)).unwrap();
            b.set_velocity(Vect::new(Real::from_bits(vx), Real::from_bits(vy)));
            b.set_angular_velocity(Real::from_bits(w));
            let sq = |r: i64| u128::from(r.unsigned_abs()).pow(2);
            let twice = u128::from(m) * (sq(vx) + sq(vy)) + u128::from(i) * sq(w);
            let want = (twice + (1 << 64)) >> 65;
            assert_eq!(
                b.kinetic_energy().to_bits() as u128,
                want,
                "{m} {i} {vx} {vy} {w}"
            );
        }
    }
}
