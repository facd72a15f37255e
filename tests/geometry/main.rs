//! Geometry: the narrow phase, shapes, queries, the broadphase's trees and
//! the fixed-point trigonometry, one test program (each former test file
//! is a module; `cargo test --test geometry <module>::` runs one).
//!
//! * `collision`: property tests of the narrow phase;
//! * `polygon_manifold`: the separating-axis polygon path against GJK + EPA;
//! * `shapes`: convex hull, polygon construction, mass helpers;
//! * `queries`: the space-level queries and the geometry queries;
//! * `query_broadphase`: queries through the broadphase equal a full scan;
//! * `shape_casts`: the shape casts against a fine-stepped reference, and
//!   on the space;
//! * `static_tree_rebuilds`: the static tree is rebuilt only when needed;
//! * `math_trig`: `tamias2d::math::trig` against an `f64` oracle.
mod collision;
mod math_trig;
mod polygon_manifold;
mod queries;
mod query_broadphase;
mod shape_casts;
mod shapes;
mod static_tree_rebuilds;
