//! Deterministic broadphase: which shape pairs have overlapping bounding boxes.
//!
//! * Moving shapes (dynamic and kinematic bodies) are found by
//!   **sort-and-sweep** on x: sort their boxes by left edge, then each box is
//!   tested against the boxes that start before it ends. Sorting keys are
//!   `(left, shape index)`, unique, so the order depends only on state.
//! * Static shapes go into a **static tree** (a bounding-volume hierarchy
//!   built by median splits), rebuilt only when the set of static shapes or
//!   their boxes change. Moving boxes query it, so a scene pays nothing per
//!   step for static shapes no moving shape is near.
//! * The output is a list of `(lower index, higher index)` pairs sorted
//!   ascending: the **canonical pair order**. The solver is Gauss–Seidel, so
//!   its order changes results; this order depends only on the shapes' slot
//!   indices and positions, never on a hash or on the sweep's internals.
use crate::math::wide::{raw_diff, raw_sum};
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
}

impl StaticTree {
    /// Builds the tree over `proxies` (deterministic: median splits along the
    /// longer axis, ties broken by shape index).
    pub fn build(mut proxies: Vec<Proxy>) -> StaticTree {
        proxies.sort_unstable_by_key(|p| p.index);
        let mut tree = StaticTree {
            proxies,
            nodes: Vec::new(),
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
            if !node.bb.intersects(bb) {
                continue;
            }
            if node.leaf {
                for p in self
                    .proxies
                    .get(node.first as usize..node.second as usize)
                    .unwrap_or(&[])
                {
                    if p.bb.intersects(bb) {
                        f(p.index);
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

/// Reusable broadphase buffers (not simulation state: rebuilt every step).
#[derive(Clone, Debug, Default)]
pub struct Broadphase {
    sorted: Vec<Proxy>,
    /// Candidate pairs of the last [`Broadphase::find_pairs`] call.
    pub pairs: Vec<(u32, u32)>,
}

impl Broadphase {
    /// Finds every pair of overlapping boxes among `moving` and between
    /// `moving` and `statics`, and leaves them in [`Broadphase::pairs`] in
    /// canonical order (sorted, lower index first, no duplicates).
    pub fn find_pairs(&mut self, moving: &[Proxy], statics: &StaticTree) {
        self.pairs.clear();
        self.sorted.clear();
        self.sorted.extend_from_slice(moving);
        self.sorted.sort_unstable_by_key(|p| (p.bb.l, p.index));
        let mut rest = self.sorted.as_slice();
        while let Some((a, later)) = rest.split_first() {
            rest = later;
            for b in later {
                if b.bb.l > a.bb.r {
                    break;
                }
                if a.bb.b <= b.bb.t && b.bb.b <= a.bb.t {
                    self.pairs.push(ordered(a.index, b.index));
                }
            }
            let pairs = &mut self.pairs;
            statics.query(&a.bb, |s| {
                if s != a.index {
                    pairs.push(ordered(a.index, s));
                }
            });
        }
        self.pairs.sort_unstable();
        self.pairs.dedup();
    }
}

/// The broadphase stage's buffers in the space (stage 3; not simulation
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
}

impl BroadphaseCache {
    /// Empty buffers whose static tree is rebuilt on the next step.
    pub(crate) fn dirty() -> BroadphaseCache {
        BroadphaseCache {
            statics_dirty: true,
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
mod tests {
    use super::*;
    use crate::math::{Real, Vect};

    fn proxy(i: u32, x: i32, y: i32) -> Proxy {
        Proxy {
            index: i,
            bb: BB::for_circle(Vect::from_ints(x, y), Real::ONE),
        }
    }

    #[test]
    fn finds_exactly_the_overlapping_pairs_in_canonical_order() {
        let moving = vec![
            proxy(5, 0, 0),
            proxy(2, 1, 0),
            proxy(9, 10, 0),
            proxy(7, 1, 1),
        ];
        let statics = StaticTree::build(vec![proxy(1, 11, 0), proxy(3, 50, 50)]);
        let mut bp = Broadphase::default();
        bp.find_pairs(&moving, &statics);
        assert_eq!(bp.pairs, vec![(1, 9), (2, 5), (2, 7), (5, 7)]);
    }

    #[test]
    fn static_tree_query_matches_brute_force() {
        let statics: Vec<Proxy> = (0..100)
            .map(|i| proxy(i, (i as i32 % 10) * 3, (i as i32 / 10) * 3))
            .collect();
        let tree = StaticTree::build(statics.clone());
        let q = BB::new(
            Real::from_int(4),
            Real::from_int(4),
            Real::from_int(10),
            Real::from_int(7),
        );
        let mut got = Vec::new();
        tree.query(&q, |i| got.push(i));
        got.sort_unstable();
        let want: Vec<u32> = statics
            .iter()
            .filter(|p| p.bb.intersects(&q))
            .map(|p| p.index)
            .collect();
        assert_eq!(got, want);
    }

    #[test]
    fn static_tree_splits_boxes_near_the_range_edge_by_position() {
        // Boxes around x = 2^31 − 1000: `l + r` on `Real` saturates for every
        // one of them, and a key built on it would order them by shape index
        // alone. The exact key keeps each leaf's boxes next to each other.
        let n = 64u32;
        let far = Real::MAX - Real::from_int(1000);
        let proxies: Vec<Proxy> = (0..n)
            .map(|k| Proxy {
                index: (k * 37) % n, // index order unrelated to position
                bb: BB::for_circle(
                    Vect::new(far + Real::from_int(3 * k as i32), Real::ZERO),
                    Real::ONE,
                ),
            })
            .collect();
        assert!((proxies[0].bb.l + proxies[0].bb.r).is_saturated());
        let tree = StaticTree::build(proxies.clone());
        let leaves: Vec<&Node> = tree.nodes.iter().filter(|n| n.leaf).collect();
        assert_eq!(leaves.len(), 16);
        for leaf in leaves {
            // 4 neighbours 3 apart, radius 1: 3·3 + 2 wide.
            assert_eq!(leaf.second - leaf.first, 4);
            assert_eq!(leaf.bb.r - leaf.bb.l, Real::from_int(11), "{leaf:?}");
        }
        // Queries still find exactly the touching boxes.
        let q = BB::for_circle(Vect::new(far + Real::from_int(30), Real::ZERO), Real::TWO);
        let mut got = Vec::new();
        tree.query(&q, |i| got.push(i));
        got.sort_unstable();
        let mut want: Vec<u32> = proxies
            .iter()
            .filter(|p| p.bb.intersects(&q))
            .map(|p| p.index)
            .collect();
        want.sort_unstable();
        assert_eq!(got, want);
        assert_eq!(want.len(), 3);
    }
}
