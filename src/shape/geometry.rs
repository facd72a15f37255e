//! Shape geometry: circle, segment and convex polygon, in body-local space or
//! (after [`Geometry::to_world`]) in world space.
//!
//! Geometry is a small `Copy` value with inline vertex storage (at most
//! [`MAX_POLY_VERTICES`]): moving shapes into world space each step allocates
//! nothing, and snapshots hold plain values.
use core::hash::Hash;

use serde::{Deserialize, Serialize};

pub use super::error::MAX_POLY_VERTICES;
use super::ShapeError;
use crate::compact;
use crate::math::{Real, Rot, Vect, BB};

/// A circle: centre offset from the body origin and radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Circle {
    /// Centre, in body coordinates (world coordinates once transformed).
    pub offset: Vect,
    /// Radius, ≥ 0.
    pub radius: Real,
}

/// A segment from `a` to `b` with a rounding radius (a capsule when r > 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Segment {
    /// First endpoint.
    pub a: Vect,
    /// Second endpoint.
    pub b: Vect,
    /// Unit normal, `rperp(b − a)` normalised (Chipmunk's convention: the
    /// right-hand side of a → b). Zero for a zero-length segment.
    pub normal: Vect,
    /// Rounding radius, ≥ 0.
    pub radius: Real,
    /// Tangent towards the previous neighbour (`prev − a`), or zero if none.
    /// A contact at a joint whose normal points into the neighbour is left
    /// to the neighbour (cores apart) or kept with the chain's normal at the
    /// joint (cores touching), so a chain of segments behaves like smooth
    /// terrain (see `collision::pairs`).
    pub a_tangent: Vect,
    /// Tangent towards the next neighbour (`next − b`), or zero if none.
    pub b_tangent: Vect,
}

/// A convex polygon with counter-clockwise vertices and a rounding radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Poly {
    /// Number of used entries of `verts`/`normals` (3..=MAX_POLY_VERTICES).
    pub(crate) count: u8,
    /// Vertices, counter-clockwise; entries past `count` are zero.
    pub(crate) verts: [Vect; MAX_POLY_VERTICES],
    /// `normals[i]` is the outward unit normal of edge `verts[i] → verts[i+1]`.
    pub(crate) normals: [Vect; MAX_POLY_VERTICES],
    /// Rounding radius, ≥ 0.
    pub(crate) radius: Real,
}

/// The geometry of one shape.
///
/// Serde: a binary serializer (snapshots) gets the compact form of
/// [`snapshot`](crate::snapshot) format version 6 (no normals, only the
/// used polygon vertices, zero words left out; see the `Serialize` impl);
/// a human-readable one every field, as a derive would.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// A circle.
    Circle(Circle),
    /// A segment (capsule).
    Segment(Segment),
    /// A convex polygon.
    Poly(Poly),
}

/// The variant-by-variant serde form of [`Geometry`] (a derive's), used
/// for human-readable formats.
#[derive(Serialize, Deserialize)]
#[serde(remote = "Geometry", rename = "Geometry")]
enum GeometryFields {
    Circle(Circle),
    Segment(Segment),
    Poly(Poly),
}

/// Head of the compact form: the kind (bits 0–1: circle, segment,
/// polygon), a polygon's vertex count (bits 2–5) and form (bits 6–7:
/// general, axis-aligned rectangle, centred axis-aligned rectangle), then
/// the presence mask of the kind's words from bit 8.
const GEOM_POLY_COUNT_SHIFT: u32 = 2;
const GEOM_FORM_SHIFT: u32 = 6;
const GEOM_MASK_SHIFT: u32 = 8;
/// The head bits below the presence mask: kind, polygon count, form.
pub(crate) const GEOM_FORM_HEAD: u32 = (1 << GEOM_MASK_SHIFT) - 1;
/// Polygon forms.
const FORM_GENERAL: u32 = 0;
const FORM_RECT: u32 = 1;
const FORM_CENTRED_RECT: u32 = 2;
/// Most words of one geometry: a polygon's 8 vertices and its radius.
pub(crate) const GEOM_MAX_WORDS: usize = 2 * MAX_POLY_VERTICES + 1;

/// `(l, b, r, t)` when `p` is the rectangle [`Poly::from_bb`] builds
/// (4 vertices `(r, b), (r, t), (l, t), (l, b)`): then those four values
/// give every vertex back exactly.
fn rect_of(p: &Poly) -> Option<[Real; 4]> {
    match p.verts() {
        [v0, v1, v2, v3] if v0.x == v1.x && v1.y == v2.y && v2.x == v3.x && v3.y == v0.y => {
            Some([v2.x, v0.y, v0.x, v1.y])
        }
        _ => None,
    }
}

/// `-v`, exactly, or `None` for the one raw value without a negation.
fn neg_exact(v: Real) -> Option<Real> {
    v.to_bits().checked_neg().map(Real::from_bits)
}

/// The form a polygon is written in, with its rectangle when it has one:
/// centred rectangle when `l = −r` and `b = −t`, else rectangle, else
/// general. Decoding checks that the polygon it builds has the form it was
/// read in (one encoding per polygon).
fn poly_form(p: &Poly) -> (u32, [Real; 4]) {
    match rect_of(p) {
        Some([l, b, r, t]) if neg_exact(r) == Some(l) && neg_exact(t) == Some(b) => {
            (FORM_CENTRED_RECT, [l, b, r, t])
        }
        Some(ltrb) => (FORM_RECT, ltrb),
        None => (FORM_GENERAL, [Real::ZERO; 4]),
    }
}

/// Binary (snapshot format 6): a tuple of a `u32` head (see
/// `GEOM_POLY_COUNT_SHIFT` and around) and the kind's non-zero words as raw
/// `i64`:
/// * circle: offset (x, y), radius;
/// * segment: a, b, radius, a_tangent, b_tangent — not the normal, a pure
///   function of a and b (`Segment::new`, the only way a segment's
///   endpoints are set, computes it; validation demands exactly that one);
/// * polygon, general form: the `count` used vertices, radius; rectangle
///   form (the 4 vertices of [`Poly::from_bb`]): l, b, r, t, radius;
///   centred rectangle (l = −r, b = −t: [`Poly::new_box`]): r, t, radius.
///   Never the normals (pure functions of the vertices,
///   `Poly::from_ccw_unchecked` computes them for every polygon the API
///   makes) nor the unused vertex and normal slots (zero).
///
/// Decoding rebuilds the polygon with `Poly::from_ccw_unchecked` (normals
/// exactly as the constructor computes them, zeros past the count) and the
/// segment with `Segment::new`'s normal; validation then checks convexity,
/// counts and ranges as before. Human-readable: the derive's form.
impl Serialize for Geometry {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        if s.is_human_readable() {
            return GeometryFields::serialize(self, s);
        }
        let (form_head, words, n) = self.compact_form();
        let words = words.get(..n).unwrap_or(&[]);
        let mask = compact::mask_of(words);
        let head = form_head | mask << GEOM_MASK_SHIFT;
        let mut t = compact::tuple(s, compact::count(mask).saturating_add(1))?;
        t.serialize_element(&head)?;
        compact::write_words(&mut t, words, mask, 0)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for Geometry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Geometry, D::Error> {
        if d.is_human_readable() {
            GeometryFields::deserialize(d)
        } else {
            compact::deserialize(d)
        }
    }
}

impl compact::Compact for Geometry {
    const EXPECTING: &'static str = "a compact geometry";
    const MAX_ELEMENTS: usize = 1 + GEOM_MAX_WORDS;

    fn read<'de, A: serde::de::SeqAccess<'de>>(
        r: &mut compact::Reader<'de, A>,
    ) -> Result<Geometry, A::Error> {
        let head: u32 = r.next()?;
        let form_head = head & GEOM_FORM_HEAD;
        let mask = head >> GEOM_MASK_SHIFT;
        let Some(n) = Geometry::compact_len(form_head) else {
            return Err(r.error("unknown kind, count or form"));
        };
        if mask & !compact::bit(n).saturating_sub(1) != 0 {
            return Err(r.error("presence bits past the last word"));
        }
        let mut w = [Real::ZERO; GEOM_MAX_WORDS];
        r.words(mask, None, w.get_mut(..n).unwrap_or(&mut []))?;
        Geometry::from_compact(form_head, &w).map_err(|e| r.error(e))
    }
}

impl Geometry {
    /// The compact forms' description of this geometry: the kind, count
    /// and form bits of the head ([`GEOM_FORM_HEAD`]), the stored words and
    /// how many there are (see the `Serialize` impl).
    #[inline]
    pub(crate) fn compact_form(&self) -> (u32, [Real; GEOM_MAX_WORDS], usize) {
        let mut words = [Real::ZERO; GEOM_MAX_WORDS];
        let mut n = 0usize;
        let mut put = |w: Real| {
            if let Some(slot) = words.get_mut(n) {
                *slot = w;
                n = n.saturating_add(1);
            }
        };
        let (kind, form): (u32, u32) = match self {
            Geometry::Circle(c) => {
                [c.offset.x, c.offset.y, c.radius].into_iter().for_each(put);
                (0, 0)
            }
            Geometry::Segment(g) => {
                [
                    g.a.x,
                    g.a.y,
                    g.b.x,
                    g.b.y,
                    g.radius,
                    g.a_tangent.x,
                    g.a_tangent.y,
                    g.b_tangent.x,
                    g.b_tangent.y,
                ]
                .into_iter()
                .for_each(put);
                (1, 0)
            }
            Geometry::Poly(p) => {
                // A stored count past 15 (only a corrupted in-memory state)
                // is written as 15, which the decoder rejects.
                let kind = 2 | u32::from(p.count.min(15)) << GEOM_POLY_COUNT_SHIFT;
                let (form, [l, b, r, t]) = poly_form(p);
                match form {
                    FORM_CENTRED_RECT => [r, t, p.radius].into_iter().for_each(put),
                    FORM_RECT => [l, b, r, t, p.radius].into_iter().for_each(put),
                    _ => {
                        for v in p.verts() {
                            put(v.x);
                            put(v.y);
                        }
                        put(p.radius);
                    }
                }
                (kind, form)
            }
        };
        (kind | form << GEOM_FORM_SHIFT, words, n)
    }

    /// Whether [`from_compact`](Self::from_compact) of these head bits and
    /// words would give exactly this geometry, decided without building
    /// it, for circles, segments and rectangles (the usual shapes of a
    /// frame); `None` for a general polygon (its form check needs the
    /// polygon: compare [`compact_form`](Self::compact_form) instead).
    /// Exact because every stored geometry's derived fields (normals) are
    /// those of its defining fields, which the compact form holds.
    #[inline]
    pub(crate) fn matches_compact(
        &self,
        form_head: u32,
        w: &[Real; GEOM_MAX_WORDS],
    ) -> Option<bool> {
        let kind = form_head & 3;
        let count = (form_head >> GEOM_POLY_COUNT_SHIFT) & 15;
        let form = (form_head >> GEOM_FORM_SHIFT) & 3;
        let v = |x: Real, y: Real| Vect::new(x, y);
        let [w0, w1, w2, w3, w4, w5, w6, w7, w8, ..] = *w;
        Some(match (self, kind, form, count) {
            (Geometry::Circle(c), 0, 0, 0) => c.offset == v(w0, w1) && c.radius == w2,
            (Geometry::Segment(g), 1, 0, 0) => {
                g.a == v(w0, w1)
                    && g.b == v(w2, w3)
                    && g.radius == w4
                    && g.a_tangent == v(w5, w6)
                    && g.b_tangent == v(w7, w8)
            }
            (Geometry::Poly(p), 2, FORM_CENTRED_RECT, 4) => {
                let (r, t) = (w0, w1);
                let (Some(l), Some(b)) = (neg_exact(r), neg_exact(t)) else {
                    return Some(false);
                };
                p.verts() == [v(r, b), v(r, t), v(l, t), v(l, b)] && p.radius == w2
            }
            (Geometry::Poly(p), 2, FORM_RECT, 4) => {
                let (l, b, r, t) = (w0, w1, w2, w3);
                // A centred rectangle is not written in this form.
                let centred = neg_exact(r) == Some(l) && neg_exact(t) == Some(b);
                !centred && p.verts() == [v(r, b), v(r, t), v(l, t), v(l, b)] && p.radius == w4
            }
            (Geometry::Poly(_), 2, FORM_GENERAL, _) => return None,
            _ => false,
        })
    }

    /// Number of words of the compact form with these head bits, `None`
    /// for an unknown kind, count or form.
    #[inline]
    pub(crate) fn compact_len(form_head: u32) -> Option<usize> {
        let kind = form_head & 3;
        let count = (form_head >> GEOM_POLY_COUNT_SHIFT) & 15;
        let form = (form_head >> GEOM_FORM_SHIFT) & 3;
        match (kind, form) {
            (0, 0) if count == 0 => Some(3),
            (1, 0) if count == 0 => Some(9),
            // At most 2·8 + 1: no overflow.
            (2, FORM_GENERAL) if count as usize <= MAX_POLY_VERTICES => {
                Some((count as usize).saturating_mul(2).saturating_add(1))
            }
            (2, FORM_RECT) if count == 4 => Some(5),
            (2, FORM_CENTRED_RECT) if count == 4 => Some(3),
            _ => None,
        }
    }

    /// The geometry of a compact form (head bits and words, those past
    /// [`compact_len`](Self::compact_len) zero), derived fields rebuilt;
    /// an error for an unknown form or a polygon not in its own form.
    #[inline]
    pub(crate) fn from_compact(
        form_head: u32,
        w: &[Real; GEOM_MAX_WORDS],
    ) -> Result<Geometry, &'static str> {
        let Some(n) = Geometry::compact_len(form_head) else {
            return Err("unknown kind, count or form");
        };
        let kind = form_head & 3;
        let count = (form_head >> GEOM_POLY_COUNT_SHIFT) & 15;
        let form = (form_head >> GEOM_FORM_SHIFT) & 3;
        let v = |x: Real, y: Real| Vect::new(x, y);
        let [w0, w1, w2, w3, w4, w5, w6, w7, w8, ..] = *w;
        let geometry = match (kind, form) {
            (0, _) => Geometry::Circle(Circle {
                offset: v(w0, w1),
                radius: w2,
            }),
            (1, _) => Geometry::Segment(Segment {
                a_tangent: v(w5, w6),
                b_tangent: v(w7, w8),
                // The normal is derived, see the `Serialize` impl.
                ..Segment::new(v(w0, w1), v(w2, w3), w4)
            }),
            (_, FORM_GENERAL) => {
                // `count` ≤ MAX_POLY_VERTICES (checked above).
                let count = count as usize;
                let mut verts = [Vect::ZERO; MAX_POLY_VERTICES];
                for (vert, pair) in verts.iter_mut().zip(w.chunks_exact(2)).take(count) {
                    if let [x, y] = pair {
                        *vert = v(*x, *y);
                    }
                }
                let radius = w.get(n.saturating_sub(1)).copied().unwrap_or(Real::ZERO);
                // Normals derived, see the `Serialize` impl; validation
                // checks the vertices (3..=8, strictly convex, ccw).
                Geometry::Poly(Poly::from_ccw_unchecked(
                    verts.get(..count).unwrap_or(&[]),
                    radius,
                ))
            }
            (_, FORM_RECT) => {
                let (l, b, rr, t) = (w0, w1, w2, w3);
                let verts = [v(rr, b), v(rr, t), v(l, t), v(l, b)];
                Geometry::Poly(Poly::from_ccw_unchecked(&verts, w4))
            }
            _ => {
                let (rr, t) = (w0, w1);
                let (Some(l), Some(b)) = (neg_exact(rr), neg_exact(t)) else {
                    return Err("a centred rectangle's half size has no negation");
                };
                let verts = [v(rr, b), v(rr, t), v(l, t), v(l, b)];
                Geometry::Poly(Poly::from_ccw_unchecked(&verts, w2))
            }
        };
        if let Geometry::Poly(p) = &geometry {
            if poly_form(p).0 != form {
                return Err("a polygon not in its own form");
            }
        }
        Ok(geometry)
    }
}

/// Which kind of geometry; also the collision-table order (circle < segment < poly).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum ShapeKind {
    /// [`Circle`].
    Circle,
    /// [`Segment`].
    Segment,
    /// [`Poly`].
    Poly,
}

impl Circle {
    /// A circle with the given radius and offset (validation happens in the
    /// shape constructors).
    pub const fn new(radius: Real, offset: Vect) -> Circle {
        Circle { offset, radius }
    }

    /// Moved into world space.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Circle {
        // A centred circle (the usual one) is at `pos`: exactly what the
        // rotation of a zero offset would give.
        let offset = if self.offset == Vect::ZERO {
            pos
        } else {
            pos + rot.apply(self.offset)
        };
        Circle {
            offset,
            radius: self.radius,
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        BB::for_circle(self.offset, self.radius)
    }
}

impl Segment {
    /// A segment without neighbours.
    pub fn new(a: Vect, b: Vect, radius: Real) -> Segment {
        Segment {
            a,
            b,
            normal: edge_normal((b - a).rperp()),
            radius,
            a_tangent: Vect::ZERO,
            b_tangent: Vect::ZERO,
        }
    }

    /// Sets the neighbours `prev` (joined at `a`) and `next` (joined at `b`),
    /// MIS/Chipmunk `segmentShapeSetNeighbors`.
    pub fn with_neighbors(mut self, prev: Vect, next: Vect) -> Segment {
        self.a_tangent = prev - self.a;
        self.b_tangent = next - self.b;
        self
    }

    /// Moved into world space.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Segment {
        Segment {
            a: pos + rot.apply(self.a),
            b: pos + rot.apply(self.b),
            normal: rot.apply(self.normal),
            radius: self.radius,
            a_tangent: rot.apply(self.a_tangent),
            b_tangent: rot.apply(self.b_tangent),
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        BB::for_point(self.a).expand(self.b).grow(self.radius)
    }
}

/// The index after `i` around a closed polygon of `n` vertices: `i + 1`, or
/// 0 after the last (the same as `(i + 1) % n` for `i < n`; 0 otherwise).
#[inline]
pub(crate) fn next_index(i: usize, n: usize) -> usize {
    match i.checked_add(1) {
        Some(j) if j < n => j,
        _ => 0,
    }
}

/// `d.normalize()`, bit for bit, without the square root when `d` is
/// axis-aligned (every rectangle's edges; decoding a snapshot rebuilds the
/// normals of each polygon): `normalize` scales `(x, 0)` so that the root
/// of `x²` is exactly `|x|`, and the rounded quotient `x·2^32 / |x|` is
/// exactly ±1 (±0 for 0), whatever `x`, `i64::MIN` included (a unit test
/// compares both on the extremes).
#[inline]
fn edge_normal(d: Vect) -> Vect {
    if d.y.is_zero() {
        Vect::new(d.x.signum(), Real::ZERO)
    } else if d.x.is_zero() {
        Vect::new(Real::ZERO, d.y.signum())
    } else {
        d.normalize()
    }
}

impl Poly {
    /// Builds a polygon from vertices that are already convex and
    /// counter-clockwise, without checks. Callers in this crate validate
    /// first (see `shape::poly`); `verts.len()` must be in `1..=MAX`.
    pub(crate) fn from_ccw_unchecked(verts: &[Vect], radius: Real) -> Poly {
        let mut p = Poly {
            count: 0,
            verts: [Vect::ZERO; MAX_POLY_VERTICES],
            normals: [Vect::ZERO; MAX_POLY_VERTICES],
            radius,
        };
        for (slot, v) in p.verts.iter_mut().zip(verts) {
            *slot = *v;
            // At most `MAX_POLY_VERTICES` slots: never saturates.
            p.count = p.count.saturating_add(1);
        }
        p.compute_normals();
        p
    }

    fn compute_normals(&mut self) {
        let n = self.count();
        for i in 0..n {
            let a = self.vert(i);
            let b = self.vert(next_index(i, n));
            if let Some(slot) = self.normals.get_mut(i) {
                *slot = edge_normal((b - a).rperp());
            }
        }
    }

    /// Number of vertices.
    #[inline]
    pub fn count(&self) -> usize {
        usize::from(self.count).min(MAX_POLY_VERTICES)
    }

    /// The vertices, counter-clockwise.
    #[inline]
    pub fn verts(&self) -> &[Vect] {
        self.verts.get(..self.count()).unwrap_or(&[])
    }

    /// The outward edge normals (`normals()[i]` belongs to edge i → i+1).
    #[inline]
    pub fn normals(&self) -> &[Vect] {
        self.normals.get(..self.count()).unwrap_or(&[])
    }

    /// Vertex `i` (wrapping past the end is the caller's job); out of range gives zero.
    #[inline]
    pub fn vert(&self, i: usize) -> Vect {
        self.verts.get(i).copied().unwrap_or(Vect::ZERO)
    }

    /// Normal of edge `i`; out of range gives zero.
    #[inline]
    pub fn normal(&self, i: usize) -> Vect {
        self.normals.get(i).copied().unwrap_or(Vect::ZERO)
    }

    /// Rounding radius.
    #[inline]
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// Moved into world space (normals are rotated, not recomputed, so the
    /// result is exact up to one rounding per component).
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Poly {
        let mut out = *self;
        let n = self.count();
        for (dst, src) in out.verts.iter_mut().zip(&self.verts).take(n) {
            *dst = pos + rot.apply(*src);
        }
        for (dst, src) in out.normals.iter_mut().zip(&self.normals).take(n) {
            *dst = rot.apply(*src);
        }
        out
    }

    /// [`to_world`](Self::to_world) written over `out`, a polygon of the
    /// same vertex count: only the used entries change (the unused ones of
    /// both are zero), so a cache entry is rewritten without copying the
    /// whole polygon twice.
    fn write_world_over(&self, pos: Vect, rot: Rot, out: &mut Poly) {
        let n = self.count();
        out.radius = self.radius;
        // A box (four points: the common polygon) with its sizes known to the compiler.
        if let (Ok(src), Ok(dst)) = (
            <&[Vect; 4]>::try_from(self.verts()),
            <&mut [Vect; 4]>::try_from(out.verts.get_mut(..n).unwrap_or(&mut [])),
        ) {
            place_box_points(src, dst, pos, rot);
            if let (Ok(src), Ok(dst)) = (
                <&[Vect; 4]>::try_from(self.normals()),
                <&mut [Vect; 4]>::try_from(out.normals.get_mut(..n).unwrap_or(&mut [])),
            ) {
                place_box_points(src, dst, Vect::ZERO, rot);
                return;
            }
        }
        for (dst, src) in out.verts.iter_mut().zip(&self.verts).take(n) {
            *dst = pos + rot.apply(*src);
        }
        for (dst, src) in out.normals.iter_mut().zip(&self.normals).take(n) {
            *dst = rot.apply(*src);
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        let mut it = self.verts().iter();
        let first = it.next().copied().unwrap_or(Vect::ZERO);
        it.fold(BB::for_point(first), |bb, v| bb.expand(*v))
            .grow(self.radius)
    }
}

/// `dst[i] = pos + rot.apply(src[i])` for a box's four points, the same
/// bits, rotating only two of them where the box is symmetric about its
/// body's origin (a centred box; every box's normals): where point `i + 2`
/// is exactly `−src[i]`, its rotation is exactly the negated rotation of
/// `src[i]`, since the rounding of `rotate` (nearest, ties away from zero)
/// is symmetric under negation. Only a saturated rotation breaks that
/// symmetry (`Real::MIN` has no negation): it is rotated again.
#[inline(always)]
fn place_box_points(src: &[Vect; 4], dst: &mut [Vect; 4], pos: Vect, rot: Rot) {
    let (src_lo, src_hi) = src.split_at(2);
    let (dst_lo, dst_hi) = dst.split_at_mut(2);
    let opposite = |a: Real, b: Real| a.to_bits().checked_neg() == Some(b.to_bits());
    for (((s0, s1), d0), d1) in src_lo.iter().zip(src_hi).zip(dst_lo).zip(dst_hi) {
        let r0 = rot.apply(*s0);
        let mirrored = opposite(s0.x, s1.x)
            && opposite(s0.y, s1.y)
            && !r0.x.is_saturated()
            && !r0.y.is_saturated();
        let r1 = if mirrored { -r0 } else { rot.apply(*s1) };
        *d0 = pos + r0;
        *d1 = pos + r1;
    }
}

impl Geometry {
    /// The kind of geometry.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Geometry::Circle(_) => ShapeKind::Circle,
            Geometry::Segment(_) => ShapeKind::Segment,
            Geometry::Poly(_) => ShapeKind::Poly,
        }
    }

    /// Moved into world space by a rigid placement.
    pub fn to_world(&self, pos: Vect, rot: Rot) -> Geometry {
        match self {
            Geometry::Circle(c) => Geometry::Circle(c.to_world(pos, rot)),
            Geometry::Segment(s) => Geometry::Segment(s.to_world(pos, rot)),
            Geometry::Poly(p) => Geometry::Poly(p.to_world(pos, rot)),
        }
    }

    /// [`to_world`](Self::to_world) written into `out` (a shape cache's
    /// entry, usually last step's world geometry of the same shape): the
    /// same value, without building a whole `Geometry` and moving it.
    pub(crate) fn write_world_into(&self, pos: Vect, rot: Rot, out: &mut Geometry) {
        match (self, out) {
            (Geometry::Circle(c), Geometry::Circle(o)) => *o = c.to_world(pos, rot),
            (Geometry::Segment(s), Geometry::Segment(o)) => *o = s.to_world(pos, rot),
            (Geometry::Poly(p), Geometry::Poly(o)) if o.count == p.count => {
                p.write_world_over(pos, rot, o);
            }
            (g, out) => *out = g.to_world(pos, rot),
        }
    }

    /// Bounding box.
    pub fn bb(&self) -> BB {
        match self {
            Geometry::Circle(c) => c.bb(),
            Geometry::Segment(s) => s.bb(),
            Geometry::Poly(p) => p.bb(),
        }
    }

    /// Rounding radius (the circle's radius for circles).
    pub fn radius(&self) -> Real {
        match self {
            Geometry::Circle(c) => c.radius,
            Geometry::Segment(s) => s.radius,
            Geometry::Poly(p) => p.radius,
        }
    }

    /// The extent rule every shape obeys (checked by every constructor and
    /// setter of [`Shape`](super::Shape) and by [`Geometry::validate`]): the
    /// local bounding box, rounding radius included, lies inside the `Real`
    /// range and spans *less than 2^31 m* on each axis. Then the difference
    /// of any two points of the shape fits a `Real` (edge vectors, segment
    /// directions, support-point differences), and so does the sum of two
    /// shapes' radii (each below 2^30 m), the contact distance of two
    /// rounded shapes. A circle's radius is thus below 2^30 m, a segment
    /// shorter than 2^31 m − 2r. Errors with
    /// [`ShapeError::OutOfRange`]`("shape extent")`.
    pub fn check_extent(&self) -> Result<(), ShapeError> {
        let fits = match self {
            Geometry::Circle(c) => extent_fits(&[c.offset], c.radius),
            Geometry::Segment(s) => extent_fits(&[s.a, s.b], s.radius),
            Geometry::Poly(p) => extent_fits(p.verts(), p.radius),
        };
        if fits {
            Ok(())
        } else {
            Err(ShapeError::OutOfRange("shape extent"))
        }
    }

    /// Checks stored geometry (snapshot loading, `Space::validate`): radius
    /// ≥ 0; the extent rule ([`Geometry::check_extent`]); a segment's normal is exactly the one [`Segment::new`] computes
    /// from its endpoints; a polygon has 3..=[`MAX_POLY_VERTICES`] vertices,
    /// is strictly convex and counter-clockwise, and equals what
    /// [`Poly::from_ccw`] builds from its vertices (same normals, zeros past
    /// `count`). Returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.radius().is_negative() {
            return Err("negative radius".into());
        }
        self.check_extent().map_err(|e| e.to_string())?;
        match self {
            Geometry::Circle(_) => Ok(()),
            Geometry::Segment(s) => {
                if Segment::new(s.a, s.b, s.radius).normal == s.normal {
                    Ok(())
                } else {
                    Err("segment normal does not match its endpoints".into())
                }
            }
            Geometry::Poly(p) => {
                let n = usize::from(p.count);
                if !(3..=MAX_POLY_VERTICES).contains(&n) {
                    return Err(format!(
                        "polygon has {n} vertices (3..={MAX_POLY_VERTICES})"
                    ));
                }
                match Poly::from_ccw(p.verts(), p.radius) {
                    Ok(rebuilt) if rebuilt == *p => Ok(()),
                    Ok(_) => {
                        Err("polygon normals or unused entries do not match its vertices".into())
                    }
                    Err(e) => Err(format!("polygon: {e}")),
                }
            }
        }
    }
}

/// The extent rule of [`Geometry::check_extent`] for core points grown by
/// `radius`, on exact 128-bit raw values: raw coordinates are within ±2^63
/// and a valid radius in [0, 2^63), so no sum or difference below comes
/// near the `i128` range (the saturating forms never saturate).
fn extent_fits(points: &[Vect], radius: Real) -> bool {
    let r = i128::from(radius.to_bits());
    let (min, max) = (i128::from(i64::MIN), i128::from(i64::MAX));
    let axis = |coord: fn(&Vect) -> Real| {
        let mut it = points.iter().map(|p| i128::from(coord(p).to_bits()));
        let Some(first) = it.next() else {
            return true;
        };
        let (lo, hi) = it.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let (lo, hi) = (lo.saturating_sub(r), hi.saturating_add(r));
        lo >= min && hi <= max && hi.saturating_sub(lo) <= max
    };
    axis(|p| p.x) && axis(|p| p.y)
}

/// The kind (and a polygon's vertex count) in one word, then the fields.
impl Hash for Geometry {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        self.hash_with_tag(h, 0);
    }
}

impl Geometry {
    /// [`Hash`]: one word holding `bits` (below 2^8: a caller's own small
    /// fields, see `Shape`'s hash), the kind and a polygon's vertex count,
    /// then the fields.
    #[inline(always)]
    pub(crate) fn hash_with_tag<H: core::hash::Hasher>(&self, h: &mut H, bits: u64) {
        match self {
            Geometry::Circle(c) => {
                h.write_u64(bits);
                c.hash(h);
            }
            Geometry::Segment(s) => {
                h.write_u64(bits | 1 << 8);
                s.hash(h);
            }
            Geometry::Poly(p) => {
                h.write_u64(bits | 2 << 8 | u64::from(p.count) << 16);
                p.hash_fields(h);
            }
        }
    }
}

/// The vertex count, the radius and every vertex slot (the slots past the
/// count are zero in every valid polygon), mixed; the normals are folded
/// into one word by exclusive or. In every valid polygon (validation
/// rebuilds the polygon from its vertices and compares) the normals follow
/// from the vertices, so they carry no information of their own; a change
/// of any one of their numbers still changes the fold, hence the checksum,
/// at a fraction of the cost of a word each (a polygon is hashed every
/// frame).
impl Hash for Poly {
    #[inline]
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        h.write_u8(self.count);
        self.hash_fields(h);
    }
}

impl Poly {
    /// [`Hash`] but the count: the radius, the vertex slots, the normals'
    /// fold.
    #[inline(always)]
    fn hash_fields<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Poly {
            count: _, // hashed by the caller
            verts,
            normals,
            radius,
        } = self;
        radius.hash(h);
        // Fixed length, no branch: straight-line code.
        for v in verts {
            v.hash(h);
        }
        let fold = normals
            .iter()
            .fold(0, |z, n| z ^ n.x.to_bits() ^ n.y.to_bits());
        h.write_i64(fold);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// A box symmetric about its origin, placed by mirroring two of its
        /// rotated points (and normals), gives `to_world`'s bits at any size,
        /// angle and position, the saturating edges of `Real` included; so
        /// does a symmetric hexagon, which takes the general path.
        #[test]
        fn mirrored_placement_is_to_world(
            (hx, hy, k) in (1i64..(1 << 62), 1i64..(1 << 62), 0i64..(1 << 40)),
            (c, s) in (proptest::num::i64::ANY, proptest::num::i64::ANY),
            (px, py) in (proptest::num::i64::ANY, proptest::num::i64::ANY),
            hexagon in proptest::bool::ANY,
        ) {
            let (x, y) = (Real::from_bits(hx), Real::from_bits(hy));
            let w = Real::from_bits(k);
            let v = |x: Real, y: Real| Vect::new(x, y);
            let points = if hexagon {
                vec![v(x, Real::ZERO), v(w, y), v(-w, y), v(-x, Real::ZERO), v(-w, -y), v(w, -y)]
            } else {
                vec![v(x, y), v(-x, y), v(-x, -y), v(x, -y)]
            };
            // Unchecked, as a snapshot could hold it: any extent, normals from the edges.
            let poly = Poly::from_ccw_unchecked(&points, Real::ZERO);
            let rot = crate::math::Rot { c: Real::from_bits(c), s: Real::from_bits(s) };
            let pos = Vect::new(Real::from_bits(px), Real::from_bits(py));
            let mut out = poly;
            poly.write_world_over(pos, rot, &mut out);
            proptest::prop_assert_eq!(out, poly.to_world(pos, rot));
            // A unit rotation and a near position: no saturation anywhere.
            let rot = crate::math::Rot::from_angle(Real::from_bits(c >> 30));
            let pos = Vect::new(Real::from_bits(px >> 20), Real::from_bits(py >> 20));
            poly.write_world_over(pos, rot, &mut out);
            proptest::prop_assert_eq!(out, poly.to_world(pos, rot));
        }
    }

    /// Writing a world geometry over a cache entry gives exactly the
    /// geometry `to_world` builds, whatever the entry held before: another
    /// kind, a polygon of another vertex count, another placement.
    #[test]
    fn write_world_into_is_to_world_over_any_prior_entry() {
        let r = |n: i64| Real::from_bits(n << 28);
        let v = |x: i64, y: i64| Vect::new(r(x), r(y));
        let shapes = [
            Geometry::Circle(Circle::new(r(5), Vect::ZERO)),
            Geometry::Circle(Circle::new(r(5), v(1, -2))),
            Geometry::Segment(
                Segment::new(v(0, 0), v(9, 3), r(1)).with_neighbors(v(-4, 0), v(12, 3)),
            ),
            Geometry::Poly(Poly::new_box(r(16), r(8), r(1)).unwrap()),
            Geometry::Poly(
                Poly::from_ccw(&[v(0, 0), v(4, 0), v(5, 3), v(0, 2)], Real::ZERO).unwrap(),
            ),
            Geometry::Poly(Poly::from_ccw(&[v(0, 0), v(4, 0), v(1, 3)], r(2)).unwrap()),
        ];
        let placements = [
            (v(3, -7), crate::math::Rot::IDENTITY),
            (
                v(-100, 40),
                crate::math::Rot::from_angle(Real::ratio(7, 10)),
            ),
            (
                Vect::new(Real::MAX, Real::MIN),
                crate::math::Rot::from_angle(Real::PI),
            ),
        ];
        for g in &shapes {
            for &(pos, rot) in &placements {
                let want = g.to_world(pos, rot);
                for prior in &shapes {
                    for &(p2, r2) in &placements {
                        let mut entry = prior.to_world(p2, r2);
                        g.write_world_into(pos, rot, &mut entry);
                        assert_eq!(entry, want, "{g:?} over {prior:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn matches_compact_agrees_with_from_compact() {
        let r = |n: i64| Real::from_bits(n << 28);
        let v = |x: i64, y: i64| Vect::new(r(x), r(y));
        let shapes = [
            Geometry::Circle(Circle::new(r(5), v(1, -2))),
            Geometry::Segment(
                Segment::new(v(0, 0), v(9, 3), r(1)).with_neighbors(v(-4, 0), v(12, 3)),
            ),
            Geometry::Poly(Poly::new_box(r(16), r(8), r(1)).unwrap()),
            Geometry::Poly(
                Poly::from_bb(crate::math::BB::new(r(1), r(2), r(7), r(5)), Real::ZERO).unwrap(),
            ),
            Geometry::Poly(
                Poly::from_ccw(&[v(0, 0), v(4, 0), v(5, 3), v(0, 2)], Real::ZERO).unwrap(),
            ),
        ];
        for g in &shapes {
            let (form, words, n) = g.compact_form();
            let built = Geometry::from_compact(form, &words);
            assert_eq!(built.as_ref(), Ok(g));
            match g.matches_compact(form, &words) {
                Some(same) => assert!(same, "{g:?}"),
                None => assert!(matches!(g, Geometry::Poly(_))),
            }
            // Every word changed in turn: a match only if the rebuilt
            // geometry is this one.
            for i in 0..n {
                for delta in [1i64, -1 << 30] {
                    let mut w = words;
                    w[i] = Real::from_bits(w[i].to_bits().wrapping_add(delta));
                    if let Some(same) = g.matches_compact(form, &w) {
                        let rebuilt = Geometry::from_compact(form, &w);
                        assert_eq!(same, rebuilt.as_ref() == Ok(g), "{g:?} word {i}");
                    }
                }
            }
            // Another geometry's form never matches.
            for other in &shapes {
                let (f2, w2, _) = other.compact_form();
                if other != g {
                    assert_ne!(g.matches_compact(f2, &w2), Some(true), "{g:?} vs {other:?}");
                }
            }
        }
        // A centred rectangle's words in the general rectangle form: not
        // canonical, so no match (and no geometry).
        let centred = &shapes[2];
        let Geometry::Poly(p) = centred else {
            unreachable!()
        };
        let [x0, y0, x1, y1] = [
            p.verts()[2].x,
            p.verts()[0].y,
            p.verts()[0].x,
            p.verts()[1].y,
        ];
        let mut w = [Real::ZERO; GEOM_MAX_WORDS];
        w[..5].copy_from_slice(&[x0, y0, x1, y1, p.radius]);
        let rect_form = 2 | 4 << GEOM_POLY_COUNT_SHIFT | FORM_RECT << GEOM_FORM_SHIFT;
        assert_eq!(centred.matches_compact(rect_form, &w), Some(false));
        assert!(Geometry::from_compact(rect_form, &w).is_err());
    }

    #[test]
    fn edge_normal_is_normalize_bit_for_bit() {
        let raws = [
            0,
            1,
            -1,
            2,
            3,
            1 << 20,
            (1 << 32) + 7,
            1 << 32,
            -(1 << 40) - 3,
            i64::MAX,
            i64::MAX - 1,
            i64::MIN,
            i64::MIN + 1,
            0x5555_5555_5555_5555,
        ];
        for raw in raws {
            let r = Real::from_bits(raw);
            for d in [Vect::new(r, Real::ZERO), Vect::new(Real::ZERO, r)] {
                assert_eq!(edge_normal(d), d.normalize(), "{raw}");
            }
            let skew = Vect::new(r, Real::from_bits(3));
            assert_eq!(edge_normal(skew), skew.normalize(), "{raw}");
        }
    }
}
