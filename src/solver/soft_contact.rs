//! The soft step's contact rows: one row per manifold point, prepared once
//! per step from the contacts found at the collide, and solved in every
//! sub-step against the bodies' motion since then.
//!
//! A row is built from the anchors `r1`, `r2` (the contact's points on the
//! two surfaces, relative to the centres of gravity at the collide) and
//! keeps the separation `dist` measured there. In a sub-step the
//! separation is re-estimated without colliding again:
//! `s = dist + n·((Δp_b − Δp_a) + (Δq_b·r2 − r2) − (Δq_a·r1 − r1))`, where
//! `Δp` and `Δq` are a body's translation and rotation since the collide
//! ([`Motion`]), computed as `n·Δp + (cos − 1)(n·r) + sin (r × n)` from the
//! products stored at prepare; both terms are exactly zero for a body that
//! has not moved, so a resting contact sees exactly its collide
//! separation. The normal and the Jacobian's anchors stay those of the
//! collide.
//!
//! The normal impulse is soft (module `softness`): below `−slop` the bias
//! is `max(bias_rate·(s + slop), −push_out_speed)`; above 0 (the shapes
//! moved apart) the row lets the gap close exactly (`bias = s/h`, rigid);
//! the relax pass solves rigid rows without bias, which removes the
//! velocity the push-out added. Friction is a rigid row bounded by
//! `friction·jn`. Restitution runs once after the sub-steps.
//!
//! Accumulated impulses are per sub-step (Box2D's convention): each
//! sub-step's warm start re-applies them, and the step stores them for
//! the next step's.
use crate::arbiter::Arbiter;
use crate::arena::Arena;
use crate::body::Body;
use crate::math::{Real, Saturating};

use super::contact_solver::{color_arbiters, ContactSolver};
use super::graph;
use super::kernel::{load_pair, store_pair};
use super::sweep;
use super::SolverBody;

mod grid;
mod narrow;
mod pass;
mod row;
mod wide;

pub(crate) use pass::Compiled;
use pass::Pass;
use row::{
    on_bodies, prepare_split, scale_impulses, solve_manifold, warm_start_manifold, PrepareJob,
};
pub(crate) use row::{Motion, SoftContact, SoftContactParams};
/// The soft rows of a step and the bodies' motion.
#[derive(Clone, Debug, Default)]
pub(crate) struct SoftContacts {
    rows: Vec<SoftContact>,
    motion: Vec<Motion>,
    /// Each manifold's first row, in solve order, and the end.
    manifold_rows: Vec<u32>,
    /// Each arbiter's first row (by arbiter index; `u32::MAX`: none), for
    /// the store, which then walks the arbiters in order.
    arbiter_rows: Vec<u32>,
    /// Each color's first row (the overflow's at `graph::COLORS`), and the
    /// end.
    color_rows: [u32; graph::COLORS + 2],
    /// The bodies while threads share them.
    shared: Vec<sweep::SharedBody>,
    /// Whether any row has restitution (else the restitution pass has
    /// nothing to do, and skips reading every row).
    bouncy: bool,
    /// The wide kernels' batches, when this step's passes run them (they
    /// then hold the running impulses of the rows they batch, until
    /// [`end_passes`](Self::end_passes)).
    wide: wide::WideContacts,
}

impl SoftContacts {
    /// The soft step's [`Stage::Prepare`](crate::space::Stage::Prepare) of
    /// the contacts: the bodies' poses at the collide, then one row per
    /// manifold point of the `active` arbiters, color by color (module
    /// `graph`): the order the threads can share, and on the soft step no
    /// worse than the canonical one (`docs/solver.md`). Returns the number
    /// of rows.
    pub(crate) fn prepare(
        &mut self,
        solver: &mut ContactSolver,
        arbiters: &[Arbiter],
        bodies: &Arena<Body>,
        active: &[u32],
        params: &SoftContactParams,
    ) -> u32 {
        let ContactSolver {
            bodies: solver_bodies,
            graph,
            ..
        } = solver;
        let soft = self;
        soft.wide.clear();
        soft.motion.clear();
        soft.motion.resize(solver_bodies.len(), Motion::default());
        bodies.zip_values_split(&mut soft.motion, BODY_PIECE, &|body: &Body, m| {
            *m = Motion {
                p0: body.p,
                rot0: body.rot,
                ..Motion::default()
            };
        });
        color_arbiters(graph, arbiters, active, solver_bodies);
        // Where each manifold's rows go, in one pass: then the manifolds
        // are prepared in pieces, halves in parallel where there are
        // threads (inline on one), each writing only its own rows.
        // First each manifold's row count (at most
        // MAX_CONTACTS_PER_ARBITER, 2), with `BOUNCY` if it has
        // restitution, read from the arbiters in pieces the threads share
        // (the arbiters in solve order are cache misses); then in place
        // the running sums.
        const BOUNCY: u32 = 1 << 8;
        let order = graph.order();
        soft.manifold_rows.clear();
        soft.manifold_rows.resize(order.len(), 0);
        crate::threads::zip_split(order, &mut soft.manifold_rows, ROW_PIECE, &|&i, size| {
            *size = arbiters.get(i as usize).map_or(0, |arb| {
                let bouncy = if arb.restitution.is_zero() { 0 } else { BOUNCY };
                arb.contacts().len() as u32 | bouncy
            });
        });
        soft.arbiter_rows.clear();
        soft.arbiter_rows.resize(arbiters.len(), u32::MAX);
        let mut count = 0u32;
        soft.bouncy = false;
        for (first_row, &i) in soft.manifold_rows.iter_mut().zip(order) {
            let size = *first_row;
            *first_row = count;
            if let Some(first) = soft.arbiter_rows.get_mut(i as usize) {
                *first = count;
            }
            count = count.saturating_add(size & (BOUNCY - 1));
            soft.bouncy |= size & BOUNCY != 0;
        }
        soft.manifold_rows.push(count);
        soft.rows.truncate(count as usize);
        soft.rows.resize(count as usize, SoftContact::default());
        let job = PrepareJob {
            arbiters,
            bodies: solver_bodies,
            params,
        };
        prepare_split(&job, graph.order(), &soft.manifold_rows, &mut soft.rows);
        let rows = count;
        for (c, first_row) in soft.color_rows.iter_mut().enumerate() {
            let first_manifold = graph.range(c).start;
            *first_row = soft
                .manifold_rows
                .get(first_manifold)
                .copied()
                .unwrap_or(rows);
        }
        rows
    }

    /// Runs this step's in-place passes ([`warm_start`](Self::warm_start),
    /// [`solve`](Self::solve)) on the wide kernels compiled as `compiled`
    /// (module `wide`; `None`: the scalar ones). After the prepare; the
    /// same bits either way.
    ///
    /// With `narrow` (the narrow contact kernels, module `narrow`) the
    /// passes always run in lanes, whatever `compiled` says: the portable
    /// lanes are then the reference kernel, and the AVX2 ones give their
    /// bits.
    pub(crate) fn use_wide(
        &mut self,
        compiled: Option<Compiled>,
        narrow: bool,
        graph: &graph::ConstraintGraph,
        bodies: &[SolverBody],
    ) {
        // The narrow-grid study rounds in the scalar kernels only.
        let compiled = if narrow {
            Some(compiled.unwrap_or(Compiled::Portable))
        } else {
            compiled.filter(|_| !grid::ON)
        };
        match compiled {
            Some(c) => self
                .wide
                .build(c, narrow, &self.rows, &self.manifold_rows, graph, bodies),
            None => self.wide.clear(),
        }
    }

    /// The end of the sub-steps' passes: the wide kernels' running
    /// impulses back into the rows, which the restitution pass and the
    /// store read.
    pub(crate) fn end_passes(&mut self) {
        if self.wide.is_on() {
            self.wide.write_back(&mut self.rows, &self.color_rows);
            self.wide.clear();
        }
    }

    /// The soft step's [`Stage::WarmStart`](crate::space::Stage::WarmStart)
    /// of the contacts, in every sub-step: the accumulated impulses applied
    /// again, first scaled by `dt_coef` (the first sub-step's
    /// `min(h / previous h, 1)`; 1 after it). Without warm starting the
    /// accumulators start from 0.
    pub(crate) fn warm_start(&mut self, bodies: &mut [SolverBody], warm: Option<Real>) {
        if self.wide.is_on() {
            match warm {
                Some(dt_coef) => {
                    self.wide
                        .run(Pass::WarmStart(dt_coef), &mut self.rows, bodies, &[]);
                }
                None => self.wide.zero_impulses(&mut self.rows),
            }
            return;
        }
        let Some(dt_coef) = warm else {
            for row in &mut self.rows {
                row.jn = Real::ZERO;
                row.jt = Real::ZERO;
            }
            return;
        };
        let mut rest = self.rows.as_mut_slice();
        while let Some(first) = rest.first() {
            let arbiter = first.arbiter;
            let n = if rest.get(1).is_some_and(|r| r.arbiter == arbiter) {
                2
            } else {
                1
            };
            let (manifold, tail) = rest.split_at_mut(n);
            scale_impulses(manifold, dt_coef);
            on_bodies(manifold, bodies, |m, copy| warm_start_manifold(m, copy));
            rest = tail;
        }
    }

    /// The number of manifolds of this step.
    pub(crate) fn manifolds(&self) -> usize {
        self.manifold_rows.len().saturating_sub(1)
    }

    /// [`warm_start`](Self::warm_start) and [`solve`](Self::solve) passes,
    /// in order, on threads: each color's manifolds (or, with the wide
    /// kernels, its batches) split between them on shared bodies
    /// ([`sweep`]), the same bits. The bodies are shared once
    /// for all the `passes` (each sharing moves every body between the
    /// cores' caches).
    pub(crate) fn solve_split(
        &mut self,
        bodies: &mut [SolverBody],
        graph: &graph::ConstraintGraph,
        params: &SoftContactParams,
        passes: &[SoftPass],
    ) {
        self.share_bodies(bodies);
        self.solve_shared(graph, params, passes);
        self.unshare_bodies(bodies);
    }

    /// The bodies into the copy threads share ([`shared_bodies`](Self::shared_bodies)).
    pub(crate) fn share_bodies(&mut self, bodies: &[SolverBody]) {
        sweep::share(bodies, &mut self.shared);
    }

    /// The shared copy back into `bodies`.
    pub(crate) fn unshare_bodies(&self, bodies: &mut [SolverBody]) {
        sweep::unshare(&self.shared, bodies);
    }

    /// The bodies while threads share them (by slot).
    pub(crate) fn shared_bodies(&self) -> &[sweep::SharedBody] {
        &self.shared
    }

    /// The shared bodies, and the motion to track from the bodies' poses.
    pub(crate) fn shared_bodies_and_motion(&mut self) -> (&[sweep::SharedBody], &mut [Motion]) {
        (&self.shared, &mut self.motion)
    }

    /// [`solve_split`](Self::solve_split) on the bodies already shared
    /// ([`share_bodies`](Self::share_bodies)), left there.
    pub(crate) fn solve_shared(
        &mut self,
        graph: &graph::ConstraintGraph,
        params: &SoftContactParams,
        passes: &[SoftPass],
    ) {
        let SoftContacts {
            rows,
            motion,
            manifold_rows,
            color_rows,
            shared,
            wide,
            ..
        } = self;
        let layout = sweep::ColorLayout {
            graph,
            color_rows,
            manifold_rows,
        };
        let motion = motion.as_slice();
        if wide.is_on() {
            // The lane passes between warm starts without warm starting
            // (which zero the impulses) in one set of stages.
            let mut lane_passes = Vec::with_capacity(passes.len());
            for &pass in passes {
                match pass {
                    SoftPass::WarmStart(None) => {
                        if !lane_passes.is_empty() {
                            wide.run_shared(&lane_passes, rows, shared, motion);
                            lane_passes.clear();
                        }
                        wide.zero_impulses(rows);
                    }
                    SoftPass::WarmStart(Some(dt_coef)) => {
                        lane_passes.push(Pass::WarmStart(dt_coef));
                    }
                    SoftPass::Solve { use_bias } => {
                        lane_passes.push(Pass::Solve(*params, use_bias));
                    }
                }
            }
            if !lane_passes.is_empty() {
                wide.run_shared(&lane_passes, rows, shared, motion);
            }
            return;
        }
        for &pass in passes {
            let kernel = |m: &mut [SoftContact], copy: &mut [SolverBody; 2]| match pass {
                SoftPass::WarmStart(Some(dt_coef)) => {
                    scale_impulses(m, dt_coef);
                    warm_start_manifold(m, copy);
                }
                SoftPass::WarmStart(None) => {}
                SoftPass::Solve { use_bias } => solve_manifold(m, copy, motion, params, use_bias),
            };
            match pass {
                SoftPass::WarmStart(None) => {
                    for row in rows.iter_mut() {
                        row.jn = Real::ZERO;
                        row.jt = Real::ZERO;
                    }
                }
                _ => sweep::for_each_color(rows, layout, shared, &kernel),
            }
        }
    }

    /// One pass over the rows in solve order: with `use_bias` the sub-step's
    /// soft solve ([`Stage::Solve`](crate::space::Stage::Solve)), without
    /// it the relax pass ([`Stage::Relax`](crate::space::Stage::Relax)).
    /// A manifold's points are solved together: both normal rows, then
    /// both friction rows (friction bounded by the normal impulses of this
    /// pass), on one copy of the two bodies.
    pub(crate) fn solve(
        &mut self,
        bodies: &mut [SolverBody],
        params: &SoftContactParams,
        use_bias: bool,
    ) {
        if self.wide.is_on() {
            let pass = Pass::Solve(*params, use_bias);
            self.wide.run(pass, &mut self.rows, bodies, &self.motion);
            return;
        }
        let motion = &self.motion;
        let mut rest = self.rows.as_mut_slice();
        while let Some(first) = rest.first() {
            let arbiter = first.arbiter;
            let n = if rest.get(1).is_some_and(|r| r.arbiter == arbiter) {
                2
            } else {
                1
            };
            let (manifold, tail) = rest.split_at_mut(n);
            on_bodies(manifold, bodies, |m, copy| {
                solve_manifold(m, copy, motion, params, use_bias);
            });
            rest = tail;
        }
    }

    /// [`Stage::Restitution`](crate::space::Stage::Restitution), once after
    /// the sub-steps: points that approached faster than the threshold and
    /// pushed get the bounce `−e·approach` as their normal velocity.
    pub(crate) fn restitution(&mut self, bodies: &mut [SolverBody], params: &SoftContactParams) {
        self.end_passes();
        if !params.restitution || !self.bouncy {
            return;
        }
        for row in &mut self.rows {
            if row.restitution.is_zero()
                || row.approach > -params.restitution_threshold
                || !row.max_jn.is_positive()
            {
                continue;
            }
            let mut r = *row;
            let ok = r.run(bodies, |r, a, b, ar| r.bounce(a, b, ar));
            *row = if ok {
                r
            } else {
                let mut r = *row;
                if let Some((mut a, mut b)) = load_pair(bodies, r.a, r.b) {
                    r.bounce(&mut a, &mut b, &mut Saturating);
                    store_pair(bodies, r.a, a, r.b, b);
                }
                r
            };
        }
    }

    /// The bodies' motion since the collide, after a sub-step's positions
    /// were integrated: `Δp = p − p₀`, `Δq = q·q₀⁻¹` (exact while a body
    /// has not moved).
    pub(crate) fn track_motion(&mut self, bodies: &Arena<Body>) {
        bodies.zip_values_split(
            &mut self.motion,
            BODY_PIECE,
            &|body: &Body, m: &mut Motion| m.track(body),
        );
    }

    /// The soft rows' accumulated impulses into the arbiters' manifold
    /// points (the next step's warm start, and the handlers'). On one
    /// thread, row by row; with threads (`split`), arbiter by arbiter from
    /// each one's own rows, in pieces the threads share (the rows are in
    /// solve order: split by rows, the pieces would write the arbiters at
    /// random), settling each arbiter on the way with `settle`'s stamp
    /// ([`Arbiter::settle`]). The same values either way. Returns whether
    /// it settled every arbiter (the split walk with a stamp, over the
    /// arbiters the prepare saw).
    pub(crate) fn store_impulses(&self, arbiters: &mut [Arbiter], how: StoreImpulses) -> bool {
        if !how.split || self.arbiter_rows.len() != arbiters.len() {
            for r in &self.rows {
                if let Some(arb) = arbiters.get_mut(r.arbiter as usize) {
                    arb.set_impulses(r.slot, r.jn, r.jt);
                }
            }
            return false;
        }
        let rows = self.rows.as_slice();
        crate::threads::zip_split(&self.arbiter_rows, arbiters, STORE_PIECE, &|&first, arb| {
            if let Some(stamp) = how.settle {
                arb.settle(stamp);
            }
            if first == u32::MAX {
                return; // Not solved this step (a cached arbiter).
            }
            let first = first as usize;
            let n = arb.count();
            for r in rows.get(first..first.saturating_add(n)).unwrap_or(&[]) {
                arb.set_impulses(r.slot, r.jn, r.jt);
            }
        });
        how.settle.is_some()
    }
}

/// How [`SoftContacts::store_impulses`] walks: split between threads, and
/// with the step's stamp to settle every arbiter on the way.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StoreImpulses {
    pub(crate) split: bool,
    pub(crate) settle: Option<u64>,
}

/// Manifolds per piece of the split row count (a few µs).
const ROW_PIECE: usize = 1024;

/// Arbiters per piece of the split store (a few µs).
const STORE_PIECE: usize = 256;

/// Body slots per piece of the split motion tracking (a few µs).
const BODY_PIECE: usize = 512;

/// A pass of the soft contacts: the warm start (`None`: warm starting off,
/// the accumulators start from 0; `Some(dt_coef)`: scaled by it), or a
/// solve (with bias) or relax (without) pass.
#[derive(Clone, Copy, Debug)]
pub(crate) enum SoftPass {
    WarmStart(Option<Real>),
    Solve { use_bias: bool },
}
