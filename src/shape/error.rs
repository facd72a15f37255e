//! The errors of shape construction ([`ShapeError`], [`ChainError`]) and
//! the polygon size bound they report ([`MAX_POLY_VERTICES`]).
//!
//! A file of its own, below every other file of the module: the geometry,
//! chain and polygon code all return these errors, and the module root
//! (which holds [`Shape`](super::Shape)) builds on them, so none of those
//! may be where the errors live without the files importing each other in
//! a circle. Everything here is re-exported from [`shape`](super) (and
//! from the files that defined it before: `shape::geometry::MAX_POLY_VERTICES`,
//! `shape::chain::ChainError`).
use core::fmt;

/// The most vertices a polygon may have (Box2D uses the same bound). Inline
/// storage keeps geometry `Copy` and the per-step world-space update free of
/// allocation; rounder shapes are better made of circles or rounded polygons.
pub const MAX_POLY_VERTICES: usize = 8;

/// Why a list of points does not make a chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChainError {
    /// Too few points: an open chain needs 2, a loop 3.
    TooFewPoints {
        /// Points given.
        count: usize,
        /// Points needed.
        needed: usize,
    },
    /// Points `index` and the next one (the first one, after the last point
    /// of a loop) are equal: the segment between them has no length.
    RepeatedPoint {
        /// Index of the first of the two points.
        index: usize,
    },
    /// The chain turns straight back at point `index` (the segments before
    /// and after it lie on one line, pointing opposite ways), so the
    /// neighbour rule cannot tell the two sides of the joint apart.
    FoldsBack {
        /// Index of the joint.
        index: usize,
    },
}

impl fmt::Display for ChainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChainError::TooFewPoints { count, needed } => {
                write!(f, "chain has {count} points, needs at least {needed}")
            }
            ChainError::RepeatedPoint { index } => write!(
                f,
                "chain point {index} equals the next point (a loop must not repeat its first point)"
            ),
            ChainError::FoldsBack { index } => {
                write!(f, "chain turns straight back at point {index}")
            }
        }
    }
}

/// Errors of shape construction and the MIS getters/setters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShapeError {
    /// MIS NotCircleShape: a circle routine was given another kind.
    NotCircleShape,
    /// A segment routine was given another kind.
    NotSegmentShape,
    /// MIS NotPolyShape: a polygon routine was given another kind.
    NotPolyShape,
    /// MIS IndexOutOfBounds: vertex `index` of a polygon with `count` vertices.
    IndexOutOfBounds {
        /// Requested index.
        index: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A radius, size, mass, density, friction or elasticity was negative.
    Negative(&'static str),
    /// A value limited to [0, 1] (elasticity) was above 1.
    AboveOne(&'static str),
    /// The points span no area (fewer than 3 distinct, non-collinear points).
    DegeneratePolygon,
    /// The points' convex hull has more than [`MAX_POLY_VERTICES`] vertices.
    TooManyVertices(usize),
    /// `poly_shape_new_raw` input is not convex and counter-clockwise.
    NotConvex,
    /// A value saturated: the input is outside the representable range.
    OutOfRange(&'static str),
    /// The points do not make a chain (see [`Chain::new`](super::Chain::new)).
    Chain(ChainError),
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShapeError::NotCircleShape => f.write_str("shape is not a circle"),
            ShapeError::NotSegmentShape => f.write_str("shape is not a segment"),
            ShapeError::NotPolyShape => f.write_str("shape is not a polygon"),
            ShapeError::IndexOutOfBounds { index, count } => {
                write!(
                    f,
                    "vertex index {index} out of bounds for a polygon of {count} vertices"
                )
            }
            ShapeError::Negative(what) => write!(f, "{what} must not be negative"),
            ShapeError::AboveOne(what) => write!(f, "{what} must not be above 1"),
            ShapeError::DegeneratePolygon => {
                f.write_str("polygon needs at least 3 distinct, non-collinear points")
            }
            ShapeError::TooManyVertices(n) => write!(
                f,
                "polygon hull has {n} vertices, more than the maximum of {MAX_POLY_VERTICES}"
            ),
            ShapeError::NotConvex => f.write_str("vertices are not convex and counter-clockwise"),
            ShapeError::OutOfRange(what) => write!(f, "{what} is outside the representable range"),
            ShapeError::Chain(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for ShapeError {}
