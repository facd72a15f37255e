//! A small physics game under bevy_ggrs, shared by the `synctest` and `p2p`
//! examples: two player balls in a box, driven by button masks, with crates
//! that rain in, and are despawned, while rollbacks happen.
//!
//! Everything the game adds to rollback is its own: the frame counter and
//! the score. The physics (bodies, colliders, the world) is registered by
//! `TamiasPlugin::rollback()`.
#![allow(dead_code)] // each example uses a part

use std::hash::Hash;

use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use core::time::Duration;
use tamias2d::constraint::PivotJoint;
use tamias2d::{real, Real, Vect};
use tamias2d_bevy::bevy_ggrs::prelude::*;
use tamias2d_bevy::bevy_ggrs::{
    LoadWorld, LocalInputs, RollbackDespawnCommandExtension, RollbackFrameCount,
};
use tamias2d_bevy::prelude::*;

/// Push left.
pub const LEFT: u8 = 1 << 0;
/// Push right.
pub const RIGHT: u8 = 1 << 1;
/// Jump.
pub const JUMP: u8 = 1 << 2;

/// The GGRS configuration: one byte of buttons per player.
pub type Config = GgrsConfig<u8>;

/// A player's ball.
#[derive(Component, Clone, Copy)]
pub struct Player(pub usize);

/// A crate, with the frame it was spawned on.
#[derive(Component, Clone, Copy)]
pub struct Crate {
    born: u32,
}

/// Frames simulated (rolled back).
#[derive(Resource, Clone, Copy, Default, Hash)]
pub struct GameFrame(pub u32);

/// Contacts that began between a player and a crate (rolled back, hashed
/// into the checksum): game logic reading the physics' contact lists.
#[derive(Resource, Clone, Copy, Default, Hash)]
pub struct Score(pub u32);

/// Not rolled back: how many times the real clock asked for inputs, and
/// how many rollbacks ran.
#[derive(Resource, Default)]
pub struct Counters {
    pub input_reads: u64,
    pub loads: u64,
}

/// Test hook: when set, the 100th simulated frame (re-simulations count)
/// nudges player 0 from state outside the snapshot, the classic desync.
#[derive(Resource, Default)]
pub struct Sabotage {
    pub on: bool,
    pub simulated: u32,
}

/// The scripted buttons of `player` at input read `n` (both peers of the
/// P2P example script their own player the same way).
pub fn scripted_buttons(player: usize, n: u64) -> u8 {
    let phase = (n / 20 + player as u64 * 3) % 6;
    match phase {
        0 | 1 => RIGHT,
        2 => JUMP | LEFT,
        3 | 4 => LEFT,
        _ => JUMP,
    }
}

/// The app of the game around a session, headless, one frame per update.
pub fn game_app(session: Session<Config>, local_players: Vec<usize>) -> App {
    let mut app = App::new();
    app.add_plugins(MinimalPlugins)
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_nanos(
            1_000_000_000 / 60,
        )))
        .add_plugins(GgrsPlugin::<Config>::default())
        .add_plugins(TamiasPlugin::rollback())
        .insert_resource(session)
        .insert_resource(LocalScript(local_players))
        .init_resource::<GameFrame>()
        .init_resource::<Score>()
        .init_resource::<Counters>()
        .init_resource::<Sabotage>()
        .init_resource::<Pile>()
        .rollback_resource_with_copy::<GameFrame>()
        .rollback_resource_with_copy::<Score>()
        .checksum_resource_with_hash::<Score>()
        .rollback_component_with_copy::<Player>()
        .rollback_component_with_copy::<Crate>()
        .rollback_component_with_copy::<Ledge>()
        .add_systems(Startup, setup)
        .add_systems(ReadInputs, read_inputs)
        .add_systems(LoadWorld, count_loads)
        .add_systems(
            GgrsSchedule,
            (
                tick,
                push_players,
                rain_crates,
                clear_crates,
                move_the_ledge,
                sabotage,
            )
                .chain()
                .before(PhysicsSystems::Step),
        )
        .add_systems(GgrsSchedule, keep_score.after(PhysicsSystems::Step));
    app
}

/// Boxes piled on the floor at the start (0 by default): a heavier world
/// for timing the rollback (`synctest -- --pile 300`).
#[derive(Resource, Default)]
pub struct Pile(pub i32);

/// Which players this app scripts.
#[derive(Resource)]
struct LocalScript(Vec<usize>);

fn setup(mut commands: Commands, mut physics: ResMut<Physics>, pile: Res<Pile>) {
    physics.set_dt(Real::ratio(1, 60));
    for i in 0..pile.0 {
        let (column, row) = (i % 20 - 10, 1 + i / 20);
        commands.spawn((
            RigidBody::dynamic().at(Vect::new(
                Real::from_int(column) * Real::HALF,
                Real::from_int(row) * Real::HALF,
            )),
            Collider::rectangle(real!(0.45), real!(0.45)),
        ));
    }
    // The box: floor and walls (static bodies).
    let wall = |a: Vect, b: Vect| {
        (
            RigidBody::fixed(),
            Collider::segment(a, b, real!(0.1)).with_material(Real::ONE, Real::ZERO),
        )
    };
    commands.spawn(wall(Vect::from_ints(-10, 0), Vect::from_ints(10, 0)));
    commands.spawn(wall(Vect::from_ints(-10, 0), Vect::from_ints(-10, 12)));
    commands.spawn(wall(Vect::from_ints(10, 0), Vect::from_ints(10, 12)));
    for (player, x) in [(0, -4), (1, 4)] {
        commands.spawn((
            Player(player),
            RigidBody::dynamic().at(Vect::from_ints(x, 2)),
            Collider::circle(real!(0.6)).with_material(real!(0.8), Real::ZERO),
        ));
    }
}

fn read_inputs(mut commands: Commands, script: Res<LocalScript>, mut counters: ResMut<Counters>) {
    let n = counters.input_reads;
    counters.input_reads += 1;
    let inputs: HashMap<_, _> = script
        .0
        .iter()
        .map(|&p| (p, scripted_buttons(p, n)))
        .collect();
    commands.insert_resource(LocalInputs::<Config>(inputs));
}

fn count_loads(mut counters: ResMut<Counters>) {
    counters.loads += 1;
}

fn tick(mut frame: ResMut<GameFrame>) {
    frame.0 += 1;
}

fn push_players(
    inputs: Res<PlayerInputs<Config>>,
    players: Query<(&Player, &RigidBody)>,
    mut physics: ResMut<Physics>,
) {
    // Forces on different bodies commute: query order does not matter.
    for (player, rb) in &players {
        let (Some(&(buttons, _)), Some(handle)) = (inputs.get(player.0), rb.handle()) else {
            continue;
        };
        let Some(body) = physics.space_mut().body_mut(handle) else {
            continue;
        };
        let mut force = Vect::ZERO;
        if buttons & LEFT != 0 {
            force.x = real!(-40);
        }
        if buttons & RIGHT != 0 {
            force.x = real!(40);
        }
        body.apply_force_at_local_point(force, Vect::ZERO);
        let on_ground = body.position().y < real!(0.8) && body.velocity().y.abs() < real!(0.5);
        if buttons & JUMP != 0 && on_ground {
            body.apply_impulse_at_local_point(Vect::new(Real::ZERO, real!(6)), Vect::ZERO);
        }
    }
}

/// A crate every 25 frames, dropped at a place the frame number picks.
fn rain_crates(mut commands: Commands, frame: Res<GameFrame>) {
    if !frame.0.is_multiple_of(25) {
        return;
    }
    let x = Real::from_int(((frame.0 / 25) * 7 % 17) as i32 - 8);
    commands.spawn((
        Crate { born: frame.0 },
        RigidBody::dynamic().at(Vect::new(x, real!(10))),
        Collider::rectangle(real!(0.8), real!(0.8)).with_density(real!(0.5)),
    ));
}

/// A static ledge appears at frame 300, with a weight hanging from it by a
/// pivot joint, and all three go at frame 450: the level itself, and a
/// joint between entities, come and go inside the rollback window.
fn move_the_ledge(
    mut commands: Commands,
    frame: Res<GameFrame>,
    ledges: Query<Entity, With<Ledge>>,
) {
    if frame.0 == 300 {
        let ledge = commands
            .spawn((
                Ledge,
                RigidBody::fixed().at(Vect::from_ints(0, 4)),
                Collider::rectangle(real!(6), real!(0.4)),
            ))
            .id();
        let weight = commands
            .spawn((
                Ledge,
                RigidBody::dynamic().at(Vect::new(real!(2.5), real!(3))),
                Collider::circle(real!(0.3)),
            ))
            .id();
        // Commands apply in order: both bodies exist when the joint is built.
        if let Ok(pivot) = PivotJoint::new(Vect::new(real!(1.5), Real::ZERO), Vect::ZERO) {
            commands.spawn((Ledge, Joint::new(ledge, weight, pivot)));
        }
    }
    if frame.0 == 450 {
        for ledge in &ledges {
            commands.entity(ledge).despawn();
        }
    }
}

/// The ledge.
#[derive(Component, Clone, Copy)]
pub struct Ledge;

/// Crates live 150 frames; half leave through bevy_ggrs' deferred
/// despawn, half through a plain despawn: rollback handles both.
fn clear_crates(mut commands: Commands, frame: Res<GameFrame>, crates: Query<(Entity, &Crate)>) {
    for (entity, c) in &crates {
        if frame.0 == c.born + 150 {
            if c.born.is_multiple_of(50) {
                commands.entity(entity).despawn_rollback();
            } else {
                commands.entity(entity).despawn();
            }
        }
    }
}

fn sabotage(
    mut sabotage: ResMut<Sabotage>,
    mut physics: ResMut<Physics>,
    players: Query<(&Player, &RigidBody)>,
) {
    if !sabotage.on {
        return;
    }
    sabotage.simulated += 1;
    if sabotage.simulated != 100 {
        return;
    }
    for (player, rb) in &players {
        if player.0 == 0 {
            if let Some(body) = rb.handle().and_then(|h| physics.space_mut().body_mut(h)) {
                let v = body.velocity();
                body.set_velocity(v + Vect::new(real!(0.001), Real::ZERO));
            }
        }
    }
}

fn keep_score(
    mut score: ResMut<Score>,
    physics: Res<Physics>,
    players: Query<&Player>,
    crates: Query<&Crate>,
) {
    for contact in physics.contacts_started() {
        let (Some(a), Some(b)) = contact.entities else {
            continue;
        };
        let player_and_crate = (players.contains(a) && crates.contains(b))
            || (players.contains(b) && crates.contains(a));
        if player_and_crate {
            score.0 += 1;
        }
    }
}

/// Runs `app` until its session has simulated `frames` frames (or a
/// generous bound of updates, for a session that stalls).
pub fn run_frames(app: &mut App, frames: i32) {
    for _ in 0..frames * 4 + 100 {
        if app.world().resource::<RollbackFrameCount>().0 >= frames {
            break;
        }
        app.update();
    }
}
