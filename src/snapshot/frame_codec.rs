//! The payload of frame snapshots (frame format 7), written and read by
//! hand: objects straight from the world's arenas into bytes and from
//! bytes into a reused [`FrameState`], each as a head byte and a list of
//! words in the [`wire`](super::wire) coding (integers in as few bytes as
//! their value needs).
//!
//! ```text
//! level digest u64, stamp u64, steps u64, current dt u64, previous dt u64
//! settings          u32 byte count, then bincode (the full snapshots' configuration)
//! constraints       u32 byte count, then bincode
//! bodies, shapes    a part: words [slot count, length, held slots, free
//!                   slots], the free list (words, 32 a group), then each
//!                   held slot (the slots outside the level, in order)
//! arbiters          u32 count, then each arbiter
//! dormant arbiters  u32 count, then each arbiter
//! ```
//! * **Body slot**: a head byte — bit 0 live; for a live body bits 1–2 the
//!   type (0 dynamic, 1 kinematic, 2 static), 3 explicit mass, 4 sleep
//!   allowed, 5 bullet, 6 asleep — then the words: generation, the island
//!   root when asleep, and a live body's 19 state words (`Body::compact_words`).
//! * **Shape slot**: a `u16` head — bit 0 live, bits 1–2 the mass
//!   specification (none, mass, density), 3 sensor, 4 a filter follows, 5 a
//!   collision type follows, bits 8–15 the geometry's kind, polygon count
//!   and form — then the words: generation, the body handle (slot,
//!   generation), the filter (group, categories, mask) and the collision
//!   type when flagged, friction, elasticity, surface velocity (x, y), the
//!   mass or density, and the geometry's words (`Geometry::compact_form`).
//! * **Arbiter**: a head byte — bits 0–1 the contact count, 2–3 the state,
//!   4 sensor — then the words: shape a and shape b (slot, generation), the
//!   warm-start id, the frame's stamp minus the arbiter's (0 for a pair
//!   touching this step), the six arbiter words and, per contact, its
//!   feature id and seven words (`Arbiter::compact_words`). Ids are written
//!   nibble-ordered ([`nibbles_first`]: small indices, 2 bytes) and `r2`
//!   as its residual from what `r1`, the bodies' positions, the normal and
//!   the separation imply ([`r2_residual`]: about 1 byte instead of 5).
//!
//! Not written, and rebuilt: what the object forms leave out (inverse mass
//! and moment, polygon and segment normals, contact slots past the count),
//! and **an arbiter's bodies**, the bodies of its shapes, filled in when the
//! frame is installed (`Space::load_frame_snapshot`), where the level's
//! shapes are at hand; `r2` is completed there too ([`complete_arbiter`]). Every unused head bit must be clear and every flag
//! meaningful (a flagged filter is not the default one, a flagged collision
//! type not 0, no mass word without a mass specification), so one state has
//! one encoding.
use crate::arbiter::{Arbiter, CompactHead, ARB_MAX_WORDS, ARB_WORDS, CONTACT_WORDS};
use crate::arena::{Arena, ArenaPart, Handle};
use crate::body::{Body, BodyType, CompactFlags, BODY_WORDS};
use crate::collision::MAX_CONTACTS_PER_ARBITER;
use crate::math::{Real, Vect};
use crate::shape::geometry::{GEOM_FORM_HEAD, GEOM_MAX_WORDS};
use crate::shape::{Geometry, MassSpec, Material, Shape, ShapeFilter};
use crate::space::{FrameState, Space};

use super::wire::{Dec, Enc, WireError};
use super::CONFIG;

const BODY_LIVE: u8 = 1;
const BODY_TYPE_SHIFT: u32 = 1;
const BODY_EXPLICIT_MASS: u8 = 1 << 3;
const BODY_SLEEP_ALLOWED: u8 = 1 << 4;
const BODY_BULLET: u8 = 1 << 5;
const BODY_ASLEEP: u8 = 1 << 6;

const SHAPE_LIVE: u16 = 1;
const SHAPE_MASS_SHIFT: u32 = 1;
const SHAPE_SENSOR: u16 = 1 << 3;
const SHAPE_FILTER: u16 = 1 << 4;
const SHAPE_COLLISION_TYPE: u16 = 1 << 5;
const SHAPE_GEOMETRY_SHIFT: u32 = 8;
const SHAPE_HEAD: u16 = SHAPE_LIVE
    | 3 << SHAPE_MASS_SHIFT
    | SHAPE_SENSOR
    | SHAPE_FILTER
    | SHAPE_COLLISION_TYPE
    | 0xff00;

const ARB_STATE_SHIFT: u32 = 2;
const ARB_SENSOR: u8 = 1 << 4;
const ARB_HEAD: u8 = 3 | 3 << ARB_STATE_SHIFT | ARB_SENSOR;

/// Free-list entries per group of words.
const FREE_GROUP: usize = 32;

/// The body handle an arbiter holds until its frame is installed (see the
/// module docs).
pub(crate) const UNFILLED: Handle<Body> = Handle::from_raw_parts(u32::MAX, u32::MAX);
const UNFILLED_SHAPE: Handle<Shape> = Handle::from_raw_parts(u32::MAX, u32::MAX);

/// Feature and warm-start ids pack small indices into bytes (`a << 16 |
/// b`, `a₀ << 24 | b₀ << 16 | a₁ << 8 | b₁`). Written as their low nibbles
/// (the four bytes' low nibbles, then the high ones) they take 2 bytes
/// instead of 3–4 when every index is below 16. A bijection of `u32`.
#[inline(always)]
fn nibbles_first(x: u32) -> u32 {
    fn gather(v: u32) -> u32 {
        // The low nibble of each byte, packed into 16 bits.
        let v = v & 0x0F0F_0F0F;
        let v = (v | v >> 4) & 0x00FF_00FF;
        (v | v >> 8) & 0x0000_FFFF
    }
    gather(x) | gather(x >> 4) << 16
}

/// The inverse of [`nibbles_first`].
#[inline(always)]
fn nibbles_back(x: u32) -> u32 {
    fn spread(v: u32) -> u32 {
        // 16 bits into the low nibble of each byte.
        let v = v & 0x0000_FFFF;
        let v = (v | v << 8) & 0x00FF_00FF;
        (v | v << 4) & 0x0F0F_0F0F
    }
    spread(x) | spread(x >> 16) << 4
}

/// Contact point `r2` is written relative to what the rest of the
/// contact implies: `r2 − r1 − (pa − pb)` is `point_b − point_a`, which
/// the narrowphase makes the separation along the normal, `n · dist`, up to
/// rounding. So the word written is `r2 − r1 − (pa − pb) − n · dist`: a
/// byte or two instead of 5 (wrapping arithmetic on the raw words, `n ·
/// dist` by the engine's own product: exact both ways whatever the values).
#[inline(always)]
fn r2_residual(r1: Real, r2: Real, pa: Real, pb: Real, predicted: Real) -> i64 {
    r2.to_bits()
        .wrapping_sub(r1.to_bits())
        .wrapping_sub(pa.to_bits().wrapping_sub(pb.to_bits()))
        .wrapping_sub(predicted.to_bits())
}

/// Completes a decoded arbiter once its bodies are known: its contacts'
/// `r2` from the residuals the bytes hold (see [`r2_residual`]).
pub(crate) fn complete_arbiter(a: &mut Arbiter, pa: Vect, pb: Vect) {
    let count = a.contacts().len();
    let n = a.normal;
    for c in a.contacts.iter_mut().take(count) {
        let predicted = n.mult(c.dist);
        c.r2 = Vect::new(
            r2_from_residual(c.r1.x, c.r2.x, pa.x, pb.x, predicted.x),
            r2_from_residual(c.r1.y, c.r2.y, pa.y, pb.y, predicted.y),
        );
    }
}

/// The inverse of [`r2_residual`].
#[inline(always)]
fn r2_from_residual(r1: Real, residual: Real, pa: Real, pb: Real, predicted: Real) -> Real {
    Real::from_bits(
        residual
            .to_bits()
            .wrapping_add(r1.to_bits())
            .wrapping_add(pa.to_bits().wrapping_sub(pb.to_bits()))
            .wrapping_add(predicted.to_bits()),
    )
}

/// Appends the frame payload of `space` to `out`. Cannot fail but for the
/// bincode parts (settings, constraints), which into a `Vec` do not.
pub(crate) fn encode(space: &Space, out: &mut Vec<u8>) -> bool {
    space.with_level(|level| {
        let st = &space.state;
        let mut e = Enc::new(out);
        e.u64(level.digest);
        e.u64(st.stamp);
        e.u64(st.steps);
        e.u64(st.current_dt.to_bits() as u64);
        e.u64(st.prev_dt.to_bits() as u64);
        if !bincode_part(&mut e, &st.settings) || !bincode_part(&mut e, &st.constraints) {
            return false;
        }
        put_part(&mut e, &st.bodies, &level.body_runs, put_body);
        put_part(&mut e, &st.shapes, &level.shape_runs, put_shape);
        for list in [&st.arbiters, &st.dormant_arbiters] {
            e.u32(list.len() as u32);
            for a in list {
                let p = |h| st.bodies.get(h).map_or(Vect::ZERO, |b: &Body| b.p);
                put_arbiter(&mut e, a, st.stamp, [p(a.body_a), p(a.body_b)]);
            }
        }
        e.finish();
        true
    })
}

/// A serde value as a byte count and bincode.
fn bincode_part<T: serde::Serialize>(e: &mut Enc<'_>, value: &T) -> bool {
    let out = e.buffer();
    let at = out.len();
    out.extend_from_slice(&[0; 4]);
    if bincode::serde::encode_into_std_write(value, &mut *out, CONFIG).is_err() {
        return false;
    }
    let len = out.len().saturating_sub(at).saturating_sub(4) as u32;
    match out.get_mut(at..at.saturating_add(4)) {
        Some(slot) => {
            slot.copy_from_slice(&len.to_le_bytes());
            true
        }
        None => false,
    }
}

fn put_part<T>(
    e: &mut Enc<'_>,
    arena: &Arena<T>,
    runs: &[(u32, u32)],
    mut put: impl FnMut(&mut Enc<'_>, u32, Option<&T>),
) {
    let (slot_count, free, len) = arena.bookkeeping();
    let level: u64 = runs
        .iter()
        .map(|&(a, b)| u64::from(b.saturating_sub(a)))
        .sum();
    let held = u64::from(slot_count).saturating_sub(level);
    e.words(&[
        slot_count.into(),
        len.into(),
        held as i64,
        free.len() as i64,
    ]);
    for group in free.chunks(FREE_GROUP) {
        let mut o = e.object(group.len());
        for &i in group {
            o.word(i.into());
        }
        o.finish();
    }
    arena.for_each_outside(runs, |generation, value| put(e, generation, value));
}

fn put_body(e: &mut Enc<'_>, generation: u32, body: Option<&Body>) {
    let Some(b) = body else {
        e.u8(0);
        e.words(&[generation.into()]);
        return;
    };
    let flags = b.compact_flags();
    let kind: u8 = match b.body_type() {
        BodyType::Dynamic => 0,
        BodyType::Kinematic => 1,
        BodyType::Static => 2,
    };
    let flag = |on: bool, bit: u8| if on { bit } else { 0 };
    e.u8(BODY_LIVE
        | kind << BODY_TYPE_SHIFT
        | flag(flags.explicit_mass, BODY_EXPLICIT_MASS)
        | flag(flags.sleep_allowed, BODY_SLEEP_ALLOWED)
        | flag(flags.bullet, BODY_BULLET)
        | flag(flags.island.is_some(), BODY_ASLEEP));
    let n = 1usize
        .saturating_add(usize::from(flags.island.is_some()))
        .saturating_add(BODY_WORDS);
    let mut o = e.object(n);
    o.word(generation.into());
    if let Some(root) = flags.island {
        o.word(root.into());
    }
    for r in b.compact_words() {
        o.real(r);
    }
    o.finish();
}

fn put_shape(e: &mut Enc<'_>, generation: u32, shape: Option<&Shape>) {
    let Some(s) = shape else {
        e.u16(0);
        e.words(&[generation.into()]);
        return;
    };
    let (mass_kind, spec): (u16, Real) = match s.mass_spec {
        MassSpec::None => (0, Real::ZERO),
        MassSpec::Mass(m) => (1, m),
        MassSpec::Density(d) => (2, d),
    };
    let filter = s.filter != ShapeFilter::ALL;
    let collision_type = s.collision_type != 0;
    let (form, gw, n) = s.geometry.compact_form();
    let flag = |on: bool, bit: u16| if on { bit } else { 0 };
    // The form head is 8 bits (`GEOM_FORM_HEAD`).
    e.u16(
        SHAPE_LIVE
            | mass_kind << SHAPE_MASS_SHIFT
            | flag(s.sensor, SHAPE_SENSOR)
            | flag(filter, SHAPE_FILTER)
            | flag(collision_type, SHAPE_COLLISION_TYPE)
            | ((form & GEOM_FORM_HEAD) as u16) << SHAPE_GEOMETRY_SHIFT,
    );
    let words = 8usize
        .saturating_add(if filter { 3 } else { 0 })
        .saturating_add(usize::from(collision_type))
        .saturating_add(n);
    let mut o = e.object(words);
    o.word(generation.into());
    o.word(s.body.index().into());
    o.word(s.body.generation().into());
    if filter {
        o.word(s.filter.group.into());
        o.word(s.filter.categories.into());
        o.word(s.filter.mask.into());
    }
    if collision_type {
        o.word(s.collision_type.into());
    }
    let m = &s.material;
    for r in [
        m.friction,
        m.elasticity,
        m.surface_velocity.x,
        m.surface_velocity.y,
        spec,
    ] {
        o.real(r);
    }
    for &r in gw.get(..n).unwrap_or(&[]) {
        o.real(r);
    }
    o.finish();
}

/// `p`: the positions of the arbiter's bodies (see [`r2_residual`]).
fn put_arbiter(e: &mut Enc<'_>, a: &Arbiter, stamp: u64, [pa, pb]: [Vect; 2]) {
    // A count past 2 (only a corrupted in-memory state) is written as 3,
    // which the reader rejects.
    let contacts = a.contacts();
    let count = contacts.len();
    let head = (count.min(3) as u8)
        | (a.compact_state() as u8) << ARB_STATE_SHIFT
        | if a.sensor { ARB_SENSOR } else { 0 };
    e.u8(head);
    // 12 + 8 per contact (at most 2).
    let mut o = e.object(count.saturating_mul(8).saturating_add(12));
    o.word(a.shape_a.index().into());
    o.word(a.shape_a.generation().into());
    o.word(a.shape_b.index().into());
    o.word(a.shape_b.generation().into());
    o.word(nibbles_first(a.warm_start_id).into());
    o.word(stamp.wrapping_sub(a.stamp) as i64);
    for r in [
        a.normal.x,
        a.normal.y,
        a.restitution,
        a.friction,
        a.surface_velocity.x,
        a.surface_velocity.y,
    ] {
        o.real(r);
    }
    // The words of `Arbiter::compact_words`, each contact's feature id
    // before its own.
    for c in contacts {
        o.word(nibbles_first(c.feature_id).into());
        o.real(c.r1.x);
        o.real(c.r1.y);
        let predicted = a.normal.mult(c.dist);
        o.word(r2_residual(c.r1.x, c.r2.x, pa.x, pb.x, predicted.x));
        o.word(r2_residual(c.r1.y, c.r2.y, pa.y, pb.y, predicted.y));
        for r in [c.dist, c.jn_acc, c.jt_acc] {
            o.real(r);
        }
    }
    o.finish();
}

/// Decodes a frame payload into `frame`, reusing its buffers. The result
/// is not checked against anything but the coding (the level, the arenas'
/// tiling and every state invariant are checked when it is installed), and
/// its arbiters' bodies are [`UNFILLED`]. On error `frame` is left
/// half-written, fit only to be decoded into again.
pub(crate) fn decode_into(payload: &[u8], frame: &mut FrameState) -> Result<(), WireError> {
    let mut d = Dec::new(payload);
    // The full snapshots' limit: what is decoded is bounded by the bytes
    // present (every count is checked against them first).
    if payload.len() > super::MAX_SNAPSHOT_BYTES {
        return Err(d.error("a payload over the size limit"));
    }
    frame.level_digest = d.u64()?;
    frame.stamp = d.u64()?;
    frame.steps = d.u64()?;
    frame.current_dt = Real::from_bits(d.u64()? as i64);
    frame.prev_dt = Real::from_bits(d.u64()? as i64);
    frame.settings = bincode_read(&mut d)?;
    frame.constraints = bincode_read(&mut d)?;
    // A body slot takes at least 2 bytes, a shape slot 3, an arbiter 4.
    read_part(&mut d, &mut frame.bodies, 2, read_body)?;
    read_part(&mut d, &mut frame.shapes, 3, read_shape)?;
    let stamp = frame.stamp;
    for list in [&mut frame.arbiters, &mut frame.dormant_arbiters] {
        let n = d.count(4)?;
        // Written over the arbiters already there (no move of a whole
        // arbiter per entry), then any more appended.
        list.truncate(n);
        for a in list.iter_mut() {
            read_arbiter(&mut d, stamp, a)?;
        }
        list.reserve(n.saturating_sub(list.len()));
        while list.len() < n {
            let mut a = blank_arbiter();
            read_arbiter(&mut d, stamp, &mut a)?;
            list.push(a);
        }
    }
    if d.remaining() != 0 {
        return Err(d.error("bytes after the frame"));
    }
    Ok(())
}

/// An arbiter to decode into.
fn blank_arbiter() -> Arbiter {
    let head = CompactHead {
        count: 0,
        state: 0,
        sensor: false,
        warm_start_id: 0,
        stamp: 0,
    };
    let words = [Real::ZERO; ARB_MAX_WORDS];
    Arbiter::from_compact([UNFILLED_SHAPE; 2], [UNFILLED; 2], head, [0; 2], &words)
}

fn bincode_read<T: serde::de::DeserializeOwned>(d: &mut Dec<'_>) -> Result<T, WireError> {
    let n = d.u32()? as usize;
    let at = d.error("");
    let bytes = d.take(n)?;
    match bincode::serde::decode_from_slice::<T, _>(bytes, CONFIG) {
        Ok((v, read)) if read == n => Ok(v),
        Ok(_) => Err(WireError {
            what: "bytes left in a bincode part",
            ..at
        }),
        Err(_) => Err(WireError {
            what: "a bincode part that does not decode",
            ..at
        }),
    }
}

fn u32_of(d: &Dec<'_>, v: i64) -> Result<u32, WireError> {
    u32::try_from(v).map_err(|_| d.error("an unsigned 32-bit field out of range"))
}

fn read_part<T>(
    d: &mut Dec<'_>,
    part: &mut ArenaPart<T>,
    min_slot_bytes: usize,
    mut read: impl FnMut(&mut Dec<'_>, &mut u32, &mut Option<T>) -> Result<(), WireError>,
) -> Result<(), WireError> {
    let mut head = [0i64; 4];
    d.words(&mut head)?;
    let [slot_count, len, held, free] = head;
    let (slot_count, len) = (u32_of(d, slot_count)?, u32_of(d, len)?);
    let (held, free) = (u32_of(d, held)? as usize, u32_of(d, free)? as usize);
    if held > slot_count as usize || free > held {
        return Err(d.error("more held or free slots than slots"));
    }
    if held.saturating_mul(min_slot_bytes) > d.remaining() {
        return Err(d.error("a slot count past the end of the bytes"));
    }
    let list = part.free_mut();
    list.clear();
    let mut left = free;
    let mut group = [0i64; FREE_GROUP];
    while left > 0 {
        let n = left.min(FREE_GROUP);
        let g = group.get_mut(..n).unwrap_or(&mut []);
        d.words(g)?;
        for &i in g.iter() {
            list.push(u32_of(d, i)?);
        }
        left = left.saturating_sub(n);
    }
    part.refill((slot_count, len), held, |generation, value| {
        read(d, generation, value)
    })
}

/// A free slot after its head (`clear`: the head has no flag set): its
/// generation.
fn read_free_slot<T>(
    d: &mut Dec<'_>,
    clear: bool,
    generation: &mut u32,
    value: &mut Option<T>,
) -> Result<(), WireError> {
    if !clear {
        return Err(d.error("a free slot with flags"));
    }
    let mut o = d.object(1)?;
    *generation = o.u32();
    o.finish()?;
    *value = None;
    Ok(())
}

fn read_body(
    d: &mut Dec<'_>,
    generation: &mut u32,
    value: &mut Option<Body>,
) -> Result<(), WireError> {
    let head = d.u8()?;
    if head & BODY_LIVE == 0 {
        return read_free_slot(d, head == 0, generation, value);
    }
    if head & 0x80 != 0 {
        return Err(d.error("unknown bits set in a body head"));
    }
    let body_type = match (head >> BODY_TYPE_SHIFT) & 3 {
        0 => BodyType::Dynamic,
        1 => BodyType::Kinematic,
        2 => BodyType::Static,
        _ => return Err(d.error("unknown body type")),
    };
    let asleep = head & BODY_ASLEEP != 0;
    let mut o = d.object(
        1usize
            .saturating_add(usize::from(asleep))
            .saturating_add(BODY_WORDS),
    )?;
    let gen = o.u32();
    let island = if asleep { Some(o.u32()) } else { None };
    let mut reals = [Real::ZERO; BODY_WORDS];
    for r in reals.iter_mut() {
        *r = o.real();
    }
    o.finish()?;
    *generation = gen;
    let flags = CompactFlags {
        explicit_mass: head & BODY_EXPLICIT_MASS != 0,
        sleep_allowed: head & BODY_SLEEP_ALLOWED != 0,
        bullet: head & BODY_BULLET != 0,
        island,
    };
    // Written in place over a body already there.
    match value {
        Some(b) => *b = Body::from_compact_reusing(body_type, flags, reals, Some(b)),
        None => *value = Some(Body::from_compact(body_type, flags, reals)),
    }
    Ok(())
}

fn read_shape(
    d: &mut Dec<'_>,
    generation: &mut u32,
    value: &mut Option<Shape>,
) -> Result<(), WireError> {
    let head = d.u16()?;
    if head & SHAPE_LIVE == 0 {
        return read_free_slot(d, head == 0, generation, value);
    }
    if head & !SHAPE_HEAD != 0 {
        return Err(d.error("unknown bits set in a shape head"));
    }
    let form = u32::from(head >> SHAPE_GEOMETRY_SHIFT);
    let Some(geometry_words) = Geometry::compact_len(form) else {
        return Err(d.error("unknown geometry kind, count or form"));
    };
    let filter = head & SHAPE_FILTER != 0;
    let collision_type = head & SHAPE_COLLISION_TYPE != 0;
    let n = 8usize
        .saturating_add(if filter { 3 } else { 0 })
        .saturating_add(usize::from(collision_type))
        .saturating_add(geometry_words);
    let at = d.error("");
    let mut o = d.object(n)?;
    let gen = o.u32();
    let body = Handle::from_raw_parts(o.u32(), o.u32());
    let filter = if filter {
        Some(ShapeFilter {
            group: o.u32(),
            categories: o.u32(),
            mask: o.u32(),
        })
    } else {
        None
    };
    let collision_type = if collision_type { Some(o.u32()) } else { None };
    let (friction, elasticity, sv_x, sv_y, spec) =
        (o.real(), o.real(), o.real(), o.real(), o.real());
    let mut gw = [Real::ZERO; GEOM_MAX_WORDS];
    for g in gw.iter_mut().take(geometry_words) {
        *g = o.real();
    }
    o.finish()?;
    let fail = |what| WireError { what, ..at };
    *generation = gen;
    let filter = match filter {
        Some(f) if f == ShapeFilter::ALL => return Err(fail("the default filter stored")),
        Some(f) => f,
        None => ShapeFilter::ALL,
    };
    let collision_type = match collision_type {
        Some(0) => return Err(fail("collision type 0 stored")),
        Some(c) => c,
        None => 0,
    };
    let mass_spec = match (head >> SHAPE_MASS_SHIFT) & 3 {
        0 if spec.is_zero() => MassSpec::None,
        1 => MassSpec::Mass(spec),
        2 => MassSpec::Density(spec),
        _ => return Err(fail("bad mass specification")),
    };
    let material = Material {
        friction,
        elasticity,
        surface_velocity: Vect::new(sv_x, sv_y),
    };
    let sensor = head & SHAPE_SENSOR != 0;
    // A shape decoded over one with the same geometry (a frame's shapes
    // rarely change form) keeps it: the geometry is a pure function of its
    // compact form, so nothing is rebuilt.
    if let Some(old) = value.as_mut() {
        let same = old.geometry.matches_compact(form, &gw).unwrap_or_else(|| {
            let (old_form, old_words, old_n) = old.geometry.compact_form();
            old_form == form
                && old_n == geometry_words
                && old_words.get(..old_n) == gw.get(..geometry_words)
        });
        if same {
            old.body = body;
            old.material = material;
            old.filter = filter;
            old.collision_type = collision_type;
            old.sensor = sensor;
            old.mass_spec = mass_spec;
            return Ok(());
        }
    }
    let shape = Shape {
        body,
        geometry: Geometry::from_compact(form, &gw).map_err(fail)?,
        material,
        filter,
        collision_type,
        sensor,
        mass_spec,
    };
    match value {
        Some(s) => *s = shape,
        None => *value = Some(shape),
    }
    Ok(())
}

#[inline(always)]
fn read_arbiter(d: &mut Dec<'_>, stamp: u64, out: &mut Arbiter) -> Result<(), WireError> {
    let head = d.u8()?;
    if head & !ARB_HEAD != 0 {
        return Err(d.error("unknown bits set in an arbiter head"));
    }
    let count = usize::from(head & 3);
    if count > MAX_CONTACTS_PER_ARBITER {
        return Err(d.error("too many contacts"));
    }
    // At most 12 + 2 · 8 = 28 words.
    let mut o = d.object(12usize.saturating_add(count.saturating_mul(1 + CONTACT_WORDS)))?;
    let shape_a = Handle::from_raw_parts(o.u32(), o.u32());
    let shape_b = Handle::from_raw_parts(o.u32(), o.u32());
    let warm_start_id = nibbles_back(o.u32());
    let arb_stamp = stamp.wrapping_sub(o.word() as u64);
    let mut words = [Real::ZERO; ARB_MAX_WORDS];
    let (head_words, contact_words) = words.split_at_mut(ARB_WORDS);
    for x in head_words {
        *x = o.real();
    }
    let mut features = [0u32; MAX_CONTACTS_PER_ARBITER];
    for (f, cw) in features
        .iter_mut()
        .zip(contact_words.chunks_exact_mut(CONTACT_WORDS))
        .take(count)
    {
        *f = nibbles_back(o.u32());
        for x in cw {
            *x = o.real();
        }
    }
    o.finish()?;
    *out = Arbiter::from_compact(
        [shape_a, shape_b],
        [UNFILLED, UNFILLED],
        CompactHead {
            count,
            state: u32::from((head >> ARB_STATE_SHIFT) & 3),
            sensor: head & ARB_SENSOR != 0,
            warm_start_id,
            stamp: arb_stamp,
        },
        features,
        &words,
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn id_nibble_order_is_a_bijection_that_shrinks_small_indices() {
        for x in [
            0u32,
            1,
            0x0001_0000,
            0x0203_0405,
            0x0706_0504,
            u32::MAX,
            0xF0F0_F0F0,
            0x1234_5678,
        ] {
            assert_eq!(nibbles_back(nibbles_first(x)), x, "{x:#x}");
            assert_eq!(nibbles_first(nibbles_back(x)), x, "{x:#x}");
        }
        // Indices below 16 in every byte: 16 bits.
        assert_eq!(nibbles_first(0x0203_0405), 0x2345);
        assert_eq!(nibbles_first(0x0007_0003), 0x0703);
    }

    #[test]
    fn r2_residuals_round_trip_exactly_at_the_extremes() {
        let raws = [0i64, 1, -1, 1 << 40, i64::MAX, i64::MIN, -(1 << 33) + 5];
        for &r1 in &raws {
            for &r2 in &raws {
                for &pa in &raws {
                    let (r1, r2, pa, pb) = (
                        Real::from_bits(r1),
                        Real::from_bits(r2),
                        Real::from_bits(pa),
                        Real::from_bits(7),
                    );
                    let q = Real::from_bits(-3);
                    let d = Real::from_bits(r2_residual(r1, r2, pa, pb, q));
                    assert_eq!(r2_from_residual(r1, d, pa, pb, q), r2);
                }
            }
        }
    }
}
