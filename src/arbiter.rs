//! Arbiters: the persistent state of one touching shape pair.
//!
//! An arbiter lives as long as its two shapes touch, plus
//! `collision_persistence` steps after they stop (so a pair that separates
//! for a frame keeps its warm-start impulses). Each step the narrowphase
//! contacts are matched to last step's by **feature id**: a contact between
//! the same two features (vertex, edge) inherits the accumulated impulses
//! (warm starting), which is what lets stacks come to rest in few iterations.
//!
//! Arbiters are kept in a `Vec` sorted by `(shape_a, shape_b)` slot indices —
//! the canonical pair order — so lookup is a binary search and the solver's
//! order depends only on the state.
//!
//! # Lifecycle
//! Every state change is a method here; the step (`space/step/`) only
//! decides when to call which:
//!
//! | when (step stage) | method | state |
//! |---|---|---|
//! | 4, a pair touches for the first time | `Arbiter::new`, then `touch` | `FirstCollision` |
//! | 4, a known pair touches | `touch`: contacts matched by feature id, stamp set | `Cached` → `FirstCollision`, others kept |
//! | 4, the begin handler rejects it | `ignore` | `FirstCollision` → `Ignore` (until the shapes separate) |
//! | 5, a known pair does not touch | separate handler (unless already `Cached`), then `cache` | → `Cached` |
//! | 5, `Cached` for `collision_persistence` steps | `is_expired`: dropped | — |
//! | 13, after the post-solve handlers | `settle` | `FirstCollision` → `Normal` |
//!
//! Between steps an arbiter is therefore `Normal` or `Ignore` (touched in the
//! last step) or `Cached` (not touched), never `FirstCollision`
//! (`Arbiter::validate`).
use serde::{Deserialize, Serialize};

use crate::body::BodyHandle;
use crate::collision::{CollisionInfo, WarmStartId, MAX_CONTACTS_PER_ARBITER};
use crate::compact;
use crate::math::{Real, Vect};
use crate::shape::{Shape, ShapeHandle};

/// One point of an arbiter's contact manifold: the **persistent** state of
/// one contact, kept in the arbiter from step to step (and serialized in
/// snapshots): where it is and the impulses it has accumulated, carried to
/// the next step for warm starting.
///
/// One of the engine's four contact types: the narrowphase produces a
/// [`collision::Contact`](crate::collision::Contact) (a point pair with its
/// feature id), the arbiter keeps it as a `ManifoldPoint`, the solver
/// turns it into a per-step
/// `solver::ContactConstraint` row, and
/// the public query [`shapes_collide`](crate::collision::shapes_collide)
/// answers with [`collision::ContactPoint`](crate::collision::ContactPoint)s
/// (no feature id).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ManifoldPoint {
    /// Contact point relative to body a's centre of gravity.
    pub r1: Vect,
    /// Contact point relative to body b's centre of gravity.
    pub r2: Vect,
    /// Signed separation (negative when penetrating).
    pub dist: Real,
    /// Feature id ([`collision::Contact::feature_id`](crate::collision::Contact::feature_id)):
    /// matches this contact with last step's for warm starting.
    pub feature_id: u32,
    /// Accumulated normal impulse (warm-started).
    pub jn_acc: Real,
    /// Accumulated friction impulse (warm-started).
    pub jt_acc: Real,
}

/// The arbiter stage's buffers in the space (the narrowphase stage; not simulation
/// state): the allocation of last step's arbiter list, reused for the next
/// one, and the indices of the arbiters solved this step.
#[derive(Clone, Debug, Default)]
pub(crate) struct ArbiterBuffers {
    /// Last step's arbiter buffer, kept for its allocation.
    pub(crate) spare: Vec<Arbiter>,
    /// Indices (into the world's arbiter list) of the arbiters solved this
    /// step.
    pub(crate) active: Vec<u32>,
    /// The narrowphase's answer for each candidate pair when threads
    /// compute them ahead of the merge (`space/step/`).
    pub(crate) infos: Vec<Option<crate::collision::CollisionInfo>>,
    /// With threads: each candidate pair's warm-start id (its arbiter's,
    /// or 0), kept for its allocation.
    pub(crate) warm_start_ids: Vec<u32>,
    /// With threads: for each arbiter of last step's list, the candidate
    /// pair it matches (`u32::MAX`: none), kept for its allocation.
    pub(crate) matched: Vec<u32>,
    /// With threads: for each arbiter of last step's list, the candidate
    /// pair it matches or, if none, the first pair whose key follows its
    /// own (the number of pairs if none does): nondecreasing, kept for its
    /// allocation.
    pub(crate) place: Vec<u32>,
    /// With threads: for each candidate pair, whether it touches and
    /// whether its narrowphase hit the iteration cap (bit flags, `space/step/`),
    /// kept for its allocation.
    pub(crate) answer_flags: Vec<u8>,
    /// With threads and no collision handler: which arbiter fills each
    /// slot of this step's list (`space/step/`), kept for its allocation.
    pub(crate) slots: Vec<MergeSlot>,
}

/// One slot of a step's arbiter list as the split merge plans it
/// (`space/step/`): which arbiter fills it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MergeSlot {
    /// The arbiter of last step's list that fills the slot (its index), or
    /// `u32::MAX`: a new arbiter.
    pub(crate) old: u32,
    /// The candidate pair whose answer the arbiter takes (its index), or
    /// `u32::MAX`: the arbiter retires (its pair no longer touches).
    pub(crate) pair: u32,
    /// Set by the fill: the arbiter goes to the solver.
    pub(crate) active: bool,
}

/// Where an arbiter is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ArbiterState {
    /// Touching for the first step: the begin handler runs.
    FirstCollision,
    /// Touching, begin already accepted.
    Normal,
    /// A begin handler returned false: ignored until the shapes separate.
    Ignore,
    /// Not touching this step; kept for warm starting until it expires.
    Cached,
}

/// The persistent contact state of a shape pair (Chipmunk `cpArbiter`).
///
/// Serde: a binary serializer (snapshots) gets the compact form of
/// [`snapshot`](crate::snapshot) format version 6 (only the used contacts,
/// zero words left out; see the `Serialize` impl); a human-readable one
/// every field, as a derive would.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Arbiter {
    pub(crate) shape_a: ShapeHandle,
    pub(crate) shape_b: ShapeHandle,
    pub(crate) body_a: BodyHandle,
    pub(crate) body_b: BodyHandle,
    /// Contact normal, from shape a to shape b.
    pub(crate) normal: Vect,
    pub(crate) count: u8,
    pub(crate) contacts: [ManifoldPoint; MAX_CONTACTS_PER_ARBITER],
    /// Restitution (product of the shapes' elasticities unless a handler changed it).
    pub restitution: Real,
    /// Friction (product of the shapes' frictions unless a handler changed it).
    pub friction: Real,
    /// Relative surface velocity, tangential part (conveyor belts).
    pub surface_velocity: Vect,
    /// GJK warm-start cache for the next narrowphase of this pair (MIS
    /// `CollisionID`; not a feature id).
    pub(crate) warm_start_id: WarmStartId,
    /// Step stamp of the last step the shapes touched.
    pub(crate) stamp: u64,
    pub(crate) state: ArbiterState,
    /// True while the pair involves a sensor (callbacks only, no solving).
    pub(crate) sensor: bool,
}

/// The field-by-field serde form of [`Arbiter`] (a derive's), used for
/// human-readable formats.
#[derive(Serialize, Deserialize)]
#[serde(remote = "Arbiter", rename = "Arbiter")]
struct ArbiterFields {
    shape_a: ShapeHandle,
    shape_b: ShapeHandle,
    body_a: BodyHandle,
    body_b: BodyHandle,
    normal: Vect,
    count: u8,
    contacts: [ManifoldPoint; MAX_CONTACTS_PER_ARBITER],
    restitution: Real,
    friction: Real,
    surface_velocity: Vect,
    warm_start_id: WarmStartId,
    stamp: u64,
    state: ArbiterState,
    sensor: bool,
}

/// Words of the compact form before the contacts: normal (x, y),
/// restitution, friction, surface velocity (x, y).
pub(crate) const ARB_WORDS: usize = 6;
/// Words per used contact: r1 (x, y), r2 (x, y), dist, jn_acc, jt_acc.
pub(crate) const CONTACT_WORDS: usize = 7;
pub(crate) const ARB_MAX_WORDS: usize = ARB_WORDS + CONTACT_WORDS * MAX_CONTACTS_PER_ARBITER;
/// Head: the contact count (bits 0–1), the state (bits 2–3), `sensor`
/// (bit 4), then the presence mask of the words from bit 5.
const ARB_STATE_SHIFT: u32 = 2;
const ARB_SENSOR: u32 = 1 << 4;
const ARB_MASK_SHIFT: u32 = 5;
/// Head bit 30: a narrow mask follows (bits 25–29 are clear).
const ARB_NARROW: u32 = 1 << 30;

/// Binary (snapshot format 6): a tuple of
/// * a `u32` head: bits 0–1 the contact count, 2–3 the state (0
///   `FirstCollision`, 1 `Normal`, 2 `Ignore`, 3 `Cached`), bit 4
///   `sensor`, bits 5..25 the presence mask of the words below, bit 30
///   "narrow mask follows";
/// * the narrow mask (`u32`, not zero) when bit 30 is set: the present
///   words whose raw value fits an `i32`;
/// * shape a, shape b, body a, body b (handles: two `u32` each),
///   `warm_start_id` (`u32`), `stamp` (`u64`);
/// * the feature id (`u32`) of each used contact;
/// * the non-zero words, raw, as `i32` when narrow and `i64` otherwise:
///   normal (x, y), restitution, friction,
///   surface velocity (x, y), then per used contact r1, r2, dist, jn_acc,
///   jt_acc.
///
/// Not stored: the contact slots past the count, which the narrowphase
/// clears (`Arbiter::update`; validation demands it) and decoding leaves at
/// their default. The bodies are copies of the shapes' bodies (validation
/// checks that) but are stored: the shapes are not at hand when one
/// arbiter is decoded. Human-readable: the derive's form.
impl Serialize for Arbiter {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        if s.is_human_readable() {
            return ArbiterFields::serialize(self, s);
        }
        let used = self.contacts();
        let (words, n) = self.compact_words();
        let words = words.get(..n).unwrap_or(&[]);
        let mask = compact::mask_of(words);
        let narrow = compact::narrow_of(words, mask);
        let state = self.compact_state();
        // A count past 3 (only a corrupted in-memory state) is written as
        // 3, which the decoder rejects.
        let head = u32::from(self.count.min(3))
            | state << ARB_STATE_SHIFT
            | if self.sensor { ARB_SENSOR } else { 0 }
            | mask << ARB_MASK_SHIFT
            | if narrow != 0 { ARB_NARROW } else { 0 };
        let len = compact::count(mask)
            .saturating_add(used.len())
            .saturating_add(usize::from(narrow != 0))
            .saturating_add(7);
        let mut t = compact::tuple(s, len)?;
        t.serialize_element(&head)?;
        if narrow != 0 {
            t.serialize_element(&narrow)?;
        }
        t.serialize_element(&self.shape_a)?;
        t.serialize_element(&self.shape_b)?;
        t.serialize_element(&self.body_a)?;
        t.serialize_element(&self.body_b)?;
        t.serialize_element(&self.warm_start_id)?;
        t.serialize_element(&self.stamp)?;
        for c in used {
            t.serialize_element(&c.feature_id)?;
        }
        compact::write_words(&mut t, words, mask, narrow)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for Arbiter {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Arbiter, D::Error> {
        if d.is_human_readable() {
            ArbiterFields::deserialize(d)
        } else {
            compact::deserialize(d)
        }
    }
}

impl compact::Compact for Arbiter {
    const EXPECTING: &'static str = "a compact arbiter";
    const MAX_ELEMENTS: usize = 8 + MAX_CONTACTS_PER_ARBITER + ARB_MAX_WORDS;

    fn read<'de, A: serde::de::SeqAccess<'de>>(
        r: &mut compact::Reader<'de, A>,
    ) -> Result<Arbiter, A::Error> {
        let head: u32 = r.next()?;
        let count = (head & 3) as usize;
        if count > MAX_CONTACTS_PER_ARBITER {
            return Err(r.error("too many contacts"));
        }
        let state = (head >> ARB_STATE_SHIFT) & 3;
        // count ≤ 2: at most 6 + 14 words.
        let n = CONTACT_WORDS
            .saturating_mul(count)
            .saturating_add(ARB_WORDS);
        let mask = (head & !ARB_NARROW) >> ARB_MASK_SHIFT;
        if mask & !compact::bit(n).saturating_sub(1) != 0 {
            return Err(r.error("presence bits past the last word"));
        }
        let narrow = if head & ARB_NARROW != 0 {
            let m: u32 = r.next()?;
            if m == 0 {
                return Err(r.error("an empty narrow mask"));
            }
            m
        } else {
            0
        };
        let shape_a: ShapeHandle = r.next()?;
        let shape_b: ShapeHandle = r.next()?;
        let body_a: BodyHandle = r.next()?;
        let body_b: BodyHandle = r.next()?;
        let warm_start_id: WarmStartId = r.next()?;
        let stamp: u64 = r.next()?;
        let mut features = [0u32; MAX_CONTACTS_PER_ARBITER];
        for f in features.iter_mut().take(count) {
            *f = r.next()?;
        }
        let mut w = [Real::ZERO; ARB_MAX_WORDS];
        r.words(mask, Some(narrow), w.get_mut(..n).unwrap_or(&mut []))?;
        Ok(Arbiter::from_compact(
            [shape_a, shape_b],
            [body_a, body_b],
            CompactHead {
                count,
                state,
                sensor: head & ARB_SENSOR != 0,
                warm_start_id,
                stamp,
            },
            features,
            &w,
        ))
    }
}

/// The integers of an arbiter's compact forms besides handles and words.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CompactHead {
    /// Used contacts (at most [`MAX_CONTACTS_PER_ARBITER`]).
    pub(crate) count: usize,
    /// 0 `FirstCollision`, 1 `Normal`, 2 `Ignore`, 3 `Cached`.
    pub(crate) state: u32,
    pub(crate) sensor: bool,
    pub(crate) warm_start_id: WarmStartId,
    pub(crate) stamp: u64,
}

impl Arbiter {
    /// The stored words of the compact forms and how many there are:
    /// normal (x, y), restitution, friction, surface velocity (x, y), then
    /// per used contact r1 (x, y), r2 (x, y), dist, jn_acc, jt_acc.
    #[inline]
    pub(crate) fn compact_words(&self) -> ([Real; ARB_MAX_WORDS], usize) {
        let mut words = [Real::ZERO; ARB_MAX_WORDS];
        let mut n = 0usize;
        let mut put = |w: Real| {
            if let Some(slot) = words.get_mut(n) {
                *slot = w;
                n = n.saturating_add(1);
            }
        };
        [
            self.normal.x,
            self.normal.y,
            self.restitution,
            self.friction,
            self.surface_velocity.x,
            self.surface_velocity.y,
        ]
        .into_iter()
        .for_each(&mut put);
        for c in self.contacts() {
            [c.r1.x, c.r1.y, c.r2.x, c.r2.y, c.dist, c.jn_acc, c.jt_acc]
                .into_iter()
                .for_each(&mut put);
        }
        (words, n)
    }

    /// The state's code in the compact forms (see [`CompactHead`]).
    #[inline]
    pub(crate) fn compact_state(&self) -> u32 {
        match self.state {
            ArbiterState::FirstCollision => 0,
            ArbiterState::Normal => 1,
            ArbiterState::Ignore => 2,
            ArbiterState::Cached => 3,
        }
    }

    /// The arbiter of a compact form: handles, head, the used contacts'
    /// feature ids and the words (those past the count zero); the contact
    /// slots past the count stay at their default.
    #[inline]
    pub(crate) fn from_compact(
        [shape_a, shape_b]: [ShapeHandle; 2],
        [body_a, body_b]: [BodyHandle; 2],
        head: CompactHead,
        features: [u32; MAX_CONTACTS_PER_ARBITER],
        w: &[Real; ARB_MAX_WORDS],
    ) -> Arbiter {
        let count = head.count.min(MAX_CONTACTS_PER_ARBITER);
        let (head_words, contact_words) = w.split_at(ARB_WORDS);
        let [nx, ny, restitution, friction, sv_x, sv_y] =
            <[Real; ARB_WORDS]>::try_from(head_words).unwrap_or([Real::ZERO; ARB_WORDS]);
        let mut contacts = [ManifoldPoint::default(); MAX_CONTACTS_PER_ARBITER];
        for ((c, cw), f) in contacts
            .iter_mut()
            .zip(contact_words.chunks_exact(CONTACT_WORDS))
            .zip(features)
            .take(count)
        {
            if let [r1x, r1y, r2x, r2y, dist, jn, jt] = *cw {
                c.r1 = Vect::new(r1x, r1y);
                c.r2 = Vect::new(r2x, r2y);
                c.dist = dist;
                c.jn_acc = jn;
                c.jt_acc = jt;
                c.feature_id = f;
            }
        }
        Arbiter {
            shape_a,
            shape_b,
            body_a,
            body_b,
            normal: Vect::new(nx, ny),
            // count ≤ 2.
            count: count as u8,
            contacts,
            restitution,
            friction,
            surface_velocity: Vect::new(sv_x, sv_y),
            warm_start_id: head.warm_start_id,
            stamp: head.stamp,
            state: match head.state {
                0 => ArbiterState::FirstCollision,
                1 => ArbiterState::Normal,
                2 => ArbiterState::Ignore,
                _ => ArbiterState::Cached,
            },
            sensor: head.sensor,
        }
    }
}

impl Arbiter {
    /// A fresh arbiter for a touching pair (state `FirstCollision`, no
    /// contacts yet: [`touch`](Self::touch) follows).
    pub(crate) fn new(sa: ShapeHandle, a: &Shape, sb: ShapeHandle, b: &Shape) -> Arbiter {
        Arbiter {
            shape_a: sa,
            shape_b: sb,
            body_a: a.body,
            body_b: b.body,
            state: ArbiterState::FirstCollision,
            sensor: a.sensor || b.sensor,
            ..Arbiter::blank()
        }
    }

    /// A placeholder, overwritten before it is read: the slots by which
    /// the list of arbiters grows before threads fill them.
    pub(crate) fn blank() -> Arbiter {
        let (shape, body) = (
            ShapeHandle::from_raw_parts(0, 0),
            BodyHandle::from_raw_parts(0, 0),
        );
        Arbiter {
            shape_a: shape,
            shape_b: shape,
            body_a: body,
            body_b: body,
            normal: Vect::ZERO,
            count: 0,
            contacts: [ManifoldPoint::default(); MAX_CONTACTS_PER_ARBITER],
            restitution: Real::ZERO,
            friction: Real::ZERO,
            surface_velocity: Vect::ZERO,
            warm_start_id: 0,
            stamp: 0,
            state: ArbiterState::Cached,
            sensor: false,
        }
    }

    /// The shapes touch in this step (stamp `stamp`): takes the narrowphase
    /// result ([`update`](Self::update)), and a `Cached` arbiter starts a new
    /// contact (`FirstCollision`: the begin handler runs again).
    pub(crate) fn touch(
        &mut self,
        info: &CollisionInfo,
        a: &Shape,
        b: &Shape,
        centers: (Vect, Vect),
        stamp: u64,
    ) {
        self.update(info, a, b, centers.0, centers.1);
        if self.state == ArbiterState::Cached {
            self.state = ArbiterState::FirstCollision;
        }
        self.stamp = stamp;
    }

    /// The begin handler rejected the pair: ignored (no pre-solve, no
    /// solving) until the shapes separate.
    pub(crate) fn ignore(&mut self) {
        self.state = ArbiterState::Ignore;
    }

    /// True while a begin handler's rejection holds.
    pub(crate) fn is_ignored(&self) -> bool {
        self.state == ArbiterState::Ignore
    }

    /// True when the shapes did not touch in the last step that saw them
    /// (the separate handler has run).
    pub(crate) fn is_cached(&self) -> bool {
        self.state == ArbiterState::Cached
    }

    /// The shapes stopped touching (the caller has run the separate
    /// handler): kept only for warm starting until it expires.
    pub(crate) fn cache(&mut self) {
        self.state = ArbiterState::Cached;
    }

    /// True once the shapes have not touched for `persistence` steps
    /// (`world_stamp − stamp ≥ persistence`): the arbiter is dropped.
    pub(crate) fn is_expired(&self, world_stamp: u64, persistence: u32) -> bool {
        let idle = world_stamp.saturating_sub(self.stamp);
        idle >= u64::from(persistence)
    }

    /// The solver's accumulated impulses into manifold point `slot` (the
    /// next step's warm start, and the handlers'); nothing past the
    /// points.
    pub(crate) fn set_impulses(&mut self, slot: u32, jn: Real, jt: Real) {
        if let Some(contact) = self.contacts.get_mut(slot as usize) {
            contact.jn_acc = jn;
            contact.jt_acc = jt;
        }
    }

    /// End of a step that touched it (`stamp` is the world's): a first
    /// contact becomes `Normal`, so the begin handler does not run again.
    pub(crate) fn settle(&mut self, stamp: u64) {
        if self.stamp == stamp && self.state == ArbiterState::FirstCollision {
            self.state = ArbiterState::Normal;
        }
    }

    /// Takes this step's narrowphase result: new contacts inherit the
    /// accumulated impulses of last step's contacts with the same feature id;
    /// material values are recomputed (handlers may override them afterwards).
    /// `pa`/`pb` are the bodies' centres of gravity.
    fn update(&mut self, info: &CollisionInfo, a: &Shape, b: &Shape, pa: Vect, pb: Vect) {
        let old = self.contacts;
        let old_count = usize::from(self.count).min(MAX_CONTACTS_PER_ARBITER);
        self.normal = info.normal;
        self.warm_start_id = info.warm_start_id;
        self.count = 0;
        // Slots past the new count are cleared, so the state (and its
        // checksum) does not depend on how many contacts the pair had before.
        self.contacts = [ManifoldPoint::default(); MAX_CONTACTS_PER_ARBITER];
        for (slot, c) in self.contacts.iter_mut().zip(info.contacts()) {
            let mut new = ManifoldPoint {
                r1: c.point_a - pa,
                r2: c.point_b - pb,
                dist: c.distance,
                feature_id: c.feature_id,
                ..ManifoldPoint::default()
            };
            if let Some(prev) = old
                .iter()
                .take(old_count)
                .find(|o| o.feature_id == c.feature_id)
            {
                new.jn_acc = prev.jn_acc;
                new.jt_acc = prev.jt_acc;
            }
            *slot = new;
            // At most `MAX_CONTACTS_PER_ARBITER` slots: never saturates.
            self.count = self.count.saturating_add(1);
        }
        self.restitution = a.material.elasticity * b.material.elasticity;
        self.friction = a.material.friction * b.material.friction;
        // Only the tangential part of the relative surface velocity matters.
        let sv = b.material.surface_velocity - a.material.surface_velocity;
        // Equal surface velocities (most often none) give an exact zero.
        self.surface_velocity = if sv == Vect::ZERO {
            Vect::ZERO
        } else {
            let t = self.normal.perp();
            t * sv.dot(t)
        };
    }

    /// The two shapes, in the arbiter's (canonical) order. In a collision
    /// handler, `ArbiterContext::shapes` and `ArbiterContext::bodies` give
    /// the handler's order instead.
    pub fn shapes(&self) -> (ShapeHandle, ShapeHandle) {
        (self.shape_a, self.shape_b)
    }

    /// The two bodies, in the arbiter's order: those of
    /// [`shapes`](Self::shapes).
    pub fn bodies(&self) -> (BodyHandle, BodyHandle) {
        (self.body_a, self.body_b)
    }

    /// Number of contacts (0..=2).
    pub fn count(&self) -> usize {
        usize::from(self.count).min(MAX_CONTACTS_PER_ARBITER)
    }

    /// Contact normal, pointing from shape a to shape b.
    pub fn normal(&self) -> Vect {
        self.normal
    }

    /// The contact manifold: the persistent state of each contact.
    pub fn contacts(&self) -> &[ManifoldPoint] {
        self.contacts.get(..self.count()).unwrap_or(&[])
    }

    /// Penetration depth of contact `i` (positive when overlapping).
    pub fn depth(&self, i: usize) -> Option<Real> {
        self.contacts().get(i).map(|c| -c.dist)
    }

    /// True on the first step the shapes touch.
    pub fn is_first_contact(&self) -> bool {
        self.state == ArbiterState::FirstCollision
    }

    /// The lifecycle state.
    pub fn state(&self) -> ArbiterState {
        self.state
    }

    /// Total impulse applied this step (Chipmunk `cpArbiterTotalImpulse`).
    pub fn total_impulse(&self) -> Vect {
        self.contacts().iter().fold(Vect::ZERO, |acc, c| {
            acc + self.normal.rotate(Vect::new(c.jn_acc, c.jt_acc))
        })
    }

    /// Key of the canonical order.
    pub(crate) fn key(&self) -> (u32, u32) {
        (self.shape_a.index(), self.shape_b.index())
    }

    /// Checks what an arbiter stored between steps must satisfy, given the
    /// world's step stamp (snapshot loading, `Space::validate`): 1..=MAX
    /// contacts, each with `jn_acc ≥ 0` (the solver clamps the accumulated
    /// normal impulse); a stamp in `1..=world_stamp`; `Cached` exactly when
    /// the pair did not touch in the last step (`stamp < world_stamp`); and
    /// never `FirstCollision`, which the step turns into `Normal` before it
    /// returns.
    pub(crate) fn validate(&self, world_stamp: u64) -> Result<(), String> {
        let n = usize::from(self.count);
        if !(1..=MAX_CONTACTS_PER_ARBITER).contains(&n) {
            return Err(format!("{n} contacts (1..={MAX_CONTACTS_PER_ARBITER})"));
        }
        if self.contacts().iter().any(|c| c.jn_acc.is_negative()) {
            return Err("negative accumulated normal impulse".into());
        }
        if self.stamp == 0 || self.stamp > world_stamp {
            return Err(format!("stamp {} outside 1..={world_stamp}", self.stamp));
        }
        let touching = self.stamp == world_stamp;
        match self.state {
            ArbiterState::FirstCollision => Err("state FirstCollision outside a step".into()),
            ArbiterState::Cached if touching => {
                Err("state Cached but touched in the last step".into())
            }
            ArbiterState::Normal | ArbiterState::Ignore if !touching => Err(format!(
                "state {:?} but not touched in the last step",
                self.state
            )),
            ArbiterState::Normal | ArbiterState::Ignore | ArbiterState::Cached => Ok(()),
        }
    }
}

/// Every field, the small ones packed into one word (count, state, sensor
/// flag, warm-start id), then the numbers and the contact slots: the
/// checksum costs per word, and arbiters are hashed every frame.
impl core::hash::Hash for Arbiter {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Arbiter {
            shape_a,
            shape_b,
            body_a,
            body_b,
            normal,
            count,
            contacts,
            restitution,
            friction,
            surface_velocity,
            warm_start_id,
            stamp,
            state,
            sensor,
        } = self;
        let state: u64 = match state {
            ArbiterState::FirstCollision => 0,
            ArbiterState::Normal => 1,
            ArbiterState::Ignore => 2,
            ArbiterState::Cached => 3,
        };
        shape_a.hash(h);
        shape_b.hash(h);
        body_a.hash(h);
        body_b.hash(h);
        h.write_u64(
            u64::from(*count)
                | state << 8
                | u64::from(*sensor) << 10
                | u64::from(*warm_start_id) << 32,
        );
        stamp.hash(h);
        normal.hash(h);
        restitution.hash(h);
        friction.hash(h);
        surface_velocity.hash(h);
        // Both slots, fixed length: straight-line code (the slots past the
        // count are zero in every valid arbiter).
        for c in contacts {
            c.hash(h);
        }
    }
}
