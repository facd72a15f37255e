//! The solver row of the two distance joints, pin and slide: an impulse
//! along one axis `n` between two anchors. They differ only in the clamp
//! of the accumulated impulse (and so in whether a row can be inactive),
//! chosen at compile time by `ONE_SIDED`.
use super::kernel::{accumulate, soften, JointKernel};
use super::prep::Prep;
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{apply_impulses, effective_mass, mult, normal_relative_velocity};
use crate::solver::softness::Softness;
use crate::solver::{k_scalar_body, SolverBody};

/// The row of a distance along `n` for one sub-step. A pin joint's
/// ([`PinRow`], `ONE_SIDED = false`) holds the distance both ways, its
/// accumulated impulse within `±j_max`. A slide joint's ([`SlideRow`],
/// `ONE_SIDED = true`) only pulls back towards the violated limit, within
/// `[−j_max, 0]`, and is inactive when no limit is violated (`n = 0`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisRow<const ONE_SIDED: bool> {
    r1: Vect,
    r2: Vect,
    /// Unit direction of the impulse on b (0: an inactive slide row).
    n: Vect,
    /// `1/k` along `n`.
    n_mass: Real,
    bias: Real,
}

/// A pin joint's row.
pub(crate) type PinRow = AxisRow<false>;

/// A slide joint's row.
pub(crate) type SlideRow = AxisRow<true>;

impl<const ONE_SIDED: bool> AxisRow<ONE_SIDED> {
    /// The row along `n` at the arms `r1`, `r2` (world orientation): the
    /// effective mass along `n` and the bias velocity
    /// `−bias_coef·error/dt`, capped at `max_bias`.
    pub(crate) fn along(p: &Prep<'_>, r1: Vect, r2: Vect, n: Vect, error: Real) -> Self {
        let k = k_scalar_body(p.sa, r1, n) + k_scalar_body(p.sb, r2, n);
        AxisRow {
            r1,
            r2,
            n,
            n_mass: effective_mass(k),
            bias: p.bias(error),
        }
    }
}

impl<const ONE_SIDED: bool> JointKernel for AxisRow<ONE_SIDED> {
    type Impulse = Real;

    /// A slide row inside the limits does nothing (and keeps a zero
    /// accumulator: the cached impulse is dropped); a pin row always acts.
    #[inline(always)]
    fn is_active(&self) -> bool {
        !ONE_SIDED || self.n != Vect::ZERO
    }

    #[inline(always)]
    fn relax(&mut self) {
        self.bias = Real::ZERO;
    }

    #[inline(always)]
    fn apply<A: FixedArith>(&self, a: &mut SolverBody, b: &mut SolverBody, j: Real, ar: &mut A) {
        apply_along(a, b, self.r1, self.r2, self.n, j, ar);
    }

    /// Drive the relative velocity along `n` to the bias, the accumulated
    /// impulse clamped to `±j_max` (pin) or `[−j_max, 0]` (slide).
    #[inline(always)]
    fn iterate<A: FixedArith>(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        acc: &mut Real,
        j_max: Real,
        soft: Softness,
        ar: &mut A,
    ) {
        let vrn = normal_relative_velocity(a, b, self.r1, self.r2, self.n, ar);
        let err = ar.sub(self.bias, vrn);
        let jn = soften(ar.mul(err, self.n_mass), *acc, soft, ar);
        let hi = if ONE_SIDED { Real::ZERO } else { j_max };
        let d = accumulate(acc, jn, -j_max, hi, ar);
        self.apply(a, b, d, ar);
    }
}

/// The impulse `n·j` at the anchors `r1` of `a` (−) and `r2` of `b` (+):
/// the warm start and the change of a row along one axis (the distance
/// joints', the damped spring's).
#[inline(always)]
pub(crate) fn apply_along<A: FixedArith>(
    a: &mut SolverBody,
    b: &mut SolverBody,
    r1: Vect,
    r2: Vect,
    n: Vect,
    j: Real,
    ar: &mut A,
) {
    let p = mult(n, j, ar);
    apply_impulses(a, b, r1, r2, p, ar);
}

#[cfg(test)]
impl<const ONE_SIDED: bool> AxisRow<ONE_SIDED> {
    /// A row from free values (the kernel tests); a slide row is inactive
    /// when `n` is 0.
    pub(crate) fn from_raw(v: &[Real]) -> Self {
        use crate::constraint::kernel::tests::{at, vect_at};
        AxisRow {
            r1: vect_at(v, 0),
            r2: vect_at(v, 2),
            n: vect_at(v, 4),
            n_mass: at(v, 6),
            bias: at(v, 7),
        }
    }
}
