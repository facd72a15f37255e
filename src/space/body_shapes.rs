//! Which shapes each body owns: a cache derived from the shape arena (each
//! shape names its body), never state and never serialized. It lets
//! `add_shape`, `remove_shape` and `remove_body` touch only the body
//! concerned instead of scanning every shape of the world.
//!
//! The lists hold shape slot indices in ascending order, so walking a list
//! visits the body's shapes in slot order, the canonical order in which the
//! mass is summed (exactly the order of a scan of the whole arena).

use crate::arena::Arena;
use crate::body::BodyHandle;
use crate::shape::Shape;

/// Per body slot: the slot indices of its shapes, ascending. `None` until
/// built from the arena (after a new space, a clone or a restored state: one
/// scan of the shapes, then kept up to date by the edits).
#[derive(Default)]
pub(crate) struct BodyShapes {
    lists: Option<Vec<Vec<u32>>>,
}

impl BodyShapes {
    /// Forgets the lists (the shape arena was replaced); the next use
    /// rebuilds them.
    pub(crate) fn invalidate(&mut self) {
        self.lists = None;
    }

    /// Brings built lists up to date after a frame was installed around an
    /// unchanged level (`space::frame`): the lists of the level's bodies
    /// (whose shapes are all level shapes) stay; every other body's list is
    /// rebuilt from the shapes outside the level. Costs the frame, not the
    /// level, and keeps queries on the broadphase after a rollback.
    pub(crate) fn refresh_frame(
        &mut self,
        shapes: &Arena<Shape>,
        body_runs: &[(u32, u32)],
        shape_runs: &[(u32, u32)],
    ) {
        let Some(lists) = self.lists.as_mut() else {
            return;
        };
        for i in crate::arena::outside_runs(body_runs, lists.len() as u32) {
            if let Some(list) = lists.get_mut(i as usize) {
                list.clear();
            }
        }
        for i in crate::arena::outside_runs(shape_runs, shapes.capacity_slots() as u32) {
            if let Some((_, s)) = shapes.get_by_index(i) {
                push_sorted(lists, s.body.index(), i);
            }
        }
    }

    /// The lists, built from `shapes` if they are not.
    fn lists(&mut self, shapes: &Arena<Shape>) -> &mut Vec<Vec<u32>> {
        self.lists.get_or_insert_with(|| {
            let mut lists: Vec<Vec<u32>> = Vec::new();
            for (sh, s) in shapes.iter() {
                push_sorted(&mut lists, s.body.index(), sh.index());
            }
            lists
        })
    }

    /// Records that shape slot `shape` (already in `shapes`) belongs to
    /// `body`.
    pub(crate) fn insert(&mut self, shapes: &Arena<Shape>, body: BodyHandle, shape: u32) {
        let built = self.lists.is_some();
        let lists = self.lists(shapes);
        // Freshly built lists already hold the new shape.
        if built {
            push_sorted(lists, body.index(), shape);
        }
    }

    /// Records that shape slot `shape` no longer belongs to `body` (call
    /// with the shape still in `shapes` or already removed: either way the
    /// lists end up without it).
    pub(crate) fn remove(&mut self, shapes: &Arena<Shape>, body: BodyHandle, shape: u32) {
        let lists = self.lists(shapes);
        if let Some(list) = lists.get_mut(body.index() as usize) {
            if let Ok(at) = list.binary_search(&shape) {
                list.remove(at);
            }
        }
    }

    /// The slot indices of `body`'s shapes, ascending (a copy: the caller
    /// may edit the space while walking it).
    pub(crate) fn of(&mut self, shapes: &Arena<Shape>, body: BodyHandle) -> Vec<u32> {
        self.lists(shapes)
            .get(body.index() as usize)
            .cloned()
            .unwrap_or_default()
    }

    /// The slot indices of the shapes of the body in slot `body`,
    /// ascending, if the lists are built (`None` otherwise: read-only
    /// callers fall back to a scan).
    pub(crate) fn built(&self, body: u32) -> Option<&[u32]> {
        let lists = self.lists.as_ref()?;
        Some(lists.get(body as usize).map_or(&[][..], Vec::as_slice))
    }

    /// Calls `f` on each shape of `body` in slot order.
    pub(crate) fn for_each<'a>(
        &mut self,
        shapes: &'a Arena<Shape>,
        body: BodyHandle,
        mut f: impl FnMut(&'a Shape),
    ) {
        let Some(list) = self.lists(shapes).get(body.index() as usize) else {
            return;
        };
        for &i in list {
            if let Some((_, s)) = shapes.get_by_index(i) {
                // The lists are keyed by slot; a shape of a dead body in the
                // same slot cannot exist (a body's shapes go before it).
                if s.body == body {
                    f(s);
                }
            }
        }
    }
}

/// Inserts `shape` into `body`'s list, keeping it ascending (new shapes
/// usually take a new, highest slot: a push).
fn push_sorted(lists: &mut Vec<Vec<u32>>, body: u32, shape: u32) {
    let b = body as usize;
    if lists.len() <= b {
        lists.resize_with(b.saturating_add(1), Vec::new);
    }
    if let Some(list) = lists.get_mut(b) {
        match list.last() {
            Some(&last) if last >= shape => {
                if let Err(at) = list.binary_search(&shape) {
                    list.insert(at, shape);
                }
            }
            _ => list.push(shape),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::body::{Body, BodyHandle, BodyType};
    use crate::math::{Real, Vect};
    use crate::shape::{Shape, ShapeHandle};
    use crate::space::{Space, WorldState};

    /// The mass computation as it was before the per-body lists: a scan of
    /// every shape of the world in slot order (the oracle).
    fn reference_masses(state: &WorldState) -> WorldState {
        let mut out = state.clone();
        for (bh, body) in out.bodies.iter_mut() {
            if body.body_type() != BodyType::Dynamic || body.explicit_mass {
                continue;
            }
            let mut mass = Real::ZERO;
            let mut cog = Vect::ZERO;
            let mut moment = Real::ZERO;
            for (_, s) in state.shapes.iter().filter(|(_, s)| s.body == bh) {
                let info = s.mass_info();
                if !info.mass.is_positive() {
                    continue;
                }
                let total = mass + info.mass;
                let new_cog = cog.lerp(info.cog, info.mass / total);
                moment = moment
                    + mass * (cog - new_cog).length_sq()
                    + info.mass * (info.moment_per_mass + (info.cog - new_cog).length_sq());
                cog = new_cog;
                mass = total;
            }
            body.set_mass_properties(mass, moment, cog);
        }
        out
    }

    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self, n: usize) -> usize {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((self.0 >> 33) % (n.max(1) as u64)) as usize
        }
    }

    fn random_shape(rng: &mut Lcg, body: BodyHandle) -> Shape {
        let r = |rng: &mut Lcg| Real::ratio(rng.next(40) as i32 + 1, 16);
        let off = |rng: &mut Lcg| Real::ratio(rng.next(64) as i32 - 32, 8);
        let mut s = match rng.next(2) {
            0 => Shape::circle_shape_new(body, r(rng), Vect::new(off(rng), off(rng))),
            _ => Shape::segment_shape_new(
                body,
                Vect::new(off(rng), off(rng)),
                Vect::new(off(rng), off(rng)),
                r(rng),
            ),
        }
        .unwrap();
        match rng.next(3) {
            0 => s.set_density(r(rng)).unwrap(),
            1 => s.set_mass(r(rng)).unwrap(),
            _ => {}
        }
        s
    }

    /// Interleaved adds and removes of shapes and bodies (slots reused out
    /// of order, rollbacks and clones in between): every body's mass equals
    /// the full-scan result, bit for bit.
    #[test]
    fn per_body_lists_give_the_full_scan_masses() {
        let mut rng = Lcg(7);
        let mut space = Space::new();
        let mut bodies: Vec<BodyHandle> = Vec::new();
        let mut shapes: Vec<ShapeHandle> = Vec::new();
        let mut saved = None;
        for step in 0..3000 {
            match rng.next(10) {
                0 => {
                    let body = match rng.next(4) {
                        0 => Body::new_static(),
                        1 => Body::new(Real::ONE, Real::ONE).unwrap(),
                        _ => Body::new(Real::ZERO, Real::ZERO).unwrap(),
                    };
                    bodies.push(space.add_body(body).unwrap());
                }
                1 if !bodies.is_empty() => {
                    let b = bodies.swap_remove(rng.next(bodies.len()));
                    space.remove_body(b).unwrap();
                    shapes.retain(|&s| space.shape(s).is_some());
                }
                2 | 3 if !shapes.is_empty() => {
                    let s = shapes.swap_remove(rng.next(shapes.len()));
                    space.remove_shape(s).unwrap();
                }
                4 if !shapes.is_empty() => {
                    let s = *shapes.get(rng.next(shapes.len())).unwrap();
                    let d = Real::ratio(rng.next(30) as i32 + 1, 4);
                    space.modify_shape(s, |sh| sh.set_density(d)).unwrap();
                }
                5 if step % 7 == 0 => saved = Some((space.state().clone(), bodies.clone())),
                6 if step % 5 == 0 => {
                    if let Some((state, b)) = &saved {
                        space.restore_state(state);
                        bodies = b.clone();
                        shapes = space.state().shapes.iter().map(|(h, _)| h).collect();
                    }
                }
                7 if step % 11 == 0 => space = space.clone(),
                _ if !bodies.is_empty() => {
                    let b = *bodies.get(rng.next(bodies.len())).unwrap();
                    let shape = random_shape(&mut rng, b);
                    shapes.push(space.add_shape(shape).unwrap());
                }
                _ => {}
            }
            assert_eq!(
                space.state(),
                &reference_masses(space.state()),
                "step {step}"
            );
        }
        assert!(space.state().shapes.len() > 20, "the world grew");
    }
}
