//! Shape casts (`collision::shape_cast`) of arbitrary shapes along
//! arbitrary translations. Checked on every input:
//! * safety: never a panic; a hit's fraction is in `[0, 1]`;
//! * for shapes up to 2^10 m (1 km) across, within ±2^24 m: a cast that starts
//!   overlapping hits at fraction 0 under `StartContact::Hit`, and a cast
//!   whose shapes overlap at its end is a hit: no crossing is missed.
//!   "Overlap" is deeper than the cast's documented slack:
//!   `CAST_TOLERANCE`, plus `2^-26` of the translation, plus `2^-28` of the
//!   two shapes' size (the rounding of the outline's unit normals grows
//!   with the outline).
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::collision::{shape_cast, shapes_collide, StartContact, CAST_TOLERANCE};
use tamias2d::math::{Real, Rot, Vect};
use tamias2d::shape::{Circle, Geometry, Poly, Segment};

#[derive(Arbitrary, Debug)]
enum ShapeIn {
    Circle {
        r: i32,
        x: i64,
        y: i64,
    },
    Segment {
        ax: i64,
        ay: i64,
        bx: i64,
        by: i64,
        r: i32,
    },
    Box {
        w: i32,
        h: i32,
        r: i32,
        x: i64,
        y: i64,
        angle: i64,
    },
}

#[derive(Arbitrary, Debug)]
struct Input {
    a: ShapeIn,
    b: ShapeIn,
    dx: i64,
    dy: i64,
}

fn r(bits: i64) -> Real {
    Real::from_bits(bits)
}

fn build(s: &ShapeIn) -> Option<Geometry> {
    Some(match *s {
        ShapeIn::Circle { r: rad, x, y } => {
            Geometry::Circle(Circle::new(r(i64::from(rad)).abs(), Vect::new(r(x), r(y))))
        }
        ShapeIn::Segment {
            ax,
            ay,
            bx,
            by,
            r: rad,
        } => Geometry::Segment(Segment::new(
            Vect::new(r(ax), r(ay)),
            Vect::new(r(bx), r(by)),
            r(i64::from(rad)).abs(),
        )),
        ShapeIn::Box {
            w,
            h,
            r: rad,
            x,
            y,
            angle,
        } => Poly::new_box(
            Real::from_bits(i64::from(w) << 16),
            Real::from_bits(i64::from(h) << 16),
            r(i64::from(rad)).abs(),
        )
        .ok()
        .map(|p| Geometry::Poly(p).to_world(Vect::new(r(x), r(y)), Rot::from_angle(r(angle))))?,
    })
}

/// 2^24 m in raw bits: inside it every difference the cast takes is exact.
const ENVELOPE: u64 = 1 << 56;

fn inside(g: &Geometry) -> bool {
    let bb = g.bb();
    [bb.l, bb.b, bb.r, bb.t]
        .iter()
        .all(|v| v.to_bits().unsigned_abs() < ENVELOPE)
}

fn deepest(a: &Geometry, b: &Geometry) -> Option<Real> {
    let set = shapes_collide(a, b);
    set.points.iter().take(set.count).map(|p| p.distance).min()
}

fuzz_target!(|input: Input| {
    let (Some(a), Some(b)) = (build(&input.a), build(&input.b)) else {
        return;
    };
    let d = Vect::new(r(input.dx), r(input.dy));
    let hit = shape_cast(&a, d, &b, StartContact::Hit);
    let approaching = shape_cast(&a, d, &b, StartContact::HitIfApproaching);
    for h in [hit, approaching].into_iter().flatten() {
        assert!(h.fraction >= Real::ZERO && h.fraction <= Real::ONE, "{h:?}");
    }
    let size = |g: &Geometry| {
        let bb = g.bb();
        (bb.r - bb.l).max(bb.t - bb.b)
    };
    if !(inside(&a)
        && inside(&b)
        && d.x.to_bits().unsigned_abs() < ENVELOPE
        && d.y.to_bits().unsigned_abs() < ENVELOPE)
        || size(&a).max(size(&b)) > Real::from_int(1 << 10)
    {
        return;
    }
    let slack = CAST_TOLERANCE
        + Real::from_bits(d.length().to_bits() >> 26)
        + Real::from_bits((size(&a) + size(&b)).to_bits() >> 28);
    if deepest(&a, &b).is_some_and(|s| s < -slack) {
        assert_eq!(
            hit.map(|h| h.fraction),
            Some(Real::ZERO),
            "started inside: {a:?} {b:?}"
        );
    }
    let end = a.to_world(d, Rot::IDENTITY);
    if deepest(&end, &b).is_some_and(|s| s < -slack) {
        assert!(
            hit.is_some(),
            "missed a crossing: {a:?} by {d:?} into {b:?}"
        );
    }
});
