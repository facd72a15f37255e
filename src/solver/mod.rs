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
use core::fmt;

pub mod block;
mod body;
pub(crate) mod contact_solver;
pub(crate) mod graph;
pub(crate) mod kernel;
pub(crate) mod sweep;

use crate::arbiter::ManifoldPoint;
use crate::math::{below_2_62, Bounded, FixedArith, Real, Saturating, Unsaturated, Vect};
pub use body::SolverBody;
pub(crate) use kernel::effective_mass;
use kernel::{load_pair, neg, store_pair};

/// MIS UnsolvableCollision: both bodies have infinite mass along the
/// direction, so no impulse can change their relative velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnsolvableCollision;

impl fmt::Display for UnsolvableCollision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("unsolvable collision: effective mass is infinite (k = 0)")
    }
}

impl std::error::Error for UnsolvableCollision {}

/// MIS `relative_velocity`: velocity of `b` at `r2` minus velocity of `a` at `r1`.
#[inline(always)]
pub fn relative_velocity(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect) -> Vect {
    let va = a.v + r1.perp() * a.w;
    let vb = b.v + r2.perp() * b.w;
    vb - va
}

/// MIS `normal_relative_velocity`: `relative_velocity · n`.
#[inline(always)]
pub fn normal_relative_velocity(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
) -> Real {
    relative_velocity(a, b, r1, r2).dot(n)
}

/// MIS `apply_impulse`: `v += j·m⁻¹`, `ω += I⁻¹ (r × j)`.
#[inline(always)]
pub fn apply_impulse(body: &mut SolverBody, j: Vect, r: Vect) {
    body.v += j * body.m_inv;
    body.w += body.i_inv * r.cross(j);
}

/// MIS `apply_impulses`: `−j` on `a` at `r1`, `+j` on `b` at `r2`.
#[inline(always)]
pub fn apply_impulses(a: &mut SolverBody, b: &mut SolverBody, r1: Vect, r2: Vect, j: Vect) {
    apply_impulse(a, -j, r1);
    apply_impulse(b, j, r2);
}

/// MIS `apply_bias_impulse`: like [`apply_impulse`] on the pseudo-velocities.
#[inline(always)]
pub fn apply_bias_impulse(body: &mut SolverBody, j: Vect, r: Vect) {
    body.v_bias += j * body.m_inv;
    body.w_bias += body.i_inv * r.cross(j);
}

/// MIS `apply_bias_impulses`: `−j` on `a` at `r1`, `+j` on `b` at `r2`.
#[inline(always)]
pub fn apply_bias_impulses(a: &mut SolverBody, b: &mut SolverBody, r1: Vect, r2: Vect, j: Vect) {
    apply_bias_impulse(a, -j, r1);
    apply_bias_impulse(b, j, r2);
}

/// MIS `k_scalar_body`: `m⁻¹ + I⁻¹ (r × n)²`.
#[inline(always)]
pub fn k_scalar_body(body: &SolverBody, r: Vect, n: Vect) -> Real {
    let rcn = r.cross(n);
    body.m_inv + body.i_inv * rcn * rcn
}

/// MIS `k_scalar`: the effective inverse mass of the pair along `n`;
/// [`UnsolvableCollision`] when it is zero.
#[inline]
pub fn k_scalar(
    a: &SolverBody,
    b: &SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
) -> Result<Real, UnsolvableCollision> {
    let k = k_scalar_body(a, r1, n) + k_scalar_body(b, r2, n);
    if k.is_positive() {
        Ok(k)
    } else {
        Err(UnsolvableCollision)
    }
}

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
mod tests {
    use super::*;
    use crate::real;

    fn body(m_inv: i32, i_inv: i32) -> SolverBody {
        SolverBody {
            m_inv: Real::from_int(m_inv),
            i_inv: Real::from_int(i_inv),
            ..Default::default()
        }
    }

    #[test]
    fn k_scalar_sums_both_bodies_and_rejects_infinite_pairs() {
        let a = body(1, 1);
        let b = body(2, 0);
        let r = Vect::from_ints(0, 1);
        let n = Vect::X;
        // (r × n)² = 1 for a; b has no rotation.
        assert_eq!(k_scalar(&a, &b, r, r, n), Ok(Real::from_int(4)));
        assert_eq!(
            k_scalar(&body(0, 0), &body(0, 0), r, r, n),
            Err(UnsolvableCollision)
        );
    }

    #[test]
    fn impulses_are_equal_and_opposite() {
        let mut a = body(1, 0);
        let mut b = body(1, 0);
        apply_impulses(
            &mut a,
            &mut b,
            Vect::ZERO,
            Vect::ZERO,
            Vect::from_ints(2, 0),
        );
        assert_eq!(a.v, Vect::from_ints(-2, 0));
        assert_eq!(b.v, Vect::from_ints(2, 0));
        let vr = relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO);
        assert_eq!(vr, Vect::from_ints(4, 0));
        assert_eq!(
            normal_relative_velocity(&a, &b, Vect::ZERO, Vect::ZERO, Vect::X),
            Real::from_int(4)
        );
    }

    #[test]
    fn normal_impulse_stops_approach_without_pulling() {
        // Two unit masses approaching at 2 along the normal: one iteration stops them.
        let mut bodies = [body(1, 0), body(1, 0)];
        bodies[0].v = Vect::from_ints(1, 0);
        bodies[1].v = Vect::from_ints(-1, 0);
        let params = ContactParams {
            dt_inv: Real::from_int(60),
            slop: Real::ZERO,
            bias_coef: Real::ZERO,
            max_bias: Real::MAX,
            switches: SolverSwitches::ALL,
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n: Vect::X,
            e: Real::ZERO,
            friction: Real::ZERO,
            surface_vr: Vect::ZERO,
        };
        let mut c = ContactConstraint::new(&ManifoldPoint::default(), &bodies, &pair, &params);
        c.solve(&mut bodies);
        assert_eq!(bodies[0].v, Vect::ZERO);
        assert_eq!(bodies[1].v, Vect::ZERO);
        assert_eq!(c.jn_acc, Real::ONE);
        // Separating: no impulse (accumulated impulse cannot go negative).
        bodies[0].v = Vect::from_ints(-1, 0);
        c.jn_acc = Real::ZERO;
        c.solve(&mut bodies);
        assert_eq!(c.jn_acc, Real::ZERO);
        assert_eq!(bodies[0].v, Vect::from_ints(-1, 0));
    }

    #[test]
    fn friction_is_bounded_by_the_normal_impulse() {
        // Body b slides along +x on a static a, pressed down by 1 unit of normal impulse.
        let mut bodies = [body(0, 0), body(1, 0)];
        bodies[1].v = Vect::new(Real::from_int(5), -Real::ONE);
        let params = ContactParams {
            dt_inv: Real::from_int(60),
            slop: Real::ZERO,
            bias_coef: Real::ZERO,
            max_bias: Real::MAX,
            switches: SolverSwitches::ALL,
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n: Vect::Y,
            e: Real::ZERO,
            friction: Real::HALF,
            surface_vr: Vect::ZERO,
        };
        let mut c = ContactConstraint::new(&ManifoldPoint::default(), &bodies, &pair, &params);
        c.solve(&mut bodies);
        assert_eq!(c.jn_acc, Real::ONE);
        assert_eq!(c.jt_acc.abs(), Real::HALF);
        assert_eq!(bodies[1].v, Vect::new(real!(4.5), Real::ZERO));
    }

    /// Raw values over the whole range: small (ordinary scenes), large
    /// (near saturation) and the extremes.
    fn any_real() -> impl proptest::strategy::Strategy<Value = Real> {
        use proptest::prelude::*;
        prop_oneof![
            (-(1i64 << 40)..(1i64 << 40)).prop_map(Real::from_bits),
            // Tiny raw values times multiples of ½: rounding ties.
            (-64i64..64).prop_map(Real::from_bits),
            (-8i64..8).prop_map(|k| Real::from_bits(k << 31)),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| Real::from_bits(v >> s)),
            Just(Real::MAX),
            Just(Real::MIN),
        ]
    }

    fn solver_body(v: [Real; 8]) -> SolverBody {
        SolverBody {
            v: Vect::new(v[0], v[1]),
            w: v[2],
            v_bias: Vect::new(v[3], v[4]),
            w_bias: v[5],
            m_inv: v[6].abs(),
            i_inv: v[7].abs(),
        }
    }

    fn contact(v: &[Real]) -> ContactConstraint {
        let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
        let mut c = ContactConstraint {
            a: 0,
            b: 1,
            n: Vect::new(r(0), r(1)),
            rn_a: r(2),
            rn_b: r(3),
            rt_a: r(4),
            rt_b: r(5),
            kn_a: r(6),
            kn_b: r(7),
            kt_a: r(8),
            kt_b: r(9),
            m_inv_a: r(10),
            m_inv_b: r(11),
            n_mass: r(12),
            t_mass: r(13),
            bias_target: r(14),
            bounce: r(15),
            friction: r(16).abs(),
            surface_t: r(17),
            jn_acc: r(18).abs(),
            jt_acc: r(19),
            jb_acc: r(20).abs(),
            ..ContactConstraint::default()
        };
        c.check_range();
        c
    }

    /// Any value below `2^62` raw in magnitude, the largest included: the
    /// constants [`Bounded`] arithmetic accepts.
    fn bounded_real() -> impl proptest::strategy::Strategy<Value = Real> {
        use proptest::prelude::*;
        prop_oneof![
            any_real().prop_map(|r| Real::from_bits(r.to_bits() % (1 << 62))),
            Just(Real::from_bits((1 << 62) - 1)),
            Just(Real::from_bits(1 - (1 << 62))),
        ]
    }

    /// `solve_with` (fast path, fallback on overflow) against the
    /// saturating reference alone, for one feature combination.
    fn check_fast_path<const F: bool, const B: bool>(
        c: ContactConstraint,
        a: SolverBody,
        b: SolverBody,
    ) -> Result<(), proptest::test_runner::TestCaseError> {
        let mut fast = c;
        let mut bodies = [a, b];
        fast.solve_with::<F, B>(&mut bodies);
        let mut reference = c;
        let mut ref_bodies = [a, b];
        reference.solve_saturating::<F, B>(&mut ref_bodies, (reference.a, reference.b));
        proptest::prop_assert_eq!(bodies, ref_bodies);
        proptest::prop_assert_eq!(
            [fast.jb_acc, fast.jn_acc, fast.jt_acc],
            [reference.jb_acc, reference.jn_acc, reference.jt_acc]
        );
        Ok(())
    }

    /// The same for the warm start.
    fn check_fast_warm_start<const F: bool>(
        c: ContactConstraint,
        a: SolverBody,
        b: SolverBody,
        dt_coef: Real,
    ) -> Result<(), proptest::test_runner::TestCaseError> {
        let mut c = c;
        c.scale_cached_impulses::<F>(dt_coef);
        let mut bodies = [a, b];
        c.warm_start_with::<F>(&mut bodies, (c.a, c.b));
        let mut ref_bodies = [a, b];
        c.warm_start_saturating::<F>(&mut ref_bodies, (c.a, c.b));
        proptest::prop_assert_eq!(bodies, ref_bodies);
        Ok(())
    }

    /// A block of two rows from raw values (the matrix entries are free:
    /// the fast path must match the reference on any input).
    fn manifold_block(v: &[Real]) -> block::ManifoldBlock {
        let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
        block::ManifoldBlock {
            normal: block::NormalBlock {
                k11: r(0),
                k12: r(1),
                k22: r(2),
                inv11: r(3),
                inv12: r(4),
                inv22: r(5),
            },
            t2: Vect::new(r(6), r(7)),
            st_a: r(8),
            st_b: r(9),
            kt_a: r(10),
            kt_b: r(11),
            t_mass: r(12),
            bounded: false, // set by `check_fast_block` from the rows
        }
    }

    /// `block::solve_with` against the saturating reference alone.
    fn check_fast_block<const F: bool, const B: bool>(
        c1: ContactConstraint,
        c2: ContactConstraint,
        blk: &block::ManifoldBlock,
        a: SolverBody,
        b: SolverBody,
    ) -> Result<(), proptest::test_runner::TestCaseError> {
        let mut blk = *blk;
        blk.check_range(&c1, &c2);
        let blk = &blk;
        let (mut f1, mut f2) = (c1, c2);
        let mut bodies = [a, b];
        block::solve_with::<F, B>(&mut f1, &mut f2, blk, &mut bodies);
        let (mut r1, mut r2) = (c1, c2);
        let mut ref_bodies = [a, b];
        let ends = (r1.a, r1.b);
        block::solve_saturating::<F, B>(&mut r1, &mut r2, blk, &mut ref_bodies, ends);
        proptest::prop_assert_eq!(bodies, ref_bodies);
        proptest::prop_assert_eq!(
            [f1.jb_acc, f1.jn_acc, f1.jt_acc],
            [r1.jb_acc, r1.jn_acc, r1.jt_acc]
        );
        proptest::prop_assert_eq!(
            [f2.jb_acc, f2.jn_acc, f2.jt_acc],
            [r2.jb_acc, r2.jn_acc, r2.jt_acc]
        );
        Ok(())
    }

    /// A realistic two-contact face: box of half-size `h` on another body,
    /// contacts at `±x` along the face, normal `n`, both rows built by the
    /// pre-step from the same bodies.
    fn face_rows(
        bodies: &[SolverBody; 2],
        n: Vect,
        x: Real,
        h: Real,
        dist: [Real; 2],
    ) -> (ContactConstraint, ContactConstraint) {
        let t = n.perp();
        let params = ContactParams {
            dt_inv: Real::from_int(60),
            slop: Real::ZERO,
            bias_coef: Real::ratio(1, 10),
            max_bias: Real::MAX,
            switches: SolverSwitches::ALL,
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n,
            e: Real::ZERO,
            friction: Real::HALF,
            surface_vr: Vect::ZERO,
        };
        let row = |side: Real, d: Real| {
            let r1 = t * (side * x) + n * h;
            let r2 = t * (side * x) - n * h;
            let p = ManifoldPoint {
                r1,
                r2,
                dist: d,
                ..ManifoldPoint::default()
            };
            ContactConstraint::new(&p, bodies, &pair, &params)
        };
        (row(Real::ONE, dist[0]), row(-Real::ONE, dist[1]))
    }

    #[test]
    fn block_is_symmetric_in_its_two_contacts() {
        // Swapping the rows of a block swaps the impulses and leaves the
        // bodies' velocities exactly the same: the order of the contacts
        // in the manifold does not matter (what makes mirrors exact).
        let body = |vx: i32, vy: i32, w: i32| SolverBody {
            v: Vect::new(Real::ratio(vx, 7), Real::ratio(vy, 3)),
            w: Real::ratio(w, 11),
            v_bias: Vect::ZERO,
            w_bias: Real::ZERO,
            m_inv: Real::ONE,
            i_inv: Real::from_int(6),
        };
        for (vx, vy, w) in [(1, -5, 3), (-2, -1, -7), (0, -9, 0), (3, 2, 5)] {
            let bodies = [body(0, 0, 0), body(vx, vy, w)];
            let n = Vect::new(Real::ratio(3, 5), Real::ratio(4, 5));
            let (c1, c2) = face_rows(
                &bodies,
                n,
                Real::HALF,
                Real::HALF,
                [real!(-0.02), real!(-0.01)],
            );
            let blk = block::ManifoldBlock::new(&c1, &c2, &bodies, true)
                .unwrap_or_else(|| panic!("well conditioned"));
            let blk_swapped = block::ManifoldBlock::new(&c2, &c1, &bodies, true)
                .unwrap_or_else(|| panic!("well conditioned"));
            let (mut x1, mut x2, mut bx) = (c1, c2, bodies);
            let (mut y1, mut y2, mut by) = (c1, c2, bodies);
            for _ in 0..10 {
                block::solve_with::<true, true>(&mut x1, &mut x2, &blk, &mut bx);
                block::solve_with::<true, true>(&mut y2, &mut y1, &blk_swapped, &mut by);
            }
            assert_eq!(bx, by);
            assert_eq!((x1.jn_acc, x2.jn_acc), (y1.jn_acc, y2.jn_acc));
            assert_eq!((x1.jb_acc, x2.jb_acc), (y1.jb_acc, y2.jb_acc));
            assert_eq!((x1.jt_acc, x2.jt_acc), (y1.jt_acc, y2.jt_acc));
            // And the answer is a complementarity solution: both pushing
            // contacts end at zero normal velocity error (to rounding).
            let vn = |c: &ContactConstraint| {
                let dv = bx[1].v - bx[0].v;
                dv.dot(c.n) + bx[1].w * c.rn_b - bx[0].w * c.rn_a
            };
            for c in [&x1, &x2] {
                assert!(!c.jn_acc.is_negative());
                if c.jn_acc.is_positive() {
                    assert!(vn(c).abs() <= Real::from_bits(64), "{:?}", vn(c));
                } else {
                    assert!(!(vn(c) + Real::from_bits(64)).is_negative());
                }
            }
        }
    }

    #[test]
    fn nearly_coincident_contacts_are_not_a_block() {
        // Two contacts at the same lever arm make K singular: the condition
        // guard refuses the block and the rows are solved sequentially.
        let b = SolverBody {
            m_inv: Real::ONE,
            i_inv: Real::from_int(6),
            ..SolverBody::default()
        };
        let bodies = [SolverBody::default(), b];
        let (c1, c2) = face_rows(
            &bodies,
            Vect::Y,
            Real::from_bits(3),
            Real::HALF,
            [Real::ZERO; 2],
        );
        assert!(block::ManifoldBlock::new(&c1, &c2, &bodies, true).is_none());
        let (c1, c2) = face_rows(&bodies, Vect::Y, Real::HALF, Real::HALF, [Real::ZERO; 2]);
        assert!(block::ManifoldBlock::new(&c1, &c2, &bodies, true).is_some());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The block kernel's fast path is bit-identical to its saturating
        /// reference on any input, extremes and ties included.
        #[test]
        fn fast_block_iteration_equals_the_saturating_one(
            c1v in proptest::collection::vec(any_real(), 21),
            c2v in proptest::collection::vec(any_real(), 21),
            kv in proptest::collection::vec(any_real(), 13),
            av in proptest::array::uniform8(any_real()),
            bv in proptest::array::uniform8(any_real()),
        ) {
            let (c1, mut c2) = (contact(&c1v), contact(&c2v));
            c2.n = c1.n;
            c2.check_range();
            let blk = manifold_block(&kv);
            let (a, b) = (solver_body(av), solver_body(bv));
            check_fast_block::<true, true>(c1, c2, &blk, a, b)?;
            check_fast_block::<true, false>(c1, c2, &blk, a, b)?;
            check_fast_block::<false, true>(c1, c2, &blk, a, b)?;
            check_fast_block::<false, false>(c1, c2, &blk, a, b)?;
        }

        /// The same on blocks the pre-step builds from bounded, realistic
        /// inputs (where the fast path is taken, not only the fallback).
        #[test]
        fn fast_block_equals_the_saturating_one_on_built_blocks(
            vx in -1000i32..1000, vy in -1000i32..1000, w in -1000i32..1000,
            nx in -100i32..100, x in 1i32..100, h in 1i32..100,
            d1 in -100i32..10, d2 in -100i32..10, jn in 0i32..1000,
        ) {
            let len = Vect::new(Real::from_int(nx), Real::from_int(100)).length();
            let n = Vect::new(Real::from_int(nx) / len, Real::from_int(100) / len);
            let body = SolverBody {
                v: Vect::new(Real::ratio(vx, 100), Real::ratio(vy, 100)),
                w: Real::ratio(w, 100),
                m_inv: Real::ONE,
                i_inv: Real::from_int(6),
                ..SolverBody::default()
            };
            let bodies = [SolverBody { m_inv: Real::HALF, i_inv: Real::from_int(3), ..SolverBody::default() }, body];
            let (mut c1, mut c2) = face_rows(
                &bodies, n, Real::ratio(x, 100), Real::ratio(h, 100),
                [Real::ratio(d1, 1000), Real::ratio(d2, 1000)],
            );
            c1.jn_acc = Real::ratio(jn, 1000);
            c2.jn_acc = Real::ratio(jn, 700);
            // Realistic rows take the `Bounded` fast path: the range check
            // is not so strict that the fast path is never used.
            proptest::prop_assert!(c1.is_bounded() && c2.is_bounded());
            if let Some(blk) = block::ManifoldBlock::new(&c1, &c2, &bodies, true) {
                proptest::prop_assert!(blk.bounded);
                check_fast_block::<true, true>(c1, c2, &blk, bodies[0], bodies[1])?;
                check_fast_block::<false, false>(c1, c2, &blk, bodies[0], bodies[1])?;
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The unsaturated fast path is bit-identical to the saturating
        /// iteration on any input, extremes included.
        #[test]
        fn fast_iteration_equals_the_saturating_one(
            cv in proptest::collection::vec(any_real(), 21),
            av in proptest::array::uniform8(any_real()),
            bv in proptest::array::uniform8(any_real()),
            dt_coef in any_real(),
        ) {
            let (c, a, b) = (contact(&cv), solver_body(av), solver_body(bv));
            check_fast_warm_start::<true>(c, a, b, dt_coef)?;
            check_fast_warm_start::<false>(c, a, b, dt_coef)?;
            check_fast_path::<true, true>(c, a, b)?;
            check_fast_path::<true, false>(c, a, b)?;
            check_fast_path::<false, true>(c, a, b)?;
            check_fast_path::<false, false>(c, a, b)?;
        }

        /// The same with every constant of the dot products accepted by
        /// `below_2_62` (up to its edge) and free velocities and impulses:
        /// the `Bounded` kernel runs, and matches the reference on any
        /// input. A missing overflow case in its unflagged sums or
        /// negations fails here.
        #[test]
        fn bounded_iteration_equals_the_saturating_one(
            kv in proptest::collection::vec(bounded_real(), 10),
            cv in proptest::collection::vec(any_real(), 21),
            bk in proptest::collection::vec(bounded_real(), 6),
            av in proptest::array::uniform8(any_real()),
            bv in proptest::array::uniform8(any_real()),
        ) {
            let mut v = cv.clone();
            v[..10].copy_from_slice(&kv);
            let c1 = contact(&v);
            proptest::prop_assert!(c1.bounded);
            let mut c2 = contact(&cv);
            c2.n = c1.n;
            c2.rn_a = kv[3];
            c2.rn_b = kv[2];
            c2.kn_a = kv[7];
            c2.kn_b = kv[6];
            c2.check_range();
            let (a, b) = (solver_body(av), solver_body(bv));
            check_fast_path::<true, true>(c1, a, b)?;
            check_fast_path::<false, false>(c1, a, b)?;
            let mut k = cv[..13].to_vec();
            k[6..12].copy_from_slice(&bk);
            let blk = manifold_block(&k);
            check_fast_block::<true, true>(c1, c2, &blk, a, b)?;
            check_fast_block::<true, false>(c1, c2, &blk, a, b)?;
            check_fast_block::<false, true>(c1, c2, &blk, a, b)?;
        }
    }
}

#[cfg(test)]
mod pre_step_tests {
    //! The pre-step's fast path against the saturating pre-step it
    //! replaced, kept here verbatim as the oracle: bit for bit on free
    //! inputs (the fields need not be consistent), extremes and rounding
    //! ties included, and on the fast path (no fallback) in range.
    use super::kernel::tests::{any_real, moderate};
    use super::*;
    use proptest::prelude::*;

    /// `ContactConstraint::new` as it was (saturating `Real` and `Vect`
    /// operators, `Real::recip`).
    fn new_reference(
        c: &ManifoldPoint,
        bodies: &[SolverBody],
        pair: &PairParams,
        params: &ContactParams,
    ) -> ContactConstraint {
        let zero = SolverBody::default();
        let a = bodies.get(pair.a as usize).unwrap_or(&zero);
        let b = bodies.get(pair.b as usize).unwrap_or(&zero);
        let f = params.switches;
        let n = pair.n;
        let (rn_a, rn_b) = (c.r1.cross(n), c.r2.cross(n));
        let n_mass = k_scalar(a, b, c.r1, c.r2, n).map_or(Real::ZERO, Real::recip);
        let mut sc = ContactConstraint {
            a: pair.a,
            b: pair.b,
            n,
            rn_a,
            rn_b,
            kn_a: a.i_inv * rn_a,
            kn_b: b.i_inv * rn_b,
            m_inv_a: a.m_inv,
            m_inv_b: b.m_inv,
            n_mass,
            ..ContactConstraint::default()
        };
        if f.friction {
            let t = n.perp();
            let (rt_a, rt_b) = (c.r1.cross(t), c.r2.cross(t));
            sc.rt_a = rt_a;
            sc.rt_b = rt_b;
            sc.kt_a = a.i_inv * rt_a;
            sc.kt_b = b.i_inv * rt_b;
            sc.t_mass = k_scalar(a, b, c.r1, c.r2, t).map_or(Real::ZERO, Real::recip);
            sc.friction = pair.friction;
            sc.surface_t = pair.surface_vr.dot(t);
        }
        if f.bias_impulses {
            let overlap = (c.dist + params.slop).min(Real::ZERO);
            sc.bias_target = (-params.bias_coef * overlap * params.dt_inv).min(params.max_bias);
        }
        if f.restitution {
            sc.bounce = normal_relative_velocity(a, b, c.r1, c.r2, n) * pair.e;
        }
        if f.warm_starting {
            sc.jn_acc = c.jn_acc;
            if f.friction {
                sc.jt_acc = c.jt_acc;
            }
        }
        // The range flag (newer than this oracle) is a function of the fields.
        sc.check_range();
        sc
    }

    fn solver_body(v: [Real; 8]) -> SolverBody {
        SolverBody {
            v: Vect::new(v[0], v[1]),
            w: v[2],
            v_bias: Vect::new(v[3], v[4]),
            w_bias: v[5],
            m_inv: v[6].abs(),
            i_inv: v[7].abs(),
        }
    }

    /// One pre-step case from free values: the manifold point, the pair,
    /// the step's parameters (`v` has 19 values), the feature switches.
    fn case(v: &[Real], f: [bool; 4]) -> (ManifoldPoint, PairParams, ContactParams) {
        let r = |i: usize| v.get(i).copied().unwrap_or(Real::ZERO);
        let point = ManifoldPoint {
            r1: Vect::new(r(0), r(1)),
            r2: Vect::new(r(2), r(3)),
            dist: r(4),
            feature_id: 0,
            jn_acc: r(5),
            jt_acc: r(6),
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n: Vect::new(r(7), r(8)),
            e: r(9),
            friction: r(10),
            surface_vr: Vect::new(r(11), r(12)),
        };
        let params = ContactParams {
            dt_inv: r(13),
            slop: r(14),
            bias_coef: r(15),
            max_bias: r(16),
            switches: SolverSwitches {
                warm_starting: f[0],
                friction: f[1],
                restitution: f[2],
                bias_impulses: f[3],
            },
        };
        (point, pair, params)
    }

    /// `new` and `prepare` against the reference; returns whether the
    /// arithmetic stayed on the fast path.
    fn check(
        v: &[Real],
        f: [bool; 4],
        av: [Real; 8],
        bv: [Real; 8],
    ) -> Result<bool, TestCaseError> {
        let (point, pair, params) = case(v, f);
        let bodies = [solver_body(av), solver_body(bv)];
        let want = new_reference(&point, &bodies, &pair, &params);
        prop_assert_eq!(
            ContactConstraint::new(&point, &bodies, &pair, &params),
            want
        );
        // `prepare` is `new` with the tangent mass left to the caller.
        let (mut row, k_t) = ContactConstraint::prepare(&point, &bodies, &pair, &params);
        prop_assert_eq!(row.t_mass, Real::ZERO);
        row.t_mass = effective_mass(k_t);
        prop_assert_eq!(row, want);
        let mut u = Unsaturated::new();
        let _ = pre_step_terms(&point, &bodies[0], &bodies[1], &pair, &params, &mut u);
        Ok(!u.overflowed())
    }

    #[test]
    fn effective_mass_is_the_rounded_reciprocal() {
        let edges = [
            i64::MIN,
            -1,
            0,
            1,
            2,
            3,
            4,
            5,
            7,
            1 << 31,
            (1 << 32) - 1,
            1 << 32,
            (1 << 32) + 1,
            3 << 31,
            i64::MAX - 1,
            i64::MAX,
        ];
        for bits in edges {
            let k = Real::from_bits(bits);
            let want = if k.is_positive() {
                k.recip()
            } else {
                Real::ZERO
            };
            assert_eq!(effective_mass(k), want, "{bits}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        #[test]
        fn effective_mass_equals_recip(k in any_real()) {
            let want = if k.is_positive() { k.recip() } else { Real::ZERO };
            prop_assert_eq!(effective_mass(k), want);
        }

        /// The fast pre-step is bit-identical to the saturating one on any
        /// input, extremes and ties included, every feature combination.
        #[test]
        fn fast_pre_step_equals_the_saturating_one(
            v in proptest::collection::vec(any_real(), 17),
            f in proptest::array::uniform4(any::<bool>()),
            av in proptest::array::uniform8(any_real()),
            bv in proptest::array::uniform8(any_real()),
        ) {
            check(&v, f, av, bv)?;
        }

        /// The same on moderate inputs (within ±16), where the pre-step
        /// must stay on the fast path: the first test alone could pass
        /// with a fallback that always runs.
        #[test]
        fn fast_pre_step_stays_fast_in_range(
            v in proptest::collection::vec(moderate(), 17),
            f in proptest::array::uniform4(any::<bool>()),
            av in proptest::array::uniform8(moderate()),
            bv in proptest::array::uniform8(moderate()),
        ) {
            prop_assert!(check(&v, f, av, bv)?, "an in-range case left the fast path");
        }
    }
}
