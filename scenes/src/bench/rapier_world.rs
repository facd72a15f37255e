//! A [`SceneDesc`] as a Rapier world: same bodies, shapes, materials,
//! gravity, time step and iteration count, with the scripted forces and
//! spawns replayed as [`ScriptedWorld::step`](crate::ScriptedWorld::step) does.
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
//! A, 1 otherwise) as given; sleeping off (we have none); the velocity cap
//! (`normalized_max_linear_velocity`, 400 m/s) off, because
//! `projectile_45` starts at 1200 m/s; everything else at Rapier's defaults
//! (soft contacts, speculative contacts, contact recycling, CCD of fast
//! bodies against fixed ones). Collision slop and bias have no Rapier
//! counterpart and are not mapped; damping is mapped to Rapier's linear and
//! angular damping (`−ln damping`), though every built-in scene has none.
use crate::{
    BodyDesc, BodyKind, GeometryDesc, MassDesc, SceneDesc, ShapeDesc, ShapeMassDesc, SpawnDesc,
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
        };
        let damping = desc.settings.damping.to_f64();
        if damping > 0.0 && damping < 1.0 {
            run.damping = -damping.ln() as f32;
        }
        for body in &desc.bodies {
            run.add(body);
        }
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
            .can_sleep(false)
            .ccd_enabled(desc.bullet);
        let explicit = match desc.mass {
            MassDesc::Explicit { mass, moment } if desc.kind == BodyKind::Dynamic => {
                builder = builder.additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    f(mass),
                    f(moment),
                ));
                true
            }
            _ => false,
        };
        let h = self.world.bodies.insert(builder);
        let massive = desc.kind == BodyKind::Dynamic && !explicit;
        for shape in &desc.shapes {
            let collider = collider(shape, massive);
            self.world
                .colliders
                .insert_with_parent(collider, h, &mut self.world.bodies);
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
