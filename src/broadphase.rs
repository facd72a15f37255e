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
        let bb = slice
            .iter()
            .skip(1)
            .fold(slice.first().map(|p| p.bb).unwrap_or_default(), |acc, p| {
                acc.merge(&p.bb)
            });
        let id = self.nodes.len() as u32;
        if end - start <= LEAF_SIZE {
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
        let wide = (bb.r - bb.l) >= (bb.t - bb.b);
        if let Some(slice) = self.proxies.get_mut(start..end) {
            // Twice the centre, to stay exact: l + r.
            if wide {
                slice.sort_unstable_by_key(|p| (p.bb.l + p.bb.r, p.index));
            } else {
                slice.sort_unstable_by_key(|p| (p.bb.b + p.bb.t, p.index));
            }
        }
        let mid = start + (end - start) / 2;
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
        // Explicit stack: depth is O(log n), the vector is reused per call.
        let mut stack: [u32; 64] = [0; 64];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
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
            } else if top + 2 <= stack.len() {
                if let Some(slot) = stack.get_mut(top) {
                    *slot = node.second;
                }
                if let Some(slot) = stack.get_mut(top + 1) {
                    *slot = node.first;
                }
                top += 2;
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
        for (i, a) in self.sorted.iter().enumerate() {
            for b in self.sorted.iter().skip(i + 1) {
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
}
