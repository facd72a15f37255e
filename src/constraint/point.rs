//! The shared arithmetic of the point constraints (pivot and groove
//! joints): the inverse of their 2×2 effective-mass matrix ([`KInv`]) and
//! the root-free length clamp of their accumulated impulse ([`clamp_len`]).
use crate::math::exact::int::{sum_sq, wide_mul_u64};
use crate::math::{FixedArith, Real, Vect};
use crate::solver::kernel::{relative_velocity, sub};
use crate::solver::SolverBody;

/// The inverse of the 2×2 effective-mass matrix of a point constraint
/// (Chipmunk's `k_tensor`), symmetric: `[[k11, k12], [k12, k22]]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KInv {
    k11: Real,
    k12: Real,
    k22: Real,
}

impl KInv {
    /// `K = (m_a⁻¹ + m_b⁻¹)·I + I_a⁻¹·[r1]ᵀ[r1] + I_b⁻¹·[r2]ᵀ[r2]` with
    /// `[r]ᵀ[r] = [[r_y², −r_x r_y], [−r_x r_y, r_x²]]` (an impulse `j` at `r`
    /// changes the point velocity by `m⁻¹ j + I⁻¹ (r × j) r⊥`). `K` is
    /// symmetric positive definite when a body can move, so `K⁻¹ =
    /// adj(K)/det K`; a determinant that is not positive (two immovable
    /// bodies, or rounding to 0) gives `K⁻¹ = 0`: no impulse. In fixed point
    /// `det` has the absolute resolution of `Real`, so for heavy bodies
    /// (inverse masses near 10⁻³) `K⁻¹` is accurate to about 10⁻⁴ relative;
    /// that only slows the iterations' convergence, not their fixed point.
    pub(crate) fn new(a: &SolverBody, b: &SolverBody, r1: Vect, r2: Vect) -> KInv {
        let m_sum = a.m_inv + b.m_inv;
        let k11 = m_sum + a.i_inv * r1.y * r1.y + b.i_inv * r2.y * r2.y;
        let k12 = -(a.i_inv * r1.x * r1.y) - b.i_inv * r2.x * r2.y;
        let k22 = m_sum + a.i_inv * r1.x * r1.x + b.i_inv * r2.x * r2.x;
        let det = Real::mul_sub2(k11, k22, k12, k12);
        if det.is_positive() {
            KInv {
                k11: k22 / det,
                k12: -(k12 / det),
                k22: k11 / det,
            }
        } else {
            KInv {
                k11: Real::ZERO,
                k12: Real::ZERO,
                k22: Real::ZERO,
            }
        }
    }

    /// `K⁻¹·e`.
    #[inline(always)]
    pub(crate) fn apply<A: FixedArith>(&self, e: Vect, ar: &mut A) -> Vect {
        Vect::new(
            ar.mul_add2(self.k11, e.x, self.k12, e.y),
            ar.mul_add2(self.k12, e.x, self.k22, e.y),
        )
    }

    /// The impulse `K⁻¹ (bias − vr)` that cancels the anchors' relative
    /// velocity `vr` minus the bias (pivot and groove joints).
    #[inline(always)]
    pub(crate) fn point_impulse<A: FixedArith>(
        &self,
        a: &SolverBody,
        b: &SolverBody,
        r1: Vect,
        r2: Vect,
        bias: Vect,
        ar: &mut A,
    ) -> Vect {
        let vr = relative_velocity(a, b, r1, r2, ar);
        let e = sub(bias, vr, ar);
        self.apply(e, ar)
    }
}

#[cfg(test)]
impl KInv {
    /// A matrix from free values (the kernel tests).
    pub(crate) fn from_raw(v: &[Real]) -> KInv {
        use crate::constraint::kernel::tests::at;
        KInv {
            k11: at(v, 0),
            k12: at(v, 1),
            k22: at(v, 2),
        }
    }
}

/// `v` shortened to length `max` if longer: `v.clamp(max)`, bit for bit,
/// without its square root when `v` is kept.
///
/// Why: the accumulated impulse is clamped every iteration, and is almost
/// always far inside the bound (`max_force` is unbounded by default, and
/// then `j_max = max_force·dt` is huge but not `Real::MAX`), while the
/// root is most of an iteration's cost. `Vect::clamp` keeps `v` iff
/// `⌊√S⌋ ≤ L`, with `S = |v|²` exact in raw units and `L = max(max, 0)`
/// raw, i.e. iff `S < (L + 1)²`, i.e. iff `S ≤ L·(L + 2)`: an exact
/// integer test (`L < 2^63`, so `L·(L + 2) < 2^127`). `Real::MAX` bounds
/// every length. Only a vector longer than `max` takes the root.
#[inline(always)]
pub(crate) fn clamp_len(v: Vect, max: Real) -> Vect {
    if max == Real::MAX {
        return v;
    }
    let l = max.to_bits().max(0).unsigned_abs();
    // l < 2^63 (not Real::MAX), so l + 2 never saturates.
    let bound = wide_mul_u64(l, l.saturating_add(2));
    if sum_sq(v.x.to_bits(), v.y.to_bits()) <= bound {
        v
    } else {
        v.clamp(max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::kernel::tests::any_real;
    use proptest::prelude::*;

    #[test]
    fn clamp_len_keeps_the_boundary_exactly_as_vect_clamp() {
        // (3, 4) raw has length exactly 5 raw; ⌊√S⌋ ≤ L up to S = L·(L + 2).
        let r = Real::from_bits;
        for (x, y, l) in [
            (3, 4, 5),
            (3, 4, 4),
            (5, 0, 4),
            (0, 0, 0),
            (1, 1, 0),
            (1, 1, 1),
        ] {
            let v = Vect::new(r(x), r(y));
            assert_eq!(clamp_len(v, r(l)), v.clamp(r(l)), "{x} {y} {l}");
        }
        // At L = 5 the bound is S ≤ 35: S = 34 is kept (⌊√34⌋ = 5), S = 36 is not.
        assert_eq!(
            clamp_len(Vect::new(r(5), r(3)), r(5)),
            Vect::new(r(5), r(3))
        );
        assert_ne!(
            clamp_len(Vect::new(r(6), r(0)), r(5)),
            Vect::new(r(6), r(0))
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5000))]
        /// The root-free test gives `Vect::clamp`'s bits on any input.
        #[test]
        fn clamp_len_is_vect_clamp(x in any_real(), y in any_real(), max in any_real()) {
            let v = Vect::new(x, y);
            prop_assert_eq!(clamp_len(v, max), v.clamp(max));
            // Near the boundary: max = the vector's own length, ±1 ulp.
            let l = v.length();
            for m in [l, l - Real::from_bits(1), l + Real::from_bits(1)] {
                prop_assert_eq!(clamp_len(v, m), v.clamp(m));
            }
        }
    }
}
