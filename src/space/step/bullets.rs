//! [`Stage::Bullets`](super::Stage::Bullets): each bullet swept from its
//! pose before the step to where the integration put it, against the
//! static shapes its swept box reaches and the kinematic bodies' shapes,
//! and put back at the earliest time of impact. The sweep itself (motions,
//! conservative advancement) is `space::ccd`'s; this is the stage that
//! runs it on the space.
use crate::arbiter::Arbiter;
use crate::body::{BodyHandle, BodyType};
use crate::math::Real;

use super::super::ccd::{half_thickness, reach, time_of_impact, Motion, Pose, Swept, DELTA_MAX};
use super::super::Space;
use super::shape_caches::ShapeCache;

impl Space {
    /// Before the integrate-positions stage: the poses of the bullets (and, if there is one, of
    /// the kinematic bodies) the sweep starts from.
    pub(super) fn record_sweep_starts(&mut self) {
        let ccd = &mut self.caches.ccd;
        ccd.bullets.clear();
        ccd.kinematic.clear();
        ccd.hits = 0;
        let bodies = &self.state.bodies;
        ccd.bullets.extend(
            bodies
                .iter()
                .filter(|(_, b)| b.bullet && b.body_type == BodyType::Dynamic)
                .map(|(h, b)| (h, Pose::of(b))),
        );
        if ccd.bullets.is_empty() {
            return;
        }
        ccd.kinematic.extend(
            bodies
                .iter()
                .filter(|(_, b)| b.body_type == BodyType::Kinematic)
                .map(|(h, b)| (h, Pose::of(b))),
        );
    }

    /// [`Stage::Bullets`](super::Stage::Bullets): sweeps each bullet and pulls it back to its earliest time
    /// of impact (see the module docs); rewrites its shapes' caches and
    /// broadphase boxes. Nothing to do without bullets.
    pub(super) fn sweep_bullets(&mut self) {
        if self.caches.ccd.bullets.is_empty() {
            return;
        }
        self.update_static_tree();
        self.update_constraint_filter();
        let bullets = core::mem::take(&mut self.caches.ccd.bullets);
        for &(h, start) in &bullets {
            if let Some(impact) = self.bullet_impact(h, start) {
                self.move_bullet(h, start, impact);
            }
        }
        self.caches.ccd.bullets = bullets;
    }

    /// The earliest time of impact of bullet `h` (which started the
    /// sub-step at `start`) with a static or kinematic shape.
    fn bullet_impact(&mut self, h: BodyHandle, start: Pose) -> Option<Impact> {
        let body = self.state.bodies.get(h)?;
        let motion = Motion::new(start, body);
        let slop = self.state.settings.collision_slop;
        let own = self.caches.body_shapes.of(&self.state.shapes, h);
        let mut candidates = core::mem::take(&mut self.caches.ccd.candidates);
        let mut best: Option<Impact> = None;
        for ia in own {
            let Some((_, sa)) = self.state.shapes.get_by_index(ia) else {
                continue;
            };
            let Some(end) = self.caches.shapes.get(ia as usize).and_then(Option::as_ref) else {
                continue;
            };
            if sa.sensor {
                continue;
            }
            let a = Swept {
                local: &sa.geometry,
                motion,
                reach: reach(&sa.geometry, body.cog),
            };
            // Half its half thickness (Box2D v3's margin): moving less is
            // slow; no sweep takes it deeper into what it touches.
            let margin = half_thickness(&sa.geometry) * Real::HALF;
            let bb = a.swept_bb(&end.bb, DELTA_MAX);
            candidates.clear();
            if a.motion.dp.length() + a.turn_bound() >= margin {
                self.caches
                    .broadphase
                    .static_tree
                    .query(&bb, |i| candidates.push(i));
            }
            for &ib in &candidates {
                let Some(b) = self.static_target(ib) else {
                    continue;
                };
                if self.pair_is_swept(ia, ib) {
                    let toi = time_of_impact(&a, &b, slop, margin);
                    best = earlier(best, toi.map(|t| Impact { t, carrier: None }));
                }
            }
            for &(kh, kstart) in &self.caches.ccd.kinematic {
                let Some(kbody) = self.state.bodies.get(kh) else {
                    continue;
                };
                let kmotion = Motion::new(kstart, kbody);
                let Some(kshapes) = self.caches.body_shapes.built(kh.index()) else {
                    continue;
                };
                for &ib in kshapes {
                    let Some((_, sb)) = self.state.shapes.get_by_index(ib) else {
                        continue;
                    };
                    let Some(kend) = self.caches.shapes.get(ib as usize).and_then(Option::as_ref)
                    else {
                        continue;
                    };
                    let b = Swept {
                        local: &sb.geometry,
                        motion: kmotion,
                        reach: reach(&sb.geometry, kbody.cog),
                    };
                    if b.swept_bb(&kend.bb, Real::ZERO).intersects(&bb)
                        && self.pair_is_swept(ia, ib)
                    {
                        let toi = time_of_impact(&a, &b, slop, margin);
                        let carrier = Some(kmotion);
                        best = earlier(best, toi.map(|t| Impact { t, carrier }));
                    }
                }
            }
        }
        self.caches.ccd.candidates = candidates;
        best
    }

    /// The static shape in slot `i` as a sweep target.
    fn static_target(&self, i: u32) -> Option<Swept<'_>> {
        let (_, s) = self.state.shapes.get_by_index(i)?;
        let body = self.state.bodies.get(s.body)?;
        Some(Swept {
            local: &s.geometry,
            motion: Motion::fixed(body),
            reach: Real::ZERO,
        })
    }

    /// True if shapes `ia` (a bullet's) and `ib` could make a contact: the
    /// narrowphase's filter (different bodies, filters, sensors, joints),
    /// and not a pair a begin handler rejected (ignored until it separates).
    fn pair_is_swept(&self, ia: u32, ib: u32) -> bool {
        let (Some((_, sa)), Some((_, sb))) = (
            self.state.shapes.get_by_index(ia),
            self.state.shapes.get_by_index(ib),
        ) else {
            return false;
        };
        let key = (ia.min(ib), ia.max(ib));
        let arbiters = &self.state.arbiters;
        let ignored = arbiters
            .binary_search_by_key(&key, Arbiter::key)
            .ok()
            .and_then(|k| arbiters.get(k))
            .is_some_and(Arbiter::is_ignored);
        sa.body != sb.body
            && !sb.sensor
            && !sa.filter.rejects(&sb.filter)
            && !self.caches.constraints.rejects(sa.body, sb.body)
            && !ignored
    }

    /// Puts bullet `h` at the time of `impact` on its path (carried on by
    /// a kinematic body it hit for the rest of the sub-step) and rewrites
    /// its shapes' caches and broadphase boxes (the shape-cache stage's work for the new
    /// pose).
    fn move_bullet(&mut self, h: BodyHandle, start: Pose, impact: Impact) {
        let Some(body) = self.state.bodies.get_mut(h) else {
            return;
        };
        let at = Motion::new(start, body).at(impact.t);
        let (p, a, rot) = match impact.carrier {
            Some(k) => k.carry(impact.t, at),
            None => at,
        };
        body.p = p;
        body.a = a;
        body.rot = rot;
        let (origin, rot) = (body.position(), body.rotation());
        self.caches.ccd.hits = self.caches.ccd.hits.saturating_add(1);
        let Some(own) = self.caches.body_shapes.built(h.index()) else {
            return;
        };
        for &i in own {
            let Some((_, s)) = self.state.shapes.get_by_index(i) else {
                continue;
            };
            let geometry = s.geometry.to_world(origin, rot);
            let bb = geometry.bb();
            if let Some(entry) = self.caches.shapes.get_mut(i as usize) {
                *entry = Some(ShapeCache {
                    geometry,
                    bb,
                    is_static: false,
                });
            }
            let proxies = &mut self.caches.broadphase.proxies;
            if let Ok(k) = proxies.binary_search_by_key(&i, |p| p.index) {
                if let Some(proxy) = proxies.get_mut(k) {
                    proxy.bb = bb;
                }
            }
        }
    }
}

/// A bullet's earliest impact in a sub-step.
#[derive(Clone, Copy, Debug)]
struct Impact {
    /// Time of impact, in `[0, 1)`.
    t: Real,
    /// The kinematic body hit (the bullet moves on with it after `t`, so
    /// that the two are in the pose of the impact at the end of the
    /// sub-step), or `None` for a static shape.
    carrier: Option<Motion>,
}

/// The earlier of two impacts; the first one on a tie (candidates come in
/// a fixed order: the bullet's shapes in slot order, for each the static
/// shapes in tree order, then the kinematic bodies in slot order).
fn earlier(a: Option<Impact>, b: Option<Impact>) -> Option<Impact> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.t < x.t { y } else { x }),
        (x, None) => x,
        (None, y) => y,
    }
}
