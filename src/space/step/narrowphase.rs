//! [`Stage::Narrowphase`](super::Stage::Narrowphase): every candidate pair filtered and collided,
//! matched with its arbiter (which keeps the accumulated impulses of the
//! points it matches by feature id), the begin and pre-solve handlers run;
//! arbiters whose pair stopped touching retire (separate handler, expiry).
//! With threads, every pair's collision and its arbiter's update first,
//! in pieces; then the same merge in pair order.
use core::mem;

use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::Body;
use crate::collision::{collide, CollisionInfo, WarmStartId};
use crate::constraint::solve::ConstraintScratch;
use crate::math::Vect;
use crate::shape::Shape;

use super::super::Space;
use super::context::StepStats;
use super::shape_caches::ShapeCache;

impl Space {
    /// [`Stage::Narrowphase`](super::Stage::Narrowphase): narrowphase and arbiter matching. Old and new arbiters
    /// are both sorted by pair key, so matching is one merge pass; arbiters
    /// whose pair is not touching are retired on the way (separate handler,
    /// expiry). Returns the indices of the arbiters to solve this step.
    pub(super) fn collide_pairs(&mut self) -> Vec<u32> {
        // Double-buffered: last step's list is drained into this step's,
        // and both allocations are kept for the next step.
        let mut old = mem::take(&mut self.state.arbiters);
        let mut arbiters = mem::take(&mut self.caches.arbiters.spare);
        arbiters.clear();
        let mut active = mem::take(&mut self.caches.arbiters.active);
        active.clear();
        let pairs = mem::take(&mut self.caches.broadphase.sweep.pairs);
        self.caches.step.stats = StepStats {
            candidate_pairs: pairs.len() as u32,
            ..StepStats::default()
        };
        // With threads, every pair's narrowphase first, in parallel; then
        // the same merge.
        let mut infos = mem::take(&mut self.caches.arbiters.infos);
        let ahead = self.caches.threads.parallel();
        if ahead {
            self.collide_ahead(&pairs, &mut old, &mut infos);
        }
        let mut old_iter = old.drain(..);
        for (k, &(ia, ib)) in pairs.iter().enumerate() {
            // Arbiters of pairs that the broadphase no longer reports.
            while let Some(arb) = take_if(&mut old_iter, |key| key < (ia, ib)) {
                self.retire(arb, &mut arbiters);
            }
            // The pair's arbiter stays in `old` until it is copied once,
            // straight into `arbiters`: an arbiter is some 250 bytes, and
            // a move through a local was a second copy.
            let existing = old_iter.as_slice().first().filter(|a| a.key() == (ia, ib));
            let warm_start_id = existing.map_or(0, |a| a.warm_start_id);
            let existing = existing.is_some().then_some(&mut old_iter);
            // By reference: an info is 150-odd bytes, a move is a memcpy.
            let computed;
            let info = if ahead {
                infos.get(k).and_then(Option::as_ref)
            } else {
                computed = self.narrowphase(ia, ib, warm_start_id);
                computed.as_ref()
            };
            // Touched in place at the end of `arbiters`.
            if self.collide_pair(ia, ib, info, existing, ahead, &mut arbiters) {
                let index = arbiters.len().saturating_sub(1) as u32;
                if let Some(arb) = arbiters.last_mut() {
                    if self.run_contact_handlers(arb) {
                        active.push(index);
                    }
                }
            }
        }
        for arb in old_iter {
            self.retire(arb, &mut arbiters);
        }
        self.caches.broadphase.sweep.pairs = pairs;
        self.caches.arbiters.infos = infos;
        self.state.arbiters = arbiters;
        self.caches.arbiters.spare = old;
        active
    }

    /// [`Stage::Narrowphase`](super::Stage::Narrowphase) for every candidate pair at once, split between threads:
    /// `infos[k]` becomes pair `k`'s narrowphase answer, warm-started from
    /// its arbiter in `old` (last step's, in canonical order like `pairs`),
    /// and each arbiter of `old` whose pair touches takes its answer
    /// ([`Arbiter::touch`]), also split. The merge then only moves them:
    /// a touch reads the answer, the shapes and the bodies' centres, which
    /// nothing in the merge changes (the handlers change only their own
    /// arbiter, after its touch), so the bits are the serial pass's.
    fn collide_ahead(
        &mut self,
        pairs: &[(u32, u32)],
        old: &mut [Arbiter],
        infos: &mut Vec<Option<CollisionInfo>>,
    ) {
        // Every slot is written by `collide_split`: only new ones need a
        // value first (a refill would touch every slot's cache lines on
        // this thread alone).
        infos.truncate(pairs.len());
        infos.resize(pairs.len(), None);
        // The warm-start ids, and each old arbiter's pair, by the merge the
        // serial pass makes.
        let mut matched = mem::take(&mut self.caches.arbiters.matched);
        matched.clear();
        matched.resize(old.len(), u32::MAX);
        let mut ids = mem::take(&mut self.caches.arbiters.warm_start_ids);
        ids.clear();
        let mut next_old = 0usize;
        ids.extend(pairs.iter().enumerate().map(|(k, &key)| {
            while old.get(next_old).is_some_and(|a| a.key() < key) {
                next_old = next_old.saturating_add(1);
            }
            match old.get(next_old).filter(|a| a.key() == key) {
                Some(a) => {
                    if let Some(m) = matched.get_mut(next_old) {
                        *m = k as u32;
                    }
                    a.warm_start_id
                }
                None => 0,
            }
        }));
        let view = NarrowView {
            shapes: &self.state.shapes,
            bodies: &self.state.bodies,
            caches: &self.caches.shapes,
            constraints: &self.caches.constraints,
        };
        collide_split(&view, pairs, &ids, infos);
        let stamp = self.state.stamp;
        let infos: &[Option<CollisionInfo>] = infos;
        crate::threads::zip_split(&matched, old, PAIR_PIECE, &|&k, arb: &mut Arbiter| {
            let (Some(Some(info)), Some(&(ia, ib))) =
                (infos.get(k as usize), pairs.get(k as usize))
            else {
                return;
            };
            if let Some((sa, sb, centers)) = view.touch_inputs(ia, ib) {
                arb.touch(info, sa, sb, centers, stamp);
            }
        });
        self.caches.arbiters.matched = matched;
        self.caches.arbiters.warm_start_ids = ids;
    }

    /// [`Stage::Narrowphase`](super::Stage::Narrowphase) for one candidate pair, given the narrowphase's
    /// `info`: pushes the touched arbiter (the pair's existing one, the
    /// next of the old list `existing` when the pair has one, or a new
    /// one) onto `arbiters` and gives true. A pair that does not touch
    /// retires its existing arbiter into `arbiters` and gives false.
    /// `touched_ahead`: an existing arbiter has already taken `info`
    /// ([`collide_ahead`](Self::collide_ahead)).
    fn collide_pair(
        &mut self,
        ia: u32,
        ib: u32,
        info: Option<&CollisionInfo>,
        existing: Option<&mut std::vec::Drain<'_, Arbiter>>,
        touched_ahead: bool,
        arbiters: &mut Vec<Arbiter>,
    ) -> bool {
        let Some(info) = info else {
            if let Some(arb) = existing.and_then(Iterator::next) {
                self.retire(arb, arbiters);
            }
            return false;
        };
        let stats = &mut self.caches.step.stats;
        stats.touching_pairs = stats.touching_pairs.saturating_add(1);
        stats.iteration_cap_hits = stats
            .iteration_cap_hits
            .saturating_add(u32::from(info.hit_iteration_cap));
        // An arbiter touched ahead took the answer already, from shapes
        // and bodies that the answer proves exist: no lookup.
        let inputs = if touched_ahead && existing.is_some() {
            None
        } else {
            let (Some((ha, sa)), Some((hb, sb))) = (
                self.state.shapes.get_by_index(ia),
                self.state.shapes.get_by_index(ib),
            ) else {
                // The pair's arbiter (if any) is dropped.
                existing.and_then(Iterator::next);
                return false;
            };
            let (Some(body_a), Some(body_b)) = (
                self.state.bodies.get(sa.body),
                self.state.bodies.get(sb.body),
            ) else {
                existing.and_then(Iterator::next);
                return false;
            };
            Some((ha, sa, hb, sb, (body_a.center(), body_b.center())))
        };
        match existing {
            // One copy, from the old list into the new one.
            Some(old) => {
                arbiters.extend_from_slice(old.as_slice().get(..1).unwrap_or(&[]));
                old.next();
            }
            None => {
                let Some((ha, sa, hb, sb, _)) = inputs else {
                    return false;
                };
                arbiters.push(Arbiter::new(ha, sa, hb, sb));
            }
        }
        if let (Some((_, sa, _, sb, centers)), Some(arb)) = (inputs, arbiters.last_mut()) {
            arb.touch(info, sa, sb, centers, self.state.stamp);
        }
        true
    }

    /// Retires one arbiter whose shapes did not touch this step: the
    /// separate handler runs once (it becomes `Cached`), and it is kept in
    /// `arbiters` until it has not touched for `collision_persistence` steps.
    fn retire(&mut self, mut arb: Arbiter, arbiters: &mut Vec<Arbiter>) {
        if !arb.is_cached() {
            self.handlers.separate(
                &mut arb,
                &self.state.bodies,
                &self.state.shapes,
                &mut self.post_step,
            );
            arb.cache();
        }
        let persistence = self.state.settings.collision_persistence;
        if !arb.is_expired(self.state.stamp, persistence) {
            arbiters.push(arb);
        }
    }

    /// Filters a candidate pair and collides it; `None` if rejected or not touching.
    /// `warm_start_id`: the pair's arbiter's, or 0 for a new pair.
    fn narrowphase(&self, ia: u32, ib: u32, warm_start_id: WarmStartId) -> Option<CollisionInfo> {
        let view = NarrowView {
            shapes: &self.state.shapes,
            bodies: &self.state.bodies,
            caches: &self.caches.shapes,
            constraints: &self.caches.constraints,
        };
        view.collide(ia, ib, warm_start_id)
    }

    /// Begin and pre-solve handlers; true if the arbiter goes to the solver.
    fn run_contact_handlers(&mut self, arb: &mut Arbiter) -> bool {
        let (bodies, shapes, q) = (&self.state.bodies, &self.state.shapes, &mut self.post_step);
        if arb.is_first_contact() && !self.handlers.begin(arb, bodies, shapes, q) {
            arb.ignore();
        }
        if arb.is_ignored() {
            return false;
        }
        let accept = self.handlers.pre_solve(arb, bodies, shapes, q);
        accept && !arb.sensor
    }
}

/// What the narrowphase of a pair reads: the space's parts threads may
/// share (the space itself holds callbacks, which they may not).
struct NarrowView<'a> {
    shapes: &'a Arena<Shape>,
    bodies: &'a Arena<Body>,
    caches: &'a [Option<ShapeCache>],
    constraints: &'a ConstraintScratch,
}

impl NarrowView<'_> {
    /// Filters the candidate pair of shape slots `ia`, `ib` and collides
    /// it from warm-start id `ws`; `None` if rejected or not touching.
    #[inline]
    fn collide(&self, ia: u32, ib: u32, ws: u32) -> Option<CollisionInfo> {
        let (_, sa) = self.shapes.get_by_index(ia)?;
        let (_, sb) = self.shapes.get_by_index(ib)?;
        if sa.body == sb.body || sa.filter.rejects(&sb.filter) || (sa.sensor && sb.sensor) {
            return None;
        }
        if self.constraints.rejects(sa.body, sb.body) {
            return None;
        }
        let ba = self.bodies.get(sa.body)?;
        let bb = self.bodies.get(sb.body)?;
        // Two bodies that cannot move, or a sleeping body and one that
        // does not move it (the wake stage woke the islands a mover touches).
        let awake = |b: &Body| b.is_dynamic() && !b.is_sleeping();
        if !awake(ba) && !awake(bb) {
            return None;
        }
        let ca = self.caches.get(ia as usize)?.as_ref()?;
        let cb = self.caches.get(ib as usize)?.as_ref()?;
        let info = collide(&ca.geometry, &cb.geometry, ws);
        (info.count > 0).then_some(info)
    }

    /// What [`Arbiter::touch`] reads for the pair of shape slots `ia`,
    /// `ib` besides the answer: the shapes and the bodies' centres.
    fn touch_inputs(&self, ia: u32, ib: u32) -> Option<(&Shape, &Shape, (Vect, Vect))> {
        let (_, sa) = self.shapes.get_by_index(ia)?;
        let (_, sb) = self.shapes.get_by_index(ib)?;
        let ba = self.bodies.get(sa.body)?;
        let bb = self.bodies.get(sb.body)?;
        Some((sa, sb, (ba.center(), bb.center())))
    }
}

/// Pairs per piece of the split narrowphase (a few µs of work).
const PAIR_PIECE: usize = 64;

/// [`NarrowView::collide`] for every pair, halves in parallel down to
/// [`PAIR_PIECE`]s: each piece writes its own slots of `infos`.
fn collide_split(
    view: &NarrowView<'_>,
    pairs: &[(u32, u32)],
    ids: &[u32],
    infos: &mut [Option<CollisionInfo>],
) {
    if infos.len() <= PAIR_PIECE {
        for ((info, &(ia, ib)), &ws) in infos.iter_mut().zip(pairs).zip(ids) {
            *info = view.collide(ia, ib, ws);
        }
        return;
    }
    let mid = infos.len() / 2;
    let (left, right) = infos.split_at_mut(mid);
    let (pl, pr) = (
        pairs.get(..mid).unwrap_or(&[]),
        pairs.get(mid..).unwrap_or(&[]),
    );
    let (il, ir) = (ids.get(..mid).unwrap_or(&[]), ids.get(mid..).unwrap_or(&[]));
    crate::threads::join(
        || collide_split(view, pl, il, left),
        || collide_split(view, pr, ir, right),
    );
}

/// The next arbiter of `old` if its pair key satisfies `pred`.
/// `Drain::as_slice` peeks without moving: each kept arbiter is moved once
/// out of the old list and once into the new one (they are 240 bytes).
fn take_if(
    old: &mut std::vec::Drain<'_, Arbiter>,
    pred: impl FnOnce((u32, u32)) -> bool,
) -> Option<Arbiter> {
    if old.as_slice().first().is_some_and(|a| pred(a.key())) {
        old.next()
    } else {
        None
    }
}
