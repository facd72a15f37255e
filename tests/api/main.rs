//! The public API's contracts, one test program (each former test file is
//! a module; `cargo test --test api <module>::` runs one).
//!
//! * `edges`: bad input is a clear error that leaves the world unchanged;
//!   custom integration;
//! * `handlers`: collision handlers and post-step callbacks;
//! * `untrusted_limits`: limits for untrusted bytes;
//! * `debug_draw`: debug drawing (feature `debug-draw`);
//! * `step_validation`: validation builds check every step;
//! * `architecture`: the library's imports follow the layer table of
//!   `docs/architecture.md`, without circles, and the step table names
//!   the stages in run order.
mod architecture;
mod debug_draw;
mod edges;
mod handlers;
mod step_validation;
mod untrusted_limits;
