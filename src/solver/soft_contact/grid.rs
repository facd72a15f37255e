//! The narrow lane grid, as a quality study (the `grid-study*` features,
//! off by default; `docs/numerics.md`, "The narrow lane grid").
//!
//! A wide kernel whose lane values fit 32 bits multiplies them as 32×32→64
//! products into 64-bit sums, where today's exact `Real` products need
//! 64×64→128. The study asks what that costs in quality before any such
//! kernel is written: with a study feature on, the scalar soft contact
//! passes round what such a kernel would hold in 32 bits to its grid, and
//! nothing else changes. Four designs, each narrowing more:
//! `grid-study-constants` only the row's constants (every product 64×32),
//! `grid-study-reads` also the velocities the solve and relax passes read
//! (the relative velocity's products 32×32), `grid-study` and
//! `grid-study-fine` also the bias and the impulses (every product 32×32),
//! on [`IMPULSE_BITS`] fraction bits. Velocities read go to
//! [`VELOCITY_BITS`]; the unit normal, friction, restitution and the soft
//! scales to [`UNIT_BITS`]; the lever arms across the normal and tangent,
//! the inverse masses and `I⁻¹ (r × d)` to [`ARM_BITS`]; the effective
//! masses to [`MASS_BITS`]. The bodies' velocities themselves stay
//! `Real`: a row's velocity changes are added at full resolution. A row
//! whose constants leave the grid's window (a value of 2^31 grid units or
//! more) keeps full precision for the step, and a pass whose velocities or
//! impulses leave it keeps full precision for that pass: the "full path"
//! of a real narrow kernel. The restitution pass (once a step, not a hot
//! loop) keeps full precision in every design.
//!
//! The module is compiled in every build (so it is checked and linted) and
//! folded away when [`ON`] is false: without the feature no bit moves.
use crate::math::Real;
use crate::solver::SolverBody;

/// Whether the soft contact passes run on a narrow grid (a study build).
/// The study runs the scalar kernels only.
pub(super) const ON: bool = cfg!(any(
    feature = "grid-study",
    feature = "grid-study-fine",
    feature = "grid-study-reads",
    feature = "grid-study-constants"
));

/// Whether the velocities the solve and relax passes read go to the lane
/// grid (every study build but `grid-study-constants`): the relative
/// velocity's products are then 32×32→64.
pub(super) const NARROW_READS: bool = cfg!(any(
    feature = "grid-study",
    feature = "grid-study-fine",
    feature = "grid-study-reads"
));

/// Whether biases and impulses go to a lane grid too (`grid-study`,
/// `grid-study-fine`: every product 32×32→64); else they keep full
/// precision and the products that apply an impulse are 64×32.
pub(super) const NARROW_IMPULSES: bool =
    cfg!(any(feature = "grid-study", feature = "grid-study-fine"));

/// Fraction bits of velocities read in the lanes (Q16.16: ±32,768 m/s,
/// steps of 1.5·10⁻⁵ m/s).
pub(super) const VELOCITY_BITS: u32 = 16;

/// Fraction bits of biases and impulses in the lanes: Q16.16 in
/// `grid-study`, Q8.24 (±128 N·s, steps of 6·10⁻⁸) in `grid-study-fine`.
pub(super) const IMPULSE_BITS: u32 = if cfg!(feature = "grid-study-fine") {
    24
} else {
    16
};
/// Fraction bits of values at most about 1: the normal's components,
/// friction, restitution, the soft scales (Q2.30).
pub(super) const UNIT_BITS: u32 = 30;
/// Fraction bits of lever arms across a direction, inverse masses and
/// `I⁻¹ (r × d)` (Q8.24: ±128, steps of 6·10⁻⁸).
pub(super) const ARM_BITS: u32 = 24;
/// Fraction bits of effective masses (Q16.16).
pub(super) const MASS_BITS: u32 = 16;

/// Whether `x` is a 32-bit lane value on a grid of `bits` fraction bits
/// (its magnitude below 2^31 grid units).
pub(super) fn fits(x: Real, bits: u32) -> bool {
    let limit = 1u64.checked_shl(63u32.saturating_sub(bits)).unwrap_or(0);
    x.to_bits().unsigned_abs() < limit
}

/// `x` on the grid of `bits` fraction bits: to nearest, ties away from
/// zero (symmetric under negation, as every rounding of the engine).
pub(super) fn round(x: Real, bits: u32) -> Real {
    // bits ≤ 31 for every grid: a shift of 1 to 32.
    let shift = 32u32.saturating_sub(bits).max(1);
    let half = 1u64 << shift.wrapping_sub(1);
    let m = (x.to_bits().unsigned_abs().saturating_add(half) >> shift) << shift;
    let m = i64::try_from(m).unwrap_or(i64::MAX);
    Real::from_bits(if x.is_negative() { m.wrapping_neg() } else { m })
}

/// Rounds `x` in place if it fits the grid; false if it does not.
pub(super) fn narrow(x: &mut Real, bits: u32) -> bool {
    if !fits(*x, bits) {
        return false;
    }
    *x = round(*x, bits);
    true
}

/// The two bodies with their velocities on the grid, as a narrow kernel
/// reads them; `None` if one leaves the window (the pass keeps full
/// precision).
pub(super) fn narrow_bodies(a: &SolverBody, b: &SolverBody) -> Option<(SolverBody, SolverBody)> {
    if !NARROW_READS {
        return Some((*a, *b));
    }
    let on_grid = |body: &SolverBody| {
        let mut c = *body;
        let ok = narrow(&mut c.v.x, VELOCITY_BITS)
            && narrow(&mut c.v.y, VELOCITY_BITS)
            && narrow(&mut c.w, VELOCITY_BITS);
        ok.then_some(c)
    };
    Some((on_grid(a)?, on_grid(b)?))
}

/// A bias or an impulse on its grid, if it fits (else unchanged).
pub(super) fn impulse(x: Real) -> Real {
    if !NARROW_IMPULSES {
        return x;
    }
    let mut y = x;
    narrow(&mut y, IMPULSE_BITS);
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_nearest_ties_away_and_symmetric() {
        let ulp = |k: i64| Real::from_bits(k);
        // One velocity grid step is 2^16 raw units; half of it ties away.
        let step = 1i64 << 16;
        assert_eq!(round(ulp(step / 2), VELOCITY_BITS), ulp(step));
        assert_eq!(round(ulp(step / 2 - 1), VELOCITY_BITS), ulp(0));
        assert_eq!(round(ulp(-step / 2), VELOCITY_BITS), ulp(-step));
        for k in [1, 12_345, step - 1, step + 1, 3 * step / 2, i64::MAX / 4] {
            assert_eq!(round(ulp(-k), VELOCITY_BITS), -round(ulp(k), VELOCITY_BITS));
            let r = round(ulp(k), ARM_BITS);
            assert!((r - ulp(k)).abs() <= ulp(1 << 7), "{k}");
        }
        // The range's ends round without a panic (a windowed value never
        // gets there).
        assert!(round(Real::MIN, UNIT_BITS).is_negative());
        assert!(round(Real::MAX, UNIT_BITS).is_positive());
    }

    #[test]
    fn windows_are_32_bit_lanes() {
        let lim = Real::from_int(32_768);
        assert!(fits(lim - Real::from_bits(1 << 16), VELOCITY_BITS));
        assert!(!fits(lim, VELOCITY_BITS));
        assert!(!fits(-lim, VELOCITY_BITS));
        assert!(fits(Real::ONE, UNIT_BITS) && !fits(Real::from_int(2), UNIT_BITS));
        assert!(fits(Real::from_int(127), ARM_BITS) && !fits(Real::from_int(128), ARM_BITS));
    }
}
