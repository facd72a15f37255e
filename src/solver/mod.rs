//! The impulse half of the MIS Collision Solver (§10): relative velocities,
//! effective masses, and normal, friction and bias impulses.
//!
//! # Glossary
//!
//! The engine's four contact types, from narrowphase to solver:
//! * [`collision::Contact`](crate::collision::Contact): one narrowphase
//!   output point pair (world-space points on both surfaces, signed
//!   distance, feature id), an element of MIS `CollisionInfo`; per step.
//! * [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint): the
//!   *persistent* state of one contact, kept in its arbiter between steps
//!   and serialized in snapshots (`r1`, `r2`, `dist`, `feature_id`,
//!   `jn_acc`, `jt_acc`).
//! * [`ContactConstraint`]: the per-step solver row built from a manifold
//!   point by the pre-step; its impulses are written back to the manifold
//!   point after the iterations.
//! * [`collision::ContactPoint`](crate::collision::ContactPoint) /
//!   [`ContactPointSet`](crate::collision::ContactPointSet): the public query
//!   answer of `shapes_collide` and the handlers (no feature id).
//!
//! Two ids, never mixed:
//! * **feature id** (`Contact::feature_id`, `ManifoldPoint::feature_id`):
//!   `(feature on a) << 16 | (feature on b)`; matches a contact with last
//!   step's for warm starting the impulses.
//! * **warm-start id** ([`WarmStartId`](crate::collision::WarmStartId), MIS
//!   `CollisionID`; `CollisionInfo::warm_start_id`, `Arbiter::warm_start_id`):
//!   the GJK/EPA starting edge for the next narrowphase of the pair.
//!
//! Symbols:
//! * `a`, `b`: the two bodies of a contact; the normal `n` points from a to b.
//! * `r1`, `r2`: contact point relative to a's and b's centre of gravity.
//! * `vr`: relative velocity of b with respect to a at the contact,
//!   `(v_b + ω_b × r2) − (v_a + ω_a × r1)`.
//! * `m_inv`, `i_inv` (per body), `m_inv_a`, `m_inv_b` (per contact):
//!   inverse mass and inverse moment, 0 for infinite mass.
//! * `k`: effective inverse mass along a direction `d` (only this meaning),
//!   `k = m_a⁻¹ + m_b⁻¹ + I_a⁻¹ (r1 × d)² + I_b⁻¹ (r2 × d)²`; an impulse `j`
//!   along `d` changes `vr·d` by `k·j`, so `j = −Δ/k` cancels a velocity error
//!   `Δ`. `n_mass = 1/k(n)` and `t_mass = 1/k(t)` are computed once per step
//!   (pre-step): the iterations only multiply. (`kn_a` … `kt_b` are the
//!   angular terms `I⁻¹ (r × d)`; the step's `dt`-derived constants are
//!   `dtc`.)
//! * `jn_acc`, `jt_acc`, `jb_acc`: accumulated normal, tangent (friction)
//!   and bias impulses. Clamping the *accumulated* value (`jn_acc ≥ 0`,
//!   `|jt_acc| ≤ μ·jn_acc`, `jb_acc ≥ 0`) instead of each increment lets
//!   later iterations take back impulse, which is what makes sequential
//!   impulses converge (Catto, GDC 2006).
//! * **bias** — position correction by impulses on pseudo-velocities:
//!   - `collision_bias` (setting, Chipmunk's name): fraction of overlap
//!     left uncorrected after one second;
//!   - `bias_coef = 1 − collision_bias^dt`: fraction corrected this step;
//!   - `bias_target`: the separation velocity one contact's bias row aims for,
//!     `−bias_coef · min(0, dist + slop) / dt`, capped at `max_bias`;
//!   - `v_bias`, `w_bias`: the bodies' *pseudo-velocities*, changed only by
//!     bias impulses; they move positions in the next position update but
//!     add no momentum, so resolving overlap does not make objects bounce;
//!   - `jb_acc`: the accumulated bias impulse;
//!   - `bias_impulses` (setting and [`SolverSwitches`] switch): whether the
//!     bias row runs at all (`BIAS` in the monomorphised iteration).
//! * `bounce`: restitution target, `e · (vr·n)` at the start of the step, so
//!   the normal impulse drives `vr·n` to `−bounce`.
//!
//! Bodies are copied into a contiguous [`SolverBody`] array for the
//! iterations (inverse masses and velocities side by side); static and
//! kinematic bodies have zero inverse mass, so impulses leave them unchanged.

pub mod block;
mod body;
pub(crate) mod contact_solver;
pub(crate) mod graph;
pub(crate) mod kernel;
mod kernels;
mod reference;
pub(crate) mod soft_contact;
pub mod softness;
pub(crate) mod sweep;

use crate::arbiter::ManifoldPoint;
use crate::math::{below_2_62, Bounded, FixedArith, Real, Saturating, Unsaturated, Vect};
pub use body::SolverBody;
pub(crate) use kernel::effective_mass;
pub use kernel::k_scalar_body;
use kernel::{load_pair, neg, store_pair};
pub use kernels::Kernels;
pub use reference::{
    apply_bias_impulse, apply_bias_impulses, apply_impulse, apply_impulses, k_scalar,
    normal_relative_velocity, relative_velocity, UnsolvableCollision,
};

/// Which parts of the contact model the solver computes (from the space's
/// [`Settings`](crate::space::Settings)). A part switched off is skipped,
/// not computed and discarded: the pre-step leaves its constants at zero,
/// the warm-start stage is not run, and the iterations use a routine
/// compiled without the friction or bias row ([`ContactConstraint::solve_with`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SolverSwitches {
    /// Start from last step's impulses (otherwise from zero).
    pub warm_starting: bool,
    /// Friction impulses (otherwise as if every friction were 0).
    pub friction: bool,
    /// Restitution targets (otherwise as if every elasticity were 0).
    pub restitution: bool,
    /// Bias impulses (otherwise overlap is never corrected).
    pub bias_impulses: bool,
}

impl SolverSwitches {
    /// Everything on (the default settings).
    pub const ALL: SolverSwitches = SolverSwitches {
        warm_starting: true,
        friction: true,
        restitution: true,
        bias_impulses: true,
    };
}

impl Default for SolverSwitches {
    fn default() -> Self {
        SolverSwitches::ALL
    }
}

/// Step-wide constants of the contact solver.
#[derive(Clone, Copy, Debug)]
pub struct ContactParams {
    /// `1/dt`.
    pub dt_inv: Real,
    /// Allowed overlap that is not corrected.
    pub slop: Real,
    /// Fraction of the remaining overlap corrected this step,
    /// `1 − collision_bias^dt`.
    pub bias_coef: Real,
    /// Largest bias velocity (Chipmunk's arbiter `maxBias`, unbounded by default).
    pub max_bias: Real,
    /// The parts of the model computed this step.
    pub switches: SolverSwitches,
}

/// The arbiter-wide inputs of a contact's pre-step.
#[derive(Clone, Copy, Debug)]
pub struct PairParams {
    /// Solver index of body a.
    pub a: u32,
    /// Solver index of body b.
    pub b: u32,
    /// Unit normal from a to b.
    pub n: Vect,
    /// Restitution.
    pub e: Real,
    /// Friction coefficient.
    pub friction: Real,
    /// Relative surface velocity (tangential).
    pub surface_vr: Vect,
}

/// One contact prepared for the iterations (the per-step solver row, built
/// from an [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint); the
/// other contact types are `collision::Contact` and `collision::ContactPoint`,
/// see the module glossary): everything the inner loop needs,
/// side by side, with every division and cross product done once.
///
/// With `t = perp(n)`, the velocity along a direction `d` at the contact is
/// `(v_b − v_a)·d + ω_b (r2 × d) − ω_a (r1 × d)`, so storing `r × n` and
/// `r × t` turns each relative velocity into one 4-term dot product (one
/// rounding), and storing `I⁻¹ (r × d)` turns each angular impulse into one
/// multiplication.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContactConstraint {
    /// Solver index of body a.
    pub a: u32,
    /// Solver index of body b.
    pub b: u32,
    /// Index of the arbiter and of the contact in it (for the write-back).
    pub arbiter: u32,
    /// Contact slot in the arbiter.
    pub slot: u32,
    /// On the first row of a two-contact manifold solved as a block: the
    /// block's index + 1 in the scratch's `blocks` (the next row is the
    /// second contact); 0 for a row solved on its own.
    pub block: u32,
    /// Unit normal from a to b.
    pub n: Vect,
    /// `r1 × n`, `r2 × n`, `r1 × t`, `r2 × t`.
    pub rn_a: Real,
    pub rn_b: Real,
    pub rt_a: Real,
    pub rt_b: Real,
    /// `I_a⁻¹ (r1 × n)` and friends: angular velocity change per unit impulse.
    pub kn_a: Real,
    pub kn_b: Real,
    pub kt_a: Real,
    pub kt_b: Real,
    /// Inverse masses.
    pub m_inv_a: Real,
    pub m_inv_b: Real,
    /// `1/k(n)`, `1/k(t)` (`effective_mass`). `t_mass` stays 0 on the
    /// rows of a block: its face friction has its own, and the division
    /// is not done for nothing.
    pub n_mass: Real,
    pub t_mass: Real,
    /// Bias row target velocity and restitution target.
    pub bias_target: Real,
    pub bounce: Real,
    /// Friction coefficient and tangential surface velocity.
    pub friction: Real,
    pub surface_t: Real,
    /// Accumulated normal, friction and bias impulses.
    pub jn_acc: Real,
    pub jt_acc: Real,
    pub jb_acc: Real,
    /// The constants that multiply in the iteration's dot products (`n`,
    /// the lever arms `r × n`, `r × t` and `I⁻¹ (r × n)`) are below `2^62`
    /// raw ([`below_2_62`]): the iteration may run in [`Bounded`]
    /// arithmetic. Set by the pre-step ([`check_range`](Self::check_range))
    /// and only by it (read it with [`is_bounded`](Self::is_bounded)); a
    /// row without it (positions near the edge of the range) is solved in
    /// saturating arithmetic.
    pub(crate) bounded: bool,
}

impl ContactConstraint {
    /// Pre-step for one contact (Chipmunk `preStep`): effective masses
    /// `1/k`, bias `−bias_coef·min(0, dist + slop)/dt` and bounce
    /// `e·(vr·n)` from the velocities before gravity. The only divisions of
    /// the contact solver happen here. Parts switched off in
    /// `params.switches` are left at zero: without friction no tangent
    /// terms (and no tangent effective mass, a division), without
    /// restitution no bounce, without bias no bias target, without warm
    /// starting no cached impulses.
    ///
    /// Runs on the solver's fast path (see [`prepare`](Self::prepare)).
    pub fn new(
        c: &ManifoldPoint,
        bodies: &[SolverBody],
        pair: &PairParams,
        params: &ContactParams,
    ) -> ContactConstraint {
        let (mut sc, k_t) = ContactConstraint::prepare(c, bodies, pair, params);
        sc.t_mass = effective_mass(k_t);
        sc
    }

    /// [`new`](Self::new) without the tangent effective mass: the row with
    /// `t_mass` left at zero, and the tangent `k(t)` (zero without
    /// friction) whose `effective_mass` it is. The space's pre-step
    /// computes that division only for a row solved on its own: a row of a
    /// block uses the block's face friction instead
    /// ([`ManifoldBlock`]), never its own `t_mass`.
    ///
    /// The arithmetic runs first in [`Unsaturated`] arithmetic (plain wide
    /// integer operations and one overflow flag, as the iterations);
    /// only if the flag is raised is it recomputed in saturating [`Real`]
    /// arithmetic by the same generic code, so the row is the saturating
    /// one bit for bit and an ordinary contact pays for no saturation
    /// check. The divisions come after, on the chosen `k`: they are exact
    /// (rounded to nearest as [`Real::recip`]) and the same in both modes.
    #[inline]
    pub fn prepare(
        c: &ManifoldPoint,
        bodies: &[SolverBody],
        pair: &PairParams,
        params: &ContactParams,
    ) -> (ContactConstraint, Real) {
        let zero = SolverBody::default();
        let a = bodies.get(pair.a as usize).unwrap_or(&zero);
        let b = bodies.get(pair.b as usize).unwrap_or(&zero);
        let mut fast = Unsaturated::new();
        let (mut sc, mut k) = pre_step_terms(c, a, b, pair, params, &mut fast);
        if fast.overflowed() {
            (sc, k) = pre_step_saturating(c, a, b, pair, params);
        }
        // A zero k (two infinite masses) gives mass 0: the contact applies no impulse.
        sc.n_mass = effective_mass(k[0]);
        sc.check_range();
        (sc, k[1])
    }

    /// True if the row's constants passed the range check of the
    /// [`Bounded`] fast path (see [`check_range`](Self::check_range)).
    pub fn is_bounded(&self) -> bool {
        self.bounded
    }

    /// Sets [`bounded`](Self::bounded) from the row's constants.
    #[inline(always)]
    pub fn check_range(&mut self) {
        self.bounded = below_2_62(&[
            self.n.x, self.n.y, self.rn_a, self.rn_b, self.rt_a, self.rt_b, self.kn_a, self.kn_b,
        ]);
    }

    /// Applies the impulse `n·jn + t·jt` to the velocities (−a, +b).
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
        // P = n·jn + perp(n)·jt, with perp(n) = (−n.y, n.x).
        let p = Vect::new(ar.mul_sub2(n.x, jn, n.y, jt), ar.mul_add2(n.y, jn, n.x, jt));
        let dwa = ar.mul_add2(self.kn_a, jn, self.kt_a, jt);
        let dwb = ar.mul_add2(self.kn_b, jn, self.kt_b, jt);
        move_bodies(
            a,
            b,
            p,
            dwa,
            dwb,
            self.m_inv_a,
            self.m_inv_b,
            ar,
            Velocity::Real,
        );
    }

    /// Applies the normal impulse `n·jn` alone (the friction-free
    /// [`apply`](Self::apply): `apply(a, b, jn, 0)` gives the same bits).
    #[inline(always)]
    fn apply_normal<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        jn: Real,
        ar: &mut A,
        which: Velocity,
    ) {
        let n = self.n;
        let p = Vect::new(ar.mul(n.x, jn), ar.mul(n.y, jn));
        let dwa = ar.mul(self.kn_a, jn);
        let dwb = ar.mul(self.kn_b, jn);
        move_bodies(a, b, p, dwa, dwb, self.m_inv_a, self.m_inv_b, ar, which);
    }

    /// Scales the cached impulses by `dt_coef = dt/prev_dt` and applies
    /// them (the warm start).
    ///
    /// The scaled impulses *become* the accumulated impulses the iterations
    /// start from, so the accumulators always hold exactly the impulse
    /// applied to the bodies: the clamps `jn_acc ≥ 0` and
    /// `|jt_acc| ≤ μ·jn_acc` can then take back all of it. (Chipmunk's
    /// `cpArbiterApplyCachedImpulse` applies `dt_coef·jn_acc` but lets the
    /// iterations start from the unscaled `jn_acc`: when `dt` grows 8×, a
    /// contact is pushed apart by 8× its cached impulse and the clamp can
    /// take back only 1×, which is how a pyramid stepped at alternating
    /// 1/240 and 1/30 s exploded.) The space passes
    /// `dt_coef = min(dt/prev_dt, 1)` (see the warm-start stage). With a constant
    /// `dt`, `dt_coef` is exactly 1 and the scaling changes no bit.
    pub fn warm_start(&mut self, bodies: &mut [SolverBody], dt_coef: Real) {
        self.warm_start_at::<true>(bodies, dt_coef, (self.a, self.b));
    }

    /// [`warm_start`](Self::warm_start) of the normal impulse alone (friction
    /// off: `jt_acc` is 0).
    pub fn warm_start_normal(&mut self, bodies: &mut [SolverBody], dt_coef: Real) {
        self.warm_start_at::<false>(bodies, dt_coef, (self.a, self.b));
    }

    /// [`warm_start`](Self::warm_start) (`FRICTION`) or
    /// [`warm_start_normal`](Self::warm_start_normal) with bodies `a` and
    /// `b` at `bodies[ends.0]` and `bodies[ends.1]` (the solver's own
    /// slots, or a copy of the two: see [`solve_prepared`](Self::solve_prepared)).
    #[inline]
    pub(crate) fn warm_start_at<const FRICTION: bool>(
        &mut self,
        bodies: &mut [SolverBody],
        dt_coef: Real,
        ends: (u32, u32),
    ) {
        self.scale_cached_impulses::<FRICTION>(dt_coef);
        self.warm_start_with::<FRICTION>(bodies, ends);
    }

    /// `jn_acc ← jn_acc·dt_coef` (and `jt_acc` with friction), saturating.
    #[inline(always)]
    fn scale_cached_impulses<const FRICTION: bool>(&mut self, dt_coef: Real) {
        self.jn_acc *= dt_coef;
        if FRICTION {
            self.jt_acc *= dt_coef;
        }
    }

    /// Applies the accumulated impulses, fast path first as in
    /// [`solve_with`](Self::solve_with).
    #[inline]
    fn warm_start_with<const FRICTION: bool>(&self, bodies: &mut [SolverBody], ends: (u32, u32)) {
        let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
            return;
        };
        let mut fast = Unsaturated::new();
        self.warm_start_bodies::<_, FRICTION>(&mut a, &mut b, &mut fast);
        if fast.overflowed() {
            // The inputs are still in `bodies`: no copies kept.
            self.warm_start_saturating::<FRICTION>(bodies, ends);
            return;
        }
        store_pair(bodies, ends.0, a, ends.1, b);
    }

    /// The reference path of [`warm_start_with`](Self::warm_start_with).
    #[cold]
    #[inline(never)]
    fn warm_start_saturating<const FRICTION: bool>(
        &self,
        bodies: &mut [SolverBody],
        ends: (u32, u32),
    ) {
        let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
            return;
        };
        self.warm_start_bodies::<_, FRICTION>(&mut a, &mut b, &mut Saturating);
        store_pair(bodies, ends.0, a, ends.1, b);
    }

    /// Applies the accumulated impulses to body copies.
    #[inline(always)]
    fn warm_start_bodies<A: FixedArith, const FRICTION: bool>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        ar: &mut A,
    ) {
        if FRICTION {
            self.apply(a, b, self.jn_acc, self.jt_acc, ar);
        } else {
            self.apply_normal(a, b, self.jn_acc, ar, Velocity::Real);
        }
    }

    /// One iteration (Chipmunk `applyImpulse`): bias, normal and friction.
    ///
    /// * bias: `jb = (bias_target − vb·n)·n_mass` on the pseudo-velocities,
    ///   accumulated and clamped ≥ 0;
    /// * normal: `jn = −(bounce + vr·n)·n_mass`, accumulated and clamped ≥ 0;
    /// * friction: `jt = −(vr·t + surface_vr·t)·t_mass`, accumulated and
    ///   clamped to `±μ·jn_acc`.
    #[inline]
    pub fn solve(&mut self, bodies: &mut [SolverBody]) {
        self.solve_with::<true, true>(bodies);
    }

    /// [`solve`](Self::solve) with the friction row and the bias row compiled
    /// in or out. `solve_with::<true, true>` is `solve`; without `FRICTION`
    /// the result is that of friction 0 (and the tangent velocity, clamp and
    /// tangent impulse are not computed), without `BIAS` that of a zero bias
    /// target with no bias velocities (the bias row is not computed). The
    /// space picks one of the four once per step.
    ///
    /// The iteration runs first in [`Bounded`] arithmetic on copies;
    /// only if an operation left the range (the overflow flag) is it
    /// recomputed in saturating [`Real`] arithmetic. Both run the same
    /// generic code (`iterate`), so the result is always
    /// the saturating one, bit for bit, and ordinary scenes pay for no
    /// saturation checks. The row's constants are range-checked first
    /// ([`check_range`](Self::check_range)): its fields are public and may
    /// have changed since the pre-step.
    #[inline]
    pub fn solve_with<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        bodies: &mut [SolverBody],
    ) {
        self.check_range();
        self.solve_prepared::<FRICTION, BIAS>(bodies, (self.a, self.b));
    }

    /// [`solve_with`](Self::solve_with) trusting [`bounded`](Self::bounded)
    /// as the pre-step set it: the space's step, whose rows live in its
    /// scratch and are changed by nothing between the pre-step and the
    /// iterations. Bodies `a` and `b` are `bodies[ends.0]` and
    /// `bodies[ends.1]`: the row's own slots, or those of a copy of the
    /// two (a thread's, see [`sweep`]).
    #[inline]
    pub(crate) fn solve_prepared<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        bodies: &mut [SolverBody],
        ends: (u32, u32),
    ) {
        if !self.bounded {
            self.solve_saturating::<FRICTION, BIAS>(bodies, ends);
            return;
        }
        let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
            return;
        };
        let mut acc = [self.jb_acc, self.jn_acc, self.jt_acc];
        let mut fast = Bounded(Unsaturated::new());
        self.iterate::<_, FRICTION, BIAS>(&mut a, &mut b, &mut acc, &mut fast);
        if fast.0.overflowed() {
            // The inputs are still in `bodies` and `self`: no copies kept.
            self.solve_saturating::<FRICTION, BIAS>(bodies, ends);
            return;
        }
        [self.jb_acc, self.jn_acc, self.jt_acc] = acc;
        store_pair(bodies, ends.0, a, ends.1, b);
    }

    /// The reference path of [`solve_with`](Self::solve_with), kept out of
    /// line: it runs only when something saturates.
    #[cold]
    #[inline(never)]
    fn solve_saturating<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        bodies: &mut [SolverBody],
        ends: (u32, u32),
    ) {
        let Some((mut a, mut b)) = load_pair(bodies, ends.0, ends.1) else {
            return;
        };
        let mut acc = [self.jb_acc, self.jn_acc, self.jt_acc];
        self.iterate::<_, FRICTION, BIAS>(&mut a, &mut b, &mut acc, &mut Saturating);
        [self.jb_acc, self.jn_acc, self.jt_acc] = acc;
        store_pair(bodies, ends.0, a, ends.1, b);
    }

    /// One iteration on body copies `a`, `b` and the accumulated impulses
    /// `acc = [jb_acc, jn_acc, jt_acc]`, in the arithmetic `ar`.
    #[inline(always)]
    fn iterate<A: FixedArith, const FRICTION: bool, const BIAS: bool>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut [Real; 3],
        ar: &mut A,
    ) {
        let n = self.n;
        let [jb_old, jn_old, jt_old] = *acc;

        // The bias row is an exact no-op (every product and sum is of
        // zeros) while both bodies have no bias velocity and the row has
        // neither a target nor an impulse: skipped, same bits.
        let bias_idle = || {
            self.bias_target.is_zero() && jb_old.is_zero() && a.bias_is_zero() && b.bias_is_zero()
        };
        if BIAS && !bias_idle() {
            let dvb = Vect::new(
                ar.sub(b.v_bias.x, a.v_bias.x),
                ar.sub(b.v_bias.y, a.v_bias.y),
            );
            let neg_rn_a = ar.neg_const(self.rn_a);
            let vbn = ar.dot4_bounded(
                [dvb.x, dvb.y, b.w_bias, a.w_bias],
                [n.x, n.y, self.rn_b, neg_rn_a],
            );
            let err = ar.sub(self.bias_target, vbn);
            let jb = ar.mul(err, self.n_mass);
            acc[0] = ar.add(jb_old, jb).max(Real::ZERO);
            let djb = ar.sub(acc[0], jb_old);
            if !djb.is_zero() {
                self.apply_normal(a, b, djb, ar, Velocity::Bias);
            }
        }

        let dv = Vect::new(ar.sub(b.v.x, a.v.x), ar.sub(b.v.y, a.v.y));
        let neg_rn_a = ar.neg_const(self.rn_a);
        let vn = ar.dot4_bounded([dv.x, dv.y, b.w, a.w], [n.x, n.y, self.rn_b, neg_rn_a]);
        let err = ar.add(self.bounce, vn);
        let djn = ar.mul(err, self.n_mass);
        acc[1] = ar.sub(jn_old, djn).max(Real::ZERO);
        let jn = ar.sub(acc[1], jn_old);

        if FRICTION {
            let (neg_ny, neg_rt_a) = (ar.neg_const(n.y), ar.neg_const(self.rt_a));
            let vt = ar.dot4_bounded([dv.x, dv.y, b.w, a.w], [neg_ny, n.x, self.rt_b, neg_rt_a]);
            let vt = ar.add(vt, self.surface_t);
            let jt_max = ar.mul(self.friction, acc[1]);
            let djt = ar.mul(vt, self.t_mass);
            acc[2] = ar.sub(jt_old, djt).clamp(-jt_max, jt_max);
            let jt = ar.sub(acc[2], jt_old);
            self.apply(a, b, jn, jt, ar);
        } else {
            self.apply_normal(a, b, jn, ar, Velocity::Real);
        }
    }
}

/// The pre-step arithmetic of one row in the arithmetic `ar`: the row
/// without its effective masses, and `[k(n), k(t)]` (`k(t)` is zero
/// without friction). The same operations, in the same order of rounding,
/// as the saturating code it replaced (`k_scalar`,
/// `normal_relative_velocity`, `Vect::cross`, …).
#[inline(always)]
fn pre_step_terms<A: FixedArith>(
    c: &ManifoldPoint,
    a: &SolverBody,
    b: &SolverBody,
    pair: &PairParams,
    params: &ContactParams,
    ar: &mut A,
) -> (ContactConstraint, [Real; 2]) {
    let f = params.switches;
    let n = pair.n;
    let (r1, r2) = (c.r1, c.r2);
    // k along d: (m_a + (I_a⁻¹·(r1 × d))·(r1 × d)) + (m_b + …), as `k_scalar`.
    let k_of = |ra: Real, rb: Real, ka: Real, kb: Real, ar: &mut A| {
        let ta = ar.mul(ka, ra);
        let tb = ar.mul(kb, rb);
        let sa = ar.add(a.m_inv, ta);
        let sb = ar.add(b.m_inv, tb);
        ar.add(sa, sb)
    };
    let rn_a = ar.mul_sub2(r1.x, n.y, r1.y, n.x);
    let rn_b = ar.mul_sub2(r2.x, n.y, r2.y, n.x);
    let kn_a = ar.mul(a.i_inv, rn_a);
    let kn_b = ar.mul(b.i_inv, rn_b);
    let k_n = k_of(rn_a, rn_b, kn_a, kn_b, ar);
    let mut sc = ContactConstraint {
        a: pair.a,
        b: pair.b,
        n,
        rn_a,
        rn_b,
        kn_a,
        kn_b,
        m_inv_a: a.m_inv,
        m_inv_b: b.m_inv,
        ..ContactConstraint::default()
    };
    let mut k_t = Real::ZERO;
    if f.friction {
        // t = perp(n) = (−n.y, n.x).
        let t = Vect::new(neg(n.y, ar), n.x);
        let rt_a = ar.mul_sub2(r1.x, t.y, r1.y, t.x);
        let rt_b = ar.mul_sub2(r2.x, t.y, r2.y, t.x);
        sc.rt_a = rt_a;
        sc.rt_b = rt_b;
        sc.kt_a = ar.mul(a.i_inv, rt_a);
        sc.kt_b = ar.mul(b.i_inv, rt_b);
        k_t = k_of(rt_a, rt_b, sc.kt_a, sc.kt_b, ar);
        sc.friction = pair.friction;
        sc.surface_t = ar.mul_add2(pair.surface_vr.x, t.x, pair.surface_vr.y, t.y);
    }
    if f.bias_impulses {
        let overlap = ar.add(c.dist, params.slop).min(Real::ZERO);
        let coef = neg(params.bias_coef, ar);
        let v = ar.mul(coef, overlap);
        sc.bias_target = ar.mul(v, params.dt_inv).min(params.max_bias);
    }
    // `x·0` is 0 for every x, saturated or not: no elasticity, no velocity
    // to compute (the usual case).
    if f.restitution && !pair.e.is_zero() {
        let vn = kernel::normal_relative_velocity(a, b, r1, r2, n, ar);
        sc.bounce = ar.mul(vn, pair.e);
    }
    if f.warm_starting {
        sc.jn_acc = c.jn_acc;
        if f.friction {
            sc.jt_acc = c.jt_acc;
        }
    }
    (sc, [k_n, k_t])
}

/// The reference path of [`ContactConstraint::prepare`], out of line: it
/// runs only when something saturates.
#[cold]
#[inline(never)]
fn pre_step_saturating(
    c: &ManifoldPoint,
    a: &SolverBody,
    b: &SolverBody,
    pair: &PairParams,
    params: &ContactParams,
) -> (ContactConstraint, [Real; 2]) {
    pre_step_terms(c, a, b, pair, params, &mut Saturating)
}

/// Which velocity an impulse changes: the real one or the bias
/// pseudo-velocity.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Velocity {
    Real,
    Bias,
}

/// `a −= (p·m_inv_a, dwa)`, `b += (p·m_inv_b, dwb)` on the chosen velocity.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // all scalars of one impulse, inlined
fn move_bodies<A: FixedArith>(
    a: &mut SolverBody,
    b: &mut SolverBody,
    p: Vect,
    dwa: Real,
    dwb: Real,
    m_inv_a: Real,
    m_inv_b: Real,
    ar: &mut A,
    which: Velocity,
) {
    let pa = Vect::new(ar.mul(p.x, m_inv_a), ar.mul(p.y, m_inv_a));
    let pb = Vect::new(ar.mul(p.x, m_inv_b), ar.mul(p.y, m_inv_b));
    let (va, wa, vb, wb) = match which {
        Velocity::Real => (&mut a.v, &mut a.w, &mut b.v, &mut b.w),
        Velocity::Bias => (&mut a.v_bias, &mut a.w_bias, &mut b.v_bias, &mut b.w_bias),
    };
    *va = Vect::new(ar.sub(va.x, pa.x), ar.sub(va.y, pa.y));
    *wa = ar.sub(*wa, dwa);
    *vb = Vect::new(ar.add(vb.x, pb.x), ar.add(vb.y, pb.y));
    *wb = ar.add(*wb, dwb);
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod pre_step_tests;
