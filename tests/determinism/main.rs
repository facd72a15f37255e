//! Determinism, rollback and desync tools, one test program (each former
//! test file is a module; `cargo test --test determinism <module>::` runs
//! one). The parallel step's thread counts have a program of their own
//! (`tests/parallel.rs`).
//!
//! * `scenes`: every built-in scene stepped twice, rebuilt from a snapshot
//!   or rolled back gives the same bits;
//! * `ggrs`: rollback through GGRS (sync test and two peers);
//! * `replay`: recorded runs verify, tampering is caught at its frame;
//! * `game_inputs`: replays of a game's own input type (button masks);
//! * `desync_coverage`: every field of the world state is seen by the
//!   desync tools (checksum, `first_difference`).
mod desync_coverage;
mod game_inputs;
mod ggrs;
mod replay;
mod scenes;
