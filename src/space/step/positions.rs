//! [`Stage::IntegratePositions`](super::Stage::IntegratePositions): every awake body moves by its velocity
//! and bias velocity (or its custom position integrator). Body by body,
//! in pieces the threads share, when no custom integrator is set.
use crate::body::BodyType;
use crate::math::Real;

use super::super::Space;

impl Space {
    /// [`Stage::IntegratePositions`](super::Stage::IntegratePositions): `p += (v + v_bias)·dt` and the same for the angle.
    pub(super) fn integrate_positions(&mut self, dt: Real) {
        if self.integrators.position.is_empty() {
            // Without custom integrators, one path for any thread count:
            // body by body in pieces, halves in parallel where there are
            // threads (inline on one). The closures of custom integrators
            // run on the stepping thread, in slot order (the loop below):
            // the same bits, as each body moves alone.
            let level_touched = core::sync::atomic::AtomicBool::new(false);
            self.state
                .bodies
                .for_each_value_split(BODY_PIECE, &|body: &mut crate::body::Body| {
                    if body.is_sleeping() {
                        return;
                    }
                    if body.body_type() == BodyType::Static
                        && (body.v_bias != crate::math::Vect::ZERO || !body.w_bias.is_zero())
                    {
                        level_touched.store(true, core::sync::atomic::Ordering::Relaxed);
                    }
                    body.update_position(dt);
                });
            if level_touched.into_inner() {
                self.forget_level();
            }
            return;
        }
        let custom = &mut self.integrators.position;
        let mut moved_static = false;
        let mut level_touched = false;
        let mut moved_by_hand = Vec::new();
        for (h, body) in self.state.bodies.iter_mut() {
            if body.is_sleeping() {
                continue;
            }
            match custom.get_mut(&h) {
                Some(f) => {
                    // A custom integrator may move even a static body: its
                    // shapes' cache entries and the static tree are redone.
                    moved_static |= body.body_type() == BodyType::Static;
                    if !body.is_dynamic() {
                        moved_by_hand.push(h);
                    }
                    f(body, dt)
                }
                None => {
                    // Clearing a static body's bias velocities (set through
                    // the API) changes the level (`space::level`).
                    level_touched |= body.body_type() == BodyType::Static
                        && (body.v_bias != crate::math::Vect::ZERO || !body.w_bias.is_zero());
                    body.update_position(dt)
                }
            }
        }
        if level_touched {
            self.forget_level();
        }
        if moved_static {
            self.caches.broadphase.statics_dirty = true;
            self.forget_level();
        }
        // Sleeping piles do not see a static or kinematic body that an
        // integrator teleports (only velocities are noticed): wake them.
        for h in moved_by_hand {
            self.wake_for_moved(h);
        }
    }
}

/// Body slots per piece of the split body integrations (a few µs).
pub(super) const BODY_PIECE: usize = 256;
