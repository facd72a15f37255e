//! Solver quality, measured on a running [`Space`] through the engine's
//! public API only: how far the joints are from holding, and how deep the
//! shapes overlap.
//!
//! | kind   | joint error (m)                                              |
//! |--------|--------------------------------------------------------------|
//! | pivot  | distance between the two world anchors                        |
//! | pin    | \| distance between the anchors − the pin's length \|         |
//! | slide  | how far that distance is outside `[min, max]`                 |
//! | groove | distance of b's anchor from the groove segment on a           |
//!
//! Other constraints (springs, motors, gears, ratchets, rotary limits) are
//! not positional joints and are not measured. Anchors are in body
//! coordinates, brought to the world by
//! [`Body::local_to_world`](tamias2d::body::Body::local_to_world), as the
//! solver does.
//!
//! Penetration is read from the arbiters of the last step
//! ([`Space::arbiters`]): the deepest contact (the most negative contact
//! distance, as a positive depth) over the arbiters whose shapes touched in
//! that step. Cached arbiters (shapes that separated; their contacts are
//! last touch's, stale), ignored pairs and pairs with a sensor are left
//! out. The contacts are the narrowphase's, computed during the step, so
//! this is the overlap the step started its solve from.
//!
//! All in `Real`: no float enters the measure. [`Quality`] keeps the
//! largest of both over a run.
use tamias2d::arbiter::ArbiterState;
use tamias2d::constraint::{Constraint, JointKind};
use tamias2d::math::{Real, Vect};
use tamias2d::space::Space;

/// The error of one constraint of `space` in metres (see the module
/// docs), or `None` for a kind that is not measured or a constraint whose
/// bodies are not in `space`.
pub fn joint_error(space: &Space, c: &Constraint) -> Option<Real> {
    let a = space.body(c.body_a())?;
    let b = space.body(c.body_b())?;
    let between = |anchor_a: Vect, anchor_b: Vect| {
        a.local_to_world(anchor_a).dist(b.local_to_world(anchor_b))
    };
    let error = match c.kind() {
        JointKind::Pivot(j) => between(j.anchor_a(), j.anchor_b()),
        JointKind::Pin(j) => (between(j.anchor_a(), j.anchor_b()) - j.dist()).abs(),
        JointKind::Slide(j) => {
            let d = between(j.anchor_a(), j.anchor_b());
            (j.min() - d).max(d - j.max()).max(Real::ZERO)
        }
        JointKind::Groove(j) => {
            let start = a.local_to_world(j.groove_a());
            let end = a.local_to_world(j.groove_b());
            let p = b.local_to_world(j.anchor_b());
            p.dist(closest_on_segment(start, end, p))
        }
        _ => return None,
    };
    Some(error)
}

/// The point of the segment `start`–`end` closest to `p`.
fn closest_on_segment(start: Vect, end: Vect, p: Vect) -> Vect {
    let d = end - start;
    let len_sq = d.length_sq();
    if !len_sq.is_positive() {
        return start;
    }
    let t = ((p - start).dot(d) / len_sq).clamp(Real::ZERO, Real::ONE);
    start + d.mult(t)
}

/// The largest [`joint_error`] over the constraints of `space`, or `None`
/// when it has no measured joint.
pub fn max_joint_error(space: &Space) -> Option<Real> {
    space
        .constraints()
        .filter_map(|(_, c)| joint_error(space, c))
        .reduce(Real::max)
}

/// How far the relative angle of a rotary limit joint is outside its
/// `[min, max]` (radians, 0 inside); `None` for another kind or missing
/// bodies.
pub fn limit_overrun(space: &Space, c: &Constraint) -> Option<Real> {
    let JointKind::RotaryLimit(j) = c.kind() else {
        return None;
    };
    let a = space.body(c.body_a())?;
    let b = space.body(c.body_b())?;
    let rel = b.angle() - a.angle();
    Some((j.min() - rel).max(rel - j.max()).max(Real::ZERO))
}

/// The largest [`limit_overrun`] over the constraints of `space`, or
/// `None` when it has no rotary limit.
pub fn max_limit_overrun(space: &Space) -> Option<Real> {
    space
        .constraints()
        .filter_map(|(_, c)| limit_overrun(space, c))
        .reduce(Real::max)
}

/// The deepest penetration among the current contacts of `space` (see the
/// module docs), ≥ 0; 0 without a touching pair.
pub fn max_penetration(space: &Space) -> Real {
    let sensor = |h| space.shape(h).is_some_and(|s| s.sensor);
    space
        .arbiters()
        .iter()
        .filter(|arb| !matches!(arb.state(), ArbiterState::Cached | ArbiterState::Ignore))
        .filter(|arb| {
            let (sa, sb) = arb.shapes();
            !sensor(sa) && !sensor(sb)
        })
        .flat_map(|arb| arb.contacts().iter().map(|c| -c.dist))
        .fold(Real::ZERO, Real::max)
}

/// The largest joint error and penetration seen over a run: call
/// [`Quality::measure`] after every step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Quality {
    /// Largest [`max_joint_error`] measured (m); `None` while no measured
    /// joint has been seen.
    pub max_joint_error: Option<Real>,
    /// Largest [`max_penetration`] measured (m).
    pub max_penetration: Real,
    /// Largest [`max_limit_overrun`] measured (rad); `None` while no
    /// rotary limit has been seen.
    pub max_limit_overrun: Option<Real>,
    /// Measurements taken.
    pub samples: u64,
}

impl Quality {
    /// Nothing measured yet.
    pub fn new() -> Quality {
        Quality::default()
    }

    /// Measures `space` now and keeps the largest values.
    pub fn measure(&mut self, space: &Space) {
        if let Some(e) = max_joint_error(space) {
            self.max_joint_error = Some(self.max_joint_error.map_or(e, |m| m.max(e)));
        }
        self.max_penetration = self.max_penetration.max(max_penetration(space));
        if let Some(e) = max_limit_overrun(space) {
            self.max_limit_overrun = Some(self.max_limit_overrun.map_or(e, |m| m.max(e)));
        }
        self.samples = self.samples.saturating_add(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BodyDesc, BodyKind, ConstraintDesc, JointType, SceneDesc, ShapeDesc};
    use tamias2d::real;

    /// A static body at the origin and a dynamic one at `(1, 0)`, joined
    /// by `c` (bodies 0 and 1), gravity off.
    fn two_bodies(c: ConstraintDesc) -> Space {
        let mut desc = SceneDesc::new("quality", Real::ratio(1, 60), 1);
        desc.settings.gravity = Vect::ZERO;
        desc.bodies.push(BodyDesc::static_body());
        desc.bodies.push(BodyDesc::dynamic(
            Vect::from_ints(1, 0),
            Real::ONE,
            Real::ONE,
        ));
        desc.constraints.push(c);
        desc.build().expect("valid scene").space
    }

    fn close(got: Option<Real>, want: Real) {
        let got = got.expect("a measured joint");
        assert!(
            (got - want).abs() < Real::from_bits(64),
            "got {got:?}, want {want:?}"
        );
    }

    #[test]
    fn pivot_anchors_a_tenth_apart_measure_a_tenth() {
        let mut c = ConstraintDesc::new(JointType::Pivot, 0, 1);
        c.anchor_a = Some(Vect::new(real!(0.9), Real::ZERO));
        c.anchor_b = Some(Vect::ZERO);
        close(max_joint_error(&two_bodies(c)), real!(0.1));
        let mut held = ConstraintDesc::new(JointType::Pivot, 0, 1);
        held.pivot = Some(Vect::from_ints(1, 0));
        close(max_joint_error(&two_bodies(held)), Real::ZERO);
    }

    #[test]
    fn pin_measures_the_distance_off_its_length() {
        let mut c = ConstraintDesc::new(JointType::Pin, 0, 1);
        c.dist = Some(real!(1.25));
        close(max_joint_error(&two_bodies(c)), real!(0.25));
    }

    #[test]
    fn slide_measures_only_outside_its_range() {
        let mut inside = ConstraintDesc::new(JointType::Slide, 0, 1);
        inside.min = Some(Real::HALF);
        inside.max = Some(Real::TWO);
        close(max_joint_error(&two_bodies(inside)), Real::ZERO);
        let mut long = ConstraintDesc::new(JointType::Slide, 0, 1);
        long.min = Some(Real::ZERO);
        long.max = Some(real!(0.75));
        close(max_joint_error(&two_bodies(long)), real!(0.25));
        let mut short = ConstraintDesc::new(JointType::Slide, 0, 1);
        short.min = Some(real!(1.5));
        short.max = Some(Real::TWO);
        close(max_joint_error(&two_bodies(short)), Real::HALF);
    }

    #[test]
    fn groove_measures_the_distance_to_the_segment() {
        // b's anchor at (1, 0); the groove from (0, 0.3) to (2, 0.3).
        let mut c = ConstraintDesc::new(JointType::Groove, 0, 1);
        c.groove_a = Some(Vect::new(Real::ZERO, real!(0.3)));
        c.groove_b = Some(Vect::new(Real::TWO, real!(0.3)));
        close(max_joint_error(&two_bodies(c)), real!(0.3));
        // Past the groove's end: the distance to the end point (0.6, 0.8).
        let mut past = ConstraintDesc::new(JointType::Groove, 0, 1);
        past.groove_a = Some(Vect::new(real!(-1), real!(-0.8)));
        past.groove_b = Some(Vect::new(real!(0.4), real!(-0.8)));
        close(max_joint_error(&two_bodies(past)), Real::ONE);
    }

    #[test]
    fn springs_and_motors_are_not_measured() {
        let mut c = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
        c.rate = Some(Real::ONE);
        assert_eq!(max_joint_error(&two_bodies(c)), None);
    }

    #[test]
    fn penetration_is_the_deepest_touching_contact() {
        // A unit box resting 0.1 m into a static box, no gravity: after a
        // step the contacts report about 0.1 m (less what one step pushed
        // out).
        let mut desc = SceneDesc::new("overlap", Real::ratio(1, 60), 1);
        desc.settings.gravity = Vect::ZERO;
        desc.bodies
            .push(BodyDesc::static_body().with_shape(ShapeDesc::box_shape(
                Real::from_int(4),
                Real::ONE,
                Real::ZERO,
            )));
        desc.bodies.push(
            BodyDesc::new(BodyKind::Dynamic, Vect::new(Real::ZERO, real!(0.9))).with_shape(
                ShapeDesc::box_shape(Real::ONE, Real::ONE, Real::ZERO).density(Real::ONE),
            ),
        );
        let mut world = desc.build().expect("valid scene");
        assert_eq!(max_penetration(&world.space), Real::ZERO, "no step yet");
        world.step().expect("step");
        let depth = max_penetration(&world.space);
        assert!(
            depth > real!(0.08) && depth <= real!(0.1),
            "depth {depth:?}"
        );
        let mut q = Quality::new();
        q.measure(&world.space);
        assert_eq!(q.max_penetration, depth);
        assert_eq!(q.max_joint_error, None);
        assert_eq!(q.samples, 1);
    }

    #[test]
    fn a_hanging_chain_starts_with_its_joints_closed() {
        let world = crate::builtin("hanging_chain_20_100")
            .expect("registered")
            .build()
            .expect("valid");
        close(max_joint_error(&world.space), Real::ZERO);
        assert_eq!(world.space.constraints().count(), 21);
    }
}
