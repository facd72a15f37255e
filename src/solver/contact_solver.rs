//! The contact solver: the loops over the contact rows of a step, over
//! its own scratch (the solver bodies, the rows in solve order, the
//! blocks, the colors). The step calls it in stage order:
//! [`load_bodies`](ContactSolver::load_bodies),
//! [`prepare`](ContactSolver::prepare), then, after the velocities are
//! integrated, [`warm_start_and_solve`](ContactSolver::warm_start_and_solve)
//! (which interleaves the joints' rows, through [`JointRows`]), and
//! [`store`](ContactSolver::store).
//!
//! With threads, the preparation is split between them manifold by
//! manifold, and with the colored order the warm start and the
//! iterations color by color ([`sweep`]): the same bits as one thread.
use crate::arbiter::{Arbiter, ManifoldPoint};
use crate::arena::Arena;
use crate::body::{Body, BodyType};
use crate::math::Real;

use super::block::ManifoldBlock;
use super::{
    effective_mass, graph, sweep, ContactConstraint, ContactParams, PairParams, SolverBody,
    SolverSwitches,
};

/// The contact solver's scratch (not simulation state): the contiguous
/// body array, indexed by body slot, and this step's contact rows in solve
/// order (by color, see [`graph`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct ContactSolver {
    /// Velocities and inverse masses of every body slot.
    pub(crate) bodies: Vec<SolverBody>,
    /// One row per contact of the solved arbiters.
    pub(crate) constraints: Vec<ContactConstraint>,
    /// The blocks of two-contact manifolds (see [`super::block`]), referred
    /// to by their first row's [`ContactConstraint::block`].
    pub(crate) blocks: Vec<ManifoldBlock>,
    /// The arbiters' colors: the order the rows are built and solved in.
    pub(crate) graph: graph::ConstraintGraph,
    /// `color_rows[c]..color_rows[c + 1]`: the rows of color `c` (the
    /// overflow's at `c = graph::COLORS`).
    pub(crate) color_rows: [u32; graph::COLORS + 2],
    /// The first row of each manifold in solve order, and the end: a
    /// color's manifolds are the pieces [`sweep`] splits it into.
    pub(crate) manifold_rows: Vec<u32>,
    /// The first block slot of each manifold in solve order, and the end
    /// (a two-contact manifold has one, used if it is solved as a block).
    pub(crate) manifold_blocks: Vec<u32>,
    /// The bodies while threads share them ([`sweep::SharedBody`]).
    pub(crate) shared: Vec<sweep::SharedBody>,
}

/// The rows the contact solver interleaves with its own in every pass: the
/// joints' (implemented by `constraint::solve::ConstraintScratch`, a layer
/// above the solver). Solved after the contacts, on the bodies unshared.
pub(crate) trait JointRows {
    /// No rows at all (then the threads need not unshare the bodies).
    fn is_empty(&self) -> bool;
    /// Re-applies last step's impulses, scaled by `dt_coef`.
    fn warm_start(&mut self, bodies: &mut [SolverBody], dt_coef: Real);
    /// One Gauss–Seidel pass over the rows.
    fn iterate(&mut self, bodies: &mut [SolverBody]);
}

/// How the contact rows are ordered and grouped (from the settings).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowOrder {
    /// Color by color (`Settings::colored_solver`), or canonical.
    pub(crate) colored: bool,
    /// Two-contact manifolds as blocks (`Settings::block_solver`).
    pub(crate) blocks: bool,
}

impl ContactSolver {
    /// The solver bodies: velocities, bias velocities and inverse masses of
    /// every body slot, side by side. A sleeping or non-dynamic body gets
    /// zero inverse mass (it is never in an active contact with a sleeping
    /// one: the wake stage woke whatever touches it). Returns how many
    /// awake dynamic bodies have no mass (a diagnostic).
    pub(crate) fn load_bodies(&mut self, bodies: &Arena<Body>) -> u32 {
        let sb = &mut self.bodies;
        sb.clear();
        sb.resize(bodies.capacity_slots(), SolverBody::default());
        // Body by body (slot i into solver slot i), in pieces the threads
        // share; the count does not depend on the order.
        let massless = core::sync::atomic::AtomicU32::new(0);
        bodies.zip_values_split(sb, 512, &|body: &Body, slot: &mut SolverBody| {
            let dynamic = body.body_type() == BodyType::Dynamic && !body.is_sleeping();
            if dynamic && !body.can_step() {
                massless.fetch_add(1, core::sync::atomic::Ordering::Relaxed);
            }
            *slot = SolverBody {
                v: body.velocity(),
                w: body.angular_velocity(),
                v_bias: body.v_bias,
                w_bias: body.w_bias,
                m_inv: if dynamic { body.mass_inv() } else { Real::ZERO },
                i_inv: if dynamic {
                    body.moment_inv()
                } else {
                    Real::ZERO
                },
            };
        });
        massless.into_inner()
    }

    /// The rows of the `active` arbiters: the solve order (canonical, or by
    /// color: [`graph`]), then one row per manifold point with its
    /// effective masses, bias and bounce (every division of the contact
    /// solver happens here). One path for any thread count: a first pass
    /// places each manifold's rows and block slot, then the manifolds are
    /// prepared in pieces, halves in parallel where there are threads
    /// (inline on one), each writing only its own rows. Returns the number
    /// of rows.
    pub(crate) fn prepare(
        &mut self,
        arbiters: &[Arbiter],
        active: &[u32],
        params: &ContactParams,
        order: RowOrder,
    ) -> u32 {
        let ContactSolver {
            bodies: solver_bodies,
            constraints: contact_constraints,
            blocks,
            graph,
            color_rows,
            manifold_rows,
            manifold_blocks,
            ..
        } = self;
        if !order.colored {
            graph.uncolored(active);
        } else {
            color_arbiters(graph, arbiters, active, solver_bodies);
        }
        let use_blocks = order.blocks;
        let job = PrepareJob {
            arbiters,
            bodies: solver_bodies,
            params,
            friction: params.switches.friction,
        };
        // Where each manifold's rows and block go, in one pass over the
        // arbiters: the manifolds can then be prepared in any order, and
        // split between threads.
        manifold_rows.clear();
        manifold_blocks.clear();
        let (mut rows, mut block_count) = (0u32, 0u32);
        for &i in graph.order() {
            manifold_rows.push(rows);
            manifold_blocks.push(block_count);
            // At most MAX_CONTACTS_PER_ARBITER (2) rows per arbiter, and
            // rows are counted in u32 like the stats.
            let n = arbiters
                .get(i as usize)
                .map_or(0, |a| a.contacts().len() as u32);
            rows = rows.saturating_add(n);
            block_count = block_count.saturating_add(u32::from(use_blocks && n == 2));
        }
        manifold_rows.push(rows);
        manifold_blocks.push(block_count);
        // Every row is written below, and a block slot is read only by the
        // row that points at it once written: last step's contents stay
        // where the lists were long enough (no 200-byte default per row).
        contact_constraints.truncate(rows as usize);
        contact_constraints.resize(rows as usize, ContactConstraint::default());
        blocks.truncate(block_count as usize);
        blocks.resize(block_count as usize, ManifoldBlock::default());
        let order = graph.order();
        let parts = ManifoldParts {
            order,
            rows: manifold_rows,
            blocks: manifold_blocks,
        };
        prepare_split(&job, parts, contact_constraints, blocks);
        for (c, first_row) in color_rows.iter_mut().enumerate() {
            let first_manifold = graph.range(c).start;
            *first_row = manifold_rows.get(first_manifold).copied().unwrap_or(0);
        }
        contact_constraints.len() as u32
    }

    /// The warm start (with warm starting on) and `iterations` passes:
    /// the contacts, then the joints' rows, in every pass, with the
    /// iteration routine of the switched-on parts chosen once (see
    /// [`ContactConstraint::solve_with`]). With `split` (threads and the
    /// colored order), both run color by color on bodies the threads share
    /// ([`sweep`]): the same bits.
    pub(crate) fn warm_start_and_solve(
        &mut self,
        joints: &mut impl JointRows,
        switches: SolverSwitches,
        dt_coef: Real,
        iterations: u32,
        split: bool,
    ) {
        let n = iterations;
        if split {
            let warm = switches.warm_starting.then_some(dt_coef);
            match (switches.friction, switches.bias_impulses) {
                (true, true) => self.solve_split::<true, true>(joints, n, warm),
                (true, false) => self.solve_split::<true, false>(joints, n, warm),
                (false, true) => self.solve_split::<false, true>(joints, n, warm),
                (false, false) => self.solve_split::<false, false>(joints, n, warm),
            }
            return;
        }
        if switches.warm_starting {
            self.warm_start(switches, dt_coef);
            if !joints.is_empty() {
                joints.warm_start(&mut self.bodies, dt_coef);
            }
        }
        match (switches.friction, switches.bias_impulses) {
            (true, true) => self.iterate::<true, true>(joints, n),
            (true, false) => self.iterate::<true, false>(joints, n),
            (false, true) => self.iterate::<false, true>(joints, n),
            (false, false) => self.iterate::<false, false>(joints, n),
        }
    }

    /// Re-applies last step's accumulated impulses, scaled by
    /// `dt_coef = min(dt / prev_dt, 1)`; the scaled impulses become the
    /// accumulators the iterations start from
    /// ([`ContactConstraint::warm_start`]).
    ///
    /// Why never more than 1: a contact's impulse is part force (a resting
    /// load, proportional to `dt`) and part impact (a velocity change,
    /// independent of `dt`). Scaling the impact part up by a long step
    /// after a short one pushes the bodies apart by many times the impulse
    /// that stopped them; the iterations can take it back only as far as
    /// they propagate through a stack in `iterations` passes, and
    /// `pyramid_20` alternating 1/1000 and 1/30 s reached 27 m/s even with
    /// consistent accumulators. A guess that is too small only costs
    /// convergence (the iterations add the rest, the bias corrects the
    /// overlap), so after a longer step the cached impulse is applied
    /// unscaled. A shorter step scales it down. For a constant `dt` the
    /// ratio is exactly 1 and no bit changes.
    fn warm_start(&mut self, switches: SolverSwitches, dt_coef: Real) {
        let (bodies, rows) = (&mut self.bodies, &mut self.constraints);
        if switches.friction {
            for c in rows.iter_mut() {
                c.warm_start(bodies, dt_coef);
            }
        } else {
            for c in rows.iter_mut() {
                c.warm_start_normal(bodies, dt_coef);
            }
        }
    }

    /// `n` Gauss–Seidel passes in place over the contacts in solve order
    /// (canonical, or color by color: see [`graph`]), each followed by the
    /// joints' rows.
    fn iterate<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        joints: &mut impl JointRows,
        n: u32,
    ) {
        let (bodies, rows, blocks) = (&mut self.bodies, &mut self.constraints, &self.blocks);
        for _ in 0..n {
            sweep::solve_rows::<FRICTION, BIAS>(rows, blocks, bodies);
            joints.iterate(bodies);
        }
    }

    /// The warm start (with `warm = Some(dt_coef)`) and the passes on
    /// threads: each color split between them on shared bodies, the
    /// overflow in order on one, the joints on one with the bodies
    /// unshared. The order of [`iterate`](Self::iterate) and of the serial
    /// warm start exactly.
    fn solve_split<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        joints: &mut impl JointRows,
        n: u32,
        warm: Option<Real>,
    ) {
        let ContactSolver {
            bodies,
            constraints: rows,
            blocks,
            color_rows,
            manifold_rows,
            graph,
            shared,
            ..
        } = self;
        let layout = sweep::ColorLayout {
            graph,
            color_rows,
            manifold_rows,
        };
        sweep::share(bodies, shared);
        if let Some(dt_coef) = warm {
            let kernel = |m: &mut [ContactConstraint], copy: &mut [SolverBody; 2]| {
                sweep::warm_start_copy::<FRICTION>(m, dt_coef, copy);
            };
            sweep::for_each_color(rows, layout, shared, &kernel);
            if !joints.is_empty() {
                sweep::unshare(shared, bodies);
                joints.warm_start(bodies, dt_coef);
                sweep::share(bodies, shared);
            }
        }
        let blocks = blocks.as_slice();
        let kernel = |m: &mut [ContactConstraint], copy: &mut [SolverBody; 2]| {
            sweep::solve_copy::<FRICTION, BIAS>(m, blocks, copy);
        };
        for _ in 0..n {
            sweep::for_each_color(rows, layout, shared, &kernel);
            if !joints.is_empty() {
                sweep::unshare(shared, bodies);
                joints.iterate(bodies);
                sweep::share(bodies, shared);
            }
        }
        sweep::unshare(shared, bodies);
    }

    /// The results: accumulated impulses back into the arbiters' manifold
    /// points (for warm starting and handlers), velocities and bias
    /// velocities back into the awake dynamic bodies.
    pub(crate) fn store(&self, arbiters: &mut [Arbiter], bodies: &mut Arena<Body>) {
        for c in &self.constraints {
            if let Some(arb) = arbiters.get_mut(c.arbiter as usize) {
                arb.set_impulses(c.slot, c.jn_acc, c.jt_acc);
            }
        }
        self.store_velocities(bodies);
    }

    /// Velocities and bias velocities back into the awake dynamic bodies.
    pub(crate) fn store_velocities(&self, bodies: &mut Arena<Body>) {
        // Body by body (slot i from solver slot i), in pieces the threads
        // share.
        bodies.zip_values_mut_split(&self.bodies, 512, &store_velocity);
    }
}

/// The velocities and bias velocities of solver body `s` into `body`, if
/// it is dynamic and awake (the solver moves no other).
#[inline]
pub(crate) fn store_velocity(body: &mut Body, s: &SolverBody) {
    if body.body_type() != BodyType::Dynamic || body.is_sleeping() {
        return;
    }
    body.v = s.v;
    body.w = s.w;
    body.v_bias = s.v_bias;
    body.w_bias = s.w_bias;
}

/// Colors the `active` arbiters ([`graph::ConstraintGraph::color`]): a
/// body the solver moves (non-zero inverse mass or moment in
/// `solver_bodies`) appears in at most one arbiter of a color.
pub(crate) fn color_arbiters(
    graph: &mut graph::ConstraintGraph,
    arbiters: &[Arbiter],
    active: &[u32],
    solver_bodies: &[SolverBody],
) {
    graph.color(active, solver_bodies.len(), |i| {
        let movable = |slot: u32| {
            solver_bodies
                .get(slot as usize)
                .is_some_and(|b| !b.m_inv.is_zero() || !b.i_inv.is_zero())
        };
        arbiters.get(i as usize).map_or([(0, false); 2], |arb| {
            let (a, b) = (arb.body_a.index(), arb.body_b.index());
            [(a, movable(a)), (b, movable(b))]
        })
    });
}

/// What preparing a manifold reads.
struct PrepareJob<'a> {
    arbiters: &'a [Arbiter],
    bodies: &'a [SolverBody],
    params: &'a ContactParams,
    friction: bool,
}

/// A run of manifolds in solve order: their arbiters, and the first row
/// and first block slot of each (absolute, as in the scratch) and the end.
#[derive(Clone, Copy)]
struct ManifoldParts<'a> {
    order: &'a [u32],
    rows: &'a [u32],
    blocks: &'a [u32],
}

impl<'a> ManifoldParts<'a> {
    /// The manifolds `..mid` and `mid..`.
    fn split(self, mid: usize) -> (ManifoldParts<'a>, ManifoldParts<'a>) {
        let head = |v: &'a [u32]| v.get(..=mid).unwrap_or(&[]);
        let tail = |v: &'a [u32]| v.get(mid..).unwrap_or(&[]);
        (
            ManifoldParts {
                order: self.order.get(..mid).unwrap_or(&[]),
                rows: head(self.rows),
                blocks: head(self.blocks),
            },
            ManifoldParts {
                order: self.order.get(mid..).unwrap_or(&[]),
                rows: tail(self.rows),
                blocks: tail(self.blocks),
            },
        )
    }
}

/// Manifolds per piece of the split pre-step.
const PREPARE_PIECE: usize = 32;

/// The preparation of the manifolds of `parts`, whose rows are `rows` and whose
/// block slots are `blocks`: halves in parallel down to
/// [`PREPARE_PIECE`]s, each writing only its own rows and slots.
fn prepare_split(
    job: &PrepareJob<'_>,
    parts: ManifoldParts<'_>,
    rows: &mut [ContactConstraint],
    blocks: &mut [ManifoldBlock],
) {
    let n = parts.order.len();
    let row_base = parts.rows.first().copied().unwrap_or(0);
    let block_base = parts.blocks.first().copied().unwrap_or(0);
    if n <= PREPARE_PIECE {
        for (k, &i) in parts.order.iter().enumerate() {
            let at = |v: &[u32], k: usize| v.get(k).copied().unwrap_or(0);
            let (r0, r1) = (at(parts.rows, k), at(parts.rows, k.wrapping_add(1)));
            let (b0, b1) = (at(parts.blocks, k), at(parts.blocks, k.wrapping_add(1)));
            let range = r0.wrapping_sub(row_base) as usize..r1.wrapping_sub(row_base) as usize;
            let (Some(arb), Some(out)) = (job.arbiters.get(i as usize), rows.get_mut(range)) else {
                continue;
            };
            // A block slot (b1 = b0 + 1) and its index + 1 for the row.
            let slot = (b1 > b0)
                .then(|| blocks.get_mut(b0.wrapping_sub(block_base) as usize))
                .flatten()
                .map(|dst| (dst, b0.saturating_add(1)));
            prepare_manifold(job, i, arb, out, slot);
        }
        return;
    }
    let mid = n / 2;
    let (left, right) = parts.split(mid);
    let row_cut = left
        .rows
        .last()
        .copied()
        .unwrap_or(row_base)
        .wrapping_sub(row_base);
    let block_cut = left
        .blocks
        .last()
        .copied()
        .unwrap_or(block_base)
        .wrapping_sub(block_base);
    let (Some((rows_l, rows_r)), Some((blocks_l, blocks_r))) = (
        rows.split_at_mut_checked(row_cut as usize),
        blocks.split_at_mut_checked(block_cut as usize),
    ) else {
        return;
    };
    crate::threads::join(
        || prepare_split(job, left, rows_l, blocks_l),
        || prepare_split(job, right, rows_r, blocks_r),
    );
}

/// The preparation of arbiter `i` (`arb`): its rows into `out`, and with a block
/// `slot` (a two-contact manifold, block solver on) its block, if its
/// normal matrix is well conditioned ([`finish_block`]).
fn prepare_manifold(
    job: &PrepareJob<'_>,
    i: u32,
    arb: &Arbiter,
    out: &mut [ContactConstraint],
    slot: Option<(&mut ManifoldBlock, u32)>,
) {
    let pair = pair_params(arb);
    let block = slot.is_some();
    let mut k_t = [Real::ZERO; 2];
    let rows = arb.contacts().iter().enumerate().zip(out.iter_mut());
    for (((n, c), row), k) in rows.zip(&mut k_t) {
        (*row, *k) = prepare_row(job, &pair, i, n, c, block);
    }
    let (Some((dst, id)), [c1, c2]) = (slot, out) else {
        return;
    };
    if let Some(b) = finish_block(job, c1, c2, k_t) {
        *dst = b;
        c1.block = id;
    }
}

/// What the rows of arbiter `arb` share.
#[inline]
fn pair_params(arb: &Arbiter) -> PairParams {
    PairParams {
        a: arb.body_a.index(),
        b: arb.body_b.index(),
        n: arb.normal,
        e: arb.restitution,
        friction: arb.friction,
        surface_vr: arb.surface_velocity,
    }
}

/// The preparation of contact `n` (`c`) of arbiter `i`: its row, and `k(t)`. A
/// row of a `block` does not get its tangent effective mass (a division):
/// the block's face friction has its own ([`finish_block`]).
#[inline(always)]
fn prepare_row(
    job: &PrepareJob<'_>,
    pair: &PairParams,
    i: u32,
    n: usize,
    c: &ManifoldPoint,
    block: bool,
) -> (ContactConstraint, Real) {
    let (mut row, k) = ContactConstraint::prepare(c, job.bodies, pair, job.params);
    if !block {
        row.t_mass = effective_mass(k);
    }
    row.arbiter = i;
    // n < MAX_CONTACTS_PER_ARBITER.
    row.slot = n as u32;
    (row, k)
}

/// The block of a two-contact manifold's rows `c1`, `c2` if its normal
/// matrix is well conditioned ([`ManifoldBlock::new`]); otherwise the rows
/// are solved on their own and get their tangent effective masses from
/// `k_t`. The caller stores the block and points `c1` at it.
#[inline]
fn finish_block(
    job: &PrepareJob<'_>,
    c1: &mut ContactConstraint,
    c2: &mut ContactConstraint,
    k_t: [Real; 2],
) -> Option<ManifoldBlock> {
    let b = ManifoldBlock::new(c1, c2, job.bodies, job.friction);
    if b.is_none() {
        c1.t_mass = effective_mass(k_t[0]);
        c2.t_mass = effective_mass(k_t[1]);
    }
    b
}
