//! `BB`: an axis-aligned bounding box (Chipmunk's `cpBB`: left, bottom,
//! right, top), used by the broadphase and the bounding-box query.
use serde::{Deserialize, Serialize};

use super::{Real, Vect};

/// Axis-aligned bounding box with `l ≤ r` and `b ≤ t` when built by the
/// constructors here.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct BB {
    /// Left (min x).
    pub l: Real,
    /// Bottom (min y).
    pub b: Real,
    /// Right (max x).
    pub r: Real,
    /// Top (max y).
    pub t: Real,
}

impl BB {
    /// A box from its four sides; swapped sides are put in order.
    pub fn new(l: Real, b: Real, r: Real, t: Real) -> BB {
        BB {
            l: l.min(r),
            b: b.min(t),
            r: l.max(r),
            t: b.max(t),
        }
    }

    /// The box centred on `c` with half-extents `hw`, `hh`.
    pub fn for_extents(c: Vect, hw: Real, hh: Real) -> BB {
        let (hw, hh) = (hw.abs(), hh.abs());
        BB {
            l: c.x - hw,
            b: c.y - hh,
            r: c.x + hw,
            t: c.y + hh,
        }
    }

    /// The box around a circle.
    pub fn for_circle(p: Vect, r: Real) -> BB {
        BB::for_extents(p, r, r)
    }

    /// The box around one point.
    pub fn for_point(p: Vect) -> BB {
        BB {
            l: p.x,
            b: p.y,
            r: p.x,
            t: p.y,
        }
    }

    /// True if the boxes overlap (touching counts).
    #[inline]
    pub fn intersects(&self, o: &BB) -> bool {
        self.l <= o.r && o.l <= self.r && self.b <= o.t && o.b <= self.t
    }

    /// True if `o` lies entirely inside `self`.
    pub fn contains_bb(&self, o: &BB) -> bool {
        self.l <= o.l && self.r >= o.r && self.b <= o.b && self.t >= o.t
    }

    /// True if the point lies inside (boundary included).
    pub fn contains_vect(&self, v: Vect) -> bool {
        self.l <= v.x && self.r >= v.x && self.b <= v.y && self.t >= v.y
    }

    /// The smallest box containing both.
    pub fn merge(&self, o: &BB) -> BB {
        BB {
            l: self.l.min(o.l),
            b: self.b.min(o.b),
            r: self.r.max(o.r),
            t: self.t.max(o.t),
        }
    }

    /// The smallest box containing `self` and `v`.
    pub fn expand(&self, v: Vect) -> BB {
        BB {
            l: self.l.min(v.x),
            b: self.b.min(v.y),
            r: self.r.max(v.x),
            t: self.t.max(v.y),
        }
    }

    /// Grown by `d` on every side.
    pub fn grow(&self, d: Real) -> BB {
        BB {
            l: self.l - d,
            b: self.b - d,
            r: self.r + d,
            t: self.t + d,
        }
    }

    /// The centre.
    pub fn center(&self) -> Vect {
        Vect::new(self.l, self.b).lerp(Vect::new(self.r, self.t), Real::HALF)
    }

    /// The area (saturating).
    pub fn area(&self) -> Real {
        (self.r - self.l) * (self.t - self.b)
    }

    /// The point of the box closest to `v`.
    pub fn clamp_vect(&self, v: Vect) -> Vect {
        Vect::new(v.x.clamp(self.l, self.r), v.y.clamp(self.b, self.t))
    }
}
