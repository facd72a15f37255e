//! Regression tests, one test program: each module (formerly
//! `tests/regression_<name>.rs`) pins one fixed bug, its symptom, cause
//! and fix in its header. `cargo test --test regressions <module>::` runs
//! one.
mod body_replaced_in_place;
mod bullet_tunnelling;
mod chain_fall_through;
mod collide_symmetry;
mod float_conversions;
mod handle_origin;
mod handler_body_order;
mod hull_wide_extent;
mod massless_dynamic_body;
mod material_validation;
mod query_after_type_change;
mod rollback_callbacks;
mod shape_extent;
mod static_cache;
mod thin_ray_miss;
mod validated_state_can_step;
mod variable_dt;
