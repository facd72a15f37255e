//! [`Stage::Narrowphase`](super::Stage::Narrowphase)'s merge split between
//! threads, when no collision handler is registered. The serial merge
//! copies every kept arbiter (some 240 bytes) from last step's list into
//! this step's on the stepping thread, one after the other. Here the
//! stepping thread only plans the new list: which of last step's arbiters,
//! or which new pair, fills each slot, from indices the threads computed
//! beside the narrowphase (no arbiter is read but the few that retire).
//! The threads then fill the slots in pieces: copies of last step's
//! arbiters (which took their pair's answer in the narrowphase's pieces),
//! and new arbiters, made and touched. The plan is the serial merge's order
//! and a slot's arbiter depends on its own inputs alone: the same list,
//! the same bits. (A handler may read or change any arbiter, in the
//! merge's order: with one, the merge stays serial.)
use crate::arbiter::{Arbiter, MergeSlot};

use super::super::Space;
use super::narrowphase::{MergeInputs, NarrowView, HIT_CAP, NONE, TOUCHES};

/// Slots per piece of the split fill (a copy each, a new arbiter's touch
/// besides: a few µs a piece).
const SLOT_PIECE: usize = 64;

impl Space {
    /// The merge of [`collide_pairs`](Self::collide_pairs) split between
    /// threads: this step's arbiters into `arbiters` (whatever it held is
    /// overwritten), the indices of those to solve into `active`. Only
    /// with no collision handler: the serial merge's begin, pre-solve and
    /// separate handlers would find every arbiter in the same state.
    pub(super) fn merge_split(
        &mut self,
        input: &MergeInputs<'_>,
        arbiters: &mut Vec<Arbiter>,
        active: &mut Vec<u32>,
    ) {
        let mut slots = core::mem::take(&mut self.caches.arbiters.slots);
        self.plan_merge(input, &mut slots);
        // The list grows (rarely: it is the one of two steps ago) by
        // placeholders; every slot is overwritten by the fill.
        arbiters.truncate(slots.len());
        arbiters.resize(slots.len(), Arbiter::blank());
        let view = self.narrow_view();
        let stamp = self.state.stamp;
        crate::threads::zip_mut_split(&mut slots, arbiters, SLOT_PIECE, &|slot, arb| {
            fill(&view, input, stamp, slot, arb);
        });
        active.extend(
            slots
                .iter()
                .enumerate()
                .filter(|(_, slot)| slot.active)
                .map(|(index, _)| index as u32),
        );
        self.caches.arbiters.slots = slots;
    }

    /// The slots of this step's list in the serial merge's order: last
    /// step's arbiters of pairs no longer reported (or no longer touching)
    /// where they fall, unless expired; each touching pair's arbiter, the
    /// old one or a new one. Counts the touching pairs.
    fn plan_merge(&mut self, input: &MergeInputs<'_>, slots: &mut Vec<MergeSlot>) {
        slots.clear();
        let (stamp, persistence) = (self.state.stamp, self.state.settings.collision_persistence);
        let retired = |i: usize, slots: &mut Vec<MergeSlot>| {
            if input
                .old
                .get(i)
                .is_some_and(|arb| !arb.is_expired(stamp, persistence))
            {
                slots.push(MergeSlot {
                    old: i as u32,
                    pair: NONE,
                    active: false,
                });
            }
        };
        let unmatched_before = |i: usize, k: u32| {
            input.matched.get(i) == Some(&NONE) && input.place.get(i).is_some_and(|&p| p <= k)
        };
        let view = self.narrow_view();
        let (mut touching, mut cap_hits) = (0u32, 0u32);
        let mut i = 0usize;
        for (k, (&flags, &(ia, ib))) in input.flags.iter().zip(input.pairs).enumerate() {
            let k = k as u32;
            while unmatched_before(i, k) {
                retired(i, slots);
                i = i.saturating_add(1);
            }
            let existing = (input.matched.get(i) == Some(&k)).then_some(i);
            if existing.is_some() {
                i = i.saturating_add(1);
            }
            if flags & TOUCHES == 0 {
                if let Some(e) = existing {
                    retired(e, slots);
                }
                continue;
            }
            touching = touching.saturating_add(1);
            cap_hits = cap_hits.saturating_add(u32::from(flags & HIT_CAP != 0));
            // A new pair's shapes and bodies exist (the narrowphase found
            // them); the serial merge drops a pair whose lookup fails.
            let old = match existing {
                Some(e) => e as u32,
                None if view.touch_inputs(ia, ib).is_some() => NONE,
                None => continue,
            };
            slots.push(MergeSlot {
                old,
                pair: k,
                active: false,
            });
        }
        for rest in i..input.old.len() {
            retired(rest, slots);
        }
        let stats = &mut self.caches.step.stats;
        stats.touching_pairs = stats.touching_pairs.saturating_add(touching);
        stats.iteration_cap_hits = stats.iteration_cap_hits.saturating_add(cap_hits);
    }
}

/// Fills one planned slot: a copy of last step's arbiter (touched already
/// if its pair touches), cached if it retires; or a new arbiter touched
/// with its pair's answer.
fn fill(
    view: &NarrowView<'_>,
    input: &MergeInputs<'_>,
    stamp: u64,
    slot: &mut MergeSlot,
    arb: &mut Arbiter,
) {
    if let Some(old) = input.old.get(slot.old as usize) {
        arb.clone_from(old);
        if slot.pair == NONE {
            arb.cache();
        }
    } else {
        let (Some(Some(info)), Some(&(ia, ib))) = (
            input.infos.get(slot.pair as usize),
            input.pairs.get(slot.pair as usize),
        ) else {
            return;
        };
        // Present: the plan checked.
        let Some(((ha, sa), (hb, sb), centers)) = view.touch_handles(ia, ib) else {
            return;
        };
        *arb = Arbiter::new(ha, sa, hb, sb);
        arb.touch(info, sa, sb, centers, stamp);
    }
    slot.active = slot.pair != NONE && !arb.is_ignored() && !arb.sensor;
}
