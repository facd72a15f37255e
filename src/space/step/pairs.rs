//! [`Stage::Broadphase`](super::Stage::Broadphase): the candidate pairs of this sub-step, from the
//! moving shapes' sweep and the static and sleeping trees.
use crate::broadphase::Proxy;

use super::super::Space;

impl Space {
    /// [`Stage::Broadphase`](super::Stage::Broadphase): moving shapes are swept (their boxes listed by the shape-cache stage),
    /// static shapes come from the static tree (rebuilt only when statics
    /// changed). False, with no pairs, when there are more than the
    /// space's limits allow.
    pub(super) fn find_pairs(&mut self) -> bool {
        self.update_static_tree();
        self.rebuild_sleeping_tree();
        let budget = self.limits.pair_budget();
        let bp = &mut self.caches.broadphase;
        bp.sweep
            .find_pairs_with(&bp.proxies, &bp.static_tree, &bp.sleeping_tree, budget)
    }

    /// The sleeping tree from this step's sleeping boxes, if they changed
    /// (bodies fell asleep or woke since the last build).
    fn rebuild_sleeping_tree(&mut self) {
        let bp = &mut self.caches.broadphase;
        if bp.sleepers_dirty {
            bp.sleeping_tree = crate::broadphase::StaticTree::build(bp.sleepers.clone());
            bp.sleepers_dirty = false;
        }
    }

    /// The first half of [`Stage::Broadphase`](super::Stage::Broadphase) (also run by [`Stage::Bullets`](super::Stage::Bullets)):
    /// rebuilds the static tree from the static shapes' boxes if statics
    /// changed.
    pub(in crate::space) fn update_static_tree(&mut self) {
        if self.caches.broadphase.statics_dirty {
            let statics: Vec<Proxy> = self
                .caches
                .shapes
                .iter()
                .enumerate()
                .filter_map(|(i, c)| {
                    c.as_ref().filter(|c| c.is_static).map(|c| Proxy {
                        index: i as u32,
                        bb: c.bb,
                    })
                })
                .collect();
            self.caches.broadphase.set_statics(statics);
        }
    }
}
