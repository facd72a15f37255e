//! Extreme scenes, one test program (each former test file is a module;
//! `cargo test --test extremes <module>::` runs one), with their shared
//! helpers (`common`):
//!
//! * `diagnostics`: part 0, diagnostics and degenerate input;
//! * `translation`: part 1, far from the origin;
//! * `scale`: part 2, sizes and masses;
//! * `motion`: part 3, speed, overlap and time;
//! * `report`: the envelope report of `docs/numerics.md` (ignored: run it
//!   with `cargo test --release --test extremes -- --ignored --nocapture
//!   envelope_report`).
mod common;
mod diagnostics;
mod motion;
mod report;
mod scale;
mod translation;
