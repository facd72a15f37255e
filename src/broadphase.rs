//! Deterministic broadphase: which shape pairs have overlapping bounding boxes.
//!
//! * Moving shapes (dynamic and kinematic bodies) are found by
//!   **sort-and-sweep** on x: sort their boxes by left edge, then each box is
//!   tested against the boxes that start before it ends. Sorting keys are
//!   `(left, shape index)`, unique, so the order depends only on state. The
//!   sort starts from last step's order (an insertion sort, nearly linear
//!   when bodies move a little; see [`Broadphase`]): unique keys have one
//!   sorted order, so this changes the work, never the result.
//! * Static shapes go into a **static tree** (a bounding-volume hierarchy
//!   built by median splits), rebuilt only when the set of static shapes or
//!   their boxes change. Moving boxes query it, so a scene pays nothing per
//!   step for static shapes no moving shape is near. Each moving shape
//!   keeps the tree's answer for a **fattened box** around its own and
//!   re-queries only when its box leaves the fat one (Box2D's fat AABBs,
//!   here a cache): the answer for the fat box holds every static box the
//!   shape's box can touch, so filtering it gives the very pairs a fresh
//!   query gives.
//! * The output is a list of `(lower index, higher index)` pairs sorted
//!   ascending (a counting sort on the lower index): the **canonical pair
//!   order**. The solver is Gauss–Seidel, so
//!   its order changes results; this order depends only on the shapes' slot
//!   indices and positions, never on a hash or on the sweep's internals.
use crate::math::exact::{raw_diff, raw_sum};
use crate::math::BB;

/// A box to sort, with the shape slot it belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Proxy {
    /// Shape slot index.
    pub index: u32,
    /// World bounding box.
    pub bb: BB,
}

/// A node of the static tree: either a leaf range of proxies or two children.
#[derive(Clone, Copy, Debug)]
struct Node {
    bb: BB,
    /// Leaf: `start..end` into `StaticTree::proxies`; inner: children indices.
    first: u32,
    second: u32,
    leaf: bool,
}

/// Leaves hold up to this many proxies (a few box tests beat deeper trees).
const LEAF_SIZE: usize = 4;

/// Bounding-volume hierarchy over static shapes.
#[derive(Clone, Debug, Default)]
pub struct StaticTree {
    proxies: Vec<Proxy>,
    nodes: Vec<Node>,
    /// Which build this is (unique per [`StaticTree::build`] in the
    /// process; a clone keeps it, the empty default tree is 0): what a
    /// [`Broadphase`]'s cached answers were taken from. Never part of a
    /// result: a cache that is cold or dropped gives the same pairs.
    id: u64,
}

/// The next [`StaticTree::id`]. A process-wide counter, so two trees built
/// apart never share an id, whatever space or thread built them; which
/// number a tree gets changes how often a cache is reused, never a pair.
static NEXT_TREE_ID: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(1);

impl StaticTree {
    /// Builds the tree over `proxies` (deterministic: median splits along the
    /// longer axis, ties broken by shape index).
    pub fn build(mut proxies: Vec<Proxy>) -> StaticTree {
        proxies.sort_unstable_by_key(|p| p.index);
        let proxies_empty = proxies.is_empty();
        let mut tree = StaticTree {
            proxies,
            nodes: Vec::new(),
            // Empty trees answer alike: they share the default's id 0, so a
            // rebuilt empty tree (no body asleep) keeps the answers cached.
            id: if proxies_empty {
                0
            } else {
                NEXT_TREE_ID.fetch_add(1, core::sync::atomic::Ordering::Relaxed)
            },
        };
        if !tree.proxies.is_empty() {
            let n = tree.proxies.len();
            tree.build_node(0, n);
        }
        tree
    }

    fn build_node(&mut self, start: usize, end: usize) -> u32 {
        let slice = self.proxies.get(start..end).unwrap_or(&[]);
        let count = slice.len();
        let bb = slice
            .iter()
            .skip(1)
            .fold(slice.first().map(|p| p.bb).unwrap_or_default(), |acc, p| {
                acc.merge(&p.bb)
            });
        let id = self.nodes.len() as u32;
        if count <= LEAF_SIZE {
            self.nodes.push(Node {
                bb,
                first: start as u32,
                second: end as u32,
                leaf: true,
            });
            return id;
        }
        self.nodes.push(Node {
            bb,
            first: 0,
            second: 0,
            leaf: false,
        });
        // Extents and centres on i128, exact: `Real` sums and differences
        // saturate for boxes near ±2^31, which would spoil the balance (and
        // give every such box the same key). The sort key `l + r` is twice
        // the centre.
        let wide = raw_diff(bb.r, bb.l) >= raw_diff(bb.t, bb.b);
        if let Some(slice) = self.proxies.get_mut(start..end) {
            if wide {
                slice.sort_unstable_by_key(|p| (raw_sum(p.bb.l, p.bb.r), p.index));
            } else {
                slice.sort_unstable_by_key(|p| (raw_sum(p.bb.b, p.bb.t), p.index));
            }
        }
        // `count` is the length of `proxies[start..end]`, so the sum is at
        // most `end`: never saturates.
        let mid = start.saturating_add(count / 2);
        let first = self.build_node(start, mid);
        let second = self.build_node(mid, end);
        if let Some(node) = self.nodes.get_mut(id as usize) {
            node.first = first;
            node.second = second;
        }
        id
    }

    /// Number of static proxies.
    pub fn len(&self) -> usize {
        self.proxies.len()
    }

    /// True if there are no static proxies.
    pub fn is_empty(&self) -> bool {
        self.proxies.is_empty()
    }

    /// Calls `f` with the index of every static proxy whose box touches `bb`.
    pub fn query(&self, bb: &BB, mut f: impl FnMut(u32)) {
        self.query_proxies(bb, |_| true, |p| f(p.index));
    }

    /// [`query`](Self::query) that also skips every node and proxy whose
    /// box fails `keep` (a finer test than the box overlap, e.g. a ray's
    /// line): `keep` must hold for every box that can contain a hit.
    pub fn query_where(&self, bb: &BB, keep: impl Fn(&BB) -> bool, mut f: impl FnMut(u32)) {
        self.query_proxies(bb, keep, |p| f(p.index));
    }

    /// [`query_where`](Self::query_where), handing out each proxy (its box
    /// too), in the tree's fixed depth-first order.
    fn query_proxies(&self, bb: &BB, keep: impl Fn(&BB) -> bool, mut f: impl FnMut(&Proxy)) {
        if self.nodes.is_empty() {
            return;
        }
        // Explicit stack: depth is O(log n), the array lives on the stack.
        let mut stack: [u32; 64] = [0; 64];
        let mut top = 1usize;
        while let Some(below) = top.checked_sub(1) {
            top = below;
            let Some(node) = stack.get(top).and_then(|&i| self.nodes.get(i as usize)) else {
                continue;
            };
            if !node.bb.intersects(bb) || !keep(&node.bb) {
                continue;
            }
            if node.leaf {
                for p in self
                    .proxies
                    .get(node.first as usize..node.second as usize)
                    .unwrap_or(&[])
                {
                    if p.bb.intersects(bb) && keep(&p.bb) {
                        f(p);
                    }
                }
            } else if let Some([second, first, ..]) = stack.get_mut(top..) {
                *second = node.second;
                *first = node.first;
                // Two slots at `top..` exist, so `top + 2 ≤ stack.len()`.
                top = top.saturating_add(2);
            }
        }
    }
}

/// Reusable broadphase buffers (not simulation state: any content gives the
/// same pairs).
///
/// The sweep keeps last call's sorted order and re-sorts it by insertion:
/// boxes move a little between steps, so the order is nearly right and the
/// sort costs about one comparison per box instead of a full sort's
/// `log n`. The sort keys `(left, shape index)` are unique, so every sorting
/// method gives the same sequence: the order kept from last step changes
/// the work, never the pairs or their order. A call whose boxes are far
/// from last call's order (the first one, a restore, a teleport of many
/// bodies) notices the many shifts and finishes with a full sort.
#[derive(Clone, Debug, Default)]
pub struct Broadphase {
    /// The moving boxes sorted by `(left, index)`, kept between calls.
    sorted: Vec<Proxy>,
    /// Per shape slot: its position in this call's `moving` (scratch).
    slot_pos: Vec<u32>,
    /// Pairs as found, before they are put in canonical order (scratch).
    found: Vec<(u32, u32)>,
    /// Per lower shape slot: the start of its pairs in `pairs` (scratch).
    bucket: Vec<u32>,
    /// Candidate pairs of the last [`Broadphase::find_pairs`] call.
    pub pairs: Vec<(u32, u32)>,
    /// Per moving shape slot: the trees' answer for its fat box.
    hits: Vec<StaticHits>,
    /// With threads: the moving pairs each piece of the sweep found
    /// (scratch, kept so that a warm step does not allocate).
    pieces: Vec<Vec<(u32, u32)>>,
}

/// The static and sleeping proxies whose boxes touch `fat`, as the trees
/// `trees` (their ids; `None`: not asked yet) answered; valid for any box
/// inside `fat` and those same trees.
#[derive(Clone, Debug, Default)]
struct StaticHits {
    trees: Option<(u64, u64)>,
    fat: BB,
    found: Vec<Proxy>,
    /// The shape's box at the last call: how far it moves per step.
    last: BB,
}

/// Steps of motion a fat box looks ahead.
const LOOK_AHEAD: i32 = 8;

/// The box to query for `bb`, whose box one call ago was `last` (`None`:
/// no earlier call): `bb` stretched [`LOOK_AHEAD`] steps' motion along the
/// way each edge moves (Box2D's predicted displacement, here measured from
/// the boxes), at most 4 sides' worth (a teleport asks for no giant box),
/// plus an eighth of its larger side on every side for turning and jitter.
/// A fat box reaches ahead, not sideways: a shape running down a corridor
/// of static shapes meets few more candidates than its own box does. `Real`
/// arithmetic saturates: near the range's edge the box is clamped there and
/// still holds `bb`.
fn fatten(bb: &BB, last: Option<&BB>) -> BB {
    use crate::math::Real;
    let side = (bb.r - bb.l).max(bb.t - bb.b);
    let margin = side / Real::from_int(8);
    let (ahead, cap) = (Real::from_int(LOOK_AHEAD), side * Real::from_int(4));
    // How far to stretch an edge that moved by `d` (outward only).
    let stretch = |d: Real| (d.abs() * ahead).min(cap);
    let (dl, db, dr, dt) = last.map_or((Real::ZERO, Real::ZERO, Real::ZERO, Real::ZERO), |o| {
        (bb.l - o.l, bb.b - o.b, bb.r - o.r, bb.t - o.t)
    });
    let out = |d: Real, sign_out: bool| {
        if d.is_negative() == sign_out && !d.is_zero() {
            stretch(d)
        } else {
            Real::ZERO
        }
    };
    BB::new(
        bb.l - out(dl, true) - margin,
        bb.b - out(db, true) - margin,
        bb.r + out(dr, false) + margin,
        bb.t + out(dt, false) + margin,
    )
}

impl StaticHits {
    /// The answer for `bb`: the cached one if `bb` lies in the fat box and
    /// the trees are the ones it came from, else a new query of a fat box
    /// around `bb` (see [`StaticHits::fatten`]). Either way the list holds
    /// every proxy touching `bb` (and maybe a few more).
    fn refresh(&mut self, bb: &BB, statics: &StaticTree, sleeping: &StaticTree) -> &[Proxy] {
        let trees = Some((statics.id, sleeping.id));
        if self.trees != trees || !self.fat.contains_bb(bb) {
            self.fat = fatten(bb, self.trees.map(|_| &self.last));
            self.trees = trees;
            self.found.clear();
            for tree in [statics, sleeping] {
                tree.query_proxies(&self.fat, |_| true, |p| self.found.push(*p));
            }
        }
        self.last = *bb;
        &self.found
    }
}

/// The pairs of `a` with the boxes after it in sweep order (`later`)
/// whose boxes overlap it: the scan stops at the first box that starts
/// to the right of `a`.
#[inline]
fn sweep_one(a: &Proxy, later: &[Proxy], found: &mut Vec<(u32, u32)>) {
    for b in later {
        if b.bb.l > a.bb.r {
            break;
        }
        if a.bb.b <= b.bb.t && b.bb.b <= a.bb.t {
            found.push(ordered(a.index, b.index));
        }
    }
}

/// Sorted boxes per piece of the split sweep (each scans its neighbours:
/// tens of µs of work in a pile); a few in unit tests, so that their small
/// worlds are split too.
#[cfg(not(test))]
const SWEEP_PIECE: usize = 256;
#[cfg(test)]
const SWEEP_PIECE: usize = 3;

/// [`sweep_one`] for the boxes of `sorted` from piece `first` on, one
/// piece per entry of `out` (cleared first), halves in parallel.
/// A piece stops once it holds more than `limit` pairs (the whole sweep
/// is then over the limit).
fn sweep_split(sorted: &[Proxy], first: usize, out: &mut [Vec<(u32, u32)>], limit: usize) {
    if let [found] = out {
        found.clear();
        let start = first.saturating_mul(SWEEP_PIECE);
        let end = start.saturating_add(SWEEP_PIECE).min(sorted.len());
        for k in start..end {
            if found.len() > limit {
                return;
            }
            if let (Some(a), Some(later)) = (sorted.get(k), sorted.get(k.saturating_add(1)..)) {
                sweep_one(a, later, found);
            }
        }
        return;
    }
    if out.is_empty() {
        return;
    }
    let mid = out.len() / 2;
    let (left, right) = out.split_at_mut(mid);
    crate::threads::join(
        || sweep_split(sorted, first, left, limit),
        || sweep_split(sorted, first.saturating_add(mid), right, limit),
    );
}

/// No position (a slot without a box in this call).
const NONE: u32 = u32::MAX;

/// The sort key of the sweep; unique per proxy (shape indices are unique).
#[inline]
fn sweep_key(p: &Proxy) -> (crate::math::Real, u32) {
    (p.bb.l, p.index)
}

impl Broadphase {
    /// Finds every pair of overlapping boxes among `moving` and between
    /// `moving` and `statics`, and leaves them in [`Broadphase::pairs`] in
    /// canonical order (sorted, lower index first, no duplicates).
    /// `sleeping` holds the shapes of sleeping bodies: queried like
    /// `statics`, so they pair only with moving shapes.
    pub fn find_pairs(&mut self, moving: &[Proxy], statics: &StaticTree, sleeping: &StaticTree) {
        self.find_pairs_with(moving, statics, sleeping, usize::MAX);
    }

    /// [`find_pairs`](Self::find_pairs) with a pair budget. The sweep of
    /// the moving boxes against each other runs in pieces, halves in
    /// parallel where the step has threads ([`crate::threads::join`]; inline
    /// on one), before the static queries. The same pairs on any thread
    /// count: the order pairs are found in is put right by
    /// [`canonical_pairs`](Self::canonical_pairs).
    ///
    /// More than `limit` pairs (a budget for untrusted worlds, see
    /// `crate::limits`) stops the search as soon as it is known, with the
    /// work done bounded by the limit (per piece of a split sweep), and
    /// returns `false`: the pairs are then incomplete and must not be used.
    pub(crate) fn find_pairs_with(
        &mut self,
        moving: &[Proxy],
        statics: &StaticTree,
        sleeping: &StaticTree,
        limit: usize,
    ) -> bool {
        self.sort_moving(moving);
        self.found.clear();
        // One path for any thread count: the sweep in pieces, halves in
        // parallel where there are threads (inline on one), joined in
        // order; then each box against the trees.
        let pieces = self.sorted.len().div_ceil(SWEEP_PIECE);
        self.pieces.resize_with(pieces, Vec::new);
        sweep_split(&self.sorted, 0, &mut self.pieces, limit);
        for piece in self.pieces.get(..pieces).unwrap_or(&[]) {
            self.found.extend_from_slice(piece);
        }
        // The fat-box answers, by shape slot counted from the lowest moving
        // one (a level's static slots below take no room), when those slots
        // are dense (see `dense_limit`); otherwise every box queries the
        // trees with its own box. Which entry serves which shape changes
        // the work only: an entry answers any box inside its fat box.
        let base = self.sorted.iter().map(|p| p.index).min().unwrap_or(0);
        let at = |index: u32| index.wrapping_sub(base) as usize;
        let slots = self
            .sorted
            .iter()
            .map(|p| at(p.index))
            .max()
            .map_or(0, |m| m.saturating_add(1));
        let table = slots <= dense_limit(self.sorted.len());
        if table && self.hits.len() < slots {
            self.hits.resize_with(slots, StaticHits::default);
        }
        let Broadphase {
            found, hits, pairs, ..
        } = self;
        // In the caller's order (by shape slot where a space calls), not
        // the sweep's: the table is then read in order instead of at
        // random, and the pairs are sorted below anyway.
        for a in moving {
            if found.len() > limit {
                found.clear();
                pairs.clear();
                return false;
            }
            if statics.is_empty() && sleeping.is_empty() {
                break;
            }
            match hits.get_mut(at(a.index)).filter(|_| table) {
                Some(cache) => {
                    for s in cache.refresh(&a.bb, statics, sleeping) {
                        if s.index != a.index && s.bb.intersects(&a.bb) {
                            found.push(ordered(a.index, s.index));
                        }
                    }
                }
                None => {
                    for tree in [statics, sleeping] {
                        tree.query(&a.bb, |s| {
                            if s != a.index {
                                found.push(ordered(a.index, s));
                            }
                        });
                    }
                }
            }
        }
        if found.len() > limit {
            found.clear();
            pairs.clear();
            return false;
        }
        self.canonical_pairs();
        true
    }

    /// Leaves `moving` in `sorted`, sorted by [`sweep_key`]: last call's
    /// order with this call's boxes (shapes gone dropped, new ones
    /// appended), then insertion sort; a full sort if `moving` repeats a
    /// shape index or the insertion sort shifts too much.
    fn sort_moving(&mut self, moving: &[Proxy]) {
        // The table covers the moving shapes' slots only, from the lowest:
        // a level's static slots below them cost nothing.
        let base = moving.iter().map(|p| p.index).min().unwrap_or(0);
        let at = |index: u32| index.wrapping_sub(base) as usize;
        let slots = moving
            .iter()
            .map(|p| at(p.index))
            .max()
            .map_or(0, |m| m.saturating_add(1));
        self.slot_pos.clear();
        let mut unique = slots <= dense_limit(moving.len());
        if unique {
            self.slot_pos.resize(slots, NONE);
        }
        for (k, p) in moving.iter().enumerate() {
            if let Some(pos) = self.slot_pos.get_mut(at(p.index)) {
                unique &= *pos == NONE;
                *pos = k as u32;
            }
        }
        // Repeated indices, or indices too sparse for a table: a plain sort.
        if !unique {
            self.sorted.clear();
            self.sorted.extend_from_slice(moving);
            self.sorted.sort_unstable_by_key(sweep_key);
            return;
        }
        // Last call's order, each box replaced by this call's (or dropped);
        // a slot taken here is marked so the new ones can be found.
        let slot_pos = &mut self.slot_pos;
        self.sorted.retain_mut(|p| {
            // A shape below `base` is gone (wrapping puts it past the table).
            let Some(pos) = slot_pos.get_mut(at(p.index)) else {
                return false;
            };
            match moving.get(*pos as usize) {
                Some(now) => {
                    *p = *now;
                    *pos = NONE;
                    true
                }
                None => false,
            }
        });
        for p in moving {
            if self.slot_pos.get(at(p.index)) != Some(&NONE) {
                self.sorted.push(*p);
            }
        }
        if !insertion_sort(&mut self.sorted) {
            self.sorted.sort_unstable_by_key(sweep_key);
        }
    }

    /// Puts `found` into `pairs` in canonical order without duplicates: a
    /// counting sort on the lower index, then an insertion sort of each
    /// lower index's few partners.
    fn canonical_pairs(&mut self) {
        self.pairs.clear();
        let slots = self
            .found
            .iter()
            .map(|&(lo, _)| lo as usize)
            .max()
            .map_or(0, |m| m.saturating_add(2));
        self.bucket.clear();
        // The counting sort walks a table of every slot up to the highest
        // lower index: worth it when the pairs are many for the slots (a
        // pile), not for a few pairs among a large level's slots.
        if slots > dense_limit(self.found.len()) || slots > self.found.len().saturating_mul(8) {
            self.pairs.extend_from_slice(&self.found);
            self.pairs.sort_unstable();
            self.pairs.dedup();
            return;
        }
        self.bucket.resize(slots, 0);
        // Counts at lo + 1, then running sums: bucket[lo] is the start of
        // lo's pairs. Sums never exceed `found.len()`: no saturation.
        for &(lo, _) in &self.found {
            if let Some(c) = self.bucket.get_mut((lo as usize).saturating_add(1)) {
                *c = c.saturating_add(1);
            }
        }
        let mut sum = 0u32;
        for c in &mut self.bucket {
            sum = sum.saturating_add(*c);
            *c = sum;
        }
        self.pairs.resize(self.found.len(), (0, 0));
        for &pair in &self.found {
            if let Some(at) = self.bucket.get_mut(pair.0 as usize) {
                if let Some(slot) = self.pairs.get_mut(*at as usize) {
                    *slot = pair;
                }
                *at = at.saturating_add(1);
            }
        }
        // Each lower index's run is now contiguous and the runs ascend; the
        // runs are short (a shape's neighbours), so insertion sort them all
        // at once: it only ever moves an entry within its run.
        if !insertion_sort_pairs(&mut self.pairs) {
            self.pairs.sort_unstable();
        }
        self.pairs.dedup();
    }
}

/// The largest table indexed by shape slot that the sweep builds for `len`
/// entries: a space's slots are dense (at most its shape count), but a
/// caller of [`Broadphase::find_pairs`] may pass any index, and a table
/// for index 2^32 − 1 would take 16 GiB. Above it, plain sorts.
#[inline]
fn dense_limit(len: usize) -> usize {
    len.saturating_mul(4).saturating_add(4096)
}

/// Insertion sort by [`sweep_key`]; gives up (returning `false`, the slice
/// then holds a permutation of its entries) once it has shifted more than
/// a few entries per element, which only a far-from-sorted input does.
fn insertion_sort(v: &mut [Proxy]) -> bool {
    let budget = v.len().saturating_mul(4).saturating_add(64);
    insertion_sort_by(v, budget, |a, b| sweep_key(a) > sweep_key(b))
}

/// [`insertion_sort`] for pairs in lexicographic order.
fn insertion_sort_pairs(v: &mut [(u32, u32)]) -> bool {
    let budget = v.len().saturating_mul(8).saturating_add(64);
    insertion_sort_by(v, budget, |a, b| a > b)
}

/// Insertion sort with `after(x, y)` meaning "x goes after y", stopping
/// (returning `false`) once more than `budget` entries have been shifted.
fn insertion_sort_by<T: Copy>(v: &mut [T], budget: usize, after: impl Fn(&T, &T) -> bool) -> bool {
    let mut shifted = 0usize;
    for i in 1..v.len() {
        let Some(&x) = v.get(i) else { break };
        let mut j = i;
        while let Some(prev) = j.checked_sub(1).and_then(|k| v.get(k)).copied() {
            if !after(&prev, &x) {
                break;
            }
            if let Some(slot) = v.get_mut(j) {
                *slot = prev;
            }
            j = j.saturating_sub(1);
            shifted = shifted.saturating_add(1);
        }
        if let Some(slot) = v.get_mut(j) {
            *slot = x;
        }
        if shifted > budget {
            return false;
        }
    }
    true
}

/// The broadphase stage's buffers in the space (the broadphase stage; not simulation
/// state: derived from the shapes and rebuilt as needed).
#[derive(Clone, Debug, Default)]
pub(crate) struct BroadphaseCache {
    /// The moving shapes' boxes of this step.
    pub(crate) proxies: Vec<Proxy>,
    /// The static shapes' tree, rebuilt only when `statics_dirty`.
    pub(crate) static_tree: StaticTree,
    /// Set when static shapes were added, removed or moved (or the state
    /// replaced): the next step rebuilds the static tree.
    pub(crate) statics_dirty: bool,
    /// The sweep and its output pairs.
    pub(crate) sweep: Broadphase,
    /// The static boxes `static_tree` was built from (slot order): a step
    /// that finds the same ones (a restore of the same level, a static body
    /// set to where it was) keeps the tree.
    pub(crate) static_inputs: Vec<Proxy>,
    /// How many times the static tree was built (diagnostics, tests).
    pub(crate) static_builds: u64,
    /// The sleeping bodies' shapes (see `space::sleep`), rebuilt when
    /// `sleepers_dirty`.
    pub(crate) sleeping_tree: StaticTree,
    /// Set when bodies fell asleep or woke (or the state was replaced):
    /// the next step rewrites the sleeping shapes' entries and rebuilds
    /// `sleeping_tree`.
    pub(crate) sleepers_dirty: bool,
    /// The sleeping shapes' boxes of this step (filled when dirty).
    pub(crate) sleepers: Vec<Proxy>,
    /// How many bodies sleep, once counted (`None`: unknown since the
    /// sleeping set changed or a state was loaded). Lets the API skip
    /// sleep checks while a level is built.
    pub(crate) sleeping_count: Option<usize>,
}

impl BroadphaseCache {
    /// Empty buffers whose static tree is rebuilt on the next step.
    pub(crate) fn dirty() -> BroadphaseCache {
        BroadphaseCache {
            statics_dirty: true,
            sleepers_dirty: true,
            ..BroadphaseCache::default()
        }
    }

    /// Takes the static shapes' boxes in slot order and rebuilds the static
    /// tree only if they differ from those it was built from (the tree is
    /// a function of them: keeping it changes nothing).
    pub(crate) fn set_statics(&mut self, statics: Vec<Proxy>) {
        self.statics_dirty = false;
        if statics == self.static_inputs {
            return;
        }
        self.static_tree = StaticTree::build(statics.clone());
        self.static_inputs = statics;
        self.static_builds = self.static_builds.saturating_add(1);
    }
}

fn ordered(a: u32, b: u32) -> (u32, u32) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

#[cfg(test)]
mod tests;
