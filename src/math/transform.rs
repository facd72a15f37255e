//! `Transform`: a 2×3 affine matrix (Chipmunk's `cpTransform`), used to place
//! polygon vertices (`poly_new`) and to move shapes into world space.
//!
//! ```text
//! | a  c  tx |   x' = a·x + c·y + tx
//! | b  d  ty |   y' = b·x + d·y + ty
//! ```
use serde::{Deserialize, Serialize};

use super::{Real, Rot, Vect};

/// An affine transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Transform {
    /// x scale / rotation cos.
    pub a: Real,
    /// rotation sin.
    pub b: Real,
    /// −rotation sin.
    pub c: Real,
    /// y scale / rotation cos.
    pub d: Real,
    /// x translation.
    pub tx: Real,
    /// y translation.
    pub ty: Real,
}

impl Default for Transform {
    fn default() -> Transform {
        Transform::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Transform = Transform {
        a: Real::ONE,
        b: Real::ZERO,
        c: Real::ZERO,
        d: Real::ONE,
        tx: Real::ZERO,
        ty: Real::ZERO,
    };

    /// `[a, b, c, d, tx, ty]` as `f64`, for rendering (output only): the
    /// order of a canvas `setTransform(a, b, c, d, e, f)` and of a
    /// column-major 2×3 matrix.
    pub fn to_f64(&self) -> [f64; 6] {
        [self.a, self.b, self.c, self.d, self.tx, self.ty].map(Real::to_f64)
    }

    /// `[a, b, c, d, tx, ty]` as `f32`, for rendering (output only; order as
    /// [`Transform::to_f64`]).
    pub fn to_f32(&self) -> [f32; 6] {
        [self.a, self.b, self.c, self.d, self.tx, self.ty].map(Real::to_f32)
    }

    /// A pure translation.
    pub fn translate(t: Vect) -> Transform {
        Transform {
            tx: t.x,
            ty: t.y,
            ..Transform::IDENTITY
        }
    }

    /// A scale about the origin.
    pub fn scale(sx: Real, sy: Real) -> Transform {
        Transform {
            a: sx,
            d: sy,
            ..Transform::IDENTITY
        }
    }

    /// Rotation then translation: the placement of a rigid body.
    pub fn rigid(position: Vect, rot: Rot) -> Transform {
        Transform {
            a: rot.c,
            b: rot.s,
            c: -rot.s,
            d: rot.c,
            tx: position.x,
            ty: position.y,
        }
    }

    /// Applies the transform to a point.
    #[inline]
    pub fn point(&self, p: Vect) -> Vect {
        Vect::new(
            Real::mul_add2(self.a, p.x, self.c, p.y) + self.tx,
            Real::mul_add2(self.b, p.x, self.d, p.y) + self.ty,
        )
    }

    /// Applies the linear part only (no translation) to a vector.
    #[inline]
    pub fn vect(&self, v: Vect) -> Vect {
        Vect::new(
            Real::mul_add2(self.a, v.x, self.c, v.y),
            Real::mul_add2(self.b, v.x, self.d, v.y),
        )
    }

    /// `self ∘ other`: applies `other` first.
    pub fn compose(&self, o: &Transform) -> Transform {
        Transform {
            a: Real::mul_add2(self.a, o.a, self.c, o.b),
            b: Real::mul_add2(self.b, o.a, self.d, o.b),
            c: Real::mul_add2(self.a, o.c, self.c, o.d),
            d: Real::mul_add2(self.b, o.c, self.d, o.d),
            tx: Real::mul_add2(self.a, o.tx, self.c, o.ty) + self.tx,
            ty: Real::mul_add2(self.b, o.tx, self.d, o.ty) + self.ty,
        }
    }

    /// The determinant of the linear part.
    pub fn determinant(&self) -> Real {
        Real::mul_sub2(self.a, self.d, self.c, self.b)
    }

    /// The inverse, or `None` for a singular matrix.
    pub fn inverse(&self) -> Option<Transform> {
        let det = self.determinant();
        if det.is_zero() {
            return None;
        }
        let inv = det.recip();
        let a = self.d * inv;
        let b = -self.b * inv;
        let c = -self.c * inv;
        let d = self.a * inv;
        let tx = -Real::mul_add2(a, self.tx, c, self.ty);
        let ty = -Real::mul_add2(b, self.tx, d, self.ty);
        Some(Transform { a, b, c, d, tx, ty })
    }
}
