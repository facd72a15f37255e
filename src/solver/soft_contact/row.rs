//! A soft contact row (one manifold point) and the scalar kernels of a
//! manifold's passes: the row's constants from the collide, the warm
//! start, the solve and relax passes and the restitution row, each fast
//! path first (`Ranged`) and the saturating reference if it left its
//! window. The module `soft_contact` documents the model.
use crate::arbiter::Arbiter;
use crate::math::{
    below_2_62, range_record, FixedArith, Ranged, Real, Rot, Saturating, Unsaturated, Vect,
    RANGED_INPUT,
};

use crate::solver::kernel::{effective_mass, load_pair, point_velocity, store_pair, sub};
use crate::solver::softness::Softness;
use crate::solver::sweep::ManifoldRow;
use crate::solver::SolverBody;

use super::grid;
/// A body's motion since the collide (by body slot): its pose then, and
/// how far it has moved and turned since.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Motion {
    /// Centre of gravity at the collide.
    pub(super) p0: Vect,
    /// Rotation at the collide.
    pub(super) rot0: Rot,
    /// Translation since the collide.
    pub(super) dp: Vect,
    /// The rotation since the collide, `(cos − 1, sin)` of its angle: both
    /// exactly 0 while the body has not turned.
    pub(super) dq_c1: Real,
    pub(super) dq_s: Real,
}

impl Motion {
    /// The motion of `body` (at this slot) since the collide, after a
    /// sub-step's positions were integrated: `Δp = p − p₀`,
    /// `Δq = q·q₀⁻¹` (exact while the body has not moved); a sleeping
    /// body's is left as it is.
    #[inline]
    pub(crate) fn track(&mut self, body: &crate::body::Body) {
        if body.is_sleeping() {
            return;
        }
        self.dp = body.p - self.p0;
        (self.dq_c1, self.dq_s) = if body.rot == self.rot0 {
            (Real::ZERO, Real::ZERO)
        } else {
            let dq = body.rot.compose(self.rot0.inv()).as_vect();
            (dq.x - Real::ONE, dq.y)
        };
    }
}

/// The soft step's contact constants of one step (from the settings and
/// the sub-step length).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SoftContactParams {
    /// Contacts between two bodies that move.
    pub(crate) contact: Softness,
    /// Contacts with a static or kinematic body (twice the frequency).
    pub(crate) fixed: Softness,
    /// `1/h` of the sub-step.
    pub(crate) h_inv: Real,
    /// Overlap left uncorrected.
    pub(crate) slop: Real,
    /// Largest push-out speed.
    pub(crate) push_out: Real,
    /// Approach speed above which restitution applies.
    pub(crate) restitution_threshold: Real,
    /// Friction rows (the `friction` setting).
    pub(crate) friction: bool,
    /// The restitution pass (the `restitution` setting).
    pub(crate) restitution: bool,
    /// The narrow contact kernels (`ContactPrecision::Narrow`).
    pub(crate) narrow: bool,
}

/// One manifold point's row.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct SoftContact {
    /// Solver slots of the bodies.
    pub(super) a: u32,
    pub(super) b: u32,
    /// Arbiter index and contact slot (for the write-back).
    pub(super) arbiter: u32,
    pub(super) slot: u32,
    /// Unit normal from a to b.
    pub(super) n: Vect,
    /// Separation at the collide.
    pub(super) dist: Real,
    /// The separation the last relax pass estimated (`dist` before the
    /// first): the motion does not change between a relax pass and the
    /// next sub-step's solve, so the solve reuses it (the same bits: both
    /// are the saturating evaluation of the same formula on the same
    /// values, the fast path's agreeing with it whenever it is kept).
    pub(super) sep: Real,
    /// `n·r1`, `n·r2`: with `r × n`, what a rotation of the anchors does
    /// to the separation.
    pub(super) nr_a: Real,
    pub(super) nr_b: Real,
    /// `r × n`, `r × t` of both anchors, and `I⁻¹ (r × n)`, `I⁻¹ (r × t)`.
    pub(super) rn_a: Real,
    pub(super) rn_b: Real,
    pub(super) rt_a: Real,
    pub(super) rt_b: Real,
    pub(super) kn_a: Real,
    pub(super) kn_b: Real,
    pub(super) kt_a: Real,
    pub(super) kt_b: Real,
    pub(super) m_inv_a: Real,
    pub(super) m_inv_b: Real,
    /// `1/k(n)`, `1/k(t)`.
    pub(super) n_mass: Real,
    pub(super) t_mass: Real,
    pub(super) friction: Real,
    pub(super) restitution: Real,
    /// Tangential surface velocity.
    pub(super) surface_t: Real,
    /// Normal relative velocity at the start of the step (restitution).
    pub(super) approach: Real,
    /// The row's softness (contact or fixed).
    pub(super) soft: Softness,
    /// Accumulated normal and friction impulses (per sub-step).
    pub(super) jn: Real,
    pub(super) jt: Real,
    /// Largest normal impulse applied this step (restitution applies only
    /// to points that pushed).
    pub(super) max_jn: Real,
    /// The range record of the constants the passes add (`dist`,
    /// `surface_t`) when the constants that multiply in the passes' dot
    /// products (`n`, `n·r`, `r × n`, `r × t`) are below `2^62` raw, so
    /// that the passes may run in [`Ranged`] arithmetic; `u64::MAX`
    /// otherwise (positions near the edge of the range), which sends them
    /// to saturating arithmetic.
    pub(super) constant_record: u64,
}

/// One pass over a manifold's rows (one or two points of one body pair)
/// on a copy of its bodies: fast path first; if it overflowed, the rows'
/// impulses and the bodies are put back and the saturating reference
/// runs.
#[inline(always)]
pub(super) fn solve_manifold(
    rows: &mut [SoftContact],
    copy: &mut [SolverBody; 2],
    motion: &[Motion],
    p: &SoftContactParams,
    use_bias: bool,
) {
    if manifold_record(rows, copy, motion, p, use_bias) < RANGED_INPUT {
        let saved = impulses(rows);
        let mut fast = Ranged::new();
        let [mut a, mut b] = *copy;
        manifold_pass(rows, &mut a, &mut b, motion, p, use_bias, &mut fast);
        if !fast.overflowed() {
            *copy = [a, b];
            return;
        }
        restore_impulses(rows, saved);
    }
    let [a, b] = copy;
    manifold_pass(rows, a, b, motion, p, use_bias, &mut Saturating);
}

/// The range record of what a solve pass of a manifold reads and adds
/// ([`Ranged`]'s input check; `u64::MAX` if a row's constants are not
/// bounded). Below [`RANGED_INPUT`] (`2^58`) with every rounded product
/// at most `2^60`, no addition of the pass wraps: a body is changed at
/// most 4 times (2 normal and 2 friction rows), so its velocities stay
/// below `2^58 + 4·2^60 < 2^63` and their differences below
/// `2·(2^58 + 3·2^60) < 2^63`; the separation is below `2^58 + 2·2^60`
/// (plus the slop, below `2^58`); an impulse minus a product, and the new
/// impulse minus the old, below `2^58 + 2^61 + 2^58`.
#[inline(always)]
pub(super) fn manifold_record(
    rows: &[SoftContact],
    copy: &[SolverBody; 2],
    motion: &[Motion],
    p: &SoftContactParams,
    use_bias: bool,
) -> u64 {
    let [a, b] = copy;
    let mut rec = range_record(&[a.v.x, a.v.y, a.w, b.v.x, b.v.y, b.w, p.slop]);
    if use_bias {
        for r in rows {
            rec |= range_record(&[r.sep]);
        }
    } else if let Some(first) = rows.first() {
        let none = Motion::default();
        let ma = motion.get(first.a as usize).unwrap_or(&none);
        let mb = motion.get(first.b as usize).unwrap_or(&none);
        rec |= range_record(&[
            ma.dp.x, ma.dp.y, ma.dq_c1, ma.dq_s, mb.dp.x, mb.dp.y, mb.dq_c1, mb.dq_s,
        ]);
    }
    for r in rows {
        rec |= r.constant_record | range_record(&[r.jn, r.jt]);
    }
    rec
}

/// What preparing a manifold reads.
pub(super) struct PrepareJob<'a> {
    pub(super) arbiters: &'a [Arbiter],
    pub(super) bodies: &'a [SolverBody],
    pub(super) params: &'a SoftContactParams,
}

/// Manifolds per piece of the split preparation.
const PREPARE_PIECE: usize = 32;

/// The rows of the manifolds `order` (arbiter indices), whose first rows
/// are `starts` (absolute; `rows` begins at `starts[0]`): halves in
/// parallel down to [`PREPARE_PIECE`]s.
pub(super) fn prepare_split(
    job: &PrepareJob<'_>,
    order: &[u32],
    starts: &[u32],
    rows: &mut [SoftContact],
) {
    let base = starts.first().copied().unwrap_or(0);
    if order.len() <= PREPARE_PIECE {
        for (k, &i) in order.iter().enumerate() {
            let at = |k: usize| starts.get(k).map_or(0, |&s| s.wrapping_sub(base) as usize);
            let (Some(arb), Some(out)) = (
                job.arbiters.get(i as usize),
                rows.get_mut(at(k)..at(k.wrapping_add(1)).max(at(k))),
            ) else {
                continue;
            };
            prepare_manifold(job, i, arb, out);
        }
        return;
    }
    let mid = order.len() / 2;
    let cut = starts.get(mid).copied().unwrap_or(base).wrapping_sub(base);
    let (Some((left, right)), Some((order_l, order_r))) = (
        rows.split_at_mut_checked(cut as usize),
        order.split_at_checked(mid),
    ) else {
        return;
    };
    let (starts_l, starts_r) = (
        starts.get(..=mid).unwrap_or(&[]),
        starts.get(mid..).unwrap_or(&[]),
    );
    crate::threads::join(
        || prepare_split(job, order_l, starts_l, left),
        || prepare_split(job, order_r, starts_r, right),
    );
}

/// The rows of arbiter `i` (`arb`) into `out`, one per manifold point.
pub(super) fn prepare_manifold(
    job: &PrepareJob<'_>,
    i: u32,
    arb: &Arbiter,
    out: &mut [SoftContact],
) {
    let params = job.params;
    let zero = SolverBody::default();
    let (ia, ib) = (arb.body_a.index(), arb.body_b.index());
    let a = job.bodies.get(ia as usize).unwrap_or(&zero);
    let b = job.bodies.get(ib as usize).unwrap_or(&zero);
    let fixed = a.m_inv.is_zero() && a.i_inv.is_zero() || b.m_inv.is_zero() && b.i_inv.is_zero();
    let n = arb.normal;
    let t = n.perp();
    // Only the restitution pass reads a row's approach speed, and it skips
    // rows without restitution.
    let bouncy = params.restitution && !arb.restitution.is_zero();
    for ((slot, c), row) in arb.contacts().iter().enumerate().zip(out) {
        let (r1, r2) = (c.r1, c.r2);
        let k = RowConstants::of(a, b, n, t, [r1, r2], arb.surface_velocity, bouncy);
        let RowConstants {
            rn_a,
            rn_b,
            rt_a,
            rt_b,
            nr_a,
            nr_b,
            kn_a,
            kn_b,
            kt_a,
            kt_b,
            k_n,
            k_t,
            approach,
            surface_t,
        } = k;
        *row = SoftContact {
            a: ia,
            b: ib,
            arbiter: i,
            // slot < MAX_CONTACTS_PER_ARBITER.
            slot: slot as u32,
            n,
            dist: c.dist,
            sep: c.dist,
            nr_a,
            nr_b,
            rn_a,
            rn_b,
            rt_a,
            rt_b,
            kn_a,
            kn_b,
            kt_a,
            kt_b,
            m_inv_a: a.m_inv,
            m_inv_b: b.m_inv,
            n_mass: effective_mass(k_n),
            t_mass: if params.friction {
                effective_mass(k_t)
            } else {
                Real::ZERO
            },
            friction: if params.friction {
                arb.friction
            } else {
                Real::ZERO
            },
            restitution: arb.restitution,
            surface_t,
            approach,
            soft: if fixed { params.fixed } else { params.contact },
            jn: c.jn_acc,
            jt: if params.friction {
                c.jt_acc
            } else {
                Real::ZERO
            },
            max_jn: Real::ZERO,
            constant_record: if below_2_62(&[n.x, n.y, nr_a, nr_b, rn_a, rn_b, rt_a, rt_b]) {
                range_record(&[c.dist, surface_t])
            } else {
                u64::MAX
            },
        };
        if grid::ON {
            row.narrow_to_grid();
        }
    }
}

/// A row's constants from its anchors, computed once per step: the lever
/// arms across the normal and the tangent, `I⁻¹` times them, the
/// effective masses' denominators, and the approach and surface speeds.
#[derive(Clone, Copy, Debug)]
struct RowConstants {
    rn_a: Real,
    rn_b: Real,
    rt_a: Real,
    rt_b: Real,
    nr_a: Real,
    nr_b: Real,
    kn_a: Real,
    kn_b: Real,
    kt_a: Real,
    kt_b: Real,
    k_n: Real,
    k_t: Real,
    approach: Real,
    surface_t: Real,
}

impl RowConstants {
    /// In [`Unsaturated`] arithmetic first (no saturation test per
    /// operation), in saturating arithmetic if that overflowed: the bits of
    /// the saturating formulas either way.
    ///
    /// The approach speed only with `approach` (else 0), and the surface
    /// speed only for a surface velocity (else the formula's exact 0): a
    /// sixth of the products.
    #[inline(always)]
    fn of(
        a: &SolverBody,
        b: &SolverBody,
        n: Vect,
        t: Vect,
        r: [Vect; 2],
        surface: Vect,
        approach: bool,
    ) -> RowConstants {
        let mut fast = Unsaturated::new();
        let k = Self::with(a, b, n, t, r, surface, approach, &mut fast);
        if !fast.overflowed() {
            return k;
        }
        Self::saturating(a, b, n, t, r, surface, approach)
    }

    /// The saturating reference, kept out of line: inlined, the compiler
    /// shared its products with the fast path's and kept them all alive
    /// (in memory) across it.
    #[cold]
    #[inline(never)]
    fn saturating(
        a: &SolverBody,
        b: &SolverBody,
        n: Vect,
        t: Vect,
        r: [Vect; 2],
        surface: Vect,
        approach: bool,
    ) -> RowConstants {
        Self::with(a, b, n, t, r, surface, approach, &mut Saturating)
    }

    /// The formulas, operation for operation those of the saturating
    /// operators they replaced: `r × d` and `d·r` rounded once, `k(d) =
    /// m_a⁻¹ + m_b⁻¹ + (I_a⁻¹ (r1 × d))(r1 × d) + (I_b⁻¹ (r2 × d))(r2 × d)`
    /// added left to right, `v_r = (v_b + perp(r2) ω_b) − (v_a + perp(r1)
    /// ω_a)`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn with<A: FixedArith>(
        a: &SolverBody,
        b: &SolverBody,
        n: Vect,
        t: Vect,
        [r1, r2]: [Vect; 2],
        surface: Vect,
        approach: bool,
        ar: &mut A,
    ) -> RowConstants {
        let cross = |r: Vect, d: Vect, ar: &mut A| ar.mul_sub2(r.x, d.y, r.y, d.x);
        let (rn_a, rn_b) = (cross(r1, n, ar), cross(r2, n, ar));
        let (rt_a, rt_b) = (cross(r1, t, ar), cross(r2, t, ar));
        // `n·r` is `r × t` for `t = perp(n) = (−n_y, n_x)`: `r_x n_x − r_y
        // (−n_y)`, the same integer rounded once, in both arithmetics (the
        // fast one even wraps alike), unless negating `n_y` saturated.
        let perp = t.y == n.x && t.x.to_bits().checked_neg() == Some(n.y.to_bits());
        let (nr_a, nr_b) = if perp {
            (rt_a, rt_b)
        } else {
            (
                ar.mul_add2(n.x, r1.x, n.y, r1.y),
                ar.mul_add2(n.x, r2.x, n.y, r2.y),
            )
        };
        let (kn_a, kn_b) = (ar.mul(a.i_inv, rn_a), ar.mul(b.i_inv, rn_b));
        let (kt_a, kt_b) = (ar.mul(a.i_inv, rt_a), ar.mul(b.i_inv, rt_b));
        let m_ab = ar.add(a.m_inv, b.m_inv);
        let k = |ka: Real, ra: Real, kb: Real, rb: Real, ar: &mut A| {
            let (qa, qb) = (ar.mul(ka, ra), ar.mul(kb, rb));
            let s = ar.add(m_ab, qa);
            ar.add(s, qb)
        };
        let k_n = k(kn_a, rn_a, kn_b, rn_b, ar);
        let k_t = k(kt_a, rt_a, kt_b, rt_b, ar);
        let approach = if approach {
            let vr = sub(point_velocity(b, r2, ar), point_velocity(a, r1, ar), ar);
            ar.mul_add2(vr.x, n.x, vr.y, n.y)
        } else {
            Real::ZERO
        };
        let surface_t = if surface == Vect::ZERO {
            Real::ZERO
        } else {
            ar.mul_add2(surface.x, t.x, surface.y, t.y)
        };
        RowConstants {
            rn_a,
            rn_b,
            rt_a,
            rt_b,
            nr_a,
            nr_b,
            kn_a,
            kn_b,
            kt_a,
            kt_b,
            k_n,
            k_t,
            approach,
            surface_t,
        }
    }
}
/// Runs `f` on one manifold's rows with a copy of its two bodies, and
/// stores them back (nothing for a body paired with itself).
#[inline(always)]
pub(super) fn on_bodies(
    rows: &mut [SoftContact],
    bodies: &mut [SolverBody],
    f: impl FnOnce(&mut [SoftContact], &mut [SolverBody; 2]),
) {
    let Some(first) = rows.first() else {
        return;
    };
    let (ia, ib) = (first.a, first.b);
    let Some((a, b)) = load_pair(bodies, ia, ib) else {
        return;
    };
    let mut copy = [a, b];
    f(rows, &mut copy);
    let [a, b] = copy;
    store_pair(bodies, ia, a, ib, b);
}

/// The cached impulses scaled by `dt_coef` (nothing for exactly 1).
#[inline(always)]
pub(super) fn scale_impulses(rows: &mut [SoftContact], dt_coef: Real) {
    if dt_coef != Real::ONE {
        for row in rows {
            row.jn *= dt_coef;
            row.jt *= dt_coef;
            if grid::ON && row.fits_grid() {
                row.jn = grid::impulse(row.jn);
                row.jt = grid::impulse(row.jt);
            }
        }
    }
}

/// The warm start of a manifold's rows on a copy of its bodies, fast path
/// first as [`solve_manifold`].
#[inline(always)]
pub(super) fn warm_start_manifold(rows: &[SoftContact], copy: &mut [SolverBody; 2]) {
    // Each body changes once per row (at most 2), by rounded products of
    // at most 2^60 (`Ranged`): from below 2^58, no addition wraps.
    let [a0, b0] = copy;
    if range_record(&[a0.v.x, a0.v.y, a0.w, b0.v.x, b0.v.y, b0.w]) < RANGED_INPUT {
        let mut fast = Ranged::new();
        let [mut a, mut b] = *copy;
        for r in rows {
            r.apply(&mut a, &mut b, r.jn, r.jt, &mut fast);
        }
        if !fast.overflowed() {
            *copy = [a, b];
            return;
        }
    }
    let [a, b] = copy;
    for r in rows {
        r.apply(a, b, r.jn, r.jt, &mut Saturating);
    }
}

/// The state a pass changes in a manifold's rows: `(jn, jt, max_jn)`.
type Impulses = [(Real, Real, Real); 2];

#[inline(always)]
pub(super) fn impulses(rows: &[SoftContact]) -> Impulses {
    let mut out = [(Real::ZERO, Real::ZERO, Real::ZERO); 2];
    for (o, r) in out.iter_mut().zip(rows) {
        *o = (r.jn, r.jt, r.max_jn);
    }
    out
}

#[cold]
pub(super) fn restore_impulses(rows: &mut [SoftContact], saved: Impulses) {
    for (r, &(jn, jt, max_jn)) in rows.iter_mut().zip(&saved) {
        (r.jn, r.jt, r.max_jn) = (jn, jt, max_jn);
    }
}

/// The normal rows of a manifold, then its friction rows.
#[inline(always)]
pub(super) fn manifold_pass<A: FixedArith>(
    rows: &mut [SoftContact],
    a: &mut SolverBody,
    b: &mut SolverBody,
    motion: &[Motion],
    p: &SoftContactParams,
    use_bias: bool,
    ar: &mut A,
) {
    for r in rows.iter_mut() {
        // The solve pass follows the positions' relax pass of the last
        // sub-step (or the prepare, with no motion: `dist` exactly).
        let s = if use_bias {
            r.sep
        } else {
            let s = r.separation(motion, ar);
            r.sep = s;
            s
        };
        r.solve_normal(a, b, s, p, use_bias, ar);
    }
    if p.friction {
        for r in rows.iter_mut() {
            r.solve_friction(a, b, ar);
        }
    }
}

impl ManifoldRow for SoftContact {
    #[inline(always)]
    fn ends(&self) -> (u32, u32) {
        (self.a, self.b)
    }
}

impl SoftContact {
    /// The current separation from the bodies' motion since the collide:
    /// `n·(Δq·r − r) = (cos − 1)·(n·r) + sin·(r × n)` for a turn `Δq`.
    #[inline(always)]
    fn separation<A: FixedArith>(&self, motion: &[Motion], ar: &mut A) -> Real {
        let none = Motion::default();
        let ma = motion.get(self.a as usize).unwrap_or(&none);
        let mb = motion.get(self.b as usize).unwrap_or(&none);
        let n = self.n;
        let dx = ar.sub(mb.dp.x, ma.dp.x);
        let dy = ar.sub(mb.dp.y, ma.dp.y);
        let moved_b = ar.dot4_bounded(
            [dx, dy, mb.dq_c1, mb.dq_s],
            [n.x, n.y, self.nr_b, self.rn_b],
        );
        let turned_a = ar.mul_add2(ma.dq_c1, self.nr_a, ma.dq_s, self.rn_a);
        let d = ar.sub(moved_b, turned_a);
        ar.add(self.dist, d)
    }

    /// Runs `f` on copies of the row's two bodies in [`Unsaturated`]
    /// arithmetic and stores them back; false (nothing stored) if it
    /// overflowed.
    #[inline(always)]
    pub(super) fn run(
        &mut self,
        bodies: &mut [SolverBody],
        f: impl FnOnce(&mut SoftContact, &mut SolverBody, &mut SolverBody, &mut Unsaturated),
    ) -> bool {
        let Some((mut a, mut b)) = load_pair(bodies, self.a, self.b) else {
            return true;
        };
        let mut fast = Unsaturated::new();
        f(self, &mut a, &mut b, &mut fast);
        if fast.overflowed() {
            return false;
        }
        store_pair(bodies, self.a, a, self.b, b);
        true
    }

    /// `n·jn + t·jt` on the bodies (−a, +b).
    #[inline(always)]
    fn apply<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        jn: Real,
        jt: Real,
        ar: &mut A,
    ) {
        let n = self.n;
        let p = Vect::new(ar.mul_sub2(n.x, jn, n.y, jt), ar.mul_add2(n.y, jn, n.x, jt));
        let dwa = ar.mul_add2(self.kn_a, jn, self.kt_a, jt);
        let dwb = ar.mul_add2(self.kn_b, jn, self.kt_b, jt);
        let (dva, dvb) = self.velocity_changes(p, ar);
        a.v = Vect::new(ar.sub(a.v.x, dva.x), ar.sub(a.v.y, dva.y));
        a.w = ar.sub(a.w, dwa);
        b.v = Vect::new(ar.add(b.v.x, dvb.x), ar.add(b.v.y, dvb.y));
        b.w = ar.add(b.w, dwb);
    }

    /// `p·m_a⁻¹` and `p·m_b⁻¹`, the second taken from the first when the
    /// inverse masses are equal (a pile of like bodies), and exactly 0 for a
    /// body of infinite mass (a contact with the ground): the same bits and
    /// the same overflow record as the four products (the record is an OR,
    /// which a repeated product, or a product of 0, leaves unchanged).
    #[inline(always)]
    fn velocity_changes<A: FixedArith>(&self, p: Vect, ar: &mut A) -> (Vect, Vect) {
        let times = |m: Real, ar: &mut A| {
            if m.is_zero() {
                Vect::ZERO
            } else {
                Vect::new(ar.mul(p.x, m), ar.mul(p.y, m))
            }
        };
        let dva = times(self.m_inv_a, ar);
        if self.m_inv_b == self.m_inv_a {
            return (dva, dva);
        }
        (dva, times(self.m_inv_b, ar))
    }

    /// An impulse `j` along the unit direction `d` (the normal or the
    /// tangent), whose angular terms per unit impulse are `k = [I_a⁻¹ (r1 ×
    /// d), I_b⁻¹ (r2 × d)]`: half the products of [`apply`](Self::apply).
    #[inline(always)]
    fn apply_along<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        d: Vect,
        k: [Real; 2],
        j: Real,
        ar: &mut A,
    ) {
        let [ka, kb] = k;
        let p = Vect::new(ar.mul(d.x, j), ar.mul(d.y, j));
        let (dwa, dwb) = (ar.mul(ka, j), ar.mul(kb, j));
        let (dva, dvb) = self.velocity_changes(p, ar);
        a.v = Vect::new(ar.sub(a.v.x, dva.x), ar.sub(a.v.y, dva.y));
        a.w = ar.sub(a.w, dwa);
        b.v = Vect::new(ar.add(b.v.x, dvb.x), ar.add(b.v.y, dvb.y));
        b.w = ar.add(b.w, dwb);
    }

    /// Whether every constant this row's passes multiply by fits its
    /// narrow grid (the narrow-grid study, module `grid`).
    pub(super) fn fits_grid(&self) -> bool {
        use grid::{fits, ARM_BITS, IMPULSE_BITS, MASS_BITS, NARROW_IMPULSES, UNIT_BITS};
        let unit = [
            self.n.x,
            self.n.y,
            self.friction,
            self.restitution,
            self.soft.mass_scale,
            self.soft.impulse_scale,
        ];
        let arm = [
            self.rn_a,
            self.rn_b,
            self.rt_a,
            self.rt_b,
            self.kn_a,
            self.kn_b,
            self.kt_a,
            self.kt_b,
            self.m_inv_a,
            self.m_inv_b,
        ];
        unit.iter().all(|&x| fits(x, UNIT_BITS))
            && arm.iter().all(|&x| fits(x, ARM_BITS))
            && fits(self.n_mass, MASS_BITS)
            && fits(self.t_mass, MASS_BITS)
            && (!NARROW_IMPULSES
                || [self.surface_t, self.jn, self.jt]
                    .iter()
                    .all(|&x| fits(x, IMPULSE_BITS)))
    }

    /// A freshly prepared row's constants (and, where the design narrows
    /// them, its warm-start impulses) on their grids, if they all fit;
    /// else the row keeps full precision.
    pub(super) fn narrow_to_grid(&mut self) {
        use grid::{narrow, ARM_BITS, IMPULSE_BITS, MASS_BITS, NARROW_IMPULSES, UNIT_BITS};
        if !self.fits_grid() {
            return;
        }
        for x in [
            &mut self.n.x,
            &mut self.n.y,
            &mut self.friction,
            &mut self.restitution,
            &mut self.soft.mass_scale,
            &mut self.soft.impulse_scale,
        ] {
            narrow(x, UNIT_BITS);
        }
        for x in [
            &mut self.rn_a,
            &mut self.rn_b,
            &mut self.rt_a,
            &mut self.rt_b,
            &mut self.kn_a,
            &mut self.kn_b,
            &mut self.kt_a,
            &mut self.kt_b,
            &mut self.m_inv_a,
            &mut self.m_inv_b,
        ] {
            narrow(x, ARM_BITS);
        }
        narrow(&mut self.n_mass, MASS_BITS);
        narrow(&mut self.t_mass, MASS_BITS);
        if NARROW_IMPULSES {
            for x in [&mut self.surface_t, &mut self.jn, &mut self.jt] {
                narrow(x, IMPULSE_BITS);
            }
        }
    }

    /// The bodies as a narrow kernel reads them, when the narrow-grid study
    /// is on and the row and the velocities fit its grid (module `grid`);
    /// `None` (full precision) otherwise, and always without the study.
    #[inline(always)]
    fn grid_view(&self, a: &SolverBody, b: &SolverBody) -> Option<(SolverBody, SolverBody)> {
        if grid::ON && self.fits_grid() {
            grid::narrow_bodies(a, b)
        } else {
            None
        }
    }

    /// The normal relative velocity `(v_b + ω_b × r2 − v_a − ω_a × r1)·n`.
    #[inline(always)]
    fn normal_velocity<A: FixedArith>(&self, a: &SolverBody, b: &SolverBody, ar: &mut A) -> Real {
        let n = self.n;
        let dv = Vect::new(ar.sub(b.v.x, a.v.x), ar.sub(b.v.y, a.v.y));
        let neg_rn_a = ar.neg_const(self.rn_a);
        ar.dot4_bounded([dv.x, dv.y, b.w, a.w], [n.x, n.y, self.rn_b, neg_rn_a])
    }

    /// The normal row: soft with `use_bias`, rigid without.
    #[inline(always)]
    fn solve_normal<A: FixedArith>(
        &mut self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        s: Real,
        p: &SoftContactParams,
        use_bias: bool,
        ar: &mut A,
    ) {
        let (bias, soft) = if s.is_positive() {
            // Apart: let the gap close within the sub-step, no push.
            (ar.mul(s, p.h_inv), Softness::RIGID)
        } else if use_bias {
            let overlap = ar.add(s, p.slop).min(Real::ZERO);
            let push = ar.mul(self.soft.bias_rate, overlap);
            (push.max(-p.push_out), self.soft)
        } else {
            (Real::ZERO, Softness::RIGID)
        };
        let narrow = self.grid_view(a, b);
        let (vn, bias) = match &narrow {
            Some((na, nb)) => (self.normal_velocity(na, nb, ar), grid::impulse(bias)),
            None => (self.normal_velocity(a, b, ar), bias),
        };
        let err = ar.add(vn, bias);
        let mut jn = ar.mul(err, self.n_mass);
        if !soft.is_rigid() {
            let scaled = ar.mul(jn, soft.mass_scale);
            let back = ar.mul(soft.impulse_scale, self.jn);
            jn = ar.add(scaled, back);
        }
        if narrow.is_some() {
            jn = grid::impulse(jn);
        }
        let old = self.jn;
        self.jn = ar.sub(old, jn).max(Real::ZERO);
        let djn = ar.sub(self.jn, old);
        self.max_jn = self.max_jn.max(djn);
        self.apply_along(a, b, self.n, [self.kn_a, self.kn_b], djn, ar);
    }

    /// The friction row, bounded by `friction·jn`.
    #[inline(always)]
    fn solve_friction<A: FixedArith>(
        &mut self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        ar: &mut A,
    ) {
        {
            let n = self.n;
            let narrow = self.grid_view(a, b);
            let (va, vb) = match &narrow {
                Some((na, nb)) => (na, nb),
                None => (&*a, &*b),
            };
            let dv = Vect::new(ar.sub(vb.v.x, va.v.x), ar.sub(vb.v.y, va.v.y));
            let (neg_ny, neg_rt_a) = (ar.neg_const(n.y), ar.neg_const(self.rt_a));
            let vt = ar.dot4_bounded([dv.x, dv.y, vb.w, va.w], [neg_ny, n.x, self.rt_b, neg_rt_a]);
            let vt = ar.add(vt, self.surface_t);
            let mut jt_max = ar.mul(self.friction, self.jn);
            let mut djt = ar.mul(vt, self.t_mass);
            if narrow.is_some() {
                jt_max = grid::impulse(jt_max);
                djt = grid::impulse(djt);
            }
            let old = self.jt;
            self.jt = ar.sub(old, djt).clamp(-jt_max, jt_max);
            let jt = ar.sub(self.jt, old);
            self.apply_along(a, b, self.n.perp(), [self.kt_a, self.kt_b], jt, ar);
        }
    }

    /// The restitution row: drive the normal velocity to `−e·approach`.
    #[inline(always)]
    pub(super) fn bounce<A: FixedArith>(
        &mut self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        ar: &mut A,
    ) {
        let vn = self.normal_velocity(a, b, ar);
        let target = ar.mul(self.restitution, self.approach);
        let err = ar.add(vn, target);
        let jn = ar.mul(err, self.n_mass);
        let old = self.jn;
        self.jn = ar.sub(old, jn).max(Real::ZERO);
        let djn = ar.sub(self.jn, old);
        self.apply_along(a, b, self.n, [self.kn_a, self.kn_b], djn, ar);
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::math::lanes::{Lane, Ops, Portable, LANES};
    use proptest::prelude::*;

    /// Four manifolds (bodies `2k`, `2k + 1`, of one or two points each;
    /// `like`: of equal inverse masses, as in a pile of like bodies),
    /// eight bodies, their motion and the parameters, from `v`.
    #[allow(clippy::type_complexity)]
    pub(crate) fn case(
        v: Vec<i64>,
        points: [bool; LANES],
        friction: bool,
        like: bool,
    ) -> (
        Vec<SoftContact>,
        [(u32, u32); LANES],
        Vec<SolverBody>,
        Vec<Motion>,
        SoftContactParams,
    ) {
        let mut v = v.into_iter().cycle();
        let mut rows = Vec::new();
        let mut manifolds = [(0u32, 0u32); LANES];
        for (k, (m, &two)) in manifolds.iter_mut().zip(&points).enumerate() {
            let start = rows.len() as u32;
            let mine = rows_from(&mut v, if two { 2 } else { 1 });
            for mut row in mine.iter().copied() {
                (row.a, row.b, row.arbiter) = (2 * k as u32, 2 * k as u32 + 1, k as u32);
                // One manifold's rows share its bodies' masses and its
                // softness (as the prepare makes them).
                if let Some(first) = mine.first() {
                    (row.m_inv_a, row.m_inv_b, row.soft) =
                        (first.m_inv_a, first.m_inv_b, first.soft);
                }
                if like {
                    row.m_inv_b = row.m_inv_a;
                }
                rows.push(row);
            }
            *m = (start, rows.len() as u32);
        }
        let mut r = || Real::from_bits(v.next().unwrap_or(0));
        let bodies = (0..2 * LANES)
            .map(|_| SolverBody {
                v: Vect::new(r(), r()),
                w: r(),
                m_inv: r(),
                i_inv: r(),
                ..SolverBody::default()
            })
            .collect();
        let motion = (0..2 * LANES)
            .map(|_| Motion {
                dp: Vect::new(r(), r()),
                dq_c1: r(),
                dq_s: r(),
                ..Motion::default()
            })
            .collect();
        let p = SoftContactParams {
            contact: Softness::RIGID,
            fixed: Softness::RIGID,
            h_inv: r(),
            slop: r(),
            push_out: r(),
            restitution_threshold: Real::ZERO,
            friction,
            restitution: false,
            narrow: false,
        };
        (rows, manifolds, bodies, motion, p)
    }

    /// Raw values for whole batches of rows (the wide kernels' tests).
    pub(crate) fn values() -> impl Strategy<Value = Vec<i64>> {
        // Short values (below 2^32, as most scenes' constants), alone or
        // with a few long ones: short and long factors in one batch.
        let short = || -(1i64 << 32) + 1..(1i64 << 32);
        prop_oneof![
            prop::collection::vec(bits(), 200),
            prop::collection::vec(mid(), 200),
            prop::collection::vec(-(1i64 << 36)..(1i64 << 36), 200),
            prop::collection::vec(short(), 200),
            prop::collection::vec(prop_oneof![20 => short(), 1 => bits()], 200),
        ]
    }

    /// [`Portable`], counting the lane operations (each one AVX2
    /// instruction in `tamias2d_simd::Avx2`).
    #[derive(Clone, Copy)]
    pub(in crate::solver::soft_contact) struct Counting<'a>(
        pub(in crate::solver::soft_contact) &'a core::cell::Cell<u64>,
    );

    macro_rules! counted {
        ($($name:ident($($arg:ident),*)),* $(,)?) => {$(
            fn $name(self, $($arg: Lane),*) -> Lane {
                self.0.set(self.0.get() + 1);
                Portable.$name($($arg),*)
            }
        )*};
    }

    impl Ops for Counting<'_> {
        counted!(
            add(a, b),
            sub(a, b),
            xor(a, b),
            and(a, b),
            or(a, b),
            gt(a, b),
            mul_lo32(a, b),
            mul_i32(a, b),
            shr32(a),
            shl32(a),
            select(mask, a, b),
        );

        fn shr_n<const N: i32>(self, a: Lane) -> Lane {
            self.0.set(self.0.get() + 1);
            Portable.shr_n::<N>(a)
        }

        fn shl_n<const N: i32>(self, a: Lane) -> Lane {
            self.0.set(self.0.get() + 1);
            Portable.shl_n::<N>(a)
        }

        fn run_part<K: tamias2d_simd::Kernel>(self, kernel: K) -> K::Output {
            kernel.run()
        }
    }

    #[test]
    fn a_narrowed_row_is_on_its_grids() {
        use grid::{round, ARM_BITS, IMPULSE_BITS, MASS_BITS, NARROW_IMPULSES, UNIT_BITS};
        let n = Vect::new(Real::lit("0.6"), Real::lit("-0.8"));
        let (arm, mass, jn) = (
            Real::lit("0.3333333"),
            Real::lit("0.7777777"),
            Real::lit("0.0123456789"),
        );
        let mut r = SoftContact {
            n,
            rn_a: arm,
            n_mass: mass,
            jn,
            ..SoftContact::default()
        };
        r.narrow_to_grid();
        assert_eq!(r.n, Vect::new(round(n.x, UNIT_BITS), round(n.y, UNIT_BITS)));
        assert_eq!(r.rn_a, round(arm, ARM_BITS));
        assert_eq!(r.n_mass, round(mass, MASS_BITS));
        // Impulses go to their grid only in the designs that narrow them.
        let want = if NARROW_IMPULSES {
            round(jn, IMPULSE_BITS)
        } else {
            jn
        };
        assert_eq!(r.jn, want);
        // A row out of the window keeps every bit.
        let mut far = SoftContact {
            rn_a: Real::from_int(200),
            n,
            ..SoftContact::default()
        };
        let before = far;
        far.narrow_to_grid();
        assert_eq!(far, before);
    }

    /// Raw values over the whole range: small, scene-like, near the
    /// range check's edge (2^58) and the extremes.
    pub(crate) fn bits() -> impl Strategy<Value = i64> {
        prop_oneof![
            (-(1i64 << 36)..(1i64 << 36)),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| v >> s),
            (-4i64..4).prop_map(|k| (1i64 << 58).wrapping_add(k)),
            (-4i64..4).prop_map(|k| (-(1i64 << 58)).wrapping_add(k)),
            any::<i64>(),
            Just(i64::MIN),
            Just(i64::MAX),
        ]
    }

    /// Scene-like values (products up to past `Ranged`'s record limit)
    /// with a few at the range check's edge.
    pub(crate) fn mid() -> impl Strategy<Value = i64> {
        prop_oneof![
            20 => -(1i64 << 47)..(1i64 << 47),
            1 => (-4i64..4).prop_map(|k| (1i64 << 58).wrapping_add(k)),
            1 => (-4i64..4).prop_map(|k| (-(1i64 << 58)).wrapping_add(k)),
        ]
    }

    /// Cases that took the fast path and kept it (coverage, printed).
    static FAST: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(0);
    static CASES: core::sync::atomic::AtomicU64 = core::sync::atomic::AtomicU64::new(0);

    pub(crate) fn rows_from(v: &mut impl Iterator<Item = i64>, count: usize) -> Vec<SoftContact> {
        let mut r = || Real::from_bits(v.next().unwrap_or(0));
        (0..count)
            .map(|slot| {
                let n = Vect::new(r(), r());
                let (nr_a, nr_b, rn_a, rn_b, rt_a, rt_b) = (r(), r(), r(), r(), r(), r());
                let mut row = SoftContact {
                    a: 0,
                    b: 1,
                    arbiter: 0,
                    slot: slot as u32,
                    n,
                    dist: r(),
                    sep: r(),
                    nr_a,
                    nr_b,
                    rn_a,
                    rn_b,
                    rt_a,
                    rt_b,
                    kn_a: r(),
                    kn_b: r(),
                    kt_a: r(),
                    kt_b: r(),
                    m_inv_a: r(),
                    m_inv_b: r(),
                    n_mass: r(),
                    t_mass: r(),
                    friction: r(),
                    restitution: Real::ZERO,
                    surface_t: r(),
                    approach: Real::ZERO,
                    soft: Softness {
                        bias_rate: r(),
                        mass_scale: r(),
                        impulse_scale: r(),
                    },
                    jn: r(),
                    jt: r(),
                    max_jn: r(),
                    constant_record: 0,
                };
                row.constant_record = if below_2_62(&[n.x, n.y, nr_a, nr_b, rn_a, rn_b, rt_a, rt_b])
                {
                    range_record(&[row.dist, row.surface_t])
                } else {
                    u64::MAX
                };
                row
            })
            .collect()
    }

    proptest! {
        // 20,000 cases take about 40 s unoptimised, the longest unit test
        // by far: a debug build runs a quarter of them
        // (`cargo test --release --lib` runs them all).
        #![proptest_config(ProptestConfig::with_cases(if cfg!(debug_assertions) { 5_000 } else { 20_000 }))]
        /// The `Ranged` fast path (with its range check and fallback)
        /// gives the saturating reference's bits on any input.
        #[test]
        fn ranged_passes_match_the_saturating_reference(
            vals in prop_oneof![
                prop::collection::vec(bits(), 80),
                prop::collection::vec(mid(), 80),
                prop::collection::vec(-(1i64 << 36)..(1i64 << 36), 80),
            ],
            two in any::<bool>(),
            use_bias in any::<bool>(),
            friction in any::<bool>(),
        ) {
            let mut v = vals.into_iter();
            let rows = rows_from(&mut v, if two { 2 } else { 1 });
            let mut r = || Real::from_bits(v.next().unwrap_or(0));
            let body = |r: &mut dyn FnMut() -> Real| SolverBody {
                v: Vect::new(r(), r()),
                w: r(),
                ..SolverBody::default()
            };
            let bodies = [body(&mut r), body(&mut r)];
            let motion = [0, 1].map(|_| Motion {
                dp: Vect::new(r(), r()),
                dq_c1: r(),
                dq_s: r(),
                ..Motion::default()
            });
            let p = SoftContactParams {
                contact: Softness::RIGID,
                fixed: Softness::RIGID,
                h_inv: r(),
                slop: r(),
                push_out: r(),
                restitution_threshold: Real::ZERO,
                friction,
                restitution: false,
                narrow: false,
            };
            let (mut fast_rows, mut ref_rows) = (rows.clone(), rows.clone());
            {
                use core::sync::atomic::Ordering::Relaxed;
                let mut probe_rows = rows.clone();
                let [mut a, mut b] = bodies;
                let mut ar = Ranged::new();
                let kept = manifold_record(&rows, &bodies, &motion, &p, use_bias) < RANGED_INPUT && {
                    manifold_pass(&mut probe_rows, &mut a, &mut b, &motion, &p, use_bias, &mut ar);
                    !ar.overflowed()
                };
                let cases = CASES.fetch_add(1, Relaxed) + 1;
                let fast = FAST.fetch_add(u64::from(kept), Relaxed) + u64::from(kept);
                if cases % 5000 == 0 {
                    eprintln!("fast path kept in {fast} of {cases} cases");
                }
            }
            let mut fast = bodies;
            solve_manifold(&mut fast_rows, &mut fast, &motion, &p, use_bias);
            let [mut a, mut b] = bodies;
            manifold_pass(&mut ref_rows, &mut a, &mut b, &motion, &p, use_bias, &mut Saturating);
            prop_assert_eq!(fast_rows, ref_rows);
            prop_assert_eq!(fast, [a, b]);

            let mut fast = bodies;
            warm_start_manifold(&rows, &mut fast);
            let [mut a, mut b] = bodies;
            for row in &rows {
                row.apply(&mut a, &mut b, row.jn, row.jt, &mut Saturating);
            }
            prop_assert_eq!(fast, [a, b]);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]
        /// A row's constants from the fast path give the bits of the
        /// saturating operators' formulas (the prepare they replaced), on
        /// any input, overflowing ones included.
        #[test]
        fn row_constants_match_the_operator_formulas(
            v in prop::collection::vec(bits(), 18),
        ) {
            let x = |k: usize| Real::from_bits(v.get(k).copied().unwrap_or(0));
            let body = |k: usize| SolverBody {
                v: Vect::new(x(k), x(k + 1)),
                w: x(k + 2),
                m_inv: x(k + 3),
                i_inv: x(k + 4),
                ..SolverBody::default()
            };
            let (a, b) = (body(0), body(5));
            let (n, r1, r2, surface) = (
                Vect::new(x(10), x(11)),
                Vect::new(x(12), x(13)),
                Vect::new(x(14), x(15)),
                Vect::new(x(16), x(17)),
            );
            let t = n.perp();
            let k = RowConstants::of(&a, &b, n, t, [r1, r2], surface, true);
            let (rn_a, rn_b) = (r1.cross(n), r2.cross(n));
            let (rt_a, rt_b) = (r1.cross(t), r2.cross(t));
            let vr = (b.v + r2.perp() * b.w) - (a.v + r1.perp() * a.w);
            let got = [
                k.rn_a, k.rn_b, k.rt_a, k.rt_b, k.nr_a, k.nr_b, k.kn_a, k.kn_b, k.kt_a, k.kt_b,
                k.k_n, k.k_t, k.approach, k.surface_t,
            ];
            let want = [
                rn_a,
                rn_b,
                rt_a,
                rt_b,
                n.dot(r1),
                n.dot(r2),
                a.i_inv * rn_a,
                b.i_inv * rn_b,
                a.i_inv * rt_a,
                b.i_inv * rt_b,
                a.m_inv + b.m_inv + a.i_inv * rn_a * rn_a + b.i_inv * rn_b * rn_b,
                a.m_inv + b.m_inv + a.i_inv * rt_a * rt_a + b.i_inv * rt_b * rt_b,
                vr.dot(n),
                surface.dot(t),
            ];
            prop_assert_eq!(got, want);
            // Without the approach speed, every other constant is the same.
            let k0 = RowConstants::of(&a, &b, n, t, [r1, r2], surface, false);
            let approach_free = |k: &RowConstants| RowConstants { approach: Real::ZERO, ..*k };
            prop_assert_eq!(format!("{:?}", approach_free(&k0)), format!("{:?}", approach_free(&k)));
        }
    }

    proptest! {
        /// Sharing the velocity change of equal inverse masses and skipping
        /// those of infinite mass gives the four products' bits and the
        /// same overflow record.
        #[test]
        fn velocity_changes_are_the_four_products(
            px in bits(), py in bits(), ma in bits(), mb in bits(), pick in 0u8..4,
        ) {
            let m = |x: i64| Real::from_bits(x);
            let (m_inv_a, m_inv_b) = match pick {
                0 => (m(ma), m(ma)),
                1 => (Real::ZERO, m(mb)),
                2 => (m(ma), Real::ZERO),
                _ => (m(ma), m(mb)),
            };
            let row = SoftContact { m_inv_a, m_inv_b, ..SoftContact::default() };
            let p = Vect::new(m(px), m(py));
            let mut fast = Unsaturated::new();
            let got = row.velocity_changes(p, &mut fast);
            let mut each = Unsaturated::new();
            let want = (
                Vect::new(each.mul(p.x, m_inv_a), each.mul(p.y, m_inv_a)),
                Vect::new(each.mul(p.x, m_inv_b), each.mul(p.y, m_inv_b)),
            );
            prop_assert_eq!(got, want);
            prop_assert_eq!(fast, each);
            prop_assert_eq!(row.velocity_changes(p, &mut Saturating), (p * m_inv_a, p * m_inv_b));
        }
    }
}
