//! Spatial queries on the `pyramid_20` scene (a ground segment and 210 unit
//! boxes): what is under a point, what a ray hits first, what lies in a box,
//! and what a circle would touch. Queries read the world; they never change
//! it, so the checksum is the same before and after.
//!
//! ```text
//! cargo run --example queries
//! ```
use tamias2d::body::BodyType;
use tamias2d::math::{Real, Vect, BB};
use tamias2d::real;
use tamias2d::shape::{Circle, Geometry, ShapeFilter};
use tamias2d::space::{ShapeHandle, Space};
use tamias2d_scenes as scenes;

/// Where a shape's body is, for printing.
fn describe(space: &Space, h: ShapeHandle) -> String {
    let Some(body) = space.shape(h).and_then(|s| space.body(s.body())) else {
        return format!("{h:?} (gone)");
    };
    let p = body.position();
    let kind = match body.body_type() {
        BodyType::Static => "static",
        BodyType::Kinematic => "kinematic",
        BodyType::Dynamic => "box",
    };
    format!("{kind} {h:?} at ({:.1}, {:.1})", p.x.to_f64(), p.y.to_f64())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut scene = scenes::builtin("pyramid_20").ok_or("scene")?.build()?;
    scene.step_n(60)?; // one second: the pyramid has settled
    let space = &scene.space;
    let before = space.checksum();
    let all = ShapeFilter::ALL;

    // 1. Point query: the shape under a "mouse" at (0.2, 10.3), and every
    //    shape within 0.6 m of it.
    let mouse = Vect::new(real!(0.2), real!(10.3));
    if let Some((h, info)) = space.point_query_nearest(mouse, Real::ONE, all) {
        println!(
            "under the mouse: {} (distance {:.3}, negative = inside)",
            describe(space, h),
            info.distance.to_f64()
        );
    }
    let near = space.point_query(mouse, real!(0.6), all);
    println!("shapes within 0.6 m of the mouse: {}", near.len());

    // 2. Ray cast: a horizontal ray at y = 2.5 from the left; the first box
    //    it hits, and how many it crosses.
    let (a, b) = (
        Vect::new(real!(-30), real!(2.5)),
        Vect::new(real!(30), real!(2.5)),
    );
    if let Some((h, hit)) = space.segment_query_first(a, b, Real::ZERO, all) {
        println!(
            "ray y = 2.5 first hits {} at x = {:.3}, normal ({:.1}, {:.1})",
            describe(space, h),
            hit.point.x.to_f64(),
            hit.normal.x.to_f64(),
            hit.normal.y.to_f64()
        );
    }
    println!(
        "the ray crosses {} boxes",
        space.segment_query(a, b, Real::ZERO, all).len()
    );

    // 3. Box query: shapes whose bounding boxes touch a 2 x 2 m area at
    //    the apex.
    let area = BB::new(real!(-1), real!(17), real!(1), real!(19));
    let in_area = space.bb_query(area, all);
    println!(
        "bounding boxes touching [-1, 1] x [17, 19]: {}",
        in_area.len()
    );
    for h in &in_area {
        println!("  {}", describe(space, *h));
    }

    // 4. Shape query: what a circle of radius 1.5 sunk 0.1 m into the ground
    //    at x = 12 (beside the pyramid) would touch: the ground only.
    let probe = Geometry::Circle(Circle::new(real!(1.5), Vect::new(real!(12), real!(1.4))));
    for (h, contacts) in space.shape_query(&probe, all) {
        println!(
            "a circle at (12, 1.4) touches {} ({} contact point(s), depth {:.3})",
            describe(space, h),
            contacts.count,
            (-contacts.points[0].distance).to_f64()
        );
    }

    assert_eq!(space.checksum(), before, "queries do not change the world");
    println!("checksum: {before:#018x} (unchanged by the queries)");
    Ok(())
}
