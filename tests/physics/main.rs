//! Physics: bodies in motion, contact, joints and sleep, one test program
//! (each former test file is a module; `cargo test --test physics <module>::`
//! runs one).
//!
//! * `closed_forms`: accuracy against closed forms (free fall, projectiles,
//!   spin, elastic collisions, Newton's cradle, the incline);
//! * `stacking`: resting contact and stacking;
//! * `chain`, `platformer`: smooth terrain (chains);
//! * `character`: the kinematic character mover;
//! * `constraints`: joints;
//! * `joint_setters`: joints driven in place (setters, warm start, waking);
//! * `sleep`: sleeping islands;
//! * `bullets`: continuous collision;
//! * `settings_switches`: sub-steps and the solver switches;
//! * `mirror_symmetry`: a mirrored scene evolves as the exact mirror;
//! * `rapier_joints`: the joint scenes as Rapier worlds (the performance
//!   report's converter).
mod bullets;
mod chain;
mod character;
mod closed_forms;
mod constraints;
mod joint_setters;
mod mirror_symmetry;
mod platformer;
mod rapier_joints;
mod settings_switches;
mod sleep;
mod soft_step;
mod stacking;
