//! The sleep stage's buffers and its union–find over body slots: leaf
//! types the space's caches hold, apart from the stage (`space::sleep`)
//! that runs on the space.
use crate::math::Real;

/// Buffers of the sleep stage, kept between steps so that a step allocates
/// nothing once they have grown (contents are rewritten every step).
#[derive(Default)]
pub(crate) struct SleepScratch {
    pub(super) parent: Vec<u32>,
    pub(super) restless: Vec<u32>,
    pub(super) restless_slot: Vec<bool>,
    pub(super) least: Vec<Option<Real>>,
}

/// Union–find over body slots with the lowest slot as the representative
/// (so an island's root is its lowest slot, whatever the union order).
pub(super) struct Islands<'a> {
    parent: &'a mut Vec<u32>,
}

impl<'a> Islands<'a> {
    /// `n` singletons, in `parent`'s storage.
    pub(super) fn new(parent: &'a mut Vec<u32>, n: usize) -> Islands<'a> {
        parent.clear();
        parent.extend(0..n as u32);
        Islands { parent }
    }

    pub(super) fn find(&mut self, mut i: u32) -> u32 {
        while let Some(&p) = self.parent.get(i as usize) {
            if p == i {
                break;
            }
            // Path halving: point at the grandparent.
            let gp = self.parent.get(p as usize).copied().unwrap_or(p);
            if let Some(slot) = self.parent.get_mut(i as usize) {
                *slot = gp;
            }
            i = gp;
        }
        i
    }

    pub(super) fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        if let Some(slot) = self.parent.get_mut(hi as usize) {
            *slot = lo;
        }
    }
}
