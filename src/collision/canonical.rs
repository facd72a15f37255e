//! The canonical form of a pair (steps 1 and 2 of the pipeline in the
//! [module docs](super)): the total order that decides which of two shapes
//! goes first, and the translation of both next to the origin.
//!
//! Both are exact and commute: comparing coordinates is unchanged by
//! translating both shapes, so [`collide`](super::collide) and the pair
//! functions reach the same order before and after the move.
use core::cmp::Ordering;

use crate::math::{Real, Vect};
use crate::shape::{Circle, Geometry, Poly, Segment};

/// True if the pair must be swapped into canonical order: by kind, then (same
/// kind) by coordinates, lexicographically. Comparing coordinates is
/// unchanged by translating both shapes, so the order is too.
pub(super) fn comes_after(a: &Geometry, b: &Geometry) -> bool {
    match a.kind().cmp(&b.kind()) {
        Ordering::Less => false,
        Ordering::Greater => true,
        Ordering::Equal => compare_same_kind(a, b) == Ordering::Greater,
    }
}

/// A total order on the data of two geometries of the same kind.
fn compare_same_kind(a: &Geometry, b: &Geometry) -> Ordering {
    match (a, b) {
        (Geometry::Circle(x), Geometry::Circle(y)) => compare_circles(x, y),
        (Geometry::Segment(x), Geometry::Segment(y)) => compare_segments(x, y),
        (Geometry::Poly(x), Geometry::Poly(y)) => compare_polys(x, y),
        // Different kinds never reach here; order them by kind for totality.
        (Geometry::Circle(_) | Geometry::Segment(_) | Geometry::Poly(_), _) => {
            a.kind().cmp(&b.kind())
        }
    }
}

/// The coordinates of `vs`, flattened (`x₀, y₀, x₁, …`).
pub(super) fn flat(vs: &[Vect]) -> impl Iterator<Item = Real> + '_ {
    vs.iter().flat_map(|v| [v.x, v.y])
}

/// Lexicographic order on (centre, radius). Comparing coordinates is
/// unchanged by translating both shapes, so the order is too.
pub(crate) fn compare_circles(x: &Circle, y: &Circle) -> Ordering {
    (x.offset.x, x.offset.y, x.radius).cmp(&(y.offset.x, y.offset.y, y.radius))
}

/// Lexicographic order on every field (endpoints first).
pub(crate) fn compare_segments(x: &Segment, y: &Segment) -> Ordering {
    let key = |s: &Segment| {
        [
            s.a,
            s.b,
            s.normal,
            s.a_tangent,
            s.b_tangent,
            Vect::new(s.radius, Real::ZERO),
        ]
    };
    flat(&key(x)).cmp(flat(&key(y)))
}

/// Lexicographic order on (vertices, normals, radius).
/// Written as a walk over the two key sequences (the former iterator chain
/// copied its arrays; unit test `compare_polys_is_the_chained_order`).
pub(crate) fn compare_polys(x: &Poly, y: &Poly) -> Ordering {
    // The first vertex (keys 0 and 1) almost always decides.
    if x.count() == 0 || y.count() == 0 {
        return compare_poly_keys(x, y, 0);
    }
    let (a, b) = (x.vert(0), y.vert(0));
    match (a.x, a.y).cmp(&(b.x, b.y)) {
        Ordering::Equal => compare_poly_keys(x, y, 2),
        unequal => unequal,
    }
}

/// The lexicographic order of the two key sequences from key `k` on (the
/// keys before it being equal).
fn compare_poly_keys(x: &Poly, y: &Poly, mut k: usize) -> Ordering {
    loop {
        match (poly_key(x, k), poly_key(y, k)) {
            (Some(a), Some(b)) => match a.cmp(&b) {
                Ordering::Equal => k = k.saturating_add(1),
                unequal => return unequal,
            },
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
        }
    }
}

/// Element `k` of a polygon's key sequence `x₀, y₀, x₁, …` (vertices),
/// then the normals the same way, then the radius; `None` past the end.
#[inline]
fn poly_key(p: &Poly, k: usize) -> Option<Real> {
    let coord = |v: Vect, k: usize| if k % 2 == 0 { v.x } else { v.y };
    let n = p.count().saturating_mul(2);
    if k < n {
        Some(coord(p.vert(k / 2), k))
    } else if k < n.saturating_mul(2) {
        Some(coord(p.normal((k.saturating_sub(n)) / 2), k))
    } else if k == n.saturating_mul(2) {
        Some(p.radius())
    } else {
        None
    }
}

/// The point the computation is made relative to.
pub(super) fn anchor_of(g: &Geometry) -> Vect {
    match g {
        Geometry::Circle(c) => c.offset,
        Geometry::Segment(s) => s.a,
        Geometry::Poly(p) => p.vert(0),
    }
}

/// True for a polygon without vertices (possible only from corrupt data).
pub(super) fn is_empty(g: &Geometry) -> bool {
    match g {
        Geometry::Poly(p) => p.count() == 0,
        Geometry::Circle(_) | Geometry::Segment(_) => false,
    }
}

/// The geometry translated by `−anchor` (directions are unchanged).
pub(super) fn moved(g: &Geometry, anchor: Vect) -> Geometry {
    match g {
        Geometry::Circle(c) => Geometry::Circle(Circle {
            offset: c.offset - anchor,
            ..*c
        }),
        Geometry::Segment(s) => Geometry::Segment(Segment {
            a: s.a - anchor,
            b: s.b - anchor,
            ..*s
        }),
        Geometry::Poly(p) => Geometry::Poly(moved_poly(p, anchor)),
    }
}

#[inline(always)]
pub(super) fn moved_poly(p: &Poly, anchor: Vect) -> Poly {
    let n = p.count();
    // Built in place (a copy, then a loop over it, cost two extra copies).
    Poly {
        count: p.count,
        verts: core::array::from_fn(|i| {
            let v = p.verts.get(i).copied().unwrap_or(Vect::ZERO);
            if i < n {
                v - anchor
            } else {
                v
            }
        }),
        normals: p.normals,
        radius: p.radius,
    }
}
