//! Deterministic trigonometry on `Real` (placeholder: being written).
use super::Real;

/// Sine and cosine of `angle` (radians).
pub fn sin_cos(angle: Real) -> (Real, Real) {
    let _ = angle;
    (Real::ZERO, Real::ONE)
}

/// Four-quadrant arctangent of `y / x`.
pub fn atan2(y: Real, x: Real) -> Real {
    let _ = (y, x);
    Real::ZERO
}
