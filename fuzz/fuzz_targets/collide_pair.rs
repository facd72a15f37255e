//! Collision of arbitrary shape pairs at arbitrary placements. Checked on
//! every input:
//! * safety: never a panic, never more than 2 contacts;
//! * swap symmetry, exact: `collide(b, a, swap(id))` is the mirror of
//!   `collide(a, b, id)` bit for bit (normal negated, points, feature-id
//!   halves and warm-start id bytes swapped, the same distances), and so is
//!   each same-kind pair function called directly; except for two identical
//!   geometries, where both orders are the same call and cannot return
//!   opposite normals;
//! * warm start: an arbitrary warm-start id gives a correct answer, i.e. the
//!   cold start's up to rounding: the same deepest contact distance within
//!   64 ulp + 2^-20 of its size, and the same touching decision unless the
//!   one that touches does so within 64 ulp of `CONTACT_TOLERANCE`.
//!   Not bit for bit: when two features of the Minkowski difference are
//!   equally deep (a box centred in a wider one: up and down) or deep to
//!   within rounding, GJK/EPA report the one their starting point leads to,
//!   and both are right (`docs/numerics.md`, "Collision symmetry").
//!
//! The symmetry and warm-start checks run inside the documented envelope
//! (shapes within ±2^24 of the origin); beyond it, saturation may break them,
//! never safety. Inputs that broke them before are regression seeds in
//! `fuzz/seeds/collide_pair/regression-*`.
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::collision::{
    circle_to_circle, collide, poly_to_poly, segment_to_segment, CollisionInfo, CONTACT_TOLERANCE,
};
use tamias2d::math::{Real, Rot, Vect};
use tamias2d::shape::{Circle, Geometry, Poly, Segment};

#[derive(Arbitrary, Debug)]
enum ShapeIn {
    Circle {
        r: i64,
        x: i64,
        y: i64,
    },
    Segment {
        ax: i64,
        ay: i64,
        bx: i64,
        by: i64,
        r: i64,
    },
    Box {
        w: i32,
        h: i32,
        r: i64,
    },
    Poly {
        pts: Vec<(i32, i32)>,
        r: i64,
    },
}

#[derive(Arbitrary, Debug)]
struct Placed {
    shape: ShapeIn,
    x: i64,
    y: i64,
    angle: i64,
}

fn r(bits: i64) -> Real {
    Real::from_bits(bits)
}

fn build(p: &Placed) -> Option<Geometry> {
    let g = match &p.shape {
        ShapeIn::Circle { r: rad, x, y } => {
            Geometry::Circle(Circle::new(r(*rad).abs(), Vect::new(r(*x), r(*y))))
        }
        ShapeIn::Segment {
            ax,
            ay,
            bx,
            by,
            r: rad,
        } => Geometry::Segment(Segment::new(
            Vect::new(r(*ax), r(*ay)),
            Vect::new(r(*bx), r(*by)),
            r(*rad).abs(),
        )),
        ShapeIn::Box { w, h, r: rad } => Geometry::Poly(
            Poly::new_box(
                Real::from_bits(i64::from(*w) << 16),
                Real::from_bits(i64::from(*h) << 16),
                r(*rad).abs(),
            )
            .ok()?,
        ),
        ShapeIn::Poly { pts, r: rad } => {
            let v: Vec<Vect> = pts
                .iter()
                .take(16)
                .map(|&(x, y)| {
                    Vect::new(
                        Real::from_bits(i64::from(x) << 16),
                        Real::from_bits(i64::from(y) << 16),
                    )
                })
                .collect();
            Geometry::Poly(
                Poly::from_points(&v, &tamias2d::Transform::IDENTITY, r(*rad).abs()).ok()?,
            )
        }
    };
    Some(g.to_world(Vect::new(r(p.x), r(p.y)), Rot::from_angle(r(p.angle))))
}

/// The warm-start id with the roles of the shapes exchanged.
fn swap_id(id: u32) -> u32 {
    ((id & 0x00FF_00FF) << 8) | ((id >> 8) & 0x00FF_00FF)
}

/// `info` seen from the other shape (as `collide` mirrors it).
fn mirrored(mut info: CollisionInfo) -> CollisionInfo {
    info.normal = -info.normal;
    for c in info.contacts.iter_mut().take(info.count) {
        core::mem::swap(&mut c.point_a, &mut c.point_b);
        c.feature_id = c.feature_id.rotate_left(16);
    }
    info.warm_start_id = swap_id(info.warm_start_id);
    info
}

/// A same-kind pair function called directly in both orders (the results of
/// `(a, b)` and the mirrored result of `(b, a)`), `None` for mixed kinds.
fn pair_both_ways(ga: &Geometry, gb: &Geometry, id: u32) -> Option<(CollisionInfo, CollisionInfo)> {
    let run = |f: &dyn Fn(&mut CollisionInfo, &mut CollisionInfo)| {
        let (mut ab, mut ba) = (CollisionInfo::new(id), CollisionInfo::new(swap_id(id)));
        f(&mut ab, &mut ba);
        (ab, mirrored(ba))
    };
    match (ga, gb) {
        (Geometry::Circle(x), Geometry::Circle(y)) => Some(run(&|ab, ba| {
            circle_to_circle(x, y, ab);
            circle_to_circle(y, x, ba);
        })),
        (Geometry::Segment(x), Geometry::Segment(y)) => Some(run(&|ab, ba| {
            segment_to_segment(x, y, ab);
            segment_to_segment(y, x, ba);
        })),
        (Geometry::Poly(x), Geometry::Poly(y)) => Some(run(&|ab, ba| {
            poly_to_poly(x, y, ab);
            poly_to_poly(y, x, ba);
        })),
        _ => None,
    }
}

/// The deepest (smallest) contact distance, if any.
fn deepest(info: &CollisionInfo) -> Option<Real> {
    info.contacts().iter().map(|c| c.distance).min()
}

/// Warm start vs cold start: the same answer up to rounding (module docs):
/// deepest distances within 64 ulp + 2^-20 of their size, and the same
/// touching decision unless the one touching does so within 64 ulp of the
/// contact tolerance. (Contact distances are rounded a few times, each time
/// to about 1 ulp of the distance or of a unit normal times it.)
fn check_warm_start(warm: &CollisionInfo, cold: &CollisionInfo, what: &dyn Fn() -> String) {
    let slack = Real::from_bits(64);
    match (deepest(warm), deepest(cold)) {
        (Some(w), Some(c)) => {
            let size = w.abs().max(c.abs());
            let tol = slack + Real::from_bits(size.to_bits() >> 20);
            assert!((w - c).abs() <= tol, "warm {w:?} cold {c:?}: {}", what());
        }
        (Some(d), None) | (None, Some(d)) => {
            assert!(
                d >= CONTACT_TOLERANCE - slack,
                "only one touches, at {d:?}: {}",
                what()
            );
        }
        (None, None) => {}
    }
}

fuzz_target!(|input: (Placed, Placed, u32)| {
    let (a, b, id) = input;
    let (Some(ga), Some(gb)) = (build(&a), build(&b)) else {
        return;
    };
    let ab = collide(&ga, &gb, id);
    let ba = collide(&gb, &ga, swap_id(id));
    let cold = collide(&ga, &gb, 0);
    assert!(ab.count <= 2 && ba.count <= 2 && cold.count <= 2);
    let limit = Real::from_int(1 << 24);
    let inside = |g: &Geometry| {
        let bb = g.bb();
        bb.l > -limit && bb.b > -limit && bb.r < limit && bb.t < limit
    };
    if !(inside(&ga) && inside(&gb)) {
        return;
    }
    let what = || format!("{ga:?} {gb:?} id {id:#x}");
    if ga != gb {
        assert_eq!(mirrored(ab), ba, "swap: {}", what());
        if let Some((direct, swapped)) = pair_both_ways(&ga, &gb, id) {
            assert_eq!(direct, swapped, "pair function swap: {}", what());
        }
    }
    check_warm_start(&ab, &cold, &what);
});
