//! The data description of a scene: plain serde data, no handles, no
//! closures, so a scene can be written to JSON, read back, diffed, and fed to
//! another engine with exactly the same numbers.
//!
//! Every `Real` is a decimal string in the serialized form (see
//! module `dec`); optional fields have defaults, so a hand-written
//! file only needs what differs from them. Unknown fields are rejected
//! (typos must not silently become defaults).
//!
//! A description is validated when it is built ([`SceneDesc::build`]), not
//! when it is parsed: parsing checks the syntax, building checks the physics
//! (negative radius, concave raw polygon, massless dynamic body …) and
//! returns a [`SceneError`](super::SceneError) naming the body and shape.
use serde::{Deserialize, Serialize};

use super::dec;
pub use super::joints::{ConstraintDesc, JointType};
use tamias2d::math::{Real, Vect};
use tamias2d::shape::{CollisionType, ShapeFilter};
use tamias2d::space::{
    ContactPrecision, Settings, SoftStep, Solver, DEFAULT_IDLE_SPEED_THRESHOLD,
    DEFAULT_SLEEP_TIME_THRESHOLD,
};

/// A whole scene: settings, time step, bodies and scripted events.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// Registry name (e.g. `pyramid_20`) or any label.
    pub name: String,
    /// Space settings.
    #[serde(default)]
    pub settings: SettingsDesc,
    /// Time step of every step, > 0.
    #[serde(with = "dec::real")]
    pub dt: Real,
    /// Default number of steps a run of this scene takes.
    pub steps: u32,
    /// Bodies present from the start, in creation (and so handle) order.
    pub bodies: Vec<BodyDesc>,
    /// Forces and torques applied before every step.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub forces: Vec<ForceDesc>,
    /// Bodies added later (e.g. rain), in order of `at_step`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spawns: Vec<SpawnDesc>,
    /// Collision type pairs whose `begin` callbacks are counted.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub begin_counters: Vec<CounterDesc>,
    /// Joints between initial bodies, added in order after the bodies.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constraints: Vec<ConstraintDesc>,
}

/// [`Settings`] with decimal reals; missing fields take Chipmunk's defaults.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SettingsDesc {
    /// Gravity acceleration.
    #[serde(with = "dec::vect")]
    pub gravity: Vect,
    /// Solver iterations per step.
    pub iterations: u32,
    /// Fraction of velocity kept after one second.
    #[serde(with = "dec::real")]
    pub damping: Real,
    /// Overlap allowed without correction.
    #[serde(with = "dec::real")]
    pub collision_slop: Real,
    /// Fraction of overlap left uncorrected after one second.
    #[serde(with = "dec::real")]
    pub collision_bias: Real,
    /// Steps an arbiter is kept after its shapes separate.
    pub collision_persistence: u32,
    /// Sub-steps per step (see [`Settings::substeps`]); omitted when 1.
    #[serde(skip_serializing_if = "is_one")]
    pub substeps: u32,
    /// Warm starting (see [`Settings::warm_starting`]); omitted when on.
    #[serde(skip_serializing_if = "is_true")]
    pub warm_starting: bool,
    /// Friction (see [`Settings::friction`]); omitted when on.
    #[serde(skip_serializing_if = "is_true")]
    pub friction: bool,
    /// Restitution (see [`Settings::restitution`]); omitted when on.
    #[serde(skip_serializing_if = "is_true")]
    pub restitution: bool,
    /// Bias impulses (see [`Settings::bias_impulses`]); omitted when on.
    #[serde(skip_serializing_if = "is_true")]
    pub bias_impulses: bool,
    /// Block solver (see [`Settings::block_solver`]); omitted when on.
    #[serde(skip_serializing_if = "is_true")]
    pub block_solver: bool,
    /// Colored solver (see [`Settings::colored_solver`]); omitted when off.
    #[serde(skip_serializing_if = "is_false")]
    pub colored_solver: bool,
    /// Seconds of rest before an island sleeps (see
    /// [`Settings::sleep_time_threshold`]); omitted when the default.
    #[serde(
        with = "dec::real",
        default = "default_sleep_time",
        skip_serializing_if = "is_default_sleep_time"
    )]
    pub sleep_time_threshold: Real,
    /// Idle speed (see [`Settings::idle_speed_threshold`]); omitted when
    /// the default.
    #[serde(
        with = "dec::real",
        default = "default_idle_speed",
        skip_serializing_if = "is_default_idle_speed"
    )]
    pub idle_speed_threshold: Real,
    /// The solver (see [`Settings::solver`]): `"sequential"` (the default,
    /// omitted) or `{"soft": {…}}` with any of [`SoftStepDesc`]'s fields.
    #[serde(skip_serializing_if = "SolverDesc::is_sequential")]
    pub solver: SolverDesc,
}

/// The soft step at its defaults for a world with `gravity`: its speeds and
/// slop scaled by the length unit read off the gravity (`|g| / 10` units
/// per metre, rounded, when that exceeds 1).
pub fn soft_step_for(gravity: Vect) -> SoftStep {
    let unit = (gravity.length() / Real::from_int(10) + Real::lit("0.5"))
        .floor()
        .max(Real::ONE);
    SoftStep::DEFAULT.scaled(unit)
}

/// [`Solver`] in a scene file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum SolverDesc {
    /// Sequential impulses.
    #[default]
    Sequential,
    /// The soft step.
    Soft(SoftStepDesc),
}

impl SolverDesc {
    /// The soft step at its defaults.
    pub const SOFT: SolverDesc = SolverDesc::Soft(SoftStepDesc(SoftStep::DEFAULT));

    fn is_sequential(&self) -> bool {
        *self == SolverDesc::Sequential
    }
}

/// [`SoftStep`] with decimal reals; missing fields take its defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(from = "SoftStepFields", into = "SoftStepFields")]
pub struct SoftStepDesc(pub SoftStep);

/// The serialized fields of [`SoftStepDesc`].
#[derive(Clone, Copy, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct SoftStepFields {
    substeps: u32,
    #[serde(with = "dec::real")]
    contact_hertz: Real,
    #[serde(with = "dec::real")]
    contact_damping_ratio: Real,
    #[serde(with = "dec::real")]
    joint_hertz: Real,
    #[serde(with = "dec::real")]
    joint_damping_ratio: Real,
    #[serde(with = "dec::real")]
    push_out_speed: Real,
    #[serde(with = "dec::real")]
    restitution_threshold: Real,
    #[serde(with = "dec::real")]
    slop: Real,
    /// The narrow contact kernels (`ContactPrecision::Narrow`); left out
    /// when off.
    #[serde(skip_serializing_if = "core::ops::Not::not")]
    narrow_contacts: bool,
}

impl Default for SoftStepFields {
    fn default() -> Self {
        SoftStepDesc(SoftStep::DEFAULT).into()
    }
}

impl From<SoftStepFields> for SoftStepDesc {
    fn from(f: SoftStepFields) -> Self {
        SoftStepDesc(SoftStep {
            substeps: f.substeps,
            contact_hertz: f.contact_hertz,
            contact_damping_ratio: f.contact_damping_ratio,
            joint_hertz: f.joint_hertz,
            joint_damping_ratio: f.joint_damping_ratio,
            push_out_speed: f.push_out_speed,
            restitution_threshold: f.restitution_threshold,
            slop: f.slop,
            contact_precision: if f.narrow_contacts {
                ContactPrecision::Narrow
            } else {
                ContactPrecision::Full
            },
        })
    }
}

impl From<SoftStepDesc> for SoftStepFields {
    fn from(SoftStepDesc(s): SoftStepDesc) -> Self {
        SoftStepFields {
            substeps: s.substeps,
            contact_hertz: s.contact_hertz,
            contact_damping_ratio: s.contact_damping_ratio,
            joint_hertz: s.joint_hertz,
            joint_damping_ratio: s.joint_damping_ratio,
            push_out_speed: s.push_out_speed,
            restitution_threshold: s.restitution_threshold,
            slop: s.slop,
            narrow_contacts: s.contact_precision == ContactPrecision::Narrow,
        }
    }
}

impl From<Solver> for SolverDesc {
    fn from(s: Solver) -> Self {
        match s {
            Solver::Sequential => SolverDesc::Sequential,
            Solver::Soft(soft) => SolverDesc::Soft(SoftStepDesc(soft)),
        }
    }
}

impl From<SolverDesc> for Solver {
    fn from(s: SolverDesc) -> Self {
        match s {
            SolverDesc::Sequential => Solver::Sequential,
            SolverDesc::Soft(SoftStepDesc(soft)) => Solver::Soft(soft),
        }
    }
}

fn default_sleep_time() -> Real {
    DEFAULT_SLEEP_TIME_THRESHOLD
}

fn is_default_sleep_time(v: &Real) -> bool {
    *v == DEFAULT_SLEEP_TIME_THRESHOLD
}

fn default_idle_speed() -> Real {
    DEFAULT_IDLE_SPEED_THRESHOLD
}

fn is_default_idle_speed(v: &Real) -> bool {
    *v == DEFAULT_IDLE_SPEED_THRESHOLD
}

// The settings added after the first scene files are written only when they
// differ from the default, so the files of existing scenes stay as they were
// (and `#[serde(default)]` reads those files).
fn is_one(v: &u32) -> bool {
    *v == 1
}

fn is_true(v: &bool) -> bool {
    *v
}

impl From<&Settings> for SettingsDesc {
    fn from(s: &Settings) -> SettingsDesc {
        let Settings {
            iterations,
            gravity,
            damping,
            collision_slop,
            collision_bias,
            collision_persistence,
            substeps,
            warm_starting,
            friction,
            restitution,
            bias_impulses,
            block_solver,
            colored_solver,
            sleep_time_threshold,
            idle_speed_threshold,
            solver,
        } = *s;
        SettingsDesc {
            gravity,
            iterations,
            damping,
            collision_slop,
            collision_bias,
            collision_persistence,
            substeps,
            warm_starting,
            friction,
            restitution,
            bias_impulses,
            block_solver,
            colored_solver,
            sleep_time_threshold,
            idle_speed_threshold,
            solver: solver.into(),
        }
    }
}

impl From<&SettingsDesc> for Settings {
    fn from(s: &SettingsDesc) -> Settings {
        let SettingsDesc {
            gravity,
            iterations,
            damping,
            collision_slop,
            collision_bias,
            collision_persistence,
            substeps,
            warm_starting,
            friction,
            restitution,
            bias_impulses,
            block_solver,
            colored_solver,
            sleep_time_threshold,
            idle_speed_threshold,
            solver,
        } = *s;
        Settings {
            iterations,
            gravity,
            damping,
            collision_slop,
            collision_bias,
            collision_persistence,
            substeps,
            warm_starting,
            friction,
            restitution,
            bias_impulses,
            block_solver,
            colored_solver,
            sleep_time_threshold,
            idle_speed_threshold,
            solver: solver.into(),
        }
    }
}

/// The engine's default settings, except the collision slop: the standard
/// scenes keep Chipmunk's 0.1 (the engine's default became the metre-scale
/// 0.005), because they mirror Chipmunk's benchmark scenes number for number
/// and their goldens were recorded with it. A scene file that sets
/// `collision_slop` uses its own value.
impl Default for SettingsDesc {
    fn default() -> SettingsDesc {
        SettingsDesc {
            collision_slop: tamias2d::space::CHIPMUNK_COLLISION_SLOP,
            // Scene files written before the solver was a setting name none:
            // they keep the solver they ran on.
            solver: SolverDesc::Sequential,
            ..SettingsDesc::from(&Settings::default())
        }
    }
}

impl SettingsDesc {
    /// The soft step at its defaults for this scene: its speeds and slop
    /// scaled by the scene's length unit, read off its gravity (`|g| / 10`
    /// units per metre, rounded, when that exceeds 1: the pixel scenes'
    /// gravity of 100 makes 10 units per metre).
    pub fn soft_solver(&self) -> SolverDesc {
        SolverDesc::Soft(SoftStepDesc(soft_step_for(self.gravity)))
    }

    /// Switches the scene to the soft step at its defaults
    /// ([`soft_solver`](Self::soft_solver)), with one whole-pipeline
    /// sub-step: the soft step sub-steps its solver itself, so a scene's
    /// own `substeps` (chosen for the sequential solver) would multiply
    /// its sub-steps.
    pub fn use_soft_step(&mut self) {
        self.solver = self.soft_solver();
        self.substeps = 1;
    }

    /// [`use_soft_step`](Self::use_soft_step) with the narrow contact
    /// kernels (`ContactPrecision::Narrow`).
    pub fn use_narrow_soft_step(&mut self) {
        self.use_soft_step();
        if let SolverDesc::Soft(SoftStepDesc(soft)) = &mut self.solver {
            soft.contact_precision = ContactPrecision::Narrow;
        }
    }

    /// Chipmunk's defaults with the given gravity and iteration count.
    pub fn with_gravity(gravity: Vect, iterations: u32) -> SettingsDesc {
        SettingsDesc {
            gravity,
            iterations,
            ..SettingsDesc::default()
        }
    }
}

/// How a body moves (mirrors [`BodyType`](tamias2d::body::BodyType)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyKind {
    /// Moved by forces, gravity and collisions.
    Dynamic,
    /// Moved only by its own velocity.
    Kinematic,
    /// Never moves.
    Static,
}

/// Where a body's mass and moment come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MassDesc {
    /// Summed from the shapes' mass or density (kinematic and static bodies
    /// always use this: they have no mass).
    #[default]
    FromShapes,
    /// Set on the body; both must be > 0. The shapes' own mass is then ignored.
    Explicit {
        /// Mass.
        #[serde(with = "dec::real")]
        mass: Real,
        /// Moment of inertia about the centre of gravity.
        #[serde(with = "dec::real")]
        moment: Real,
    },
}

/// One body and its shapes.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDesc {
    /// A name to find the body's handle with ([`ScriptedWorld::body`](crate::ScriptedWorld::body)); unique.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// Dynamic, kinematic or static.
    pub kind: BodyKind,
    /// Position of the body origin.
    #[serde(default, with = "dec::vect")]
    pub position: Vect,
    /// Angle in radians.
    #[serde(default, with = "dec::real")]
    pub angle: Real,
    /// Linear velocity.
    #[serde(default, with = "dec::vect")]
    pub velocity: Vect,
    /// Angular velocity (rad/s, counter-clockwise).
    #[serde(default, with = "dec::real")]
    pub angular_velocity: Real,
    /// Mass and moment.
    #[serde(default)]
    pub mass: MassDesc,
    /// Continuous collision ([`Body::set_bullet`](tamias2d::body::Body::set_bullet));
    /// omitted when false.
    #[serde(default, skip_serializing_if = "is_false")]
    pub bullet: bool,
    /// Shapes, in creation order.
    pub shapes: Vec<ShapeDesc>,
}

/// Both neighbours of a segment (Chipmunk `cpSegmentShapeSetNeighbors`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Neighbors {
    /// The previous segment's far end, joined at `a`.
    #[serde(with = "dec::vect")]
    pub prev: Vect,
    /// The next segment's far end, joined at `b`.
    #[serde(with = "dec::vect")]
    pub next: Vect,
}

/// Shape geometry in body coordinates.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum GeometryDesc {
    /// A circle of `radius` centred at `offset`.
    Circle {
        /// Radius, ≥ 0.
        #[serde(with = "dec::real")]
        radius: Real,
        /// Centre.
        #[serde(default, with = "dec::vect")]
        offset: Vect,
    },
    /// A segment from `a` to `b` with rounding `radius`.
    Segment {
        /// First endpoint.
        #[serde(with = "dec::vect")]
        a: Vect,
        /// Second endpoint.
        #[serde(with = "dec::vect")]
        b: Vect,
        /// Rounding radius, ≥ 0.
        #[serde(default, with = "dec::real")]
        radius: Real,
        /// Smooth-terrain neighbours.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        neighbors: Option<Neighbors>,
    },
    /// The convex hull of `verts` (MIS `polyShapeNew`, identity transform).
    Poly {
        /// Points; interior and repeated points are dropped.
        #[serde(with = "dec::vects")]
        verts: Vec<Vect>,
        /// Rounding radius, ≥ 0.
        #[serde(default, with = "dec::real")]
        radius: Real,
    },
    /// Vertices that must already be convex and counter-clockwise (MIS
    /// `polyShapeNewRaw`): checked, never repaired.
    RawPoly {
        /// Vertices, counter-clockwise.
        #[serde(with = "dec::vects")]
        verts: Vec<Vect>,
        /// Rounding radius, ≥ 0.
        #[serde(default, with = "dec::real")]
        radius: Real,
    },
    /// A `width × height` box centred at `offset` (MIS `boxShapeNew`, or
    /// `boxShapeNew2` when offset).
    Box {
        /// Width, > 0.
        #[serde(with = "dec::real")]
        width: Real,
        /// Height, > 0.
        #[serde(with = "dec::real")]
        height: Real,
        /// Rounding radius, ≥ 0.
        #[serde(default, with = "dec::real")]
        radius: Real,
        /// Centre.
        #[serde(default, with = "dec::vect")]
        offset: Vect,
    },
}

/// Mass of a shape (mirrors [`MassSpec`](tamias2d::shape::MassSpec)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeMassDesc {
    /// Massless.
    #[default]
    None,
    /// A fixed mass, ≥ 0.
    Mass(#[serde(with = "dec::real")] Real),
    /// Mass = density · area; density ≥ 0.
    Density(#[serde(with = "dec::real")] Real),
}

/// One shape: geometry, material, filter and mass.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeDesc {
    /// Geometry.
    pub geometry: GeometryDesc,
    /// Friction coefficient, ≥ 0 (the pair uses the product).
    #[serde(default, with = "dec::real")]
    pub friction: Real,
    /// Elasticity, ≥ 0 (the pair uses the product).
    #[serde(default, with = "dec::real")]
    pub elasticity: Real,
    /// Surface velocity (conveyor belts).
    #[serde(default, with = "dec::vect", skip_serializing_if = "is_zero_vect")]
    pub surface_velocity: Vect,
    /// Collision type (selects handlers).
    #[serde(default, skip_serializing_if = "is_zero_u32")]
    pub collision_type: CollisionType,
    /// Collision filter (group, categories, mask).
    #[serde(default, skip_serializing_if = "is_filter_all")]
    pub filter: ShapeFilter,
    /// Sensors report contacts but never push.
    #[serde(default, skip_serializing_if = "is_false")]
    pub sensor: bool,
    /// Mass or density.
    #[serde(default, skip_serializing_if = "is_massless")]
    pub mass: ShapeMassDesc,
}

fn is_zero_vect(v: &Vect) -> bool {
    *v == Vect::ZERO
}

fn is_zero_u32(v: &u32) -> bool {
    *v == 0
}

fn is_filter_all(f: &ShapeFilter) -> bool {
    *f == ShapeFilter::ALL
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_massless(m: &ShapeMassDesc) -> bool {
    *m == ShapeMassDesc::None
}

/// A force and torque applied to one of the initial bodies before every step
/// (the accumulators are cleared by each step, so a constant force must be
/// re-applied).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceDesc {
    /// Index into [`SceneDesc::bodies`].
    pub body: u32,
    /// Force at the centre of gravity.
    #[serde(default, with = "dec::vect")]
    pub force: Vect,
    /// Torque.
    #[serde(default, with = "dec::real")]
    pub torque: Real,
}

/// Bodies added once `at_step` steps have been taken (0: when the scene is built).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpawnDesc {
    /// Number of steps taken before the bodies appear.
    pub at_step: u32,
    /// The bodies, in creation order.
    pub bodies: Vec<BodyDesc>,
}

/// Counts `begin` callbacks of shape pairs with these collision types (the
/// pair is still accepted). Read with [`ScriptedWorld::begin_count`](crate::ScriptedWorld::begin_count).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CounterDesc {
    /// Collision type of one shape.
    pub type_a: CollisionType,
    /// Collision type of the other.
    pub type_b: CollisionType,
}

impl SceneDesc {
    /// An empty scene with Chipmunk's default settings.
    pub fn new(name: &str, dt: Real, steps: u32) -> SceneDesc {
        SceneDesc {
            name: name.to_owned(),
            settings: SettingsDesc::default(),
            dt,
            steps,
            bodies: Vec::new(),
            forces: Vec::new(),
            spawns: Vec::new(),
            begin_counters: Vec::new(),
            constraints: Vec::new(),
        }
    }

    /// Number of bodies the scene has once every spawn has happened.
    pub fn total_bodies(&self) -> usize {
        // Counts of bodies in memory: the sums never saturate.
        self.spawns
            .iter()
            .map(|s| s.bodies.len())
            .fold(self.bodies.len(), usize::saturating_add)
    }

    /// Number of shapes the scene has once every spawn has happened.
    pub fn total_shapes(&self) -> usize {
        let all = self
            .bodies
            .iter()
            .chain(self.spawns.iter().flat_map(|s| &s.bodies));
        all.map(|b| b.shapes.len()).sum()
    }
}

impl BodyDesc {
    /// A body of `kind` at `position`, at rest, mass from shapes, no shapes.
    pub fn new(kind: BodyKind, position: Vect) -> BodyDesc {
        BodyDesc {
            label: None,
            kind,
            position,
            angle: Real::ZERO,
            velocity: Vect::ZERO,
            angular_velocity: Real::ZERO,
            mass: MassDesc::FromShapes,
            bullet: false,
            shapes: Vec::new(),
        }
    }

    /// A dynamic body with an explicit mass and moment.
    pub fn dynamic(position: Vect, mass: Real, moment: Real) -> BodyDesc {
        BodyDesc {
            mass: MassDesc::Explicit { mass, moment },
            ..BodyDesc::new(BodyKind::Dynamic, position)
        }
    }

    /// A static body at the origin.
    pub fn static_body() -> BodyDesc {
        BodyDesc::new(BodyKind::Static, Vect::ZERO)
    }

    /// Builder: sets the label.
    pub fn labeled(mut self, label: &str) -> BodyDesc {
        self.label = Some(label.to_owned());
        self
    }

    /// Builder: marks the body as a bullet (continuous collision).
    pub fn bullet(mut self) -> BodyDesc {
        self.bullet = true;
        self
    }

    /// Builder: sets the velocity.
    pub fn moving(mut self, velocity: Vect) -> BodyDesc {
        self.velocity = velocity;
        self
    }

    /// Builder: adds a shape.
    pub fn with_shape(mut self, shape: ShapeDesc) -> BodyDesc {
        self.shapes.push(shape);
        self
    }
}

impl ShapeDesc {
    /// A massless shape without friction or elasticity, default filter.
    pub fn new(geometry: GeometryDesc) -> ShapeDesc {
        ShapeDesc {
            geometry,
            friction: Real::ZERO,
            elasticity: Real::ZERO,
            surface_velocity: Vect::ZERO,
            collision_type: 0,
            filter: ShapeFilter::ALL,
            sensor: false,
            mass: ShapeMassDesc::None,
        }
    }

    /// A circle of `radius` centred on the body origin.
    pub fn circle(radius: Real) -> ShapeDesc {
        ShapeDesc::new(GeometryDesc::Circle {
            radius,
            offset: Vect::ZERO,
        })
    }

    /// A circle of `radius` centred at `offset`.
    pub fn circle_at(radius: Real, offset: Vect) -> ShapeDesc {
        ShapeDesc::new(GeometryDesc::Circle { radius, offset })
    }

    /// A segment without neighbours.
    pub fn segment(a: Vect, b: Vect, radius: Real) -> ShapeDesc {
        ShapeDesc::new(GeometryDesc::Segment {
            a,
            b,
            radius,
            neighbors: None,
        })
    }

    /// A `width × height` box centred on the body origin.
    pub fn box_shape(width: Real, height: Real, radius: Real) -> ShapeDesc {
        ShapeDesc::box_at(width, height, radius, Vect::ZERO)
    }

    /// A `width × height` box centred at `offset`.
    pub fn box_at(width: Real, height: Real, radius: Real, offset: Vect) -> ShapeDesc {
        ShapeDesc::new(GeometryDesc::Box {
            width,
            height,
            radius,
            offset,
        })
    }

    /// The convex hull of `verts` with rounding `radius`.
    pub fn poly(verts: Vec<Vect>, radius: Real) -> ShapeDesc {
        ShapeDesc::new(GeometryDesc::Poly { verts, radius })
    }

    /// Builder: friction and elasticity.
    pub fn material(mut self, friction: Real, elasticity: Real) -> ShapeDesc {
        self.friction = friction;
        self.elasticity = elasticity;
        self
    }

    /// Builder: density (mass = density · area).
    pub fn density(mut self, density: Real) -> ShapeDesc {
        self.mass = ShapeMassDesc::Density(density);
        self
    }

    /// Builder: collision type.
    pub fn collision_type(mut self, t: CollisionType) -> ShapeDesc {
        self.collision_type = t;
        self
    }
}
