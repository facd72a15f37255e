//! Two peers of the small physics game in one process, over loopback UDP:
//! each runs its own Bevy app with a bevy_ggrs P2P session (one local
//! player, one remote), predicting the other's buttons and rolling back
//! when they arrive. Every frame both peers confirmed must have the same
//! physics checksum on both.
//!
//! `cargo run -p tamias2d-bevy --example p2p` prints the frames compared
//! and the rollbacks; `cargo test` runs the same check.
mod common;

use std::collections::BTreeMap;
use std::net::{SocketAddr, UdpSocket};

use bevy::prelude::*;
use common::{game_app, Config, Counters};
use tamias2d_bevy::bevy_ggrs::ggrs::UdpNonBlockingSocket;
use tamias2d_bevy::bevy_ggrs::prelude::*;
use tamias2d_bevy::bevy_ggrs::{
    ConfirmedFrameCount, RollbackFrameCount, SaveWorld, SaveWorldSystems,
};
use tamias2d_bevy::prelude::*;

/// Frames both peers must confirm.
const FRAMES: i32 = 300;

/// The physics checksum saved for each frame (the last save wins: a
/// re-simulation overwrites its frames). Not rolled back.
#[derive(Resource, Default)]
struct Saved(BTreeMap<i32, u64>);

fn record(mut saved: ResMut<Saved>, frame: Res<RollbackFrameCount>, physics: Res<Physics>) {
    saved.0.insert(frame.0, physics.checksum());
}

fn free_port() -> std::io::Result<u16> {
    Ok(UdpSocket::bind(("127.0.0.1", 0))?.local_addr()?.port())
}

/// Peer `me` of two, listening on `ports[me]`.
fn peer(me: usize, ports: [u16; 2]) -> Result<App, Box<dyn std::error::Error>> {
    let other = 1 - me;
    let remote = SocketAddr::from(([127, 0, 0, 1], ports[other]));
    let session = SessionBuilder::<Config>::new()
        .with_num_players(2)?
        // No input delay: the remote buttons of a frame always arrive late,
        // so each peer predicts them and rolls back when they change.
        .with_input_delay(0)
        .add_player(PlayerType::Local, me)?
        .add_player(PlayerType::Remote(remote), other)?
        .start_p2p_session(UdpNonBlockingSocket::bind_to_port(ports[me])?)?;
    let mut app = game_app(Session::P2P(session), vec![me]);
    app.init_resource::<Saved>()
        .add_systems(SaveWorld, record.after(SaveWorldSystems::Checksum));
    Ok(app)
}

/// What the two peers agreed on.
struct Agreement {
    compared: usize,
    differing: Vec<i32>,
    rollbacks: [u64; 2],
}

fn run_peers() -> Result<Agreement, Box<dyn std::error::Error>> {
    let ports = [free_port()?, free_port()?];
    let mut peers = [peer(0, ports)?, peer(1, ports)?];
    let confirmed = |app: &App| app.world().resource::<ConfirmedFrameCount>().0;
    // Both apps run on the same manual clock; a bound for a stalled link.
    for _ in 0..FRAMES * 20 {
        if peers.iter().all(|p| confirmed(p) >= FRAMES) {
            break;
        }
        for p in &mut peers {
            p.update();
        }
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    let last = confirmed(&peers[0]).min(confirmed(&peers[1]));
    if last < FRAMES {
        return Err(format!("the peers confirmed only {last} frames").into());
    }
    let [a, b] = [&peers[0], &peers[1]].map(|p| &p.world().resource::<Saved>().0);
    let frames = 1..=last;
    let differing = frames
        .clone()
        .filter(|f| a.get(f).is_none() || a.get(f) != b.get(f))
        .collect();
    Ok(Agreement {
        compared: frames.count(),
        differing,
        rollbacks: [&peers[0], &peers[1]].map(|p| p.world().resource::<Counters>().loads),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let agreement = run_peers()?;
    println!(
        "p2p: {} confirmed frames compared, {} differ; rollbacks {} and {}",
        agreement.compared,
        agreement.differing.len(),
        agreement.rollbacks[0],
        agreement.rollbacks[1]
    );
    if !agreement.differing.is_empty() {
        return Err(format!("frames differ: {:?}", agreement.differing).into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_peers_agree_on_every_confirmed_frame() {
        let agreement = run_peers().expect("the peers ran");
        assert!(agreement.compared >= FRAMES as usize);
        assert_eq!(agreement.differing, Vec::<i32>::new());
        // The check means something only if predictions were corrected.
        assert!(agreement.rollbacks.iter().sum::<u64>() > 0, "no rollback");
    }
}
