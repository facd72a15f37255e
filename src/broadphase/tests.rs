//! Tests of the sort-and-sweep, the static tree and their split between threads.
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
    bp.find_pairs(&moving, &statics, &StaticTree::default());
    assert_eq!(bp.pairs, vec![(1, 9), (2, 5), (2, 7), (5, 7)]);
}

/// The sweep before it kept its order between calls: a full sort of the
/// boxes and of the pairs on every call.
fn find_pairs_full_sort(moving: &[Proxy], statics: &StaticTree) -> Vec<(u32, u32)> {
    let mut sorted = moving.to_vec();
    sorted.sort_unstable_by_key(|p| (p.bb.l, p.index));
    let mut pairs = Vec::new();
    for (i, a) in sorted.iter().enumerate() {
        for b in &sorted[i + 1..] {
            if b.bb.l > a.bb.r {
                break;
            }
            if a.bb.b <= b.bb.t && b.bb.b <= a.bb.t {
                pairs.push(ordered(a.index, b.index));
            }
        }
        statics.query(&a.bb, |s| {
            if s != a.index {
                pairs.push(ordered(a.index, s));
            }
        });
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// One step of a random world of boxes `(index, x, y)`: each move
/// `(index, dx, dy, what)` removes the box (`what` 0), adds one at
/// `jump` times `(dx, dy)` (1), or moves it by `(dx, dy)`; the world
/// is left sorted by index.
fn apply_moves(world: &mut Vec<(u32, i32, i32)>, moves: &[(u32, i32, i32, u8)], jump: i32) {
    for &(i, dx, dy, what) in moves {
        match what {
            0 => world.retain(|b| b.0 != i),
            1 => world.push((i, dx * jump, dy * jump)),
            _ => {
                for b in world.iter_mut().filter(|b| b.0 == i) {
                    b.1 += dx;
                    b.2 += dy;
                }
            }
        }
    }
    world.sort_by_key(|b| b.0);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
    /// Calls on one `Broadphase` whose boxes move a little, jump, appear,
    /// vanish, tie on their left edges or repeat an index give exactly the
    /// pairs of a fresh full sort, in the same order; so does the sweep
    /// split in pieces, empty worlds included.
    #[test]
    fn persistent_sweep_gives_the_full_sort_pairs(
        start in proptest::collection::vec((0u32..60, -20i32..20, -20i32..20), 0..60),
        moves in proptest::collection::vec(
            proptest::collection::vec((0u32..60, -3i32..=3, -3i32..=3, 0u8..10), 0..40),
            1..6,
        ),
        statics in proptest::collection::vec((60u32..80, -20i32..20, -20i32..20), 0..10),
    ) {
        let tree = StaticTree::build(statics.iter().map(|&(i, x, y)| proxy(i, x, y)).collect());
        let mut world: Vec<(u32, i32, i32)> = start;
        let mut bp = Broadphase::default();
        for step in moves {
            apply_moves(&mut world, &step, 7);
            let moving: Vec<Proxy> = world.iter().map(|&(i, x, y)| proxy(i, x, y)).collect();
            bp.find_pairs(&moving, &tree, &StaticTree::default());
            proptest::prop_assert_eq!(&bp.pairs, &find_pairs_full_sort(&moving, &tree));
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]
    /// The fat-box cache changes no pair: calls on one `Broadphase`
    /// whose moving boxes creep, jump, vanish and come back, while the
    /// static and sleeping trees are rebuilt, kept or swapped, give
    /// exactly the pairs of a fresh `Broadphase` (cold cache) each call.
    #[test]
    fn cached_static_answers_give_the_pairs_of_fresh_queries(
        start in proptest::collection::vec((0u32..40, -30i32..30, -30i32..30), 0..40),
        steps in proptest::collection::vec(
            (
                proptest::collection::vec((0u32..40, -4i32..=4, -4i32..=4, 0u8..12), 0..30),
                0u8..6,
            ),
            1..8,
        ),
        statics in proptest::collection::vec((40u32..90, -30i32..30, -30i32..30), 0..40),
    ) {
        let build = |list: &[(u32, i32, i32)]| {
            StaticTree::build(list.iter().map(|&(i, x, y)| proxy(i, x, y)).collect())
        };
        let mut level = statics.clone();
        let mut tree = build(&level);
        let mut sleeping = StaticTree::default();
        let mut world: Vec<(u32, i32, i32)> = start;
        let mut bp = Broadphase::default();
        for (moves, what_trees) in steps {
            apply_moves(&mut world, &moves, 9);
            world.dedup_by_key(|b| b.0);
            match what_trees {
                // A static shape moves: a new tree.
                0 => {
                    if let Some(s) = level.first_mut() {
                        s.1 += 3;
                    }
                    tree = build(&level);
                }
                // Some moving boxes fall asleep (a sleeping tree of them).
                1 => sleeping = build(&world.iter().take(3).map(|&(i, x, y)| (i + 100, x, y)).collect::<Vec<_>>()),
                2 => sleeping = StaticTree::default(),
                // The same boxes, a rebuilt tree (a new id).
                3 => tree = build(&level),
                _ => {}
            }
            let moving: Vec<Proxy> = world.iter().map(|&(i, x, y)| proxy(i, x, y)).collect();
            bp.find_pairs(&moving, &tree, &sleeping);
            let mut cold = Broadphase::default();
            cold.find_pairs(&moving, &tree, &sleeping);
            proptest::prop_assert_eq!(&bp.pairs, &cold.pairs);
        }
    }
}

#[test]
fn a_moving_shape_re_queries_only_when_it_leaves_its_fat_box() {
    // Boxes are 2 × 2 around their points; a static box at x = 6.
    let tree = StaticTree::build(vec![proxy(10, 6, 0), proxy(11, 60, 0)]);
    let empty = StaticTree::default();
    let mut bp = Broadphase::default();
    let at = |x: i32| Proxy {
        index: 1,
        bb: BB::for_circle(Vect::new(Real::ratio(x, 2), Real::ZERO), Real::ONE),
    };
    // x = 0, then x = 0.5: the second fat box reaches 8 steps of 0.5
    // ahead (to x = 5.25), which takes in the static box (5..7).
    bp.find_pairs(&[at(0)], &tree, &empty);
    bp.find_pairs(&[at(1)], &tree, &empty);
    let fat = bp.hits.first().map(|h| h.fat);
    assert!(fat.is_some_and(|f| f.r > Real::from_int(5)), "{fat:?}");
    // Moving on at 0.5 per call: the same fat box answers, and the pair
    // appears when the boxes touch (x = 4: 3..5 touches 5..7).
    for x in 2..=8 {
        bp.find_pairs(&[at(x)], &tree, &empty);
        assert_eq!(bp.hits.first().map(|h| h.fat), fat, "x = {x}/2");
        let touching = x >= 8;
        assert_eq!(bp.pairs == vec![(1, 10)], touching, "x = {x}/2");
    }
    // Far away: a new fat box, the other static box.
    bp.find_pairs(
        &[Proxy {
            index: 1,
            bb: BB::for_circle(Vect::from_ints(59, 0), Real::ONE),
        }],
        &tree,
        &empty,
    );
    assert_ne!(bp.hits.first().map(|h| h.fat), fat);
    assert_eq!(bp.pairs, vec![(1, 11)]);
}

#[test]
fn sparse_indices_take_the_plain_sorts() {
    // Slot tables for these indices would take gigabytes: the sweep and
    // the pair order fall back to plain sorts, with the same answer.
    let tree = StaticTree::build(vec![proxy(u32::MAX - 2, 0, 1)]);
    let moving = vec![
        proxy(u32::MAX - 1, 0, 0),
        proxy(7, 1, 0),
        proxy(u32::MAX, 1, 1),
    ];
    let mut bp = Broadphase::default();
    for _ in 0..2 {
        bp.find_pairs(&moving, &tree, &StaticTree::default());
        assert_eq!(bp.pairs, find_pairs_full_sort(&moving, &tree));
        assert_eq!(bp.pairs.len(), 6);
    }
    assert!(bp.slot_pos.capacity() < 1 << 20 && bp.bucket.capacity() < 1 << 20);
}

#[test]
fn persistent_sweep_survives_a_reversal() {
    // Every box jumps past every other: the insertion sort gives up and
    // the full sort finishes; the pairs are those of a fresh sweep.
    let tree = StaticTree::default();
    let forward: Vec<Proxy> = (0..200).map(|i| proxy(i, i as i32, 0)).collect();
    let backward: Vec<Proxy> = (0..200).map(|i| proxy(i, -(i as i32), 0)).collect();
    let mut bp = Broadphase::default();
    for moving in [&forward, &backward, &forward] {
        bp.find_pairs(moving, &tree, &StaticTree::default());
        assert_eq!(bp.pairs, find_pairs_full_sort(moving, &tree));
        assert_eq!(bp.pairs.len(), 199 + 198);
    }
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
