//! The joints of a scene in engine-neutral form ([`Resolved`]) and the
//! joint error ([`JointError`]) read from either engine's body states.
//!
//! A [`ConstraintDesc`] leaves some of its geometry to the build (a pivot
//! given as a world point, a pin whose length is measured); [`resolve`]
//! works it out once, in `f64`, from the description's initial poses, the
//! way the Tamias2D build does (`cpPivotJointNew`, `cpPinJointNew`). The
//! Rapier mapping ([`rapier_world`](super::rapier_world)) and the error
//! measure both start from it, so both engines are measured against the
//! same anchors.
//!
//! The error measure, per joint, from the bodies' origins and angles
//! ([`BodyState`](super::measure::BodyState), the same reading for both engines):
//!
//! | kind           | positional error (m)                                   |
//! |----------------|--------------------------------------------------------|
//! | pivot          | distance between the two world anchors                 |
//! | pin            | \| distance between the anchors − the pin's length \|  |
//! | slide          | how far that distance is outside `[min, max]`          |
//! | groove         | distance of b's anchor from the groove segment on a    |
//! | rotary limit   | (angular, rad) how far `θb − θa` is outside `[min, max]` |
//!
//! Springs, motors, gears and ratchets are not measured: springs are meant
//! to stretch, and gears and ratchets have no Rapier counterpart.
use crate::{ConstraintDesc, JointType, SceneDesc};
use tamias2d::math::{Real, Vect};

use crate::bench::measure::Engine;

/// One joint with its geometry worked out (body-local anchors, lengths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolved {
    /// The kind.
    pub kind: JointType,
    /// Body a (index in creation order).
    pub a: usize,
    /// Body b.
    pub b: usize,
    /// Anchor on a, body-local (relative to the body origin).
    pub anchor_a: [f64; 2],
    /// Anchor on b, body-local.
    pub anchor_b: [f64; 2],
    /// Groove: its two ends on a, body-local.
    pub groove: [[f64; 2]; 2],
    /// Pin: its length.
    pub dist: f64,
    /// Slide and rotary limit: the lower limit.
    pub min: f64,
    /// Slide and rotary limit: the upper limit.
    pub max: f64,
    /// Springs: rest length or rest angle.
    pub rest: f64,
    /// Springs: stiffness.
    pub stiffness: f64,
    /// Springs: damping.
    pub damping: f64,
    /// Simple motor: rate (Chipmunk's sign: `ω_b − ω_a = −rate`).
    pub rate: f64,
    /// Largest force or torque, if bounded.
    pub max_force: Option<f64>,
    /// Whether the two bodies' shapes collide.
    pub collide: bool,
}

fn r(x: Option<Real>) -> f64 {
    x.map_or(0.0, Real::to_f64)
}

fn v(x: Option<Vect>) -> [f64; 2] {
    let (x, y) = x.unwrap_or(Vect::ZERO).to_f64();
    [x, y]
}

/// `local` (relative to the origin of a body at `p`, turned by `angle`) in
/// world coordinates.
pub fn to_world(p: [f64; 2], angle: f64, local: [f64; 2]) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [
        p[0] + c * local[0] - s * local[1],
        p[1] + s * local[0] + c * local[1],
    ]
}

/// The world point `w` in the coordinates of a body at `p` turned by `angle`.
pub fn to_local(p: [f64; 2], angle: f64, w: [f64; 2]) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    let (dx, dy) = (w[0] - p[0], w[1] - p[1]);
    [c * dx + s * dy, -s * dx + c * dy]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The joints of `desc`, in order, resolved against its initial poses.
pub fn resolve(desc: &SceneDesc) -> Vec<Resolved> {
    let pose = |i: u32| {
        desc.bodies.get(i as usize).map_or(([0.0; 2], 0.0), |b| {
            let (x, y) = b.position.to_f64();
            ([x, y], b.angle.to_f64())
        })
    };
    desc.constraints
        .iter()
        .map(|c: &ConstraintDesc| {
            let (pa, aa) = pose(c.a);
            let (pb, ab) = pose(c.b);
            let (anchor_a, anchor_b) = match c.pivot {
                Some(p) => {
                    let w = v(Some(p));
                    (to_local(pa, aa, w), to_local(pb, ab, w))
                }
                None => (v(c.anchor_a), v(c.anchor_b)),
            };
            let measured = dist(to_world(pa, aa, anchor_a), to_world(pb, ab, anchor_b));
            let rest = match c.kind {
                JointType::DampedRotarySpring => r(c.rest_angle),
                _ => r(c.rest_length),
            };
            Resolved {
                kind: c.kind,
                a: c.a as usize,
                b: c.b as usize,
                anchor_a,
                anchor_b,
                groove: [v(c.groove_a), v(c.groove_b)],
                dist: c.dist.map_or(measured, Real::to_f64),
                min: r(c.min),
                max: r(c.max),
                rest,
                stiffness: r(c.stiffness),
                damping: r(c.damping),
                rate: r(c.rate),
                max_force: c.max_force.map(Real::to_f64),
                collide: c.collide_bodies.unwrap_or(true),
            }
        })
        .collect()
}

/// The joint error of one moment, or the worst and mean over a run
/// ([`JointError::merge`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointError {
    /// Largest positional error of a pivot, pin, slide or groove (m).
    pub position: f64,
    /// Largest rotary-limit violation (rad).
    pub angle: f64,
    /// Sum over the merged moments of each moment's `position`.
    pub position_sum: f64,
    /// Moments merged.
    pub samples: u64,
    /// Whether the scene has joints whose position error is measured.
    pub has_position: bool,
    /// Whether the scene has rotary limits.
    pub has_angle: bool,
}

impl JointError {
    /// Adds the error of another moment (or run).
    pub fn merge(&mut self, other: JointError) {
        self.position = self.position.max(other.position);
        self.angle = self.angle.max(other.angle);
        self.position_sum += other.position_sum;
        self.samples += other.samples;
        self.has_position |= other.has_position;
        self.has_angle |= other.has_angle;
    }

    /// Mean over the merged moments of the worst positional error.
    pub fn position_mean(&self) -> f64 {
        if self.samples == 0 {
            0.0
        } else {
            self.position_sum / self.samples as f64
        }
    }
}

/// `a` brought into [−π, π).
fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    (a + PI).rem_euclid(TAU) - PI
}

/// The error of `joints` in `engine`'s current state (see the module docs).
pub fn error(joints: &[Resolved], engine: &dyn Engine) -> JointError {
    let mut out = JointError {
        samples: 1,
        ..JointError::default()
    };
    let states = engine.states();
    let body = |i: usize| states.get(i).copied().unwrap_or_default();
    for j in joints {
        let sa = body(j.a);
        let sb = body(j.b);
        let wa = to_world(sa.position, sa.angle, j.anchor_a);
        let wb = to_world(sb.position, sb.angle, j.anchor_b);
        let e = match j.kind {
            JointType::Pivot => dist(wa, wb),
            JointType::Pin => (dist(wa, wb) - j.dist).abs(),
            JointType::Slide => {
                let d = dist(wa, wb);
                (d - j.max).max(j.min - d).max(0.0)
            }
            JointType::Groove => {
                let g0 = to_world(sa.position, sa.angle, j.groove[0]);
                let g1 = to_world(sa.position, sa.angle, j.groove[1]);
                let (dx, dy) = (g1[0] - g0[0], g1[1] - g0[1]);
                let len2 = dx * dx + dy * dy;
                let t = if len2 > 0.0 {
                    (((wb[0] - g0[0]) * dx + (wb[1] - g0[1]) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                dist(wb, [g0[0] + t * dx, g0[1] + t * dy])
            }
            JointType::RotaryLimit => {
                out.has_angle = true;
                let rel = wrap(sb.angle - sa.angle);
                out.angle = out.angle.max((rel - j.max).max(j.min - rel).max(0.0));
                continue;
            }
            _ => continue,
        };
        out.has_position = true;
        out.position = out.position.max(e);
    }
    out.position_sum = out.position;
    out
}
