//! Sleeping islands (Chipmunk's model, Box2D's defaults): a group of
//! dynamic bodies that has rested for a while stops costing anything, and
//! wakes as a whole when something touches or changes it.
//!
//! * **Islands.** Dynamic bodies joined by the contacts the solver solved in
//!   the step (touching, not sensors, not ignored by a handler) and by
//!   constraints. Static and kinematic bodies join no island: a floor under
//!   two piles does not make them one island.
//! * **Falling asleep** (the sleep stage, after the solver): every awake dynamic
//!   body adds `dt` to its idle time while `|v|² + (I/m)·ω² ≤
//!   idle_speed_threshold²`, and restarts from 0 otherwise (and while it
//!   touches or is jointed to a moving kinematic body, or may not sleep). An
//!   island whose every body reached `sleep_time_threshold` falls asleep:
//!   its bodies' velocities and forces become exactly 0, each records the
//!   island's root (its lowest body slot), and every arbiter that no
//!   longer has an awake dynamic body moves to the dormant list with its
//!   contacts and impulses (their stamp holds their age meanwhile, so a
//!   nap does not age them).
//! * **Asleep.** The body is not integrated, its shapes are not rewritten
//!   and sit in the broadphase's sleeping tree (queried by moving shapes
//!   only, so sleeping shapes cost nothing against each other or statics),
//!   it is not in the narrowphase or the solver. Queries still see it.
//! * **Waking** (the whole island, in root order): the wake stage, when a moving
//!   shape (an awake dynamic body's, or a kinematic body's that moves or was
//!   changed through `body_mut`) touches a sleeping one (narrowphase, not
//!   just boxes; sensors and pairs a handler ignores do not wake); and
//!   through the API, at the call (so that a wake is state, never a
//!   pending event a snapshot could lose): `body_mut` and shape changes
//!   on one of its bodies or on a body touching it; a constraint added to
//!   or removed from one of its bodies, or changed (`constraint_mut`,
//!   `modify_constraint`: only the islands of the joint's dynamic bodies,
//!   as Chipmunk's setters); a
//!   shape added to or changed on a static or kinematic body wakes the
//!   islands its box overlaps; `set_settings` with new values wakes every
//!   island; [`Space::activate_body`]. A static or kinematic body moved by
//!   hand (`body_mut` then `set_position`) wakes what touched it before,
//!   but cannot know what it will touch after: call `activate_body` on it
//!   after moving it (Chipmunk's `cpBodyActivateStatic`), which wakes the
//!   islands its shapes' boxes overlap. The dormant arbiters
//!   come back with their impulses (warm starting: no pop on waking) and
//!   the step that woke them solves them.
//!
//! Every choice is made in slot order from state alone, and the sleep
//! records and dormant arbiters are world state (snapshots, checksum,
//! `first_difference`, validation).
use super::islands::{Islands, SleepScratch};
use super::{Space, SpaceError};
use crate::arbiter::Arbiter;
use crate::body::{Body, BodyHandle, BodyType};
use crate::collision::collide;
use crate::math::Real;

/// A dynamic body that is awake: the only kind that moves by itself.
fn awake_dynamic(b: &Body) -> bool {
    b.body_type() == BodyType::Dynamic && !b.is_sleeping()
}

/// A kinematic body with a velocity: it keeps what it touches awake.
fn moving_kinematic(b: &Body) -> bool {
    b.body_type() == BodyType::Kinematic
        && (b.velocity() != crate::math::Vect::ZERO || !b.angular_velocity().is_zero())
}

impl Space {
    /// [`Stage::Sleep`](super::Stage::Sleep): idle times, islands, and islands falling asleep. `active`
    /// holds the indices of the arbiters solved in this sub-step.
    pub(super) fn update_sleep(&mut self, dt: Real, active: &[u32]) {
        let settings = &self.state.settings;
        if !settings.sleeping_enabled() {
            return;
        }
        let (threshold, idle_speed) =
            (settings.sleep_time_threshold, settings.idle_speed_threshold);
        let bodies = &mut self.state.bodies;
        let mut awake = 0usize;
        for (_, b) in bodies.iter_mut() {
            if awake_dynamic(b) {
                awake = awake.saturating_add(1);
                b.sleep.idle_time = if b.sleep.allowed && b.is_idle(idle_speed) {
                    b.sleep.idle_time + dt
                } else {
                    Real::ZERO
                };
            }
        }
        // Everything asleep (a settled world): no island to build.
        if awake == 0 {
            return;
        }
        let mut scratch = core::mem::take(&mut self.caches.sleep);
        let SleepScratch {
            parent,
            restless,
            restless_slot,
            least,
        } = &mut scratch;
        let mut islands = Islands::new(parent, bodies.capacity_slots());
        restless.clear();
        let mut link =
            |a: &Body, ia: u32, b: &Body, ib: u32| match (awake_dynamic(a), awake_dynamic(b)) {
                (true, true) => islands.union(ia, ib),
                (true, false) if moving_kinematic(b) => restless.push(ia),
                (false, true) if moving_kinematic(a) => restless.push(ib),
                _ => {}
            };
        for &i in active {
            let Some(arb) = self.state.arbiters.get(i as usize) else {
                continue;
            };
            if let (Some(a), Some(b)) = (bodies.get(arb.body_a), bodies.get(arb.body_b)) {
                link(a, arb.body_a.index(), b, arb.body_b.index());
            }
        }
        for (_, c) in self.state.constraints.iter() {
            if let (Some(a), Some(b)) = (bodies.get(c.a), bodies.get(c.b)) {
                link(a, c.a.index(), b, c.b.index());
            }
        }
        let slots = bodies.capacity_slots();
        // Bodies that keep their island awake whatever the threshold (even
        // 0): those touching a moving kinematic body, and those that may
        // not sleep.
        restless_slot.clear();
        restless_slot.resize(slots, false);
        for &i in restless.iter() {
            if let Some((_, b)) = bodies.get_by_index_mut(i) {
                b.sleep.idle_time = Real::ZERO;
            }
            if let Some(r) = restless_slot.get_mut(i as usize) {
                *r = true;
            }
        }
        // The least idle time of each island, at its root (`Real::MIN`, below
        // any threshold, for an island with a restless body).
        least.clear();
        least.resize(slots, None);
        for (h, b) in bodies.iter() {
            if awake_dynamic(b) {
                let restless = !b.sleep.allowed
                    || restless_slot
                        .get(h.index() as usize)
                        .copied()
                        .unwrap_or(false);
                let idle = if restless {
                    Real::MIN
                } else {
                    b.sleep.idle_time
                };
                let root = islands.find(h.index());
                if let Some(l) = least.get_mut(root as usize) {
                    *l = Some(l.map_or(idle, |t| t.min(idle)));
                }
            }
        }
        let mut fell_asleep = false;
        for (h, b) in bodies.iter_mut() {
            if !awake_dynamic(b) {
                continue;
            }
            let root = islands.find(h.index());
            if least
                .get(root as usize)
                .copied()
                .flatten()
                .is_some_and(|t| t >= threshold)
            {
                b.fall_asleep(root);
                fell_asleep = true;
            }
        }
        self.caches.sleep = scratch;
        if fell_asleep {
            self.park_arbiters();
        }
    }

    /// Moves every arbiter without an awake dynamic body from the live
    /// list to the dormant list (both stay sorted by pair key); its stamp
    /// becomes its age.
    fn park_arbiters(&mut self) {
        let stamp = self.state.stamp;
        let bodies = &self.state.bodies;
        let parked = |a: &Arbiter| {
            !bodies.get(a.body_a).is_some_and(awake_dynamic)
                && !bodies.get(a.body_b).is_some_and(awake_dynamic)
        };
        let (mut going, staying): (Vec<Arbiter>, Vec<Arbiter>) =
            core::mem::take(&mut self.state.arbiters)
                .into_iter()
                .partition(|a| parked(a));
        self.state.arbiters = staying;
        for a in &mut going {
            a.stamp = stamp.saturating_sub(a.stamp);
        }
        let dormant = core::mem::take(&mut self.state.dormant_arbiters);
        self.state.dormant_arbiters = merge_by_key(dormant, going);
        self.caches.broadphase.sleepers_dirty = true;
        self.caches.broadphase.sleeping_count = None;
    }

    /// Wakes the islands whose roots are in `roots` (sorted, unique):
    /// their bodies, then their dormant arbiters, whose stamps become
    /// `last_stamp − age` (`last_stamp`: the last finished sub-step).
    pub(super) fn wake_islands(&mut self, roots: &[u32], last_stamp: u64) {
        if roots.is_empty() {
            return;
        }
        for (_, b) in self.state.bodies.iter_mut() {
            if b.sleep
                .island
                .is_some_and(|r| roots.binary_search(&r).is_ok())
            {
                b.wake();
            }
        }
        let bodies = &self.state.bodies;
        let has_awake = |a: &Arbiter| {
            bodies.get(a.body_a).is_some_and(awake_dynamic)
                || bodies.get(a.body_b).is_some_and(awake_dynamic)
        };
        let (mut back, staying): (Vec<Arbiter>, Vec<Arbiter>) =
            core::mem::take(&mut self.state.dormant_arbiters)
                .into_iter()
                .partition(|a| has_awake(a));
        self.state.dormant_arbiters = staying;
        for a in &mut back {
            a.stamp = last_stamp.saturating_sub(a.stamp);
        }
        let live = core::mem::take(&mut self.state.arbiters);
        self.state.arbiters = merge_by_key(live, back);
        self.caches.broadphase.sleepers_dirty = true;
        self.caches.broadphase.sleeping_count = None;
    }

    /// The island roots that body slot `i` being changed must wake: its own
    /// island, and those of sleeping bodies a dormant arbiter joins it to
    /// (a static or kinematic body under a sleeping pile).
    fn roots_touching(&self, i: u32) -> Vec<u32> {
        let mut roots = Vec::new();
        let root_of = |h: BodyHandle| self.state.bodies.get(h).and_then(|b| b.sleep.island);
        if let Some(r) = self
            .state
            .bodies
            .get_by_index(i)
            .and_then(|(_, b)| b.sleep.island)
        {
            roots.push(r);
        }
        for a in &self.state.dormant_arbiters {
            if a.body_a.index() == i {
                roots.extend(root_of(a.body_b));
            } else if a.body_b.index() == i {
                roots.extend(root_of(a.body_a));
            }
        }
        roots.sort_unstable();
        roots.dedup();
        roots
    }

    /// Wakes what a change to body `h` must wake (see [`roots_touching`]);
    /// called by the API operations that change a body, its shapes or its
    /// constraints, between steps.
    ///
    /// [`roots_touching`]: Space::roots_touching
    pub(super) fn wake_touching(&mut self, h: BodyHandle) {
        if self.state.dormant_arbiters.is_empty()
            && !self.state.bodies.get(h).is_some_and(Body::is_sleeping)
        {
            return;
        }
        let roots = self.roots_touching(h.index());
        self.wake_islands(&roots, self.state.stamp);
    }

    /// Wakes every sleeping body (settings changed, e.g. gravity).
    pub(super) fn wake_all(&mut self) {
        let mut roots: Vec<u32> = self
            .state
            .bodies
            .iter()
            .filter_map(|(_, b)| b.sleep.island)
            .collect();
        roots.sort_unstable();
        roots.dedup();
        self.wake_islands(&roots, self.state.stamp);
    }

    /// [`Stage::Wake`](super::Stage::Wake): wakes the islands that a moving shape touches, found among
    /// the broadphase's candidate pairs; true if any woke (the caller then
    /// redoes the shape-cache and broadphase stages with their shapes moving).
    pub(super) fn wake_touched_islands(&mut self) -> bool {
        if self.caches.broadphase.sleeping_tree.is_empty() {
            return false;
        }
        let mut roots = Vec::new();
        for &(ia, ib) in &self.caches.broadphase.sweep.pairs {
            let (Some((_, sa)), Some((_, sb))) = (
                self.state.shapes.get_by_index(ia),
                self.state.shapes.get_by_index(ib),
            ) else {
                continue;
            };
            let (Some(ba), Some(bb)) = (
                self.state.bodies.get(sa.body),
                self.state.bodies.get(sb.body),
            ) else {
                continue;
            };
            let mover = |b: &Body| awake_dynamic(b) || moving_kinematic(b);
            let root = match (ba.sleep.island, bb.sleep.island) {
                (Some(r), None) if mover(bb) => r,
                (None, Some(r)) if mover(ba) => r,
                _ => continue,
            };
            if sa.sensor
                || sb.sensor
                || sa.filter.rejects(&sb.filter)
                || self.caches.constraints.rejects(sa.body, sb.body)
            {
                continue;
            }
            let ignored = self
                .state
                .arbiters
                .binary_search_by_key(&(ia, ib), Arbiter::key)
                .ok()
                .and_then(|k| self.state.arbiters.get(k))
                .is_some_and(Arbiter::is_ignored);
            if ignored {
                continue;
            }
            let (Some(Some(ca)), Some(Some(cb))) = (
                self.caches.shapes.get(ia as usize),
                self.caches.shapes.get(ib as usize),
            ) else {
                continue;
            };
            if collide(&ca.geometry, &cb.geometry, 0).count > 0 {
                roots.push(root);
            }
        }
        if roots.is_empty() {
            return false;
        }
        roots.sort_unstable();
        roots.dedup();
        // Inside the sub-step, whose stamp is already counted.
        let last = self.state.stamp.saturating_sub(1);
        self.wake_islands(&roots, last);
        true
    }

    /// MIS-style `cpBodyActivate`: wakes the island of body `h` (and resets
    /// its idle time); a body that is awake just has its idle time reset.
    /// A static or kinematic body wakes the islands resting on it
    /// (Chipmunk's `cpBodyActivateStatic`).
    pub fn activate_body(&mut self, h: BodyHandle) -> Result<(), SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        if !self.state.bodies.contains(h) {
            return Err(SpaceError::StaleBody(h));
        }
        self.wake_touching(h);
        if self.state.bodies.get(h).is_some_and(|b| !b.is_dynamic()) {
            let boxes = self.shape_boxes_of(h);
            self.wake_overlapping(&boxes);
        }
        if let Some(b) = self.state.bodies.get_mut(h) {
            b.sleep.idle_time = Real::ZERO;
        }
        Ok(())
    }

    /// Wakes the islands with a shape whose box overlaps one of `boxes`,
    /// from the state alone (the sleeping shapes' world boxes are
    /// recomputed): what a static shape added or reshaped, or a static or
    /// kinematic body moved by hand, may now touch. Nothing to do, and O(1)
    /// once known, when no body sleeps (a level being built); otherwise it
    /// costs the sleeping shapes times `boxes`. API calls only.
    pub(super) fn wake_overlapping(&mut self, boxes: &[crate::math::BB]) {
        let roots = self.roots_overlapping(boxes);
        self.wake_islands(&roots, self.state.stamp);
    }

    /// The world boxes of body `h`'s shapes (through the per-body shape
    /// lists: no scan of the world's shapes).
    pub(super) fn shape_boxes_of(&mut self, h: BodyHandle) -> Vec<crate::math::BB> {
        let Some(body) = self.state.bodies.get(h) else {
            return Vec::new();
        };
        let (p, rot) = (body.position(), body.rotation());
        self.caches
            .body_shapes
            .of(&self.state.shapes, h)
            .into_iter()
            .filter_map(|i| self.state.shapes.get_by_index(i))
            .filter(|(_, s)| s.body == h)
            .map(|(_, s)| s.geometry.to_world(p, rot).bb())
            .collect()
    }

    /// The integrate-positions stage's part: a static or kinematic body that a custom position
    /// integrator moved wakes what touched it and what it now overlaps.
    pub(super) fn wake_for_moved(&mut self, h: BodyHandle) {
        let mut roots = self.roots_touching(h.index());
        let boxes = self.shape_boxes_of(h);
        roots.extend(self.roots_overlapping(&boxes));
        roots.sort_unstable();
        roots.dedup();
        // Inside the sub-step, whose stamp is already counted.
        let last = self.state.stamp.saturating_sub(1);
        self.wake_islands(&roots, last);
    }

    /// Whether some body sleeps: counted once after the sleeping set
    /// changed (or a state was loaded), then remembered.
    fn any_body_sleeps(&mut self) -> bool {
        let bodies = &self.state.bodies;
        let n = *self
            .caches
            .broadphase
            .sleeping_count
            .get_or_insert_with(|| bodies.iter().filter(|(_, b)| b.is_sleeping()).count());
        n > 0
    }

    /// The roots of the islands [`wake_overlapping`](Self::wake_overlapping) wakes.
    fn roots_overlapping(&mut self, boxes: &[crate::math::BB]) -> Vec<u32> {
        if boxes.is_empty() || !self.any_body_sleeps() {
            return Vec::new();
        }
        let state = &self.state;
        let mut roots: Vec<u32> = Vec::new();
        for (_, s) in state.shapes.iter() {
            let Some(b) = state.bodies.get(s.body) else {
                continue;
            };
            let Some(root) = b.sleep.island else {
                continue;
            };
            let bb = s.geometry.to_world(b.position(), b.rotation()).bb();
            if boxes.iter().any(|m| m.intersects(&bb)) {
                roots.push(root);
            }
        }
        roots.sort_unstable();
        roots.dedup();
        roots
    }

    /// Chipmunk's `cpBodySleep`: puts the island of dynamic body `h` (the
    /// bodies its touching contacts and constraints join it to) to sleep
    /// now, whatever their idle time. Errors: a body that is not dynamic,
    /// may not sleep, or whose island has a body that may not sleep or
    /// touches a moving kinematic body.
    pub fn sleep_body(&mut self, h: BodyHandle) -> Result<(), SpaceError> {
        self.sleep_island_of(h, None)
    }

    /// Chipmunk's `cpBodySleepWithGroup`: like [`sleep_body`](Self::sleep_body),
    /// but the island joins the sleeping island of `group`, so that waking
    /// either wakes both (e.g. a level section's bodies that should wake
    /// together). `group` must be asleep.
    pub fn sleep_body_with_group(
        &mut self,
        h: BodyHandle,
        group: BodyHandle,
    ) -> Result<(), SpaceError> {
        self.check_origin(group)?;
        let root = self
            .state
            .bodies
            .get(group)
            .ok_or(SpaceError::StaleBody(group))?
            .sleep
            .island
            .ok_or(SpaceError::Sleep("the group body is not asleep"))?;
        self.sleep_island_of(h, Some(root))
    }

    fn sleep_island_of(&mut self, h: BodyHandle, group: Option<u32>) -> Result<(), SpaceError> {
        self.check_unlocked()?;
        self.check_origin(h)?;
        let body = self.state.bodies.get(h).ok_or(SpaceError::StaleBody(h))?;
        if body.body_type() != BodyType::Dynamic {
            return Err(SpaceError::Sleep("only a dynamic body can sleep"));
        }
        if body.is_sleeping() {
            return Ok(());
        }
        // The island by the rules of the sleep stage: touching solved
        // contacts (live, touching in the last step, not sensors or
        // ignored) and constraints between awake dynamic bodies.
        let bodies = &self.state.bodies;
        // An API call, not per step: its own buffer.
        let mut parent = Vec::new();
        let mut islands = Islands::new(&mut parent, bodies.capacity_slots());
        let stamp = self.state.stamp;
        let mut pairs: Vec<(u32, u32, bool)> = Vec::new();
        for a in &self.state.arbiters {
            if a.stamp == stamp && !a.sensor && !a.is_ignored() && !a.is_cached() {
                pairs.push((a.body_a.index(), a.body_b.index(), false));
            }
        }
        for (_, c) in self.state.constraints.iter() {
            pairs.push((c.a.index(), c.b.index(), true));
        }
        let by_slot = |i: u32| bodies.get_by_index(i).map(|(_, b)| b);
        let mut restless = false;
        for &(ia, ib, _) in &pairs {
            if let (Some(a), Some(b)) = (by_slot(ia), by_slot(ib)) {
                if awake_dynamic(a) && awake_dynamic(b) {
                    islands.union(ia, ib);
                }
            }
        }
        let target = islands.find(h.index());
        for &(ia, ib, _) in &pairs {
            if let (Some(a), Some(b)) = (by_slot(ia), by_slot(ib)) {
                let touches_mover =
                    (awake_dynamic(a) && islands.find(ia) == target && moving_kinematic(b))
                        || (awake_dynamic(b) && islands.find(ib) == target && moving_kinematic(a));
                restless |= touches_mover;
            }
        }
        if restless {
            return Err(SpaceError::Sleep(
                "the island touches a moving kinematic body",
            ));
        }
        let members: Vec<u32> = bodies
            .iter()
            .filter(|(_, b)| awake_dynamic(b))
            .map(|(bh, _)| bh.index())
            .filter(|&i| islands.find(i) == target)
            .collect();
        if members
            .iter()
            .any(|&i| by_slot(i).is_some_and(|b| !b.sleep.allowed))
        {
            return Err(SpaceError::Sleep("a body of the island may not sleep"));
        }
        let root = group.unwrap_or(target);
        for i in members {
            if let Some((_, b)) = self.state.bodies.get_by_index_mut(i) {
                b.fall_asleep(root);
            }
        }
        self.park_arbiters();
        Ok(())
    }

    /// How many bodies are asleep.
    pub fn sleeping_bodies(&self) -> usize {
        self.state
            .bodies
            .iter()
            .filter(|(_, b)| b.is_sleeping())
            .count()
    }
}

/// Merges two lists sorted by pair key (keys unique across both).
fn merge_by_key(a: Vec<Arbiter>, b: Vec<Arbiter>) -> Vec<Arbiter> {
    if b.is_empty() {
        return a;
    }
    if a.is_empty() {
        return b;
    }
    let mut out = Vec::with_capacity(a.len().saturating_add(b.len()));
    let mut a = a.into_iter().peekable();
    let mut b = b.into_iter().peekable();
    loop {
        let take_a = match (a.peek(), b.peek()) {
            (Some(x), Some(y)) => x.key() <= y.key(),
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => break,
        };
        let next = if take_a { a.next() } else { b.next() };
        out.extend(next);
    }
    out
}
