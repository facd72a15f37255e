use tamias2d::math::{Real, Vect, Rot};
use tamias2d::shape::ShapeFilter;
use tamias2d::space::{ShapeCast, StartContact};
use tamias2d_scenes::character_level::CharacterGame;
fn main() {
    let mut game = CharacterGame::new().unwrap();
    for _ in 0..3 { game.step(&[Default::default()]).unwrap(); }
    for c in &game.crates { let b = game.space.body(*c).unwrap(); println!("crate {:?}", b.position().to_f64()); }
    for (x, y, dx, dy, inf) in [(8.4, 0.71, 0.0667, 0.0, true), (8.4, 0.71, 0.0667, 0.0, false), (8.4, 0.71, 0.0667, -0.0028, true), (11.933, 0.71, 0.0667, -0.0028, true), (12.067, 0.71, 0.0667, -0.0028, true), (12.133, 0.68, 0.0667, -0.0028, true)] {
        let mut g = *game.config.shape();
        if inf { if let tamias2d::shape::Geometry::Segment(s) = &mut g { s.radius += Real::from_f64(0.01).unwrap(); } }
        let cast = ShapeCast::new(g, Vect::from_f64(x, y).unwrap(), Rot::IDENTITY, Vect::from_f64(dx, dy).unwrap()).with_start(StartContact::HitIfApproaching);
        let hits = game.space.shape_cast_all(&cast, ShapeFilter::ALL);
        println!("cast from ({x},{y}) by ({dx},{dy}) inflated {inf}:");
        for (h, c) in hits { println!("   {:?} t={} n={:?} p={:?}", h, c.fraction.to_f64(), c.normal.to_f64(), c.point.to_f64()); }
    }
}
