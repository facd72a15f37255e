//! SplitMix64: the scenes' deterministic random numbers.
//!
//! Scenes must be pure functions of their parameters on every platform, so
//! randomness comes from an integer generator and is turned into [`Real`]s
//! by bit manipulation only (no float is ever involved). SplitMix64 (Steele,
//! Lea and Flood, 2014) is tiny, has a full 2^64 period and passes BigCrush;
//! that is plenty for placing bodies. The standard seed is [`SEED`].
use tamias2d::math::{Real, Vect};

/// Seed of every built-in scene that needs randomness (scenes/README.md).
pub const SEED: u64 = 45073;

/// The SplitMix64 generator.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator with the given seed.
    pub const fn new(seed: u64) -> SplitMix64 {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` on the full `Real` grid: the top 32 bits are the
    /// fraction.
    pub fn unit(&mut self) -> Real {
        Real::from_bits((self.next_u64() >> 32) as i64)
    }

    /// Uniform in `[-1, 1)` on the full `Real` grid (33 random bits).
    pub fn signed_unit(&mut self) -> Real {
        // (bits >> 31) is in [0, 2^33); minus 2^32 gives raw values in
        // [-2^32, 2^32): the subtraction never saturates.
        Real::from_bits(((self.next_u64() >> 31) as i64).saturating_sub(1i64 << 32))
    }

    /// Uniform in `[lo, hi)`: `lo + (hi − lo)·u`, rounded to nearest.
    pub fn range(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in the open unit disk, by rejection sampling: draw `x` then
    /// `y` in `[-1, 1)` until `x² + y² < 1` (tested exactly on the raw bits).
    /// Accepts π/4 ≈ 79% of the draws.
    pub fn in_unit_disk(&mut self) -> Vect {
        loop {
            let x = self.signed_unit();
            let y = self.signed_unit();
            // |raw| ≤ 2^32: the exact squares sum to at most 2^65.
            if raw_sq(x).saturating_add(raw_sq(y)) < 1u128 << 64 {
                return Vect::new(x, y);
            }
        }
    }

    /// Uniform in the disk of `radius` around the origin: a unit-disk sample
    /// scaled (exact for an integer radius).
    pub fn in_disk(&mut self, radius: Real) -> Vect {
        self.in_unit_disk().mult(radius)
    }
}

/// `|a|²` of raw bits (units of 2^-64), exact: at most 2^126.
fn raw_sq(a: Real) -> u128 {
    let m = u128::from(a.to_bits().unsigned_abs());
    // m ≤ 2^63: m² ≤ 2^126, never saturates.
    m.saturating_mul(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_reference_sequence() {
        // Reference values of SplitMix64 for seed 0 (Vigna's splitmix64.c).
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
    }

    #[test]
    fn samples_stay_in_their_ranges() {
        let mut r = SplitMix64::new(SEED);
        for _ in 0..10_000 {
            let u = r.unit();
            assert!(u >= Real::ZERO && u < Real::ONE);
            let s = r.signed_unit();
            assert!(s >= -Real::ONE && s < Real::ONE);
            let p = r.in_unit_disk();
            assert!(p.x.abs() < Real::ONE && p.y.abs() < Real::ONE);
            let q = r.range(tamias2d::real!(0.25), Real::HALF);
            assert!(q >= tamias2d::real!(0.25) && q <= Real::HALF);
        }
    }
}
