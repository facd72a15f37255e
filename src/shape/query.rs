//! Geometry queries on one world-space [`Geometry`]: the nearest surface
//! point with a signed distance ([`point_query`], Chipmunk
//! `cpShapePointQuery`), and the first hit of a ray or swept circle
//! ([`segment_query`], Chipmunk `cpShapeSegmentQuery`). The space-level
//! queries (`space::query`) run these on each candidate shape.
//!
//! # How they are computed, and why
//! Every product is taken on a *relative* vector (query point minus a vertex,
//! centre or ray start), so results do not depend on where the scene sits and
//! products stay small. Loops over polygon edges use only dot products and
//! exact 128-bit comparisons; the one square root and the one or two
//! divisions of a query happen once, after the nearest feature is known:
//!
//! * **Point query.** A circle is its centre plus a radius. A segment
//!   (capsule) projects the point on its unit tangent (the stored normal
//!   turned 90°): inside the span the distance is the signed separation from
//!   the line, beyond it the distance to the endpoint. A convex polygon
//!   computes each edge's separation `n·(p − v)`: if none is positive the
//!   point is inside and the nearest boundary point is its projection on the
//!   least-deep edge (for a convex polygon the nearest edge *line* is also the
//!   nearest edge); otherwise the candidates are the edges that face the
//!   point, each clamped to its span, compared by exact squared distance.
//!   The rounding radius is subtracted at the end.
//! * **Segment query.** A shape with rounding radius `r` swept by a circle of
//!   radius `r₂` is hit where the centre of the moving circle enters the
//!   shape's core grown by `r + r₂`: the core's planes pushed out by
//!   `r + r₂`, with the corners rounded. The ray is clipped against the pushed
//!   planes (a polygon, or a segment as a two-sided "polygon") keeping the
//!   entry and exit times as exact fractions compared by cross
//!   multiplication, so no division happens per edge. If the entry point lies
//!   within its edge's span it is the hit; otherwise it lies in a corner
//!   region, where the only part of the grown shape is the circle around
//!   that corner vertex (a line leaving a convex set never re-enters it), so
//!   one ray–circle test decides. A segment's two faces are measured from
//!   one point with one rounded offset, so its slab is never inverted.
//! * **Misses are judged exactly.** The clip uses rounded unit normals, so
//!   for a shape with no thickness (a sharp segment) or a ray through a
//!   sharp corner, rounding alone could turn a crossing into a miss. A miss
//!   of the clip is clipped again with the reach grown by a bound on its
//!   rounding (2^-27 of the query's distances plus 64 ulp): still a miss
//!   is a miss for certain; a hit then is judged by `reach`, which decides
//!   in integers (signs of dot and cross products on 128 and 256 bits)
//!   whether the segment comes within the reach of the core, and reported
//!   if it does. So a ray that crosses or touches a shape is always a hit,
//!   and a hit is never further than that margin from the surface.
//!
//! # Start inside
//! When the query starts within reach (the point query at `a` gives a
//! distance ≤ `radius`, which includes starting inside the shape), the hit is
//! reported at `alpha = 0`, like Chipmunk, with `point` = the surface point
//! nearest to `a` and `normal` = the outward surface normal there (the point
//! query's gradient). Chipmunk keeps `point = b` and uses
//! `normalize(a − nearest)`, which points *inwards* for a start inside and is
//! zero for a start on the surface; we give the outward normal in every case,
//! so `normal` always faces away from the shape.
//!
//! # Precision
//! With coordinates within ±64 (the property tests' range; errors scale with
//! distances, not with the position in the world): a circle's or an
//! axis-aligned box's distance is within 2 ulp of the exact value (exact
//! differences, floor square root); a rotated polygon's is within
//! `8 + 2·(distance from its centre + half-extents)` ulp, from the rounding
//! of its rotated normals. A segment-query hit point lies within
//! `64 + 8·|b − a|` ulp of the surface (the hit time is rounded to 2^-32).
//! Translating a shape and its query by any vector gives bit-identical,
//! shifted answers. `tests/geometry/queries.rs` checks all of this against `f64`
//! oracles.
use serde::{Deserialize, Serialize};

use super::geometry::{next_index, Circle, Geometry, Poly, Segment};
use super::hull::orientation;
use super::reach;
use crate::math::exact::{raw_sq, wide_mul};
use crate::math::{Real, Vect, BB};

/// The result of a point query (Chipmunk `cpPointQueryInfo`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PointQueryInfo {
    /// The nearest point on the shape's surface (rounding radius included).
    pub point: Vect,
    /// Signed distance from the query point to the surface: negative inside.
    pub distance: Real,
    /// Unit gradient of the signed distance: the outward surface normal at
    /// `point`. At a circle's exact centre, where every direction is nearest,
    /// it is `+y` (Chipmunk's choice); on a segment's core line it is the
    /// segment's normal.
    pub gradient: Vect,
}

/// The result of a segment query (Chipmunk `cpSegmentQueryInfo`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SegmentQueryInfo {
    /// The point of the shape's surface that is hit.
    pub point: Vect,
    /// Outward unit surface normal at the hit.
    pub normal: Vect,
    /// Fraction of `a → b` travelled at the hit, in `[0, 1]`.
    pub alpha: Real,
}

/// Nearest surface point, signed distance and gradient of world-space
/// geometry `g` for the point `p` (Chipmunk `cpShapePointQuery`).
pub fn point_query(g: &Geometry, p: Vect) -> PointQueryInfo {
    match g {
        Geometry::Circle(c) => circle_point_query(c, p),
        Geometry::Segment(s) => segment_point_query(s, p),
        Geometry::Poly(poly) => poly_point_query(poly, p),
    }
}

/// The first hit of world-space geometry `g` by the segment `a → b` swept by
/// a circle of `radius` (a ray for 0; a negative radius counts as 0), or
/// `None` (Chipmunk `cpShapeSegmentQuery`). A start within reach hits at
/// `alpha = 0` (see the module docs). `a == b` outside reach never hits.
pub fn segment_query(g: &Geometry, a: Vect, b: Vect, radius: Real) -> Option<SegmentQueryInfo> {
    Target::Geometry(g).segment_query(a, b, radius)
}

/// A convex outline with more vertices than a [`Poly`] holds (a Minkowski
/// difference of two polygons, up to twice [`MAX_POLY_VERTICES`]): the
/// shape casts of `collision::cast` ray-cast it with [`convex_segment_query`].
///
/// [`MAX_POLY_VERTICES`]: super::MAX_POLY_VERTICES
#[derive(Clone, Copy, Debug)]
pub(crate) struct Convex<'a> {
    /// At least 3 vertices, strictly convex and counter-clockwise.
    pub(crate) verts: &'a [Vect],
    /// `normals[i]`: the outward unit normal of edge `i → i+1`.
    pub(crate) normals: &'a [Vect],
    /// Rounding radius, ≥ 0.
    pub(crate) radius: Real,
}

/// [`segment_query`] on a [`Convex`] outline: the same computation a
/// [`Poly`] with these vertices, normals and radius gets, bit for bit.
pub(crate) fn convex_segment_query(
    c: Convex<'_>,
    a: Vect,
    b: Vect,
    radius: Real,
) -> Option<SegmentQueryInfo> {
    Target::Convex(c).segment_query(a, b, radius)
}

/// What a segment query runs on: a shape's geometry, or a convex outline
/// of the casts.
#[derive(Clone, Copy)]
enum Target<'a> {
    Geometry(&'a Geometry),
    Convex(Convex<'a>),
}

impl Target<'_> {
    fn point_query(self, p: Vect) -> PointQueryInfo {
        match self {
            Target::Geometry(g) => point_query(g, p),
            Target::Convex(c) => outline_point_query(c.verts, c.normals, c.radius, p, true),
        }
    }

    fn first_hit(self, sweep: &Sweep) -> Option<SegmentQueryInfo> {
        match self {
            Target::Geometry(g) => sweep.first_hit(g),
            Target::Convex(c) => {
                sweep.rounded_convex(c.verts, c.normals, c.radius, Outline::Closed)
            }
        }
    }

    fn bb(self) -> BB {
        match self {
            Target::Geometry(g) => g.bb(),
            Target::Convex(c) => outline_bb(c.verts, c.radius),
        }
    }

    fn reaches(self, a: Vect, b: Vect, radius: Real) -> bool {
        match self {
            Target::Geometry(g) => reach::segment_reaches(g, a, b, radius),
            Target::Convex(c) => reach::outline_reaches(c.verts, c.radius, a, b, radius),
        }
    }

    /// The segment query (see [`segment_query`]).
    fn segment_query(self, a: Vect, b: Vect, radius: Real) -> Option<SegmentQueryInfo> {
        let radius = radius.max(Real::ZERO);
        let start = self.point_query(a);
        if start.distance <= radius {
            return Some(start_hit(start));
        }
        let sweep = Sweep {
            a,
            d: b - a,
            radius,
            margin: Real::ZERO,
        };
        if let Some(hit) = self.first_hit(&sweep) {
            return Some(hit);
        }
        // The clip's unit normals are rounded: a ray through a shape with no
        // thickness, or grazing a corner, can be clipped away by that rounding
        // alone. Clipped again with the reach grown by a bound on the rounding,
        // a ray that misses still is a miss for certain (the usual case, at the
        // cost of a second clip); one that now hits is judged exactly.
        let margin = rounding_margin(&self.bb(), a, sweep.d);
        let grown = if start.distance <= radius + margin {
            start_hit(start)
        } else {
            self.first_hit(&Sweep { margin, ..sweep })?
        };
        self.reaches(a, b, radius).then_some(grown)
    }
}

/// The bounding box of an outline's vertices grown by `radius` (a
/// [`Poly`]'s [`bb`](Poly::bb), bit for bit).
fn outline_bb(verts: &[Vect], radius: Real) -> BB {
    let mut it = verts.iter();
    let first = it.next().copied().unwrap_or(Vect::ZERO);
    it.fold(BB::for_point(first), |bb, v| bb.expand(*v))
        .grow(radius)
}

/// The hit of a query that starts within reach: at `alpha = 0`, on the
/// nearest surface point, facing out.
fn start_hit(start: PointQueryInfo) -> SegmentQueryInfo {
    SegmentQueryInfo {
        point: start.point,
        normal: start.gradient,
        alpha: Real::ZERO,
    }
}

/// A bound on how far the rounding of the clip (unit normals within a few
/// ulp, one rounding per product) can move a plane of `g` as seen from a
/// query starting at `a` and moving by `d`. The clip's errors come from
/// unit vectors within 2 ulp per component, each applied once to a
/// distance of the query (start to vertex, motion, hit to vertex): below
/// 2^-29 of their sum. The margin is 2^-27 of a sum that exceeds it (the
/// start's distances to the box's sides, the motion's components), plus 64
/// ulp; a hit found with it lies within that margin of the surface. `bb`
/// is the shape's bounding box.
fn rounding_margin(bb: &BB, a: Vect, d: Vect) -> Real {
    let extent = (a.x - bb.l).abs()
        + (a.x - bb.r).abs()
        + (a.y - bb.b).abs()
        + (a.y - bb.t).abs()
        + d.x.abs()
        + d.y.abs();
    Real::from_bits(extent.to_bits() >> 27) + Real::from_bits(64)
}

/// Exact `|v|²` in units of 2^-64 (each square ≤ 2^126, the sum ≤ 2^127:
/// never overflows).
fn length_sq_wide(v: Vect) -> u128 {
    // (Never saturates, see above.)
    raw_sq(v.x).saturating_add(raw_sq(v.y))
}

/// Exact `s²` in units of 2^-64.
fn square_wide(s: Real) -> u128 {
    raw_sq(s)
}

/// Unit direction and distance from `from` to `p`; `fallback` (and 0) when
/// they coincide.
fn direction_from(from: Vect, p: Vect, fallback: Vect) -> (Vect, Real) {
    let (dir, len) = (p - from).normalize_with_length();
    if dir == Vect::ZERO {
        (fallback, Real::ZERO)
    } else {
        (dir, len)
    }
}

/// Applies the rounding radius to a result on the core (the bare circle
/// centre, segment or polygon): the surface is `radius` further along the
/// gradient.
fn rounded(closest: Vect, core_distance: Real, gradient: Vect, radius: Real) -> PointQueryInfo {
    PointQueryInfo {
        point: closest + gradient * radius,
        distance: core_distance - radius,
        gradient,
    }
}

fn circle_point_query(c: &Circle, p: Vect) -> PointQueryInfo {
    let (gradient, d) = direction_from(c.offset, p, Vect::Y);
    rounded(c.offset, d, gradient, c.radius)
}

fn segment_point_query(s: &Segment, p: Vect) -> PointQueryInfo {
    let n = s.normal;
    // perp(rperp(b − a)/|b − a|) is the unit tangent a → b (zero if a == b).
    let tangent = n.perp();
    let rel = p - s.a;
    let along = rel.dot(tangent);
    let span = (s.b - s.a).dot(tangent);
    let fallback = if n == Vect::ZERO { Vect::Y } else { n };
    if along <= Real::ZERO {
        let (gradient, d) = direction_from(s.a, p, fallback);
        rounded(s.a, d, gradient, s.radius)
    } else if along >= span {
        let (gradient, d) = direction_from(s.b, p, fallback);
        rounded(s.b, d, gradient, s.radius)
    } else {
        // Inside the span: the separation from the line is the distance.
        let h = rel.dot(n);
        let gradient = if h.is_negative() { -n } else { n };
        rounded(p - n * h, h.abs(), gradient, s.radius)
    }
}

/// The nearest core feature of a polygon to an outside point.
#[derive(Clone, Copy)]
enum Feature {
    /// The inside of an edge's span: the nearest point is the projection.
    Edge { normal: Vect, separation: Real },
    /// A vertex; `normal` is the facing edge's (fallback gradient only).
    Vertex { at: Vect, normal: Vect },
}

fn poly_point_query(poly: &Poly, p: Vect) -> PointQueryInfo {
    outline_point_query(poly.verts(), poly.normals(), poly.radius(), p, false)
}

/// The point query of a convex outline: counter-clockwise `verts`, their
/// edges' outward unit `normals`, rounding radius `r`.
///
/// With `exact_sides`, which edges face the point is decided by exact
/// orientation, not by the rounded unit normals: a cast's outline can be a
/// sliver (two nearly parallel segments) whose short edges' normals round
/// to a long edge's, and the rounded test would put a point on the long
/// edge outside a short one and measure it from a far vertex.
fn outline_point_query(
    verts: &[Vect],
    normals: &[Vect],
    r: Real,
    p: Vect,
    exact_sides: bool,
) -> PointQueryInfo {
    let n = verts.len();
    // Least-deep edge (largest separation), for a point inside the core.
    let mut shallowest: Option<(Real, Vect)> = None;
    // Nearest facing feature by exact squared distance, for a point outside.
    let mut nearest: Option<(u128, Feature)> = None;
    for (i, (&v0, &normal)) in verts.iter().zip(normals).enumerate() {
        let rel = p - v0;
        let separation = rel.dot(normal);
        if shallowest.is_none_or(|(best, _)| separation > best) {
            shallowest = Some((separation, normal));
        }
        let v1 = verts.get(next_index(i, n)).copied().unwrap_or(v0);
        let facing = if exact_sides {
            orientation(v0, v1, p) < 0
        } else {
            separation.is_positive()
        };
        if !facing {
            continue;
        }
        // The edge faces the point: clamp to its span (tangent = perp(normal)).
        let tangent = normal.perp();
        let along = rel.dot(tangent);
        let candidate = if along <= Real::ZERO {
            (length_sq_wide(rel), Feature::Vertex { at: v0, normal })
        } else if along >= (v1 - v0).dot(tangent) {
            (length_sq_wide(p - v1), Feature::Vertex { at: v1, normal })
        } else {
            (
                square_wide(separation),
                Feature::Edge { normal, separation },
            )
        };
        // Strict: ties keep the lowest edge index.
        if nearest.is_none_or(|(best, _)| candidate.0 < best) {
            nearest = Some(candidate);
        }
    }
    match (nearest, shallowest) {
        (Some((_, Feature::Vertex { at, normal })), _) => {
            let (gradient, d) = direction_from(at, p, normal);
            rounded(at, d, gradient, r)
        }
        (Some((_, Feature::Edge { normal, separation })), _)
        | (None, Some((separation, normal))) => {
            rounded(p - normal * separation, separation, normal, r)
        }
        // No vertices: unreachable through the validated constructors; treat
        // the polygon as the point `vert(0)` so the answer is still defined.
        (None, None) => {
            let at = verts.first().copied().unwrap_or(Vect::ZERO);
            let (gradient, d) = direction_from(at, p, Vect::Y);
            rounded(at, d, gradient, r)
        }
    }
}

/// Whether the outline's edges close (a polygon) or form the two sides of a
/// segment, whose "polygon" is an infinite slab.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Outline {
    Closed,
    Open,
}

/// A time `num / den` along the sweep, `den > 0`, kept unrounded so that
/// comparisons are exact.
#[derive(Clone, Copy)]
struct Fraction {
    num: Real,
    den: Real,
}

impl Fraction {
    const ZERO: Fraction = Fraction {
        num: Real::ZERO,
        den: Real::ONE,
    };
    const ONE: Fraction = Fraction {
        num: Real::ONE,
        den: Real::ONE,
    };

    /// `self > other`, by cross multiplication on 128 bits (each product of
    /// two raw `i64` values is below 2^126: exact).
    fn gt(self, other: Fraction) -> bool {
        let lhs = wide_mul(self.num.to_bits(), other.den.to_bits());
        let rhs = wide_mul(other.num.to_bits(), self.den.to_bits());
        lhs > rhs
    }

    /// As a `Real` in `[0, 1]`.
    fn to_alpha(self) -> Real {
        (self.num / self.den).clamp(Real::ZERO, Real::ONE)
    }

    /// `v · num / den` with one rounding per component.
    fn scale(self, v: Vect) -> Vect {
        Vect::new(
            v.x.mul_div(self.num, self.den),
            v.y.mul_div(self.num, self.den),
        )
    }
}

/// A circle of `radius` swept from `a` by `d` (a ray for radius 0).
#[derive(Clone, Copy)]
struct Sweep {
    a: Vect,
    d: Vect,
    radius: Real,
    /// Added to the reach only (not to where the hit point is put): the
    /// rounding bound of the exact judge's second clip, else zero.
    margin: Real,
}

impl Sweep {
    /// The first hit of `g`, for a start out of reach.
    fn first_hit(&self, g: &Geometry) -> Option<SegmentQueryInfo> {
        match g {
            Geometry::Circle(c) => self.circle(c.offset, c.radius),
            Geometry::Segment(s) => {
                self.rounded_convex(&[s.a, s.b], &[s.normal, -s.normal], s.radius, Outline::Open)
            }
            Geometry::Poly(p) => {
                self.rounded_convex(p.verts(), p.normals(), p.radius(), Outline::Closed)
            }
        }
    }

    /// The sweep against a circle of `core_radius` around `centre`.
    ///
    /// With `u` the unit direction and `f = a − centre`, the moving centre
    /// `a + s·u` is at distance `reach = core_radius + radius` from `centre`
    /// when `s = −f·u ± √(reach² − h²)`, where `h = |f × u|` is the distance
    /// of `centre` from the line; the entry is the smaller root, and
    /// `reach² − h²` is formed as `(reach − h)(reach + h)` to stay exact-ish
    /// near grazing and small for large values (exact, then rooted once).
    fn circle(&self, centre: Vect, core_radius: Real) -> Option<SegmentQueryInfo> {
        let reach = core_radius + self.radius + self.margin;
        let (u, len) = self.d.normalize_with_length();
        if len.is_zero() {
            return None;
        }
        let f = self.a - centre;
        let off = f.cross(u).abs();
        if off > reach {
            return None;
        }
        // The exact product, rooted on 128 bits: a reach of a few ulp (the
        // exact judge's margin) keeps its half chord instead of squaring to
        // nothing.
        let product = wide_mul((reach - off).to_bits(), (reach + off).to_bits());
        let root = product.unsigned_abs().isqrt();
        let half_chord = Real::from_bits(i64::try_from(root).unwrap_or(i64::MAX));
        let s = -f.dot(u) - half_chord;
        // With a margin, rounding may put an entry at the very start or end
        // a few ulp outside the motion: clamped (the margin covers it).
        let slack = self.margin;
        if s < -slack || s > len + slack {
            return None;
        }
        let s = s.clamp(Real::ZERO, len);
        let normal = (f + u * s).normalize();
        // A zero-reach graze of the exact centre: face the ray.
        let normal = if normal == Vect::ZERO { -u } else { normal };
        Some(SegmentQueryInfo {
            point: centre + normal * core_radius,
            normal,
            alpha: (s / len).clamp(Real::ZERO, Real::ONE),
        })
    }

    /// The sweep against a convex outline (`verts` counter-clockwise,
    /// `normals[i]` the outward unit normal of edge `i → i+1`) with rounding
    /// `core_radius`. The start must be out of reach (checked by the caller).
    fn rounded_convex(
        &self,
        verts: &[Vect],
        normals: &[Vect],
        core_radius: Real,
        outline: Outline,
    ) -> Option<SegmentQueryInfo> {
        let reach = core_radius + self.radius + self.margin;
        let n = verts.len();
        // A segment's two sides are one line: both planes are measured from
        // its first endpoint with one rounded offset, so the slab they bound
        // is never inverted by rounding (empty for a sharp segment).
        let open_offset = (outline == Outline::Open)
            .then(|| verts.first().zip(normals.first()))
            .flatten()
            .map(|(&v, &normal)| (self.a - v).dot(normal));
        // Clip t ∈ [0, 1] against each pushed-out plane g(t) = num + t·den ≤ 0.
        let mut lower = Fraction::ZERO;
        let mut upper = Fraction::ONE;
        let mut entry: Option<usize> = None;
        for (i, (&v, &normal)) in verts.iter().zip(normals).enumerate() {
            let offset = match open_offset {
                Some(h) if i == 0 => h,
                Some(h) => -h,
                None => (self.a - v).dot(normal),
            };
            let num = offset - reach;
            let den = self.d.dot(normal);
            if den.is_negative() {
                let t = Fraction { num, den: -den };
                // Strict: ties keep the lowest edge index.
                if t.gt(lower) {
                    lower = t;
                    entry = Some(i);
                }
            } else if den.is_positive() {
                let t = Fraction { num: -num, den };
                if upper.gt(t) {
                    upper = t;
                }
            } else if num.is_positive() {
                // Parallel to the plane and outside it.
                return None;
            }
        }
        if lower.gt(upper) {
            return None;
        }
        let Some(i) = entry else {
            // The start is inside every pushed plane but out of reach: it is in
            // a corner region, whose only part of the shape is the circle
            // around the nearest vertex (first one on a tie).
            let corner = verts
                .iter()
                .copied()
                .min_by_key(|v| length_sq_wide(self.a - *v))?;
            return if reach.is_zero() {
                None
            } else {
                self.circle(corner, core_radius)
            };
        };
        let v0 = verts.get(i).copied().unwrap_or(Vect::ZERO);
        let v1 = verts.get(next_index(i, n)).copied().unwrap_or(v0);
        let normal = normals.get(i).copied().unwrap_or(Vect::ZERO);
        let centre = self.a + lower.scale(self.d);
        let tangent = normal.perp();
        let along = (centre - v0).dot(tangent);
        let within = !along.is_negative() && along <= (v1 - v0).dot(tangent);
        if within {
            return Some(SegmentQueryInfo {
                point: centre - normal * self.radius,
                normal,
                alpha: lower.to_alpha(),
            });
        }
        // Another edge on the same plane (two edges whose rounded normals
        // and offsets agree, as a sliver's short edge and its long
        // neighbour can) may hold the entry point: the tie went to the
        // lower index, not to the edge the ray enters through.
        let mut corner = if along.is_negative() { v0 } else { v1 };
        if outline == Outline::Closed {
            if let Some(hit) = self.coplanar_entry(verts, normals, reach, lower, i, centre) {
                return Some(hit);
            }
            // Past the entry edge's span the ray meets a rounded corner: the
            // one nearest the entry point. Nearly parallel edges (a sliver,
            // a tie between coplanar edges) can make the entry edge's own
            // end the wrong one, so every vertex is considered.
            if let Some(nearest) = verts
                .iter()
                .copied()
                .min_by_key(|v| length_sq_wide(centre - *v))
            {
                corner = nearest;
            }
        }
        // A sharp polygon's entry point is always on the entry edge: outside
        // the span it is off by rounding only (amplified at a sharp corner,
        // where two nearly parallel planes meet), so it is a hit at the end
        // of the edge it passed.
        if reach.is_zero() && outline == Outline::Closed {
            return Some(SegmentQueryInfo {
                point: corner,
                normal,
                alpha: lower.to_alpha(),
            });
        }
        self.circle(corner, core_radius)
    }

    /// The hit on another edge than `skip` that holds the entry point
    /// `centre` in its span and whose pushed-out plane passes through it
    /// up to the rounding of the unit normals (the nearest such plane):
    /// with nearly parallel edges (a sliver, an edge one ulp off another's
    /// direction) the rounded normals can make the wrong one of them the
    /// last plane entered.
    fn coplanar_entry(
        &self,
        verts: &[Vect],
        normals: &[Vect],
        reach: Real,
        lower: Fraction,
        skip: usize,
        centre: Vect,
    ) -> Option<SegmentQueryInfo> {
        let n = verts.len();
        let tolerance = rounding_margin(&outline_bb(verts, Real::ZERO), self.a, self.d);
        let mut best: Option<(Real, Vect)> = None;
        for (j, (&w0, &normal)) in verts.iter().zip(normals).enumerate() {
            if j == skip || !self.d.dot(normal).is_negative() {
                continue;
            }
            let gap = (centre - w0).dot(normal) - reach;
            let w1 = verts.get(next_index(j, n)).copied().unwrap_or(w0);
            let tangent = normal.perp();
            let along = (centre - w0).dot(tangent);
            let within = !along.is_negative() && along <= (w1 - w0).dot(tangent);
            if within && gap >= -tolerance && best.is_none_or(|(g, _)| gap > g) {
                best = Some((gap, normal));
            }
        }
        best.map(|(_, normal)| SegmentQueryInfo {
            point: centre - normal * self.radius,
            normal,
            alpha: lower.to_alpha(),
        })
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;
    use crate::math::BB;
    use crate::real;

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    fn vf(x: f64, y: f64) -> Vect {
        Vect::from_f64(x, y).unwrap_or(Vect::ZERO)
    }

    fn rf(x: f64) -> Real {
        Real::from_f64(x).unwrap_or(Real::ZERO)
    }

    /// True if `a` and `b` differ by at most `ulps` units of 2^-32.
    fn near(a: Real, b: Real, ulps: i64) -> bool {
        (a.to_bits() - b.to_bits()).abs() <= ulps
    }

    fn near_v(a: Vect, b: Vect, ulps: i64) -> bool {
        near(a.x, b.x, ulps) && near(a.y, b.y, ulps)
    }

    fn near_f(a: Real, b: f64, tol: f64) -> bool {
        (a.to_f64() - b).abs() <= tol
    }

    fn pq(point: Vect, distance: Real, gradient: Vect) -> PointQueryInfo {
        PointQueryInfo {
            point,
            distance,
            gradient,
        }
    }

    fn sq(point: Vect, normal: Vect, alpha: Real) -> SegmentQueryInfo {
        SegmentQueryInfo {
            point,
            normal,
            alpha,
        }
    }

    fn circle(r: Real, c: Vect) -> Geometry {
        Geometry::Circle(Circle::new(r, c))
    }

    fn capsule(a: Vect, b: Vect, r: Real) -> Geometry {
        Geometry::Segment(Segment::new(a, b, r))
    }

    /// A `w × h` box centred on the origin with rounding `r`.
    fn boxed(w: i32, h: i32, r: Real) -> Geometry {
        let (hw, hh) = (
            Real::from_int(w) * Real::HALF,
            Real::from_int(h) * Real::HALF,
        );
        match Poly::from_bb(BB::new(-hw, -hh, hw, hh), r) {
            Ok(p) => Geometry::Poly(p),
            Err(e) => panic!("box: {e}"),
        }
    }

    #[test]
    fn circle_point_outside_inside_and_at_centre() {
        let g = circle(Real::TWO, v(1, 1));
        let out = point_query(&g, v(4, 5));
        assert_eq!(out.distance, Real::from_int(3));
        assert!(near_v(out.gradient, vf(0.6, 0.8), 1), "{out:?}");
        assert!(near_v(out.point, vf(2.2, 2.6), 2), "{out:?}");
        let inside = point_query(&g, v(1, 2));
        assert_eq!(inside, pq(v(1, 3), -Real::ONE, Vect::Y));
        let centre = point_query(&g, v(1, 1));
        assert_eq!(centre, pq(v(1, 3), -Real::TWO, Vect::Y));
    }

    #[test]
    fn capsule_point_beside_inside_on_core_and_past_end() {
        // Normal rperp((4, 0)) = (0, −1).
        let g = capsule(v(0, 0), v(4, 0), Real::ONE);
        let above = point_query(&g, v(2, 3));
        assert_eq!(above, pq(v(2, 1), Real::TWO, Vect::Y));
        let inside = point_query(&g, Vect::new(Real::TWO, -Real::HALF));
        assert_eq!(inside, pq(v(2, -1), -Real::HALF, v(0, -1)));
        let core = point_query(&g, v(2, 0));
        assert_eq!(core, pq(v(2, -1), -Real::ONE, v(0, -1)));
        let past = point_query(&g, v(7, 4));
        assert_eq!(past.distance, Real::from_int(4));
        assert!(near_v(past.gradient, vf(0.6, 0.8), 1), "{past:?}");
        assert!(near_v(past.point, vf(4.6, 0.8), 2), "{past:?}");
    }

    #[test]
    fn box_point_beside_face_at_corner_and_inside() {
        let g = boxed(4, 2, Real::ZERO);
        let face = point_query(&g, v(5, 0));
        assert_eq!(face, pq(v(2, 0), Real::from_int(3), Vect::X));
        let corner = point_query(&g, v(5, 5));
        assert_eq!(corner.distance, Real::from_int(5));
        assert_eq!(corner.point, v(2, 1));
        assert!(near_v(corner.gradient, vf(0.6, 0.8), 1), "{corner:?}");
        // Nearest edge is the top one (0.5 away), not the sides (2 away).
        let inside = point_query(&g, Vect::new(Real::ZERO, Real::HALF));
        assert_eq!(inside, pq(v(0, 1), -Real::HALF, Vect::Y));
        // On the boundary: distance 0, gradient the face normal.
        let on = point_query(&g, v(2, 0));
        assert_eq!(on, pq(v(2, 0), Real::ZERO, Vect::X));
    }

    #[test]
    fn rounded_box_point_beside_face_at_corner_and_inside() {
        let g = boxed(4, 2, Real::HALF);
        let face = point_query(&g, v(5, 0));
        assert_eq!(face.distance, real!(2.5));
        assert_eq!(face.point, Vect::new(real!(2.5), Real::ZERO));
        let corner = point_query(&g, v(5, 5));
        assert_eq!(corner.distance, real!(4.5));
        assert!(near_v(corner.point, vf(2.3, 1.4), 2), "{corner:?}");
        let inside = point_query(&g, Vect::new(Real::ZERO, Real::HALF));
        assert_eq!(inside.distance, -Real::ONE);
        assert_eq!(inside.point, Vect::new(Real::ZERO, real!(1.5)));
        assert_eq!(inside.gradient, Vect::Y);
    }

    #[test]
    fn ray_hits_circle_front() {
        let g = circle(Real::ONE, v(5, 0));
        let hit = segment_query(&g, v(0, 0), v(10, 0), Real::ZERO);
        assert_eq!(hit, Some(sq(v(4, 0), v(-1, 0), Real::ratio(2, 5))));
        // Behind the start, or short of it: no hit.
        assert_eq!(segment_query(&g, v(0, 0), v(-10, 0), Real::ZERO), None);
        assert_eq!(segment_query(&g, v(0, 0), v(3, 0), Real::ZERO), None);
        // Off to the side by more than the radius.
        assert_eq!(segment_query(&g, v(0, 2), v(10, 2), Real::ZERO), None);
    }

    #[test]
    fn ray_hits_circle_off_centre() {
        // y = 0.5 line: enters at x = 5 − √0.75.
        let g = circle(Real::ONE, v(5, 0));
        let a = Vect::new(Real::ZERO, Real::HALF);
        let b = Vect::new(Real::from_int(10), Real::HALF);
        let hit = segment_query(&g, a, b, Real::ZERO).unwrap_or_else(|| panic!("no hit"));
        let x = 5.0 - 0.75f64.sqrt();
        assert!(near_f(hit.alpha, x / 10.0, 1e-9), "{hit:?}");
        assert!(
            near_f(hit.point.x, x, 1e-8) && near_f(hit.point.y, 0.5, 1e-8),
            "{hit:?}"
        );
        assert!(near_f(hit.normal.x, -(0.75f64.sqrt()), 1e-9) && near_f(hit.normal.y, 0.5, 1e-9));
    }

    #[test]
    fn ray_hits_box_face() {
        let g = boxed(2, 2, Real::ZERO);
        let a = Vect::new(-Real::from_int(5), Real::HALF);
        let b = Vect::new(Real::from_int(5), Real::HALF);
        let hit = segment_query(&g, a, b, Real::ZERO);
        assert_eq!(
            hit,
            Some(sq(
                Vect::new(-Real::ONE, Real::HALF),
                v(-1, 0),
                Real::ratio(2, 5)
            ))
        );
        // Passing above the box.
        assert_eq!(segment_query(&g, v(-5, 3), v(5, 3), Real::ZERO), None);
        // Exactly through a corner of a sharp box: a face hit there.
        let corner = segment_query(&g, v(4, 4), v(0, 0), Real::ZERO);
        assert_eq!(
            corner.map(|h| (h.point, h.alpha)),
            Some((v(1, 1), Real::ratio(3, 4)))
        );
    }

    #[test]
    fn ray_hits_rounded_corner() {
        // Box 2×2 with r = 1; the vertical line x = 1.5 meets the corner
        // circle around (1, 1) at y = 1 + √0.75.
        let g = boxed(2, 2, Real::ONE);
        let a = Vect::new(real!(1.5), Real::from_int(5));
        let b = Vect::new(real!(1.5), -Real::from_int(5));
        let hit = segment_query(&g, a, b, Real::ZERO).unwrap_or_else(|| panic!("no hit"));
        let y = 1.0 + 0.75f64.sqrt();
        assert!(near_f(hit.alpha, (5.0 - y) / 10.0, 1e-9), "{hit:?}");
        assert!(
            near_f(hit.point.x, 1.5, 1e-8) && near_f(hit.point.y, y, 1e-8),
            "{hit:?}"
        );
        assert!(near_f(hit.normal.x, 0.5, 1e-9) && near_f(hit.normal.y, 0.75f64.sqrt(), 1e-9));
        // Diagonal into the corner: hits the arc at (1, 1) + (1, 1)/√2.
        let diag =
            segment_query(&g, v(4, 4), v(0, 0), Real::ZERO).unwrap_or_else(|| panic!("no hit"));
        let s = 1.0 + 0.5f64.sqrt();
        assert!(
            near_f(diag.point.x, s, 1e-8) && near_f(diag.point.y, s, 1e-8),
            "{diag:?}"
        );
        assert!(near_f(diag.alpha, (4.0 - s) / 4.0, 1e-9), "{diag:?}");
    }

    #[test]
    fn ray_through_corner_region_that_misses_the_arc_misses() {
        // x + y = 3.5 crosses the sharp grown square [−2, 2]² but passes
        // 1.5/√2 ≈ 1.06 > 1 from the corner centre (1, 1).
        let g = boxed(2, 2, Real::ONE);
        let a = Vect::new(-Real::HALF, Real::from_int(4));
        let b = Vect::new(real!(4.5), -Real::ONE);
        assert_eq!(segment_query(&g, a, b, Real::ZERO), None);
        // Just inside the arc (x + y = 3.4, 1.4/√2 ≈ 0.99): a hit.
        let a2 = Vect::new(-Real::HALF, real!(3.9));
        let b2 = Vect::new(real!(4.5), -real!(1.1));
        let hit = segment_query(&g, a2, b2, Real::ZERO).unwrap_or_else(|| panic!("no hit"));
        assert!(
            point_query(&g, hit.point).distance.abs() <= Real::from_bits(64),
            "{hit:?}"
        );
    }

    #[test]
    fn swept_circle_hits_circle_and_box_face() {
        let g = circle(Real::ONE, v(5, 0));
        let hit = segment_query(&g, v(0, 0), v(10, 0), Real::HALF);
        assert_eq!(hit, Some(sq(v(4, 0), v(-1, 0), Real::ratio(7, 20))));
        let b = boxed(2, 2, Real::ZERO);
        let hit = segment_query(&b, v(-5, 0), v(5, 0), Real::HALF);
        assert_eq!(hit, Some(sq(v(-1, 0), v(-1, 0), Real::ratio(7, 20))));
        // A swept circle passing 0.75 above a sharp box corner (1, 1)... at
        // y = 1.75 with radius 0.5: clear. With radius 1: it clips the corner.
        let a = Vect::new(-Real::from_int(5), real!(1.75));
        let bb = Vect::new(Real::from_int(5), real!(1.75));
        assert_eq!(segment_query(&b, a, bb, Real::HALF), None);
        let clip = segment_query(&b, a, bb, Real::ONE).unwrap_or_else(|| panic!("no hit"));
        assert_eq!(clip.point, v(-1, 1));
        // Centre at (−1 − √(1 − 0.75²), 1.75) touches the corner (−1, 1).
        let x = -1.0 - (1.0 - 0.5625f64).sqrt();
        assert!(near_f(clip.alpha, (x + 5.0) / 10.0, 1e-9), "{clip:?}");
    }

    #[test]
    fn capsule_hit_on_side_and_end_cap() {
        let g = capsule(v(0, 0), v(4, 0), Real::HALF);
        let side = segment_query(&g, v(2, 5), v(2, -5), Real::ZERO);
        assert_eq!(
            side,
            Some(sq(
                Vect::new(Real::TWO, Real::HALF),
                Vect::Y,
                Real::ratio(9, 20)
            ))
        );
        let below = segment_query(&g, v(2, -5), v(2, 5), Real::ZERO);
        assert_eq!(below.map(|h| h.normal), Some(v(0, -1)));
        // Along the axis from beyond b: the end cap around (4, 0).
        let cap = segment_query(&g, v(10, 0), v(0, 0), Real::ZERO);
        assert_eq!(
            cap,
            Some(sq(
                Vect::new(real!(4.5), Real::ZERO),
                Vect::X,
                Real::ratio(11, 20)
            ))
        );
        // Crossing the line beyond the end, outside the cap.
        assert_eq!(segment_query(&g, v(5, 5), v(5, -5), Real::ZERO), None);
    }

    #[test]
    fn thin_segment_hit_only_within_its_span() {
        let g = capsule(v(0, 0), v(4, 0), Real::ZERO);
        let hit = segment_query(&g, v(2, 5), v(2, -5), Real::ZERO);
        assert_eq!(hit, Some(sq(v(2, 0), Vect::Y, Real::HALF)));
        assert_eq!(segment_query(&g, v(5, 5), v(5, -5), Real::ZERO), None);
        // Collinear with the segment, zero radius: never hits (Chipmunk too).
        assert_eq!(segment_query(&g, v(10, 0), v(5, 0), Real::ZERO), None);
    }

    #[test]
    fn start_inside_or_within_reach_hits_at_alpha_zero() {
        let g = circle(Real::ONE, v(0, 0));
        let inside = segment_query(&g, Vect::new(Real::HALF, Real::ZERO), v(5, 0), Real::ZERO);
        assert_eq!(inside, Some(sq(v(1, 0), Vect::X, Real::ZERO)));
        // Outside, but the swept circle already overlaps.
        let reach = segment_query(&g, v(0, 2), v(0, 5), Real::ONE);
        assert_eq!(reach, Some(sq(v(0, 1), Vect::Y, Real::ZERO)));
        let b = boxed(2, 2, Real::ZERO);
        let in_box = segment_query(&b, Vect::new(Real::ZERO, Real::HALF), v(0, -5), Real::ZERO);
        assert_eq!(in_box, Some(sq(v(0, 1), Vect::Y, Real::ZERO)));
    }

    #[test]
    fn zero_length_query_outside_never_hits() {
        let g = boxed(2, 2, Real::HALF);
        assert_eq!(segment_query(&g, v(3, 3), v(3, 3), Real::ZERO), None);
        let c = circle(Real::ONE, v(0, 0));
        assert_eq!(segment_query(&c, v(3, 0), v(3, 0), Real::ONE), None);
    }

    #[test]
    fn rotated_box_ray_hit_lies_on_the_surface() {
        let local = boxed(2, 4, rf(0.25));
        let g = local.to_world(vf(3.5, -1.25), crate::math::Rot::from_angle(rf(0.6)));
        let hit =
            segment_query(&g, v(-6, 1), v(9, -3), Real::ZERO).unwrap_or_else(|| panic!("no hit"));
        assert!(
            point_query(&g, hit.point).distance.abs() <= Real::from_bits(256),
            "{hit:?}"
        );
        assert!(hit.alpha.is_positive() && hit.alpha < Real::ONE);
    }
}
