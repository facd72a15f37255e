//! Regression: rays (radius 0) missed sharp segments they cross.
//!
//! Symptom: vertical rays through a 4 m segment of radius 0 turned 5° missed
//! 94 times in 100, at 40° every time, at 60° 44 times; a radius of 0.001
//! hit every time. Cause: the ray was clipped against the segment's two
//! faces as two planes, each measured from its own endpoint with the
//! rounded unit normal. For a segment with no thickness the two planes
//! are one line, and the rounding put one a few ulp beyond the other: the
//! slab between them was empty and every ray "passed". Now both faces are
//! measured from one point with one rounded offset (the slab can no longer
//! invert), and a miss of that clip is judged exactly in integers: a ray
//! that reaches the shape is always a hit.
//!
//! The property test compares every shape kind (circle, sharp segment,
//! capsule, sharp and rounded polygons) against an exact integer
//! reference, through the shape query and the space's ray queries: a ray
//! that crosses (or touches) the shape is never reported as a miss, and a
//! ray that stays a grid step away is never reported as a hit.
#![allow(clippy::float_arithmetic)]
use proptest::prelude::*;
use tamias2d::body::Body;
use tamias2d::shape::query::{point_query, segment_query};
use tamias2d::shape::{Circle, Geometry, Poly, Segment, Shape, ShapeFilter};
use tamias2d::space::Space;
use tamias2d::{Real, Vect};

/// The test grid: coordinates are integers in units of 2^-12 m.
const GRID_SHIFT: u32 = 20;

fn g(k: i64) -> Real {
    Real::from_bits(k << GRID_SHIFT)
}

fn gv(x: i64, y: i64) -> Vect {
    Vect::new(g(x), g(y))
}

/// A point of the grid, in grid units (exact: every test value lies on it).
type P = (i128, i128);

fn sub(a: P, b: P) -> P {
    (a.0 - b.0, a.1 - b.1)
}

fn cross(a: P, b: P) -> i128 {
    a.0 * b.1 - a.1 * b.0
}

fn dot(a: P, b: P) -> i128 {
    a.0 * b.0 + a.1 * b.1
}

/// Exact: is `p` within `√r2` of the segment `a–b`?
fn point_near_segment(p: P, a: P, b: P, r2: i128) -> bool {
    let (d, f) = (sub(b, a), sub(p, a));
    let t = dot(f, d);
    let dd = dot(d, d);
    if t <= 0 || dd == 0 {
        dot(f, f) <= r2
    } else if t >= dd {
        let e = sub(p, b);
        dot(e, e) <= r2
    } else {
        let c = cross(d, f);
        c * c <= r2 * dd
    }
}

/// Exact: do the segments `a–b` and `c–d` come within `√r2`?
fn segments_near(a: P, b: P, c: P, d: P, r2: i128) -> bool {
    let o = |p: P, q: P, r: P| cross(sub(q, p), sub(r, p)).signum();
    let (o1, o2, o3, o4) = (o(a, b, c), o(a, b, d), o(c, d, a), o(c, d, b));
    let proper = !(o1 == 0 && o2 == 0) && o1 * o2 <= 0 && o3 * o4 <= 0;
    proper
        || point_near_segment(a, c, d, r2)
        || point_near_segment(b, c, d, r2)
        || point_near_segment(c, a, b, r2)
        || point_near_segment(d, a, b, r2)
}

/// A shape of the test in grid units: its core and its rounding radius.
#[derive(Clone, Debug)]
enum Core {
    Point(P),
    Segment(P, P),
    /// Counter-clockwise.
    Polygon(Vec<P>),
}

/// Exact: does the ray `a–b` come within `reach` grid units of `core`?
fn reaches(core: &Core, reach: i128, a: P, b: P) -> bool {
    let r2 = reach * reach;
    match core {
        Core::Point(c) => point_near_segment(*c, a, b, r2),
        Core::Segment(p, q) => segments_near(*p, *q, a, b, r2),
        Core::Polygon(vs) => {
            let edges = || vs.iter().zip(vs.iter().cycle().skip(1));
            let inside = edges().all(|(&p, &q)| cross(sub(q, p), sub(a, p)) >= 0);
            inside || edges().any(|(&p, &q)| segments_near(p, q, a, b, r2))
        }
    }
}

/// The engine's geometry for a test shape (grid units → `Real`).
fn geometry(core: &Core, radius: i64) -> Geometry {
    let v = |p: &P| gv(p.0 as i64, p.1 as i64);
    match core {
        Core::Point(c) => Geometry::Circle(Circle::new(g(radius), v(c))),
        Core::Segment(p, q) => Geometry::Segment(Segment::new(v(p), v(q), g(radius))),
        Core::Polygon(vs) => {
            let verts: Vec<Vect> = vs.iter().map(v).collect();
            Geometry::Poly(Poly::from_ccw(&verts, g(radius)).unwrap())
        }
    }
}

/// A square turned by any angle whose corners lie on the grid: the centre
/// plus the half-diagonal `(u, w)` turned by quarter turns.
fn square(c: P, u: i128, w: i128) -> Core {
    Core::Polygon(vec![
        (c.0 + u, c.1 + w),
        (c.0 - w, c.1 + u),
        (c.0 - u, c.1 - w),
        (c.0 + w, c.1 - u),
    ])
}

const SPAN: i64 = 1 << 16; // ±16 m

fn point() -> impl Strategy<Value = P> {
    (-SPAN..SPAN, -SPAN..SPAN).prop_map(|(x, y)| (i128::from(x), i128::from(y)))
}

fn core() -> impl Strategy<Value = Core> {
    prop_oneof![
        point().prop_map(Core::Point),
        (point(), point()).prop_map(|(p, q)| Core::Segment(p, q)),
        (point(), 1i64..4096, 0i64..4096).prop_map(|(c, u, w)| square(
            c,
            i128::from(u),
            i128::from(w)
        )),
        (point(), point(), point()).prop_filter_map("a triangle", |(p, q, r)| {
            match cross(sub(q, p), sub(r, p)).signum() {
                1 => Some(Core::Polygon(vec![p, q, r])),
                -1 => Some(Core::Polygon(vec![p, r, q])),
                _ => None,
            }
        }),
    ]
}

/// Rounding radius: sharp half of the time (circles always get one).
fn radius_for(core: &Core, r: i64) -> i64 {
    match core {
        Core::Point(_) => r.max(1),
        _ if r % 2 == 0 => 0,
        _ => r,
    }
}

/// A ray that the reference says touches `core`: aimed at a point of the
/// shape (a vertex, the middle of an edge or the centre) from anywhere,
/// and carried on past it by a random amount.
fn aimed_ray(core: &Core, from: P, pick: usize, past: i128) -> (P, P) {
    let targets: Vec<P> = match core {
        Core::Point(c) => vec![*c],
        Core::Segment(p, q) => vec![*p, *q, ((p.0 + q.0) / 2, (p.1 + q.1) / 2)],
        Core::Polygon(vs) => vs
            .iter()
            .zip(vs.iter().cycle().skip(1))
            .flat_map(|(&p, &q)| [p, ((p.0 + q.0) / 2, (p.1 + q.1) / 2)])
            .collect(),
    };
    let t = targets[pick % targets.len()];
    let d = sub(t, from);
    (from, (t.0 + d.0 * past / 64, t.1 + d.1 * past / 64))
}

/// A static body at the origin holding `geometry` exactly (identity pose).
fn space_with(core: &Core, radius: i64) -> Space {
    let mut space = Space::new();
    let ground = space.add_body(Body::new_static()).unwrap();
    let v = |p: &P| gv(p.0 as i64, p.1 as i64);
    let shape = match core {
        Core::Point(c) => Shape::circle_shape_new(ground, g(radius), v(c)),
        Core::Segment(p, q) => Shape::segment_shape_new(ground, v(p), v(q), g(radius)),
        Core::Polygon(vs) => {
            let verts: Vec<Vect> = vs.iter().map(v).collect();
            Shape::poly_shape_new_raw(ground, &verts, g(radius))
        }
    };
    space.add_shape(shape.unwrap()).unwrap();
    space
}

/// Checks one ray against the reference: a crossing ray hits (the shape
/// query and both space queries), a ray a grid step out of reach does not,
/// and a hit lies on the surface.
fn check(core: &Core, radius: i64, a: P, b: P) -> Result<(), TestCaseError> {
    let geom = geometry(core, radius);
    let (va, vb) = (gv(a.0 as i64, a.1 as i64), gv(b.0 as i64, b.1 as i64));
    let hit = segment_query(&geom, va, vb, Real::ZERO);
    let r = i128::from(radius);
    if reaches(core, r, a, b) {
        prop_assert!(
            hit.is_some(),
            "a crossing ray missed {core:?} r={radius}: {a:?} -> {b:?}"
        );
        let space = space_with(core, radius);
        prop_assert_eq!(
            space
                .segment_query(va, vb, Real::ZERO, ShapeFilter::ALL)
                .len(),
            1
        );
        prop_assert!(space
            .segment_query_first(va, vb, Real::ZERO, ShapeFilter::ALL)
            .is_some());
    } else if !reaches(core, r + 1, a, b) {
        prop_assert!(
            hit.is_none(),
            "a ray out of reach hit {core:?} r={radius}: {a:?} -> {b:?}"
        );
    }
    if let Some(hit) = hit {
        // Within the rounding margin of `segment_query` (2^-27 of the
        // query's distances plus 64 ulp), with the box's size for its sides.
        let bb = geom.bb();
        let l1 = |v: Vect| v.x.abs() + v.y.abs();
        let extent = l1(vb - va) + l1(va - bb.center()) * Real::TWO + (bb.r - bb.l) + (bb.t - bb.b);
        let bound = Real::from_bits(extent.to_bits() >> 27) + Real::from_bits(128);
        let off = point_query(&geom, hit.point).distance.abs();
        prop_assert!(off <= bound, "hit {off} from the surface (bound {bound})");
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(if cfg!(debug_assertions) { 3000 } else { 20000 }))]

    /// Rays aimed at a vertex, an edge's middle or the centre of a shape:
    /// each crosses or touches it, many exactly through a vertex.
    #[test]
    fn aimed_rays_hit_every_shape_kind(
        core in core(),
        r in 0i64..2048,
        from in point(),
        pick in 0usize..16,
        past in 0i128..256,
    ) {
        let radius = radius_for(&core, r);
        let (a, b) = aimed_ray(&core, from, pick, past);
        check(&core, radius, a, b)?;
    }

    /// Random rays: crossings, grazes and misses.
    #[test]
    fn random_rays_agree_with_the_exact_reference(
        core in core(),
        r in 0i64..2048,
        a in point(),
        b in point(),
    ) {
        check(&core, radius_for(&core, r), a, b)?;
    }
}

/// The reported case: vertical rays through a 4 m sharp segment from the
/// origin, turned by 5°, 40° and 60° (endpoints from `f64`, as a game
/// builds them; 100 rays each, spread over the segment's span).
#[test]
fn vertical_rays_through_a_sloped_segment_all_hit() {
    for degrees in [5.0f64, 40.0, 60.0] {
        let (s, c) = degrees.to_radians().sin_cos();
        let end = Vect::from_f64(4.0 * c, 4.0 * s).unwrap();
        let geom = Geometry::Segment(Segment::new(Vect::ZERO, end, Real::ZERO));
        let mut space = Space::new();
        let ground = space.add_body(Body::new_static()).unwrap();
        space
            .add_shape(Shape::segment_shape_new(ground, Vect::ZERO, end, Real::ZERO).unwrap())
            .unwrap();
        let mut misses = (0, 0);
        for i in 0..100 {
            let x = Real::from_f64(4.0 * c * (f64::from(i) + 0.5) / 100.0).unwrap();
            let (a, b) = (
                Vect::new(x, Real::from_int(5)),
                Vect::new(x, Real::from_int(-5)),
            );
            if segment_query(&geom, a, b, Real::ZERO).is_none() {
                misses.0 += 1;
            }
            if space
                .segment_query_first(a, b, Real::ZERO, ShapeFilter::ALL)
                .is_none()
            {
                misses.1 += 1;
            }
        }
        assert_eq!(misses, (0, 0), "{degrees}°: (shape, space) misses of 100");
    }
}

/// Cases the property tests found while the fix was written: a ray through
/// a sharp square's corner (clipped away by the rounded normals), a ray
/// ending exactly on a triangle's vertex (the margin's half chord squared
/// to nothing), and a ray into a sliver's sharp corner (its entry point
/// pushed far along the spike by the rounding of nearly parallel planes).
#[test]
fn found_cases_hit_on_the_surface() {
    let cases = [
        (
            vec![
                (-59564, 54645),
                (-65989, 56378),
                (-67722, 49953),
                (-61297, 48220),
            ],
            (20437, -38206),
            12,
            190,
        ),
        (
            vec![(-38310, 13783), (16688, 57686), (0, 44766)],
            (23970, 48576),
            2,
            0,
        ),
        (
            vec![(-9932, 3497), (-28424, 24724), (45262, -59861)],
            (-12176, 30125),
            8,
            108,
        ),
    ];
    for (verts, from, pick, past) in cases {
        let core = Core::Polygon(verts);
        let (a, b) = aimed_ray(&core, from, pick, past);
        check(&core, 0, a, b).unwrap();
    }
}
