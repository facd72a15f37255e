//! Tamias2D in the browser: what the demo page (`web/static/`) runs.
//!
//! The engine compiled for `wasm32-unknown-unknown`, behind a thin API the
//! page's JavaScript calls: build a built-in scene or a scene JSON, step it,
//! read its shapes for drawing, drag a body with a joint, drop new bodies,
//! save and load a frame snapshot, and the two proofs the page exists for:
//! [`golden`] (the native goldens recomputed in the browser) and
//! [`lockstep`] (two peers, one rolling back, agreeing on every frame).
//!
//! Everything here is plain, safe Rust that also builds natively, so
//! `cargo test` tests it; only [`exports`] knows about the page (C-ABI
//! functions over one shared state and two byte buffers). No
//! `wasm-bindgen`: the API is a few dozen scalar functions and two
//! buffers, which a 200-line hand-written glue (`web/static/tamias.js`)
//! covers without a generator whose CLI must match the crate's version
//! (one more tool for CI to install and keep in step).
//!
//! Floats cross this API only as inputs (a pointer position, converted to
//! `Real` exactly once, the same way on every machine) and as drawing
//! output; nothing drawn flows back into the simulation.
// The engine's rules: no reachable panic (a panic in wasm traps and stops
// the page), no unchecked integer arithmetic.
#![cfg_attr(
    not(test),
    deny(
        clippy::arithmetic_side_effects,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]
pub mod draw;
pub mod exports;
pub mod golden;
pub mod lockstep;
pub mod play;

pub use play::Play;
