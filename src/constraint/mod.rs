//! Constraints (joints): Chipmunk's `cpConstraint` and its kinds, in fixed
//! point. Per-constraint pre-solve and post-solve callbacks (closures, not
//! state) are set on the space: `Space::set_constraint_pre_solve`,
//! `Space::set_constraint_post_solve`.
//!
//! A [`Constraint`] ties two bodies `a` and `b` of one space. The shared
//! part (Chipmunk's `cpConstraint`) holds the two bodies, `max_force`,
//! `error_bias`, `max_bias` and `collide_bodies`; the kind ([`JointKind`],
//! one file per kind) holds its parameters and its accumulated impulse.
//! Chipmunk's ten kinds, with its semantics and parameter names:
//!
//! | kind | Chipmunk | keeps |
//! |---|---|---|
//! | [`PinJoint`] | `cpPinJoint` | the distance `dist` between two anchors |
//! | [`PivotJoint`] | `cpPivotJoint` | two anchors at one point |
//! | [`DampedSpring`] | `cpDampedSpring` | a spring of `rest_length`, `stiffness`, `damping` between two anchors |
//! | [`SimpleMotor`] | `cpSimpleMotor` | the relative angular velocity at `rate` |
//! | [`GearJoint`] | `cpGearJoint` | the angles in the ratio `ratio`, offset by `phase` |
//! | [`SlideJoint`] | `cpSlideJoint` | the distance between two anchors within `[min, max]` |
//! | [`RotaryLimitJoint`] | `cpRotaryLimitJoint` | the relative angle within `[min, max]` |
//! | [`DampedRotarySpring`] | `cpDampedRotarySpring` | an angular spring of `rest_angle`, `stiffness`, `damping` |
//! | [`GrooveJoint`] | `cpGrooveJoint` | a pivot on b sliding along a groove on a |
//! | [`RatchetJoint`] | `cpRatchetJoint` | the relative angle free one way, caught every `ratchet` the other |
//!
//! # State and cache
//! A constraint is world state ([`WorldState::constraints`], an arena like
//! bodies and shapes): its parameters and its accumulated impulse (the warm
//! start of the next step, and what [`Constraint::impulse`] reports) are
//! saved in snapshots, hashed by the checksum, compared by
//! `first_difference` and checked by `validate_state`
//! ([`validate_constraints`]). Everything the solver derives from them each
//! sub-step (anchors in world space, effective masses, bias) lives in the
//! space's caches (module `solve`).
//!
//! # Solving
//! Constraints are solved in the same Gauss–Seidel iterations as contacts,
//! as Chipmunk does: prepared once per sub-step after the contacts'
//! pre-step (all divisions and the `error_bias` power happen there), warm
//! started after the contacts with the accumulated impulse scaled by
//! `min(dt / prev_dt, 1)` (as contacts are), and one impulse pass per
//! iteration after the contacts' pass, in constraint slot order (canonical:
//! it depends only on the state). Position error is corrected as in
//! Chipmunk: a bias *velocity* `−(1 − error_bias^dt)·C/dt`, capped at
//! `max_bias`, added to the velocity target (not a pseudo-velocity); the
//! accumulated impulse is clamped to `max_force·dt`.
//!
//! The warm start and the iterations run on the contacts' fast path
//! (module `kernel`): each kind's impulse code is generic over the
//! arithmetic, runs first in `math::Unsaturated` (wide integer operations,
//! one overflow flag, no per-operation saturation checks) and is rerun in
//! the saturating `Real` arithmetic only when the flag is raised, so the
//! result is always the saturating one, bit for bit. The pre-step (once per
//! sub-step, with its divisions and roots) is saturating `Real` arithmetic.
//!
//! # Parameters
//! Constructors and setters check their parameters and return
//! [`ConstraintError`] (never panic): lengths and forces must not be
//! negative, a pin joint's distance must be positive, a gear ratio
//! non-zero, `error_bias` in `[0, 1]`, and no value may be saturated
//! (`Real::MIN` or `Real::MAX`, the fixed-point stand-ins for infinities)
//! except `max_force` and `max_bias`, where `Real::MAX` means "unbounded"
//! (Chipmunk's `INFINITY`, the default). The space checks the bodies:
//! two different bodies of that space.
//!
//! # Driving a joint
//! Every parameter Chipmunk lets a game set at run time (its `cp…Set…`
//! routines) has a setter on its kind: [`SimpleMotor::set_rate`], the
//! springs' `set_stiffness`, `set_damping`, `set_rest_length` /
//! `set_rest_angle`, the limits' `set_min`, `set_max` and `set_limits`,
//! the anchors, [`GearJoint::set_ratio`], the ratchet's `set_angle`, …;
//! the shared `max_force`, `error_bias` and `max_bias` are
//! [`Constraint`]'s. A setter checks the value as the constructor does
//! (the same [`ConstraintError`]), leaves the joint unchanged on an error,
//! and keeps the accumulated impulse: the next step warm starts from it,
//! as Chipmunk's setters keep `jAcc`. (Replacing the kind with
//! [`Constraint::set_kind`] starts it from the new kind's impulse, zero for
//! a constructed one.)
//!
//! A joint is reached by its type ([`Joint`]): [`Constraint::joint`] and
//! [`Constraint::joint_mut`] (the latter an error,
//! [`ConstraintError::WrongKind`], for a joint of another kind, so that it
//! composes with `?`). In a space,
//! [`Space::modify_constraint`](crate::space::Space::modify_constraint)
//! applies a closure to a copy, keeps it only if every step of it
//! succeeded, and wakes the joint's dynamic bodies (Chipmunk's
//! `cpConstraintActivateBodies`):
//! `space.modify_constraint(h, |c| c.joint_mut::<SimpleMotor>()?.set_rate(r))`.
//! [`Space::constraint_mut`](crate::space::Space::constraint_mut) and a
//! pre-solve callback's [`ConstraintContext`](crate::space::ConstraintContext)
//! give the constraint mutably as well.
//!
//! [`WorldState::constraints`]: crate::space::WorldState::constraints
mod axis;
mod damped_rotary_spring;
mod damped_spring;
mod error;
mod gear;
mod groove;
pub(crate) mod kernel;
mod pin;
mod pivot;
mod point;
mod prep;
mod ratchet;
mod rotary_limit;
mod simple_motor;
mod slide;
pub(crate) mod solve;

use serde::{Deserialize, Serialize};

pub use damped_rotary_spring::DampedRotarySpring;
pub use damped_spring::DampedSpring;
pub use error::ConstraintError;
pub use gear::GearJoint;
pub use groove::GrooveJoint;
pub use pin::PinJoint;
pub use pivot::PivotJoint;
pub use ratchet::RatchetJoint;
pub use rotary_limit::RotaryLimitJoint;
pub use simple_motor::SimpleMotor;
pub use slide::SlideJoint;

use crate::arena::{Arena, Handle};
use crate::body::{Body, BodyHandle};
use crate::math::Real;

/// Chipmunk's default `error_bias`, `0.9^60` (10 % of the error corrected
/// per 1/60 s), computed exactly at compile time: the same value as the
/// space's default collision bias.
pub const DEFAULT_ERROR_BIAS: Real = {
    let base = Real::lit("0.9");
    let mut acc = Real::ONE;
    let mut i = 0;
    while i < 60 {
        acc = acc.mul_const(base);
        i += 1;
    }
    acc
};

/// Handle of a constraint in a space.
pub type ConstraintHandle = Handle<Constraint>;

/// The kind of a constraint: its parameters and accumulated impulse.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum JointKind {
    /// [`PinJoint`].
    Pin(PinJoint),
    /// [`PivotJoint`].
    Pivot(PivotJoint),
    /// [`DampedSpring`].
    DampedSpring(DampedSpring),
    /// [`SimpleMotor`].
    SimpleMotor(SimpleMotor),
    /// [`GearJoint`].
    Gear(GearJoint),
    /// [`SlideJoint`].
    Slide(SlideJoint),
    /// [`RotaryLimitJoint`].
    RotaryLimit(RotaryLimitJoint),
    /// [`DampedRotarySpring`].
    DampedRotarySpring(DampedRotarySpring),
    /// [`GrooveJoint`].
    Groove(GrooveJoint),
    /// [`RatchetJoint`].
    Ratchet(RatchetJoint),
}

/// A joint kind's parameter type ([`PinJoint`], [`SimpleMotor`], …): what
/// [`Constraint::joint`] and [`Constraint::joint_mut`] reach by type.
/// Sealed: implemented by the ten kinds only.
pub trait Joint: Copy + Into<JointKind> + sealed::Sealed {
    /// The kind's short name ([`JointKind::name`]).
    const NAME: &'static str;
    /// The kind's parameters, if `kind` is of this kind.
    fn of(kind: &JointKind) -> Option<&Self>;
    /// The kind's parameters, mutably, if `kind` is of this kind.
    fn of_mut(kind: &mut JointKind) -> Option<&mut Self>;
}

mod sealed {
    /// Only the crate's joint kinds are [`Joint`](super::Joint)s.
    pub trait Sealed {}
}

/// `From<Kind> for JointKind` and `Joint for Kind`, for each kind.
macro_rules! joint_kinds {
    ($($kind:ident => $variant:ident, $name:literal;)*) => {$(
        impl From<$kind> for JointKind {
            fn from(j: $kind) -> Self {
                JointKind::$variant(j)
            }
        }
        impl sealed::Sealed for $kind {}
        impl Joint for $kind {
            const NAME: &'static str = $name;
            fn of(kind: &JointKind) -> Option<&Self> {
                match kind {
                    JointKind::$variant(j) => Some(j),
                    _ => None,
                }
            }
            fn of_mut(kind: &mut JointKind) -> Option<&mut Self> {
                match kind {
                    JointKind::$variant(j) => Some(j),
                    _ => None,
                }
            }
        }
    )*};
}

joint_kinds! {
    PinJoint => Pin, "pin";
    PivotJoint => Pivot, "pivot";
    DampedSpring => DampedSpring, "damped_spring";
    SimpleMotor => SimpleMotor, "simple_motor";
    GearJoint => Gear, "gear";
    SlideJoint => Slide, "slide";
    RotaryLimitJoint => RotaryLimit, "rotary_limit";
    DampedRotarySpring => DampedRotarySpring, "damped_rotary_spring";
    GrooveJoint => Groove, "groove";
    RatchetJoint => Ratchet, "ratchet";
}

impl JointKind {
    /// The kind's own parameter checks (the same as its constructor's).
    pub fn validate(&self) -> Result<(), ConstraintError> {
        match self {
            JointKind::Pin(j) => j.validate(),
            JointKind::Pivot(j) => j.validate(),
            JointKind::DampedSpring(j) => j.validate(),
            JointKind::SimpleMotor(j) => j.validate(),
            JointKind::Gear(j) => j.validate(),
            JointKind::Slide(j) => j.validate(),
            JointKind::RotaryLimit(j) => j.validate(),
            JointKind::DampedRotarySpring(j) => j.validate(),
            JointKind::Groove(j) => j.validate(),
            JointKind::Ratchet(j) => j.validate(),
        }
    }

    /// The impulse of the last step (see [`Constraint::impulse`]).
    fn impulse(&self) -> Real {
        match self {
            JointKind::Pin(j) => j.jn_acc.abs(),
            JointKind::Pivot(j) => j.j_acc.length(),
            JointKind::DampedSpring(j) => j.j_acc,
            JointKind::SimpleMotor(j) => j.j_acc.abs(),
            JointKind::Gear(j) => j.j_acc.abs(),
            JointKind::Slide(j) => j.jn_acc.abs(),
            JointKind::RotaryLimit(j) => j.j_acc.abs(),
            JointKind::DampedRotarySpring(j) => j.j_acc,
            JointKind::Groove(j) => j.j_acc.length(),
            JointKind::Ratchet(j) => j.j_acc.abs(),
        }
    }

    /// The kind's short name, as in scene files ([`Joint::NAME`]).
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Pin(_) => PinJoint::NAME,
            JointKind::Pivot(_) => PivotJoint::NAME,
            JointKind::DampedSpring(_) => DampedSpring::NAME,
            JointKind::SimpleMotor(_) => SimpleMotor::NAME,
            JointKind::Gear(_) => GearJoint::NAME,
            JointKind::Slide(_) => SlideJoint::NAME,
            JointKind::RotaryLimit(_) => RotaryLimitJoint::NAME,
            JointKind::DampedRotarySpring(_) => DampedRotarySpring::NAME,
            JointKind::Groove(_) => GrooveJoint::NAME,
            JointKind::Ratchet(_) => RatchetJoint::NAME,
        }
    }
}

/// A constraint between two bodies (Chipmunk `cpConstraint`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Constraint {
    pub(crate) a: BodyHandle,
    pub(crate) b: BodyHandle,
    pub(crate) max_force: Real,
    pub(crate) error_bias: Real,
    pub(crate) max_bias: Real,
    pub(crate) collide_bodies: bool,
    pub(crate) kind: JointKind,
    /// The soft step's stiffness of this joint (`None`: the world's
    /// `SoftStep::joint_hertz` and `joint_damping_ratio`).
    pub(crate) softness: Option<JointSoftness>,
}

/// The derive's hash of every field in declaration order, except that a
/// constraint without its own softness adds nothing for it: worlds built
/// before joints had a softness keep their checksums.
impl core::hash::Hash for Constraint {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Constraint {
            a,
            b,
            max_force,
            error_bias,
            max_bias,
            collide_bodies,
            kind,
            softness,
        } = self;
        a.hash(h);
        b.hash(h);
        max_force.hash(h);
        error_bias.hash(h);
        max_bias.hash(h);
        collide_bodies.hash(h);
        kind.hash(h);
        if let Some(s) = softness {
            s.hash(h);
        }
    }
}

/// A joint's own stiffness on the soft step: a frequency and a damping
/// ratio, as `SoftStep::joint_hertz` and `joint_damping_ratio` (capped at
/// a quarter of the sub-step rate alike). The sequential solver ignores it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct JointSoftness {
    /// Stiffness in hertz (0: rigid, no position correction).
    pub hertz: Real,
    /// Damping ratio.
    pub damping_ratio: Real,
}

impl JointSoftness {
    /// Both in `[0, MAX_SOFT_PARAMETER]` (10⁶).
    pub fn validate(&self) -> Result<(), ConstraintError> {
        let max = Real::from_int(1_000_000);
        for (v, name) in [(self.hertz, "hertz"), (self.damping_ratio, "damping_ratio")] {
            if v.is_negative() {
                return Err(ConstraintError::Negative(name));
            }
            if v > max {
                return Err(ConstraintError::Saturated(name));
            }
        }
        Ok(())
    }
}

impl Constraint {
    /// A constraint of `kind` between bodies `a` and `b`, with Chipmunk's
    /// defaults: unbounded `max_force` and `max_bias`, `error_bias` =
    /// `0.9^60` (10 % of the error corrected per 1/60 s), `collide_bodies`
    /// true. Errors if `a == b`; [`Space::add_constraint`](crate::space::Space::add_constraint)
    /// checks that both bodies are in the space.
    pub fn new(
        a: BodyHandle,
        b: BodyHandle,
        kind: impl Into<JointKind>,
    ) -> Result<Constraint, ConstraintError> {
        if a == b {
            return Err(ConstraintError::SameBody);
        }
        let kind = kind.into();
        kind.validate()?;
        Ok(Constraint {
            a,
            b,
            max_force: Real::MAX,
            error_bias: DEFAULT_ERROR_BIAS,
            max_bias: Real::MAX,
            collide_bodies: true,
            kind,
            softness: None,
        })
    }

    /// Body a (Chipmunk `cpConstraintGetBodyA`).
    pub fn body_a(&self) -> BodyHandle {
        self.a
    }

    /// Body b.
    pub fn body_b(&self) -> BodyHandle {
        self.b
    }

    /// The kind, with its parameters.
    pub fn kind(&self) -> &JointKind {
        &self.kind
    }

    /// The kind's parameters if the constraint is of kind `T`:
    /// `c.joint::<SimpleMotor>().map(SimpleMotor::rate)`.
    pub fn joint<T: Joint>(&self) -> Option<&T> {
        T::of(&self.kind)
    }

    /// The kind's parameters, mutably, for their setters (Chipmunk's
    /// `cp…Set…` routines: [`SimpleMotor::set_rate`],
    /// [`DampedSpring::set_stiffness`], …), which check the new value as
    /// the constructor does, leave the joint unchanged on an error and keep
    /// the accumulated impulse (the warm start: a motor whose rate changes
    /// every frame does not start from zero each time, as it would after
    /// [`set_kind`](Self::set_kind)). [`ConstraintError::WrongKind`] if the
    /// constraint is of another kind, so that `?` reads well in
    /// [`Space::modify_constraint`](crate::space::Space::modify_constraint):
    ///
    /// ```
    /// # use tamias2d::body::Body;
    /// # use tamias2d::constraint::{Constraint, SimpleMotor};
    /// # use tamias2d::space::Space;
    /// # use tamias2d::Real;
    /// # let mut space = Space::new();
    /// # let a = space.add_body(Body::new_static())?;
    /// # let b = space.add_body(Body::new(Real::ONE, Real::ONE)?)?;
    /// let motor = space.add_constraint(Constraint::new(a, b, SimpleMotor::new(Real::ZERO)?)?)?;
    /// space.modify_constraint(motor, |c| c.joint_mut::<SimpleMotor>()?.set_rate(Real::TWO))?;
    /// assert_eq!(space.constraint(motor).and_then(|c| c.joint::<SimpleMotor>()).map(|m| m.rate()), Some(Real::TWO));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// Assigning a whole value through the reference (`*m = other`) skips
    /// the checks of a value built elsewhere (deserialised); that is what
    /// [`set_kind`](Self::set_kind) is for.
    pub fn joint_mut<T: Joint>(&mut self) -> Result<&mut T, ConstraintError> {
        let found = self.kind.name();
        T::of_mut(&mut self.kind).ok_or(ConstraintError::WrongKind {
            expected: T::NAME,
            found,
        })
    }

    /// Replaces the kind's parameters after checking them (the accumulated
    /// impulse comes with `kind`; a kind built by its constructor starts
    /// from zero).
    pub fn set_kind(&mut self, kind: impl Into<JointKind>) -> Result<(), ConstraintError> {
        let kind = kind.into();
        kind.validate()?;
        self.kind = kind;
        Ok(())
    }

    /// Largest force the constraint applies (Chipmunk `maxForce`;
    /// `Real::MAX`: unbounded).
    pub fn max_force(&self) -> Real {
        self.max_force
    }

    /// Sets `max_force` (≥ 0; `Real::MAX` for unbounded).
    pub fn set_max_force(&mut self, max_force: Real) -> Result<(), ConstraintError> {
        if max_force.is_negative() {
            return Err(ConstraintError::Negative("max_force"));
        }
        self.max_force = max_force;
        Ok(())
    }

    /// Fraction of the position error left uncorrected after one second
    /// (Chipmunk `errorBias`, default `0.9^60`).
    pub fn error_bias(&self) -> Real {
        self.error_bias
    }

    /// Sets `error_bias` (in `[0, 1]`; 1 corrects nothing).
    pub fn set_error_bias(&mut self, error_bias: Real) -> Result<(), ConstraintError> {
        if error_bias.is_negative() || error_bias > Real::ONE {
            return Err(ConstraintError::ErrorBiasRange);
        }
        self.error_bias = error_bias;
        Ok(())
    }

    /// Largest speed of the error correction (Chipmunk `maxBias`;
    /// `Real::MAX`: unbounded).
    pub fn max_bias(&self) -> Real {
        self.max_bias
    }

    /// Sets `max_bias` (≥ 0; `Real::MAX` for unbounded).
    pub fn set_max_bias(&mut self, max_bias: Real) -> Result<(), ConstraintError> {
        if max_bias.is_negative() {
            return Err(ConstraintError::Negative("max_bias"));
        }
        self.max_bias = max_bias;
        Ok(())
    }

    /// The joint's own stiffness on the soft step, if it has one.
    pub fn softness(&self) -> Option<JointSoftness> {
        self.softness
    }

    /// Gives the joint its own stiffness on the soft step (`None`: the
    /// world's). Errors on a negative or absurd (> 10⁶) value.
    pub fn set_softness(&mut self, softness: Option<JointSoftness>) -> Result<(), ConstraintError> {
        if let Some(s) = &softness {
            s.validate()?;
        }
        self.softness = softness;
        Ok(())
    }

    /// Whether the shapes of the two bodies collide with each other
    /// (Chipmunk `collideBodies`, default true).
    pub fn collide_bodies(&self) -> bool {
        self.collide_bodies
    }

    /// Sets `collide_bodies`.
    pub fn set_collide_bodies(&mut self, collide: bool) {
        self.collide_bodies = collide;
    }

    /// The impulse the constraint applied in the last sub-step (Chipmunk
    /// `cpConstraintGetImpulse`): the magnitude of the accumulated impulse,
    /// signed for the springs as in Chipmunk ([`DampedSpring`]: negative
    /// pulls the anchors together; [`DampedRotarySpring`]: positive turns
    /// b forward). Divide by the step's `dt` for the force; a game breaks a
    /// joint when it exceeds a threshold.
    pub fn impulse(&self) -> Real {
        self.kind.impulse()
    }

    /// The shared parameters' checks (see [`validate_constraints`]).
    pub fn validate(&self) -> Result<(), ConstraintError> {
        if self.a == self.b {
            return Err(ConstraintError::SameBody);
        }
        if self.max_force.is_negative() {
            return Err(ConstraintError::Negative("max_force"));
        }
        if self.max_bias.is_negative() {
            return Err(ConstraintError::Negative("max_bias"));
        }
        if self.error_bias.is_negative() || self.error_bias > Real::ONE {
            return Err(ConstraintError::ErrorBiasRange);
        }
        if let Some(s) = &self.softness {
            s.validate()?;
        }
        self.kind.validate()
    }
}

/// The constraint invariants of `validate_state`: each constraint's
/// parameters ([`Constraint::validate`]) and two different live bodies.
pub fn validate_constraints(
    constraints: &Arena<Constraint>,
    bodies: &Arena<Body>,
) -> Result<(), String> {
    constraints
        .validate()
        .map_err(|e| format!("constraints: {e}"))?;
    for (h, c) in constraints.iter() {
        c.validate().map_err(|e| format!("constraint {h:?}: {e}"))?;
        for body in [c.a, c.b] {
            if !bodies.contains(body) {
                return Err(format!("constraint {h:?} names missing body {body:?}"));
            }
        }
    }
    Ok(())
}
