//! [`Stage::Narrowphase`](super::Stage::Narrowphase): every candidate pair filtered and collided,
//! matched with its arbiter (which keeps the accumulated impulses of the
//! points it matches by feature id), the begin and pre-solve handlers run;
//! arbiters whose pair stopped touching retire (separate handler, expiry).
//! With threads, every pair's collision first, in pieces; then the same
//! merge in pair order, split between threads when no handler is
//! registered (`arbiter_merge`).
use core::mem;

use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::Body;
use crate::collision::{collide, CollisionInfo, WarmStartId};
use crate::constraint::solve::ConstraintScratch;
use crate::math::Vect;
use crate::shape::{Shape, ShapeHandle};

use super::super::Space;
use super::context::StepStats;
use super::shape_caches::ShapeCache;

impl Space {
    /// [`Stage::Narrowphase`](super::Stage::Narrowphase): narrowphase and arbiter matching. Old and new arbiters
    /// are both sorted by pair key, so matching is one merge pass; arbiters
    /// whose pair is not touching are retired on the way (separate handler,
    /// expiry). Returns the indices of the arbiters to solve this step.
    pub(super) fn collide_pairs(&mut self) -> Vec<u32> {
        // Double-buffered: last step's list is copied into this step's
        // (drained on this thread, or read whole by the split merge), and
        // both allocations are kept for the next step.
        let mut old = mem::take(&mut self.state.arbiters);
        let mut arbiters = mem::take(&mut self.caches.arbiters.spare);
        let mut active = mem::take(&mut self.caches.arbiters.active);
        active.clear();
        let pairs = mem::take(&mut self.caches.broadphase.sweep.pairs);
        self.caches.step.stats = StepStats {
            candidate_pairs: pairs.len() as u32,
            ..StepStats::default()
        };
        // With threads, every pair's narrowphase first, in parallel; then
        // the same merge, also split if no handler needs it in order.
        let mut infos = mem::take(&mut self.caches.arbiters.infos);
        let ahead = self.caches.threads.parallel();
        let split_merge = ahead && self.handlers.is_empty();
        if ahead {
            self.collide_ahead(&pairs, &mut old, &mut infos);
        }
        if split_merge {
            let matched = mem::take(&mut self.caches.arbiters.matched);
            let place = mem::take(&mut self.caches.arbiters.place);
            let flags = mem::take(&mut self.caches.arbiters.answer_flags);
            let input = MergeInputs {
                pairs: &pairs,
                infos: &infos,
                flags: &flags,
                old: &old,
                matched: &matched,
                place: &place,
            };
            self.merge_split(&input, &mut arbiters, &mut active);
            self.caches.arbiters.matched = matched;
            self.caches.arbiters.place = place;
            self.caches.arbiters.answer_flags = flags;
        } else {
            arbiters.clear();
            self.merge_serial((&pairs, &infos), &mut old, &mut arbiters, &mut active);
        }
        self.caches.broadphase.sweep.pairs = pairs;
        self.caches.arbiters.infos = infos;
        self.state.arbiters = arbiters;
        self.caches.arbiters.spare = old;
        active
    }

    /// The merge of [`collide_pairs`](Self::collide_pairs) on this thread:
    /// each candidate pair's arbiter (last step's, drained from `old`, or
    /// a new one) touched with the pair's answer (`infos[k]` if computed
    /// ahead) and pushed onto `arbiters`, its handlers run; last step's
    /// arbiters whose pair is gone or not touching retired in between.
    fn merge_serial(
        &mut self,
        (pairs, infos): (&[(u32, u32)], &[Option<CollisionInfo>]),
        old: &mut Vec<Arbiter>,
        arbiters: &mut Vec<Arbiter>,
        active: &mut Vec<u32>,
    ) {
        let ahead = self.caches.threads.parallel();
        let mut old_iter = old.drain(..);
        for (k, &(ia, ib)) in pairs.iter().enumerate() {
            // Arbiters of pairs that the broadphase no longer reports.
            while let Some(arb) = take_if(&mut old_iter, |key| key < (ia, ib)) {
                self.retire(arb, arbiters);
            }
            // The pair's arbiter stays in `old` until it is copied once,
            // straight into `arbiters`: an arbiter is some 240 bytes, and
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
            if self.collide_pair(ia, ib, info, existing, ahead, arbiters) {
                let index = arbiters.len().saturating_sub(1) as u32;
                if let Some(arb) = arbiters.last_mut() {
                    if self.run_contact_handlers(arb) {
                        active.push(index);
                    }
                }
            }
        }
        for arb in old_iter {
            self.retire(arb, arbiters);
        }
    }

    /// [`Stage::Narrowphase`](super::Stage::Narrowphase) for every candidate pair at once, split between threads:
    /// `infos[k]` becomes pair `k`'s narrowphase answer (and the answer
    /// flags its [`answer_flags`]), warm-started from its arbiter in `old`
    /// (last step's, in canonical order like `pairs`); `matched` and
    /// `place` ([`MergeInputs`]) record where each arbiter of `old` falls
    /// among the pairs. Each arbiter of `old` whose pair touches takes its
    /// answer ([`Arbiter::touch`]) in the same piece, while the pair's
    /// shapes and bodies are in cache, and the merge only moves them: a
    /// touch reads the answer, the shapes and the bodies' centres, which
    /// nothing in the merge changes (the handlers change only their own
    /// arbiter, after its touch), so the bits are the serial pass's.
    fn collide_ahead(
        &mut self,
        pairs: &[(u32, u32)],
        old: &mut [Arbiter],
        infos: &mut Vec<Option<CollisionInfo>>,
    ) {
        // Every slot is written by the pieces: only new ones need a
        // value first (a refill would touch every slot's cache lines on
        // this thread alone).
        infos.truncate(pairs.len());
        infos.resize(pairs.len(), None);
        let mut flags = mem::take(&mut self.caches.arbiters.answer_flags);
        flags.truncate(pairs.len());
        flags.resize(pairs.len(), 0);
        // The warm-start ids, and each old arbiter's pair, by the merge the
        // serial pass makes.
        let mut matched = mem::take(&mut self.caches.arbiters.matched);
        matched.clear();
        matched.resize(old.len(), NONE);
        let mut place = mem::take(&mut self.caches.arbiters.place);
        place.clear();
        place.resize(old.len(), 0);
        let mut ids = mem::take(&mut self.caches.arbiters.warm_start_ids);
        ids.clear();
        ids.resize(pairs.len(), 0);
        let walk = KeyWalk {
            first: 0,
            pairs,
            old,
            ids: &mut ids,
            matched: &mut matched,
            place: &mut place,
        };
        walk.run_split();
        let view = self.narrow_view();
        let piece = AheadPiece {
            first: 0,
            pairs,
            ids: &ids,
            infos,
            flags: &mut flags,
            old,
            matched: &matched,
            place: &place,
        };
        piece.run_split(&view, self.state.stamp);
        self.caches.arbiters.matched = matched;
        self.caches.arbiters.place = place;
        self.caches.arbiters.answer_flags = flags;
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
        self.narrow_view().collide(ia, ib, warm_start_id)
    }

    /// What the narrowphase reads, for threads to share.
    pub(super) fn narrow_view(&self) -> NarrowView<'_> {
        NarrowView {
            shapes: &self.state.shapes,
            bodies: &self.state.bodies,
            caches: &self.caches.shapes,
            constraints: &self.caches.constraints,
        }
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
pub(super) struct NarrowView<'a> {
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
    pub(super) fn touch_inputs(&self, ia: u32, ib: u32) -> Option<(&Shape, &Shape, (Vect, Vect))> {
        let ((_, sa), (_, sb), centers) = self.touch_handles(ia, ib)?;
        Some((sa, sb, centers))
    }

    /// [`touch_inputs`](Self::touch_inputs) with the shapes' handles
    /// (what [`Arbiter::new`] reads).
    pub(super) fn touch_handles(
        &self,
        ia: u32,
        ib: u32,
    ) -> Option<(HandledShape<'_>, HandledShape<'_>, (Vect, Vect))> {
        let (ha, sa) = self.shapes.get_by_index(ia)?;
        let (hb, sb) = self.shapes.get_by_index(ib)?;
        let ba = self.bodies.get(sa.body)?;
        let bb = self.bodies.get(sb.body)?;
        Some(((ha, sa), (hb, sb), (ba.center(), bb.center())))
    }
}

/// An index meaning "none": in `matched`, and in a [`MergeSlot`](crate::arbiter::MergeSlot).
pub(super) const NONE: u32 = u32::MAX;

/// [`answer_flags`]: the pair touches.
pub(super) const TOUCHES: u8 = 1;
/// [`answer_flags`]: the pair's narrowphase hit its iteration cap.
pub(super) const HIT_CAP: u8 = 2;

/// What the split merge's plan reads of a pair's narrowphase answer, a byte a pair where
/// the answer is some 150: whether it touches, and whether it hit the
/// iteration cap.
pub(super) fn answer_flags(info: Option<&CollisionInfo>) -> u8 {
    info.map_or(0, |info| {
        TOUCHES | if info.hit_iteration_cap { HIT_CAP } else { 0 }
    })
}

/// What the merge reads besides the space: the step's candidate pairs,
/// their narrowphase answers and those answers' [`answer_flags`], last
/// step's arbiters, and for each of those the pair it matches (`matched`,
/// [`NONE`]: none) or, if none, the first pair whose key follows its own
/// (`place`).
pub(super) struct MergeInputs<'a> {
    pub(super) pairs: &'a [(u32, u32)],
    pub(super) infos: &'a [Option<CollisionInfo>],
    pub(super) flags: &'a [u8],
    pub(super) old: &'a [Arbiter],
    pub(super) matched: &'a [u32],
    pub(super) place: &'a [u32],
}

/// A shape and its handle.
type HandledShape<'a> = (ShapeHandle, &'a Shape);

/// Pairs per piece of the split narrowphase (a few µs of work).
const PAIR_PIECE: usize = 64;

/// Pairs per piece of the split key walk (a cache miss an arbiter).
const WALK_PIECE: usize = 1024;

/// The merge walk of a run of the candidate pairs (`first` is the index
/// of `pairs[0]` among all of them) and of the run of last step's
/// arbiters whose keys fall before the next run's first pair: each pair's
/// warm-start id (`ids`, its arbiter's or 0) and each arbiter's `matched`
/// and `place` ([`MergeInputs`]), the serial merge's matching.
struct KeyWalk<'a> {
    first: u32,
    pairs: &'a [(u32, u32)],
    old: &'a [Arbiter],
    ids: &'a mut [u32],
    matched: &'a mut [u32],
    place: &'a mut [u32],
}

impl KeyWalk<'_> {
    /// Halves in parallel down to [`WALK_PIECE`] pairs: the arbiters
    /// split at the first whose key is not below the second half's first
    /// pair (a binary search of the sorted keys).
    fn run_split(self) {
        let mid = self.pairs.len() / 2;
        let Some(&key) = self
            .pairs
            .get(mid)
            .filter(|_| self.pairs.len() > WALK_PIECE)
        else {
            self.run();
            return;
        };
        let old_mid = self.old.partition_point(|a| a.key() < key);
        let (pairs_l, pairs_r) = self.pairs.split_at(mid);
        let (old_l, old_r) = self.old.split_at(old_mid);
        let (ids_l, ids_r) = self.ids.split_at_mut(mid.min(self.ids.len()));
        let (matched_l, matched_r) = self.matched.split_at_mut(old_mid.min(self.matched.len()));
        let (place_l, place_r) = self.place.split_at_mut(old_mid.min(self.place.len()));
        let left = KeyWalk {
            first: self.first,
            pairs: pairs_l,
            old: old_l,
            ids: ids_l,
            matched: matched_l,
            place: place_l,
        };
        let right = KeyWalk {
            first: self.first.saturating_add(mid as u32),
            pairs: pairs_r,
            old: old_r,
            ids: ids_r,
            matched: matched_r,
            place: place_r,
        };
        crate::threads::join(|| left.run_split(), || right.run_split());
    }

    /// The walk of the run on this thread.
    fn run(self) {
        // An arbiter after the run's last pair comes before the next
        // run's first (or after every pair).
        let end = self.first.saturating_add(self.pairs.len() as u32);
        self.place.fill(end);
        let mut next_old = 0usize;
        for (local, (&key, id)) in self.pairs.iter().zip(self.ids.iter_mut()).enumerate() {
            let k = self.first.saturating_add(local as u32);
            while self.old.get(next_old).is_some_and(|a| a.key() < key) {
                // An arbiter that matched a pair keeps that pair's index.
                if self.matched.get(next_old) == Some(&NONE) {
                    if let Some(p) = self.place.get_mut(next_old) {
                        *p = k;
                    }
                }
                next_old = next_old.saturating_add(1);
            }
            *id = match self.old.get(next_old).filter(|a| a.key() == key) {
                Some(a) => {
                    if let (Some(m), Some(p)) =
                        (self.matched.get_mut(next_old), self.place.get_mut(next_old))
                    {
                        (*m, *p) = (k, k);
                    }
                    a.warm_start_id
                }
                None => 0,
            };
        }
    }
}

/// A run of the candidate pairs (`first` is the index of `pairs[0]` among
/// all of them) with their warm-start ids and the slots for their answers,
/// and the run of last step's arbiters that falls among them: those whose
/// `place` (nondecreasing, [`MergeInputs`]) is in the run.
struct AheadPiece<'a> {
    first: u32,
    pairs: &'a [(u32, u32)],
    ids: &'a [u32],
    infos: &'a mut [Option<CollisionInfo>],
    flags: &'a mut [u8],
    old: &'a mut [Arbiter],
    matched: &'a [u32],
    place: &'a [u32],
}

impl AheadPiece<'_> {
    /// [`NarrowView::collide`] for every pair and [`Arbiter::touch`] for
    /// every arbiter whose pair touches, halves in parallel down to
    /// [`PAIR_PIECE`] pairs: each piece writes its own slots.
    fn run_split(self, view: &NarrowView<'_>, stamp: u64) {
        if self.pairs.len() <= PAIR_PIECE {
            self.run(view, stamp);
            return;
        }
        let (left, right) = self.split();
        crate::threads::join(
            || left.run_split(view, stamp),
            || right.run_split(view, stamp),
        );
    }

    /// The first half of the pairs and the arbiters placed among them, and
    /// the rest.
    fn split(self) -> (Self, Self) {
        let mid = self.pairs.len() / 2;
        let bound = self.first.saturating_add(mid as u32);
        let old_mid = self.place.partition_point(|&p| p < bound);
        let (pairs_l, pairs_r) = self.pairs.split_at(mid);
        let (ids_l, ids_r) = self.ids.split_at(mid.min(self.ids.len()));
        let (infos_l, infos_r) = self.infos.split_at_mut(mid.min(self.infos.len()));
        let (flags_l, flags_r) = self.flags.split_at_mut(mid.min(self.flags.len()));
        let (old_l, old_r) = self.old.split_at_mut(old_mid.min(self.old.len()));
        let (matched_l, matched_r) = self.matched.split_at(old_mid.min(self.matched.len()));
        let (place_l, place_r) = self.place.split_at(old_mid);
        let left = AheadPiece {
            first: self.first,
            pairs: pairs_l,
            ids: ids_l,
            infos: infos_l,
            flags: flags_l,
            old: old_l,
            matched: matched_l,
            place: place_l,
        };
        let right = AheadPiece {
            first: bound,
            pairs: pairs_r,
            ids: ids_r,
            infos: infos_r,
            flags: flags_r,
            old: old_r,
            matched: matched_r,
            place: place_r,
        };
        (left, right)
    }

    /// The piece on this thread: the pairs' answers, then the touches.
    fn run(self, view: &NarrowView<'_>, stamp: u64) {
        let out = self.infos.iter_mut().zip(self.flags.iter_mut());
        for (((info, flag), &(ia, ib)), &ws) in out.zip(self.pairs).zip(self.ids) {
            *info = view.collide(ia, ib, ws);
            *flag = answer_flags(info.as_ref());
        }
        for (arb, &k) in self.old.iter_mut().zip(self.matched) {
            let local = k.wrapping_sub(self.first) as usize;
            let (Some(Some(info)), Some(&(ia, ib))) =
                (self.infos.get(local), self.pairs.get(local))
            else {
                continue;
            };
            if let Some((sa, sb, centers)) = view.touch_inputs(ia, ib) {
                arb.touch(info, sa, sb, centers, stamp);
            }
        }
    }
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
