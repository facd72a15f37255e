//! Soft constraint coefficients (the soft step's): a constraint corrects
//! its position error like a damped spring of frequency `f` (hertz) and
//! damping ratio `ζ` would, solved implicitly over a sub-step `h`.
//!
//! With `ω = 2πf`, `a₁ = 2ζ + hω`, `a₂ = hω·a₁` and `a₃ = 1/(1 + a₂)`, the
//! impulse of a row with effective mass `m`, velocity error `Ċ`, position
//! error `C` and accumulated impulse `λ` is
//! `−m·mass_scale·(Ċ + bias_rate·C) − impulse_scale·λ`, where
//! `bias_rate = ω/a₁`, `mass_scale = a₂·a₃` and `impulse_scale = a₃`.
//! Frequency 0 is a rigid row without bias (`bias_rate = 0`,
//! `mass_scale = 1`, `impulse_scale = 0`), which is also what the relax
//! pass uses. Computed once per step, exactly, in fixed point.
use crate::math::Real;

/// The coefficients of one stiffness, damping ratio and sub-step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Softness {
    /// Position error corrected per second, `ω/a₁` (1/s).
    pub bias_rate: Real,
    /// Fraction of the rigid impulse applied, `a₂/(1 + a₂)`.
    pub mass_scale: Real,
    /// Fraction of the accumulated impulse taken back, `1/(1 + a₂)`.
    pub impulse_scale: Real,
}

impl Default for Softness {
    fn default() -> Self {
        Softness::RIGID
    }
}

impl Softness {
    /// A rigid row without bias (frequency 0, and the relax pass).
    pub const RIGID: Softness = Softness {
        bias_rate: Real::ZERO,
        mass_scale: Real::ONE,
        impulse_scale: Real::ZERO,
    };

    /// The coefficients of frequency `hertz` and damping ratio `zeta` on
    /// a sub-step of `h`; [`RIGID`](Self::RIGID) for a frequency or a
    /// sub-step of 0 (negative values count as 0). Saturating arithmetic
    /// throughout; the settings' bounds keep every term far from the range.
    pub fn new(hertz: Real, zeta: Real, h: Real) -> Softness {
        if !hertz.is_positive() || !h.is_positive() {
            return Softness::RIGID;
        }
        let zeta = zeta.max(Real::ZERO);
        let omega = Real::TAU * hertz;
        let h_omega = h * omega;
        let a1 = (zeta + zeta) + h_omega;
        let a2 = h_omega * a1;
        let a3 = (Real::ONE + a2).recip();
        Softness {
            // a1 ≥ hω > 0 unless hω rounds to 0: then no bias at all.
            bias_rate: if a1.is_zero() { Real::ZERO } else { omega / a1 },
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }

    /// True for [`RIGID`](Self::RIGID)'s scales (the impulse is the rigid
    /// row's, unchanged).
    #[inline(always)]
    pub fn is_rigid(&self) -> bool {
        self.mass_scale == Real::ONE && self.impulse_scale.is_zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_frequency_is_rigid() {
        let h = Real::lit("0.004166666");
        assert_eq!(Softness::new(Real::ZERO, Real::ONE, h), Softness::RIGID);
        assert_eq!(
            Softness::new(Real::ONE, Real::ONE, Real::ZERO),
            Softness::RIGID
        );
        assert!(Softness::RIGID.is_rigid());
    }

    #[test]
    fn coefficients_match_the_closed_form() {
        // 30 Hz, ζ = 10, h = 1/240: ω = 188.5, a1 = 20.785, a2 = 16.32,
        // a3 = 0.05772: bias_rate 9.069, mass_scale 0.9423.
        let s = Softness::new(
            Real::lit("30"),
            Real::lit("10"),
            Real::ONE / Real::lit("240"),
        );
        let near = |x: Real, want: &str, tol: &str| (x - Real::lit(want)).abs() < Real::lit(tol);
        assert!(near(s.bias_rate, "9.0690", "0.001"), "{:?}", s);
        assert!(near(s.mass_scale, "0.94227", "0.0001"), "{:?}", s);
        assert!(near(s.impulse_scale, "0.05773", "0.0001"), "{:?}", s);
        // mass_scale + impulse_scale = 1 up to rounding.
        assert!((s.mass_scale + s.impulse_scale - Real::ONE).abs() < Real::lit("0.000001"));
    }
}
