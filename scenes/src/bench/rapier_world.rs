//! A [`SceneDesc`] as a Rapier world: same bodies, shapes, materials,
//! gravity, time step and iteration count, with the scripted forces and
//! spawns replayed as [`ScriptedWorld::step`](crate::ScriptedWorld::step) does,
//! and the constraints as the closest Rapier joints ([`JOINT_MAPPING`]; gears
//! and ratchets have none and are left out, [`RapierRun::left_out`]).
//!
//! The mapping, shape by shape (Chipmunk's rounding radius is Rapier's
//! border radius: both grow the core shape outward):
//!
//! | ours                         | Rapier                                        |
//! |------------------------------|-----------------------------------------------|
//! | circle `r` at `offset`       | `ball(r)` translated by `offset`              |
//! | segment, radius 0            | `segment(a, b)`                               |
//! | segment, radius `r > 0`      | `capsule_from_endpoints(a, b, r)`             |
//! | poly (hull of the points)    | `convex_hull` / `round_convex_hull`           |
//! | raw poly (already convex)    | `convex_polyline` / `round_convex_polyline`   |
//! | box `w × h`, radius, offset  | `cuboid` / `round_cuboid` translated          |
//!
//! Materials: friction and restitution with the `Multiply` combine rule (our
//! contacts multiply the two shapes' values). Mass: an explicit body mass
//! becomes Rapier's additional mass properties (centre at the body origin,
//! as ours) with massless colliders; otherwise colliders carry their mass
//! or density and Rapier sums them as we do.
//!
//! Rapier settings: `num_solver_iterations` = our iterations (in Rapier
//! these are sub-steps, each with one PGS and one stabilisation pass),
//! `dt`, gravity and `length_unit` (10 for the pixel-unit scenes of section
//! A, 1 otherwise) as given; sleeping off (as in the Tamias2D scenes of the
//! side-by-side; [`RapierRun::with_sleep`] turns it on, see [`RapierSleep`]
//! for how our idle test maps to Rapier's); the velocity cap
//! (`normalized_max_linear_velocity`, 400 m/s) off, because
//! `projectile_45` starts at 1200 m/s; everything else at Rapier's defaults
//! (soft contacts, speculative contacts, contact recycling, CCD of fast
//! bodies against fixed ones). Collision slop and bias have no Rapier
//! counterpart and are not mapped; damping is mapped to Rapier's linear and
//! angular damping (`−ln damping`), though every built-in scene has none.
use crate::{
    BodyDesc, BodyKind, GeometryDesc, JointType, MassDesc, SceneDesc, ShapeDesc, ShapeMassDesc,
    SpawnDesc,
};
use rapier2d::prelude::*;
use tamias2d::math::Vect;
use tamias2d::shape::ShapeFilter;

use crate::bench::measure::{BodyState, Engine, Penetration};
use crate::bench::Config;

/// A Rapier world built from a scene description.
pub struct RapierRun {
    /// The world.
    pub world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
    forces: Vec<(RigidBodyHandle, Vector, f32)>,
    spawns: Vec<SpawnDesc>,
    next_spawn: usize,
    steps_taken: u64,
    /// Steps of `sub_dt` per scene step (forces re-applied before each, as
    /// our `Settings::substeps` does).
    substeps: u32,
    sub_dt: f32,
    /// Rapier damping of every body (from the scene's damping setting).
    damping: f32,
    /// Rapier joints made from the scene's constraints (see
    /// [`JOINT_MAPPING`]), placeholders that only disable contacts
    /// included.
    pub joints: usize,
    /// Constraints of the scene that have no Rapier counterpart and were
    /// left out (their kinds, in scene order).
    pub left_out: Vec<JointType>,
    /// Sleeping of the dynamic bodies (`None`: they never sleep).
    sleep: Option<RapierSleep>,
    length_unit: f32,
}

/// Sleeping in Rapier set to match ours (`Settings::idle_speed_threshold`
/// and `sleep_time_threshold`), body by body.
///
/// Ours: a body is idle while `|v|² + (I/m)·ω² ≤ idle²` (its speed with the
/// rotation counted at the radius of gyration `r_g = √(I/m)`), and an island
/// sleeps once every body of it has been idle for `time`. Rapier 0.36
/// (`RigidBodyActivation::update_energy`) counts a body with colliders as
/// still while `½·(|Δx| + 2·sin(|Δθ|/2)·R) < normalized_linear_threshold ·
/// length_unit · dt`, where `Δx`, `Δθ` are its actual pose change over the
/// step and `R` its farthest collider point from the centre of mass
/// (`max_extent`), i.e. roughly `|v| + |ω|·R < 2 · threshold`; its
/// `angular_threshold` only applies to bodies without colliders (with
/// colliders it only gates at ω < π/2 rad/s). So:
///
/// * `normalized_linear_threshold = idle / (2 · length_unit)`: a body that
///   only translates is idle below the same speed in both engines;
/// * `angular_threshold = idle / r_g` of that body (what ours allows for a
///   pure rotation; unused by Rapier for bodies with colliders);
/// * `time_until_sleep = time`.
///
/// What stays different: for rotation Rapier counts the farthest point
/// (`R ≥ r_g`, e.g. 1.6 `r_g` for our rounded boxes) and adds the two parts
/// where we add their squares, so its test is the stricter one; and it
/// measures the pose change (position corrections included) where we
/// measure velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierSleep {
    /// Our `idle_speed_threshold`, in the scene's length units per second.
    pub idle_speed: f32,
    /// Our `sleep_time_threshold` (s).
    pub time: f32,
}

fn v2(v: Vect) -> Vector {
    let (x, y) = v.to_f64();
    Vector::new(x as f32, y as f32)
}

fn f(r: tamias2d::math::Real) -> f32 {
    r.to_f32()
}

impl RapierRun {
    /// The world for `desc` (made by [`scene_with`](super::scene_with) for
    /// `config`), with Rapier's length unit `length_unit`.
    pub fn new(desc: &SceneDesc, config: Config, length_unit: f32) -> RapierRun {
        RapierRun::with_sleep(desc, config, length_unit, None)
    }

    /// As [`new`](Self::new), with the dynamic bodies (spawned ones
    /// included) allowed to sleep as `sleep` says (`None`: never).
    pub fn with_sleep(
        desc: &SceneDesc,
        config: Config,
        length_unit: f32,
        sleep: Option<RapierSleep>,
    ) -> RapierRun {
        let mut world = PhysicsWorld::new();
        world.gravity = v2(desc.settings.gravity);
        let substeps = config.substeps.max(1);
        let sub_dt = f(desc.dt) / substeps as f32;
        let p = &mut world.integration_parameters;
        p.dt = sub_dt;
        p.num_solver_iterations = desc.settings.iterations.max(1) as usize;
        p.length_unit = length_unit;
        p.normalized_max_linear_velocity = f32::MAX;
        let mut run = RapierRun {
            world,
            handles: Vec::with_capacity(desc.total_bodies()),
            forces: Vec::new(),
            spawns: Vec::new(),
            next_spawn: 0,
            steps_taken: 0,
            substeps,
            sub_dt,
            damping: 0.0,
            joints: 0,
            left_out: Vec::new(),
            sleep,
            length_unit,
        };
        let damping = desc.settings.damping.to_f64();
        if damping > 0.0 && damping < 1.0 {
            run.damping = -damping.ln() as f32;
        }
        for body in &desc.bodies {
            run.add(body);
        }
        run.add_joints(desc);
        for force in &desc.forces {
            let h = run.handles[force.body as usize];
            run.forces.push((h, v2(force.force), f(force.torque)));
        }
        run.spawns = desc.spawns.clone();
        run.spawns.sort_by_key(|s| s.at_step);
        run.spawn_due();
        // A zero-dt step applies the insertions (mass properties from the
        // colliders, broadphase) without moving anything, so states read
        // before the first step are complete.
        run.world.integration_parameters.dt = 0.0;
        run.world.step();
        run.world.integration_parameters.dt = sub_dt;
        run
    }

    fn add(&mut self, desc: &BodyDesc) {
        let builder = match desc.kind {
            BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
            BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
            BodyKind::Static => RigidBodyBuilder::fixed(),
        };
        let mut builder = builder
            .translation(v2(desc.position))
            .rotation(f(desc.angle))
            .linvel(v2(desc.velocity))
            .angvel(f(desc.angular_velocity))
            .linear_damping(self.damping)
            .angular_damping(self.damping)
            .can_sleep(self.sleep.is_some())
            .ccd_enabled(desc.bullet);
        let explicit = match desc.mass {
            MassDesc::Explicit { mass, moment } if desc.kind == BodyKind::Dynamic => {
                Some(MassProperties::new(Vector::ZERO, f(mass), f(moment)))
            }
            _ => None,
        };
        if let Some(props) = explicit {
            builder = builder.additional_mass_properties(props);
        }
        let h = self.world.bodies.insert(builder);
        let massive = desc.kind == BodyKind::Dynamic && explicit.is_none();
        // The body's mass properties as Rapier will sum them (for the
        // angular sleep threshold).
        let mut mass_props = explicit.unwrap_or_default();
        for shape in &desc.shapes {
            let collider = collider(shape, massive);
            mass_props += collider.mass_properties().transform_by(collider.position());
            self.world
                .colliders
                .insert_with_parent(collider, h, &mut self.world.bodies);
        }
        if let (Some(sleep), BodyKind::Dynamic) = (self.sleep, desc.kind) {
            let mass = mass_props.mass();
            let r_g = if mass > 0.0 {
                (mass_props.principal_inertia() / mass).sqrt()
            } else {
                0.0
            };
            let a = self.world.bodies[h].activation_mut();
            a.normalized_linear_threshold = sleep.idle_speed / (2.0 * self.length_unit);
            a.angular_threshold = if r_g > 0.0 {
                sleep.idle_speed / r_g
            } else {
                sleep.idle_speed
            };
            a.time_until_sleep = sleep.time;
        }
        self.handles.push(h);
    }

    /// Adds the bodies of every spawn due at the current step count.
    fn spawn_due(&mut self) {
        while let Some(spawn) = self.spawns.get(self.next_spawn) {
            if u64::from(spawn.at_step) > self.steps_taken {
                break;
            }
            let bodies = spawn.bodies.clone();
            self.next_spawn += 1;
            for b in &bodies {
                self.add(b);
            }
        }
    }

    /// One scene step: scripted forces, `world.step()`, due spawns.
    /// One Rapier step of `sub_dt`, with the scripted forces set anew.
    fn sub_step(&mut self) {
        for &(h, force, torque) in &self.forces {
            if let Some(rb) = self.world.bodies.get_mut(h) {
                // Rapier keeps user forces across steps; ours are cleared by
                // every step and re-applied by the scene (and, within a
                // sub-stepped step, by the space before each sub-step).
                rb.reset_forces(false);
                rb.reset_torques(false);
                rb.add_force(force, true);
                rb.add_torque(torque, true);
            }
        }
        debug_assert_eq!(self.world.integration_parameters.dt, self.sub_dt);
        self.world.step();
    }
}

/// How each of our joint kinds is built in Rapier 0.36, one row per kind:
/// (kind, Rapier joint, notes). The performance report prints it.
///
/// Rules behind it: the hard joints map to Rapier's joints with their
/// default softness (`SpringCoefficients::joint_defaults`, 1 MHz, ζ = 1:
/// effectively rigid); where a Chipmunk constraint is rigid but Rapier only
/// has a motor for it (a pin, a velocity motor), the motor is given that
/// same softness as stiffness and damping (`k = ω²`, `c = 2ζω`, with
/// `AccelerationBased` coefficients these give Rapier's joint `erp` and a
/// negligible `cfm`), so it is as rigid as Rapier's own joints. Chipmunk's `max_bias` and
/// `error_bias` have no Rapier counterpart (its joints use the softness
/// above); `max_force` is mapped where Rapier has it (motors). An angular
/// constraint (rotary limit, motor, rotary spring) between two bodies that
/// a revolute (or pin-slot) joint already holds becomes that joint's
/// angular limit or motor, as a Rapier user would write it; otherwise it is
/// a generic joint with no locked axis and only that limit or motor.
/// Angles: Chipmunk's rotary limit bounds `θb − θa`, its motor drives
/// `ω_b − ω_a` to `−rate` and its rotary spring drives `θa − θb` to the
/// rest angle; Rapier's angular axis measures `θ2 − θ1`, so the rate and
/// the rest angle change sign.
pub const JOINT_MAPPING: &[(&str, &str, &str)] = &[
    (
        "pivot",
        "`RevoluteJoint` (local anchors)",
        "exact counterpart",
    ),
    (
        "pin",
        "`SpringJoint` (rest length = the pin's length) made rigid: stiffness and \
         damping of Rapier's own joint softness, `MotorModel::AccelerationBased`",
        "Rapier has no rigid distance joint: `RopeJoint`'s distance limit holds only the \
         max (`limit_linear_coupled`: \"FIXME: handle min limit too\"), and a pin also pushes",
    ),
    (
        "slide",
        "`RopeJoint` (max distance = `max`)",
        "`min` is not held (same limitation); every slide of section D has `min` = 0",
    ),
    (
        "groove",
        "`PinSlotJoint` (anchor 1 = groove start, axis along the groove, \
         limits [0, groove length], anchor 2 = b's anchor)",
        "exact counterpart (free rotation, translation along the slot)",
    ),
    (
        "damped spring",
        "`SpringJoint` (rest length, stiffness, damping; `MotorModel::ForceBased`)",
        "same spring law, both implicit",
    ),
    (
        "damped rotary spring",
        "angular position motor (target −rest angle, stiffness, damping, \
         `ForceBased`) on the pair's revolute joint",
        "same spring law",
    ),
    (
        "rotary limit",
        "angular limits [min, max] on the pair's revolute joint",
        "exact counterpart",
    ),
    (
        "simple motor",
        "angular velocity motor (target −rate, factor = Rapier's joint damping \
         2ζω, max force = `max_force`) on the pair's revolute or pin-slot joint",
        "Chipmunk's is a rigid velocity constraint; Rapier's is as stiff as its joints",
    ),
    (
        "gear",
        "none",
        "no Rapier joint couples two angles; left out",
    ),
    (
        "ratchet",
        "none (an empty `GenericJoint` keeps `contacts_enabled(false)` where the \
         ratchet disabled contacts)",
        "no one-way angular joint in Rapier; left out",
    ),
];

/// Which angular slots of a Rapier joint are taken.
#[derive(Clone, Copy, Default)]
struct AngularSlots {
    /// The joint frees rotation (revolute, pin slot): an angular limit or
    /// motor of the same pair can go on it.
    host: bool,
    limit: bool,
    motor: bool,
}

impl RapierRun {
    /// Adds the Rapier joints of `desc`'s constraints ([`JOINT_MAPPING`]).
    fn add_joints(&mut self, desc: &SceneDesc) {
        let resolved = super::joints::resolve(desc);
        let rigid = SpringCoefficients::<f32>::joint_defaults();
        let omega = rigid.angular_frequency();
        let (rigid_k, rigid_c) = (omega * omega, 2.0 * rigid.damping_ratio * omega);
        let vf = |p: [f64; 2]| Vector::new(p[0] as f32, p[1] as f32);
        // (a, b, joint, angular slots), in scene order.
        let mut built: Vec<(usize, usize, GenericJoint, AngularSlots)> = Vec::new();
        for j in &resolved {
            let (a1, a2) = (vf(j.anchor_a), vf(j.anchor_b));
            let plain = |mut g: GenericJoint| {
                g.set_local_anchor1(a1)
                    .set_local_anchor2(a2)
                    .set_contacts_enabled(j.collide);
                g
            };
            let (joint, slots) = match j.kind {
                JointType::Pivot => (
                    plain(RevoluteJoint::new().data),
                    AngularSlots {
                        host: true,
                        ..AngularSlots::default()
                    },
                ),
                JointType::Pin => {
                    let mut spring = SpringJoint::new(j.dist as f32, rigid_k, rigid_c);
                    spring.set_spring_model(MotorModel::AccelerationBased);
                    (plain(spring.data), AngularSlots::default())
                }
                JointType::Slide => (
                    plain(RopeJoint::new(j.max as f32).data),
                    AngularSlots::default(),
                ),
                JointType::Groove => {
                    let (g0, g1) = (j.groove[0], j.groove[1]);
                    let axis = [g1[0] - g0[0], g1[1] - g0[1]];
                    let len = axis[0].hypot(axis[1]);
                    let unit = vf([axis[0] / len, axis[1] / len]);
                    let mut g = PinSlotJoint::new(unit).data;
                    g.set_local_anchor1(vf(g0))
                        .set_local_anchor2(a2)
                        .set_limits(JointAxis::LinX, [0.0, len as f32])
                        .set_contacts_enabled(j.collide);
                    (
                        g,
                        AngularSlots {
                            host: true,
                            ..AngularSlots::default()
                        },
                    )
                }
                JointType::DampedSpring => (
                    plain(
                        SpringJoint::new(j.rest as f32, j.stiffness as f32, j.damping as f32).data,
                    ),
                    AngularSlots::default(),
                ),
                JointType::RotaryLimit | JointType::SimpleMotor | JointType::DampedRotarySpring => {
                    let is_motor = j.kind != JointType::RotaryLimit;
                    // The pair's revolute or pin-slot joint with that slot free.
                    let host = built.iter().position(|(a, b, _, s)| {
                        s.host
                            && ((*a, *b) == (j.a, j.b) || (*a, *b) == (j.b, j.a))
                            && if is_motor { !s.motor } else { !s.limit }
                    });
                    let index = host.unwrap_or_else(|| {
                        let mut g = GenericJoint::new(JointAxesMask::empty());
                        g.set_contacts_enabled(j.collide);
                        built.push((j.a, j.b, g, AngularSlots::default()));
                        built.len() - 1
                    });
                    let (a, _, target, s) = &mut built[index];
                    if is_motor {
                        s.motor = true;
                    } else {
                        s.limit = true;
                    }
                    target.contacts_enabled &= j.collide;
                    let sign = if *a == j.a { 1.0 } else { -1.0 };
                    angular(target, j, sign, rigid_c);
                    continue;
                }
                JointType::Gear | JointType::Ratchet => {
                    self.left_out.push(j.kind);
                    if j.collide {
                        continue;
                    }
                    let mut g = GenericJoint::new(JointAxesMask::empty());
                    g.set_contacts_enabled(false);
                    (g, AngularSlots::default())
                }
            };
            built.push((j.a, j.b, joint, slots));
        }
        for (a, b, joint, _) in built {
            let (h1, h2) = (self.handles[a], self.handles[b]);
            self.world.impulse_joints.insert(h1, h2, joint, true);
            self.joints += 1;
        }
    }
}

/// Puts the angular limit or motor of `j` on `g`, whose angle is
/// `sign · (θb − θa)` of `j`'s bodies (see [`JOINT_MAPPING`]).
fn angular(g: &mut GenericJoint, j: &super::joints::Resolved, sign: f64, rigid_c: f32) {
    let ax = JointAxis::AngX;
    match j.kind {
        JointType::RotaryLimit => {
            let (lo, hi) = if sign > 0.0 {
                (j.min, j.max)
            } else {
                (-j.max, -j.min)
            };
            g.set_limits(ax, [lo as f32, hi as f32]);
        }
        JointType::SimpleMotor => {
            g.set_motor_velocity(ax, (-j.rate * sign) as f32, rigid_c)
                .set_motor_model(ax, MotorModel::AccelerationBased);
            if let Some(f) = j.max_force {
                g.set_motor_max_force(ax, f as f32);
            }
        }
        JointType::DampedRotarySpring => {
            g.set_motor_position(
                ax,
                (-j.rest * sign) as f32,
                j.stiffness as f32,
                j.damping as f32,
            )
            .set_motor_model(ax, MotorModel::ForceBased);
        }
        _ => {}
    }
}

/// The Rapier collider of one of our shapes. `massive`: the shape's own
/// mass or density counts (not for explicit-mass or non-dynamic bodies).
fn collider(d: &ShapeDesc, massive: bool) -> Collider {
    let groups = interaction_groups(&d.filter);
    let builder = match &d.geometry {
        GeometryDesc::Circle { radius, offset } => {
            ColliderBuilder::ball(f(*radius)).translation(v2(*offset))
        }
        GeometryDesc::Segment { a, b, radius, .. } => {
            if radius.is_positive() {
                ColliderBuilder::capsule_from_endpoints(v2(*a), v2(*b), f(*radius))
            } else {
                ColliderBuilder::segment(v2(*a), v2(*b))
            }
        }
        GeometryDesc::Poly { verts, radius } => {
            let pts: Vec<Vector> = verts.iter().map(|v| v2(*v)).collect();
            let built = if radius.is_positive() {
                ColliderBuilder::round_convex_hull(&pts, f(*radius))
            } else {
                ColliderBuilder::convex_hull(&pts)
            };
            built.expect("polygon hull")
        }
        GeometryDesc::RawPoly { verts, radius } => {
            let pts: Vec<Vector> = verts.iter().map(|v| v2(*v)).collect();
            let built = if radius.is_positive() {
                ColliderBuilder::round_convex_polyline(pts, f(*radius))
            } else {
                ColliderBuilder::convex_polyline(pts)
            };
            built.expect("convex polygon")
        }
        GeometryDesc::Box {
            width,
            height,
            radius,
            offset,
        } => {
            let (hx, hy) = (f(*width) * 0.5, f(*height) * 0.5);
            let b = if radius.is_positive() {
                ColliderBuilder::round_cuboid(hx, hy, f(*radius))
            } else {
                ColliderBuilder::cuboid(hx, hy)
            };
            b.translation(v2(*offset))
        }
    };
    let mut builder = builder
        .friction(f(d.friction))
        .restitution(f(d.elasticity))
        .friction_combine_rule(CoefficientCombineRule::Multiply)
        .restitution_combine_rule(CoefficientCombineRule::Multiply)
        .sensor(d.sensor)
        .collision_groups(groups);
    builder = match d.mass {
        ShapeMassDesc::Mass(m) if massive => builder.mass(f(m)),
        ShapeMassDesc::Density(rho) if massive => builder.density(f(rho)),
        _ => builder.density(0.0),
    };
    builder.build()
}

/// Rapier's interaction groups for a Chipmunk filter that uses only its
/// group (categories and mask all set; anything else is not mapped): group
/// `g` in 1..=31 is membership bit `g` with every other bit in the filter,
/// so shapes of one group never meet and meet every other shape; group 0
/// is bit 0 with every bit in the filter.
fn interaction_groups(filter: &ShapeFilter) -> InteractionGroups {
    assert!(
        filter.categories == ShapeFilter::ALL.categories
            && filter.mask == ShapeFilter::ALL.mask
            && filter.group < 32,
        "only collision filter groups 0..32 are mapped to Rapier"
    );
    let own = Group::from_bits_truncate(1u32 << filter.group);
    let others = if filter.group == 0 {
        Group::ALL
    } else {
        Group::ALL.difference(own)
    };
    InteractionGroups::new(own, others, InteractionTestMode::And)
}

impl Engine for RapierRun {
    fn name(&self) -> &'static str {
        "Rapier"
    }

    fn step(&mut self) {
        for _ in 0..self.substeps {
            self.sub_step();
        }
        self.steps_taken += 1;
        self.spawn_due();
    }

    fn body_count(&self) -> usize {
        self.handles.len()
    }

    fn body(&self, index: usize) -> BodyState {
        let Some(rb) = self
            .handles
            .get(index)
            .and_then(|h| self.world.bodies.get(*h))
        else {
            return BodyState::default();
        };
        let (p, v) = (rb.translation(), rb.linvel());
        let dynamic = rb.is_dynamic();
        BodyState {
            position: [f64::from(p.x), f64::from(p.y)],
            angle: f64::from(rb.rotation().angle()),
            velocity: [f64::from(v.x), f64::from(v.y)],
            angular_velocity: f64::from(rb.angvel()),
            energy: if dynamic {
                f64::from(rb.kinetic_energy())
            } else {
                0.0
            },
            dynamic,
        }
    }

    fn sleeping_bodies(&self) -> usize {
        self.handles
            .iter()
            .filter_map(|h| self.world.bodies.get(*h))
            .filter(|rb| rb.is_dynamic() && rb.is_sleeping())
            .count()
    }

    fn penetration(&self) -> Penetration {
        let mut pen = Penetration::default();
        let colliders = &self.world.colliders;
        for pair in self.world.narrow_phase.contact_pairs() {
            if !pair.has_any_active_contact() {
                continue;
            }
            let (Some(c1), Some(c2)) =
                (colliders.get(pair.collider1), colliders.get(pair.collider2))
            else {
                continue;
            };
            if c1.is_sensor() || c2.is_sensor() {
                continue;
            }
            let contact = rapier2d::parry::query::contact(
                c1.position(),
                c1.shape(),
                c2.position(),
                c2.shape(),
                0.0,
            );
            if let Ok(Some(c)) = contact {
                pen.add(-f64::from(c.dist));
            }
        }
        pen
    }
}
