#![allow(clippy::float_arithmetic)]
//! The separating-axis polygon path (`poly_to_poly`) against the GJK + EPA
//! path it replaced (`poly_to_poly_gjk`), on fixed cases (boxes resting on
//! boxes, rotated boxes, box–triangle, rounded boxes, deep overlaps, touching
//! within tolerance, separated) and on random convex polygons.
//!
//! Agreement, when both pick the same face: the same contact count, normals
//! within 2 ulp per component, distances and points within `8 + 2·L` ulp
//! (L = the pair's largest coordinate relative to the anchor, in units, the
//! bound `tests/geometry/collision.rs` uses for GJK/EPA). Two faces equally deep to
//! within that bound may be chosen differently (EPA ranks by true distance,
//! the new path by exact products on the stored normals, ties by a fixed
//! rule): then both answers must have the same depth. A contact exactly at
//! the edge of the contact tolerance may be kept by one and not the other.
use proptest::prelude::*;
use tamias2d::collision::{
    collide, poly_to_poly, poly_to_poly_gjk, CollisionInfo, CONTACT_TOLERANCE,
};
use tamias2d::shape::{Geometry, Poly};
use tamias2d::{Real, Vect};

const ULP: f64 = 1.0 / 4_294_967_296.0;

fn r(x: f64) -> Real {
    Real::from_f64(x).expect("test value in range")
}

fn v(x: f64, y: f64) -> Vect {
    Vect::new(r(x), r(y))
}

/// A `w × h` box centred at `(cx, cy)`, turned by `ang` radians (f64 only to
/// build the test input).
fn boxed(w: f64, h: f64, (cx, cy): (f64, f64), ang: f64, radius: f64) -> Poly {
    let (s, c) = ang.sin_cos();
    let vs: Vec<Vect> = [(0.5, -0.5), (0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5)]
        .iter()
        .map(|(x, y)| (x * w, y * h))
        .map(|(x, y)| v(cx + c * x - s * y, cy + s * x + c * y))
        .collect();
    Poly::from_ccw(&vs, r(radius)).expect("convex box")
}

fn poly(pts: &[(f64, f64)], radius: f64) -> Poly {
    let vs: Vec<Vect> = pts.iter().map(|(x, y)| v(*x, *y)).collect();
    Poly::from_ccw(&vs, r(radius)).expect("convex ccw polygon")
}

fn new_and_old(a: &Poly, b: &Poly) -> (CollisionInfo, CollisionInfo) {
    let mut new = CollisionInfo::new(0);
    poly_to_poly(a, b, &mut new);
    let mut old = CollisionInfo::new(0);
    poly_to_poly_gjk(a, b, &mut old);
    (new, old)
}

/// Everything but the warm-start id (the new path passes the id through;
/// GJK returns its own).
fn manifold(i: &CollisionInfo) -> (Vect, usize, Vec<tamias2d::collision::Contact>, bool) {
    (
        i.normal,
        i.count,
        i.contacts().to_vec(),
        i.hit_iteration_cap,
    )
}

fn deepest(info: &CollisionInfo) -> Option<f64> {
    info.contacts()
        .iter()
        .map(|c| c.distance.to_f64())
        .reduce(f64::min)
}

/// Largest coordinate of the pair relative to `a`'s first vertex (units).
fn extent(a: &Poly, b: &Poly) -> f64 {
    let o = a.vert(0).to_f64();
    a.verts()
        .iter()
        .chain(b.verts())
        .map(|p| {
            let (x, y) = p.to_f64();
            (x - o.0).abs().max((y - o.1).abs())
        })
        .fold(1.0, f64::max)
}

/// `Err` with a description if the two answers disagree beyond the bounds
/// in the module docs; `Ok(true)` if they picked the same face.
fn agree(a: &Poly, b: &Poly, new: &CollisionInfo, old: &CollisionInfo) -> Result<bool, String> {
    let tol = (8.0 + 2.0 * extent(a, b)) * ULP;
    let cap = CONTACT_TOLERANCE.to_f64();
    let marginal = |i: &CollisionInfo| {
        i.contacts()
            .iter()
            .any(|c| (c.distance.to_f64() - cap).abs() <= tol)
    };
    if new.hit_iteration_cap {
        return Err("new path reports an iteration cap".into());
    }
    let (nx, ny) = new.normal.to_f64();
    let (ox, oy) = old.normal.to_f64();
    let same_face = (nx - ox).abs() <= 2.0 * ULP && (ny - oy).abs() <= 2.0 * ULP;
    if new.count != old.count && !(marginal(new) || marginal(old)) && same_face {
        return Err(format!("count {} vs {}", new.count, old.count));
    }
    match (deepest(new), deepest(old)) {
        (None, None) => return Ok(true),
        (Some(d), None) | (None, Some(d)) => {
            return if (d - cap).abs() <= tol {
                Ok(true)
            } else {
                Err(format!("one path touches at {d}, the other not"))
            };
        }
        (Some(dn), Some(dold)) => {
            if (dn - dold).abs() > tol {
                return Err(format!("deepest {dn} vs {dold} (tol {tol})"));
            }
        }
    }
    if !same_face {
        return Ok(false);
    }
    if new.count == old.count {
        for (cn, co) in new.contacts().iter().zip(old.contacts()) {
            let close = |p: Vect, q: Vect| {
                let ((px, py), (qx, qy)) = (p.to_f64(), q.to_f64());
                (px - qx).abs() <= tol && (py - qy).abs() <= tol
            };
            if !close(cn.point_a, co.point_a) || !close(cn.point_b, co.point_b) {
                return Err(format!("points differ: {cn:?} vs {co:?}"));
            }
            if (cn.distance.to_f64() - co.distance.to_f64()).abs() > tol {
                return Err(format!("distance differs: {cn:?} vs {co:?}"));
            }
            if cn.feature_id != co.feature_id {
                return Err(format!("feature id differs: {cn:?} vs {co:?}"));
            }
        }
    }
    Ok(true)
}

fn assert_agree(name: &str, a: &Poly, b: &Poly) -> (CollisionInfo, CollisionInfo) {
    let (new, old) = new_and_old(a, b);
    match agree(a, b, &new, &old) {
        Ok(true) => {}
        Ok(false) => panic!("{name}: different faces\nnew {new:?}\nold {old:?}"),
        Err(e) => panic!("{name}: {e}\nnew {new:?}\nold {old:?}"),
    }
    // Both orders: exact mirror.
    let mut swapped = CollisionInfo::new(0);
    poly_to_poly(b, a, &mut swapped);
    assert_eq!(swapped.normal, -new.normal, "{name}: swap");
    assert_eq!(swapped.count, new.count, "{name}: swap");
    (new, old)
}

#[test]
fn box_resting_on_box_matches_gjk_bit_for_bit() {
    let ground = boxed(10.0, 1.0, (0.0, -0.5), 0.0, 0.0);
    for sink in [0.25, 0.01, 1e-6, 0.0] {
        let top = boxed(2.0, 1.0, (0.3, 0.5 - sink), 0.0, 0.0);
        let (new, old) = assert_agree("resting", &ground, &top);
        assert_eq!(manifold(&new), manifold(&old), "sink {sink}");
        assert_eq!(new.count, 2);
        assert_eq!(new.normal, Vect::Y);
    }
    // Equal boxes stacked exactly (corners on corners).
    let lower = boxed(1.0, 1.0, (0.0, 0.5), 0.0, 0.0);
    let upper = boxed(1.0, 1.0, (0.0, 1.5), 0.0, 0.0);
    let (new, old) = assert_agree("stacked", &lower, &upper);
    assert_eq!(manifold(&new), manifold(&old));
    assert_eq!(new.count, 2);
}

#[test]
fn rotated_boxes_agree_with_gjk() {
    for k in 0..40 {
        let ang = f64::from(k) * 0.157;
        let a = boxed(2.0, 1.0, (0.0, 0.0), 0.1, 0.0);
        let b = boxed(1.5, 0.8, (0.9 * ang.cos(), 1.1 * ang.sin()), ang, 0.0);
        assert_agree(&format!("rotated {k}"), &a, &b);
    }
}

#[test]
fn box_and_triangle_agree_with_gjk() {
    let tri = poly(&[(0.0, 0.0), (2.0, 0.0), (1.0, 1.5)], 0.0);
    for k in 0..24 {
        let x = -1.0 + f64::from(k) * 0.15;
        let b = boxed(1.0, 0.6, (x, 1.6), 0.3 * f64::from(k % 5), 0.0);
        assert_agree(&format!("tri {k}"), &tri, &b);
    }
}

#[test]
fn rounded_boxes_touching_through_radius_agree() {
    let a = boxed(1.0, 1.0, (0.5, 0.5), 0.0, 0.25);
    // Side by side, cores 0.4 apart (vertex–face: new path).
    let b = boxed(1.0, 1.0, (1.9, 0.7), 0.0, 0.25);
    let (new, old) = assert_agree("side", &a, &b);
    assert_eq!(manifold(&new), manifold(&old));
    assert_eq!((new.count, new.normal), (2, Vect::X));
    // Corner near corner, cores apart diagonally (GJK fallback).
    let c = boxed(1.0, 1.0, (1.6, 1.6), 0.0, 0.25);
    let (new, old) = assert_agree("corner", &a, &c);
    assert_eq!(manifold(&new), manifold(&old));
    assert_eq!(new.count, 1);
    // Rotated rounded boxes overlapping through cores.
    for k in 0..20 {
        let ang = f64::from(k) * 0.31;
        let d = boxed(0.8, 0.5, (1.0 + 0.2 * ang.cos(), 0.9), ang, 0.1);
        assert_agree(&format!("rounded {k}"), &a, &d);
    }
}

#[test]
fn deep_overlaps_agree_with_gjk() {
    let a = boxed(4.0, 2.0, (0.0, 0.0), 0.05, 0.0);
    let b = boxed(1.0, 1.0, (0.3, 0.2), 0.7, 0.0);
    assert_agree("inside", &a, &b);
    let c = boxed(3.0, 1.5, (0.2, 0.1), -0.2, 0.0);
    assert_agree("mostly", &a, &c);
}

#[test]
fn touching_within_tolerance_and_separated() {
    let ground = boxed(10.0, 1.0, (0.0, -0.5), 0.0, 0.0);
    let eps = Real::DELTA.to_f64();
    // A hair above: still touching.
    let top = boxed(2.0, 1.0, (0.0, 0.5 + 100.0 * eps), 0.0, 0.0);
    let (new, old) = assert_agree("hair", &ground, &top);
    assert_eq!(manifold(&new), manifold(&old));
    assert_eq!(new.count, 2);
    // Past the tolerance: apart.
    let gap = CONTACT_TOLERANCE.to_f64() + 10.0 * eps;
    let top = boxed(2.0, 1.0, (0.0, 0.5 + gap), 0.0, 0.0);
    let (new, old) = assert_agree("gap", &ground, &top);
    assert_eq!((new.count, old.count), (0, 0));
    // Far apart.
    let far = boxed(1.0, 1.0, (30.0, 7.0), 0.4, 0.0);
    let (new, _) = assert_agree("far", &ground, &far);
    assert_eq!(new.count, 0);
}

#[test]
fn warm_start_id_does_not_change_the_polygon_answer() {
    let a = boxed(2.0, 1.0, (0.0, 0.0), 0.1, 0.0);
    let b = boxed(1.5, 0.8, (0.7, 0.6), 0.5, 0.0);
    let cold = collide(&Geometry::Poly(a), &Geometry::Poly(b), 0);
    assert!(cold.count > 0);
    for id in [1u32, 0x0102_0300, 0x0303_0101, u32::MAX] {
        let warm = collide(&Geometry::Poly(a), &Geometry::Poly(b), id);
        assert_eq!((warm.normal, warm.count), (cold.normal, cold.count));
        assert_eq!(warm.contacts(), cold.contacts());
    }
}

fn convex(s: f64, squash: f64, gaps: &[f64]) -> Vec<(f64, f64)> {
    let total: f64 = gaps.iter().map(|g| g + 0.2).sum();
    let mut ang = 0.0;
    gaps.iter()
        .map(|g| {
            ang += (g + 0.2) / total * std::f64::consts::TAU;
            (0.5 * s * ang.cos(), 0.5 * s * squash * ang.sin())
        })
        .collect()
}

fn any_local() -> impl Strategy<Value = (Vec<(f64, f64)>, f64)> {
    let shape = prop_oneof![
        (0.1f64..10.0, 0.2f64..1.0, -3.2f64..3.2).prop_map(|(w, k, ang)| {
            let (s, c) = ang.sin_cos();
            [(0.5, -0.5), (0.5, 0.5), (-0.5, 0.5), (-0.5, -0.5)]
                .iter()
                .map(|(x, y)| (x * w, y * w * k))
                .map(|(x, y)| (c * x - s * y, s * x + c * y))
                .collect::<Vec<_>>()
        }),
        (
            0.1f64..10.0,
            0.3f64..1.0,
            prop::collection::vec(0.0f64..1.0, 3..=8)
        )
            .prop_map(|(s, q, g)| convex(s, q, &g)),
    ];
    (shape, prop_oneof![Just(0.0), 0.0f64..0.2])
}

fn build(local: &[(f64, f64)], rad: f64, (cx, cy): (f64, f64)) -> Option<Poly> {
    let vs: Vec<Vect> = local.iter().map(|(x, y)| v(cx + x, cy + y)).collect();
    let size = local.iter().map(|(x, y)| x.hypot(*y)).fold(0.0, f64::max);
    Poly::from_ccw(&vs, r(rad * size)).ok()
}

fn reach(local: &[(f64, f64)], rad: f64) -> f64 {
    let size = local.iter().map(|(x, y)| x.hypot(*y)).fold(0.0, f64::max);
    size * (1.0 + rad)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn random_polygons_agree_with_gjk(
        (la, ra) in any_local(),
        (lb, rb) in any_local(),
        (cx, cy) in (-1000.0f64..1000.0, -1000.0f64..1000.0),
        (ux, uy) in (-1.0f64..1.0, -1.0f64..1.0),
    ) {
        let reach = reach(&la, ra) + reach(&lb, rb);
        let a = build(&la, ra, (cx, cy));
        let b = build(&lb, rb, (cx + ux * reach, cy + uy * reach));
        prop_assume!(a.is_some() && b.is_some());
        let (a, b) = (a.unwrap_or_else(|| unreachable!()), b.unwrap_or_else(|| unreachable!()));
        let (new, old) = new_and_old(&a, &b);
        if let Err(e) = agree(&a, &b, &new, &old) {
            return Err(TestCaseError::fail(format!("{e}\nnew {new:?}\nold {old:?}\na {a:?}\nb {b:?}")));
        }
        // Swap: exact mirror (through `collide` too).
        let mut swapped = CollisionInfo::new(0);
        poly_to_poly(&b, &a, &mut swapped);
        prop_assert_eq!(swapped.normal, -new.normal);
        prop_assert_eq!(swapped.count, new.count);
        for (s, n) in swapped.contacts().iter().zip(new.contacts()) {
            prop_assert_eq!((s.point_a, s.point_b, s.distance), (n.point_b, n.point_a, n.distance));
            prop_assert_eq!(s.feature_id, n.feature_id.rotate_left(16));
        }
        let (ga, gb) = (Geometry::Poly(a), Geometry::Poly(b));
        let ab = collide(&ga, &gb, 0);
        let ba = collide(&gb, &ga, 0);
        prop_assert_eq!(ab.normal, -ba.normal);
        prop_assert_eq!(ab.count, ba.count);
        prop_assert!(!ab.hit_iteration_cap);
    }
}
