//! Collision micro-benchmarks (filled in with the collision module).
fn main() {}
