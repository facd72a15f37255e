//! One Gauss–Seidel pass over rows of whole manifolds: in order on one
//! thread, or one color's manifolds split between threads.
//!
//! A color's manifolds share no body the solver moves
//! ([`graph`](super::graph)), so they can be solved at the same time on
//! bodies that threads share ([`SharedBody`]): the same bits as solving them
//! one after the other in place, however the color is split. Bodies the
//! solver does not move (static, kinematic, sleeping: zero inverse mass and
//! moment) may be in several of a color's manifolds; they are only read.
use core::sync::atomic::{
    AtomicBool, AtomicI64, AtomicUsize,
    Ordering::{Acquire, Relaxed, Release},
};
use std::sync::{Mutex, PoisonError};

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
/// so no ordering is needed; atomics make the sharing safe Rust.
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
    #[inline(always)]
    fn load(&self) -> SolverBody {
        let [vx, vy, w, bx, by, bw, m, i] = self
            .words
            .each_ref()
            .map(|x| Real::from_bits(x.load(Relaxed)));
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

    /// Sets the velocities (the solver never changes the inverse masses).
    #[inline(always)]
    fn store_velocities(&self, b: &SolverBody) {
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

/// The fewest manifolds in a block (about 1 µs of work: several times the
/// cost of claiming it and of the bodies' cache lines moving between
/// cores).
const MIN_PIECE: usize = 16;

/// The most blocks a color is cut into: enough to balance 16 threads, few
/// enough that the blocks are long.
const MAX_PIECES: usize = 16;

/// The block size for a color of `manifolds`: set by the count alone.
fn piece_size(manifolds: usize) -> usize {
    manifolds.div_ceil(MAX_PIECES).max(MIN_PIECE)
}

/// Runs `kernel` on each manifold of `rows` in order, with its bodies from
/// `shared` ([`on_manifold_shared`]): `starts` holds each manifold's first
/// row (absolute, as in the scratch) and the end.
fn in_order<R: ManifoldRow, K>(rows: &mut [R], starts: &[u32], shared: &[SharedBody], kernel: &K)
where
    K: Fn(&mut [R], &mut [SolverBody; 2]),
{
    let base = starts.first().copied().unwrap_or(0);
    for pair in starts.windows(2) {
        let &[s, e] = pair else {
            continue;
        };
        let range = s.wrapping_sub(base) as usize..e.wrapping_sub(base) as usize;
        if let Some(manifold) = rows.get_mut(range) {
            on_manifold_shared(manifold, shared, kernel);
        }
    }
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
/// after color and the overflow last, in order: one pass of the step's
/// order. Each color is cut into blocks of [`piece_size`] manifolds (the
/// overflow into one, run in order); each thread of the step
/// ([`crate::threads::on_every_thread`]) runs its share of every color
/// (the same part of each, so that a body tends to stay in one core's
/// cache), then any block of the color no thread has claimed yet (a
/// thread that starts late, or not at all, leaves its share to the
/// others), then waits until the color is done. A thread waits only on
/// blocks that running threads have claimed, so the pass ends on any
/// number of threads. Blocks are cut by the counts alone and no two
/// blocks of a color share a movable body: the same bits however the
/// threads take them. One hand-over per thread and pass.
pub(crate) fn for_each_color<R: ManifoldRow, K>(
    rows: &mut [R],
    layout: ColorLayout<'_>,
    shared: &[SharedBody],
    kernel: &K,
) where
    K: Fn(&mut [R], &mut [SolverBody; 2]) + Sync,
{
    let (blocks, colors) = color_blocks(rows, layout);
    let participants = crate::threads::participants();
    let arrived = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let run = |block: &ClaimedBlock<'_, R>| {
        if block.claimed.swap(true, Relaxed) {
            return;
        }
        {
            let mut b = block.work.lock().unwrap_or_else(PoisonError::into_inner);
            let Block { rows, starts } = &mut *b;
            in_order(rows, starts, shared, kernel);
        }
        // Publishes the block's bodies to the threads that wait on it.
        done.fetch_add(1, Release);
    };
    crate::threads::on_every_thread(&|| {
        let me = arrived.fetch_add(1, Relaxed);
        for pair in colors.windows(2) {
            let &[first, end] = pair else {
                continue;
            };
            let color = blocks.get(first..end).unwrap_or(&[]);
            color
                .get(part_of(color.len(), me, participants))
                .unwrap_or(&[])
                .iter()
                .for_each(run);
            color.iter().for_each(run);
            wait_until(&done, end);
        }
    });
}

/// Participant `me`'s part of `len` blocks among `of` (empty past the
/// last participant).
fn part_of(len: usize, me: usize, of: usize) -> core::ops::Range<usize> {
    let at = |k: usize| len.saturating_mul(k).checked_div(of).unwrap_or(0);
    if me >= of {
        return 0..0;
    }
    at(me)..at(me.saturating_add(1))
}

/// A block of a pass: whole manifolds of one color, run in order.
struct Block<'a, R> {
    rows: &'a mut [R],
    /// Each manifold's first row (absolute), and the end.
    starts: &'a [u32],
}

/// A block and whether a thread has claimed it (the lock is then taken
/// once, by that thread).
struct ClaimedBlock<'a, R> {
    claimed: AtomicBool,
    work: Mutex<Block<'a, R>>,
}

/// The blocks of a pass, in order: each color's manifolds in pieces of
/// [`piece_size`], the overflow's in one; and each color's first block
/// and the end.
type Blocks<'a, R> = (Vec<ClaimedBlock<'a, R>>, [usize; COLORS + 2]);

fn color_blocks<'a, R>(rows: &'a mut [R], layout: ColorLayout<'a>) -> Blocks<'a, R> {
    let mut blocks = Vec::new();
    let mut colors = [0usize; COLORS + 2];
    let mut rest = rows;
    let mut consumed = 0usize;
    for c in 0..=COLORS {
        let (Some(&start), Some(&end)) = (
            layout.color_rows.get(c),
            layout.color_rows.get(c.wrapping_add(1)),
        ) else {
            continue;
        };
        let range = layout.graph.range(c);
        let starts = layout
            .manifold_rows
            .get(range.start..=range.end)
            .unwrap_or(&[]);
        let manifolds = starts.len().saturating_sub(1);
        let (Some(skip), Some(len)) = (
            (start as usize).checked_sub(consumed),
            end.checked_sub(start),
        ) else {
            continue;
        };
        let taken = core::mem::take(&mut rest);
        let Some((_, tail)) = taken.split_at_mut_checked(skip) else {
            continue;
        };
        let Some((mut color, tail)) = tail.split_at_mut_checked(len as usize) else {
            continue;
        };
        rest = tail;
        consumed = end as usize;
        let piece = if c < COLORS {
            piece_size(manifolds)
        } else {
            usize::MAX
        };
        let mut first = 0usize;
        while first < manifolds {
            let last = first.saturating_add(piece).min(manifolds);
            let (Some(&s), Some(&e)) = (starts.get(first), starts.get(last)) else {
                break;
            };
            let taken = core::mem::take(&mut color);
            let Some((block_rows, tail)) = taken.split_at_mut_checked(e.saturating_sub(s) as usize)
            else {
                break;
            };
            color = tail;
            blocks.push(ClaimedBlock {
                claimed: AtomicBool::new(false),
                work: Mutex::new(Block {
                    rows: block_rows,
                    starts: starts.get(first..=last).unwrap_or(&[]),
                }),
            });
            first = last;
        }
        if let Some(end) = colors.get_mut(c.wrapping_add(1)) {
            *end = blocks.len();
        }
    }
    for k in 1..colors.len() {
        // Colors skipped above (none in a consistent layout) end where the
        // one before them does.
        let before = colors.get(k.wrapping_sub(1)).copied().unwrap_or(0);
        if let Some(c) = colors.get_mut(k) {
            *c = (*c).max(before);
        }
    }
    (blocks, colors)
}

/// Waits until `done` reaches `count`: spinning briefly, then giving the
/// core away (with more threads than cores, the thread it waits on may
/// need this one).
fn wait_until(done: &AtomicUsize, count: usize) {
    let mut spins = 0u32;
    while done.load(Acquire) < count {
        if spins < 256 {
            spins = spins.wrapping_add(1);
            core::hint::spin_loop();
        } else {
            std::thread::yield_now();
        }
    }
}
