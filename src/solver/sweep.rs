//! One Gauss–Seidel pass over rows of whole manifolds: in order on one
//! thread, or one color's manifolds split between threads.
//!
//! A color's manifolds share no body the solver moves
//! ([`graph`](super::graph)), so they can be solved at the same time on
//! bodies that threads share ([`SharedBody`]): the same bits as solving them
//! one after the other in place, however the color is split. Bodies the
//! solver does not move (static, kinematic, sleeping: zero inverse mass and
//! moment) may be in several of a color's manifolds; they are only read.
use core::sync::atomic::{AtomicI64, Ordering::Relaxed};

use super::block::{self, ManifoldBlock};
use super::graph::{ConstraintGraph, COLORS};
use super::{ContactConstraint, SolverBody};
use crate::math::{Real, Vect};

/// Solves `rows` (whole manifolds, in order) on `bodies`: a block's two
/// rows together, every other row on its own.
#[inline]
pub(crate) fn solve_rows<const FRICTION: bool, const BIAS: bool>(
    rows: &mut [ContactConstraint],
    blocks: &[ManifoldBlock],
    bodies: &mut [SolverBody],
) {
    let mut i = 0usize;
    while let Some((c, tail)) = rows
        .get_mut(i..)
        .and_then(<[ContactConstraint]>::split_first_mut)
    {
        let ends = (c.a, c.b);
        let block = c.block.checked_sub(1).and_then(|k| blocks.get(k as usize));
        if let (Some(block), Some(c2)) = (block, tail.first_mut()) {
            block::solve_prepared::<FRICTION, BIAS>(c, c2, block, bodies, ends);
            i = i.saturating_add(2);
        } else {
            c.solve_prepared::<FRICTION, BIAS>(bodies, ends);
            i = i.saturating_add(1);
        }
    }
}

/// A row of a manifold: which two solver bodies it joins (the rows of one
/// manifold join the same two). The contact solver's rows and the soft
/// step's both sweep through this module.
pub(crate) trait ManifoldRow: Send {
    /// Solver slots of bodies a and b.
    fn ends(&self) -> (u32, u32);
}

impl ManifoldRow for ContactConstraint {
    #[inline(always)]
    fn ends(&self) -> (u32, u32) {
        (self.a, self.b)
    }
}

/// A [`SolverBody`] threads can share: each field an atomic word, read
/// and written with relaxed loads and stores (plain moves on 64-bit
/// targets). Within a color no two threads touch the same movable body,
/// so no ordering is needed; atomics make the sharing safe Rust. One body
/// per 64-byte cache line, so that threads never write the same line.
#[derive(Debug, Default)]
#[repr(align(64))]
pub(crate) struct SharedBody {
    words: [AtomicI64; 8],
}

impl Clone for SharedBody {
    fn clone(&self) -> Self {
        let copy = SharedBody::default();
        copy.store(&self.load());
        copy
    }
}

impl SharedBody {
    /// The body's current value.
    ///
    /// Every word loaded by name, here and below: an array `map` over
    /// atomics was left out of line in a build of the kernels (a call to
    /// `try_map` per body), where the in-place loads were inlined.
    #[inline(always)]
    pub(crate) fn load(&self) -> SolverBody {
        let [vx, vy, w, bx, by, bw, m, i] = &self.words;
        let at = |x: &AtomicI64| Real::from_bits(x.load(Relaxed));
        let [vx, vy, w, bx, by, bw, m, i] =
            [at(vx), at(vy), at(w), at(bx), at(by), at(bw), at(m), at(i)];
        SolverBody {
            v: Vect::new(vx, vy),
            w,
            v_bias: Vect::new(bx, by),
            w_bias: bw,
            m_inv: m,
            i_inv: i,
        }
    }

    /// Sets the body to `b`.
    #[inline(always)]
    fn store(&self, b: &SolverBody) {
        let words = [
            b.v.x, b.v.y, b.w, b.v_bias.x, b.v_bias.y, b.w_bias, b.m_inv, b.i_inv,
        ];
        for (x, r) in self.words.iter().zip(words) {
            x.store(r.to_bits(), Relaxed);
        }
    }

    /// The raw bits of the velocities `[v.x, v.y, ω]` (the bias
    /// velocities and masses not read).
    #[inline(always)]
    pub(crate) fn velocity_bits(&self) -> [i64; 3] {
        let [x, y, w, ..] = &self.words;
        [x.load(Relaxed), y.load(Relaxed), w.load(Relaxed)]
    }

    /// Sets the velocities `[v.x, v.y, ω]` from raw bits (the bias
    /// velocities untouched, as the in-place store leaves them).
    #[inline(always)]
    pub(crate) fn set_velocity_bits(&self, [vx, vy, vw]: [i64; 3]) {
        let [x, y, w, ..] = &self.words;
        x.store(vx, Relaxed);
        y.store(vy, Relaxed);
        w.store(vw, Relaxed);
    }

    /// Sets the velocities (the solver never changes the inverse masses).
    #[inline(always)]
    pub(crate) fn store_velocities(&self, b: &SolverBody) {
        let words = [b.v.x, b.v.y, b.w, b.v_bias.x, b.v_bias.y, b.w_bias];
        for (x, r) in self.words.iter().zip(words) {
            x.store(r.to_bits(), Relaxed);
        }
    }
}

/// Copies `bodies` into `shared` (resized to match), in pieces the threads
/// share.
pub(crate) fn share(bodies: &[SolverBody], shared: &mut Vec<SharedBody>) {
    if shared.len() != bodies.len() {
        shared.clear();
        shared.resize_with(bodies.len(), SharedBody::default);
    }
    copy_split(bodies, shared, &|b, s| s.store(b));
}

/// Copies `shared` back into `bodies`, in pieces the threads share.
pub(crate) fn unshare(shared: &[SharedBody], bodies: &mut [SolverBody]) {
    copy_split(shared, bodies, &|s, b| *b = s.load());
}

/// Bodies per piece of the copies (a few µs of copying).
const COPY_PIECE: usize = 1024;

/// `f(src[i], dst[i])` for every `i` of both, split between threads
/// ([`crate::threads::zip_split`]).
fn copy_split<S: Sync, D: Send>(src: &[S], dst: &mut [D], f: &(impl Fn(&S, &mut D) + Sync)) {
    crate::threads::zip_split(src, dst, COPY_PIECE, f);
}

/// Runs `kernel` on one manifold's `rows` with a copy of its two bodies
/// loaded from `shared` (`a` at 0, `b` at 1), and stores the movable ones
/// back (a body the solver does not move comes back unchanged: not
/// stored, so threads sharing it never write its cache line). Nothing
/// where the in-place pass does nothing (a body paired with itself, a
/// slot out of range).
#[inline]
fn on_manifold_shared<R: ManifoldRow, K>(rows: &mut [R], shared: &[SharedBody], kernel: &K)
where
    K: Fn(&mut [R], &mut [SolverBody; 2]),
{
    let Some(first) = rows.first() else {
        return;
    };
    let (a, b) = first.ends();
    let (Some(sa), Some(sb)) = (shared.get(a as usize), shared.get(b as usize)) else {
        return;
    };
    if a == b {
        return;
    }
    let mut copy = [sa.load(), sb.load()];
    kernel(rows, &mut copy);
    for (s, body) in [sa, sb].into_iter().zip(&copy) {
        if !body.m_inv.is_zero() || !body.i_inv.is_zero() {
            s.store_velocities(body);
        }
    }
}

/// The iteration of one manifold's `rows` on a copy of its two bodies
/// (a block's two rows together, every other row on its own): the kernel
/// of the shared sweep, the same arithmetic as [`solve_rows`].
#[inline(always)]
pub(crate) fn solve_copy<const FRICTION: bool, const BIAS: bool>(
    rows: &mut [ContactConstraint],
    blocks: &[ManifoldBlock],
    copy: &mut [SolverBody; 2],
) {
    let mut i = 0usize;
    while let Some((c, tail)) = rows
        .get_mut(i..)
        .and_then(<[ContactConstraint]>::split_first_mut)
    {
        let block = c.block.checked_sub(1).and_then(|k| blocks.get(k as usize));
        if let (Some(block), Some(c2)) = (block, tail.first_mut()) {
            block::solve_prepared::<FRICTION, BIAS>(c, c2, block, copy, (0, 1));
            i = i.saturating_add(2);
        } else {
            c.solve_prepared::<FRICTION, BIAS>(copy, (0, 1));
            i = i.saturating_add(1);
        }
    }
}

/// The warm start of one manifold's `rows` on a copy of its two bodies
/// ([`ContactConstraint::warm_start_at`], in row order as the warm-start stage).
#[inline(always)]
pub(crate) fn warm_start_copy<const FRICTION: bool>(
    rows: &mut [ContactConstraint],
    dt_coef: Real,
    copy: &mut [SolverBody; 2],
) {
    for c in rows {
        c.warm_start_at::<FRICTION>(copy, dt_coef, (0, 1));
    }
}

/// The fewest manifolds in a piece of a split color (about 1 µs of work:
/// several times the cost of handing a piece to another thread).
const MIN_PIECE: usize = 16;

/// The most pieces a color is split into: enough to balance 16 threads,
/// few enough that a large color's pieces are long (each split is a
/// `join`, a hand-over between threads).
const MAX_PIECES: usize = 16;

/// The piece size for a color of `manifolds`: set by the count alone.
fn piece_size(manifolds: usize) -> usize {
    manifolds.div_ceil(MAX_PIECES).max(MIN_PIECE)
}

/// Runs `kernel` (such as [`solve_copy`]) on each manifold of `rows`, one
/// color's or the overflow's, with its bodies from `shared`
/// ([`on_manifold_shared`]): `starts` holds each manifold's first row
/// (absolute, as in the scratch) and the end. A color's manifolds are
/// split in halves down to pieces of [`piece_size`] (boundaries set by the
/// count alone) and run in parallel inside a pool
/// ([`crate::threads::join`]); any split gives the same bits, as no two
/// manifolds of a color share a movable body. `split = false` (the
/// overflow): in order.
pub(crate) fn for_each_shared<R: ManifoldRow, K>(
    rows: &mut [R],
    starts: &[u32],
    shared: &[SharedBody],
    split: bool,
    kernel: &K,
) where
    K: Fn(&mut [R], &mut [SolverBody; 2]) + Sync,
{
    let manifolds = starts.len().saturating_sub(1);
    let piece = if split {
        piece_size(manifolds)
    } else {
        usize::MAX
    };
    pieces(rows, starts, shared, piece, kernel);
}

/// [`for_each_shared`] down to pieces of at most `piece` manifolds.
fn pieces<R: ManifoldRow, K>(
    rows: &mut [R],
    starts: &[u32],
    shared: &[SharedBody],
    piece: usize,
    kernel: &K,
) where
    K: Fn(&mut [R], &mut [SolverBody; 2]) + Sync,
{
    let base = starts.first().copied().unwrap_or(0);
    let manifolds = starts.len().saturating_sub(1);
    if manifolds <= piece {
        for (k, &s) in starts.iter().enumerate().take(manifolds) {
            let Some(&e) = starts.get(k.wrapping_add(1)) else {
                continue;
            };
            let range = s.wrapping_sub(base) as usize..e.wrapping_sub(base) as usize;
            if let Some(manifold) = rows.get_mut(range) {
                on_manifold_shared(manifold, shared, kernel);
            }
        }
        return;
    }
    let mid = manifolds / 2;
    let cut = starts.get(mid).copied().unwrap_or(base);
    let Some((left_rows, right_rows)) = rows.split_at_mut_checked(cut.wrapping_sub(base) as usize)
    else {
        return;
    };
    let (left_starts, right_starts) = (
        starts.get(..=mid).unwrap_or(&[]),
        starts.get(mid..).unwrap_or(&[]),
    );
    crate::threads::join(
        || pieces(left_rows, left_starts, shared, piece, kernel),
        || pieces(right_rows, right_starts, shared, piece, kernel),
    );
}

/// Where the rows of each color are: the pre-step's placing pass.
#[derive(Clone, Copy)]
pub(crate) struct ColorLayout<'a> {
    /// The manifolds of each color ([`ConstraintGraph::range`]).
    pub(crate) graph: &'a ConstraintGraph,
    /// Each color's first row, and the end.
    pub(crate) color_rows: &'a [u32],
    /// Each manifold's first row (in solve order), and the end.
    pub(crate) manifold_rows: &'a [u32],
}

/// Runs `kernel` on every manifold of `rows` on the shared bodies, color
/// after color (each split between threads) and the overflow last, in
/// order ([`for_each_shared`]): one pass of the step's order.
pub(crate) fn for_each_color<R: ManifoldRow, K>(
    rows: &mut [R],
    layout: ColorLayout<'_>,
    shared: &[SharedBody],
    kernel: &K,
) where
    K: Fn(&mut [R], &mut [SolverBody; 2]) + Sync,
{
    for c in 0..=COLORS {
        let (Some(&start), Some(&end)) = (
            layout.color_rows.get(c),
            layout.color_rows.get(c.wrapping_add(1)),
        ) else {
            continue;
        };
        let Some(rows) = rows.get_mut(start as usize..end as usize) else {
            continue;
        };
        let range = layout.graph.range(c);
        let starts = layout
            .manifold_rows
            .get(range.start..=range.end)
            .unwrap_or(&[]);
        for_each_shared(rows, starts, shared, c < COLORS, kernel);
    }
}
