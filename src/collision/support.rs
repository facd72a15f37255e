//! Support points and support edges (MIS §10: `SupportPoint`, `MinkowskiPoint`,
//! `SupportContext`, `support`, `EdgePoint`, `Edge`, `supportEdgeFor`).
//!
//! GJK and EPA never look at a shape's geometry directly: they only ask for
//! the point of a shape that lies furthest along a direction (its *support
//! point*), and, to warm-start, for the point with a given index. Circles,
//! segments and polygons answer through the [`SupportShape`] trait, so GJK is
//! generic and monomorphised per pair (no dynamic dispatch in the hot loop).
//!
//! The shapes here are *cores*: a circle is its centre, a segment its two
//! endpoints, a polygon its vertices. Rounding radii are handled by the pair
//! functions, which subtract them from the core distance (as Chipmunk does).
//!
//! Support queries compare exact 128-bit dot products (`exact::dot`), and ties
//! go to the lowest index, so the chosen vertex is the same on every platform
//! and unaffected by rounding.
use super::info::WarmStartId;
use crate::math::exact;
use crate::math::{Real, Vect};
use crate::shape::geometry::next_index;
use crate::shape::{Circle, Poly, Segment};

/// A point of one shape's core with its feature index (MIS `SupportPoint`):
/// the circle centre (index 0), a segment endpoint (0 = `a`, 1 = `b`) or a
/// polygon vertex (its index).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SupportPoint {
    /// The point.
    pub p: Vect,
    /// Its feature (vertex) index.
    pub index: u32,
}

/// A point of the Minkowski difference `B − A` (MIS `MinkowskiPoint`): the
/// support points on each shape and their difference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MinkowskiPoint {
    /// Point on shape A.
    pub a: Vect,
    /// Point on shape B.
    pub b: Vect,
    /// `b − a`.
    pub ab: Vect,
    /// `(index on A & 0xFF) << 8 | (index on B & 0xFF)`.
    pub id: WarmStartId,
}

impl MinkowskiPoint {
    /// The Minkowski point of two support points.
    #[inline]
    pub fn new(a: SupportPoint, b: SupportPoint) -> MinkowskiPoint {
        MinkowskiPoint {
            a: a.p,
            b: b.p,
            ab: b.p - a.p,
            id: ((a.index & 0xFF) << 8) | (b.index & 0xFF),
        }
    }
}

/// A shape core GJK can query (the MIS `SupportPointFunc` of each shape kind).
pub trait SupportShape {
    /// The core point furthest along `n` (`n` need not be unit length; for
    /// `n = 0` every point ties and index 0 wins).
    fn support_point(&self, n: Vect) -> SupportPoint;
    /// The core point with feature index `index`, if it exists (warm start).
    fn point(&self, index: u32) -> Option<Vect>;
    /// A point inside the core, used to pick GJK's first search direction.
    fn center(&self) -> Vect;
}

/// MIS circle `SupportPoint`: the centre, index 0.
#[inline]
pub fn circle_support_point(circle: &Circle, _n: Vect) -> SupportPoint {
    SupportPoint {
        p: circle.offset,
        index: 0,
    }
}

/// MIS segment `SupportPoint`: the endpoint furthest along `n` (`b` on a tie).
#[inline]
pub fn segment_support_point(seg: &Segment, n: Vect) -> SupportPoint {
    if exact::dot(seg.a, n) > exact::dot(seg.b, n) {
        SupportPoint { p: seg.a, index: 0 }
    } else {
        SupportPoint { p: seg.b, index: 1 }
    }
}

/// Index of the polygon vertex furthest along `n` (lowest index on a tie;
/// 0 for an empty polygon).
#[inline]
pub fn poly_support_index(poly: &Poly, n: Vect) -> usize {
    support_index_by(poly, n, exact::dot)
}

/// [`poly_support_index`] with the exact dot product `dot`.
#[inline(always)]
fn support_index_by(poly: &Poly, n: Vect, dot: impl Fn(Vect, Vect) -> i128) -> usize {
    let mut best = 0;
    let mut best_dot = i128::MIN;
    for (i, v) in poly.verts().iter().enumerate() {
        let d = dot(*v, n);
        if d > best_dot {
            best = i;
            best_dot = d;
        }
    }
    best
}

/// MIS polygon `SupportPoint`: the vertex furthest along `n`.
#[inline]
pub fn poly_support_point(poly: &Poly, n: Vect) -> SupportPoint {
    let i = poly_support_index(poly, n);
    SupportPoint {
        p: poly.vert(i),
        // i < MAX_POLY_VERTICES, so the cast is lossless.
        index: i as u32,
    }
}

impl SupportShape for Circle {
    #[inline]
    fn support_point(&self, n: Vect) -> SupportPoint {
        circle_support_point(self, n)
    }
    #[inline]
    fn point(&self, index: u32) -> Option<Vect> {
        (index == 0).then_some(self.offset)
    }
    #[inline]
    fn center(&self) -> Vect {
        self.offset
    }
}

impl SupportShape for Segment {
    #[inline]
    fn support_point(&self, n: Vect) -> SupportPoint {
        segment_support_point(self, n)
    }
    #[inline]
    fn point(&self, index: u32) -> Option<Vect> {
        match index {
            0 => Some(self.a),
            1 => Some(self.b),
            _ => None,
        }
    }
    #[inline]
    fn center(&self) -> Vect {
        self.a + (self.b - self.a).mult(Real::HALF)
    }
}

impl SupportShape for Poly {
    #[inline]
    fn support_point(&self, n: Vect) -> SupportPoint {
        poly_support_point(self, n)
    }
    #[inline]
    fn point(&self, index: u32) -> Option<Vect> {
        self.verts().get(usize::try_from(index).ok()?).copied()
    }
    #[inline]
    fn center(&self) -> Vect {
        // The midpoint of a diagonal lies inside a convex polygon; it costs
        // no division (unlike the vertex average).
        let a = self.vert(0);
        let b = self.vert(self.count() / 2);
        a + (b - a).mult(Real::HALF)
    }
}

/// The two shapes GJK works on (MIS `SupportContext`): the Minkowski
/// difference is `b − a`, so normals point from `a` toward `b`.
#[derive(Clone, Copy, Debug)]
pub struct SupportContext<'s, A, B> {
    /// Shape A.
    pub a: &'s A,
    /// Shape B.
    pub b: &'s B,
}

impl<'s, A: SupportShape, B: SupportShape> SupportContext<'s, A, B> {
    /// A context for the pair (a, b).
    #[inline]
    pub fn new(a: &'s A, b: &'s B) -> Self {
        SupportContext { a, b }
    }
}

/// MIS `support`: the point of `B − A` furthest along `n`, i.e. B's support
/// point along `n` minus A's support point along `−n`.
#[inline]
pub fn support<A: SupportShape, B: SupportShape>(
    ctx: &SupportContext<'_, A, B>,
    n: Vect,
) -> MinkowskiPoint {
    MinkowskiPoint::new(ctx.a.support_point(-n), ctx.b.support_point(n))
}

/// One end of a support edge (MIS `EdgePoint`): the point and its feature
/// index (the MIS hash; contact ids combine the indices of both shapes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgePoint {
    /// The point.
    pub p: Vect,
    /// Feature (vertex) index on its shape.
    pub index: u32,
}

/// The edge of a shape that faces a direction (MIS `Edge`). Edges run
/// counter-clockwise around their shape: `normal` is `rperp(b − a)`
/// normalised and points out of the shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Edge {
    /// First endpoint.
    pub a: EdgePoint,
    /// Second endpoint.
    pub b: EdgePoint,
    /// Rounding radius of the shape.
    pub radius: Real,
    /// Outward unit normal.
    pub normal: Vect,
}

impl Edge {
    /// The edge with both ends moved by `−anchor` (as the vertices of a
    /// polygon moved into the frame whose origin is `anchor`), for a
    /// caller that has checked that no moved coordinate saturates: the
    /// difference is then exact, and the subtraction needs no saturation
    /// test (the saturating operator's value).
    #[inline]
    pub(crate) fn moved_unsaturated(self, anchor: Vect) -> Edge {
        let sub = |r: Real, by: Real| Real::from_bits(r.to_bits().wrapping_sub(by.to_bits()));
        let moved = |p: Vect| Vect::new(sub(p.x, anchor.x), sub(p.y, anchor.y));
        let mut e = self;
        e.a.p = moved(e.a.p);
        e.b.p = moved(e.b.p);
        e
    }
}

/// MIS `supportEdgeForPoly`: of the two edges at the vertex furthest along
/// `n`, the one whose normal is closer to `n` (the later edge on a tie).
pub fn support_edge_for_poly(poly: &Poly, n: Vect) -> Edge {
    support_edge_by(poly, n, exact::dot)
}

/// [`support_edge_for_poly`] for `n` within the unit square (the caller
/// checks): its dot products need no saturation test
/// ([`exact::dot_unit`]), the same edge.
#[inline]
pub(crate) fn support_edge_for_poly_unit(poly: &Poly, n: Vect) -> Edge {
    support_edge_by(poly, n, exact::dot_unit)
}

/// [`support_edge_for_poly`] with the exact dot product `dot`.
#[inline(always)]
fn support_edge_by(poly: &Poly, n: Vect, dot: impl Fn(Vect, Vect) -> i128) -> Edge {
    let count = poly.count();
    let i1 = support_index_by(poly, n, &dot);
    // count ≥ 1 whenever a vertex exists; max(1) keeps the indices defined for
    // an empty polygon (whose edge is then the zero point). i1 < m (an index
    // of the vertices, or 0): i0 and i2 are its cyclic neighbours, i1 − 1 (or
    // m − 1 before 0, never saturating as m ≥ 1) and i1 + 1 (or 0 after the last).
    let m = count.max(1);
    let i0 = i1.checked_sub(1).unwrap_or(m.saturating_sub(1));
    let i2 = next_index(i1, m);
    let (from, to) = if dot(poly.normal(i0), n) > dot(poly.normal(i1), n) {
        (i0, i1)
    } else {
        (i1, i2)
    };
    Edge {
        // Indices < MAX_POLY_VERTICES: the casts are lossless.
        a: EdgePoint {
            p: poly.vert(from),
            index: from as u32,
        },
        b: EdgePoint {
            p: poly.vert(to),
            index: to as u32,
        },
        radius: poly.radius(),
        normal: poly.normal(from),
    }
}

/// MIS `supportEdgeForSegment`: the segment itself, oriented so that its
/// normal faces `n` (`a → b` if `normal · n > 0`, else `b → a`).
pub fn support_edge_for_segment(seg: &Segment, n: Vect) -> Edge {
    let pa = EdgePoint { p: seg.a, index: 0 };
    let pb = EdgePoint { p: seg.b, index: 1 };
    if exact::dot(seg.normal, n) > 0 {
        Edge {
            a: pa,
            b: pb,
            radius: seg.radius,
            normal: seg.normal,
        }
    } else {
        Edge {
            a: pb,
            b: pa,
            radius: seg.radius,
            normal: -seg.normal,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real;

    fn unit_box() -> Poly {
        Poly::new_box(Real::TWO, Real::TWO, Real::ZERO).unwrap_or_else(|_| {
            Poly::from_ccw_unchecked(&[Vect::ZERO, Vect::X, Vect::Y], Real::ZERO)
        })
    }

    #[test]
    fn poly_support_point_picks_extreme_vertex_lowest_index_on_tie() {
        let b = unit_box(); // verts (1,-1) (1,1) (-1,1) (-1,-1)
        assert_eq!(poly_support_point(&b, Vect::from_ints(1, 1)).index, 1);
        assert_eq!(poly_support_point(&b, Vect::from_ints(-1, -1)).index, 3);
        // +x ties between vertex 0 and 1: the lower index wins.
        assert_eq!(poly_support_point(&b, Vect::X).index, 0);
    }

    #[test]
    fn support_edge_for_poly_faces_direction() {
        let b = unit_box();
        let e = support_edge_for_poly(&b, Vect::Y);
        assert_eq!((e.a.index, e.b.index), (1, 2));
        assert_eq!(e.normal, Vect::Y);
        let e = support_edge_for_poly(&b, Vect::new(real!(0.1), -Real::ONE));
        assert_eq!((e.a.index, e.b.index), (3, 0));
        assert_eq!(e.normal, -Vect::Y);
    }

    #[test]
    fn support_edge_for_segment_orients_normal() {
        let s = Segment::new(Vect::ZERO, Vect::from_ints(2, 0), Real::ZERO);
        // normal = rperp(b − a) = (0, −1)
        let e = support_edge_for_segment(&s, -Vect::Y);
        assert_eq!((e.a.index, e.b.index, e.normal), (0, 1, -Vect::Y));
        let e = support_edge_for_segment(&s, Vect::Y);
        assert_eq!((e.a.index, e.b.index, e.normal), (1, 0, Vect::Y));
    }

    #[test]
    fn minkowski_support_is_difference_of_supports() {
        let a = unit_box();
        let c = Circle::new(Real::ONE, Vect::from_ints(5, 0));
        let ctx = SupportContext::new(&a, &c);
        let m = support(&ctx, Vect::X);
        // A's support along −x is vertex 2 (−1, 1) (first of the tie 2/3).
        assert_eq!(m.a, Vect::from_ints(-1, 1));
        assert_eq!(m.ab, Vect::from_ints(6, -1));
        assert_eq!(m.id, 2 << 8);
    }
}
