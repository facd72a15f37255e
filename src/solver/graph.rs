//! The constraint graph's colors: the order the contact solver runs in.
//!
//! Each solved arbiter gets a *color* such that no two arbiters of one
//! color share a body the solver can move (a body with a nonzero inverse
//! mass or moment: static, kinematic and sleeping bodies are never written
//! to, so any number of a color's arbiters may share one). The iterations
//! then sweep the colors in order, and the arbiters of one color in
//! canonical order. Within a color no arbiter reads what another writes,
//! so a color's arbiters give the same bits in any order and on any number
//! of threads: this is what lets the `parallel` feature split a color
//! between threads and still give the serial build's bits (Box2D v3's
//! constraint graph, made canonical).
//!
//! The colors are recomputed every step from the step's active arbiters in
//! canonical order, greedily: an arbiter takes the first color where
//! neither of its movable bodies is taken yet, searching from the color
//! after the highest one its bodies are taken in (and wrapping around), so
//! that the canonical order's dependencies survive where the colors allow:
//! Gauss–Seidel converges by its order (see
//! [`Settings::colored_solver`](crate::space::Settings::colored_solver)). So they depend only on the
//! world state, never on the order contacts were created in, on the
//! history of insertions and removals or on a snapshot round trip. An
//! arbiter that fits none of the [`COLORS`] colors goes to the *overflow*,
//! solved after the colors in canonical order (by one thread).
//!
//! The cost is one pass over the arbiters with a few bit operations each
//! (every body keeps a mask of the colors it is taken in: the free colors
//! of a pair are the complement of their two masks' union, the first one
//! from the start color its lowest set bit), and one mask cleared per body
//! taken at the end: no pass over the bodies.

/// The number of colors before the overflow. Box2D v3 uses 24; a body
/// touching more than 24 moving bodies is rare, and an empty color costs
/// nothing.
pub(crate) const COLORS: usize = 24;

/// Bands of body slots a color's arbiters are ordered by (see
/// [`ConstraintGraph::color`]); set by nothing but the slot count, so the
/// order is the same for any thread count.
const BANDS: usize = 64;

/// An arbiter end that is not a movable body (in `ends_of`).
const NO_SLOT: u32 = u32::MAX;

/// Arbiters per piece of the split read of their bodies (a few µs).
const ENDS_PIECE: usize = 1024;

/// Every color's bit.
const ALL: u32 = (1 << COLORS) - 1;

/// The color of an arbiter whose bodies are taken in the colors of
/// `taken` (one bit per color): the first free one from the color after
/// the highest taken (wrapping around), or [`COLORS`] (the overflow) if
/// none is free.
#[inline]
fn first_free(taken: u32) -> usize {
    let free = !taken & ALL;
    // The highest taken color + 1 (0 if none), at most COLORS: a color.
    let start = u32::BITS
        .wrapping_sub(taken.leading_zeros())
        .checked_rem(COLORS as u32)
        .unwrap_or(0);
    let from_start = free & (ALL << start);
    match (from_start, free) {
        (0, 0) => COLORS,
        (0, _) => free.trailing_zeros() as usize,
        _ => from_start.trailing_zeros() as usize,
    }
}

/// The colors of one step's arbiters, and the scratch that computes them.
#[derive(Clone, Debug, Default)]
pub(crate) struct ConstraintGraph {
    /// Per body slot, one bit per color: set while the body is taken in
    /// the color. All clear between steps.
    used: Vec<u32>,
    /// Color (or [`COLORS`] for the overflow) of each arbiter of the
    /// input, in input order.
    color_of: Vec<u8>,
    /// The movable body slots of each arbiter of the input (`NO_SLOT`:
    /// none), in input order: looked up once, used again to sort and clear.
    ends_of: Vec<[u32; 2]>,
    /// The counting sort's buckets (scratch).
    next: Vec<u32>,
    /// The input arbiters in solve order: by color, the overflow last,
    /// input order within each.
    order: Vec<u32>,
    /// `starts[c]..starts[c + 1]` is color `c`'s part of `order`; the
    /// overflow is `starts[COLORS]..starts[COLORS + 1]`.
    starts: [u32; COLORS + 2],
}

impl ConstraintGraph {
    /// Colors `arbiters` (arbiter indices in canonical order): `bodies(i)`
    /// gives arbiter `i`'s two body slots and whether each is movable.
    /// Slots at or above `body_slots` are treated as not movable.
    pub(crate) fn color(
        &mut self,
        arbiters: &[u32],
        body_slots: usize,
        bodies: impl Fn(u32) -> [(u32, bool); 2] + Sync,
    ) {
        if self.used.len() != body_slots {
            // All masks are clear here (cleared after each use).
            self.used.clear();
            self.used.resize(body_slots, 0);
        }
        self.color_of.clear();
        // Each arbiter's movable bodies first, in pieces the threads share
        // (the arbiters' and bodies' reads are the cache misses); then the
        // colors one arbiter after the other, from that compact list.
        self.ends_of.clear();
        self.ends_of.resize(arbiters.len(), [NO_SLOT; 2]);
        crate::threads::zip_split(arbiters, &mut self.ends_of, ENDS_PIECE, &|&i, ends| {
            // Slots below body_slots fit u32 (they came as u32).
            *ends = bodies(i).map(|(slot, movable)| {
                if movable && (slot as usize) < body_slots {
                    slot
                } else {
                    NO_SLOT
                }
            });
        });
        for ends in &self.ends_of {
            let ends = ends.map(|e| (e != NO_SLOT).then_some(e as usize));
            // Start after the highest color its bodies are taken in, so
            // that an arbiter sharing a body with earlier ones is solved
            // after them whenever the colors allow (the canonical order's
            // dependencies, kept until the colors run out and wrap).
            // Measured on the pyramids against plain first fit and against
            // "after the color last taken": the best of the three on
            // `pyramid_20`, `many_pyramids_4x4` and `pyramid_100`.
            let taken = ends.iter().flatten().fold(0u32, |m, &slot| {
                m | self.used.get(slot).copied().unwrap_or(ALL)
            });
            let color = first_free(taken);
            if color < COLORS {
                for &slot in ends.iter().flatten() {
                    if let Some(m) = self.used.get_mut(slot) {
                        *m |= 1 << color;
                    }
                }
            }
            // color ≤ COLORS = 24 fits a u8.
            self.color_of.push(color as u8);
        }
        // Counting sort by color and, within a color, by the band of body
        // slots of the arbiter's first movable body (`band`), stable: a
        // color's arbiters share no movable body, so their order within
        // the color changes no bit, and banded, the halves a color is
        // split into between threads touch mostly the same bodies from one
        // color to the next (a body's cache line stays with one thread).
        // The overflow keeps the canonical order: its arbiters may share.
        let band_of = |ends: &[u32; 2]| {
            let slot = ends.iter().find(|&&e| e != NO_SLOT).copied().unwrap_or(0);
            // slot < body_slots: the band is below BANDS.
            (slot as usize)
                .saturating_mul(BANDS)
                .checked_div(body_slots)
                .unwrap_or(0)
        };
        let bucket = |c: u8, ends: &[u32; 2]| {
            let c = usize::from(c);
            if c < COLORS {
                c.saturating_mul(BANDS)
                    .saturating_add(band_of(ends).min(BANDS - 1))
            } else {
                COLORS * BANDS
            }
        };
        if arbiters.is_empty() {
            // No arbiter: every color empty, without the buckets.
            self.order.clear();
            self.starts = [0; COLORS + 2];
            return;
        }
        let mut next = core::mem::take(&mut self.next);
        next.clear();
        next.resize(COLORS * BANDS + 2, 0);
        for (ends, &c) in self.ends_of.iter().zip(&self.color_of) {
            if let Some(n) = next.get_mut(bucket(c, ends).saturating_add(1)) {
                *n = n.saturating_add(1);
            }
        }
        let mut sum = 0u32;
        for n in next.iter_mut() {
            sum = sum.saturating_add(*n);
            *n = sum;
        }
        for (c, s) in self.starts.iter_mut().enumerate().take(COLORS + 1) {
            *s = next.get(c.saturating_mul(BANDS)).copied().unwrap_or(0);
        }
        self.starts[COLORS + 1] = sum;
        self.order.clear();
        self.order.resize(arbiters.len(), 0);
        for ((&i, ends), &c) in arbiters.iter().zip(&self.ends_of).zip(&self.color_of) {
            if let Some(at) = next.get_mut(bucket(c, ends)) {
                if let Some(slot) = self.order.get_mut(*at as usize) {
                    *slot = i;
                }
                *at = at.saturating_add(1);
            }
        }
        self.next = next;
        // Clear what was taken, arbiter by arbiter (no pass over the bodies).
        for (ends, &c) in self.ends_of.iter().zip(&self.color_of) {
            let c = usize::from(c);
            if c >= COLORS {
                continue;
            }
            for &slot in ends.iter().filter(|&&slot| slot != NO_SLOT) {
                if let Some(m) = self.used.get_mut(slot as usize) {
                    *m = 0;
                }
            }
        }
    }

    /// No colors: every arbiter of `arbiters` in the overflow, in their
    /// order (the canonical solver, [`Settings::colored_solver`] off).
    ///
    /// [`Settings::colored_solver`]: crate::space::Settings::colored_solver
    pub(crate) fn uncolored(&mut self, arbiters: &[u32]) {
        self.order.clear();
        self.order.extend_from_slice(arbiters);
        // At most 2^32 arbiters (they are counted in u32).
        let n = arbiters.len() as u32;
        self.starts = [0; COLORS + 2];
        self.starts[COLORS + 1] = n;
    }

    /// The arbiters in solve order (by color, then the overflow).
    pub(crate) fn order(&self) -> &[u32] {
        &self.order
    }

    /// The part of [`order`](Self::order) of color `c` (`c == COLORS`:
    /// the overflow); empty past it.
    pub(crate) fn range(&self, c: usize) -> core::ops::Range<usize> {
        let start = self.starts.get(c).copied().unwrap_or(0) as usize;
        let end = self.starts.get(c.saturating_add(1)).copied().unwrap_or(0) as usize;
        start..end.max(start)
    }

    /// The number of colors used (the last non-empty color + 1), not
    /// counting the overflow.
    #[cfg(test)]
    pub(crate) fn colors_used(&self) -> usize {
        (0..COLORS)
            .rev()
            .find(|&c| !self.range(c).is_empty())
            .map_or(0, |c| c + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The color search as a loop over the colors: from the color after
    /// the highest taken one, wrapping around, the first one not taken.
    fn first_free_reference(taken: u32) -> usize {
        let start = (0..COLORS)
            .rev()
            .find(|&c| taken & (1 << c) != 0)
            .map_or(0, |c| c + 1);
        (0..COLORS)
            .map(|k| (k + start) % COLORS)
            .find(|&c| taken & (1 << c) == 0)
            .unwrap_or(COLORS)
    }

    #[test]
    fn the_bit_search_is_the_loop_over_colors() {
        // Masks on a prime stride, every mask with at most two colors free
        // or at most two taken, and the edges.
        let all = (1u32 << COLORS) - 1;
        let sparse = (0..COLORS).flat_map(|i| (0..COLORS).map(move |j| (1u32 << i) | (1 << j)));
        let masks = (0..=all)
            .step_by(9_973)
            .chain(sparse.clone())
            .chain(sparse.map(|m| all & !m))
            .chain([
                0,
                all,
                all & !1,
                all & !(1 << (COLORS - 1)),
                1,
                1 << (COLORS - 1),
            ]);
        for taken in masks {
            assert_eq!(first_free(taken), first_free_reference(taken), "{taken:#x}");
        }
    }

    /// Colors `pairs` (body slots, all movable unless ≥ 100 = static).
    fn colors(pairs: &[(u32, u32)]) -> ConstraintGraph {
        let mut g = ConstraintGraph::default();
        let ids: Vec<u32> = (0..pairs.len() as u32).collect();
        g.color(&ids, 200, |i| {
            let (a, b) = pairs[i as usize];
            [(a, a < 100), (b, b < 100)]
        });
        g
    }

    #[test]
    fn no_two_arbiters_of_a_color_share_a_movable_body() {
        // A chain 0-1-2-3-4 and every body on the ground (static 100).
        let mut pairs: Vec<(u32, u32)> = (0..4).map(|i| (i, i + 1)).collect();
        pairs.extend((0..5).map(|i| (100, i)));
        let g = colors(&pairs);
        for c in 0..=COLORS {
            let mut seen = std::collections::BTreeSet::new();
            for &i in &g.order()[g.range(c)] {
                let (a, b) = pairs[i as usize];
                for body in [a, b].into_iter().filter(|&s| s < 100) {
                    assert!(c == COLORS || seen.insert(body), "color {c} shares {body}");
                }
            }
        }
        // Each arbiter searches from the color after the highest its
        // bodies are in: the chain's links take colors 0, 1, 2, 3 (each
        // after the link before it, as in canonical order), and each
        // ground contact the color after its body's last link: body 0's
        // color 1, body 1's color 2 … body 4's color 4 (with body 3's).
        assert_eq!(g.order(), &[0, 1, 4, 2, 5, 3, 6, 7, 8]);
        assert_eq!(g.colors_used(), 5);
        assert!(g.range(COLORS).is_empty());
    }

    #[test]
    fn a_body_in_more_arbiters_than_colors_overflows_in_input_order() {
        let pairs: Vec<(u32, u32)> = (1..=COLORS as u32 + 3).map(|i| (0, i)).collect();
        let g = colors(&pairs);
        assert_eq!(g.colors_used(), COLORS);
        let overflow: Vec<u32> = g.order()[g.range(COLORS)].to_vec();
        assert_eq!(overflow, [24, 25, 26]);
        // The bits are all clear again: a second coloring is the same.
        let again = colors(&pairs);
        assert_eq!(again.order(), g.order());
        let mut g = g;
        let ids: Vec<u32> = (0..pairs.len() as u32).collect();
        g.color(&ids, 200, |i| {
            let (a, b) = pairs[i as usize];
            [(a, true), (b, true)]
        });
        assert_eq!(g.order(), again.order());
    }

    /// The colors past the last one in use are empty, at the end of the
    /// order; the ranges tile the order (none of the scene's arbiters, and
    /// a few).
    #[test]
    fn unused_colors_are_empty_at_the_end() {
        for pairs in [vec![], vec![(0, 1), (1, 2), (100, 0)]] {
            let g = colors(&pairs);
            let mut end = 0;
            for c in 0..=COLORS {
                let r = g.range(c);
                assert_eq!(r.start, end, "color {c}");
                assert!(c < g.colors_used() || r.is_empty(), "color {c}");
                end = r.end;
            }
            assert_eq!(end, pairs.len());
        }
    }
}
