//! The soft contacts' wide kernels: the warm start, solve and relax passes
//! on four manifolds of one color at a time, in lanes
//! ([`LaneArith`](crate::math::lanes::LaneArith)), with the bits of the
//! scalar kernels.
//!
//! Within a color no two manifolds share a body the solver moves (module
//! `graph`), so four of them are four independent computations: a
//! **batch** holds their rows' constants structure-of-arrays (one
//! [`Lane`] per field and point), gathered once per step, and each pass
//! gathers the eight bodies' velocities, runs every operation of the
//! scalar manifold pass on the four lanes at once, and scatters them back.
//! Manifolds of one point and of two batch apart, and a batch solves as
//! many points as its largest manifold has (a missing point is zeros,
//! which applies an impulse of exactly 0). Where the scalar pass computes
//! one branch
//! (apart or overlapping, soft or rigid), the lanes compute both and
//! select: a rigid row's `jn·1 + 0·jn_acc` is `jn` exactly, so the soft
//! formula gives the rigid row's bits.
//!
//! A lane whose record is set (an input or a product left the window,
//! module `lanes`) is not scattered: that manifold is run again by the
//! scalar kernel from its state before the pass, exactly as if the lanes
//! had never seen it. The other lanes' bodies are untouched by it (the
//! color's promise), so the order does not matter. A color's last three
//! manifolds of a kind make a batch with one empty lane (no bodies, no
//! impulse). Manifolds that cannot join a batch (the overflow color, a
//! color's last one or two of each kind, a body paired with itself, rows
//! that do not share their bodies' masses and softness) run the scalar
//! kernel, after the color's batches.
//! With threads a color's batches are split between them on the shared
//! bodies; the kernels read and write bodies through a [`BodyStore`], in
//! place or shared.
//!
//! The batches hold the rows' running impulses and separations while the
//! sub-steps run; [`SoftContacts`](super::SoftContacts) writes them back
//! to its rows before anything else reads the rows.
use crate::math::lanes::{is_short, Factor, Lane, LaneArith, Ops, LANES};
use crate::math::{Real, Vect};
use crate::solver::softness::Softness;
use crate::solver::{graph, sweep, SolverBody};

use super::narrow::{gather_narrow, put_narrow, zero_narrow, NarrowBatch};
use super::pass::{
    dispatch, keep_left, movable, on_store, set, BodyStore, Compiled, InPlace, LaneBatch, Pass,
    PointState, Shared,
};
use super::row::{
    scale_impulses, solve_manifold, warm_start_manifold, Motion, SoftContact, SoftContactParams,
};

/// One point (the first or the second) of four manifolds: every field of
/// [`SoftContact`] a pass reads or writes, one lane per manifold.
#[derive(Clone, Copy, Debug, Default)]
struct PointLanes {
    n_x: Lane,
    n_y: Lane,
    dist: Lane,
    nr_a: Lane,
    nr_b: Lane,
    rn_a: Lane,
    rn_b: Lane,
    rt_a: Lane,
    rt_b: Lane,
    kn_a: Lane,
    kn_b: Lane,
    kt_a: Lane,
    kt_b: Lane,
    n_mass: Lane,
    t_mass: Lane,
    friction: Lane,
    surface_t: Lane,
    constant_record: [u64; LANES],
    /// Whether the constants a product takes (all but `kn`, `kt`) are
    /// short in every lane ([`is_short`]); found once per step.
    short: bool,
    /// The running state: the separation, the accumulated impulses and
    /// the largest normal impulse of the step.
    state: PointState,
}

impl PointLanes {
    /// [`PointLanes::short`] of the point's constants.
    fn find_short(&self) -> bool {
        [
            &self.n_x,
            &self.n_y,
            &self.nr_a,
            &self.nr_b,
            &self.rn_a,
            &self.rn_b,
            &self.rt_a,
            &self.rt_b,
            &self.n_mass,
            &self.t_mass,
            &self.friction,
        ]
        .into_iter()
        .all(is_short)
    }
}

/// Four manifolds of one color.
#[derive(Clone, Copy, Debug, Default)]
struct Batch {
    /// Each manifold's body slots.
    a: [u32; LANES],
    b: [u32; LANES],
    /// Each manifold's first row in `SoftContacts::rows`, and its count
    /// (1 or 2).
    first: [u32; LANES],
    count: [u32; LANES],
    /// The most points of the four manifolds (1 or 2): the points the
    /// passes solve.
    points_used: usize,
    m_inv_a: Lane,
    m_inv_b: Lane,
    /// Each manifold's softness (contact or fixed).
    bias_rate: Lane,
    mass_scale: Lane,
    impulse_scale: Lane,
    points: [PointLanes; 2],
}

/// The batches of one step, and what runs in each color.
#[derive(Clone, Debug, Default)]
pub(crate) struct WideContacts {
    batches: Vec<Batch>,
    /// Each color's first batch (the overflow has none), and the end.
    color_batches: Vec<u32>,
    /// The manifolds the scalar kernel runs, as row ranges, color by
    /// color (the overflow's last).
    scalar: Vec<(u32, u32)>,
    /// Each color's first manifold in `scalar`, and the end.
    color_scalar: Vec<u32>,
    /// Each batch's manifolds (row ranges), found before the batches are
    /// gathered (kept for its allocation).
    plan: Vec<[(u32, u32); LANES]>,
    /// Each color's plan (the overflow's last), before they are joined
    /// into `plan` and `scalar` (kept for their allocations).
    color_plans: Vec<ColorPlan>,
    /// The batches on the narrow grids, when this step's contacts are
    /// narrow (module `narrow`; `batches` is then empty).
    narrow: Vec<NarrowBatch>,
    /// How the passes run this step (`None`: the wide kernels are off).
    compiled: Option<Compiled>,
    /// One bit per color (the overflow's at `graph::COLORS`) with batches
    /// or scalar manifolds.
    colors_in_use: u32,
}

const _: () = assert!(graph::COLORS < 32, "a color's bit in a u32");

impl WideContacts {
    /// The colors (the overflow's `graph::COLORS` last) with batches or
    /// scalar manifolds, in order: a pass skips the empty ones without
    /// looking into them (a small scene uses a few of the colors).
    fn colors_in_use(&self) -> impl Iterator<Item = usize> {
        let mut left = self.colors_in_use;
        core::iter::from_fn(move || {
            let c = left.trailing_zeros();
            // Clears the lowest set bit (none once `left` is 0).
            left &= left.wrapping_sub(1);
            (c < u32::BITS).then_some(c as usize)
        })
    }

    /// Whether the passes run the batches this step.
    pub(crate) fn is_on(&self) -> bool {
        self.compiled.is_some()
    }

    /// Turns the wide kernels off (the rows hold the state).
    pub(crate) fn clear(&mut self) {
        // The batches keep their length (and memory): `build` resets each
        // one it gathers and empties the other kind, and nothing reads
        // them while the wide kernels are off.
        self.color_batches.clear();
        self.scalar.clear();
        self.color_scalar.clear();
        self.colors_in_use = 0;
        self.compiled = None;
    }

    /// The batches of a step: each color's manifolds in batches of four,
    /// the rest (and the overflow) for the scalar kernel. With `narrow`
    /// (module `narrow`), on the narrow grids, and every manifold that can
    /// join a batch does: a color's last ones in a batch with empty
    /// lanes, each of the overflow color's in a batch of its own (they
    /// may share bodies, so they run one after the other).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn build(
        &mut self,
        compiled: Compiled,
        narrow: bool,
        rows: &[SoftContact],
        manifold_rows: &[u32],
        graph: &graph::ConstraintGraph,
        bodies: &[SolverBody],
    ) {
        self.clear();
        // Each color's plan alone, colors in parallel where there are
        // threads (a color's plan reads only its own manifolds), then
        // the plans one after the other.
        let colors: [usize; graph::COLORS + 1] = core::array::from_fn(|c| c);
        self.color_plans
            .resize_with(graph::COLORS.wrapping_add(1), ColorPlan::default);
        let step = StepRows {
            narrow,
            rows,
            manifold_rows,
            graph,
            bodies,
        };
        crate::threads::zip_split(&colors, &mut self.color_plans, 1, &|&c, out| {
            step.plan_color(c, out);
        });
        self.plan.clear();
        for p in &self.color_plans {
            self.color_batches.push(self.plan.len() as u32);
            self.color_scalar.push(self.scalar.len() as u32);
            self.plan.extend_from_slice(&p.batches);
            self.scalar.extend_from_slice(&p.scalar);
        }
        self.color_batches.push(self.plan.len() as u32);
        self.color_scalar.push(self.scalar.len() as u32);
        let filled = |starts: &[u32], c: usize| match (starts.get(c), starts.get(c.wrapping_add(1)))
        {
            (Some(a), Some(b)) => a < b,
            _ => false,
        };
        for c in 0..=graph::COLORS {
            if filled(&self.color_batches, c) || filled(&self.color_scalar, c) {
                self.colors_in_use |= 1 << c;
            }
        }
        // The gathers, about 3 % of a step, split between threads (each
        // batch is gathered alone: the same bits).
        if narrow {
            // Each batch is reset to the default in its gather, on the
            // thread that gathers it and just before (not in one serial
            // fill of the whole vector first: some 1.7 kB a batch).
            let n = self.plan.len();
            self.batches.clear();
            self.narrow.truncate(n);
            self.narrow.resize(n, NarrowBatch::default());
            crate::threads::zip_split(&self.plan, &mut self.narrow, GATHER_PIECE, &|m, batch| {
                *batch = NarrowBatch::default();
                gather_narrow(batch, *m, rows, bodies);
            });
        } else {
            self.narrow.clear();
            let n = self.plan.len();
            self.batches.truncate(n);
            self.batches.resize(n, Batch::default());
            gather_split(&mut self.batches, &self.plan, rows);
        }
        self.compiled = Some(compiled);
    }

    /// The batches' state back into `rows` (the wide kernels stay on),
    /// whose colors start at `color_rows` (the overflow's at
    /// `graph::COLORS`, then the end). The narrow batches' halves of the
    /// colors in parallel: a color's batches write only its rows.
    pub(crate) fn write_back(&self, rows: &mut [SoftContact], color_rows: &[u32]) {
        for batch in &self.batches {
            for lane in 0..LANES {
                put_lane(batch, lane, rows);
            }
        }
        let colors = ColorParts {
            batches: &self.narrow,
            color_batches: &self.color_batches,
            color_rows,
        };
        colors.put(0..graph::COLORS.wrapping_add(1), rows, 0);
    }

    /// Warm starting off: every accumulated impulse starts from 0.
    pub(crate) fn zero_impulses(&mut self, rows: &mut [SoftContact]) {
        for row in rows.iter_mut() {
            row.jn = Real::ZERO;
            row.jt = Real::ZERO;
        }
        for point in self.batches.iter_mut().flat_map(|b| &mut b.points) {
            point.state.jn = [0; LANES];
            point.state.jt = [0; LANES];
        }
        self.narrow.iter_mut().for_each(zero_narrow);
    }

    /// `pass` in place, color after color: a color's batches, then its
    /// other manifolds.
    pub(crate) fn run(
        &mut self,
        pass: Pass,
        rows: &mut [SoftContact],
        bodies: &mut [SolverBody],
        motion: &[Motion],
    ) {
        let compiled = self.compiled;
        for c in self.colors_in_use() {
            let batches = part_mut(&mut self.batches, &self.color_batches, c);
            dispatch(compiled, pass, batches, InPlace(bodies), rows, motion);
            let narrow = part_mut(&mut self.narrow, &self.color_batches, c);
            dispatch(compiled, pass, narrow, InPlace(bodies), rows, motion);
            for &(start, end) in part(&self.scalar, &self.color_scalar, c) {
                if let Some(m) = rows.get_mut(start as usize..end as usize) {
                    scalar_pass(pass, m, &mut InPlace(bodies), motion);
                }
            }
        }
    }

    /// `passes` on bodies threads share, in order, color after color: a
    /// color's batches split between the threads in blocks of
    /// [`BATCH_PIECE`] (any split gives the same bits, as no two
    /// manifolds of a color share a body the solver moves), then its other
    /// manifolds on this thread. One set of stages for all the passes
    /// ([`crate::threads::stages`]): the threads meet between colors on a
    /// counter instead of a hand-over per color.
    pub(crate) fn run_shared(
        &mut self,
        passes: &[Pass],
        rows: &mut [SoftContact],
        shared: &[sweep::SharedBody],
        motion: &[Motion],
    ) {
        // Pass after pass, color after color.
        let stages: Vec<(Pass, usize)> = passes
            .iter()
            .flat_map(|&pass| self.colors_in_use().map(move |c| (pass, c)))
            .collect();
        let WideContacts {
            batches,
            color_batches,
            scalar,
            color_scalar,
            narrow,
            compiled,
            ..
        } = self;
        let run = SharedRun {
            compiled: *compiled,
            stages: &stages,
            color_batches,
            scalar,
            color_scalar,
        };
        // One kind of batch holds a step's manifolds (`build`).
        if narrow.is_empty() {
            run.run(batches, rows, shared, motion);
        } else {
            run.run(narrow, rows, shared, motion);
        }
    }
}

/// One color's plan: each of its batches' manifolds (row ranges), and
/// the manifolds the scalar kernel runs.
#[derive(Clone, Debug, Default)]
struct ColorPlan {
    batches: Vec<[(u32, u32); LANES]>,
    scalar: Vec<(u32, u32)>,
}

/// What [`WideContacts::build`] plans from: a step's rows, where each
/// manifold's rows start, the colors and the bodies.
struct StepRows<'a> {
    narrow: bool,
    rows: &'a [SoftContact],
    manifold_rows: &'a [u32],
    graph: &'a graph::ConstraintGraph,
    bodies: &'a [SolverBody],
}

impl StepRows<'_> {
    /// Manifold `m`'s rows.
    fn rows_of(&self, m: usize) -> (u32, u32) {
        let start = self.manifold_rows.get(m).copied().unwrap_or(0);
        let end = self
            .manifold_rows
            .get(m.saturating_add(1))
            .copied()
            .unwrap_or(start);
        (start, end.max(start))
    }

    /// Color `c`'s plan into `out` (emptied first): its manifolds in
    /// batches of four, the rest for the scalar kernel (see
    /// [`WideContacts::build`]).
    fn plan_color(&self, c: usize, out: &mut ColorPlan) {
        out.batches.clear();
        out.scalar.clear();
        let (rows, bodies) = (self.rows, self.bodies);
        // Manifolds of one and of two points batch apart (a batch solves
        // as many points as its largest manifold has).
        let mut pending: [[usize; LANES]; 2] = [[0; LANES]; 2];
        let mut counts = [0usize; 2];
        for m in self.graph.range(c) {
            let (start, end) = self.rows_of(m);
            let joins = (c < graph::COLORS || self.narrow)
                && rows.get(start as usize).is_some_and(|r| {
                    r.a != r.b && (r.a as usize) < bodies.len() && (r.b as usize) < bodies.len()
                })
                && matches!(end.wrapping_sub(start), 1 | 2)
                && rows
                    .get(start as usize..end as usize)
                    .is_some_and(shares_manifold_constants);
            if !joins {
                out.scalar.push((start, end));
                continue;
            }
            if c == graph::COLORS {
                let mut alone = [(u32::MAX, u32::MAX); LANES];
                set(&mut alone, 0, (start, end));
                out.batches.push(alone);
                continue;
            }
            let kind = usize::from(end.wrapping_sub(start) == 2);
            let (Some(group), Some(n)) = (pending.get_mut(kind), counts.get_mut(kind)) else {
                continue;
            };
            if let Some(slot) = group.get_mut(*n) {
                *slot = m;
                *n = n.saturating_add(1);
            }
            if *n == LANES {
                out.batches.push(group.map(|m| self.rows_of(m)));
                *n = 0;
            }
        }
        let padded = if self.narrow { 1 } else { PADDED_BATCH };
        for (group, &n) in pending.iter().zip(&counts) {
            if n >= padded {
                let mut manifolds = [(u32::MAX, u32::MAX); LANES];
                for (slot, &m) in manifolds.iter_mut().zip(group.iter().take(n)) {
                    *slot = self.rows_of(m);
                }
                out.batches.push(manifolds);
            } else {
                out.scalar
                    .extend(group.iter().take(n).map(|&m| self.rows_of(m)));
            }
        }
    }
}

/// The stages of [`WideContacts::run_shared`] (a pass and a color each),
/// and where each color's batches and scalar manifolds start.
struct SharedRun<'a> {
    compiled: Option<Compiled>,
    stages: &'a [(Pass, usize)],
    color_batches: &'a [u32],
    scalar: &'a [(u32, u32)],
    color_scalar: &'a [u32],
}

impl SharedRun<'_> {
    /// The stages on one kind of batch: a color's blocks on any thread
    /// (each locked by the one thread that claimed it), its scalar
    /// manifolds on this thread once the blocks are done (the rows locked
    /// for writing then, for reading while blocks run).
    fn run<B: LaneBatch>(
        &self,
        batches: &mut [B],
        rows: &mut [SoftContact],
        shared: &[sweep::SharedBody],
        motion: &[Motion],
    ) {
        use std::sync::{Mutex, PoisonError, RwLock};
        // Each color's batches in blocks (the overflow's in one, in
        // order: its manifolds may share bodies), and each color's first
        // block.
        let mut blocks: Vec<Mutex<&mut [B]>> = Vec::new();
        let mut first_block = [0u32; graph::COLORS + 2];
        let mut rest = batches;
        for (c, first) in first_block.iter_mut().enumerate() {
            *first = blocks.len() as u32;
            let Some((mine, tail)) =
                core::mem::take(&mut rest).split_at_mut_checked(part_len(self.color_batches, c))
            else {
                continue;
            };
            rest = tail;
            if c == graph::COLORS {
                blocks.extend((!mine.is_empty()).then(|| Mutex::new(mine)));
            } else {
                blocks.extend(mine.chunks_mut(BATCH_PIECE).map(Mutex::new));
            }
        }
        let counts: Vec<u32> = self
            .stages
            .iter()
            .map(|&(_, c)| part_len(&first_block, c) as u32)
            .collect();
        let rows = RwLock::new(rows);
        let block = |s: usize, k: u32| {
            let Some(&(pass, c)) = self.stages.get(s) else {
                return;
            };
            let index = first_block.get(c).copied().unwrap_or(0).saturating_add(k);
            let Some(block) = blocks.get(index as usize) else {
                return;
            };
            let mut batches = block.lock().unwrap_or_else(PoisonError::into_inner);
            let rows = rows.read().unwrap_or_else(PoisonError::into_inner);
            dispatch(
                self.compiled,
                pass,
                &mut batches,
                Shared(shared),
                &rows,
                motion,
            );
        };
        let serial = |s: usize| {
            let Some(&(pass, c)) = self.stages.get(s) else {
                return;
            };
            let manifolds = part(self.scalar, self.color_scalar, c);
            if manifolds.is_empty() {
                return;
            }
            let mut rows = rows.write().unwrap_or_else(PoisonError::into_inner);
            for &(start, end) in manifolds {
                if let Some(m) = rows.get_mut(start as usize..end as usize) {
                    scalar_pass(pass, m, &mut Shared(shared), motion);
                }
            }
        };
        crate::threads::stages(&counts, &block, serial);
    }
}

/// The narrow batches by color, and where each color's batches and rows
/// start.
struct ColorParts<'a> {
    batches: &'a [NarrowBatch],
    color_batches: &'a [u32],
    color_rows: &'a [u32],
}

impl ColorParts<'_> {
    /// The batches of `colors` back into `rows`, the rows of those colors
    /// (the first of which is row `base`): halves of the colors in
    /// parallel down to [`BATCH_PIECE`] batches.
    fn put(&self, colors: core::ops::Range<usize>, rows: &mut [SoftContact], base: u32) {
        let at = |starts: &[u32], c: usize| starts.get(c).copied().unwrap_or(0);
        let batches =
            at(self.color_batches, colors.end).saturating_sub(at(self.color_batches, colors.start));
        let mid = colors.start.wrapping_add(colors.len() / 2);
        let cut = at(self.color_rows, mid);
        let halves = cut
            .checked_sub(base)
            .and_then(|cut| rows.split_at_mut_checked(cut as usize));
        match halves {
            Some((left, right)) if colors.len() > 1 && batches as usize > BATCH_PIECE => {
                crate::threads::join(
                    || self.put(colors.start..mid, left, base),
                    || self.put(mid..colors.end, right, cut),
                );
            }
            _ => {
                for c in colors {
                    for batch in part(self.batches, self.color_batches, c) {
                        put_narrow(batch, rows, base);
                    }
                }
            }
        }
    }
}

/// Batches per block of a split color (a µs or two of work).
const BATCH_PIECE: usize = 8;

/// Part `c` of `items`, whose parts start at `starts` (and end at the
/// next start).
fn part<'a, T>(items: &'a [T], starts: &[u32], c: usize) -> &'a [T] {
    let start = starts.get(c).copied().unwrap_or(0) as usize;
    let end = starts.get(c.saturating_add(1)).copied().unwrap_or(0) as usize;
    items.get(start..end.max(start)).unwrap_or(&[])
}

/// The length of part `c` of items whose parts start at `starts`.
fn part_len(starts: &[u32], c: usize) -> usize {
    let at = |c: usize| starts.get(c).copied().unwrap_or(0) as usize;
    at(c.saturating_add(1)).saturating_sub(at(c))
}

/// [`part`], mutable.
fn part_mut<'a, T>(items: &'a mut [T], starts: &[u32], c: usize) -> &'a mut [T] {
    let start = starts.get(c).copied().unwrap_or(0) as usize;
    let end = starts.get(c.saturating_add(1)).copied().unwrap_or(0) as usize;
    items.get_mut(start..end.max(start)).unwrap_or(&mut [])
}

/// The scalar kernel's `pass` on one manifold's rows.
#[inline(always)]
fn scalar_pass<S: BodyStore>(pass: Pass, m: &mut [SoftContact], store: &mut S, motion: &[Motion]) {
    match pass {
        Pass::WarmStart(dt_coef) => {
            scale_impulses(m, dt_coef);
            on_store(m, store, |m, copy| warm_start_manifold(m, copy));
        }
        Pass::Solve(p, use_bias) => on_store(m, store, |m, copy| {
            solve_manifold(m, copy, motion, &p, use_bias);
        }),
    }
}

impl LaneBatch for Batch {
    type PassConstants = ();

    fn pass_constants(_: &Pass) {}

    #[inline(always)]
    fn run_pass<O: Ops, S: BodyStore>(
        &mut self,
        ops: O,
        pass: Pass,
        (): (),
        store: &mut S,
        _rows: &[SoftContact],
        motion: &[Motion],
    ) {
        match pass {
            Pass::WarmStart(dt_coef) => {
                warm_start_batch(ops, self, store, dt_coef);
            }
            Pass::Solve(p, use_bias) => {
                solve_batch(ops, self, store, motion, &p, use_bias);
            }
        }
    }
}

/// True when a manifold's rows agree on what a batch keeps once per
/// manifold: the inverse masses and the softness (the prepare gives every
/// row of a manifold those of its bodies).
fn shares_manifold_constants(rows: &[SoftContact]) -> bool {
    let Some(first) = rows.first() else {
        return false;
    };
    rows.iter()
        .all(|r| r.m_inv_a == first.m_inv_a && r.m_inv_b == first.m_inv_b && r.soft == first.soft)
}

/// The fewest manifolds a color's last batch of a kind takes (the rest
/// of its lanes empty); fewer run the scalar kernel. A batch costs the
/// same however many lanes it uses.
const PADDED_BATCH: usize = LANES / 2 + 1;

/// [`gather_into`] a new batch (the tests' form).
#[cfg(test)]
fn gather_batch(manifolds: [(u32, u32); LANES], rows: &[SoftContact]) -> Batch {
    let mut batch = Batch::default();
    gather_into(&mut batch, manifolds, rows);
    batch
}

/// Batches per piece of the split gathers (a few µs of work).
const GATHER_PIECE: usize = 64;

/// Each batch of `batches` reset and gathered from its manifolds in
/// `plan` ([`gather_into`]), in place (a batch is about
/// 1.5 KB: building it apart and moving it in cost two copies), halves in
/// parallel down to [`GATHER_PIECE`]s.
fn gather_split(batches: &mut [Batch], plan: &[[(u32, u32); LANES]], rows: &[SoftContact]) {
    crate::threads::zip_split(plan, batches, GATHER_PIECE, &|manifolds, batch| {
        *batch = Batch::default();
        gather_into(batch, *manifolds, rows);
    });
}

/// The lanes of four manifolds' rows (`(start, end)` each; an empty lane,
/// `start` past the rows, has no bodies and applies nothing) into
/// `batch`, which holds `Batch::default()`.
#[inline(always)]
fn gather_into(batch: &mut Batch, manifolds: [(u32, u32); LANES], rows: &[SoftContact]) {
    batch.a = [u32::MAX; LANES];
    batch.b = [u32::MAX; LANES];
    for (lane, &(start, end)) in manifolds.iter().enumerate() {
        let Some(first) = rows.get(start as usize) else {
            continue;
        };
        set(&mut batch.a, lane, first.a);
        set(&mut batch.b, lane, first.b);
        set(&mut batch.first, lane, start);
        set(&mut batch.count, lane, end.wrapping_sub(start));
        batch.points_used = batch
            .points_used
            .max(end.wrapping_sub(start) as usize)
            .min(2);
        set(&mut batch.m_inv_a, lane, first.m_inv_a.to_bits());
        set(&mut batch.m_inv_b, lane, first.m_inv_b.to_bits());
        set(&mut batch.bias_rate, lane, first.soft.bias_rate.to_bits());
        set(&mut batch.mass_scale, lane, first.soft.mass_scale.to_bits());
        set(
            &mut batch.impulse_scale,
            lane,
            first.soft.impulse_scale.to_bits(),
        );
        for (point, row) in batch
            .points
            .iter_mut()
            .zip(rows.get(start as usize..end as usize).unwrap_or(&[]))
        {
            let bits = |v: Real| v.to_bits();
            set(&mut point.n_x, lane, bits(row.n.x));
            set(&mut point.n_y, lane, bits(row.n.y));
            set(&mut point.dist, lane, bits(row.dist));
            set(&mut point.nr_a, lane, bits(row.nr_a));
            set(&mut point.nr_b, lane, bits(row.nr_b));
            set(&mut point.rn_a, lane, bits(row.rn_a));
            set(&mut point.rn_b, lane, bits(row.rn_b));
            set(&mut point.rt_a, lane, bits(row.rt_a));
            set(&mut point.rt_b, lane, bits(row.rt_b));
            set(&mut point.kn_a, lane, bits(row.kn_a));
            set(&mut point.kn_b, lane, bits(row.kn_b));
            set(&mut point.kt_a, lane, bits(row.kt_a));
            set(&mut point.kt_b, lane, bits(row.kt_b));
            set(&mut point.n_mass, lane, bits(row.n_mass));
            set(&mut point.t_mass, lane, bits(row.t_mass));
            set(&mut point.friction, lane, bits(row.friction));
            set(&mut point.surface_t, lane, bits(row.surface_t));
            set(&mut point.constant_record, lane, row.constant_record);
            set(&mut point.state.sep, lane, bits(row.sep));
            set(&mut point.state.jn, lane, bits(row.jn));
            set(&mut point.state.jt, lane, bits(row.jt));
            set(&mut point.state.max_jn, lane, bits(row.max_jn));
        }
    }
    for point in &mut batch.points {
        point.short = point.find_short();
    }
}

/// `values[lane]` (0 past the end).
#[inline(always)]
fn get(values: &Lane, lane: usize) -> Real {
    Real::from_bits(values.get(lane).copied().unwrap_or(0))
}

/// A lane's state into its rows.
#[inline(always)]
fn put_lane(batch: &Batch, lane: usize, rows: &mut [SoftContact]) {
    let start = batch.first.get(lane).copied().unwrap_or(0) as usize;
    let count = batch.count.get(lane).copied().unwrap_or(0) as usize;
    let Some(out) = rows.get_mut(start..start.saturating_add(count)) else {
        return;
    };
    for (row, point) in out.iter_mut().zip(&batch.points) {
        let s = &point.state;
        row.sep = get(&s.sep, lane);
        row.jn = get(&s.jn, lane);
        row.jt = get(&s.jt, lane);
        row.max_jn = get(&s.max_jn, lane);
    }
}

/// A lane's rows as the scalar kernels read them, rebuilt from the batch
/// (every field a pass reads; the restitution's and the write-back's
/// are left at 0), and their count.
fn lane_rows(batch: &Batch, lane: usize) -> ([SoftContact; 2], usize) {
    let mut out = [SoftContact::default(); 2];
    let count = batch.count.get(lane).copied().unwrap_or(0) as usize;
    for (row, pt) in out.iter_mut().zip(&batch.points) {
        let at = |v: &Lane| get(v, lane);
        *row = SoftContact {
            a: batch.a.get(lane).copied().unwrap_or(0),
            b: batch.b.get(lane).copied().unwrap_or(0),
            n: Vect::new(at(&pt.n_x), at(&pt.n_y)),
            dist: at(&pt.dist),
            sep: at(&pt.state.sep),
            nr_a: at(&pt.nr_a),
            nr_b: at(&pt.nr_b),
            rn_a: at(&pt.rn_a),
            rn_b: at(&pt.rn_b),
            rt_a: at(&pt.rt_a),
            rt_b: at(&pt.rt_b),
            kn_a: at(&pt.kn_a),
            kn_b: at(&pt.kn_b),
            kt_a: at(&pt.kt_a),
            kt_b: at(&pt.kt_b),
            m_inv_a: at(&batch.m_inv_a),
            m_inv_b: at(&batch.m_inv_b),
            n_mass: at(&pt.n_mass),
            t_mass: at(&pt.t_mass),
            friction: at(&pt.friction),
            surface_t: at(&pt.surface_t),
            soft: Softness {
                bias_rate: at(&batch.bias_rate),
                mass_scale: at(&batch.mass_scale),
                impulse_scale: at(&batch.impulse_scale),
            },
            jn: at(&pt.state.jn),
            jt: at(&pt.state.jt),
            max_jn: at(&pt.state.max_jn),
            constant_record: pt.constant_record.get(lane).copied().unwrap_or(u64::MAX),
            ..SoftContact::default()
        };
    }
    (out, count.min(2))
}

/// A lane's state from its rows (after the scalar kernel ran them).
#[inline(always)]
fn take_lane(batch: &mut Batch, lane: usize, rows: &[SoftContact]) {
    for (row, point) in rows.iter().zip(&mut batch.points) {
        let s = &mut point.state;
        set(&mut s.sep, lane, row.sep.to_bits());
        set(&mut s.jn, lane, row.jn.to_bits());
        set(&mut s.jt, lane, row.jt.to_bits());
        set(&mut s.max_jn, lane, row.max_jn.to_bits());
    }
}

/// Four bodies' velocities.
#[derive(Clone, Copy, Debug)]
struct BodyLanes {
    vx: Lane,
    vy: Lane,
    w: Lane,
    /// Which are bodies the solver moves (the others are not stored).
    movable: [bool; LANES],
}

impl BodyLanes {
    #[inline(always)]
    fn gather<S: BodyStore>(store: &S, slots: &[u32; LANES]) -> BodyLanes {
        let mut out = BodyLanes {
            vx: [0; LANES],
            vy: [0; LANES],
            w: [0; LANES],
            movable: [false; LANES],
        };
        for (lane, &slot) in slots.iter().enumerate() {
            if let Some(b) = store.load(slot) {
                set(&mut out.vx, lane, b.v.x.to_bits());
                set(&mut out.vy, lane, b.v.y.to_bits());
                set(&mut out.w, lane, b.w.to_bits());
                set(&mut out.movable, lane, movable(&b));
            }
        }
        out
    }

    /// Stores the movable bodies of the lanes not `left`.
    #[inline(always)]
    fn scatter<S: BodyStore>(&self, store: &mut S, slots: &[u32; LANES], left: &[bool; LANES]) {
        for (lane, ((&slot, &l), &m)) in slots.iter().zip(left).zip(&self.movable).enumerate() {
            if l || !m {
                continue;
            }
            let body = SolverBody {
                v: Vect::new(get(&self.vx, lane), get(&self.vy, lane)),
                w: get(&self.w, lane),
                ..SolverBody::default()
            };
            store.store(slot, &body);
        }
    }

    /// `dv` and `dw` added (`add`) or taken away.
    #[inline(always)]
    fn change<O: Ops>(&mut self, o: O, dv: (Lane, Lane), dw: Lane, add: bool) {
        if add {
            self.vx = o.add(self.vx, dv.0);
            self.vy = o.add(self.vy, dv.1);
            self.w = o.add(self.w, dw);
        } else {
            self.vx = o.sub(self.vx, dv.0);
            self.vy = o.sub(self.vy, dv.1);
            self.w = o.sub(self.w, dw);
        }
    }
}

/// `Real` bits in every lane.
#[inline(always)]
fn lane_of(v: Real) -> Lane {
    [v.to_bits(); LANES]
}

/// A batch's inverse masses.
#[derive(Clone, Copy)]
struct Masses {
    a: Lane,
    b: Lane,
    /// Every lane's two inverse masses are equal (a pile of like bodies):
    /// the velocity changes of b are those of a.
    same: bool,
}

impl Masses {
    #[inline(always)]
    fn of(batch: &Batch) -> Masses {
        Masses {
            a: batch.m_inv_a,
            b: batch.m_inv_b,
            same: batch.m_inv_a == batch.m_inv_b,
        }
    }

    /// `p·m_a⁻¹` and `p·m_b⁻¹` (the same products once when the masses
    /// are equal: the same bits and the same record, an OR).
    #[inline(always)]
    fn velocity_changes<O: Ops>(
        &self,
        px: Lane,
        py: Lane,
        ar: &mut LaneArith<O>,
    ) -> ((Lane, Lane), (Lane, Lane)) {
        let (px, py) = (ar.factor(px), ar.factor(py));
        let m = ar.factor(self.a);
        let dva = (ar.mul_factors(&px, &m), ar.mul_factors(&py, &m));
        if self.same {
            return (dva, dva);
        }
        let m = ar.factor(self.b);
        let dvb = (ar.mul_factors(&px, &m), ar.mul_factors(&py, &m));
        (dva, dvb)
    }
}

/// A direction of a point's rows and its angular terms: the normal
/// `(n, r × n, I⁻¹ (r × n))` or the tangent.
#[derive(Clone, Copy)]
struct Direction<const SHORT: bool> {
    x: Factor<SHORT>,
    y: Factor<SHORT>,
    /// `[r_b × d, −(r_a × d)]`: the relative velocity's lever terms.
    levers: [Factor<SHORT>; 2],
    /// `[I_a⁻¹ (r_a × d), I_b⁻¹ (r_b × d)]` (long: `I⁻¹` is often above 1).
    k: [Factor; 2],
}

impl<const SHORT: bool> Direction<SHORT> {
    /// The normal of a point's rows.
    #[inline(always)]
    fn normal<O: Ops>(pt: &PointLanes, ar: &LaneArith<O>) -> Direction<SHORT> {
        let o = ar.ops();
        Direction {
            x: ar.split(pt.n_x),
            y: ar.split(pt.n_y),
            levers: [ar.split(pt.rn_b), ar.split(o.neg(pt.rn_a))],
            k: [ar.factor(pt.kn_a), ar.factor(pt.kn_b)],
        }
    }

    /// The tangent `(−n_y, n_x)` of a point's rows.
    #[inline(always)]
    fn tangent<O: Ops>(pt: &PointLanes, ar: &LaneArith<O>) -> Direction<SHORT> {
        let o = ar.ops();
        Direction {
            x: ar.split(o.neg(pt.n_y)),
            y: ar.split(pt.n_x),
            levers: [ar.split(pt.rt_b), ar.split(o.neg(pt.rt_a))],
            k: [ar.factor(pt.kt_a), ar.factor(pt.kt_b)],
        }
    }
}

/// An impulse `p = d·j` along `d` with angular terms `k`: `SoftContact::
/// apply_along`, lane by lane.
#[inline(always)]
fn apply_along<O: Ops, const SHORT: bool>(
    a: &mut BodyLanes,
    b: &mut BodyLanes,
    masses: &Masses,
    d: &Direction<SHORT>,
    j: Lane,
    ar: &mut LaneArith<O>,
) {
    let o = ar.ops();
    let j = ar.factor(j);
    let (px, py) = (ar.mul_factors(&d.x, &j), ar.mul_factors(&d.y, &j));
    let [ka, kb] = &d.k;
    let (dwa, dwb) = (ar.mul_factors(ka, &j), ar.mul_factors(kb, &j));
    let (dva, dvb) = masses.velocity_changes(px, py, ar);
    a.change(o, dva, dwa, false);
    b.change(o, dvb, dwb, true);
}

/// The velocity of b relative to a along `d`: `dot4([Δv, ω_b, ω_a], [d,
/// r_b × d, −(r_a × d)])`.
#[inline(always)]
fn relative_velocity<O: Ops, const SHORT: bool>(
    a: &BodyLanes,
    b: &BodyLanes,
    d: &Direction<SHORT>,
    ar: &mut LaneArith<O>,
) -> Lane {
    let o = ar.ops();
    let dvx = o.sub(b.vx, a.vx);
    let dvy = o.sub(b.vy, a.vy);
    let [rb, ra] = d.levers;
    ar.dot_by([dvx, dvy, b.w, a.w], &[d.x, d.y, rb, ra])
}

/// The solve (`use_bias`) or relax pass of a batch: `manifold_pass` on
/// four lanes, the lanes that left the window run again by the scalar
/// kernel; returns how many.
#[inline(always)]
fn solve_batch<O: Ops, S: BodyStore>(
    ops: O,
    batch: &mut Batch,
    store: &mut S,
    motion: &[Motion],
    p: &SoftContactParams,
    use_bias: bool,
) -> usize {
    let a = BodyLanes::gather(store, &batch.a);
    let b = BodyLanes::gather(store, &batch.b);
    let mut ar = LaneArith::new(ops);
    ar.check_inputs(&[a.vx, a.vy, a.w, b.vx, b.vy, b.w, lane_of(p.slop)]);
    let mut state = batch.points.map(|pt| pt.state);
    let used = batch.points_used;
    for (pt, s) in batch.points.iter().zip(&state) {
        ar.check_records(&pt.constant_record);
        ar.check_inputs(&[s.jn, s.jt]);
    }
    // The motion since the collide (relax pass only).
    let mut ma = [[0i64; LANES]; 4];
    let mut mb = [[0i64; LANES]; 4];
    if use_bias {
        for s in &state {
            ar.check_inputs(&[s.sep]);
        }
    } else {
        let none = Motion::default();
        for lane in 0..LANES {
            let m_a = batch
                .a
                .get(lane)
                .and_then(|&i| motion.get(i as usize))
                .unwrap_or(&none);
            let m_b = batch
                .b
                .get(lane)
                .and_then(|&i| motion.get(i as usize))
                .unwrap_or(&none);
            for (out, m) in [(&mut ma, m_a), (&mut mb, m_b)] {
                let [dx, dy, c1, s1] = out;
                set(dx, lane, m.dp.x.to_bits());
                set(dy, lane, m.dp.y.to_bits());
                set(c1, lane, m.dq_c1.to_bits());
                set(s1, lane, m.dq_s.to_bits());
            }
        }
        ar.check_inputs(&ma);
        ar.check_inputs(&mb);
    }
    let pass = RowPass {
        p,
        use_bias,
        masses: Masses::of(batch),
        motion: [ma, mb],
        bias_rate: batch.bias_rate,
        mass_scale: batch.mass_scale,
        impulse_scale: batch.impulse_scale,
    };
    let mut bodies = [a, b];
    for (pt, st) in batch.points.iter().zip(&mut state).take(used) {
        row_part(Row::Normal, &pass, pt, st, &mut bodies, &mut ar);
    }
    if p.friction {
        for (pt, st) in batch.points.iter().zip(&mut state).take(used) {
            row_part(Row::Friction, &pass, pt, st, &mut bodies, &mut ar);
        }
    }
    let [a, b] = bodies;
    let left = ar.left();
    a.scatter(store, &batch.a, &left);
    b.scatter(store, &batch.b, &left);
    if left.contains(&true) {
        // The lanes that left keep their state from before the pass, for
        // the scalar kernel to start from.
        for (pt, st) in batch.points.iter_mut().zip(&state) {
            pt.state = keep_left(pt.state, *st, &left);
        }
        rerun_left(batch, store, &left, |m, copy| {
            solve_manifold(m, copy, motion, p, use_bias);
        })
    } else {
        for (pt, st) in batch.points.iter_mut().zip(&state) {
            pt.state = *st;
        }
        0
    }
}

/// What the rows of one solve or relax pass over a batch share.
struct RowPass<'a> {
    p: &'a SoftContactParams,
    use_bias: bool,
    masses: Masses,
    /// Each body's motion since the collide (`[dx, dy, cos − 1, sin]`,
    /// relax pass only).
    motion: [[Lane; 4]; 2],
    bias_rate: Lane,
    mass_scale: Lane,
    impulse_scale: Lane,
}

/// Which row of a point.
#[derive(Clone, Copy, Debug)]
enum Row {
    Normal,
    Friction,
}

/// One point's `row` in a solve or relax pass, as a part of the pass
/// kernel ([`Ops::run_part`]): a function of its own, compiled for the
/// kernel's lane operations. Inlined, the rows' short and long copies
/// made the pass kernel one function so large that optimising it took
/// most of the engine's compile time; as parts, a call per row, whose
/// lanes pass through memory.
#[inline(always)]
fn row_part<O: Ops>(
    row: Row,
    pass: &RowPass<'_>,
    pt: &PointLanes,
    st: &mut PointState,
    bodies: &mut [BodyLanes; 2],
    ar: &mut LaneArith<O>,
) {
    let o = ar.ops();
    if pt.short {
        o.run_part(RowPart::<O, true> {
            row,
            pass,
            pt,
            st,
            bodies,
            ar,
        });
    } else {
        o.run_part(RowPart::<O, false> {
            row,
            pass,
            pt,
            st,
            bodies,
            ar,
        });
    }
}

/// What [`row_part`] hands to its part (`SHORT`: the point's constants
/// are short).
struct RowPart<'r, 'p, O: Ops, const SHORT: bool> {
    row: Row,
    pass: &'r RowPass<'p>,
    pt: &'r PointLanes,
    st: &'r mut PointState,
    bodies: &'r mut [BodyLanes; 2],
    ar: &'r mut LaneArith<O>,
}

impl<O: Ops, const SHORT: bool> tamias2d_simd::Kernel for RowPart<'_, '_, O, SHORT> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let RowPart {
            row,
            pass,
            pt,
            st,
            bodies,
            ar,
        } = self;
        match row {
            Row::Normal => normal_row::<O, SHORT>(pass, pt, st, bodies, ar),
            Row::Friction => friction_row::<O, SHORT>(pass, pt, st, bodies, ar),
        }
    }
}

/// A point's normal row (`SHORT`: its constants are short).
#[inline(always)]
fn normal_row<O: Ops, const SHORT: bool>(
    pass: &RowPass<'_>,
    pt: &PointLanes,
    st: &mut PointState,
    [a, b]: &mut [BodyLanes; 2],
    ar: &mut LaneArith<O>,
) {
    let (o, p) = (ar.ops(), pass.p);
    let zero = [0i64; LANES];
    let one = lane_of(Real::ONE);
    let normal = Direction::<SHORT>::normal(pt, ar);
    // The separation: kept from the last relax pass, or estimated.
    let s = if pass.use_bias {
        st.sep
    } else {
        let [[adx, ady, ac1, as1], [bdx, bdy, bc1, bs1]] = pass.motion;
        let dx = o.sub(bdx, adx);
        let dy = o.sub(bdy, ady);
        let (nr_b, rn_b) = (ar.split::<SHORT>(pt.nr_b), ar.split::<SHORT>(pt.rn_b));
        let moved_b = ar.dot_by([dx, dy, bc1, bs1], &[normal.x, normal.y, nr_b, rn_b]);
        let (nr_a, rn_a) = (ar.split::<SHORT>(pt.nr_a), ar.split::<SHORT>(pt.rn_a));
        let turned_a = ar.dot_by([ac1, as1], &[nr_a, rn_a]);
        let s = o.add(pt.dist, o.sub(moved_b, turned_a));
        st.sep = s;
        s
    };
    // The normal row: apart, the gap closes within the sub-step
    // (rigid); overlapping, the soft push (solve) or nothing (relax).
    let apart = o.positive(s);
    let close = ar.mul(s, lane_of(p.h_inv));
    let (bias, mass_scale, impulse_scale) = if pass.use_bias {
        let overlap = o.min(o.add(s, lane_of(p.slop)), zero);
        let push = o.max(ar.mul(overlap, pass.bias_rate), lane_of(-p.push_out));
        (
            o.select(apart, close, push),
            o.select(apart, one, pass.mass_scale),
            o.select(apart, zero, pass.impulse_scale),
        )
    } else {
        (o.select(apart, close, zero), one, zero)
    };
    let vn = relative_velocity(a, b, &normal, ar);
    let err = o.add(vn, bias);
    let jn = ar.mul_by(err, &ar.split::<SHORT>(pt.n_mass));
    let scaled = ar.mul(jn, mass_scale);
    let back = ar.mul(st.jn, impulse_scale);
    let jn = o.add(scaled, back);
    let old = st.jn;
    st.jn = o.max(o.sub(old, jn), zero);
    let djn = o.sub(st.jn, old);
    st.max_jn = o.max(st.max_jn, djn);
    apply_along(a, b, &pass.masses, &normal, djn, ar);
}

/// A point's friction row (`SHORT`: its constants are short).
#[inline(always)]
fn friction_row<O: Ops, const SHORT: bool>(
    pass: &RowPass<'_>,
    pt: &PointLanes,
    st: &mut PointState,
    [a, b]: &mut [BodyLanes; 2],
    ar: &mut LaneArith<O>,
) {
    let o = ar.ops();
    let tangent = Direction::<SHORT>::tangent(pt, ar);
    let vt = relative_velocity(a, b, &tangent, ar);
    let vt = o.add(vt, pt.surface_t);
    let jt_max = ar.mul_by(st.jn, &ar.split::<SHORT>(pt.friction));
    let djt = ar.mul_by(vt, &ar.split::<SHORT>(pt.t_mass));
    let old = st.jt;
    st.jt = o.min(o.max(o.sub(old, djt), o.neg(jt_max)), jt_max);
    let jt = o.sub(st.jt, old);
    apply_along(a, b, &pass.masses, &tangent, jt, ar);
}

/// The warm start of a batch: `warm_start_manifold` on four lanes;
/// returns how many lanes ran again on the scalar kernel.
#[inline(always)]
fn warm_start_batch<O: Ops, S: BodyStore>(
    ops: O,
    batch: &mut Batch,
    store: &mut S,
    dt_coef: Real,
) -> usize {
    if dt_coef != Real::ONE {
        // The first sub-step after a change of time step (rare): the
        // scalar kernel's saturating products.
        for pt in &mut batch.points {
            for v in pt.state.jn.iter_mut().chain(&mut pt.state.jt) {
                *v = (Real::from_bits(*v) * dt_coef).to_bits();
            }
        }
    }
    let mut a = BodyLanes::gather(store, &batch.a);
    let mut b = BodyLanes::gather(store, &batch.b);
    let mut ar = LaneArith::new(ops);
    let o = ops;
    ar.check_inputs(&[a.vx, a.vy, a.w, b.vx, b.vy, b.w]);
    let masses = Masses::of(batch);
    for pt in batch.points.iter().take(batch.points_used) {
        // The negated normal component below needs the constants' bound.
        ar.check_records(&pt.constant_record);
        let j = [ar.factor(pt.state.jn), ar.factor(pt.state.jt)];
        let ((dva, dvb), dwa, dwb) = if pt.short {
            o.run_part(WarmStartPart::<O, true> {
                pt,
                masses: &masses,
                j: &j,
                ar: &mut ar,
            })
        } else {
            o.run_part(WarmStartPart::<O, false> {
                pt,
                masses: &masses,
                j: &j,
                ar: &mut ar,
            })
        };
        a.change(o, dva, dwa, false);
        b.change(o, dvb, dwb, true);
    }
    let left = ar.left();
    a.scatter(store, &batch.a, &left);
    b.scatter(store, &batch.b, &left);
    if left.contains(&true) {
        rerun_left(batch, store, &left, |m, copy| {
            warm_start_manifold(m, copy);
        })
    } else {
        0
    }
}

/// A point's warm start as a part of the pass kernel (as [`row_part`]):
/// [`warm_start_point`]'s arguments.
struct WarmStartPart<'r, O: Ops, const SHORT: bool> {
    pt: &'r PointLanes,
    masses: &'r Masses,
    j: &'r [Factor; 2],
    ar: &'r mut LaneArith<O>,
}

impl<O: Ops, const SHORT: bool> tamias2d_simd::Kernel for WarmStartPart<'_, O, SHORT> {
    type Output = (((Lane, Lane), (Lane, Lane)), Lane, Lane);

    #[inline(always)]
    fn run(self) -> Self::Output {
        warm_start_point::<O, SHORT>(self.pt, self.masses, self.j, self.ar)
    }
}

/// A point's warm start: the velocity changes `(dv_a, dv_b)`, `dω_a`,
/// `dω_b` of its impulses `j = [jn, jt]` (`SHORT`: its constants are
/// short).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn warm_start_point<O: Ops, const SHORT: bool>(
    pt: &PointLanes,
    masses: &Masses,
    j: &[Factor; 2],
    ar: &mut LaneArith<O>,
) -> (((Lane, Lane), (Lane, Lane)), Lane, Lane) {
    let o = ar.ops();
    let (n_x, n_y) = (ar.split::<SHORT>(pt.n_x), ar.split::<SHORT>(pt.n_y));
    let t_x = ar.split::<SHORT>(o.neg(pt.n_y));
    let px = ar.dot_factors(&[n_x, t_x], j);
    let py = ar.dot_factors(&[n_y, n_x], j);
    let dwa = ar.dot_factors(&[ar.factor(pt.kn_a), ar.factor(pt.kt_a)], j);
    let dwb = ar.dot_factors(&[ar.factor(pt.kn_b), ar.factor(pt.kt_b)], j);
    (masses.velocity_changes(px, py, ar), dwa, dwb)
}

/// The lanes that left the window, run again by the scalar kernel `f`
/// from their state before the pass (which the batch still holds), on
/// rows rebuilt from the batch; returns how many.
#[cold]
#[inline(never)]
fn rerun_left<S: BodyStore>(
    batch: &mut Batch,
    store: &mut S,
    left: &[bool; LANES],
    mut f: impl FnMut(&mut [SoftContact], &mut [SolverBody; 2]),
) -> usize {
    let mut count = 0usize;
    for (lane, _) in left.iter().enumerate().filter(|(_, &l)| l) {
        count = count.saturating_add(1);
        let (mut rows, n) = lane_rows(batch, lane);
        let m = rows.get_mut(..n).unwrap_or(&mut []);
        on_store(m, store, &mut f);
        take_lane(batch, lane, m);
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lanes::Portable;
    use crate::solver::soft_contact::row::on_bodies;
    use crate::solver::soft_contact::row::tests::{case, values, Counting};
    use proptest::prelude::*;

    /// Lanes that left their window in the cases so far, and cases
    /// (coverage of the rerun path, printed).
    static LEFT: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(0);
    static CASES: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(0);

    /// A pass of the wide kernel on `ops` against the scalar kernel on
    /// each manifold: the same rows, bodies and bits.
    /// `used`: the manifolds in the batch (the other lanes empty, as in a
    /// color's last batch).
    fn compare<O: Ops>(
        ops: O,
        vals: Vec<i64>,
        (points, friction, like, used): ([bool; LANES], bool, bool, usize),
        pass: Option<bool>,
    ) -> Result<(), TestCaseError> {
        let (rows, mut manifolds, bodies, motion, p) = case(vals, points, friction, like);
        for m in manifolds.iter_mut().skip(used) {
            *m = (u32::MAX, u32::MAX);
        }
        // Scalar.
        let (mut s_rows, mut s_bodies) = (rows.clone(), bodies.clone());
        for &(start, end) in manifolds.iter().take(used) {
            let m = &mut s_rows[start as usize..end as usize];
            match pass {
                Some(use_bias) => on_bodies(m, &mut s_bodies, |m, copy| {
                    solve_manifold(m, copy, &motion, &p, use_bias);
                }),
                None => on_bodies(m, &mut s_bodies, |m, copy| warm_start_manifold(m, copy)),
            }
        }
        // Wide.
        let (mut w_rows, mut w_bodies) = (rows.clone(), bodies.clone());
        let mut batch = gather_batch(manifolds, &w_rows);
        let mut store = InPlace(&mut w_bodies);
        let left = match pass {
            Some(use_bias) => solve_batch(ops, &mut batch, &mut store, &motion, &p, use_bias),
            None => warm_start_batch(ops, &mut batch, &mut store, Real::ONE),
        };
        LEFT.fetch_add(left as u64, core::sync::atomic::Ordering::Relaxed);
        for lane in 0..LANES {
            put_lane(&batch, lane, &mut w_rows);
        }
        prop_assert_eq!(w_rows, s_rows);
        prop_assert_eq!(w_bodies, s_bodies);
        Ok(())
    }

    /// The lane operations of each pass over a batch of four two-point
    /// manifolds with friction, per row (a manifold point): the figure
    /// `docs/performance.md` reports, and a bound a change that adds
    /// operations to the kernels has to move.
    #[test]
    fn lane_operations_per_row_and_pass() {
        // Scene-like values, any bits: magnitudes up to 2 (raw 2^33, where
        // about half the constants are long) and below 1 (every constant
        // short, as in a pile of boxes under a metre).
        let count = |shift: u32, pass: Option<bool>| {
            let vals: Vec<i64> = (1..200i64)
                .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> shift)
                .collect();
            let (rows, manifolds, bodies, motion, p) = case(vals, [true; LANES], true, false);
            let ops = core::cell::Cell::new(0);
            let mut bodies = bodies.clone();
            let mut batch = gather_batch(manifolds, &rows);
            let mut store = InPlace(&mut bodies);
            let left = match pass {
                Some(use_bias) => solve_batch(
                    Counting(&ops),
                    &mut batch,
                    &mut store,
                    &motion,
                    &p,
                    use_bias,
                ),
                None => warm_start_batch(Counting(&ops), &mut batch, &mut store, Real::ONE),
            };
            assert_eq!(
                left, 0,
                "a lane left the window: the count would include a rerun"
            );
            ops.get() as f64 / (2 * LANES) as f64
        };
        let passes = |shift| {
            (
                count(shift, None),
                count(shift, Some(true)),
                count(shift, Some(false)),
            )
        };
        let (warm, solve, relax) = passes(30);
        eprintln!(
            "lane operations per row, up to 2: warm start {warm}, solve {solve}, relax {relax}"
        );
        let (s_warm, s_solve, s_relax) = passes(31);
        eprintln!("lane operations per row, below 1: warm start {s_warm}, solve {s_solve}, relax {s_relax}");
        // 5 % above today's counts.
        assert!(warm <= 85.0 && solve <= 195.0 && relax <= 236.0);
        assert!(s_warm <= 78.0 && s_solve <= 169.0 && s_relax <= 199.0);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2_000))]
        /// The wide kernels, portable and (where the processor has it)
        /// AVX2, give the scalar kernels' bits on any input: in the
        /// window, at its edges and past them (where lanes run again on
        /// the scalar kernel).
        #[test]
        fn wide_passes_match_the_scalar_kernels(
            vals in values(),
            points in prop::array::uniform4(any::<bool>()),
            friction in any::<bool>(),
            like in any::<bool>(),
            used in prop_oneof![3 => Just(LANES), 1 => 1..LANES],
            pass in prop_oneof![Just(None), Just(Some(true)), Just(Some(false))],
        ) {
            let shape = (points, friction, like, used);
            compare(Portable, vals.clone(), shape, pass)?;
            if let Some(avx2) = tamias2d_simd::Avx2::new() {
                compare(avx2, vals.clone(), shape, pass)?;
            }
            // Coverage: how often a lane left (and ran the scalar kernel).
            use core::sync::atomic::Ordering::Relaxed;
            let cases = CASES.fetch_add(1, Relaxed) + 1;
            if cases % 1000 == 0 {
                eprintln!("cases {cases}, lanes left so far {}", LEFT.load(Relaxed));
            }
        }
    }
}
