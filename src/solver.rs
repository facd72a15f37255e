//! The impulse half of the MIS Collision Solver (§10): relative velocities,
//! effective masses, and normal, friction and bias impulses.
//!
//! # Glossary
//! * `a`, `b`: the two bodies of a contact; the normal `n` points from a to b.
//! * `r1`, `r2`: contact point relative to a's and b's centre of gravity.
//! * `vr`: relative velocity of b with respect to a at the contact,
//!   `(v_b + ω_b × r2) − (v_a + ω_a × r1)`.
//! * `k`: effective inverse mass along a direction `d`,
//!   `k = m_a⁻¹ + m_b⁻¹ + I_a⁻¹ (r1 × d)² + I_b⁻¹ (r2 × d)²`; an impulse `j`
//!   along `d` changes `vr·d` by `k·j`, so `j = −Δ/k` cancels a velocity error
//!   `Δ`. `n_mass = 1/k(n)` and `t_mass = 1/k(t)` are computed once per step
//!   (pre-step): the iterations only multiply.
//! * `jn_acc`, `jt_acc`: accumulated normal and tangent (friction) impulses.
//!   Clamping the *accumulated* value (`jn_acc ≥ 0`, `|jt_acc| ≤ μ·jn_acc`)
//!   instead of each increment lets later iterations take back impulse, which
//!   is what makes sequential impulses converge (Catto, GDC 2006).
//! * `bias`: target separation velocity that removes penetration beyond the
//!   slop: `bias = −bias_coef · min(0, dist + slop) / dt`. It is applied as a
//!   *pseudo-velocity* (`v_bias`, `ω_bias`, `j_bias`) that moves positions in
//!   the next position update but adds no momentum, so resolving overlap does
//!   not make objects bounce.
//! * `bounce`: restitution target, `e · (vr·n)` at the start of the step, so
//!   the normal impulse drives `vr·n` to `−bounce`.
//!
//! Bodies are copied into a contiguous [`SolverBody`] array for the
//! iterations (inverse masses and velocities side by side); static and
//! kinematic bodies have zero inverse mass, so impulses leave them unchanged.
use core::fmt;

use crate::math::{Real, Vect};

/// The per-body data the iterations touch, stored contiguously.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverBody {
    /// Linear velocity.
    pub v: Vect,
    /// Angular velocity.
    pub w: Real,
    /// Linear pseudo-velocity from bias impulses.
    pub v_bias: Vect,
    /// Angular pseudo-velocity from bias impulses.
    pub w_bias: Real,
    /// Inverse mass (0 for infinite mass).
    pub m_inv: Real,
    /// Inverse moment (0 for infinite moment).
    pub i_inv: Real,
}

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

/// The persistent part of one contact: where it is and the impulses it has
/// accumulated (carried to the next step for warm starting).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct ContactConstraint {
    /// Contact point relative to body a's centre of gravity.
    pub r1: Vect,
    /// Contact point relative to body b's centre of gravity.
    pub r2: Vect,
    /// Signed separation (negative when penetrating).
    pub dist: Real,
    /// Feature id: matches this contact with last step's for warm starting.
    pub id: u32,
    /// Accumulated normal impulse (warm-started).
    pub jn_acc: Real,
    /// Accumulated friction impulse (warm-started).
    pub jt_acc: Real,
}

/// Which parts of the contact model the solver computes (from the space's
/// [`Settings`](crate::space::Settings)). A part switched off is skipped,
/// not computed and discarded: the pre-step leaves its constants at zero,
/// the warm-start stage is not run, and the iterations use a routine
/// compiled without the friction or bias row ([`SolverContact::solve_with`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactFeatures {
    /// Start from last step's impulses (otherwise from zero).
    pub warm_starting: bool,
    /// Friction impulses (otherwise as if every friction were 0).
    pub friction: bool,
    /// Restitution targets (otherwise as if every elasticity were 0).
    pub restitution: bool,
    /// Bias impulses (otherwise overlap is never corrected).
    pub bias: bool,
}

impl ContactFeatures {
    /// Everything on (the default settings).
    pub const ALL: ContactFeatures = ContactFeatures {
        warm_starting: true,
        friction: true,
        restitution: true,
        bias: true,
    };
}

impl Default for ContactFeatures {
    fn default() -> Self {
        ContactFeatures::ALL
    }
}

/// Step-wide constants of the contact solver.
#[derive(Clone, Copy, Debug)]
pub struct ContactParams {
    /// `1/dt`.
    pub dt_inv: Real,
    /// Allowed overlap that is not corrected.
    pub slop: Real,
    /// Fraction of the remaining overlap corrected this step, `1 − bias^dt`.
    pub bias_coef: Real,
    /// Largest bias velocity (Chipmunk's arbiter `maxBias`, unbounded by default).
    pub max_bias: Real,
    /// The parts of the model computed this step.
    pub features: ContactFeatures,
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

/// One contact prepared for the iterations: everything the inner loop needs,
/// side by side, with every division and cross product done once.
///
/// With `t = perp(n)`, the velocity along a direction `d` at the contact is
/// `(v_b − v_a)·d + ω_b (r2 × d) − ω_a (r1 × d)`, so storing `r × n` and
/// `r × t` turns each relative velocity into one 4-term dot product (one
/// rounding), and storing `I⁻¹ (r × d)` turns each angular impulse into one
/// multiplication.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverContact {
    /// Solver index of body a.
    pub a: u32,
    /// Solver index of body b.
    pub b: u32,
    /// Index of the arbiter and of the contact in it (for the write-back).
    pub arbiter: u32,
    /// Contact slot in the arbiter.
    pub slot: u32,
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
    pub m_a: Real,
    pub m_b: Real,
    /// `1/k(n)`, `1/k(t)`.
    pub n_mass: Real,
    pub t_mass: Real,
    /// Target bias velocity and restitution target.
    pub bias: Real,
    pub bounce: Real,
    /// Friction coefficient and tangential surface velocity.
    pub friction: Real,
    pub surface_t: Real,
    /// Accumulated impulses.
    pub jn_acc: Real,
    pub jt_acc: Real,
    pub j_bias: Real,
}

impl SolverContact {
    /// Pre-step for one contact (Chipmunk `preStep`): effective masses
    /// `1/k`, bias `−bias_coef·min(0, dist + slop)/dt` and bounce
    /// `e·(vr·n)` from the velocities before gravity. The only divisions of
    /// the contact solver happen here. Parts switched off in
    /// `params.features` are left at zero: without friction no tangent
    /// terms (and no tangent effective mass, a division), without
    /// restitution no bounce, without bias no bias target, without warm
    /// starting no cached impulses.
    pub fn new(
        c: &ContactConstraint,
        bodies: &[SolverBody],
        pair: &PairParams,
        params: &ContactParams,
    ) -> SolverContact {
        let zero = SolverBody::default();
        let a = bodies.get(pair.a as usize).unwrap_or(&zero);
        let b = bodies.get(pair.b as usize).unwrap_or(&zero);
        let f = params.features;
        let n = pair.n;
        let (rn_a, rn_b) = (c.r1.cross(n), c.r2.cross(n));
        // A zero k (two infinite masses) gives mass 0: the contact applies no impulse.
        let n_mass = k_scalar(a, b, c.r1, c.r2, n).map_or(Real::ZERO, Real::recip);
        let mut sc = SolverContact {
            a: pair.a,
            b: pair.b,
            n,
            rn_a,
            rn_b,
            kn_a: a.i_inv * rn_a,
            kn_b: b.i_inv * rn_b,
            m_a: a.m_inv,
            m_b: b.m_inv,
            n_mass,
            ..SolverContact::default()
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
        if f.bias {
            let overlap = (c.dist + params.slop).min(Real::ZERO);
            sc.bias = (-params.bias_coef * overlap * params.dt_inv).min(params.max_bias);
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
        sc
    }

    /// Applies the impulse `n·jn + t·jt` to the velocities (−a, +b).
    #[inline(always)]
    fn apply(&self, a: &mut SolverBody, b: &mut SolverBody, jn: Real, jt: Real) {
        let n = self.n;
        // P = n·jn + perp(n)·jt, with perp(n) = (−n.y, n.x).
        let p = Vect::new(
            Real::mul_sub2(n.x, jn, n.y, jt),
            Real::mul_add2(n.y, jn, n.x, jt),
        );
        a.v -= p * self.m_a;
        a.w -= Real::mul_add2(self.kn_a, jn, self.kt_a, jt);
        b.v += p * self.m_b;
        b.w += Real::mul_add2(self.kn_b, jn, self.kt_b, jt);
    }

    /// Applies the normal impulse `n·jn` alone (the friction-free
    /// [`apply`](Self::apply): `apply(a, b, jn, 0)` gives the same bits).
    #[inline(always)]
    fn apply_normal(&self, a: &mut SolverBody, b: &mut SolverBody, jn: Real) {
        let p = self.n * jn;
        a.v -= p * self.m_a;
        a.w -= self.kn_a * jn;
        b.v += p * self.m_b;
        b.w += self.kn_b * jn;
    }

    /// Applies the cached (warm-start) impulse, scaled by `dt_coef = dt/prev_dt`.
    pub fn warm_start(&self, bodies: &mut [SolverBody], dt_coef: Real) {
        let Some((mut a, mut b)) = load_pair(bodies, self.a, self.b) else {
            return;
        };
        self.apply(&mut a, &mut b, self.jn_acc * dt_coef, self.jt_acc * dt_coef);
        store_pair(bodies, self.a, a, self.b, b);
    }

    /// [`warm_start`](Self::warm_start) of the normal impulse alone (friction
    /// off: `jt_acc` is 0).
    pub fn warm_start_normal(&self, bodies: &mut [SolverBody], dt_coef: Real) {
        let Some((mut a, mut b)) = load_pair(bodies, self.a, self.b) else {
            return;
        };
        self.apply_normal(&mut a, &mut b, self.jn_acc * dt_coef);
        store_pair(bodies, self.a, a, self.b, b);
    }

    /// One iteration (Chipmunk `applyImpulse`): bias, normal and friction.
    ///
    /// * bias: `jb = (bias − vb·n)·n_mass` on the pseudo-velocities,
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
    #[inline]
    pub fn solve_with<const FRICTION: bool, const BIAS: bool>(
        &mut self,
        bodies: &mut [SolverBody],
    ) {
        let Some((mut a, mut b)) = load_pair(bodies, self.a, self.b) else {
            return;
        };
        let n = self.n;

        if BIAS {
            let dvb = b.v_bias - a.v_bias;
            let vbn = Real::dot4(
                [dvb.x, dvb.y, b.w_bias, a.w_bias],
                [n.x, n.y, self.rn_b, -self.rn_a],
            );
            let jb_old = self.j_bias;
            self.j_bias = (jb_old + (self.bias - vbn) * self.n_mass).max(Real::ZERO);
            let djb = self.j_bias - jb_old;
            if !djb.is_zero() {
                let p = n * djb;
                a.v_bias -= p * self.m_a;
                a.w_bias -= self.kn_a * djb;
                b.v_bias += p * self.m_b;
                b.w_bias += self.kn_b * djb;
            }
        }

        let dv = b.v - a.v;
        let vn = Real::dot4([dv.x, dv.y, b.w, a.w], [n.x, n.y, self.rn_b, -self.rn_a]);
        // Computed before the normal update, as in `solve` before the
        // switches existed: the same order keeps the default routine's
        // machine code (and cost) what it was.
        let vt = if FRICTION {
            Real::dot4([dv.x, dv.y, b.w, a.w], [-n.y, n.x, self.rt_b, -self.rt_a]) + self.surface_t
        } else {
            Real::ZERO
        };
        let jn_old = self.jn_acc;
        self.jn_acc = (jn_old - (self.bounce + vn) * self.n_mass).max(Real::ZERO);

        if FRICTION {
            let jt_max = self.friction * self.jn_acc;
            let jt_old = self.jt_acc;
            self.jt_acc = (jt_old - vt * self.t_mass).clamp(-jt_max, jt_max);
            self.apply(&mut a, &mut b, self.jn_acc - jn_old, self.jt_acc - jt_old);
        } else {
            self.apply_normal(&mut a, &mut b, self.jn_acc - jn_old);
        }
        store_pair(bodies, self.a, a, self.b, b);
    }
}

/// Copies out two distinct solver bodies (`None` if equal or out of range).
#[inline(always)]
fn load_pair(bodies: &[SolverBody], a: u32, b: u32) -> Option<(SolverBody, SolverBody)> {
    if a == b {
        return None;
    }
    Some((*bodies.get(a as usize)?, *bodies.get(b as usize)?))
}

#[inline(always)]
fn store_pair(bodies: &mut [SolverBody], ia: u32, a: SolverBody, ib: u32, b: SolverBody) {
    if let Some(slot) = bodies.get_mut(ia as usize) {
        *slot = a;
    }
    if let Some(slot) = bodies.get_mut(ib as usize) {
        *slot = b;
    }
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
            features: ContactFeatures::ALL,
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n: Vect::X,
            e: Real::ZERO,
            friction: Real::ZERO,
            surface_vr: Vect::ZERO,
        };
        let mut c = SolverContact::new(&ContactConstraint::default(), &bodies, &pair, &params);
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
            features: ContactFeatures::ALL,
        };
        let pair = PairParams {
            a: 0,
            b: 1,
            n: Vect::Y,
            e: Real::ZERO,
            friction: Real::HALF,
            surface_vr: Vect::ZERO,
        };
        let mut c = SolverContact::new(&ContactConstraint::default(), &bodies, &pair, &params);
        c.solve(&mut bodies);
        assert_eq!(c.jn_acc, Real::ONE);
        assert_eq!(c.jt_acc.abs(), Real::HALF);
        assert_eq!(bodies[1].v, Vect::new(real!(4.5), Real::ZERO));
    }
}
