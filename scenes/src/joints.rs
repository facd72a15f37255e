//! Joints in scene descriptions ([`ConstraintDesc`]) and the joint scenes
//! of the registry (section D: `pendulum`, `chain_100`, `windmill`, …).
//!
//! A constraint is one flat JSON object: its `type` (`pin`, `slide`,
//! `pivot`, `groove`, `damped_spring`, `damped_rotary_spring`,
//! `rotary_limit`, `ratchet`, `gear`, `simple_motor`), the two bodies `a`
//! and `b` (indices into `SceneDesc::bodies`), the kind's parameters under
//! Chipmunk's names as exact decimal strings, and optionally `max_force`,
//! `max_bias`, `error_bias` and `collide_bodies`. A parameter the kind does
//! not have is an error, as is a missing one, when the scene is built:
//!
//! ```json
//! { "type": "pin", "a": 0, "b": 1 }
//! { "type": "damped_spring", "a": 0, "b": 2, "anchor_a": ["1", "0"],
//!   "rest_length": "2", "stiffness": "100", "damping": "0.5" }
//! ```
//!
//! Anchors default to the bodies' origins; a pin without `dist` takes the
//! current distance of its anchors (Chipmunk's `cpPinJointNew`), a pivot
//! with `pivot` (a world point) converts it to both bodies' coordinates
//! (`cpPivotJointNew`).
use serde::{Deserialize, Serialize};

use super::dec;
use super::desc::{BodyDesc, BodyKind, MassDesc, SceneDesc, SettingsDesc, ShapeDesc, SpawnDesc};
use tamias2d::body::BodyHandle;
use tamias2d::constraint::{
    Constraint, DampedRotarySpring, DampedSpring, GearJoint, GrooveJoint, JointKind, PinJoint,
    PivotJoint, RatchetJoint, RotaryLimitJoint, SimpleMotor, SlideJoint,
};
use tamias2d::math::{Real, Vect};
use tamias2d::real;
use tamias2d::space::{Space, SpaceError};

/// The kind of a [`ConstraintDesc`] (its `type`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointType {
    /// [`PinJoint`].
    #[default]
    Pin,
    /// [`SlideJoint`].
    Slide,
    /// [`PivotJoint`].
    Pivot,
    /// [`GrooveJoint`].
    Groove,
    /// [`DampedSpring`].
    DampedSpring,
    /// [`DampedRotarySpring`].
    DampedRotarySpring,
    /// [`RotaryLimitJoint`].
    RotaryLimit,
    /// [`RatchetJoint`].
    Ratchet,
    /// [`GearJoint`].
    Gear,
    /// [`SimpleMotor`].
    SimpleMotor,
}

/// One joint of a scene (see the module docs for the format).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintDesc {
    /// The kind.
    #[serde(rename = "type")]
    pub kind: JointType,
    /// Index of body a in `SceneDesc::bodies`.
    pub a: u32,
    /// Index of body b.
    pub b: u32,
    /// Anchor on a (body coordinates); default the origin.
    #[serde(
        default,
        with = "dec::opt_vect",
        skip_serializing_if = "Option::is_none"
    )]
    pub anchor_a: Option<Vect>,
    /// Anchor on b (body coordinates); default the origin.
    #[serde(
        default,
        with = "dec::opt_vect",
        skip_serializing_if = "Option::is_none"
    )]
    pub anchor_b: Option<Vect>,
    /// Pivot: the shared point in world coordinates (instead of anchors).
    #[serde(
        default,
        with = "dec::opt_vect",
        skip_serializing_if = "Option::is_none"
    )]
    pub pivot: Option<Vect>,
    /// Groove: start on a.
    #[serde(
        default,
        with = "dec::opt_vect",
        skip_serializing_if = "Option::is_none"
    )]
    pub groove_a: Option<Vect>,
    /// Groove: end on a.
    #[serde(
        default,
        with = "dec::opt_vect",
        skip_serializing_if = "Option::is_none"
    )]
    pub groove_b: Option<Vect>,
    /// Pin: distance (default: measured).
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub dist: Option<Real>,
    /// Slide and rotary limit: lower limit.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub min: Option<Real>,
    /// Slide and rotary limit: upper limit.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub max: Option<Real>,
    /// Damped spring: rest length.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub rest_length: Option<Real>,
    /// Damped rotary spring: rest angle.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub rest_angle: Option<Real>,
    /// Springs: stiffness.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub stiffness: Option<Real>,
    /// Springs: damping.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub damping: Option<Real>,
    /// Gear and ratchet: phase.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub phase: Option<Real>,
    /// Gear: ratio.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub ratio: Option<Real>,
    /// Ratchet: tooth spacing.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub ratchet: Option<Real>,
    /// Simple motor: rate.
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub rate: Option<Real>,
    /// Largest force (default unbounded).
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub max_force: Option<Real>,
    /// Largest correction speed (default unbounded).
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub max_bias: Option<Real>,
    /// Error left after one second (default `0.9^60`).
    #[serde(
        default,
        with = "dec::opt_real",
        skip_serializing_if = "Option::is_none"
    )]
    pub error_bias: Option<Real>,
    /// Whether the two bodies' shapes collide (default true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collide_bodies: Option<bool>,
}

impl ConstraintDesc {
    /// A constraint of `kind` between bodies `a` and `b`, every parameter
    /// unset.
    pub fn new(kind: JointType, a: u32, b: u32) -> ConstraintDesc {
        ConstraintDesc {
            kind,
            a,
            b,
            ..ConstraintDesc::default()
        }
    }

    /// The parameters that are set, by name.
    fn given(&self) -> [(&'static str, bool); 14] {
        [
            ("anchor_a", self.anchor_a.is_some()),
            ("anchor_b", self.anchor_b.is_some()),
            ("pivot", self.pivot.is_some()),
            ("groove_a", self.groove_a.is_some()),
            ("groove_b", self.groove_b.is_some()),
            ("dist", self.dist.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("rest_length", self.rest_length.is_some()),
            ("rest_angle", self.rest_angle.is_some()),
            ("stiffness", self.stiffness.is_some()),
            ("damping", self.damping.is_some()),
            ("phase", self.phase.is_some()),
            ("ratio", self.ratio.is_some()),
        ]
    }

    /// Builds the constraint between `a` and `b` of `space` (bodies already
    /// added). Errors name the problem.
    pub(crate) fn build(
        &self,
        space: &Space,
        a: BodyHandle,
        b: BodyHandle,
    ) -> Result<Constraint, String> {
        let kind = self.kind;
        let allowed: &[&str] = match kind {
            JointType::Pin => &["anchor_a", "anchor_b", "dist"],
            JointType::Slide => &["anchor_a", "anchor_b", "min", "max"],
            JointType::Pivot => &["anchor_a", "anchor_b", "pivot"],
            JointType::Groove => &["groove_a", "groove_b", "anchor_b"],
            JointType::DampedSpring => &[
                "anchor_a",
                "anchor_b",
                "rest_length",
                "stiffness",
                "damping",
            ],
            JointType::DampedRotarySpring => &["rest_angle", "stiffness", "damping"],
            JointType::RotaryLimit => &["min", "max"],
            JointType::Ratchet => &["phase"],
            JointType::Gear => &["phase", "ratio"],
            JointType::SimpleMotor => &[],
        };
        let extra = [
            ("ratchet", self.ratchet.is_some(), JointType::Ratchet),
            ("rate", self.rate.is_some(), JointType::SimpleMotor),
        ];
        if let Some((name, _)) = self
            .given()
            .iter()
            .find(|(n, set)| *set && !allowed.contains(n))
        {
            return Err(format!("{name} is not a parameter of {kind:?}"));
        }
        if let Some((name, _, _)) = extra.iter().find(|(_, set, k)| *set && *k != kind) {
            return Err(format!("{name} is not a parameter of {kind:?}"));
        }
        let need = |v: Option<Real>, name: &str| v.ok_or(format!("{kind:?} needs {name}"));
        let anchor_a = self.anchor_a.unwrap_or(Vect::ZERO);
        let anchor_b = self.anchor_b.unwrap_or(Vect::ZERO);
        let err = |e: tamias2d::constraint::ConstraintError| e.to_string();
        let space_err = |e: SpaceError| e.to_string();
        let joint: JointKind = match kind {
            JointType::Pin => match self.dist {
                Some(d) => PinJoint::new(anchor_a, anchor_b, d).map_err(err)?.into(),
                None => *space
                    .pin_joint(a, b, anchor_a, anchor_b)
                    .map_err(space_err)?
                    .kind(),
            },
            JointType::Slide => SlideJoint::new(
                anchor_a,
                anchor_b,
                need(self.min, "min")?,
                need(self.max, "max")?,
            )
            .map_err(err)?
            .into(),
            JointType::Pivot => match self.pivot {
                Some(p) => {
                    if self.anchor_a.is_some() || self.anchor_b.is_some() {
                        return Err("a pivot takes either `pivot` or anchors".into());
                    }
                    *space.pivot_joint(a, b, p).map_err(space_err)?.kind()
                }
                None => PivotJoint::new(anchor_a, anchor_b).map_err(err)?.into(),
            },
            JointType::Groove => GrooveJoint::new(
                self.groove_a.ok_or("Groove needs groove_a")?,
                self.groove_b.ok_or("Groove needs groove_b")?,
                anchor_b,
            )
            .map_err(err)?
            .into(),
            JointType::DampedSpring => DampedSpring::new(
                anchor_a,
                anchor_b,
                need(self.rest_length, "rest_length")?,
                need(self.stiffness, "stiffness")?,
                need(self.damping, "damping")?,
            )
            .map_err(err)?
            .into(),
            JointType::DampedRotarySpring => DampedRotarySpring::new(
                need(self.rest_angle, "rest_angle")?,
                need(self.stiffness, "stiffness")?,
                need(self.damping, "damping")?,
            )
            .map_err(err)?
            .into(),
            JointType::RotaryLimit => {
                RotaryLimitJoint::new(need(self.min, "min")?, need(self.max, "max")?)
                    .map_err(err)?
                    .into()
            }
            JointType::Ratchet => RatchetJoint::new(
                self.phase.unwrap_or(Real::ZERO),
                need(self.ratchet, "ratchet")?,
            )
            .map_err(err)?
            .into(),
            JointType::Gear => {
                GearJoint::new(self.phase.unwrap_or(Real::ZERO), need(self.ratio, "ratio")?)
                    .map_err(err)?
                    .into()
            }
            JointType::SimpleMotor => SimpleMotor::new(need(self.rate, "rate")?)
                .map_err(err)?
                .into(),
        };
        let mut c = Constraint::new(a, b, joint).map_err(err)?;
        if let Some(f) = self.max_force {
            c.set_max_force(f).map_err(err)?;
        }
        if let Some(m) = self.max_bias {
            c.set_max_bias(m).map_err(err)?;
        }
        if let Some(e) = self.error_bias {
            c.set_error_bias(e).map_err(err)?;
        }
        if let Some(collide) = self.collide_bodies {
            c.set_collide_bodies(collide);
        }
        Ok(c)
    }
}

fn scene(name: &str, steps: u32) -> SceneDesc {
    SceneDesc {
        settings: SettingsDesc::with_gravity(Vect::from_ints(0, -10), 10),
        ..SceneDesc::new(name, Real::ratio(1, 60), steps)
    }
}

/// `pendulum`: a 1 kg bob (a circle of radius 0.1, moment 0.005) on a
/// 1 m pin joint from a static body at the origin, released at rest 0.6 m
/// to the right (about 37° from the vertical); 600 steps (10 s). g = 10.
pub fn pendulum() -> SceneDesc {
    let mut desc = scene("pendulum", 600);
    desc.bodies.push(BodyDesc::static_body().labeled("pivot"));
    let bob = BodyDesc::dynamic(Vect::new(real!(0.6), real!(-0.8)), Real::ONE, real!(0.005))
        .with_shape(ShapeDesc::circle(real!(0.1)))
        .labeled("bob");
    desc.bodies.push(bob);
    desc.constraints
        .push(ConstraintDesc::new(JointType::Pin, 0, 1));
    desc
}

/// `chain_{n}`: `n` links (boxes 0.9 × 0.2 m, density 1, friction 0.6)
/// hanging from a static body by pivot joints 1 m apart, starting
/// horizontal to the right at y = 0 and falling under g = 10; the last
/// link is 100 times denser (a 100:1 end-mass ratio). Neighbouring links
/// do not collide (`collide_bodies = false`); 4 sub-steps of 10
/// iterations (a single 1/60 s step lets the swinging end, at up to
/// 45 m/s, open the joints by metres; 30 iterations do not help, sub-steps
/// do: the joints' error grows with the square of the step); 600 steps.
pub fn chain(n: u32) -> SceneDesc {
    let mut desc = scene(&format!("chain_{n}"), 600);
    desc.settings.substeps = 4;
    desc.bodies.push(BodyDesc::static_body().labeled("anchor"));
    for i in 0..n {
        let x = Real::from_int(i32::try_from(i).unwrap_or(0)) + Real::HALF;
        let density = if i.saturating_add(1) == n {
            Real::from_int(100)
        } else {
            Real::ONE
        };
        let shape = ShapeDesc::box_shape(real!(0.9), real!(0.2), Real::ZERO)
            .material(real!(0.6), Real::ZERO)
            .density(density);
        let link = BodyDesc {
            mass: MassDesc::FromShapes,
            ..BodyDesc::new(BodyKind::Dynamic, Vect::new(x, Real::ZERO))
        }
        .with_shape(shape);
        desc.bodies.push(link);
        let mut c = ConstraintDesc::new(JointType::Pivot, i, i.saturating_add(1));
        c.anchor_a = Some(if i == 0 {
            Vect::ZERO
        } else {
            Vect::new(Real::HALF, Real::ZERO)
        });
        c.anchor_b = Some(Vect::new(-Real::HALF, Real::ZERO));
        c.collide_bodies = Some(false);
        desc.constraints.push(c);
    }
    if let Some(end) = desc.bodies.last_mut() {
        end.label = Some("end".into());
    }
    desc
}

/// Length of a link of [`hanging_chain`] (m).
const LINK: Real = Real::HALF;
/// Mass of a link of [`hanging_chain`] (kg).
const LINK_MASS: Real = Real::ONE;
/// Moment of a link of [`hanging_chain`] about its centre (kg·m²): a
/// 0.5 m rod-like link (a thin rod would have 1/48 = 0.0208).
const LINK_MOMENT: Real = real!(0.0217);
/// Radius of the end mass of [`hanging_chain`] (m).
const END_RADIUS: Real = real!(0.25);
/// Sideways speed of the end mass of a kicked [`hanging_chain`] (m/s).
const KICK: i32 = 5;

/// `hanging_chain_{links}_{end_mass}` (and `…_kicked` when `kicked`): a
/// chain of `links` links hanging straight down at rest from a static body
/// (labelled `anchor`) at the origin, with an end mass, for measuring how
/// well a solver holds joints under a large mass ratio. Link `i` (0 at the
/// top) is a dynamic body of mass 1 kg and moment 0.0217 kg·m² (set
/// explicitly) centred at (0, −0.25 − 0.5·i), drawn and collided as a
/// vertical segment from (0, −0.25) to (0, 0.25) rounded by 0.05; a
/// [`PivotJoint`] joins it at (0, −0.5·i) to the body above (anchors
/// (0, −0.25) on the link above, or (0, 0) on the static body, and (0, 0.25)
/// on the link). The end mass (labelled `end`: a circle of radius 0.25, mass
/// `end_mass` kg, the moment of a disc, `end_mass/32`) is centred on the
/// last link's lower end, (0, −0.5·links), and joined there by a pivot at
/// its centre; kicked, it starts moving sideways at (5, 0) m/s. Every shape
/// is in one group (the links and the end mass never collide with each
/// other) and no pivot lets its bodies collide. g = 10, 10 iterations,
/// one step of 1/60 s, sleeping off (a chain at rest would otherwise
/// sleep after half a second), 600 steps. `links + 2` bodies.
pub fn hanging_chain(links: u32, end_mass: u32, kicked: bool) -> SceneDesc {
    let kick = if kicked { "_kicked" } else { "" };
    let mut desc = scene(&format!("hanging_chain_{links}_{end_mass}{kick}"), 600);
    desc.settings.sleep_time_threshold = tamias2d::space::SLEEP_NEVER;
    desc.bodies.push(BodyDesc::static_body().labeled("anchor"));
    let group = tamias2d::shape::ShapeFilter {
        group: 1,
        ..tamias2d::shape::ShapeFilter::ALL
    };
    let half = LINK * Real::HALF;
    let up = Vect::new(Real::ZERO, half);
    let link_y = |i: u32| -(LINK * Real::from_int(i32::try_from(i).unwrap_or(i32::MAX)));
    for i in 0..links {
        let mut shape = ShapeDesc::segment(-up, up, real!(0.05)).material(real!(0.6), Real::ZERO);
        shape.filter = group;
        let centre = Vect::new(Real::ZERO, link_y(i) - half);
        desc.bodies
            .push(BodyDesc::dynamic(centre, LINK_MASS, LINK_MOMENT).with_shape(shape));
        let mut c = ConstraintDesc::new(JointType::Pivot, i, i.saturating_add(1));
        c.anchor_a = Some(if i == 0 { Vect::ZERO } else { -up });
        c.anchor_b = Some(up);
        c.collide_bodies = Some(false);
        desc.constraints.push(c);
    }
    let mass = Real::from_int(i32::try_from(end_mass).unwrap_or(i32::MAX));
    let mut shape = ShapeDesc::circle(END_RADIUS).material(real!(0.6), Real::ZERO);
    shape.filter = group;
    let mut end = BodyDesc::dynamic(
        Vect::new(Real::ZERO, link_y(links)),
        mass,
        mass * END_RADIUS * END_RADIUS * Real::HALF,
    )
    .with_shape(shape)
    .labeled("end");
    if kicked {
        end = end.moving(Vect::from_ints(KICK, 0));
    }
    desc.bodies.push(end);
    let mut c = ConstraintDesc::new(JointType::Pivot, links, links.saturating_add(1));
    c.anchor_a = Some(if links == 0 { Vect::ZERO } else { -up });
    c.anchor_b = Some(Vect::ZERO);
    c.collide_bodies = Some(false);
    desc.constraints.push(c);
    desc
}

/// A box of `side` (density 1, friction 0.6) at `(x, y)`, dropped.
fn crate_box(x: Real, y: Real, side: Real) -> BodyDesc {
    BodyDesc::new(BodyKind::Dynamic, Vect::new(x, y)).with_shape(
        ShapeDesc::box_shape(side, side, Real::ZERO)
            .material(real!(0.6), Real::ZERO)
            .density(Real::ONE),
    )
}

/// `windmill`: a simple motor drives a four-bladed rotor pivoted on a
/// static post, and boxes dropped on it are batted away. The post (static,
/// labelled `post`, with a 0.4 × 6 m box under the pivot and a 30 m ground
/// segment at y = −6) holds the rotor (labelled `rotor`: two crossed
/// 4 × 0.2 m boxes, density 1, friction 0.6, centred on the pivot at the
/// origin) by a pivot joint; a [`SimpleMotor`] of rate 1.5 (Chipmunk's
/// sign: the rotor turns at −1.5 rad/s, clockwise) and `max_force` 500
/// drives it. Neither joint lets the post and the rotor collide. Ten
/// 0.5 m boxes (density 1, friction 0.6) are dropped from y = 4, two at
/// x = ±1.2 every 30 steps from step 0 to step 120; they land on the
/// ground, below the blades' reach. g = 10, 10 iterations, 600 steps.
pub fn windmill() -> SceneDesc {
    let mut desc = scene("windmill", 600);
    let post = BodyDesc::static_body()
        .with_shape(
            ShapeDesc::box_at(real!(0.4), real!(6), Real::ZERO, Vect::from_ints(0, -3))
                .material(real!(0.6), Real::ZERO),
        )
        .with_shape(
            ShapeDesc::segment(
                Vect::from_ints(-15, -6),
                Vect::from_ints(15, -6),
                real!(0.1),
            )
            .material(real!(0.8), Real::ZERO),
        )
        .labeled("post");
    desc.bodies.push(post);
    let blade = |w: Real, h: Real| {
        ShapeDesc::box_shape(w, h, Real::ZERO)
            .material(real!(0.6), Real::ZERO)
            .density(Real::ONE)
    };
    let rotor = BodyDesc::new(BodyKind::Dynamic, Vect::ZERO)
        .with_shape(blade(real!(4), real!(0.2)))
        .with_shape(blade(real!(0.2), real!(4)))
        .labeled("rotor");
    desc.bodies.push(rotor);
    let mut pivot = ConstraintDesc::new(JointType::Pivot, 0, 1);
    pivot.pivot = Some(Vect::ZERO);
    pivot.collide_bodies = Some(false);
    desc.constraints.push(pivot);
    let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
    motor.rate = Some(real!(1.5));
    motor.max_force = Some(Real::from_int(500));
    motor.collide_bodies = Some(false);
    desc.constraints.push(motor);
    for k in 0..5u32 {
        let bodies = [real!(-1.2), real!(1.2)]
            .into_iter()
            .map(|x| crate_box(x, Real::from_int(4), Real::HALF))
            .collect();
        desc.spawns.push(SpawnDesc {
            at_step: k.saturating_mul(30),
            bodies,
        });
    }
    desc
}

/// A pivot joint from body `a` to body `b` at the world point `at`.
fn pivot_at(a: u32, b: u32, at: Vect) -> ConstraintDesc {
    let mut c = ConstraintDesc::new(JointType::Pivot, a, b);
    c.pivot = Some(at);
    c.collide_bodies = Some(false);
    c
}

/// `gear_train`: four wheels on pivot joints to a static frame, each meshed
/// with the next by a [`GearJoint`], the first driven by a
/// [`SimpleMotor`]. The wheels (labelled `wheel_1` … `wheel_4`, circles of
/// radius 1, 0.5, 1 and 0.25, density 1, friction 0.6) sit on y = 0 at
/// x = 0, 1.55, 3.1 and 4.4, 0.05 m apart rim to rim (they never touch);
/// the last carries an off-centre weight (a circle of radius 0.1 at
/// (0.15, 0), density 20), so the train lifts a load that changes with its
/// angle. Gear `i` joins wheel `i` (a) to wheel `i + 1` (b) with phase 0
/// and ratio `−r_b / r_a` (−0.5, −2, −0.25: meshed wheels turn opposite
/// ways, `ω_a = ratio·ω_b`); the motor (rate 1, `max_force` 100) turns
/// wheel 1 at −1 rad/s, so the wheels turn at −1, 2, −1 and 4 rad/s.
/// g = 10, 10 iterations, 600 steps.
pub fn gear_train() -> SceneDesc {
    let mut desc = scene("gear_train", 600);
    desc.bodies.push(BodyDesc::static_body().labeled("frame"));
    let wheels = [
        (Real::ONE, Real::ZERO, real!(-0.5)),
        (Real::HALF, real!(1.55), real!(-2)),
        (Real::ONE, real!(3.1), real!(-0.25)),
        (real!(0.25), real!(4.4), Real::ZERO),
    ];
    for (i, &(radius, x, ratio)) in (1u32..).zip(wheels.iter()) {
        let mut wheel = BodyDesc::new(BodyKind::Dynamic, Vect::new(x, Real::ZERO)).with_shape(
            ShapeDesc::circle(radius)
                .material(real!(0.6), Real::ZERO)
                .density(Real::ONE),
        );
        if i == 4 {
            wheel = wheel.with_shape(
                ShapeDesc::circle_at(real!(0.1), Vect::new(real!(0.15), Real::ZERO))
                    .material(real!(0.6), Real::ZERO)
                    .density(Real::from_int(20)),
            );
        }
        desc.bodies.push(wheel.labeled(&format!("wheel_{i}")));
        desc.constraints
            .push(pivot_at(0, i, Vect::new(x, Real::ZERO)));
        if i < 4 {
            let mut gear = ConstraintDesc::new(JointType::Gear, i, i.saturating_add(1));
            gear.phase = Some(Real::ZERO);
            gear.ratio = Some(ratio);
            desc.constraints.push(gear);
        }
    }
    let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
    motor.rate = Some(Real::ONE);
    motor.max_force = Some(Real::from_int(100));
    desc.constraints.push(motor);
    desc
}

/// `spring_mass`: a [`DampedSpring`] and a [`DampedRotarySpring`]. A 1 kg
/// mass (labelled `mass`, moment 0.02, a circle of radius 0.2) hangs from
/// a static ceiling (labelled `ceiling`, a segment from (−1, 0) to (1, 0))
/// on a spring from the ceiling's origin to the mass's centre: rest length
/// 1, stiffness 100, damping 2. Released at rest at (0, −1.5), 0.4 m below
/// its equilibrium y = −(1 + m·g/k) = −1.1, it rings at
/// √(k/m − (c/2m)²) = √99 rad/s and decays at c/2m = 1 /s. Beside it a
/// wheel (labelled `wheel`, mass 1, moment 0.5, a circle of radius 1 at
/// (3, −1)) on a pivot joint to the ceiling body, held by a rotary spring
/// (rest angle 0, stiffness 2, damping 0.1), starts at rest turned 1 rad:
/// it rings at √(k/I − (c/2I)²) = √3.99 rad/s and decays at c/2I = 0.1 /s.
/// g = 10, 10 iterations, 600 steps.
pub fn spring_mass() -> SceneDesc {
    let mut desc = scene("spring_mass", 600);
    desc.bodies.push(
        BodyDesc::static_body()
            .with_shape(ShapeDesc::segment(
                Vect::from_ints(-1, 0),
                Vect::from_ints(1, 0),
                real!(0.05),
            ))
            .labeled("ceiling"),
    );
    desc.bodies.push(
        BodyDesc::dynamic(Vect::new(Real::ZERO, real!(-1.5)), Real::ONE, real!(0.02))
            .with_shape(ShapeDesc::circle(real!(0.2)))
            .labeled("mass"),
    );
    let mut wheel = BodyDesc::dynamic(Vect::from_ints(3, -1), Real::ONE, Real::HALF)
        .with_shape(ShapeDesc::circle(Real::ONE))
        .labeled("wheel");
    wheel.angle = Real::ONE;
    desc.bodies.push(wheel);
    let mut spring = ConstraintDesc::new(JointType::DampedSpring, 0, 1);
    spring.rest_length = Some(Real::ONE);
    spring.stiffness = Some(Real::from_int(100));
    spring.damping = Some(Real::TWO);
    desc.constraints.push(spring);
    desc.constraints
        .push(pivot_at(0, 2, Vect::from_ints(3, -1)));
    let mut rotary = ConstraintDesc::new(JointType::DampedRotarySpring, 0, 2);
    rotary.rest_angle = Some(Real::ZERO);
    rotary.stiffness = Some(Real::TWO);
    rotary.damping = Some(real!(0.1));
    desc.constraints.push(rotary);
    desc
}

/// `ratchet`: a [`RatchetJoint`] turns a weighted wheel one way only,
/// driven by a [`SimpleMotor`] through a linkage whose drive reverses.
/// On a static frame (labelled `frame`): a crank (labelled `crank`, a
/// circle of radius 0.3, density 1) on a pivot joint at the origin, turned
/// by a simple motor of rate −3 (counter-clockwise at 3 rad/s) with
/// `max_force` 1000; a connecting rod (a pin joint, its length measured:
/// √3.89 ≈ 1.97 m) from the crank's rim point (0.3, 0) to the tip of a
/// rocker (labelled `rocker`, a 0.1 × 1 m bar, density 1, standing on a
/// pivot joint at (2, 0)), which therefore swings back and forth through
/// about 0.62 rad, reversing twice per crank turn (a crank–rocker
/// four-bar: ground 2, crank 0.3, rod 1.97, rocker 1). On the rocker's
/// axle turns the wheel (labelled `wheel`, a circle of radius 0.5,
/// density 1, with a weight: a circle of radius 0.1 at (0.4, 0), density
/// 10) on its own pivot joint. The drive ratchet (rocker → wheel, phase
/// 0, ratchet 0.1 rad) pushes the wheel counter-clockwise on the rocker's
/// forward strokes and slips on the back strokes; the pawl ratchet
/// (frame → wheel, phase 0, ratchet 0.1 rad) keeps the weight from
/// turning the wheel back by more than a tooth. Shapes on one axle do not
/// collide. g = 10, 10 iterations, 600 steps.
pub fn ratchet() -> SceneDesc {
    let mut desc = scene("ratchet", 600);
    desc.bodies.push(BodyDesc::static_body().labeled("frame"));
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::ZERO)
            .with_shape(ShapeDesc::circle(real!(0.3)).density(Real::ONE))
            .labeled("crank"),
    );
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(2, 0))
            .with_shape(
                ShapeDesc::box_at(
                    real!(0.1),
                    Real::ONE,
                    Real::ZERO,
                    Vect::new(Real::ZERO, Real::HALF),
                )
                .density(Real::ONE),
            )
            .labeled("rocker"),
    );
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(2, 0))
            .with_shape(ShapeDesc::circle(Real::HALF).density(Real::ONE))
            .with_shape(
                ShapeDesc::circle_at(real!(0.1), Vect::new(real!(0.4), Real::ZERO))
                    .density(Real::from_int(10)),
            )
            .labeled("wheel"),
    );
    desc.constraints.push(pivot_at(0, 1, Vect::ZERO));
    let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 0, 1);
    motor.rate = Some(Real::from_int(-3));
    motor.max_force = Some(Real::from_int(1000));
    desc.constraints.push(motor);
    let mut rod = ConstraintDesc::new(JointType::Pin, 1, 2);
    rod.anchor_a = Some(Vect::new(real!(0.3), Real::ZERO));
    rod.anchor_b = Some(Vect::new(Real::ZERO, Real::ONE));
    desc.constraints.push(rod);
    desc.constraints.push(pivot_at(0, 2, Vect::from_ints(2, 0)));
    desc.constraints.push(pivot_at(0, 3, Vect::from_ints(2, 0)));
    for a in [2, 0] {
        let mut r = ConstraintDesc::new(JointType::Ratchet, a, 3);
        r.phase = Some(Real::ZERO);
        r.ratchet = Some(real!(0.1));
        r.collide_bodies = Some(false);
        desc.constraints.push(r);
    }
    desc
}

/// `rope_bridge`: twelve planks (0.9 × 0.2 m boxes, density 1, friction
/// 0.8) joined end to end by [`PivotJoint`]s 1 m apart, laid straight from
/// x = −6 to x = 6 at y = 0 between two static cliffs (one static body,
/// labelled `cliffs`: 4 × 4 m boxes centred at (±9, −2), their inner top
/// corners at (±7, 0), and a ground segment at y = −12). The end planks
/// hang from the cliff corners by [`SlideJoint`] ropes (min 0, max 1.5 m:
/// 0.5 m of slack each), so the bridge drops into a sag and swings. Six
/// 0.5 m boxes (density 2, friction 0.8) are dropped on it from y = 3 at
/// x = −2, 0 and 2, three at step 120 and three at step 180. Neighbouring
/// planks do not collide. The planks are labelled `plank_0` … `plank_11`,
/// the boxes `box_0` … `box_5`. g = 10, 2 sub-steps of 10 iterations (the
/// jerk of the ropes going taut opens the joints by 8.5 cm in one 1/60 s
/// step, 3.6 cm in two sub-steps), 600 steps.
pub fn rope_bridge() -> SceneDesc {
    let mut desc = scene("rope_bridge", 600);
    desc.settings.substeps = 2;
    let cliff = |x: i32| {
        ShapeDesc::box_at(real!(4), real!(4), Real::ZERO, Vect::from_ints(x, -2))
            .material(real!(0.8), Real::ZERO)
    };
    desc.bodies.push(
        BodyDesc::static_body()
            .with_shape(cliff(-9))
            .with_shape(cliff(9))
            .with_shape(
                ShapeDesc::segment(
                    Vect::from_ints(-20, -12),
                    Vect::from_ints(20, -12),
                    real!(0.1),
                )
                .material(real!(0.8), Real::ZERO),
            )
            .labeled("cliffs"),
    );
    let planks = 12u32;
    let half = Vect::new(Real::HALF, Real::ZERO);
    for i in 0..planks {
        let x = Real::from_int(i32::try_from(i).unwrap_or(0)) - Real::from_int(6) + Real::HALF;
        let plank = BodyDesc::new(BodyKind::Dynamic, Vect::new(x, Real::ZERO))
            .with_shape(
                ShapeDesc::box_shape(real!(0.9), real!(0.2), Real::ZERO)
                    .material(real!(0.8), Real::ZERO)
                    .density(Real::ONE),
            )
            .labeled(&format!("plank_{i}"));
        desc.bodies.push(plank);
        if i > 0 {
            let mut c = ConstraintDesc::new(JointType::Pivot, i, i.saturating_add(1));
            c.anchor_a = Some(half);
            c.anchor_b = Some(-half);
            c.collide_bodies = Some(false);
            desc.constraints.push(c);
        }
    }
    for (plank, corner, end) in [(1, -7, -half), (planks, 7, half)] {
        let mut rope = ConstraintDesc::new(JointType::Slide, 0, plank);
        rope.anchor_a = Some(Vect::from_ints(corner, 0));
        rope.anchor_b = Some(end);
        rope.min = Some(Real::ZERO);
        rope.max = Some(real!(1.5));
        desc.constraints.push(rope);
    }
    for (k, at) in [(0u32, 120u32), (1, 180)] {
        let bodies = [-2, 0, 2]
            .into_iter()
            .enumerate()
            .map(|(j, x)| {
                BodyDesc::new(BodyKind::Dynamic, Vect::from_ints(x, 3))
                    .with_shape(
                        ShapeDesc::box_shape(Real::HALF, Real::HALF, Real::ZERO)
                            .material(real!(0.8), Real::ZERO)
                            .density(Real::TWO),
                    )
                    .labeled(&format!(
                        "box_{}",
                        k.saturating_mul(3)
                            .saturating_add(u32::try_from(j).unwrap_or(0))
                    ))
            })
            .collect();
        desc.spawns.push(SpawnDesc {
            at_step: at,
            bodies,
        });
    }
    desc
}

/// One ragdoll part: a dynamic body at `at` (world) with `shape`.
fn part(at: Vect, shape: ShapeDesc) -> BodyDesc {
    BodyDesc::new(BodyKind::Dynamic, at)
        .with_shape(shape.material(real!(0.6), Real::ZERO).density(Real::ONE))
}

/// `ragdolls_{n}`: `n` ragdolls of six bodies falling onto a flight of
/// stairs, each limb held to the torso by a [`PivotJoint`] and a
/// [`RotaryLimitJoint`]. A ragdoll (density 1, friction 0.6, upright, its
/// torso's centre at the origin of its own frame): a 0.4 × 0.6 m torso; a
/// head (circle of radius 0.15) centred at (0, 0.45), neck pivot at
/// (0, 0.3), limit −0.4 to 0.4 rad; two arms (0.12 × 0.6 m boxes) centred
/// at (±0.28, 0), shoulder pivots at (±0.28, 0.25), limits −1.5 to 1.5;
/// two legs (0.14 × 0.7 m boxes) centred at (±0.11, −0.65), hip pivots at
/// (±0.11, −0.3), limits −1 to 1 (each limit on the limb's angle minus
/// the torso's). A limb does not collide with its torso. The ragdolls
/// stand in rows of 5, 3 m apart from x = 0.75 and 2.5 m apart from
/// y = 3, and fall onto the stairs: one static body of ten 1.5 m wide
/// steps, step `k` a box from x = 1.5k to 1.5k + 1.5 whose top is at
/// y = −0.5k, down to y = −6, a wall segment at x = 0 from y = 0 to 12
/// and a ground segment at y = −6 from x = 15 to 40. g = 10, 2 sub-steps
/// of 10 iterations (one 1/60 s step lets the landings push the neck
/// 0.58 rad past its limit, two sub-steps 0.31), 600 steps.
pub fn ragdolls(n: u32) -> SceneDesc {
    let mut desc = scene(&format!("ragdolls_{n}"), 600);
    desc.settings.substeps = 2;
    let mut stairs = BodyDesc::static_body().labeled("stairs");
    for k in 0..10i32 {
        let top = -(Real::from_int(k) * Real::HALF);
        let height = top + Real::from_int(6);
        let centre = Vect::new(
            real!(1.5) * Real::from_int(k) + real!(0.75),
            (top - Real::from_int(6)) * Real::HALF,
        );
        stairs = stairs.with_shape(
            ShapeDesc::box_at(real!(1.5), height, Real::ZERO, centre)
                .material(real!(0.8), Real::ZERO),
        );
    }
    for (a, b) in [((0, 0), (0, 12)), ((15, -6), (40, -6))] {
        stairs = stairs.with_shape(
            ShapeDesc::segment(
                Vect::from_ints(a.0, a.1),
                Vect::from_ints(b.0, b.1),
                real!(0.1),
            )
            .material(real!(0.8), Real::ZERO),
        );
    }
    desc.bodies.push(stairs);
    for r in 0..n {
        let (col, row) = (r.checked_rem(5).unwrap_or(0), r.checked_div(5).unwrap_or(0));
        let origin = Vect::new(
            real!(0.75) + Real::from_int(3) * Real::from_int(i32::try_from(col).unwrap_or(0)),
            Real::from_int(3) + real!(2.5) * Real::from_int(i32::try_from(row).unwrap_or(0)),
        );
        let torso = u32::try_from(desc.bodies.len()).unwrap_or(0);
        desc.bodies.push(
            part(
                origin,
                ShapeDesc::box_shape(real!(0.4), real!(0.6), Real::ZERO),
            )
            .labeled(&format!("torso_{r}")),
        );
        // (centre, pivot, shape, min, max), relative to the torso.
        let limbs = [
            (
                Vect::new(Real::ZERO, real!(0.45)),
                Vect::new(Real::ZERO, real!(0.3)),
                ShapeDesc::circle(real!(0.15)),
                real!(-0.4),
                real!(0.4),
            ),
            (
                Vect::new(real!(-0.28), Real::ZERO),
                Vect::new(real!(-0.28), real!(0.25)),
                ShapeDesc::box_shape(real!(0.12), real!(0.6), Real::ZERO),
                real!(-1.5),
                real!(1.5),
            ),
            (
                Vect::new(real!(0.28), Real::ZERO),
                Vect::new(real!(0.28), real!(0.25)),
                ShapeDesc::box_shape(real!(0.12), real!(0.6), Real::ZERO),
                real!(-1.5),
                real!(1.5),
            ),
            (
                Vect::new(real!(-0.11), real!(-0.65)),
                Vect::new(real!(-0.11), real!(-0.3)),
                ShapeDesc::box_shape(real!(0.14), real!(0.7), Real::ZERO),
                -Real::ONE,
                Real::ONE,
            ),
            (
                Vect::new(real!(0.11), real!(-0.65)),
                Vect::new(real!(0.11), real!(-0.3)),
                ShapeDesc::box_shape(real!(0.14), real!(0.7), Real::ZERO),
                -Real::ONE,
                Real::ONE,
            ),
        ];
        for (centre, pivot, shape, min, max) in limbs {
            let limb = u32::try_from(desc.bodies.len()).unwrap_or(0);
            desc.bodies.push(part(origin + centre, shape));
            desc.constraints.push(pivot_at(torso, limb, origin + pivot));
            let mut limit = ConstraintDesc::new(JointType::RotaryLimit, torso, limb);
            limit.min = Some(min);
            limit.max = Some(max);
            limit.collide_bodies = Some(false);
            desc.constraints.push(limit);
        }
    }
    desc
}

/// `car`: a chassis on two wheels, each held by a [`GrooveJoint`] (a
/// vertical slot on the chassis) and a [`DampedSpring`] (the suspension)
/// and driven by a [`SimpleMotor`], over bumpy terrain. The chassis
/// (labelled `chassis`, a 3 × 0.5 m box, density 1, friction 0.6) starts
/// at (0, 1.4); the wheels (labelled `wheel_rear` and `wheel_front`,
/// circles of radius 0.4, density 1, friction 1) at (∓1, 0.6). Each
/// groove runs on the chassis from (∓1, −0.3) to (∓1, −1.1) with the
/// wheel's centre as its anchor; each spring (rest length 0.9, stiffness
/// 50, damping 3) joins (∓1, 0) on the chassis to the wheel's centre;
/// each motor (rate 6, `max_force` 20) turns its wheel at −6 rad/s
/// relative to the chassis (clockwise: forward, to the right, at about
/// 2.4 m/s). The chassis and its wheels do not collide. The terrain
/// (static, labelled `terrain`, friction 1) is a chain of segments through
/// x = −5, −3, …, 55 with heights repeating 0, 0.2, 0, 0.1, 0.3, 0. g = 10,
/// 10 iterations, 600 steps.
pub fn car() -> SceneDesc {
    let mut desc = scene("car", 600);
    let heights = [
        Real::ZERO,
        real!(0.2),
        Real::ZERO,
        real!(0.1),
        real!(0.3),
        Real::ZERO,
    ];
    let points: Vec<Vect> = (0..=30i32)
        .zip(heights.iter().cycle())
        .map(|(k, &h)| Vect::new(Real::TWO * Real::from_int(k) - Real::from_int(5), h))
        .collect();
    let mut terrain = BodyDesc::static_body().labeled("terrain");
    for pair in points.windows(2) {
        if let [a, b] = *pair {
            terrain = terrain
                .with_shape(ShapeDesc::segment(a, b, real!(0.05)).material(Real::ONE, Real::ZERO));
        }
    }
    desc.bodies.push(terrain);
    desc.bodies.push(
        BodyDesc::new(BodyKind::Dynamic, Vect::new(Real::ZERO, real!(1.4)))
            .with_shape(
                ShapeDesc::box_shape(real!(3), Real::HALF, Real::ZERO)
                    .material(real!(0.6), Real::ZERO)
                    .density(Real::ONE),
            )
            .labeled("chassis"),
    );
    for (x, label) in [(-1, "wheel_rear"), (1, "wheel_front")] {
        let wheel = u32::try_from(desc.bodies.len()).unwrap_or(0);
        desc.bodies.push(
            BodyDesc::new(BodyKind::Dynamic, Vect::new(Real::from_int(x), real!(0.6)))
                .with_shape(
                    ShapeDesc::circle(real!(0.4))
                        .material(Real::ONE, Real::ZERO)
                        .density(Real::ONE),
                )
                .labeled(label),
        );
        let x = Real::from_int(x);
        let mut groove = ConstraintDesc::new(JointType::Groove, 1, wheel);
        groove.groove_a = Some(Vect::new(x, real!(-0.3)));
        groove.groove_b = Some(Vect::new(x, real!(-1.1)));
        groove.collide_bodies = Some(false);
        desc.constraints.push(groove);
        let mut spring = ConstraintDesc::new(JointType::DampedSpring, 1, wheel);
        spring.anchor_a = Some(Vect::new(x, Real::ZERO));
        spring.rest_length = Some(real!(0.9));
        spring.stiffness = Some(Real::from_int(50));
        spring.damping = Some(Real::from_int(3));
        spring.collide_bodies = Some(false);
        desc.constraints.push(spring);
        let mut motor = ConstraintDesc::new(JointType::SimpleMotor, 1, wheel);
        motor.rate = Some(Real::from_int(6));
        motor.max_force = Some(Real::from_int(20));
        motor.collide_bodies = Some(false);
        desc.constraints.push(motor);
    }
    desc
}
