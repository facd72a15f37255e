//! Continuous collision for bullets ([`Stage::Bullets`](super::Stage::Bullets), see `step/`).
//!
//! A body marked with [`Body::set_bullet`](crate::body::Body::set_bullet)
//! is swept, in every (sub-)step, from where it was before position
//! integration (the integrate-positions stage) to where the integration put it, against every
//! static and kinematic shape its swept box reaches (the static tree and
//! the kinematic bodies' shapes). If one of its shapes would reach another
//! shape during the motion, the body is put back on its path at the
//! earliest such time of impact, just touching: the narrowphase of the same
//! sub-step (the narrowphase stage) finds the contact and the solver stops the bullet
//! there, instead of finding it already past a thin wall. Its velocity is
//! not changed here (the contact does that).
//!
//! # Where in the step
//! After the shape-cache stage (every shape's world geometry at the integrated pose, the
//! static tree rebuilt if statics changed) and before the broadphase, so
//! the sweep reads only caches rebuilt from the state in this sub-step (a
//! restored world sweeps exactly as the straight run), and the pulled-back
//! bullet's shape caches and broadphase boxes are rewritten before any
//! pair is looked for. The start poses are recorded just before the integrate-positions stage,
//! so whatever moved the body (the default integrator or a custom one) is
//! swept. A world without bullets pays one flag test per body.
//!
//! # The time of impact
//! Conservative advancement (Mirtich's, as Box2D v2.0 had it) along the
//! separating normal, in `Real` (I32F32) only. Positions move linearly in
//! the sweep parameter `t ∈ [0, 1]` and angles too (`rot(t) = rot₀ ·
//! rot(Δθ·t)`). At the current `t`, [`separation`] gives the signed
//! distance `d` between the two shapes (negative when they overlap) and
//! the direction `n` it is measured along; the separation along the fixed
//! `n` cannot shrink faster than `rate = (Δp_a − Δp_b)·n + |Δθ_a|·r_a +
//! |Δθ_b|·r_b` per unit of `t` (`r`: the largest distance of a core point
//! from the centre of gravity), and the signed distance is never less than
//! the separation along `n`. So `t` may advance by `(d − floor + δ) / rate`
//! (rounded down by one ulp) without `d` falling more than `δ` below the
//! `floor`; the loop stops when `d ≤ floor` (the time of impact), when `t`
//! would pass 1 (no impact in this sub-step), or when `rate ≤ 0` (the
//! shapes separate along `n` for the rest of the motion: no impact).
//!
//! * The `floor` is 0 for a pair apart at the start (`d > `
//!   [`CONTACT_TOLERANCE`]): at the time of impact the shapes overlap by
//!   at most `δ`. A pair that touches at the start is the next section's.
//! * `δ` is `collision_slop / 4`, clamped to `[2^-20, 2^-10]` m, and at
//!   least `2^-30` of the relative motion (so that one ulp of `t`, `2^-32`
//!   of the motion, is always a small part of it: a step of `t` is never
//!   rounded to nothing). A contact that deep is found by the narrowphase
//!   (`d ≤ 0`) and is within the slop, so it gets no bias push.
//! * **Iterations:** at most [`MAX_TOI_ITERATIONS`] (20) per pair of
//!   shapes; a head-on approach ends in one, a rotating or grazing one in a
//!   few. Each iteration is one [`separation`] (a closed form or GJK, itself
//!   capped). Nothing loops without a bound and nothing divides by zero
//!   (`rate > 0` is checked).
//! * **Error bound:** at the returned time `d` is at least `floor − δ`
//!   (plus the rounding of GJK and of the pose, a few ulp); if the loop
//!   ran out of iterations or of resolution it returns a time at which `d`
//!   is still above the floor: the bullet stops short for this sub-step,
//!   never past it.
//!
//! # The margin: slow pairs and touching pairs
//! Each bullet shape has a margin, half its half thickness (the radius of
//! the largest circle about an inner point that the shape contains: its
//! radius for a circle or a capsule; Box2D v3's margin for the same
//! purposes).
//!
//! A pair whose relative motion in the sub-step (the bound above) is less
//! than the margin is not swept: the shape's inner point cannot get past
//! the middle of what it hits, so the discrete contact catches it (Box2D
//! v3 sweeps only bodies that move more than half their smallest extent,
//! for the same reason). A bullet at rest or moving slowly costs one length
//! per shape.
//!
//! A pair that already touches at the start of the sweep (`d ≤`
//! [`CONTACT_TOLERANCE`]: typically a bullet this sweep put against a wall
//! in the previous sub-step) is swept with the floor `−margin`: the motion
//! may take the shapes up to the margin into each other (the solver
//! already acts on that contact, and a bullet sliding or rolling along the
//! ground must not be pinned), no further. That is what stops a bullet
//! that turns about the point it touches with: a box that hits a wall
//! with a corner leaves the impact spinning fast (a 0.2 × 0.1 m box at
//! 450 m/s turned 0.3 rad: 1,800 rad/s, 30 rad in the next sub-step), and
//! the straight-line interpolation of that turn carries it through the
//! wall unless this pair is swept. An overlap of at most the margin keeps
//! the shape's inner point more than the margin on its own side, so the
//! narrowphase's contact normal pushes it back out the way it came (a
//! deeper overlap could reverse it: the least push-out of an elongated
//! shape spanning a thin wall can be through the wall). A pair that
//! overlaps by more than the margin at the start is not swept: the sweep
//! leaves a pair at most `δ` past the margin, which its contact pushes
//! back out, so a pair that deep got there otherwise (a handler rejected
//! the contact, or a slow motion) and the discrete step decides (a
//! pre-solve handler that rejects the contact lets the bullet through
//! this way).
//!
//! So no bullet shape wider than `2δ` passes a static or kinematic shape,
//! at any speed the step can represent, any angle and spin: `tests/
//! physics/bullets.rs` and `tests/regressions/bullet_tunnelling.rs` fire every
//! shape kind at thin segments, thin static boxes and kinematic walls.
//!
//! # What is not swept
//! Other dynamic bodies (bullets included): a sweep against moving dynamic
//! bodies would have to order the impacts of many bodies (Box2D v3 sweeps
//! bullets against non-bullet dynamic bodies after their own continuous
//! pass), and the fast bodies a game has are mostly small projectiles
//! hitting level geometry. Fast dynamic bodies that are not bullets are not
//! swept at all (Chipmunk's model, and Box2D v3's for dynamic–dynamic
//! pairs): they tunnel once they move more than their own size plus the
//! obstacle's in one sub-step (see `docs/numerics.md`); mark them as
//! bullets or raise the sub-steps. Sensors, shapes whose filters reject
//! each other and bodies joined by a constraint with `collide_bodies =
//! false` are not swept against, as they never make contacts; nor is a
//! pair whose begin handler rejected the contact (a one-way platform: the
//! arbiter is ignored until the shapes separate), so the bullet goes
//! through in the sub-step after the one that put it against the shape. A
//! pre-solve handler that rejects the contact lets it through a sub-step
//! or two later (the pair is swept down to the margin first).
use crate::body::{Body, BodyHandle};
use crate::collision::{separation, SupportShape, CONTACT_TOLERANCE};
use crate::math::{Real, Rot, Vect, BB};
use crate::shape::Geometry;

/// Iteration cap of one time-of-impact search (see the module docs).
pub const MAX_TOI_ITERATIONS: u32 = 20;

/// Largest target overlap `δ` from the slop (2^-10 m, about 1 mm).
pub(super) const DELTA_MAX: Real = Real::from_bits(1 << 22);
/// Smallest target overlap `δ` (2^-20 m).
const DELTA_MIN: Real = Real::from_bits(1 << 12);

/// Where a body was before the integrate-positions stage.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pose {
    p: Vect,
    a: Real,
    rot: Rot,
}

impl Pose {
    pub(super) fn of(b: &Body) -> Pose {
        Pose {
            p: b.p,
            a: b.a,
            rot: b.rot,
        }
    }
}

/// The sweep's buffers (not state: rebuilt every sub-step).
#[derive(Default)]
pub(crate) struct CcdCache {
    /// Bullets (dynamic bodies with the flag) and their poses before
    /// the integrate-positions stage, in slot order.
    pub(super) bullets: Vec<(BodyHandle, Pose)>,
    /// Kinematic bodies and their poses before the integrate-positions stage (recorded only when
    /// there is a bullet), in slot order.
    pub(super) kinematic: Vec<(BodyHandle, Pose)>,
    /// Static shape slots the swept box reaches (scratch).
    pub(super) candidates: Vec<u32>,
    /// Time-of-impact hits of the last sub-step (bullets pulled back).
    pub(crate) hits: u32,
}

/// A body's motion over the sub-step, `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
    p0: Vect,
    pub(super) dp: Vect,
    pub(super) a0: Real,
    pub(super) da: Real,
    pub(super) rot0: Rot,
    pub(super) cog: Vect,
    /// The pose at `t = 1` as the integration left it (`at(1)` may differ
    /// from it by rounding).
    pub(super) end: Pose,
}

impl Motion {
    pub(super) fn new(start: Pose, end: &Body) -> Motion {
        Motion {
            p0: start.p,
            dp: end.p - start.p,
            a0: start.a,
            da: end.a - start.a,
            rot0: start.rot,
            cog: end.cog,
            end: Pose::of(end),
        }
    }

    /// A body that does not move (a static one).
    pub(super) fn fixed(b: &Body) -> Motion {
        Motion::new(Pose::of(b), b)
    }

    /// Centre of gravity, angle and rotation at `t`.
    pub(super) fn at(&self, t: Real) -> (Vect, Real, Rot) {
        let p = self.p0 + self.dp * t;
        if self.da.is_zero() {
            return (p, self.a0, self.rot0);
        }
        let da = self.da * t;
        (p, self.a0 + da, self.rot0.compose(Rot::from_angle(da)))
    }

    /// Where a point that is at `(p, a, rot)` at time `t` and moves with
    /// this body from then on is at `t = 1`.
    pub(super) fn carry(&self, t: Real, (p, a, rot): (Vect, Real, Rot)) -> (Vect, Real, Rot) {
        let (q, b, r) = self.at(t);
        let local = r.apply_inv(p - q);
        let turn = self.end.a - b;
        let rot = if turn.is_zero() {
            rot
        } else {
            rot.compose(Rot::from_angle(turn))
        };
        (self.end.p + self.end.rot.apply(local), a + turn, rot)
    }

    /// `local` placed at `t` (as the shape-cache stage places a shape: at the body
    /// origin `p − rot·cog`).
    pub(super) fn geometry_at(&self, local: &Geometry, t: Real) -> Geometry {
        let (p, _, rot) = self.at(t);
        local.to_world(p - rot.apply(self.cog), rot)
    }
}

/// The largest distance of a core point of `local` from `cog`, rounded up:
/// a point of the shape moves by at most this times the angle turned.
pub(super) fn reach(local: &Geometry, cog: Vect) -> Real {
    let far = |v: Vect| (v - cog).length();
    let r = match local {
        Geometry::Circle(c) => far(c.offset),
        Geometry::Segment(s) => far(s.a).max(far(s.b)),
        Geometry::Poly(p) => p
            .verts()
            .iter()
            .map(|&v| far(v))
            .max()
            .unwrap_or(Real::ZERO),
    };
    r + Real::DELTA
}

/// The inner point of `local` its core is centred on: a circle's centre,
/// a segment's midpoint, a polygon's vertex average (inside it, as it is
/// convex).
fn inner_point(local: &Geometry) -> Vect {
    match local {
        Geometry::Circle(c) => c.offset,
        Geometry::Segment(s) => s.center(),
        Geometry::Poly(p) => {
            let verts = p.verts();
            let sum = verts.iter().fold(Vect::ZERO, |acc, &v| acc + v);
            let n = i32::try_from(verts.len()).unwrap_or(1).max(1);
            Vect::new(sum.x / Real::from_int(n), sum.y / Real::from_int(n))
        }
    }
}

/// Half the thickness of `local`: the radius of the largest circle about
/// its [`inner_point`] that it contains (its radius for a circle or a
/// segment; for a polygon the least distance from that point to an edge,
/// plus the rounding radius). A shape that moves less than this in a
/// sub-step cannot pass anything: its centre never reaches the far side of
/// what it hits.
pub(super) fn half_thickness(local: &Geometry) -> Real {
    match local {
        Geometry::Circle(c) => c.radius,
        Geometry::Segment(s) => s.radius,
        Geometry::Poly(p) => {
            let c = inner_point(local);
            let inner = p
                .verts()
                .iter()
                .zip(p.normals())
                .map(|(&v, &n)| n.dot(v - c))
                .min()
                .unwrap_or(Real::ZERO);
            inner.max(Real::ZERO) + p.radius()
        }
    }
}

/// One side of a swept pair: its shape in body coordinates, its motion
/// and its reach.
pub(super) struct Swept<'a> {
    pub(super) local: &'a Geometry,
    pub(super) motion: Motion,
    pub(super) reach: Real,
}

impl Swept<'_> {
    pub(super) fn at(&self, t: Real) -> Geometry {
        self.motion.geometry_at(self.local, t)
    }

    /// How far a point of the shape can move per unit of `t` by turning.
    pub(super) fn turn_bound(&self) -> Real {
        self.motion.da.abs() * self.reach
    }

    /// The swept box over `[0, 1]`: the boxes at both ends, grown by the
    /// turn bound (a turning point leaves the segment between its ends by
    /// at most that) and by `margin`.
    pub(super) fn swept_bb(&self, end: &BB, margin: Real) -> BB {
        self.at(Real::ZERO)
            .bb()
            .merge(end)
            .grow(self.turn_bound() + margin)
    }
}

/// The target overlap `δ` for a sweep with this slop and full motion bound.
fn target_overlap(slop: Real, full: Real) -> Real {
    let base = (slop * Real::from_bits(1 << 30)).clamp(DELTA_MIN, DELTA_MAX);
    base.max(Real::from_bits(full.to_bits() >> 30))
}

/// The time of impact of bullet shape `a` and `b` over `[0, 1]` (see the
/// module docs; `margin` is half the half thickness of `a`): `Some(t)` with
/// `t < 1` if they come within contact during the motion, `None` if not
/// (or if they move less than `margin` relative to each other: the
/// discrete step handles that). If they already touch at `t = 0`,
/// `Some(t)` if they would overlap by more than `margin` (or, if they
/// overlap by more already, by more than at `t = 0`).
pub(super) fn time_of_impact(
    a: &Swept<'_>,
    b: &Swept<'_>,
    slop: Real,
    margin: Real,
) -> Option<Real> {
    let full = motion_bound(a, b);
    if full < margin {
        return None;
    }
    let delta = target_overlap(slop, full);
    let start = separation(&a.at(Real::ZERO), &b.at(Real::ZERO));
    // Apart: up to contact. Touching: down to `margin` of overlap, the
    // step's overshoot (at most `delta`) included. Deeper already: not
    // swept (see the module docs).
    let floor = if start.0 > CONTACT_TOLERANCE {
        Real::ZERO
    } else if start.0 >= -margin {
        start.0.min(delta - margin)
    } else {
        return None;
    };
    advance(a, b, start, floor, delta)
}

/// How far a point of `a` can move relative to `b` over `[0, 1]` (the
/// ulp covers the rounding of the normal and of the poses).
fn motion_bound(a: &Swept<'_>, b: &Swept<'_>) -> Real {
    (a.motion.dp - b.motion.dp).length() + a.turn_bound() + b.turn_bound() + Real::DELTA
}

/// Conservative advancement of `a` toward `b` from `t = 0`, where their
/// separation and its direction are `start`, until the separation is at
/// most `floor` (overshooting it by at most `delta`): `Some(t)` with
/// `t < 1`, or `None` if it stays above `floor` over `[0, 1]`.
fn advance(
    a: &Swept<'_>,
    b: &Swept<'_>,
    start: (Real, Vect),
    floor: Real,
    delta: Real,
) -> Option<Real> {
    let dp = a.motion.dp - b.motion.dp;
    let turn = a.turn_bound() + b.turn_bound();
    let full = motion_bound(a, b);
    let (mut d, mut n) = start;
    let mut t = Real::ZERO;
    for _ in 0..MAX_TOI_ITERATIONS {
        let rate = if n == Vect::ZERO {
            full
        } else {
            dp.dot(n) + turn + Real::DELTA
        };
        if !rate.is_positive() {
            return None;
        }
        // Rounded down: the step never overshoots by rounding.
        let step = (d - floor + delta) / rate - Real::DELTA;
        if !step.is_positive() {
            return Some(t);
        }
        let next = t + step;
        if next >= Real::ONE {
            return None;
        }
        t = next;
        (d, n) = separation(&a.at(t), &b.at(t));
        if d <= floor {
            return Some(t);
        }
    }
    Some(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real;
    use crate::shape::{Circle, Segment};

    const SLOP: Real = Real::lit("0.1");

    fn circle() -> Geometry {
        Geometry::Circle(Circle::new(real!(0.05), Vect::ZERO))
    }

    /// A body at `p0` (angle `a0`) moving by `dp` and turning by `da`.
    fn motion(p0: Vect, dp: Vect, a0: Real, da: Real) -> Motion {
        let rot0 = Rot::from_angle(a0);
        Motion {
            p0,
            dp,
            a0,
            da,
            rot0,
            cog: Vect::ZERO,
            end: Pose {
                p: p0 + dp,
                a: a0 + da,
                rot: rot0.compose(Rot::from_angle(da)),
            },
        }
    }

    fn wall() -> Geometry {
        Geometry::Segment(Segment::new(
            Vect::from_ints(0, -5),
            Vect::from_ints(0, 5),
            Real::ZERO,
        ))
    }

    fn fixed(g: &Geometry) -> Swept<'_> {
        Swept {
            local: g,
            motion: motion(Vect::ZERO, Vect::ZERO, Real::ZERO, Real::ZERO),
            reach: Real::ZERO,
        }
    }

    fn bullet(g: &Geometry, p0: Vect, dp: Vect) -> Swept<'_> {
        Swept {
            local: g,
            motion: motion(p0, dp, Real::ZERO, Real::ZERO),
            reach: reach(g, Vect::ZERO),
        }
    }

    fn toi(a: &Swept<'_>, b: &Swept<'_>, margin: Real) -> Option<Real> {
        time_of_impact(a, b, SLOP, margin)
    }

    /// The separation of the pair at `t`.
    fn gap(a: &Swept<'_>, b: &Swept<'_>, t: Real) -> Real {
        separation(&a.at(t), &b.at(t)).0
    }

    #[test]
    fn head_on_stops_within_delta_of_contact() {
        let (c, w) = (circle(), wall());
        // 5 m of travel from 1 m before the wall: contact at t ≈ 0.19.
        let a = bullet(&c, Vect::from_ints(-1, 0), Vect::from_ints(5, 0));
        let b = fixed(&w);
        let t = toi(&a, &b, Real::ZERO).unwrap_or(Real::ONE);
        let d = gap(&a, &b, t);
        assert!(d <= Real::ZERO && d >= -DELTA_MAX, "t {t:?} d {d:?}");
        assert!((t - real!(0.19)).abs() < real!(0.001), "{t:?}");
    }

    #[test]
    fn misses_grazes_and_sliding_give_none() {
        let (c, w) = (circle(), wall());
        let b = fixed(&w);
        // Moving away, parallel, or stopping short.
        for dp in [(-5, 0), (0, 3)] {
            let a = bullet(&c, Vect::from_ints(-1, 0), Vect::from_ints(dp.0, dp.1));
            assert_eq!(toi(&a, &b, Real::ZERO), None, "{dp:?}");
        }
        let short = bullet(
            &c,
            Vect::from_ints(-1, 0),
            Vect::new(real!(0.9), Real::ZERO),
        );
        assert_eq!(toi(&short, &b, Real::ZERO), None);
        // Touching at the start and sliding along or leaving: not pinned.
        for dp in [(0, 5), (-5, 3)] {
            let touching = bullet(
                &c,
                Vect::new(-real!(0.05), Real::ZERO),
                Vect::from_ints(dp.0, dp.1),
            );
            assert_eq!(toi(&touching, &b, Real::ZERO), None, "{dp:?}");
        }
        // Slow: moving less than `slow` is left to the discrete step.
        let a = bullet(&c, Vect::from_ints(-1, 0), Vect::from_ints(5, 0));
        assert_eq!(toi(&a, &b, Real::from_int(6)), None);
    }

    #[test]
    fn touching_at_the_start_it_gets_no_deeper_than_the_margin() {
        let (c, w) = (circle(), wall());
        let b = fixed(&w);
        let margin = half_thickness(&c) * Real::HALF;
        // Touching the wall and moving 5 m into it: stopped once it
        // overlaps by the margin (0.025 m), t ≈ 0.025 / 5.
        let touching = bullet(
            &c,
            Vect::new(-real!(0.05), Real::ZERO),
            Vect::from_ints(5, 0),
        );
        let t = toi(&touching, &b, margin).unwrap_or(Real::ONE);
        let d = gap(&touching, &b, t);
        assert!(d <= DELTA_MAX - margin && d >= -margin, "t {t:?} d {d:?}");
        // Overlapping by less than the margin: down to the margin.
        let part = bullet(
            &c,
            Vect::new(-real!(0.03), Real::ZERO),
            Vect::from_ints(5, 0),
        );
        let t = toi(&part, &b, margin).unwrap_or(Real::ONE);
        let d = gap(&part, &b, t);
        assert!(d <= DELTA_MAX - margin && d >= -margin, "t {t:?} d {d:?}");
        // Overlapping by more already: not swept (see the module docs).
        let deep = bullet(
            &c,
            Vect::new(-real!(0.02), Real::ZERO),
            Vect::from_ints(5, 0),
        );
        assert_eq!(toi(&deep, &b, margin), None);
    }

    #[test]
    fn a_turning_box_never_overshoots() {
        // A 1 x 0.2 box turning 3 rad while moving 4 m toward the wall:
        // whatever the iterations do, the returned pose overlaps by at
        // most delta (or is still apart).
        let v = [
            Vect::new(real!(0.5), -real!(0.1)),
            Vect::new(real!(0.5), real!(0.1)),
            Vect::new(-real!(0.5), real!(0.1)),
            Vect::new(-real!(0.5), -real!(0.1)),
        ];
        let g = Geometry::Poly(crate::shape::Poly::from_ccw_unchecked(&v, Real::ZERO));
        let w = wall();
        let b = fixed(&w);
        for k in 0..16 {
            let a = Swept {
                local: &g,
                motion: motion(
                    Vect::new(-Real::from_int(2), Real::ZERO),
                    Vect::new(Real::from_int(4), Real::ZERO),
                    Real::ratio(k, 8),
                    Real::from_int(3),
                ),
                reach: reach(&g, Vect::ZERO),
            };
            let t = toi(&a, &b, Real::ZERO);
            let Some(t) = t else {
                panic!("angle {k}/8: the box must hit the wall");
            };
            assert!(gap(&a, &b, t) >= -DELTA_MAX, "angle {k}/8 t {t:?}");
            // Nothing touched before t: sample the path.
            for i in 0..64 {
                let s = t * Real::ratio(i, 64);
                assert!(gap(&a, &b, s) > -DELTA_MAX, "angle {k}/8 at {s:?}");
            }
        }
    }

    #[test]
    fn half_thickness_of_each_kind() {
        assert_eq!(half_thickness(&circle()), real!(0.05));
        assert_eq!(half_thickness(&wall()), Real::ZERO);
        let v = [
            Vect::from_ints(1, -1),
            Vect::from_ints(1, 1),
            Vect::from_ints(-1, 1),
            Vect::from_ints(-1, -1),
        ];
        let g = Geometry::Poly(crate::shape::Poly::from_ccw_unchecked(&v, real!(0.25)));
        assert_eq!(half_thickness(&g), real!(1.25));
    }
}
