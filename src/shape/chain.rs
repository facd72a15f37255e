//! Chains: smooth terrain made of segments (Box2D's chain shape).
//!
//! A [`Chain`] is a polyline ([`ChainKind::Open`]) or a closed loop
//! ([`ChainKind::Loop`]) of points. It becomes one segment shape per pair of
//! consecutive points, each with its neighbours set (Chipmunk
//! `segmentShapeSetNeighbors`). Without neighbours, a box or capsule
//! sliding along the segments catches on every seam: at the joint it
//! touches the free end of the next segment, and that end pushes back
//! against the motion. With them, a contact found at a joint whose normal
//! points into the neighbouring segment is either left to that neighbour,
//! when the shapes' cores are apart (the neighbour is then nearer and
//! reports its own contact), or kept with the normal the chain has at the
//! joint, when they touch or overlap (there the normal does not say where
//! the other shape is, and leaving the contact to the neighbour could
//! leave it to nobody). So a joint never pushes against motion along the
//! chain and never lets a body through. [`Space::add_chain`](crate::space::Space::add_chain)
//! adds the segments to a body in one call.
//!
//! The ends of an open chain have no neighbour: a body reaching them meets
//! the rounded end of the last segment, as with a lone segment. Segments are
//! two-sided (as all segments here): a chain may be walked on from either
//! side, and its direction (clockwise or counter-clockwise) does not matter.
//!
//! The points are validated when the chain is made, so adding it cannot
//! fail half-way for bad geometry: at least 2 points (3 for a loop), no two
//! consecutive points equal (a loop's last point is joined to its first, so
//! do not repeat the first point at the end), and no joint that turns
//! straight back on the previous segment.
pub use super::error::ChainError;
use super::{check_radius, CollisionType, Material, Segment, Shape, ShapeError, ShapeFilter};
use crate::body::BodyHandle;
use crate::math::exact;
use crate::math::{Real, Vect};

/// Whether a chain's last point joins its first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChainKind {
    /// A polyline: `n` points make `n − 1` segments; the two ends are free.
    Open,
    /// A closed loop: `n` points make `n` segments, the last one from the
    /// last point back to the first.
    Loop,
}

/// A validated polyline or loop of points, with the data its segments share
/// (rounding radius, material, filter, collision type).
///
/// ```
/// use tamias2d::shape::{Chain, ChainKind};
/// use tamias2d::Vect;
///
/// let points = [Vect::from_ints(0, 0), Vect::from_ints(1, 0), Vect::from_ints(2, 0)];
/// let chain = Chain::new(&points, ChainKind::Open)?;
/// assert_eq!(chain.segments().len(), 2);
/// // Repeating a point is an error, not a zero-length segment.
/// let bad = [Vect::from_ints(0, 0), Vect::from_ints(0, 0)];
/// assert!(Chain::new(&bad, ChainKind::Open).is_err());
/// # Ok::<(), tamias2d::shape::ShapeError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Chain {
    points: Vec<Vect>,
    kind: ChainKind,
    radius: Real,
    material: Material,
    /// Collision filter of every segment.
    pub filter: ShapeFilter,
    /// Collision type of every segment.
    pub collision_type: CollisionType,
}

impl Chain {
    /// A chain through `points` with radius 0, default material and filter.
    /// Errors (never panics) on too few points, repeated consecutive points
    /// or a joint that folds straight back; see [`ChainError`].
    pub fn new(points: &[Vect], kind: ChainKind) -> Result<Chain, ShapeError> {
        check_points(points, kind).map_err(ShapeError::Chain)?;
        Ok(Chain {
            points: points.to_vec(),
            kind,
            radius: Real::ZERO,
            material: Material::default(),
            filter: ShapeFilter::ALL,
            collision_type: 0,
        })
    }

    /// The same chain with rounded segments of `radius` (errors if negative).
    pub fn with_radius(mut self, radius: Real) -> Result<Chain, ShapeError> {
        check_radius(radius)?;
        self.radius = radius;
        Ok(self)
    }

    /// The same chain with every segment's friction and elasticity (errors
    /// if either is negative, as [`Shape::with_material`]).
    pub fn with_material(mut self, friction: Real, elasticity: Real) -> Result<Chain, ShapeError> {
        if friction.is_negative() {
            return Err(ShapeError::Negative("friction"));
        }
        if elasticity.is_negative() {
            return Err(ShapeError::Negative("elasticity"));
        }
        self.material.friction = friction;
        self.material.elasticity = elasticity;
        Ok(self)
    }

    /// The same chain with every segment's surface velocity (conveyor belts).
    pub fn with_surface_velocity(mut self, v: Vect) -> Chain {
        self.material.surface_velocity = v;
        self
    }

    /// The points, as given.
    pub fn points(&self) -> &[Vect] {
        &self.points
    }

    /// Open or loop.
    pub fn kind(&self) -> ChainKind {
        self.kind
    }

    /// The segments' rounding radius.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The segments' material.
    pub fn material(&self) -> Material {
        self.material
    }

    /// The segments in chain order, in the body's coordinates, each with its
    /// neighbours set (the free ends of an open chain have none).
    pub fn segments(&self) -> Vec<Segment> {
        let n = self.points.len();
        let closed = self.kind == ChainKind::Loop;
        let count = if closed { n } else { n.saturating_sub(1) };
        let at = |i: usize| i.checked_rem(n).and_then(|i| self.points.get(i)).copied();
        let mut out = Vec::with_capacity(count);
        for i in 0..count {
            let (Some(a), Some(b)) = (at(i), at(i.saturating_add(1))) else {
                continue;
            };
            let mut s = Segment::new(a, b, self.radius);
            // The neighbour before `a` and after `b`; none at an open end.
            let prev = if closed || i > 0 {
                at(i.saturating_add(n).saturating_sub(1))
            } else {
                None
            };
            let next = if closed || i.saturating_add(2) < n {
                at(i.saturating_add(2))
            } else {
                None
            };
            if let Some(p) = prev {
                s.a_tangent = p - a;
            }
            if let Some(q) = next {
                s.b_tangent = q - b;
            }
            out.push(s);
        }
        out
    }

    /// The segments as shapes of `body`, with the chain's material, filter
    /// and collision type (massless, not sensors).
    pub fn shapes(&self, body: BodyHandle) -> Vec<Shape> {
        self.segments()
            .into_iter()
            .map(|s| {
                let mut shape = Shape::from_geometry(body, super::Geometry::Segment(s));
                shape.material = self.material;
                shape.filter = self.filter;
                shape.collision_type = self.collision_type;
                shape
            })
            .collect()
    }
}

fn check_points(points: &[Vect], kind: ChainKind) -> Result<(), ChainError> {
    let n = points.len();
    let needed = match kind {
        ChainKind::Open => 2,
        ChainKind::Loop => 3,
    };
    if n < needed {
        return Err(ChainError::TooFewPoints { count: n, needed });
    }
    let closed = kind == ChainKind::Loop;
    let at = |i: usize| {
        i.checked_rem(n)
            .and_then(|i| points.get(i))
            .copied()
            .unwrap_or(Vect::ZERO)
    };
    let edges = if closed { n } else { n.saturating_sub(1) };
    for i in 0..edges {
        if at(i) == at(i.saturating_add(1)) {
            return Err(ChainError::RepeatedPoint { index: i });
        }
    }
    // Joint j between edge j−1 → j and j → j+1: interior points of an open
    // chain, every point of a loop.
    let joints = if closed { 0..n } else { 1..n.saturating_sub(1) };
    for j in joints {
        let p = at(j.saturating_add(n).saturating_sub(1));
        let (q, r) = (at(j), at(j.saturating_add(1)));
        let (d1, d2) = (q - p, r - q);
        let (cross, dot) = (exact::cross(d1, d2), exact::dot(d1, d2));
        if cross == 0 && dot < 0 {
            return Err(ChainError::FoldsBack { index: j });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: i32, y: i32) -> Vect {
        Vect::from_ints(x, y)
    }

    #[test]
    fn open_chain_sets_inner_neighbours_only() {
        let c = Chain::new(&[v(0, 0), v(1, 0), v(2, 1)], ChainKind::Open).unwrap_or_else(|e| {
            panic!("{e}");
        });
        let s = c.segments();
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].a, s[0].b), (v(0, 0), v(1, 0)));
        assert_eq!(s[0].a_tangent, Vect::ZERO, "free start");
        assert_eq!(s[0].b_tangent, v(1, 1), "next − b");
        assert_eq!(s[1].a_tangent, v(-1, 0), "prev − a");
        assert_eq!(s[1].b_tangent, Vect::ZERO, "free end");
        // The same as setting the neighbours by hand.
        let by_hand = Segment::new(v(1, 0), v(2, 1), Real::ZERO).with_neighbors(v(0, 0), v(2, 1));
        assert_eq!(s[1].a_tangent, by_hand.a_tangent);
    }

    #[test]
    fn loop_closes_and_every_joint_has_neighbours() {
        let c = Chain::new(&[v(0, 0), v(2, 0), v(2, 2), v(0, 2)], ChainKind::Loop)
            .unwrap_or_else(|e| panic!("{e}"));
        let s = c.segments();
        assert_eq!(s.len(), 4);
        assert_eq!((s[3].a, s[3].b), (v(0, 2), v(0, 0)));
        for (i, seg) in s.iter().enumerate() {
            let prev = s[(i + 3) % 4];
            let next = s[(i + 1) % 4];
            assert_eq!(seg.a_tangent, prev.a - seg.a, "segment {i}");
            assert_eq!(seg.b_tangent, next.b - seg.b, "segment {i}");
        }
    }

    #[test]
    fn bad_points_are_errors() {
        let err = |p: &[Vect], k| Chain::new(p, k).err();
        let chain = |e| Some(ShapeError::Chain(e));
        assert_eq!(
            err(&[], ChainKind::Open),
            chain(ChainError::TooFewPoints {
                count: 0,
                needed: 2
            })
        );
        assert_eq!(
            err(&[v(0, 0)], ChainKind::Open),
            chain(ChainError::TooFewPoints {
                count: 1,
                needed: 2
            })
        );
        assert_eq!(
            err(&[v(0, 0), v(1, 0)], ChainKind::Loop),
            chain(ChainError::TooFewPoints {
                count: 2,
                needed: 3
            })
        );
        assert_eq!(
            err(&[v(0, 0), v(1, 0), v(1, 0)], ChainKind::Open),
            chain(ChainError::RepeatedPoint { index: 1 })
        );
        assert_eq!(
            err(&[v(0, 0), v(1, 0), v(1, 1), v(0, 0)], ChainKind::Loop),
            chain(ChainError::RepeatedPoint { index: 3 }),
            "a loop repeating its first point"
        );
        assert_eq!(
            err(&[v(0, 0), v(2, 0), v(1, 0)], ChainKind::Open),
            chain(ChainError::FoldsBack { index: 1 })
        );
        assert_eq!(
            err(&[v(0, 0), v(1, 0), v(2, 0)], ChainKind::Loop),
            chain(ChainError::FoldsBack { index: 0 }),
            "a collinear loop folds back (first at its first point)"
        );
        // Straight on is fine.
        assert!(err(&[v(0, 0), v(1, 0), v(2, 0)], ChainKind::Open).is_none());
        let ok = Chain::new(&[v(0, 0), v(1, 0)], ChainKind::Open).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            ok.clone().with_radius(-Real::ONE).err(),
            Some(ShapeError::Negative("radius"))
        );
        assert_eq!(
            ok.with_material(-Real::ONE, Real::ZERO).err(),
            Some(ShapeError::Negative("friction"))
        );
    }
}
