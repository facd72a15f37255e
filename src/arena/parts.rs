//! Arenas in two parts: the slots of a world's level (runs of slots that
//! stay put from frame to frame) and the rest, the frame's.
//!
//! [`Runs`] name the level's slots; [`outside_runs`] and [`gaps`] walk the
//! others; an [`ArenaPart`] holds them with the arena's bookkeeping, and the
//! `Arena` methods here save, restore, swap and hash that part, so that a
//! frame costs what it holds, not what the level holds. A file of its own
//! because it is a second job built on the arena (the arena itself, in
//! `arena.rs`, knows nothing of levels); it reaches the arena's private
//! slots as a child module. Everything is re-exported from `arena`, so the
//! paths (`crate::arena::gaps`, `crate::arena::ArenaPart`, …) are
//! unchanged.
use serde::{Deserialize, Serialize};

use super::{hash_slot, Arena, Slot};

/// Sorted, disjoint, half-open slot ranges `start..end`: the slots an
/// [`ArenaPart`] leaves out (a world's level, see `space::level`).
pub(crate) type Runs = [(u32, u32)];

/// Number of slots the runs cover.
pub(crate) fn runs_len(runs: &Runs) -> u64 {
    runs.iter()
        .map(|&(a, b)| u64::from(b.saturating_sub(a)))
        .sum()
}

/// The indices `0..slot_count` outside `runs`, increasing (the runs must
/// be sorted and disjoint; indices past `slot_count` are ignored).
pub(crate) fn outside_runs(runs: &Runs, slot_count: u32) -> impl Iterator<Item = u32> + '_ {
    let mut next_run = 0usize;
    let mut i = 0u32;
    core::iter::from_fn(move || loop {
        if i >= slot_count {
            return None;
        }
        match runs.get(next_run) {
            Some(&(a, b)) if i >= a => {
                if i < b {
                    i = b;
                }
                next_run = next_run.saturating_add(1);
            }
            _ => {
                let out = i;
                i = i.saturating_add(1);
                return Some(out);
            }
        }
    })
}

/// The gaps between `runs` within `0..count`, as index ranges in order:
/// the slots [`outside_runs`] yields, a range at a time (for loops that
/// walk slices).
pub(crate) fn gaps(runs: &Runs, count: u32) -> impl Iterator<Item = core::ops::Range<usize>> + '_ {
    let mut start = 0u32;
    runs.iter()
        .copied()
        .chain(core::iter::once((count, count)))
        .map(move |(a, b)| {
            let gap = start as usize..a.min(count).max(start) as usize;
            start = start.max(b);
            gap
        })
}

/// Part of an arena: every slot outside some runs (the level's), with the
/// arena's free list, length and slot count. A world's per-frame state
/// holds its arenas this way, so that saving, restoring and hashing a
/// frame cost what the frame holds, not what the level holds. The held
/// slots carry no index: they are the slots outside the runs, in order
/// (which `check_against` makes sure of).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(bound(serialize = "T: Serialize", deserialize = "T: Deserialize<'de>"))]
pub struct ArenaPart<T> {
    /// Slots of the whole arena (those left out included).
    slot_count: u32,
    /// Every slot outside the runs, by increasing index.
    slots: Vec<Slot<T>>,
    /// The arena's free list (free slots are never in the runs).
    free: Vec<u32>,
    /// The arena's number of live objects (those left out included).
    len: u32,
}

impl<T> Default for ArenaPart<T> {
    fn default() -> Self {
        ArenaPart {
            slot_count: 0,
            slots: Vec::new(),
            free: Vec::new(),
            len: 0,
        }
    }
}

impl<T> ArenaPart<T> {
    /// Number of slots held.
    pub(crate) fn held(&self) -> usize {
        self.slots.len()
    }

    /// The held objects, mutably.
    pub(crate) fn values_mut(&mut self) -> impl Iterator<Item = &mut T> {
        self.slots.iter_mut().filter_map(|s| s.value.as_mut())
    }

    /// The free list, to be refilled (with [`refill`](Self::refill)).
    pub(crate) fn free_mut(&mut self) -> &mut Vec<u32> {
        &mut self.free
    }

    /// Refills the part in place, its buffers reused: the bookkeeping and
    /// `held` slots, each filled by `slot(generation, value)` in order (the
    /// free list is [`free_mut`](Self::free_mut)'s). Nothing is checked
    /// here; a part left half-filled by an error is only fit to be refilled.
    pub(crate) fn refill<E>(
        &mut self,
        (slot_count, len): (u32, u32),
        held: usize,
        mut slot: impl FnMut(&mut u32, &mut Option<T>) -> Result<(), E>,
    ) -> Result<(), E> {
        self.slot_count = slot_count;
        self.len = len;
        self.slots.truncate(held);
        self.slots.resize_with(held, Slot::empty);
        for s in &mut self.slots {
            slot(&mut s.generation, &mut s.value)?;
        }
        Ok(())
    }

    /// Checks that the part and `runs` tile `0..slot_count` exactly: every
    /// run inside `0..slot_count`, and as many held slots as the runs leave.
    /// What installing needs to be exact; the bookkeeping is
    /// [`check_bookkeeping`](Self::check_bookkeeping)'s.
    pub(crate) fn check_against(&self, runs: &Runs) -> Result<(), String> {
        if runs.iter().any(|&(_, b)| b > self.slot_count) {
            return Err(format!(
                "the level has slots past the part's {} slots",
                self.slot_count
            ));
        }
        let expected = u64::from(self.slot_count).saturating_sub(runs_len(runs));
        if self.slots.len() as u64 != expected {
            return Err(format!(
                "{} slots held, the level leaves {expected}",
                self.slots.len()
            ));
        }
        Ok(())
    }

    /// Checks the arena bookkeeping the part carries, for a part that
    /// [`check_against`](Self::check_against) accepted for `runs` (the
    /// level's slots, all live): the length counts the live held slots plus
    /// the level's, and the free list names each empty held slot exactly
    /// once and nothing else. What [`Arena::validate`] checks of the arena
    /// the part makes, at the cost of the part.
    pub(crate) fn check_bookkeeping(&self, runs: &Runs) -> Result<(), String> {
        let level_len = runs_len(runs);
        let live = self.slots.iter().filter(|s| s.value.is_some()).count() as u64;
        if live.saturating_add(level_len) != u64::from(self.len) {
            return Err(format!(
                "arena length {} but {live} live slots besides the level's {level_len}",
                self.len
            ));
        }
        let empty = (self.slots.len() as u64).saturating_sub(live);
        if self.free.len() as u64 != empty {
            return Err(format!(
                "{empty} empty slots but {} on the free list",
                self.free.len()
            ));
        }
        let held: Vec<u32> = outside_runs(runs, self.slot_count).collect();
        let mut seen = vec![false; self.slots.len()];
        for &i in &self.free {
            let Ok(pos) = held.binary_search(&i) else {
                return Err(format!("free list names slot {i}, not an empty slot"));
            };
            if self.slots.get(pos).is_some_and(|s| s.value.is_some()) {
                return Err(format!("free list names live slot {i}"));
            }
            match seen.get_mut(pos) {
                Some(flag) if !*flag => *flag = true,
                _ => return Err(format!("free list names slot {i} twice")),
            }
        }
        Ok(())
    }

    /// Hashes the part exactly as [`Arena::hash_part`] hashes the arena it
    /// was saved from.
    pub(crate) fn hash_into<H: core::hash::Hasher>(&self, h: &mut H)
    where
        T: core::hash::Hash,
    {
        let ArenaPart {
            slot_count,
            slots,
            free,
            len,
        } = self;
        hash_part_words(
            h,
            *slot_count,
            |h| {
                for slot in slots {
                    hash_slot(slot, h);
                }
            },
            free,
            *len,
        );
    }
}

/// The one hashing sequence of an arena part, shared by the arena (walking
/// its slots outside the runs) and a saved [`ArenaPart`]: the slot count,
/// the slots (`hash_slots`, each by `hash_slot`, by increasing index; their
/// indices are implied by the runs), the free list and the length.
#[inline(always)]
fn hash_part_words<H: core::hash::Hasher>(
    h: &mut H,
    slot_count: u32,
    hash_slots: impl FnOnce(&mut H),
    free: &[u32],
    len: u32,
) {
    h.write_u32(slot_count);
    hash_slots(h);
    h.write_u64(free.len() as u64);
    for &i in free {
        h.write_u32(i);
    }
    h.write_u32(len);
}

impl<T: Clone> Arena<T> {
    /// Copies the slots outside `runs` (and the bookkeeping) into `out`,
    /// reusing its buffer: no allocation once it has grown.
    pub(crate) fn save_part(&self, runs: &Runs, out: &mut ArenaPart<T>) {
        out.slot_count = self.slots.len() as u32;
        out.slots.clear();
        out.slots.extend(
            outside_runs(runs, out.slot_count).filter_map(|i| self.slots.get(i as usize).cloned()),
        );
        out.free.clone_from(&self.free);
        out.len = self.len;
    }

    /// Installs a part that [`ArenaPart::check_against`] accepted for
    /// `runs`, the runs of this arena's kept slots: the slots outside the
    /// runs, the free list and the length become the part's; the slots in
    /// the runs stay. `adopt` fixes each installed object (its handles'
    /// origin).
    pub(crate) fn restore_part(
        &mut self,
        runs: &Runs,
        part: &ArenaPart<T>,
        mut adopt: impl FnMut(&mut T),
    ) {
        self.slots
            .resize_with(part.slot_count as usize, Slot::empty);
        for (i, slot) in outside_runs(runs, part.slot_count).zip(&part.slots) {
            if let Some(dst) = self.slots.get_mut(i as usize) {
                dst.clone_from(slot);
                if let Some(v) = dst.value.as_mut() {
                    adopt(v);
                }
            }
        }
        self.free.clone_from(&part.free);
        self.len = part.len;
    }
}

impl<T> Arena<T> {
    /// Exchanges the slots outside `runs` (and the bookkeeping) with those of
    /// `part`, which [`ArenaPart::check_against`] accepted for `runs`
    /// (and so did this arena, as it holds them): installing and undoing
    /// are the same call, exact both ways, without cloning an object.
    pub(crate) fn swap_part(&mut self, runs: &Runs, part: &mut ArenaPart<T>) {
        let mine = self.slots.len() as u32;
        if part.slot_count == mine {
            // The same slot count (the usual case): slot for slot in place,
            // gap by gap between the runs; no buffer, no object moved twice.
            let mut held = part.slots.iter_mut();
            for gap in gaps(runs, mine) {
                let slots = self.slots.get_mut(gap).unwrap_or(&mut []);
                for (dst, src) in slots.iter_mut().zip(&mut held) {
                    core::mem::swap(dst, src);
                }
            }
            core::mem::swap(&mut self.free, &mut part.free);
            core::mem::swap(&mut self.len, &mut part.len);
            return;
        }
        let mut taken = Vec::with_capacity(part.slots.len());
        for i in outside_runs(runs, mine) {
            if let Some(s) = self.slots.get_mut(i as usize) {
                taken.push(core::mem::replace(s, Slot::empty()));
            }
        }
        self.slots
            .resize_with(part.slot_count as usize, Slot::empty);
        for (i, slot) in outside_runs(runs, part.slot_count).zip(part.slots.drain(..)) {
            if let Some(dst) = self.slots.get_mut(i as usize) {
                *dst = slot;
            }
        }
        part.slots = taken;
        part.slot_count = mine;
        core::mem::swap(&mut self.free, &mut part.free);
        core::mem::swap(&mut self.len, &mut part.len);
    }

    /// Hashes the slots outside `runs` and the bookkeeping, as the saved
    /// part would hash ([`ArenaPart::hash_into`]).
    pub(crate) fn hash_part<H: core::hash::Hasher>(&self, runs: &Runs, h: &mut H)
    where
        T: core::hash::Hash,
    {
        let count = self.slots.len() as u32;
        // The gaps between the runs as slices: the same slots, in the same
        // order, as `outside_runs`, each gap walked by a plain loop (the
        // checksum's hot path: the hasher's lanes stay in registers).
        hash_part_words(
            h,
            count,
            |h| {
                for gap in gaps(runs, count) {
                    for slot in self.slots.get(gap).unwrap_or(&[]) {
                        hash_slot(slot, h);
                    }
                }
            },
            &self.free,
            self.len,
        );
    }

    /// Every slot, in order, with its index: for computing runs.
    pub(crate) fn raw_slots(&self) -> impl Iterator<Item = (u32, Option<&T>)> {
        self.slots
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u32, s.value.as_ref()))
    }

    /// The slot count, free list and length: what a part carries besides
    /// its slots.
    pub(crate) fn bookkeeping(&self) -> (u32, &[u32], u32) {
        (self.slots.len() as u32, &self.free, self.len)
    }

    /// Calls `f(generation, value)` for each slot outside `runs`, by
    /// increasing index (the slots a part saved for `runs` holds).
    #[inline]
    pub(crate) fn for_each_outside(&self, runs: &Runs, mut f: impl FnMut(u32, Option<&T>)) {
        for gap in gaps(runs, self.slots.len() as u32) {
            for slot in self.slots.get(gap).unwrap_or(&[]) {
                f(slot.generation, slot.value.as_ref());
            }
        }
    }

    /// The slot's generation and value (for hashing a level).
    pub(crate) fn slot(&self, index: u32) -> Option<&Slot<T>> {
        self.slots.get(index as usize)
    }
}
