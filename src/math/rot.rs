//! `Rot`: a rotation stored as a unit complex number `(c, s) = (cos θ, sin θ)`.
//!
//! Bodies keep their orientation as a `Rot`, not an angle: rotating a vector
//! is then two multiply-adds (no trig in the step), and integrating an angular
//! velocity is a complex multiplication followed by a cheap renormalisation.
//! The angle exists only on demand ([`Rot::angle`]).
use serde::{Deserialize, Serialize};

use super::{Real, Vect};

/// A rotation as a unit complex number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Rot {
    /// cos θ.
    pub c: Real,
    /// sin θ.
    pub s: Real,
}

impl Default for Rot {
    fn default() -> Rot {
        Rot::IDENTITY
    }
}

impl Rot {
    /// No rotation.
    pub const IDENTITY: Rot = Rot {
        c: Real::ONE,
        s: Real::ZERO,
    };

    /// The rotation by `angle` radians (any angle; see `math::trig`).
    pub fn from_angle(angle: Real) -> Rot {
        let (s, c) = angle.sin_cos();
        Rot { c, s }
    }

    /// The rotation that turns +x onto the direction of `v`; zero gives identity.
    pub fn from_vect(v: Vect) -> Rot {
        let n = v.normalize();
        if n == Vect::ZERO {
            Rot::IDENTITY
        } else {
            Rot { c: n.x, s: n.y }
        }
    }

    /// `(cos θ, sin θ)` as `f64`, for rendering (output only).
    pub fn to_f64(self) -> (f64, f64) {
        (self.c.to_f64(), self.s.to_f64())
    }

    /// `(cos θ, sin θ)` as `f32`, for rendering (output only).
    pub fn to_f32(self) -> (f32, f32) {
        (self.c.to_f32(), self.s.to_f32())
    }

    /// The angle in `[-π, π]`.
    pub fn angle(self) -> Real {
        self.s.atan2(self.c)
    }

    /// As the vector `(c, s)`.
    #[inline(always)]
    pub fn as_vect(self) -> Vect {
        Vect::new(self.c, self.s)
    }

    /// Rotates `v` by this rotation.
    #[inline(always)]
    pub fn apply(self, v: Vect) -> Vect {
        v.rotate(self.as_vect())
    }

    /// Rotates `v` by the inverse rotation.
    #[inline(always)]
    pub fn apply_inv(self, v: Vect) -> Vect {
        v.unrotate(self.as_vect())
    }

    /// `self` followed by `other` (angles add).
    #[inline]
    pub fn compose(self, other: Rot) -> Rot {
        let v = self.as_vect().rotate(other.as_vect());
        Rot { c: v.x, s: v.y }
    }

    /// The inverse rotation.
    #[inline]
    pub fn inv(self) -> Rot {
        Rot {
            c: self.c,
            s: -self.s,
        }
    }

    /// Advances by the small angle `w·dt` without trig: `q ← q·(1 + i·w·dt)`,
    /// then renormalised. Exact to second order in `w·dt`, the same order as
    /// the integrator; Chipmunk stores the angle and calls sin/cos instead.
    pub fn integrate(self, w_dt: Real) -> Rot {
        let c = self.c - self.s * w_dt;
        let s = self.s + self.c * w_dt;
        Rot::from_vect(Vect::new(c, s))
    }

    /// Renormalises to unit length (identity for a zero input).
    pub fn normalize(self) -> Rot {
        Rot::from_vect(self.as_vect())
    }
}
