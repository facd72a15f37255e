//! Queries through the broadphase give exactly the results (and order) of
//! the scan of every shape. The oracle is a clone of the space: its caches
//! start empty, so its queries scan every shape.

use tamias2d::body::Body;
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::space::Space;
use tamias2d::{Real, Vect, BB};

struct Lcg(u64);
impl Lcg {
    fn next(&mut self, n: i32) -> i32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) % (n.max(1) as u64)) as i32
    }
    fn real(&mut self, lo: i32, hi: i32) -> Real {
        Real::ratio(self.next((hi - lo) * 16) + lo * 16, 16)
    }
    fn vect(&mut self) -> Vect {
        Vect::new(self.real(-40, 40), self.real(-40, 40))
    }
}

fn random_world(rng: &mut Lcg) -> Space {
    let mut space = Space::new();
    space.set_gravity(Vect::new(Real::ZERO, Real::from_int(-10)));
    let ground = space.add_body(Body::new_static()).unwrap();
    let mut dynamic = Vec::new();
    for i in 0..400 {
        let kind = rng.next(10);
        let body = if kind < 6 {
            ground
        } else {
            let mut b = if kind < 8 {
                Body::new(Real::ZERO, Real::ZERO).unwrap()
            } else {
                Body::new_kinematic()
            };
            b.set_position(rng.vect());
            let h = space.add_body(b).unwrap();
            dynamic.push(h);
            h
        };
        let p = if body == ground {
            rng.vect()
        } else {
            Vect::ZERO
        };
        let mut s = match rng.next(3) {
            0 => Shape::circle_shape_new(body, rng.real(0, 2), p).unwrap(),
            1 => Shape::segment_shape_new(
                body,
                p,
                p + rng.vect() * Real::ratio(1, 8),
                rng.real(0, 1),
            )
            .unwrap(),
            _ => Shape::box_shape_new(body, rng.real(1, 3), rng.real(1, 3), Real::ZERO).unwrap(),
        };
        s.set_mass(Real::ONE).unwrap();
        s.sensor = rng.next(8) == 0;
        if rng.next(6) == 0 {
            s.filter = ShapeFilter {
                group: 0,
                categories: 2,
                mask: u32::MAX,
            };
        }
        space.add_shape(s).unwrap();
        if i % 50 == 0 && !dynamic.is_empty() {
            // Reuse slots out of order.
            let h = dynamic.swap_remove(rng.next(dynamic.len() as i32) as usize);
            space.remove_body(h).unwrap();
        }
    }
    space
}

fn compare(space: &Space, rng: &mut Lcg, rays: usize) {
    let oracle = space.clone();
    assert!(!oracle.queries_use_broadphase());
    let filters = [
        ShapeFilter::ALL,
        ShapeFilter {
            group: 0,
            categories: 1,
            mask: 1,
        },
    ];
    for i in 0..rays {
        let (a, b) = (rng.vect(), rng.vect());
        // Short rays as well as long ones.
        let b = if i % 2 == 0 {
            a + (b - a) * Real::ratio(1, 8)
        } else {
            b
        };
        let r = if i % 3 == 0 {
            Real::ZERO
        } else {
            rng.real(0, 2)
        };
        let f = filters[i % 2];
        assert_eq!(
            space.segment_query(a, b, r, f),
            oracle.segment_query(a, b, r, f)
        );
        assert_eq!(
            space.segment_query_first(a, b, r, f),
            oracle.segment_query_first(a, b, r, f)
        );
        let d = rng.real(0, 4);
        assert_eq!(space.point_query(a, d, f), oracle.point_query(a, d, f));
        assert_eq!(
            space.point_query_nearest(a, d, f),
            oracle.point_query_nearest(a, d, f)
        );
        let bb = BB::for_point(a).expand(b);
        assert_eq!(space.bb_query(bb, f), oracle.bb_query(bb, f));
    }
}

#[test]
fn broadphase_queries_equal_the_full_scan() {
    let mut rng = Lcg(11);
    for _ in 0..3 {
        let mut space = random_world(&mut rng);
        compare(&space, &mut rng, 50);
        let dt = Real::ratio(1, 60);
        for _ in 0..3 {
            space.step(dt).unwrap();
        }
        assert!(space.queries_use_broadphase());
        let hits: usize = (0..50)
            .map(|_| {
                let (a, b) = (rng.vect(), rng.vect());
                space
                    .segment_query(a, b, Real::ZERO, ShapeFilter::ALL)
                    .len()
            })
            .sum();
        assert!(hits > 50, "rays hit things ({hits})");
        compare(&space, &mut rng, 300);
        // Moving bodies by hand (no step): still exact.
        let moved: Vec<_> = space
            .bodies()
            .filter(|(_, b)| b.body_type() != tamias2d::body::BodyType::Static)
            .map(|(h, _)| h)
            .take(20)
            .collect();
        for h in moved {
            let p = rng.vect();
            space.body_mut(h).unwrap().set_position(p);
        }
        assert!(space.queries_use_broadphase());
        compare(&space, &mut rng, 200);
    }
}
