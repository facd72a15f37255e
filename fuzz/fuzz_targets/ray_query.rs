//! Ray and swept-circle queries (`shape::query::segment_query`) of
//! arbitrary shapes at arbitrary placements. Checked on every input:
//! * safety: never a panic; a hit's `alpha` is in `[0, 1]`;
//! * a ray (radius 0) that crosses or touches a sharp segment or a sharp
//!   polygon is a hit, decided exactly by orientation tests on the raw
//!   coordinates (within ±2^24 m, where every difference and product fits
//!   an `i128`; beyond it, safety only).
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::math::{Real, Rot, Vect};
use tamias2d::shape::query::segment_query;
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
        x: i64,
        y: i64,
        angle: i64,
    },
}

#[derive(Arbitrary, Debug)]
struct Input {
    shape: ShapeIn,
    ax: i64,
    ay: i64,
    bx: i64,
    by: i64,
    radius: i64,
}

fn r(bits: i64) -> Real {
    Real::from_bits(bits)
}

fn build(s: &ShapeIn) -> Option<Geometry> {
    Some(match *s {
        ShapeIn::Circle { r: rad, x, y } => {
            Geometry::Circle(Circle::new(r(rad).abs(), Vect::new(r(x), r(y))))
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
            r(rad).abs(),
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
            r(rad).abs(),
        )
        .ok()
        .map(|p| Geometry::Poly(p).to_world(Vect::new(r(x), r(y)), Rot::from_angle(r(angle))))?,
    })
}

type P = (i128, i128);

fn raw(v: Vect) -> P {
    (i128::from(v.x.to_bits()), i128::from(v.y.to_bits()))
}

fn side(p: P, q: P, s: P) -> i32 {
    let c = (q.0 - p.0) * (s.1 - p.1) - (q.1 - p.1) * (s.0 - p.0);
    c.signum() as i32
}

/// Whether the segments `a–b` and `c–d` cross or touch (collinear
/// overlaps and points included), exactly.
fn touch(a: P, b: P, c: P, d: P) -> bool {
    let (o1, o2, o3, o4) = (side(a, b, c), side(a, b, d), side(c, d, a), side(c, d, b));
    if o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0 {
        let within = |p: P, q: P, s: P| {
            p.0.min(q.0) <= s.0 && s.0 <= p.0.max(q.0) && p.1.min(q.1) <= s.1 && s.1 <= p.1.max(q.1)
        };
        return within(a, b, c) || within(a, b, d) || within(c, d, a) || within(c, d, b);
    }
    o1 * o2 <= 0 && o3 * o4 <= 0
}

const ENVELOPE: u64 = 1 << 56; // 2^24 m in raw bits

fuzz_target!(|input: Input| {
    let Some(g) = build(&input.shape) else {
        return;
    };
    let (a, b) = (
        Vect::new(r(input.ax), r(input.ay)),
        Vect::new(r(input.bx), r(input.by)),
    );
    let radius = r(input.radius);
    let hit = segment_query(&g, a, b, radius);
    if let Some(h) = hit {
        assert!(
            h.alpha >= Real::ZERO && h.alpha <= Real::ONE,
            "alpha {:?}",
            h.alpha
        );
    }
    if !radius.is_zero() {
        return;
    }
    let inside = |v: Vect| {
        v.x.to_bits().unsigned_abs() < ENVELOPE && v.y.to_bits().unsigned_abs() < ENVELOPE
    };
    if !(inside(a) && inside(b)) {
        return;
    }
    let (ra, rb) = (raw(a), raw(b));
    let crosses = match &g {
        Geometry::Segment(s) if s.radius.is_zero() && inside(s.a) && inside(s.b) => {
            touch(raw(s.a), raw(s.b), ra, rb)
        }
        Geometry::Poly(p) if p.radius().is_zero() && p.verts().iter().all(|&v| inside(v)) => {
            let vs: Vec<P> = p.verts().iter().map(|&v| raw(v)).collect();
            let edges = || vs.iter().zip(vs.iter().cycle().skip(1));
            edges().all(|(&p0, &p1)| side(p0, p1, ra) >= 0)
                || edges().any(|(&p0, &p1)| touch(p0, p1, ra, rb))
        }
        _ => false,
    };
    if crosses {
        assert!(hit.is_some(), "a crossing ray missed: {g:?} {a:?} -> {b:?}");
    }
});
