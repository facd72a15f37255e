use tamias2d_scenes::character_level::{script, CharacterGame};
fn main() {
    let mut game = CharacterGame::new().unwrap();
    let every: u64 = std::env::var("EVERY").ok().and_then(|s| s.parse().ok()).unwrap_or(10);
    let upto: u64 = std::env::var("UPTO").ok().and_then(|s| s.parse().ok()).unwrap_or(1800);
    for f in 0..upto {
        game.step(&[script(f)]).unwrap();
        if f % every == 0 {
            let p = &game.players[0];
            let r = &game.last[0];
            println!("{f:5} pos ({:8.3},{:8.3}) v ({:6.2},{:6.2}) g={} gap={:?} wall={} ceil={} slope={} step={} snap={} push={} dep={:.4} carried={}",
                p.character.position.x.to_f64(), p.character.position.y.to_f64(),
                p.velocity.x.to_f64(), p.velocity.y.to_f64(), r.grounded as u8,
                r.ground_gap.map(|g| (g.to_f64()*1000.0).round()/1000.0), r.hit_wall as u8, r.hit_ceiling as u8, r.blocked_by_slope as u8, r.stepped as u8, r.snapped as u8, r.pushed, r.depenetration.to_f64(), r.carried_by.is_some() as u8);
        }
    }
}
